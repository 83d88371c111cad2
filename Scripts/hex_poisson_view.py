#!/usr/bin/env python3
"""The iso-value and camera of the hexahedral Poisson dataset's pictures: vtkContourFilter's and
TetDSR's.

Scripts/make_hex_poisson.py chooses its exact solution around ISO_VALUE and calls this file for
the picture; a TetDSR picture of Data/hex_poisson.vtu meant to be compared with it should import
ISO_VALUE, IMAGE_SIZE and set_camera from here. Needs an X server (ParaView's VTK has no
off-screen GL of its own):

  xvfb-run -a /usr/bin/python3 Scripts/hex_poisson_view.py Data/hex_poisson.vtu \
      docs/images/hex_poisson_contour.png
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Scripts/hex_poisson_view.py \
      --tetdsr Data/hex_poisson.vtu docs/images/hex_poisson_tetdsr.png

(TetDSR's picture needs no X server: the filter ray casts on the CPU. It needs a TetDSR build
that handles VTK_QUADRATIC_HEXAHEDRON cells.)

The contour picture prints the contour's triangles and connected pieces, and the number of
pieces of the exact level set (make_hex_poisson.exact_pieces: one per bump whose peak exceeds
ISO_VALUE, checked on a grid).
"""
import os
import sys

from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import (vtkCleanPolyData, vtkContourFilter, vtkExtractEdges,
                                       vtkPolyDataConnectivityFilter)
from vtkmodules.vtkFiltersGeometry import vtkUnstructuredGridGeometryFilter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (registers the OpenGL render window)
from vtkmodules.vtkCommonCore import vtkLogger

vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_WARNING)  # vtkExtractEdges logs at INFO

# The level of the point array "u" whose isosurface the pictures show.
ISO_VALUE = 0.5
IMAGE_SIZE = (600, 600)
# The part (a quarter of a thick cylindrical shell, radii 0.5 to 1.5, 0 <= z <= 1.1) seen from
# outside its outer wall along the bisector x = y, 50 degrees above the x-y plane, 4.7 away from
# the focal point: the whole part is in view (the outer wall's ends near the picture's sides) and
# the four bumps' pieces of the level set lie apart on the screen (bump 3's, missed by
# vtkContourFilter, would be at the left, near the outer wall; bump 2's the small one at right).
CAMERA = {"position": (2.76, 2.76, 3.95), "focal_point": (0.62, 0.62, 0.35),
          "view_up": (0.0, 0.0, 1.0), "view_angle": 30.0}
SURFACE_COLOR = (0.85, 0.45, 0.2)


def set_camera(camera):
    """Puts CAMERA on a vtkCamera (clipping range left to the renderer)."""
    camera.SetPosition(CAMERA["position"])
    camera.SetFocalPoint(CAMERA["focal_point"])
    camera.SetViewUp(CAMERA["view_up"])
    camera.SetViewAngle(CAMERA["view_angle"])


def contour(vtu_path):
    """vtkContourFilter's isosurface u = ISO_VALUE of the file (flat: no normals), and the number
    of its connected pieces (coincident points merged first)."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu_path)
    contour_filter = vtkContourFilter()
    contour_filter.SetInputConnection(reader.GetOutputPort())
    contour_filter.SetInputArrayToProcess(0, 0, 0, 0, "u")  # 0: points
    contour_filter.SetValue(0, ISO_VALUE)
    contour_filter.ComputeScalarsOff()
    contour_filter.ComputeNormalsOff()  # flat facets: the picture shows what the triangles are
    clean = vtkCleanPolyData()
    clean.SetInputConnection(contour_filter.GetOutputPort())
    pieces = vtkPolyDataConnectivityFilter()
    pieces.SetInputConnection(clean.GetOutputPort())
    pieces.SetExtractionModeToAllRegions()
    pieces.Update()
    surface = vtkPolyData()
    surface.ShallowCopy(clean.GetOutput())
    return reader, surface, pieces.GetNumberOfExtractedRegions()


def render_contour(vtu_path, png_path):
    """vtkContourFilter's isosurface u = ISO_VALUE of the file, flat shaded with its triangles'
    edges drawn, inside the faint edges of the mesh's boundary faces (each quadratic edge drawn
    as its two halves through the mid-edge node), written as a PNG; returns the triangle count and
    the number of connected pieces."""
    reader, surface, regions = contour(vtu_path)

    renderer = vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    actor = vtkActor()
    actor.SetMapper(vtkPolyDataMapper())
    actor.GetMapper().SetInputData(surface)
    actor.GetProperty().SetColor(*SURFACE_COLOR)
    actor.GetProperty().EdgeVisibilityOn()
    actor.GetProperty().SetEdgeColor(0.45, 0.2, 0.05)
    renderer.AddActor(actor)

    boundary = vtkUnstructuredGridGeometryFilter()  # boundary faces, as 8-node quadratic quads
    boundary.SetInputConnection(reader.GetOutputPort())
    edges = vtkExtractEdges()
    edges.SetInputConnection(boundary.GetOutputPort())
    mesh = vtkActor()
    mesh.SetMapper(vtkPolyDataMapper())
    mesh.GetMapper().SetInputConnection(edges.GetOutputPort())
    mesh.GetMapper().ScalarVisibilityOff()
    mesh.GetProperty().SetColor(0.55, 0.6, 0.7)
    mesh.GetProperty().SetOpacity(0.35)
    mesh.GetProperty().LightingOff()
    renderer.AddActor(mesh)
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
    return surface.GetNumberOfCells(), regions


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
    caster.SetSurfaceColor(*SURFACE_COLOR)  # as the contour picture's
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


def exact_piece_count():
    """The number of pieces of the exact level set, from make_hex_poisson.py's exact solution
    (needs only numpy and scipy, which Debian's python3 has with python3-scipy; None without)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    try:
        from make_hex_poisson import exact_pieces
    except ImportError:
        return None
    return len(exact_pieces())


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
        triangles, regions = render_contour(*arguments)
        exact = exact_piece_count()
        print(f"wrote {arguments[1]}: vtkContourFilter, u = {ISO_VALUE}: {triangles} triangles "
              f"in {regions} connected pieces; the exact level set has "
              f"{exact if exact is not None else '(scipy missing: not counted)'} pieces")
