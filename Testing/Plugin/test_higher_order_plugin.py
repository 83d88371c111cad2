"""The plugin on VTK_LAGRANGE_TETRAHEDRON and VTK_BEZIER_TETRAHEDRON grids (straight, order 3 and 4,
built by Testing/Python/higher_order_grids.py on VTK's own node positions and written to .vtu).

Usage:
  pvpython test_higher_order_plugin.py <TetDSR.so> <work directory> serial
      the Direct Surface Ray Cast filter on an order-4 torus (Lagrange and Bezier) against the
      analytic first root per pixel, and the "Direct Surface" representation on order-3/4 cells
      against the same quadratic field on VTK_QUADRATIC_TETRA cells (the same screenshot);
  pvbatch test_higher_order_plugin.py <TetDSR.so> <work directory> reference
      (serial) writes the Lagrange torus as two pieces (a .pvtu) and the serial results;
  mpirun -np 2 pvbatch test_higher_order_plugin.py <TetDSR.so> <work directory> compare
      the same from the .pvtu, one piece per rank, against the serial results.
  reference and compare take an optional last argument, the mesh: "torus" (the default) or
  "mixed": hex_wedge_grids.mixed_mesh, curved (20-node hexahedra, 15- and 18-node wedges and
  quadratic tetrahedra, sharing faces), holding a sphere cut by the pieces' boundary.
"""
import os
import sys

import numpy as np
import paraview.simple as simple
from paraview import servermanager
from paraview.simple import (ColorBy, CreateView, LoadPlugin, SaveScreenshot, Show,
                             XMLPartitionedUnstructuredGridReader, XMLUnstructuredGridReader)
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import (VTK_BEZIER_TETRAHEDRON, VTK_LAGRANGE_TETRAHEDRON,
                                           VTK_QUADRATIC_TETRA)
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLImageDataWriter, vtkXMLUnstructuredGridWriter

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import hex_wedge_grids as hw  # noqa: E402
import higher_order_grids as hog  # noqa: E402

plugin_path, work_dir, mode = sys.argv[1:4]
MESH = sys.argv[4] if len(sys.argv) > 4 else "torus"
os.makedirs(work_dir, exist_ok=True)
LoadPlugin(plugin_path, remote=False, ns=globals())
simple._DisableFirstRenderCameraReset()
ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


W, H = (320, 240) if MESH == "torus" else (200, 150)  # (curved hexahedra: a solve per ray)
CAMERA = dict(CameraPosition=[1.7, 1.35, 2.5], CameraFocalPoint=[0.5, 0.5, 0.5],
              CameraViewUp=[0.0, 1.0, 0.0], CameraViewAngle=24.0)
ARRAYS = ["Colors", "Depth", "Normals", "CellId", "ColorValues"]
TORUS = hog.torus()
SPHERE = hog.sphere(np.array([0.47, 0.53, 0.51]), 0.3)
ISO = TORUS.iso if MESH == "torus" else SPHERE.iso


def colour(x):
    return x[..., 0] ** 2 - x[..., 1] * x[..., 2]


def quadric(x):
    d = x - np.array([0.47, 0.52, 0.5])
    return d[..., 0] ** 2 + 1.3 * d[..., 1] ** 2 + 0.8 * d[..., 2] ** 2


def write(grid, name):
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(os.path.join(work_dir, name))
    writer.SetDataModeToBinary()  # inline: this Debian's expat cannot read appended data
    writer.SetInputData(grid)
    writer.Write()
    return os.path.join(work_dir, name)


def run_filter(source, iso, colour_array=None):
    """The filter's output, the ranks' blocks put together: {array name: values per pixel}."""
    caster = DirectSurfaceRayCast(Input=source, ContourBy=["POINTS", "f"], Isosurfaces=[iso])  # noqa: F821
    caster.ImageSize = [W, H]
    caster.FitCameraToMesh = 0
    for key, value in CAMERA.items():
        setattr(caster, key, value)
    if colour_array:
        caster.ColorByArray = 1
        caster.ColorArray = ["POINTS", colour_array]
        caster.ColorRange = [-1.0, 1.0]
    caster.UpdatePipeline()
    images = {}
    for rank in range(ranks):
        block = servermanager.Fetch(caster, rank) if ranks > 1 else servermanager.Fetch(caster)
        e = block.GetExtent()
        i, j = np.meshgrid(np.arange(e[0], e[1] + 1), np.arange(e[2], e[3] + 1))
        pixels = (i + W * j).ravel()
        for name in ARRAYS:
            array = block.GetPointData().GetArray(name)
            if array is None:
                continue
            values = vtk_to_numpy(array)
            if name not in images:
                images[name] = np.zeros((W * H,) + values.shape[1:], values.dtype)
            images[name][pixels] = values
    simple.Delete(caster)
    return images


def screenshot(source, iso, name, colour_array=None):
    """The "Direct Surface" representation's picture (RGB per pixel)."""
    view = CreateView("RenderView")
    view.ViewSize = [W, H]
    view.OrientationAxesVisibility = 0
    view.UseFXAA = 0
    for key, value in CAMERA.items():
        setattr(view, key, value)
    display = Show(source, view)
    display.SetRepresentationType("Direct Surface")
    display.ContourBy = ["POINTS", "f"]
    display.Isosurfaces = [iso]
    if colour_array:
        ColorBy(display, ("POINTS", colour_array))
        simple.GetColorTransferFunction(colour_array).RescaleTransferFunction(-1.0, 1.0)
    else:
        display.ColorArrayName = ["POINTS", ""]
    path = os.path.join(work_dir, name)
    SaveScreenshot(path, view, ImageResolution=[W, H])
    simple.Delete(view)
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    return vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)


def mesh_grid():
    if MESH == "torus":
        return hog.grid(2, VTK_LAGRANGE_TETRAHEDRON, 4, {"f": TORUS.value, "colour": colour})
    return hw.mixed_mesh(hw.bulge(), {"f": SPHERE.value, "colour": colour})


if mode == "serial":
    rays = hog.pixel_rays(CAMERA["CameraPosition"], CAMERA["CameraFocalPoint"], CAMERA["CameraViewUp"],
                          CAMERA["CameraViewAngle"], W, H)
    t, grazing = hog.first_crossing(TORUS, *rays)
    for kind, vtk_type in (("Lagrange", VTK_LAGRANGE_TETRAHEDRON), ("Bezier", VTK_BEZIER_TETRAHEDRON)):
        path = write(hog.grid(2, vtk_type, 4, {"f": TORUS.value, "colour": colour}), f"torus_{kind}.vtu")
        reader = XMLUnstructuredGridReader(FileName=[path])
        out = run_filter(reader, TORUS.iso, "colour")
        ours, exact = np.isfinite(out["Depth"]), np.isfinite(t)
        wrong = int(((ours != exact) & ~grazing).sum())
        both = ours & exact & ~grazing
        depth = float(np.abs(out["Depth"][both] - t[both]).max()) / np.sqrt(3.0)
        points = rays[0][both] + t[both, None] * rays[1][both]
        values = float(np.abs(out["ColorValues"][both] - colour(points)).max())
        print(f"filter in pvpython, {kind} order-4 torus: {int(both.sum())} pixels, {wrong} differ in "
              f"coverage, depth within {depth:.2e} of the diagonal, colour values within {values:.2e}")
        check(both.sum() > 5000, f"{kind}: expected more than 5000 surface pixels, got {both.sum()}")
        check(wrong == 0, f"{kind}: expected the torus's coverage, got {wrong} pixels differing")
        check(depth < 1e-9, f"{kind}: expected depth within 1e-9 of the diagonal, got {depth:.2e}")
        check(values < 1e-9, f"{kind}: expected the analytic colour values, got an error of {values:.2e}")
        simple.Delete(reader)
    pictures = {}
    for name, vtk_type, order in (("Lagrange 4", VTK_LAGRANGE_TETRAHEDRON, 4), ("Bezier 3", VTK_BEZIER_TETRAHEDRON, 3),
                                  ("quadratic", VTK_QUADRATIC_TETRA, 2)):
        path = write(hog.grid(2, vtk_type, order, {"f": quadric, "colour": colour}), f"quadric_{order}.vtu")
        reader = XMLUnstructuredGridReader(FileName=[path])
        pictures[name] = screenshot(reader, 0.1, f"quadric_{order}.png", "colour")
        simple.Delete(reader)
    reference = pictures.pop("quadratic")
    background = reference[0]
    for name, picture in pictures.items():
        covered = int(np.any(reference != background, axis=1).sum())
        error = int(np.abs(picture - reference).max())
        print(f"representation, {name} vs VTK_QUADRATIC_TETRA: {covered} surface pixels, "
              f"colours within {error}/255")
        check(covered > 5000, f"{name}: expected a visible surface, got {covered} pixels")
        check(error <= 1, f"{name}: expected the quadratic cells' picture, got a difference of {error}/255")
elif mode == "reference":
    check(ranks == 1, f"reference: expected one process, got {ranks}")
    grid = mesh_grid()
    # Two pieces: the cells whose nodes' mean lies on either side of x = 0.5 (the surface is cut).
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    connectivity = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    x = vtk_to_numpy(grid.GetPoints().GetData())[:, 0]
    centroid_x = np.array([x[connectivity[a:b]].mean() for a, b in zip(offsets[:-1], offsets[1:])])
    from vtkmodules.vtkCommonCore import vtkIdList
    from vtkmodules.vtkFiltersCore import vtkExtractCells
    for piece, cells in enumerate([np.flatnonzero(centroid_x < 0.5), np.flatnonzero(centroid_x >= 0.5)]):
        ids = vtkIdList()
        for cell in cells:
            ids.InsertNextId(int(cell))
        extract = vtkExtractCells()
        extract.SetInputData(grid)
        extract.SetCellList(ids)
        extract.Update()
        write(extract.GetOutput(), f"piece{piece}.vtu")
    with open(os.path.join(work_dir, "mesh.pvtu"), "w") as out:
        out.write("""<?xml version="1.0"?>
<VTKFile type="PUnstructuredGrid" version="0.1" byte_order="LittleEndian" header_type="UInt32">
  <PUnstructuredGrid GhostLevel="0">
    <PPointData Scalars="f">
      <PDataArray type="Float64" Name="f"/>
      <PDataArray type="Float64" Name="colour"/>
    </PPointData>
    <PCellData>
      <PDataArray type="Int64" IdType="1" Name="vtkOriginalCellIds"/>
    </PCellData>
    <PPoints>
      <PDataArray type="Float64" Name="Points" NumberOfComponents="3"/>
    </PPoints>
    <Piece Source="piece0.vtu"/>
    <Piece Source="piece1.vtu"/>
  </PUnstructuredGrid>
</VTKFile>
""")
    whole = XMLUnstructuredGridReader(FileName=[write(grid, "mesh.vtu")])
    serial = screenshot(whole, ISO, "serial_view.png", "colour")
    np.save(os.path.join(work_dir, "serial_view.npy"), serial)
    half = screenshot(XMLUnstructuredGridReader(FileName=[os.path.join(work_dir, "piece0.vtu")]),
                      ISO, "piece0_view.png", "colour")
    differing = int(np.any(half != serial, axis=1).sum())
    check(differing > 2000, f"the second piece should change more than 2000 pixels of the picture, "
                            f"got {differing}")  # (else a lost piece could go unnoticed)
    images = run_filter(whole, ISO, "colour")
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    image = vtkImageData()
    image.SetDimensions(W, H, 1)
    for key, values in images.items():
        array = numpy_to_vtk(values, deep=1)
        array.SetName(key)
        image.GetPointData().AddArray(array)
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(os.path.join(work_dir, "serial_filter.vti"))
    writer.SetDataModeToBinary()
    writer.SetInputData(image)
    writer.Write()
    print(f"reference written to {work_dir}: {int(np.isfinite(images['Depth']).sum())} surface pixels")
else:
    check(ranks == 2, f"compare: expected 2 MPI ranks, got {ranks}")
    pieces = XMLPartitionedUnstructuredGridReader(FileName=[os.path.join(work_dir, "mesh.pvtu")])
    pieces.UpdatePipeline()
    pixels = screenshot(pieces, ISO, "mpi_view.png", "colour")
    serial = np.load(os.path.join(work_dir, "serial_view.npy"))
    difference = np.abs(pixels - serial).max(axis=1)
    print(f"representation, 2 ranks: {int((difference > 0).sum())} of {W * H} pixels differ from the "
          f"serial picture (max {difference.max()} / 255)")
    check(difference.max() == 0, f"representation: expected the serial picture, got "
                                 f"{int((difference > 0).sum())} pixels differing by up to {difference.max()}")
    original = np.concatenate([
        vtk_to_numpy(servermanager.Fetch(XMLUnstructuredGridReader(
            FileName=[os.path.join(work_dir, f"piece{k}.vtu")])).GetCellData().GetArray(
            "vtkOriginalCellIds")) for k in range(2)])
    ours = run_filter(pieces, ISO, "colour")
    reader = vtkXMLImageDataReader()
    reader.SetFileName(os.path.join(work_dir, "serial_filter.vti"))
    reader.Update()
    reference = {key: vtk_to_numpy(reader.GetOutput().GetPointData().GetArray(key)) for key in ARRAYS}
    hit = ours["CellId"] >= 0
    ours["CellId"][hit] = original[ours["CellId"][hit]]
    finite = np.isfinite(reference["Depth"])
    coverage = int((finite != np.isfinite(ours["Depth"])).sum())
    both = finite & np.isfinite(ours["Depth"])
    depth = float(np.abs(ours["Depth"][both] - reference["Depth"][both]).max())
    cells = int((ours["CellId"] != reference["CellId"]).sum())
    colours = int(np.any(ours["Colors"] != reference["Colors"], axis=1).sum())
    print(f"filter, 2 ranks: of {int(finite.sum())} surface pixels, coverage differs at {coverage}, "
          f"cell ids at {cells}, colours at {colours}; depth within {depth:.1e}")
    check(coverage == 0 and cells == 0 and depth == 0.0 and colours == 0,
          f"filter: expected the serial image exactly, got coverage {coverage}, cell ids {cells}, "
          f"colours {colours}, depth {depth}")

if failures:
    sys.exit(1)
print(f"higher-order plugin test ({mode}): 0 failed")
