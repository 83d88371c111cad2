"""Ghost cells under MPI: each rank reads its piece of DOLFINx's 2-rank output
(Testing/Data/dolfinx_ghosts: every piece carries the other rank's cells that touch its own,
flagged DUPLICATECELL), and ParaView's Ghost Cells Generator adds a layer of its own to the pieces
stripped of theirs. Shown as a Direct Surface, translucent around an opaque inner sphere, beside
an opaque box, every picture equals the picture of the pieces without ghost cells (Remove Ghost
Information) over the whole view, and Select Cells On over the whole view selects each mesh cell
at most once and never a ghost cell.

Usage (one rank per piece):
  mpirun -np 2 pvbatch test_ghost_cells_mpi.py <TetDSR.so> <Testing/Data directory> <work directory>
"""
import os
import sys

import numpy as np
import paraview.simple as simple
from paraview import servermanager
from paraview.simple import (Box, CreateView, GhostCellsGenerator, LoadPlugin, RemoveGhostInformation,
                             SaveScreenshot, Show, XMLPartitionedUnstructuredGridReader)
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

plugin_path, data_dir, work_dir = sys.argv[1:4]
os.makedirs(work_dir, exist_ok=True)
LoadPlugin(plugin_path, remote=False, ns=globals())
simple._DisableFirstRenderCameraReset()
ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


W, H = 300, 200
CAMERA = dict(CameraPosition=[2.2, 1.5, 2.6], CameraFocalPoint=[0.55, 0.5, 0.5],
              CameraViewUp=[0.0, 1.0, 0.0], CameraViewAngle=30.0)
DUPLICATE, HIDDEN = 1, 32


def show(source, view):
    display = Show(source, view)
    display.SetRepresentationType("Direct Surface")
    display.ContourBy = ["POINTS", "u"]
    display.Isosurfaces = [0.1, 0.04]  # radius 0.32 translucent around radius 0.2 opaque
    display.IsoValueOpacities = [0.4, 1.0]
    display.ColorArrayName = ["POINTS", ""]
    return display


def new_view():
    view = CreateView("RenderView")
    view.ViewSize = [W, H]
    view.OrientationAxesVisibility = 0
    view.UseFXAA = 0
    for key, value in CAMERA.items():
        setattr(view, key, value)
    return view


def picture(source, name):
    view = new_view()
    show(source, view)
    box = Box(XLength=0.3, YLength=0.6, ZLength=0.3, Center=[1.05, 0.5, 0.6])
    box_display = Show(box, view)
    box_display.DiffuseColor = [0.9, 0.8, 0.1]
    box_display.ColorArrayName = ["POINTS", ""]
    path = os.path.join(work_dir, name)
    SaveScreenshot(path, view, ImageResolution=[W, H])
    simple.Delete(view)
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    return vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)


def ghost_counts(source):
    """Per rank: (cells, cells flagged duplicate or hidden)."""
    counts = []
    for rank in range(ranks):
        data = servermanager.Fetch(source, rank) if ranks > 1 else servermanager.Fetch(source)
        flags = data.GetCellData().GetArray("vtkGhostType")
        ghosts = 0 if flags is None else int(((vtk_to_numpy(flags) & (DUPLICATE | HIDDEN)) != 0).sum())
        counts.append((data.GetNumberOfCells(), ghosts))
    return counts


def cell_keys(data):
    """Each cell's centroid of its 4 vertices, rounded: names a mesh cell on every rank (DOLFINx's
    vtkOriginalCellIds are each rank's own numbers)."""
    points = vtk_to_numpy(data.GetPoints().GetData())
    ids = vtk_to_numpy(data.GetCells().GetConnectivityArray())
    offsets = vtk_to_numpy(data.GetCells().GetOffsetsArray())
    return [tuple(np.round(points[ids[offsets[c]:offsets[c] + 4]].mean(axis=0), 9))
            for c in range(data.GetNumberOfCells())]


def select_all(source):
    """Select Cells On over the whole view of the surface alone: every selected cell (its
    centroid) and its ghost flag, over the ranks."""
    view = new_view()
    show(source, view)
    simple.Render(view)
    simple.SelectSurfaceCells(Rectangle=[0, 0, W - 1, H - 1], View=view, Modifier=None)
    extract = simple.ExtractSelection(Input=source)
    originals, flags = [], []
    for rank in range(ranks):
        data = servermanager.Fetch(extract, rank) if ranks > 1 else servermanager.Fetch(extract)
        if data.GetNumberOfCells() == 0:
            continue
        originals += cell_keys(data)
        ghost = data.GetCellData().GetArray("vtkGhostType")
        flags += [0] * data.GetNumberOfCells() if ghost is None else vtk_to_numpy(ghost).tolist()
    simple.Delete(extract)
    simple.ClearSelection(source)
    simple.Delete(view)
    return originals, flags


reader = XMLPartitionedUnstructuredGridReader(
    FileName=[os.path.join(data_dir, "dolfinx_ghosts", "ball000000.pvtu")])
own = RemoveGhostInformation(Input=reader)
generated = GhostCellsGenerator(Input=own)
generated.BuildIfRequired = 0  # a layer whether or not a downstream filter asks for one
sources = {"DOLFINx's ghost cells": reader, "Ghost Cells Generator": generated}

print(f"{ranks} ranks")
reference = picture(own, "own.png")
covered = int((np.abs(reference - reference[0]).max(axis=1) > 0).sum())
check(covered > 5000, f"the surface and box cover {covered} pixels: expected over 5000")
own_selection, _ = select_all(own)
check(len(own_selection) > 50 and len(set(own_selection)) == len(own_selection),
      f"{len(own_selection)} cells selected without ghost cells, {len(set(own_selection))} different")
for label, source in sources.items():
    counts = ghost_counts(source)
    print(f"{label}: (cells, ghost cells) per rank: {counts}")
    if ranks > 1:
        check(all(ghosts > 0 for _, ghosts in counts), f"{label}: every rank must hold ghost cells")
    image = picture(source, label.split()[0].lower().replace("'", "") + ".png")
    differ = int((np.abs(image - reference).max(axis=1) > 2).sum())
    print(f"{label}: {differ} of {W * H} pixels ({covered} covered) differ by more than 2/255 "
          "from the picture without ghost cells")
    check(differ == 0, f"{label}: {differ} pixels differ from the picture without ghost cells")
    originals, flags = select_all(source)
    ghosts = sum(1 for flag in flags if flag & (DUPLICATE | HIDDEN))
    repeated = len(originals) - len(set(originals))
    print(f"{label}: {len(originals)} cells selected, {ghosts} ghost cells, {repeated} selected "
          f"twice; {len(set(originals) ^ set(own_selection))} differ from the selection without")
    check(ghosts == 0 and repeated == 0, f"{label}: selection names {ghosts} ghost cells, "
          f"{repeated} cells twice")
    check(set(originals) == set(own_selection),
          f"{label}: the selection differs from the one without ghost cells")

if failures:
    print(f"{len(failures)} failures")
    sys.exit(1)
print("ghost cells under MPI: OK")
