"""Loads the built TetDSR plugin by path in pvpython and runs its "Exact Isosurface (TetDSR)"
filter (DirectSurfaceContour): on the sphere inside one cell (Data/sphere_in_cell.vtu), where
ParaView's Contour finds nothing, against the analytic sphere; then on the expansion flow, shown
in a render view, whose screenshot it saves.

Usage: pvpython test_contour_plugin.py <path to TetDSR.so> <Data directory> <screenshot.png>
(docs/images/exact-surface-paraview.png is this test's screenshot.)
"""
import math
import os
import sys

from paraview import servermanager
from paraview.simple import (ColorBy, Contour, CreateView, GetColorTransferFunction, LoadPlugin,
                             Outline, Render, SaveScreenshot, Show,
                             XMLUnstructuredGridReader, _DisableFirstRenderCameraReset)

plugin_path, data_dir, screenshot = sys.argv[1], sys.argv[2], sys.argv[3]
LoadPlugin(plugin_path, remote=False, ns=globals())

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


# The sphere |x - c|^2 = r^2 inside cell 0 (every nodal value above 0).
reader = XMLUnstructuredGridReader(FileName=[os.path.join(data_dir, "sphere_in_cell.vtu")])
reader.UpdatePipeline()
field_data = servermanager.Fetch(reader).GetFieldData()
centre = [field_data.GetArray("SphereCentre").GetValue(k) for k in range(3)]
radius = field_data.GetArray("SphereRadius").GetValue(0)
exact_area = 4.0 * math.pi * radius ** 2

contour = Contour(Input=reader, ContourBy=["POINTS", "sphere"], Isosurfaces=[0.0])
contour.UpdatePipeline()
contour_cells = servermanager.Fetch(contour).GetNumberOfCells()
check(contour_cells == 0, f"Contour: expected 0 cells (the missing-surface case), got {contour_cells}")

exact = ExactIsosurfaceTetDSR(Input=reader)  # noqa: F821 (defined by LoadPlugin)
for name, default in (("Tolerance", 1e-3), ("AbsoluteTolerance", 0.0), ("ComputeIntegrals", 1)):
    value = exact.GetPropertyValue(name)
    check(value == default, f"default {name}: expected {default}, got {value}")
exact.ContourBy = ["POINTS", "sphere"]
exact.Isosurfaces = [0.0]
# The certified bound is conservative: the default 1e-3 takes minutes here; 2e-2 takes seconds.
exact.Tolerance = 2e-2
exact.UpdatePipeline()
surface = servermanager.Fetch(exact)
triangles = surface.GetNumberOfCells()
check(triangles > 100, f"sphere: expected more than 100 triangles, got {triangles}")
check(all(surface.GetCellType(t) == 5 for t in range(triangles)), "sphere: triangles (VTK_TRIANGLE) only")
farthest = max((abs(math.dist(surface.GetPoint(p), centre) - radius)
                for p in range(surface.GetNumberOfPoints())), default=math.inf)
check(farthest <= 1e-9 * radius, f"sphere vertices: expected within 1e-9 r of the sphere, got {farthest / radius} r")
area = surface.GetFieldData().GetArray("Area")
area_error = surface.GetFieldData().GetArray("AreaError")
check(area is not None and area.GetNumberOfTuples() == 1, "field data Area: one tuple expected")
if area is not None and area_error is not None:
    off = abs(area.GetValue(0) - exact_area)
    check(off <= area_error.GetValue(0) + 1e-6 * exact_area,
          f"area: expected 4 pi r^2 = {exact_area} within {area_error.GetValue(0)} + 1e-6 relative, "
          f"got {area.GetValue(0)}")
# What the Information panel lists: the output's field data, as the client sees it.
information = exact.FieldData
for name in ("Area", "AreaError", "Volume", "VolumeError", "IsoValues", "DistanceBound",
             "UnresolvedSubcells", "sphere Integral"):
    check(name in information.keys(), f"the Information panel should list the field array {name}")

# The expansion flow: speed = 0.25, coloured by pressure, inside the domain's outline.
flow = XMLUnstructuredGridReader(FileName=[os.path.join(data_dir, "expansion_flow.vtu")])
jet = ExactIsosurfaceTetDSR(Input=flow, ContourBy=["POINTS", "speed"], Isosurfaces=[0.25],  # noqa: F821
                           Tolerance=2e-2)
jet.UpdatePipeline()
jet_surface = servermanager.Fetch(jet)
jet_fields = jet_surface.GetFieldData()
check(jet_surface.GetNumberOfCells() > 1000,
      f"flow: expected more than 1000 triangles, got {jet_surface.GetNumberOfCells()}")
check(jet_fields.GetArray("Area") is not None and jet_fields.GetArray("Area").GetValue(0) > 0.0,
      "flow: a positive Area expected")
for name in ("NonManifoldEdges", "UnresolvedSubcells"):
    array = jet_fields.GetArray(name)
    check(array is not None and array.GetValue(0) == 0, f"flow: {name} expected 0")
check(jet_surface.GetPointData().GetArray("pressure") is not None, "flow: pressure interpolated")
print(f"sphere: {triangles} triangles, area {area.GetValue(0) if area else None} (exact {exact_area}); "
      f"flow: {jet_surface.GetNumberOfCells()} triangles, area {jet_fields.GetArray('Area').GetValue(0)}, "
      f"{jet_fields.GetArray('BoundaryEdges').GetValue(0)} boundary edges")

_DisableFirstRenderCameraReset()
view = CreateView("RenderView")
view.ViewSize = [1000, 620]
view.OrientationAxesVisibility = 0
outline = Show(Outline(Input=flow), view)
outline.DiffuseColor = outline.AmbientColor = [0.8, 0.8, 0.8]
display = Show(jet, view)
ColorBy(display, ("POINTS", "pressure"))
GetColorTransferFunction("pressure").RescaleTransferFunction(
    *jet_surface.GetPointData().GetArray("pressure").GetRange())
display.SetScalarBarVisibility(view, True)
display.Specular = 0.3
view.CameraPosition = [0.3, -5.2, 4.6]
view.CameraFocalPoint = [4.6, 0.0, -0.4]
view.CameraViewUp = [0.25, 0.55, 0.8]
view.CameraViewAngle = 30
Render(view)
os.makedirs(os.path.dirname(os.path.abspath(screenshot)), exist_ok=True)
SaveScreenshot(screenshot, view, ImageResolution=[1000, 620])
check(os.path.getsize(screenshot) > 10000, f"the screenshot {screenshot} should not be empty")

if failures:
    print(f"{len(failures)} check(s) failed")
    sys.exit(1)
print("all checks passed")
