"""Run by the ParaView GUI connected to a pvserver (paraview --dr --server-url=cs://... --script=this):
shows the expansion flow as "Direct Surface" on the server, saves the view and compares it with
the builtin session's still frame (test_client_server.py reference), then quits the GUI with the
result as its exit status. Arguments come through the environment: TETDSR_PLUGIN, TETDSR_DATA,
TETDSR_WORK."""
import os
import sys

import numpy as np
from paraview.simple import (Box, ColorBy, GetActiveViewOrCreate, GetColorTransferFunction, LoadPlugin,
                             Render, SaveScreenshot, Show, XMLUnstructuredGridReader)
import paraview.simple as simple
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

def say(text):
    """To the terminal: the GUI sends print() to its own Python shell."""
    sys.__stdout__.write(text + "\n")
    sys.__stdout__.flush()


code = 1
try:
    plugin, data, work = (os.environ[k] for k in ("TETDSR_PLUGIN", "TETDSR_DATA", "TETDSR_WORK"))
    LoadPlugin(plugin, remote=True, ns=globals())
    LoadPlugin(plugin, remote=False, ns=globals())
    simple._DisableFirstRenderCameraReset()
    view = GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 0
    view.UseFXAA = 0
    view.CameraPosition = [4.5, -4.0, 10.0]
    view.CameraFocalPoint = [4.2, 0.0, 0.0]
    view.CameraViewUp = [0.0, 1.0, 0.0]
    view.CameraViewAngle = 30.0
    display = Show(XMLUnstructuredGridReader(FileName=[os.path.join(data, "expansion_flow.vtu")]), view)
    display.SetRepresentationType("Direct Surface")
    display.ContourBy = ["POINTS", "speed"]
    display.Isosurfaces = [0.25]
    ColorBy(display, ("POINTS", "pressure"))
    lut = GetColorTransferFunction("pressure")
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(-0.027, 0.51)
    box = Show(Box(XLength=0.6, YLength=1.2, ZLength=0.25, Center=[4.5, 0.0, 0.0]), view)
    box.DiffuseColor = [0.9, 0.8, 0.1]
    box.ColorArrayName = ["POINTS", ""]
    Render(view)
    path = os.path.join(work, "gui_still.png")
    SaveScreenshot(path, view, ImageResolution=[400, 240])
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    ours = vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)
    reference = np.load(os.path.join(work, "builtin.npz"))["still"]
    difference = np.abs(ours - reference).max(axis=1)
    over = int((difference > 2).sum())
    say(f"GUI client: {int((difference > 0).sum())} of {len(ours)} pixels differ from the builtin "
        f"session (max {difference.max()} / 255), {over} by more than 2 / 255")
    code = 0 if over == 0 else 1
except Exception as error:  # reported, and the GUI still quits
    say(f"gui_client_server failed: {error!r}")
os._exit(code)
