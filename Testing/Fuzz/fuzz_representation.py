"""Fuzzer of ParaView's "Direct Surface" representation: random and hostile small meshes,
property values (types, counts, NaN, Inf, huge, negative), cameras and renders, in pvpython.

Every case is made from (seed, case index) alone, so any case can be replayed. Each case runs in
its own pvpython process, with a time limit, on an X server of this run's own (one per job; a
case that the X server refused, or that died in Xlib with no TetDSR frame, is run again, up to
three times). Failures:
  crash:  the case died by a signal, or printed "Segmentation fault" / "Aborted";
  hang:   it did not finish within the time limit;
  silent: its last render drew nothing (every pixel the background), no Direct Surface object
          said anything (an error or warning from vtkDirectSurface*), the input had cells, and
          nothing that may legitimately hide the surface was chosen (a random camera, an
          iso-value outside the field's range, clipping planes, a transform, Opacity below 1/4,
          Visibility off);
  harness: the case script itself failed (a bug of the fuzzer).
ParaView refusing a value itself (a Python exception on a wrong type or count) is a refusal,
not a failure: it is loud.

A case is a list of "knobs" (mesh, properties, camera, renders), each drawn from its own random
stream, so that a failing case can be shrunk by switching knobs off (--without).

Usage (run with /usr/bin/python3; pvpython must be on PATH):
  fuzz_representation.py --plugin <TetDSR.so> [--seed S] [--cases N | --minutes M]
                         [--timeout T] [--jobs J] [--out DIR]
  fuzz_representation.py --plugin <TetDSR.so> --seed S --replay I [--without knob,knob]
Exit status: 0 when no case crashed, hung, was silent or broke the harness; 1 otherwise.
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time

from fuzz_common import X_REFUSALS, Case as BaseCase, pick

KNOBS = {
    "mesh": 1.0,
    "multiblock": 0.2,
    "contour_by": 0.3,
    "iso_values": 0.4,
    "numbers": 0.4,
    "colors": 0.3,
    "lists": 0.4,
    "transform": 0.15,
    "color_by": 0.3,
    "camera": 0.3,
    "renders": 0.4,
}
# Knobs that may hide a valid surface without any message being owed.
MAY_HIDE = {"camera", "transform"}
MESSAGE = re.compile(r"(ERR|WARN)\|.*vtkDirectSurface")
CRASH_TEXT = ("Segmentation fault", "Aborted", "terminate called", "Loguru caught a signal")


class Case(BaseCase):
    """A case's choices (fuzz_common.Case): one random stream per knob; notes are printed as
    they come (the parent keeps the case's output)."""

    KNOBS = KNOBS

    def __init__(self, seed, index, without=()):
        super().__init__(seed, index, without)
        self.may_hide = False  # something chosen may hide a valid surface

    def knob(self, name):
        rng = super().knob(name)
        if rng is not None and name in MAY_HIDE:
            self.may_hide = True
        return rng

    def note(self, text):
        super().note(text)
        print("  " + text, flush=True)


def hostile_number(rng):
    return pick(rng, [float("nan"), float("inf"), -float("inf"), 1e308, -1e308, -1.0, -1e-300,
                      0.0, 2.0, 1e9, float(rng.normal()), float(rng.uniform(0, 1)), 7])


def hostile_value(rng, count):
    """A value for a property of `count` numbers: right or wrong type and count."""
    kind = pick(rng, ["right", "right", "right", "count", "number", "string", "none"])
    if kind == "count":
        count = int(rng.integers(0, 9))
    if kind == "string":
        return pick(rng, ["abc", "", "1,2,3", "nan"])
    if kind == "none":
        return None
    values = [hostile_number(rng) if rng.random() < 0.4 else float(rng.uniform(0, 1))
              for _ in range(count)]
    return values[0] if kind == "number" and values else values


# ---------------------------------------------------------------------------------------------
# The case, in pvpython

def build_grid(case, rng, vtk, np):
    """A small unstructured grid: quadratic tets (a soup), perhaps with hostile contents.
    Returns (grid, iso-value through a cell or None, whether the input can show a surface)."""
    kind = pick(rng, ["soup", "soup", "soup", "empty", "points_only", "nan_points", "nan_field",
                      "mixed", "linear_only", "constant"])
    count = 0 if kind in ("empty", "points_only") else int(rng.integers(1, 12))
    grid = vtk.vtkUnstructuredGrid()
    points = vtk.vtkPoints()
    points.SetDataTypeToDouble()
    mids = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    coordinates = []
    for c in range(count):
        verts = rng.uniform(-1, 1, 3) + rng.normal(0, 0.5, (4, 3))
        if np.linalg.det(verts[1:] - verts[0]) < 0:
            verts[[1, 2]] = verts[[2, 1]]
        nodes = list(verts) + [0.5 * (verts[a] + verts[b]) for a, b in mids]
        ids = vtk.vtkIdList()
        for node in nodes:
            ids.InsertNextId(points.InsertNextPoint(*node))
            coordinates.append(node)
        grid.InsertNextCell(24, ids)
    if kind == "points_only":
        for _ in range(5):
            points.InsertNextPoint(*rng.uniform(-1, 1, 3))
    if kind == "mixed" or kind == "linear_only":
        if kind == "linear_only":
            grid = vtk.vtkUnstructuredGrid()
            points = vtk.vtkPoints()
            coordinates = []
        base = points.GetNumberOfPoints()
        for p in rng.uniform(-1, 1, (8, 3)):
            points.InsertNextPoint(*p)
            coordinates.append(p)
        cells = [(12, list(range(8))), (5, [0, 1, 2]), (1, [3])]
        if kind == "mixed":
            cells.append((10, [0, 1, 2, 4]))
        for cell_type, ids in cells:
            grid.InsertNextCell(cell_type, len(ids), [base + i for i in ids])
    grid.SetPoints(points)
    n = points.GetNumberOfPoints()
    centre = rng.uniform(-0.5, 0.5, 3)
    xyz = np.array(coordinates).reshape(-1, 3) if n else np.zeros((0, 3))
    if len(xyz) < n:
        xyz = np.vstack([xyz, np.zeros((n - len(xyz), 3))])
    values = np.sum((xyz - centre) ** 2, axis=1)
    if kind == "constant":
        values[:] = 0.25
    if kind == "nan_field":
        values[:] = np.nan
    field = vtk.vtkDoubleArray()
    field.SetName("f")
    for v in values:
        field.InsertNextValue(v)
    grid.GetPointData().AddArray(field)
    vector = vtk.vtkDoubleArray()
    vector.SetName("vec")
    vector.SetNumberOfComponents(3)
    for p in xyz:
        vector.InsertNextTuple3(*p)
    grid.GetPointData().AddArray(vector)
    cellf = vtk.vtkDoubleArray()
    cellf.SetName("cellf")
    for c in range(grid.GetNumberOfCells()):
        cellf.InsertNextValue(float(c))
    grid.GetCellData().AddArray(cellf)
    if kind == "nan_points":
        for p in range(n):
            points.SetPoint(p, np.nan, np.nan, np.nan)
    iso = None
    if count and kind in ("soup", "mixed"):
        cell = int(rng.integers(count))
        nodal = values[10 * cell:10 * cell + 10]
        iso = float(0.5 * (nodal.min() + nodal.max()))
    case.note("mesh: %s, %d quadratic tets, %d points, %d cells" % (
        kind, count, n, grid.GetNumberOfCells()))
    showable = iso is not None
    return grid, iso, showable


def run_case(seed, index, without, plugin):
    """In pvpython: builds the case, renders it, prints RESULT <json>."""
    import numpy as np
    import paraview.simple as simple
    from paraview.simple import CreateView, LoadPlugin, Render, Show
    from vtkmodules import all as vtk

    case = Case(seed, index, without)
    LoadPlugin(plugin, remote=False, ns={})
    simple._DisableFirstRenderCameraReset()
    rng = case.knob("mesh")
    grid, iso, showable = build_grid(case, rng, vtk, np)
    data = grid
    if (rng := case.knob("multiblock")):
        data = vtk.vtkMultiBlockDataSet()
        layout = pick(rng, ["grid", "grid_and_empty", "empty_only", "none", "nested", "polydata"])
        blocks = {"grid": [grid], "grid_and_empty": [vtk.vtkUnstructuredGrid(), grid],
                  "empty_only": [vtk.vtkUnstructuredGrid()], "none": [],
                  "nested": [None], "polydata": [vtk.vtkPolyData(), grid]}[layout]
        for k, block in enumerate(blocks):
            if block is None:
                inner = vtk.vtkMultiBlockDataSet()
                inner.SetBlock(0, grid)
                block = inner
            data.SetBlock(k, block)
        if layout in ("empty_only", "none"):
            showable = False
        case.note("multiblock: %s" % layout)
    producer = simple.TrivialProducer()
    producer.GetClientSideObject().SetOutput(data)
    producer.UpdatePipeline()

    view = CreateView("RenderView")
    view.ViewSize = [96, 72]
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.0, 0.0, 1.0]
    display = Show(producer, view)
    result = dict(index=index, refusals=[], drawn=[])
    if "Direct Surface" not in display.GetProperty("Representation").Available:
        # (a multiblock with a block of another type: ParaView does not offer it)
        case.note("Direct Surface is not offered for this input")
        result.update(active=case.active, may_hide=True, showable=False, has_cells=False,
                      drawn=[0])
        print("RESULT " + json.dumps(result), flush=True)
        os._exit(0)
    display.SetRepresentationType("Direct Surface")
    display.ContourBy = ["POINTS", "f"]
    display.Isosurfaces = [iso if iso is not None else 0.25]
    display.ColorArrayName = ["POINTS", ""]
    display.DiffuseColor = [1.0, 1.0, 1.0]
    display.AmbientColor = [1.0, 1.0, 1.0]
    Render(view)
    view.ResetCamera()

    def attempt(name, value):
        """Sets a property as a user of pvpython would; ParaView's own refusals are fine."""
        case.note("%s = %r" % (name, value))
        try:
            setattr(display, name, value)
        except Exception as error:  # a refusal by ParaView: loud, not silent
            result["refusals"].append("%s: %s: %s" % (name, type(error).__name__, error))

    def mutate():
        if (rng := case.knob("contour_by")):
            name = pick(rng, ["f", "vec", "cellf", "nope", ""])
            association = pick(rng, ["POINTS", "POINTS", "CELLS"])
            attempt("ContourBy", [association, name])
            if name != "f" or association != "POINTS":
                case.may_hide = case.may_hide or name == ""  # no field chosen: nothing to draw
        if (rng := case.knob("iso_values")):
            kind = pick(rng, ["hostile", "many", "outside", "empty"])
            if kind == "hostile":
                attempt("Isosurfaces", hostile_value(rng, int(rng.integers(1, 4))))
            elif kind == "many":
                attempt("Isosurfaces", list(rng.uniform(0, 3, int(rng.integers(2, 60)))))
            elif kind == "outside":
                attempt("Isosurfaces", [1e6])
            else:
                attempt("Isosurfaces", [])
            case.may_hide = True  # the surface may lie outside the view or the range
        if (rng := case.knob("numbers")):
            for name in ["Opacity", "Ambient", "Diffuse", "Specular", "SpecularPower"]:
                if rng.random() < 0.4:
                    attempt(name, hostile_value(rng, 1))
            case.may_hide = True  # Opacity 0, Diffuse 0 on a black ambient...
        if (rng := case.knob("colors")):
            for name in ["AmbientColor", "DiffuseColor", "SpecularColor"]:
                if rng.random() < 0.5:
                    attempt(name, hostile_value(rng, 3))
            case.may_hide = True  # a blue surface on the blue background
        if (rng := case.knob("lists")):
            for name, per in [("IsoValueColors", 3), ("IsoValueOpacities", 1), ("ClipPlanes", 6)]:
                if rng.random() < 0.5:
                    attempt(name, hostile_value(rng, per * int(rng.integers(0, 4))))
            case.may_hide = True
        if (rng := case.knob("transform")):
            for name in ["Position", "Orientation", "Origin", "Scale"]:
                if rng.random() < 0.4:
                    attempt(name, hostile_value(rng, 3))
            if rng.random() < 0.3:
                attempt("UserTransform", hostile_value(rng, 16))
        if (rng := case.knob("color_by")):
            name = pick(rng, ["f", "vec", "cellf", "nope"])
            association = pick(rng, ["POINTS", "POINTS", "CELLS"])
            try:
                simple.ColorBy(display, (association, name))
                case.note("ColorBy %s %s" % (association, name))
            except Exception as error:
                result["refusals"].append("ColorBy: %s" % error)
            if rng.random() < 0.3:
                attempt("MapScalars", pick(rng, [0, 1, 2, -1]))
            case.may_hide = True
        if (rng := case.knob("camera")):
            position = [hostile_number(rng) if rng.random() < 0.2 else float(x)
                        for x in rng.normal(0, 4, 3)]
            focal = pick(rng, [[0.0, 0.0, 0.0], position, [float(x) for x in rng.normal(0, 1, 3)]])
            attempt_view = [("CameraPosition", position), ("CameraFocalPoint", focal),
                            ("CameraViewUp", pick(rng, [[0, 1, 0], [0, 0, 0], position])),
                            ("CameraViewAngle", pick(rng, [30.0, 1e-6, 179.0, hostile_number(rng)])),
                            ("CameraParallelProjection", pick(rng, [0, 1]))]
            for name, value in attempt_view:
                case.note("view.%s = %r" % (name, value))
                try:
                    setattr(view, name, value)
                except Exception as error:
                    result["refusals"].append("view.%s: %s" % (name, error))

    def render():
        """Renders and counts the pixels that are not the background."""
        Render(view)
        from vtkmodules.util.numpy_support import vtk_to_numpy
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(view.GetRenderWindow())
        grab.ReadFrontBufferOff()
        grab.ShouldRerenderOff()
        grab.Update()
        scalars = grab.GetOutput().GetPointData().GetScalars()
        pixels = vtk_to_numpy(scalars).reshape(-1, scalars.GetNumberOfComponents())
        drawn = int(np.sum(np.any(pixels[:, :3] != (0, 0, 255), axis=1)))
        result["drawn"].append(drawn)
        case.note("render: %d pixels drawn" % drawn)

    render()
    mutate()
    render()
    if (rng := case.knob("renders")):
        for _ in range(int(rng.integers(1, 4))):
            kind = pick(rng, ["again", "hide_show", "reset_camera", "resize", "modified"])
            case.note("between renders: %s" % kind)
            if kind == "hide_show":
                simple.Hide(producer, view)
                Render(view)
                simple.Show(producer, view)
            elif kind == "reset_camera":
                view.ResetCamera()
            elif kind == "resize":
                view.ViewSize = [int(rng.integers(1, 160)), int(rng.integers(1, 120))]
                case.may_hide = True
            elif kind == "modified":
                grid.Modified()
                producer.MarkModified(producer)
            render()
    result.update(active=case.active, may_hide=case.may_hide, showable=showable,
                  has_cells=grid.GetNumberOfCells() > 0)
    print("RESULT " + json.dumps(result), flush=True)
    # Leave without ParaView's teardown: Mesa's GLX sometimes fails it (GLXBadContext) after
    # the case is over, which is no finding of the case's.
    os._exit(0)


# ---------------------------------------------------------------------------------------------
# The parent: X servers, one process per case, verdicts

class Display:
    """A private Xvfb (never the shared :99), started on a free display number."""

    def __init__(self):
        read, write = os.pipe()
        self.proc = subprocess.Popen(
            ["Xvfb", "-displayfd", str(write), "-screen", "0", "1280x1024x24", "-nolisten", "tcp"],
            pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            start_new_session=True)
        os.close(write)
        with os.fdopen(read) as f:
            self.name = ":" + f.readline().strip()

    def close(self):
        self.proc.terminate()
        self.proc.wait()


def run_one(args, display, index, without):
    """One case in its own pvpython on `display`; retried only when X refused it."""
    command = ["pvpython", os.path.abspath(__file__), "--case", "--plugin", args.plugin,
               "--seed", str(args.seed), "--replay", str(index)]
    if without:  # (pvpython aborts on an empty argument)
        command += ["--without", ",".join(without)]
    env = dict(os.environ, DISPLAY=display.name)
    for attempt in range(3):
        started = time.time()
        proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                env=env, start_new_session=True)
        try:
            output, _ = proc.communicate(timeout=args.timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            output, _ = proc.communicate()
            return dict(status="hang", signature="hang (> %g s)" % args.timeout,
                        output=output.decode(errors="replace")[-3000:])
        text = output.decode(errors="replace")
        if proc.returncode != 0 and x_refused(text):
            time.sleep(1.0)
            continue
        return verdict(text, proc.returncode, time.time() - started)
    return dict(status="xrefused", output=text[-2000:])


def x_refused(text):
    """The X server refused or dropped the case's connection: VTK says so, or the case died in
    Xlib (XSync, from the interactor's first render: seed 3131 case 175, which replays clean)
    with no TetDSR frame on the stack."""
    frames = [line for line in text.splitlines() if re.search(r"0x[0-9a-f]+ ", line)]
    in_xlib = any("XSync" in f for f in frames[-4:])  # (Loguru lists the innermost last)
    ours = any("DirectSurface" in f or "tetdsr" in f for f in frames)
    return any(r in text for r in X_REFUSALS) or (in_xlib and not ours)


def verdict(text, returncode, seconds):
    lines = [re.sub(r"\x1b\[[0-9;]*m", "", line) for line in text.splitlines()]
    messages = [line.split("|", 1)[-1].strip() for line in lines if MESSAGE.search(line)]
    result = next((json.loads(line[7:]) for line in lines if line.startswith("RESULT ")), None)
    crashed = returncode < 0 or any(t in text for t in CRASH_TEXT)
    if crashed:
        kind = "signal %s" % signal.Signals(-returncode).name if returncode < 0 else next(
            t for t in CRASH_TEXT if t in text)
        return dict(status="crash", signature="crash: " + kind, output=text[-3000:])
    if result is None or returncode != 0:
        trace = [line for line in lines if line.strip()][-6:]
        return dict(status="harness", signature="harness: " + (trace[-1] if trace else "?"),
                    output=text[-3000:])
    result.update(status="ok", messages=messages[:5], seconds=round(seconds, 2))
    silent = (result["drawn"][-1] == 0 and not messages and result["has_cells"] and
              not result["may_hide"] and not result["refusals"])
    if silent:
        result.update(status="silent", signature="silent: nothing drawn, no message")
    elif messages or result["refusals"]:
        result["status"] = "refused"
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--plugin", required=True, help="path of TetDSR.so")
    parser.add_argument("--seed", type=int, default=None)
    parser.add_argument("--cases", type=int, default=None)
    parser.add_argument("--minutes", type=float, default=None)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per case")
    parser.add_argument("--jobs", type=int, default=1, help="cases at a time (an X server each)")
    parser.add_argument("--first", type=int, default=0)
    parser.add_argument("--out", default="fuzz-representation-failures")
    parser.add_argument("--replay", type=int, default=None, help="run one case and show it")
    parser.add_argument("--without", default="", help="knobs to switch off, comma-separated")
    parser.add_argument("--case", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.seed is None:
        args.seed = int(time.time()) % 1000000
    without = [k for k in args.without.split(",") if k]
    if args.case:
        return run_case(args.seed, args.replay, without, args.plugin)
    if not shutil.which("pvpython") or not shutil.which("Xvfb"):
        print("fuzz_representation: pvpython and Xvfb must be on PATH", file=sys.stderr)
        return 2

    displays = [Display() for _ in range(args.jobs)]
    try:
        if args.replay is not None:
            result = run_one(args, displays[0], args.replay, without)
            print(result.pop("output", ""))
            print(json.dumps(result, indent=1))
            return 0 if result["status"] in ("ok", "refused") else 1
        return fuzz(args, displays, without)
    finally:
        for display in displays:
            display.close()


def fuzz(args, displays, without):
    from concurrent.futures import ThreadPoolExecutor
    stop_at = time.time() + 60 * args.minutes if args.minutes else None
    count = args.cases if args.cases is not None else (None if stop_at else 20)
    tally = dict(cases=0, ok=0, refused=0, crash=0, hang=0, silent=0, harness=0, xrefused=0)
    classes, messages = {}, {}
    started = time.time()
    print("fuzz_representation: seed %d, %s, timeout %g s, %d job(s)" % (
        args.seed, "%d cases" % count if count is not None else "%g minutes" % args.minutes,
        args.timeout, args.jobs), flush=True)
    next_index = [args.first]
    lock = threading.Lock()

    def worker(display):
        while True:
            with lock:
                index = next_index[0]
                if (count is not None and index >= args.first + count) or \
                        (stop_at and time.time() > stop_at):
                    return
                next_index[0] += 1
            result = run_one(args, display, index, without)
            tally["cases"] += 1
            tally[result["status"]] += 1
            for message in result.get("messages", []):
                key = re.sub(r"\(0x[0-9a-f]+\)|-?\d[\d.e+-]*|'[^']*'", "#", message)[:100]
                messages[key] = messages.get(key, 0) + 1
            if result["status"] in ("crash", "hang", "silent", "harness"):
                entry = classes.setdefault(result["signature"], dict(count=0, first=index))
                entry["count"] += 1
                os.makedirs(args.out, exist_ok=True)
                result.update(seed=args.seed, index=index, replay="%s %s --plugin %s --seed %d "
                              "--replay %d" % (sys.executable, os.path.abspath(__file__),
                                               args.plugin, args.seed, index))
                with open(os.path.join(args.out, "seed%d-case%d.json" % (args.seed, index)),
                          "w") as f:
                    json.dump(result, f, indent=1)
                print("case %d: %s" % (index, result["signature"]), flush=True)

    with ThreadPoolExecutor(len(displays)) as pool:
        list(pool.map(worker, displays))
    elapsed = time.time() - started
    header = ("cases", "drawn", "refused", "crashes", "hangs", "silent", "harness", "xrefused",
              "seconds")
    print("\n" + " ".join("%-9s" % h for h in header))
    print(" ".join("%-9d" % v for v in (
        tally["cases"], tally["ok"], tally["refused"], tally["crash"], tally["hang"],
        tally["silent"], tally["harness"], tally["xrefused"], elapsed)))
    print("(drawn: no message and no failure; refused: a Direct Surface message or a refusal by "
          "ParaView; xrefused: the X server refused all three attempts)")
    print("\nDirect Surface messages by kind:")
    for key, n in sorted(messages.items(), key=lambda e: -e[1])[:15]:
        print("  %5d  %s" % (n, key))
    if classes:
        print("\nDistinct failures (count, first case):")
        for sig, entry in sorted(classes.items(), key=lambda e: -e[1]["count"]):
            print("  %4d  case %-6d %s" % (entry["count"], entry["first"], sig))
        print("Failing cases written to %s/" % args.out)
    return 1 if classes else 0


if __name__ == "__main__":
    sys.exit(main())
