"""vtkDirectSurfaceRayCaster in a VTK Python pipeline (run with /usr/bin/python3).

Expected values come from analytic geometry (ray/sphere intersection in numpy), not from the
filter. Usage: test_filter.py <Data directory>
"""
import math
import os
import sys
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand, vtkDoubleArray
from vtkmodules.vtkCommonDataModel import (VTK_HEXAGONAL_PRISM, VTK_PENTAGONAL_PRISM, VTK_TETRA, vtkPlane,
                                           vtkUnstructuredGrid)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkCamera, vtkColorTransferFunction

import vtk  # noqa: F401  (the filter must work next to `import vtk`)
from shared_helpers import Messages
from tetdsr import vtkDirectSurfaceRayCaster

DATA = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "Data")


def read(name):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(DATA, name))
    reader.Update()
    return reader


def arrays(image):
    pd = image.GetPointData()
    return {name: vtk_to_numpy(pd.GetArray(name)).copy() for name in ("Colors", "Depth", "Normals", "CellId")}


def pixel_rays(camera, width, height):
    """Rays through pixel centres, per the filter's documented convention (independent code)."""
    position = np.array(camera.GetPosition())
    forward = np.array(camera.GetFocalPoint()) - position
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, camera.GetViewUp())
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = (camera.GetParallelScale() if camera.GetParallelProjection()
            else math.tan(math.radians(camera.GetViewAngle()) / 2))
    i, j = np.meshgrid(np.arange(width), np.arange(height))
    x = ((2 * (i + 0.5) / width - 1) * half * width / height).reshape(-1, 1)
    y = ((2 * (j + 0.5) / height - 1) * half).reshape(-1, 1)
    offset = x * right + y * up
    if camera.GetParallelProjection():
        return position + offset, np.tile(forward, (len(offset), 1))
    directions = forward + offset
    return np.tile(position, (len(offset), 1)), directions / np.linalg.norm(directions, axis=1, keepdims=True)


def sphere_truth(origins, directions, centre, radius):
    """First t >= 0 on the sphere per ray (inf if none) and the relative grazing margin."""
    oc = origins - centre
    half = np.einsum("ij,ij->i", directions, oc)
    closest2 = np.einsum("ij,ij->i", oc, oc) - half ** 2
    margin = np.abs(np.sqrt(np.maximum(closest2, 0)) - radius) / radius
    with np.errstate(invalid="ignore"):
        t = -half - np.sqrt(radius ** 2 - closest2)
    t[~(closest2 <= radius ** 2) | (t < 0)] = np.inf
    return t, margin


class SphereInCell(unittest.TestCase):
    def setUp(self):
        self.reader = read("sphere_in_cell.vtu")
        fd = self.reader.GetOutput().GetFieldData()
        self.centre = np.array([fd.GetArray("SphereCentre").GetValue(k) for k in range(3)])
        self.radius = fd.GetArray("SphereRadius").GetValue(0)
        self.camera = vtkCamera()
        self.camera.SetFocalPoint(*self.centre)
        self.camera.SetPosition(*(self.centre + [0.4, -0.7, 1.3]))
        self.camera.SetViewUp(0, 1, 0)
        self.camera.SetViewAngle(18)
        self.caster = vtkDirectSurfaceRayCaster()
        self.caster.SetInputConnection(self.reader.GetOutputPort())
        self.caster.SetValue(0, 0.0)
        self.caster.SetCamera(self.camera)
        self.caster.SetImageSize(160, 120)

    def check_against_sphere(self, radius, camera):
        self.caster.Update()
        out = arrays(self.caster.GetOutput())
        origins, directions = pixel_rays(camera, 160, 120)
        t, margin = sphere_truth(origins, directions, self.centre, radius)
        compared = margin > 1e-6
        ours = np.isfinite(out["Depth"])
        truth = np.isfinite(t)
        self.assertGreater(truth.sum(), 1000)
        mismatched = int(np.sum((ours != truth) & compared))
        self.assertEqual(mismatched, 0, f"expected coverage of {truth.sum()} pixels, got {ours.sum()}")
        both = ours & truth & compared
        depth_error = np.max(np.abs(out["Depth"][both] - t[both]))
        self.assertLess(depth_error, 1e-12, f"max depth error {depth_error}")
        points = origins[both] + t[both, None] * directions[both]
        expected_normals = (points - self.centre) / radius
        cos = np.einsum("ij,ij->i", out["Normals"][both], expected_normals)
        self.assertGreater(cos.min(), 1 - 1e-12)
        self.assertTrue(np.all(out["CellId"][ours] == 0), "every hit lies in cell 0")
        self.assertTrue(np.all(out["Colors"][~ours] == 0), "background is (0, 0, 0, 0)")
        self.assertTrue(np.all(out["Colors"][ours, 3] == 255))
        return out

    def test_exact_sphere_perspective_and_parallel(self):
        self.check_against_sphere(self.radius, self.camera)
        self.camera.ParallelProjectionOn()
        self.camera.SetParallelScale(0.3)
        self.check_against_sphere(self.radius, self.camera)

    def test_output_layout(self):
        self.caster.Update()
        image = self.caster.GetOutput()
        self.assertEqual(image.GetDimensions(), (160, 120, 1))
        self.assertEqual(image.GetPointData().GetScalars().GetName(), "Colors")
        self.assertEqual(image.GetPointData().GetArray("Colors").GetNumberOfComponents(), 4)
        self.assertEqual(image.GetPointData().GetArray("CellId").GetDataTypeAsString(), "idtype")

    def test_default_camera_sees_the_whole_mesh(self):
        caster = vtkDirectSurfaceRayCaster()
        caster.SetInputConnection(self.reader.GetOutputPort())
        caster.SetValue(0, 0.0)
        caster.Update()
        image = caster.GetOutput()
        self.assertEqual(image.GetDimensions(), (512, 512, 1))
        # ResetCamera's placement: looking down -z at the bounds' centre (0,0,0), view angle 30,
        # distance = radius / sin(15 deg), radius = half the bounds' diagonal.
        camera = vtkCamera()
        distance = math.sqrt(3.0) / math.sin(math.radians(15))
        camera.SetPosition(0, 0, distance)
        origins, directions = pixel_rays(camera, 512, 512)
        t, margin = sphere_truth(origins, directions, self.centre, self.radius)
        ours = np.isfinite(vtk_to_numpy(image.GetPointData().GetArray("Depth")))
        self.assertEqual(int(np.sum((ours != np.isfinite(t)) & (margin > 1e-6))), 0)
        self.assertGreater(ours.sum(), 500)

    def test_same_image_for_any_thread_count(self):
        images = []
        for threads in (1, 2, 0):
            self.caster.SetNumberOfThreads(threads)
            self.caster.Update()
            images.append(arrays(self.caster.GetOutput()))
        for other in images[1:]:
            for name in images[0]:
                self.assertTrue(np.array_equal(images[0][name], other[name]), f"{name} differs")

    def test_array_change_rebuilds_and_iso_change_rerenders(self):
        self.check_against_sphere(self.radius, self.camera)
        # iso-value r'^2 - r^2 shows the sphere of radius r' (same field, no rebuild needed)
        bigger = 1.3 * self.radius
        self.caster.SetValue(0, bigger ** 2 - self.radius ** 2)
        self.check_against_sphere(bigger, self.camera)
        # Edit the array in place: the cached preprocessing must notice.
        self.caster.SetValue(0, 0.0)
        mesh = self.reader.GetOutput()
        values = vtk_to_numpy(mesh.GetPointData().GetArray("sphere"))
        smaller = 0.7 * self.radius
        values += self.radius ** 2 - smaller ** 2
        mesh.GetPointData().GetArray("sphere").Modified()
        self.check_against_sphere(smaller, self.camera)

    def test_progress_is_reported_and_abort_empties_the_output(self):
        progress = []
        self.caster.AddObserver(vtkCommand.ProgressEvent,
                                lambda obj, event: progress.append(obj.GetProgress()))
        self.caster.Update()
        self.assertGreater(len(progress), 10)
        self.assertAlmostEqual(progress[-1], 1.0)

        caster = vtkDirectSurfaceRayCaster()
        caster.SetInputConnection(self.reader.GetOutputPort())
        caster.SetValue(0, 0.0)
        caster.SetCamera(self.camera)
        caster.SetImageSize(160, 120)
        messages = Messages(caster)

        def abort_halfway(obj, event):
            if obj.GetProgress() >= 0.5:
                obj.SetAbortExecute(1)

        observer = caster.AddObserver(vtkCommand.ProgressEvent, abort_halfway)
        caster.Update()
        self.assertTrue(any("Aborted after" in w for w in messages.warnings), messages.warnings)
        # VTK's convention: an aborted filter's output is emptied, never half-rendered.
        self.assertEqual(caster.GetOutput().GetNumberOfPoints(), 0)
        caster.RemoveObserver(observer)
        caster.SetAbortExecute(0)
        caster.Modified()
        caster.Update()
        self.assertEqual(caster.GetOutput().GetDimensions(), (160, 120, 1))


class SeveralIsoValues(unittest.TestCase):
    def test_nearest_crossing_of_any_value(self):
        reader = read("cube27.vtu")
        camera = vtkCamera()
        camera.SetPosition(2.5, 1.8, 3.9)
        depths = []
        for values in ([0.6], [0.95], [0.6, 0.95]):
            caster = vtkDirectSurfaceRayCaster()
            caster.SetInputConnection(reader.GetOutputPort())
            caster.SetNumberOfContours(len(values))
            for i, v in enumerate(values):
                caster.SetValue(i, v)
            caster.SetCamera(camera)
            caster.SetImageSize(90, 70)
            caster.Update()
            depths.append(vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth")).copy())
        self.assertTrue(np.array_equal(depths[2], np.minimum(depths[0], depths[1])))
        self.assertGreater(np.sum(depths[1] < depths[0]), 100, "the outer surface is in front")

        caster = vtkDirectSurfaceRayCaster()
        caster.GenerateValues(3, 0.5, 1.0)
        self.assertEqual(caster.GetNumberOfContours(), 3)
        self.assertEqual([caster.GetValue(i) for i in range(3)], [0.5, 0.75, 1.0])


class Appearance(unittest.TestCase):
    """Options of issue 5 seen from Python: what must not change, what must re-execute."""

    def caster(self):
        caster = vtkDirectSurfaceRayCaster()
        self.reader = read("cube27.vtu")  # the pipeline holds no reference to its producer
        caster.SetInputConnection(self.reader.GetOutputPort())
        caster.SetValue(0, 0.8)
        caster.SetImageSize(64, 48)
        return caster

    def test_opaque_styles_give_the_default_image(self):
        plain = self.caster()
        plain.Update()
        styled = self.caster()
        styled.SetIsoValueOpacity(0, 1.0)
        styled.SetIsoValueColor(0, 1.0, 1.0, 1.0)
        styled.Update()
        for name, values in arrays(plain.GetOutput()).items():
            np.testing.assert_array_equal(values, arrays(styled.GetOutput())[name], err_msg=name)
        self.assertIsNone(styled.GetOutput().GetPointData().GetArray("ColorValues"))

    def test_lookup_table_and_plane_edits_re_execute(self):
        caster = self.caster()
        caster.ColorByArrayOn()
        caster.SetInputArrayToProcess(1, 0, 0, 0, "distance")
        table = vtkColorTransferFunction()
        table.AddRGBPoint(0.0, 0.0, 0.0, 0.0)
        table.AddRGBPoint(1.0, 1.0, 1.0, 1.0)
        caster.SetLookupTable(table)
        plane = vtkPlane()
        plane.SetNormal(0.0, 0.0, -1.0)
        plane.SetOrigin(0.0, 0.0, 2.0)  # keeps everything
        caster.AddClippingPlane(plane)
        caster.Update()
        before = arrays(caster.GetOutput())
        table.AddRGBPoint(1.0, 1.0, 0.0, 0.0)  # white end turns red
        caster.Update()
        after = arrays(caster.GetOutput())
        hit = np.isfinite(before["Depth"])
        self.assertTrue((after["Colors"][hit, 1] <= before["Colors"][hit, 1]).all())
        self.assertGreater((after["Colors"][hit, 1] < before["Colors"][hit, 1]).sum(), 100)
        plane.SetOrigin(0.0, 0.0, 0.0)  # now removes z > 0: the camera (on +z) sees deeper
        caster.Update()
        clipped = arrays(caster.GetOutput())["Depth"]
        both = hit & np.isfinite(clipped)
        self.assertTrue((clipped[both] >= before["Depth"][both]).all())
        self.assertGreater((clipped[both] > before["Depth"][both] + 0.1).sum(), 100)

    def test_depth_buffer_normals_with_translucent_surfaces(self):
        caster = self.caster()
        caster.SetValue(1, 0.5)
        caster.SetIsoValueOpacity(0, 0.5)
        caster.Update()
        exact = arrays(caster.GetOutput())
        caster.SetNormalMode(vtkDirectSurfaceRayCaster.DEPTH_BUFFER)
        caster.Update()
        depth_buffer = arrays(caster.GetOutput())
        np.testing.assert_array_equal(exact["Depth"], depth_buffer["Depth"])
        # Same coverage and opacity; the colours differ only by the nearest surface's shading.
        np.testing.assert_array_equal(exact["Colors"][:, 3], depth_buffer["Colors"][:, 3])
        # Rays through the outer surface only (opacity 0.5, crossed twice: 1 - 0.5^2 = 0.75) and
        # rays that also reach the opaque inner one.
        alpha = exact["Colors"][:, 3][np.isfinite(exact["Depth"])]
        self.assertEqual(set(np.unique(alpha)), {191, 255})


class TransverseTest(unittest.TestCase):
    def test_paper_heuristic_leaves_a_hole_the_bernstein_bound_does_not(self):
        # One cell: vertex values 1, mid-edge values 0.9, so f = 0.8 + 0.2 sum(L^2) dips to 0.85
        # at the centroid; the 25%-widened nodal range [0.875, 1.025] excludes the iso-value 0.86.
        mesh = vtkUnstructuredGrid()
        points = vtk.vtkPoints()
        vertices = np.eye(4, 3, k=-1)  # (0,0,0), (1,0,0), (0,1,0), (0,0,1)
        edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
        for p in list(vertices) + [(vertices[a] + vertices[b]) / 2 for a, b in edges]:
            points.InsertNextPoint(*p)
        mesh.SetPoints(points)
        mesh.InsertNextCell(vtk.VTK_QUADRATIC_TETRA, 10, list(range(10)))
        values = vtkDoubleArray()
        values.SetName("bubble")
        for v in [1.0] * 4 + [0.9] * 6:
            values.InsertNextValue(v)
        mesh.GetPointData().SetScalars(values)
        camera = vtkCamera()
        camera.SetFocalPoint(0.25, 0.25, 0.25)
        camera.SetPosition(1.5, 1.2, 2.0)
        caster = vtkDirectSurfaceRayCaster()
        caster.SetInputData(mesh)
        caster.SetValue(0, 0.86)
        caster.SetCamera(camera)
        caster.SetImageSize(64, 64)

        def covered():
            caster.Update()
            depth = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth"))
            return int(np.isfinite(depth).sum())

        exact = covered()
        self.assertGreater(exact, 100)
        caster.SetTransverseTest(vtkDirectSurfaceRayCaster.WIDENED_NODAL_RANGE)
        self.assertEqual(covered(), 0, "the paper's 25% widening misses the cell")
        caster.SetNodalRangeWidening(0.5)
        self.assertEqual(covered(), exact, "widened enough, it finds the same surface")


class BadInput(unittest.TestCase):
    def run_filter(self, mesh, configure=None):
        caster = vtkDirectSurfaceRayCaster()
        caster.SetInputData(mesh)
        caster.SetValue(0, 0.0)
        caster.SetImageSize(40, 30)
        if configure:
            configure(caster)
        messages = Messages(caster)
        caster.Update()
        return caster, messages

    def mesh(self):
        mesh = vtkUnstructuredGrid()
        mesh.DeepCopy(read("sphere_in_cell.vtu").GetOutput())
        return mesh

    def test_no_scalars(self):
        mesh = self.mesh()
        mesh.GetPointData().SetActiveScalars(None)
        _, messages = self.run_filter(mesh)
        self.assertTrue(any("No point scalars" in e for e in messages.errors), messages.errors)

    def test_missing_named_array(self):
        _, messages = self.run_filter(
            self.mesh(), lambda c: c.SetInputArrayToProcess(0, 0, 0, 0, "pressure"))
        self.assertTrue(any("'pressure'" in e for e in messages.errors), messages.errors)

    def test_multicomponent_array_needs_a_component(self):
        mesh = self.mesh()
        vector = vtkDoubleArray()
        vector.SetName("velocity")
        vector.SetNumberOfComponents(3)
        sphere = mesh.GetPointData().GetArray("sphere")
        for p in range(mesh.GetNumberOfPoints()):
            vector.InsertNextTuple3(1.0, sphere.GetValue(p), 2.0)
        mesh.GetPointData().AddArray(vector)
        select = lambda c: c.SetInputArrayToProcess(0, 0, 0, 0, "velocity")  # noqa: E731
        _, messages = self.run_filter(mesh, select)
        self.assertTrue(any("3 components" in e for e in messages.errors), messages.errors)
        caster, messages = self.run_filter(mesh, lambda c: (select(c), c.SetArrayComponent(1)))
        self.assertEqual(messages.errors, [])
        covered = np.isfinite(vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth")))
        self.assertGreater(covered.sum(), 0)

    def test_colour_array_errors(self):
        _, messages = self.run_filter(self.mesh(), lambda c: c.ColorByArrayOn())
        self.assertTrue(any("no colour array is chosen" in e for e in messages.errors), messages.errors)
        _, messages = self.run_filter(
            self.mesh(), lambda c: (c.ColorByArrayOn(), c.SetInputArrayToProcess(1, 0, 0, 0, "speed")))
        self.assertTrue(any("no point array named 'speed'" in e for e in messages.errors), messages.errors)
        _, messages = self.run_filter(self.mesh(), lambda c: (
            c.ColorByArrayOn(), c.SetInputArrayToProcess(1, 0, 0, 0, "sphere"), c.SetColorArrayComponent(2)))
        self.assertTrue(any("ColorArrayComponent 2 is out of range" in e for e in messages.errors),
                        messages.errors)

    def test_clipping_plane_errors(self):
        def planes(count, normal=(1.0, 0.0, 0.0)):
            def configure(caster):
                for _ in range(count):
                    plane = vtkPlane()
                    plane.SetNormal(*normal)
                    caster.AddClippingPlane(plane)
            return configure
        _, messages = self.run_filter(self.mesh(), planes(7))
        self.assertTrue(any("7 clipping planes: at most 6" in e for e in messages.errors), messages.errors)
        _, messages = self.run_filter(self.mesh(), planes(1, (0.0, 0.0, 0.0)))
        self.assertTrue(any("zero normal" in e for e in messages.errors), messages.errors)
        caster, messages = self.run_filter(self.mesh(), planes(6))
        self.assertEqual(messages.errors, [])

    def test_empty_mesh_and_zero_image_size(self):
        _, messages = self.run_filter(vtkUnstructuredGrid())
        self.assertTrue(any("empty" in e for e in messages.errors), messages.errors)
        _, messages = self.run_filter(self.mesh(), lambda c: c.SetImageSize(0, 30))
        self.assertTrue(any("ImageSize" in e for e in messages.errors), messages.errors)

    def test_no_iso_value(self):
        _, messages = self.run_filter(self.mesh(), lambda c: c.SetNumberOfContours(0))
        self.assertTrue(any("iso-value" in e for e in messages.errors), messages.errors)

    def test_other_cell_types_skipped_and_linear_tets_rendered(self):
        mesh = self.mesh()
        base = mesh.GetNumberOfPoints()
        for p in range(12):  # a hexagonal and a pentagonal prism far away (types TetDSR does not
            # read), and a linear tet
            mesh.GetPoints().InsertNextPoint(5 + (p & 1), 5 + ((p >> 1) & 1), 5 + (p >> 2))
            mesh.GetPointData().GetArray("sphere").InsertNextValue(-1.0)
        mesh.InsertNextCell(VTK_HEXAGONAL_PRISM, 12, [base + k for k in range(12)])
        mesh.InsertNextCell(VTK_PENTAGONAL_PRISM, 10, [base + k for k in range(10)])
        mesh.InsertNextCell(VTK_TETRA, 4, [base, base + 1, base + 2, base + 4])
        caster, messages = self.run_filter(mesh)
        self.assertEqual(caster.GetNumberOfUnsupportedCells(), 2)
        self.assertEqual(caster.GetNumberOfRenderedCells(), 7)
        self.assertTrue(any("Skipped 2 cells of a type TetDSR does not read" in w and "VTK_TETRA" in w
                            for w in messages.warnings), messages.warnings)

    def test_float32_points_give_the_same_image(self):
        # The bundled cube's coordinates (-1, 0, 1) are exact in float32: same image bit for bit.
        reference = vtkUnstructuredGrid()
        reference.DeepCopy(read("cube27.vtu").GetOutput())
        single = vtkUnstructuredGrid()
        single.DeepCopy(reference)
        points = vtk.vtkPoints()
        points.SetDataTypeToFloat()
        points.DeepCopy(reference.GetPoints())
        self.assertEqual(points.GetDataType(), vtk.VTK_FLOAT)
        single.SetPoints(points)
        images = []
        for mesh in (reference, single):
            caster, messages = self.run_filter(mesh, lambda c: c.SetValue(0, 0.8))
            self.assertEqual(messages.errors, [])
            images.append(arrays(caster.GetOutput()))
        self.assertGreater(np.isfinite(images[0]["Depth"]).sum(), 100)
        for name in images[0]:
            self.assertTrue(np.array_equal(images[0][name], images[1][name]), name)

    def test_nan_and_inf_values_skipped_and_counted(self):
        for node, value in ((26, float("nan")), (3, float("inf"))):
            mesh = self.mesh()
            users = sum(1 for c in range(mesh.GetNumberOfCells())
                        if node in [mesh.GetCell(c).GetPointId(k) for k in range(10)])
            mesh.GetPointData().GetArray("sphere").SetValue(node, value)
            caster, messages = self.run_filter(mesh)
            self.assertEqual(caster.GetNumberOfNonFiniteCells(), users)
            self.assertTrue(any(f"Skipped {users} cells with NaN or Inf" in w
                                for w in messages.warnings), messages.warnings)

if __name__ == "__main__":
    unittest.main(verbosity=2)
