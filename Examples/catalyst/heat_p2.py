"""In situ: a time-dependent finite-element simulation on P2 (10-node) tetrahedra hands each
step's mesh and temperature to ParaView Catalyst in memory, whose pipeline
(direct_surface_pipeline.py) writes a Direct Surface picture of the exact isosurfaces every N
steps. No file lies between the solver and the pictures.

The simulation (written here with scikit-fem): heat conduction in the unit cube, u_t = k lap u
+ f, u = 0 on the boundary, a Gaussian heat source circling the cube's axis; implicit Euler with
P2 elements. Under `mpirun -np N` every process solves the (small) problem and hands Catalyst
its share of the cells (a slab in x), as a distributed simulation owns its part of the mesh.

Usage (the venv of Scripts/flow-venv.sh has scikit-fem and sees ParaView's Python):
  bash Scripts/flow-venv.sh Examples/catalyst/heat_p2.py --out DIR [--steps 40] [--every 10]
      [--refine 3] [--plugin build/.../TetDSR.so]
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -np 2 build/flow-venv/bin/python \\
      Examples/catalyst/heat_p2.py --out DIR   (each rank on a display: Testing/Plugin/mpi_private_displays.py)
"""
import argparse
import glob
import os
import statistics
import sys
import time

import numpy as np
import skfem
from skfem.models.poisson import laplace, mass

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def vtk_edge_order(basis):
    """The permutation of a P2 cell's ten local dofs into VTK_QUADRATIC_TETRA's node order, from
    VTK's own node parametric coordinates: node k of VTK's cell at parametric point r_k is the dof
    of scikit-fem's reference element located there."""
    from vtkmodules.vtkCommonDataModel import vtkQuadraticTetra
    vtk_nodes = np.array(vtkQuadraticTetra().GetParametricCoords()).reshape(10, 3)
    # scikit-fem's reference dof locations: map the reference tetrahedron's vertices through
    # the dofs of one element of a reference mesh.
    reference = skfem.MeshTet(np.array([[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]),
                              np.array([[0], [1], [2], [3]]))
    ref_basis = skfem.Basis(reference, skfem.ElementTetP2())
    locations = ref_basis.doflocs[:, ref_basis.element_dofs[:, 0]].T  # (10, 3), local dof order
    order = [int(np.argmin(np.linalg.norm(locations - node, axis=1))) for node in vtk_nodes]
    if sorted(order) != list(range(10)) or not np.allclose(locations[order], vtk_nodes):
        raise RuntimeError("scikit-fem's P2 dofs do not sit at VTK's quadratic tetrahedron's nodes")
    return order


def check_node_order(basis, order, samples=200, seed=1):
    """A quadratic polynomial held by the P2 dofs, interpolated by VTK's own quadratic
    tetrahedron (its shape functions at random points of random cells), against the polynomial:
    the largest difference (rounding only when the node order is right)."""
    from vtkmodules.vtkCommonDataModel import vtkQuadraticTetra
    rng = np.random.default_rng(seed)
    q = lambda p: 1.0 + p[0] - 2 * p[1] + 0.5 * p[2] + p[0] * p[1] - 3 * p[2] ** 2 + 2 * p[0] * p[2]
    values = q(basis.doflocs)
    cell = vtkQuadraticTetra()
    weights = [0.0] * 10
    worst = 0.0
    for element in rng.integers(0, basis.element_dofs.shape[1], samples):
        dofs = basis.element_dofs[order, element]
        r = rng.dirichlet(np.ones(4))[1:]
        cell.InterpolateFunctions(r, weights)
        nodes = basis.doflocs[:, dofs]
        point = nodes[:, :4] @ np.r_[1 - r.sum(), r]  # straight cells: the vertices' affine map
        worst = max(worst, abs(np.dot(weights, values[dofs]) - q(point)))
    return worst


def to_vtk(basis, order, cells, values):
    """A vtkUnstructuredGrid of VTK_QUADRATIC_TETRA (the given cells) with the dof values."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_TETRA, vtkCellArray, vtkUnstructuredGrid
    grid = vtkUnstructuredGrid()
    points = vtkPoints()
    points.SetData(numpy_to_vtk(np.ascontiguousarray(basis.doflocs.T), deep=1))
    grid.SetPoints(points)
    connectivity = basis.element_dofs[:, cells].T[:, order]
    array = vtkCellArray()
    array.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 10 * len(cells) + 1, 10, dtype=np.int64), deep=1),
                  numpy_to_vtkIdTypeArray(np.ascontiguousarray(connectivity.ravel(), dtype=np.int64), deep=1))
    grid.SetCells(numpy_to_vtk(np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8), deep=1), array)
    temperature = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
    temperature.SetName("temperature")
    grid.GetPointData().AddArray(temperature)
    return grid


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--every", type=int, default=10, help="a picture every N steps")
    parser.add_argument("--refine", type=int, default=3, help="cube refinements: 20 x 8^r cells")
    parser.add_argument("--plugin", default=None)
    parser.add_argument("--size", type=int, nargs=2, default=[480, 360])
    args = parser.parse_args()
    plugin = args.plugin or (glob.glob(os.path.join(ROOT, "build", "**", "TetDSR.so"), recursive=True) or [None])[0]
    if not plugin:
        sys.exit("heat_p2: no TetDSR.so: run Scripts/setup.sh, or give --plugin")
    os.makedirs(args.out, exist_ok=True)

    # Catalyst first (it initialises ParaView, and MPI under mpirun), the pipeline's settings
    # through the environment.
    from paraview.catalyst import bridge
    os.environ.update(TETDSR_PLUGIN=os.path.abspath(plugin), TETDSR_OUT=os.path.abspath(args.out),
                      TETDSR_EVERY=str(args.every), TETDSR_SIZE=f"{args.size[0]} {args.size[1]}")
    bridge.initialize()
    bridge.add_pipeline(os.path.join(HERE, "direct_surface_pipeline.py"), 2)
    from vtkmodules.vtkParallelCore import vtkMultiProcessController
    controller = vtkMultiProcessController.GetGlobalController()
    rank = controller.GetLocalProcessId() if controller else 0
    ranks = controller.GetNumberOfProcesses() if controller else 1

    # The simulation.
    mesh = skfem.MeshTet().refined(args.refine)
    basis = skfem.Basis(mesh, skfem.ElementTetP2())
    order = vtk_edge_order(basis)
    node_order_error = check_node_order(basis, order)
    if node_order_error > 1e-10:
        sys.exit(f"heat_p2: the cells' node order is not VTK's: a quadratic interpolated by VTK's "
                 f"shape functions is off by {node_order_error:.1e}")
    conductivity, dt = 0.05, 0.02
    K = laplace.assemble(basis) * conductivity
    M = mass.assemble(basis)
    A = (M + dt * K).tocsr()
    u = np.zeros(basis.N)
    x = basis.doflocs
    centroids = mesh.p[:, mesh.t].mean(axis=1)
    mine = np.nonzero((centroids[0] * ranks).astype(int).clip(0, ranks - 1) == rank)[0]

    solve_times, catalyst_times = [], []
    for step in range(1, args.steps + 1):  # (step 0, u = 0, has no surface)
        start = time.perf_counter()
        t = step * dt
        centre = np.array([0.5 + 0.25 * np.cos(2.0 * t), 0.5 + 0.25 * np.sin(2.0 * t), 0.5])
        source = 40.0 * np.exp(-np.sum((x - centre[:, None]) ** 2, axis=0) / 0.02)
        b = M @ (u + dt * source)
        u = skfem.solve(*skfem.condense(A, b, D=basis.get_dofs(), x=np.zeros(basis.N)))
        solve_times.append(time.perf_counter() - start)
        start = time.perf_counter()
        bridge.coprocess(step * dt, step, to_vtk(basis, order, mine, u), name="input")
        catalyst_times.append((time.perf_counter() - start, step % args.every == 0))
    bridge.finalize()

    if rank == 0:
        rendering = [s for s, picture in catalyst_times if picture]
        handing = [s for s, picture in catalyst_times if not picture]
        print(f"heat_p2: node order checked with VTK's shape functions (a quadratic within "
              f"{node_order_error:.1e})")
        print(f"heat_p2: {mesh.t.shape[1]} P2 cells ({basis.N} nodes), {args.steps} steps, "
              f"{ranks} process(es), pictures every {args.every} steps at {args.size[0]} x {args.size[1]}")
        print("| step | count | median s | min s | max s |")
        print("|---|---|---|---|---|")
        for name, values in (("simulation (solve)", solve_times), ("Catalyst, picture", rendering),
                             ("Catalyst, no picture", handing)):
            if values:
                print(f"| {name} | {len(values)} | {statistics.median(values):.4f} | "
                      f"{min(values):.4f} | {max(values):.4f} |")


if __name__ == "__main__":
    main()
