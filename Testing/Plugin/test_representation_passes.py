"""The "Direct Surface" representation under ParaView's render-view passes: StereoRender with the
stereo types 'Red-Blue', 'SplitViewportHorizontal', 'Left' and 'Right' (at ParaView's default eye
angle of 2 degrees and at 8), ambient occlusion (UseAmbientOcclusion) and depth peeling (the
view's default) with a translucent sphere. In one view, the exact
sphere of Data/sphere_in_cell.vtu (the field |x - c|^2 - r^2, held exactly by its quadratic
cells) cut by a polygon plane, then a polygon sphere of the same centre and radius in its place:
the two screenshots must agree (pixels whose colour differs by more than rounding are counted;
a few may differ where the polygon sphere's facets meet a pixel centre on the silhouette). The
camera's focal point lies behind the sphere, so that the eyes' views differ there. Prints a
table of mode -> result.

Usage: pvpython test_representation_passes.py <path to TetDSR.so> <Data directory> <output dir>
"""
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.simple import (CreateView, Hide, LoadPlugin, Plane, Render, SaveScreenshot, Show,
                             Sphere, XMLUnstructuredGridReader)
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand
from vtkmodules.vtkIOImage import vtkPNGReader
import numpy as np

plugin_path, data_dir, out_dir = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(out_dir, exist_ok=True)
LoadPlugin(plugin_path, remote=False, ns=globals())
simple._DisableFirstRenderCameraReset()

W, H = 200, 150
COLOR_TOLERANCE = 3
SILHOUETTE_PIXELS = 6
failures = []
rows = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


reader = XMLUnstructuredGridReader(FileName=[data_dir + "/sphere_in_cell.vtu"])
reader.UpdatePipeline()
field_data = servermanager.Fetch(reader).GetFieldData()
centre = np.array([field_data.GetArray("SphereCentre").GetValue(k) for k in range(3)])
radius = field_data.GetArray("SphereRadius").GetValue(0)

view = CreateView("RenderView")
view.ViewSize = [W, H]
view.OrientationAxesVisibility = 0
view.UseFXAA = 0
view.UseColorPaletteForBackground = 0
view.Background = [0.0, 0.0, 0.0]
view.CameraPosition = list(centre + radius * np.array([0.6, 0.7, 4.8]))
view.CameraFocalPoint = list(centre + radius * np.array([-0.15, -0.15, -2.3]))
view.CameraViewUp = [0.0, 1.0, 0.0]
view.CameraViewAngle = 32.0
view.CameraParallelProjection = 0

exact = Show(reader, view)
exact.SetRepresentationType("Direct Surface")
exact.ContourBy = ["POINTS", "sphere"]
exact.Isosurfaces = [0.0]
polygon_source = Sphere(Center=list(centre), Radius=radius, ThetaResolution=512,
                        PhiResolution=256)
polygons = Show(polygon_source, view)
# The plane through the sphere, 37 degrees to the view (as Testing/Python/test_mapper_passes.py).
plane_source = Plane(Origin=list(centre + radius * np.array([-1.7, -1.55, -1.2])),
                     Point1=list(centre + radius * np.array([1.7, -1.55, 1.35])),
                     Point2=list(centre + radius * np.array([-1.7, 1.55, -1.2])))
plane = Show(plane_source, view)
# The mesh's outline in both pictures, so that the view's bounds (and with them ParaView's
# clipping range and its ambient occlusion's default radius) are the same in both.
outline = Show(simple.Outline(Input=reader), view)
for display, color in ((exact, [1.0, 0.5, 0.0]), (polygons, [1.0, 0.5, 0.0]),
                       (plane, [0.1, 0.3, 1.0]), (outline, [0.5, 0.5, 0.5])):
    display.ColorArrayName = ["POINTS", ""]
    display.AmbientColor = color
    display.DiffuseColor = color


def lighting(lit):
    for display in (exact, polygons, plane):
        display.Ambient = 0.3 if lit else 1.0
        display.Diffuse = 0.7 if lit else 0.0
        display.Specular = 0.0


def screenshot(name, show_exact):
    """The view with the exact sphere or the polygon one, as an (H, W, 3) array."""
    Hide(polygon_source if show_exact else reader, view)
    Show(reader if show_exact else polygon_source, view)
    Render(view)
    path = os.path.join(out_dir, name + ("-exact" if show_exact else "-polygons") + ".png")
    SaveScreenshot(path, view, ImageResolution=[W, H])
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    pixels = vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())
    return pixels.reshape(H, W, -1)[..., :3].astype(int)


def differing(a, b):
    return int((np.abs(a - b).max(axis=2) > COLOR_TOLERANCE).sum())


def compare(name, parallax_reference=None, tolerance=SILHOUETTE_PIXELS):
    """The exact sphere's screenshot against the polygon sphere's; with parallax_reference, also
    against that screenshot of the exact sphere (which a picture without parallax would equal)."""
    a, b = screenshot(name, True), screenshot(name, False)
    differ = differing(a, b)
    text = "%d pixels differ from polygons (largest channel difference %d)" % (
        differ, np.abs(a - b).max())
    if parallax_reference is not None:
        text += " (%d from the eye angle 0 picture)" % differing(a, parallax_reference)
    rows.append((name, text))
    print("%-40s %s" % (name, text), flush=True)
    check(differ <= tolerance, f"{name}: {differ} pixels differ from the polygon sphere")
    return a, b


lighting(False)
for stereo_type in ("Red-Blue", "SplitViewportHorizontal", "Left", "Right"):
    view.StereoType = stereo_type
    view.StereoRender = 1
    view.EyeAngle = 0.0
    flat = screenshot("stereo-%s-angle-0" % stereo_type, True)
    for angle in (2.0, 8.0):
        view.EyeAngle = angle
        picture, _ = compare("stereo %s, eye angle %g" % (stereo_type, angle), flat)
        check(differing(picture, flat) > 50,
              f"stereo {stereo_type} at {angle} degrees: no parallax in the picture")
view.StereoRender = 0
view.EyeAngle = 2.0
# (The first screenshot after stereo is turned off differs from the next in about 250 pixels,
# the plane's among them, with either sphere: not compared.)
screenshot("after-stereo", True)

lighting(True)
plain, _ = compare("no ambient occlusion")
view.UseAmbientOcclusion = 1
# ParaView's default occlusion is not blurred: its noise differs by a few levels here and there
# between the pictures of the two spheres (a blotch is hundreds of pixels off by tens of levels).
occluded, occluded_polygons = compare("ambient occlusion", tolerance=30)
check(np.abs(occluded - occluded_polygons).max() <= 12,
      "ambient occlusion: a pixel differs from the polygon sphere's by more than its noise")
check(differing(occluded_polygons, plain) > 100,
      "ambient occlusion changed the polygon picture too little to compare")
view.UseAmbientOcclusion = 0

# Translucency: ParaView's view peels depth by default. The translucent sphere alone against the
# translucent polygon sphere; then, with the plane translucent too, the mapper's one warning
# that it cannot interleave the two, and none with the plane opaque beside 2D text.
check(view.DepthPeeling == 1, "the render view's depth peeling is on by default")
for display in (exact, polygons):
    display.Opacity = 0.5
Hide(plane_source, view)
compare("depth peeling, translucent sphere alone")
Hide(polygon_source, view)
Show(plane_source, view)
Show(simple.Text(Text="2D text over the view"), view)
Show(reader, view)
Render(view)
actors = view.GetRenderer().GetActors()
mapper = [actors.GetItemAsObject(k).GetMapper() for k in range(actors.GetNumberOfItems())
          if actors.GetItemAsObject(k).GetMapper() is not None
          and actors.GetItemAsObject(k).GetMapper().IsA("vtkDirectSurfaceMapper")][0]
warnings = []


@calldata_type(VTK_STRING)
def on_warning(caller, event, text):
    warnings.append(text)


mapper.AddObserver(vtkCommand.WarningEvent, on_warning)
for plane_opacity in (1.0, 0.5):
    plane.Opacity = plane_opacity
    Render(view)
    Render(view)
    said = [w for w in warnings if "translucent" in w]
    rows.append(("translucent plane, opacity %g" % plane_opacity, "%d warnings" % len(said)))
    check(len(said) == (1 if plane_opacity < 1 else 0),
          f"plane opacity {plane_opacity}: expected {1 if plane_opacity < 1 else 0} warning, got {said}")
check(any("1 other translucent prop: depth peeling cannot interleave" in w for w in warnings),
      f"the warning names depth peeling and the one prop: {warnings}")

print("\nmode -> result")
for name, text in rows:
    print("  %-40s %s" % (name, text))
if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
