#!/usr/bin/env python3
"""Steady flow through a 3D sudden expansion, written as VTK_QUADRATIC_TETRA cells (.vtu).

Run it through Scripts/make-expansion-flow.sh, which makes the venv (gmsh, scikit-fem, pyamg)
and passes its arguments on. Data/expansion_flow.vtu is the default run:

  bash Scripts/make-expansion-flow.sh --out Data/expansion_flow.vtu --check

The geometry stands in for the "Newtonian expansion flow" of Simpson's paper: a square inlet duct
(1 x 1, 2 long, x in [6, 8]) opens into a square duct twice as wide and tall (2 x 2, 6 long,
x in [0, 6]); the fluid flows from right to left (-x), as in the paper's figure. gmsh meshes it
with second-order tetrahedra whose mid-edge nodes lie at the edge midpoints
(Mesh.SecondOrderLinear). scikit-fem solves steady incompressible flow with Taylor-Hood elements
(P2 velocity, P1 pressure): inflow u = -(1 - 4y^2)(1 - 4z^2) e_x at x = 8 (speed 1 on the axis),
no slip on the walls, do-nothing outflow at x = 0. --reynolds 0 gives Stokes flow; the default,
Reynolds number 50, gives a jet that reaches well into the wide duct and eddies in the corners
behind the step.

The .vtu has point arrays "velocity" (3 components), "speed" (its magnitude at the nodes, so a
quadratic interpolant of the speed, not the exact magnitude of the P2 velocity), "vx" (its
x-component: the main flow has vx < 0, so vx > 0 marks the backflow of the eddies) and "pressure"
(P1, so its mid-edge values are the means of the edge's vertex values). --check reads the written
file back with VTK and compares VTK's quadratic-tetra interpolation with scikit-fem's own
evaluation at random points in the cells.

Measured on the 2-core development machine (mesh: gmsh meshing; solve: assembly, Stokes flow,
then Picard steps, each linear system solved by GMRES with an algebraic multigrid block
preconditioner; solve times of two runs where the machine was also busy with other jobs;
memory: peak resident set size of the whole run):

  --size  --reynolds   cells    nodes    mesh    solve        Picard steps   .vtu      memory
  0.3     50            5103     8703    0.1 s    24 -  34 s  12             0.73 MB   0.4 GB
  0.25    50            8396    13728    0.2 s    43 -  85 s  13             1.22 MB   0.6 GB
  0.2     50           15904    25051    0.4 s    83 -  87 s  13             2.35 MB   1.1 GB
  0.15    50           37298    56533    0.9 s   209 - 256 s  13             5.72 MB   2.3 GB
  0.15     0           37298    56533    0.8 s    16 s         -             5.73 MB   2.1 GB
  0.1      0          119712   173235    4.4 s    49 s         -            18.70 MB   4.6 GB
"""
import argparse
import os
import sys
import time

import gmsh
import numpy as np
import pyamg
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import (Basis, BilinearForm, ElementTetP1, ElementTetP2, ElementVector, MeshTet, asm,
                   condense)
from skfem.helpers import dot, grad, mul
from skfem.models.general import divergence
from skfem.models.poisson import mass, vector_laplace
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable
from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_TETRA
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

from flow_mesh_io import tetrahedra_nodes, write_vtu

INLET_X, STEP_X, OUTLET_X = 8.0, 6.0, 0.0
INLET_HALF_WIDTH, OUTLET_HALF_WIDTH = 0.5, 1.0

# VTK_QUADRATIC_TETRA's mid-edge nodes 4..9 lie on these vertex pairs.
VTK_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
# gmsh's 10-node tetrahedron (element type 11) lists edge (2, 3) before edge (1, 3).
GMSH_TO_VTK = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]
GMSH_TET10 = 11

# Largest relative velocity change of a converged Picard step, and the most steps tried.
PICARD_TOLERANCE, PICARD_STEPS = 1e-8, 60


def mesh_expansion(size):
    """Nodes (n x 3) and 10-node cells (m x 10, VTK order) of the expansion, edge length ~size."""
    gmsh.initialize(readConfigFiles=False)  # no user gmshrc: reproducible meshes
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("expansion")
        wide = gmsh.model.occ.addBox(OUTLET_X, -OUTLET_HALF_WIDTH, -OUTLET_HALF_WIDTH,
                                     STEP_X - OUTLET_X, 2 * OUTLET_HALF_WIDTH,
                                     2 * OUTLET_HALF_WIDTH)
        narrow = gmsh.model.occ.addBox(STEP_X, -INLET_HALF_WIDTH, -INLET_HALF_WIDTH,
                                       INLET_X - STEP_X, 2 * INLET_HALF_WIDTH,
                                       2 * INLET_HALF_WIDTH)
        gmsh.model.occ.fuse([(3, wide)], [(3, narrow)])
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.model.mesh.generate(3)
        # Straight-sided quadratic cells: the affine P2 geometry scikit-fem solves on.
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 1)
        gmsh.model.mesh.setOrder(2)
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        _, cell_node_tags = gmsh.model.mesh.getElementsByType(GMSH_TET10)
    finally:
        gmsh.finalize()
    points, cells = tetrahedra_nodes(node_tags, coords, cell_node_tags)
    return points, cells[:, GMSH_TO_VTK]


def check_mesh(points, cells):
    """Exits unless every mid-edge node is its edge's midpoint and every cell has volume > 0."""
    midpoint_error = max(
        np.abs(points[cells[:, 4 + k]] - 0.5 * (points[cells[:, a]] + points[cells[:, b]])).max()
        for k, (a, b) in enumerate(VTK_EDGES))
    corner = points[cells[:, :4]]
    # Six times the signed volume; VTK's reference tetrahedron (0, e_x, e_y, e_z) has it > 0.
    volumes = np.linalg.det(corner[:, 1:] - corner[:, :1])
    print(f"mesh check: mid-edge nodes off their midpoints by at most {midpoint_error:.1e}, "
          f"6 x cell volume in [{volumes.min():.3e}, {volumes.max():.3e}]")
    if midpoint_error > 1e-12 * np.abs(points).max() or volumes.min() <= 0:
        sys.exit("mesh check FAILED")


@BilinearForm
def convection(u, v, w):
    """((wind . grad) u) . v: the Oseen linearisation of the convective term."""
    return dot(mul(grad(u), w["wind"]), v)


def solve_flow(points, cells, reynolds):
    """Taylor-Hood solution: (velocity basis, velocity DOFs, pressure basis, pressure).

    Stokes flow for reynolds == 0 (viscosity 1), else steady Navier-Stokes with viscosity
    1/reynolds (inlet speed 1, inlet width 1, density 1) by Picard iteration from Stokes flow.
    """
    vertex_nodes, vertex_of_cell = np.unique(cells[:, :4], return_inverse=True)
    mesh = MeshTet(np.ascontiguousarray(points[vertex_nodes].T),
                   np.ascontiguousarray(vertex_of_cell.reshape(-1, 4).T))
    velocity_basis = Basis(mesh, ElementVector(ElementTetP2()))
    pressure_basis = velocity_basis.with_element(ElementTetP1())
    viscosity = 1.0 / reynolds if reynolds > 0 else 1.0

    viscous = viscosity * asm(vector_laplace, velocity_basis)
    div = asm(divergence, velocity_basis, pressure_basis)
    pressure_mass = asm(mass, pressure_basis).diagonal()

    inlet = mesh.facets_satisfying(lambda x: np.isclose(x[0], INLET_X))
    outlet = mesh.facets_satisfying(lambda x: np.isclose(x[0], OUTLET_X))
    walls = np.setdiff1d(mesh.boundary_facets(), np.concatenate([inlet, outlet]))
    prescribed = np.union1d(velocity_basis.get_dofs(walls).all(),
                            velocity_basis.get_dofs(inlet).all())
    x_dofs = np.concatenate([velocity_basis.nodal_dofs[0], velocity_basis.edge_dofs[0]])
    inlet_x_dofs = np.intersect1d(velocity_basis.get_dofs(inlet).all(), x_dofs)
    y, z = velocity_basis.doflocs[1:, inlet_x_dofs]
    solution = np.zeros(velocity_basis.N + pressure_basis.N)
    solution[inlet_x_dofs] = -(1 - (y / INLET_HALF_WIDTH) ** 2) * (1 - (z / INLET_HALF_WIDTH) ** 2)
    # The outlet's natural condition (nu grad u - p I) n = 0 also fixes the pressure level.
    free = np.setdiff1d(np.arange(len(solution)), prescribed)
    velocity_count = np.count_nonzero(free < velocity_basis.N)

    def solve_linearised(momentum):
        """Solves [[momentum, -div^T], [-div, 0]] (u, p) = 0 for the free DOFs, in place."""
        system = sp.bmat([[momentum, -div.T], [-div, None]], format="csr")
        reduced, rhs = condense(system, np.zeros(len(solution)), x=solution, D=prescribed,
                                expand=False)
        momentum_free = reduced[:velocity_count, :velocity_count].tocsr()
        gradient_free = reduced[:velocity_count, velocity_count:]
        amg = pyamg.smoothed_aggregation_solver(
            momentum_free, symmetry="symmetric" if reynolds == 0 else "nonsymmetric"
        ).aspreconditioner()

        # Block upper-triangular preconditioner (Elman, Silvester & Wathen): an AMG V-cycle
        # for the momentum block, and -diag(pressure mass) / viscosity for the Schur complement
        # -div momentum^-1 div^T (spectrally equivalent for Stokes, fair at moderate Reynolds).
        def precondition(r):
            pressure_part = -viscosity * r[velocity_count:] / pressure_mass
            velocity_part = amg(r[:velocity_count] - gradient_free @ pressure_part)
            return np.concatenate([velocity_part, pressure_part])

        iterations = [0]

        def count(_):
            iterations[0] += 1

        result, info = spla.gmres(
            reduced, rhs, x0=solution[free], M=spla.LinearOperator(reduced.shape, precondition),
            rtol=1e-10, restart=200, maxiter=20, callback=count, callback_type="pr_norm")
        if info != 0:
            sys.exit(f"GMRES did not converge (info {info})")
        solution[free] = result
        return iterations[0]

    print(f"{velocity_basis.N} velocity + {pressure_basis.N} pressure unknowns")
    iterations = solve_linearised(viscous)
    print(f"Stokes flow: {iterations} GMRES iterations")
    picard_step = 0
    while reynolds > 0:
        picard_step += 1
        previous = solution[:velocity_basis.N].copy()
        wind = velocity_basis.interpolate(previous)
        iterations = solve_linearised(viscous + asm(convection, velocity_basis, wind=wind))
        change = (np.abs(solution[:velocity_basis.N] - previous).max()
                  / np.abs(solution[:velocity_basis.N]).max())
        print(f"Picard step {picard_step}: {iterations} GMRES iterations, "
              f"velocity change {change:.1e}")
        if change < PICARD_TOLERANCE:
            break
        if picard_step == PICARD_STEPS:
            sys.exit(f"Picard iteration did not converge in {PICARD_STEPS} steps")
    return velocity_basis, solution[:velocity_basis.N], pressure_basis, solution[velocity_basis.N:]


def nodal_fields(cells, velocity_basis, velocity, pressure_basis, pressure):
    """Velocity (n x 3) and pressure (n) at the mesh nodes, from the P2 and P1 DOFs."""
    mesh = velocity_basis.mesh
    node_count = cells.max() + 1
    nodal_velocity = np.zeros((node_count, 3))
    nodal_pressure = np.zeros(node_count)
    vertex_nodes = np.unique(cells[:, :4])  # skfem vertex i is node vertex_nodes[i]
    nodal_velocity[vertex_nodes] = velocity[velocity_basis.nodal_dofs].T
    nodal_pressure[vertex_nodes] = pressure[pressure_basis.nodal_dofs[0]]
    # skfem numbers its edges by sorted vertex pairs: look up each cell edge's pair.
    edge_keys = mesh.edges[0].astype(np.int64) * mesh.nvertices + mesh.edges[1]
    order = np.argsort(edge_keys)
    vertex_of_node = np.full(node_count, -1)
    vertex_of_node[vertex_nodes] = np.arange(len(vertex_nodes))
    for k, (a, b) in enumerate(VTK_EDGES):
        ends = np.sort(vertex_of_node[cells[:, [a, b]]], axis=1)
        edges = order[np.searchsorted(edge_keys, ends[:, 0] * mesh.nvertices + ends[:, 1],
                                      sorter=order)]
        nodal_velocity[cells[:, 4 + k]] = velocity[velocity_basis.edge_dofs[:, edges]].T
        nodal_pressure[cells[:, 4 + k]] = 0.5 * (nodal_pressure[cells[:, a]] +
                                                 nodal_pressure[cells[:, b]])
    return nodal_velocity, nodal_pressure


def check_file(path, velocity_basis, velocity, pressure_basis, pressure, cell_count, rng):
    """Largest relative difference between VTK's interpolation of the file and scikit-fem's."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    mesh = velocity_basis.mesh
    cell_types = vtk_to_numpy(grid.GetCellTypesArray())
    if len(cell_types) != mesh.nelements or np.any(cell_types != VTK_QUADRATIC_TETRA):
        sys.exit(f"{path}: expected {mesh.nelements} quadratic tetrahedra")
    file_velocity = vtk_to_numpy(grid.GetPointData().GetArray("velocity"))
    file_pressure = vtk_to_numpy(grid.GetPointData().GetArray("pressure"))

    # Four random points in each chosen cell: reference coordinates in scikit-fem's tetrahedron.
    cells = rng.choice(mesh.nelements, size=min(cell_count, mesh.nelements), replace=False)
    reference = rng.dirichlet(np.ones(4), size=4)[:, 1:].T
    quadrature = (reference, np.ones(reference.shape[1]))
    sample_velocity = Basis(mesh, velocity_basis.elem, quadrature=quadrature, elements=cells)
    sample_pressure = sample_velocity.with_element(pressure_basis.elem)
    positions = sample_velocity.global_coordinates().value
    expected_velocity = sample_velocity.interpolate(velocity).value
    expected_pressure = sample_pressure.interpolate(pressure).value

    file_points = vtk_to_numpy(grid.GetPoints().GetData())
    location, weights, sub_id = [0.0] * 3, [0.0] * 10, mutable(0)
    position_error = velocity_error = pressure_error = 0.0
    for i, c in enumerate(cells):
        cell = grid.GetCell(int(c))
        ids = [cell.GetPointId(k) for k in range(10)]
        corners = file_points[ids[:4]]
        # The cells are affine, so x = X0 + [X1-X0, X2-X0, X3-X0] r gives the parametric
        # coordinates r exactly (VTK 9.2's EvaluatePosition finds them only to ~1e-5 here).
        parametric = np.linalg.solve((corners[1:] - corners[0]).T,
                                     positions[:, i, :] - corners[0][:, None])
        for j in range(parametric.shape[1]):
            # VTK's quadratic-tetra shape functions: the position from the file's 10 nodes and
            # the weights that interpolate the file's nodal values.
            cell.EvaluateLocation(sub_id, parametric[:, j], location, weights)
            position_error = max(position_error, np.abs(np.subtract(location,
                                                                    positions[:, i, j])).max())
            velocity_error = max(velocity_error, np.abs(
                np.dot(weights, file_velocity[ids]) - expected_velocity[:, i, j]).max())
            pressure_error = max(pressure_error, abs(
                np.dot(weights, file_pressure[ids]) - expected_pressure[i, j]))
    return (position_error / np.abs(file_points).max(),
            velocity_error / np.abs(file_velocity).max(),
            pressure_error / np.abs(file_pressure).max(), len(cells) * reference.shape[1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=float, default=0.25,
                        help="target edge length of the tetrahedra (inlet width 1; default 0.25)")
    parser.add_argument("--reynolds", type=float, default=50.0,
                        help="Reynolds number of inlet speed and width (default 50); "
                             "0: Stokes flow")
    parser.add_argument("--out", default="build/expansion_flow.vtu", help="output .vtu")
    parser.add_argument("--check", action="store_true",
                        help="compare VTK's interpolation of the written file with scikit-fem's "
                             "at random points; exit 1 on a relative difference above 1e-12")
    args = parser.parse_args()

    start = time.perf_counter()
    points, cells = mesh_expansion(args.size)
    mesh_time = time.perf_counter() - start
    print(f"mesh: {len(cells)} cells, {len(points)} nodes, {mesh_time:.1f} s")
    check_mesh(points, cells)

    start = time.perf_counter()
    velocity_basis, velocity, pressure_basis, pressure = solve_flow(points, cells, args.reynolds)
    solve_time = time.perf_counter() - start
    print(f"solve: {solve_time:.1f} s")

    nodal_velocity, nodal_pressure = nodal_fields(cells, velocity_basis, velocity,
                                                  pressure_basis, pressure)
    speed = np.linalg.norm(nodal_velocity, axis=1)
    write_vtu(args.out, points, cells, {"velocity": nodal_velocity, "speed": speed,
                                        "vx": nodal_velocity[:, 0].copy(),
                                        "pressure": nodal_pressure})
    print(f"wrote {args.out} ({os.path.getsize(args.out) / 1e6:.2f} MB): "
          f"speed in [0, {speed.max():.4f}], "
          f"pressure in [{nodal_pressure.min():.3f}, {nodal_pressure.max():.3f}]")

    if args.check:
        errors = check_file(args.out, velocity_basis, velocity, pressure_basis, pressure, 5000,
                            np.random.default_rng(1))
        print(f"check: {errors[3]} random points, VTK vs scikit-fem relative difference "
              f"{errors[0]:.1e} (position), {errors[1]:.1e} (velocity), {errors[2]:.1e} (pressure)")
        if max(errors[:3]) > 1e-12:
            sys.exit("check FAILED")


if __name__ == "__main__":
    main()
