#!/usr/bin/env python3
"""The iso-value and camera of the P3 Poisson dataset's pictures, and vtkContourFilter's picture.

Scripts/make_p3_poisson.py chooses its exact solution around ISO_VALUE and calls this file for
the picture; a TetDSR picture of Data/p3_poisson.vtu meant to be compared with it should import
ISO_VALUE, IMAGE_SIZE and set_camera from here. Needs an X server (ParaView's VTK has no
off-screen GL of its own):

  xvfb-run -a /usr/bin/python3 Scripts/p3_poisson_view.py Data/p3_poisson.vtu \
      docs/images/p3_poisson_contour.png
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


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(f"usage: {sys.argv[0]} input.vtu output.png")
    triangles = render_contour(sys.argv[1], sys.argv[2])
    print(f"wrote {sys.argv[2]}: vtkContourFilter, u = {ISO_VALUE}: {triangles} triangles")
