"""vtkDirectSurfaceMapper's translucent surfaces across processes, in plain VTK (no ParaView
compositor): under `mpirun -np 2 pvbatch`, each rank holds every other cell of a lattice holding
|x|^2 exactly (so every ray's crossings alternate between the ranks), two nested translucent
spheres, and rank 0 an opaque plane through them. Each rank calls
DrawTranslucentAcrossProcesses at its renderer's EndEvent without a compositor's image: rank 0
reads its own depth and draws over its frame buffer. Its picture must be that of one process
holding every cell (a second window on rank 0), within 2 / 255; rank 0's half alone must not be.

Usage: mpirun -np 2 pvbatch --symmetric test_mapper_mpi.py   (the tetdsr package on PYTHONPATH;
--symmetric: every rank runs the script, not rank 0 alone)
"""
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
from vtkmodules.vtkFiltersCore import vtkExtractCells
from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkFiltersSources import vtkPlaneSource
from vtkmodules.vtkParallelCore import vtkMultiProcessController
from vtkmodules.vtkRenderingCore import vtkActor, vtkRenderer, vtkRenderWindow
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_mapper import grid, polygon_actor  # noqa: E402
from tetdsr import vtkDirectSurfaceMapper  # noqa: E402

W, H = 200, 150
controller = vtkMultiProcessController.GetGlobalController()
ranks = controller.GetNumberOfProcesses() if controller else 1
rank = controller.GetLocalProcessId() if controller else 0
if ranks != 2:
    sys.exit(f"test_mapper_mpi: expected 2 MPI ranks, got {ranks}")


def cells_of(mesh, keep):
    ids = vtkIdList()
    for cell in range(mesh.GetNumberOfCells()):
        if keep(cell):
            ids.InsertNextId(cell)
    extract = vtkExtractCells()
    extract.SetInputData(mesh)
    extract.SetCellList(ids)
    extract.Update()
    piece = vtkUnstructuredGrid()
    piece.ShallowCopy(extract.GetOutput())
    return piece


def render(mesh, distributed, plane):
    """The scene's RGBA; distributed: the mapper composites across the ranks."""
    mapper = vtkDirectSurfaceMapper()
    mapper.SetInputData(mesh)
    mapper.SetValue(0, 0.5)
    mapper.SetValue(1, 0.2)
    mapper.SetIsoValueOpacity(0, 0.45)
    mapper.SetIsoValueOpacity(1, 0.6)
    mapper.SetIsoValueColor(1, 0.9, 0.5, 0.2)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer = vtkRenderer()
    renderer.SetBackground(0.2, 0.25, 0.3)
    renderer.AddActor(actor)
    if plane:
        source = vtkPlaneSource()
        source.SetOrigin(-1.2, -1.2, 0.1)
        source.SetPoint1(1.2, -1.2, 0.1)
        source.SetPoint2(-1.2, 1.2, -0.2)
        wall = polygon_actor(source, (0.3, 0.8, 0.4))
        renderer.AddActor(wall)
    window = vtkRenderWindow()
    window.SetSize(W, H)
    window.OffScreenRenderingOn()
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(2.2, 1.6, 3.0)
    camera.SetFocalPoint(0.05, -0.03, 0.02)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(30)
    # The mapper's bounds (each rank's own) must not set the clipping range: the whole lattice's.
    renderer.ResetCameraClippingRange(-1.0, 1.0, -1.0, 1.0, -1.0, 1.0)
    renderer.GetActiveCamera().SetClippingRange(0.5, 8.0)
    if distributed:
        mapper.SetController(controller)
        renderer.AddObserver("EndEvent", lambda caller, event: mapper.DrawTranslucentAcrossProcesses(
            renderer, actor, None, None, [0, 0]), 1.0)
    window.Render()
    pixels = vtkUnsignedCharArray()
    window.GetRGBACharPixelData(0, 0, W - 1, H - 1, 1, pixels)
    return vtk_to_numpy(pixels).reshape(H, W, 4).astype(int)


whole = grid(4)
mine = cells_of(whole, lambda cell: cell % 2 == rank)
distributed = render(mine, True, plane=(rank == 0))
if rank == 0:
    serial = render(whole, False, plane=True)
    half = render(mine, False, plane=True)
    difference = np.abs(distributed - serial)[:, :, :3].max(axis=2)
    lost = int((np.abs(half - serial)[:, :, :3].max(axis=2) > 2).sum())
    covered = int((np.abs(serial - render(grid(1, {"f": lambda x: 0 * x[:, 0] + 9}), False, plane=True))[:, :, :3].max(axis=2) > 0).sum())
    print(f"2 ranks, cells alternating: {int((difference > 0).sum())} of {W * H} pixels differ from "
          f"one process (max {difference.max()} / 255); rank 0's half alone: {lost} pixels off by "
          f"more than 2 / 255; the spheres cover {covered} pixels")
    failures = []
    if difference.max() > 2:
        failures.append(f"expected one process's picture within 2 / 255, got {int((difference > 2).sum())} pixels off by up to {difference.max()}")
    if lost < 1000:
        failures.append(f"rank 0's half alone should differ in more than 1000 pixels, got {lost}")
    if covered < 5000:
        failures.append(f"the spheres should cover more than 5000 pixels, got {covered}")
    for failure in failures:
        print("FAILED:", failure)
    if failures:
        sys.exit(1)  # (a normal end lets pvbatch finalize MPI on every rank)
    print("test_mapper_mpi: 0 failed")
