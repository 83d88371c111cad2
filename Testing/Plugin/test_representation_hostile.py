"""The "Direct Surface" representation given hostile inputs and property values (what
Testing/Fuzz/fuzz_representation.py and issue 21 found silent): each is refused or used with a
message naming what is wrong, and nothing that cannot be drawn is drawn without a word.

Usage: pvpython test_representation_hostile.py <path to TetDSR.so> <Data directory>

Messages are caught with observers on the representation's and the mapper's ErrorEvent and
WarningEvent (what ParaView's Output Messages window shows). Each check prints its name; a failure
prints what was expected and what came.
"""
import math
import sys

import paraview.simple as simple
from paraview.simple import (Calculator, CreateView, GroupDatasets, LoadPlugin, Render, Show,
                             Threshold, XMLUnstructuredGridReader)
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand

import tetdsr  # noqa: F401 (the mapper's Python class, for its own methods)

plugin_path, data_dir = sys.argv[1], sys.argv[2]
LoadPlugin(plugin_path, remote=False, ns=globals())
simple._DisableFirstRenderCameraReset()

failures = []


def check(name, condition, message):
    print(("ok     " if condition else "FAILED ") + name + ("" if condition else ": " + message))
    if not condition:
        failures.append(name)


reader = XMLUnstructuredGridReader(FileName=[data_dir + "/sphere_in_cell.vtu"])
view = CreateView("RenderView")
view.ViewSize = [80, 60]
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = [0.0, 0.0, 1.0]


def direct_surface_actors():
    actors = view.GetRenderer().GetActors()
    actors = [actors.GetItemAsObject(k) for k in range(actors.GetNumberOfItems())]
    return [a for a in actors if a.GetMapper() is not None and
            a.GetMapper().IsA("vtkDirectSurfaceMapper")]


class Shown:
    """A source shown as Direct Surface in the view, with its messages caught."""

    def __init__(self, source, contour_by="sphere"):
        before = set(direct_surface_actors())
        self.display = Show(source, view)
        self.display.SetRepresentationType("Direct Surface")
        self.display.ContourBy = ["POINTS", contour_by]
        self.display.Isosurfaces = [0.0]
        self.display.ColorArrayName = ["POINTS", ""]
        # The composite representation's active one is vtkDirectSurfaceRepresentation.
        self.representation = self.display.GetClientSideObject().GetActiveRepresentation()
        self.messages = []
        # (the representation's class is not wrapped for Python: its actor is the new one)
        self.actor = [a for a in direct_surface_actors() if a not in before][0]
        self.mapper = self.actor.GetMapper()
        self.observe(self.representation)
        self.observe(self.mapper)
        self.source = source

    def observe(self, obj):
        def on(kind):
            @calldata_type(VTK_STRING)  # the message comes as the call data
            def callback(caller, event, text):
                self.messages.append((kind, text.strip()))
            return callback
        obj.RemoveAllObservers()
        obj.AddObserver(vtkCommand.ErrorEvent, on("error"))
        obj.AddObserver(vtkCommand.WarningEvent, on("warning"))

    def take(self):
        messages, self.messages = self.messages, []
        return messages

    def hide(self):
        simple.Hide(self.source, view)


def with_text(messages, kind, fragment):
    return [m for k, m in messages if k == kind and fragment in m]


def drawn_pixels():
    """Pixels of the last render that are not the blue background."""
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
    grab = vtkWindowToImageFilter()
    grab.SetInput(view.GetRenderWindow())
    grab.ReadFrontBufferOff()
    grab.ShouldRerenderOff()
    grab.Update()
    scalars = grab.GetOutput().GetPointData().GetScalars()
    count = 0
    for i in range(scalars.GetNumberOfTuples()):
        if scalars.GetTuple3(i) != (0.0, 0.0, 255.0):
            count += 1
    return count


# --- Valid use says nothing and draws ------------------------------------------------------
shown = Shown(reader)
Render(view)
view.ResetCamera()
Render(view)
messages = shown.take()
covered = drawn_pixels()
check("valid_use_is_quiet", messages == [] and covered > 20,
      f"expected no message and more than 20 pixels drawn, got {messages} and {covered}")
mapper = shown.mapper

# --- ClipPlanes: a count of numbers that is not whole planes -------------------------------
for count in (5, 7):
    shown.display.ClipPlanes = [0.5] * count
    Render(view)
    messages = shown.take()
    found = with_text(messages, "error", f"ClipPlanes has {count} numbers, not a multiple of 6")
    planes = mapper.GetClippingPlanes()
    used = planes.GetNumberOfItems() if planes else 0
    check(f"clip_planes_{count}_numbers_refused", len(found) == 1 and used == 0,
          f"expected one error naming ClipPlanes and {count} numbers, and 0 planes used; got "
          f"{messages} and {used} planes")
shown.display.ClipPlanes = [0.5, 0.5, 0.5, 1.0, 0.0, 0.0]
Render(view)
planes = mapper.GetClippingPlanes()
used = planes.GetNumberOfItems() if planes else 0
check("clip_planes_6_numbers_used", used == 1 and shown.take() == [],
      f"expected 1 plane and no message, got {used} planes")
shown.display.ClipPlanes = []
Render(view)

# --- IsoValueColors: not whole colours; components outside [0, 1] or NaN ------------------
for count in (2, 4):
    shown.display.IsoValueColors = [0.25] * count
    Render(view)
    messages = shown.take()
    found = with_text(messages, "error", f"IsoValueColors has {count} numbers, not a multiple of 3")
    color = [0.0, 0.0, 0.0]
    mapper.GetIsoValueColor(0, color)
    check(f"iso_value_colors_{count}_numbers_refused",
          len(found) == 1 and color != [0.25, 0.25, 0.25],
          f"expected one error naming IsoValueColors and {count} numbers, and no colour set; got "
          f"{messages} and colour {color}")
shown.display.IsoValueColors = [2.0, 0.5, -1.0]
Render(view)
messages = shown.take()
color = [0.0, 0.0, 0.0]
mapper.GetIsoValueColor(0, color)
check("iso_value_colors_outside_clamped_with_warning",
      len(with_text(messages, "warning", "IsoValueColors 2 is outside [0, 1]: 1 is used")) == 1
      and len(with_text(messages, "warning", "IsoValueColors -1 is outside [0, 1]: 0 is used")) == 1
      and color == [1.0, 0.5, 0.0],
      f"expected two warnings and colour [1, 0.5, 0], got {messages} and {color}")
shown.display.IsoValueColors = [math.nan, 0.5, 0.5]
Render(view)
messages = shown.take()
check("iso_value_colors_nan_refused",
      len(with_text(messages, "error", "IsoValueColors must be a number, got NaN")) == 1,
      f"expected an error naming IsoValueColors and NaN, got {messages}")
shown.display.IsoValueColors = []

# --- IsoValueOpacities outside [0, 1] or NaN -------------------------------------------
for given, expected in ((2.0, 1.0), (-0.5, 0.0)):
    shown.display.IsoValueOpacities = [given]
    Render(view)
    messages = shown.take()
    used = mapper.GetIsoValueOpacity(0)
    check(f"iso_value_opacity_{given:g}_clamped_with_warning",
          len(with_text(messages, "warning", f"IsoValueOpacities {given:g} is outside [0, 1]")) == 1
          and used == expected,
          f"expected a warning and opacity {expected}, got {messages} and {used}")
shown.display.IsoValueOpacities = []
shown.display.IsoValueOpacities = [math.nan]
Render(view)
messages = shown.take()
used = mapper.GetIsoValueOpacity(0)
check("iso_value_opacity_nan_refused",
      len(with_text(messages, "error", "IsoValueOpacities must be a number, got NaN")) == 1
      and used == 1.0,
      f"expected an error and the opacity unset (1), got {messages} and {used}")
shown.display.IsoValueOpacities = []

# --- Numbers of the display: NaN refused, outside the range clamped with a warning --------
actor_property = shown.actor.GetProperty()
shown.display.Opacity = math.nan
Render(view)
messages = shown.take()
check("opacity_nan_refused",
      len(with_text(messages, "error", "Opacity must be a number, got NaN")) == 1
      and actor_property.GetOpacity() == 1.0,
      f"expected an error and Opacity kept at 1, got {messages} and {actor_property.GetOpacity()}")
shown.display.Opacity = 1.0
shown.display.SpecularPower = 1000.0
Render(view)
messages = shown.take()
check("specular_power_clamped_with_warning",
      len(with_text(messages, "warning", "SpecularPower 1000 is outside [0, 128]: 128 is used")) == 1
      and actor_property.GetSpecularPower() == 128.0,
      f"expected a warning and 128, got {messages} and {actor_property.GetSpecularPower()}")
shown.display.SpecularPower = 100.0
shown.display.Position = [0.0, math.nan, 0.0]
Render(view)
messages = shown.take()
check("position_nan_refused",
      len(with_text(messages, "error", "Position must be a number, got NaN")) == 1
      and shown.actor.GetPosition() == (0.0, 0.0, 0.0),
      f"expected an error and the position kept, got {messages}")
shown.display.Position = [0.0, 0.0, 0.0]
shown.take()

# --- Contour By: an array of 3 components, a missing one, a cell array ---------------------
vector = Calculator(Input=reader, ResultArrayName="vec", Function="coords")
shown.hide()
vector_shown = Shown(vector, contour_by="vec")
Render(view)
messages = vector_shown.take()
covered = drawn_pixels()
check("contour_by_3_components_refused",
      len(with_text(messages, "error", "Array 'vec' has 3 components")) == 1 and covered == 0,
      f"expected one error naming 'vec' and its 3 components and nothing drawn, got {messages} "
      f"and {covered} pixels")
vector_shown.display.ContourBy = ["POINTS", "nope"]
Render(view)
messages = vector_shown.take()
check("contour_by_missing_refused",
      len(with_text(messages, "error", "No point array named 'nope'")) == 1,
      f"expected an error naming 'nope', got {messages}")
vector_shown.display.ContourBy = ["POINTS", "sphere"]
Render(view)
covered = drawn_pixels()
check("contour_by_fixed_draws", vector_shown.take() == [] and covered > 20,
      f"expected no message and more than 20 pixels once Contour By is 'sphere', got {covered}")
vector_shown.hide()

# --- Inputs that cannot show anything: said once per change of the input -------------------
empty = Threshold(Input=reader, Scalars=["POINTS", "sphere"], LowerThreshold=1e9,
                  UpperThreshold=2e9)
empty_shown = Shown(empty)
Render(view)
Render(view)
messages = empty_shown.take()
check("empty_grid_said_once",
      len(with_text(messages, "error", "The input mesh is empty")) == 1,
      f"expected one error 'The input mesh is empty' over two renders, got {messages}")
empty.LowerThreshold = 2e9  # a new (still empty) input: said again
Render(view)
messages = empty_shown.take()
check("empty_grid_said_again_on_change",
      len(with_text(messages, "error", "The input mesh is empty")) == 1,
      f"expected the error again after the input changed, got {messages}")
empty_shown.hide()

empty_group = GroupDatasets(Input=[empty])
group_shown = Shown(empty_group)
Render(view)
messages = group_shown.take()
check("empty_multiblock_said",
      len(with_text(messages, "error", "The input mesh is empty")) == 1,
      f"expected one error 'The input mesh is empty', got {messages}")
group_shown.hide()

def with_nan(what):
    """sphere_in_cell with NaN coordinates or NaN field values (a Calculator would replace or
    refuse them), through a TrivialProducer."""
    from paraview import servermanager
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
    grid = vtkUnstructuredGrid()
    grid.DeepCopy(servermanager.Fetch(reader))
    if what == "points":
        for p in range(grid.GetNumberOfPoints()):
            grid.GetPoints().SetPoint(p, math.nan, math.nan, math.nan)
    else:
        field = grid.GetPointData().GetArray("sphere")
        for p in range(grid.GetNumberOfPoints()):
            field.SetValue(p, math.nan)
    producer = simple.TrivialProducer()
    producer.GetClientSideObject().SetOutput(grid)
    return producer


nan_points_shown = Shown(with_nan("points"))
Render(view)
messages = nan_points_shown.take()
check("nan_points_said",
      len(with_text(messages, "error", "has finite coordinates")) == 1,
      f"expected one error about no finite coordinates, got {messages}")
nan_points_shown.hide()

nan_field_shown = Shown(with_nan("field"))
Render(view)
messages = nan_field_shown.take()
check("nan_field_said",
      len(with_text(messages, "error", "No cell can be rendered")) >= 1,
      f"expected an error 'No cell can be rendered', got {messages}")
nan_field_shown.hide()

constant = Calculator(Input=reader, ResultArrayName="sphere", Function="0*sphere")
constant_shown = Shown(constant)
Render(view)
messages = constant_shown.take()
check("constant_field_at_iso_value_said",
      len(with_text(messages, "warning", "'sphere' is 0 everywhere, equal to an iso-value")) == 1,
      f"expected a warning that 'sphere' is 0 everywhere, got {messages}")
constant_shown.hide()

# --- The filter's proxy: the same lists, the same refusals ------------------------------------
caster = DirectSurfaceRayCast(Input=reader)  # noqa: F821 (defined by LoadPlugin)
caster.ContourBy = ["POINTS", "sphere"]
caster.ImageSize = [16, 16]
caster_messages = []


@calldata_type(VTK_STRING)
def on_caster_error(caller, event, text):
    caster_messages.append(("error", text.strip()))


@calldata_type(VTK_STRING)
def on_caster_warning(caller, event, text):
    caster_messages.append(("warning", text.strip()))


caster.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, on_caster_error)
caster.GetClientSideObject().AddObserver(vtkCommand.WarningEvent, on_caster_warning)
for name, count, fragment in (("ClipPlanes", 7, "ClipPlanes has 7 numbers, not a multiple of 6"),
                              ("IsoValueColors", 2, "IsoValueColors has 2 numbers, not a multiple of 3")):
    caster_messages.clear()
    setattr(caster, name, [0.5] * count)
    caster.UpdatePipeline()
    check(f"filter_{name}_{count}_numbers_refused",
          len(with_text(caster_messages, "error", fragment)) == 1,
          f"expected one error '{fragment}', got {caster_messages}")
    setattr(caster, name, [])
caster_messages.clear()
caster.IsoValueOpacities = [math.nan]
caster.UpdatePipeline()
check("filter_iso_value_opacity_nan_refused",
      len(with_text(caster_messages, "error", "IsoValueOpacities must be a number, got NaN")) == 1,
      f"expected an error naming IsoValueOpacities and NaN, got {caster_messages}")

if failures:
    print(f"{len(failures)} failed: {', '.join(failures)}")
    sys.exit(1)
print("representation hostile test: 0 failed")
