"""The interactive frame rate of the "Direct Surface" representation in the ParaView GUI, read
from ParaView's own timer log (Tools > Timer Log). A measurement, not a test.

Usage (an X display is needed, e.g. under xvfb-run; the build must have run cmake):
  xvfb-run -a -s "-screen 0 1600x1000x24" /usr/bin/python3 Testing/Plugin/gui_frame_rate.py \
      [build directory] [view width] [view height] [mouse moves]

It replays the GUI test's events (build/Testing/Plugin/gui_representation.xml: load the plugin
through the plugin manager, open Data/expansion_flow.vtu, pick "Direct Surface", speed = 0.25,
Color By pressure) with the view locked to width x height (default 640 x 480), clears the timer
log, drags the mouse around the view (a rotation: one interactive render per move, default 120),
saves the timer log and prints the interactive render times.
"""
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile

build = sys.argv[1] if len(sys.argv) > 1 else "build"
width, height = (int(sys.argv[2]), int(sys.argv[3])) if len(sys.argv) > 3 else (640, 480)
moves = int(sys.argv[4]) if len(sys.argv) > 4 else 120

events = open(os.path.join(build, "Testing/Plugin/gui_representation.xml")).read()
events = events.replace(
    'arguments="actionTesting_Window_Size" />',
    f'''arguments="actionTesting_Window_Size_Custom" />
  <pqevent object="pqClientMainWindow/pqLockViewSizeCustomDialog/Width" command="set_string" arguments="{width}" />
  <pqevent object="pqClientMainWindow/pqLockViewSizeCustomDialog/Height" command="set_string" arguments="{height}" />
  <pqevent object="pqClientMainWindow/pqLockViewSizeCustomDialog/ButtonBox/1QPushButton0" command="activate" arguments="" />''')
viewport = ("pqClientMainWindow/centralwidget/MultiViewWidget/CoreWidget/qt_tabwidget_stackedwidget/"
            "MultiViewWidget1/Container/Frame.0/CentralWidgetFrame/Viewport")
log = os.path.join(tempfile.mkdtemp(prefix="tetdsr-timer-log-"), "timer_log.txt")
drag = [f'<pqevent object="{viewport}" command="mousePress" arguments="(0.5,0.5,1,1,0)" />']
for k in range(1, moves + 1):
    angle = 2 * math.pi * k / moves  # a figure of eight around the centre: rotations both ways
    drag.append(f'<pqevent object="{viewport}" command="mouseMove" arguments='
                f'"({0.5 + 0.3 * math.sin(angle):.4f},{0.5 + 0.2 * math.sin(2 * angle):.4f},1,0,0)" />')
drag.append(f'<pqevent object="{viewport}" command="mouseRelease" arguments="(0.5,0.5,1,0,0)" />')
tail = "\n".join([
    '<pqevent object="pqClientMainWindow/menubar" command="activate" arguments="menuTools" />',
    '<pqevent object="pqClientMainWindow/menubar/menuTools" command="activate" arguments="actionToolsTimerLog" />',
    '<pqevent object="pqTimerLogDisplay/clearButton" command="activate" arguments="" />',
    *drag,
    '<pqevent object="pqTimerLogDisplay/refreshButton" command="activate" arguments="" />',
    '<pqevent object="pqTimerLogDisplay/saveButton" command="activate" arguments="" />',
    f'<pqevent object="pqTimerLogDisplay/TimerLogSaveDialog" command="filesSelected" arguments="{log}" />',
])
events = events.replace("</pqevents>", tail + "\n</pqevents>")
script = os.path.join(os.path.dirname(log), "frame_rate.xml")
with open(script, "w") as out:
    out.write(events)
subprocess.run(["paraview", "--dr", f"--test-script={script}", "--exit"], check=True,
               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

text = open(log).read()
times = [float(t) for t in re.findall(r"^Interactive Render,\s+([0-9.e+-]+) seconds", text, re.M)]
if not times:
    sys.exit(f"no interactive render in the timer log {log}")
mean, median = statistics.mean(times), statistics.median(times)
print(f"view {width} x {height}, {len(times)} interactive renders (timer log: {log})")
print("| | seconds per frame | frames per second |")
print("|---|---|---|")
for label, value in (("mean", mean), ("median", median), ("fastest", min(times)),
                     ("slowest", max(times))):
    print(f"| {label} | {value:.4f} | {1 / value:.1f} |")
