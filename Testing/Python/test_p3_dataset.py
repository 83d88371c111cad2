"""The real P3 dataset (Data/p3_poisson.vtu: 2,885 VTK_LAGRANGE_TETRAHEDRON cells of order 3 from
gmsh, 699 of them curved at the ball's boundary, written in dolfinx's VTKFile layout) through the
VTK filter.

Truth:
- a linear field a . x sampled at the nodes is represented exactly by the isoparametric cells, so
  its isosurface is the plane a . x = c inside the mesh: every pixel's depth against the exact
  ray/plane intersection, and coverage against the ball (the mesh's boundary is the P3
  interpolant of the sphere: pixels whose plane point lies within a band of the sphere, the band
  four times the boundary's largest measured distance from the sphere, are left out and counted);
- the FE solution u at 0.5: the exact solution's level set has five closed pieces (the
  generator's check, Scripts/make_p3_poisson.py), vtkContourFilter finds four, TetDSR must show
  all five as separate blobs in its picture.

Usage: test_p3_dataset.py <Data folder>
"""
import os
import sys
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
from vtkmodules.vtkFiltersCore import vtkContourFilter, vtkPolyDataConnectivityFilter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkCamera

from tetdsr import vtkDirectSurfaceRayCaster

DATA = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "Data")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Scripts"))
import p3_poisson_view as view  # noqa: E402  (the dataset's iso-value and camera)

A = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
PLANE_VALUE = 0.1


def read():
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(DATA, "p3_poisson.vtu"))
    reader.Update()
    return reader.GetOutput()


def boundary_deviation(grid):
    """The largest distance from the unit sphere of the mesh's boundary: every face whose nodes
    all lie on the sphere (VTK's own faces of the Lagrange cells), sampled with VTK's own map
    (vtkLagrangeTriangle.EvaluateLocation)."""
    points = vtk_to_numpy(grid.GetPoints().GetData())
    on_sphere = np.abs(np.linalg.norm(points, axis=1) - 1.0) < 1e-12
    sub_id = mutable(0)
    x = [0.0, 0.0, 0.0]
    worst = 0.0
    samples = [(a / 8, b / 8, 0.0) for a in range(9) for b in range(9 - a)]
    for c in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(c)
        if sum(on_sphere[cell.GetPointId(k)] for k in range(4)) < 3:
            continue
        for f in range(cell.GetNumberOfFaces()):
            face = cell.GetFace(f)
            ids = [face.GetPointId(k) for k in range(face.GetNumberOfPoints())]
            if not all(on_sphere[i] for i in ids):
                continue
            weights = [0.0] * face.GetNumberOfPoints()
            for pcoords in samples:
                face.EvaluateLocation(sub_id, pcoords, x, weights)
                worst = max(worst, abs(np.linalg.norm(x) - 1.0))
    return worst


def render(grid, array, iso, size, camera):
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(grid)
    caster.SetInputArrayToProcess(0, 0, 0, 0, array)
    caster.SetValue(0, iso)
    caster.SetImageSize(*size)
    caster.SetCamera(camera)
    caster.Update()
    return caster


def pixel_rays(camera, width, height):
    """Origins and unit directions of the filter's pixel rays (perspective; pixel centres, j = 0
    at the bottom), from the camera's own frame."""
    position = np.array(camera.GetPosition())
    focal = np.array(camera.GetFocalPoint())
    forward = (focal - position) / np.linalg.norm(focal - position)
    up = np.array(camera.GetViewUp())
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = np.tan(np.radians(camera.GetViewAngle()) / 2)
    i, j = np.meshgrid(np.arange(width), np.arange(height))
    u = ((i + 0.5) / width * 2 - 1) * half * width / height
    v = ((j + 0.5) / height * 2 - 1) * half
    directions = forward + u[..., None] * right + v[..., None] * up
    directions /= np.linalg.norm(directions, axis=-1)[..., None]
    return position, directions.reshape(-1, 3)


def blobs(mask):
    """The number of 4-connected components of a boolean image."""
    label = np.zeros(mask.shape, dtype=int)
    count = 0
    for start in zip(*np.nonzero(mask)):
        if label[start]:
            continue
        count += 1
        stack = [start]
        label[start] = count
        while stack:
            y, x = stack.pop()
            for ny, nx in ((y + 1, x), (y - 1, x), (y, x + 1), (y, x - 1)):
                if 0 <= ny < mask.shape[0] and 0 <= nx < mask.shape[1] and mask[ny, nx] and not label[ny, nx]:
                    label[ny, nx] = count
                    stack.append((ny, nx))
    return count


class P3Dataset(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.grid = read()

    def test_every_cell_is_read_and_the_curved_ones_are_found(self):
        caster = render(self.grid, "u", view.ISO_VALUE, (8, 8), vtkCamera())
        self.assertEqual(caster.GetNumberOfRenderedCells(), 2885)
        self.assertEqual(caster.GetNumberOfHigherOrderCells(), 2885)
        self.assertEqual(caster.GetNumberOfCurvedCells(), 699)
        self.assertEqual(caster.GetNumberOfTangledCells(), 0)

    def test_a_plane_in_the_curved_mesh_is_exact(self):
        grid = vtkUnstructuredGrid()
        grid.ShallowCopy(self.grid)
        points = vtk_to_numpy(grid.GetPoints().GetData())
        linear = numpy_to_vtk(points @ A, deep=1)
        linear.SetName("linear")
        grid.GetPointData().AddArray(linear)
        band = 4.0 * boundary_deviation(grid) + 1e-9
        self.assertLess(band, 0.05, "the P3 boundary stays near the sphere")
        width, height = 120, 100
        camera = vtkCamera()
        camera.SetPosition(2.2, -1.6, 2.9)
        camera.SetFocalPoint(0.0, 0.0, 0.0)
        camera.SetViewUp(0.0, 0.0, 1.0)
        camera.SetViewAngle(30.0)
        caster = render(grid, "linear", PLANE_VALUE, (width, height), camera)
        depth = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth"))
        origin, directions = pixel_rays(camera, width, height)
        t = (PLANE_VALUE - origin @ A) / (directions @ A)
        hit_point = origin + t[:, None] * directions
        radius = np.linalg.norm(hit_point, axis=1)
        decided = np.abs(radius - 1.0) > band
        expected = (radius < 1.0) & (t > 0)
        got = np.isfinite(depth)
        wrong = int(((got != expected) & decided).sum())
        covered = expected & decided & got
        worst = float(np.max(np.abs(depth[covered] - t[covered]))) if covered.any() else 0.0
        print(f"plane in the P3 mesh: {int(covered.sum())} pixels compared, "
              f"{int((~decided).sum())} in the boundary band ({band:.2e}), {wrong} wrong, "
              f"max depth error {worst:.2e} (of the diagonal 2: {worst / 2:.1e})")
        self.assertEqual(wrong, 0)
        self.assertGreater(int(covered.sum()), 3000)
        self.assertLess(worst, 1e-9 * 2.0)
        # Rays through the curved cells: some of the compared pixels hit a curved cell.
        cells = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("CellId"))
        curved_hits = sum(1 for c in cells[covered] if self._curved(int(c)))
        self.assertGreater(curved_hits, 50, "pixels whose plane point lies in a curved cell")

    def _curved(self, cell):
        if not hasattr(self, "_curved_cells"):
            points = vtk_to_numpy(self.grid.GetPoints().GetData())
            on_sphere = np.abs(np.linalg.norm(points, axis=1) - 1.0) < 1e-12
            self._curved_cells = set()
            for c in range(self.grid.GetNumberOfCells()):
                ids = self.grid.GetCell(c).GetPointIds()
                if sum(on_sphere[ids.GetId(k)] for k in range(20)) >= 4:
                    self._curved_cells.add(c)
        return cell in self._curved_cells

    def test_the_five_pieces_where_contouring_finds_four(self):
        camera = vtkCamera()
        view.set_camera(camera)
        caster = render(self.grid, "u", view.ISO_VALUE, view.IMAGE_SIZE, camera)
        width, height = view.IMAGE_SIZE
        depth = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth")).reshape(height, width)
        pieces = blobs(np.isfinite(depth))
        contour = vtkContourFilter()
        contour.SetInputData(self.grid)
        contour.SetInputArrayToProcess(0, 0, 0, 0, "u")
        contour.SetValue(0, view.ISO_VALUE)
        connectivity = vtkPolyDataConnectivityFilter()
        connectivity.SetInputConnection(contour.GetOutputPort())
        connectivity.SetExtractionModeToAllRegions()
        connectivity.Update()
        regions = connectivity.GetNumberOfExtractedRegions()
        print(f"u = {view.ISO_VALUE}: TetDSR shows {pieces} pieces ({int(np.isfinite(depth).sum())} "
              f"pixels), vtkContourFilter {regions} ({contour.GetOutput().GetNumberOfCells()} triangles)")
        self.assertEqual(pieces, 5)
        self.assertEqual(regions, 4)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1])
