#!/usr/bin/env python3
"""Steady flow around a cylinder (Schafer & Turek "3D-1Z", Re 20) on curved quadratic tetrahedra.

Run it through Scripts/make-cylinder-flow.sh, which runs it, with its arguments, in the venv that
Scripts/flow-venv.sh makes or reuses (gmsh, scikit-fem, scipy; shared with make-expansion-flow.sh).
Data/cylinder_flow.vtu is the default run:

  bash Scripts/make-cylinder-flow.sh --out Data/cylinder_flow.vtu --check

The benchmark: a channel [0, 2.5] x [0, 0.41] x [0, 0.41] minus a cylinder of diameter D = 0.1
whose axis is parallel to z through (x, y) = (0.5, 0.2) and which spans the whole height; inflow
u = (16 Um y z (H - y)(H - z) / H^4, 0, 0) at x = 0 (H = 0.41, Um = 0.45, so the mean velocity is
U = 0.2), no slip on the other walls and on the cylinder, do-nothing outflow at x = 2.5,
viscosity 1e-3, density 1: Reynolds number U D / nu = 20. Drag and lift coefficients:
c_D = 2 F_D / (U^2 D H), c_L = 2 F_L / (U^2 D H); the published reference values, computed on
much finer meshes than this one, are c_D = 6.18533 and c_L = 0.009401.

gmsh (OpenCASCADE: box minus cylinder) meshes it with second-order tetrahedra whose mid-edge
nodes on the cylinder lie ON the cylinder (Mesh.SecondOrderLinear = 0), so the cells there are
curved. Target edge lengths: --cylinder-size at the cylinder, growing linearly to --size at
--refine-distance from it; --size in the channel up to x = 1, growing linearly to --outflow-size
at the outflow. scikit-fem solves steady Navier-Stokes on the isoparametric quadratic mesh
(MeshTet2 built from gmsh's 10-node tetrahedra, whose node order the script finds by geometry:
gmsh lists the mid-edge nodes of edges (2, 3) and (1, 3) the other way round from VTK and
scikit-fem) with Taylor-Hood elements (P2 velocity, P1 pressure): Stokes flow, then Newton
steps. Each linear system is solved by GMRES with a block upper-triangular preconditioner: for
the momentum block, one sparse LU of the scalar Oseen operator (viscous + convection, the same
for the three components; Newton's extra term is left to GMRES), for the Schur complement the
least-squares commutator (Elman et al. 2006). The drag and lift come from the residual of the
momentum equations tested with the P2 function that is 1 on the cylinder and 0 at all other
nodes (the volume-integral form of the surface force, as in John 2004; where the cylinder meets
the walls z = 0 and z = H, that function is not 0 on the walls' cells next to it, a
contribution that vanishes as the mesh is refined).

The .vtu has VTK_QUADRATIC_TETRA cells whose nodes are the isoparametric mesh's nodes (curved
mid-edge nodes kept as they are), point arrays "velocity" (3 components), "speed" (its magnitude
at the nodes), "vx" (its x-component: vx < 0 marks the recirculation behind the cylinder) and
"pressure" (P1, so its mid-edge values are the means of the edge's vertex values), and field
data "drag_coefficient", "lift_coefficient" and their published values. --check reads the file
back with VTK and compares VTK's quadratic-tetra interpolation with scikit-fem's evaluation on
the curved mesh at random points.

Measured on the 2-core development machine while other jobs kept it busy (load average 3 to 5),
so the times are only indicative. Sizes: --size / --cylinder-size / --outflow-size (all with
--refine-distance 0.1); curved: cells with a mid-edge node off its edge's midpoint by more than
1e-9 of the edge length; offset: the largest such distance relative to the edge length; solve:
assembly, Stokes flow, 6 Newton steps of 100 to 140 GMRES iterations each, forces; memory: peak
resident set size of the whole run. The default run (the last row) took 3.5 minutes in all.

  sizes                cells   nodes  curved  offset    .vtu    solve   memory
  0.1  / 0.02  / 0.1    4924    8703    1259   0.062   0.71 MB    24 s   0.6 GB
  0.08 / 0.008 / 0.08  18133   30445    6938   0.029   2.72 MB   181 s   1.9 GB
  0.06 / 0.012 / 0.06  17517   28579    3478   0.040   2.61 MB   153 s   1.8 GB
  0.05 / 0.012 / 0.1   15774   26140    3105   0.040   2.34 MB   129 s   1.6 GB
  0.045/ 0.01  / 0.1   20761   34152    4295   0.038   3.09 MB   177 s   2.1 GB
  0.04 / 0.015 / 0.1   21147   33764    2123   0.048   3.15 MB   176 s   1.7 GB
  0.04 / 0.012 / 0.1   22960   36883    3117   0.040   3.43 MB   204 s   1.9 GB   (default)

Forces: c_D and c_L from the volume integral (the printed values, written to the file), and from
the surface integral of the stress as a cross-check:

  sizes                c_D volume (vs 6.18533)   c_D surface   c_L volume   c_L surface
  0.1  / 0.02  / 0.1   6.21859  (+0.54%)          5.887          -0.0232       0.0082
  0.08 / 0.008 / 0.08  6.25185  (+1.08%)          6.188           0.0048       0.0067
  0.06 / 0.012 / 0.06  6.20762  (+0.36%)          6.094           0.0222       0.0114
  0.05 / 0.012 / 0.1   6.21005  (+0.40%)          6.065           0.0135       0.0136
  0.045/ 0.01  / 0.1   6.20607  (+0.34%)          6.095           0.0026      -0.0065
  0.04 / 0.015 / 0.1   6.18749  (+0.03%)          5.980          -0.0009       0.0014
  0.04 / 0.012 / 0.1   6.19569  (+0.17%)          6.048           0.0191       0.0111   (default)

The volume-integral drag is within 1.1% of the published value (0.03% to 1.08%), and depends on the
channel's edge length (--size) more than on the cylinder's: a finer cylinder in a coarse channel
(0.08 / 0.008) does worst, and the 0.03% of 0.04 / 0.015 is a lucky cancellation, not
convergence. The lift (0.15% of the drag) is not resolved on meshes this small: its computed
values scatter around the published 0.009401 by more than its size. The curved cylinder's area
on the isoparametric mesh is within 2e-5 (coarsest) to 5e-7 of pi D H.

--check on the default file (20,000 random points, half of them in curved cells): VTK's
EvaluateLocation at scikit-fem's reference coordinates gives the same position, velocity and
pressure to 7e-16, 4e-16 and 4e-16 (relative); VTK's EvaluatePosition, which finds the
parametric coordinates of a global point by Newton's method, stops within 1e-5 of them in
curved and straight cells alike, so its velocity differs by up to 1.5e-5 of the largest speed.
"""
import argparse
import os
import resource
import sys
import time

import gmsh
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import (Basis, BilinearForm, ElementTetP1, ElementTetP2, ElementVector, FacetBasis,
                   Functional, LinearForm, MeshTet2, asm, condense)
from skfem.helpers import dot, grad, mul
from skfem.models.general import divergence
from skfem.models.poisson import laplace, vector_laplace
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable, reference
from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_TETRA
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

from flow_mesh_io import tetrahedra_nodes, write_vtu

LENGTH, H = 2.5, 0.41                       # channel [0, LENGTH] x [0, H] x [0, H]
CENTRE, DIAMETER = (0.5, 0.2), 0.1          # cylinder axis (x, y), parallel to z
U_MAX, VISCOSITY = 0.45, 1e-3               # inflow centre-line speed; density 1
U_MEAN = 4 * U_MAX / 9                      # 0.2: mean inflow velocity
REFERENCE_DRAG, REFERENCE_LIFT = 6.18533, 0.009401
COARSEN_FROM_X = 1.0                        # the mesh coarsens towards the outflow from here

# VTK_QUADRATIC_TETRA's mid-edge nodes 4..9 lie on these vertex pairs (so do scikit-fem's
# MeshTet2 edge nodes: its reference tetrahedron lists the same edges in the same order).
VTK_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
GMSH_TET10 = 11
CURVED = 1e-9

# Largest relative velocity change of a converged Newton step, and the most steps tried.
NEWTON_TOLERANCE, NEWTON_STEPS = 1e-8, 20


def gmsh_to_vtk_order(points, cells):
    """The column order that puts gmsh's 10-node cells in VTK's node order, found by geometry.

    Each of gmsh's mid-edge slots 4..9 is matched with the vertex pair whose midpoint is nearest
    (largest distance over all cells, relative to the edge length); exits unless the matching is
    a permutation and every mid-edge node is much nearer its own edge's midpoint than any other.
    """
    slot_of_edge = {}
    for slot in range(4, 10):
        offsets = []
        for a, b in VTK_EDGES:
            ends = points[cells[:, a]], points[cells[:, b]]
            offsets.append((np.linalg.norm(points[cells[:, slot]] - 0.5 * (ends[0] + ends[1]),
                                           axis=1)
                            / np.linalg.norm(ends[1] - ends[0], axis=1)).max())
        best = int(np.argmin(offsets))
        if offsets[best] > 0.25 or sorted(offsets)[1] < 0.4:
            sys.exit(f"gmsh mid-edge slot {slot}: no clear edge (relative offsets {offsets})")
        slot_of_edge[best] = slot
    if sorted(slot_of_edge) != list(range(6)):
        sys.exit(f"gmsh mid-edge slots do not match VTK's edges one to one: {slot_of_edge}")
    return [0, 1, 2, 3] + [slot_of_edge[k] for k in range(6)]


def mesh_cylinder_channel(size, cylinder_size, refine_distance, outflow_size):
    """Nodes (n x 3), 10-node cells (m x 10, VTK order) and gmsh's order, curved at the cylinder."""
    gmsh.initialize(readConfigFiles=False)  # no user gmshrc: reproducible meshes
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("cylinder_channel")
        box = gmsh.model.occ.addBox(0, 0, 0, LENGTH, H, H)
        cylinder = gmsh.model.occ.addCylinder(CENTRE[0], CENTRE[1], 0, 0, 0, H, DIAMETER / 2)
        gmsh.model.occ.cut([(3, box)], [(3, cylinder)])
        gmsh.model.occ.synchronize()
        curved = [tag for dim, tag in gmsh.model.getEntities(2)
                  if gmsh.model.getType(dim, tag) != "Plane"]
        # Edge length cylinder_size on the cylinder, growing linearly to size at refine_distance.
        field = gmsh.model.mesh.field
        distance = field.add("Distance")
        field.setNumbers(distance, "SurfacesList", curved)
        field.setNumber(distance, "Sampling", 100)
        threshold = field.add("Threshold")
        field.setNumber(threshold, "InField", distance)
        field.setNumber(threshold, "SizeMin", cylinder_size)
        field.setNumber(threshold, "SizeMax", max(size, outflow_size))
        field.setNumber(threshold, "DistMin", 0.0)
        field.setNumber(threshold, "DistMax", refine_distance)
        # Edge length size up to x = COARSEN_FROM_X, then growing linearly to outflow_size at the
        # outflow (the flow there matters little for the forces on the cylinder).
        channel = field.add("MathEval")
        field.setString(channel, "F", f"{size} + {outflow_size - size} * "
                        f"max(0, x - {COARSEN_FROM_X}) / {LENGTH - COARSEN_FROM_X}")
        smallest = field.add("Min")
        field.setNumbers(smallest, "FieldsList", [threshold, channel])
        field.setAsBackgroundMesh(smallest)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.model.mesh.generate(3)
        # Mid-edge nodes of boundary edges on the geometry: curved cells at the cylinder.
        gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)
        gmsh.model.mesh.setOrder(2)
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        _, cell_node_tags = gmsh.model.mesh.getElementsByType(GMSH_TET10)
    finally:
        gmsh.finalize()
    points, cells = tetrahedra_nodes(node_tags, coords, cell_node_tags)
    order = gmsh_to_vtk_order(points, cells)
    return points, cells[:, order], order


def mid_edge_offsets(points, cells):
    """Per cell, the largest distance of a mid-edge node from its edge's midpoint, relative to
    the edge's length. The cell counts as curved where it exceeds CURVED."""
    return np.stack([
        np.linalg.norm(points[cells[:, 4 + k]] - 0.5 * (points[cells[:, a]] + points[cells[:, b]]),
                       axis=1) / np.linalg.norm(points[cells[:, b]] - points[cells[:, a]], axis=1)
        for k, (a, b) in enumerate(VTK_EDGES)], axis=1).max(axis=1)


def isoparametric_mesh(points, cells):
    """scikit-fem's MeshTet2 of the cells; exits unless its nodes are the cells' nodes and the
    isoparametric map has a positive Jacobian at every quadrature point."""
    mesh = MeshTet2(np.ascontiguousarray(points.T), np.ascontiguousarray(cells.T))
    # MeshTet2 renumbers the nodes (vertices first, then one node per edge): each cell's nodes
    # must still be the same points in the same (VTK) order.
    node_error = np.abs(mesh.doflocs[:, mesh.dofs.element_dofs].transpose(2, 0, 1)
                        - points[cells].transpose(0, 2, 1)).max()
    quadrature = Basis(mesh, ElementTetP1(), intorder=4).X
    det = mesh.mapping().detDF(np.hstack([quadrature, mesh.init_refdom().p]))
    volume = det.min(axis=1) / np.abs(det).max()  # smallest det per cell / largest overall
    print(f"isoparametric mesh: {mesh.nvertices} vertices + {mesh.nedges} edges, nodes moved by "
          f"{node_error:.1e}, smallest Jacobian determinant / largest {volume.min():.2e}")
    if node_error > 0 or volume.min() <= 0:
        sys.exit("isoparametric mesh check FAILED")
    return mesh


@Functional
def traction_x(w):
    """x-component of the stress (nu grad u - p I) n."""
    return VISCOSITY * mul(w["u"].grad, w.n)[0] - w["p"] * w.n[0]


@Functional
def traction_y(w):
    """y-component of the stress (nu grad u - p I) n."""
    return VISCOSITY * mul(w["u"].grad, w.n)[1] - w["p"] * w.n[1]


@Functional
def unit(w):
    """1: integrates to the area."""
    return np.ones_like(w.x[0])


@BilinearForm
def vector_mass(u, v, _):
    """u . v"""
    return dot(u, v)


@BilinearForm
def scalar_convection(u, v, w):
    """(wind . grad u) v: the Oseen convection of one velocity component."""
    return dot(w["wind"], grad(u)) * v


@BilinearForm
def convection_derivative(u, v, w):
    """((wind . grad) u + (u . grad) wind) . v: the derivative of the convective term."""
    return dot(mul(grad(u), w["wind"]) + mul(grad(w["wind"]), u), v)


@LinearForm
def convective_term(v, w):
    """((wind . grad) wind) . v"""
    return dot(mul(grad(w["wind"]), w["wind"]), v)


def solve_flow(mesh):
    """Taylor-Hood solution and forces: (velocity basis, velocity, pressure basis, pressure,
    forces), forces a dictionary of drag and lift coefficients and the cylinder's area."""
    velocity_basis = Basis(mesh, ElementVector(ElementTetP2()))
    pressure_basis = velocity_basis.with_element(ElementTetP1())

    viscous = VISCOSITY * asm(vector_laplace, velocity_basis)
    # One velocity component: the Oseen operator of the preconditioner is assembled on P2.
    scalar_basis = velocity_basis.with_element(ElementTetP2())
    scalar_viscous = VISCOSITY * asm(laplace, scalar_basis)
    div = asm(divergence, velocity_basis, pressure_basis)

    inlet = mesh.facets_satisfying(lambda x: np.isclose(x[0], 0.0))
    outlet = mesh.facets_satisfying(lambda x: np.isclose(x[0], LENGTH))
    channel_walls = mesh.facets_satisfying(
        lambda x: np.isclose(x[1], 0.0) | np.isclose(x[1], H) | np.isclose(x[2], 0.0)
        | np.isclose(x[2], H))
    boundary = mesh.boundary_facets()
    cylinder = np.setdiff1d(boundary, np.concatenate([inlet, outlet, channel_walls]))
    # Facet centroids of the (flat) vertex triangles lie just inside the circle of radius D/2.
    radius = np.hypot(*(mesh.p[:2, mesh.facets[:, cylinder]].mean(axis=1)
                        - np.array(CENTRE)[:, None]))
    if radius.min() < 0.45 * DIAMETER or radius.max() > 0.5 * DIAMETER + 1e-12:
        sys.exit(f"cylinder facets off the cylinder: radius in [{radius.min()}, {radius.max()}]")
    prescribed = np.unique(np.concatenate([velocity_basis.get_dofs(f).all()
                                           for f in (inlet, channel_walls, cylinder)]))
    x_dofs = np.concatenate([velocity_basis.nodal_dofs[0], velocity_basis.edge_dofs[0]])
    y_dofs = np.concatenate([velocity_basis.nodal_dofs[1], velocity_basis.edge_dofs[1]])
    inlet_x_dofs = np.intersect1d(velocity_basis.get_dofs(inlet).all(), x_dofs)
    y, z = velocity_basis.doflocs[1:, inlet_x_dofs]
    solution = np.zeros(velocity_basis.N + pressure_basis.N)
    solution[inlet_x_dofs] = 16 * U_MAX * y * z * (H - y) * (H - z) / H ** 4
    # The outlet's natural condition (nu grad u - p I) n = 0 also fixes the pressure level.
    free = np.setdiff1d(np.arange(len(solution)), prescribed)
    velocity_count = np.count_nonzero(free < velocity_basis.N)

    # The momentum block acts on each velocity component alike (the vector Laplacian and the
    # convection (w . grad) u are componentwise, and all three components are prescribed at the
    # same nodes): free_rows[c] are the rows of component c's free DOFs, node by node.
    velocity_free = free[:velocity_count]
    free_rows = []
    for c in range(3):
        dofs = np.concatenate([velocity_basis.nodal_dofs[c], velocity_basis.edge_dofs[c]])
        is_free = np.isin(dofs, velocity_free)
        if free_rows and np.any(is_free != free_nodes):
            sys.exit("velocity components prescribed at different nodes")
        free_nodes = is_free
        free_rows.append(np.searchsorted(velocity_free, dofs[is_free]))
    free_rows = np.array(free_rows)
    # Scalar P2 DOF k is node k, as is the k-th entry of each component's DOFs above.
    if abs(viscous[velocity_free][:, velocity_free][free_rows[0]][:, free_rows[0]]
           - scalar_viscous[free_nodes][:, free_nodes]).max() > 1e-12 * abs(scalar_viscous).max():
        sys.exit("vector and scalar viscous operators differ")
    # Diagonal of the (scalar) velocity mass matrix, for the least-squares commutator.
    lumped_mass = asm(vector_mass, velocity_basis).diagonal()[velocity_free]

    def solve_linearised(momentum, scalar_oseen, rhs, x):
        """Solves [[momentum, -div^T], [-div, 0]] y = rhs with y = x at the prescribed DOFs.

        Returns (y at the free DOFs, GMRES iterations). The preconditioner takes its momentum
        solves from the Oseen operator (viscous + convection), the same for every component:
        scalar_oseen is that of one component.
        """
        system = sp.bmat([[momentum, -div.T], [-div, None]], format="csr")
        reduced, reduced_rhs = condense(system, rhs, x=x, D=prescribed, expand=False)
        momentum_free = reduced[:velocity_count, :velocity_count].tocsr()
        gradient_free = reduced[:velocity_count, velocity_count:].tocsc()
        divergence_free = reduced[velocity_count:, :velocity_count].tocsr()
        # One sparse LU of the scalar Oseen block solves all three components.
        component_lu = spla.splu(scalar_oseen[free_nodes][:, free_nodes].tocsc())
        # Least-squares commutator (Elman, Howle, Shadid, Shuttleworth & Tuminaro 2006) for the
        # Schur complement S = -B F^-1 B^T, B = divergence_free, B^T = gradient_free:
        # S^-1 ~ -(B Q^-1 B^T)^-1 (B Q^-1 F Q^-1 B^T) (B Q^-1 B^T)^-1, Q = diag(velocity mass).
        pressure_lu = spla.splu((divergence_free @ sp.diags(1 / lumped_mass)
                                 @ gradient_free).tocsc())

        def precondition(r):
            """Block upper-triangular preconditioner: Oseen momentum solves, LSC Schur part."""
            pressure_part = pressure_lu.solve(r[velocity_count:])
            pressure_part = -pressure_lu.solve(divergence_free @ (
                momentum_free @ (gradient_free @ pressure_part / lumped_mass) / lumped_mass))
            velocity_rhs = r[:velocity_count] - gradient_free @ pressure_part
            velocity_part = np.empty(velocity_count)
            velocity_part[free_rows] = component_lu.solve(
                np.ascontiguousarray(velocity_rhs[free_rows].T)).T
            return np.concatenate([velocity_part, pressure_part])

        iterations = [0]

        def count(_):
            iterations[0] += 1

        result, info = spla.gmres(
            reduced, reduced_rhs, M=spla.LinearOperator(reduced.shape, precondition),
            rtol=1e-10, restart=200, maxiter=5, callback=count, callback_type="pr_norm")
        if info != 0:
            sys.exit(f"GMRES did not converge (info {info})")
        return result, iterations[0]

    print(f"{velocity_basis.N} velocity + {pressure_basis.N} pressure unknowns")
    solution[free], iterations = solve_linearised(viscous, scalar_viscous,
                                                  np.zeros(len(solution)), solution)
    print(f"Stokes flow: {iterations} GMRES iterations")
    # Newton's method from Stokes flow: J (du, dp) = -R(u, p), R the residual of the discrete
    # steady Navier-Stokes equations, J its derivative.
    for step in range(1, NEWTON_STEPS + 1):
        velocity = solution[:velocity_basis.N]
        wind = velocity_basis.interpolate(velocity)
        jacobian = viscous + asm(convection_derivative, velocity_basis, wind=wind)
        scalar_oseen = scalar_viscous + asm(scalar_convection, scalar_basis, wind=wind)
        residual = np.concatenate([
            viscous @ velocity + asm(convective_term, velocity_basis, wind=wind)
            - div.T @ solution[velocity_basis.N:], -div @ velocity])
        update, iterations = solve_linearised(jacobian, scalar_oseen, -residual,
                                              np.zeros(len(solution)))
        solution[free] += update
        change = np.abs(update[:velocity_count]).max() / np.abs(velocity).max()
        print(f"Newton step {step}: {iterations} GMRES iterations, velocity change {change:.1e}")
        if change < NEWTON_TOLERANCE:
            break
    else:
        sys.exit(f"Newton's method did not converge in {NEWTON_STEPS} steps")

    velocity, pressure = solution[:velocity_basis.N], solution[velocity_basis.N:]
    # Force on the cylinder: F . e = -(a(u, v) + c(u; u, v) - (p, div v)) with v = e at the
    # cylinder's nodes and 0 at all others (John 2004; the sign because the residual is the
    # force of the cylinder on the fluid).
    residual = (viscous @ velocity + asm(convective_term, velocity_basis,
                                         wind=velocity_basis.interpolate(velocity))
                - div.T @ pressure)
    cylinder_dofs = velocity_basis.get_dofs(cylinder).all()
    scale = 2 / (U_MEAN ** 2 * DIAMETER * H)
    drag = -scale * residual[np.intersect1d(cylinder_dofs, x_dofs)].sum()
    lift = -scale * residual[np.intersect1d(cylinder_dofs, y_dofs)].sum()
    # Cross-check: the surface integral of the stress over the curved cylinder facets, with the
    # fluid's outer normal n (F = -int (nu grad u - p I) n; less accurate than the volume form).
    facet_basis = FacetBasis(mesh, velocity_basis.elem, facets=cylinder, intorder=6)
    stress = dict(u=facet_basis.interpolate(velocity),
                  p=facet_basis.with_element(ElementTetP1()).interpolate(pressure))
    return velocity_basis, velocity, pressure_basis, pressure, {
        "drag": drag, "lift": lift,
        "surface drag": -scale * traction_x.assemble(facet_basis, **stress),
        "surface lift": -scale * traction_y.assemble(facet_basis, **stress),
        "area": unit.assemble(facet_basis)}


def nodal_fields(velocity_basis, velocity, pressure_basis, pressure):
    """Velocity (n x 3) and pressure (n) at the mesh nodes (mesh.doflocs), from the DOFs."""
    mesh = velocity_basis.mesh
    # MeshTet2's nodes are its vertices, then one per edge, as ElementTetP2's DOFs.
    dofs = np.hstack([velocity_basis.nodal_dofs, velocity_basis.edge_dofs])
    if np.abs(velocity_basis.doflocs[:, dofs[0]] - mesh.doflocs).max() > 0:
        sys.exit("velocity DOFs are not at the mesh nodes")
    vertex_pressure = pressure[pressure_basis.nodal_dofs[0]]
    nodal_pressure = np.concatenate([vertex_pressure,
                                     0.5 * vertex_pressure[mesh.edges].sum(axis=0)])
    return velocity[dofs].T.copy(), nodal_pressure


def check_file(path, velocity_basis, velocity, pressure_basis, pressure, cell_count, rng):
    """Compares VTK's interpolation of the written file with scikit-fem's at random points.

    Four random points in each of cell_count random cells (half of them curved), chosen by
    reference coordinates in scikit-fem's reference tetrahedron, which is VTK's (vertices 0,
    e_x, e_y, e_z). Returns a dictionary of
      - "position", "velocity", "pressure": the largest differences, relative to the largest
        coordinate, speed and pressure, of VTK's values at the same parametric coordinates
        (vtkQuadraticTetra::EvaluateLocation: its shape functions on the file's 10 nodes);
      - "found velocity", "found parametric", "outside" for curved and straight cells: VTK's
        velocity at the same global point (vtkQuadraticTetra::EvaluatePosition inverts the
        cell's map by Newton's method, then interpolates) relative to the largest speed, the
        largest parametric-coordinate difference, the number of points VTK places outside;
      - "points", "curved points": the number of points, of which in curved cells.
    """
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
    file_points = vtk_to_numpy(grid.GetPoints().GetData())
    file_cells = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 10)

    is_curved = mid_edge_offsets(file_points, file_cells) > CURVED
    count = min(cell_count, mesh.nelements)
    curved = rng.permutation(np.flatnonzero(is_curved))[:count // 2]
    cells = np.concatenate([curved, rng.permutation(np.flatnonzero(~is_curved))[
        :count - len(curved)]])
    reference_points = rng.dirichlet(np.ones(4), size=4)[:, 1:].T
    quadrature = (reference_points, np.ones(reference_points.shape[1]))
    sample_velocity = Basis(mesh, velocity_basis.elem, quadrature=quadrature, elements=cells)
    sample_pressure = sample_velocity.with_element(pressure_basis.elem)
    positions = sample_velocity.global_coordinates().value
    expected_velocity = sample_velocity.interpolate(velocity).value
    expected_pressure = sample_pressure.interpolate(pressure).value

    location, weights, sub_id = [0.0] * 3, [0.0] * 10, mutable(0)
    closest, parametric, distance2 = [0.0] * 3, [0.0] * 3, reference(0.0)
    errors = {"position": 0.0, "velocity": 0.0, "pressure": 0.0}
    for kind in ("curved", "straight"):
        errors.update({f"found velocity {kind}": 0.0, f"found parametric {kind}": 0.0,
                       f"outside {kind}": 0})
    for i, c in enumerate(cells):
        cell = grid.GetCell(int(c))
        ids = [cell.GetPointId(k) for k in range(10)]
        kind = "curved" if is_curved[c] else "straight"
        for j in range(reference_points.shape[1]):
            cell.EvaluateLocation(sub_id, reference_points[:, j], location, weights)
            errors["position"] = max(errors["position"], np.abs(
                np.subtract(location, positions[:, i, j])).max())
            errors["velocity"] = max(errors["velocity"], np.abs(
                np.dot(weights, file_velocity[ids]) - expected_velocity[:, i, j]).max())
            errors["pressure"] = max(errors["pressure"], abs(
                np.dot(weights, file_pressure[ids]) - expected_pressure[i, j]))
            inside = cell.EvaluatePosition(positions[:, i, j], closest, sub_id, parametric,
                                           distance2, weights)
            errors[f"outside {kind}"] += int(inside != 1)
            errors[f"found parametric {kind}"] = max(errors[f"found parametric {kind}"], np.abs(
                np.subtract(parametric, reference_points[:, j])).max())
            errors[f"found velocity {kind}"] = max(errors[f"found velocity {kind}"], np.abs(
                np.dot(weights, file_velocity[ids]) - expected_velocity[:, i, j]).max())
    speed = np.linalg.norm(file_velocity, axis=1).max()
    errors["position"] /= np.abs(file_points).max()
    errors["velocity"] /= speed
    errors["pressure"] /= np.abs(file_pressure).max()
    for kind in ("curved", "straight"):
        errors[f"found velocity {kind}"] /= speed
    errors["points"] = len(cells) * reference_points.shape[1]
    errors["curved points"] = len(curved) * reference_points.shape[1]
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=float, default=0.04,
                        help="target edge length in the channel up to x = 1 (default 0.04)")
    parser.add_argument("--cylinder-size", type=float, default=0.012,
                        help="target edge length at the cylinder (default 0.012; D = 0.1)")
    parser.add_argument("--refine-distance", type=float, default=0.1,
                        help="distance from the cylinder where the edge length reaches --size "
                             "(default 0.1)")
    parser.add_argument("--outflow-size", type=float, default=0.1,
                        help="target edge length at the outflow x = 2.5, reached linearly from "
                             "x = 1 (default 0.1)")
    parser.add_argument("--out", default="build/cylinder_flow.vtu", help="output .vtu")
    parser.add_argument("--check", action="store_true",
                        help="compare VTK's interpolation of the written file with scikit-fem's "
                             "at random points; exit 1 on a relative difference above 1e-12 at "
                             "the same parametric coordinates")
    args = parser.parse_args()
    run_start = time.perf_counter()

    start = time.perf_counter()
    points, cells, gmsh_order = mesh_cylinder_channel(args.size, args.cylinder_size,
                                                      args.refine_distance, args.outflow_size)
    mesh_time = time.perf_counter() - start
    offsets = mid_edge_offsets(points, cells)
    curved_cells, largest_offset = np.count_nonzero(offsets > CURVED), offsets.max()
    print(f"mesh: {len(cells)} cells, {len(points)} nodes, {mesh_time:.1f} s; "
          f"VTK node k is gmsh node {gmsh_order}[k]")
    print(f"curved cells: {curved_cells} (mid-edge node off its edge's midpoint by more than "
          f"1e-9 of the edge), largest offset {largest_offset:.4f} of the edge length")
    mesh = isoparametric_mesh(points, cells)

    start = time.perf_counter()
    velocity_basis, velocity, pressure_basis, pressure, forces = solve_flow(mesh)
    solve_time = time.perf_counter() - start
    print(f"solve: {solve_time:.1f} s")
    drag, lift = forces["drag"], forces["lift"]
    area = np.pi * DIAMETER * H
    print(f"cylinder area on the curved mesh {forces['area']:.7f} (exact {area:.7f}, relative "
          f"difference {(forces['area'] - area) / area:+.1e}); surface integral of the stress "
          f"(cross-check, less accurate): c_D = {forces['surface drag']:.4f}, "
          f"c_L = {forces['surface lift']:.4f}")
    print(f"drag coefficient c_D = {drag:.5f}   (published {REFERENCE_DRAG}, relative difference "
          f"{(drag - REFERENCE_DRAG) / REFERENCE_DRAG:+.2%})")
    print(f"lift coefficient c_L = {lift:.6f}  (published {REFERENCE_LIFT}, relative difference "
          f"{(lift - REFERENCE_LIFT) / REFERENCE_LIFT:+.1%})")

    nodal_velocity, nodal_pressure = nodal_fields(velocity_basis, velocity, pressure_basis,
                                                  pressure)
    speed = np.linalg.norm(nodal_velocity, axis=1)
    write_vtu(args.out, mesh.doflocs.T, mesh.dofs.element_dofs.T,
              {"velocity": nodal_velocity, "speed": speed, "vx": nodal_velocity[:, 0].copy(),
               "pressure": nodal_pressure},
              {"drag_coefficient": drag, "lift_coefficient": lift,
               "published_drag_coefficient": REFERENCE_DRAG,
               "published_lift_coefficient": REFERENCE_LIFT})
    print(f"wrote {args.out} ({os.path.getsize(args.out) / 1e6:.2f} MB): "
          f"speed in [0, {speed.max():.4f}], "
          f"pressure in [{nodal_pressure.min():.4f}, {nodal_pressure.max():.4f}]")

    failed = False
    if args.check:
        errors = check_file(args.out, velocity_basis, velocity, pressure_basis, pressure, 5000,
                            np.random.default_rng(1))
        print(f"check: {errors['points']} random points ({errors['curved points']} in curved "
              f"cells); VTK vs scikit-fem relative difference at the same parametric "
              f"coordinates: {errors['position']:.1e} (position), {errors['velocity']:.1e} "
              f"(velocity), {errors['pressure']:.1e} (pressure)")
        for kind in ("curved", "straight"):
            print(f"check: at the same global points in {kind} cells (VTK's EvaluatePosition "
                  f"finds the parametric coordinates): velocity "
                  f"{errors[f'found velocity {kind}']:.1e} relative to the largest speed, "
                  f"parametric coordinates off by up to {errors[f'found parametric {kind}']:.1e}, "
                  f"{errors[f'outside {kind}']} points reported outside their cell")
        failed = max(errors["position"], errors["velocity"], errors["pressure"]) > 1e-12
    memory = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
    print(f"total {time.perf_counter() - run_start:.1f} s, peak memory {memory:.2f} GB")
    if failed:
        sys.exit("check FAILED")


if __name__ == "__main__":
    main()
