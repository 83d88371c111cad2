"""Client-server: the "Direct Surface" representation rendered by pvserver for a pvpython client
(Connect), against the same script in pvpython's builtin session.

Usage:
  pvpython test_client_server.py <TetDSR.so> <Data directory> <work directory> reference
      renders every state in the builtin session and keeps the pictures (and cuts the flow into
      the two pieces a 2-process server reads);
  client_server.py <ranks> <seconds> pvserver pvpython test_client_server.py <TetDSR.so>
      <Data directory> <work directory> connect [--pieces]
      connects to the server the launcher started (it appends --port), renders the same states
      there (--pieces: each server process reads one piece of the .pvtu) and compares.

The states: the surface speed = 0.25 coloured by pressure beside an opaque box (still frame);
the camera moved and the iso-value changed (interaction); a translucent outer surface added
(speed = 0.1 at opacity 0.4); an interactive frame with its level of detail forced to 4 x 4
pixels a ray (ParaView's interactive render, whose sample distance the server reports through
the LastImageSampleDistance information property); the still frame after it. Still frames must
equal the builtin ones within 2 / 255 in every pixel.
"""
import argparse
import os
import sys

import numpy as np
import paraview.simple as simple
from paraview.simple import (Box, ColorBy, Connect, CreateView, GetColorTransferFunction, LoadPlugin,
                             Render, SaveScreenshot, Show, XMLPartitionedUnstructuredGridReader,
                             XMLUnstructuredGridReader)
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pieces import make_pieces  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("plugin")
parser.add_argument("data")
parser.add_argument("work")
parser.add_argument("mode", choices=["reference", "connect"])
parser.add_argument("--port", type=int)
parser.add_argument("--pieces", action="store_true")
args = parser.parse_args()
os.makedirs(args.work, exist_ok=True)

W, H = 400, 240
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message, flush=True)


def pixels(path):
    png = vtkPNGReader()
    png.SetFileName(path)
    png.Update()
    return vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)


def render_states(source, tag):
    """{state: pixels}, and the sample distances the interactive and the still frame reported."""
    view = CreateView("RenderView")
    view.ViewSize = [W, H]
    view.OrientationAxesVisibility = 0
    view.UseFXAA = 0
    view.CameraPosition = [4.5, -4.0, 10.0]
    view.CameraFocalPoint = [4.2, 0.0, 0.0]
    view.CameraViewUp = [0.0, 1.0, 0.0]
    view.CameraViewAngle = 30.0
    display = Show(source, view)
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
    pictures, distances = {}, {}

    def shot(state):
        path = os.path.join(args.work, f"{tag}_{state}.png")
        SaveScreenshot(path, view, ImageResolution=[W, H])
        pictures[state] = pixels(path)

    shot("still")
    view.CameraPosition = [7.0, -3.0, 9.0]
    display.Isosurfaces = [0.2]
    shot("moved")
    display.Isosurfaces = [0.25, 0.1]
    display.IsoValueOpacities = [1.0, 0.4]
    shot("translucent")
    display.AutoAdjustSampleDistances = 0
    display.InteractiveImageSampleDistance = 4.0
    view.UseInteractiveRenderingForScreenshots = 1
    shot("interactive")
    display.UpdatePropertyInformation()
    distances["interactive"] = display.GetPropertyValue("LastImageSampleDistance")
    view.UseInteractiveRenderingForScreenshots = 0
    Render(view)  # a still render (the screenshot alone would show the last frame again)
    shot("after")
    display.UpdatePropertyInformation()
    distances["after"] = display.GetPropertyValue("LastImageSampleDistance")
    return pictures, distances


if args.mode == "reference":
    LoadPlugin(args.plugin, remote=False, ns=globals())
    simple._DisableFirstRenderCameraReset()
    make_pieces(args.data, args.work)
    source = XMLUnstructuredGridReader(FileName=[os.path.join(args.data, "expansion_flow.vtu")])
    pictures, distances = render_states(source, "builtin")
    background = np.array([int(round(255 * c)) for c in (0.32, 0.34, 0.43)])
    covered = int((np.abs(pictures["still"] - pictures["still"][0]).max(axis=1) > 0).sum())
    check(covered > 5000, f"the surface and box should cover more than 5000 pixels, got {covered}")
    for state in ("moved", "translucent"):
        changed = int((np.abs(pictures[state] - pictures["still"]).max(axis=1) > 2).sum())
        check(changed > 2000, f"{state}: should change more than 2000 pixels, got {changed}")
    lod = int((np.abs(pictures["interactive"] - pictures["after"]).max(axis=1) > 2).sum())
    check(distances["interactive"] == 4.0 and distances["after"] == 1.0 and lod > 200,
          f"level of detail: expected 4 then 1 pixels a ray and a coarser interactive frame, got "
          f"{distances} and {lod} pixels differing")
    np.savez(os.path.join(args.work, "builtin.npz"), **pictures)
    print(f"builtin: {covered} pixels covered; interactive frame at {distances['interactive']} "
          f"pixels a ray differs from the still one in {lod} pixels")
else:
    Connect("localhost", args.port)
    LoadPlugin(args.plugin, remote=True, ns=globals())
    LoadPlugin(args.plugin, remote=False, ns=globals())
    simple._DisableFirstRenderCameraReset()
    if args.pieces:
        source = XMLPartitionedUnstructuredGridReader(FileName=[os.path.join(args.work, "expansion_flow.pvtu")])
    else:
        source = XMLUnstructuredGridReader(FileName=[os.path.join(args.data, "expansion_flow.vtu")])
    tag = "server2" if args.pieces else "server"
    pictures, distances = render_states(source, tag)
    reference = np.load(os.path.join(args.work, "builtin.npz"))
    for state in ("still", "moved", "translucent", "after"):
        difference = np.abs(pictures[state] - reference[state]).max(axis=1)
        over = int((difference > 2).sum())
        check(over == 0, f"{state}: expected the builtin picture within 2 / 255, got {over} pixels "
                         f"off by up to {difference.max()} / 255")
        print(f"{tag}, {state}: {int((difference > 0).sum())} of {W * H} pixels differ from the "
              f"builtin session (max {difference.max()} / 255)")
    # The interactive frame: coarser than the still one (ParaView also reduces the image it
    # sends while interacting, so the picture alone cannot tell the mapper's level of detail; the
    # builtin run checks that through LastImageSampleDistance, which the client reads from its
    # own copy here), yet the same scene: most pixels within 16 / 255 of the still frame.
    difference = np.abs(pictures["interactive"] - pictures["after"]).max(axis=1)
    lod, close = int((difference > 2).sum()), float((difference <= 16).mean())
    check(lod > 200 and close > 0.9, f"interactive frame: expected a coarser picture of the same "
                                     f"scene, got {lod} pixels differing, {close:.0%} within 16 / 255")
    print(f"{tag}, interactive: {lod} pixels differ from the still frame after it, "
          f"{close:.1%} within 16 / 255")

if failures:
    sys.exit(1)
print(f"client-server test ({args.mode}): 0 failed")
