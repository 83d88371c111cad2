"""Picking the exact surface in VTK: vtkDirectSurfaceMapper.Pick at display positions and
vtkDirectSurfacePicker (a vtkCellPicker) against truth: a lattice whose quadratic cells hold
|x|^2 exactly, the sphere |x|^2 = 0.5 seen through an actor that is moved, turned and scaled,
cut by a clipping plane. The exact hit comes from the camera's composite projection, the actor's
matrix and the ray/sphere roots; a linear array g = x + 2y - z is interpolated exactly."""
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkPlane
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkRenderingCore import vtkActor, vtkCamera, vtkCellPicker, vtkRenderer

from test_mapper import W, H, grid, matrix, shared_window, window_depth, zbuffer, DEPTH_TOLERANCE
from tetdsr import vtkDirectSurfaceMapper, vtkDirectSurfacePick, vtkDirectSurfacePicker, vtkDirectSurfaceRayCaster

RADIUS2 = 0.5
DIAGONAL = np.sqrt(12.0)  # of the lattice [-1, 1]^3


def actor_matrix(actor):
    m = actor.GetMatrix()
    return np.array([[m.GetElement(r, c) for c in range(4)] for r in range(4)])


def scene():
    mesh = grid(4)
    points = np.array([mesh.GetPoint(k) for k in range(mesh.GetNumberOfPoints())])
    g = numpy_to_vtk(points[:, 0] + 2 * points[:, 1] - points[:, 2], deep=1)
    g.SetName("g")
    mesh.GetPointData().AddArray(g)
    mapper = vtkDirectSurfaceMapper()
    mapper.SetInputData(mesh)
    mapper.SetInputArrayToProcess(0, 0, 0, 0, "f")
    mapper.SetValue(0, RADIUS2)
    mapper.ScalarVisibilityOff()
    plane = vtkPlane()  # keeps y <= 0.3 (input coordinates)
    plane.SetOrigin(0.0, 0.3, 0.0)
    plane.SetNormal(0.0, -1.0, 0.0)
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.SetPosition(0.2, -0.1, 0.05)
    actor.SetOrientation(10.0, 25.0, -5.0)
    actor.SetScale(1.1, 0.9, 1.0)
    # The mapper's clipping planes are in world coordinates: the plane above, moved with the actor.
    world = actor_matrix(actor)
    origin = world @ np.array([0.0, 0.3, 0.0, 1.0])
    normal = np.linalg.inv(world[:3, :3]).T @ np.array([0.0, -1.0, 0.0])
    plane.SetOrigin(*origin[:3])
    plane.SetNormal(*normal)
    mapper.AddClippingPlane(plane)
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    window = shared_window()
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(2.2, 1.6, 3.0)
    camera.SetFocalPoint(0.05, -0.03, 0.02)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(30)
    renderer.ResetCameraClippingRange()
    window.Render()
    return window, renderer, mapper, actor


def exact_hit(composite, model, x, y):
    """The exact first hit (world point) of the ray through display position (x, y) (VTK's
    display coordinates: pixel (i, j)'s centre at (i + 0.5, j + 0.5)) with the sphere inside the kept side y <= 0.3 of the input,
    or None; and how far from grazing the ray is."""
    inverse = np.linalg.inv(composite)
    ndc = np.array([2 * x / W - 1, 2 * y / H - 1])
    near, far = (inverse @ np.r_[ndc, z, 1.0] for z in (-1.0, 1.0))
    to_model = np.linalg.inv(model)
    o = (to_model @ (near / near[3]))[:3]
    d = (to_model @ (far / far[3]))[:3] - o
    d /= np.linalg.norm(d)
    b, c = o @ d, o @ o - RADIUS2
    disc = b * b - c
    if disc < 0:
        return None, abs(disc)
    for t in (-b - np.sqrt(disc), -b + np.sqrt(disc)):
        p = o + t * d
        if t >= 0 and p[1] <= 0.3:
            return (model @ np.r_[p, 1.0])[:3], min(abs(disc), abs(p[1] - 0.3))
    return None, abs(disc)


class TestPick(unittest.TestCase):
    def test_pick_against_the_exact_sphere(self):
        window, renderer, mapper, actor = scene()
        composite = matrix(renderer)
        model = actor_matrix(actor)
        rng = np.random.default_rng(3)
        result = vtkDirectSurfacePick()
        hits = misses = 0
        position_error = normal_error = value_error = g_error = parametric_error = 0.0
        for x, y in zip(rng.uniform(0, W, 3000), rng.uniform(0, H, 3000)):
            expected, margin = exact_hit(composite, model, x, y)
            found = mapper.Pick(x, y, renderer, actor, result)
            if margin < 1e-6:
                continue  # grazing the silhouette or the plane's edge: either answer is right
            self.assertEqual(found, expected is not None, (x, y))
            self.assertEqual(found, result.GetHit())
            if not found:
                misses += 1
                continue
            hits += 1
            position = np.array(result.GetPosition())
            position_error = max(position_error, np.linalg.norm(position - expected) / DIAGONAL)
            p = np.array(result.GetMapperPosition())
            gradient_world = np.linalg.inv(model[:3, :3]).T @ (2 * p)
            normal_error = max(normal_error, np.linalg.norm(
                np.array(result.GetNormal()) - gradient_world / np.linalg.norm(gradient_world)))
            value_error = max(value_error, abs(result.GetValue() - RADIUS2))
            g = result.GetPointData().GetArray("g").GetValue(0)
            g_error = max(g_error, abs(g - (p[0] + 2 * p[1] - p[2])))
            self.assertTrue(result.GetHasParametricCoordinates())
            self.assertEqual(result.GetIsoValueIndex(), 0)
            # The parametric coordinates give the point back through the cell's vertices.
            cell = result.GetDataSet().GetCell(result.GetCellId())
            v = np.array([result.GetDataSet().GetPoint(cell.GetPointId(k)) for k in range(4)])
            r = np.array(result.GetParametricCoordinates())
            parametric_error = max(parametric_error, np.linalg.norm(v[0] + (v[1:] - v[0]).T @ r - p))
        print(f"Pick: {hits} hits, {misses} misses at random display positions; position within "
              f"{position_error:.1e} of the diagonal, normal {normal_error:.1e}, value "
              f"{value_error:.1e}, g {g_error:.1e}, point from parametric coordinates "
              f"{parametric_error:.1e}")
        self.assertGreater(hits, 500)
        self.assertGreater(misses, 500)
        self.assertLess(position_error, 1e-9)
        self.assertLess(normal_error, 1e-9)
        self.assertLess(value_error, 1e-12)
        self.assertLess(g_error, 1e-12)
        self.assertLess(parametric_error, 1e-12)

        # At pixel centres a pick is what the still frame shows there: its window depth.
        z = zbuffer(window)
        depth_error, coverage = 0.0, 0
        for j in range(0, H, 3):
            for i in range(0, W, 3):
                found = mapper.Pick(i + 0.5, j + 0.5, renderer, actor, result)
                coverage += found != (z[j, i] < 1.0)
                if found and z[j, i] < 1.0:
                    depth_error = max(depth_error, abs(window_depth(composite, np.array([result.GetPosition()]))[0] - z[j, i]))
        print(f"Pick at pixel centres: {coverage} pixels where the pick and the frame disagree, "
              f"window depth within {depth_error:.1e}")
        self.assertEqual(coverage, 0)
        self.assertLess(depth_error, DEPTH_TOLERANCE)

    def test_picker(self):
        window, renderer, mapper, actor = scene()
        composite = matrix(renderer)
        model = actor_matrix(actor)
        picker = vtkDirectSurfacePicker()
        plain = vtkCellPicker()
        rng = np.random.default_rng(5)
        hits = 0
        on_sphere = projection = plain_off = 0.0
        plain_far = 0
        for x, y in zip(rng.integers(0, W, 400), rng.integers(0, H, 400)):
            expected, margin = exact_hit(composite, model, x, y)
            if margin < 1e-3:
                continue
            found = picker.Pick(float(x), float(y), 0.0, renderer)
            self.assertEqual(bool(found), expected is not None, (x, y))
            if not found:
                continue
            hits += 1
            self.assertIs(picker.GetActor(), actor)
            world = np.array(picker.GetPickPosition())
            p = (np.linalg.inv(model) @ np.r_[world, 1.0])[:3]
            on_sphere = max(on_sphere, abs(p @ p - RADIUS2))
            self.assertTrue(picker.GetLastPick().GetHit())
            self.assertEqual(picker.GetCellId(), picker.GetLastPick().GetCellId())
            # It lies on the line of sight of the picked pixel.
            renderer.SetWorldPoint(*world, 1.0)
            renderer.WorldToDisplay()
            display = np.array(renderer.GetDisplayPoint()[:2])
            projection = max(projection, np.abs(display - [x, y]).max())
            # vtkCellPicker finds a face of the mesh instead.
            if plain.Pick(float(x), float(y), 0.0, renderer):
                q = (np.linalg.inv(model) @ np.r_[plain.GetPickPosition(), 1.0])[:3]
                plain_off = max(plain_off, abs(q @ q - RADIUS2))
                plain_far += abs(q @ q - RADIUS2) > 1e-3
        print(f"vtkDirectSurfacePicker: {hits} picks; on the sphere within {on_sphere:.1e}, on the "
              f"picked pixel's line of sight within {projection:.1e} pixels; vtkCellPicker: "
              f"{plain_far} picks off the sphere by more than 1e-3 (up to {plain_off:.2f})")
        self.assertGreater(hits, 50)
        self.assertLess(on_sphere, 1e-12)
        self.assertLess(projection, 1e-6)
        self.assertGreater(plain_far, hits // 2)

    def test_filter_pick_with_a_cap(self):
        # The filter cut by the plane z = 0.2 (keeping z <= 0.2), capped inside the sphere: picks
        # against the exact plane and sphere, and at pixel centres against its own output.
        mesh = grid(4)
        caster = vtkDirectSurfaceRayCaster()
        caster.SetInputData(mesh)
        caster.SetValue(0, RADIUS2)
        camera = vtkCamera()
        camera.SetPosition(0.9, 1.4, 3.0)
        camera.SetFocalPoint(0.0, 0.0, 0.0)
        camera.SetViewUp(0, 1, 0)
        camera.SetViewAngle(30)
        caster.SetCamera(camera)
        caster.SetImageSize(W, H)
        plane = vtkPlane()
        plane.SetOrigin(0.0, 0.0, 0.2)
        plane.SetNormal(0.0, 0.0, -1.0)
        caster.AddClippingPlane(plane)
        caster.SetCapping(vtkDirectSurfaceRayCaster.CAP_BELOW_ISO_VALUE)
        result = vtkDirectSurfacePick()
        self.assertFalse(caster.Pick(10.0, 10.0, result))  # before an execution
        caster.Update()
        image = caster.GetOutput().GetPointData()
        depth = vtk_to_numpy(image.GetArray("Depth")).reshape(H, W)
        cells = vtk_to_numpy(image.GetArray("CellId")).reshape(H, W)
        eye = np.array(camera.GetPosition())
        caps = surfaces = mismatched = 0
        error = 0.0
        for j in range(0, H, 2):
            for i in range(0, W, 2):
                found = caster.Pick(i + 0.5, j + 0.5, result)
                mismatched += found != np.isfinite(depth[j, i])
                if not found:
                    continue
                p = np.array(result.GetPosition())
                mismatched += abs(np.linalg.norm(p - eye) - depth[j, i]) > 1e-12 * DIAGONAL
                mismatched += result.GetCellId() != cells[j, i]
                if result.GetIsoValueIndex() == -1:
                    caps += 1
                    error = max(error, abs(p[2] - 0.2), abs(result.GetValue() - p @ p))
                    error = max(error, np.linalg.norm(np.array(result.GetNormal()) - [0, 0, -1]))
                    self.assertEqual(result.GetClippingPlaneId(), 0)
                    self.assertLess(p @ p, RADIUS2)
                else:
                    surfaces += 1
                    error = max(error, abs(p @ p - RADIUS2))
                    self.assertLessEqual(p[2], 0.2 + 1e-12)
        print(f"filter Pick: {caps} cap and {surfaces} surface picks at pixel centres, "
              f"{mismatched} disagreeing with the image; largest error {error:.1e}")
        self.assertGreater(caps, 200)
        self.assertGreater(surfaces, 100)
        self.assertEqual(mismatched, 0)
        self.assertLess(error, 1e-12)
        # After the input changes, the last image's picks are gone.
        mesh.GetPoints().Modified()
        self.assertFalse(caster.Pick(W / 2, H / 2, result))


if __name__ == "__main__":
    unittest.main()
