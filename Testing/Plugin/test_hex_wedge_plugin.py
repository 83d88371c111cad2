"""The plugin's Direct Surface Ray Cast filter in pvpython on hexahedra and wedges, read from .vtu
files (Testing/Python/hex_wedge_grids.py builds them on VTK's own node positions), against the
analytic first crossing per pixel: straight VTK_QUADRATIC_HEXAHEDRON cells holding a degree-4
polynomial of their space (coloured by a second one), and curved VTK_QUADRATIC_WEDGE cells
holding a plane (coloured by a linear field).

Usage: pvpython test_hex_wedge_plugin.py <TetDSR.so> <work directory>
"""
import os
import sys

import numpy as np
import paraview.simple as simple
from paraview import servermanager
from paraview.simple import LoadPlugin, XMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import VTK_QUADRATIC_HEXAHEDRON, VTK_QUADRATIC_WEDGE
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
import hex_wedge_grids as hw  # noqa: E402
import higher_order_grids as hog  # noqa: E402
from test_hex_wedge import PLANE, SPACES, linear_colour  # noqa: E402

plugin_path, work_dir = sys.argv[1:3]
os.makedirs(work_dir, exist_ok=True)
LoadPlugin(plugin_path, remote=False, ns=globals())
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


W, H = 200, 150
CAMERA = dict(CameraPosition=[1.7, 1.35, 2.5], CameraFocalPoint=[0.5, 0.5, 0.5],
              CameraViewUp=[0.0, 1.0, 0.0], CameraViewAngle=24.0)


def write(grid, name):
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(os.path.join(work_dir, name))
    writer.SetDataModeToBinary()  # inline: this Debian's expat cannot read appended data
    writer.SetInputData(grid)
    writer.Write()
    return os.path.join(work_dir, name)


rays = hog.pixel_rays(CAMERA["CameraPosition"], CAMERA["CameraFocalPoint"], CAMERA["CameraViewUp"],
                      CAMERA["CameraViewAngle"], W, H)
cases = (("VTK_QUADRATIC_HEXAHEDRON straight", VTK_QUADRATIC_HEXAHEDRON, 20, SPACES["serendipity"], None),
         ("VTK_QUADRATIC_WEDGE curved", VTK_QUADRATIC_WEDGE, 15, (PLANE, linear_colour), hw.bulge()))
for name, vtk_type, nodes, (field, colour), warp in cases:
    grid = hw.grid(2, vtk_type, nodes, {"f": field.value, "colour": colour}, warp=warp)
    reader = XMLUnstructuredGridReader(FileName=[write(grid, f"{vtk_type}.vtu")])
    caster = DirectSurfaceRayCast(Input=reader, ContourBy=["POINTS", "f"], Isosurfaces=[field.iso])  # noqa: F821
    caster.ImageSize = [W, H]
    caster.FitCameraToMesh = 0
    for key, value in CAMERA.items():
        setattr(caster, key, value)
    caster.ColorByArray = 1
    caster.ColorArray = ["POINTS", "colour"]
    caster.UpdatePipeline()
    image = servermanager.Fetch(caster)
    out = {key: vtk_to_numpy(image.GetPointData().GetArray(key)) for key in ("Depth", "ColorValues", "CellId")}
    t, grazing = hog.first_crossing(field, *rays)
    ours, exact = np.isfinite(out["Depth"]), np.isfinite(t)
    wrong = int(((ours != exact) & ~grazing).sum())
    both = ours & exact & ~grazing
    depth = float(np.abs(out["Depth"][both] - t[both]).max()) / np.sqrt(3.0)
    points = rays[0][both] + t[both, None] * rays[1][both]
    values = float(np.abs(out["ColorValues"][both] - colour(points)).max())
    cells = grid.GetNumberOfCells()
    ids = out["CellId"][ours]
    print(f"filter in pvpython, {name}: {int(both.sum())} pixels ({int(grazing.sum())} grazing), {wrong} differ "
          f"in coverage, depth within {depth:.2e} of the diagonal, colour values within {values:.2e}, "
          f"cell ids in [{ids.min()}, {ids.max()}] of {cells} cells")
    check(both.sum() > 5000, f"{name}: expected more than 5000 surface pixels, got {both.sum()}")
    check(wrong == 0, f"{name}: expected the analytic coverage, got {wrong} pixels differing")
    check(depth < 1e-9, f"{name}: expected depth within 1e-9 of the diagonal, got {depth:.2e}")
    check(values < 1e-9, f"{name}: expected the analytic colour values, got an error of {values:.2e}")
    check(ids.min() >= 0 and ids.max() < cells, f"{name}: expected input cell ids in [0, {cells}), got "
                                                f"[{ids.min()}, {ids.max()}]")
    simple.Delete(caster)
    simple.Delete(reader)

if failures:
    print(f"{len(failures)} failures")
    sys.exit(1)
print("all checks passed")
