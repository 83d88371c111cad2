"""The "Direct Surface" representation in a ParaView render view (pvpython or pvbatch), against
analytic truth.

Usage: pvpython test_representation.py <path to TetDSR.so> <Data directory> <output directory>

The mesh is Data/sphere_in_cell.vtu: the field |x - c|^2 - r^2 is held exactly by the quadratic
cells, so the isosurface 0 is the sphere (c, r) and a ray's first hit is the smaller root of a
quadratic. The surface is coloured by x (a Calculator array, reproduced exactly by the shape
functions) through a black-to-white lookup table with unlit shading (Ambient 1, Diffuse 0), so
every covered pixel's grey level is known: (x_hit - lo) / (hi - lo). An unlit red box that cuts
into the sphere shares the view; per pixel, whichever is nearer along the ray must show. Pixels
next to an edge of the truth (a silhouette or a box edge: the truth differs within one pixel)
are not compared. The screenshots are kept in the output directory.
"""
import math
import os
import sys

import paraview.simple as simple
from paraview import servermanager
from paraview.simple import (Box, Calculator, ColorBy, CreateView, GetColorTransferFunction,
                             GroupDatasets, LoadPlugin, Render, SaveScreenshot, Show,
                             XMLUnstructuredGridReader)
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkIOImage import vtkPNGReader

import tetdsr  # noqa: F401 (the mapper's Python class, for its own methods)

plugin_path, data_dir, out_dir = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(out_dir, exist_ok=True)
LoadPlugin(plugin_path, remote=False, ns=globals())
simple._DisableFirstRenderCameraReset()

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


W, H = 160, 120
BACKGROUND = (0, 0, 255)  # pure blue: never a grey level nor the box's red

reader = XMLUnstructuredGridReader(FileName=[data_dir + "/sphere_in_cell.vtu"])
reader.UpdatePipeline()
field_data = servermanager.Fetch(reader).GetFieldData()
centre = [field_data.GetArray("SphereCentre").GetValue(k) for k in range(3)]
radius = field_data.GetArray("SphereRadius").GetValue(0)
xcoord = Calculator(Input=reader, ResultArrayName="xcoord", Function="coordsX")

view = CreateView("RenderView")
view.ViewSize = [W, H]
view.OrientationAxesVisibility = 0
view.UseFXAA = 0  # anti-aliasing would blur the steep grey ramp at the sphere's limb
view.UseColorPaletteForBackground = 0
view.Background = [c / 255 for c in BACKGROUND]
position = [centre[0] + 0.5, centre[1] + 0.4, centre[2] + 1.4]
view.CameraPosition = position
view.CameraFocalPoint = centre
view.CameraViewUp = [0.0, 1.0, 0.0]
view.CameraViewAngle = 20.0

# --- The representation and its properties ----------------------------------------------------
display = Show(xcoord, view)
types = display.GetProperty("Representation").Available
check("Direct Surface" in types, f"representation types: expected 'Direct Surface' among {types}")
display.SetRepresentationType("Direct Surface")
check(display.Representation == "Direct Surface",
      f"Representation: expected 'Direct Surface', got {display.Representation!r}")
domain = display.GetProperty("ContourBy").SMProperty.FindDomain("vtkSMArrayListDomain")
arrays = [domain.GetString(k) for k in range(domain.GetNumberOfStrings())]
check("sphere" in arrays and "xcoord" in arrays,
      f"ContourBy choices: expected the point arrays 'sphere' and 'xcoord', got {arrays}")
display.ContourBy = ["POINTS", "sphere"]
display.Isosurfaces = [0.0]
lo, hi = centre[0] - radius, centre[0] + radius


def color_by_x(display):
    """Color By xcoord through a black-to-white table over [lo, hi], unlit."""
    ColorBy(display, ("POINTS", "xcoord"))
    lut = GetColorTransferFunction("xcoord")
    lut.AutomaticRescaleRangeMode = "Never"
    lut.ColorSpace = "RGB"
    lut.Discretize = 0
    lut.RGBPoints = [lo, 0.0, 0.0, 0.0, hi, 1.0, 1.0, 1.0]
    display.Ambient = 1.0
    display.Diffuse = 0.0
    display.Specular = 0.0


color_by_x(display)

# The properties reached the mapper (pvpython and pvbatch render in this process): the view's
# renderer holds the representation's actor.
Render(view)
actors = view.GetRenderer().GetActors()
mappers = [actors.GetItemAsObject(k).GetMapper() for k in range(actors.GetNumberOfItems())]
mappers = [m for m in mappers if m is not None and m.IsA("vtkDirectSurfaceMapper")]
check(len(mappers) == 1, f"actors with a vtkDirectSurfaceMapper: expected 1, got {len(mappers)}")
mapper = mappers[0]
check(mapper.GetNumberOfContours() == 1 and mapper.GetValue(0) == 0.0,
      f"mapper iso-values: expected [0.0], got "
      f"{[mapper.GetValue(i) for i in range(mapper.GetNumberOfContours())]}")
check(mapper.GetInputArrayInformation(0).Get(vtkDataObject.FIELD_NAME()) == "sphere",
      "mapper field: expected 'sphere'")
check(mapper.GetScalarVisibility() == 1 and mapper.GetArrayName() == "xcoord",
      f"mapper colouring: expected ScalarVisibility 1 and array 'xcoord', got "
      f"{mapper.GetScalarVisibility()} and {mapper.GetArrayName()!r}")
check(mapper.GetLookupTable() is not None and mapper.GetLookupTable().GetRange() == (lo, hi),
      f"mapper lookup table: expected ParaView's xcoord table over ({lo}, {hi})")
check(mapper.GetNumberOfRenderedCells() == 6,
      f"rendered cells: expected 6, got {mapper.GetNumberOfRenderedCells()}")


# --- Truth -----------------------------------------------------------------------------------
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pixel_rays import camera_frame, cross, dot, sub, unit  # noqa: E402,F401

forward, right, up, half = camera_frame(centre, position, 20.0)


def ray(i, j):
    """The unit direction of pixel (i, j)'s ray (j = 0 the bottom row)."""
    x = (2 * (i + 0.5) / W - 1) * half * W / H
    y = (2 * (j + 0.5) / H - 1) * half
    return unit([forward[k] + x * right[k] + y * up[k] for k in range(3)])


def sphere_hits(d):
    """Both t > 0 with |position + t d - centre| = radius, nearest first (none on a miss)."""
    oc = sub(position, centre)
    b = dot(d, oc)
    disc = b * b - (dot(oc, oc) - radius * radius)
    return [-b - math.sqrt(disc), -b + math.sqrt(disc)] if disc > 0 else []


def box_hit(d, box_lo, box_hi):
    """The entry t of the ray into the axis-aligned box (slab method), or None."""
    t0, t1 = 0.0, math.inf
    for k in range(3):
        if d[k] == 0.0:
            if not box_lo[k] <= position[k] <= box_hi[k]:
                return None
            continue
        a, b = (box_lo[k] - position[k]) / d[k], (box_hi[k] - position[k]) / d[k]
        t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
    return t0 if t0 <= t1 else None


def truth_image(box=None, opacity=1.0):
    """Per pixel: (kind, expected RGB) with kind 'sphere', 'box' or 'background'. Translucent,
    both crossings of the sphere are composited front to back over the background."""
    image = {}
    for j in range(H):
        for i in range(W):
            d = ray(i, j)
            t_sphere = sphere_hits(d)
            t_box = box_hit(d, *box) if box else None
            if t_box is not None and (not t_sphere or t_box < t_sphere[0]):
                image[i, j] = ("box", (255, 0, 0))
            elif t_sphere:
                greys = [255 * (position[0] + t * d[0] - lo) / (hi - lo) for t in t_sphere]
                if opacity == 1.0:
                    greys = greys[:1]
                weights = [opacity * (1 - opacity) ** n for n in range(len(greys))]
                rest = 1 - sum(weights)
                rgb = [sum(w * g for w, g in zip(weights, greys)) + rest * c for c in BACKGROUND]
                image[i, j] = ("sphere", tuple(rgb))
            else:
                image[i, j] = ("background", BACKGROUND)
    return image


def screenshot(name):
    path = os.path.join(out_dir, name)
    SaveScreenshot(path, view, ImageResolution=[W, H])
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    pixels = png.GetOutput().GetPointData().GetScalars()
    return lambda i, j: tuple(pixels.GetComponent(i + j * W, c) for c in range(3))


def compare(truth, picture, label, tolerance):
    """Counts pixels of the wrong kind and the worst colour error, away from truth edges."""
    compared = wrong = 0
    worst = 0.0
    counts = {"sphere": 0, "box": 0, "background": 0}
    for (i, j), (kind, rgb) in truth.items():
        neighbours = [truth.get((i + di, j + dj), truth[i, j])[0]
                      for di in (-1, 0, 1) for dj in (-1, 0, 1)]
        if any(n != kind for n in neighbours):
            continue  # within a pixel of an edge of the truth
        compared += 1
        counts[kind] += 1
        error = max(abs(a - b) for a, b in zip(picture(i, j), rgb))
        worst = max(worst, error) if kind == "sphere" else worst
        if error > (tolerance if kind == "sphere" else 0):
            wrong += 1
            if wrong <= 3:
                print(f"  pixel ({i}, {j}): expected {kind} {tuple(round(c, 1) for c in rgb)}, "
                      f"got {picture(i, j)}")
    check(wrong == 0, f"{label}: expected every pixel as the truth (colour within {tolerance} "
                      f"on the sphere), got {wrong} of {compared} wrong")
    print(f"{label}: {compared} pixels compared ({counts}), worst grey error {worst:.2f} / 255")
    return counts


# The linear table is sampled exactly; colours are rounded to bytes by the mapper and, when
# translucent, once more by the frame buffer's blend: 1 / 255 covers both roundings.
GREY_TOLERANCE = 1.0
truth = truth_image()
counts = compare(truth, screenshot("direct_surface.png"), "sphere alone", GREY_TOLERANCE)
check(counts["sphere"] > 1500, f"covered pixels: expected more than 1500, got {counts['sphere']}")

# --- An opaque box in the same view, cutting into the sphere ---------------------------------
box_centre = [centre[0] + 0.15, centre[1] + 0.1, centre[2] - 0.05]
box_size = 0.25
box = Box(XLength=box_size, YLength=box_size, ZLength=box_size, Center=box_centre)
box_display = Show(box, view)
box_display.AmbientColor = [1.0, 0.0, 0.0]
box_display.DiffuseColor = [1.0, 0.0, 0.0]
box_display.Ambient = 1.0
box_display.Diffuse = 0.0
box_display.ColorArrayName = ["POINTS", ""]
box_bounds = ([c - box_size / 2 for c in box_centre], [c + box_size / 2 for c in box_centre])
truth_box = truth_image(box=box_bounds)
counts = compare(truth_box, screenshot("direct_surface_box.png"), "sphere and box", GREY_TOLERANCE)
hidden = sum(1 for p, (kind, _) in truth_box.items() if kind == "sphere" and truth[p][0] == "sphere")
in_front = sum(1 for p, (kind, _) in truth_box.items() if kind == "box" and truth[p][0] == "sphere")
behind = sum(1 for p, (kind, _) in truth_box.items()
             if kind == "sphere" and box_hit(ray(*p), *box_bounds) is not None)
check(in_front > 200 and behind > 200,
      f"the box should hide part of the sphere and be hidden by it: expected more than 200 pixels "
      f"each, got {in_front} box pixels over the sphere and {behind} sphere pixels over the box")
print(f"box in front of the sphere at {in_front} pixels, sphere in front of the box at {behind}")

# --- Selection: Select Cells / Points On sees the surface, and the box in front of it -----------
def selected(select, rectangle, ids):
    """The ids (vtkOriginalCellIds or vtkOriginalPointIds) of the sphere's mesh that ParaView's
    selection of `rectangle` extracts."""
    select(Rectangle=rectangle, View=view, Modifier=None)
    extract = simple.ExtractSelection(Input=xcoord)
    data = servermanager.Fetch(extract)
    array = data.GetCellData().GetArray(ids) or data.GetPointData().GetArray(ids)
    found = {array.GetValue(k) for k in range(array.GetNumberOfTuples())} if array else set()
    simple.Delete(extract)
    simple.ClearSelection(xcoord)
    return found


def block_of(kind_now, kind_without_box):
    """A 5 x 5 block of pixels (x0, y0, x1, y1) that all show `kind_now` with the box and
    `kind_without_box` without it."""
    for j in range(2, H - 7):
        for i in range(2, W - 7):
            if all(truth_box[i + a, j + b][0] == kind_now and truth[i + a, j + b][0] == kind_without_box
                   for a in range(5) for b in range(5)):
                return [i, j, i + 4, j + 4]
    return None


shown, hidden_by_box = block_of("sphere", "sphere"), block_of("box", "sphere")
check(shown is not None and hidden_by_box is not None, "expected blocks where the sphere shows and "
      "where the box hides it")
# The sphere lies inside cell 0 (Data/sphere_in_cell.vtu): its cell where it shows, nothing of the
# mesh where the box hides it; its points are nodes of cell 0.
cells = selected(simple.SelectSurfaceCells, shown, "vtkOriginalCellIds")
check(cells == {0}, f"Select Cells On where the sphere shows: expected cell 0, got {sorted(cells)}")
cells = selected(simple.SelectSurfaceCells, hidden_by_box, "vtkOriginalCellIds")
check(cells == set(), f"Select Cells On where the box hides the sphere: expected none of the mesh, "
                      f"got {sorted(cells)}")
nodes = servermanager.Fetch(xcoord).GetCell(0).GetPointIds()
cell0 = {nodes.GetId(k) for k in range(nodes.GetNumberOfIds())}
points = selected(simple.SelectSurfacePoints, [0, 0, W - 1, H - 1], "vtkOriginalPointIds")
check(points and points <= cell0, f"Select Points On: expected nodes of cell 0, got {sorted(points)}")
print(f"selection: cell 0 where the sphere shows {shown}, nothing where the box hides it "
      f"{hidden_by_box}; {len(points)} nodes of cell 0 over the whole view")
simple.Hide(box, view)

# --- Opacity from the display properties -----------------------------------------------------
display.Opacity = 0.5
compare(truth_image(opacity=0.5), screenshot("direct_surface_opacity.png"), "opacity 0.5",
        GREY_TOLERANCE)
display.Opacity = 1.0

# --- A multiblock of the grid gets the same representation and the same picture --------------
group = GroupDatasets(Input=[xcoord])
simple.Hide(xcoord, view)
group_display = Show(group, view)
check("Direct Surface" in group_display.GetProperty("Representation").Available,
      "a multiblock of unstructured grids should offer 'Direct Surface'")
group_display.SetRepresentationType("Direct Surface")
group_display.ContourBy = ["POINTS", "sphere"]
group_display.Isosurfaces = [0.0]
color_by_x(group_display)
compare(truth, screenshot("direct_surface_multiblock.png"), "multiblock", GREY_TOLERANCE)

if failures:
    sys.exit(1)
print("representation test: 0 failed")
