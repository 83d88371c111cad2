#!/usr/bin/env python3
"""Curved cells, side by side with the same camera: TetDSR on the mesh as given (curved cells
exact), TetDSR with the mid-edge nodes moved to their edges' midpoints (what a straight-sided
renderer draws), and vtkContourFilter (8 linear sub-tets per cell, its triangles rendered by
VTK). Writes one PNG. Needs an X display (xvfb-run -a).

  PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \\
      Examples/compare_curved.py Data/cylinder_flow.vtu speed 0.1 Examples/images/curved_cylinder.png \\
      --focal 0.5 0.2 0.205 --offset -0.05 -0.22 0.12
"""
import argparse

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
from vtkmodules.vtkFiltersCore import vtkContourFilter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkCamera, vtkPolyDataMapper, vtkRenderWindow,
                                         vtkRenderer, vtkTextActor, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingFreeType  # noqa: F401 (text)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the OpenGL backend)

from tetdsr import vtkDirectSurfaceMapper

EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]


def straightened(grid):
    copy = vtkUnstructuredGrid()
    copy.DeepCopy(grid)
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 10)
    for e, (a, b) in enumerate(EDGES):
        points[conn[:, 4 + e]] = 0.5 * (points[conn[:, a]] + points[conn[:, b]])
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=1))
    copy.SetPoints(vtk_points)
    return copy


def label(renderer, text):
    actor = vtkTextActor()
    actor.SetInput(text)
    actor.GetTextProperty().SetFontSize(15)
    actor.SetPosition(8, 8)
    renderer.AddActor2D(actor)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("array")
    parser.add_argument("iso", type=float)
    parser.add_argument("out")
    parser.add_argument("--focal", type=float, nargs=3, default=None)
    parser.add_argument("--offset", type=float, nargs=3, default=(2.0, -2.5, 1.8))
    parser.add_argument("--up", type=float, nargs=3, default=(0, 0, 1))
    parser.add_argument("--angle", type=float, default=30)
    parser.add_argument("--panel", type=int, default=420)
    args = parser.parse_args()

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.mesh)
    reader.Update()
    mesh = reader.GetOutput()
    bounds = mesh.GetBounds()
    focal = args.focal or [(bounds[2 * k] + bounds[2 * k + 1]) / 2 for k in range(3)]
    camera = vtkCamera()
    camera.SetFocalPoint(*focal)
    camera.SetPosition(*[focal[k] + args.offset[k] for k in range(3)])
    camera.SetViewUp(*args.up)
    camera.SetViewAngle(args.angle)

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(3 * args.panel, args.panel)
    contour = vtkContourFilter()
    contour.SetInputData(mesh)
    contour.SetInputArrayToProcess(0, 0, 0, 0, args.array)
    contour.SetValue(0, args.iso)
    contour.Update()
    panels = []
    for k, (title, data) in enumerate((("TetDSR: curved cells exact", mesh),
                                       ("TetDSR, mid-edge nodes ignored", straightened(mesh)),
                                       (None, None))):
        renderer = vtkRenderer()
        renderer.SetViewport(k / 3, 0, (k + 1) / 3, 1)
        renderer.SetActiveCamera(camera)
        renderer.SetBackground(0.32, 0.34, 0.43)
        if data is not None:
            mapper = vtkDirectSurfaceMapper()
            mapper.SetInputData(data)
            mapper.SetInputArrayToProcess(0, 0, 0, 0, args.array)
            mapper.SetValue(0, args.iso)
            mapper.ScalarVisibilityOff()
            panels.append(mapper)
        else:
            mapper = vtkPolyDataMapper()
            mapper.SetInputConnection(contour.GetOutputPort())
            mapper.ScalarVisibilityOff()
            title = "vtkContourFilter: %d triangles" % contour.GetOutput().GetNumberOfCells()
        actor = vtkActor()
        actor.SetMapper(mapper)
        renderer.AddActor(actor)
        label(renderer, "%s\n%s = %g" % (title, args.array, args.iso))
        window.AddRenderer(renderer)
    camera.SetClippingRange(1e-3 * np.linalg.norm(args.offset), 100 * np.linalg.norm(args.offset))
    window.Render()
    window.Render()  # (the mapper's full-resolution frame once the camera is still)
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    writer = vtkPNGWriter()
    writer.SetFileName(args.out)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    print("wrote", args.out)


if __name__ == "__main__":
    main()
