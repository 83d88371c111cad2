#!/usr/bin/env python3
"""What curved cells cost: each mesh with curved (isoparametric) cells beside its straightened
copy (mid-edge nodes moved to their edges' midpoints), through the VTK filter on all cores.
Prints a Markdown table: cells (curved), preprocessing + first frame, the scene's memory, a frame
after a camera move, a frame after an iso-value change, and the extra time per pixel whose ray
ends in a curved cell.

  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Testing/Benchmark/curved_cost.py \
      [image size] [mesh.vtu:array:iso ...]
Without meshes: the gmsh test meshes, Data/cylinder_flow.vtu when present, and a lattice of
20^3 x 6 cells, all curved by the map (x + 0.5 y^2, y + 0.5 z^2, z).
"""
import os
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_TETRA, vtkCellArray, vtkUnstructuredGrid

from tetdsr import vtkDirectSurfaceRayCaster

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "Testing", "Python"))
from curved_reference import VTK_EDGES as EDGES, read_vtu as read, straightened  # noqa: E402
from kuhn_lattice import kuhn_vertices  # noqa: E402


def warped_lattice(n, alpha=0.5):
    """n^3 cubes x 6 Kuhn tets on [0,1]^3, every node moved by (x + a y^2, y + a z^2, z); field
    'wave' = sin 7x cos 5y + sin(6z + 1) of the unmoved coordinates."""
    m = 2 * n + 1
    g = np.arange(m) / (m - 1.0)
    z, y, x = np.meshgrid(g, g, g, indexing="ij")
    pts = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    wave = np.sin(7 * pts[:, 0]) * np.cos(5 * pts[:, 1]) + np.sin(6 * pts[:, 2] + 1)
    idx = lambda i, j, k: i + m * (j + m * k)  # noqa: E731
    cells = []
    base = np.stack(np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij"),
                    axis=-1).reshape(-1, 3)
    for v in kuhn_vertices(base, 2):  # (the cells path by path, each over every cube)
        ids = [idx(c[:, 0], c[:, 1], c[:, 2]) for c in v]
        mids = [idx(*(((v[a] + v[b]) // 2).T)) for a, b in EDGES]
        cells.append(np.stack(ids + mids, axis=1))
    conn = np.concatenate(cells).astype(np.int64)
    moved = pts + alpha * np.stack([pts[:, 1] ** 2, pts[:, 2] ** 2, 0 * pts[:, 0]], axis=1)
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(moved, deep=1))
    grid.SetPoints(vtk_points)
    ca = vtkCellArray()
    ca.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 10 * len(conn) + 1, 10, dtype=np.int64), deep=1),
               numpy_to_vtkIdTypeArray(conn.ravel(), deep=1))
    grid.SetCells(VTK_QUADRATIC_TETRA, ca)
    values = numpy_to_vtk(wave, deep=1)
    values.SetName("wave")
    grid.GetPointData().AddArray(values)
    return grid


def measure(grid, array, iso, size):
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(grid)
    caster.SetInputArrayToProcess(0, 0, 0, 0, array)
    caster.SetValue(0, iso)
    caster.SetImageSize(size, size)
    start = time.perf_counter()
    caster.Update()
    first = time.perf_counter() - start
    # A camera move: the filter's default camera turned 30 degrees about the view-up.
    from vtkmodules.vtkRenderingCore import vtkCamera
    b = grid.GetBounds()
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    radius = 0.5 * np.linalg.norm([b[1] - b[0], b[3] - b[2], b[5] - b[4]])
    camera = vtkCamera()
    camera.SetFocalPoint(*centre)
    camera.SetPosition(centre[0] + 2.2 * radius, centre[1] - 2.6 * radius, centre[2] + 1.8 * radius)
    camera.SetViewUp(0, 0, 1)
    caster.SetCamera(camera)
    caster.Update()  # (the first frame from this camera)
    moves = []
    for k in range(3):
        camera.Azimuth(10)
        start = time.perf_counter()
        caster.Update()
        moves.append(time.perf_counter() - start)
    cells = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("CellId")).copy()
    caster.SetValue(0, iso * 1.001 + 1e-3)
    start = time.perf_counter()
    caster.Update()
    iso_change = time.perf_counter() - start
    return dict(first=first, memory=caster.GetPreprocessedBytes(), move=min(moves),
                iso=iso_change, cells=cells, curved=caster.GetNumberOfCurvedCells(),
                rendered=caster.GetNumberOfRenderedCells())


def main():
    size = int(sys.argv[1]) if len(sys.argv) > 1 else 512
    cases = []
    for spec in sys.argv[2:]:
        path, array, iso = spec.rsplit(":", 2)
        cases.append((os.path.basename(path), read(path), array, float(iso)))
    if not cases:
        data = os.path.join(ROOT, "Testing", "Data")
        cases.append(("gmsh ball", read(os.path.join(data, "curved_ball.vtu")), "quadratic", 0.8))
        cases.append(("gmsh part, two holes", read(os.path.join(data, "curved_part.vtu")), "quadratic", 1.5))
        flow = os.path.join(ROOT, "Data", "cylinder_flow.vtu")
        if os.path.exists(flow):
            cases.append(("cylinder flow (speed)", read(flow), "speed", 0.3))
        cases.append(("lattice 20^3 x 6, all curved", warped_lattice(20), "wave", 0.6))
    print("image %d x %d, %d cores" % (size, size, os.cpu_count()))
    print()
    print("| mesh | cells (curved) | geometry | preprocessing + first frame (s) | scene memory (MB) "
          "| camera move (s) | iso-value change (s) | pixels ending in a curved cell |")
    print("|---|---|---|---|---|---|---|---|")
    for name, grid, array, iso in cases:
        curved = measure(grid, array, iso, size)
        flat = measure(straightened(grid), array, iso, size)
        conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 10)
        pts = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
        edge = np.max([np.linalg.norm(pts[conn[:, a]] - pts[conn[:, b]], axis=1) for a, b in EDGES], axis=0)
        offset = np.max([np.linalg.norm(pts[conn[:, 4 + e]] - 0.5 * (pts[conn[:, a]] + pts[conn[:, b]]), axis=1)
                         for e, (a, b) in enumerate(EDGES)], axis=0)
        is_curved = offset > 64 * 2.0 ** -52 * edge
        hit = curved["cells"] >= 0
        in_curved = int(np.sum(is_curved[curved["cells"][hit]]))
        for label, r in (("curved", curved), ("straightened", flat)):
            print("| %s | %d (%d) | %s | %.3f | %.1f | %.4f | %.4f | %s |" % (
                name, r["rendered"], r["curved"], label, r["first"], r["memory"] / 1e6, r["move"],
                r["iso"], in_curved if label == "curved" else ""))
        extra = curved["move"] - flat["move"]
        if in_curved:
            print("|  |  | extra per pixel ending in a curved cell | | | %.2f us | | |"
                  % (1e6 * extra / in_curved * os.cpu_count()))


if __name__ == "__main__":
    main()
