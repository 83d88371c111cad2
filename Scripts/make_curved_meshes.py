#!/usr/bin/env python3
"""Small curved (isoparametric) VTK_QUADRATIC_TETRA meshes for testing, written as .vtu.

gmsh meshes each shape with second-order tetrahedra and places the mid-edge nodes of boundary
edges ON the curved geometry (Mesh.ElementOrder = 2, Mesh.SecondOrderLinear = 0), so the cells
touching a curved face are curved: the cell is the image x(xi) of the reference tetrahedron under
the quadratic map of its 10 nodes.

  Testing/Data/curved_ball.vtu   the ball of radius 1 about the origin (coarse)
  Testing/Data/curved_part.vtu   a machined part: the block [-2, 2] x [-1, 1] x [-0.5, 0.5] with two
                                 cylindrical through-holes along z, radius 0.45, axes x = -1 and
                                 x = +1 (y = 0)

Point arrays (both meshes):
  "linear"     f = a.x with a = (0.3, -0.5, 0.8). Quadratic interpolation reproduces it exactly
               on curved cells too (f(xi) = a.x(xi)), so its isosurface a.x = c is the plane,
               clipped to the curved domain: analytic truth.
  "quadratic"  f = |x - c|^2 with c = (0.3, 0.2, -0.1) (ball; iso-value 0.8 cuts the ball) or
               c = (-0.5, 0.3, 0.2) (part; iso-value 1.5 cuts the block and a hole). On curved
               cells the interpolated field is NOT |x(xi) - c|^2 (that is quartic in xi); its
               isosurface is what a curved-cell renderer must reproduce.

Node order: VTK_QUADRATIC_TETRA has vertices 0..3, then the mid-edge nodes of edges (0,1) (1,2)
(0,2) (0,3) (1,3) (2,3). gmsh's 10-node tetrahedron (element type 11) lists edge (2,3) before
edge (1,3), so its nodes 8 and 9 are swapped. The conversion is checked by geometry: each
mid-edge node must lie nearer the midpoint of the edge VTK assigns it to than any other edge's
midpoint, and within a quarter of that edge's length; the script fails otherwise.

Run it in a Python with gmsh (4.15.2), numpy (< 2) and ParaView's VTK 9.2, e.g.

  /usr/bin/python3 -m venv --system-site-packages /tmp/curved-venv
  /tmp/curved-venv/bin/pip install gmsh==4.15.2 'numpy<2'
  /tmp/curved-venv/bin/python Scripts/make_curved_meshes.py            # writes both files

Options: --out-dir DIR (default Testing/Data), --ball-size, --part-size (gmsh mesh sizes).
Per mesh it prints cells, points, curved cells (a mid-edge node off its edge midpoint by more than
1e-9 of the edge length), the largest offset / edge length, the smallest ratio of the Jacobian
determinant to the cell's straight-sided (vertex) determinant at sampled points (> 0: no cell is
folded) and the file size. gmsh is run without user configuration files, on one thread, so the
meshes are reproducible with the pinned gmsh version.
"""
import argparse
import os
import sys

import gmsh
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import (VTK_QUADRATIC_TETRA, vtkCellArray, vtkQuadraticTetra,
                                           vtkUnstructuredGrid)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

GMSH_TET10 = 11
# VTK_QUADRATIC_TETRA's mid-edge nodes 4..9 lie on these vertex pairs.
VTK_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
# gmsh's 10-node tetrahedron: nodes 4..9 on edges (0,1) (1,2) (2,0) (3,0) (3,2) (3,1).
GMSH_TO_VTK = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]

LINEAR_A = np.array([0.3, -0.5, 0.8])
BALL_CENTRE = np.array([0.3, 0.2, -0.1])      # "quadratic" on the ball; iso-value 0.8
PART_CENTRE = np.array([-0.5, 0.3, 0.2])      # "quadratic" on the part; iso-value 1.5
CURVED_TOLERANCE = 1e-9


def start(name):
    gmsh.initialize(readConfigFiles=False)  # no user gmshrc: reproducible meshes
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.model.add(name)


def second_order_mesh(size):
    """Meshes the current model with order-2 tets, mid-edge nodes on the geometry."""
    gmsh.option.setNumber("Mesh.MeshSizeMin", size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)          # Delaunay
    gmsh.option.setNumber("Mesh.ElementOrder", 2)
    gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)    # mid-edge nodes on the curved geometry
    gmsh.option.setNumber("Mesh.HighOrderOptimize", 0)
    gmsh.model.mesh.generate(3)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    points = coords.reshape(-1, 3)
    _, node_tags = gmsh.model.mesh.getElementsByType(GMSH_TET10)
    cells_gmsh = index[node_tags.astype(np.int64)].reshape(-1, 10)
    if (cells_gmsh < 0).any():
        raise SystemExit("gmsh returned a tetrahedron node that is not in the node list")
    # Only the nodes the tets use, renumbered in order of first use.
    used, inverse = np.unique(cells_gmsh, return_inverse=True)
    return points[used], inverse.reshape(-1, 10)


def ball_mesh(size):
    start("ball")
    try:
        gmsh.model.occ.addSphere(0, 0, 0, 1.0)
        gmsh.model.occ.synchronize()
        return second_order_mesh(size)
    finally:
        gmsh.finalize()


def part_mesh(size):
    start("part")
    try:
        occ = gmsh.model.occ
        block = occ.addBox(-2, -1, -0.5, 4, 2, 1)
        holes = [occ.addCylinder(x, 0, -1, 0, 0, 2, 0.45) for x in (-1.0, 1.0)]
        occ.cut([(3, block)], [(3, h) for h in holes])
        occ.synchronize()
        return second_order_mesh(size)
    finally:
        gmsh.finalize()


def order_mismatches(points, cells):
    """Per cell: does some mid-edge node lie nearer another VTK edge's midpoint than its own?"""
    x = points[cells]
    midpoints = np.stack([(x[:, a] + x[:, b]) / 2 for a, b in VTK_EDGES], axis=1)
    dist = np.linalg.norm(x[:, 4:, None, :] - midpoints[:, None, :, :], axis=3)
    return (dist.argmin(axis=2) != np.arange(6)).any(axis=1)


def to_vtk_order(points, cells_gmsh):
    """gmsh 10-node tets to VTK order, checked by geometry (SystemExit if it does not fit)."""
    cells = cells_gmsh[:, GMSH_TO_VTK]
    x = points[cells]                                            # (m, 10, 3)
    midpoints = np.stack([(x[:, a] + x[:, b]) / 2 for a, b in VTK_EDGES], axis=1)   # (m, 6, 3)
    lengths = np.stack([np.linalg.norm(x[:, a] - x[:, b], axis=1) for a, b in VTK_EDGES], axis=1)
    # distance of mid-edge node k (VTK slot 4+k) to the midpoint of edge l
    dist = np.linalg.norm(x[:, 4:, None, :] - midpoints[:, None, :, :], axis=3)    # (m, 6, 6)
    nearest = dist.argmin(axis=2)
    wrong = nearest != np.arange(6)
    offset = dist[:, np.arange(6), np.arange(6)] / lengths
    if wrong.any() or (offset > 0.25).any():
        cell, slot = np.argwhere(wrong | (offset > 0.25))[0]
        raise SystemExit(
            f"node order check failed: cell {cell}, VTK node {4 + slot} (edge {VTK_EDGES[slot]}) "
            f"is {offset[cell, slot]:.3g} edge lengths from its edge midpoint and nearest to the "
            f"midpoint of edge {VTK_EDGES[nearest[cell, slot]]}; {int(wrong.any(axis=1).sum())} "
            f"cells mismatch")
    # The check is not vacuous: gmsh's order taken as VTK's fails it in every cell.
    unswapped = int(order_mismatches(points, cells_gmsh).sum())
    return cells, offset, unswapped


def jacobian_ratio(points, cells, samples=20, seed=1):
    """Smallest det J(xi) / det J_straight over the nodes' xi and random points, all cells."""
    rng = np.random.default_rng(seed)
    xi = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [.5, 0, 0], [.5, .5, 0],
                   [0, .5, 0], [0, 0, .5], [.5, 0, .5], [0, .5, .5], [.25, .25, .25]], float)
    r = rng.random((samples, 3))
    r = r[r.sum(axis=1) <= 1]
    xi = np.vstack([xi, r])
    quad = vtkQuadraticTetra()
    derivs = np.zeros(30)
    worst = np.inf
    x = points[cells]                                       # (m, 10, 3)
    straight = np.linalg.det(np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]],
                                      axis=2))
    for p in xi:
        quad.InterpolateDerivs(p, derivs)
        d = derivs.reshape(3, 10)                           # d[i, n] = dN_n / dxi_i
        jac = np.einsum("mnk,in->mki", x, d)                # columns dx/dxi_i
        worst = min(worst, float((np.linalg.det(jac) / straight).min()))
    return worst


def write_vtu(path, points, cells, arrays):
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=True))
    grid.SetPoints(pts)
    conn = vtkCellArray()
    offsets = np.arange(0, 10 * len(cells) + 1, 10, dtype=np.int64)
    conn.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                 numpy_to_vtkIdTypeArray(cells.astype(np.int64).ravel(), deep=True))
    grid.SetCells(VTK_QUADRATIC_TETRA, conn)
    for name, values in arrays.items():
        arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=True)
        arr.SetName(name)
        grid.GetPointData().AddArray(arr)
    grid.GetPointData().SetActiveScalars("quadratic")
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(grid)
    # Inline binary (base64) like the project's other .vtu files: appended-data files of this
    # size written by ParaView's VTK 9.2 fail to read back with it ("junk after document element").
    writer.SetDataModeToBinary()
    writer.SetCompressorTypeToZLib()
    if not writer.Write():
        raise SystemExit(f"could not write {path}")
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    back = reader.GetOutput()
    if (back.GetNumberOfCells() != len(cells) or back.GetNumberOfPoints() != len(points)
            or not all(back.GetPointData().GetArray(n) for n in arrays)):
        raise SystemExit(f"{path} does not read back")


def make(name, points, cells_gmsh, centre, path):
    cells, offset, unswapped = to_vtk_order(points, cells_gmsh)
    curved = (offset > CURVED_TOLERANCE).any(axis=1)
    arrays = {"linear": points @ LINEAR_A,
              "quadratic": ((points - centre) ** 2).sum(axis=1)}
    write_vtu(path, points, cells, arrays)
    ratio = jacobian_ratio(points, cells)
    print(f"{name}: {len(cells)} cells, {len(points)} points, {int(curved.sum())} curved cells, "
          f"max mid-node offset / edge length {offset.max():.4f}, "
          f"min det J / straight det J {ratio:.3f}, {os.path.getsize(path) / 1e3:.1f} kB "
          f"-> {path}; "
          f"gmsh's order read as VTK's would misplace mid-edge nodes in {unswapped} of "
          f"{len(cells)} cells")
    if ratio <= 0:
        raise SystemExit(f"{name}: a cell is folded (det J <= 0 somewhere)")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("--out-dir", default=os.path.join(here, "..", "Testing", "Data"))
    parser.add_argument("--ball-size", type=float, default=0.4)
    parser.add_argument("--part-size", type=float, default=0.3)
    args = parser.parse_args(argv)
    os.makedirs(args.out_dir, exist_ok=True)
    print("node order: VTK = gmsh[[0, 1, 2, 3, 4, 5, 6, 7, 9, 8]] (checked by geometry per cell)")
    make("curved_ball", *ball_mesh(args.ball_size), BALL_CENTRE,
         os.path.normpath(os.path.join(args.out_dir, "curved_ball.vtu")))
    make("curved_part", *part_mesh(args.part_size), PART_CENTRE,
         os.path.normpath(os.path.join(args.out_dir, "curved_part.vtu")))


if __name__ == "__main__":
    sys.exit(main())
