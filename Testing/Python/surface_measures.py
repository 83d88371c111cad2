"""Measures of triangle surfaces that the exact-surface test (test_exact_surface.py) and the
speed-against-error study (Testing/SpeedVsError/exact_surface_vs_contour.py) share: the triangles
of a vtkPolyData as arrays, dense samples of them, distances from points to them (VTK's
vtkStaticCellLocator: the exact nearest point on each triangle), connected pieces and how many
triangles use each edge. Only VTK's API and numpy: none of TetDSR's code."""
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkGenericCell, vtkPolyData, vtkStaticCellLocator
from vtkmodules.vtkFiltersCore import vtkPolyDataConnectivityFilter, vtkTriangleFilter


def triangles_of(surface):
    """(points (n, 3), triangles (m, 3) int64) of a vtkPolyData whose polygons are triangles
    (asserted: a polygon of another size is a defect of the surface)."""
    points = vtk_to_numpy(surface.GetPoints().GetData()).astype(np.float64) if surface.GetPoints() else np.zeros((0, 3))
    polys = surface.GetPolys()
    if polys.GetNumberOfCells() == 0:
        return points, np.zeros((0, 3), np.int64)
    offsets = vtk_to_numpy(polys.GetOffsetsArray())
    assert np.all(np.diff(offsets) == 3), "the surface has polygons that are not triangles"
    return points, vtk_to_numpy(polys.GetConnectivityArray()).astype(np.int64).reshape(-1, 3)


def as_triangles(surface):
    """The surface with every polygon and strip as triangles (vtkContourFilter may give both)."""
    triangulate = vtkTriangleFilter()
    triangulate.SetInputData(surface)
    triangulate.PassVertsOff()
    triangulate.PassLinesOff()
    triangulate.Update()
    out = vtkPolyData()
    out.ShallowCopy(triangulate.GetOutput())
    return out


def sample_triangles(points, triangles, level):
    """Points of each triangle at the barycentric lattice of `level` steps per edge (vertices,
    edges and inside: (level + 1)(level + 2)/2 per triangle), as one (k, 3) array."""
    weights = np.array([(i, j, level - i - j) for i in range(level + 1) for j in range(level + 1 - i)],
                       float) / level
    corners = points[triangles]  # (m, 3 corners, 3)
    return np.einsum("wc,mcd->mwd", weights, corners).reshape(-1, 3)


def flat_area(points, triangles):
    """The triangles' total area."""
    if len(triangles) == 0:
        return 0.0
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())


class NearestTriangle:
    """Distances from points to a triangle surface: vtkStaticCellLocator.FindClosestPoint, the
    exact nearest point of the nearest triangle."""

    def __init__(self, surface):
        self.surface = surface
        self.empty = surface.GetNumberOfCells() == 0
        if not self.empty:
            self.locator = vtkStaticCellLocator()
            self.locator.SetDataSet(surface)
            self.locator.BuildLocator()

    def distances(self, query):
        """Per point of `query` ((k, 3)), its distance to the surface (inf if it has none)."""
        if self.empty:
            return np.full(len(query), np.inf)
        nearest, cell, sub, squared = [0.0, 0.0, 0.0], mutable(0), mutable(0), mutable(0.0)
        scratch = vtkGenericCell()
        out = np.empty(len(query))
        for k, x in enumerate(np.asarray(query, np.float64).tolist()):
            self.locator.FindClosestPoint(x, nearest, scratch, cell, sub, squared)
            out[k] = float(squared)
        return np.sqrt(out)


def components(surface):
    """The number of connected pieces of a triangle surface (triangles joined by shared points)."""
    if surface.GetNumberOfCells() == 0:
        return 0
    connectivity = vtkPolyDataConnectivityFilter()
    connectivity.SetInputData(surface)
    connectivity.SetExtractionModeToAllRegions()
    connectivity.Update()
    return connectivity.GetNumberOfExtractedRegions()


def edge_uses(triangles):
    """(edges (e, 2) sorted vertex pairs, how many triangles use each (e,))."""
    if len(triangles) == 0:
        return np.zeros((0, 2), np.int64), np.zeros(0, np.int64)
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    return unique, counts


def polydata(points, triangles):
    """A vtkPolyData of triangles given as arrays (the points kept whole, ids unchanged)."""
    out = vtkPolyData()
    p = vtkPoints()
    p.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=1))
    out.SetPoints(p)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(triangles) + 1, 3, dtype=np.int64), deep=1),
                  numpy_to_vtkIdTypeArray(np.ascontiguousarray(triangles, dtype=np.int64).ravel(), deep=1))
    out.SetPolys(cells)
    return out
