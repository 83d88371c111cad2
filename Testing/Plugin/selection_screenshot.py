"""The picture of docs/paraview.md's "Selection" section: ParaView's Select Cells On over a
rectangle of the "Direct Surface" of the expansion flow (speed = 0.25, coloured by pressure); the
selected cells (those the rays hit in the rectangle) are drawn by ParaView as a magenta wireframe.

Usage: pvpython selection_screenshot.py <TetDSR.so> <Data directory> <output .png>
"""
import sys

import paraview.simple as simple
from paraview import servermanager

plugin_path, data_dir, out = sys.argv[1:4]
simple.LoadPlugin(plugin_path, remote=False, ns=globals())
simple._DisableFirstRenderCameraReset()
reader = simple.XMLUnstructuredGridReader(FileName=[data_dir + "/expansion_flow.vtu"])
view = simple.CreateView("RenderView")
view.ViewSize = [800, 450]
view.OrientationAxesVisibility = 0
view.CameraPosition = [3.0, -2.2, 4.2]
view.CameraFocalPoint = [3.4, 0.0, 0.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
view.CameraViewAngle = 30.0
display = simple.Show(reader, view)
display.SetRepresentationType("Direct Surface")
display.ContourBy = ["POINTS", "speed"]
display.Isosurfaces = [0.25]
simple.ColorBy(display, ("POINTS", "pressure"))
simple.Render(view)
simple.SelectSurfaceCells(Rectangle=[250, 130, 470, 330], View=view, Modifier=None)
simple.Render(view)
simple.SaveScreenshot(out, view, ImageResolution=[800, 450])
extract = simple.ExtractSelection(Input=reader)
print(f"{servermanager.Fetch(extract).GetNumberOfCells()} cells selected; picture: {out}")
