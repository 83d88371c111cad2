"""Run inside the ParaView GUI (paraview --dr --script=this) by gui_responsiveness.py, which reads
its log and answers through a control file: the user's actions on a "Direct Surface"
representation, one at a time, each timed from its start to its return (the GUI thread busy) and
to the render that shows the refined (full-resolution) frame.

It loads the plugin, opens the data as Surface, locks the view to the size asked for (View >
Preview), and then, from a repeating timer on the view's interactor (so that the GUI's event loop
runs between actions, as it does between a user's clicks), plays each action once the driver has
acknowledged the one before (it clicks the File menu and measures how long the GUI takes to open
it; the first action waits for its measurement of the idle GUI). Log lines (the file TETDSR_GUI_LOG, flushed at once; times are time.time()):
  ready <time>                       the GUI is up, the data shown as Surface
  start <action> <time>              an action begins (the GUI thread is then busy with it)
  returned <action> <time>           its synchronous part returned to the event loop
  refined <action> <time> <w> <h>    the mapper drew its full cast of <w> x <h> rays
  failed <text>                      and the GUI quits with status 1
  screenshot <refining> <pixels>     at the screenshot action: whether the view was refining when
                                     it was captured, and how many pixels differ from a capture of
                                     the refined view (a capture is exact: 0)
Actions: show (Surface to Direct Surface), iso (new iso-values), colour (Color By another
array), reset (an orbit, then Reset Camera), wheel (the driver turns the mouse wheel over the
view: only marked here), screenshot (the first iso-value again, and SaveScreenshot at once). Environment: TETDSR_PLUGIN, TETDSR_GUI_DATA, TETDSR_GUI_ARRAY,
TETDSR_GUI_ISO (the iso-value shown, then the iso-values it changes to, comma-separated), TETDSR_GUI_COLOR, TETDSR_GUI_SIZE ("W H"),
TETDSR_GUI_LOG, TETDSR_GUI_CONTROL.
"""
import os
import sys
import time
import traceback

import paraview.simple as simple

ACTIONS = ("show", "iso", "colour", "reset", "wheel", "screenshot")
REFINE_TIMEOUT = 60.0  # seconds an action may take to show its refined frame

log = open(os.environ["TETDSR_GUI_LOG"], "a", buffering=1)


def say(*words):
    log.write(" ".join(str(w) for w in words) + "\n")


def fail(text):
    say("failed", text.replace("\n", " | "))
    os._exit(1)


def acknowledged():
    """How many actions the driver has finished measuring (the control file's number)."""
    try:
        with open(os.environ["TETDSR_GUI_CONTROL"]) as control:
            return int(control.read().strip() or 0)
    except (OSError, ValueError):
        return 0


try:
    simple.LoadPlugin(os.environ["TETDSR_PLUGIN"], remote=False, ns=globals())
    import tetdsr  # noqa: F401 (the mapper's Python class, for its own methods)
    width, height = (int(v) for v in os.environ["TETDSR_GUI_SIZE"].split())
    shown_text, changed_text = os.environ["TETDSR_GUI_ISO"].split()
    iso_shown, iso_changed = float(shown_text), [float(v) for v in changed_text.split(",")]
    array = os.environ["TETDSR_GUI_ARRAY"]
    colour = os.environ["TETDSR_GUI_COLOR"]
    simple.GetLayout().PreviewMode = [width, height]
    view = simple.GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 0
    reader = simple.OpenDataFile(os.environ["TETDSR_GUI_DATA"])
    display = simple.Show(reader, view)
    display.ContourBy = ["POINTS", array]
    display.Isosurfaces = [iso_shown]
    view.ResetCamera()
    simple.Render(view)
    interactor = view.GetRenderWindow().GetInteractor()
    if os.environ.get("TETDSR_GUI_TRACE"):
        say("interactors", interactor.GetClassName(), interactor.GetAddressAsString(""),
            view.GetClientSideObject().GetInteractor().GetAddressAsString(""))
except Exception:
    fail(traceback.format_exc())


def mapper():
    """The Direct Surface representation's mapper (null before it is shown)."""
    actors = view.GetRenderer().GetActors()
    for k in range(actors.GetNumberOfItems()):
        m = actors.GetItemAsObject(k).GetMapper()
        if m is not None and m.IsA("vtkDirectSurfaceMapper") and actors.GetItemAsObject(k).GetVisibility():
            return m
    return None


def act(name):
    if name == "show":
        display.SetRepresentationType("Direct Surface")
    elif name == "iso":
        display.Isosurfaces = iso_changed
    elif name == "colour":
        simple.ColorBy(display, ("POINTS", colour))
    elif name == "reset":
        camera = view.GetActiveCamera()
        camera.Azimuth(35)
        camera.Elevation(20)
        view.ResetCamera()
    elif name == "screenshot":
        display.Isosurfaces = [iso_shown]
    if name != "wheel":  # (the driver turns the wheel: ParaView renders as it does for a user)
        simple.Render(view)
    if name == "screenshot":  # at once, while the view shows the coarse frame
        state["capture refining"] = int(mapper().GetLastRenderRefining())
        simple.SaveScreenshot(screenshot_path(1), view, ImageResolution=[width, height])


def screenshot_path(k):
    return os.path.join(os.path.dirname(os.environ["TETDSR_GUI_LOG"]), f"screenshot{k}.png")


def differing_pixels(first, second):
    from vtkmodules.vtkIOImage import vtkPNGReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    images = []
    for path in (first, second):
        png = vtkPNGReader()
        png.SetFileName(path)
        png.Update()
        images.append(vtk_to_numpy(png.GetOutput().GetPointData().GetScalars()).astype(int))
    if images[0].shape != images[1].shape:
        return -1
    return int((abs(images[0] - images[1]).max(axis=1) > 0).sum())


state = {"next": 0, "pending": None, "since": 0.0, "ready": False}


def tick(caller, event):
    try:
        now = time.time()
        if not state["ready"]:
            state["ready"] = True
            say("ready", now)
            return
        pending = state["pending"]
        if pending is not None:
            m = mapper()
            if m is not None and os.environ.get("TETDSR_GUI_TRACE"):
                seen = (*m.GetLastCastSize(), m.GetLastImageSampleDistance(),
                        int(m.GetLastRenderRefining()), int(m.GetLastRenderReusedImage()))
                if seen != state.get("seen"):
                    state["seen"] = seen
                    say("trace", pending, now, *seen)
            moved = view.GetActiveCamera().GetPosition() != state["camera"]
            if (m is not None and m.GetLastCastSize()[0] >= width - 1 and not m.GetLastRenderRefining()
                    and m.GetLastImageSampleDistance() == 1.0 and (pending != "wheel" or moved)):
                size = m.GetLastCastSize()
                if pending == "screenshot":  # the refined view, captured again: the same image
                    simple.SaveScreenshot(screenshot_path(2), view, ImageResolution=[width, height])
                    say("screenshot", state["capture refining"],
                        differing_pixels(screenshot_path(1), screenshot_path(2)))
                say("refined", pending, now, size[0], size[1])
                state["pending"] = None
            elif now - state["since"] > REFINE_TIMEOUT:
                fail(f"no refined frame {REFINE_TIMEOUT} s after '{pending}'")
            return
        if acknowledged() <= state["next"]:
            return  # the driver is still measuring the idle GUI, or the previous action
        if state["next"] == len(ACTIONS):
            log.close()
            os._exit(0)
        name = ACTIONS[state["next"]]
        state["next"] += 1
        state["pending"] = name
        state["camera"] = view.GetActiveCamera().GetPosition()
        say("start", name, time.time())
        act(name)
        state["since"] = time.time()
        m = mapper()
        say("returned", name, state["since"], *(() if m is None else (
            "cast", *m.GetLastCastSize(), "refining", int(m.GetLastRenderRefining()),
            "seconds", round(m.GetTimeToDraw(), 3))))
    except Exception:
        fail(traceback.format_exc())


observer = interactor.AddObserver("TimerEvent", tick)
timer = interactor.CreateRepeatingTimer(20)
