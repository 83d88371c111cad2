#!/usr/bin/env python3
"""Curved cells, side by side with the same camera: TetDSR on the mesh as given (curved cells
exact), TetDSR with the mid-edge nodes moved to their edges' midpoints (what a straight-sided
renderer draws), and vtkContourFilter (8 linear sub-tets per cell, its triangles rendered by
VTK). Writes one PNG. Needs an X display (xvfb-run -a).

  PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \\
      Examples/compare_curved.py Data/cylinder_flow.vtu speed 0.15 Examples/images/curved_cylinder.png \\
      --focal 0.5 0.25 0.2 --offset 0 0 0.03 --up 1 0 0 --angle 30 --clip 0 0 0.2 0 0 -1
"""
import argparse

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
from vtkmodules.vtkFiltersCore import vtkContourFilter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkCommonDataModel import vtkPlane
from vtkmodules.vtkRenderingCore import (vtkActor, vtkCamera, vtkImageActor, vtkPolyDataMapper,
                                         vtkRenderWindow, vtkRenderer, vtkTextActor,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingFreeType  # noqa: F401 (text)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the OpenGL backend)

from tetdsr import vtkDirectSurfaceRayCaster

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
    actor.GetTextProperty().SetBackgroundColor(0.1, 0.1, 0.1)
    actor.GetTextProperty().SetBackgroundOpacity(0.7)
    actor.SetPosition(8, 8)
    renderer.AddActor2D(actor)


def caster_image(data, args, camera, size):
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(data)
    caster.SetInputArrayToProcess(0, 0, 0, 0, args.array)
    caster.SetValue(0, args.iso)
    caster.SetCamera(camera)
    caster.SetImageSize(size, size)
    if args.clip:
        plane = vtkPlane()
        plane.SetOrigin(*args.clip[:3])
        plane.SetNormal(*args.clip[3:])
        caster.AddClippingPlane(plane)
        caster.SetCapping(vtkDirectSurfaceRayCaster.CAP_BELOW_ISO_VALUE)
        caster.SetColorRange(0.0, args.iso)
    caster.Update()
    return caster


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
    parser.add_argument("--clip", type=float, nargs=6, default=None,
                        help="a clipping plane (origin, normal: the normal points to what stays), "
                             "capped where the field is below the iso-value")
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
    cut = " (cut, capped)" if args.clip else ""
    for k, (title, data) in enumerate((("TetDSR: curved cells exact" + cut, mesh),
                                       ("TetDSR, mid-edge nodes ignored" + cut, straightened(mesh)))):
        caster = caster_image(data, args, camera, args.panel)
        renderer = vtkRenderer()
        renderer.SetViewport(k / 3, 0, (k + 1) / 3, 1)
        image = vtkImageActor()
        image.GetMapper().SetInputConnection(caster.GetOutputPort())
        renderer.AddActor(image)
        renderer.ResetCamera()
        renderer.GetActiveCamera().ParallelProjectionOn()
        renderer.GetActiveCamera().SetParallelScale(args.panel / 2)
        label(renderer, "%s\n%s = %g" % (title, args.array, args.iso))
        window.AddRenderer(renderer)
    # vtkContourFilter's triangles, rendered by VTK with the same camera (and the same plane).
    contour = vtkContourFilter()
    contour.SetInputData(mesh)
    contour.SetInputArrayToProcess(0, 0, 0, 0, args.array)
    contour.SetValue(0, args.iso)
    contour.Update()
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(contour.GetOutputPort())
    mapper.ScalarVisibilityOff()
    if args.clip:
        plane = vtkPlane()
        plane.SetOrigin(*args.clip[:3])
        plane.SetNormal(*args.clip[3:])
        mapper.AddClippingPlane(plane)
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer = vtkRenderer()
    renderer.SetViewport(2 / 3, 0, 1, 1)
    renderer.SetActiveCamera(camera)
    renderer.AddActor(actor)
    label(renderer, "vtkContourFilter: %d triangles%s\n%s = %g" % (
        contour.GetOutput().GetNumberOfCells(), " (cut, no cap)" if args.clip else "", args.array,
        args.iso))
    window.AddRenderer(renderer)
    camera.SetClippingRange(1e-3 * np.linalg.norm(args.offset), 100 * np.linalg.norm(args.offset))
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    writer = vtkPNGWriter()
    writer.SetFileName(args.out)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    print("wrote", args.out)


if __name__ == "__main__":
    main()
