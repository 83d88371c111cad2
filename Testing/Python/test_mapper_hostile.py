"""vtkDirectSurfaceMapper under hostile use (issue 21): setters given NaN or the wrong object,
a mapper shared by actors, renderers and windows, unusual projections, inputs that draw nothing,
and arrays edited in place without Modified(). Each test is named for the case it keeps: a
reproducer of ../shared/hostile-inputs/faces/ or a finding of Testing/Fuzz/fuzz_mapper.py.
Truth: the exact ray/sphere intersection (the cells hold |x|^2 exactly), a fresh mapper of its
own for each view, and vtkPolyDataMapper drawing a fine polygonal sphere."""
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkFloatArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkPolyData, vtkUnstructuredGrid
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)

from shared_helpers import Messages
from test_mapper import RADIUS2, H, W, grid, matrix, rgba, scene, shared_window, sphere_truth, zbuffer
from tetdsr import vtkDirectSurfaceMapper, vtkDirectSurfaceRayCaster

MESH = grid()


def covered(window, size=(W, H)):
    z = vtkFloatArray()
    window.GetZbufferData(0, 0, size[0] - 1, size[1] - 1, z)
    return vtk_to_numpy(z).reshape(size[1], size[0]) < 1


def coloured(window):
    return rgba(window)[..., :3].sum(axis=2) > 0


def silhouette(mask):
    """Pixels next to an edge of the mask (their coverage may differ by rasterisation)."""
    edge = np.zeros_like(mask)
    for axis in (0, 1):
        for shift in (1, -1):
            edge |= mask != np.roll(mask, shift, axis)
    return edge


def place_camera(renderer, position=(2.2, 1.6, 3.0)):
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*position)
    camera.SetFocalPoint(0.05, -0.03, 0.02)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(30)
    return camera


class Setters(unittest.TestCase):
    def test_nan_interactive_sample_distance_refused(self):
        # mapper_nan_interactive_sample_distance.py: a NaN distance cast a 1 x 1 image over the
        # whole window, with no message.
        window, renderer, mapper, _ = scene(MESH)
        messages = Messages(mapper)
        mapper.SetInteractiveImageSampleDistance(float("nan"))
        mapper.SetMaximumImageSampleDistance(float("nan"))
        print("errors:", [e.strip().splitlines()[-1] for e in messages.errors])
        self.assertEqual(len(messages.errors), 2)
        self.assertIn("InteractiveImageSampleDistance must be a number, got NaN", messages.errors[0])
        self.assertEqual(mapper.GetInteractiveImageSampleDistance(), 2.0)
        self.assertEqual(mapper.GetMaximumImageSampleDistance(), 8.0)
        window.Render()
        still = covered(window).sum()
        mapper.AutoAdjustSampleDistancesOff()
        window.SetDesiredUpdateRate(1000.0)
        renderer.GetActiveCamera().Azimuth(1)
        window.Render()
        cast = mapper.GetLastCastSize()
        print("interactive cast", cast, "covered", covered(window).sum(), "still", still)
        self.assertEqual(tuple(cast), (W // 2, H // 2))
        self.assertLess(abs(int(covered(window).sum()) - int(still)), 0.1 * still)
        # Out of range is clamped, as before.
        mapper.SetInteractiveImageSampleDistance(1000.0)
        self.assertEqual(mapper.GetInteractiveImageSampleDistance(), 64.0)

    def test_non_finite_scalar_range_refused(self):
        mapper = vtkDirectSurfaceMapper()
        messages = Messages(mapper)
        mapper.SetScalarRange(2.0, 3.0)
        for bad in ((float("nan"), 1.0), (0.0, float("inf"))):
            mapper.SetScalarRange(*bad)
        print("errors:", [e.strip().splitlines()[-1] for e in messages.errors])
        self.assertEqual(len(messages.errors), 2)
        self.assertIn("ScalarRange must be finite numbers, got (nan, 1)", messages.errors[0])
        self.assertEqual(mapper.GetScalarRange(), (2.0, 3.0))

    def test_input_of_another_type_refused(self):
        mapper = vtkDirectSurfaceMapper()
        messages = Messages(mapper)
        mapper.SetInputData(MESH)
        mapper.SetInputData(vtkPolyData())
        print("errors:", [e.strip().splitlines()[-1] for e in messages.errors])
        self.assertEqual(len(messages.errors), 1)
        self.assertIn("A vtkPolyData cannot be drawn", messages.errors[0])
        self.assertIs(mapper.GetInputDataObject(0, 0), MESH)

    def test_many_component_field_advice_names_a_real_setting(self):
        mesh = grid(fields={"v": lambda x: np.c_[x, np.sum(x ** 2, axis=1)]})
        window, renderer, mapper, _ = scene(mesh)
        messages = Messages(mapper)
        window.Render()
        print("errors:", [e.strip().splitlines()[-1] for e in messages.errors])
        self.assertTrue(messages.errors)
        self.assertIn("Array 'v' has 4 components", messages.errors[0])
        self.assertIn("SetInputArrayToProcess(0, 0, 0, FIELD_ASSOCIATION_POINTS, name)",
                      messages.errors[0])
        self.assertNotIn("the field's component", messages.errors[0])
        self.assertEqual(int(covered(window).sum()), 0)


class Silence(unittest.TestCase):
    """Inputs whose bounds are empty: VTK's culler drops the actor before the mapper renders,
    so the mapper says why from GetBounds, once per change of the input."""

    def check_reported(self, data, text):
        collected = []
        window, renderer, mapper, _ = scene(
            data, configure=lambda mapper, actor, renderer: collected.append(Messages(mapper)))
        messages = collected[0]
        renderer.ResetCamera()
        window.Render()
        window.Render()
        said = [e for e in messages.errors if text in e]
        print("%s: %d errors, %d saying %r" % (data.GetClassName(), len(messages.errors), len(said), text))
        self.assertEqual(len(said), 1, messages.errors)
        self.assertEqual(int(covered(window).sum()), 0)
        return mapper, messages, window

    def test_empty_grid_reported(self):
        self.check_reported(vtkUnstructuredGrid(), "The input mesh is empty")

    def test_empty_multiblock_reported(self):
        self.check_reported(vtkMultiBlockDataSet(), "The input mesh is empty")

    def test_all_nan_points_reported(self):
        mesh = grid()
        points = vtkPoints()
        points.SetData(numpy_to_vtk(np.full((mesh.GetNumberOfPoints(), 3), np.nan), deep=1))
        mesh.SetPoints(points)
        mapper, messages, window = self.check_reported(mesh, "No cell can be rendered: all %d input cells were skipped" % mesh.GetNumberOfCells())
        # A change of the input is reported again.
        mesh.GetPoints().Modified()
        window.Render()
        self.assertEqual(sum("No cell can be rendered" in e for e in messages.errors), 2)

    def test_blocks_of_other_types_counted(self):
        blocks = vtkMultiBlockDataSet()
        blocks.SetBlock(0, MESH)
        blocks.SetBlock(1, vtkPolyData())
        window, renderer, mapper, _ = scene(blocks)
        messages = Messages(mapper)
        window.Render()
        print("warnings:", [w.strip().splitlines()[-1] for w in messages.warnings])
        self.assertTrue(any("1 of 2 blocks of the composite input are not vtkUnstructuredGrid" in w
                            for w in messages.warnings))
        self.assertGreater(int(covered(window).sum()), 1000)


class Sharing(unittest.TestCase):
    def test_two_actors_sharing_a_translucent_mapper_both_drawn(self):
        # mapper_two_actors_translucent.py: only the last actor's surface was drawn.
        masks = {}
        for shown in ("left", "right", "both"):
            mapper = vtkDirectSurfaceMapper()
            mapper.SetInputData(MESH)
            mapper.SetValue(0, RADIUS2)
            mapper.ScalarVisibilityOff()
            renderer = vtkRenderer()
            for name, x in (("left", -1.5), ("right", 1.5)):
                actor = vtkActor()
                actor.SetMapper(mapper)
                actor.SetPosition(x, 0, 0)
                actor.GetProperty().SetOpacity(0.5)
                actor.SetVisibility(shown in (name, "both"))
                renderer.AddActor(actor)
            window = shared_window()
            window.AddRenderer(renderer)
            place_camera(renderer, (0.0, 0.5, 9.0)).SetFocalPoint(0, 0, 0)
            renderer.ResetCameraClippingRange()
            window.Render()
            masks[shown] = coloured(window)
        union = masks["left"] | masks["right"]
        print("coloured: left %d, right %d, both %d, union %d" % (
            masks["left"].sum(), masks["right"].sum(), masks["both"].sum(), union.sum()))
        self.assertGreater(masks["left"].sum(), 500)
        self.assertGreater(masks["right"].sum(), 500)
        self.assertEqual(int((masks["both"] != union).sum()), 0)

    def test_two_opaque_actors_each_reuse_their_image(self):
        # Each view (renderer and actor) keeps its own image: a still second frame casts nothing.
        mapper = vtkDirectSurfaceMapper()
        mapper.SetInputData(MESH)
        mapper.SetValue(0, RADIUS2)
        renderer = vtkRenderer()
        for x in (-1.5, 1.5):
            actor = vtkActor()
            actor.SetMapper(mapper)
            actor.SetPosition(x, 0, 0)
            renderer.AddActor(actor)
        window = shared_window()
        window.AddRenderer(renderer)
        place_camera(renderer, (0.0, 0.5, 9.0)).SetFocalPoint(0, 0, 0)
        renderer.ResetCameraClippingRange()
        window.Render()
        first = zbuffer(window)
        window.Render()
        print("second frame re-used the image: %s; %d pixels changed" % (
            mapper.GetLastRenderReusedImage(), (zbuffer(window) != first).sum()))
        self.assertTrue(mapper.GetLastRenderReusedImage())
        self.assertEqual(int((zbuffer(window) != first).sum()), 0)
        self.assertGreater(int((first < 1).sum()), 1000)

    def test_one_mapper_in_two_windows_and_two_viewports(self):
        # Each view must equal what a mapper of its own draws there (and the exact sphere).
        shared = vtkDirectSurfaceMapper()
        shared.SetInputData(MESH)
        shared.SetValue(0, RADIUS2)
        positions = [(2.2, 1.6, 3.0), (-3.0, 0.4, 1.5), (0.5, -2.5, 2.0)]
        windows, renderers = [], []
        for w in range(2):
            window = vtkRenderWindow()
            window.SetMultiSamples(0)  # (pixel-centre pictures, as test_mapper's shared_window)
            window.SetSize(W, H)
            window.OffScreenRenderingOn()
            windows.append(window)
        # Window 0: one full viewport; window 1: two viewports side by side.
        layout = [(0, (0, 0, 1, 1)), (1, (0, 0, 0.5, 1)), (1, (0.5, 0, 1, 1))]
        for (w, viewport), position in zip(layout, positions):
            renderer = vtkRenderer()
            renderer.SetViewport(*viewport)
            actor = vtkActor()
            actor.SetMapper(shared)
            renderer.AddActor(actor)
            place_camera(renderer, position)
            renderer.ResetCameraClippingRange()
            windows[w].AddRenderer(renderer)
            renderers.append(renderer)
        for _ in range(2):  # the second frame re-uses each window's own image
            for window in windows:
                window.Render()
        shared_z = [zbuffer(window) for window in windows]
        # The same views, one fresh mapper each.
        for (w, viewport), renderer in zip(layout, renderers):
            own = vtkDirectSurfaceMapper()
            own.SetInputData(MESH)
            own.SetValue(0, RADIUS2)
            renderer.GetActors().GetLastActor().SetMapper(own)
        for window in windows:
            window.Render()
        for w, window in enumerate(windows):
            own_z = zbuffer(window)
            differ = int((own_z != shared_z[w]).sum())
            print("window %d: %d covered, %d pixels differ from a mapper per view" % (
                w, (shared_z[w] < 1).sum(), differ))
            self.assertGreater((shared_z[w] < 1).sum(), 1000)
            self.assertEqual(differ, 0)
        # And window 0 is the exact sphere.
        truth, margin = sphere_truth(matrix(renderers[0]))
        wrong = ((shared_z[0] < 1) != (truth < 1)) & (margin > 1e-6)
        self.assertEqual(int(wrong.sum()), 0)


class Projections(unittest.TestCase):
    """Unusual projections: the mapper must cover what vtkPolyDataMapper covers (a polygonal
    sphere of 400 x 400 facets, inscribed: silhouettes differ by under a pixel) and what the
    exact sphere covers."""

    def check(self, name, configure):
        images = {}
        for kind in ("mapper", "polygons"):
            window = shared_window()
            renderer = vtkRenderer()
            if kind == "mapper":
                mapper = vtkDirectSurfaceMapper()
                mapper.SetInputData(MESH)
                mapper.SetValue(0, RADIUS2)
            else:
                source = vtkSphereSource()
                source.SetRadius(np.sqrt(RADIUS2))
                source.SetThetaResolution(400)
                source.SetPhiResolution(400)
                mapper = vtkPolyDataMapper()
                mapper.SetInputConnection(source.GetOutputPort())
            actor = vtkActor()
            actor.SetMapper(mapper)
            renderer.AddActor(actor)
            window.AddRenderer(renderer)
            camera = place_camera(renderer)
            configure(camera)
            window.Render()
            images[kind] = covered(window)
            if kind == "mapper":
                truth, margin = sphere_truth(matrix(renderer))
        mine, polygons = images["mapper"], images["polygons"]
        edge = silhouette(polygons) | silhouette(mine)
        differ = int(((mine != polygons) & ~edge).sum())
        exact = int(((mine != (truth < 1)) & (margin > 1e-6)).sum())
        print("%s: mapper %d, polygons %d pixels; %d differ off the silhouettes; %d differ from "
              "the exact sphere" % (name, mine.sum(), polygons.sum(), differ, exact))
        self.assertGreater(polygons.sum(), 500)
        self.assertEqual(differ, 0)
        self.assertEqual(exact, 0)

    def test_far_near_ratio_1e8(self):
        self.check("near 1e-5, far 1e3", lambda camera: camera.SetClippingRange(1e-5, 1e3))

    def test_near_plane_cuts_the_sphere(self):
        distance = np.linalg.norm(np.array([2.2, 1.6, 3.0]) - [0.05, -0.03, 0.02])
        self.check("near plane through the sphere",
                   lambda camera: camera.SetClippingRange(distance - 0.2, distance + 5))

    def test_parallel_projection(self):
        def parallel(camera):
            camera.ParallelProjectionOn()
            camera.SetParallelScale(1.1)
            camera.SetClippingRange(0.1, 100)
        self.check("parallel", parallel)

    def test_off_axis_window_centre(self):
        def off_axis(camera):
            camera.SetWindowCenter(0.45, -0.3)
            camera.SetClippingRange(0.1, 100)
        self.check("off-axis (window centre 0.45, -0.3)", off_axis)

    def test_off_axis_parallel_sheared(self):
        def sheared(camera):
            camera.ParallelProjectionOn()
            camera.SetParallelScale(1.1)
            camera.SetViewShear(0.3, -0.2, 1.0)
            camera.SetClippingRange(0.1, 100)
        self.check("parallel, view shear (0.3, -0.2)", sheared)


class EditedWithoutModified(unittest.TestCase):
    """mapper_connectivity_edited_without_modified.py and its filter variant: the ids edited in
    place to 10^12 without Modified(), then colouring (or nodal normals) turned on: a segfault.
    Now no crash and no read outside the arrays (the ids are checked again on every read); the
    picture may be the last one (VTK's contract is Modified())."""

    def edited(self):
        mesh = grid(fields={"f": lambda x: np.sum(x ** 2, axis=1),
                            "c": lambda x: np.arange(len(x), dtype=float)})
        return mesh, lambda: vtk_to_numpy(mesh.GetCells().GetConnectivityArray()).__setitem__(
            slice(None), 10 ** 12)

    def test_mapper_colour_after_edit(self):
        mesh, edit = self.edited()
        window, renderer, mapper, _ = scene(mesh)
        window.Render()
        before = covered(window).sum()
        edit()
        mapper.ScalarVisibilityOn()
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray("c")
        window.Render()
        print("covered before the edit %d, after %d" % (before, covered(window).sum()))
        self.assertGreater(before, 1000)
        # Now with Modified(): every id is out of range, the mapper says so and draws nothing.
        messages = Messages(mapper)
        mesh.GetCells().GetConnectivityArray().Modified()
        window.Render()
        print("after Modified():", [e.strip().splitlines()[-1] for e in messages.errors][:1])
        self.assertTrue(any("No cell can be rendered" in e for e in messages.errors))
        self.assertEqual(int(covered(window).sum()), 0)

    def test_filter_colour_and_nodal_normals_after_edit(self):
        for variant in ("ColorByArrayOn", "SetNormalMode(2)"):
            mesh, edit = self.edited()
            caster = vtkDirectSurfaceRayCaster()
            caster.SetInputData(mesh)
            caster.SetValue(0, RADIUS2)
            caster.SetImageSize(40, 30)
            caster.Update()
            edit()
            if variant == "ColorByArrayOn":
                caster.ColorByArrayOn()
                caster.SetInputArrayToProcess(1, 0, 0, 0, "c")
            else:
                caster.SetNormalMode(2)
            caster.Update()
            ids = caster.GetOutput().GetPointData().GetArray("CellId")
            hits = -1 if ids is None else int((vtk_to_numpy(ids) >= 0).sum())
            print("filter, %s after the edit: %d hits, no crash" % (variant, hits))
            self.assertGreaterEqual(hits, 0)


if __name__ == "__main__":
    unittest.main(verbosity=2)
