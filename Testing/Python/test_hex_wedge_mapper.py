"""vtkDirectSurfaceMapper on hexahedra and wedges in a real render window (Xvfb): the depth buffer
against the analytic first crossing along each pixel's ray (higher_order_grids.first_crossing, as
window depth) for straight VTK_QUADRATIC_HEXAHEDRON cells holding a degree-4 polynomial of their
space, curved (bulged) VTK_BIQUADRATIC_QUADRATIC_WEDGE cells holding a plane, and straight
order-3 Lagrange hexahedra and order-4 Bezier wedges holding a Q3 and a P4 x P4 polynomial."""
import unittest

import numpy as np
from vtkmodules.vtkCommonDataModel import (VTK_BEZIER_WEDGE, VTK_BIQUADRATIC_QUADRATIC_WEDGE,
                                           VTK_LAGRANGE_HEXAHEDRON, VTK_QUADRATIC_HEXAHEDRON)

import hex_wedge_grids as hw
import higher_order_grids as hog
from test_hex_wedge import N, PLANE, SPACES
from test_higher_order_mapper import look_at_the_unit_cube
from test_mapper import DEPTH_TOLERANCE, matrix, pixel_rays, scene, window_depth, zbuffer


class HexWedgeMapper(unittest.TestCase):
    def test_depth_equals_the_analytic_surface(self):
        for name, vtk_type, nodes, field, warp in (
                ("VTK_QUADRATIC_HEXAHEDRON straight, serendipity field", VTK_QUADRATIC_HEXAHEDRON, 20,
                 SPACES["serendipity"][0], None),
                ("VTK_BIQUADRATIC_QUADRATIC_WEDGE curved, plane", VTK_BIQUADRATIC_QUADRATIC_WEDGE, 18, PLANE,
                 hw.bulge()),
                ("VTK_LAGRANGE_HEXAHEDRON order 3 straight, Q3 field", VTK_LAGRANGE_HEXAHEDRON, 64,
                 SPACES["Q3"][0], None),
                ("VTK_BEZIER_WEDGE order 4 straight, P4xP4 field", VTK_BEZIER_WEDGE, 75, SPACES["P4xP4"][0],
                 None)):
            mesh = hw.grid(N, vtk_type, nodes, {"f": field.value}, warp=warp)
            window, renderer, mapper, _ = scene(mesh, iso=field.iso, configure=look_at_the_unit_cube)
            window.Render()
            z = zbuffer(window)
            composite = matrix(renderer)
            origins, directions = pixel_rays(composite)
            t, grazing = hog.first_crossing(field, origins, directions)
            truth = np.ones(len(t))
            hit = np.isfinite(t)
            truth[hit] = window_depth(composite, origins[hit] + t[hit, None] * directions[hit])
            truth, grazing = truth.reshape(z.shape), grazing.reshape(z.shape)
            covered, expected = z < 1, truth < 1
            wrong = int(((covered != expected) & ~grazing).sum())
            both = covered & expected & ~grazing
            error = float(np.abs(z - truth)[both].max())
            print(f"mapper, {name}: {int(both.sum())} pixels ({int(grazing.sum())} grazing), {wrong} differ in "
                  f"coverage, max |depth - exact| {error:.2e} (tolerance {DEPTH_TOLERANCE:.2e})")
            self.assertGreater(both.sum(), 3000, f"{name}: expected a visible surface, got {int(both.sum())} pixels")
            self.assertEqual(wrong, 0, f"{name}: expected the analytic coverage, got {wrong} pixels differing")
            self.assertLess(error, DEPTH_TOLERANCE,
                            f"{name}: expected depth within {DEPTH_TOLERANCE:.2e}, got {error:.2e}")


if __name__ == "__main__":
    unittest.main(verbosity=2)
