"""Loads the built TetDSR plugin by path in pvpython or pvbatch and runs the
"Direct Surface Ray Cast" filter with non-default properties, its interactive clip plane, and
its display defaults.

Usage: pvpython test_plugin.py <path to TetDSR.so> <Data directory>
Expected coverage comes from the analytic sphere (ray/sphere intersection), not the filter.
"""
import math
import os
import sys

from paraview import servermanager
from paraview.simple import Calculator, CreateView, LoadPlugin, Show, XMLUnstructuredGridReader

plugin_path, data_dir = sys.argv[1], sys.argv[2]
LoadPlugin(plugin_path, remote=False, ns=globals())

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


reader = XMLUnstructuredGridReader(FileName=[data_dir + "/sphere_in_cell.vtu"])
reader.UpdatePipeline()
field_data = servermanager.Fetch(reader).GetFieldData()
centre = [field_data.GetArray("SphereCentre").GetValue(k) for k in range(3)]
radius = field_data.GetArray("SphereRadius").GetValue(0)

dsr = DirectSurfaceRayCast(Input=reader)  # noqa: F821 (defined by LoadPlugin)
check(list(dsr.ImageSize) == [512, 512], f"default ImageSize: expected [512, 512], got {list(dsr.ImageSize)}")
check(dsr.FitCameraToMesh == 1, "FitCameraToMesh should default to on")

width, height = 120, 90
position = [centre[0] + 0.5, centre[1] + 0.4, centre[2] + 1.4]
dsr.ContourBy = ["POINTS", "sphere"]
dsr.Isosurfaces = [0.0]
dsr.ImageSize = [width, height]
dsr.FitCameraToMesh = 0
dsr.CameraPosition = position
dsr.CameraFocalPoint = centre
dsr.CameraViewUp = [0.0, 1.0, 0.0]
dsr.CameraViewAngle = 20.0
dsr.SurfaceColor = [1.0, 0.0, 0.0]
dsr.Ambient = 0.2
dsr.Specular = 0.3
dsr.NumberOfThreads = 2
dsr.UpdatePipeline()
image = servermanager.Fetch(dsr)

check(image.GetDimensions() == (width, height, 1), f"dimensions: got {image.GetDimensions()}")
colors = image.GetPointData().GetArray("Colors")
depth = image.GetPointData().GetArray("Depth")
check(colors is not None and depth is not None, "Colors and Depth arrays expected")

# Independent truth: perspective rays through pixel centres (the filter's documented convention).
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pixel_rays import camera_frame, cross, dot, sub, unit  # noqa: E402,F401

forward, right, up, half = camera_frame(centre, position, 20.0)
oc = sub(position, centre)


def pixel_rays():
    """(pixel id, unit direction, b = d.(position - centre)) of every pixel's ray."""
    for j in range(height):
        for i in range(width):
            x = (2 * (i + 0.5) / width - 1) * half * width / height
            y = (2 * (j + 0.5) / height - 1) * half
            d = unit([forward[k] + x * right[k] + y * up[k] for k in range(3)])
            yield i + j * width, d, dot(d, oc)


mismatches = covered = reddish = 0
for pixel, d, b in pixel_rays():
    closest = math.sqrt(max(dot(oc, oc) - b * b, 0.0))
    if abs(closest - radius) < 1e-6 * radius:
        continue  # grazing ray: not compared
    truth = closest < radius
    ours = math.isfinite(depth.GetValue(pixel))
    mismatches += truth != ours
    if ours:
        covered += 1
        r, g, bl, a = (colors.GetComponent(pixel, k) for k in range(4))
        # Red surface, white highlights: G == B (specular only), R above them by the
        # ambient + diffuse part (>= 0.2 * 255).
        reddish += g == bl and r - g >= 50 and a == 255

check(mismatches == 0, f"coverage differs from the analytic sphere at {mismatches} pixels")
check(covered > 1000, f"expected more than 1000 covered pixels, got {covered}")
check(reddish == covered, f"{covered - reddish} covered pixels do not show the red surface colour")

print(f"plugin test: {covered} pixels on the sphere, {mismatches} coverage mismatches")

# Colour by a second array, a clipping plane and a translucent surface, set as properties. The
# second array is x, which the quadratic shape functions reproduce exactly; the plane keeps
# x >= centre x; with opacity 0.5, a grey colour map over [lo, hi] and flat shading, the pixel's
# alpha and colour follow from the sphere's crossings in the kept half-space.
xcoord = Calculator(Input=reader, ResultArrayName="xcoord", Function="coordsX")
lo, hi = centre[0] - radius, centre[0] + radius
dsr.Input = xcoord
dsr.ColorByArray = 1
dsr.ColorArray = ["POINTS", "xcoord"]
dsr.ColorMap = 2  # grayscale
dsr.ColorRange = [lo, hi]
dsr.IsoValueOpacities = [0.5]
dsr.ClipPlanes = centre + [1.0, 0.0, 0.0]
dsr.Ambient = 1.0
dsr.Diffuse = 0.0
dsr.Specular = 0.0
dsr.UpdatePipeline()
image = servermanager.Fetch(dsr)
colors = image.GetPointData().GetArray("Colors")
values = image.GetPointData().GetArray("ColorValues")
check(values is not None, "ColorValues array expected when colouring by an array")
worst_alpha = worst_grey = worst_value = 0.0
layers_seen = set()
compared = 0
for pixel, d, b in pixel_rays():
    disc = b * b - (dot(oc, oc) - radius * radius)
    if abs(disc) < 1e-6 * radius * radius:
        continue  # grazing ray: not compared
    roots = [-b - math.sqrt(disc), -b + math.sqrt(disc)] if disc > 0 else []
    xs = [position[0] + t * d[0] for t in roots]
    kept = [xv for xv in xs if xv >= centre[0]]
    if any(abs(xv - centre[0]) < 1e-6 for xv in xs):
        continue  # a crossing on the plane itself: not compared
    alpha = colors.GetComponent(pixel, 3) / 255
    expected_alpha = 1 - 0.5 ** len(kept)
    worst_alpha = max(worst_alpha, abs(alpha - expected_alpha))
    layers_seen.add(len(kept))
    compared += 1
    if kept:
        greys = [(xv - lo) / (hi - lo) for xv in kept]
        weights = [0.5 * 0.5 ** n for n in range(len(kept))]
        grey = sum(w * g for w, g in zip(weights, greys)) / sum(weights)
        worst_grey = max(worst_grey, abs(colors.GetComponent(pixel, 0) / 255 - grey))
        worst_value = max(worst_value, abs(values.GetValue(pixel) - kept[0]))
check(layers_seen == {0, 1, 2}, f"expected pixels with 0, 1 and 2 kept crossings, got {layers_seen}")
check(worst_alpha <= 1 / 255, f"alpha: expected 1 - 0.5^crossings, off by up to {worst_alpha}")
check(worst_grey <= 1.5 / 255, f"grey: expected the composited colour map, off by up to {worst_grey}")
check(worst_value < 1e-9, f"ColorValues: expected x at the nearest kept crossing, off by {worst_value}")
print(f"colour by array + clip plane + opacity 0.5: {compared} pixels, alpha within {worst_alpha:.4f}, "
      f"grey within {worst_grey:.4f}, colour value within {worst_value:.2e}")

# The interactive clip plane (the plane widget's proxy) cuts as the same plane in the list.
plane = dsr.InteractiveClipPlane
check(list(plane.Origin) == [0.0, 0.0, 0.0],
      f"interactive clip plane origin: expected the centre of the mesh's bounds (0, 0, 0), got "
      f"{list(plane.Origin)}")
listed = servermanager.Fetch(dsr).GetPointData().GetArray("Colors")
dsr.ClipPlanes = []
dsr.ClipWithPlane = 1
plane.Origin = centre
plane.Normal = [1.0, 0.0, 0.0]
dsr.UpdatePipeline()
interactive = servermanager.Fetch(dsr).GetPointData().GetArray("Colors")
differing = sum(1 for p in range(width * height)
                if interactive.GetTuple4(p) != listed.GetTuple4(p))
check(differing == 0, f"interactive clip plane: expected the listed plane's image, got {differing} "
                      f"pixels differing")
dsr.ClipWithPlane = 0
dsr.UpdatePipeline()
unclipped = servermanager.Fetch(dsr).GetPointData().GetArray("Colors")
opened = sum(1 for p in range(width * height) if unclipped.GetTuple4(p) != listed.GetTuple4(p))
check(opened > 1000, f"turning the clip plane off should change more than 1000 pixels, got {opened}")

# A piece of the image (as a streaming or parallel consumer asks for one) is that block of the
# whole image.
whole = servermanager.Fetch(dsr)
algorithm = dsr.GetClientSideObject()
algorithm.UpdatePiece(1, 3, 0)
block = algorithm.GetOutput()
e = block.GetExtent()
check(e[0] <= e[1] and e[2] <= e[3] and (e[1] - e[0] + 1) * (e[3] - e[2] + 1) < width * height,
      f"piece 1 of 3: expected a block of the image, got extent {e}")
mismatched = sum(1 for j in range(e[2], e[3] + 1) for i in range(e[0], e[1] + 1)
                 if block.GetPointData().GetArray("Colors").GetTuple4(
                     (i - e[0]) + (j - e[2]) * (e[1] - e[0] + 1))
                 != whole.GetPointData().GetArray("Colors").GetTuple4(i + j * width))
check(mismatched == 0, f"piece 1 of 3: expected the whole image's pixels, got {mismatched} differing")
algorithm.UpdatePiece(0, 1, 0)

# In ParaView: the progress bar names the filter, and its picture shows in its own colours.
text = dsr.GetClientSideObject().GetProgressText()
check(text == "Direct Surface Ray Cast", f"progress text: expected 'Direct Surface Ray Cast', got {text!r}")
view = CreateView("RenderView")
display = Show(dsr, view)
check(display.MapScalars == 0, f"MapScalars of the output's display: expected 0, got {display.MapScalars}")
check(list(display.ColorArrayName) == ["POINTS", "Colors"],
      f"the output's display: expected coloured by Colors, got {list(display.ColorArrayName)}")
other = Show(reader, view)
check(other.MapScalars == 1, f"MapScalars of another dataset's display: expected 1 (ParaView's "
                             f"default), got {other.MapScalars}")

if failures:
    sys.exit(1)
print("1 passed, 0 failed")
