#!/usr/bin/env python3
"""A P2 field on a tetrahedral mesh written by DOLFINx's own VTKFile from 2 MPI ranks, with the
ghost cells DOLFINx leaves in every piece: test data for ghost cells (vtkGhostType).

Run it through Scripts/make-dolfinx-ghosts.sh, which makes or reuses build/dolfinx-venv (a pyenv
Python 3.12 venv with the pinned `dolfinx-solver-real` wheel and its MPICH) and runs this script
on 2 ranks with that MPICH's mpiexec (Debian's Open MPI cannot start it). The default run:

  bash Scripts/make-dolfinx-ghosts.sh Testing/Data/dolfinx_ghosts

The mesh: dolfinx.mesh.create_unit_cube(COMM_WORLD, 4, 4, 4) with GhostMode.shared_facet (384
tetrahedra; each rank owns about half and holds as ghosts the other rank's cells that share a
facet with its own). The field "u" = (x - 0.5)^2 + (y - 0.5)^2 + (z - 0.5)^2, interpolated into
P2 (Lagrange, degree 2), which holds it exactly: its level sets are spheres about the cube's
centre. io.VTKFile writes VTK_LAGRANGE_TETRAHEDRON cells of 10 nodes, one .vtu per rank (each with
a vtkGhostType cell array: 1 on the ghost cells) and a .pvtu naming both pieces.
"""
import sys

import dolfinx_solver  # noqa: F401  (before dolfinx: it loads the solver's libraries)
import dolfinx
from dolfinx import fem, io, mesh
from mpi4py import MPI


def main(out):
    comm = MPI.COMM_WORLD
    if comm.size != 2:
        sys.exit("run on 2 ranks (Scripts/make-dolfinx-ghosts.sh)")
    domain = mesh.create_unit_cube(comm, 4, 4, 4, ghost_mode=mesh.GhostMode.shared_facet)
    space = fem.functionspace(domain, ("Lagrange", 2))
    u = fem.Function(space)
    u.name = "u"
    u.interpolate(lambda x: (x[0] - 0.5) ** 2 + (x[1] - 0.5) ** 2 + (x[2] - 0.5) ** 2)
    cells = domain.topology.index_map(3)
    print(f"rank {comm.rank}: {cells.size_local} cells of its own, {cells.num_ghosts} ghost cells "
          f"(dolfinx {dolfinx.__version__})", flush=True)
    with io.VTKFile(comm, f"{out}/ball.pvd", "w") as file:
        file.write_function(u, 0.0)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "Testing/Data/dolfinx_ghosts")
