"""The interactive frame rate of the "Direct Surface" representation in the ParaView GUI, read
from ParaView's own timer log (Tools > Timer Log), with a screenshot of the X screen taken in the
middle of the mouse drag. A measurement, not a test.

Usage (an X display is needed, e.g. under xvfb-run; the build must have run cmake; Linux x86-64):
  xvfb-run -a -s "-screen 0 1600x1000x24" /usr/bin/python3 Testing/Plugin/gui_frame_rate.py \
      [build directory] [view width] [view height] [mouse moves] \
      [--data FILE.vtu --array NAME --iso VALUE --color NAME] [--screenshot FILE.png]

It replays the GUI test's events (build/Testing/Plugin/gui_representation.xml: load the plugin
through the plugin manager, open Data/expansion_flow.vtu, pick "Direct Surface", speed = 0.25,
Color By pressure; --data, --array, --iso and --color replace the file, the contoured array, the
iso-value and the colouring array) in a main window as large as the X screen (Qt's -geometry),
with the view locked to width x height (default 640 x 480; ParaView shrinks a view larger than
the space its panels leave: on a 1600 x 1000 screen 1330 x 660 became 1292 x 660). It opens the
timer log with every event shown (no time threshold) and a buffer long enough for the whole drag,
clears it and closes it (it would cover the view; the log goes on), drags the mouse around the
view (a rotation: one interactive render per move, default 120), releases the button, saves the
timer log and prints the interactive render times and the still render that follows the release.
The cells are counted from the .vtu's <Piece NumberOfCells=...> headers.

Half way through the drag, with the button still down, the playback pauses (a "pause" event:
the GUI thread sleeps PAUSE_MS). A thread of this script sees the GUI thread in that sleep for
SLEEP_POLLS polls (/proc/<pid>/syscall: nanosleep or clock_nanosleep) and grabs the X screen
through the X connection it opened before ParaView started (Xvfb refuses some simultaneous
connections), so the PNG shows the last interactive frame as the GUI displays it. The pause is
outside the timed renders. Default PNG: gui_mid_drag.png beside the saved timer log.
"""
import argparse
import ctypes
import math
import os
import re
import statistics
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zlib

PAUSE_MS = 3000
SLEEP_SYSCALLS = ("35", "230")  # x86-64 nanosleep, clock_nanosleep
SLEEP_POLLS = 25                # consecutive 20 ms polls in the sleep before the screen is grabbed


class XImage(ctypes.Structure):
    """The leading fields of Xlib's XImage (enough to read the pixels)."""
    _fields_ = [("width", ctypes.c_int), ("height", ctypes.c_int), ("xoffset", ctypes.c_int),
                ("format", ctypes.c_int), ("data", ctypes.c_void_p),
                ("byte_order", ctypes.c_int), ("bitmap_unit", ctypes.c_int),
                ("bitmap_bit_order", ctypes.c_int), ("bitmap_pad", ctypes.c_int),
                ("depth", ctypes.c_int), ("bytes_per_line", ctypes.c_int),
                ("bits_per_pixel", ctypes.c_int), ("red_mask", ctypes.c_ulong),
                ("green_mask", ctypes.c_ulong), ("blue_mask", ctypes.c_ulong)]


class Screen:
    """One X connection, opened once, that grabs the root window as a PNG."""

    def __init__(self):
        self.xlib = ctypes.CDLL("libX11.so.6")
        self.xlib.XOpenDisplay.restype = ctypes.c_void_p
        self.xlib.XOpenDisplay.argtypes = [ctypes.c_char_p]
        self.xlib.XDefaultRootWindow.restype = ctypes.c_ulong
        self.xlib.XDefaultRootWindow.argtypes = [ctypes.c_void_p]
        self.xlib.XDisplayWidth.argtypes = self.xlib.XDisplayHeight.argtypes = [
            ctypes.c_void_p, ctypes.c_int]
        self.xlib.XGetImage.restype = ctypes.POINTER(XImage)
        self.xlib.XGetImage.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int,
                                        ctypes.c_int, ctypes.c_uint, ctypes.c_uint,
                                        ctypes.c_ulong, ctypes.c_int]
        self.xlib.XDestroyImage.argtypes = [ctypes.POINTER(XImage)]
        self.display = self.xlib.XOpenDisplay(None)
        if not self.display:
            sys.exit(f"cannot open the X display {os.environ.get('DISPLAY')!r}")
        self.width = self.xlib.XDisplayWidth(self.display, 0)
        self.height = self.xlib.XDisplayHeight(self.display, 0)

    def grab_png(self, path):
        """Writes the screen to path as a PNG; returns whether it is all one colour (blank)."""
        image = self.xlib.XGetImage(self.display, self.xlib.XDefaultRootWindow(self.display), 0, 0,
                                    self.width, self.height, ctypes.c_ulong(-1).value, 2)  # ZPixmap
        if not image:
            raise RuntimeError("XGetImage failed")
        try:
            im = image.contents
            if (im.bits_per_pixel, im.byte_order, im.red_mask, im.green_mask, im.blue_mask) != (
                    32, 0, 0xFF0000, 0xFF00, 0xFF):
                raise RuntimeError("not a 32-bit BGRX screen (run Xvfb with -screen 0 WxHx24)")
            stride = im.bytes_per_line
            data = ctypes.string_at(im.data, stride * self.height)
        finally:
            self.xlib.XDestroyImage(image)
        bgrx = b"".join(data[y * stride:y * stride + 4 * self.width] for y in range(self.height))
        rgb = bytearray(3 * self.width * self.height)
        rgb[0::3], rgb[1::3], rgb[2::3] = bgrx[2::4], bgrx[1::4], bgrx[0::4]
        lines = b"".join(b"\0" + rgb[y * 3 * self.width:(y + 1) * 3 * self.width]
                         for y in range(self.height))

        def chunk(tag, body):
            return (struct.pack(">I", len(body)) + tag + body
                    + struct.pack(">I", zlib.crc32(tag + body)))

        with open(path, "wb") as out:
            out.write(b"\x89PNG\r\n\x1a\n"
                      + chunk(b"IHDR", struct.pack(">IIBBBBB", self.width, self.height, 8, 2, 0,
                                                   0, 0))
                      + chunk(b"IDAT", zlib.compress(bytes(lines), 6)) + chunk(b"IEND", b""))
        return rgb.count(rgb[:3]) == self.width * self.height


def grab_when_paused(process, screen, path, result):
    """Grabs the screen once the GUI thread has slept for SLEEP_POLLS polls (the pause event)."""
    streak = 0
    while process.poll() is None:
        try:
            with open(f"/proc/{process.pid}/syscall") as status:
                call = status.read().split()[0]
        except OSError:
            return
        streak = streak + 1 if call in SLEEP_SYSCALLS else 0
        if streak == SLEEP_POLLS:
            result.append(path + (" (BLANK: one colour)" if screen.grab_png(path) else ""))
            return
        time.sleep(0.02)


def set_argument(events, object_suffix, command, value):
    """Sets the arguments of the one event on an object whose name ends with object_suffix."""
    pattern = re.compile(rf'(object="[^"]*{re.escape(object_suffix)}" command="{command}" '
                         rf'arguments=")[^"]*"')
    events, count = pattern.subn(lambda m: m.group(1) + value + '"', events)
    if count != 1:
        sys.exit(f"{count} events '{command}' on ...{object_suffix} in the GUI test's events")
    return events


parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("build", nargs="?", default="build")
parser.add_argument("width", nargs="?", type=int, default=640)
parser.add_argument("height", nargs="?", type=int, default=480)
parser.add_argument("moves", nargs="?", type=int, default=120)
parser.add_argument("--data", help=".vtu file to open (default: the GUI test's expansion flow)")
parser.add_argument("--array", default="speed", help="point array to contour (default speed)")
parser.add_argument("--iso", type=float, default=0.25, help="iso-value (default 0.25)")
parser.add_argument("--color", default="pressure",
                    help="point array to colour by (default pressure)")
parser.add_argument("--screenshot", help="PNG of the X screen mid-drag")
args = parser.parse_args()

events = open(os.path.join(args.build, "Testing/Plugin/gui_representation.xml")).read()
if args.data:
    events = set_argument(events, "/FileOpenDialog", "filesSelected", os.path.abspath(args.data))
data = re.search(r'FileOpenDialog" command="filesSelected" arguments="([^"]*)"', events).group(1)
properties = "DisplayFrame/ProxyPanel/"
events = set_argument(events, properties + "ContourBy/ComboBox", "activated", args.array)
events = set_argument(events, "/1QExpandingLineEdit0", "set_string", str(args.iso))
events = set_argument(events, properties + "Isosurfaces/ScalarValueList/Table", "editAccepted",
                      f"0.0,{args.iso}")
events = set_argument(events, "/displayColor/Variables", "activated", args.color)
events = events.replace(
    'arguments="actionTesting_Window_Size" />',
    f'''arguments="actionTesting_Window_Size_Custom" />
  <pqevent object="pqClientMainWindow/pqLockViewSizeCustomDialog/Width" command="set_string" arguments="{args.width}" />
  <pqevent object="pqClientMainWindow/pqLockViewSizeCustomDialog/Height" command="set_string" arguments="{args.height}" />
  <pqevent object="pqClientMainWindow/pqLockViewSizeCustomDialog/ButtonBox/1QPushButton0" command="activate" arguments="" />''')
viewport = ("pqClientMainWindow/centralwidget/MultiViewWidget/CoreWidget/qt_tabwidget_stackedwidget/"
            "MultiViewWidget1/Container/Frame.0/CentralWidgetFrame/Viewport")
log = os.path.join(tempfile.mkdtemp(prefix="tetdsr-timer-log-"), "timer_log.txt")
screenshot = os.path.abspath(args.screenshot or os.path.join(os.path.dirname(log),
                                                             "gui_mid_drag.png"))
drag = [f'<pqevent object="{viewport}" command="mousePress" arguments="(0.5,0.5,1,1,0)" />']
for k in range(1, args.moves + 1):
    angle = 2 * math.pi * k / args.moves  # a figure of eight around the centre: rotations both ways
    drag.append(f'<pqevent object="{viewport}" command="mouseMove" arguments='
                f'"({0.5 + 0.3 * math.sin(angle):.4f},{0.5 + 0.2 * math.sin(2 * angle):.4f},1,0,0)" />')
    if k == args.moves // 2:
        drag.append(f'<pqevent object="{viewport}" command="pause" arguments="{PAUSE_MS}" />')
drag.append(f'<pqevent object="{viewport}" command="mouseRelease" arguments="(0.5,0.5,1,0,0)" />')
open_timer_log = [
    '<pqevent object="pqClientMainWindow/menubar" command="activate" arguments="menuTools" />',
    '<pqevent object="pqClientMainWindow/menubar/menuTools" command="activate" arguments="actionToolsTimerLog" />']
tail = "\n".join([
    *open_timer_log,
    '<pqevent object="pqTimerLogDisplay/timeThreshold" command="activated" arguments="Show All" />',
    '<pqevent object="pqTimerLogDisplay/bufferLength" command="activated" arguments="5000" />',
    '<pqevent object="pqTimerLogDisplay/clearButton" command="activate" arguments="" />',
    '<pqevent object="pqTimerLogDisplay/buttonBox/1QPushButton0" command="activate" arguments="" />',
    *drag,
    *open_timer_log,
    '<pqevent object="pqTimerLogDisplay/refreshButton" command="activate" arguments="" />',
    '<pqevent object="pqTimerLogDisplay/saveButton" command="activate" arguments="" />',
    f'<pqevent object="pqTimerLogDisplay/TimerLogSaveDialog" command="filesSelected" arguments="{log}" />',
])
events = events.replace("</pqevents>", tail + "\n</pqevents>")
script = os.path.join(os.path.dirname(log), "frame_rate.xml")
with open(script, "w") as out:
    out.write(events)
screen = Screen()
grabbed = []
paraview = subprocess.Popen(["paraview", "--dr", "-geometry", f"{screen.width}x{screen.height}+0+0",
                             f"--test-script={script}", "--exit"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
watcher = threading.Thread(target=grab_when_paused, args=(paraview, screen, screenshot, grabbed))
watcher.start()
if paraview.wait():
    sys.exit(f"paraview failed (exit code {paraview.returncode}); events: {script}")
watcher.join()

text = open(log).read()
times = [float(t) for t in re.findall(r"^Interactive Render,\s+([0-9.e+-]+) seconds", text, re.M)]
still = re.findall(r"^Still Render,\s+([0-9.e+-]+) seconds", text, re.M)
if len(times) < 2:
    sys.exit(f"fewer than 2 interactive renders in the timer log {log}")
vtu = open(data, errors="replace").read()
cells = sum(int(n) for n in re.findall(r'<Piece\b[^>]*\bNumberOfCells="(\d+)"', vtu))
median = statistics.median(times)
still_ms = f"{1e3 * float(still[-1]):.1f}" if still else "none in the log"
print(f"timer log: {log}; events: {script}")
print("| view | dataset | cells | interactive renders | median / p90 / max ms | fps (median) "
      "| still render after release ms |")
print("|---|---|---|---|---|---|---|")
print(f"| {args.width} x {args.height} | {os.path.basename(data)} ({args.array} = {args.iso}) "
      f"| {cells:,} | {len(times)} | {1e3 * median:.1f} / "
      f"{1e3 * statistics.quantiles(times, n=10)[-1]:.1f} / {1e3 * max(times):.1f} "
      f"| {1 / median:.1f} | {still_ms} |")
print(f"mid-drag screenshot (after move {args.moves // 2} of {args.moves}, button down): "
      f"{grabbed[0] if grabbed else 'NOT TAKEN'}")
