"""vtkDirectSurfaceMapper in a real render window (Xvfb, OpenGL), against independent truth:
the exact ray/sphere intersection of a field held exactly by the cells, the filter's depth for
the same camera, a polygon surface lit by the same lights, and the lookup table's colours; its
interactive frames against their own cast (rendered as a still frame of the cast's size)."""
import time
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkFloatArray, vtkPoints, vtkUnsignedCharArray
from vtkmodules.vtkCommonDataModel import (VTK_QUADRATIC_TETRA, vtkCellArray, vtkPlane,
                                           vtkUnstructuredGrid)
from vtkmodules.vtkCommonCore import vtkLookupTable
from vtkmodules.vtkFiltersSources import vtkPlaneSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkLightKit, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow, vtkRenderWindowInteractor)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)
import vtkmodules.vtkRenderingUI  # noqa: F401 (the X interactor, whose event loop runs timers)

from kuhn_lattice import lattice
from tetdsr import vtkDirectSurfaceMapper, vtkDirectSurfaceRayCaster

W, H = 160, 120
RADIUS2 = 0.5  # iso-value of |x|^2: a sphere of radius sqrt(0.5), held exactly by the cells
# Depth tolerance: the colour and depth images travel as float (24-bit mantissa) into a depth
# buffer of 24 or 32 bits; 4 units of 2^-24 covers both roundings.
DEPTH_TOLERANCE = 4 * 2.0 ** -24


def grid(n=3, fields=None, cell_range=None):
    points, cells = lattice(n)
    if cell_range:
        cells = cells[cell_range[0]:cell_range[1]]
    ug = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetData(numpy_to_vtk(points, deep=1))
    ug.SetPoints(p)
    ca = vtkCellArray()
    ca.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 10 * len(cells) + 1, 10), deep=1),
               numpy_to_vtkIdTypeArray(cells.ravel(), deep=1))
    ug.SetCells(numpy_to_vtk(np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8), deep=1), ca)
    fields = fields or {"f": lambda x: np.sum(x ** 2, axis=1)}
    for k, (name, function) in enumerate(fields.items()):
        a = numpy_to_vtk(np.ascontiguousarray(function(points)), deep=1)
        a.SetName(name)
        ug.GetPointData().AddArray(a)
        if k == 0:
            ug.GetPointData().SetActiveScalars(name)
    return ug


WINDOW = []


def shared_window():
    """One render window (one X connection) for every test, emptied of its renderers: Xvfb on
    these machines refuses a few connections in a hundred under load. Single-sampled: the tests
    check coverage and depth at pixel centres, the mapper's one ray a pixel there (VTK's windows
    ask for 8 samples by default, and in a multisampled window the mapper covers its silhouettes
    sample by sample: test_mapper_passes.py)."""
    if not WINDOW:
        window = vtkRenderWindow()
        window.SetMultiSamples(0)
        window.SetSize(W, H)
        window.OffScreenRenderingOn()
        WINDOW.append(window)
    window = WINDOW[0]
    window.SetSize(W, H)
    renderers = window.GetRenderers()
    while renderers.GetNumberOfItems():
        window.RemoveRenderer(renderers.GetFirstRenderer())
    window.SetDesiredUpdateRate(0.0001)
    return window


def scene(mesh, iso=RADIUS2, parallel=False, configure=None, window=None):
    mapper = vtkDirectSurfaceMapper()
    mapper.SetInputData(mesh)
    mapper.SetValue(0, iso)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    window = window if window is not None else shared_window()
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(2.2, 1.6, 3.0)
    camera.SetFocalPoint(0.05, -0.03, 0.02)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(30)
    if parallel:
        camera.ParallelProjectionOn()
        camera.SetParallelScale(0.9)
    if configure:
        configure(mapper, actor, renderer)
    renderer.ResetCameraClippingRange()
    return window, renderer, mapper, actor


def polygon_actor(source, color):
    """An opaque actor drawing the polygons of `source` (an algorithm) in `color`."""
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*color)
    return actor


def event_loop(window):
    """An interactor on `window` whose events the test processes itself (an event loop, as far as
    the mapper can tell), and process_events(until, seconds): processes them until `until()` or
    `seconds` have passed; returns until()."""
    interactor = vtkRenderWindowInteractor()
    interactor.SetRenderWindow(window)
    interactor.SetStillUpdateRate(0.0001)
    interactor.Initialize()

    def process_events(until, seconds):
        end = time.perf_counter() + seconds
        while not until() and time.perf_counter() < end:
            interactor.ProcessEvents()
            time.sleep(0.005)
        return until()

    return interactor, process_events


def zbuffer(window):
    width, height = window.GetSize()
    z = vtkFloatArray()
    window.GetZbufferData(0, 0, width - 1, height - 1, z)
    return vtk_to_numpy(z).reshape(height, width).astype(float)


def rgba(window):
    width, height = window.GetSize()
    c = vtkUnsignedCharArray()
    window.GetRGBACharPixelData(0, 0, width - 1, height - 1, 1, c)
    return vtk_to_numpy(c).reshape(height, width, 4).astype(int)


def matrix(renderer):
    m = renderer.GetActiveCamera().GetCompositeProjectionTransformMatrix(renderer.GetTiledAspectRatio(), -1, 1)
    return np.array([[m.GetElement(r, c) for c in range(4)] for r in range(4)])


def window_depth(composite, points):
    clip = np.c_[points, np.ones(len(points))] @ composite.T
    return 0.5 * clip[:, 2] / clip[:, 3] + 0.5


def pixel_rays(composite, width=W, height=H):
    """Rays through pixel centres from the inverse composite projection (near to far plane)."""
    inverse = np.linalg.inv(composite)
    i, j = np.meshgrid(np.arange(width), np.arange(height))
    x = (2 * (i.ravel() + 0.5) / width - 1)
    y = (2 * (j.ravel() + 0.5) / height - 1)
    def unproject(z):
        p = np.c_[x, y, np.full_like(x, z), np.ones_like(x)] @ inverse.T
        return p[:, :3] / p[:, 3:]
    near = unproject(-1.0)
    direction = unproject(1.0) - near
    return near, direction / np.linalg.norm(direction, axis=1)[:, None]


def sphere_truth(composite, radius2=RADIUS2, width=W, height=H):
    """Exact first hit of each pixel ray with |x|^2 = radius2, as window depth (1 on a miss),
    and each ray's margin: how far from grazing (|discriminant| / radius^2)."""
    origin, direction = pixel_rays(composite, width, height)
    b = np.sum(origin * direction, axis=1)
    c = np.sum(origin * origin, axis=1) - radius2
    disc = b * b - c
    t = -b - np.sqrt(np.maximum(disc, 0))
    hit = disc >= 0
    depth = np.ones(len(t))
    depth[hit] = window_depth(composite, origin[hit] + t[hit, None] * direction[hit])
    return depth.reshape(height, width), np.abs(disc).reshape(height, width) / radius2


def nested_spheres(mapper, actor, renderer):
    """Two iso-values of |x|^2 in pure colours: the sphere of radius sqrt(0.5) red, opened towards
    the camera by a clipping plane, and the sphere of radius sqrt(0.15) green inside it, seen in
    front of the red sphere's far wall; a black background. Silhouettes against the background
    and between the two colours; no specular light, so every pixel of one surface has exactly
    one nonzero channel, and a blend of the two has two."""
    mapper.SetNumberOfContours(2)
    mapper.SetValue(0, 0.5)
    mapper.SetValue(1, 0.15)
    mapper.SetIsoValueColor(0, 1.0, 0.0, 0.0)
    mapper.SetIsoValueColor(1, 0.0, 1.0, 0.0)
    toward_camera = np.array(renderer.GetActiveCamera().GetPosition())
    toward_camera /= np.linalg.norm(toward_camera)
    # The plane keeps u . x <= 0.55: it cuts the outer sphere (radius 0.71), not the inner (0.39).
    plane = vtkPlane()
    plane.SetOrigin(*(0.55 * toward_camera))
    plane.SetNormal(*(-toward_camera))
    mapper.AddClippingPlane(plane)
    actor.GetProperty().SetAmbient(0.3)  # every lit pixel keeps its colour's channel above 0
    actor.GetProperty().SetDiffuse(0.7)
    actor.GetProperty().SetSpecular(0.0)
    renderer.SetBackground(0.0, 0.0, 0.0)


def interactive_cast_and_still(mesh, distance, width, height):
    """nested_spheres in a width x height window: an interactive frame cast at `distance`, the
    still frame, and the cast itself (the still frame of a window of the cast's size: with the
    same aspect ratio the composite projection, hence every ray, is the same). Each (rgba, z)."""
    window, renderer, mapper, _ = scene(mesh, configure=nested_spheres)
    window.SetSize(width, height)
    interactor = vtkRenderWindowInteractor()  # (no event loop: still frames are cast at once)
    interactor.SetRenderWindow(window)
    interactor.SetStillUpdateRate(0.0001)
    mapper.AutoAdjustSampleDistancesOff()
    mapper.SetInteractiveImageSampleDistance(distance)
    window.SetDesiredUpdateRate(15)
    window.Render()
    cast_size = (width // distance, height // distance)
    assert tuple(mapper.GetLastCastSize()) == cast_size, mapper.GetLastCastSize()
    interactive = rgba(window), zbuffer(window)
    window.SetDesiredUpdateRate(0.0001)
    window.Render()
    still = rgba(window), zbuffer(window)
    window.SetSize(*cast_size)
    window.Render()
    cast = rgba(window), zbuffer(window)
    return interactive, cast, still


def cast_pixels_under(width, height, cast_width, cast_height):
    """For a width x height window drawing a cast_width x cast_height image: per row and per
    column, the nearest cast pixel and the two cast pixels whose centres surround the window
    pixel's centre (the upsampling's 2 x 2, clamped at the edges)."""
    def axis(size, cast_size):
        x = (np.arange(size) + 0.5) * cast_size / size
        nearest = np.minimum(x.astype(int), cast_size - 1)
        around = np.clip(np.floor(x - 0.5).astype(int)[:, None] + [0, 1], 0, cast_size - 1)
        return nearest, around
    return axis(height, cast_height), axis(width, cast_width)


def surface_of(image):
    """1 where a pixel is purely red, 2 purely green, 0 otherwise (background, or a blend)."""
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return np.where((r > 0) & (g == 0) & (b == 0), 1, np.where((g > 0) & (r == 0) & (b == 0), 2, 0))


class Mapper(unittest.TestCase):
    mesh = grid()

    def check_against_sphere(self, parallel):
        window, renderer, mapper, _ = scene(self.mesh, parallel=parallel)
        window.Render()
        z = zbuffer(window)
        truth, margin = sphere_truth(matrix(renderer))
        covered, expected = z < 1, truth < 1
        clear = margin > 1e-6  # rays not grazing the silhouette
        self.assertGreater(expected.sum(), 0.2 * W * H)
        self.assertEqual(int((covered != expected)[clear].sum()), 0, "missed or false pixels")
        both = covered & expected
        error = np.abs(z - truth)[both].max()
        print("%s: %d pixels, max |depth - exact| = %.2e (tolerance %.2e)"
              % ("parallel" if parallel else "perspective", both.sum(), error, DEPTH_TOLERANCE))
        self.assertLess(error, DEPTH_TOLERANCE)

    def test_depth_equals_exact_sphere_perspective(self):
        self.check_against_sphere(False)

    def test_depth_equals_exact_sphere_parallel(self):
        self.check_against_sphere(True)

    def check_against_filter(self, parallel):
        window, renderer, mapper, _ = scene(self.mesh, parallel=parallel)
        window.Render()
        z = zbuffer(window)
        camera = renderer.GetActiveCamera()
        caster = vtkDirectSurfaceRayCaster()
        caster.SetInputData(self.mesh)
        caster.SetValue(0, RADIUS2)
        caster.SetImageSize(W, H)
        caster.SetCamera(camera)
        caster.Update()
        t = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth"))
        # The filter's rays (see tetdsr/common/Camera.h): from the camera position (perspective) or
        # its plane (parallel); the hit point, then its window depth.
        position = np.array(camera.GetPosition())
        forward = np.array(camera.GetFocalPoint()) - position
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, camera.GetViewUp())
        right /= np.linalg.norm(right)
        up = np.cross(right, forward)
        half_h = camera.GetParallelScale() if parallel else np.tan(np.radians(camera.GetViewAngle() / 2))
        half_w = half_h * W / H
        i, j = np.meshgrid(np.arange(W), np.arange(H))
        x = (2 * (i.ravel() + 0.5) / W - 1)[:, None]
        y = (2 * (j.ravel() + 0.5) / H - 1)[:, None]
        offset = x * half_w * right + y * half_h * up
        if parallel:
            origin, direction = position + offset, np.tile(forward, (W * H, 1))
        else:
            direction = forward + offset
            direction /= np.linalg.norm(direction, axis=1)[:, None]
            origin = np.tile(position, (W * H, 1))
        hit = np.isfinite(t)
        filter_depth = np.ones(W * H)
        filter_depth[hit] = window_depth(matrix(renderer), origin[hit] + t[hit, None] * direction[hit])
        filter_depth = filter_depth.reshape(H, W)
        both = (z < 1) & (filter_depth < 1)
        differ = int(((z < 1) != (filter_depth < 1)).sum())
        error = np.abs(z - filter_depth)[both].max()
        print("%s: mapper vs filter depth on %d pixels: max difference %.2e; coverage differs on %d"
              % ("parallel" if parallel else "perspective", both.sum(), error, differ))
        self.assertLess(error, DEPTH_TOLERANCE)
        self.assertLessEqual(differ, 0.002 * both.sum(), "silhouette pixels only")

    def test_depth_equals_filter_perspective(self):
        self.check_against_filter(False)

    def test_depth_equals_filter_parallel(self):
        self.check_against_filter(True)

    def test_curved_cells_plane_depth(self):
        """Curved cells (gmsh ball, mid-edge nodes on the sphere) holding f = a . x exactly: the
        mapper's depth is the plane's, and its coverage the filter's."""
        import os
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data",
                                        "curved_ball.vtu"))
        reader.Update()
        ball = reader.GetOutput()
        a, iso = np.array([0.3, -0.5, 0.8]), 0.15

        def linear(mapper, actor, renderer):
            mapper.SetInputArrayToProcess(0, 0, 0, 0, "linear")
            renderer.GetActiveCamera().SetPosition(2.6, 1.9, 3.4)
            renderer.GetActiveCamera().SetFocalPoint(0, 0, 0)
        window, renderer, mapper, _ = scene(ball, iso=iso, configure=linear)
        window.Render()
        z = zbuffer(window)
        composite = matrix(renderer)
        origin, direction = pixel_rays(composite)
        t = (iso - origin @ a) / (direction @ a)
        plane = window_depth(composite, origin + t[:, None] * direction).reshape(H, W)
        caster = vtkDirectSurfaceRayCaster()
        caster.SetInputData(ball)
        caster.SetInputArrayToProcess(0, 0, 0, 0, "linear")
        caster.SetValue(0, iso)
        caster.SetImageSize(W, H)
        caster.SetCamera(renderer.GetActiveCamera())
        caster.Update()
        self.assertGreater(caster.GetNumberOfCurvedCells(), 200)
        filter_hit = np.isfinite(vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth"))).reshape(H, W)
        covered = z < 1
        self.assertGreater(covered.sum(), 0.2 * W * H)
        differ = int((covered != filter_hit).sum())
        error = np.abs(z - plane)[covered].max()
        print("curved ball, plane a.x = %g: %d pixels, max |depth - plane| = %.2e; coverage "
              "differs from the filter's on %d" % (iso, covered.sum(), error, differ))
        self.assertLess(error, DEPTH_TOLERANCE)
        self.assertLessEqual(differ, 0.002 * covered.sum(), "silhouette pixels only")

    def test_lighting_matches_a_polygon_surface(self):
        # f = x + 2y + 3z: its iso-surface 0.4 is a plane, drawn once by the mapper and once as a
        # polygon (vtkPlaneSource over the same plane) with the same property and lights.
        plane_mesh = grid(fields={"g": lambda x: x[:, 0] + 2 * x[:, 1] + 3 * x[:, 2]})
        for lights in ("headlight", "light kit", "check"):
            def style(actor, renderer):
                p = actor.GetProperty()
                p.SetColor(0.9, 0.6, 0.3)
                p.SetAmbient(0.1)
                p.SetDiffuse(0.7)
                p.SetSpecular(0.4)
                p.SetSpecularPower(15)
                if lights != "headlight":
                    renderer.AutomaticLightCreationOff()
                    vtkLightKit().AddLightsToRenderer(renderer)
            window, renderer, mapper, actor = scene(
                plane_mesh, iso=0.4, configure=lambda m, a, r: style(a, r))
            window.Render()
            surface = rgba(window)
            covered = zbuffer(window) < 1
            source = vtkPlaneSource()
            # Three points of x + 2y + 3z = 0.4 spanning the cube's section.
            source.SetOrigin(-1.0, -1.0, (0.4 + 3) / 3)
            source.SetPoint1(1.0, -1.0, (0.4 + 1) / 3)
            source.SetPoint2(-1.0, 1.0, (0.4 - 1) / 3)
            polygon_mapper = vtkPolyDataMapper()
            polygon_mapper.SetInputConnection(source.GetOutputPort())
            actor.SetMapper(polygon_mapper)
            if lights == "check":
                actor.GetProperty().SetSpecular(0.0)
            window.Render()
            polygon = rgba(window)
            inside = covered & (zbuffer(window) < 1)
            # Away from the cube's edges, where the two outlines differ.
            inside[:2, :] = inside[-2:, :] = inside[:, :2] = inside[:, -2:] = False
            inside &= np.roll(inside, 1, 0) & np.roll(inside, -1, 0) & np.roll(inside, 1, 1) & np.roll(inside, -1, 1)
            difference = np.abs(surface - polygon)[inside][:, :3]
            print("%s: %d pixels, max colour difference %d, mean %.2f"
                  % (lights, inside.sum(), difference.max(), difference.mean()))
            self.assertGreater(inside.sum(), 1000)
            if lights != "headlight":  # (VTK's headlight shades a plane uniformly)
                spread = np.ptp(surface[inside][:, :3], axis=0).max()
                self.assertGreater(spread, 10, "the highlight varies the colour")
            if lights == "check":  # a different specular must show: the comparison can fail
                self.assertGreater(difference.max(), 10)
            else:
                self.assertLessEqual(difference.max(), 3, lights)

    def test_lookup_table_colours_and_clipping_planes(self):
        mesh = grid(fields={"f": lambda x: np.sum(x ** 2, axis=1), "x": lambda x: x[:, 0].copy()})
        table = vtkLookupTable()
        table.SetHueRange(0.66, 0.0)
        table.Build()
        def configure(mapper, actor, renderer):
            mapper.ScalarVisibilityOn()
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SelectColorArray("x")
            mapper.SetLookupTable(table)
            mapper.SetScalarRange(-0.7, 0.7)
            actor.GetProperty().SetAmbient(1.0)  # unlit colour: exactly the table's
            actor.GetProperty().SetDiffuse(0.0)
            actor.GetProperty().SetSpecular(0.0)
            plane = vtkPlane()
            plane.SetOrigin(-0.2, 0, 0)
            plane.SetNormal(1, 0, 0)  # keeps x >= -0.2
            mapper.AddClippingPlane(plane)
        window, renderer, mapper, actor = scene(mesh, configure=configure)
        window.Render()
        z, colours = zbuffer(window), rgba(window)
        covered = z < 1
        # Each covered pixel's point: unproject its window depth.
        inverse = np.linalg.inv(matrix(renderer))
        i, j = np.meshgrid(np.arange(W), np.arange(H))
        ndc = np.c_[2 * (i[covered] + 0.5) / W - 1, 2 * (j[covered] + 0.5) / H - 1, 2 * z[covered] - 1,
                    np.ones(covered.sum())]
        p = ndc @ inverse.T
        x = p[:, 0] / p[:, 3]
        self.assertGreater(covered.sum(), 1000)
        self.assertGreater(x.min(), -0.2 - 1e-4, "clipped away: x < -0.2")
        table.SetRange(-0.7, 0.7)
        def colour(value):
            rgb = [0.0, 0.0, 0.0]
            table.GetColor(value, rgb)
            return rgb
        # The table is discrete (256 entries over the range): a value within one entry's width
        # (or the depth buffer's rounding) may take the neighbouring entry.
        step = 1.4 / table.GetNumberOfTableValues()
        error = np.min([np.abs(colours[covered][:, :3] - np.array([colour(v + d) for v in x]) * 255).max(axis=1)
                        for d in (-step, 0.0, step)], axis=0)
        print("lookup table: %d pixels, max colour error %.1f" % (covered.sum(), error.max()))
        self.assertLessEqual(error.max(), 3.0)  # 8-bit rounding of the table and of the image

    def test_level_of_detail_and_image_reuse(self):
        window, renderer, mapper, actor = scene(self.mesh)
        interactor = vtkRenderWindowInteractor()
        interactor.SetRenderWindow(window)
        interactor.SetStillUpdateRate(0.0001)
        window.SetDesiredUpdateRate(0.0001)
        window.Render()
        self.assertEqual(tuple(mapper.GetLastCastSize()), (W, H))
        window.Render()
        self.assertTrue(mapper.GetLastRenderReusedImage(), "an unchanged render re-uses the image")
        camera = renderer.GetActiveCamera()
        # Interaction: a fixed reduced resolution, then one adjusted to a tiny allotted time.
        mapper.AutoAdjustSampleDistancesOff()
        mapper.SetInteractiveImageSampleDistance(4)
        window.SetDesiredUpdateRate(15)
        camera.Azimuth(5)
        window.Render()
        self.assertEqual(tuple(mapper.GetLastCastSize()), (W // 4, H // 4))
        mapper.AutoAdjustSampleDistancesOn()
        window.SetDesiredUpdateRate(100000)  # 10 microseconds per frame: as coarse as allowed
        for _ in range(3):
            camera.Azimuth(5)
            window.Render()
        self.assertGreater(mapper.GetLastImageSampleDistance(), 2.0)
        self.assertLess(mapper.GetLastCastSize()[0], W // 2)
        # Still again: full resolution, identical to a fresh render of the same view.
        window.SetDesiredUpdateRate(0.0001)
        window.Render()
        self.assertEqual(tuple(mapper.GetLastCastSize()), (W, H))
        still_z, still_rgba = zbuffer(window), rgba(window)
        fresh_window, fresh_renderer, _, _ = scene(self.mesh)
        fresh_renderer.GetActiveCamera().DeepCopy(camera)
        fresh_renderer.ResetCameraClippingRange()
        fresh_renderer.GetActiveCamera().SetClippingRange(camera.GetClippingRange())
        fresh_window.Render()
        np.testing.assert_array_equal(still_z, zbuffer(fresh_window))
        np.testing.assert_array_equal(still_rgba, rgba(fresh_window))

    def test_still_frame_after_interaction_is_the_full_cast(self):
        # After upsampled interactive frames (and with an interactor attached whose event loop
        # never runs), a still render is cast at full resolution before it returns and drawn
        # pixel for pixel: its silhouette and depth are the exact sphere's, as in
        # check_against_sphere; the interactive frame's are not, so the check can tell them apart.
        window, renderer, mapper, _ = scene(self.mesh)
        interactor = vtkRenderWindowInteractor()
        interactor.SetRenderWindow(window)
        interactor.SetStillUpdateRate(0.0001)
        mapper.AutoAdjustSampleDistancesOff()
        mapper.SetInteractiveImageSampleDistance(4)
        window.SetDesiredUpdateRate(15)
        window.Render()
        interactive = zbuffer(window)
        window.SetDesiredUpdateRate(0.0001)
        window.Render()
        self.assertEqual(tuple(mapper.GetLastCastSize()), (W, H))
        self.assertFalse(mapper.GetLastRenderRefining())
        truth, margin = sphere_truth(matrix(renderer))
        clear = margin > 1e-6
        for name, z in (("interactive", interactive), ("still", zbuffer(window))):
            wrong = int(((z < 1) != (truth < 1))[clear].sum())
            both = (z < 1) & (truth < 1)
            error = np.abs(z - truth)[both].max()
            print("%s frame: coverage differs from the exact sphere's on %d pixels; max |depth - "
                  "exact| = %.2e" % (name, wrong, error))
            if name == "still":
                self.assertEqual(wrong, 0)
                self.assertLess(error, DEPTH_TOLERANCE)
            else:
                self.assertGreater(wrong, 20, "the upscaled silhouette is the cast's staircase")

    def test_upsampling_keeps_surfaces_apart(self):
        # An interactive frame at sample distance 4 against its own cast: coverage is the nearest
        # cast pixel's, exactly; every covered pixel shows the nearest cast pixel's surface, its
        # colour and depth within the range of that surface's cast pixels among the 2 x 2 it
        # blends (a convex combination of them); the background stays untouched.
        (up, up_z), (cast, cast_z), _ = interactive_cast_and_still(self.mesh, 4, 320, 240)
        (rows, rows_around), (columns, columns_around) = cast_pixels_under(320, 240, 80, 60)
        cast_surface = surface_of(cast)
        self.assertTrue((cast_surface[cast_z < 1] > 0).all(), "the cast shows pure colours")
        covered = up_z < 1
        np.testing.assert_array_equal(covered, (cast_z < 1)[rows][:, columns])
        self.assertEqual(int(up[~covered][:, :3].max()), 0, "colour outside the cast's coverage")
        nearest_surface = cast_surface[rows][:, columns]
        mixed = covered & (surface_of(up) != nearest_surface)
        self.assertEqual(int(mixed.sum()), 0, "pixels blending two surfaces, or taking another's")
        # The 2 x 2 cast pixels of each window pixel: surfaces (h, w, 4), colours, depths.
        around_rows = rows_around[:, [0, 0, 1, 1]][:, None, :]
        around_columns = columns_around[:, [0, 1, 0, 1]][None, :, :]
        around_surfaces = cast_surface[around_rows, around_columns]
        same = around_surfaces == nearest_surface[..., None]
        colours = cast[..., :3][around_rows, around_columns]
        low = np.where(same[..., None], colours, 255).min(axis=2)
        high = np.where(same[..., None], colours, 0).max(axis=2)
        outside = covered & ((up[..., :3] < low - 1) | (up[..., :3] > high + 1)).any(axis=2)
        self.assertEqual(int(outside.sum()), 0, "colours outside their surface's cast pixels")
        depths = cast_z[around_rows, around_columns]
        low_z = np.where(same, depths, 2.0).min(axis=2)
        high_z = np.where(same, depths, -1.0).max(axis=2)
        outside_z = covered & ((up_z < low_z - DEPTH_TOLERANCE) | (up_z > high_z + DEPTH_TOLERANCE))
        self.assertEqual(int(outside_z.sum()), 0, "depths outside their surface's cast pixels")
        # The scene tests something: at this many pixels a plain bilinear filter would have
        # blended another surface or the background in.
        across = covered & (around_surfaces != nearest_surface[..., None]).any(axis=2)
        blended = covered & (up[..., :3] != cast[..., :3][rows][:, columns]).any(axis=2)
        print("upsampling: %d covered pixels, %d next to another surface or the background, %d "
              "blended" % (covered.sum(), across.sum(), blended.sum()))
        self.assertGreater(int(across.sum()), 300)
        self.assertGreater(int(blended.sum()), 0.5 * covered.sum(), "the interior is blended")

    def test_upsampling_is_closer_to_the_still_frame_than_nearest(self):
        # The same interactive frame, and the nearest-neighbour upscaling of its cast (what the
        # quad drew before), against the still frame of the same camera: the PSNR rises (a little:
        # most of the error is at silhouettes, which keep the nearest cast pixel's surface by
        # design), the pixels off by more than 16/255 do not grow in number, and those off by
        # more than 4/255 (smooth shading seen as blocks) drop to less than half.
        (up, _), (cast, _), (still, _) = interactive_cast_and_still(self.mesh, 4, 320, 240)
        (rows, _), (columns, _) = cast_pixels_under(320, 240, 80, 60)
        nearest = cast[rows][:, columns]

        def psnr(image):
            return 10 * np.log10(255.0 ** 2 / np.mean((image[..., :3] - still[..., :3]) ** 2.0))

        def off(image, level):
            return np.mean(np.abs(image[..., :3] - still[..., :3]).max(axis=2) > level)
        print("vs the still frame: nearest %.2f dB, %.2f %% off by > 4/255, %.2f %% by > 16/255; "
              "upsampled %.2f dB, %.2f %%, %.2f %%" % (psnr(nearest), 100 * off(nearest, 4),
              100 * off(nearest, 16), psnr(up), 100 * off(up, 4), 100 * off(up, 16)))
        self.assertGreater(psnr(up), psnr(nearest))
        self.assertLess(off(up, 4), 0.5 * off(nearest, 4))
        self.assertLessEqual(off(up, 16), off(nearest, 16))

    def test_progressive_refinement_after_interaction(self):
        # In a window whose interactor's events are processed (an event loop), the still render
        # after interaction shows the interactive image at once and casts the full frame in the
        # background; the event loop then shows it, equal to a synchronous still render. A new
        # interactive frame cancels a background cast instead of waiting for it.
        window = vtkRenderWindow()  # on screen, as an event loop's window is
        window.SetMultiSamples(0)  # (pixel-centre pictures, as shared_window's)
        window.SetSize(800, 600)
        window, renderer, mapper, _ = scene(self.mesh, window=window)
        mapper.SetNumberOfThreads(1)  # a background cast of some tenths of a second
        mapper.AutoAdjustSampleDistancesOff()
        mapper.SetInteractiveImageSampleDistance(4)
        interactor, process_events = event_loop(window)
        camera = renderer.GetActiveCamera()

        def interact():
            camera.Azimuth(10)
            window.SetDesiredUpdateRate(15)
            window.Render()
            self.assertEqual(tuple(mapper.GetLastCastSize()), (200, 150))
            self.assertFalse(mapper.GetLastRenderRefining())
            return rgba(window)

        window.SetDesiredUpdateRate(0.0001)
        window.Render()
        process_events(lambda: False, 0.2)  # (the loop runs: the mapper's first timer fires)
        interactive = interact()
        window.SetDesiredUpdateRate(0.0001)
        start = time.perf_counter()
        window.Render()
        self.assertTrue(mapper.GetLastRenderRefining(), "the full frame is cast in the background")
        self.assertEqual(tuple(mapper.GetLastCastSize()), (200, 150))
        np.testing.assert_array_equal(rgba(window), interactive, "the interactive image, at once")
        self.assertTrue(process_events(lambda: tuple(mapper.GetLastCastSize()) == (800, 600), 60),
                        "the event loop shows the refined frame")
        refinement_seconds = time.perf_counter() - start
        self.assertFalse(mapper.GetLastRenderRefining())
        refined = rgba(window), zbuffer(window)
        mapper.ProgressiveRefinementOff()  # (a changed setting: cast again, synchronously)
        window.Render()
        self.assertFalse(mapper.GetLastRenderReusedImage())
        np.testing.assert_array_equal(zbuffer(window), refined[1])
        np.testing.assert_array_equal(rgba(window), refined[0])

        mapper.ProgressiveRefinementOn()
        interact()
        window.SetDesiredUpdateRate(0.0001)
        window.Render()
        self.assertTrue(mapper.GetLastRenderRefining())
        start = time.perf_counter()
        interactive = interact()
        cancel_seconds = time.perf_counter() - start
        process_events(lambda: False, 0.5)
        self.assertEqual(tuple(mapper.GetLastCastSize()), (200, 150))
        np.testing.assert_array_equal(rgba(window), interactive, "no refined frame of the old view")
        print("background cast shown %.3f s after the still render; the interactive frame that "
              "cancelled one took %.3f s" % (refinement_seconds, cancel_seconds))
        # Waiting for the cancelled cast would take about as long as the refinement did; the
        # interactive frame casts 1/16 of its rays (a ratio, not a time limit: load slows both).
        self.assertLess(cancel_seconds, 0.5 * refinement_seconds)

    def test_translucent_surfaces_blend_over_opaque_geometry(self):
        # A translucent sphere (opacity a, two crossings per ray: front and back) in front of an
        # opaque plane, on a black background: where both are seen the colour must be
        # C = C_sphere_alone + (1 - a)^2 C_plane_alone, for plain blending, order-independent
        # translucency (actor opacity) and depth peeling alike; the sphere writes no depth.
        a = 0.4
        position = np.array([2.2, 1.6, 3.0])
        u = position / np.linalg.norm(position)
        side = np.cross(u, [0, 1, 0])
        side /= np.linalg.norm(side)
        up = np.cross(side, u)
        source = vtkPlaneSource()  # perpendicular to the view, behind the sphere, half of it
        centre = -1.2 * u
        source.SetOrigin(*(centre - 2.0 * up))
        source.SetPoint1(*(centre - 2.0 * up + 4.0 * side))
        source.SetPoint2(*(centre + 0.0 * up))
        for mode in ("iso-value opacity", "actor opacity", "actor opacity, depth peeling"):
            images = {}
            for content in ("sphere", "plane", "both"):
                def configure(mapper, actor, renderer):
                    renderer.SetBackground(0, 0, 0)
                    if mode == "iso-value opacity":
                        mapper.SetIsoValueOpacity(0, a)
                    else:
                        actor.GetProperty().SetOpacity(a)
                    if "peeling" in mode:
                        renderer.UseDepthPeelingOn()
                    plane_actor = polygon_actor(source, (0.2, 0.4, 1.0))
                    renderer.AddActor(plane_actor)
                    actor.SetVisibility(content != "plane")
                    plane_actor.SetVisibility(content != "sphere")
                window, renderer, mapper, actor = scene(self.mesh, configure=configure)
                window.Render()
                images[content] = (rgba(window)[..., :3], zbuffer(window))
            sphere, plane, both = images["sphere"][0], images["plane"][0], images["both"][0]
            seen = (sphere.sum(axis=2) > 0) & (plane.sum(axis=2) > 0)
            # Not on either outline (a polygon's edge pixels may rasterise differently).
            for axis in (0, 1):
                for shift in (1, -1):
                    seen &= np.roll(seen, shift, axis)
            self.assertGreater(seen.sum(), 500, mode)
            expected = sphere + (1 - a) ** 2 * plane
            error = np.abs(both - expected)[seen].max()
            print("%s: %d pixels, max |C - (C_sphere + (1-a)^2 C_plane)| = %.1f" % (mode, seen.sum(), error))
            self.assertLessEqual(error, 3.0, mode)
            self.assertTrue((images["sphere"][1] == 1).all(), "translucent surfaces write no depth")

    def test_composite_input_equals_one_grid(self):
        # The mesh split into two blocks of a multiblock dataset: the same picture.
        from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
        blocks = vtkMultiBlockDataSet()
        cells = self.mesh.GetNumberOfCells()
        for b, (first, last) in enumerate([(0, cells // 2), (cells // 2, cells)]):
            block = grid(cell_range=(first, last))
            blocks.SetBlock(b, block)
        pictures = []
        for data in (self.mesh, blocks):
            window, renderer, mapper, actor = scene(data)
            window.Render()
            pictures.append((zbuffer(window), rgba(window)))
        self.assertEqual(mapper.GetNumberOfRenderedCells(), cells)
        np.testing.assert_array_equal(pictures[0][0], pictures[1][0])
        np.testing.assert_array_equal(pictures[0][1], pictures[1][1])

    def test_abort_is_honoured(self):
        from vtkmodules.vtkCommonCore import vtkCommand
        window, renderer, mapper, actor = scene(self.mesh)
        tag = window.AddObserver(vtkCommand.AbortCheckEvent, lambda w, e: w.SetAbortRender(1))
        window.Render()
        self.assertTrue((zbuffer(window) == 1).all(), "an aborted cast draws nothing")
        window.RemoveObserver(tag)
        renderer.GetActiveCamera().Azimuth(1)
        window.Render()
        self.assertFalse(mapper.GetLastRenderReusedImage())
        self.assertGreater((zbuffer(window) < 1).sum(), 1000)

    def test_bad_input_is_reported_not_rendered(self):
        window, renderer, mapper, actor = scene(self.mesh)
        mapper.SetInputArrayToProcess(0, 0, 0, 0, "no such array")
        errors = []
        from vtkmodules.vtkCommonCore import vtkCommand
        mapper.AddObserver(vtkCommand.ErrorEvent, lambda *a: errors.append(1))
        window.Render()
        self.assertTrue(errors)
        self.assertTrue((zbuffer(window) == 1).all())


if __name__ == "__main__":
    unittest.main(verbosity=2)
