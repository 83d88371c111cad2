#!/usr/bin/env python3
"""A Poisson problem solved with isoparametric P3 elements on a curved mesh of the unit ball,
written as VTK_LAGRANGE_TETRAHEDRON cells (20 nodes) in the layout of dolfinx's VTKFile.

Run it through Scripts/make-p3-poisson.sh, which runs it, with its arguments, in the venv that
Scripts/flow-venv.sh makes or reuses (gmsh, scipy, and ParaView's VTK). Data/p3_poisson.vtu and
its picture are the default run:

  bash Scripts/make-p3-poisson.sh --out Data/p3_poisson.vtu \
      --image docs/images/p3_poisson_contour.png

The problem: -laplace(u) = f in the unit ball, u = g on the sphere, with f and g taken from the
known solution u = sum of five Gaussian bumps a exp(-|x - c|^2 / (2 s^2)) (BUMPS below). Its level
set u = ISO_VALUE (0.5, Scripts/p3_poisson_view.py) is five closed pieces: one around each bump,
since every peak value exceeds 0.5 and the bumps are far apart; three of the peaks exceed it by
only 2 to 7 %, so those pieces are 0.03 to 0.05 across, smaller than the cells around them.

gmsh (OpenCASCADE sphere) meshes it with third-order tetrahedra (Mesh.ElementOrder = 3) whose
boundary nodes lie on the sphere, edge length s near each bump (--size-factor scales every
length), growing to 0.3 away from them. The script's own assembly (numpy, scipy; scikit-fem has
no P3 tetrahedron) uses the isoparametric map x(r) = sum_i X_i phi_i(r) of the 20 nodes, with the
P3 Lagrange basis phi_i built from VTK's reference nodes (the inverse Vandermonde matrix of the
20 monomials of degree <= 3) and gmsh's 43-point degree-8 Gauss rule; a sparse LU solves it.

The error against the exact solution is printed and asserted: the problem is solved again on a
mesh with every length doubled, and the observed rates log2(e(2h) / e(h)) of the L2 and
H1-seminorm errors must be near P3's 4 and 3 (with gmsh's 2nd-degree rule "Gauss2" instead of
Gauss8 the errors grow without bound; a basis whose node order differs from the mesh's inverts
cells, which the assembly refuses); the FE solution at each bump's centre must exceed ISO_VALUE
(so that its own level set has all five pieces). The rates do not test the curved boundary: u is
defined beyond the ball and below 0.01 on the sphere, and a straight-sided run
(Mesh.SecondOrderLinear = 1) gives the same rates; the mesh check (boundary nodes on the sphere to
1e-12) and the file check (VTK's map against gmsh's) do.

The .vtu follows dolfinx's io.VTKFile for a P3 function on a P3 mesh (cpp/dolfinx/io/VTKFile.cpp):
one piece, ascii, Points (Float64 x 3) one per node and shared by the cells that meet there,
Cells connectivity and offsets (Int32) and types (Int8, 71), CellData vtkGhostType (UInt8) and
vtkOriginalCellIds (Int64), PointData vtkOriginalPointIds (Int64), vtkGhostType (UInt8) and the
functions, Scalars="u". Point arrays: "u" (the FE solution), "u_exact" (the exact solution at the
nodes) and "error" (u - u_exact). The node order within a cell is VTK's, found by matching gmsh's
reference node coordinates with those of VTK's own vtkLagrangeTetra; the script reads the file
back and checks VTK's geometry (EvaluateLocation) against gmsh's element map and its
interpolation (InterpolateFunctions) against the script's own P3 basis at random points.

Finally it counts what vtkContourFilter makes of the level set ISO_VALUE (triangles, connected
pieces, which of the five it misses, how far its triangles' vertices and centres lie from the
exact surface) and, with --image, has Scripts/p3_poisson_view.py draw it (under xvfb-run).

Measured on the 2-core development machine (load about 1), the default run: 2,885 cells (699
curved), 13,809 nodes, 2.13 MB; mesh 0.2 s, solve 3.9 s, 7.4 s in all with the picture, peak
memory 0.46 GB; errors: nodal max 7.1e-3, L2 1.24e-3, H1 seminorm 6.1e-2 (on the doubled mesh,
215 cells: 2.9e-1, 2.97e-2, 0.65; rates 4.59 and 3.42); the file check 1.1e-15 at worst;
vtkContourFilter: 1,756 triangles in 4 pieces of the 5, the missing one the bump 2 % above 0.5.
The written file is the same byte for byte on every run.
"""
import argparse
import hashlib
import os
import subprocess
import sys
import time

import gmsh
import numpy as np
import scipy.ndimage as ndimage
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable, vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_LAGRANGE_TETRAHEDRON, vtkLagrangeTetra
from vtkmodules.vtkFiltersCore import (vtkCleanPolyData, vtkContourFilter,
                                       vtkPolyDataConnectivityFilter)
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

from flow_mesh_io import tetrahedra_nodes
from p3_poisson_view import ISO_VALUE

GMSH_TET20 = 29
NODES = 20
RADIUS = 1.0
# The exact solution's bumps: (centre c, width s, peak a); u = sum a exp(-|x - c|^2 / (2 s^2)).
BUMPS = [((-0.30, -0.10, 0.00), 0.22, 1.00),
         ((0.35, 0.35, 0.10), 0.10, 0.70),
         ((0.40, -0.30, -0.20), 0.07, 0.53),
         ((0.00, 0.45, -0.35), 0.07, 0.505),
         ((0.10, -0.40, 0.40), 0.07, 0.52)]
# Edge length: the bump's width within 1.5 widths of its centre, growing by GRADING per unit
# distance beyond, at most FAR_SIZE (all times --size-factor).
FAR_SIZE, GRADING = 0.3, 0.5
# The smallest observed convergence rates accepted (P3 in theory: 4 in L2, 3 in H1).
MIN_L2_RATE, MIN_H1_RATE = 3.5, 2.6
QUADRATURE = "Gauss8"  # gmsh's rule exact for degree 8 (43 points)


def exact_solution(x):
    """u, grad u and laplace(u) of the bumps at points x (..., 3)."""
    u = np.zeros(x.shape[:-1])
    gradient = np.zeros(x.shape)
    laplacian = np.zeros(x.shape[:-1])
    for centre, width, peak in BUMPS:
        d = x - np.asarray(centre)
        r2 = np.einsum("...k,...k->...", d, d)
        bump = peak * np.exp(-r2 / (2 * width ** 2))
        u += bump
        gradient -= bump[..., None] * d / width ** 2
        # laplace exp(-r^2 / (2 s^2)) = (r^2 / s^4 - 3 / s^2) exp(-r^2 / (2 s^2)) in 3D.
        laplacian += bump * (r2 / width ** 4 - 3 / width ** 2)
    return u, gradient, laplacian


def vtk_reference_nodes():
    """VTK's parametric coordinates of vtkLagrangeTetra's 20 nodes (20 x 3), from the cell."""
    cell = vtkLagrangeTetra()
    cell.GetPointIds().SetNumberOfIds(NODES)
    cell.GetPoints().SetNumberOfPoints(NODES)
    for i in range(NODES):
        cell.GetPointIds().SetId(i, i)
        cell.GetPoints().SetPoint(i, 0.0, 0.0, 0.0)
    cell.Initialize()  # sizes the cell's parametric lattice (without it VTK 9.2 crashes here)
    coords = cell.GetParametricCoords()
    return np.array([coords[i] for i in range(3 * NODES)]).reshape(NODES, 3)


def gmsh_to_vtk_order(gmsh_nodes, vtk_nodes):
    """order[k] = the gmsh node at VTK node k's reference position; exits unless one to one."""
    distance = np.linalg.norm(vtk_nodes[:, None, :] - gmsh_nodes[None, :, :], axis=2)
    order = distance.argmin(axis=1)
    # Lattice points are 1/3 apart: anything above 1e-9 is no match.
    if distance[np.arange(NODES), order].max() > 1e-9 or len(set(order)) != NODES:
        sys.exit(f"gmsh's and VTK's 20-node reference tetrahedra do not match:\n"
                 f"gmsh {gmsh_nodes.tolist()}\nVTK {vtk_nodes.tolist()}")
    return order


class P3Basis:
    """The P3 Lagrange basis of the reference tetrahedron whose nodes are the given 20 points:
    phi_i = sum_k C[k, i] m_k with m_k the monomials r^a s^b t^c (a + b + c <= 3) and
    C = V^-1, V[j, k] = m_k(node_j), so that phi_i(node_j) = delta_ij."""

    EXPONENTS = np.array([(a, b, c) for a in range(4) for b in range(4) for c in range(4)
                          if a + b + c <= 3])

    def __init__(self, nodes):
        self.coefficients = np.linalg.inv(self._monomials(nodes))

    def _monomials(self, r):
        return np.prod(r[:, None, :] ** self.EXPONENTS[None, :, :], axis=2)

    def values(self, r):
        """phi_i(r_q), (q x 20)."""
        return self._monomials(r) @ self.coefficients

    def gradients(self, r):
        """d phi_i / d r_k at r_q, (q x 20 x 3)."""
        result = np.empty((len(r), NODES, 3))
        for k in range(3):
            lowered = self.EXPONENTS.copy()
            factor = lowered[:, k].astype(float)
            lowered[:, k] = np.maximum(lowered[:, k] - 1, 0)
            derivative = factor * np.prod(r[:, None, :] ** lowered[None, :, :], axis=2)
            result[:, :, k] = derivative @ self.coefficients
        return result


def mesh_ball(size_factor, sample_points):
    """The curved P3 mesh: points (n x 3), cells (m x 20, VTK order), the boundary nodes, gmsh's
    element map at the reference points sample_points (m x p x 3, for the file check), the order
    (VTK node k is gmsh node order[k]) and gmsh's smallest Jacobian determinant."""
    gmsh.initialize(readConfigFiles=False)  # no user gmshrc: reproducible meshes
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)  # one thread: the same mesh every run
        gmsh.model.add("ball")
        gmsh.model.occ.addSphere(0, 0, 0, RADIUS)
        gmsh.model.occ.synchronize()
        field = gmsh.model.mesh.field
        sizes = []
        for (cx, cy, cz), width, _ in BUMPS:
            size = field.add("MathEval")
            distance = f"sqrt((x - ({cx}))^2 + (y - ({cy}))^2 + (z - ({cz}))^2)"
            field.setString(size, "F", f"{size_factor} * min({FAR_SIZE}, {width} + {GRADING} * "
                                       f"max(0, {distance} - {1.5 * width}))")
            sizes.append(size)
        smallest = field.add("Min")
        field.setNumbers(smallest, "FieldsList", sizes)
        field.setAsBackgroundMesh(smallest)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        # Third-order cells whose boundary nodes gmsh puts on the sphere (curved cells).
        gmsh.option.setNumber("Mesh.ElementOrder", 3)
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)
        gmsh.model.mesh.generate(3)

        _, _, _, node_count, gmsh_nodes, _ = gmsh.model.mesh.getElementProperties(GMSH_TET20)
        order = gmsh_to_vtk_order(np.reshape(gmsh_nodes, (node_count, 3)), vtk_reference_nodes())
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        _, cell_node_tags = gmsh.model.mesh.getElementsByType(GMSH_TET20)
        (sphere,) = [tag for _, tag in gmsh.model.getBoundary([(3, 1)], oriented=False)]
        boundary_tags, _, _ = gmsh.model.mesh.getNodes(2, sphere, includeBoundary=True)
        # gmsh's own element map x(r) and det(dx/dr) at the sample points (for the check).
        _, determinants, mapped = gmsh.model.mesh.getJacobians(GMSH_TET20,
                                                               sample_points.ravel())
        _, quadrature_determinants, _ = gmsh.model.mesh.getJacobians(
            GMSH_TET20, gmsh.model.mesh.getIntegrationPoints(GMSH_TET20, QUADRATURE)[0])
    finally:
        gmsh.finalize()
    points, cells = tetrahedra_nodes(node_tags, coords, cell_node_tags, NODES)
    # tetrahedra_nodes numbered the used nodes by sorted tag: find the boundary ones.
    used = np.unique(np.asarray(cell_node_tags, dtype=np.int64))
    boundary = np.searchsorted(used, np.intersect1d(used, np.asarray(boundary_tags)))
    gmsh_positions = np.reshape(mapped, (len(cells), len(sample_points), 3))
    smallest_determinant = min(np.min(determinants), np.min(quadrature_determinants))
    return points, cells[:, order], boundary, gmsh_positions, order, smallest_determinant


def gauss_rule():
    """gmsh's QUADRATURE on the reference tetrahedron: points (q x 3), weights (q)."""
    gmsh.initialize(readConfigFiles=False)
    try:
        points, weights = gmsh.model.mesh.getIntegrationPoints(GMSH_TET20, QUADRATURE)
    finally:
        gmsh.finalize()
    return np.reshape(points, (-1, 3)), np.asarray(weights)


def geometry(points, cells, basis, reference):
    """Physical points (m x q x 3), det(dx/dr) (m x q) and basis gradients in x (m x q x 20 x 3)
    of the isoparametric map at the reference points."""
    nodes = points[cells]                                     # m x 20 x 3
    physical = np.einsum("qi,mik->mqk", basis.values(reference), nodes)
    reference_gradients = basis.gradients(reference)          # q x 20 x 3
    jacobian = np.einsum("mia,qib->mqab", nodes, reference_gradients)  # dx_a / dr_b
    determinant = np.linalg.det(jacobian)
    # grad_x phi = J^-T grad_r phi: as a row vector, (grad_r phi) J^-1.
    gradients = np.einsum("qib,mqba->mqia", reference_gradients, np.linalg.inv(jacobian))
    return physical, determinant, gradients


def solve_poisson(points, cells, boundary, basis, rule):
    """Nodal values of the P3 Galerkin solution of -laplace(u) = f, u = g on the boundary."""
    reference, weights = rule
    physical, determinant, gradients = geometry(points, cells, basis, reference)
    if determinant.min() <= 0:
        sys.exit(f"inverted cell: det(dx/dr) = {determinant.min():.3e} at a quadrature point")
    dx = weights[None, :] * determinant                        # m x q
    stiffness = np.einsum("mq,mqia,mqja->mij", dx, gradients, gradients)
    _, _, laplacian = exact_solution(physical)
    load = np.einsum("mq,qi->mi", -laplacian * dx, basis.values(reference))

    rows = np.repeat(cells, NODES, axis=1).ravel()
    columns = np.tile(cells, (1, NODES)).ravel()
    matrix = sp.csr_matrix((stiffness.ravel(), (rows, columns)), shape=(len(points),) * 2)
    rhs = np.bincount(cells.ravel(), weights=load.ravel(), minlength=len(points))

    u = np.zeros(len(points))
    u[boundary], _, _ = exact_solution(points[boundary])  # the nodes are on the sphere
    free = np.setdiff1d(np.arange(len(points)), boundary)
    reduced_rhs = rhs[free] - matrix[free][:, boundary] @ u[boundary]
    u[free] = spla.spsolve(matrix[free][:, free].tocsc(), reduced_rhs)
    return u


def errors(points, cells, u, basis, rule):
    """Max nodal error, max error at the quadrature points, L2 error, H1-seminorm error, and the
    L2 and H1-seminorm norms of the exact solution."""
    reference, weights = rule
    physical, determinant, gradients = geometry(points, cells, basis, reference)
    dx = weights[None, :] * determinant
    exact, exact_gradient, _ = exact_solution(physical)
    value = np.einsum("qi,mi->mq", basis.values(reference), u[cells]) - exact
    gradient = np.einsum("mqia,mi->mqa", gradients, u[cells]) - exact_gradient
    nodal = np.abs(u - exact_solution(points)[0]).max()
    return {"nodal max": nodal, "quadrature-point max": np.abs(value).max(),
            "L2": np.sqrt(np.sum(dx * value ** 2)),
            "H1 seminorm": np.sqrt(np.sum(dx * np.sum(gradient ** 2, axis=2))),
            "L2 norm of u": np.sqrt(np.sum(dx * exact ** 2)),
            "H1 seminorm of u": np.sqrt(np.sum(dx * np.sum(exact_gradient ** 2, axis=2)))}


def evaluate_at(points, cells, u, basis, position):
    """The FE solution at a physical position: Newton's method on x(r) = position in each cell
    whose node box holds it; exits unless one cell holds it."""
    nodes = points[cells]
    margin = 0.1 * (nodes.max(axis=1) - nodes.min(axis=1)).max(axis=1, keepdims=True)
    candidates = np.flatnonzero(np.all((nodes.min(axis=1) - margin <= position) &
                                       (position <= nodes.max(axis=1) + margin), axis=1))
    for c in candidates:
        r = np.full((1, 3), 0.25)
        for _ in range(30):
            residual = basis.values(r)[0] @ nodes[c] - position
            jacobian = nodes[c].T @ basis.gradients(r)[0]
            r = r - np.linalg.solve(jacobian, residual)[None, :]
            if np.abs(residual).max() < 1e-14:
                break
        barycentric = np.append(r[0], 1 - r[0].sum())
        if np.abs(residual).max() < 1e-12 and barycentric.min() > -1e-10:
            return basis.values(r)[0] @ u[cells[c]]
    sys.exit(f"no cell holds {position}")


def write_dolfinx_vtu(path, points, cells, arrays):
    """Writes the cells as VTK_LAGRANGE_TETRAHEDRON in the layout of dolfinx's VTKFile (one
    ascii piece, ghost and original-id arrays, the point arrays as Float64, Scalars the first);
    numbers are written as the shortest decimal that reads back as the same double."""
    def numbers(values):
        return " ".join(repr(v) for v in np.asarray(values).ravel().tolist())

    def data_array(kind, name, values, components=None, extra=""):
        name = f' Name="{name}"' if name else ""
        components = f' NumberOfComponents="{components}"' if components else ""
        return (f'      <DataArray type="{kind}"{name}{components} format="ascii"{extra}>'
                f"{numbers(values)}</DataArray>\n")

    cell_ids = np.arange(len(cells))
    point_ids = np.arange(len(points))
    lines = ['<?xml version="1.0"?>\n',
             '<VTKFile type="UnstructuredGrid" version="2.2">\n', "  <UnstructuredGrid>\n",
             f'    <Piece NumberOfPoints="{len(points)}" NumberOfCells="{len(cells)}">\n',
             "    <Points>\n", data_array("Float64", None, points, 3), "    </Points>\n",
             "    <Cells>\n", data_array("Int32", "connectivity", cells),
             data_array("Int32", "offsets", NODES * (cell_ids + 1)),
             data_array("Int8", "types", np.full(len(cells), VTK_LAGRANGE_TETRAHEDRON)),
             "    </Cells>\n", "    <CellData>\n",
             data_array("UInt8", "vtkGhostType", np.zeros(len(cells), dtype=int),
                        extra=' RangeMin="0" RangeMax="1"'),
             data_array("Int64", "vtkOriginalCellIds", cell_ids,
                        extra=f' IdType="1" RangeMin="0" RangeMax="{len(cells) - 1}"'),
             "    </CellData>\n", f'    <PointData Scalars="{next(iter(arrays))}">\n',
             data_array("Int64", "vtkOriginalPointIds", point_ids,
                        extra=f' IdType="1" RangeMin="0" RangeMax="{len(points) - 1}"'),
             data_array("UInt8", "vtkGhostType", np.zeros(len(points), dtype=int),
                        extra=' RangeMin="0" RangeMax="0"')]
    lines += [data_array("Float64", name, values) for name, values in arrays.items()]
    lines += ["    </PointData>\n", "    </Piece>\n", "  </UnstructuredGrid>\n", "</VTKFile>\n"]
    with open(path, "w", encoding="ascii") as output:
        output.writelines(lines)


def read_grid(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def check_file(path, points, cells, u, basis, sample_points, gmsh_positions):
    """Reads the file back; exits unless it holds the mesh and u, VTK's element map agrees with
    gmsh's and with the script's, and VTK's interpolation of u with the script's P3 basis at the
    sample points of every cell. Returns the largest differences (relative to 1 and to max |u|)."""
    grid = read_grid(path)
    types = vtk_to_numpy(grid.GetCellTypesArray())
    file_points = vtk_to_numpy(grid.GetPoints().GetData())
    file_u = vtk_to_numpy(grid.GetPointData().GetArray("u"))
    if (len(types) != len(cells) or np.any(types != VTK_LAGRANGE_TETRAHEDRON)
            or grid.GetCell(0).GetNumberOfPoints() != NODES):
        sys.exit(f"{path}: expected {len(cells)} cells of type {VTK_LAGRANGE_TETRAHEDRON} "
                 f"with {NODES} nodes")
    if not (np.array_equal(file_points, points) and np.array_equal(file_u, u)):
        sys.exit(f"{path}: the points or u did not read back bit for bit")

    own_positions = np.einsum("pi,mik->mpk", basis.values(sample_points), points[cells])
    own_values = basis.values(sample_points) @ u[cells].T     # p x m
    location, weights, sub_id = [0.0] * 3, [0.0] * NODES, mutable(0)
    vtk_vs_gmsh = vtk_vs_own = value_difference = 0.0
    for c in range(len(cells)):
        cell = grid.GetCell(c)
        ids = [cell.GetPointId(k) for k in range(NODES)]
        if ids != cells[c].tolist():
            sys.exit(f"{path}: cell {c} has nodes {ids}, expected {cells[c].tolist()}")
        for p, r in enumerate(sample_points):
            cell.EvaluateLocation(sub_id, r, location, weights)
            vtk_vs_gmsh = max(vtk_vs_gmsh, np.abs(np.subtract(location,
                                                              gmsh_positions[c, p])).max())
            vtk_vs_own = max(vtk_vs_own, np.abs(np.subtract(location, own_positions[c, p])).max())
            cell.InterpolateFunctions(r, weights)
            value_difference = max(value_difference,
                                   abs(np.dot(weights, file_u[ids]) - own_values[p, c]))
    return vtk_vs_gmsh, vtk_vs_own, value_difference / np.abs(u).max()


def exact_pieces(spacing):
    """The closed pieces of the exact level set u = ISO_VALUE: the bumps whose centre value
    exceeds it, checked by labelling the voxels of {u > ISO_VALUE} on a grid of the given spacing
    (each bump's centre voxel counted in, as the smallest pieces fall between grid points);
    exits unless there is one component per such bump."""
    centres = np.array([centre for centre, _, _ in BUMPS])
    inside = np.flatnonzero(exact_solution(centres)[0] > ISO_VALUE)
    axis = np.arange(-RADIUS, RADIUS + spacing / 2, spacing)
    plane = np.stack(np.meshgrid(axis, axis, indexing="ij"), axis=-1)
    above = np.zeros((len(axis),) * 3, dtype=bool)
    for i, x in enumerate(axis):  # a plane x = const at a time: little memory
        grid = np.concatenate([np.full(plane.shape[:-1] + (1,), x), plane], axis=-1)
        above[i] = ((exact_solution(grid)[0] > ISO_VALUE)
                    & (np.linalg.norm(grid, axis=-1) <= RADIUS))
    for b in inside:
        above[tuple(np.rint((centres[b] + RADIUS) / spacing).astype(int))] = True
    labels, count = ndimage.label(above)
    centre_labels = {labels[tuple(np.rint((centres[b] + RADIUS) / spacing).astype(int))]
                     for b in inside}
    if count != len(inside) or len(centre_labels) != len(inside):
        sys.exit(f"exact level set: expected {len(inside)} pieces, one per bump, "
                 f"got {count} on a {spacing} grid")
    return inside


def level_set_radius(centre, directions, reach):
    """Per unit direction d, the t in (0, reach) with u(centre + t d) = ISO_VALUE, by bisection
    (u falls along each ray from a bump's centre through its piece; 60 halvings reach the
    double's resolution of reach)."""
    low = np.zeros(len(directions))
    high = np.full(len(directions), reach)
    for _ in range(60):
        middle = 0.5 * (low + high)
        above = exact_solution(centre + middle[:, None] * directions)[0] > ISO_VALUE
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
    centres = corners.mean(axis=1)
    scaled = np.stack([np.linalg.norm(centres - np.asarray(centre), axis=1) / width
                       for centre, width, _ in BUMPS], axis=1)
    nearest = scaled.argmin(axis=1)
    for b, (centre, width, _) in enumerate(BUMPS):
        mine = nearest == b
        if not np.any(mine):
            continue
        deviation = []
        for p in (corners[mine].reshape(-1, 3), centres[mine]):
            offset = p - np.asarray(centre)
            length = np.linalg.norm(offset, axis=1)
            radius = level_set_radius(np.asarray(centre), offset / length[:, None], 4 * width)
            deviation.append(np.abs(length - radius).max())
        per_bump[b] = (np.count_nonzero(mine), deviation[0], deviation[1], radius.mean())
    return triangles, pieces.GetNumberOfExtractedRegions(), per_bump


def solve(size_factor, basis, rule, sample_points):
    """Meshes, solves and measures at one resolution; returns what main writes and prints."""
    start = time.perf_counter()
    points, cells, boundary, gmsh_positions, order, smallest_determinant = mesh_ball(
        size_factor, sample_points)
    mesh_time = time.perf_counter() - start
    radii = np.linalg.norm(points[boundary], axis=1)
    print(f"size factor {size_factor}: {len(cells)} cells, {len(points)} nodes "
          f"({len(boundary)} on the sphere, |x| - 1 in [{radii.min() - 1:.1e}, "
          f"{radii.max() - 1:.1e}]), gmsh's smallest det(dx/dr) {smallest_determinant:.2e}, "
          f"mesh {mesh_time:.1f} s")
    if np.abs(radii - RADIUS).max() > 1e-12 or smallest_determinant <= 0:
        sys.exit("mesh check FAILED: boundary nodes off the sphere, or an inverted cell")
    start = time.perf_counter()
    u = solve_poisson(points, cells, boundary, basis, rule)
    measured = errors(points, cells, u, basis, rule)
    print(f"  solve {time.perf_counter() - start:.1f} s; errors: " +
          ", ".join(f"{name} {value:.3e}" for name, value in measured.items()))
    return points, cells, u, gmsh_positions, order, measured


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size-factor", type=float, default=1.0,
                        help="multiplies every target edge length (default 1)")
    parser.add_argument("--out", default="build/p3_poisson.vtu", help="output .vtu")
    parser.add_argument("--image", help="also draw vtkContourFilter's isosurface to this PNG "
                                        "(Scripts/p3_poisson_view.py under xvfb-run -a)")
    args = parser.parse_args()
    start_all = time.perf_counter()

    basis = P3Basis(vtk_reference_nodes())
    rule = gauss_rule()
    # Reference points for the file check: 4 random interior points and the centroid.
    sample_points = np.vstack([np.random.default_rng(3).dirichlet(np.ones(4), size=4)[:, 1:],
                               [[0.25, 0.25, 0.25]]])

    coarse = solve(2 * args.size_factor, basis, rule, sample_points)[-1]
    points, cells, u, gmsh_positions, order, fine = solve(args.size_factor, basis, rule,
                                                          sample_points)
    print(f"VTK node k is gmsh node {order.tolist()}[k]")
    rates = {name: np.log2(coarse[name] / fine[name]) for name in ("L2", "H1 seminorm")}
    print(f"observed rates (edge lengths halved): L2 {rates['L2']:.2f} "
          f"(expected 4, accepted >= {MIN_L2_RATE}), H1 seminorm {rates['H1 seminorm']:.2f} "
          f"(expected 3, accepted >= {MIN_H1_RATE})")
    if rates["L2"] < MIN_L2_RATE or rates["H1 seminorm"] < MIN_H1_RATE:
        sys.exit("convergence check FAILED")

    pieces = exact_pieces(0.01)
    print(f"exact level set u = {ISO_VALUE}: {len(pieces)} closed pieces, one per bump "
          f"(checked on a 0.01 grid)")
    for b, (centre, width, peak) in enumerate(BUMPS):
        at_centre = evaluate_at(points, cells, u, basis, np.asarray(centre))
        exact_at_centre = exact_solution(np.asarray(centre))[0]
        # An isolated bump's piece is the sphere of radius s sqrt(2 ln(u(c) / iso-value)).
        radius = width * np.sqrt(2 * np.log(exact_at_centre / ISO_VALUE))
        print(f"  bump {b} at {centre}: exact u(c) - iso {exact_at_centre - ISO_VALUE:.4f}, "
              f"FE u(c) - iso {at_centre - ISO_VALUE:.4f}, piece radius ~{radius:.3f}")
        if at_centre <= ISO_VALUE:
            sys.exit(f"the FE solution at bump {b}'s centre is below the iso-value: "
                     f"its level set misses a piece")

    nodal_exact = exact_solution(points)[0]
    write_dolfinx_vtu(args.out, points, cells, {"u": u, "u_exact": nodal_exact,
                                                "error": u - nodal_exact})
    with open(args.out, "rb") as written:
        digest = hashlib.sha256(written.read()).hexdigest()
    print(f"wrote {args.out} ({os.path.getsize(args.out) / 1e6:.2f} MB, sha256 {digest}): "
          f"u in [{u.min():.4f}, {u.max():.4f}]")

    geometry_gmsh, geometry_own, interpolation = check_file(args.out, points, cells, u, basis,
                                                            sample_points, gmsh_positions)
    print(f"file check at {len(sample_points)} points in each of the {len(cells)} cells: "
          f"VTK's EvaluateLocation vs gmsh's element map {geometry_gmsh:.1e}, vs the script's "
          f"{geometry_own:.1e}; VTK's InterpolateFunctions vs the script's P3 basis "
          f"{interpolation:.1e} (relative to max |u|)")
    if max(geometry_gmsh, geometry_own, interpolation) > 1e-12:
        sys.exit("file check FAILED")

    triangles, regions, per_bump = contour_facts(args.out)
    missing = [b for b in pieces if per_bump[b][0] == 0]
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
        view = os.path.join(os.path.dirname(os.path.abspath(__file__)), "p3_poisson_view.py")
        subprocess.run(["xvfb-run", "-a", sys.executable, view, args.out, args.image],
                       check=True)


if __name__ == "__main__":
    main()
