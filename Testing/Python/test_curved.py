"""Curved (isoparametric) cells through the VTK filter, on gmsh order-2 meshes with mid-edge nodes
on the curved geometry (Testing/Data/curved_*.vtu, made by Scripts/make_curved_meshes.py).

Truth: for the field "linear" (a . x, represented exactly by curved cells) the surface is the
plane a . x = c inside the mesh: depth from the exact ray/plane intersection, inside-ness from the
brute-force reference (curved_reference.py: VTK's own shape functions, subdivision and Newton,
independent of TetDSR). For the field "quadratic" the reference gives depth and normal.
Pixels the reference puts in its band (grazing or near-tangent roots, hits within 1e-7 of the
mesh boundary) are left out and counted. The same renders with the mid-edge nodes moved to their
edges' midpoints (what TetDSR drew before) show what the curvature changes.

Usage: test_curved.py <folder with curved_ball.vtu and curved_part.vtu>
"""
import os
import sys
import time
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable, vtkIdList
from vtkmodules.vtkRenderingCore import vtkCamera

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import curved_reference as reference  # noqa: E402

from tetdsr import vtkDirectSurfaceRayCaster  # noqa: E402

DATA = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    os.path.dirname(__file__), "..", "Data")
SIZE = 48
A = np.array([0.3, -0.5, 0.8])  # the "linear" field's gradient (Scripts/make_curved_meshes.py)


def read(name):
    return reference.read_vtu(os.path.join(DATA, name))


def camera_of(c):
    camera = vtkCamera()
    camera.SetPosition(*c["position"])
    camera.SetFocalPoint(*c["focal_point"])
    camera.SetViewUp(*c["view_up"])
    camera.SetViewAngle(c["view_angle"])
    return camera


def render(grid, array, iso, cam, color_array=None):
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(grid)
    caster.SetInputArrayToProcess(0, 0, 0, 0, array)
    if color_array:
        caster.SetInputArrayToProcess(1, 0, 0, 0, color_array)
        caster.ColorByArrayOn()
    caster.SetValue(0, iso)
    caster.SetCamera(camera_of(cam))
    caster.SetImageSize(SIZE, SIZE)
    start = time.perf_counter()
    caster.Update()
    seconds = time.perf_counter() - start
    pd = caster.GetOutput().GetPointData()
    out = {n: vtk_to_numpy(pd.GetArray(n)).copy() for n in ("Depth", "Normals", "CellId")}
    if color_array:
        out["ColorValues"] = vtk_to_numpy(pd.GetArray("ColorValues")).copy()
    out["seconds"] = seconds
    out["caster"] = caster
    return out


def angles(a, b):
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    b = b / np.linalg.norm(b, axis=1, keepdims=True)
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, axis=1))


def compare(image, truth_depth, truth_normal, band, diagonal):
    """Misses, false hits, max depth error / diagonal, max normal error over pixels outside the
    band; and the pixels compared."""
    keep = ~band
    hit = np.isfinite(image["Depth"])
    truth_hit = np.isfinite(truth_depth)
    misses = int(np.sum(keep & truth_hit & ~hit))
    false = int(np.sum(keep & ~truth_hit & hit))
    both = keep & hit & truth_hit
    depth = float(np.max(np.abs(image["Depth"][both] - truth_depth[both]), initial=0)) / diagonal
    normal = float(np.max(angles(image["Normals"][both], truth_normal[both]), initial=0))
    return dict(compared=int(keep.sum()), band=int(band.sum()), hits=int(both.sum()),
                misses=misses, false=false, depth=depth, normal=normal)


CASES = {
    "curved_ball.vtu": dict(
        linear=0.15, quadratic=0.8,
        cameras=[dict(position=(3.2, 1.9, 2.5), focal_point=(0, 0, 0), view_up=(0, 0, 1),
                      view_angle=30),
                 dict(position=(0.4, 0.5, -4.0), focal_point=(0, 0, 0), view_up=(0, 1, 0),
                      view_angle=28)]),
    "curved_part.vtu": dict(
        linear=0.1, quadratic=1.5,
        cameras=[dict(position=(4.5, -5.0, 4.0), focal_point=(0, 0, 0), view_up=(0, 0, 1),
                      view_angle=30)]),
}


class CurvedMeshes(unittest.TestCase):
    rows = []

    @classmethod
    def tearDownClass(cls):
        print("\n| mesh, field, camera | renderer | pixels compared (band) | misses / false | "
              "max depth error / diagonal | max normal error (rad) | seconds |")
        print("|---|---|---|---|---|---|---|")
        for row in cls.rows:
            print("| %s | %s | %d (%d) | %d / %d | %.1e | %.1e | %.3f |" % row)

    def check(self, name, field, iso, cam, k):
        grid = read(name)
        mesh = reference.CurvedMesh(grid, field)
        ref = reference.render_reference(mesh, field, iso, cam, SIZE, SIZE)
        band = reference.on_band(ref)
        if field == "linear":
            # Depth from the exact plane; the reference decides only whether the ray meets the
            # plane inside the mesh (and agrees with the plane where it does, asserted below).
            origins, directions = reference.pixel_rays(cam, SIZE, SIZE)
            t = (iso - origins @ A) / (directions @ A)
            truth_depth = np.where(np.isfinite(ref.depth), t, np.inf)
            truth_normal = np.tile(A, (SIZE * SIZE, 1))
            agree = np.isfinite(ref.depth) & ~band
            self.assertLess(np.max(np.abs(ref.depth[agree] - t[agree])) / ref.diagonal, 1e-12)
        else:
            truth_depth, truth_normal = ref.depth, ref.normal
        label = "%s, %s, camera %d" % (name[:-4], field, k)
        curved = render(grid, field, iso, cam)
        flat = render(reference.straightened(grid), field, iso, cam)
        caster = curved["caster"]
        self.assertGreater(caster.GetNumberOfCurvedCells(), 0)
        self.assertEqual(caster.GetNumberOfTangledCells(), 0)
        self.assertEqual(caster.GetNumberOfRenderedCells(), grid.GetNumberOfCells())
        self.assertEqual(caster.GetNumberOfUncertifiedHits(), 0, label)
        result = compare(curved, truth_depth, truth_normal, band, ref.diagonal)
        before = compare(flat, truth_depth, truth_normal, band, ref.diagonal)
        for r, who, image in ((result, "TetDSR", curved), (before, "TetDSR, mid-edge nodes ignored", flat)):
            self.rows.append((label, who, r["compared"], r["band"], r["misses"], r["false"],
                              r["depth"], r["normal"], image["seconds"]))
        self.assertGreater(result["hits"], 200, label)
        self.assertEqual(result["misses"], 0, label)
        self.assertEqual(result["false"], 0, label)
        self.assertLessEqual(result["depth"], 1e-9, label)
        self.assertLessEqual(result["normal"], 1e-7, label)
        # The curvature matters: ignoring it moves the surface by far more than that.
        self.assertGreater(before["depth"], 1e-4, label)

    def test_ball_linear(self):
        for k, cam in enumerate(CASES["curved_ball.vtu"]["cameras"]):
            self.check("curved_ball.vtu", "linear", CASES["curved_ball.vtu"]["linear"], cam, k)

    def test_ball_quadratic(self):
        for k, cam in enumerate(CASES["curved_ball.vtu"]["cameras"]):
            self.check("curved_ball.vtu", "quadratic", CASES["curved_ball.vtu"]["quadratic"], cam, k)

    def test_part_linear(self):
        cam = CASES["curved_part.vtu"]["cameras"][0]
        self.check("curved_part.vtu", "linear", CASES["curved_part.vtu"]["linear"], cam, 0)

    def test_part_quadratic(self):
        cam = CASES["curved_part.vtu"]["cameras"][0]
        self.check("curved_part.vtu", "quadratic", CASES["curved_part.vtu"]["quadratic"], cam, 0)

    def test_interpolation_follows_vtk_quadratic_tetra(self):
        """A second array interpolated at each hit equals VTK's own interpolation there
        (vtkQuadraticTetra::EvaluatePosition, then InterpolateFunctions' weights)."""
        grid = read("curved_ball.vtu")
        cam = CASES["curved_ball.vtu"]["cameras"][0]
        image = render(grid, "linear", 0.15, cam, color_array="quadratic")
        origins, directions = reference.pixel_rays(cam, SIZE, SIZE)
        values = vtk_to_numpy(grid.GetPointData().GetArray("quadratic"))
        points = vtk_to_numpy(grid.GetPoints().GetData())
        hits = np.flatnonzero(image["CellId"] >= 0)
        self.assertGreater(len(hits), 200)
        worst = 0.0
        ids = vtkIdList()
        for k in hits:
            x = origins[k] + image["Depth"][k] * directions[k]
            cell = grid.GetCell(int(image["CellId"][k]))
            closest, pcoords, weights = [0.0] * 3, [0.0] * 3, [0.0] * 10
            inside, dist2 = reference_evaluate(cell, x, closest, pcoords, weights)
            self.assertEqual(inside, 1)
            grid.GetCellPoints(int(image["CellId"][k]), ids)
            node_ids = [ids.GetId(n) for n in range(10)]
            # EvaluatePosition stops its Newton iteration near 1e-5 (parametric); finish it with
            # VTK's own shape functions and derivatives.
            nodes = points[node_ids]
            r = np.array(pcoords, dtype=float)
            for _ in range(8):
                w = reference.vtk_weights(r[None])[0]
                d = reference.vtk_derivs(r[None])[0]
                r = r - np.linalg.solve((d @ nodes).T, w @ nodes - x)
            w = reference.vtk_weights(r[None])[0]
            self.assertLess(np.linalg.norm(w @ nodes - x), 1e-13)
            expected = float(w @ values[node_ids])
            worst = max(worst, abs(image["ColorValues"][k] - expected))
        print("colour array at %d hits vs VTK's interpolation: max difference %.1e"
              % (len(hits), worst))
        self.assertLess(worst, 1e-12)

    def test_tangled_cells_are_skipped_and_counted(self):
        grid = read("curved_ball.vtu")
        points = vtk_to_numpy(grid.GetPoints().GetData())
        conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 10)
        # Fold a cell: its edge (0, 1) mid-node pushed past vertex 2, beyond the cell.
        cell = 0
        p = points[conn[cell]]
        points[conn[cell, 4]] = p[2] + 1.5 * (p[2] - 0.5 * (p[0] + p[1])) + (p[3] - p[0])
        grid.GetPoints().Modified()
        image = render(grid, "linear", 0.15, CASES["curved_ball.vtu"]["cameras"][0])
        caster = image["caster"]
        # Every cell sharing that mid-edge node folds.
        users = int(np.sum(np.any(conn == conn[cell, 4], axis=1)))
        self.assertGreaterEqual(caster.GetNumberOfTangledCells(), 1)
        self.assertLessEqual(caster.GetNumberOfTangledCells(), users)
        self.assertEqual(caster.GetNumberOfRenderedCells() + caster.GetNumberOfTangledCells(),
                         grid.GetNumberOfCells())


def reference_evaluate(cell, x, closest, pcoords, weights):
    """vtkCell.EvaluatePosition: (its return value, squared distance), filling pcoords and the
    shape functions' weights."""
    sub_id, d2 = mutable(0), mutable(0.0)
    inside = cell.EvaluatePosition(list(x), closest, sub_id, pcoords, d2, weights)
    return inside, float(d2)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
