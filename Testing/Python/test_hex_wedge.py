"""vtkDirectSurfaceRayCaster on hexahedra and wedges of every kind it reads (run with /usr/bin/python3):
grids of hex_wedge_grids.KINDS built on VTK's own node positions. Straight cells hold a polynomial
of their space (and a second one as a colour array), so the truth is the analytic field itself
(higher_order_grids.first_crossing, none of TetDSR's code); curved cells (hex_wedge_grids.bulge,
which keeps the unit cube's boundary) hold a linear field, a plane in any isoparametric cell.
Also: a sphere inside one cell that vtkContourFilter misses, the output CellId against the
lattice cell of the hit point, clipping with a cap and translucency against the same quadratic
field on VTK_QUADRATIC_TETRA cells, and the cells TetDSR refuses, counted and told."""
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import (
    VTK_BEZIER_HEXAHEDRON, VTK_BEZIER_WEDGE, VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON,
    VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_HEXAHEDRON, VTK_LAGRANGE_HEXAHEDRON, VTK_LAGRANGE_PYRAMID, VTK_LAGRANGE_WEDGE,
    VTK_PYRAMID,
    VTK_QUADRATIC_HEXAHEDRON, VTK_QUADRATIC_LINEAR_WEDGE, VTK_QUADRATIC_PYRAMID, VTK_QUADRATIC_TETRA, VTK_QUADRATIC_WEDGE,
    VTK_TRIQUADRATIC_HEXAHEDRON, VTK_TRIQUADRATIC_PYRAMID, VTK_VOXEL, VTK_WEDGE, vtkPlane, vtkUnstructuredGrid)

import hex_wedge_grids as hw
import higher_order_grids as hog
from shared_helpers import Messages, pick_landing_error
from tetdsr import vtkDirectSurfaceRayCaster
from test_higher_order import (DIAGONAL, caster_for, camera, contour_pixels, max_angle, outputs,
                               quadratic_field, truth)

N = 2  # cubes per axis: 8 hexahedra or 16 wedges
# Curved cells cost ~20x more per ray (subdivision solver) at total degree <= 4, and more with the
# degree (a bent hexahedron of order 2, 3, 4, degree 6, 9, 12: about 1 : 8 : 35 per ray): the
# curved images' size by degree (the same camera, fewer rays).
CURVED_SIZES = {2: (80, 60), 3: (80, 60), 4: (80, 60), 5: (64, 48), 6: (64, 48), 8: (48, 36), 9: (32, 24),
                12: (24, 18)}
CENTRE = np.array([0.48, 0.52, 0.47])


def u(x):
    """Coordinates about CENTRE, as components: (u0, u1, u2)."""
    return (x[..., 0] - CENTRE[0], x[..., 1] - CENTRE[1], x[..., 2] - CENTRE[2])


def analytic(value, gradient, iso, degree):
    """An analytic Field from value(u0, u1, u2) and gradient(u0, u1, u2) (three components)."""
    return hog.Field(lambda x: value(*u(x)), lambda x: np.stack(gradient(*u(x)), axis=-1), iso, degree)


def about_centre(value):
    return lambda x: value(*u(x))


# Per polynomial space: a field whose highest terms span the space (its iso-surface is the
# test's), and a second polynomial of the space as the colour array. Coordinates are physical:
# straight cells are axis-aligned cubes and triangles x [z0, z1], so a polynomial in (x, y, z) of
# the space is one in the cell's (r, s, t).
SPACES = {
    # Trilinear (Q1): VTK_HEXAHEDRON and its relatives.
    "Q1": (analytic(lambda a, b, c: (a + 0.18) * (b + 0.07) * (c - 0.13) + 0.05 * a,
                 lambda a, b, c: ((b + 0.07) * (c - 0.13) + 0.05, (a + 0.18) * (c - 0.13), (a + 0.18) * (b + 0.07)),
                 0.02, 3),
           about_centre(lambda a, b, c: a * b * c - 0.5 * b + 0.3 * a * c)),
    # The 20-node serendipity space: every monomial with exponents <= 2 and at most one 2
    # (degree 4 with x^2 y z).
    "serendipity": (analytic(lambda a, b, c: a * a + b * b + c * c + 0.8 * a * a * b * c,
                          lambda a, b, c: (2 * a + 1.6 * a * b * c, 2 * b + 0.8 * a * a * c, 2 * c + 0.8 * a * a * b),
                          0.33 ** 2, 4),
                    about_centre(lambda a, b, c: a * a * b * c - b * b + c)),
    # P1(x, y) x P1(z): a product of linear factors.
    "P1xP1": (analytic(lambda a, b, c: (a + 0.8 * b + 0.194) * (c + 0.77),
                    lambda a, b, c: (c + 0.77, 0.8 * (c + 0.77), a + 0.8 * b + 0.194),
                    0.1, 2),
              about_centre(lambda a, b, c: (a - 2.0 * b + 0.3) * (c - 0.4))),
    # P2(x, y) x P1(z) (VTK_QUADRATIC_LINEAR_WEDGE): a cylinder widening with z.
    "P2xP1": (analytic(lambda a, b, c: ((a - 0.02) ** 2 + (b + 0.02) ** 2) * (c + 1.47),
                    lambda a, b, c: (2 * (a - 0.02) * (c + 1.47), 2 * (b + 0.02) * (c + 1.47),
                                     (a - 0.02) ** 2 + (b + 0.02) ** 2),
                    0.09, 3),
              about_centre(lambda a, b, c: (a * b - b * b) * (c + 1.0) + a)),
    # VTK_QUADRATIC_WEDGE: P2(x, y) x P1(z) plus z^2 P1(x, y).
    "wedge15": (analytic(lambda a, b, c: a * a + b * b + c * c + 0.6 * a * c * c + 0.5 * b * b * c,
                      lambda a, b, c: (2 * a + 0.6 * c * c, 2 * b + b * c, 2 * c + 1.2 * a * c + 0.5 * b * b),
                      0.33 ** 2, 3),
                about_centre(lambda a, b, c: a * a * c + b * c * c - a)),
    # P2(x, y) x P2(z): the 18-node wedges (degree 4 with x^2 z^2).
    "P2xP2": (analytic(lambda a, b, c: a * a + b * b + c * c + 0.8 * a * a * c * c + 0.5 * a * b * c * c,
                    lambda a, b, c: (2 * a + 1.6 * a * c * c + 0.5 * b * c * c, 2 * b + 0.5 * a * c * c,
                                     2 * c + 1.6 * a * a * c + a * b * c),
                    0.33 ** 2, 4),
              about_centre(lambda a, b, c: a * b * c * c + b * b * c - a * a)),
    # P3(x, y) x P3(z): the wedges of order 3 (degree 6 with x^3 z^3).
    "P3xP3": (analytic(lambda a, b, c: a * a + b * b + c * c + 0.6 * a ** 3 * c ** 3 + 0.5 * a * b * b * c * c,
                    lambda a, b, c: (2 * a + 1.8 * a * a * c ** 3 + 0.5 * b * b * c * c, 2 * b + a * b * c * c,
                                     2 * c + 1.8 * a ** 3 * c * c + a * b * b * c),
                    0.33 ** 2, 6),
              about_centre(lambda a, b, c: a * b * b * c ** 3 - a * a + c)),
    # P4(x, y) x P4(z): the wedges of order 4 (degree 8 with x^4 z^4).
    "P4xP4": (analytic(lambda a, b, c: a * a + b * b + c * c + 0.5 * a ** 4 * c ** 4 + 0.7 * a * a * b * b * c ** 3,
                    lambda a, b, c: (2 * a + 2 * a ** 3 * c ** 4 + 1.4 * a * b * b * c ** 3,
                                     2 * b + 1.4 * a * a * b * c ** 3,
                                     2 * c + 2 * a ** 4 * c ** 3 + 2.1 * a * a * b * b * c * c),
                    0.33 ** 2, 8),
              about_centre(lambda a, b, c: a * a * b * b * c ** 4 - b ** 4 + a)),
    # VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON: Q2 without x^2 y^2 z^k (degree 5 with x^2 y z^2).
    "hex24": (analytic(lambda a, b, c: a * a + b * b + c * c + 0.8 * a * a * b * c * c + 0.5 * a * b * b * c * c,
                    lambda a, b, c: (2 * a + 1.6 * a * b * c * c + 0.5 * b * b * c * c,
                                     2 * b + 0.8 * a * a * c * c + a * b * c * c,
                                     2 * c + 1.6 * a * a * b * c + a * b * b * c),
                    0.33 ** 2, 5),
              about_centre(lambda a, b, c: a * b * b * c * c - a * a + b * c)),
    # Triquadratic (Q2): VTK_TRIQUADRATIC_HEXAHEDRON, Lagrange and Bezier hexahedra of order 2.
    "Q2": (analytic(lambda a, b, c: a * a + b * b + c * c + 3.0 * a * a * b * b * c * c,
                 lambda a, b, c: (2 * a + 6 * a * b * b * c * c, 2 * b + 6 * a * a * b * c * c,
                                  2 * c + 6 * a * a * b * b * c),
                 0.33 ** 2, 6),
           about_centre(lambda a, b, c: a * a * b * b * c * c - b * b + c * a)),
    # Q3: hexahedra of order 3 (degree 9 with x^3 y^3 z^3).
    "Q3": (analytic(lambda a, b, c: a * a + b * b + c * c + 0.8 * a * a * b * c + 4.0 * a ** 3 * b ** 3 * c ** 3,
                 lambda a, b, c: (2 * a + 1.6 * a * b * c + 12 * a * a * b ** 3 * c ** 3,
                                  2 * b + 0.8 * a * a * c + 12 * a ** 3 * b * b * c ** 3,
                                  2 * c + 0.8 * a * a * b + 12 * a ** 3 * b ** 3 * c * c),
                 0.33 ** 2, 9),
           about_centre(lambda a, b, c: a ** 3 * b ** 3 * c ** 3 - b ** 3 + a * c)),
    # Q4: hexahedra of order 4 (degree 12 with x^4 y^4 z^4).
    "Q4": (analytic(lambda a, b, c: a * a + b * b + c * c + 0.5 * a ** 4 + 8.0 * a ** 4 * b ** 4 * c ** 4,
                 lambda a, b, c: (2 * a + 2 * a ** 3 + 32 * a ** 3 * b ** 4 * c ** 4,
                                  2 * b + 32 * a ** 4 * b ** 3 * c ** 4,
                                  2 * c + 32 * a ** 4 * b ** 4 * c ** 3),
                 0.33 ** 2, 12),
           about_centre(lambda a, b, c: a ** 4 * b ** 4 * c ** 4 - b ** 4 + a * c)),
}
# Each kind's space and the total degree of its polynomials (TetDSR counts cells of degree 3 and
# more as higher-order cells), by (type, node count): every kind of hex_wedge_grids.KINDS (one
# added there without a space here is reported as a skipped subtest).
SPACE_OF = {(VTK_HEXAHEDRON, 8): ("Q1", 3), (VTK_VOXEL, 8): ("Q1", 3), (VTK_LAGRANGE_HEXAHEDRON, 8): ("Q1", 3),
            (VTK_BEZIER_HEXAHEDRON, 8): ("Q1", 3), (VTK_QUADRATIC_HEXAHEDRON, 20): ("serendipity", 4),
            (VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON, 24): ("hex24", 5), (VTK_TRIQUADRATIC_HEXAHEDRON, 27): ("Q2", 6),
            (VTK_LAGRANGE_HEXAHEDRON, 27): ("Q2", 6), (VTK_BEZIER_HEXAHEDRON, 27): ("Q2", 6),
            (VTK_LAGRANGE_HEXAHEDRON, 64): ("Q3", 9), (VTK_BEZIER_HEXAHEDRON, 64): ("Q3", 9),
            (VTK_LAGRANGE_HEXAHEDRON, 125): ("Q4", 12), (VTK_BEZIER_HEXAHEDRON, 125): ("Q4", 12),
            (VTK_WEDGE, 6): ("P1xP1", 2), (VTK_LAGRANGE_WEDGE, 6): ("P1xP1", 2), (VTK_BEZIER_WEDGE, 6): ("P1xP1", 2),
            (VTK_QUADRATIC_LINEAR_WEDGE, 12): ("P2xP1", 3), (VTK_QUADRATIC_WEDGE, 15): ("wedge15", 3),
            (VTK_BIQUADRATIC_QUADRATIC_WEDGE, 18): ("P2xP2", 4), (VTK_LAGRANGE_WEDGE, 18): ("P2xP2", 4),
            (VTK_BEZIER_WEDGE, 18): ("P2xP2", 4), (VTK_LAGRANGE_WEDGE, 40): ("P3xP3", 6),
            (VTK_BEZIER_WEDGE, 40): ("P3xP3", 6), (VTK_LAGRANGE_WEDGE, 75): ("P4xP4", 8),
            (VTK_BEZIER_WEDGE, 75): ("P4xP4", 8)}


def skip_unless_covered(test, name, vtk_type, nodes):
    """Skips the current subtest (visibly) for a kind without a space here."""
    if (vtk_type, nodes) not in SPACE_OF:
        test.skipTest(f"{name}: no polynomial space in this test")


NORMAL = np.array([0.3, 0.5, 0.8])
PLANE = hog.Field(lambda x: x @ NORMAL, lambda x: np.broadcast_to(NORMAL, x.shape), 0.8, 1)


def linear_colour(x):
    return 2.0 * x[..., 0] - x[..., 1] + 0.5 * x[..., 2]


def curved_cells(vtk_type, nodes, warp):
    """How many cells of the warped grid are curved: their nodes (control points for Bezier
    cells) are not an affine image of their parametric coordinates (least squares residual)."""
    straight = hw.cell_nodes(vtk_type, nodes, N)
    parametric = np.c_[hw.node_parametric(vtk_type, nodes), np.ones(nodes)]
    count = 0
    for cell in straight:
        moved = warp(cell)
        affine, *_ = np.linalg.lstsq(parametric, moved, rcond=None)
        count += np.abs(parametric @ affine - moved).max() > 1e-9
    return int(count)


def lattice_cell(points, vtk_type):
    """The input cell of the straight N^3 grid holding each point (hex_wedge_grids' order: cubes
    x fastest, two wedges per cube, the lower-left triangle first); -1 for a point within 1e-7
    (of a cube's side) of a cell face, which two cells share."""
    scaled = points * N
    ijk = np.clip(np.floor(scaled), 0, N - 1).astype(int)
    local = scaled - ijk
    clear = np.all((local > 1e-7) & (local < 1 - 1e-7), axis=1)
    cube = ijk[:, 0] + N * (ijk[:, 1] + N * ijk[:, 2])
    if vtk_type in hw.WEDGE_TYPES:
        diagonal = local[:, 0] + local[:, 1] - 1.0
        clear &= np.abs(diagonal) > 1e-7
        cube = 2 * cube + (diagonal > 0)
    return np.where(clear, cube, -1)


def compare(out, t, grazing, origins, directions, field):
    """Coverage, depth and normals of one image against the truth."""
    ours, exact = np.isfinite(out["Depth"]), np.isfinite(t)
    both = ours & exact & ~grazing
    return {"pixels": int(exact.sum()), "both": both, "grazing": int(grazing.sum()),
            "missed": int(np.sum(exact & ~ours & ~grazing)), "false": int(np.sum(ours & ~exact & ~grazing)),
            "depth": float(np.max(np.abs(out["Depth"][both] - t[both]), initial=0.0)) / DIAGONAL,
            "angle": max_angle(out["Normals"][both],
                               field.gradient(origins[both] + t[both, None] * directions[both]))}


CURVED_TRUTH = {}


class EveryKind(unittest.TestCase):
    """Every kind of SPACE_OF in hex_wedge_grids.KINDS, straight with a polynomial of its space
    and curved with a plane."""

    def assert_image(self, label, result, cells, caster, messages, curved, min_pixels=2000):
        print(f"{label}: {cells} cells, {result['pixels']} pixels ({result['grazing']} grazing), "
              f"{result['missed']} missed, {result['false']} false, max depth error {result['depth']:.3g} "
              f"of the diagonal, max normal error {result['angle']:.3g} rad")
        self.assertGreater(result["pixels"], min_pixels,
                           f"{label}: expected a visible surface, got {result['pixels']} pixels")
        self.assertEqual(result["missed"], 0, f"{label}: expected 0 missed pixels, got {result['missed']}")
        self.assertEqual(result["false"], 0, f"{label}: expected 0 false pixels, got {result['false']}")
        self.assertLessEqual(result["grazing"], 0.05 * result["pixels"], f"{label}: expected a grazing band under 5%")
        self.assertLess(result["depth"], 1e-9,
                        f"{label}: expected depth within 1e-9 of the diagonal, got {result['depth']:.3g}")
        self.assertLess(result["angle"], 1e-6,
                        f"{label}: expected normals within 1e-6 rad of the gradient, got {result['angle']:.3g}")
        self.assertEqual(caster.GetNumberOfRenderedCells(), cells,
                         f"{label}: expected {cells} rendered cells, got {caster.GetNumberOfRenderedCells()}")
        self.assertEqual(caster.GetNumberOfCurvedCells(), curved,
                         f"{label}: expected {curved} curved cells, got {caster.GetNumberOfCurvedCells()}")
        self.assertEqual(messages.errors, [], f"{label}: expected no errors")
        self.assertEqual(messages.warnings, [], f"{label}: expected no warnings")

    def colour_error(self, label, out, expected_at, both, origins, directions, t):
        expected = expected_at(origins[both] + t[both, None] * directions[both])
        error = float(np.max(np.abs(out["ColorValues"][both] - expected)))
        self.assertLess(error, 1e-9, f"{label}: expected the analytic colour value, got an error of {error:.3g}")
        self.assertTrue(np.all(np.isnan(out["ColorValues"][~np.isfinite(out["Depth"])])),
                        f"{label}: expected NaN colour values off the surface")
        return error

    def test_straight_cells_hold_a_polynomial_of_their_space(self):
        cam = camera()
        for name, vtk_type, nodes in hw.KINDS:
            with self.subTest(kind=name):
                skip_unless_covered(self, name, vtk_type, nodes)
                space, degree = SPACE_OF[(vtk_type, nodes)]
                scalar, colour_of = SPACES[space]
                mesh = hw.grid(N, vtk_type, nodes, {"f": scalar.value, "colour": colour_of})

                def configure(c):
                    c.ColorByArrayOn()
                    c.SetInputArrayToProcess(1, 0, 0, 0, "colour")

                caster = caster_for(mesh, [scalar.iso], cam, configure)
                messages = Messages(caster)
                out = outputs(caster)
                self.assertEqual(messages.errors, [], f"{name}: expected no errors")
                t, grazing, origins, directions = truth("hex-wedge " + space, scalar, cam)
                result = compare(out, t, grazing, origins, directions, scalar)
                cells = mesh.GetNumberOfCells()
                self.assert_image(f"{name} straight, {space} field", result, cells, caster, messages, 0)
                # Higher order: order 3 or 4 per axis (Lagrange and Bezier cells of 64, 125, 40, 75 nodes).
                higher = cells if nodes in (64, 125, 40, 75) else 0
                got = caster.GetNumberOfHigherOrderCells()
                self.assertEqual(got, higher, f"{name}: expected {higher} cells of order 3-4, got {got}")
                both = result["both"]
                colour_error = self.colour_error(name, out, colour_of, both, origins, directions, t)
                # CellId: the input cell whose lattice box (or wedge) holds the hit point.
                points = origins[both] + t[both, None] * directions[both]
                expected = lattice_cell(points, vtk_type)
                inside = expected >= 0
                wrong = int(np.sum(out["CellId"][both][inside] != expected[inside]))
                print(f"    colour ({space}) max error {colour_error:.3g}; CellId checked at {int(inside.sum())} "
                      f"pixels, {wrong} wrong")
                self.assertGreater(inside.sum(), 0.9 * both.sum())
                self.assertEqual(wrong, 0,
                                 f"{name}: expected every hit's CellId to be its lattice cell, got {wrong} wrong")
                self.assertTrue(np.all(out["CellId"][~np.isfinite(out["Depth"])] == -1))

    def test_curved_cells_hold_a_plane(self):
        warp = hw.bulge()
        cam = camera()
        for name, vtk_type, nodes in hw.KINDS:
            with self.subTest(kind=name):
                skip_unless_covered(self, name, vtk_type, nodes)
                w, h = CURVED_SIZES[SPACE_OF[(vtk_type, nodes)][1]]
                if (w, h) not in CURVED_TRUTH:
                    origins, directions = hog.pixel_rays(cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(),
                                                         cam.GetViewAngle(), w, h)
                    CURVED_TRUTH[(w, h)] = hog.first_crossing(PLANE, origins, directions) + (origins, directions)
                t, grazing, origins, directions = CURVED_TRUTH[(w, h)]
                mesh = hw.grid(N, vtk_type, nodes, {"f": PLANE.value, "colour": linear_colour}, warp=warp)

                def configure(c):
                    c.SetImageSize(w, h)
                    c.ColorByArrayOn()
                    c.SetInputArrayToProcess(1, 0, 0, 0, "colour")

                caster = caster_for(mesh, [PLANE.iso], cam, configure)
                messages = Messages(caster)
                out = outputs(caster)
                self.assertEqual(messages.errors, [], f"{name}: expected no errors")
                result = compare(out, t, grazing, origins, directions, PLANE)
                curved = curved_cells(vtk_type, nodes, warp)
                self.assertGreater(curved, 0)
                self.assert_image(f"{name} curved ({curved} curved, {w} x {h}), plane", result,
                                  mesh.GetNumberOfCells(), caster, messages, curved, min_pixels=0.25 * w * h)
                self.colour_error(name, out, linear_colour, result["both"], origins, directions, t)


class ContourMisses(unittest.TestCase):
    def test_sphere_inside_one_cell(self):
        # A small sphere between the nodes of one cell, away from every point vtkContourFilter's
        # linear subdivision uses (the 27 points of spacing 1/2: nodes, face and body centres):
        # every such value lies above the iso-value, so it contours nothing.
        for vtk_type, nodes, centre, radius in ((VTK_QUADRATIC_HEXAHEDRON, 20, (0.27, 0.24, 0.26), 0.15),
                                                (VTK_BIQUADRATIC_QUADRATIC_WEDGE, 18, (0.24, 0.26, 0.27), 0.12)):
            field = hog.sphere(np.array(centre), radius)
            mesh = hw.grid(1, vtk_type, nodes, {"f": field.value})
            nodal = vtk_to_numpy(mesh.GetPointData().GetArray("f"))
            self.assertGreater(nodal.min(), field.iso, "expected every node outside the sphere")
            cam = camera(np.array(centre) + (0.5, 0.4, 0.8), centre, 24.0)
            origins, directions = hog.pixel_rays(cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(),
                                                 cam.GetViewAngle(), 160, 120)
            t, grazing = hog.first_crossing(field, origins, directions)
            caster = caster_for(mesh, [field.iso], cam)
            out = outputs(caster)
            triangles, contour_hit = contour_pixels(mesh, field.iso, origins, directions)
            exact, ours = np.isfinite(t), np.isfinite(out["Depth"])
            both = ours & exact & ~grazing
            differ = int(np.sum((ours != exact) & ~grazing))
            depth = float(np.max(np.abs(out["Depth"][both] - t[both]))) / DIAGONAL
            name = "VTK_QUADRATIC_HEXAHEDRON" if nodes == 20 else "VTK_BIQUADRATIC_QUADRATIC_WEDGE"
            print(f"sphere inside one {name}: truth {int(exact.sum())} pixels, TetDSR {int(ours.sum())} "
                  f"({differ} differ, depth error {depth:.3g}); vtkContourFilter {triangles} triangles, "
                  f"{int(contour_hit.sum())} pixels")
            self.assertEqual(triangles, 0, f"expected vtkContourFilter to find nothing, got {triangles} triangles")
            self.assertGreater(exact.sum(), 2000)
            self.assertEqual(differ, 0, f"expected TetDSR to cover the sphere's pixels, got {differ} differing")
            self.assertLess(depth, 1e-9)


def quadratic_images(iso, configure):
    """The filter on the quadratic field in VTK_QUADRATIC_HEXAHEDRON, 18-node wedge and
    VTK_QUADRATIC_TETRA grids of [0, 1]^3, the same camera."""
    cam = camera()
    fields = {"f": quadratic_field, "colour": quadratic_field}
    meshes = {"VTK_QUADRATIC_HEXAHEDRON": hw.grid(N, VTK_QUADRATIC_HEXAHEDRON, 20, fields),
              "VTK_BIQUADRATIC_QUADRATIC_WEDGE": hw.grid(N, VTK_BIQUADRATIC_QUADRATIC_WEDGE, 18, fields),
              "VTK_QUADRATIC_TETRA": hog.grid(N, VTK_QUADRATIC_TETRA, 2, fields)}
    return {name: outputs(caster_for(mesh, iso, cam, configure)) for name, mesh in meshes.items()}


class Appearance(unittest.TestCase):
    def same_as_quadratic_tets(self, iso, configure, label):
        images = quadratic_images(iso, configure)
        reference = images.pop("VTK_QUADRATIC_TETRA")
        hit = np.isfinite(reference["Depth"])
        for name, ours in images.items():
            differ = int(np.sum(np.isfinite(ours["Depth"]) != hit))
            depth = float(np.max(np.abs(ours["Depth"][hit] - reference["Depth"][hit]), initial=0)) / DIAGONAL
            colours = int(np.max(np.abs(ours["Colors"].astype(int) - reference["Colors"].astype(int))))
            print(f"{label}, {name} vs VTK_QUADRATIC_TETRA: {int(hit.sum())} pixels, {differ} differ in "
                  f"coverage, depth {depth:.3g} of the diagonal, colours within {colours}/255")
            self.assertGreater(hit.sum(), 3000)
            self.assertLessEqual(differ, 2, f"{name}: expected the same coverage, got {differ} pixels differing")
            self.assertLess(depth, 1e-9, f"{name}: expected the same depth, got {depth:.3g} of the diagonal")
            self.assertLessEqual(colours, 1, f"{name}: expected the same colours, got a difference of {colours}/255")
        return images, reference

    def test_clipping_plane_with_cap(self):
        plane = vtkPlane()
        plane.SetOrigin(0.5, 0.55, 0.5)
        plane.SetNormal(-0.3, -1.0, 0.2)

        def configure(c):
            c.AddClippingPlane(plane)
            c.SetCapping(vtkDirectSurfaceRayCaster.CAP_BELOW_ISO_VALUE)
            c.SetColorRange(0.0, 0.09)

        images, reference = self.same_as_quadratic_tets([0.09], configure, "clipped and capped")
        for name, ours in images.items():
            cap = np.isfinite(ours["ColorValues"])
            self.assertGreater(cap.sum(), 1000, f"{name}: expected a visible cap")
            gap = float(np.max(np.abs(ours["ColorValues"][cap] - reference["ColorValues"][cap])))
            self.assertLess(gap, 1e-12, f"{name}: expected the cap's values of the tets, got a difference of {gap:.3g}")

    def test_translucent_two_iso_values(self):
        def configure(c):
            c.SetIsoValueOpacity(1, 0.45)
            c.SetIsoValueColor(0, 0.9, 0.3, 0.2)

        images, _ = self.same_as_quadratic_tets([0.03, 0.12], configure, "two iso-values, one translucent")
        for name, ours in images.items():
            alpha = ours["Colors"][np.isfinite(ours["Depth"]), 3]
            # Through the translucent shell twice (1 - 0.55^2 = 0.6975), or onto the opaque core.
            self.assertEqual(set(np.unique(alpha)), {178, 255}, f"{name}: got alphas {np.unique(alpha)}")


def with_extra_cells(mesh, points, cells):
    """A copy of `mesh` with `points` new points (far outside the view, value 1 of every array)
    and cells appended: (type, ids among the new points)."""
    out = vtkUnstructuredGrid()
    out.DeepCopy(mesh)
    first = out.GetNumberOfPoints()
    for k in range(points):
        out.GetPoints().InsertNextPoint(5.0 + 0.01 * k, 5.0, 5.0)
        for a in range(out.GetPointData().GetNumberOfArrays()):
            out.GetPointData().GetArray(a).InsertNextValue(1.0)
    for vtk_type, count in cells:
        out.InsertNextCell(vtk_type, count, list(range(first, first + count)))
    return out


class VtkConvention(unittest.TestCase):
    """Cells as VTK itself builds them (vtkCellTypeSource, every hexahedron and wedge type it makes in
    VTK 9.2) are not inverted; mirrored ones are."""

    def test_cell_type_source_cells_are_not_inverted(self):
        cases = [(VTK_HEXAHEDRON, 1), (VTK_QUADRATIC_HEXAHEDRON, 2),
                 (VTK_LAGRANGE_HEXAHEDRON, 3), (VTK_BEZIER_HEXAHEDRON, 2), (VTK_WEDGE, 1), (VTK_QUADRATIC_WEDGE, 2),
                 (VTK_LAGRANGE_WEDGE, 3), (VTK_BEZIER_WEDGE, 2), (VTK_PYRAMID, 1), (VTK_QUADRATIC_PYRAMID, 2),
                 (VTK_TRIQUADRATIC_PYRAMID, 2)]
        x_field = hog.Field(lambda x: x[..., 0], None, 0.5, 1)
        for vtk_type, order in cases:
            with self.subTest(vtk_type=vtk_type):
                for mirrored in (False, True):
                    # VTK's own cells, or their mirror images (x -> 1 - x: every cell reversed).
                    mesh = type_source_mesh(vtk_type, order, (lambda x: x * [-1.0, 1.0, 1.0] + [1.0, 0.0, 0.0])
                                            if mirrored else None, x_field)
                    cells = mesh.GetNumberOfCells()
                    caster = vtkDirectSurfaceRayCaster()
                    caster.SetInputData(mesh)
                    caster.SetInputArrayToProcess(0, 0, 0, 0, "f")
                    caster.SetValue(0, x_field.iso)
                    caster.SetImageSize(4, 4)
                    caster.Update()
                    expected = cells if mirrored else 0
                    print(f"vtkCellTypeSource type {vtk_type} order {order}{' mirrored' if mirrored else ''}: "
                          f"{cells} cells, {caster.GetNumberOfRenderedCells()} rendered, "
                          f"{caster.GetNumberOfInvertedCells()} inverted")
                    self.assertEqual(caster.GetNumberOfRenderedCells(), cells)
                    self.assertEqual(caster.GetNumberOfInvertedCells(), expected,
                                     f"type {vtk_type}: expected {expected} inverted cells, "
                                     f"got {caster.GetNumberOfInvertedCells()}")


def type_source_mesh(vtk_type, order, warp, field):
    """vtkCellTypeSource's cells of a type (2 x 2 x 2 blocks) in the unit cube, bent by `warp` (or
    not), with the point arrays "f" (`field`, active) and "colour" (linear_colour)."""
    from vtkmodules.vtkFiltersSources import vtkCellTypeSource
    source = vtkCellTypeSource()
    source.SetCellType(vtk_type)
    source.SetCellOrder(order)
    source.SetBlocksDimensions(2, 2, 2)
    source.Update()
    mesh = vtkUnstructuredGrid()
    mesh.DeepCopy(source.GetOutput())
    x = vtk_to_numpy(mesh.GetPoints().GetData()).astype(np.float64) / 2.0  # [0, 2]^3 to the unit cube
    x = warp(x) if warp is not None else x
    points = numpy_to_vtk(np.ascontiguousarray(x), deep=1)
    mesh.GetPoints().SetData(points)
    for name, values in (("f", field.value(x)), ("colour", linear_colour(x))):
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
        array.SetName(name)
        mesh.GetPointData().AddArray(array)
    mesh.GetPointData().SetActiveScalars("f")
    return mesh


class PickParametric(unittest.TestCase):
    """A pick's parametric coordinates are VTK's (r, s, t) of the cell, whatever cube TetDSR solves
    it in: VTK's own map of the picked cell (EvaluateLocation) there lands on the picked point,
    for wedges (straight: triangle x segment; bent: the collapsed cube) and the three pyramids
    (their collapsed cubes; the 19-node one's parametric cell is a pyramid)."""

    def test_picks_land_on_their_point(self):
        cam = camera()
        w, h = 40, 30
        for name, vtk_type, order in (("VTK_WEDGE", VTK_WEDGE, 1), ("VTK_QUADRATIC_WEDGE", VTK_QUADRATIC_WEDGE, 2),
                                      ("VTK_LAGRANGE_WEDGE", VTK_LAGRANGE_WEDGE, 3), ("VTK_PYRAMID", VTK_PYRAMID, 1),
                                      ("VTK_QUADRATIC_PYRAMID", VTK_QUADRATIC_PYRAMID, 2),
                                      ("VTK_TRIQUADRATIC_PYRAMID", VTK_TRIQUADRATIC_PYRAMID, 2)):
            for label, warp in (("straight", None), ("curved", hw.bulge())):
                with self.subTest(type=name, shape=label):
                    mesh = type_source_mesh(vtk_type, order, warp, PLANE)
                    caster = caster_for(mesh, [PLANE.iso], cam, lambda c: c.SetImageSize(w, h))
                    depth = outputs(caster)["Depth"].reshape(h, w)
                    checked, worst = pick_landing_error(caster, mesh, depth, 3)
                    print(f"{name} {label}: {checked} picks, VTK's map at the pick's (r, s, t) within {worst:.3g} "
                          f"of the pick")
                    self.assertGreater(checked, 20)
                    self.assertLess(worst, 1e-12)


# The products of two different coordinates (and linear terms): in the space of every
# VTK_QUADRATIC_PYRAMID of vtkCellTypeSource's cube (which holds z^2 and x y, x z, y z for a
# pyramid along z, but not x^2 or y^2: measured with its InterpolateFunctions), so its straight
# cells hold it exactly. A hyperboloid.
MIXED = analytic(lambda a, b, c: (a + 0.1) * (b - 0.05) + (b + 0.02) * (c - 0.1) + 0.7 * c * a,
                 lambda a, b, c: (b - 0.05 + 0.7 * c, a + 0.1 + c - 0.1, b + 0.02 + 0.7 * a), 0.01, 2)


class Pyramids(unittest.TestCase):
    """VTK_PYRAMID (a collapsed trilinear hexahedron), VTK_QUADRATIC_PYRAMID (a collapsed
    triquadratic one) and VTK_TRIQUADRATIC_PYRAMID (rational; a collapsed cube of degree 3 in
    HexahedronTables.cpp's coordinates) hold any linear field exactly, straight or curved: vtkCellTypeSource's
    pyramids filling the unit cube, bent by hw.bulge, with the plane's field, against the plane;
    straight quadratic pyramids also hold MIXED, against its quadric."""

    def pyramids(self, vtk_type, warp, field=None):
        return type_source_mesh(vtk_type, 1, warp, field or PLANE)

    def test_pyramids_hold_a_plane(self):
        cam = camera()
        w, h = 80, 60
        origins, directions = hog.pixel_rays(cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(),
                                             cam.GetViewAngle(), w, h)
        truths = {}
        for name, vtk_type, label, warp, field in (
                ("VTK_PYRAMID", VTK_PYRAMID, "straight", None, PLANE),
                ("VTK_PYRAMID", VTK_PYRAMID, "curved", hw.bulge(), PLANE),
                ("VTK_QUADRATIC_PYRAMID", VTK_QUADRATIC_PYRAMID, "straight", None, PLANE),
                ("VTK_QUADRATIC_PYRAMID", VTK_QUADRATIC_PYRAMID, "curved", hw.bulge(), PLANE),
                ("VTK_QUADRATIC_PYRAMID", VTK_QUADRATIC_PYRAMID, "straight, mixed products", None, MIXED),
                ("VTK_TRIQUADRATIC_PYRAMID", VTK_TRIQUADRATIC_PYRAMID, "straight", None, PLANE),
                ("VTK_TRIQUADRATIC_PYRAMID", VTK_TRIQUADRATIC_PYRAMID, "curved", hw.bulge(), PLANE)):
            with self.subTest(type=name, shape=label):
                if id(field) not in truths:
                    truths[id(field)] = hog.first_crossing(field, origins, directions)
                t, grazing = truths[id(field)]
                mesh = self.pyramids(vtk_type, warp, field)

                def configure(c):
                    c.SetImageSize(w, h)
                    c.ColorByArrayOn()
                    c.SetInputArrayToProcess(1, 0, 0, 0, "colour")

                caster = caster_for(mesh, [field.iso], cam, configure)
                messages = Messages(caster)
                out = outputs(caster)
                result = compare(out, t, grazing, origins, directions, field)
                cells = mesh.GetNumberOfCells()
                print(f"{name} {label}: {cells} cells, {caster.GetNumberOfRenderedCells()} rendered, "
                      f"{caster.GetNumberOfInvertedCells()} inverted, {result['pixels']} pixels, "
                      f"{result['missed']} missed, {result['false']} false, depth {result['depth']:.3g}, "
                      f"normal {result['angle']:.3g} rad")
                self.assertGreater(result["pixels"], 0.25 * w * h)
                self.assertEqual(result["missed"], 0, f"{label}: expected 0 missed pixels, got {result['missed']}")
                self.assertEqual(result["false"], 0, f"{label}: expected 0 false pixels, got {result['false']}")
                self.assertLess(result["depth"], 1e-9)
                self.assertLess(result["angle"], 1e-6)
                self.assertEqual(caster.GetNumberOfRenderedCells(), cells)
                self.assertEqual(caster.GetNumberOfInvertedCells(), 0)
                self.assertEqual(messages.errors, [])
                self.assertEqual(messages.warnings, [])
                EveryKind.colour_error(self, label, out, linear_colour, result["both"], origins, directions, t)


class Refusals(unittest.TestCase):
    """Cells TetDSR does not read: skipped, counted by kind, told in a warning; the rest of the
    mesh renders as without them."""

    def test_refused_cells_are_counted_and_told(self):
        scalar = SPACES["Q1"][0]
        cam = camera()
        good = hw.grid(N, VTK_HEXAHEDRON, 8, {"f": scalar.value})
        reference = outputs(caster_for(good, [scalar.iso], cam))
        # Lagrange hexahedra and Bezier wedges of order 5 (216 and 126 ids: VTK reads the order
        # from the count), a Lagrange pyramid (a type not read: VTK 9.2 has no cell class of it),
        # a hexahedron of 7 ids.
        bad = with_extra_cells(good, 216, [(VTK_LAGRANGE_HEXAHEDRON, 216), (VTK_BEZIER_WEDGE, 126),
                                           (VTK_LAGRANGE_PYRAMID, 14), (VTK_HEXAHEDRON, 7)])
        caster = caster_for(bad, [scalar.iso], cam)
        messages = Messages(caster)
        out = outputs(caster)
        counts = {"order too high": caster.GetNumberOfOrderTooHighCells(),
                  "unsupported": caster.GetNumberOfUnsupportedCells(),
                  "malformed": caster.GetNumberOfMalformedCells(), "rendered": caster.GetNumberOfRenderedCells()}
        print(f"refused: {counts}; warnings: {[w.split('): ', 1)[-1][:70] + '...' for w in messages.warnings]}")
        expected = {"order too high": 2, "unsupported": 1, "malformed": 1, "rendered": 8}
        self.assertEqual(counts, expected, f"expected {expected}, got {counts}")
        text = " ".join(messages.warnings)
        self.assertIn("Skipped 2 cells of an order TetDSR does not read", text)
        self.assertIn("Skipped 1 cells of a type TetDSR does not read", text)
        self.assertIn("not VTK_LAGRANGE_PYRAMID or VTK_BEZIER_PYRAMID: VTK 9.2 has no cell class of the type", text)
        self.assertIn("Skipped 1 malformed cells: a number of node ids that does not fit the type", text)
        self.assertIn("8 for VTK_HEXAHEDRON", text)
        self.assertEqual(messages.errors, [])
        for name in reference:
            np.testing.assert_array_equal(out[name], reference[name], err_msg=name)

    def test_rational_bezier_wedges(self):
        field = SPACES["P2xP2"][0]
        cam = camera()
        plain = hw.grid(N, VTK_BEZIER_WEDGE, 18, {"f": field.value})
        count = plain.GetNumberOfPoints()

        def weighted(weights):
            mesh = hw.grid(N, VTK_BEZIER_WEDGE, 18, {"f": field.value})
            array = numpy_to_vtk(np.ascontiguousarray(weights, dtype=np.float64), deep=1)
            array.SetName("RationalWeights")
            mesh.GetPointData().SetRationalWeights(array)
            return mesh

        reference = outputs(caster_for(plain, [field.iso], cam))
        caster = caster_for(weighted(np.ones(count)), [field.iso], cam)
        messages = Messages(caster)
        ours = outputs(caster)
        self.assertGreater(np.isfinite(ours["Depth"]).sum(), 3000)
        for name in reference:
            np.testing.assert_array_equal(ours[name], reference[name], err_msg=name)
        self.assertEqual(caster.GetNumberOfRationalCells(), 0)
        self.assertEqual(messages.warnings, [])
        # One control point's weight 1.5 (the centre of the grid): every wedge using it is
        # rational, skipped and counted.
        weights = np.ones(count)
        point = int(np.argmin(np.linalg.norm(vtk_to_numpy(plain.GetPoints().GetData()) - 0.5, axis=1)))
        weights[point] = 1.5
        users = sum(1 for c in range(plain.GetNumberOfCells())
                    if point in [plain.GetCell(c).GetPointId(k) for k in range(18)])
        caster = caster_for(weighted(weights), [field.iso], cam)
        messages = Messages(caster)
        outputs(caster)
        print(f"one weight 1.5 ({users} of {plain.GetNumberOfCells()} Bezier wedges): rational "
              f"{caster.GetNumberOfRationalCells()}, rendered {caster.GetNumberOfRenderedCells()}")
        self.assertEqual(caster.GetNumberOfRationalCells(), users,
                         f"expected {users} rational cells, got {caster.GetNumberOfRationalCells()}")
        self.assertEqual(caster.GetNumberOfRenderedCells(), plain.GetNumberOfCells() - users)
        text = " ".join(messages.warnings)
        self.assertIn(f"Skipped {users} rational Bezier cells (rational weights that differ within the cell", text)
        self.assertIn("TetDSR renders polynomial Bezier cells only", text)


if __name__ == "__main__":
    unittest.main(verbosity=2)
