#!/usr/bin/env python3
"""Benchmark (not a test): vtkDirectSurfaceMapper in a render window over a 36-frame camera orbit
(azimuth 10 degrees per frame), against vtkContourFilter + vtkPolyDataMapper, in one 1024 x 1024
offscreen window. Prints a Markdown table. Needs an X display (run_mapper_orbit.sh: xvfb-run).

  PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \
      Testing/Benchmark/mapper_orbit.py [--size 1024] [--lattice 61] [--frames 36]

Datasets: the 1.36 M-cell lattice of tetdsr_benchmark.cxx (n = 61: n^3 cubes of 6 quadratic tets
over [0,1]^3, built here with numpy exactly as MakeMesh builds it) with its "wave" field at
iso 0.3, and Data/expansion_flow.vtu ('speed', iso 0.25).

Per dataset, in the same window:
- first frame: the mapper's first (still) render, which prepares the scene (validation and the
  surface index of the iso-value) and casts at full resolution;
- interacting: what VTK's interactor styles do while the mouse drags (StartInteraction sets the
  window's DesiredUpdateRate to the interactor's DesiredUpdateRate, 15; StillUpdateRate 0.0001),
  and ParaView's rates (5.0 / 0.002); a vtkRenderWindowInteractor is attached to the window (no
  Start()), so the mapper sees the still rate and casts at a reduced resolution sized to the
  actor's allocated render time;
- still: DesiredUpdateRate = the still rate (a still render: full resolution), the camera moving
  every frame, so no frame re-uses the last image;
- image quality of the interacting rows, untimed, after each orbit: every interaction frame is
  cast again (the camera and the sample distance the mapper chose for it, with
  AutoAdjustSampleDistances off) and compared with a still render of the same camera: PSNR over
  RGB, and the share of pixels whose largest channel difference exceeds 16/255 (measured after
  the orbit because the mapper sizes each frame from the time between renders);
- vtkContourFilter (once, timed separately) + vtkPolyDataMapper over the same orbit.
Every frame ends with glFinish (WaitForCompletion), so its time includes the GL work.
"""
import argparse
import os
import re
import statistics
import sys
import time

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonCore import vtkPoints, vtkUnsignedCharArray
from vtkmodules.vtkCommonDataModel import (VTK_QUADRATIC_TETRA, vtkCellArray, vtkDataObject,
                                           vtkUnstructuredGrid)
from vtkmodules.vtkFiltersCore import vtkContourFilter
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkCamera, vtkPolyDataMapper, vtkRenderWindow,
                                         vtkRenderWindowInteractor, vtkRenderer,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkInteractionStyle  # noqa: F401 (the interactor's default style)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)
import vtkmodules.vtkRenderingUI  # noqa: F401 (the platform's vtkRenderWindowInteractor)

from tetdsr import vtkDirectSurfaceMapper

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "Testing", "Python"))
from kuhn_lattice import kuhn_quadratic_tets  # noqa: E402


def lattice(n):
    """tetdsr_benchmark.cxx's MakeMesh(n) (Testing/Benchmark/BenchmarkLattice.h): n^3 cubes over
    [0,1]^3, 6 positively oriented quadratic tets each, nodes on the half-step lattice with point
    id i + m (j + m k), m = 2 n + 1; cells in the order k, j, i, tet (kuhn_lattice.py). Point
    arrays "wave" (active scalars) and "quadric"."""
    m = 2 * n + 1
    keys, ids = kuhn_quadratic_tets(n, x_fastest=True)
    points = (np.arange(m) / (m - 1.0))[keys]  # i / (m - 1), as the C++ computes it
    x, y, z = points.T
    wave = np.sin(7.0 * x) * np.cos(5.0 * y) + np.sin(6.0 * z + 1.0)
    quadric = (x - 0.5) ** 2 + (y - 0.45) ** 2 + (z - 0.52) ** 2

    cells = 6 * n ** 3
    connectivity = numpy_support.numpy_to_vtkIdTypeArray(ids.reshape(-1), deep=True)
    offsets = numpy_support.numpy_to_vtkIdTypeArray(
        np.arange(0, 10 * cells + 1, 10, dtype=np.int64), deep=True)
    cell_array = vtkCellArray()
    cell_array.SetData(offsets, connectivity)
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_support.numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    grid.SetCells(VTK_QUADRATIC_TETRA, cell_array)
    for name, values in (("wave", wave), ("quadric", quadric)):
        array = numpy_support.numpy_to_vtk(values.ravel(), deep=True)
        array.SetName(name)
        grid.GetPointData().AddArray(array)
    grid.GetPointData().SetActiveScalars("wave")
    return grid


def read_vtu(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def machine(window):
    cpu = "unknown CPU"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    caps = window.ReportCapabilities() or ""
    renderer = re.search(r"OpenGL renderer string:\s*(.*)", caps)
    version = re.search(r"OpenGL version string:\s*(.*)", caps)
    gl = renderer.group(1).strip() if renderer else "unknown OpenGL renderer"
    if version:
        gl += ", OpenGL " + version.group(1).strip()
    return f"{os.cpu_count()} cores ({cpu}), OpenGL renderer: {gl}"


def load():
    """The 1-minute load average: other processes competing for the cores skew the timings."""
    return open("/proc/loadavg").read().split()[0]


class Bench:
    def __init__(self, size, snapshots=None):
        self.snapshots = snapshots
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(size, size)
        self.renderer = vtkRenderer()
        self.renderer.SetBackground(1.0, 1.0, 1.0)
        self.window.AddRenderer(self.renderer)
        self.interactor = vtkRenderWindowInteractor()
        self.interactor.SetRenderWindow(self.window)  # no Start(): only its StillUpdateRate counts

    def frame(self):
        start = time.perf_counter()
        self.window.Render()
        self.window.WaitForCompletion()
        return time.perf_counter() - start

    def orbit(self, frames, on_frame=None):
        """frames renders, the camera turned 10 degrees about the view up before each; returns
        the per-frame seconds."""
        camera = self.renderer.GetActiveCamera()
        times = []
        for _ in range(frames):
            camera.Azimuth(10.0)
            self.renderer.ResetCameraClippingRange()  # as the interactor styles do
            times.append(self.frame())
            if on_frame:
                on_frame()
        return times

    def snapshot(self, name):
        """The last frame as it is in the window (not re-rendered), to look at (--snapshots)."""
        if not self.snapshots:
            return
        os.makedirs(self.snapshots, exist_ok=True)
        grab = vtkWindowToImageFilter()
        grab.SetInput(self.window)
        grab.ShouldRerenderOff()
        grab.ReadFrontBufferOff()
        grab.Update()
        writer = vtkPNGWriter()
        writer.SetFileName(os.path.join(self.snapshots, re.sub(r"[^A-Za-z0-9]+", "_", name) + ".png"))
        writer.SetInputConnection(grab.GetOutputPort())
        writer.Write()

    def pixels(self):
        """The window's RGB as a (height, width, 3) int array."""
        width, height = self.window.GetSize()
        rgba = vtkUnsignedCharArray()
        self.window.GetRGBACharPixelData(0, 0, width - 1, height - 1, 1, rgba)
        return numpy_support.vtk_to_numpy(rgba).reshape(height, width, 4)[..., :3].astype(np.int64)

    def set_rates(self, desired, still):
        self.interactor.SetStillUpdateRate(still)
        self.window.SetDesiredUpdateRate(desired)  # also sets each renderer's allocated time


def interaction_quality(bench, mapper, frames, desired, still):
    """Per recorded interaction frame (a copy of its camera, the sample distance it was cast at),
    that frame cast again and a still render of the same camera: the PSNR (dB) over RGB and the
    share of pixels whose largest channel difference exceeds 16/255. Untimed."""
    camera = bench.renderer.GetActiveCamera()
    mapper.AutoAdjustSampleDistancesOff()
    psnr, off = [], []
    for saved, distance in frames:
        camera.DeepCopy(saved)
        mapper.SetInteractiveImageSampleDistance(distance)
        bench.set_rates(desired, still)
        bench.frame()
        interaction = bench.pixels()
        bench.set_rates(still, still)
        bench.frame()
        error = interaction - bench.pixels()
        mse = np.mean(error.astype(np.float64) ** 2)
        psnr.append(10.0 * np.log10(255.0 ** 2 / mse) if mse > 0 else float("inf"))
        off.append(float(np.mean(np.abs(error).max(axis=2) > 16)))
    mapper.AutoAdjustSampleDistancesOn()
    return psnr, off


def run_dataset(bench, label, grid, array, iso, view, frames, rows, elevation=0.0, dolly=1.0):
    renderer, camera = bench.renderer, bench.renderer.GetActiveCamera()

    def reset_view():
        if view == "lattice":  # tetdsr_benchmark.cxx's camera
            camera.SetFocalPoint(0.5, 0.5, 0.5)
            camera.SetPosition(2.1, 1.6, 3.0)
            camera.SetViewUp(0.0, 1.0, 0.0)
            camera.SetViewAngle(30.0)
        else:  # the whole mesh from an oblique direction (the mesh's bounds, not the props':
            # the contour's are smaller)
            camera.SetFocalPoint(0.0, 0.0, 0.0)
            camera.SetPosition(*view)
            camera.SetViewUp(0.0, 1.0, 0.0)
            camera.SetViewAngle(30.0)
            renderer.ResetCamera(grid.GetBounds())
        if elevation:  # a held-out orbit: the camera raised (or lowered) before it turns
            camera.Elevation(elevation)
            camera.OrthogonalizeViewUp()
        if dolly != 1.0:  # and moved closer (> 1) or farther
            camera.Dolly(dolly)
        renderer.ResetCameraClippingRange()

    mapper = vtkDirectSurfaceMapper()
    mapper.SetInputData(grid)
    mapper.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, array)
    mapper.SetValue(0, iso)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.9, 0.75, 0.55)
    renderer.AddActor(actor)
    reset_view()

    still_rate = 0.0001
    bench.set_rates(still_rate, still_rate)
    first = bench.frame()
    # A second still render of the same view: re-uses the image (checks the re-use path).
    reused = bench.frame()
    reuse_ok = mapper.GetLastRenderReusedImage()

    base = {"dataset": label, "cells": grid.GetNumberOfCells(), "first": first}
    for name, desired, still in (("interacting, VTK rates (15 / 0.0001)", 15.0, 0.0001),
                                 ("interacting, ParaView rates (5 / 0.002)", 5.0, 0.002)):
        reset_view()
        bench.set_rates(still, still)
        bench.frame()  # the still frame the interaction starts from
        bench.set_rates(desired, still)  # StartInteraction
        distances, casts, draws, allocated, reuses, cameras = [], [], [], [], 0, []

        def record():
            nonlocal reuses
            saved = vtkCamera()
            saved.DeepCopy(camera)
            cameras.append(saved)
            distances.append(mapper.GetLastImageSampleDistance())
            casts.append(mapper.GetLastCastSize())
            draws.append(mapper.GetTimeToDraw())
            allocated.append(actor.GetAllocatedRenderTime())
            reuses += mapper.GetLastRenderReusedImage()

        times = bench.orbit(frames, record)
        bench.snapshot(f"{label} {name}")
        bench.set_rates(still, still)  # EndInteraction: one still frame
        end_still = bench.frame()
        psnr, off = interaction_quality(bench, mapper, list(zip(cameras, distances)), desired, still)
        rows.append(dict(base, mode=f"TetDSR mapper, {name}", target=1.0 / desired, times=times,
                         distance=statistics.mean(distances), dmin=min(distances),
                         dmax=max(distances), cast=casts[len(casts) // 2], reuses=reuses,
                         end_still=end_still, allocated=statistics.mean(allocated),
                         draw=statistics.mean(draws), psnr=psnr, off=off))

    reset_view()
    bench.set_rates(still_rate, still_rate)
    bench.frame()
    distances, draws, reuses = [], [], 0

    def record_still():
        nonlocal reuses
        distances.append(mapper.GetLastImageSampleDistance())
        draws.append(mapper.GetTimeToDraw())
        reuses += mapper.GetLastRenderReusedImage()

    times = bench.orbit(frames, record_still)
    bench.snapshot(f"{label} still")
    rows.append(dict(base, mode="TetDSR mapper, still (full resolution)", times=times,
                     distance=statistics.mean(distances), dmin=min(distances), dmax=max(distances),
                     cast=mapper.GetLastCastSize(), reuses=reuses, draw=statistics.mean(draws)))
    renderer.RemoveActor(actor)
    mapper.ReleaseGraphicsResources(bench.window)

    # What a VTK user runs today: contour once, then render the triangles.
    contour = vtkContourFilter()
    contour.SetInputData(grid)
    contour.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, array)
    contour.SetValue(0, iso)
    start = time.perf_counter()
    contour.Update()
    contour_s = time.perf_counter() - start
    poly_mapper = vtkPolyDataMapper()
    poly_mapper.SetInputConnection(contour.GetOutputPort())
    poly_mapper.ScalarVisibilityOff()
    poly_actor = vtkActor()
    poly_actor.SetMapper(poly_mapper)
    poly_actor.GetProperty().SetColor(0.9, 0.75, 0.55)
    renderer.AddActor(poly_actor)
    reset_view()
    first_poly = bench.frame()
    times = bench.orbit(frames)
    bench.snapshot(f"{label} contour")
    rows.append(dict(base, mode="vtkContourFilter + vtkPolyDataMapper (still)", times=times,
                     first=contour_s + first_poly, contour=contour_s,
                     triangles=contour.GetOutput().GetNumberOfCells()))
    renderer.RemoveActor(poly_actor)
    poly_mapper.ReleaseGraphicsResources(bench.window)
    return reused, reuse_ok


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--lattice", type=int, default=61, help="lattice n (6 n^3 cells)")
    parser.add_argument("--frames", type=int, default=36)
    parser.add_argument("--elevation", type=float, default=0.0,
                        help="raise the camera by this many degrees before the orbit (held-out "
                             "orbits; the default orbit is the one the results were tuned on)")
    parser.add_argument("--dolly", type=float, default=1.0,
                        help="move the camera closer (> 1) or farther (< 1) before the orbit")
    parser.add_argument("--datasets", default="lattice,expansion_flow",
                        help="comma-separated: lattice, expansion_flow")
    parser.add_argument("--snapshots", metavar="DIR",
                        help="also write each mode's last orbit frame as a PNG into DIR")
    args = parser.parse_args()

    load_before = load()
    bench = Bench(args.size, args.snapshots)
    bench.frame()  # create the GL context
    host = machine(bench.window)
    rows, notes = [], []

    datasets = args.datasets.split(",")
    orbit = dict(elevation=args.elevation, dolly=args.dolly)
    if "lattice" in datasets:
        start = time.perf_counter()
        grid = lattice(args.lattice)
        build_s = time.perf_counter() - start
        reused, ok = run_dataset(bench, f"lattice n={args.lattice}, wave = 0.3", grid, "wave",
                                 0.3, "lattice", args.frames, rows, **orbit)
        notes.append(f"lattice built with numpy in {build_s:.2f} s; unchanged re-render "
                     f"{reused * 1e3:.1f} ms (re-used image: {bool(ok)})")
        del grid
    if "expansion_flow" in datasets:
        flow = read_vtu(os.path.join(ROOT, "Data", "expansion_flow.vtu"))
        reused, ok = run_dataset(bench, "expansion_flow, speed = 0.25", flow, "speed", 0.25,
                                 (3.0, 2.0, 4.0), args.frames, rows, **orbit)
        notes.append(f"expansion_flow: unchanged re-render {reused * 1e3:.1f} ms "
                     f"(re-used image: {bool(ok)})")

    print(f"machine: {host}; load average before / after: {load_before} / {load()}")
    held_out = (f"; camera raised {args.elevation:g} degrees and dollied {args.dolly:g} first"
                if args.elevation or args.dolly != 1.0 else "")
    print(f"window: {args.size} x {args.size} offscreen; orbit: {args.frames} frames, azimuth 10 "
          f"degrees each{held_out}; every frame timed to glFinish")
    print()
    print("| dataset | cells | renderer / mode | first frame s | fps (mean) | frame s median / max "
          "| mapper s mean | LOD sample distance mean (min-max) | cast size | frames re-used "
          "| vs still: PSNR dB mean (min) | vs still: pixels > 16/255 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        times = row["times"]
        fps = len(times) / sum(times)
        if "contour" in row:
            first = f"{row['first']:.3f} (contour {row['contour']:.3f}, {row['triangles']:,} triangles)"
            lod = cast = reuse = draw = "-"
        else:
            first = f"{row['first']:.3f}"
            lod = f"{row['distance']:.2f} ({row['dmin']:.2f}-{row['dmax']:.2f})"
            cast = f"{row['cast'][0]} x {row['cast'][1]}"
            reuse = str(row["reuses"])
            draw = f"{row['draw']:.3f}"
        psnr = off = "-"
        if "psnr" in row:
            # A frame cast at full resolution equals its still frame (infinite PSNR): counted apart.
            finite = [p for p in row["psnr"] if np.isfinite(p)]
            identical = len(row["psnr"]) - len(finite)
            psnr = f"{statistics.mean(finite):.1f} ({min(finite):.1f})" if finite else "-"
            if identical:
                psnr += f", {identical} identical"
            off = f"{100 * statistics.mean(row['off']):.2f} %"
        print(f"| {row['dataset']} | {row['cells']:,} | {row['mode']} | {first} | {fps:.1f} | "
              f"{statistics.median(times):.3f} / {max(times):.3f} | {draw} | {lod} | {cast} | {reuse} "
              f"| {psnr} | {off} |")
    print()
    print("Targets: interacting >= 10 fps on 2 cores; still frame <= 1 s.")
    for row in rows:
        if "target" in row:
            fps = len(row["times"]) / sum(row["times"])
            print(f"- {row['dataset']}, {row['mode']}: {fps:.1f} fps "
                  f"({'meets' if fps >= 10 else 'misses'} 10 fps; the rate asks for "
                  f"{1 / row['target']:.0f} fps, actor's allocated time {row['allocated']:.3f} s, "
                  f"mapper's own time {row['draw']:.3f} s of {statistics.mean(row['times']):.3f} s "
                  f"per frame); "
                  f"still frame after release {row['end_still']:.3f} s")
        elif "contour" not in row:
            worst = max(row["times"])
            print(f"- {row['dataset']}, still: slowest frame {worst:.3f} s "
                  f"({'meets' if worst <= 1.0 else 'misses'} <= 1 s)")
    notes.append("vtkContourFilter (VTK 9.2) contours quadratic tets on one thread; the mapper "
                 "uses all cores (STDThread backend)")
    for note in notes:
        print(f"- {note}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
