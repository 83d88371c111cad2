"""vtkDirectSurfaceMapper on straight Lagrange and Bezier cells of order 4 in a real render window
(Xvfb): the depth buffer against the analytic torus (higher_order_grids.first_crossing along each
pixel's ray, as window depth), and the colour against the same field rendered from
VTK_QUADRATIC_TETRA cells where the field is quadratic."""
import unittest

import numpy as np
from vtkmodules.vtkCommonDataModel import (VTK_BEZIER_TETRAHEDRON, VTK_LAGRANGE_TETRAHEDRON,
                                           VTK_QUADRATIC_TETRA)

import higher_order_grids as hog
from test_mapper import DEPTH_TOLERANCE, matrix, pixel_rays, rgba, scene, window_depth, zbuffer


def look_at_the_unit_cube(mapper, actor, renderer):
    camera = renderer.GetActiveCamera()
    camera.SetPosition(1.7, 1.35, 2.5)
    camera.SetFocalPoint(0.5, 0.5, 0.5)
    camera.SetViewAngle(26)


class HigherOrderMapper(unittest.TestCase):
    def test_depth_equals_the_analytic_torus(self):
        field = hog.torus()
        for name, vtk_type in (("Lagrange", VTK_LAGRANGE_TETRAHEDRON), ("Bezier", VTK_BEZIER_TETRAHEDRON)):
            mesh = hog.grid(2, vtk_type, 4, {"f": field.value})
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
            print(f"mapper, {name} order 4 torus: {int(both.sum())} pixels ({int(grazing.sum())} grazing), "
                  f"{wrong} differ in coverage, max |depth - exact| {error:.2e} (tolerance {DEPTH_TOLERANCE:.2e})")
            self.assertGreater(both.sum(), 3000)
            self.assertEqual(wrong, 0, f"expected the torus's coverage, got {wrong} pixels differing")
            self.assertLess(error, DEPTH_TOLERANCE)

    def test_same_picture_as_quadratic_cells(self):
        def quadric(x):
            d = x - np.array([0.47, 0.52, 0.5])
            return d[..., 0] ** 2 + 1.3 * d[..., 1] ** 2 + 0.8 * d[..., 2] ** 2

        images = {}
        for name, vtk_type, order in (("Lagrange 3", VTK_LAGRANGE_TETRAHEDRON, 3),
                                      ("Bezier 4", VTK_BEZIER_TETRAHEDRON, 4),
                                      ("quadratic", VTK_QUADRATIC_TETRA, 2)):
            mesh = hog.grid(2, vtk_type, order, {"f": quadric})
            window, renderer, mapper, _ = scene(mesh, iso=0.1, configure=look_at_the_unit_cube)
            window.Render()
            images[name] = (rgba(window), zbuffer(window))
        colour, depth = images.pop("quadratic")
        for name, (c, z) in images.items():
            colours = int(np.abs(c - colour).max())
            gap = float(np.abs(z - depth).max())
            print(f"mapper, {name} vs VTK_QUADRATIC_TETRA: {int((depth < 1).sum())} pixels, colours within "
                  f"{colours}/255, depth within {gap:.2e}")
            self.assertGreater((depth < 1).sum(), 3000)
            self.assertLessEqual(colours, 1, name)
            self.assertLess(gap, DEPTH_TOLERANCE, name)


if __name__ == "__main__":
    unittest.main(verbosity=2)
