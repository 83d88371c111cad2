#!/usr/bin/env python3
"""A linear elastic CalculiX result on 20-node hexahedra (C3D20R), converted by ccx2paraview
into VTK_QUADRATIC_HEXAHEDRON cells (type 25): an L-shaped steel bracket with tapered legs,
clamped on its back face and pressed on the top of its arm.

Run it through Scripts/make-calculix-bracket.sh, which installs CalculiX (Debian's calculix-ccx)
and a venv build/calculix-venv (ccx2paraview, and ParaView's VTK through the system site
packages) and runs it there with its arguments. Data/calculix_bracket.vtu is the default run:

  bash Scripts/make-calculix-bracket.sh --out Data/calculix_bracket.vtu

(--work DIR keeps the deck, ccx's .frd/.dat/.sta and ccx2paraview's own .vtu in DIR.)

The part (millimetres): a bracket bent from a plate, seen from the side (x to the right, z up) an
L whose vertical leg (x from 0) rises to z = HEIGHT and whose arm (z from 0) reaches x = LENGTH.
At the bend both legs are THICK_ROOT thick and WIDTH wide (y from 0), with concentric arcs: the
inner fillet of radius FILLET and the outer round of radius FILLET + THICK_ROOT, both centred at
x = z = FILLET + THICK_ROOT. Away from the bend each leg thins to THICK_TIP, thickness
THICK_ROOT - (THICK_ROOT - THICK_TIP) q^2 (q from 0 at the bend to 1 at the leg's end: the inner
face is a parabola tangent to the fillet's end; the back face x = 0 and the bottom z = 0 stay
flat), and narrows linearly to WIDTH_TIP, symmetric about y = WIDTH / 2.

The mesh is written here, not by a mesher: one structured block, CELLS_ALONG (the vertical leg,
the bend, the arm) x CELLS_THICK x CELLS_WIDE cells, along the plate, through its thickness and
across its width. Every node (corners and mid-edge nodes) is put on the exact part by the map
part_point, so the bend's cells have arcs for edges, the legs' cells parabolas (the thickness
taper) and are trapezoidal prisms (the width taper). The nodes are numbered on the block's
doubled grid; ccx's C3D20R node order is VTK's (8 corners, then the mid-edge nodes of edges
01 12 23 30 45 56 67 74 04 15 26 37), and the cells' axes are chosen so that the Jacobian is
positive (checked at 27 Gauss points of every cell before ccx sees the deck). The map is in
the serendipity space in the legs, so the mesh's volume differs from the part's only by the
quadratic arcs of the bend.

The analysis: steel (E = YOUNG MPa, nu = POISSON), *STATIC, the back face (x = 0) clamped
(*BOUNDARY 1-3 on its nodes), a pressure PRESSURE MPa on the arm's top face (*DLOAD Pn on the
C3D20R faces whose nodes all lie there), *NODE FILE U and *EL FILE S to the .frd, and the
clamped nodes' total reaction force (*NODE PRINT, TOTALS=ONLY) to the .dat, checked (1e-4)
against the load's resultant (load_resultant: the pressure on the parabolic top face, which the
quadratic faces represent exactly). ccx runs on one thread (with two its last printed digits of
near-zero values change from run to run; with one the written .vtu is the same byte for byte).
ccx writes nodal stresses extrapolated from the integration points and averaged between cells;
with S it also wrote an ERROR block (component STR(%), its stress error estimator).

ccx2paraview (its command line, `ccx2paraview bracket.frd vtu`, as CalculiX users run it) turns
the .frd into a .vtu: VTK_QUADRATIC_HEXAHEDRON cells, float32 points and double arrays, both
read from the .frd's 6 significant digits (E12.5). Its arrays are kept as they are except the
principal stresses (S_Principal, 4 components), dropped: U (D1 D2 D3), S (XX YY ZZ XY YZ ZX),
S_Mises (von Mises, computed by ccx2paraview from S; the active scalars) and ERROR (STR). The
file is rewritten by VTK's vtkXMLUnstructuredGridWriter, zlib-compressed, binary inline (base64
in each DataArray) like the project's other .vtu files, not appended: with Debian 12's libexpat
(2.5.0 with the backported reparse deferral) this VTK 9.2 cannot read appended data back, raw or
base64 ("not well-formed (invalid token)", "junk after document element"). It is read back for
the checks: the cell and point counts and types; every cell's 20 points against this script's
nodes of the same element (ccx2paraview's node reordering, to the .frd's rounding); at 27 Gauss
points of every cell the Jacobian determinant of VTK's 20-node map (positive) and the volume
(against the part's exact volume); how far each cell's mid-edge nodes lie off their chords and
its body diagonals' midpoints from each other (both 0 for a straight-edged parallelepiped); the
arrays' ranges; and vtkContourFilter's triangles and connected pieces for the von Mises
iso-values ISO_VALUES.

Measured on the 2-core development machine, the default run: 1,512 cells (16 + 8 + 18 along,
3 through, 12 across), 8,161 points, 605,168 bytes (ccx2paraview's own file, with S_Principal:
760,244); 2.7 s in all (ccx 1.2 to 2.2 s on one thread, ccx2paraview 0.7 to 1.0 s); 12.6 s with
the apt install of calculix-ccx and a new venv (pip's cache warm). Reaction (133.3333, 2.3e-9,
2520.0) N against (133.33, 0, 2520) N. Points within 5e-5 mm of the script's nodes; Jacobian
18.24 to 44.38 (all positive), cell volumes 20.38 to 44.12 mm^3, total 49261.437 (exact
49261.474); mid-edge nodes off their chords by 1.0e-3 (the legs' inner layers' parabolas)
to 0.087 mm (the bend's arcs), body diagonals' midpoints 0.023 to 0.33 mm apart: no cell is a
parallelepiped. U magnitude 0 to 0.4886 mm (the arm's tip, D3 down to -0.4847); S_Mises 0.0177 to
219.99 MPa (the fillet, x 10.6 z 14.9, at mid-width; the clamped face's lower edge reaches 215);
ERROR 5.6 to 91 %. vtkContourFilter on S_Mises: 20 MPa 3,396 triangles in 3 pieces (the arm's
low-stress core, the upper vertical leg, and a closed pocket 2.6 x 20 x 3 mm around the bend's
neutral surface); 100 MPa 2,460 in 2 (the fillet's tension side, the outer round's compression
side); 200 MPa 332 in 3 (the fillet's hot spot, 316, and the two lower corners of the clamped
face, 8 each).
"""
import argparse
import importlib.metadata
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkVersion
from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_HEXAHEDRON, vtkQuadraticHexahedron
from vtkmodules.vtkFiltersCore import vtkContourFilter, vtkPolyDataConnectivityFilter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

# The part, in millimetres.
HEIGHT, LENGTH = 80.0, 90.0  # top of the vertical leg, end of the arm
WIDTH, WIDTH_TIP = 40.0, 30.0  # the width at the bend and at the legs' ends
THICK_ROOT, THICK_TIP, FILLET = 10.0, 6.0, 8.0
BEND = FILLET + THICK_ROOT  # the bend's centre is (BEND, BEND) in (x, z)
# Cells along the vertical leg, the bend and the arm; through the thickness; across the width.
CELLS_ALONG = (16, 8, 18)
CELLS_THICK, CELLS_WIDE = 3, 12
# Material (MPa) and load.
YOUNG, POISSON, PRESSURE = 210000.0, 0.3, 1.0
# Iso-values of S_Mises (MPa) whose vtkContourFilter surfaces are printed.
ISO_VALUES = (20.0, 100.0, 200.0)
# VTK's (and ccx's) 20-node hexahedron: corners in (r, s, t), then the edges' end corners.
CORNERS = np.array([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                    (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)])
EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
         (0, 4), (1, 5), (2, 6), (3, 7)]
# ccx's faces of C3D20(R) (its manual, *DLOAD labels P1..P6), by their corners.
FACES = [(0, 1, 2, 3), (4, 7, 6, 5), (0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0)]


def thickness(q):
    """A leg's thickness at q (0 at the bend, 1 at the leg's end)."""
    return THICK_ROOT - (THICK_ROOT - THICK_TIP) * q * q


def width(q):
    """A leg's width at q (0 at the bend, 1 at the leg's end)."""
    return WIDTH - (WIDTH - WIDTH_TIP) * q


def part_point(along, across, wide):
    """The part's point (x, y, z) at the doubled-grid coordinates along (0 .. 2 sum(CELLS_ALONG)),
    across (0 .. 2 CELLS_THICK: 0 on the outer faces, the last on the inner ones) and wide
    (0 .. 2 CELLS_WIDE)."""
    n_leg, n_bend, _ = CELLS_ALONG
    r = across / (2.0 * CELLS_THICK)
    eta = wide / (2.0 * CELLS_WIDE) - 0.5
    if along <= 2 * n_leg:  # the vertical leg, from its top (along = 0) down to the bend
        q = 1.0 - along / (2.0 * n_leg)
        return np.array([r * thickness(q), 0.5 * WIDTH + eta * width(q),
                         BEND + q * (HEIGHT - BEND)])
    if along <= 2 * (n_leg + n_bend):  # the bend: concentric arcs
        angle = 0.5 * np.pi * (along - 2 * n_leg) / (2.0 * n_bend)
        radius = BEND - r * THICK_ROOT
        return np.array([BEND - radius * np.cos(angle), 0.5 * WIDTH + eta * WIDTH,
                         BEND - radius * np.sin(angle)])
    q = (along - 2 * (n_leg + n_bend)) / (2.0 * CELLS_ALONG[2])  # the arm
    return np.array([BEND + q * (LENGTH - BEND), 0.5 * WIDTH + eta * width(q),
                     r * thickness(q)])


def exact_volume():
    """The part's volume: the two tapered legs (integral over q of thickness * width) and the
    bend (a quarter annulus)."""
    dt, dw = THICK_ROOT - THICK_TIP, WIDTH - WIDTH_TIP
    leg_section = THICK_ROOT * WIDTH - THICK_ROOT * dw / 2 - dt * WIDTH / 3 + dt * dw / 4
    return (leg_section * ((HEIGHT - BEND) + (LENGTH - BEND))
            + 0.25 * np.pi * (BEND ** 2 - FILLET ** 2) * WIDTH)


def load_resultant():
    """The pressure's total force on the arm's top face z = thickness, outward normal
    (-thickness', 0, 1) per unit plan area: -PRESSURE times the integral of it over the plan."""
    dt, dw = THICK_ROOT - THICK_TIP, WIDTH - WIDTH_TIP
    return -PRESSURE * np.array([dt * (WIDTH - 2 * dw / 3), 0.0,
                                 (LENGTH - BEND) * (WIDTH - dw / 2)])


def gauss_derivatives():
    """vtkQuadraticHexahedron's shape-function derivatives at the 3 x 3 x 3 Gauss points
    (27 x 3 x 20) and the points' weights (27)."""
    g = 0.5 * np.array([1 - np.sqrt(0.6), 1.0, 1 + np.sqrt(0.6)])
    w = 0.5 * np.array([5.0, 8.0, 5.0]) / 9.0
    cell = vtkQuadraticHexahedron()
    derivs, weights = [], []
    buffer = [0.0] * 60
    for i in range(3):
        for j in range(3):
            for k in range(3):
                cell.InterpolateDerivs([g[i], g[j], g[k]], buffer)
                derivs.append(np.array(buffer).reshape(3, 20))
                weights.append(w[i] * w[j] * w[k])
    return np.array(derivs), np.array(weights)


def jacobians(nodes, derivs):
    """Jacobian determinants (cells x 27) of 20-node cells with nodes (cells x 20 x 3)."""
    jac = np.einsum('gan,cnx->cgax', derivs, nodes)
    return np.linalg.det(jac)


def make_mesh():
    """The block's nodes (n x 3, numbered from 0), its cells (cells x 20, VTK's and ccx's node
    order) and the nodes' doubled-grid coordinates (n x 3: along, across, wide)."""
    n_along = sum(CELLS_ALONG)
    shape = (2 * n_along + 1, 2 * CELLS_THICK + 1, 2 * CELLS_WIDE + 1)
    grid = np.indices(shape).reshape(3, -1).T  # (along, across, wide), doubled
    used = (grid % 2).sum(axis=1) <= 1  # corners and mid-edge points
    grid = grid[used]
    number = -np.ones(shape, dtype=np.int64)
    number[tuple(grid.T)] = np.arange(len(grid))
    nodes = np.array([part_point(*point) for point in grid])

    # The cells' local axes (r, s, t) along two of the grid's axes and across the third: the
    # orientation whose Jacobian is positive (tried on the first cell, checked on all below).
    derivs, _ = gauss_derivatives()
    for axes in ((0, 2, 1), (0, 1, 2)):
        local = np.zeros((20, 3), dtype=np.int64)
        local[:8][:, axes] = 2 * CORNERS
        for e, (a, b) in enumerate(EDGES):
            local[8 + e] = (local[a] + local[b]) // 2
        first = nodes[number[tuple(local.T)]]
        if jacobians(first[None], derivs).min() > 0:
            break
    origins = 2 * np.indices((n_along, CELLS_THICK, CELLS_WIDE)).reshape(3, -1).T
    cells = np.array([number[tuple((o + local).T)] for o in origins])
    if (cells < 0).any():
        sys.exit("a cell refers to a point that is not a node")
    return nodes, cells, grid


def write_deck(path, nodes, cells, grid):
    """The CalculiX input deck; returns the number of clamped nodes and of loaded faces."""
    n_leg, n_bend, _ = CELLS_ALONG
    clamped = np.flatnonzero((grid[:, 0] <= 2 * n_leg) & (grid[:, 1] == 0))  # x = 0
    if np.abs(nodes[clamped, 0]).max() != 0.0:
        sys.exit("a clamped node is off the back face")
    top = 2 * CELLS_THICK
    loaded = []  # (cell, face label): the arm's top face
    for c, cell in enumerate(cells):
        if grid[cell[0], 0] < 2 * (n_leg + n_bend):
            continue
        for f, face in enumerate(FACES):
            if all(grid[cell[v], 1] == top for v in face):
                loaded.append((c, f + 1))
    with open(path, 'w') as out:
        out.write("*HEADING\nTetDSR: L-shaped steel bracket, tapered legs, C3D20R "
                  "(Scripts/make_calculix_bracket.py)\n")
        out.write("*NODE, NSET=NALL\n")
        for i, (x, y, z) in enumerate(nodes):
            out.write(f"{i + 1}, {x:.12g}, {y:.12g}, {z:.12g}\n")
        out.write("*ELEMENT, TYPE=C3D20R, ELSET=EALL\n")
        for c, cell in enumerate(cells):
            ids = [str(c + 1)] + [str(n + 1) for n in cell]
            out.write(", ".join(ids[:16]) + ",\n" + ", ".join(ids[16:]) + "\n")
        out.write("*NSET, NSET=FIXED\n")
        for start in range(0, len(clamped), 16):
            out.write(", ".join(str(n + 1) for n in clamped[start:start + 16]) + "\n")
        out.write(f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{YOUNG:g}, {POISSON:g}\n"
                  "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n"
                  "*STEP\n*STATIC\n*BOUNDARY\nFIXED, 1, 3\n*DLOAD\n")
        for c, label in loaded:
            out.write(f"{c + 1}, P{label}, {PRESSURE:g}\n")
        out.write("*NODE FILE\nU\n*EL FILE\nS\n"
                  "*NODE PRINT, NSET=FIXED, TOTALS=ONLY\nRF\n*END STEP\n")
    return len(clamped), len(loaded)


def run(command, cwd, log, env=None):
    """Runs command in cwd, its output to log; exits on failure."""
    with open(log, 'w') as out:
        result = subprocess.run(command, cwd=cwd, stdout=out, stderr=subprocess.STDOUT, env=env)
    text = open(log).read()
    if result.returncode != 0 or '*ERROR' in text:
        sys.exit(f"{' '.join(command)} failed ({result.returncode}):\n{text[-3000:]}")
    return text


def reaction_totals(dat_path):
    """The clamped nodes' total reaction force (fx, fy, fz) from ccx's .dat."""
    text = open(dat_path).read()
    match = re.search(r"total force \(fx,fy,fz\) for set FIXED.*?\n\s*\n?\s*"
                      r"(\S+)\s+(\S+)\s+(\S+)", text)
    if not match:
        sys.exit(f"no total reaction force in {dat_path}:\n{text[:2000]}")
    return np.array([float(v) for v in match.groups()])


def ccx_version():
    out = subprocess.run(['ccx', '-v'], capture_output=True, text=True).stdout
    match = re.search(r"Version\s+(\S+)", out)
    return match.group(1) if match else out.strip()


def ccx2paraview_command():
    """The venv's ccx2paraview script (next to this Python), else the one on PATH."""
    here = os.path.join(os.path.dirname(sys.executable), 'ccx2paraview')
    return here if os.path.exists(here) else shutil.which('ccx2paraview')


def curved_and_skew(points):
    """For cells' points (cells x 20 x 3): each cell's largest distance of a mid-edge node from
    its edge's midpoint, and its largest distance between the midpoints of its 4 body
    diagonals (both 0 for a parallelepiped with straight edges)."""
    corners = points[:, :8]
    mid = np.stack([0.5 * (corners[:, a] + corners[:, b]) for a, b in EDGES], axis=1)
    bend = np.linalg.norm(points[:, 8:] - mid, axis=2).max(axis=1)
    diagonals = np.stack([0.5 * (corners[:, a] + corners[:, b])
                          for a, b in ((0, 6), (1, 7), (2, 4), (3, 5))], axis=1)
    skew = np.linalg.norm(diagonals[:, :, None] - diagonals[:, None, :], axis=3)
    return bend, skew.max(axis=(1, 2))


def contour(grid, name, value):
    """vtkContourFilter's triangles for the point array name = value, and its connected pieces
    (each piece's triangles and bounding box, largest first)."""
    contour_filter = vtkContourFilter()
    contour_filter.SetInputData(grid)
    contour_filter.SetInputArrayToProcess(0, 0, 0, 0, name)  # points
    contour_filter.SetValue(0, value)
    contour_filter.Update()
    surface = contour_filter.GetOutput()
    pieces = vtkPolyDataConnectivityFilter()
    pieces.SetInputData(surface)
    pieces.SetExtractionModeToAllRegions()
    pieces.ColorRegionsOn()
    pieces.Update()
    labelled = pieces.GetOutput()
    points = vtk_to_numpy(labelled.GetPoints().GetData())
    triangles = vtk_to_numpy(labelled.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    region = vtk_to_numpy(labelled.GetPointData().GetArray('RegionId'))[triangles[:, 0]]
    found = []
    for k in range(pieces.GetNumberOfExtractedRegions()):
        corners = points[triangles[region == k].ravel()]
        found.append(((region == k).sum(), corners.min(axis=0), corners.max(axis=0)))
    found.sort(key=lambda piece: -piece[0])
    return surface.GetNumberOfPolys(), found


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--out', default='Data/calculix_bracket.vtu', help='the .vtu to write')
    parser.add_argument('--work', help='keep ccx\'s and ccx2paraview\'s files in this folder '
                        '(default: a temporary folder, removed)')
    args = parser.parse_args()
    start = time.perf_counter()
    work = args.work or tempfile.mkdtemp(prefix='calculix-bracket-')
    os.makedirs(work, exist_ok=True)
    converter = ccx2paraview_command()
    if shutil.which('ccx') is None or converter is None:
        sys.exit("needs ccx (calculix-ccx) and ccx2paraview: run Scripts/make-calculix-bracket.sh")
    print(f"CalculiX ccx {ccx_version()}, ccx2paraview "
          f"{importlib.metadata.version('ccx2paraview')}, VTK {vtkVersion.GetVTKVersion()}")

    # The mesh, checked before ccx sees it.
    nodes, cells, grid = make_mesh()
    derivs, weights = gauss_derivatives()
    det = jacobians(nodes[cells], derivs)
    if det.min() <= 0:
        sys.exit(f"{(det.min(axis=1) <= 0).sum()} cells have a non-positive Jacobian")
    bend, skew = curved_and_skew(nodes[cells])
    print(f"mesh: {len(cells)} C3D20R cells ({' + '.join(map(str, CELLS_ALONG))} along x "
          f"{CELLS_THICK} through x {CELLS_WIDE} across), {len(nodes)} nodes; volume "
          f"{(det * weights).sum():.6f} mm^3 (exact {exact_volume():.6f}); each cell's "
          f"farthest mid-edge node off its chord by {bend.min():.3g} to {bend.max():.3g} mm; "
          f"its body diagonals' midpoints apart by {skew.min():.3g} to {skew.max():.3g} mm")

    # CalculiX, then ccx2paraview, as a user runs them.
    stamp = time.perf_counter()
    n_clamped, n_loaded = write_deck(os.path.join(work, 'bracket.inp'), nodes, cells, grid)
    # One thread: with two, ccx's last digits of near-zero values change from run to run.
    single = dict(os.environ, OMP_NUM_THREADS='1', CCX_NPROC_STIFFNESS='1',
                  CCX_NPROC_EQUATION_SOLVER='1', CCX_NPROC_RESULTS='1')
    log = run(['ccx', '-i', 'bracket'], work, os.path.join(work, 'ccx.log'), single)
    cpus = sorted(set(re.findall(r"Using up to (\d+) cpu", log)))
    ccx_seconds = time.perf_counter() - stamp
    reaction = reaction_totals(os.path.join(work, 'bracket.dat'))
    resultant = -load_resultant()
    print(f"ccx: {n_clamped} clamped nodes, {n_loaded} loaded faces, {ccx_seconds:.1f} s "
          f"({'/'.join(cpus)} cpu); reaction {reaction.tolist()} N, minus the load's "
          f"resultant {resultant.tolist()} N")
    if np.abs(reaction - resultant).max() > 1e-4 * np.abs(resultant).max():
        sys.exit("the reaction does not balance the load")
    stamp = time.perf_counter()
    run([converter, 'bracket.frd', 'vtu'], work, os.path.join(work, 'ccx2paraview.log'))
    print(f"ccx2paraview: {time.perf_counter() - stamp:.1f} s")

    # Rewrite: binary, zlib; without the principal stresses.
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(work, 'bracket.vtu'))
    reader.Update()
    converted = reader.GetOutput()
    point_data = converted.GetPointData()
    names = [point_data.GetArrayName(i) for i in range(point_data.GetNumberOfArrays())]
    point_type = converted.GetPoints().GetData().GetDataTypeAsString()
    print(f"ccx2paraview wrote {converted.GetNumberOfCells()} cells, "
          f"{converted.GetNumberOfPoints()} points ({point_type}), point arrays {names}, "
          f"{os.path.getsize(os.path.join(work, 'bracket.vtu'))} bytes")
    for name in names:
        if name == 'S_Principal':
            point_data.RemoveArray(name)
    point_data.SetActiveScalars('S_Mises')
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(args.out)
    writer.SetInputData(converted)
    # Inline binary (base64 in each DataArray), like the project's other .vtu files: with Debian
    # 12's libexpat (2.5.0 with the backported reparse deferral) this VTK 9.2 cannot read appended
    # data back, raw or base64 ("not well-formed (invalid token)", "junk after document element").
    writer.SetDataModeToBinary()
    writer.SetCompressorTypeToZLib()
    if not writer.Write():
        sys.exit(f"could not write {args.out}")

    # Checks of the written file.
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.out)
    reader.Update()
    out = reader.GetOutput()
    types = vtk_to_numpy(out.GetCellTypesArray())
    points = vtk_to_numpy(out.GetPoints().GetData()).astype(np.float64)
    connectivity = vtk_to_numpy(out.GetCells().GetConnectivityArray()).reshape(-1, 20)
    if out.GetNumberOfCells() != len(cells) or (types != VTK_QUADRATIC_HEXAHEDRON).any():
        sys.exit(f"expected {len(cells)} cells of type 25, got {np.unique(types)}")
    if out.GetNumberOfPoints() != len(nodes):
        sys.exit(f"expected {len(nodes)} points, got {out.GetNumberOfPoints()}")
    cell_points = points[connectivity]
    node_error = np.abs(cell_points - nodes[cells]).max()
    det = jacobians(cell_points, derivs)
    volumes = (det * weights).sum(axis=1)
    bend, skew = curved_and_skew(cell_points)
    print(f"{args.out}: {os.path.getsize(args.out)} bytes; {out.GetNumberOfCells()} cells, all "
          f"VTK_QUADRATIC_HEXAHEDRON (25); {out.GetNumberOfPoints()} points "
          f"({out.GetPoints().GetData().GetDataTypeAsString()}), each cell's 20 within "
          f"{node_error:.2g} mm of this script's nodes")
    print(f"  Jacobian at 27 Gauss points: min {det.min():.4g}, max {det.max():.4g} (positive: "
          f"{(det.min(axis=1) > 0).sum()} of {len(det)} cells); cell volumes {volumes.min():.4g} "
          f"to {volumes.max():.4g} mm^3, total {volumes.sum():.4f} (exact {exact_volume():.4f})")
    curved = bend > 1e-3
    print(f"  each cell's farthest mid-edge node off its chord by {bend.min():.3g} to "
          f"{bend.max():.3g} mm ({curved.sum()} cells above 1e-3 mm); body diagonals' midpoints "
          f"apart by {skew.min():.3g} to {skew.max():.3g} mm ({(skew > 1e-3).sum()} cells above "
          f"1e-3 mm); {(curved | (skew > 1e-3)).sum()} of {len(bend)} cells curved or not "
          f"parallelepipeds")
    if node_error > 1e-4 or det.min() <= 0:
        sys.exit("the written file's cells differ from the mesh or are inverted")
    point_data = out.GetPointData()
    for i in range(point_data.GetNumberOfArrays()):
        array = point_data.GetArray(i)
        values = vtk_to_numpy(array).reshape(out.GetNumberOfPoints(), -1)
        parts = [f"{array.GetComponentName(c) or c} [{values[:, c].min():.6g}, "
                 f"{values[:, c].max():.6g}]" for c in range(values.shape[1])]
        if values.shape[1] > 1:
            magnitude = np.linalg.norm(values, axis=1)
            parts.append(f"|.| [{magnitude.min():.6g}, {magnitude.max():.6g}]")
        print(f"  {array.GetName()} ({array.GetDataTypeAsString()}): {', '.join(parts)}")
    for value in ISO_VALUES:
        triangles, pieces = contour(out, 'S_Mises', value)
        print(f"  vtkContourFilter S_Mises = {value:g}: {triangles} triangles, {len(pieces)} "
              f"pieces: " + "; ".join(
                  f"{n} in x {lo[0]:.1f}..{hi[0]:.1f} y {lo[1]:.1f}..{hi[1]:.1f} "
                  f"z {lo[2]:.1f}..{hi[2]:.1f}" for n, lo, hi in pieces))
    if not args.work:
        shutil.rmtree(work)
    print(f"done in {time.perf_counter() - start:.1f} s")


if __name__ == '__main__':
    main()
