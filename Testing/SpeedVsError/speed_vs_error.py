#!/usr/bin/env python3
"""Speed against error of isosurface methods for quadratic tetrahedra, on the same pixel rays:
TetDSR with each normal scheme, vtkContourFilter, vtkTessellatorFilter + vtkContourFilter, and
VTK's unstructured-grid volume ray caster. Writes speed-vs-error.md (tables) and
speed-vs-error.png (time against error). Needs an X display (xvfb-run -a); run.sh sets it all up.

  PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 \
      Testing/SpeedVsError/speed_vs_error.py --out build/speed-vs-error --sizes 3 26 56 \
      --image 1024 --data Data [--flow Data/expansion_flow.vtu ...] [--check]
"""
import argparse
import os
import platform
import sys
import time
from dataclasses import dataclass
from typing import Optional

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints, vtkVersion
from vtkmodules.vtkCommonDataModel import (VTK_QUADRATIC_TETRA, VTK_TETRA, vtkCellArray,
                                           vtkPiecewiseFunction, vtkPolyData, vtkUnstructuredGrid)
from vtkmodules.vtkFiltersCore import vtkContourFilter, vtkProbeFilter
from vtkmodules.vtkFiltersGeneral import vtkDataSetTriangleFilter, vtkOBBTree, vtkTessellatorFilter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkCamera, vtkColorTransferFunction,
                                         vtkPolyDataMapper, vtkRenderWindow, vtkRenderer, vtkVolume,
                                         vtkVolumeProperty, vtkWindowToImageFilter)
from vtkmodules.vtkRenderingVolume import (vtkUnstructuredGridLinearRayIntegrator,
                                           vtkUnstructuredGridVolumeRayCastMapper)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the OpenGL backend)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401 (shows the volume ray caster's image)

from tetdsr import vtkDirectSurfaceRayCaster

from geometry import PixelRays, Quadric, cast_triangles, kuhn_lattice, kuhn_tets_crossed

# Three quadrics over the unit cube, each exactly represented by the lattice's quadratic tets.
# The disc is thinner (0.024) than the cells of all but the finest lattice: linear contouring
# loses it where no nodal value straddles the iso-value.
_DISC_NORMAL = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
_HYPERBOLOID_AXIS = np.array([0.2, 0.3, 1.0]) / np.linalg.norm([0.2, 0.3, 1.0])
ANALYTIC_FIELDS = {
    # |x - c|^2 = 0.3^2
    "sphere": (Quadric(np.eye(3), [0.5, 0.45, 0.52]), 0.09),
    # one sheet, throat radius 0.2, tilted axis: (x^2 + y^2 - z^2 in the axis frame) = 0.04
    "hyperboloid": (Quadric(np.eye(3) - 2 * np.outer(_HYPERBOLOID_AXIS, _HYPERBOLOID_AXIS),
                            [0.5, 0.5, 0.5]), 0.04),
    # oblate ellipsoid, radius 0.38, half-thickness 0.012, tilted
    "thin disc": (Quadric((np.eye(3) - np.outer(_DISC_NORMAL, _DISC_NORMAL)) / 0.38 ** 2 +
                          np.outer(_DISC_NORMAL, _DISC_NORMAL) / 0.012 ** 2, [0.5, 0.5, 0.5]), 1.0),
}
NORMAL_MODES = ("exact gradient", "central differences", "nodal interpolation", "depth buffer")
# The benchmark's view of the unit cube (camera at (2.1, 1.6, 3.0), looking at its centre),
# scaled by the bounding-box diagonal for other meshes.
VIEW_OFFSET = np.array([1.6, 1.1, 2.5]) / np.sqrt(3.0)
CAMERA_MOVE_DEGREES = 5.0
# Pixels whose truth is this ill-conditioned (relative discriminant, or distance of a root from
# the box faces in diagonals) are not compared.
AMBIGUITY = 1e-9
# The volume ray caster's transfer function: a tent of half-width 1e-3 of the iso-value around
# it, peak opacity 1 per 1e-9 of the diagonal, so that any ray whose piecewise-linear field
# passes through the tent saturates; a pixel is covered when its opacity is at least 1/2.
VOLUME_TENT = 1e-3
VOLUME_UNIT_DISTANCE = 1e-9
SAMPLE_EQUIVALENTS = (25, 50, 75)


def log(*message):
    print(*message, file=sys.stderr, flush=True)


def timed(work):
    """Wall-clock seconds of work(), and its result."""
    start = time.perf_counter()
    result = work()
    return time.perf_counter() - start, result


def make_grid(points, connectivity, cell_type, arrays):
    """A vtkUnstructuredGrid viewing numpy arrays: float64 points, one cell type, point arrays."""
    grid = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=1))
    grid.SetPoints(vtk_points)
    offsets = np.arange(0, connectivity.size + 1, connectivity.shape[1], dtype=np.int64)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(offsets, deep=1),
                  numpy_to_vtkIdTypeArray(connectivity.ravel().astype(np.int64), deep=1))
    grid.SetCells(cell_type, cells)
    for name, values in arrays.items():
        array = numpy_to_vtk(values, deep=1)
        array.SetName(name)
        grid.GetPointData().AddArray(array)
    grid.GetPointData().SetActiveScalars(next(iter(arrays)))
    return grid


def only_array(mesh, name):
    """The mesh's geometry (shared, not copied) with one point array: each method sees the field
    it renders and nothing else."""
    grid = vtkUnstructuredGrid()
    grid.CopyStructure(mesh)
    grid.GetPointData().AddArray(mesh.GetPointData().GetArray(name))
    grid.GetPointData().SetActiveScalars(name)
    return grid


@dataclass
class Scene:
    name: str
    mesh: vtkUnstructuredGrid  # carries `array` only
    array: str
    iso: float
    lo: np.ndarray
    hi: np.ndarray
    quadric: Optional[Quadric]  # exact truth; None: TetDSR's exact mode is the truth
    full_mesh: vtkUnstructuredGrid  # the same cells with every field (scenes on it share its tets)

    @property
    def diagonal(self):
        return float(np.linalg.norm(self.hi - self.lo))

    def camera(self):
        camera = vtkCamera()
        centre = (self.lo + self.hi) / 2
        camera.SetFocalPoint(*centre)
        camera.SetPosition(*(centre + VIEW_OFFSET * self.diagonal))
        camera.SetViewUp(0.0, 1.0, 0.0)
        camera.SetViewAngle(30.0)
        return camera

    def rays(self, size):
        camera = self.camera()
        return PixelRays(camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
                         camera.GetViewAngle(), size, size)


@dataclass
class Truth:
    depth: np.ndarray
    normal: np.ndarray
    excluded: np.ndarray


@dataclass
class Row:
    scene: str
    cells: int
    method: str
    family: str
    first: float  # first frame, preprocessing included
    again: float  # after the camera moved
    compared: int  # truth's covered pixels, excluded ones left out
    excluded: int
    missing: int
    false: int
    depth_error: Optional[tuple]  # (mean, max) relative to the diagonal; None: not defined
    normal_error: Optional[tuple]  # (mean, max) radians
    triangles: Optional[int] = None
    level: Optional[int] = None
    note: str = ""


def score(scene, truth, method, family, first, again, covered, depth=None, normal=None,
          lines=False, ignore=None, **extra):
    """Coverage, depth and normal errors of one method against the truth (depth and normal
    where both hit; normals compared as oriented vectors, or as lines when `lines`), leaving out
    the truth's excluded pixels and `ignore`."""
    excluded = truth.excluded if ignore is None else truth.excluded | ignore
    compared = ~excluded
    truth_hit = np.isfinite(truth.depth) & compared
    hit = covered & compared
    both = truth_hit & hit
    depth_error = normal_error = None
    if depth is not None:
        error = np.abs(depth[both] - truth.depth[both]) / scene.diagonal
        depth_error = (error.mean(), error.max()) if error.size else (0.0, 0.0)
        a, b = normal[both], truth.normal[both]
        dot = (a * b).sum(axis=1)
        # atan2 of |a x b| and a . b keeps tiny angles accurate (acos would not).
        angle = np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.abs(dot) if lines else dot)
        normal_error = (angle.mean(), angle.max()) if angle.size else (0.0, 0.0)
    log(f"  {method}: {first:.3f} s, {again:.3f} s")
    return Row(scene.name, scene.mesh.GetNumberOfCells(), method, family, first, again,
               int(truth_hit.sum()), int(excluded.sum()), int((truth_hit & ~hit).sum()),
               int((hit & ~truth_hit).sum()), depth_error, normal_error, **extra)


class Viewer:
    """One offscreen OpenGL window at the image size, reused by every method so that no
    measurement pays for creating the OpenGL context."""

    def __init__(self, size):
        self.size = size
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(size, size)
        self.renderer = None
        self.show(vtkRenderer(), None)  # creates the context
        self.release()

    def render(self):
        self.window.Render()
        self.window.WaitForCompletion()

    def release(self):
        """Drops the last scene (outside any timing: freeing a volume mapper's structures can take
        seconds)."""
        if self.renderer is not None:
            self.window.RemoveRenderer(self.renderer)
            self.renderer = None

    def show(self, renderer, camera):
        self.renderer = renderer
        self.window.AddRenderer(renderer)
        if camera is not None:
            renderer.SetActiveCamera(camera)
            renderer.ResetCameraClippingRange()
        self.render()

    def first_and_again(self, renderer, camera):
        """Time of the first render of a new scene, and of a render after the camera moved; also
        the first image (RGB, pixel id i + j * width, j = 0 the bottom row)."""
        self.release()
        first, _ = timed(lambda: self.show(renderer, camera))
        grab = vtkWindowToImageFilter()
        grab.SetInput(self.window)
        grab.ReadFrontBufferOff()
        grab.Update()
        rgb = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).reshape(self.size * self.size, -1).copy()
        camera.Azimuth(CAMERA_MOVE_DEGREES)
        renderer.ResetCameraClippingRange()
        again, _ = timed(self.render)
        return first, again, rgb


def run_tetdsr(scene, size, mode):
    camera = scene.camera()
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(scene.mesh)
    caster.SetInputArrayToProcess(0, 0, 0, 0, scene.array)  # 0 = FIELD_ASSOCIATION_POINTS
    caster.SetValue(0, scene.iso)
    caster.SetNormalMode(mode)
    caster.SetCamera(camera)
    caster.SetImageSize(size, size)
    first, _ = timed(caster.Update)
    image = caster.GetOutput().GetPointData()
    depth = vtk_to_numpy(image.GetArray("Depth")).astype(np.float64)
    normal = vtk_to_numpy(image.GetArray("Normals")).astype(np.float64)
    camera.Azimuth(CAMERA_MOVE_DEGREES)
    again, _ = timed(caster.Update)
    return first, again, depth, normal


def polygonal(scene, truth, viewer, rays, method, family, make_surface, **extra):
    """One row: make_surface() (returns the triangles) plus the first render, timed together, and
    a re-render after the camera moved; errors by ray casting the triangles on the pixel rays."""
    surface_seconds, surface = timed(make_surface)
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(surface)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    render_first, again, _ = viewer.first_and_again(renderer, scene.camera())
    triangles = surface.GetNumberOfPolys()
    if triangles == 0:
        depth, normal = np.full(rays.width * rays.height, np.inf), np.zeros((rays.width * rays.height, 3))
    else:
        corners = vtk_to_numpy(surface.GetPolys().GetConnectivityArray())
        if corners.size != 3 * triangles or surface.GetNumberOfCells() != triangles:
            raise ValueError(f"{method}: expected a surface of triangles only")
        points = vtk_to_numpy(surface.GetPoints().GetData()).astype(np.float64)
        normals = surface.GetPointData().GetNormals()
        depth, normal = cast_triangles(points, corners.reshape(-1, 3),
                                       None if normals is None else vtk_to_numpy(normals).astype(np.float64), rays)
    return score(scene, truth, method, family, surface_seconds + render_first, again,
                np.isfinite(depth), depth, normal, lines=True,
                triangles=triangles, **extra)


def contour(mesh, array, iso):
    contour_filter = vtkContourFilter()
    contour_filter.SetInputData(mesh)
    contour_filter.SetInputArrayToProcess(0, 0, 0, 0, array)
    contour_filter.SetValue(0, iso)
    contour_filter.Update()
    return contour_filter.GetOutput()


def tessellate_and_contour(mesh, array, iso, level):
    """Every edge split at every level (field criterion far below any deviation from linear), so
    level L turns each quadratic tet into 8^(L+1) linear tets."""
    values = vtk_to_numpy(mesh.GetPointData().GetArray(array))
    tessellator = vtkTessellatorFilter()
    tessellator.SetInputData(mesh)
    tessellator.SetMaximumNumberOfSubdivisions(level)
    tessellator.SetFieldCriterion(0, 1e-12 * float(np.ptp(values)))
    tessellator.Update()
    return contour(tessellator.GetOutput(), array, iso)


def volume_render(scene, viewer, tets, array):
    """vtkUnstructuredGridVolumeRayCastMapper on linear tets, with the tent transfer function;
    returns (first render s, re-render s, covered pixels)."""
    half_width = VOLUME_TENT * abs(scene.iso)
    if half_width == 0:
        raise ValueError(f"{scene.name}: the tent's width is relative to the iso-value, which is 0")
    values = vtk_to_numpy(tets.GetPointData().GetArray(array))
    low, high = float(values.min()), float(values.max())
    opacity = vtkPiecewiseFunction()
    colour = vtkColorTransferFunction()
    for value, alpha in ((low, 0.0), (scene.iso - half_width, 0.0), (scene.iso, 1.0),
                         (scene.iso + half_width, 0.0), (high, 0.0)):
        opacity.AddPoint(value, alpha)
        # VTK 9.2's linear integrator splits segments only at the colour function's points:
        # without these, the opacity tent is never sampled.
        colour.AddRGBPoint(value, 1.0, 1.0, 1.0)
    prop = vtkVolumeProperty()
    prop.SetScalarOpacity(opacity)
    prop.SetColor(colour)
    prop.SetScalarOpacityUnitDistance(VOLUME_UNIT_DISTANCE * scene.diagonal)
    mapper = vtkUnstructuredGridVolumeRayCastMapper()
    mapper.SetInputData(tets)
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectScalarArray(array)
    # Exact for piecewise-linear transfer functions on linear segments. The default integrator
    # looks the transfer function up in a table of 128 scalar steps over the data's range, too
    # coarse for the tent; the partial pre-integrator crashes (in Psi) on the 27-node cube.
    mapper.SetRayIntegrator(vtkUnstructuredGridLinearRayIntegrator())
    mapper.AutoAdjustSampleDistancesOff()
    mapper.SetImageSampleDistance(1.0)  # one ray per pixel
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer = vtkRenderer()
    renderer.SetBackground(0.0, 0.0, 0.0)
    renderer.AddVolume(volume)
    first, again, rgb = viewer.first_and_again(renderer, scene.camera())
    return first, again, rgb[:, 0] >= 128  # white on black: the red channel is the opacity


class Tetrahedralisation:
    """vtkDataSetTriangleFilter's linear tets of one mesh at a time. They do not depend on the
    field, so the scenes on one mesh share them and their measured time."""

    def __init__(self):
        self.mesh = None

    def of(self, mesh):
        if mesh is not self.mesh:
            self.mesh = self.tets = None  # free the previous mesh's tets first
            log("  tetrahedralising")
            split = vtkDataSetTriangleFilter()
            split.SetInputData(mesh)
            self.seconds, _ = timed(split.Update)
            self.mesh, self.tets = mesh, split.GetOutput()
        return self.seconds, self.tets


def analytic_truth(scene, rays):
    depth, normal, excluded = scene.quadric.first_hit(rays, scene.iso, scene.lo, scene.hi, AMBIGUITY)
    return Truth(depth, normal, excluded)


def run_scene(scene, viewer, size, tessellation_budget, tetrahedralisation):
    """All methods on one scene; returns rows and notes."""
    rows, notes = [], []
    rays = scene.rays(size)
    cells = scene.mesh.GetNumberOfCells()
    log(f"{scene.name}: {cells:,} cells")
    results = [run_tetdsr(scene, size, mode) for mode in range(len(NORMAL_MODES))]
    if scene.quadric is not None:
        truth = analytic_truth(scene, rays)
    else:
        exact_depth, exact_normal = results[0][2], results[0][3]
        truth = Truth(exact_depth, exact_normal, np.zeros(exact_depth.shape, bool))
    for mode, (first, again, depth, normal) in enumerate(results):
        rows.append(score(scene, truth, f"TetDSR, {NORMAL_MODES[mode]}", f"TetDSR {NORMAL_MODES[mode]}",
                          first, again, np.isfinite(depth), depth, normal,
                          lines=NORMAL_MODES[mode] == "depth buffer",
                          note="the truth" if scene.quadric is None and mode == 0 else ""))
    del results

    rows.append(polygonal(scene, truth, viewer, rays, "vtkContourFilter", "vtkContourFilter",
                          lambda: contour(scene.mesh, scene.array, scene.iso)))
    skipped = []
    for level in range(1, 5):
        linear_tets = cells * 8 ** (level + 1)
        if linear_tets > tessellation_budget:
            skipped.append((level, linear_tets))
            continue
        rows.append(polygonal(
            scene, truth, viewer, rays, f"tessellate level {level} + contour", "vtkTessellatorFilter + contour",
            lambda: tessellate_and_contour(scene.mesh, scene.array, scene.iso, level), level=level))
    if skipped:
        notes.append(f"{scene.name}: tessellation level(s) {', '.join(str(level) for level, _ in skipped)} "
                     f"not run: {', '.join(f'{tets / 1e6:,.1f} M' for _, tets in skipped)} linear tets, "
                     f"over the budget of {tessellation_budget / 1e6:g} M")

    triangulate_seconds, tets = tetrahedralisation.of(scene.full_mesh)
    first, again, covered = volume_render(scene, viewer, tets, scene.array)
    rows.append(score(scene, truth, "volume ray cast (8 linear tets per cell)", "volume ray cast",
                      triangulate_seconds + first, again, covered, ignore=coverage_edges(truth, size)))
    return rows, notes, truth


def coverage_edges(truth, size):
    """Pixels next to a change of the truth's coverage (8-neighbourhood). The volume ray caster's
    image is offset from pixel centres by about half a pixel (on a box of constant opacity its
    coverage centroid sits 0.56 and 0.37 pixels off, at 128 and 512 pixels alike), so its
    coverage is compared away from these edges only."""
    covered = np.isfinite(truth.depth).reshape(size, size)
    padded = np.pad(covered, 1, mode="edge")
    edges = np.zeros_like(covered)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            edges |= padded[1 + dy:1 + dy + size, 1 + dx:1 + dx + size] != covered
    return edges.ravel()


def lattice_scenes(n):
    points, connectivity = kuhn_lattice(n, quadratic=True)
    fields = {name: quadric.values(points) for name, (quadric, _) in ANALYTIC_FIELDS.items()}
    mesh = make_grid(points, connectivity, VTK_QUADRATIC_TETRA, fields)
    return [Scene(f"{name}, n = {n}", only_array(mesh, name), name, iso, np.zeros(3), np.ones(3),
                  quadric, mesh) for name, (quadric, iso) in ANALYTIC_FIELDS.items()]


def file_scene(path, iso_rule):
    """A quadratic-tet file: `speed` if it has it, else its first point array; iso-value by
    iso_rule(values)."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    mesh = reader.GetOutput()
    data = mesh.GetPointData()
    array = "speed" if data.GetArray("speed") else data.GetArrayName(0)
    values = vtk_to_numpy(data.GetArray(array))
    bounds = np.array(mesh.GetBounds())
    name = os.path.splitext(os.path.basename(path))[0]
    return Scene(f"{name} ({array})", only_array(mesh, array), array, iso_rule(values),
                 bounds[0::2], bounds[1::2], None, mesh)


def lattice_for_samples(rays, lo, hi, samples):
    """The Kuhn lattice of linear tets over the box whose mean number of tets crossed per ray
    (over rays through the box) is nearest to `samples`; returns (n, that mean)."""
    def mean_crossed(n):
        crossed = kuhn_tets_crossed(rays, lo, hi, n)
        return crossed[crossed > 0].mean()

    low, high = 1, 2
    while mean_crossed(high) < samples:
        low, high = high, 2 * high
    while high - low > 1:
        middle = (low + high) // 2
        low, high = (middle, high) if mean_crossed(middle) < samples else (low, middle)
    best = min((low, high), key=lambda n: abs(mean_crossed(n) - samples))
    return best, mean_crossed(best)


def sample_equivalent_rows(scene, truth, viewer, size, dsr_row):
    """The paper's Table 2: volume ray casting of the field resampled on a lattice of linear tets
    that each ray crosses about k times (VTK's ray caster integrates each tet crossed as one
    linear segment, so k tets = k segments, at least k samples' worth), against TetDSR."""
    rows = []
    rays = scene.rays(size)
    for samples in SAMPLE_EQUIVALENTS:
        n, crossed = lattice_for_samples(rays, scene.lo, scene.hi, samples)
        points, connectivity = kuhn_lattice(n, quadratic=False, lo=scene.lo, hi=scene.hi)
        lattice = make_grid(points, connectivity, VTK_TETRA, {"lattice": np.zeros(len(points))})

        def resample():
            probe = vtkProbeFilter()
            probe.SetInputData(lattice)
            probe.SetSourceData(scene.mesh)  # evaluates each quadratic cell's own shape functions
            probe.Update()
            return probe.GetOutput()

        resample_seconds, probed = timed(resample)
        valid = vtk_to_numpy(probed.GetPointData().GetArray("vtkValidPointMask"))
        if not valid.all():
            raise ValueError(f"{scene.name}: {int((valid == 0).sum())} lattice nodes outside the mesh")
        first, again, covered = volume_render(scene, viewer, probed, scene.array)
        row = score(scene, truth, f"volume ray cast, {samples}-sample lattice", "volume ray cast, k-sample lattice",
                    first, again, covered, ignore=coverage_edges(truth, size))
        rows.append((samples, n, crossed, resample_seconds, row))
        log(f"  {samples} samples: lattice {n}, {crossed:.1f} tets per ray, {first:.2f} s")
    return dsr_row, rows


def machine():
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")), "?")
    memory = next(int(line.split()[1]) for line in open("/proc/meminfo") if line.startswith("MemTotal"))
    return (f"{os.cpu_count()} cores ({cpu}), {memory / 2 ** 20:.0f} GiB, {platform.system()} "
            f"{platform.release()}; VTK {vtkVersion.GetVTKVersion()} (ParaView 5.11's); OpenGL: "
            f"Mesa llvmpipe under Xvfb")


def fmt_pair(pair):
    return "n/a" if pair is None else f"{pair[0]:.1e} / {pair[1]:.1e}"


def write_table(path, rows, table2, notes, args, size):
    out = []
    out.append(f"Image {size} x {size} pixels; machine: {machine()}.  ")
    out.append(f"Command: `{args.command}`")
    out.append("")
    out.append("| scene | cells | method | first frame s | after camera move s | truth pixels (excluded) "
               "| missing | false | depth error mean / max (of diagonal) | normal error mean / max rad | triangles |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        method = r.method + (f" ({r.note})" if r.note else "")
        triangles = "" if r.triangles is None else f"{r.triangles:,}"
        out.append(f"| {r.scene} | {r.cells:,} | {method} | {r.first:.3f} | {r.again:.3f} | "
                   f"{r.compared:,} ({r.excluded}) | {r.missing:,} | {r.false:,} | {fmt_pair(r.depth_error)} | "
                   f"{fmt_pair(r.normal_error)} | {triangles} |")
    out.append("")
    out.append("Table 2 analogue (TetDSR against volume ray casting at k-sample-equivalent quality):")
    out.append("")
    out.append("| scene | method | lattice n (linear tets) | mean tets crossed per ray | resample s "
               "| first frame s | after camera move s | first frame / TetDSR's | after move / TetDSR's "
               "| missing | false |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for dsr, volume_rows in table2:
        out.append(f"| {dsr.scene} | TetDSR, exact gradient | - | - | - | {dsr.first:.3f} | {dsr.again:.3f} "
                   f"| 1 | 1 | {dsr.missing:,} | {dsr.false:,} |")
        for samples, n, crossed, resample_seconds, r in volume_rows:
            out.append(f"| {r.scene} | volume ray cast ({samples}) | {n} ({6 * n ** 3:,}) | {crossed:.1f} "
                       f"| {resample_seconds:.3f} | {r.first:.3f} | {r.again:.3f} | {r.first / dsr.first:.1f} "
                       f"| {r.again / dsr.again:.1f} | {r.missing:,} | {r.false:,} |")
    out.append("")
    for note in notes:
        out.append(f"- {note}")
    with open(path, "w") as stream:
        stream.write("\n".join(out) + "\n")


def plot(path, rows, table2):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    families = ["TetDSR exact gradient", "TetDSR central differences", "TetDSR nodal interpolation",
                "TetDSR depth buffer", "vtkContourFilter", "vtkTessellatorFilter + contour",
                "volume ray cast", "volume ray cast, k-sample lattice"]
    colours = dict(zip(families, ["#1b9e77", "#66a61e", "#7570b3", "#e7298a", "#d95f02", "#a6761d",
                                  "#666666", "#000000"]))
    markers = "osD^vP*Xph<>"
    all_rows = rows + [r for _, volume_rows in table2 for *_, r in volume_rows]
    scenes = list(dict.fromkeys(r.scene for r in all_rows))
    marker = {scene: markers[i % len(markers)] for i, scene in enumerate(scenes)}
    floor = {"coverage": 1e-7, "depth": 1e-17, "normal": 1e-17}
    panels = [("coverage", "missing + false pixels / truth pixels"),
              ("depth", "mean depth error / diagonal"),
              ("normal", "mean normal error (rad)")]

    def error(r, kind):
        if kind == "coverage":
            return (r.missing + r.false) / max(r.compared, 1)
        pair = r.depth_error if kind == "depth" else r.normal_error
        return None if pair is None else pair[0]

    figure, axes = plt.subplots(1, 3, figsize=(18, 6.5), sharey=True)
    for axis, (kind, label) in zip(axes, panels):
        for r in all_rows:
            value = error(r, kind)
            if value is None or r.note == "the truth":
                continue
            axis.scatter(max(value, floor[kind]), r.first, color=colours[r.family], marker=marker[r.scene],
                         s=36, alpha=0.85)
        # Tessellation levels of one scene joined into a curve.
        for scene in scenes:
            curve = [r for r in rows if r.scene == scene and r.level is not None]
            if len(curve) > 1 and all(error(r, kind) is not None for r in curve):
                axis.plot([max(error(r, kind), floor[kind]) for r in curve], [r.first for r in curve],
                          color=colours["vtkTessellatorFilter + contour"], lw=0.8, alpha=0.6)
        axis.axvline(floor[kind], color="0.8", lw=6, zorder=0)
        axis.text(floor[kind], 1.0, " 0", transform=axis.get_xaxis_transform(), va="top", color="0.4")
        axis.set_xscale("log")
        axis.set_xlim(left=floor[kind] / 4)
        axis.set_yscale("log")
        axis.set_xlabel(label + " (0 drawn at the grey line)")
        axis.grid(True, which="major", alpha=0.3)
    axes[0].set_ylabel("first frame, preprocessing included (s)")
    method_handles = [plt.Line2D([], [], color=colours[f], marker="o", ls="", label=f) for f in families]
    scene_handles = [plt.Line2D([], [], color="0.3", marker=marker[s], ls="", label=s) for s in scenes]
    figure.legend(handles=method_handles, loc="upper left", bbox_to_anchor=(0.06, 0.02), ncol=4, fontsize=9,
                  title="method (colour)")
    figure.legend(handles=scene_handles, loc="upper right", bbox_to_anchor=(0.98, 0.02), ncol=3, fontsize=9,
                  title="scene (marker)")
    figure.suptitle("Time against error: each point one method on one scene, the same pixel rays, "
                    "errors against exact truth")
    figure.savefig(path, dpi=110, bbox_inches="tight")


def check(rows, sizes):
    """The smoke test's assertions: TetDSR's exact mode matches the analytic truth on the smallest
    lattice, vtkContourFilter loses part of the thin disc there, and the report's own geometry
    (triangle ray casting, tets crossed per ray) agrees with VTK's locators."""
    failures = []
    smallest = f"n = {min(sizes)}"
    for r in rows:
        if not r.scene.endswith(smallest):
            continue
        if r.method == "TetDSR, exact gradient":
            for what, got, limit in (("missing pixels", r.missing, 0), ("false pixels", r.false, 0),
                                     ("max depth error", r.depth_error[1], 1e-9),
                                     ("max normal error", r.normal_error[1], 1e-6)):
                if not got <= limit:
                    failures.append(f"{r.scene}, {r.method}: expected {what} <= {limit}, got {got}")
            if r.compared == 0:
                failures.append(f"{r.scene}: expected the surface in view, got 0 pixels")
        if r.method == "vtkContourFilter" and r.scene.startswith("thin disc") and not r.missing > 0:
            failures.append(f"{r.scene}, vtkContourFilter: expected missing pixels > 0, got {r.missing}")
    failures += check_geometry()
    for failure in failures:
        print("FAILED:", failure)
    return not failures


def check_geometry(size=48):
    """cast_triangles against vtkOBBTree on a contour's triangles, and kuhn_tets_crossed against
    the cells vtkProbeFilter finds at 4000 points along each ray (sampling misses very short
    crossings, and the probe's point location may name a neighbour within its tolerance, so a
    few rays may differ)."""
    failures = []
    scene = lattice_scenes(2)[0]
    rays = scene.rays(size)
    surface = contour(scene.mesh, scene.array, scene.iso)
    triangles = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    depth, _ = cast_triangles(vtk_to_numpy(surface.GetPoints().GetData()).astype(np.float64),
                              triangles, None, rays)
    tree = vtkOBBTree()
    tree.SetDataSet(surface)
    tree.BuildLocator()
    origin = rays.origin.astype(np.float64)
    expected = np.full(len(depth), np.inf)
    for pixel, direction in enumerate(rays.directions):
        points = vtkPoints()
        if tree.IntersectWithLine(origin, origin + 10 * scene.diagonal * direction, points, None):
            expected[pixel] = np.linalg.norm(vtk_to_numpy(points.GetData()) - origin, axis=1).min()
    if (np.isfinite(depth) != np.isfinite(expected)).any():
        failures.append(f"cast_triangles: expected {np.isfinite(expected).sum()} pixels covered "
                        f"(vtkOBBTree), got {np.isfinite(depth).sum()}")
    both = np.isfinite(depth) & np.isfinite(expected)
    worst = np.abs(depth[both] - expected[both]).max() / scene.diagonal
    if not worst <= 1e-6:  # vtkOBBTree's own intersections are accurate to about 1e-8
        failures.append(f"cast_triangles: expected depths within 1e-6 of vtkOBBTree's, got {worst:.1e}")

    n, samples = 3, 4000
    points, connectivity = kuhn_lattice(n, quadratic=False)
    lattice = make_grid(points, connectivity, VTK_TETRA, {"x": points[:, 0]})
    cell_ids = numpy_to_vtk(np.arange(lattice.GetNumberOfCells(), dtype=np.float64), deep=1)
    cell_ids.SetName("cell")
    lattice.GetCellData().AddArray(cell_ids)
    entry, exit_ = (t.astype(np.float64) for t in rays.box_interval(scene.lo, scene.hi))
    inside = exit_ > entry
    fractions = (np.arange(samples) + 0.5) / samples
    t = entry[inside, None] + fractions * (exit_ - entry)[inside, None]
    probe_points = vtkPoints()
    probe_points.SetData(numpy_to_vtk((origin + t[..., None] * rays.directions[inside][:, None]).reshape(-1, 3), deep=1))
    cloud = vtkPolyData()
    cloud.SetPoints(probe_points)
    probe = vtkProbeFilter()
    probe.SetInputData(cloud)
    probe.SetSourceData(lattice)
    probe.Update()
    found = vtk_to_numpy(probe.GetOutput().GetPointData().GetArray("cell")).reshape(-1, samples)
    sampled = 1 + (np.diff(found, axis=1) != 0).sum(axis=1)
    crossed = kuhn_tets_crossed(rays, scene.lo, scene.hi, n)[inside]
    if (sampled != crossed).mean() > 0.02 or abs(crossed.mean() / sampled.mean() - 1) > 0.01:
        failures.append(f"kuhn_tets_crossed: expected the sampled counts (mean {sampled.mean():.3f}) on "
                        f"98% of rays, got mean {crossed.mean():.3f}, {(sampled != crossed).sum()} of "
                        f"{len(crossed)} rays different")
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="folder for speed-vs-error.md and .png")
    parser.add_argument("--sizes", type=int, nargs="+", default=[3, 26, 56],
                        help="lattices of n^3 cubes, 6 quadratic tets each")
    parser.add_argument("--image", type=int, default=1024, help="image width = height, pixels")
    parser.add_argument("--data", required=True, help="the repository's Data folder (cube27.vtu)")
    parser.add_argument("--flow", nargs="*", default=[], help="quadratic-tet .vtu files of the real flow")
    parser.add_argument("--tessellation-budget", type=int, default=8_000_000,
                        help="run a tessellation level only if it makes at most this many linear tets")
    parser.add_argument("--check", action="store_true", help="assert the smoke test's expectations")
    parser.add_argument("--command", help="how this run was started, for the report (default: argv)")
    args = parser.parse_args()
    args.command = args.command or " ".join(sys.argv)
    os.makedirs(args.out, exist_ok=True)
    size = args.image
    viewer = Viewer(size)
    warm_up(viewer)

    rows, notes, table2 = [], [], []
    tetrahedralisation = Tetrahedralisation()
    table2_size = sorted(args.sizes)[len(args.sizes) // 2]
    for n in args.sizes:
        for scene in lattice_scenes(n):
            scene_rows, scene_notes, truth = run_scene(scene, viewer, size, args.tessellation_budget, tetrahedralisation)
            rows += scene_rows
            notes += scene_notes
            if n == table2_size and scene.array == "sphere":
                table2.append(sample_equivalent_rows(scene, truth, viewer, size, scene_rows[0]))
    # The paper's own Table 2 scene: its 27-node cube, the distance from the centre sampled at
    # the nodes, iso-value 0.8; then the real flow, iso-value at the middle of its nodal range.
    file_scenes = [file_scene(os.path.join(args.data, "cube27.vtu"), lambda values: 0.8)]
    file_scenes += [file_scene(path, lambda values: float(values.min() + values.max()) / 2) for path in args.flow]
    for scene in file_scenes:
        scene_rows, scene_notes, truth = run_scene(scene, viewer, size, args.tessellation_budget, tetrahedralisation)
        rows += scene_rows
        notes += scene_notes
        if scene is file_scenes[0]:
            table2.insert(0, sample_equivalent_rows(scene, truth, viewer, size, scene_rows[0]))

    write_table(os.path.join(args.out, "speed-vs-error.md"), rows, table2, notes, args, size)
    plot(os.path.join(args.out, "speed-vs-error.png"), rows, table2)
    log(f"wrote {args.out}/speed-vs-error.md and .png")
    if args.check and not check(rows, args.sizes):
        return 1
    return 0


def warm_up(viewer):
    """One small run of each kind first, so that no measurement pays for loading libraries or
    starting threads."""
    scene = lattice_scenes(1)[0]
    run_tetdsr(scene, 8, 0)
    renderer = vtkRenderer()
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(contour(scene.mesh, scene.array, scene.iso))
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer.AddActor(actor)
    viewer.show(renderer, scene.camera())


if __name__ == "__main__":
    sys.exit(main())
