#!/usr/bin/env python3
"""The ParaView GUI's answer after a user's action on a "Direct Surface" representation, for
several builds of the plugin and several datasets: runs Testing/Plugin/gui_responsiveness.py
(the real GUI on a private X server; the File menu clicked by xdotool right after each action)
REPEAT times per build and dataset, and prints a table of medians.

Usage (Xvfb, openbox, xdotool, paraview on PATH):
  /usr/bin/python3 Testing/Benchmark/gui_responsiveness.py --build NAME=PLUGIN.so [--build ...]
      --case FILE.vtu:ARRAY:ISO_SHOWN:ISO_CHANGED[,ISO_CHANGED...]:COLOR_ARRAY [--case ...]
      [--repeat 3] [--size 1148 746] [--wheel-notches 3]

Columns per action: the File menu's answer (seconds from the action to the menu's pop-up; the
idle GUI's time, median of 3 opens, is given per run), the mapper's render in the action (its
time on the GUI thread: TimeToDraw of the action's render), and the refined frame (seconds until
the mapper drew its full-resolution cast). Medians over the runs, with min-max of the menu.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DRIVER = os.path.join(HERE, "..", "Plugin", "gui_responsiveness.py")
ACTIONS = ("show", "iso", "colour", "reset", "wheel", "screenshot")

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--build", action="append", required=True, help="NAME=path of TetDSR.so")
parser.add_argument("--case", action="append", required=True,
                    help="FILE.vtu:ARRAY:ISO_SHOWN:ISO_CHANGED[,...]:COLOR_ARRAY")
parser.add_argument("--repeat", type=int, default=3)
parser.add_argument("--size", nargs=2, type=int, default=[1148, 746])
parser.add_argument("--wheel-notches", type=int, default=3)
args = parser.parse_args()

rows = []
for case in args.case:
    data, array, shown, changed, colour = case.split(":")
    for build in args.build:
        name, plugin = build.split("=", 1)
        runs = []
        for _ in range(args.repeat):
            out = tempfile.mktemp(suffix=".json")
            result = subprocess.run(
                [sys.executable, DRIVER, plugin, data, array, shown, changed, colour, "--size",
                 str(args.size[0]), str(args.size[1]), "--wheel-notches", str(args.wheel_notches),
                 "--json", out], capture_output=True, text=True)
            if result.returncode != 0:
                sys.exit(f"{name} on {data}: {result.stdout}{result.stderr}")
            with open(out) as f:
                runs.append(json.load(f))
            os.remove(out)
        idle = statistics.median(r["idle"] for r in runs)
        for action in ACTIONS:
            menus = [r[action]["menu"] for r in runs]
            rows.append((os.path.basename(data), f"{array} {shown} -> {changed}", name, action,
                         statistics.median(menus), min(menus), max(menus),
                         statistics.median(r[action]["render"] for r in runs),
                         statistics.median(r[action]["refined"] for r in runs), idle))
        capture = [r["screenshot"]["capture"]["differing"] for r in runs]
        print(f"{name} on {os.path.basename(data)}: idle GUI {idle:.2f} s; screenshot at once after "
              f"a change differs from the refined view's on {capture} pixels", flush=True)

print(f"\nview {args.size[0]} x {args.size[1]}, median of {args.repeat} runs, wheel zoom "
      f"{args.wheel_notches} notches\n")
print("| dataset | contour | build | action | File menu opened after s (min-max) "
      "| the mapper's render on the GUI thread s | refined frame after s |")
print("|---|---|---|---|---|---|---|")
for data, contour, name, action, menu, low, high, render, refined, idle in rows:
    render_text = "(interactive frames)" if action == "wheel" else f"{render:.3f}"
    print(f"| {data} | {contour} | {name} | {action} | {menu:.2f} ({low:.2f}-{high:.2f}) "
          f"| {render_text} | {refined:.2f} |")
