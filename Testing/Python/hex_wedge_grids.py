"""Grids of VTK's hexahedra and wedges of every kind TetDSR reads, for tests against analytic truth
(only VTK's API and numpy: none of TetDSR's code).

- Node positions come from VTK itself: each cell's GetParametricCoords (the authority for node
  order), mapped onto the cells of [0, 1]^3: n^3 cubes as hexahedra, or each cube as two wedges
  (its xy square cut along a diagonal, triangles times the z interval).
- `warp` moves every node (then cells are curved, isoparametric); warps that vanish on the unit
  cube's boundary keep the domain the unit cube, so the truth's ray clipping stays exact.
- Values are the fields at the nodes; a Bezier cell's are Bernstein coefficients, the solve of
  B c = f(nodes) with B[i, j] = VTK's InterpolateFunctions (basis j) at node i, per cell (its
  control points likewise, when warped)."""
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import (
    VTK_BEZIER_HEXAHEDRON, VTK_BEZIER_WEDGE, VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON,
    VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_HEXAHEDRON, VTK_LAGRANGE_HEXAHEDRON, VTK_LAGRANGE_WEDGE,
    VTK_QUADRATIC_HEXAHEDRON, VTK_QUADRATIC_LINEAR_WEDGE, VTK_QUADRATIC_WEDGE,
    VTK_QUADRATIC_TETRA, VTK_TRIQUADRATIC_HEXAHEDRON, VTK_VOXEL, VTK_WEDGE, vtkCellArray, vtkUnstructuredGrid)

import higher_order_grids as hog

WEDGE_TYPES = {VTK_WEDGE, VTK_QUADRATIC_WEDGE, VTK_QUADRATIC_LINEAR_WEDGE,
               VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_LAGRANGE_WEDGE, VTK_BEZIER_WEDGE}
BEZIER_TYPES = {VTK_BEZIER_HEXAHEDRON, VTK_BEZIER_WEDGE}

# Every (type, node count) TetDSR reads.
KINDS = [
    ("VTK_HEXAHEDRON", VTK_HEXAHEDRON, 8),
    ("VTK_VOXEL", VTK_VOXEL, 8),
    ("VTK_QUADRATIC_HEXAHEDRON", VTK_QUADRATIC_HEXAHEDRON, 20),
    ("VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON", VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON, 24),
    ("VTK_TRIQUADRATIC_HEXAHEDRON", VTK_TRIQUADRATIC_HEXAHEDRON, 27),
    ("VTK_LAGRANGE_HEXAHEDRON order 1", VTK_LAGRANGE_HEXAHEDRON, 8),
    ("VTK_LAGRANGE_HEXAHEDRON order 2", VTK_LAGRANGE_HEXAHEDRON, 27),
    ("VTK_LAGRANGE_HEXAHEDRON order 3", VTK_LAGRANGE_HEXAHEDRON, 64),
    ("VTK_LAGRANGE_HEXAHEDRON order 4", VTK_LAGRANGE_HEXAHEDRON, 125),
    ("VTK_BEZIER_HEXAHEDRON order 1", VTK_BEZIER_HEXAHEDRON, 8),
    ("VTK_BEZIER_HEXAHEDRON order 2", VTK_BEZIER_HEXAHEDRON, 27),
    ("VTK_BEZIER_HEXAHEDRON order 3", VTK_BEZIER_HEXAHEDRON, 64),
    ("VTK_BEZIER_HEXAHEDRON order 4", VTK_BEZIER_HEXAHEDRON, 125),
    ("VTK_WEDGE", VTK_WEDGE, 6),
    ("VTK_QUADRATIC_LINEAR_WEDGE", VTK_QUADRATIC_LINEAR_WEDGE, 12),
    ("VTK_QUADRATIC_WEDGE", VTK_QUADRATIC_WEDGE, 15),
    ("VTK_BIQUADRATIC_QUADRATIC_WEDGE", VTK_BIQUADRATIC_QUADRATIC_WEDGE, 18),
    ("VTK_LAGRANGE_WEDGE order 1", VTK_LAGRANGE_WEDGE, 6),
    ("VTK_LAGRANGE_WEDGE order 2", VTK_LAGRANGE_WEDGE, 18),
    ("VTK_LAGRANGE_WEDGE order 3", VTK_LAGRANGE_WEDGE, 40),
    ("VTK_LAGRANGE_WEDGE order 4", VTK_LAGRANGE_WEDGE, 75),
    ("VTK_BEZIER_WEDGE order 1", VTK_BEZIER_WEDGE, 6),
    ("VTK_BEZIER_WEDGE order 2", VTK_BEZIER_WEDGE, 18),
    ("VTK_BEZIER_WEDGE order 3", VTK_BEZIER_WEDGE, 40),
    ("VTK_BEZIER_WEDGE order 4", VTK_BEZIER_WEDGE, 75),
]


def vtk_cell(vtk_type, nodes):
    """VTK's own cell object of a type and node count (a one-cell grid's, so higher-order cells
    take their order from the count, as VTK reads files)."""
    ug = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetNumberOfPoints(nodes)
    for k in range(nodes):
        p.SetPoint(k, 0.0, 0.0, 0.0)
    ug.SetPoints(p)
    ug.InsertNextCell(vtk_type, nodes, list(range(nodes)))
    cell = ug.GetCell(0)
    cell.GetPoints().SetNumberOfPoints(nodes)
    return ug, cell


def node_parametric(vtk_type, nodes):
    """(nodes, 3) parametric coordinates in VTK's order."""
    keep, cell = vtk_cell(vtk_type, nodes)
    return np.array(cell.GetParametricCoords()).reshape(nodes, 3)


def basis_at(vtk_type, nodes, pcoords):
    """(len(pcoords), nodes): VTK's interpolation functions of the cell at parametric points."""
    keep, cell = vtk_cell(vtk_type, nodes)
    out = np.zeros((len(pcoords), nodes))
    for i, pc in enumerate(pcoords):
        w = [0.0] * nodes
        cell.InterpolateFunctions(list(pc), w)
        out[i] = w
    return out


def cell_nodes(vtk_type, nodes, n):
    """Per cell, its nodes' physical positions in [0, 1]^3 before any warp: (cells, nodes, 3)."""
    pc = node_parametric(vtk_type, nodes)
    h = 1.0 / n
    cells = []
    for k in range(n):
        for j in range(n):
            for i in range(n):
                base = np.array([i, j, k], float) * h
                if vtk_type in WEDGE_TYPES:
                    # Two wedges: (r, s) on the lower-left triangle, and rotated by a half turn
                    # onto the upper-right one (a positive map both times).
                    cells.append(base + h * pc)
                    turned = np.c_[1.0 - pc[:, 0], 1.0 - pc[:, 1], pc[:, 2]]
                    cells.append(base + h * turned)
                else:
                    cells.append(base + h * pc)
    return np.array(cells)


def grid(n, vtk_type, nodes, fields, warp=None):
    """[0, 1]^3 as hexahedra or wedges of one type; fields {name: f(points)}, the first the
    active scalars. Nodes at the same place are shared."""
    positions = cell_nodes(vtk_type, nodes, n)
    keys = np.rint(positions * n * 12).astype(np.int64)
    unique, first, inverse = np.unique(keys.reshape(-1, 3), axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(positions.shape[:2])
    straight = positions.reshape(-1, 3)[first]
    physical = warp(straight) if warp is not None else straight
    points = physical.copy()
    bezier = vtk_type in BEZIER_TYPES
    if bezier:
        B = basis_at(vtk_type, nodes, node_parametric(vtk_type, nodes))
        if warp is not None:
            # Control points: per cell, B c = the nodes' positions (shared control points agree:
            # neighbours have the same polynomial on a shared face).
            per_cell = np.linalg.solve(B[None], physical[inverse])
            points[inverse.ravel()] = per_cell.reshape(-1, 3)
        # (Unwarped, the map is affine, and an affine map's control points are its values at
        # the parametric lattice points, the nodes' places: exact, where the solve would round
        # them off their places by up to ~1e-13 at order 4.)
    ug = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=1))
    ug.SetPoints(p)
    ca = vtkCellArray()
    count = len(positions)
    ca.SetData(numpy_to_vtkIdTypeArray(np.arange(0, nodes * count + 1, nodes, dtype=np.int64), deep=1),
               numpy_to_vtkIdTypeArray(np.ascontiguousarray(inverse.ravel(), dtype=np.int64), deep=1))
    ug.SetCells(numpy_to_vtk(np.full(count, vtk_type, np.uint8), deep=1), ca)
    for k, (name, function) in enumerate(fields.items()):
        values = np.asarray(function(physical), dtype=np.float64)
        if bezier:
            per_cell = np.linalg.solve(B[None], values[inverse][..., None])[..., 0]
            values = np.empty(len(points))
            values[inverse.ravel()] = per_cell.ravel()
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
        array.SetName(name)
        ug.GetPointData().AddArray(array)
        if k == 0:
            ug.GetPointData().SetActiveScalars(name)
    return ug


def bulge(amount=0.06):
    """A warp that vanishes on the unit cube's boundary: cells inside are curved."""
    def warp(x):
        s = np.sin(np.pi * x[:, 0]) * np.sin(np.pi * x[:, 1]) * np.sin(np.pi * x[:, 2])
        return x + amount * s[:, None] * np.array([1.0, -0.7, 0.5])
    return warp


# The mixed mesh: blocks of side SIDE; a square's two triangles, split along its (0, 0)-(1, 1)
# diagonal as Kuhn's tetrahedra split the cube's faces (counter-clockwise: positive wedges).
SIDE = 0.5
TRIANGLES = (np.array([[0, 0], [1, 0], [1, 1]], float), np.array([[0, 0], [1, 1], [0, 1]], float))


def wedge_cells(vtk_type, nodes, base, axis):
    """The two wedges of the block at `base`: triangles in the plane across `axis` (2: z, 0: x)."""
    pc = node_parametric(vtk_type, nodes)
    cells = []
    for tri in TRIANGLES:
        across = tri[0] + pc[:, :1] * (tri[1] - tri[0]) + pc[:, 1:2] * (tri[2] - tri[0])
        local = np.c_[across, pc[:, 2]] if axis == 2 else np.c_[pc[:, 2], across]
        cells.append((vtk_type, base + SIDE * local))
    return cells


def block_cells(kind, base, wedge18):
    if kind == "tetrahedra":
        bary = hog.node_parametric(VTK_QUADRATIC_TETRA, 2)
        bary = np.c_[1.0 - bary.sum(axis=1), bary]
        return [(VTK_QUADRATIC_TETRA, base + SIDE * (bary @ corners)) for corners in hog.kuhn_tets(1)]
    if kind == "hexahedron":
        return [(VTK_QUADRATIC_HEXAHEDRON, base + SIDE * node_parametric(VTK_QUADRATIC_HEXAHEDRON, 20))]
    vtk_type, nodes = (VTK_BIQUADRATIC_QUADRATIC_WEDGE, 18) if wedge18 else (VTK_QUADRATIC_WEDGE, 15)
    return wedge_cells(vtk_type, nodes, base, 2 if kind == "wedges along z" else 0)


def mixed_mesh(warp=None, fields=()):
    """A conforming mesh of the unit cube mixing VTK_QUADRATIC_TETRA, VTK_QUADRATIC_WEDGE,
    VTK_BIQUADRATIC_QUADRATIC_WEDGE and VTK_QUADRATIC_HEXAHEDRON cells (straight, or its nodes
    moved by `warp`), with point arrays {name: f(points)} (the first the active scalars). The
    cube's 2 x 2 x 2 blocks of side 1/2, for each of the two y layers:

        z in [1/2, 1]:  6 Kuhn tetrahedra    | 2 wedges along x (triangles in x = const)
        z in [0, 1/2]:  2 wedges along z     | 1 hexahedron
                        x in [0, 1/2]          x in [1/2, 1]

    so tetrahedra meet wedge triangles and hexahedra meet wedge quadrilaterals; the wedges are
    15-node in one y layer and 18-node in the other where they lie along z, the other way round
    along x. An 18-node wedge's quadrilateral centre node, curved, is placed where its 8-node
    neighbour's face puts its centre (so both sides are the same surface)."""
    cells = []
    for j in range(2):
        for kind, (i, k) in (("wedges along z", (0, 0)), ("hexahedron", (1, 0)),
                             ("tetrahedra", (0, 1)), ("wedges along x", (1, 1))):
            wedge18 = (j == 1) == (kind == "wedges along z")
            cells += block_cells(kind, SIDE * np.array([i, j, k], float), wedge18)
    positions = np.concatenate([p for _, p in cells])
    keys = np.rint(positions * 48).astype(np.int64)
    unique, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    points = positions[first]
    sizes = [len(p) for _, p in cells]
    ug = vtkUnstructuredGrid()
    ca = vtkCellArray()
    ca.SetData(numpy_to_vtkIdTypeArray(np.r_[0, np.cumsum(sizes)].astype(np.int64), deep=1),
               numpy_to_vtkIdTypeArray(np.ascontiguousarray(inverse.ravel(), dtype=np.int64), deep=1))
    ug.SetCells(numpy_to_vtk(np.array([t for t, _ in cells], np.uint8), deep=1), ca)
    p = vtkPoints()
    p.SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=1))
    ug.SetPoints(p)
    if warp is not None:
        points = warp(points)
        # An 18-node wedge's quadrilateral centre: where the 8 other face nodes' serendipity
        # interpolation puts it (corners -1/4, mid-edge nodes 1/2), VTK's face node order.
        for c in range(ug.GetNumberOfCells()):
            cell = ug.GetCell(c)
            for f in range(cell.GetNumberOfFaces()):
                face = cell.GetFace(f)
                if face.GetNumberOfPoints() == 9:
                    ids = [face.GetPointId(k) for k in range(9)]
                    points[ids[8]] = -0.25 * points[ids[:4]].sum(axis=0) + 0.5 * points[ids[4:8]].sum(axis=0)
        p.SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=1))
    for k, (name, function) in enumerate(dict(fields).items()):
        array = numpy_to_vtk(np.ascontiguousarray(function(points), dtype=np.float64), deep=1)
        array.SetName(name)
        ug.GetPointData().AddArray(array)
        if k == 0:
            ug.GetPointData().SetActiveScalars(name)
    return ug
