#!/usr/bin/env python3
"""The pictures of the CalculiX bracket (Data/calculix_bracket.vtu: 1,512 curved C3D20R
hexahedra): vtkContourFilter's and TetDSR's isosurface of the von Mises stress at ISO_VALUE, with
the same camera, each inside the faint edges of the part's boundary. Needs an X server (ParaView's
VTK has no off-screen GL of its own) and a TetDSR build:

  PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \\
      Scripts/calculix_bracket_view.py Data/calculix_bracket.vtu docs/images/calculix_bracket

writes <prefix>_contour.png and <prefix>_tetdsr.png and prints what each shows.
"""
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkLogger
from vtkmodules.vtkFiltersCore import vtkCleanPolyData, vtkContourFilter, vtkExtractEdges, vtkPolyDataConnectivityFilter
from vtkmodules.vtkFiltersGeometry import vtkUnstructuredGridGeometryFilter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow, vtkWindowToImageFilter
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (registers the OpenGL render window)

from tetdsr import vtkDirectSurfaceMapper

vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_WARNING)  # vtkExtractEdges logs at INFO

ARRAY = "S_Mises"
ISO_VALUE = 20.0  # MPa: the arm's low-stress core, the upper leg's, and a pocket at the bend
IMAGE_SIZE = (800, 600)
SURFACE_COLOR = (0.85, 0.45, 0.2)


def set_camera(camera, bounds):
    """Looking at the bracket from the side of its open bend, a little above."""
    b = np.array(bounds)
    lo, hi = b[0::2], b[1::2]
    centre = 0.5 * (lo + hi)
    camera.SetFocalPoint(*centre)
    camera.SetPosition(*(centre + np.array([0.75, -0.9, 0.6]) * np.linalg.norm(hi - lo)))
    camera.SetViewUp(0.0, 0.0, 1.0)
    camera.SetViewAngle(30.0)


def render(reader, surface_actor, png_path):
    renderer = vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    renderer.AddActor(surface_actor)
    boundary = vtkUnstructuredGridGeometryFilter()
    boundary.SetInputConnection(reader.GetOutputPort())
    edges = vtkExtractEdges()
    edges.SetInputConnection(boundary.GetOutputPort())
    mesh = vtkActor()
    mesh.SetMapper(vtkPolyDataMapper())
    mesh.GetMapper().SetInputConnection(edges.GetOutputPort())
    mesh.GetMapper().ScalarVisibilityOff()
    mesh.GetProperty().SetColor(0.55, 0.6, 0.7)
    mesh.GetProperty().SetOpacity(0.3)
    mesh.GetProperty().LightingOff()
    renderer.AddActor(mesh)
    set_camera(renderer.GetActiveCamera(), reader.GetOutput().GetBounds())
    renderer.ResetCameraClippingRange()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*IMAGE_SIZE)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    writer = vtkPNGWriter()
    writer.SetFileName(png_path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    window.Finalize()


def main(vtu_path, prefix):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu_path)
    reader.Update()
    contour = vtkContourFilter()
    contour.SetInputConnection(reader.GetOutputPort())
    contour.SetInputArrayToProcess(0, 0, 0, 0, ARRAY)
    contour.SetValue(0, ISO_VALUE)
    contour.ComputeScalarsOff()
    contour.ComputeNormalsOff()
    clean = vtkCleanPolyData()
    clean.SetInputConnection(contour.GetOutputPort())
    pieces = vtkPolyDataConnectivityFilter()
    pieces.SetInputConnection(clean.GetOutputPort())
    pieces.SetExtractionModeToAllRegions()
    pieces.Update()
    actor = vtkActor()
    actor.SetMapper(vtkPolyDataMapper())
    actor.GetMapper().SetInputConnection(clean.GetOutputPort())
    actor.GetProperty().SetColor(*SURFACE_COLOR)
    actor.GetProperty().EdgeVisibilityOn()
    actor.GetProperty().SetEdgeColor(0.45, 0.2, 0.05)
    render(reader, actor, prefix + "_contour.png")
    print(f"vtkContourFilter, {ARRAY} = {ISO_VALUE:g}: {clean.GetOutput().GetNumberOfCells()} triangles, "
          f"{pieces.GetNumberOfExtractedRegions()} pieces")

    mapper = vtkDirectSurfaceMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.SetInputArrayToProcess(0, 0, 0, 0, ARRAY)
    mapper.SetValue(0, ISO_VALUE)
    mapper.ScalarVisibilityOff()  # the actor's colour, as the contour picture's
    surface = vtkActor()
    surface.SetMapper(mapper)
    surface.GetProperty().SetColor(*SURFACE_COLOR)
    render(reader, surface, prefix + "_tetdsr.png")
    print(f"TetDSR, {ARRAY} = {ISO_VALUE:g}: {mapper.GetNumberOfRenderedCells()} cells rendered")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
