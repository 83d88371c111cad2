#!/usr/bin/env python3
"""Area convergence of the exact surface as data (vtkDirectSurfaceContour) on bundled real datasets:
per dataset and tolerance (SetTolerance, relative to the diagonal), the triangles, seconds and the
output's field data Area, AreaError (of the curved surface), FlatArea (of the triangles), Volume,
VolumeError and DistanceBound, with each Area's and FlatArea's difference from the finest
tolerance's Area (the reference). Writes area-convergence.md (the table) into --out.

  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
      Testing/SpeedVsError/area_convergence.py --data Data --out build/area-convergence

Seconds are one wall-clock run with --threads threads (default 1: one thread), input already in
memory. The finest tolerance's Area is itself within its AreaError estimate of the true area, so
differences below that are not resolved."""
import argparse
import os
import platform
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkSMPTools, vtkVersion
from exact_surface_vs_contour import exact_surface, log, read

# Dataset, array, iso-value (the middle of the solution's range).
DATASETS = [("hex_poisson", "u", 0.5),
            ("expansion_flow", "speed", 0.5)]
TOLERANCES = [1e-1, 3e-2, 1e-2, 3e-3, 1e-3]
FIELDS = ["Area", "AreaError", "FlatArea", "Volume", "VolumeError", "DistanceBound", "UnresolvedSubcells"]


def field_data(out):
    data = out.GetFieldData()
    values = {}
    for name in FIELDS:
        array = data.GetArray(name)
        if array is None:
            raise KeyError(f"field data has no {name}: it has "
                           f"{[data.GetArrayName(i) for i in range(data.GetNumberOfArrays())]}")
        values[name] = float(vtk_to_numpy(array).ravel()[0])
    return values


def machine():
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")), "?")
    return (f"{os.cpu_count()} cores ({cpu}), {platform.system()} {platform.release()}; "
            f"VTK {vtkVersion.GetVTKVersion()} (ParaView 5.11's), SMP backend {vtkSMPTools.GetBackend()}")


def run_dataset(name, array, iso, args):
    grid = read(os.path.join(args.data, name + ".vtu"), array)
    bounds = np.array(grid.GetBounds())
    diagonal = float(np.linalg.norm(bounds[1::2] - bounds[0::2]))
    log(f"{name}: {grid.GetNumberOfCells()} cells, {array} = {iso:g}, diagonal {diagonal:.4g}")
    rows = []
    for tolerance in args.tolerances:
        start = time.perf_counter()
        out = exact_surface(grid, array, iso, tolerance, args.threads)
        seconds = time.perf_counter() - start
        row = {"tolerance": tolerance, "triangles": out.GetNumberOfCells(), "seconds": seconds, **field_data(out)}
        rows.append(row)
        log(f"  {tolerance:g}: {row['triangles']} triangles, {seconds:.2f} s, Area {row['Area']:.12g} "
            f"({row['AreaError']:.1e}), FlatArea {row['FlatArea']:.12g}, Volume {row['Volume']:.10g} "
            f"({row['VolumeError']:.1e})")
    return {"dataset": name, "cells": grid.GetNumberOfCells(), "array": array, "iso": iso, "diagonal": diagonal}, rows


def write_table(path, results, args):
    out = ["# Area convergence of the exact surface as data, on bundled real datasets", "",
           f"Machine: {machine()}; vtkDirectSurfaceContour with {args.threads or 'all'} thread(s).  ",
           f"Command: `{args.command}`", "",
           "Per dataset, the exact surface at each tolerance (SetTolerance, relative to the diagonal; "
           "DistanceBound is the absolute bound it gives), one run each: its triangles, seconds, and the "
           "output's field data: Area of the curved surface with its error estimate AreaError, FlatArea of "
           "the triangles, and Volume (of the region where the field >= the iso-value) with VolumeError. "
           "The finest tolerance's row is the reference for the differences: Area - Area(finest) and "
           "FlatArea - Area(finest) (below the finest row's AreaError they are not resolved).", ""]
    for info, rows in results:
        reference = rows[-1]["Area"]
        out += [f"## {info['dataset']} ({info['cells']:,} cells, {info['array']} = {info['iso']:g}, "
                f"diagonal {info['diagonal']:.4g})", "",
                "| tolerance | triangles | seconds | Area | AreaError | FlatArea | Area - Area(finest) "
                "| FlatArea - Area(finest) | Volume | VolumeError | DistanceBound | unresolved subcells |",
                "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in rows:
            out.append(f"| {r['tolerance']:g} | {r['triangles']:,} | {r['seconds']:.2f} | {r['Area']:.12g} "
                       f"| {r['AreaError']:.1e} | {r['FlatArea']:.12g} | {r['Area'] - reference:+.2e} "
                       f"| {r['FlatArea'] - reference:+.2e} | {r['Volume']:.10g} | {r['VolumeError']:.1e} "
                       f"| {r['DistanceBound']:.3g} | {int(r['UnresolvedSubcells'])} |")
        out.append("")
    with open(path, "w") as stream:
        stream.write("\n".join(out))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="the repository's Data folder")
    parser.add_argument("--out", required=True, help="folder for area-convergence.md")
    parser.add_argument("--dataset", nargs="+", default=[d for d, _, _ in DATASETS],
                        help="datasets among " + ", ".join(d for d, _, _ in DATASETS))
    parser.add_argument("--tolerances", type=float, nargs="+", default=TOLERANCES,
                        help="relative tolerances, coarsest first (the last is the reference)")
    parser.add_argument("--threads", type=int, default=1, help="vtkDirectSurfaceContour threads (0: all cores)")
    parser.add_argument("--command", help="how this run was started, for the report (default: argv)")
    args = parser.parse_args()
    args.command = args.command or " ".join(sys.argv)
    args.tolerances = sorted(args.tolerances, reverse=True)
    os.makedirs(args.out, exist_ok=True)
    results = [run_dataset(name, array, iso, args) for name, array, iso in DATASETS if name in args.dataset]
    write_table(os.path.join(args.out, "area-convergence.md"), results, args)
    log(f"wrote {args.out}/area-convergence.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
