#!/usr/bin/env python3
"""The iso-value and camera of the P3 Poisson dataset's pictures: vtkContourFilter's and TetDSR's.

Scripts/make_p3_poisson.py chooses its exact solution around ISO_VALUE and calls this file for
the picture; a TetDSR picture of Data/p3_poisson.vtu meant to be compared with it should import
ISO_VALUE, IMAGE_SIZE and set_camera from here. Needs an X server (ParaView's VTK has no
off-screen GL of its own):

  xvfb-run -a /usr/bin/python3 Scripts/p3_poisson_view.py Data/p3_poisson.vtu \
      docs/images/p3_poisson_contour.png
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Scripts/p3_poisson_view.py \
      --tetdsr Data/p3_poisson.vtu docs/images/p3_poisson_tetdsr.png

(TetDSR's picture needs no X server: the filter ray casts on the CPU.)
"""
import sys

from vtkmodules.vtkFiltersCore import vtkContourFilter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (registers the OpenGL render window)

# The level of the point array "u" whose isosurface the pictures show.
ISO_VALUE = 0.5
IMAGE_SIZE = (600, 600)
# Looking down (60 degrees above the x-y plane) on the five bumps of make_p3_poisson.py, from
# where their pieces of the level set lie furthest apart on the screen; the view takes in all of
# them (the ball itself, radius 1, reaches beyond it).
CAMERA = {"position": (-0.7, 1.4, 2.8), "focal_point": (0.1, 0.0, 0.0),
          "view_up": (0.0, 0.0, 1.0), "view_angle": 30.0}


def set_camera(camera):
    """Puts CAMERA on a vtkCamera (clipping range left to the renderer)."""
    camera.SetPosition(CAMERA["position"])
    camera.SetFocalPoint(CAMERA["focal_point"])
    camera.SetViewUp(CAMERA["view_up"])
    camera.SetViewAngle(CAMERA["view_angle"])


def render_contour(vtu_path, png_path):
    """vtkContourFilter's isosurface u = ISO_VALUE of the file, flat shaded with its triangles'
    edges drawn, written as a PNG; returns the triangle count."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu_path)
    contour = vtkContourFilter()
    contour.SetInputConnection(reader.GetOutputPort())
    contour.SetInputArrayToProcess(0, 0, 0, 0, "u")  # 0: points
    contour.SetValue(0, ISO_VALUE)
    contour.ComputeScalarsOff()
    contour.ComputeNormalsOff()  # flat facets: the picture shows what the triangles are
    contour.Update()

    renderer = vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    surface = vtkActor()
    surface.SetMapper(vtkPolyDataMapper())
    surface.GetMapper().SetInputConnection(contour.GetOutputPort())
    surface.GetProperty().SetColor(0.85, 0.45, 0.2)
    surface.GetProperty().EdgeVisibilityOn()
    surface.GetProperty().SetEdgeColor(0.45, 0.2, 0.05)
    renderer.AddActor(surface)
    set_camera(renderer.GetActiveCamera())
    renderer.ResetCameraClippingRange()

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*IMAGE_SIZE)
    window.SetMultiSamples(0)  # the same pixels on every run
    window.AddRenderer(renderer)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    writer = vtkPNGWriter()
    writer.SetFileName(png_path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    return contour.GetOutput().GetNumberOfCells()


def render_tetdsr(vtu_path, png_path):
    """TetDSR's exact isosurface u = ISO_VALUE of the file (vtkDirectSurfaceRayCaster, exact
    gradient normals), written as a PNG; returns (pixels on the surface, cells rendered, curved
    cells, uncertified hits)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkRenderingCore import vtkCamera
    from tetdsr import vtkDirectSurfaceRayCaster

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu_path)
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputConnection(reader.GetOutputPort())
    caster.SetInputArrayToProcess(0, 0, 0, 0, "u")  # 0: points
    caster.SetValue(0, ISO_VALUE)
    caster.SetImageSize(*IMAGE_SIZE)
    caster.SetSurfaceColor(0.85, 0.45, 0.2)  # as the contour picture's
    camera = vtkCamera()
    set_camera(camera)
    caster.SetCamera(camera)
    caster.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(png_path)
    writer.SetInputConnection(caster.GetOutputPort())
    writer.Write()
    depth = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth"))
    return (int((depth != float("inf")).sum()), caster.GetNumberOfRenderedCells(),
            caster.GetNumberOfCurvedCells(), caster.GetNumberOfUncertifiedHits())


if __name__ == "__main__":
    arguments = sys.argv[1:]
    tetdsr = arguments[:1] == ["--tetdsr"]
    if tetdsr:
        arguments = arguments[1:]
    if len(arguments) != 2:
        sys.exit(f"usage: {sys.argv[0]} [--tetdsr] input.vtu output.png")
    if tetdsr:
        pixels, cells, curved, uncertified = render_tetdsr(*arguments)
        print(f"wrote {arguments[1]}: TetDSR, u = {ISO_VALUE}: {pixels} pixels on the surface, "
              f"{cells} cells rendered ({curved} curved), {uncertified} uncertified hits")
    else:
        triangles = render_contour(*arguments)
        print(f"wrote {arguments[1]}: vtkContourFilter, u = {ISO_VALUE}: {triangles} triangles")
