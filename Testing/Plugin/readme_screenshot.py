"""The scene of the ParaView screenshot in the README and docs/paraview.md (Examples/images/paraview_direct_surface.png): the
expansion flow's isosurface speed = 0.25 as "Direct Surface", coloured by pressure, among a slice
coloured by speed and the domain's outline. Run it in the GUI from the repository's root, then
take the window:

  Xvfb :77 -screen 0 1600x1000x24 &  export DISPLAY=:77
  paraview --dr --script=Testing/Plugin/readme_screenshot.py &
  sleep 15; W=$(xdotool search --name "ParaView 5" | head -1)
  xdotool windowmove $W 0 0 windowsize $W 1400 880; sleep 3
  xdotool mousemove 130 700 click --repeat 6 5   # scroll the panel to the Direct Surface group
  import -window root -crop 1400x880+0+0 Examples/images/paraview_direct_surface.png
"""
import os

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             Hide3DWidgets, LoadPlugin, Outline, Render, SetActiveSource, Show,
                             Slice, XMLUnstructuredGridReader)

root = os.getcwd()  # the repository (ParaView runs --script files without __file__)
build = os.environ.get("TETDSR_BUILD", os.path.join(root, "build"))
LoadPlugin(os.path.join(build, "lib/paraview-5.11/plugins/TetDSR/TetDSR.so"), remote=False,
           ns=globals())
flow = XMLUnstructuredGridReader(registrationName="expansion_flow.vtu",
                                 FileName=[os.path.join(root, "Data/expansion_flow.vtu")])
view = GetActiveViewOrCreate("RenderView")

outline = Show(Outline(registrationName="Outline1", Input=flow), view)
outline.DiffuseColor = outline.AmbientColor = [0.9, 0.9, 0.9]
cut = Slice(registrationName="Slice1", Input=flow)
cut.SliceType = "Plane"
cut.SliceType.Origin = [4.0, 0.0, 0.0]
cut.SliceType.Normal = [0.0, 0.0, 1.0]
cut_display = Show(cut, view)
ColorBy(cut_display, ("POINTS", "speed"))
GetColorTransferFunction("speed").ApplyPreset("X Ray", True)
cut_display.SetScalarBarVisibility(view, False)
Hide3DWidgets(proxy=cut.SliceType)

display = Show(flow, view)
display.SetRepresentationType("Direct Surface")
display.ContourBy = ["POINTS", "speed"]
display.Isosurfaces = [0.25]
ColorBy(display, ("POINTS", "pressure"))
display.RescaleTransferFunctionToDataRange(True)
display.SetScalarBarVisibility(view, True)
display.Specular = 0.3

view.CameraPosition = [0.3, -5.2, 4.6]
view.CameraFocalPoint = [4.6, 0.0, -0.4]
view.CameraViewUp = [0.25, 0.55, 0.8]
view.CameraViewAngle = 30
SetActiveSource(flow)
Render(view)
