#!/usr/bin/env python3
"""A CalculiX result on 10-node tetrahedra (C3D10) for the GUI benchmark: a steel plate with holes
meshed by gmsh, clamped at one end and bent by a load at the other, solved by ccx and converted
by ccx2paraview into VTK_QUADRATIC_TETRA cells, as a CalculiX user gets it. Not a dataset of
the repository (about 8 MB): made when needed.

Usage, in two venvs (gmsh: Scripts/flow-venv.sh's; ccx2paraview: Scripts/make-calculix-bracket.sh's):
  build/flow-venv/bin/python Testing/Benchmark/make_tet10_part.py mesh WORK [SIZE]
  ccx -i WORK/part        (Debian's calculix-ccx, run in WORK)
  build/calculix-venv/bin/python Testing/Benchmark/make_tet10_part.py convert WORK OUT.vtu

The part (millimetres): a plate 200 x 60 x 20 with two rows of five through holes of radius 6
(x = 30, 65, ..., 170; y = 17, 43), meshed with second-order tetrahedra of size SIZE (default 2.15:
about 110,000 cells), the mid-edge nodes on the curved holes. Steel (E 210000 MPa, nu 0.3), the
face x = 0 clamped, 10 kN downwards spread over the nodes of the face x = 200. gmsh's node order
of a 10-node tetrahedron differs from CalculiX's in its last mid-edge nodes: each element's
mid-edge nodes are matched to its edges by position (the node nearest each edge's midpoint).
"""
import os
import subprocess
import sys

import numpy as np

# CalculiX C3D10 (and VTK_QUADRATIC_TETRA): corners 0-3, then edges 01 12 20 03 13 23.
EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))


def mesh(work, size):
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    occ = gmsh.model.occ
    plate = occ.addBox(0, 0, 0, 200, 60, 20)
    holes = [(3, occ.addCylinder(x, y, -1, 0, 0, 22, 6)) for x in (30, 65, 100, 135, 170)
             for y in (17, 43)]
    occ.cut([(3, plate)], holes)
    occ.synchronize()
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.5 * size)
    gmsh.option.setNumber("Mesh.ElementOrder", 2)
    gmsh.option.setNumber("Mesh.HighOrderOptimize", 1)
    gmsh.model.mesh.generate(3)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    points = coords.reshape(-1, 3)
    index = {int(t): k for k, t in enumerate(tags)}
    _, element_nodes = gmsh.model.mesh.getElementsByType(11)  # 10-node tetrahedra
    cells = np.vectorize(index.get)(element_nodes.reshape(-1, 10).astype(np.int64))
    gmsh.finalize()
    # Mid-edge nodes to CalculiX's edges, by position.
    mids = points[cells[:, 4:]]                                       # (n, 6, 3)
    expected = np.stack([(points[cells[:, a]] + points[cells[:, b]]) / 2 for a, b in EDGES], 1)
    distance = np.linalg.norm(expected[:, :, None, :] - mids[:, None, :, :], axis=3)
    match = distance.argmin(axis=2)
    if not all((np.sort(m) == np.arange(6)).all() for m in match[:1000]):
        sys.exit("ambiguous mid-edge nodes")
    cells = np.concatenate([cells[:, :4], np.take_along_axis(cells[:, 4:], match, 1)], 1)
    with open(os.path.join(work, "part.inp"), "w") as deck:
        deck.write("*NODE, NSET=NALL\n")
        deck.writelines(f"{k + 1}, {p[0]:.9g}, {p[1]:.9g}, {p[2]:.9g}\n" for k, p in enumerate(points))
        deck.write("*ELEMENT, TYPE=C3D10, ELSET=EALL\n")
        deck.writelines(f"{k + 1}, " + ", ".join(str(n + 1) for n in c) + "\n"
                        for k, c in enumerate(cells))
        clamped = np.flatnonzero(points[:, 0] < 1e-6) + 1
        loaded = np.flatnonzero(points[:, 0] > 200 - 1e-6) + 1
        deck.write("*NSET, NSET=CLAMPED\n" + "".join(f"{n},\n" for n in clamped))
        deck.write("*BOUNDARY\nCLAMPED, 1, 3\n")
        deck.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n210000., 0.3\n")
        deck.write("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
        deck.write("*STEP\n*STATIC\n*CLOAD\n")
        deck.writelines(f"{n}, 3, {-10000.0 / len(loaded):.9g}\n" for n in loaded)
        deck.write("*NODE FILE\nU\n*EL FILE\nS\n*END STEP\n")
    print(f"{len(cells)} C3D10 cells, {len(points)} nodes: {work}/part.inp")


def convert(work, out):
    subprocess.run(["ccx2paraview", os.path.join(work, "part.frd"), "vtu"], check=True)
    os.replace(os.path.join(work, "part.vtu"), out)
    print(f"wrote {out}")


if __name__ == "__main__":
    if sys.argv[1] == "mesh":
        mesh(sys.argv[2], float(sys.argv[3]) if len(sys.argv) > 3 else 2.15)
    else:
        convert(sys.argv[2], sys.argv[3])
