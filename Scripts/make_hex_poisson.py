#!/usr/bin/env python3
"""A Poisson problem solved with scikit-fem's 20-node serendipity hexahedra (ElementHexS2) on a
curved isoparametric mesh of a bulged quarter of a thick cylindrical shell, written as
VTK_QUADRATIC_HEXAHEDRON cells (type 25, 20 nodes in VTK's order).

Run it through Scripts/make-hex-poisson.sh, which runs it, with its arguments, in the venv that
Scripts/flow-venv.sh makes or reuses (scikit-fem, scipy, and ParaView's VTK). Data/hex_poisson.vtu
and its picture are the default run:

  bash Scripts/make-hex-poisson.sh --out Data/hex_poisson.vtu \
      --image docs/images/hex_poisson_contour.png

The part: the box [0,1]^3 of (xi, eta, zeta) mapped by part_map, radius 0.5 + xi (0.5 to 1.5),
angle eta pi/2 (a quarter turn), height zeta (0.8 + 0.3 sin(pi xi) sin(pi eta)) (a lid bulged
from 0.8 at its rim to 1.1). The mesh: the box's structured grid of level * BASE_CELLS cells
(radial, angular, axial); every cell's 20 nodes (corners and mid-edges of the box cell) are put
through part_map, and the cell's geometry is the serendipity map of those nodes (a mesh class
MeshHexS2: scikit-fem's MeshHex1 with ElementHexS2 as its element, so that its
MappingIsoparametric is the 20-node one). Every cell is curved (the angular edges are arcs,
and the lid bulges); the serendipity geometry differs from part_map by O(h^3) (printed).

The problem: -laplace(u) = f in the part, u = g on its boundary, with f and g taken from the
known solution u = sum of four Gaussian bumps a exp(-|x - c|^2 / (2 s^2)) (BUMPS below, centres
given in box coordinates). Its level set u = ISO_VALUE (0.5, Scripts/hex_poisson_view.py) is four
closed pieces, one around each bump: every peak exceeds 0.5 and the bumps are far apart (each
adds less than 2e-3 at another's centre); two peaks exceed it by only 2 and 6 %, so those pieces
are 0.05 and 0.08 across, smaller than the 0.07 to 0.11 cells around them. The 2 % bump (bump 3)
sits at the centre of a cell of the finest level, the point of a serendipity cell farthest from
its 20 nodes: no node of that cell reaches the iso-value, so vtkContourFilter (which skips a cell
whose nodal values do not straddle it) misses that piece.

scikit-fem assembles and solves it (Basis(mesh, ElementHexS2(), intorder=6); the Dirichlet
nodes are those on the box's boundary, checked against basis.get_dofs(), which needs the
mesh's boundary element to be ElementQuadS2: with MeshHex1's default none, get_dofs() leaves
the boundary's mid-edge nodes free and the errors stall at first order). The problem is solved at
LEVELS 1, 2, 3 (96, 768, 2,592 cells); the L2 and H1-seminorm errors against the exact solution
(intorder 10) give observed rates log(e_coarse / e_fine) / log(h_coarse / h_fine) between
consecutive levels. Serendipity P2 should give 3 and 2 here (the cells of a smooth map of a
uniform grid are asymptotically parallelepipeds, where serendipity elements keep their order;
on general distorted hexahedra they lose it, Arnold, Boffi and Falk 2002). The script exits
unless every rate is at least MIN_L2_RATE = 2.5 and MIN_H1_RATE = 1.6: halfway between the
expected order and the one below it (what the known failure modes give: a lost boundary node,
geometry or node order that is only right to first order), and still clear of the pre-asymptotic
scatter of the coarse levels (measured 3.10/2.93 and 2.10/2.04). The FE solution at each bump's
centre must exceed ISO_VALUE (so that its own level set has all four pieces).

The .vtu holds the finest level: VTK_QUADRATIC_HEXAHEDRON cells whose 20 nodes are scikit-fem's
(the mesh's nodes, shared between cells), point arrays "u" (the FE solution at the nodes, its
nodal values: ElementHexS2 is interpolatory) and "u_exact", binary (inline) and zlib-compressed.
VTK's parametric point r is scikit-fem's reference point 1 - r (scikit-fem's reference
hexahedron has its (1, 1, 1) corner at the cell's first vertex, which MeshHex1.init_tensor makes
the cell's smallest (xi, eta, zeta) corner, so its own map reverses orientation; with 1 - r,
VTK's r, s, t run along xi, eta, zeta and its cells have a positive Jacobian). The node order is
found by matching ElementHexS2.doflocs with 1 - vtkQuadraticHexahedron's GetParametricCoords,
and the file is read back (vtkXMLUnstructuredGridReader) and checked against scikit-fem: node k
of every cell where scikit-fem's map puts 1 - (VTK's parametric point k); at random points r of
every cell, VTK's map (EvaluateLocation) against scikit-fem's map at 1 - r, VTK's Jacobian
determinant positive, and VTK's interpolation of u (InterpolateFunctions) against scikit-fem's
at the same physical point (scikit-fem's Newton inverse of its map, MappingIsoparametric.invF,
in the cell, then ElementHexS2's basis: Basis.probes once it knows the cell; probes' own cell
search splits the straight-sided hexahedra into tetrahedra and misplaces points near curved
faces), all to 1e-12.

Finally it counts what vtkContourFilter makes of the level set ISO_VALUE (triangles, connected
pieces, which of the four it misses, how far its triangles lie from the exact surface) and, with
--image, has Scripts/hex_poisson_view.py draw it (under xvfb-run).

Measured on the 2-core development machine, the default run: 2,592 cells (all curved: mid-edge
nodes up to 2.5e-3 off their chords; the serendipity geometry within 4.3e-5 of part_map),
12,181 nodes, 0.49 MB; 17 s in all (22 s with the venv check and the picture), peak memory
0.71 GB; errors at levels 1, 2, 3: L2 1.89e-2, 2.19e-3, 6.61e-4 (rates 3.11, 2.96), H1 seminorm
0.474, 0.110, 0.0481 (rates 2.10, 2.05), nodal max 1.9e-3 at level 3; the file check 2.2e-15 at
worst; vtkContourFilter: 964 triangles in 3 pieces of the 4, the missing one bump 3 (2 % above
0.5), bump 2's (6 % above) 28 triangles. The written file is the same byte for byte on every run.
"""
import argparse
import hashlib
import os
import subprocess
import sys
import time
from dataclasses import dataclass, replace

import numpy as np
import scipy.ndimage as ndimage
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable, vtkPoints
from vtkmodules.vtkCommonDataModel import (VTK_QUADRATIC_HEXAHEDRON, vtkCellArray,
                                           vtkQuadraticHexahedron, vtkUnstructuredGrid)
from vtkmodules.vtkFiltersCore import (vtkCleanPolyData, vtkContourFilter,
                                       vtkPolyDataConnectivityFilter)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hex_poisson_view import ISO_VALUE  # noqa: E402

NODES = 20
# The part: radius INNER_RADIUS + (OUTER_RADIUS - INNER_RADIUS) xi, angle eta pi/2,
# height zeta (HEIGHT + BULGE sin(pi xi) sin(pi eta)).
INNER_RADIUS, OUTER_RADIUS, HEIGHT, BULGE = 0.5, 1.5, 0.8, 0.3
# The exact solution's bumps: (centre in box coordinates (xi, eta, zeta), width s, peak a);
# u = sum a exp(-|x - c|^2 / (2 s^2)) with c = part_map(centre).
BUMPS = [((0.50, 0.35, 0.50), 0.15, 1.00),
         ((0.25, 0.85, 0.50), 0.12, 0.75),
         ((0.80, 0.80, 0.55), 0.12, 0.53),
         ((9.5 / 12, 1.5 / 18, 4.5 / 12), 0.12, 0.51)]  # a finest cell's centre: see below
# Cells (radial, angular, axial) of level 1; level k has k times as many along each.
BASE_CELLS = (4, 6, 4)
LEVELS = (1, 2, 3)
# The smallest observed convergence rates accepted (serendipity P2: 3 in L2, 2 in H1).
MIN_L2_RATE, MIN_H1_RATE = 2.5, 1.6
INTORDER, ERROR_INTORDER = 6, 10  # scikit-fem's quadrature degree: solve, errors
SAMPLES = 4  # random points per cell in the file check (and the cell's centre)


def part_map(box):
    """The part's points at box coordinates (xi, eta, zeta), both (3, ...)."""
    xi, eta, zeta = box
    radius = INNER_RADIUS + (OUTER_RADIUS - INNER_RADIUS) * xi
    angle = 0.5 * np.pi * eta
    height = zeta * (HEIGHT + BULGE * np.sin(np.pi * xi) * np.sin(np.pi * eta))
    return np.array([radius * np.cos(angle), radius * np.sin(angle), height])


def inside_part(x):
    """Whether the points x (3, ...) lie in part_map's image of the box (the exact part)."""
    xi = (np.hypot(x[0], x[1]) - INNER_RADIUS) / (OUTER_RADIUS - INNER_RADIUS)
    eta = np.arctan2(x[1], x[0]) / (0.5 * np.pi)
    height = HEIGHT + BULGE * np.sin(np.pi * xi) * np.sin(np.pi * eta)
    return (xi >= 0) & (xi <= 1) & (eta >= 0) & (eta <= 1) & (x[2] >= 0) & (x[2] <= height)


def bump_centres():
    """The bumps' centres in the part (4 x 3)."""
    return part_map(np.array([centre for centre, _, _ in BUMPS]).T).T


def exact_solution(x):
    """u, grad u and laplace(u) of the bumps at points x (3, ...): (...), (3, ...), (...)."""
    u = np.zeros(x.shape[1:])
    gradient = np.zeros(x.shape)
    laplacian = np.zeros(x.shape[1:])
    for centre, (_, width, peak) in zip(bump_centres(), BUMPS):
        d = x - centre.reshape((3,) + (1,) * (x.ndim - 1))
        r2 = np.sum(d * d, axis=0)
        bump = peak * np.exp(-r2 / (2 * width ** 2))
        u += bump
        gradient -= bump * d / width ** 2
        # laplace exp(-r^2 / (2 s^2)) = (r^2 / s^4 - 3 / s^2) exp(-r^2 / (2 s^2)) in 3D.
        laplacian += bump * (r2 / width ** 4 - 3 / width ** 2)
    return u, gradient, laplacian


def serendipity_mesh_class():
    """scikit-fem's MeshHex1 with the 20-node serendipity element as its geometry (doflocs: the
    corners, then one node per edge, in scikit-fem's Dofs order) and ElementQuadS2 as its boundary
    element (get_dofs() finds the boundary's edge nodes through it)."""
    from skfem import MeshHex1
    from skfem.element import ElementHexS2, ElementQuadS2

    @dataclass(repr=False)
    class MeshHexS2(MeshHex1):
        elem: type = ElementHexS2

        @property
        def bndelem(self):
            return ElementQuadS2()

    return MeshHexS2


def vtk_parametric_coords():
    """VTK's parametric coordinates of vtkQuadraticHexahedron's 20 nodes (20 x 3)."""
    coords = vtkQuadraticHexahedron().GetParametricCoords()
    return np.array([coords[i] for i in range(3 * NODES)]).reshape(NODES, 3)


def vtk_order():
    """order[k] = ElementHexS2's local node at scikit-fem's reference point 1 - r_k, r_k VTK's
    parametric point of node k; exits unless one to one."""
    from skfem.element import ElementHexS2
    reference = 1.0 - vtk_parametric_coords()
    distance = np.linalg.norm(reference[:, None, :] - ElementHexS2.doflocs[None, :, :], axis=2)
    order = distance.argmin(axis=1)
    if distance[np.arange(NODES), order].max() > 1e-12 or len(set(order)) != NODES:
        sys.exit(f"scikit-fem's and VTK's 20-node hexahedra do not match:\n"
                 f"scikit-fem {ElementHexS2.doflocs.tolist()}\nVTK {reference.tolist()}")
    return order


def make_mesh(level):
    """The curved mesh of the level: the MeshHexS2 and its nodes' box coordinates (3 x n)."""
    from skfem import MeshHex1
    counts = [level * n for n in BASE_CELLS]
    box = MeshHex1.init_tensor(*[np.linspace(0.0, 1.0, n + 1) for n in counts])
    box_mesh = serendipity_mesh_class().from_mesh(box)  # the 20 nodes of the box's cells
    mesh = replace(box_mesh, doflocs=part_map(box_mesh.doflocs))
    if not np.array_equal(mesh.dofs.element_dofs, box_mesh.dofs.element_dofs):
        sys.exit("the mapped mesh numbers its nodes differently from the box's")
    return mesh, box_mesh.doflocs


def curved_cells(points, cells):
    """Per cell (VTK order), the largest distance of a mid-edge node from its edge's chord's
    midpoint; a cell with any above 1e-12 is curved."""
    pcoords = vtk_parametric_coords()
    deviation = np.zeros(len(cells))
    for k in range(8, NODES):
        ends = [np.flatnonzero(np.all(np.isclose(pcoords[:8], np.where(pcoords[k] == 0.5, v,
                                                                       pcoords[k])), axis=1))[0]
                for v in (0.0, 1.0)]
        chord = 0.5 * (points[cells[:, ends[0]]] + points[cells[:, ends[1]]])
        deviation = np.maximum(deviation, np.linalg.norm(points[cells[:, k]] - chord, axis=1))
    return deviation


def solve_poisson(mesh, box_nodes):
    """scikit-fem's serendipity Galerkin solution (nodal values) and its basis; exits unless the
    Dirichlet nodes are those on the box's boundary and no cell is inverted."""
    from skfem import Basis, LinearForm, condense, solve
    from skfem.element import ElementHexS2
    from skfem.models.poisson import laplace
    basis = Basis(mesh, ElementHexS2(), intorder=INTORDER)
    if not (np.array_equal(basis.doflocs, mesh.doflocs)
            and np.array_equal(basis.element_dofs, mesh.dofs.element_dofs)):
        sys.exit("the basis' nodes are not the mesh's")
    determinant = basis.mapping.detDF(basis.X)  # scikit-fem's map reverses orientation
    if determinant.max() >= 0:
        sys.exit(f"a cell is degenerate or inverted: det = {determinant.max():.3e}")
    dirichlet = basis.get_dofs().all()
    on_box_boundary = np.flatnonzero(np.any((box_nodes == 0) | (box_nodes == 1), axis=0))
    if not np.array_equal(np.sort(dirichlet), on_box_boundary):
        sys.exit(f"get_dofs() found {len(dirichlet)} boundary nodes, the box has "
                 f"{len(on_box_boundary)}")
    stiffness = laplace.assemble(basis)
    load = LinearForm(lambda v, w: -exact_solution(w.x)[2] * v).assemble(basis)
    u = np.zeros(basis.N)
    u[dirichlet] = exact_solution(mesh.doflocs[:, dirichlet])[0]
    return solve(*condense(stiffness, load, x=u, D=dirichlet)), basis


def errors(mesh, u):
    """L2 and H1-seminorm errors of u against the exact solution, and the largest nodal one."""
    from skfem import Basis, Functional
    from skfem.element import ElementHexS2
    basis = Basis(mesh, ElementHexS2(), intorder=ERROR_INTORDER)
    uh = basis.interpolate(u)
    l2 = Functional(lambda w: (w["uh"].value - exact_solution(w.x)[0]) ** 2)
    h1 = Functional(lambda w: np.sum((w["uh"].grad - exact_solution(w.x)[1]) ** 2, axis=0))
    return {"L2": np.sqrt(l2.assemble(basis, uh=uh)),
            "H1 seminorm": np.sqrt(h1.assemble(basis, uh=uh)),
            "nodal max": np.abs(u - exact_solution(mesh.doflocs)[0]).max()}


def evaluate_at(basis, u, position):
    """scikit-fem's FE solution at a physical position: Newton (invF) in each cell whose node box
    holds it; exits unless one does."""
    nodes = basis.mesh.doflocs[:, basis.element_dofs]  # 3 x 20 x m
    margin = 1e-9
    candidates = np.flatnonzero(np.all((nodes.min(axis=1) - margin <= position[:, None]) &
                                       (position[:, None] <= nodes.max(axis=1) + margin), axis=0))
    x = position.reshape(3, 1, 1)
    for c in candidates:
        try:
            reference = basis.mapping.invF(x, tind=np.array([c]))
        except Exception:  # Newton did not converge: the point is elsewhere
            continue
        if np.abs(basis.mapping.F(reference, tind=np.array([c])) - x).max() < 1e-12:
            return interpolate_in_cells(basis, u, reference, np.array([c]))[0, 0]
    sys.exit(f"no cell holds {position}")


def interpolate_in_cells(basis, u, reference, cells):
    """scikit-fem's interpolation of u at per-cell reference points (3 x len(cells) x p)."""
    return sum(basis.elem.gbasis(basis.mapping, reference, k, tind=cells)[0].value
               * u[basis.element_dofs[k, cells]][:, None] for k in range(NODES))


def write_vtu(path, points, cells, arrays):
    """Writes the cells as VTK_QUADRATIC_HEXAHEDRON with the given point arrays (the first the
    active scalars), binary and zlib-compressed."""
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    connectivity = vtkCellArray()
    connectivity.SetData(numpy_to_vtkIdTypeArray(np.arange(0, cells.size + 1, NODES), deep=True),
                         numpy_to_vtkIdTypeArray(cells.ravel().astype(np.int64), deep=True))
    grid.SetCells(VTK_QUADRATIC_HEXAHEDRON, connectivity)
    for name, values in arrays.items():
        array = numpy_to_vtk(values, deep=True)
        array.SetName(name)
        grid.GetPointData().AddArray(array)
    grid.GetPointData().SetActiveScalars(next(iter(arrays)))
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(grid)
    # Inline binary (base64 in each DataArray): this VTK 9.2 with Debian's expat cannot read
    # appended data back, raw or base64 ("Error parsing XML in stream ... not well-formed").
    writer.SetDataModeToBinary()
    writer.SetCompressorTypeToZLib()
    if not writer.Write():
        sys.exit(f"could not write {path}")


def read_grid(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def check_file(path, points, cells, arrays, basis, u, box_nodes):
    """Reads the file back; exits unless it holds the mesh and arrays bit for bit. Returns the
    largest differences: the nodes against scikit-fem's map at 1 - VTK's parametric points; at
    random points, VTK's map against scikit-fem's, VTK's interpolation of u against
    scikit-fem's at the same physical point (relative to max |u|), the recovered reference point
    against 1 - r; and the smallest det of VTK's Jacobian and the geometry's distance from
    part_map (box_nodes: the nodes' box coordinates)."""
    grid = read_grid(path)
    types = vtk_to_numpy(grid.GetCellTypesArray())
    if (len(types) != len(cells) or np.any(types != VTK_QUADRATIC_HEXAHEDRON)
            or grid.GetCell(0).GetNumberOfPoints() != NODES):
        sys.exit(f"{path}: expected {len(cells)} cells of type {VTK_QUADRATIC_HEXAHEDRON} "
                 f"with {NODES} nodes")
    file_points = vtk_to_numpy(grid.GetPoints().GetData())
    if not np.array_equal(file_points, points):
        sys.exit(f"{path}: the points did not read back bit for bit")
    for name, values in arrays.items():
        if not np.array_equal(vtk_to_numpy(grid.GetPointData().GetArray(name)), values):
            sys.exit(f"{path}: {name} did not read back bit for bit")
    file_u = vtk_to_numpy(grid.GetPointData().GetArray("u"))
    every = np.arange(len(cells))

    # Node k of each cell against scikit-fem's map at the reference point 1 - r_k.
    pcoords = vtk_parametric_coords()
    mapped = basis.mapping.F(1.0 - pcoords.T)  # 3 x m x 20
    node_difference = np.abs(mapped.transpose(1, 2, 0) - file_points[cells]).max()

    # Random parametric points (and the centre) per cell.
    rng = np.random.default_rng(7)
    samples = np.concatenate([rng.random((len(cells), SAMPLES, 3)),
                              np.full((len(cells), 1, 3), 0.5)], axis=1)  # m x p x 3
    reference = 1.0 - samples.transpose(2, 0, 1)                          # 3 x m x p
    own_positions = basis.mapping.F(reference, tind=every)                 # 3 x m x p
    vtk_positions = np.empty(samples.shape)
    vtk_values = np.empty(samples.shape[:2])
    smallest_determinant = np.inf
    location, weights, sub_id = [0.0] * 3, [0.0] * NODES, mutable(0)
    derivatives = [0.0] * 3 * NODES
    for c in range(len(cells)):
        cell = grid.GetCell(c)
        ids = [cell.GetPointId(k) for k in range(NODES)]
        if ids != cells[c].tolist():
            sys.exit(f"{path}: cell {c} has nodes {ids}, expected {cells[c].tolist()}")
        nodes = file_points[ids]
        for p, r in enumerate(samples[c]):
            cell.EvaluateLocation(sub_id, r, location, weights)
            vtk_positions[c, p] = location
            cell.InterpolateFunctions(r, weights)
            vtk_values[c, p] = np.dot(weights, file_u[ids])
            cell.InterpolateDerivs(r, derivatives)
            jacobian = nodes.T @ np.reshape(derivatives, (3, NODES)).T  # dx_a / dr_b
            smallest_determinant = min(smallest_determinant, np.linalg.det(jacobian))
    geometry_difference = np.abs(vtk_positions - own_positions.transpose(1, 2, 0)).max()

    # scikit-fem at VTK's physical points: its inverse map in the cell, then its basis.
    recovered = basis.mapping.invF(vtk_positions.transpose(2, 0, 1), tind=every)
    own_values = interpolate_in_cells(basis, u, recovered, every)
    value_difference = np.abs(vtk_values - own_values).max() / np.abs(u).max()
    reference_difference = np.abs(recovered - reference).max()

    # The serendipity geometry against the exact part: part_map at the same point of the box
    # (where the serendipity map of the box cell's nodes is the cell's affine map).
    box_positions = sum(basis.elem.lbasis(reference, k)[0]
                        * box_nodes[:, basis.element_dofs[k]][:, :, None] for k in range(NODES))
    part_difference = np.linalg.norm(part_map(box_positions) - own_positions, axis=0).max()
    return (node_difference, geometry_difference, value_difference, reference_difference,
            smallest_determinant, part_difference)


def exact_pieces(spacing=0.01):
    """The closed pieces of the exact level set u = ISO_VALUE: the bumps whose centre value
    exceeds it, checked by labelling the voxels of {u > ISO_VALUE} in the part on a grid of the
    given spacing (each bump's centre voxel counted in, as the smallest pieces may fall between
    grid points); exits unless there is one component per such bump."""
    centres = bump_centres()
    inside = np.flatnonzero(exact_solution(centres.T)[0] > ISO_VALUE)
    low = np.array([0.0, 0.0, 0.0])
    axes = [np.arange(low[a], high + spacing / 2, spacing)
            for a, high in enumerate((OUTER_RADIUS, OUTER_RADIUS, HEIGHT + BULGE))]
    plane = np.stack(np.meshgrid(axes[1], axes[2], indexing="ij"), axis=0)
    above = np.zeros([len(a) for a in axes], dtype=bool)
    for i, x in enumerate(axes[0]):  # a plane x = const at a time: little memory
        grid = np.concatenate([np.full((1,) + plane.shape[1:], x), plane], axis=0)
        above[i] = (exact_solution(grid)[0] > ISO_VALUE) & inside_part(grid)
    centre_voxels = [tuple(np.rint((centres[b] - low) / spacing).astype(int)) for b in inside]
    for voxel in centre_voxels:
        above[voxel] = True
    labels, count = ndimage.label(above)
    if count != len(inside) or len({labels[voxel] for voxel in centre_voxels}) != len(inside):
        sys.exit(f"exact level set: expected {len(inside)} pieces, one per bump, "
                 f"got {count} on a {spacing} grid")
    return inside


def level_set_radius(centre, directions, reach):
    """Per unit direction d (n x 3), the t in (0, reach) with u(centre + t d) = ISO_VALUE, by
    bisection (u falls along each ray from a bump's centre through its piece)."""
    low = np.zeros(len(directions))
    high = np.full(len(directions), reach)
    for _ in range(60):
        middle = 0.5 * (low + high)
        above = exact_solution((centre + middle[:, None] * directions).T)[0] > ISO_VALUE
        low = np.where(above, middle, low)
        high = np.where(above, high, middle)
    return 0.5 * (low + high)


def contour_facts(path):
    """What vtkContourFilter makes of u = ISO_VALUE: its triangle count, its connected pieces
    (coincident points merged), and per bump the triangles nearest that bump's centre (in units
    of its width), their vertices' and centres' largest distance from the exact level set along
    the ray from the bump's centre, and the exact piece's mean radius along those rays."""
    contour = vtkContourFilter()
    contour.SetInputData(read_grid(path))
    contour.SetInputArrayToProcess(0, 0, 0, 0, "u")
    contour.SetValue(0, ISO_VALUE)
    contour.ComputeScalarsOff()
    clean = vtkCleanPolyData()
    clean.SetInputConnection(contour.GetOutputPort())
    pieces = vtkPolyDataConnectivityFilter()
    pieces.SetInputConnection(clean.GetOutputPort())
    pieces.SetExtractionModeToAllRegions()
    pieces.Update()
    surface = clean.GetOutput()
    triangles = surface.GetNumberOfCells()
    per_bump = [(0, 0.0, 0.0, 0.0)] * len(BUMPS)
    if triangles == 0:
        return triangles, 0, per_bump
    vertices = vtk_to_numpy(surface.GetPoints().GetData())
    corners = vertices[vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)]
    middles = corners.mean(axis=1)
    centres = bump_centres()
    scaled = np.stack([np.linalg.norm(middles - centres[b], axis=1) / width
                       for b, (_, width, _) in enumerate(BUMPS)], axis=1)
    nearest = scaled.argmin(axis=1)
    for b, (_, width, _) in enumerate(BUMPS):
        mine = nearest == b
        if not np.any(mine):
            continue
        deviation = []
        for p in (corners[mine].reshape(-1, 3), middles[mine]):
            offset = p - centres[b]
            length = np.linalg.norm(offset, axis=1)
            radius = level_set_radius(centres[b], offset / length[:, None], 4 * width)
            deviation.append(np.abs(length - radius).max())
        per_bump[b] = (np.count_nonzero(mine), deviation[0], deviation[1], radius.mean())
    return triangles, pieces.GetNumberOfExtractedRegions(), per_bump


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="build/hex_poisson.vtu", help="output .vtu")
    parser.add_argument("--image", help="also draw vtkContourFilter's isosurface to this PNG "
                                        "(Scripts/hex_poisson_view.py under xvfb-run -a)")
    args = parser.parse_args()
    start_all = time.perf_counter()

    order = vtk_order()
    print(f"VTK node k is ElementHexS2's local node {order.tolist()}[k] "
          f"(scikit-fem's reference point 1 - VTK's parametric point)")
    measured = []
    for level in LEVELS:
        start = time.perf_counter()
        mesh, box_nodes = make_mesh(level)
        u, basis = solve_poisson(mesh, box_nodes)
        solved = time.perf_counter()
        measured.append(errors(mesh, u))
        print(f"level {level}: {mesh.nelements} cells, {mesh.doflocs.shape[1]} nodes; "
              f"solve {solved - start:.1f} s, errors {time.perf_counter() - solved:.1f} s: " +
              ", ".join(f"{name} {value:.3e}" for name, value in measured[-1].items()))
    failed = False
    for (coarse_level, coarse), (fine_level, fine) in zip(zip(LEVELS, measured),
                                                          zip(LEVELS[1:], measured[1:])):
        rates = {name: np.log(coarse[name] / fine[name]) / np.log(fine_level / coarse_level)
                 for name in ("L2", "H1 seminorm")}
        print(f"observed rates, level {coarse_level} to {fine_level}: L2 {rates['L2']:.2f} "
              f"(expected 3, accepted >= {MIN_L2_RATE}), H1 seminorm "
              f"{rates['H1 seminorm']:.2f} (expected 2, accepted >= {MIN_H1_RATE})")
        failed |= rates["L2"] < MIN_L2_RATE or rates["H1 seminorm"] < MIN_H1_RATE
    if failed:
        sys.exit("convergence check FAILED")

    # The finest level: checks of its mesh and solution, the file.
    points = np.ascontiguousarray(mesh.doflocs.T)
    cells = np.ascontiguousarray(basis.element_dofs.T[:, order])
    deviation = curved_cells(points, cells)
    print(f"finest mesh: {np.count_nonzero(deviation > 1e-12)} of {len(cells)} cells curved "
          f"(mid-edge nodes up to {deviation.max():.2e} off their chords)")
    pieces = exact_pieces()
    print(f"exact level set u = {ISO_VALUE}: {len(pieces)} closed pieces, one per bump "
          f"(checked on a 0.01 grid)")
    for b, (centre, (_, width, _)) in enumerate(zip(bump_centres(), BUMPS)):
        at_centre = evaluate_at(basis, u, centre)
        exact_at_centre = exact_solution(centre)[0]
        # An isolated bump's piece is the sphere of radius s sqrt(2 ln(u(c) / iso-value)).
        radius = width * np.sqrt(2 * np.log(exact_at_centre / ISO_VALUE))
        print(f"  bump {b} at {np.round(centre, 4).tolist()}: exact u(c) - iso "
              f"{exact_at_centre - ISO_VALUE:.4f}, FE u(c) - iso {at_centre - ISO_VALUE:.4f}, "
              f"piece radius ~{radius:.3f}")
        if at_centre <= ISO_VALUE:
            sys.exit(f"the FE solution at bump {b}'s centre is below the iso-value: "
                     f"its level set misses a piece")

    arrays = {"u": u, "u_exact": exact_solution(mesh.doflocs)[0]}
    write_vtu(args.out, points, cells, arrays)
    with open(args.out, "rb") as written:
        digest = hashlib.sha256(written.read()).hexdigest()
    print(f"wrote {args.out} ({os.path.getsize(args.out) / 1e6:.2f} MB, sha256 {digest}): "
          f"{len(cells)} cells, {len(points)} points, u in [{u.min():.4f}, {u.max():.4f}]")

    nodes, geometry, values, recovered, determinant, part = check_file(
        args.out, points, cells, arrays, basis, u, box_nodes)
    print(f"file check ({len(cells)} cells, {SAMPLES} random points and the centre in each): "
          f"nodes vs scikit-fem's map at 1 - r_k {nodes:.1e}; VTK's EvaluateLocation vs "
          f"scikit-fem's map {geometry:.1e}; VTK's InterpolateFunctions vs scikit-fem's "
          f"interpolation at the same physical points {values:.1e} (relative to max |u|; "
          f"scikit-fem's inverse map found 1 - r to {recovered:.1e}); VTK's smallest "
          f"det(dx/dr) {determinant:.2e}; the serendipity geometry within {part:.1e} of "
          f"part_map")
    if max(nodes, geometry, values) > 1e-12 or determinant <= 0:
        sys.exit("file check FAILED")

    triangles, regions, per_bump = contour_facts(args.out)
    missing = [int(b) for b in pieces if per_bump[b][0] == 0]
    print(f"vtkContourFilter at u = {ISO_VALUE}: {triangles} triangles in {regions} connected "
          f"pieces against the exact {len(pieces)}; no triangle at bumps {missing}")
    for b, (count, at_vertices, at_centres, radius) in enumerate(per_bump):
        if count == 0:
            print(f"  bump {b}: no triangles")
            continue
        print(f"  bump {b}: {count} triangles, off the exact level set by up to "
              f"{at_vertices:.4f} (vertices) and {at_centres:.4f} (triangle centres) along the "
              f"rays from the bump's centre; the exact piece's radius {radius:.4f}")
    print(f"total {time.perf_counter() - start_all:.1f} s")

    if args.image:
        view = os.path.join(os.path.dirname(os.path.abspath(__file__)), "hex_poisson_view.py")
        subprocess.run(["xvfb-run", "-a", sys.executable, view, args.out, args.image],
                       check=True)


if __name__ == "__main__":
    main()
