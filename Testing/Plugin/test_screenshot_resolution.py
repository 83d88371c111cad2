"""The "Direct Surface" representation in ParaView screenshots larger than the view (issue 39):
SaveScreenshot with an ImageResolution of 3 times the view's, of 2.5 times, and of another aspect
ratio, against the exact sphere and against a fine polygonal sphere (Sphere source, 400 x 400
facets) saved the same way.

Usage: pvpython test_screenshot_resolution.py <path to TetDSR.so> <Data directory> <output directory>

The mesh is Data/sphere_in_cell.vtu: the field |x - c|^2 - r^2 is held exactly by the quadratic
cells, so the isosurface 0 is the sphere (c, r). Both spheres are unlit red (Ambient 1, Diffuse 0)
on black, so a pixel is covered when it is red. Truth: the perspective ray through each pixel
centre of the screenshot (the view's camera, its vertical view angle over the screenshot's
height) hits the sphere. Pixels within one pixel of the true silhouette are not compared.
"""
import math
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.simple import (CreateView, Hide, LoadPlugin, Render, SaveScreenshot, Show, Sphere,
                             XMLUnstructuredGridReader)
from vtkmodules.vtkIOImage import vtkPNGReader

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pixel_rays import camera_frame, dot, sub, unit  # noqa: E402

plugin_path, data_dir, out_dir = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(out_dir, exist_ok=True)
LoadPlugin(plugin_path, remote=False, ns=globals())
simple._DisableFirstRenderCameraReset()

W, H = 160, 120
VIEW_ANGLE = 20.0
failures = []

reader = XMLUnstructuredGridReader(FileName=[data_dir + "/sphere_in_cell.vtu"])
reader.UpdatePipeline()
field_data = servermanager.Fetch(reader).GetFieldData()
centre = [field_data.GetArray("SphereCentre").GetValue(k) for k in range(3)]
radius = field_data.GetArray("SphereRadius").GetValue(0)
position = [centre[0] + 0.5, centre[1] + 0.4, centre[2] + 1.4]

view = CreateView("RenderView")
view.ViewSize = [W, H]
view.OrientationAxesVisibility = 0
view.UseFXAA = 0
view.UseColorPaletteForBackground = 0
view.Background = [0.0, 0.0, 0.0]
view.CameraPosition = position
view.CameraFocalPoint = centre
view.CameraViewUp = [0.0, 1.0, 0.0]
view.CameraViewAngle = VIEW_ANGLE


def unlit_red(display):
    display.ColorArrayName = ["POINTS", ""]
    display.AmbientColor = [1.0, 0.0, 0.0]
    display.DiffuseColor = [1.0, 0.0, 0.0]
    display.Ambient = 1.0
    display.Diffuse = 0.0
    display.Specular = 0.0


exact = Show(reader, view)
exact.SetRepresentationType("Direct Surface")
exact.ContourBy = ["POINTS", "sphere"]
exact.Isosurfaces = [0.0]
unlit_red(exact)
polygons = Sphere(Center=centre, Radius=radius, ThetaResolution=400, PhiResolution=400)
polygon_display = Show(polygons, view)
unlit_red(polygon_display)
Hide(polygons, view)
Render(view)


def truth(width, height):
    """Per pixel of a width x height screenshot, whether its centre's ray hits the sphere."""
    forward, right, up, half = camera_frame(centre, position, VIEW_ANGLE)
    oc = sub(position, centre)
    covered = {}
    for j in range(height):
        for i in range(width):
            x = (2 * (i + 0.5) / width - 1) * half * width / height
            y = (2 * (j + 0.5) / height - 1) * half
            d = unit([forward[k] + x * right[k] + y * up[k] for k in range(3)])
            b = dot(d, oc)
            covered[i, j] = b * b - (dot(oc, oc) - radius * radius) >= 0 and b < 0
    return covered


def screenshot(name, resolution):
    path = os.path.join(out_dir, name)
    SaveScreenshot(path, view, ImageResolution=list(resolution))
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    image = png.GetOutput()
    size = image.GetDimensions()[:2]
    scalars = image.GetPointData().GetScalars()
    red = {(i, j): scalars.GetComponent(i + j * size[0], 0) > 128
           for j in range(size[1]) for i in range(size[0])}
    return size, red


def wrong_pixels(expected, picture):
    """Pixels that differ from the truth, away from its silhouette (3 x 3)."""
    wrong = 0
    for (i, j), value in expected.items():
        neighbours = [expected.get((i + di, j + dj), value) for di in (-1, 0, 1) for dj in (-1, 0, 1)]
        if all(n == value for n in neighbours) and picture[i, j] != value:
            wrong += 1
    return wrong


print("%-24s %8s %8s %14s %14s" % ("screenshot", "size", "pixels", "mapper wrong", "polygons wrong"))
for label, resolution in (("the view's size", (W, H)), ("3 x the view", (3 * W, 3 * H)),
                          ("2.5 x the view", (400, 300)), ("wider: 500 x 240", (500, 240))):
    tag = "%dx%d" % resolution
    Show(reader, view)
    Hide(polygons, view)
    size_mapper, mine = screenshot("direct_surface_%s.png" % tag, resolution)
    Hide(reader, view)
    Show(polygons, view)
    size_polygons, theirs = screenshot("polygons_%s.png" % tag, resolution)
    Hide(polygons, view)
    if tuple(size_mapper) != tuple(resolution) or tuple(size_polygons) != tuple(resolution):
        failures.append("%s: expected %s images, got %s and %s"
                        % (label, resolution, size_mapper, size_polygons))
        continue
    expected = truth(*resolution)
    covered = sum(expected.values())
    mapper_wrong, polygons_wrong = wrong_pixels(expected, mine), wrong_pixels(expected, theirs)
    print("%-24s %8s %8d %14d %14d" % (label, tag, covered, mapper_wrong, polygons_wrong))
    if covered < 0.05 * resolution[0] * resolution[1]:
        failures.append("%s: expected the sphere to cover 5%% of the image, got %d pixels"
                        % (label, covered))
    if polygons_wrong:
        failures.append("%s: the polygon reference differs from the exact sphere at %d pixels"
                        % (label, polygons_wrong))
    if mapper_wrong:
        failures.append("%s: expected the exact sphere's pixels, got %d wrong" % (label, mapper_wrong))

for failure in failures:
    print("FAILED:", failure)
if failures:
    sys.exit(1)
print("screenshot resolution test: 0 failed")
