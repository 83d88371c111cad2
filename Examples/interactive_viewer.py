#!/usr/bin/env python3
"""Interactive viewer of the exact isosurfaces of a quadratic tetrahedral mesh (vtkDirectSurfaceMapper).

  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/interactive_viewer.py
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/interactive_viewer.py \
      mesh.vtu --array f --iso 0.3 0.5 --color-by g --size 1200 900
  ... --screenshot out.png      (render one frame offscreen, write it, exit: works headless
                                 under xvfb-run -a)

Without a mesh it opens Data/expansion_flow.vtu at speed = 0.25, coloured by pressure. The
surface is ray cast exactly per frame (reduced resolution while the camera moves, full resolution
when it stops); the mesh's bounding box is drawn as an outline.

Keys: Up / Down move the selected iso-value by 2% of the field's range (the new value is
printed), Tab selects the next iso-value (marked > <), the slider at the bottom sets the selected iso-value;
the usual VTK trackball camera (left drag rotates, right drag / wheel zooms, middle drag pans,
r resets the camera, q quits). p picks the surface under the mouse (vtkDirectSurfacePicker): the
exact hit is marked with a small sphere and its cell, point and the arrays' values there are
shown and printed; ... --screenshot out.png --pick X Y does the same at display position (X, Y).
"""
import argparse
import os
import sys

from vtkmodules.vtkCommonCore import vtkCommand, vtkLookupTable
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkFiltersModeling import vtkOutlineFilter
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkInteractionWidgets import vtkSliderRepresentation2D, vtkSliderWidget
from vtkmodules.vtkInteractionStyle import vtkInteractorStyleTrackballCamera
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingAnnotation import vtkScalarBarActor
from vtkmodules.vtkRenderingCore import (vtkActor, vtkColorTransferFunction, vtkPolyDataMapper,
                                         vtkRenderWindow, vtkRenderWindowInteractor, vtkRenderer,
                                         vtkTextActor, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingFreeType  # noqa: F401 (text)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)
import vtkmodules.vtkRenderingUI  # noqa: F401 (the platform's interactor)

from tetdsr import vtkDirectSurfaceMapper, vtkDirectSurfacePicker

DEFAULT_MESH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data",
                            "expansion_flow.vtu")
# Colours of the iso-values' surfaces when not colour-mapped.
SURFACE_COLORS = [(0.90, 0.75, 0.55), (0.55, 0.75, 0.95), (0.60, 0.90, 0.60), (0.95, 0.60, 0.60)]


def color_map(name, value_range):
    """ParaView's "Cool to Warm" (diverging) transfer function, or a rainbow lookup table."""
    if name == "cool-to-warm":
        ctf = vtkColorTransferFunction()
        ctf.SetColorSpaceToDiverging()
        ctf.AddRGBPoint(value_range[0], 0.231373, 0.298039, 0.752941)
        ctf.AddRGBPoint(0.5 * (value_range[0] + value_range[1]), 0.865003, 0.865003, 0.865003)
        ctf.AddRGBPoint(value_range[1], 0.705882, 0.0156863, 0.14902)
        ctf.SetVectorModeToMagnitude()
        return ctf
    lut = vtkLookupTable()
    lut.SetTableRange(value_range)
    if name == "grayscale":
        lut.SetHueRange(0.0, 0.0)
        lut.SetSaturationRange(0.0, 0.0)
        lut.SetValueRange(0.1, 1.0)
    else:  # rainbow, blue to red
        lut.SetHueRange(0.667, 0.0)
    lut.SetVectorModeToMagnitude()
    lut.Build()
    return lut


def array_range(array):
    """The range of a scalar array, or of a vector array's magnitude."""
    return array.GetRange(0) if array.GetNumberOfComponents() == 1 else array.GetRange(-1)


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="\n".join(__doc__.splitlines()[1:]))
    parser.add_argument("mesh", nargs="?", help="a .vtu of VTK_QUADRATIC_TETRA cells "
                        "(default: Data/expansion_flow.vtu, speed = 0.25 coloured by pressure)")
    parser.add_argument("--array", help="point array whose isosurface is drawn "
                        "(default: the active scalars, else the first point array)")
    parser.add_argument("--iso", type=float, nargs="+", help="iso-value(s) (default: mid-range)")
    parser.add_argument("--color-by", metavar="ARRAY",
                        help="colour the surface by this point array (vectors: magnitude)")
    parser.add_argument("--color-map", choices=["cool-to-warm", "rainbow", "grayscale"],
                        default="cool-to-warm")
    parser.add_argument("--opacity", type=float, nargs="+", metavar="A",
                        help="opacity per iso-value (default: 1 for one iso-value, 0.6 for several, "
                        "so that nested surfaces show)")
    parser.add_argument("--size", type=int, nargs=2, default=[1000, 800], metavar=("W", "H"))
    parser.add_argument("--screenshot", metavar="PNG",
                        help="render one frame offscreen, write it to this PNG and exit")
    parser.add_argument("--press", nargs="+", default=[], metavar="KEYSYM",
                        help="with --screenshot: press these keys first (e.g. Up Up Tab Down)")
    parser.add_argument("--pick", nargs=2, type=float, metavar=("X", "Y"),
                        help="with --screenshot: pick the surface at this display position first")
    args = parser.parse_args()
    if args.mesh is None:
        args.mesh = DEFAULT_MESH
        args.array = args.array or "speed"
        args.iso = args.iso or [0.25]
        args.color_by = args.color_by or "pressure"
    return args


def read_mesh(args):
    """The mesh's reader and grid; fills in args.array (the active scalars, else the first point
    array) and exits with a message when the file, its cells or the arrays are missing."""
    if not os.path.isfile(args.mesh):
        sys.exit(f"no such file: {args.mesh}")
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.mesh)
    reader.Update()
    grid = reader.GetOutput()
    point_data = grid.GetPointData()
    if grid.GetNumberOfCells() == 0 or point_data.GetNumberOfArrays() == 0:
        sys.exit(f"{args.mesh}: no cells or no point arrays")
    if args.array is None:
        scalars = point_data.GetScalars()
        args.array = scalars.GetName() if scalars is not None and scalars.GetName() else \
            point_array_names(grid)[0]
    if point_data.GetArray(args.array) is None:
        sys.exit(f"no point array '{args.array}' (point arrays: {', '.join(point_array_names(grid))})")
    if args.color_by and point_data.GetArray(args.color_by) is None:
        sys.exit(f"no point array '{args.color_by}' (point arrays: {', '.join(point_array_names(grid))})")
    return reader, grid


def point_array_names(grid):
    point_data = grid.GetPointData()
    return [point_data.GetArrayName(i) for i in range(point_data.GetNumberOfArrays())]


def make_surface(args, reader, isos):
    """The exact isosurfaces' mapper and actor (one opacity per iso-value)."""
    mapper = vtkDirectSurfaceMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, args.array)
    for i, value in enumerate(isos):
        mapper.SetValue(i, value)
    opacities = args.opacity or ([1.0] if len(isos) == 1 else [0.6])
    for i in range(len(isos)):
        mapper.SetIsoValueOpacity(i, opacities[min(i, len(opacities) - 1)])
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetSpecular(0.3)
    actor.GetProperty().SetSpecularPower(30.0)
    return mapper, actor


def color_surface(args, grid, mapper, actor, renderer, isos):
    """Colours by args.color_by with a scalar bar, or each iso-value's surface in a colour of its own."""
    if args.color_by:
        color_array = grid.GetPointData().GetArray(args.color_by)
        color_range = array_range(color_array)
        lut = color_map(args.color_map, color_range)
        mapper.ScalarVisibilityOn()
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray(args.color_by)
        mapper.SetLookupTable(lut)
        mapper.SetScalarRange(color_range)
        bar = vtkScalarBarActor()
        bar.SetLookupTable(lut)
        bar.SetTitle(args.color_by)
        bar.SetNumberOfLabels(5)
        bar.SetMaximumWidthInPixels(90)
        bar.GetPositionCoordinate().SetValue(0.9, 0.25)
        bar.SetWidth(0.09)
        bar.SetHeight(0.6)
        renderer.AddActor2D(bar)
    else:
        mapper.ScalarVisibilityOff()
        actor.GetProperty().SetColor(*SURFACE_COLORS[0])
        if len(isos) > 1:
            for i in range(len(isos)):
                mapper.SetIsoValueColor(i, *SURFACE_COLORS[i % len(SURFACE_COLORS)])


def add_outline(reader, renderer):
    """The mesh's bounding box, in white."""
    outline = vtkOutlineFilter()
    outline.SetInputConnection(reader.GetOutputPort())
    outline_mapper = vtkPolyDataMapper()
    outline_mapper.SetInputConnection(outline.GetOutputPort())
    outline_actor = vtkActor()
    outline_actor.SetMapper(outline_mapper)
    outline_actor.GetProperty().SetColor(1.0, 1.0, 1.0)
    outline_actor.GetProperty().SetLineWidth(1.5)
    renderer.AddActor(outline_actor)


def make_window(args, renderer):
    """The render window (offscreen for --screenshot) and its trackball interactor."""
    window = vtkRenderWindow()
    window.SetSize(*args.size)
    window.SetWindowName(f"TetDSR: {os.path.basename(args.mesh)}")
    window.AddRenderer(renderer)
    if args.screenshot:
        window.SetOffScreenRendering(1)
    interactor = vtkRenderWindowInteractor()
    interactor.SetRenderWindow(window)
    interactor.SetInteractorStyle(vtkInteractorStyleTrackballCamera())
    return window, interactor


def place_camera(renderer, room_for_scalar_bar):
    camera = renderer.GetActiveCamera()
    renderer.ResetCamera()
    camera.Azimuth(30.0)
    camera.Elevation(25.0)
    camera.OrthogonalizeViewUp()
    renderer.ResetCamera()
    if room_for_scalar_bar:  # on the right
        camera.Zoom(0.95)
        camera.SetWindowCenter(0.08, 0.0)


class IsoValueControls:
    """The iso-values the keys (Up, Down, Tab) and the slider at the bottom change, and the text
    at the top left that lists them."""

    def __init__(self, array, isos, field_range, mapper, renderer, interactor):
        self.array, self.isos, self.field_range = array, isos, field_range
        self.span = field_range[1] - field_range[0] or 1.0
        self.mapper, self.window = mapper, interactor.GetRenderWindow()
        self.selected = 0
        self.text = vtkTextActor()
        self.text.GetTextProperty().SetFontSize(18)
        self.text.GetTextProperty().SetColor(1.0, 1.0, 1.0)
        self.text.GetTextProperty().SetVerticalJustificationToTop()
        self.text.GetPositionCoordinate().SetCoordinateSystemToNormalizedDisplay()
        self.text.GetPositionCoordinate().SetValue(0.015, 0.98)
        renderer.AddActor2D(self.text)
        self.slider_rep = vtkSliderRepresentation2D()
        self.slider_rep.SetMinimumValue(field_range[0])
        self.slider_rep.SetMaximumValue(field_range[1])
        self.slider_rep.SetTitleText(f"{array} iso-value")
        self.slider_rep.GetPoint1Coordinate().SetCoordinateSystemToNormalizedDisplay()
        self.slider_rep.GetPoint1Coordinate().SetValue(0.30, 0.07)
        self.slider_rep.GetPoint2Coordinate().SetCoordinateSystemToNormalizedDisplay()
        self.slider_rep.GetPoint2Coordinate().SetValue(0.80, 0.07)
        self.slider_rep.SetSliderLength(0.02)
        self.slider_rep.SetSliderWidth(0.03)
        self.slider_rep.SetTubeWidth(0.005)
        self.slider_rep.SetLabelHeight(0.025)
        self.slider_rep.SetTitleHeight(0.025)
        self.slider_rep.SetLabelFormat("%.4g")
        self.slider = vtkSliderWidget()
        self.slider.SetInteractor(interactor)
        self.slider.SetRepresentation(self.slider_rep)
        self.slider.SetAnimationModeToJump()
        interactor.AddObserver(vtkCommand.KeyPressEvent, self.on_key)
        self.slider.AddObserver(vtkCommand.InteractionEvent, self.on_slider)
        self.update(announce=False)
        self.slider.EnabledOn()

    def update(self, announce=True):
        i = self.selected
        values = ", ".join(("> %.4g <" if k == i and len(self.isos) > 1 else "%.4g") % v
                           for k, v in enumerate(self.isos))
        self.text.SetInput(f"{self.array} = {values}\nUp/Down: +/-2% of range"
                           + (", Tab: next iso-value" if len(self.isos) > 1 else ""))
        self.slider_rep.SetValue(self.isos[i])
        if announce:
            print(f"iso-value {i}: {self.array} = {self.isos[i]:.6g}", flush=True)

    def set_iso(self, value):
        i = self.selected
        self.isos[i] = min(max(value, self.field_range[0]), self.field_range[1])
        self.mapper.SetValue(i, self.isos[i])
        self.update()
        self.window.Render()

    def on_key(self, caller, event):
        key = caller.GetKeySym()
        step = 0.02 * self.span
        if key == "Up":
            self.set_iso(self.isos[self.selected] + step)
        elif key == "Down":
            self.set_iso(self.isos[self.selected] - step)
        elif key == "Tab" and len(self.isos) > 1:
            self.selected = (self.selected + 1) % len(self.isos)
            self.update()
            self.window.Render()

    def on_slider(self, caller, event):
        self.set_iso(caller.GetRepresentation().GetValue())


class PickReport:
    """Picking (p, or --pick): the exact hit marked with a small sphere, and what the mesh holds
    there shown at the bottom left and printed."""

    def __init__(self, grid, renderer, interactor):
        marker_source = vtkSphereSource()
        marker_source.SetThetaResolution(24)
        marker_source.SetPhiResolution(12)
        bounds = grid.GetBounds()
        marker_source.SetRadius(0.008 * sum((bounds[2 * k + 1] - bounds[2 * k]) ** 2
                                            for k in range(3)) ** 0.5)
        marker_mapper = vtkPolyDataMapper()
        marker_mapper.SetInputConnection(marker_source.GetOutputPort())
        self.marker = vtkActor()
        self.marker.SetMapper(marker_mapper)
        self.marker.GetProperty().SetColor(1.0, 0.85, 0.1)
        self.marker.PickableOff()
        self.marker.VisibilityOff()
        renderer.AddActor(self.marker)
        self.picked = vtkTextActor()
        self.picked.GetTextProperty().SetFontSize(16)
        self.picked.GetTextProperty().SetColor(1.0, 0.85, 0.1)
        self.picked.GetPositionCoordinate().SetCoordinateSystemToNormalizedDisplay()
        self.picked.GetPositionCoordinate().SetValue(0.015, 0.13)
        renderer.AddActor2D(self.picked)
        self.picker = vtkDirectSurfacePicker()
        interactor.SetPicker(self.picker)
        self.picker.AddObserver(vtkCommand.EndPickEvent, self.on_pick)

    def on_pick(self, caller, event):
        pick = self.picker.GetLastPick()
        if not pick.GetHit():
            self.marker.VisibilityOff()
            self.picked.SetInput("")
            return
        self.marker.SetPosition(pick.GetPosition())
        self.marker.VisibilityOn()
        data = pick.GetPointData()
        values = ", ".join(
            f"{data.GetArrayName(k)} = " + ", ".join(
                "%.6g" % data.GetArray(k).GetComponent(0, c)
                for c in range(data.GetArray(k).GetNumberOfComponents()))
            for k in range(data.GetNumberOfArrays()))
        x = ", ".join("%.6g" % v for v in pick.GetPosition())
        line = f"picked cell {pick.GetCellId()} at ({x})\n{values}"
        self.picked.SetInput(line)
        print(line.replace("\n", "; "), flush=True)


def write_screenshot(args, window, interactor, picker, renderer, mapper, isos):
    """One frame: the keys of --press, the pick of --pick, then the window to args.screenshot."""
    window.Render()
    for key in args.press:  # as the interactor delivers a key press
        interactor.SetKeySym(key)
        interactor.InvokeEvent(vtkCommand.KeyPressEvent)
    if args.pick:
        picker.Pick(args.pick[0], args.pick[1], 0.0, renderer)
        window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(args.screenshot)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    print(f"wrote {args.screenshot} ({args.size[0]} x {args.size[1]}; "
          f"{mapper.GetNumberOfRenderedCells()} cells, {args.array} = "
          f"{', '.join('%.4g' % v for v in isos)})")


def main():
    args = parse_arguments()
    reader, grid = read_mesh(args)
    field_range = array_range(grid.GetPointData().GetArray(args.array))
    isos = list(args.iso) if args.iso else [0.5 * (field_range[0] + field_range[1])]

    mapper, actor = make_surface(args, reader, isos)
    renderer = vtkRenderer()
    renderer.SetBackground(0.32, 0.34, 0.43)
    renderer.AddActor(actor)
    color_surface(args, grid, mapper, actor, renderer, isos)
    add_outline(reader, renderer)
    window, interactor = make_window(args, renderer)
    place_camera(renderer, room_for_scalar_bar=bool(args.color_by))
    controls = IsoValueControls(args.array, isos, field_range, mapper, renderer, interactor)
    picking = PickReport(grid, renderer, interactor)

    if args.screenshot:
        write_screenshot(args, window, interactor, picking.picker, renderer, mapper, isos)
        return 0
    print(f"{args.mesh}: {grid.GetNumberOfCells()} cells; {args.array} in "
          f"[{field_range[0]:.6g}, {field_range[1]:.6g}]; Up/Down step {0.02 * controls.span:.6g}")
    window.Render()
    interactor.Start()
    return 0


if __name__ == "__main__":
    sys.exit(main())
