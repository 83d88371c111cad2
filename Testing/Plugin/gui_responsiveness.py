"""How long the ParaView GUI stays unresponsive after a user's action on a "Direct Surface"
representation, measured as a user would feel it: right after each action an X client clicks the
File menu and times how long the GUI takes to open it; and how long until the refined
(full-resolution) frame is shown. A test with --limit (it fails when, in an action listed by
--check, the mapper's render keeps the GUI thread longer than the limit without leaving its full
cast to the background, or the menu opens more
than the limit and MENU_SLACK after the idle GUI's time, or a screenshot taken at once after a
change differs from one of the refined view), a measurement otherwise.

Usage (Linux; Xvfb, openbox and xdotool on PATH; the build must have run cmake):
  /usr/bin/python3 Testing/Plugin/gui_responsiveness.py PLUGIN DATA.vtu ARRAY ISO_SHOWN
      ISO_CHANGED[,ISO_CHANGED...] COLOR_ARRAY [--size 1148 746] [--limit SECONDS --check iso,colour]
      [--json FILE]

It starts a private X server (Xvfb, 1600 x 1000 x 24, on a free display number) with openbox,
and the paraview client (--dr) with gui_responsiveness_actions.py as its --script, which plays
the actions (show, iso, colour, reset, wheel, screenshot) from a timer of the GUI's event loop
and logs when each starts, returns and shows its refined frame. For each action this script,
once it reads the start in the log, clicks the File menu (xdotool, at the menu bar's left end)
and polls for the menu's pop-up window (a new visible window of the client); the time from the
action's start to the pop-up is the GUI's answer. For "wheel" this script turns the mouse wheel
itself (3 notches forward, --wheel-notches: zooming in, over the view), then clicks. The File
menu is first opened 3 times with the GUI idle: the median is the floor of the measurement (X,
Qt and the machine's load), which --limit allows beyond.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

from mpi_private_displays import start_server, stop_server

HERE = os.path.dirname(os.path.abspath(__file__))
ACTIONS = ("show", "iso", "colour", "reset", "wheel", "screenshot")
MENU_TIMEOUT = 60.0  # seconds to wait for the File menu before calling the GUI hung
MENU_SLACK = 1.0  # seconds of ParaView's own work (and a loaded machine's) an action may add to the
# File menu's answer


def xdotool(*args, check=True):
    result = subprocess.run(["xdotool", *args], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise RuntimeError(f"xdotool {' '.join(args)}: {result.stderr.strip()}")
    return result.stdout.split()


def start_display():
    """A private Xvfb (mpi_private_displays.start_server: a display of its own, stopped so that it
    removes its lock file) with openbox; returns (display, server, window manager)."""
    server, display = start_server(screen="1600x1000x24")
    manager = subprocess.Popen(["openbox"], env={**os.environ, "DISPLAY": display},
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(0.5)
    return display, server, manager


class Gui:
    """The paraview client, its log and its control file."""

    def __init__(self, args, work):
        self.log_path = os.path.join(work, "gui.log")
        self.control_path = os.path.join(work, "control")
        open(self.log_path, "w").close()
        with open(self.control_path, "w") as control:
            control.write("0")
        self.acknowledged = 0
        # The mapper's Python class (its own methods) is beside the plugin in the build.
        build_lib = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(
            os.path.abspath(args.plugin)))))
        python_path = os.pathsep.join(p for p in (os.path.join(build_lib, "python3", "dist-packages"),
                                                  os.environ.get("PYTHONPATH")) if p)
        environment = {**os.environ, "PYTHONPATH": python_path,
                       "TETDSR_PLUGIN": os.path.abspath(args.plugin),
                       "TETDSR_GUI_DATA": os.path.abspath(args.data),
                       "TETDSR_GUI_ARRAY": args.array,
                       "TETDSR_GUI_ISO": f"{args.iso_shown} {','.join(str(float(v)) for v in args.iso_changed.split(','))}",
                       "TETDSR_GUI_COLOR": args.color,
                       "TETDSR_GUI_SIZE": f"{args.size[0]} {args.size[1]}",
                       "TETDSR_GUI_LOG": self.log_path, "TETDSR_GUI_CONTROL": self.control_path}
        self.process = subprocess.Popen(
            ["paraview", "--dr", f"--script={os.path.join(HERE, 'gui_responsiveness_actions.py')}"],
            env=environment, stdout=open(os.path.join(work, "paraview.out"), "w"),
            stderr=subprocess.STDOUT)

    def lines(self):
        with open(self.log_path) as log:
            return [line.split() for line in log if line.endswith("\n")]

    def wait_for(self, word, action=None, timeout=120.0):
        """The log line `word [action] ...`, waiting for it; exits if the GUI failed or quit."""
        end = time.time() + timeout
        while time.time() < end:
            for line in self.lines():
                if line[0] == "failed":
                    sys.exit("the GUI's script failed: " + " ".join(line[1:]))
                if line[0] == word and (action is None or line[1] == action):
                    return line
            if self.process.poll() is not None:
                sys.exit(f"paraview quit (status {self.process.returncode}) before '{word} {action}'")
            time.sleep(0.002)
        sys.exit(f"no '{word} {action or ''}' in the GUI's log after {timeout} s")

    def acknowledge(self):
        self.acknowledged += 1
        with open(self.control_path + ".new", "w") as control:
            control.write(str(self.acknowledged))
        os.replace(self.control_path + ".new", self.control_path)


def main_window():
    """The client's main window id and its geometry (x, y, width, height)."""
    for _ in range(600):
        ids = xdotool("search", "--onlyvisible", "--name", "ParaView", check=False)
        for window in ids:
            words = xdotool("getwindowgeometry", "--shell", window)
            geometry = dict(word.split("=") for word in words)
            if int(geometry["WIDTH"]) > 800:
                return window, [int(geometry[k]) for k in ("X", "Y", "WIDTH", "HEIGHT")]
        time.sleep(0.1)
    sys.exit("no ParaView main window")


def visible_windows(pid):
    return set(xdotool("search", "--onlyvisible", "--pid", str(pid), check=False))


def open_file_menu(gui, geometry, since):
    """Clicks File, waits for the menu's pop-up, closes it; seconds from `since` to the pop-up."""
    before = visible_windows(gui.process.pid)
    x, y = geometry[0] + 20, geometry[1] + 12  # the menu bar's first entry
    xdotool("mousemove", str(x), str(y), "click", "1")
    end = time.time() + MENU_TIMEOUT
    while time.time() < end:
        if visible_windows(gui.process.pid) - before:
            answered = time.time() - since
            xdotool("key", "Escape")
            for _ in range(200):  # (closed before the next action)
                if not visible_windows(gui.process.pid) - before:
                    break
                time.sleep(0.01)
            return answered
        time.sleep(0.002)
    sys.exit(f"the File menu did not open within {MENU_TIMEOUT} s")


def main_thread_cpu(pid):
    """The GUI thread's CPU seconds so far (utime + stime of the process's first thread)."""
    with open(f"/proc/{pid}/task/{pid}/stat") as stat:
        fields = stat.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def measure(args):
    work = tempfile.mkdtemp(prefix="tetdsr-gui-responsiveness-")
    display, server, manager = start_display()
    os.environ["DISPLAY"] = display
    gui = Gui(args, work)
    results = {"log": gui.log_path}
    try:
        gui.wait_for("ready", timeout=180)
        window, geometry = main_window()
        time.sleep(1.0)
        idle = []
        for _ in range(3):
            idle.append(open_file_menu(gui, geometry, time.time()))
            time.sleep(0.2)
        results["idle"] = sorted(idle)[1]
        gui.acknowledge()
        for action in ACTIONS:
            start = float(gui.wait_for("start", action)[2])
            if action == "wheel":
                # (the view's centre: the main window's centre is within it on this layout)
                xdotool("mousemove", str(geometry[0] + geometry[2] * 2 // 3),
                        str(geometry[1] + geometry[3] // 2))
                start = time.time()
                xdotool("click", "--repeat", str(args.wheel_notches), "--delay", "30", "4")
            cpu = main_thread_cpu(gui.process.pid)
            answered = open_file_menu(gui, geometry, start)
            cpu = main_thread_cpu(gui.process.pid) - cpu
            returned_line = gui.wait_for("returned", action)
            returned = float(returned_line[2])
            render = (float(returned_line[returned_line.index("seconds") + 1])
                      if "seconds" in returned_line else 0.0)
            refining = ("refining" in returned_line and
                        int(returned_line[returned_line.index("refining") + 1]) == 1)
            refined = gui.wait_for("refined", action, timeout=180)
            results[action] = {"menu": answered, "gui_cpu": cpu, "render": render,
                               "refining": refining, "returned": returned - start,
                               "refined": float(refined[2]) - start,
                               "cast": [int(refined[3]), int(refined[4])]}
            if action == "screenshot":
                line = gui.wait_for("screenshot")
                results["screenshot"]["capture"] = {"refining": int(line[1]), "differing": int(line[2])}
            gui.acknowledge()
        gui.process.wait(timeout=60)
    finally:
        if gui.process.poll() is None:
            gui.process.kill()
        manager.terminate()
        stop_server(server)
    return results


parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("plugin")
parser.add_argument("data")
parser.add_argument("array")
parser.add_argument("iso_shown", type=float)
parser.add_argument("iso_changed", help="the iso-values it changes to, comma-separated")
parser.add_argument("color")
parser.add_argument("--size", nargs=2, type=int, default=[1148, 746])
parser.add_argument("--limit", type=float, help="seconds the GUI may take to open the File menu")
parser.add_argument("--check", default="iso", help="the actions --limit applies to (comma-separated)")
parser.add_argument("--wheel-notches", type=int, default=3, help="notches of the wheel zoom")
parser.add_argument("--json", help="write the results there")
args = parser.parse_args()
for tool in ("Xvfb", "openbox", "xdotool", "xdpyinfo", "paraview"):
    if not shutil.which(tool):
        sys.exit(f"{tool} is not on PATH (Debian: xvfb, openbox, xdotool, x11-utils, paraview)")

results = measure(args)
print(f"File menu with the GUI idle: {results['idle']:.3f} s (the median of 3: the floor); log "
      f"{results['log']}")
print("| action | File menu opened after s | GUI thread's CPU s until then | action returned after s "
      "| the mapper's render in it s | refined frame after s | cast |")
print("|---|---|---|---|---|---|---|")
for action in ACTIONS:
    r = results[action]
    print(f"| {action} | {r['menu']:.2f} | {r['gui_cpu']:.2f} | {r['returned']:.2f} "
          f"| {r['render']:.3f} | {r['refined']:.2f} "
          f"| {r['cast'][0]} x {r['cast'][1]} |")
capture = results["screenshot"]["capture"]
print(f"SaveScreenshot right after a change (the view {'refining' if capture['refining'] else 'not refining'}): "
      f"{capture['differing']} pixels differ from the refined view's screenshot")
if args.json:
    with open(args.json, "w") as out:
        json.dump(results, out, indent=1)
if args.limit is not None:
    # No render of the mapper keeps the GUI thread longer than the limit: a render over it must
    # have left its full cast to the background (a coarse frame shown, the view refining; on a
    # loaded machine a coarse frame may itself take longer), and the GUI answers within
    # MENU_SLACK of the limit beyond the idle GUI's time (ParaView's own work for an action, its
    # panels and its second render, took 0.15 to 0.5 s here on 2 loaded cores).
    slow = []
    if not capture["refining"] or capture["differing"] != 0:
        slow.append("a screenshot taken while the view refined is not the refined view's "
                    f"(refining {capture['refining']}, {capture['differing']} pixels differ)")
    for a in args.check.split(","):
        r = results[a]
        if r["render"] > args.limit and not r["refining"]:
            slow.append(f"{a}: the mapper's render took {r['render']:.2f} s on the GUI thread "
                        "and left nothing to refine (a full cast on the GUI thread)")
        if r["menu"] - results["idle"] > args.limit + MENU_SLACK:
            slow.append(f"{a}: the File menu opened after {r['menu']:.2f} s "
                        f"({r['menu'] - results['idle']:.2f} s beyond the idle GUI's {results['idle']:.2f} s)")
    if slow:
        sys.exit(f"the GUI was kept busy (limit {args.limit} s a render, {args.limit + MENU_SLACK} s "
                 "to answer): " + "; ".join(slow))
    print(f"every checked action ({args.check}) kept the GUI thread at most {args.limit} s in a "
          f"render and let it answer within {args.limit + MENU_SLACK} s beyond the idle GUI's time")
