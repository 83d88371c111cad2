"""Hostile input: each case is a mesh or a setting that once crashed, hung or silently rendered
garbage. Every test asserts the contract: a clear error (or a counted warning) and, where an
image is made, the same image as for the sound input."""
import sys
import unittest

import numpy as np
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand, vtkPoints
from vtkmodules.vtkCommonDataModel import (VTK_QUADRATIC_TETRA, VTK_TETRA, vtkCellArray, vtkPlane,
                                           vtkUnstructuredGrid)
from vtkmodules.vtkRenderingCore import vtkCamera

from shared_helpers import Messages
from tetdsr import vtkDirectSurfaceRayCaster

# The unit tet's 4 vertices and 6 edge midpoints, in VTK's node order; field |x|^2, iso 0.1.
CORNERS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
NODES = np.vstack([CORNERS] + [0.5 * (CORNERS[a] + CORNERS[b]) for a, b in EDGES])
FIELD = np.sum(NODES ** 2, axis=1)
SIZE = 24


def raw_grid(points, connectivity, offsets, types, field, name="f"):
    """A grid built from raw arrays: VTK checks none of their sizes against each other."""
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=float), deep=1))
    grid.SetPoints(vtk_points)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(np.asarray(offsets, np.int64), deep=1),
                  numpy_to_vtkIdTypeArray(np.asarray(connectivity, np.int64), deep=1))
    grid.SetCells(numpy_to_vtk(np.asarray(types, np.uint8), deep=1), cells)
    values = numpy_to_vtk(np.ascontiguousarray(field, dtype=float), deep=1)
    values.SetName(name)
    grid.GetPointData().SetScalars(values)
    return grid


def one_tet(points=NODES, field=FIELD, ids=range(10)):
    return raw_grid(points, list(ids), [0, 10], [VTK_QUADRATIC_TETRA], field)


class Run:
    """An update of the filter with its errors and warnings collected."""

    def __init__(self, grid, iso=0.1, configure=None, size=SIZE):
        caster = vtkDirectSurfaceRayCaster()
        messages = Messages(caster)
        self.errors, self.warnings = messages.errors, messages.warnings
        caster.GetExecutive().AddObserver(vtkCommand.ErrorEvent, lambda *args: None)
        caster.SetInputData(grid)
        caster.SetValue(0, iso)
        caster.SetImageSize(size, size)
        if configure:
            configure(caster)
        caster.Update()
        self.caster = caster

    def array(self, name):
        array = self.caster.GetOutput().GetPointData().GetArray(name)
        return None if array is None else vtk_to_numpy(array).copy()

    def hits(self):
        ids = self.array("CellId")
        return 0 if ids is None else int((ids >= 0).sum())

    def said(self, text):
        return any(text in m for m in self.errors + self.warnings)


REFERENCE_HITS = None


def reference_hits():
    global REFERENCE_HITS
    if REFERENCE_HITS is None:
        REFERENCE_HITS = Run(one_tet()).hits()
    return REFERENCE_HITS


class HostileInput(unittest.TestCase):
    def test_reference_renders(self):
        self.assertGreater(reference_hits(), 10)

    def test_offsets_disagree_with_cell_type(self):
        # Two cells claim VTK_QUADRATIC_TETRA but the offsets give 4 ids each.
        run = Run(raw_grid(NODES, list(range(4)) * 2, [0, 4, 8], [VTK_QUADRATIC_TETRA] * 2, FIELD))
        self.assertEqual(run.hits(), 0)
        self.assertTrue(run.said("2 malformed"), run.errors + run.warnings)
        self.assertEqual(run.caster.GetNumberOfMalformedCells(), 2)
        # Offsets out of order and past the end of the connectivity: malformed, never read.
        run = Run(raw_grid(NODES, list(range(10)) * 2, [0, 10, 5, 10 ** 9],
                           [VTK_QUADRATIC_TETRA] * 3, FIELD))
        self.assertEqual(run.caster.GetNumberOfMalformedCells(), 2)
        self.assertEqual(run.hits(), reference_hits(), "the well-formed first cell still renders")

    def test_short_field_array(self):
        run = Run(one_tet(field=FIELD[:2]))
        self.assertTrue(run.said("has 2 tuples for 10 points"), run.errors)

    def test_short_colour_array(self):
        grid = one_tet()
        colours = numpy_to_vtk(np.zeros(2), deep=1)
        colours.SetName("c")
        grid.GetPointData().AddArray(colours)
        run = Run(grid, configure=lambda c: (c.ColorByArrayOn(), c.SetInputArrayToProcess(1, 0, 0, 0, "c")))
        self.assertTrue(run.said("'c' has 2 tuples for 10 points"), run.errors)

    def test_many_copies_of_one_cell(self):
        # 65,536 identical cells once wrapped a 16-bit leaf count to 0 and hung the traversal.
        copies = 65536
        run = Run(raw_grid(NODES, list(range(10)) * copies, np.arange(0, 10 * copies + 1, 10),
                           [VTK_QUADRATIC_TETRA] * copies, FIELD), size=8)
        self.assertEqual(run.caster.GetNumberOfRenderedCells(), copies)
        self.assertGreater(run.hits(), 0)

    def test_image_too_large(self):
        run = Run(one_tet(), configure=lambda c: c.SetImageSize(100000, 100000))
        self.assertTrue(run.said("100000 x 100000 pixels needs"), run.errors)
        self.assertTrue(run.said("GiB"), run.errors)

    def test_iso_value_index_out_of_range(self):
        caster = vtkDirectSurfaceRayCaster()
        errors = []
        caster.AddObserver(vtkCommand.ErrorEvent, calldata_type(VTK_STRING)(lambda o, e, t: errors.append(t)))
        caster.SetIsoValueOpacity(2 ** 31 - 1, 0.5)
        caster.SetIsoValueColor(2 ** 31 - 1, 1, 0, 0)
        caster.SetIsoValueOpacity(-1, 0.5)
        self.assertEqual(len(errors), 3, errors)
        self.assertTrue(all("is outside [0, " in e for e in errors), errors)
        self.assertEqual(caster.GetIsoValueOpacity(2 ** 31 - 1), 1.0)

    def test_negative_mid_edge_id_is_invalid(self):
        run = Run(one_tet(ids=list(range(4)) + [-1] * 6))
        self.assertEqual(run.caster.GetNumberOfInvalidIdCells(), 1)
        self.assertTrue(run.said("node ids outside [0, 10)"), run.errors + run.warnings)
        # ... also in a mesh that mixes cell types (the copying path).
        grid = raw_grid(NODES, list(range(4)) + [-1] * 6 + list(range(4)), [0, 10, 14],
                        [VTK_QUADRATIC_TETRA, VTK_TETRA], FIELD)
        run = Run(grid)
        self.assertEqual(run.caster.GetNumberOfInvalidIdCells(), 1)
        self.assertEqual(run.caster.GetNumberOfRenderedCells(), 1, "the linear tet renders")

    def test_unused_infinite_point_does_not_spoil_the_camera(self):
        points = np.vstack([NODES, [[0, np.inf, 0]]])
        run = Run(one_tet(points=points, field=np.append(FIELD, 0.0)))
        self.assertEqual(run.errors, [])
        self.assertEqual(run.hits(), reference_hits())

    def test_field_scale_does_not_change_the_image(self):
        reference = Run(one_tet())
        for scale in (1e155, 1e300, 1e-200, 1e-300):
            run = Run(one_tet(field=FIELD * scale), iso=0.1 * scale)
            self.assertEqual(run.hits(), reference.hits(), "scale %g" % scale)
            np.testing.assert_allclose(run.array("Depth")[np.isfinite(reference.array("Depth"))],
                                       reference.array("Depth")[np.isfinite(reference.array("Depth"))],
                                       rtol=1e-12, err_msg="scale %g" % scale)

    def test_coordinate_scale_limits(self):
        reference = Run(one_tet())
        for scale in (1e-90, 1e90):  # inside [1e-100, 1e100]: the same picture
            run = Run(one_tet(points=NODES * scale))
            self.assertEqual(run.hits(), reference.hits(), "scale %g" % scale)
        for scale in (1e-103, 1e120):  # outside: skipped with a message naming the limit
            run = Run(one_tet(points=NODES * scale))
            self.assertEqual(run.caster.GetNumberOfOutOfScaleCells(), 1)
            self.assertTrue(run.said("longest edge or box is outside [1e-100, 1e+100]"), run.errors + run.warnings)

    def test_connectivity_edited_in_place(self):
        grid = one_tet()
        run = Run(grid)
        self.assertGreater(run.hits(), 0)
        connectivity = grid.GetCells().GetConnectivityArray()
        vtk_to_numpy(connectivity)[:] = 10 ** 9
        connectivity.Modified()
        run.caster.SetValue(0, 0.2)
        run.caster.Update()
        self.assertEqual(run.caster.GetNumberOfInvalidIdCells(), 1)
        self.assertEqual(run.hits(), 0)

    def test_infinite_colour_value_keeps_the_colour_map(self):
        # An eleventh point, used by no cell, carries the Inf.
        grid = one_tet(points=np.vstack([NODES, [[2.0, 2.0, 2.0]]]), field=np.append(FIELD, 0.0))
        colours = np.append(NODES[:, 0], np.inf)
        array = numpy_to_vtk(colours, deep=1)
        array.SetName("c")
        grid.GetPointData().AddArray(array)
        colour_by = lambda c: (c.ColorByArrayOn(), c.SetInputArrayToProcess(1, 0, 0, 0, "c"))  # noqa: E731
        run = Run(grid, configure=colour_by)
        self.assertEqual(run.errors, [])
        # The automatic range is that of the finite values, [0, 1]: the same colours as that
        # range given explicitly, wherever the interpolated value is finite.
        explicit = Run(grid, configure=lambda c: (colour_by(c), c.SetColorRange(0.0, 1.0)))
        finite = np.isfinite(run.array("ColorValues"))
        self.assertGreater(finite.sum(), 0)
        np.testing.assert_array_equal(run.array("Colors")[finite], explicit.array("Colors")[finite])

    def test_many_translucent_iso_values_are_bounded(self):
        import time

        def configure(caster):
            caster.GenerateValues(10000, 0.01, 0.99)
            for i in range(0, 10000, 7):
                caster.SetIsoValueOpacity(i, 0.01)
        start = time.perf_counter()
        run = Run(one_tet(), configure=configure, size=32)
        elapsed = time.perf_counter() - start
        self.assertEqual(run.errors, [])
        self.assertGreater(run.hits(), 0)
        print("10,000 translucent iso-values, 32 x 32: %.2f s" % elapsed)

    # Found by the fuzzer (Testing/Fuzz/fuzz_filter.py).
    def test_nan_mid_edge_coordinate_skips_the_cell(self):
        points = NODES.copy()
        points[5, 1] = np.nan
        run = Run(one_tet(points=points))
        self.assertEqual(run.caster.GetNumberOfNonFiniteCells(), 1)
        self.assertEqual(run.hits(), 0)

    def test_nan_settings_are_refused(self):
        caster = vtkDirectSurfaceRayCaster()
        errors = []
        caster.AddObserver(vtkCommand.ErrorEvent, calldata_type(VTK_STRING)(lambda o, e, t: errors.append(t)))
        caster.SetCentralDifferenceStep(float("nan"))
        caster.SetNodalRangeWidening(float("nan"))
        self.assertEqual(len(errors), 2, errors)
        self.assertEqual(caster.GetCentralDifferenceStep(), 1e-3)
        self.assertEqual(caster.GetNodalRangeWidening(), 0.25)

    def test_non_finite_colour_and_light_position_are_refused(self):
        # Once accepted: a NaN red drew every hit with red 0, a NaN light position flat ambient
        # grey, with no message.
        reference = Run(one_tet(), configure=lambda c: c.LightAtCameraOff())
        for name, configure in [
                ("SurfaceColor", lambda c: c.SetSurfaceColor(float("nan"), 0.5, 0.5)),
                ("LightPosition", lambda c: (c.LightAtCameraOff(),
                                             c.SetLightPosition(1.0, float("inf"), 1.0)))]:
            run = Run(one_tet(), configure=configure)
            print("%s: %s" % (name, [e.strip().splitlines()[-1] for e in run.errors]))
            self.assertEqual(len(run.errors), 1, run.errors)
            self.assertIn("%s must be finite numbers" % name, run.errors[0])
            if name == "LightPosition":
                self.assertEqual(run.caster.GetLightPosition(), (0.0, 0.0, 1.0))
                np.testing.assert_array_equal(run.array("Colors"), reference.array("Colors"))
            else:
                self.assertEqual(run.caster.GetSurfaceColor(), (1.0, 1.0, 1.0))

    def test_huge_widening_finds_no_false_surface(self):
        reference = Run(one_tet())
        run = Run(one_tet(), configure=lambda c: (c.SetTransverseTest(c.WIDENED_NODAL_RANGE),
                                                  c.SetNodalRangeWidening(1e299)))
        self.assertEqual(run.hits(), reference.hits())
        normals = np.linalg.norm(run.array("Normals")[run.array("CellId") >= 0], axis=1)
        np.testing.assert_allclose(normals, 1.0, atol=1e-9)

    def test_normals_of_a_field_near_the_largest_double(self):
        # |x|^2 scaled to 1.6e308 at the far vertex: gradients overflow unless scaled.
        for mode in (0, 1, 2):  # exact, central differences, nodal interpolation
            run = Run(one_tet(field=FIELD * 1.6e308), iso=0.1 * 1.6e308,
                      configure=lambda c: c.SetNormalMode(mode))
            self.assertEqual(run.hits(), reference_hits(), "mode %d" % mode)
            normals = np.linalg.norm(run.array("Normals")[run.array("CellId") >= 0], axis=1)
            np.testing.assert_allclose(normals, 1.0, atol=1e-9, err_msg="mode %d" % mode)

    def test_messages_name_the_problem(self):
        # A needle (aspect 1e7) is called flat or needle-like, not "zero volume".
        needle = NODES * np.array([1.0, 1e-7, 1e-7])
        run = Run(one_tet(points=needle))
        self.assertTrue(run.said("flat or needle-like"), run.errors + run.warnings)
        # Huge but finite plane normals are fine.
        def plane(caster):
            p = vtkPlane()
            p.SetOrigin(0.2, 0.2, 0.2)
            p.SetNormal(1e200, 1e200, 0.0)
            caster.AddClippingPlane(p)
        run = Run(one_tet(), configure=plane)
        self.assertEqual(run.errors, [])
        self.assertGreater(run.hits(), 0)
        # A camera far away is refused for its distance, not called degenerate.
        def far(caster):
            camera = vtkCamera()
            camera.SetPosition(1e300, 0, 0)
            camera.SetFocalPoint(0, 0, 0)
            camera.SetViewUp(0, 0, 1)
            caster.SetCamera(camera)
        run = Run(one_tet(), configure=far)
        self.assertTrue(run.said("scene diagonals from the scene"), run.errors)
        # A VTK_TETRA with 10 ids is malformed, not of an unsupported type.
        run = Run(raw_grid(NODES, list(range(10)), [0, 10], [VTK_TETRA], FIELD))
        self.assertEqual(run.caster.GetNumberOfMalformedCells(), 1)
        self.assertEqual(run.caster.GetNumberOfUnsupportedCells(), 0)


if __name__ == "__main__":
    unittest.main(verbosity=2)
