"""The wheel's ParaView Python plugin (tetdsr/paraview_plugin.py) in pvpython, on ParaView's own
VTK, against the analytic sphere inside one cell. Run by Scripts/test-wheel.sh as
`pvpython pvpython_plugin_tests.py <Data folder>` with the installed `tetdsr` on PYTHONPATH."""
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import truth  # noqa: E402
import tetdsr  # noqa: E402
from paraview import servermanager  # noqa: E402
from paraview.simple import XMLUnstructuredGridReader  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

DATA = sys.argv.pop(1)
tetdsr.load_paraview_plugin(globals())
W, H = 160, 120


class PluginInPvpython(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.reader = XMLUnstructuredGridReader(FileName=[os.path.join(DATA, "sphere_in_cell.vtu")])
        cls.reader.UpdatePipeline()
        fd = servermanager.Fetch(cls.reader).GetFieldData()
        cls.centre = np.array([fd.GetArray("SphereCentre").GetValue(k) for k in range(3)])
        cls.radius = fd.GetArray("SphereRadius").GetValue(0)

    def cast(self, **properties):
        proxy = DirectSurfaceRayCastPython(Input=self.reader)  # noqa: F821 (LoadPlugin's ns)
        proxy.ContourBy = ["POINTS", "sphere"]
        proxy.ImageSize = [W, H]
        proxy.FitCameraToMesh = 0
        proxy.CameraPosition = list(self.centre + [0.4, -0.7, 1.3])
        proxy.CameraFocalPoint = list(self.centre)
        proxy.CameraViewAngle = 18.0
        for name, value in properties.items():
            setattr(proxy, name, value)
        proxy.UpdatePipeline()
        image = servermanager.Fetch(proxy)
        pd = image.GetPointData()
        return image, {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)) for k in range(pd.GetNumberOfArrays())}

    def truth(self, iso):
        origins, directions = truth.pixel_rays(self.centre + [0.4, -0.7, 1.3], self.centre,
                                               (0, 1, 0), 18.0, W, H)
        sphere = truth.QuadraticQuadric(np.eye(3), np.zeros(3), -self.radius ** 2, self.centre)
        return truth.first_hit_in_box(sphere, origins, directions, iso, -1.0, 1.0)

    def check(self, out, t, unsure):
        ours = np.isfinite(out["Depth"])
        exact = np.isfinite(t)
        wrong = int(np.count_nonzero((ours != exact) & ~unsure))
        self.assertGreater(exact.sum(), 1000)
        self.assertEqual(wrong, 0, f"expected coverage {exact.sum()}, got {ours.sum()}")
        both = ours & exact & ~unsure
        error = float(np.max(np.abs(out["Depth"][both] - t[both]))) / (2 * np.sqrt(3))
        self.assertLess(error, 1e-12, f"expected depth within 1e-12 of the diagonal, got {error:.3g}")
        return ours

    def test_sphere_against_truth_and_properties_reach_the_filter(self):
        image, out = self.cast(Isosurfaces=[0.0])
        self.assertEqual(image.GetDimensions(), (W, H, 1))
        self.assertEqual(sorted(out), ["CellId", "Colors", "Depth", "Normals"])
        self.check(out, *self.truth(0.0))
        # iso-value r'^2 - r^2 is the sphere of radius r', and a red surface without highlights is red.
        bigger = 1.3 * self.radius
        _, out = self.cast(Isosurfaces=[bigger ** 2 - self.radius ** 2], SurfaceColor=[1.0, 0.0, 0.0],
                          Specular=0.0)
        origins, directions = truth.pixel_rays(self.centre + [0.4, -0.7, 1.3], self.centre,
                                               (0, 1, 0), 18.0, W, H)
        sphere = truth.QuadraticQuadric(np.eye(3), np.zeros(3), -bigger ** 2, self.centre)
        hit = self.check(out, *truth.first_hit_in_box(sphere, origins, directions, 0.0, -1.0, 1.0))
        colors = out["Colors"][hit]
        self.assertTrue(np.all(colors[:, 1:3] == 0) and np.all(colors[:, 0] > 0),
                        f"expected red pixels, got e.g. {colors[:3].tolist()}")

    def test_clip_plane_keeps_one_side(self):
        # Keep x <= centre_x: the sphere's pixels on the other side of the plane vanish.
        _, whole = self.cast(Isosurfaces=[0.0])
        _, cut = self.cast(Isosurfaces=[0.0], ClipPlanes=list(self.centre) + [-1.0, 0.0, 0.0])
        origins, directions = truth.pixel_rays(self.centre + [0.4, -0.7, 1.3], self.centre,
                                               (0, 1, 0), 18.0, W, H)
        t, _ = self.truth(0.0)
        seen = np.isfinite(cut["Depth"])
        points = origins[seen] + cut["Depth"][seen, None] * directions[seen]
        self.assertTrue(np.all(points[:, 0] <= self.centre[0] + 1e-12), "expected no hit beyond the plane")
        self.assertLess(seen.sum(), np.isfinite(whole["Depth"]).sum() - 500)

    def test_exact_isosurface_on_the_sphere(self):
        """The plugin's exact contour: vertices on the analytic sphere, its area within the
        estimate, every edge in two triangles."""
        proxy = ExactIsosurfacePython(Input=self.reader)  # noqa: F821 (LoadPlugin's ns)
        proxy.ContourBy = ["POINTS", "sphere"]
        proxy.Isosurfaces = [0.0]
        proxy.UpdatePipeline()
        surface = servermanager.Fetch(proxy)
        self.assertGreater(surface.GetNumberOfPolys(), 20)
        points = vtk_to_numpy(surface.GetPoints().GetData())
        off = float(np.max(np.abs(np.linalg.norm(points - self.centre, axis=1) - self.radius))) / self.radius
        self.assertLess(off, 1e-9, f"expected the vertices on the sphere within 1e-9 r, got {off:.3g}")
        triangles = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
        edges = np.sort(triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        counts = np.unique(edges, axis=0, return_counts=True)[1]
        self.assertTrue(np.all(counts == 2), "expected every edge in two triangles")
        fd = surface.GetFieldData()
        area, estimate = fd.GetArray("Area").GetValue(0), fd.GetArray("AreaError").GetValue(0)
        exact = 4 * np.pi * self.radius ** 2
        self.assertLessEqual(abs(area - exact), estimate + 1e-9 * exact,
                             f"expected area {exact!r} within {estimate:.3g}, got {area!r}")


if __name__ == "__main__":
    unittest.main(verbosity=2)
