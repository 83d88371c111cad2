"""vtkDirectSurfaceRayCaster on VTK_LAGRANGE_TETRAHEDRON and VTK_BEZIER_TETRAHEDRON grids (run with
/usr/bin/python3): straight cells of orders 3 and 4 holding polynomial fields of degree <= P, so
the truth is the analytic field itself (higher_order_grids.first_crossing: sampling and bisection
of the polynomial along each pixel ray, none of TetDSR's code), and vtkContourFilter on the same
grids; colour arrays, normal schemes, clipping with caps, translucency and rational weights,
against the analytic values or against the same field on VTK_QUADRATIC_TETRA cells."""
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import (VTK_BEZIER_TETRAHEDRON, VTK_LAGRANGE_TETRAHEDRON,
                                           VTK_QUADRATIC_TETRA, vtkPlane)
from vtkmodules.vtkFiltersCore import vtkContourFilter
from vtkmodules.vtkRenderingCore import vtkCamera

import higher_order_grids as hog
from shared_helpers import Messages
from tetdsr import vtkDirectSurfaceRayCaster

W, H = 160, 120
DIAGONAL = np.sqrt(3.0)  # of the unit cube every grid here fills
KINDS = {"Lagrange": VTK_LAGRANGE_TETRAHEDRON, "Bezier": VTK_BEZIER_TETRAHEDRON}


def camera(position=(1.7, 1.35, 2.5), focal=(0.5, 0.5, 0.5), angle=22.0):
    c = vtkCamera()
    c.SetPosition(*position)
    c.SetFocalPoint(*focal)
    c.SetViewUp(0.0, 1.0, 0.0)
    c.SetViewAngle(angle)
    return c


def rays(cam):
    return hog.pixel_rays(cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(), cam.GetViewAngle(), W, H)


TRUTH = {}


def truth(name, field, cam):
    """first_crossing of a field for the default camera's rays, computed once per field."""
    if name not in TRUTH:
        origins, directions = rays(cam)
        TRUTH[name] = hog.first_crossing(field, origins, directions) + (origins, directions)
    return TRUTH[name]


def max_angle(normals, gradients):
    """The largest angle between unit normals and gradients (atan2 of |n x g| and n.g: accurate
    near 0, unlike arccos)."""
    cross = np.linalg.norm(np.cross(normals, gradients), axis=1)
    return float(np.max(np.arctan2(cross, np.einsum("ij,ij->i", normals, gradients)), initial=0.0))


def caster_for(mesh, values, cam, configure=None):
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(mesh)
    for i, v in enumerate(values):
        caster.SetValue(i, v)
    caster.SetCamera(cam)
    caster.SetImageSize(W, H)
    if configure:
        configure(caster)
    return caster


def outputs(caster):
    caster.Update()
    pd = caster.GetOutput().GetPointData()
    return {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)).copy() for k in range(pd.GetNumberOfArrays())}


def contour_pixels(mesh, iso, origins, directions):
    """vtkContourFilter's triangles on the same grid, and which pixel rays hit them."""
    contour = vtkContourFilter()
    contour.SetInputData(mesh)
    contour.SetValue(0, iso)
    contour.Update()
    surface = contour.GetOutput()
    if surface.GetNumberOfCells() == 0:
        return 0, np.zeros(len(origins), bool)
    points = vtk_to_numpy(surface.GetPoints().GetData()).astype(float)
    triangles = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return surface.GetNumberOfCells(), hog.triangle_hits(points, triangles, origins, directions)


class AgainstTruth(unittest.TestCase):
    """Depth, coverage and normals of straight order-3 and order-4 cells against the polynomial."""

    def check(self, name, field, order, kind, n=2, min_pixels=3000):
        mesh = hog.grid(n, KINDS[kind], order, {"f": field.value})
        cam = camera()
        caster = caster_for(mesh, [field.iso], cam)
        messages = Messages(caster)
        out = outputs(caster)
        t, grazing, origins, directions = truth(name, field, cam)
        ours, exact = np.isfinite(out["Depth"]), np.isfinite(t)
        self.assertGreater(exact.sum(), min_pixels, f"expected a visible surface, got {exact.sum()} pixels")
        missed = int(np.sum(exact & ~ours & ~grazing))
        false = int(np.sum(ours & ~exact & ~grazing))
        both = ours & exact & ~grazing
        depth = float(np.max(np.abs(out["Depth"][both] - t[both]))) / DIAGONAL
        angle = max_angle(out["Normals"][both], field.gradient(origins[both] + t[both, None] * directions[both]))
        print(f"{kind} order {order}: {mesh.GetNumberOfCells()} cells, "
              f"{int(both.sum())} pixels compared ({int(grazing.sum())} in the grazing band), "
              f"{missed} missed, {false} false, max depth error {depth:.3g} of the diagonal, "
              f"max normal error {angle:.3g} rad")
        self.assertEqual(missed, 0, f"expected 0 missed pixels of {exact.sum()}, got {missed}")
        self.assertEqual(false, 0, f"expected 0 false pixels, got {false}")
        self.assertLessEqual(grazing.sum(), 0.05 * exact.sum(), "expected a grazing band under 5%")
        self.assertLess(depth, 1e-9, f"expected depth within 1e-9 of the diagonal, got {depth:.3g}")
        self.assertLess(angle, 1e-6, f"expected normals within 1e-6 rad of the gradient, got {angle:.3g}")
        cells = 6 * n ** 3
        self.assertEqual(caster.GetNumberOfHigherOrderCells(), cells,
                         f"expected {cells} higher-order cells, got {caster.GetNumberOfHigherOrderCells()}")
        self.assertEqual(caster.GetNumberOfRenderedCells(), cells)
        self.assertEqual(caster.GetNumberOfCurvedCells(), 0, "expected straight cells")
        self.assertEqual(messages.errors, [])
        return mesh, out, t, grazing, origins, directions

    def test_torus_order4(self):
        for kind in KINDS:
            self.check("torus", hog.torus(), 4, kind)

    def test_cubic_order3(self):
        for kind in KINDS:
            self.check("cubic", hog.cubic_blob(), 3, kind)

    def test_contour_misses_what_tetdsr_covers(self):
        # The torus on order-4 Lagrange cells: vtkContourFilter's linear sub-cells approximate
        # it; count the truth's pixels its triangles miss.
        field = hog.torus()
        mesh, out, t, grazing, origins, directions = self.check("torus", field, 4, "Lagrange")
        triangles, contour_hit = contour_pixels(mesh, field.iso, origins, directions)
        exact = np.isfinite(t) & ~grazing
        contour_missed = int(np.sum(exact & ~contour_hit))
        print(f"torus, Lagrange order 4: vtkContourFilter {triangles} triangles, covers "
              f"{int(contour_hit.sum())} pixels, misses {contour_missed} of the truth's {int(exact.sum())} "
              f"(TetDSR covers all of them)")
        self.assertTrue(np.all(np.isfinite(out["Depth"])[exact & ~contour_hit]))
        # A sphere strictly inside one order-4 cell and between its nodes: no nodal value lies
        # below the iso-value, so vtkContourFilter returns nothing.
        for kind in KINDS:
            centre, radius = np.array([0.32, 0.18, 0.1]), 0.05
            field = hog.sphere(centre, radius)
            mesh = hog.grid(1, KINDS[kind], 4, {"f": field.value}, cells=[0])
            cam = camera((0.6, 0.5, 0.9), centre, 14.0)
            nodal = hog.grid(1, VTK_LAGRANGE_TETRAHEDRON, 4, {"f": field.value}, cells=[0])
            self.assertGreater(vtk_to_numpy(nodal.GetPointData().GetArray("f")).min(), field.iso,
                               "expected every node outside the sphere")
            origins, directions = rays(cam)
            t, grazing = hog.first_crossing(field, origins, directions)
            out = outputs(caster_for(mesh, [field.iso], cam))
            triangles, contour_hit = contour_pixels(nodal, field.iso, origins, directions)
            exact = np.isfinite(t)
            ours = np.isfinite(out["Depth"])
            both = ours & exact & ~grazing
            depth = float(np.max(np.abs(out["Depth"][both] - t[both]))) / DIAGONAL
            print(f"sphere inside one {kind} order-4 cell: truth {int(exact.sum())} pixels, TetDSR "
                  f"{int(ours.sum())} ({int(np.sum((ours != exact) & ~grazing))} differ, depth error "
                  f"{depth:.3g}); vtkContourFilter (Lagrange grid) {triangles} triangles, "
                  f"{int(contour_hit.sum())} pixels")
            self.assertEqual(triangles, 0, f"expected vtkContourFilter to find nothing, got {triangles} triangles")
            self.assertGreater(exact.sum(), 2000)
            self.assertEqual(int(np.sum((ours != exact) & ~grazing)), 0)
            self.assertLess(depth, 1e-9)


def quadratic_field(x):
    """A quadric held exactly by cells of every order >= 2."""
    d = x - np.array([0.47, 0.52, 0.5])
    return d[..., 0] ** 2 + 1.3 * d[..., 1] ** 2 + 0.8 * d[..., 2] ** 2 + 0.3 * d[..., 0] * d[..., 1]


def colour_field(x):
    """A cubic colour array (held exactly by order-3 cells)."""
    return x[..., 0] ** 3 - 2.0 * x[..., 1] * x[..., 2] + 0.5 * x[..., 1] ** 2 * x[..., 2] + x[..., 0]


class Appearance(unittest.TestCase):
    def test_colour_array_interpolated_exactly(self):
        field = hog.cubic_blob()
        for kind in KINDS:
            mesh = hog.grid(2, KINDS[kind], 3, {"f": field.value, "colour": colour_field})
            cam = camera()

            def configure(c):
                c.ColorByArrayOn()
                c.SetInputArrayToProcess(1, 0, 0, 0, "colour")

            out = outputs(caster_for(mesh, [field.iso], cam, configure))
            t, grazing, origins, directions = truth("cubic", field, cam)
            both = np.isfinite(out["Depth"]) & np.isfinite(t) & ~grazing
            expected = colour_field(origins[both] + t[both, None] * directions[both])
            error = float(np.max(np.abs(out["ColorValues"][both] - expected)))
            print(f"colour by a cubic array, {kind} order 3: {int(both.sum())} pixels, max error {error:.3g}")
            self.assertGreater(both.sum(), 3000)
            self.assertLess(error, 1e-9, f"expected the analytic colour value, got an error of {error:.3g}")
            self.assertTrue(np.all(np.isnan(out["ColorValues"][~np.isfinite(out["Depth"])])))

    def test_nodal_normals_exact_for_a_global_polynomial(self):
        # A global polynomial of degree <= P has a continuous gradient of degree <= P - 1, so the
        # mean of the cells' gradients at a node is the gradient there, and its interpolation by
        # the cell's shape functions is exact: NODAL_INTERPOLATION must give the analytic normal.
        for field, order in ((hog.cubic_blob(), 3), (hog.torus(), 4)):
            for kind in KINDS:
                mesh = hog.grid(2, KINDS[kind], order, {"f": field.value})
                cam = camera()
                caster = caster_for(mesh, [field.iso], cam,
                                    lambda c: c.SetNormalMode(vtkDirectSurfaceRayCaster.NODAL_INTERPOLATION))
                out = outputs(caster)
                t, grazing, origins, directions = truth("torus" if order == 4 else "cubic", field, cam)
                both = np.isfinite(out["Depth"]) & np.isfinite(t) & ~grazing
                angle = max_angle(out["Normals"][both],
                                  field.gradient(origins[both] + t[both, None] * directions[both]))
                print(f"nodal normals, {kind} order {order}: {int(both.sum())} pixels, max angle {angle:.3g} rad")
                self.assertLess(angle, 1e-6, f"expected the analytic normal, got {angle:.3g} rad off")

    def test_central_differences_and_depth_buffer_normals(self):
        # The paper's other two schemes on order-3 and order-4 cells: central differences of the
        # field (step 1e-3 of the hit cell) are within O(step^2) of the analytic gradient of the
        # cubic; the depth buffer's differences are the surface's normal away from silhouettes
        # (measured on pixels whose four neighbours hit the surface too).
        field = hog.cubic_blob()
        for order in (3, 4):
            for kind in KINDS:
                mesh = hog.grid(2, KINDS[kind], order, {"f": field.value})
                cam = camera()
                t, grazing, origins, directions = truth("cubic", field, cam)
                for mode, limit in ((vtkDirectSurfaceRayCaster.CENTRAL_DIFFERENCES, 1e-4),
                                    (vtkDirectSurfaceRayCaster.DEPTH_BUFFER, 0.1)):
                    out = outputs(caster_for(mesh, [field.iso], cam, lambda c: c.SetNormalMode(mode)))
                    hit = np.isfinite(out["Depth"]) & np.isfinite(t) & ~grazing
                    if mode == vtkDirectSurfaceRayCaster.DEPTH_BUFFER:
                        inner = hit.reshape(H, W).copy()
                        inner[1:-1, 1:-1] &= (hit.reshape(H, W)[:-2, 1:-1] & hit.reshape(H, W)[2:, 1:-1] &
                                              hit.reshape(H, W)[1:-1, :-2] & hit.reshape(H, W)[1:-1, 2:])
                        inner[[0, -1], :] = False
                        inner[:, [0, -1]] = False
                        hit = inner.reshape(-1)
                    gradient = field.gradient(origins[hit] + t[hit, None] * directions[hit])
                    angle = max_angle(out["Normals"][hit], gradient / np.linalg.norm(gradient, axis=1)[:, None])
                    print(f"normal mode {mode}, {kind} order {order}: {int(hit.sum())} pixels, "
                          f"max angle {angle:.3g} rad")
                    self.assertGreater(hit.sum(), 1000)
                    self.assertLess(angle, limit, f"mode {mode}: expected within {limit} rad, got {angle:.3g}")

    def same_as_quadratic(self, order, kind, iso, configure, name):
        """The filter on `kind` cells of `order` and on VTK_QUADRATIC_TETRA cells holding the same
        quadratic field: the same image."""
        cam = camera()
        images = []
        for vtk_type, p in ((KINDS[kind], order), (VTK_QUADRATIC_TETRA, 2)):
            mesh = hog.grid(2, vtk_type, p, {"f": quadratic_field, "colour": quadratic_field})
            images.append(outputs(caster_for(mesh, iso, cam, configure)))
        ours, reference = images
        hit = np.isfinite(reference["Depth"])
        differ = int(np.sum(np.isfinite(ours["Depth"]) != hit))
        depth = float(np.max(np.abs(ours["Depth"][hit] - reference["Depth"][hit]), initial=0)) / DIAGONAL
        colours = int(np.max(np.abs(ours["Colors"].astype(int) - reference["Colors"].astype(int))))
        print(f"{name}, {kind} order {order} vs VTK_QUADRATIC_TETRA: {int(hit.sum())} pixels, "
              f"{differ} differ in coverage, depth {depth:.3g} of the diagonal, colours within {colours}/255")
        self.assertGreater(hit.sum(), 3000)
        self.assertLessEqual(differ, 2, f"expected the same coverage, got {differ} pixels differing")
        self.assertLess(depth, 1e-9)
        self.assertLessEqual(colours, 1, f"expected the same colours, got a difference of {colours}/255")
        return ours, reference

    def test_clipping_plane_with_cap(self):
        plane = vtkPlane()
        plane.SetOrigin(0.5, 0.55, 0.5)
        plane.SetNormal(-0.3, -1.0, 0.2)

        def configure(c):
            c.AddClippingPlane(plane)
            c.SetCapping(vtkDirectSurfaceRayCaster.CAP_BELOW_ISO_VALUE)
            c.SetColorRange(0.0, 0.09)  # (the automatic range is the nodal values', which differ)

        for order, kind in ((3, "Lagrange"), (4, "Bezier"), (4, "Lagrange")):
            ours, reference = self.same_as_quadratic(order, kind, [0.09], configure, "clipped and capped")
            cap = np.isfinite(ours["ColorValues"])
            self.assertGreater(cap.sum(), 1000, "expected a visible cap")
            gap = float(np.max(np.abs(ours["ColorValues"][cap] - reference["ColorValues"][cap])))
            self.assertLess(gap, 1e-12)
            # The cap lies on the plane: its pixels' hit points satisfy the plane's equation.
            cam = camera()
            origins, directions = rays(cam)
            on_cap = cap & (ours["CellId"] >= 0) & (np.abs(ours["ColorValues"] - 0.09) > 1e-3)
            points = origins[on_cap] + ours["Depth"][on_cap, None] * directions[on_cap]
            field_there = quadratic_field(points)
            planar = np.abs((points - plane.GetOrigin()) @ np.array(plane.GetNormal())) / np.linalg.norm(plane.GetNormal())
            capped = field_there < 0.09
            self.assertGreater(capped.sum(), 500)
            self.assertLess(float(planar[capped].max()), 1e-9, "expected cap pixels on the plane")
            self.assertLess(float(np.max(np.abs(ours["ColorValues"][on_cap][capped] - field_there[capped]))), 1e-9,
                            "expected the cap coloured by the field's value")

    def test_translucent_two_iso_values(self):
        def configure(c):
            c.SetIsoValueOpacity(1, 0.45)
            c.SetIsoValueColor(0, 0.9, 0.3, 0.2)

        for order, kind in ((3, "Bezier"), (4, "Lagrange")):
            ours, _ = self.same_as_quadratic(order, kind, [0.03, 0.12], configure, "two iso-values, one translucent")
            alpha = ours["Colors"][np.isfinite(ours["Depth"]), 3]
            # Through the translucent shell twice (1 - 0.55^2 = 0.6975), or onto the opaque core.
            self.assertEqual(set(np.unique(alpha)), {178, 255}, f"got alphas {np.unique(alpha)}")


class RationalWeights(unittest.TestCase):
    def test_unit_weights_render_and_a_differing_weight_is_skipped(self):
        field = hog.cubic_blob()
        cam = camera()
        plain = hog.grid(2, VTK_BEZIER_TETRAHEDRON, 3, {"f": field.value})
        count = plain.GetNumberOfPoints()
        unit = hog.grid(2, VTK_BEZIER_TETRAHEDRON, 3, {"f": field.value}, weights=np.ones(count))
        reference = outputs(caster_for(plain, [field.iso], cam))
        caster = caster_for(unit, [field.iso], cam)
        messages = Messages(caster)
        ours = outputs(caster)
        self.assertGreater(np.isfinite(ours["Depth"]).sum(), 3000)
        for name in reference:
            np.testing.assert_array_equal(ours[name], reference[name], err_msg=name)
        self.assertEqual(caster.GetNumberOfRationalCells(), 0)
        self.assertEqual(messages.warnings, [])
        # One point's weight 1.5: every cell using it is rational, skipped and counted.
        weights = np.ones(count)
        point = int(plain.GetCell(0).GetPointId(12))
        weights[point] = 1.5
        users = sum(1 for c in range(plain.GetNumberOfCells())
                    if point in [plain.GetCell(c).GetPointId(k) for k in range(20)])
        rational = hog.grid(2, VTK_BEZIER_TETRAHEDRON, 3, {"f": field.value}, weights=weights)
        caster = caster_for(rational, [field.iso], cam)
        messages = Messages(caster)
        outputs(caster)
        self.assertEqual(caster.GetNumberOfRationalCells(), users,
                         f"expected {users} rational cells, got {caster.GetNumberOfRationalCells()}")
        self.assertEqual(caster.GetNumberOfRenderedCells(), 48 - users)
        text = " ".join(messages.warnings)
        print(f"one weight 1.5 ({users} cells): {messages.warnings}")
        self.assertIn(f"Skipped {users} rational Bezier cells (rational weights that "
                      "differ within the cell", text)
        self.assertIn("TetDSR renders polynomial Bezier cells only", text)


if __name__ == "__main__":
    unittest.main(verbosity=2)
