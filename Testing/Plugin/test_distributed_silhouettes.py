"""Distributed pictures equal the serial one over the whole picture, silhouettes included: a
translucent exact sphere around an opaque exact one, beside (and into) an opaque polygonal box, in
the "Direct Surface" representation, from a mesh cut into two pieces through both spheres, one per
rank, under `mpirun -np 2 pvbatch` and on a 2-process pvserver for a pvpython client.

Usage:
  pvbatch test_distributed_silhouettes.py <TetDSR.so> <work directory> reference
      (serial) writes the mesh, whole and as two pieces (a .pvtu), renders the views from the whole
      mesh and keeps the pictures;
  mpirun -np 2 pvbatch test_distributed_silhouettes.py <TetDSR.so> <work directory> compare
      renders the same from the .pvtu, each rank reading one piece, and compares;
  client_server.py 2 <seconds> pvserver pvpython test_distributed_silhouettes.py <TetDSR.so>
      <work directory> connect
      the same on a 2-process pvserver (the launcher appends --port).

The field is |x|^2 on quadratic tetrahedra, which hold it exactly: the surfaces are exact spheres
(radius 0.55 opaque, radius 1 at opacity 0.4), seen from two cameras, each with ParaView's
default FXAA, without, and with the box translucent (ParaView's ordered compositing), and both
spheres opaque beside the translucent box from two more. The pieces are the cells on either side
of the plane x + 0.35 y = 0.05 (by centroid): the cut crosses both spheres, off the lattice's
planes, so the rank boundary runs through the surfaces and along the silhouettes in every view.
Every pixel of every view must be within 2 / 255 of the serial picture; a difference picture
(<tag>_<view>_difference.png) shows where any is.
"""
import argparse
import os
import sys

import numpy as np
import paraview.simple as simple
from paraview.simple import (Box, Connect, CreateView, LoadPlugin, SaveScreenshot, Show,
                             XMLPartitionedUnstructuredGridReader, XMLUnstructuredGridReader)
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_TETRA, vtkCellArray, vtkUnstructuredGrid
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkPoints, vtkStringOutputWindow
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
sys.path.insert(0, os.path.join(here, "..", "Python"))
from kuhn_lattice import lattice  # noqa: E402
from pieces import write_pieces  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("plugin")
parser.add_argument("work")
parser.add_argument("mode", choices=["reference", "compare", "connect"])
parser.add_argument("--port", type=int)
args = parser.parse_args()
os.makedirs(args.work, exist_ok=True)

W, H = 300, 220
TOLERANCE = 2  # / 255: blending in 8 bits (the GL blend against the CPU's) rounds differently
INNER, OUTER = 0.55 ** 2, 1.0  # iso-values of |x|^2: the opaque sphere and the translucent one
CAMERAS = {  # name: camera position, focal point
    "front": ([2.1, 1.4, 3.6], [0.25, 0.0, 0.0]),
    "side": ([3.9, -1.6, 1.2], [0.3, 0.1, 0.0]),
    "back": ([-3.0, 1.0, -2.6], [0.3, 0.0, 0.0]),
    "below": ([0.5, -4.0, 1.0], [0.3, 0.0, 0.0]),
}
# name: camera, FXAA, the box's opacity, the outer sphere's opacity. The first two cameras with
# ParaView's default FXAA and without (FXAA runs once over the finished frame, after the
# compositor's and the mapper's translucent drawing) and with a translucent box: then ParaView
# composites the processes' images in order, without depth (ordered compositing), and the mapper
# composites their opaque depth itself. Under ordered compositing opaque spheres too (the other
# two cameras, which see the box beside or behind them: translucent geometry in front of them is
# hidden, as the representation warns) are composited across the processes by the mapper.
VIEWS = {f"{camera}-fxaa{fxaa}": (camera, fxaa, 1.0, 0.4)
         for camera in ("front", "side") for fxaa in (1, 0)}
VIEWS.update({f"{camera}-translucent-box": (camera, 0, 0.5, 0.4) for camera in ("front", "side")})
VIEWS.update({f"{camera}-opaque-spheres": (camera, 0, 0.5, 1.0) for camera in ("back", "below")})
ORDERED_WARNING = "composites the images of its 2 rendering processes in order"
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message, flush=True)


def sphere_grid():
    """[-1.2, 1.2]^3 as 6^3 cubes of 6 quadratic tets, holding f = |x|^2."""
    points, cells = lattice(6, -1.2, 1.2)
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=1))
    grid.SetPoints(vtk_points)
    cell_array = vtkCellArray()
    cell_array.SetData(numpy_to_vtkIdTypeArray(np.arange(0, 10 * len(cells) + 1, 10), deep=1),
                       numpy_to_vtkIdTypeArray(cells.ravel(), deep=1))
    grid.SetCells(numpy_to_vtk(np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8), deep=1),
                  cell_array)
    field = numpy_to_vtk(np.ascontiguousarray(np.sum(points ** 2, axis=1)), deep=1)
    field.SetName("f")
    grid.GetPointData().AddArray(field)
    grid.GetPointData().SetActiveScalars("f")
    return grid, points, cells


def write_mesh():
    """sphere.vtu (whole) and sphere.pvtu (two pieces, each cutting both spheres)."""
    grid, points, cells = sphere_grid()
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(os.path.join(args.work, "sphere.vtu"))
    writer.SetDataModeToBinary()
    writer.SetInputData(grid)
    writer.Write()
    centroids = points[cells[:, :4]].mean(axis=1)
    side = (centroids[:, 0] + 0.35 * centroids[:, 1] >= 0.05).astype(int)
    # Each sphere crosses cells of both pieces (cells whose nodal values straddle its iso-value).
    nodal = np.sum(points ** 2, axis=1)[cells]
    for iso in (INNER, OUTER):
        crossed = (nodal.min(axis=1) < iso) & (nodal.max(axis=1) > iso)
        counts = [int((crossed & (side == k)).sum()) for k in (0, 1)]
        check(min(counts) > 20, f"the sphere |x|^2 = {iso}: expected it in more than 20 cells of "
                                f"each piece, got {counts}")
        print(f"the sphere |x|^2 = {iso:.4f} crosses {counts} cells of the two pieces")
    write_pieces(grid, side, args.work, "sphere_piece")
    os.replace(os.path.join(args.work, "sphere_piece.pvtu"), os.path.join(args.work, "sphere.pvtu"))
    return [int((side == k).sum()) for k in (0, 1)]


def pixels(path):
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    return vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)


def save_difference(difference, path):
    """Black where a pixel equals the serial one, white where it is over TOLERANCE, grey
    between."""
    from vtkmodules.vtkCommonDataModel import vtkImageData
    shade = np.where(difference > TOLERANCE, 255, np.where(difference > 0, 96, 0)).astype(np.uint8)
    image = vtkImageData()
    image.SetDimensions(W, H, 1)
    image.GetPointData().SetScalars(numpy_to_vtk(shade, deep=1))
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()


def render_views(source, tag, opaque=False):
    """{view: pixels} of the scene from `source`, each saved as <tag>_<view>.png; opaque: both
    spheres opaque in every view."""
    view = CreateView("RenderView")
    view.ViewSize = [W, H]
    view.OrientationAxesVisibility = 0
    display = Show(source, view)
    display.SetRepresentationType("Direct Surface")
    display.ContourBy = ["POINTS", "f"]
    display.ColorArrayName = ["POINTS", ""]
    display.Isosurfaces = [INNER, OUTER]
    display.IsoValueColors = [0.9, 0.3, 0.2, 0.2, 0.5, 0.95]
    box = Show(Box(XLength=0.5, YLength=1.4, ZLength=0.5, Center=[1.25, 0.0, 0.0]), view)
    box.DiffuseColor = [0.9, 0.8, 0.1]
    box.ColorArrayName = ["POINTS", ""]
    pictures = {}
    for name, (camera, fxaa, box_opacity, outer_opacity) in VIEWS.items():
        position, focal_point = CAMERAS[camera]
        view.UseFXAA = fxaa
        box.Opacity = box_opacity
        display.IsoValueOpacities = [1.0, 1.0 if opaque else outer_opacity]
        view.CameraPosition = position
        view.CameraFocalPoint = focal_point
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.CameraViewAngle = 30.0
        path = os.path.join(args.work, f"{tag}_{name}.png")
        SaveScreenshot(path, view, ImageResolution=[W, H])
        pictures[name] = pixels(path)
    simple.Delete(view)
    return pictures


if args.mode == "reference":
    LoadPlugin(args.plugin, remote=False, ns=globals())
    simple._DisableFirstRenderCameraReset()
    counts = write_mesh()
    whole = XMLUnstructuredGridReader(FileName=[os.path.join(args.work, "sphere.vtu")])
    pictures = render_views(whole, "serial")
    opaque = render_views(whole, "serial_opaque", opaque=True)
    # Each piece alone must change the picture (else a lost piece could go unnoticed), and the
    # translucent sphere must show (else one lost in compositing could).
    for k in range(2):
        piece = XMLUnstructuredGridReader(
            FileName=[os.path.join(args.work, f"sphere_piece{k}.vtu")])
        alone = render_views(piece, f"piece{k}")
        for name in VIEWS:
            changed = int((np.abs(alone[name] - pictures[name]).max(axis=1) > TOLERANCE).sum())
            check(changed > 1000, f"piece {k} alone, {name}: should change more than 1000 pixels, "
                                  f"got {changed}")
        simple.Delete(piece)
    for name in (name for name, settings in VIEWS.items() if settings[3] < 1.0):
        shown = int((np.abs(opaque[name] - pictures[name]).max(axis=1) > TOLERANCE).sum())
        check(shown > 5000, f"{name}: the translucent sphere should change more than 5000 pixels, "
                            f"got {shown}")
        print(f"serial, {name}: the translucent sphere changes {shown} of {W * H} pixels")
    for camera in ("front", "side"):
        # FXAA smooths every silhouette, the translucent sphere's included (else a compositor's
        # FXAA, which runs over the whole frame, would differ from the serial picture there).
        smoothed = int((np.abs(pictures[f"{camera}-fxaa1"] - pictures[f"{camera}-fxaa0"])
                        .max(axis=1) > TOLERANCE).sum())
        check(smoothed > 600, f"{camera}: FXAA should change more than 600 pixels (every "
                              f"silhouette), got {smoothed}")
        print(f"serial, {camera}: FXAA changes {smoothed} pixels")
    np.savez(os.path.join(args.work, "serial.npz"), **pictures)
    print(f"reference written to {args.work}: pieces of {counts} cells")
else:
    if args.mode == "connect":
        Connect("localhost", args.port)
        LoadPlugin(args.plugin, remote=True, ns=globals())
        tag = "server2"
    else:
        tag = "mpi"
    LoadPlugin(args.plugin, remote=False, ns=globals())
    simple._DisableFirstRenderCameraReset()
    from paraview import servermanager
    ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    check(ranks == 2, f"{args.mode}: expected 2 rendering processes, got {ranks}")
    pieces = XMLPartitionedUnstructuredGridReader(FileName=[os.path.join(args.work, "sphere.pvtu")])
    if args.mode == "compare":
        # The representation speaks on process 0, this one. (pvbatch prints this script's output
        # through the output window too: the usual one is put back before anything is printed.)
        usual = vtkOutputWindow.GetInstance()
        messages = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(messages)
    pictures = render_views(pieces, tag)
    if args.mode == "compare":
        vtkOutputWindow.SetInstance(usual)
        print(messages.GetOutput(), flush=True)
        said = messages.GetOutput().count(ORDERED_WARNING)
        check(said == 1, f"ordered compositing with opaque spheres: expected the representation's "
                         f"warning once, got it {said} times")
    serial = np.load(os.path.join(args.work, "serial.npz"))
    for name in VIEWS:
        difference = np.abs(pictures[name] - serial[name]).max(axis=1)
        save_difference(difference, os.path.join(args.work, f"{tag}_{name}_difference.png"))
        over = int((difference > TOLERANCE).sum())
        check(over == 0, f"{tag}, {name}: expected the serial picture within {TOLERANCE} / 255 in "
                         f"every pixel, got {over} pixels off by up to {difference.max()} / 255")
        print(f"{tag}, {name}: {int((difference > 0).sum())} of {W * H} pixels differ from the "
              f"serial picture (max {difference.max()} / 255), {over} by more than "
              f"{TOLERANCE} / 255", flush=True)

if failures:
    sys.exit(1)
print(f"distributed silhouettes ({args.mode}): 0 failed")
