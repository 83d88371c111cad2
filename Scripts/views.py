"""What the dataset pictures share (Scripts/*_view.py): a camera from a dict, vtkContourFilter's
flat-shaded surface with its triangles' edges, the faint edges of a mesh's boundary, an
off-screen window written as a PNG, and TetDSR's picture of the same view; and their command
line ([--tetdsr] input.vtu output.png). Each *_view.py keeps its iso-value, array, size and
camera, which make_*.py and the tests import from it."""
import sys

from vtkmodules.vtkCommonCore import vtkLogger
from vtkmodules.vtkFiltersCore import (vtkCleanPolyData, vtkContourFilter, vtkExtractEdges,
                                       vtkPolyDataConnectivityFilter)
from vtkmodules.vtkFiltersGeometry import vtkUnstructuredGridGeometryFilter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkCamera, vtkPolyDataMapper, vtkRenderer,
                                         vtkRenderWindow, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (registers the OpenGL render window)

vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_WARNING)  # vtkExtractEdges logs at INFO

EDGE_COLOR = (0.45, 0.2, 0.05)  # the contour triangles' edges
MESH_COLOR = (0.55, 0.6, 0.7)   # the mesh boundary's edges


def place_camera(camera, view):
    """Puts a view dict (position, focal_point, view_up, view_angle) on a vtkCamera (clipping
    range left to the renderer)."""
    camera.SetPosition(view["position"])
    camera.SetFocalPoint(view["focal_point"])
    camera.SetViewUp(view["view_up"])
    camera.SetViewAngle(view["view_angle"])


def read(vtu_path, update=False):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu_path)
    if update:
        reader.Update()
    return reader


def contour(port, array, iso_value, clean=True):
    """vtkContourFilter's isosurface array = iso_value (flat: no normals, no scalars); with
    `clean`, coincident points merged and the connected pieces counted. Returns (the filter whose
    output is the surface, the number of pieces or None)."""
    contour_filter = vtkContourFilter()
    contour_filter.SetInputConnection(port)
    contour_filter.SetInputArrayToProcess(0, 0, 0, 0, array)  # 0: points
    contour_filter.SetValue(0, iso_value)
    contour_filter.ComputeScalarsOff()
    contour_filter.ComputeNormalsOff()  # flat facets: the picture shows what the triangles are
    if not clean:
        contour_filter.Update()
        return contour_filter, None
    cleaned = vtkCleanPolyData()
    cleaned.SetInputConnection(contour_filter.GetOutputPort())
    pieces = vtkPolyDataConnectivityFilter()
    pieces.SetInputConnection(cleaned.GetOutputPort())
    pieces.SetExtractionModeToAllRegions()
    pieces.Update()
    return cleaned, pieces.GetNumberOfExtractedRegions()


def triangles_actor(port, color):
    """A flat surface with its triangles' edges drawn."""
    actor = vtkActor()
    actor.SetMapper(vtkPolyDataMapper())
    actor.GetMapper().SetInputConnection(port)
    actor.GetProperty().SetColor(*color)
    actor.GetProperty().EdgeVisibilityOn()
    actor.GetProperty().SetEdgeColor(*EDGE_COLOR)
    return actor


def mesh_edges_actor(port, opacity):
    """The faint edges of the mesh's boundary faces (a quadratic edge drawn as its two halves
    through the mid-edge node)."""
    boundary = vtkUnstructuredGridGeometryFilter()
    boundary.SetInputConnection(port)
    edges = vtkExtractEdges()
    edges.SetInputConnection(boundary.GetOutputPort())
    mesh = vtkActor()
    mesh.SetMapper(vtkPolyDataMapper())
    mesh.GetMapper().SetInputConnection(edges.GetOutputPort())
    mesh.GetMapper().ScalarVisibilityOff()
    mesh.GetProperty().SetColor(*MESH_COLOR)
    mesh.GetProperty().SetOpacity(opacity)
    mesh.GetProperty().LightingOff()
    return mesh


def write_picture(actors, place, size, png_path):
    """The actors on white in an off-screen window of `size`, the camera placed by
    place(camera), written as a PNG (no multisampling: the same pixels on every run)."""
    renderer = vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    for actor in actors:
        renderer.AddActor(actor)
    place(renderer.GetActiveCamera())
    renderer.ResetCameraClippingRange()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*size)
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


def tetdsr_picture(vtu_path, png_path, array, iso_value, size, view, color):
    """TetDSR's exact isosurface array = iso_value of the file (vtkDirectSurfaceRayCaster, exact
    gradient normals, no X server needed) from `view`, written as a PNG; returns (pixels on the
    surface, cells rendered, curved cells, uncertified hits)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from tetdsr import vtkDirectSurfaceRayCaster

    reader = read(vtu_path)  # (kept: a connection does not keep its producer alive)
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputConnection(reader.GetOutputPort())
    caster.SetInputArrayToProcess(0, 0, 0, 0, array)  # 0: points
    caster.SetValue(0, iso_value)
    caster.SetImageSize(*size)
    caster.SetSurfaceColor(*color)  # as the contour picture's
    camera = vtkCamera()
    place_camera(camera, view)
    caster.SetCamera(camera)
    caster.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(png_path)
    writer.SetInputConnection(caster.GetOutputPort())
    writer.Write()
    depth = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth"))
    return (int((depth != float("inf")).sum()), caster.GetNumberOfRenderedCells(),
            caster.GetNumberOfCurvedCells(), caster.GetNumberOfUncertifiedHits())


def command_line(render_contour, render_tetdsr, label):
    """[--tetdsr] input.vtu output.png: runs render_tetdsr (printing its counts) or
    render_contour (printing what it returns, a sentence)."""
    arguments = sys.argv[1:]
    tetdsr = arguments[:1] == ["--tetdsr"]
    if tetdsr:
        arguments = arguments[1:]
    if len(arguments) != 2:
        sys.exit(f"usage: {sys.argv[0]} [--tetdsr] input.vtu output.png")
    if tetdsr:
        pixels, cells, curved, uncertified = render_tetdsr(*arguments)
        print(f"wrote {arguments[1]}: TetDSR, {label}: {pixels} pixels on the surface, "
              f"{cells} cells rendered ({curved} curved), {uncertified} uncertified hits")
    else:
        print(f"wrote {arguments[1]}: vtkContourFilter, {label}: {render_contour(*arguments)}")
