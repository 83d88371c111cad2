"""Still frames of vtkDirectSurfaceMapper in a window whose event loop runs (ProgressiveRefinement):
a change shows a coarse frame at once and the loop shows the full frame cast in the background,
exact against the analytic plane a.x = iso held by the curved ball's cells (as test_mapper's
test_curved_cells_plane_depth). In a process of its own: VTK 9.2's X interactor crashed in
ProcessEvents when a test's on-screen window and interactor outlived it beside another's."""
import os
import time
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkHardwareSelector, vtkRenderWindow
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)
import vtkmodules.vtkRenderingUI  # noqa: F401 (the X interactor, whose event loop runs timers)

from test_mapper import DEPTH_TOLERANCE, event_loop, matrix, pixel_rays, scene, window_depth, zbuffer
from tetdsr import vtkDirectSurfaceRayCaster


class StillRefinement(unittest.TestCase):
    def test_still_changes_are_refined_in_the_background(self):
        # In a window whose event loop runs, a still render after a change (iso-value, camera)
        # whose full cast is not quick shows a coarse cast of the new scene at once and casts the
        # full frame in the background; the loop shows it, exact: the curved ball's plane a.x =
        # iso (as test_curved_cells_plane_depth: depth against the plane, coverage against the
        # filter's). A change while it is cast cancels it (the loop shows the newer scene's). With
        # SynchronousStillRenders (a capture) the still render is the full cast before it returns,
        # also during a background cast, and setting it re-uses the image. A hardware selection
        # during a background cast, and after it, selects what a synchronous selection cast does.
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data",
                                        "curved_ball.vtu"))
        reader.Update()
        ball = reader.GetOutput()
        a = np.array([0.3, -0.5, 0.8])
        width, height = 480, 360
        window = vtkRenderWindow()  # on screen, as an event loop's window is
        window.SetMultiSamples(0)  # (pixel-centre pictures, as test_mapper's shared_window)
        window.SetSize(width, height)

        def linear(mapper, actor, renderer):
            mapper.SetInputArrayToProcess(0, 0, 0, 0, "linear")
            renderer.GetActiveCamera().SetPosition(2.6, 1.9, 3.4)
            renderer.GetActiveCamera().SetFocalPoint(0, 0, 0)
        window, renderer, mapper, _ = scene(ball, iso=0.15, configure=linear, window=window)
        mapper.SetNumberOfThreads(1)  # curved cells: full casts of about a second
        interactor, process_events = event_loop(window)
        camera = renderer.GetActiveCamera()

        def refined():
            return tuple(mapper.GetLastCastSize()) == (width, height) and not mapper.GetLastRenderRefining()

        def filter_coverage():
            caster = vtkDirectSurfaceRayCaster()
            caster.SetInputData(ball)
            caster.SetInputArrayToProcess(0, 0, 0, 0, "linear")
            caster.SetValue(0, mapper.GetValue(0))
            caster.SetImageSize(width, height)
            caster.SetCamera(camera)
            caster.Update()
            depth = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth"))
            return np.isfinite(depth).reshape(height, width)

        def check_exact(what):
            composite = matrix(renderer)
            origin, direction = pixel_rays(composite, width, height)
            iso = mapper.GetValue(0)
            t = (iso - origin @ a) / (direction @ a)
            plane = window_depth(composite, origin + t[:, None] * direction).reshape(height, width)
            z = zbuffer(window)
            covered = z < 1
            differ = int((covered != filter_coverage()).sum())
            error = np.abs(z - plane)[covered].max()
            print("%s: %d pixels, max |depth - plane| = %.2e; coverage differs from the filter's "
                  "on %d" % (what, covered.sum(), error, differ))
            self.assertGreater(covered.sum(), 0.01 * width * height, what)
            self.assertLess(error, DEPTH_TOLERANCE, what)
            self.assertLessEqual(differ, 0.002 * covered.sum(), what + ": silhouette pixels only")

        def changed(change, what):
            change()
            start = time.perf_counter()
            window.Render()
            seconds = time.perf_counter() - start, mapper.GetTimeToDraw()
            cast = tuple(mapper.GetLastCastSize())
            self.assertTrue(mapper.GetLastRenderRefining(), what + ": refined in the background")
            self.assertLess(cast[0], width / 1.9, what + ": a coarse cast")
            # The coarse frame shows the new scene: its coverage within 5% of the exact one's.
            covered = int((zbuffer(window) < 1).sum())
            exact = int(filter_coverage().sum())
            self.assertLess(abs(covered - exact), 0.05 * exact, what + ": the new scene, coarse")
            return seconds, cast

        window.Render()  # (the loop is not known yet: the full cast before Render returns)
        self.assertEqual(tuple(mapper.GetLastCastSize()), (width, height))
        full_seconds = mapper.GetTimeToDraw()
        self.assertGreater(full_seconds, 0.3, "the scene must need a background cast")
        process_events(lambda: False, 0.2)  # (the loop runs: the mapper's first timer fires)

        coarse_seconds, cast = changed(lambda: mapper.SetValue(0, 0.3), "iso-value")
        self.assertLess(coarse_seconds[1], 0.5 * full_seconds, "the coarse frame is quick")
        self.assertTrue(process_events(refined, 60), "the event loop shows the refined frame")
        check_exact("refined after an iso-value change")

        changed(lambda: camera.Azimuth(25), "camera")
        changed(lambda: mapper.SetValue(0, 0.0), "iso-value during a background cast")
        selected = self.selected_cells(renderer)  # (waits for the background cast)
        self.assertTrue(process_events(refined, 60))
        check_exact("refined after a cancelled background cast")
        self.assertEqual(self.selected_cells(renderer), selected, "after the refined frame")

        changed(lambda: mapper.SetValue(0, 0.2), "iso-value, then a capture")
        mapper.SetSynchronousStillRenders(True)  # (a capture: waits for the background cast)
        window.Render()
        self.assertFalse(mapper.GetLastRenderRefining())
        self.assertEqual(tuple(mapper.GetLastCastSize()), (width, height))
        check_exact("a capture during a background cast")
        camera.Azimuth(25)
        window.Render()
        self.assertFalse(mapper.GetLastRenderRefining())
        self.assertEqual(tuple(mapper.GetLastCastSize()), (width, height))
        check_exact("a synchronous still render")
        mapper.SetSynchronousStillRenders(False)
        window.Render()
        self.assertTrue(mapper.GetLastRenderReusedImage(), "the setting changes no image")
        mapper.SetValue(0, 0.0)
        camera.Azimuth(-25)
        mapper.ProgressiveRefinementOff()  # (the selection cast on this thread, the reference)
        window.Render()
        self.assertEqual(self.selected_cells(renderer), selected, "a selection cast of its own")
        print("full cast %.3f s; coarse frame %.3f s (%d x %d rays), its render %.3f s"
              % (full_seconds, coarse_seconds[1], cast[0], cast[1], coarse_seconds[0]))

    @staticmethod
    def selected_cells(renderer):
        """The cells a hardware selection of the whole viewport selects, sorted."""
        selector = vtkHardwareSelector()
        selector.SetRenderer(renderer)
        selector.SetFieldAssociation(vtkDataObject.FIELD_ASSOCIATION_CELLS)
        width, height = renderer.GetRenderWindow().GetSize()
        selector.SetArea(0, 0, width - 1, height - 1)
        selection = selector.Select()
        cells = set()
        for k in range(selection.GetNumberOfNodes()):
            ids = selection.GetNode(k).GetSelectionList()
            cells.update(int(ids.GetValue(i)) for i in range(ids.GetNumberOfTuples()))
        return sorted(cells)



if __name__ == "__main__":
    unittest.main()
