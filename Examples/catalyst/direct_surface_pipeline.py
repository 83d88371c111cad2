"""ParaView Catalyst pipeline (a version 2 script) for heat_p2.py: the simulation's grid,
"input", shown as Direct Surface (two nested exact isosurfaces of the temperature, the outer one
translucent), saved as a PNG every TETDSR_EVERY steps into TETDSR_OUT.
Settings come through the environment, set by the simulation."""
import os

from paraview import catalyst
from paraview.simple import CreateView, LoadPlugin, SaveScreenshot, Show, TrivialProducer

LoadPlugin(os.environ["TETDSR_PLUGIN"], remote=False, ns=globals())
EVERY = int(os.environ.get("TETDSR_EVERY", "10"))
OUT = os.environ["TETDSR_OUT"]
WIDTH, HEIGHT = (int(v) for v in os.environ.get("TETDSR_SIZE", "480 360").split())

# The simulation's grid, by the name it hands it to Catalyst with.
producer = TrivialProducer(registrationName="input")

view = None


def make_view():
    """The view, made with the first data (a Direct Surface of an empty producer would say so)."""
    global view
    view = CreateView("RenderView")
    view.ViewSize = [WIDTH, HEIGHT]
    view.OrientationAxesVisibility = 0
    view.UseFXAA = 0
    view.CameraPosition = [2.4, -1.5, 1.9]
    view.CameraFocalPoint = [0.5, 0.5, 0.45]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraViewAngle = 30.0
    display = Show(producer, view)
    display.SetRepresentationType("Direct Surface")
    display.ContourBy = ["POINTS", "temperature"]
    display.Isosurfaces = [0.05, 0.3]
    display.IsoValueColors = [0.35, 0.55, 0.9, 0.95, 0.45, 0.2]
    display.IsoValueOpacities = [0.45, 1.0]
    display.ColorArrayName = ["POINTS", ""]


options = catalyst.Options()


def catalyst_execute(info):
    if view is None:
        make_view()
    if info.timestep % EVERY == 0:
        SaveScreenshot(os.path.join(OUT, f"heat_{info.timestep:04d}.png"), view,
                       ImageResolution=[WIDTH, HEIGHT])
