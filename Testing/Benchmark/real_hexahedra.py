"""Speed on the real hexahedral results of Data/ (run with /usr/bin/python3 under xvfb-run, with
PYTHONPATH=build/lib/python3/dist-packages): per file and iso-value, TetDSR's preprocessing, first
frame and camera move (both cores) at 512 x 512 and 1024 x 1024, against vtkContourFilter's
contour plus its first render (VTK 9.2, one core) of the same iso-value at the same size, in the
same run. Prints a Markdown table; the camera move is the median of 3 (10-degree azimuth steps).

  xvfb-run -a /usr/bin/python3 Testing/Benchmark/real_hexahedra.py [Data folder]
"""
import os
import statistics
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkContourFilter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkActor, vtkCamera, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

from tetdsr import vtkDirectSurfaceRayCaster

DATA = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "Data")
CASES = [("calculix_bracket.vtu", "S_Mises", (20.0, 100.0, 200.0)),
         ("hex_poisson.vtu", "u", (0.5,)),
         ("mfem_hex_q3.vtu", "u", (0.5,))]


def camera_for(grid):
    b = np.array(grid.GetBounds())
    lo, hi = b[0::2], b[1::2]
    centre = 0.5 * (lo + hi)
    camera = vtkCamera()
    camera.SetFocalPoint(*centre)
    camera.SetPosition(*(centre + np.array([0.75, -0.9, 0.6]) * np.linalg.norm(hi - lo)))
    camera.SetViewUp(0.0, 0.0, 1.0)
    camera.SetViewAngle(30.0)
    return camera


# Camera moves timed per case (their median); the 1024^2 frames of the Q3 file take seconds each.
MOVES = 3


def tetdsr_times(grid, array, iso, size):
    camera = camera_for(grid)
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(grid)
    caster.SetInputArrayToProcess(0, 0, 0, 0, array)
    caster.SetValue(0, iso)
    caster.SetCamera(camera)
    caster.SetImageSize(1, 1)
    start = time.perf_counter()
    caster.Update()
    preprocess = time.perf_counter() - start
    caster.SetImageSize(size, size)
    start = time.perf_counter()
    caster.Update()
    first = time.perf_counter() - start
    moves = []
    for _ in range(MOVES):
        camera.Azimuth(10.0)
        start = time.perf_counter()
        caster.Update()
        moves.append(time.perf_counter() - start)
    depth = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth"))
    return preprocess, first, statistics.median(moves), int(np.isfinite(depth).sum()), caster


def contour_time(grid, array, iso, size):
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(size, size)
    renderer = vtkRenderer()
    window.AddRenderer(renderer)
    renderer.SetActiveCamera(camera_for(grid))
    start = time.perf_counter()
    contour = vtkContourFilter()
    contour.SetInputData(grid)
    contour.SetInputArrayToProcess(0, 0, 0, 0, array)
    contour.SetValue(0, iso)
    contour.Update()
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(contour.GetOutputPort())
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer.AddActor(actor)
    renderer.ResetCameraClippingRange()
    window.Render()
    elapsed = time.perf_counter() - start
    triangles = contour.GetOutput().GetNumberOfCells()
    window.Finalize()
    return elapsed, triangles


def main():
    print("| file | cells (curved) | array = iso | TetDSR preprocess s | first frame 512^2 s | camera move 512^2 s "
          "| camera move 1024^2 s | contour + first render 512^2 s (triangles) | move / contour, 512^2 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, array, isos in CASES:
        reader = vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(DATA, name))
        reader.Update()
        grid = reader.GetOutput()
        for iso in isos:
            preprocess, first, move512, _, caster = tetdsr_times(grid, array, iso, 512)
            _, _, move1024, _, _ = tetdsr_times(grid, array, iso, 1024)
            contour, triangles = contour_time(grid, array, iso, 512)
            print(f"| {name} | {grid.GetNumberOfCells()} ({caster.GetNumberOfCurvedCells()}) | {array} = {iso:g} "
                  f"| {preprocess:.3f} | {first:.3f} | {move512:.3f} | {move1024:.3f} | {contour:.3f} ({triangles}) "
                  f"| {move512 / contour:.2f} |", flush=True)


if __name__ == "__main__":
    main()
