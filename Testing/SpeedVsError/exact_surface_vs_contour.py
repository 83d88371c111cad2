#!/usr/bin/env python3
"""Speed against error of the exact surface as data (vtkDirectSurfaceContour) on the bundled real
datasets, beside vtkContourFilter alone and vtkTessellatorFilter + vtkContourFilter: per dataset
and tolerance, triangles, seconds and the measured distance to the true surface. Writes
exact-surface.md (the table) and exact-surface.png (the plot) into --out.

  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
      Testing/SpeedVsError/exact_surface_vs_contour.py --data Data --out build/exact-surface

The truth of a real dataset is its exact surface at a very tight tolerance (--truth-tolerance,
relative to the diagonal; its vertices are certified roots of the cells' own fields, its
triangles within that tolerance of the true surface). A method's measured distance is the larger
of: its triangles sampled densely -> the nearest point of the truth's triangles, and the truth's
vertices -> the nearest point of the method's triangles (surface_measures.hausdorff); it is the
distance to the true surface within the truth's own bound. Times are medians of --runs runs, with
VTK's SMP backend as configured (the table names it), input already in memory."""
import argparse
import os
import platform
import statistics
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkSMPTools, vtkVersion
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "Python"))
import surface_measures as sm  # noqa: E402
from speed_vs_error import contour, only_array, tessellate_and_contour  # noqa: E402
from tetdsr import vtkDirectSurfaceContour  # noqa: E402

# Dataset, array, iso-value (middle of the solution's range, or a stress level of the bracket).
DATASETS = [("mfem_hex_q3", "u", 0.5),
            ("p3_poisson", "u", 0.5),
            ("hex_poisson", "u", 0.5),
            ("calculix_bracket", "S_Mises", 100.0),
            ("expansion_flow", "speed", 0.5),
            ("cylinder_flow", "speed", 0.25)]
TOLERANCES = [1e-2, 3e-3, 1e-3, 3e-4, 1e-4]
TARGET_TOLERANCE = 1e-3  # the tessellation is refined until it is as close as the exact surface here
SAMPLE_LEVEL = 4         # sample_triangles' steps per edge of a method's triangles (15 points each)
TESSELLATION_SECONDS = 30.0  # a level is tried only if the one before (x 8) promises to stay below


def log(*message):
    print(*message, file=sys.stderr, flush=True)


def read(path, array):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return only_array(reader.GetOutput(), array)


def exact_surface(grid, array, iso, tolerance, threads=0):
    f = vtkDirectSurfaceContour()
    f.SetNumberOfThreads(threads)
    f.SetInputData(grid)
    f.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, array)
    f.SetValue(0, iso)
    f.SetTolerance(tolerance)
    f.SetComputeIntegrals(True)
    f.Update()
    return f.GetOutput()


def field_value(out, name):
    return float(vtk_to_numpy(out.GetFieldData().GetArray(name)).ravel()[0])


def hausdorff(method, truth, limit, seed=1):
    """Measured two-sided distance between a method's surface and the truth, each (points,
    triangles): the method's triangles sampled at SAMPLE_LEVEL -> the truth's triangles, and the
    truth's vertices -> the method's triangles. Over `limit` query points, a random subset
    (triangles, or vertices) is measured: the maximum over it bounds the true one from below.
    Returns (method to truth, truth to method, whether a subset was used)."""
    rng = np.random.default_rng(seed)
    per_triangle = (SAMPLE_LEVEL + 1) * (SAMPLE_LEVEL + 2) // 2
    triangles = method[1]
    if len(triangles) * per_triangle > limit:
        triangles = triangles[rng.choice(len(triangles), limit // per_triangle, replace=False)]
    vertices = np.unique(truth[1])
    subset = len(triangles) < len(method[1]) or len(vertices) > limit
    if len(vertices) > limit:
        vertices = rng.choice(vertices, limit, replace=False)
    forward = sm.NearestTriangle(sm.polydata(*truth)).distances(sm.sample_triangles(method[0], triangles, SAMPLE_LEVEL))
    backward = sm.NearestTriangle(sm.polydata(*method)).distances(truth[0][vertices])
    return float(forward.max(initial=0.0)), float(backward.max(initial=0.0)), subset


def median_time(work, runs):
    """Median wall-clock seconds of `runs` calls of work() (one call if the first takes over 10 s)
    and the last result."""
    times, result = [], None
    for k in range(runs):
        start = time.perf_counter()
        result = work()
        times.append(time.perf_counter() - start)
        if times[0] > 10.0:
            break
    return statistics.median(times), len(times), result


class Row:
    def __init__(self, dataset, method, setting, seconds, runs, surface, truth, diagonal, limit, bound=None,
                 area=None, area_error=None):
        self.dataset, self.method, self.setting = dataset, method, setting
        self.seconds, self.runs = seconds, runs
        self.threaded = None  # seconds with every core (the exact surface only)
        self.points, self.triangles = sm.triangles_of(surface)
        self.forward, self.backward, self.subset = hausdorff((self.points, self.triangles), truth, limit)
        self.distance = max(self.forward, self.backward) / diagonal
        self.bound = None if bound is None else bound / diagonal
        self.area, self.area_error = area, area_error
        self.flat_area = sm.flat_area(self.points, self.triangles)


def run_dataset(name, array, iso, args):
    grid = read(os.path.join(args.data, name + ".vtu"), array)
    bounds = np.array(grid.GetBounds())
    diagonal = float(np.linalg.norm(bounds[1::2] - bounds[0::2]))
    log(f"{name}: {grid.GetNumberOfCells()} cells, {array} = {iso:g}, diagonal {diagonal:.4g}")
    start = time.perf_counter()
    truth_surface = exact_surface(grid, array, iso, args.truth_tolerance)
    truth_seconds = time.perf_counter() - start
    truth = sm.triangles_of(truth_surface)
    truth_area = field_value(truth_surface, "Area")
    info = {"dataset": name, "cells": grid.GetNumberOfCells(), "array": array, "iso": iso, "diagonal": diagonal,
            "truth_triangles": len(truth[1]), "truth_seconds": truth_seconds, "truth_area": truth_area,
            "truth_area_error": field_value(truth_surface, "AreaError"),
            "truth_unresolved": int(field_value(truth_surface, "UnresolvedSubcells")),
            "truth_bound": field_value(truth_surface, "DistanceBound")}
    log(f"  truth at {args.truth_tolerance:g}: {len(truth[1])} triangles in {truth_seconds:.1f} s, "
        f"area {truth_area:.10g}")
    rows = []
    for tolerance in args.tolerances:
        seconds, runs, out = median_time(lambda: exact_surface(grid, array, iso, tolerance, 1), args.runs)
        threaded, _, _ = median_time(lambda: exact_surface(grid, array, iso, tolerance), args.runs)
        rows.append(Row(name, "exact surface", f"tolerance {tolerance:g}", seconds, runs, out, truth, diagonal,
                        args.measure_limit, bound=field_value(out, "DistanceBound"), area=field_value(out, "Area"),
                        area_error=field_value(out, "AreaError")))
        rows[-1].threaded = threaded
        log(f"  exact {tolerance:g}: {len(rows[-1].triangles)} triangles, {seconds:.3f} s ({threaded:.3f} s threaded), "
            f"measured {rows[-1].distance:.2e}, bound {rows[-1].bound:.2e}")
    seconds, runs, out = median_time(lambda: sm.as_triangles(contour(grid, array, iso)), args.runs)
    rows.append(Row(name, "vtkContourFilter", "nodal values", seconds, runs, out, truth, diagonal, args.measure_limit))
    log(f"  vtkContourFilter: {len(rows[-1].triangles)} triangles, {seconds:.3f} s, measured {rows[-1].distance:.2e}")
    target = next((r.distance for r in rows if r.setting == f"tolerance {TARGET_TOLERANCE:g}"), None)
    level, previous = 1, 0.0
    while level <= args.max_level and previous * 8 <= TESSELLATION_SECONDS:
        seconds, runs, out = median_time(
            lambda: sm.as_triangles(tessellate_and_contour(grid, array, iso, level)), args.runs)
        rows.append(Row(name, "vtkTessellatorFilter + vtkContourFilter", f"{level} subdivisions", seconds, runs, out,
                        truth, diagonal, args.measure_limit))
        log(f"  tessellation level {level}: {len(rows[-1].triangles)} triangles, {seconds:.3f} s, "
            f"measured {rows[-1].distance:.2e}")
        if target is not None and rows[-1].distance <= target:
            break
        level, previous = level + 1, seconds
    return info, rows


def machine():
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")), "?")
    return (f"{os.cpu_count()} cores ({cpu}), {platform.system()} {platform.release()}; "
            f"VTK {vtkVersion.GetVTKVersion()} (ParaView 5.11's), SMP backend {vtkSMPTools.GetBackend()} "
            f"({vtkSMPTools.GetEstimatedNumberOfThreads()} threads)")


def write_table(path, infos, rows, args):
    out = ["# The exact surface as data against vtkContourFilter, on the bundled real datasets", "",
           f"Machine: {machine()}.  ",
           f"Command: `{args.command}`", "",
           "How to rerun: `bash Testing/SpeedVsError/run_exact_surface.sh [out-folder]` (builds first; "
           "default out-folder build/exact-surface), or the script directly:",
           "`PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 "
           "Testing/SpeedVsError/exact_surface_vs_contour.py --data Data --out build/exact-surface` "
           "(`--datasets`, `--tolerances`, `--truth-tolerance`, `--runs`, `--max-level` narrow it).", "",
           "Truth: each dataset's exact surface at tolerance "
           f"{args.truth_tolerance:g} of the diagonal (certified roots as vertices). Measured distance: the "
           "larger of the method's triangles sampled at 15 points each -> nearest point of the truth's "
           "triangles, and the truth's vertices -> nearest point of the method's triangles, over the "
           "diagonal (true to within the truth's own bound; * where more than --measure-limit points would "
           "be queried a direction and a random subset was: a lower bound). Stated bound: the filter's DistanceBound over "
           "the diagonal. Area: the filter's Area of the curved surface (error estimate AreaError) and the "
           "flat area of the triangles, against the truth's Area. Seconds: median of the runs, one thread "
           "(vtkDirectSurfaceContour.SetNumberOfThreads(1); VTK's filters are serial here) and, for the exact "
           "surface, with every core (its default).",
           "", "| dataset | truth: triangles, seconds, Area (AreaError) | unresolved subcells |", "|---|---|---|"]
    for info in infos:
        out.append(f"| {info['dataset']} ({info['cells']:,} cells, {info['array']} = {info['iso']:g}, diagonal "
                   f"{info['diagonal']:.4g}) | {info['truth_triangles']:,}, {info['truth_seconds']:.1f} s, "
                   f"{info['truth_area']:.10g} ({info['truth_area_error']:.1e}) | {info['truth_unresolved']} |")
    out += ["", "| dataset | method | setting | triangles | seconds, one thread (runs) | seconds, all cores "
            "| measured distance / diagonal "
            "| stated bound / diagonal | Area - truth (AreaError) | flat area - truth |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    truth_area = {info["dataset"]: info["truth_area"] for info in infos}
    for r in rows:
        bound = "" if r.bound is None else f"{r.bound:.1e}"
        area = "" if r.area is None else f"{r.area - truth_area[r.dataset]:+.2e} ({r.area_error:.1e})"
        out.append(f"| {r.dataset} | {r.method} | {r.setting} | {len(r.triangles):,} | {r.seconds:.3f} ({r.runs}) "
                   f"| {'' if r.threaded is None else f'{r.threaded:.3f}'} "
                   f"| {r.distance:.2e}{' *' if r.subset else ''} | {bound} | {area} | {r.flat_area - truth_area[r.dataset]:+.2e} |")
    with open(path, "w") as stream:
        stream.write("\n".join(out) + "\n")


def plot(path, infos, rows, tolerances):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    methods = {"exact surface": "#1b9e77", "vtkContourFilter": "#d95f02",
               "vtkTessellatorFilter + vtkContourFilter": "#7570b3"}
    markers = dict(zip([info["dataset"] for info in infos], "osD^vP*X"))
    figure, axes = plt.subplots(1, 2, figsize=(15, 6.5), sharex=True)
    for axis, quantity, label in ((axes[0], lambda r: r.seconds, "seconds (median, one thread)"),
                                  (axes[1], lambda r: len(r.triangles), "triangles")):
        for info in infos:
            for method, colour in methods.items():
                mine = [r for r in rows if r.dataset == info["dataset"] and r.method == method]
                if not mine:
                    continue
                axis.plot([r.distance for r in mine], [quantity(r) for r in mine], color=colour,
                          marker=markers[info["dataset"]], lw=1.0, ms=6, alpha=0.85)
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("measured distance to the true surface / diagonal")
        axis.set_ylabel(label)
        axis.grid(True, which="major", alpha=0.3)
    method_handles = [plt.Line2D([], [], color=c, marker="o", label=m) for m, c in methods.items()]
    dataset_handles = [plt.Line2D([], [], color="0.3", marker=m, ls="", label=d) for d, m in markers.items()]
    figure.legend(handles=method_handles, loc="upper left", bbox_to_anchor=(0.06, 0.02), ncol=3, title="method")
    figure.legend(handles=dataset_handles, loc="upper right", bbox_to_anchor=(0.98, 0.02), ncol=3, title="dataset")
    figure.suptitle(f"Exact surface (tolerances {', '.join(f'{t:g}' for t in tolerances)}) against vtkContourFilter "
                    "and tessellation + contour")
    figure.savefig(path, dpi=110, bbox_inches="tight")


def check(infos, rows):
    """The smoke run's expectations: every exact surface within its stated bound (plus the truth's),
    fully certified, and closer than vtkContourFilter at the default tolerance."""
    ok = True
    for info in infos:
        slack = info["truth_bound"] / info["diagonal"]
        mine = [r for r in rows if r.dataset == info["dataset"]]
        for r in mine:
            if r.bound is not None and r.distance > r.bound + slack:
                log(f"FAILED {r.dataset} {r.setting}: measured {r.distance:.3e} above bound {r.bound:.3e} + truth {slack:.1e}")
                ok = False
        exact = next(r for r in mine if r.setting == f"tolerance {TARGET_TOLERANCE:g}")
        linear = next(r for r in mine if r.method == "vtkContourFilter")
        if not linear.distance > exact.distance:
            log(f"FAILED {info['dataset']}: vtkContourFilter {linear.distance:.3e} not farther than the exact "
                f"surface {exact.distance:.3e}")
            ok = False
        if info["truth_unresolved"]:
            log(f"FAILED {info['dataset']}: {info['truth_unresolved']} unresolved subcells in the truth")
            ok = False
    log("check", "passed" if ok else "FAILED")
    return ok


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="the repository's Data folder")
    parser.add_argument("--out", required=True, help="folder for exact-surface.md and .png")
    parser.add_argument("--datasets", nargs="+", default=[d for d, _, _ in DATASETS])
    parser.add_argument("--tolerances", type=float, nargs="+", default=TOLERANCES)
    parser.add_argument("--truth-tolerance", type=float, default=1e-6)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--max-level", type=int, default=4, help="most tessellation subdivisions tried")
    parser.add_argument("--measure-limit", type=int, default=1_500_000,
                        help="query points per direction at most (a random subset beyond: marked *)")
    parser.add_argument("--check", action="store_true", help="assert the smoke test's expectations")
    parser.add_argument("--command", help="how this run was started, for the report (default: argv)")
    args = parser.parse_args()
    args.command = args.command or " ".join(sys.argv)
    os.makedirs(args.out, exist_ok=True)
    infos, rows = [], []
    for name, array, iso in DATASETS:
        if name in args.datasets:
            info, dataset_rows = run_dataset(name, array, iso, args)
            infos.append(info)
            rows += dataset_rows
    write_table(os.path.join(args.out, "exact-surface.md"), infos, rows, args)
    plot(os.path.join(args.out, "exact-surface.png"), infos, rows, args.tolerances)
    log(f"wrote {args.out}/exact-surface.md and .png")
    if args.check and not check(infos, rows):
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
