"""Fuzzer of vtkDirectSurfaceMapper in a real render window: random and hostile meshes, fields,
properties, cameras, windows, renderers and actors, and edits between renders.

Every case is made from (seed, case index) alone, so any case can be replayed. Each case runs in
a process of its own (a crash or a hang costs that case only; X refusing the connection, which
Xvfb does under load, is retried). After every render each window's depth buffer must be finite
and within [0, 1], and in a "clean" case (a valid mesh holding f = |x - c|^2 exactly, opaque
surfaces whose spheres lie inside the mesh, no clipping, full resolution) each renderer's covered
pixels must be those of the exact spheres seen through its camera and each actor's matrix (a few
may differ on silhouettes), unless the mapper said why not with an error. Errors are allowed
(hostile input may be refused); crashes, sanitizer reports, hangs and broken invariants are
failures.

A case is a list of "knobs", each drawn from its own random stream, so a failing case shrinks by
switching knobs off (--without), as in fuzz_filter.py.

Usage (PYTHONPATH must reach the `tetdsr` package; run with /usr/bin/python3 under an X server,
e.g. xvfb-run -a):
  fuzz_mapper.py [--seed S] [--cases N | --minutes M] [--timeout T] [--out DIR]
  fuzz_mapper.py --seed S --replay I [--without knob,knob]   (one case, in this process)
Exit status: 0 when every case was drawn or refused with an error, 1 otherwise.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

from fuzz_common import SANITIZER, X_REFUSALS, Case as BaseCase, pick

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
from kuhn_lattice import lattice  # noqa: E402

VTK_TETRA, VTK_QUADRATIC_TETRA = 10, 24
SIZES = [(64, 48), (96, 72), (33, 17), (1, 1), (2, 120), (160, 120)]

# Knobs in the order they are applied, with the probability that a case switches each on (the
# HOSTILE ones only in hostile cases; the COVERAGE ones change the picture away from the exact
# spheres and are off in clean cases).
KNOBS = {
    "mesh": 1.0,
    "nonfinite": 0.15,
    "conn_garbage": 0.15,
    "cell_types": 0.1,
    "empty": 0.05,
    "field_array": 0.15,
    "composite": 0.25,
    "iso_values": 0.5,
    "iso_styles": 0.3,
    "property": 0.5,
    "colouring": 0.35,
    "clipping": 0.2,
    "camera": 0.8,
    "views": 0.4,
    "actors": 0.4,
    "detail": 0.25,
    "setters": 0.2,
    "edits": 0.6,
}
HOSTILE = {"nonfinite", "conn_garbage", "cell_types", "empty", "field_array", "setters"}
COVERAGE = {"iso_styles", "clipping", "detail"}


class Case(BaseCase):
    """A case's choices (fuzz_common.Case): a profile, then one random stream per knob."""

    KNOBS = KNOBS

    def __init__(self, seed, index, without=()):
        super().__init__(seed, index, without)
        profile = np.random.default_rng([seed, index, 0]).random()
        self.profile = "clean" if profile < 0.4 else "hostile"

    def allows(self, name):
        return not (self.profile == "clean" and (name in HOSTILE or name in COVERAGE))


# ---------------------------------------------------------------------------------------------
# The scene (VTK imported in the case's process only)

class Scene:
    """The case's VTK objects and what the truth needs: the spheres' centre and whether the
    picture must be the exact spheres."""

    def __init__(self, case):
        from vtkmodules.vtkRenderingCore import vtkActor, vtkRenderer, vtkRenderWindow
        from tetdsr import vtkDirectSurfaceMapper
        self.case = case
        self.errors, self.warnings = [], []
        self.exact = case.profile == "clean"
        self.mapper = vtkDirectSurfaceMapper()
        self.watch(self.mapper)
        self.windows, self.renderers, self.actors = [], [], []
        self.centre = np.zeros(3)
        self.vtkActor, self.vtkRenderer, self.vtkRenderWindow = vtkActor, vtkRenderer, vtkRenderWindow

    def watch(self, obj):
        from vtkmodules.util.misc import calldata_type
        from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand

        @calldata_type(VTK_STRING)
        def on_error(o, e, text):
            self.errors.append(text.strip().splitlines()[-1])

        @calldata_type(VTK_STRING)
        def on_warning(o, e, text):
            self.warnings.append(text.strip().splitlines()[-1])
        obj.AddObserver(vtkCommand.ErrorEvent, on_error)
        obj.AddObserver(vtkCommand.WarningEvent, on_warning)


def make_grid(points, cells, field, types=None, name="f"):
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid
    grid = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetData(numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=1))
    grid.SetPoints(p)
    ca = vtkCellArray()
    ca.SetData(numpy_to_vtkIdTypeArray(np.arange(0, cells.size + 1, 10, dtype=np.int64), deep=1),
               numpy_to_vtkIdTypeArray(np.ascontiguousarray(cells.ravel()), deep=1))
    if types is None:
        types = np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8)
    grid.SetCells(numpy_to_vtk(types, deep=1), ca)
    f = numpy_to_vtk(np.ascontiguousarray(field, dtype=np.float64), deep=1)
    f.SetName(name)
    grid.GetPointData().SetScalars(f)
    return grid


def build_input(case, scene):
    rng = case.knob("mesh")
    n = int(rng.integers(1, 4))
    points, cells = lattice(n, oriented=False)  # (as walked: the odd tets inverted)
    scene.centre = rng.uniform(-0.2, 0.2, 3)
    radius = rng.uniform(0.2, 0.7)
    field = np.sum((points - scene.centre) ** 2, axis=1)
    types = None
    values = [radius ** 2]
    case.note("mesh: lattice n=%d, sphere centre %s radius %.3f" % (n, scene.centre.round(3), radius))
    if (r := case.knob("nonfinite")):
        for _ in range(int(r.integers(1, 4))):
            target = pick(r, ["point", "field", "all_points"])
            if target == "point":
                points[int(r.integers(len(points))), int(r.integers(3))] = pick(r, [np.nan, np.inf])
            elif target == "field":
                field[int(r.integers(len(field)))] = pick(r, [np.nan, -np.inf])
            else:
                points[:] = np.nan
            case.note("nonfinite: %s" % target)
    if (r := case.knob("conn_garbage")):
        flat = cells.ravel()
        for _ in range(int(r.integers(1, 6))):
            flat[int(r.integers(len(flat)))] = pick(r, [-1, len(points), 2 ** 40, 10 ** 12])
        case.note("conn_garbage")
    if (r := case.knob("cell_types")):
        types = np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8)
        types[r.random(len(cells)) < 0.5] = pick(r, [VTK_TETRA, 12, 0, 255])
        case.note("cell_types: %s" % np.unique(types).tolist())
    grid = make_grid(points, cells, field, types)
    if (r := case.knob("empty")):
        from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
        grid = vtkUnstructuredGrid()
        case.note("empty grid")
    if (r := case.knob("field_array")):
        from vtkmodules.util.numpy_support import numpy_to_vtk
        kind = pick(r, ["vector", "cell", "missing", "short", "int8"])
        if kind == "vector":
            v = numpy_to_vtk(np.c_[field, field, field], deep=1)
        elif kind == "short":
            v = numpy_to_vtk(field[:len(field) // 2].copy(), deep=1)
        elif kind == "int8":
            v = numpy_to_vtk(np.clip(field * 50, -100, 100).astype(np.int8), deep=1)
        else:
            v = numpy_to_vtk(field[:max(grid.GetNumberOfCells(), 1)].copy(), deep=1)
        v.SetName("g")
        (grid.GetCellData() if kind == "cell" else grid.GetPointData()).AddArray(v)
        scene.mapper.SetInputArrayToProcess(0, 0, 0, 1 if kind == "cell" else 0,
                                            "nothing" if kind == "missing" else "g")
        case.note("field_array: %s" % kind)
    data = grid
    if (r := case.knob("composite")):
        from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkPolyData
        data = vtkMultiBlockDataSet()
        kind = pick(r, ["one", "two", "empty", "polydata"])
        if kind == "two" and grid.GetNumberOfCells() > 1:
            half = grid.GetNumberOfCells() // 2
            for b, part in enumerate((cells[:half], cells[half:])):
                block = make_grid(points, part, field)
                # The grid's own points and field, so that its edits are the blocks' edits.
                block.SetPoints(grid.GetPoints())
                block.GetPointData().SetScalars(grid.GetPointData().GetScalars())
                data.SetBlock(b, block)
        elif kind != "empty":
            data.SetBlock(0, grid)
        if kind == "polydata":
            data.SetBlock(1, vtkPolyData())
        case.note("composite: %s" % kind)
    scene.grid, scene.data = grid, data
    scene.mapper.SetInputData(data)
    return values


def set_mapper_options(case, scene, values):
    m = scene.mapper
    if (r := case.knob("iso_values")):
        kind = pick(r, ["several", "duplicate", "nonfinite", "none", "many", "generate", "outside"])
        if kind == "several":
            values = values + list(r.uniform(0.02, 0.49, int(r.integers(1, 4))))
        elif kind == "duplicate":
            values = values * 2
        elif kind == "many":
            values = list(np.linspace(0.02, 0.49, int(pick(r, [50, 300, 2000]))))
        elif kind == "outside":
            values = values + [pick(r, [-1.0, 50.0, 1e300])]
        elif kind == "nonfinite":
            values = values + [pick(r, [np.nan, np.inf])]
            scene.exact = False
        elif kind == "none":
            values = []
            scene.exact = False
        case.note("iso_values: %s (%d)" % (kind, len(values)))
        if kind == "generate":
            m.GenerateValues(int(r.integers(1, 8)), 0.02, 0.49)
            values = None
    if values is not None:
        m.SetNumberOfContours(len(values))
        for i, v in enumerate(values):
            m.SetValue(i, v)
    if (r := case.knob("iso_styles")):
        for _ in range(int(r.integers(1, 5))):
            i = pick(r, [0, 1, 2, -1, 2 ** 20, 2 ** 31 - 1])
            if r.random() < 0.5:
                m.SetIsoValueColor(i, *r.uniform(-1, 2, 3))
            else:
                m.SetIsoValueOpacity(i, pick(r, [0.0, 0.3, 1.0, np.nan, -1.0, 2.0]))
        case.note("iso_styles")
    if (r := case.knob("colouring")):
        from vtkmodules.util.numpy_support import numpy_to_vtk
        from vtkmodules.vtkCommonCore import vtkLookupTable
        grid = scene.grid
        npts = grid.GetNumberOfPoints()
        k = pick(r, [1, 1, 3])
        n = pick(r, [npts, npts, max(npts // 2, 0), npts + 5])
        colours = r.normal(size=(n, k)).squeeze()
        if r.random() < 0.3 and n:
            colours.ravel()[int(r.integers(colours.size))] = np.nan
        array = numpy_to_vtk(np.ascontiguousarray(colours.astype(pick(r, [np.float64, np.float32]))), deep=1)
        array.SetName("c")
        (grid.GetCellData() if r.random() < 0.15 else grid.GetPointData()).AddArray(array)
        m.ScalarVisibilityOn()
        m.SetScalarModeToUsePointFieldData() if r.random() < 0.8 else m.SetScalarModeToUseCellFieldData()
        m.SelectColorArray("c")
        m.SetScalarRange(*pick(r, [(0.0, 1.0), (-2.0, 2.0), (1.0, 1.0), (1.0, -1.0)]))
        if r.random() < 0.3:
            table = vtkLookupTable()
            table.SetRange(*pick(r, [(0.0, 1.0), (3.0, 3.0)]))
            table.Build()
            m.SetLookupTable(table)
            m.SetUseLookupTableScalarRange(bool(r.random() < 0.5))
        case.note("colouring: %d x %d" % (n, k))
    else:
        m.ScalarVisibilityOff()
    if (r := case.knob("clipping")):
        from vtkmodules.vtkCommonDataModel import vtkPlane
        for _ in range(int(r.integers(1, 8))):
            plane = vtkPlane()
            plane.SetOrigin(*r.uniform(-0.5, 0.5, 3))
            plane.SetNormal(*pick(r, [r.normal(size=3), np.zeros(3), np.array([np.nan, 0, 1])]))
            m.AddClippingPlane(plane)
        case.note("clipping: %d planes" % m.GetClippingPlanes().GetNumberOfItems())
    if (r := case.knob("detail")):
        m.SetAutoAdjustSampleDistances(bool(r.random() < 0.5))
        m.SetInteractiveImageSampleDistance(pick(r, [1.0, 2.5, 64.0, np.nan, -3.0]))
        m.SetMaximumImageSampleDistance(pick(r, [1.0, 8.0, np.nan, 1e9]))
        scene.interactive = True
        case.note("detail: interactive, auto %d" % m.GetAutoAdjustSampleDistances())
    if (r := case.knob("setters")):
        from vtkmodules.vtkCommonDataModel import vtkImageData
        m.SetScalarRange(pick(r, [np.nan, 0.0]), pick(r, [np.inf, 1.0]))
        m.SetNumberOfThreads(int(pick(r, [-5, 0, 1, 3, 2 ** 31 - 1])))
        if r.random() < 0.3:
            m.SetInputData(vtkImageData())
        case.note("setters")
    if scene.case.profile == "clean":
        m.SetNumberOfThreads(int(pick(np.random.default_rng([case.seed, case.index, 7]), [0, 1, 2])))


def set_property(case, scene, actor, rng):
    p = actor.GetProperty()
    p.SetColor(*rng.uniform(0.2, 1, 3))
    if rng.random() < 0.3:
        p.SetOpacity(pick(rng, [0.5, 0.0, 1.0]))
        if p.GetOpacity() < 1:
            scene.exact = False
    p.SetAmbient(pick(rng, [0.0, 0.3, 1.0]))
    p.SetDiffuse(pick(rng, [0.0, 0.7, 1.0]))
    p.SetSpecular(pick(rng, [0.0, 0.5]))
    p.SetSpecularPower(pick(rng, [1.0, 30.0, 128.0]))
    if rng.random() < 0.2:
        p.LightingOff()


def set_camera(case, renderer, rng):
    camera = renderer.GetActiveCamera()
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    kind = pick(rng, ["perspective"] * 6 + ["parallel"] * 3 + ["off_axis", "shear", "ratio",
                                                               "near_cut", "wide", "narrow"])
    camera.SetFocalPoint(*rng.normal(0, 0.2, 3))
    camera.SetPosition(*(np.array(camera.GetFocalPoint()) + direction * rng.uniform(2, 8)))
    camera.SetViewUp(*rng.normal(size=3))
    camera.OrthogonalizeViewUp()
    camera.SetViewAngle(rng.uniform(10, 70))
    if kind == "parallel" or (kind == "shear" and rng.random() < 0.5):
        camera.ParallelProjectionOn()
        camera.SetParallelScale(rng.uniform(0.5, 2.0))
    if kind == "off_axis":
        camera.SetWindowCenter(*rng.uniform(-0.8, 0.8, 2))
    if kind == "shear":
        camera.SetViewShear(*rng.uniform(-0.5, 0.5, 2), 1.0)
    if kind == "wide":
        camera.SetViewAngle(pick(rng, [150.0, 179.0]))
    if kind == "narrow":
        camera.SetViewAngle(pick(rng, [0.5, 1e-3]))
    renderer.ResetCameraClippingRange()
    if kind == "ratio":
        camera.SetClippingRange(pick(rng, [1e-6, 1e-4]), pick(rng, [1e3, 1e5]))
    if kind == "near_cut":
        d = camera.GetDistance()
        camera.SetClippingRange(d - 0.3, d + 3)
    return kind


def build_views(case, scene):
    """Windows, renderers (viewports) and actors, all sharing the one mapper."""
    rv = case.knob("views")
    layout = [[(0, 0, 1, 1)]]
    if rv:
        layout = pick(rv, [[[(0, 0, 1, 1)], [(0, 0, 1, 1)]], [[(0, 0, 0.5, 1), (0.5, 0, 1, 1)]],
                           [[(0, 0, 1, 1), (0.6, 0.6, 1, 1)]], [[(0, 0, 0.5, 1)], [(0.2, 0.1, 0.9, 0.8)]]])
        case.note("views: %s" % layout)
    ra = case.knob("actors")
    rc = case.knob("camera")
    rng = np.random.default_rng([case.seed, case.index, 5])
    for w, viewports in enumerate(layout):
        window = scene.vtkRenderWindow()
        window.SetSize(*pick(rng, SIZES) if rv or rc else (64, 48))
        window.OffScreenRenderingOn()
        window.SetMultiSamples(0)
        scene.windows.append(window)
        for viewport in viewports:
            renderer = scene.vtkRenderer()
            renderer.SetViewport(*viewport)
            renderer.SetBackground(0, 0, 0)
            if (ra and ra.random() < 0.2) or (rng.random() < 0.05 and case.profile == "hostile"):
                renderer.UseDepthPeelingOn()
            count = int(ra.integers(1, 4)) if ra else 1
            for _ in range(count):
                actor = scene.vtkActor()
                actor.SetMapper(scene.mapper)
                if ra and ra.random() < 0.6:
                    actor.SetPosition(*ra.normal(0, 1, 3))
                    actor.RotateWXYZ(ra.uniform(0, 360), *ra.normal(size=3))
                    actor.SetScale(*(pick(ra, [1.0, 0.5, 2.0]) * np.ones(3) if ra.random() < 0.7
                                     else ra.uniform(0.3, 2, 3)))
                set_property(case, scene, actor, ra or rng)
                renderer.AddActor(actor)
                scene.actors.append(actor)
            window.AddRenderer(renderer)
            scene.renderers.append(renderer)
            renderer.ResetCamera()
            kind = set_camera(case, renderer, rc) if rc else "default"
            case.note("renderer %d: %d actor(s), camera %s" % (len(scene.renderers) - 1, count, kind))
    if getattr(scene, "interactive", False):
        for window in scene.windows:
            window.SetDesiredUpdateRate(pick(rng, [1000.0, 30.0]))


# ---------------------------------------------------------------------------------------------
# Edits between renders

def edit(case, scene, rng, step):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    kinds = ["camera", "iso", "resize", "actor_off", "field_modified", "opacity", "remove_actor",
             "input_swap"]
    if case.profile == "hostile":
        kinds += ["ids_unmodified", "field_nan_unmodified", "points_nan_modified", "empty_input",
                  "release", "window_gone"]
    kind = pick(rng, kinds)
    case.note("edit %d: %s" % (step, kind))
    grid, m = scene.grid, scene.mapper
    if kind == "camera":
        renderer = pick(rng, scene.renderers)
        renderer.GetActiveCamera().Azimuth(rng.uniform(-90, 90))
        renderer.GetActiveCamera().Elevation(rng.uniform(-60, 60))
        renderer.GetActiveCamera().OrthogonalizeViewUp()
        renderer.ResetCameraClippingRange()
    elif kind == "iso" and m.GetNumberOfContours() > 0:
        m.SetValue(0, rng.uniform(0.02, 0.49))
    elif kind == "resize":
        pick(rng, scene.windows).SetSize(*pick(rng, SIZES))
    elif kind == "actor_off":
        actor = pick(rng, scene.actors)
        actor.SetVisibility(not actor.GetVisibility())
    elif kind == "opacity":
        pick(rng, scene.actors).GetProperty().SetOpacity(pick(rng, [0.4, 1.0]))
        scene.exact = scene.exact and all(a.GetProperty().GetOpacity() == 1 for a in scene.actors)
    elif kind == "remove_actor":
        renderer = pick(rng, scene.renderers)
        actor = renderer.GetActors().GetLastActor()
        if actor is not None:
            renderer.RemoveActor(actor)
    elif kind == "field_modified" and grid.GetPointData().GetScalars() is not None \
            and grid.GetNumberOfPoints():
        scene.centre = rng.uniform(-0.2, 0.2, 3)
        points = vtk_to_numpy(grid.GetPoints().GetData())
        scalars = grid.GetPointData().GetScalars()
        if scalars.GetNumberOfTuples() == len(points) and scalars.GetNumberOfComponents() == 1:
            vtk_to_numpy(scalars)[:] = np.sum((points - scene.centre) ** 2, axis=1)
            scalars.Modified()
    elif kind == "input_swap":
        m.SetInputData(scene.data)
    elif kind == "ids_unmodified" and grid.GetNumberOfCells():
        vtk_to_numpy(grid.GetCells().GetConnectivityArray())[:] = pick(rng, [10 ** 12, -1, 0])
        scene.exact = False
        if rng.random() < 0.5:
            m.ScalarVisibilityOn()
            m.SetScalarModeToUsePointFieldData()
            m.SelectColorArray(grid.GetPointData().GetArrayName(0) or "f")
    elif kind == "field_nan_unmodified" and grid.GetPointData().GetScalars() is not None:
        vtk_to_numpy(grid.GetPointData().GetScalars())[:] = np.nan
        scene.exact = False
    elif kind == "points_nan_modified" and grid.GetNumberOfPoints():
        vtk_to_numpy(grid.GetPoints().GetData())[:] = np.nan
        grid.GetPoints().GetData().Modified()
        scene.exact = False
    elif kind == "empty_input":
        from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
        m.SetInputData(vtkUnstructuredGrid())
        scene.exact = False
    elif kind == "release":
        m.ReleaseGraphicsResources(pick(rng, scene.windows))
    elif kind == "window_gone" and len(scene.windows) > 1:
        window = scene.windows.pop()
        for renderer in list(scene.renderers):
            if renderer.GetRenderWindow() is window:
                scene.renderers.remove(renderer)
        window.Finalize()
        del window


# ---------------------------------------------------------------------------------------------
# Invariants

def depth_of(window):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkFloatArray
    w, h = window.GetSize()
    z = vtkFloatArray()
    window.GetZbufferData(0, 0, w - 1, h - 1, z)
    return vtk_to_numpy(z).reshape(h, w).astype(np.float64)


def sphere_coverage(renderer, actor, centre, radii2):
    """Pixels of `renderer` whose ray meets one of the concentric spheres |x - centre|^2 = r2
    (r2 in `radii2`) of the model coordinates of `actor` between the near and the far plane,
    and whether each pixel is clear of grazing. The squared distance to the centre along the
    ray's segment is continuous, so the segment meets a sphere exactly when r2 lies between the
    segment's smallest and largest squared distance: one sorted search per pixel."""
    w, h = renderer.GetSize()
    x0, y0 = renderer.GetOrigin()
    m = renderer.GetActiveCamera().GetCompositeProjectionTransformMatrix(
        renderer.GetTiledAspectRatio(), -1, 1)
    composite = np.array([[m.GetElement(r, c) for c in range(4)] for r in range(4)])
    a = actor.GetMatrix()
    model = np.array([[a.GetElement(r, c) for c in range(4)] for r in range(4)])
    inverse = np.linalg.inv(composite @ model)
    i, j = np.meshgrid(np.arange(w), np.arange(h))
    x = 2 * (i.ravel() + 0.5) / w - 1
    y = 2 * (j.ravel() + 0.5) / h - 1

    def unproject(z):
        p = np.c_[x, y, np.full_like(x, z), np.ones_like(x)] @ inverse.T
        return p[:, :3] / p[:, 3:]
    near, far = unproject(-1.0), unproject(1.0)
    d = far - near
    o = near - centre
    qa, qb, qc = np.sum(d * d, 1), 2 * np.sum(o * d, 1), np.sum(o * o, 1)
    t = np.clip(-qb / (2 * qa), 0, 1)
    at_near, at_far = qc, qa + qb + qc
    lowest = qa * t * t + qb * t + qc
    highest = np.maximum(at_near, at_far)
    radii2 = np.sort(np.asarray(radii2, dtype=np.float64))
    # The first radius at or above the lowest squared distance, then whether it is below the
    # highest.
    k = np.searchsorted(radii2, lowest)
    hit = (k < len(radii2)) & (radii2[np.minimum(k, len(radii2) - 1)] <= highest)

    def clear_of(values):  # no radius within 1e-6 (relative) of these squared distances
        k = np.clip(np.searchsorted(radii2, values), 1, len(radii2) - 1) if len(radii2) > 1 \
            else np.zeros(len(values), dtype=int)
        nearest = np.minimum(np.abs(radii2[k] - values), np.abs(radii2[k - 1 if len(radii2) > 1 else k] - values))
        return nearest > 1e-6 * radii2[-1]
    clear = clear_of(lowest) & clear_of(at_near) & clear_of(at_far)
    return (x0, y0, w, h), hit.reshape(h, w), clear.reshape(h, w)


def check_render(case, scene, broken, step):
    for k, window in enumerate(scene.windows):
        z = depth_of(window)
        if not np.all(np.isfinite(z)) or z.min() < 0 or z.max() > 1:
            broken["depth-out-of-range"] = "window %d after render %d: min %r max %r" % (
                k, step, np.nanmin(z), np.nanmax(z))
    if not scene.exact or scene.errors:
        return
    # Every sphere inside the mesh (|c| <= 0.2 per axis, radius <= 0.7): a ray is covered when
    # it meets any of them between the near and the far plane.
    iso = [scene.mapper.GetValue(i) for i in range(scene.mapper.GetNumberOfContours())]
    spheres = [v for v in iso if 0.0 < v <= 0.49 + 1e-12]
    if not spheres:
        return
    for r, renderer in enumerate(scene.renderers):
        window = renderer.GetRenderWindow()
        z = depth_of(window)
        expected, clear = None, None
        for actor in renderer.GetActors():
            if not actor.GetVisibility():
                continue
            (x0, y0, w, h), hit, sure = sphere_coverage(renderer, actor, scene.centre, spheres)
            expected = hit if expected is None else expected | hit
            clear = sure if clear is None else clear & sure
        if expected is None or w <= 0 or h <= 0:
            continue
        got = z[y0:y0 + h, x0:x0 + w] < 1
        if got.shape != expected.shape:
            continue
        edge = np.zeros_like(expected)
        for axis in (0, 1):
            for shift in (1, -1):
                edge |= expected != np.roll(expected, shift, axis)
        # Renderers drawn later in the same window cover their own viewports.
        for later in scene.renderers[r + 1:]:
            if later.GetRenderWindow() is window:
                lx, ly = later.GetOrigin()
                lw, lh = later.GetSize()
                edge[max(ly - y0, 0):max(ly - y0 + lh, 0), max(lx - x0, 0):max(lx - x0 + lw, 0)] = True
        wrong = (got != expected) & clear & ~edge
        if wrong.sum() > max(2, 0.002 * expected.sum()):
            broken["coverage"] = ("renderer %d after render %d: %d pixels differ from the exact "
                                  "spheres (%d expected, %d covered), no error" % (
                                      r, step, wrong.sum(), expected.sum(), got.sum()))


def run_case(seed, index, without=(), verbose=False):
    np.seterr(all="ignore")
    case = Case(seed, index, without)
    scene = Scene(case)
    values = build_input(case, scene)
    set_mapper_options(case, scene, values)
    build_views(case, scene)
    if verbose:
        print("profile %s, knobs %s" % (case.profile, " ".join(Case.active_knobs(seed, index, without))))
        print("\n".join("  " + line for line in case.log), flush=True)
    broken = {}
    started = time.time()
    re_edit = case.knob("edits")
    steps = 1 + (int(re_edit.integers(1, 5)) if re_edit else 0)
    for step in range(steps):
        if step:
            edit(case, scene, re_edit, step)
            if verbose:
                print("  " + case.log[-1], flush=True)
        for window in scene.windows:
            window.Render()
        check_render(case, scene, broken, step)
    return dict(index=index, without=sorted(case.without), active=case.active, profile=case.profile,
                broken=broken, errors=scene.errors[:3], seconds=round(time.time() - started, 3),
                status="invariant" if broken else "error" if scene.errors else "ok", log=case.log)


# ---------------------------------------------------------------------------------------------
# The parent: one process per case

def run_child(seed, index, without, timeout):
    """Runs one case in a process of its own; retries X refusals. Returns a result dict."""
    command = [sys.executable, os.path.abspath(__file__), "--seed", str(seed), "--replay",
               str(index), "--json"] + (["--without", ",".join(without)] if without else [])
    for attempt in range(4):
        try:
            run = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 timeout=timeout, text=True, errors="replace")
        except subprocess.TimeoutExpired:
            return dict(status="hang", signature="hang (> %g s)" % timeout)
        if run.returncode != 0 and any(text in run.stderr for text in X_REFUSALS):
            time.sleep(1.0 + attempt)
            continue
        sanitizer = SANITIZER.search(run.stderr)
        lines = [line for line in run.stdout.splitlines() if line.startswith("R ")]
        if sanitizer or run.returncode not in (0, 3) or not lines:
            kind = (sanitizer.group(2) or "UB: " + re.sub(r"\d+", "N", sanitizer.group(3))[:80]) \
                if sanitizer else "exit %d" % run.returncode if run.returncode >= 0 else \
                "signal %d" % -run.returncode
            frames = re.findall(r"#\d+ 0x[0-9a-f]+ in (\S+)", run.stderr)
            where = next((f for f in frames if "DirectSurface" in f or "tetdsr" in f),
                         frames[0] if frames else "?")
            return dict(status="crash", signature="%s in %s" % (kind, where),
                        stderr=run.stderr.splitlines()[-40:])
        return json.loads(lines[-1][2:])
    return dict(status="refused-display", signature="X refused 4 times")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=None)
    parser.add_argument("--cases", type=int, default=None)
    parser.add_argument("--minutes", type=float, default=None)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per case")
    parser.add_argument("--first", type=int, default=0)
    parser.add_argument("--out", default="fuzz-mapper-failures")
    parser.add_argument("--replay", type=int, default=None)
    parser.add_argument("--without", default="")
    parser.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.seed is None:
        args.seed = int(time.time()) % 1000000
    without = [k for k in args.without.split(",") if k]
    if args.replay is not None:
        result = run_case(args.seed, args.replay, without, verbose=not args.json)
        if args.json:
            print("R " + json.dumps(result, default=str), flush=True)
        else:
            print(json.dumps({k: result[k] for k in ("status", "broken", "errors", "seconds")},
                             indent=1, default=str))
        os._exit(3 if result["status"] == "invariant" else 0)  # (no teardown of the windows)

    stop_at = time.time() + 60 * args.minutes if args.minutes else None
    count = args.cases if args.cases is not None else (None if stop_at else 50)
    tally = dict(cases=0, ok=0, error=0, crash=0, hang=0, invariant=0, harness=0)
    tally["refused-display"] = 0
    profiles = dict(clean=0, hostile=0)
    classes, failures = {}, []
    env = " ".join("%s=%s" % (k, os.environ[k]) for k in
                   ("PYTHONPATH", "LD_PRELOAD", "ASAN_OPTIONS", "UBSAN_OPTIONS") if k in os.environ)
    script = "%s %s" % (sys.executable, os.path.abspath(__file__))
    print("fuzz_mapper: seed %d, %s, timeout %g s" % (
        args.seed, "%d cases" % count if count is not None else "%g minutes" % args.minutes,
        args.timeout), flush=True)
    started = time.time()
    index = args.first
    while (count is None or index < args.first + count) and not (stop_at and time.time() > stop_at):
        result = run_child(args.seed, index, without, args.timeout)
        tally["cases"] += 1
        tally[result["status"]] = tally.get(result["status"], 0) + 1
        if "profile" in result:
            profiles[result["profile"]] += 1
        if result["status"] not in ("ok", "error"):
            sig = result.get("signature") or "invariant: " + sorted(result["broken"])[0]
            entry = classes.setdefault(sig, dict(count=0, first=index))
            entry["count"] += 1
            failures.append((index, sig, result))
            print("case %d: %s" % (index, sig), flush=True)
        index += 1
    elapsed = time.time() - started
    if failures:
        os.makedirs(args.out, exist_ok=True)
        for index, sig, result in failures:
            result.update(seed=args.seed, signature=sig, replay="%s %s --seed %d --replay %d" % (
                env, script, args.seed, index))
            with open(os.path.join(args.out, "seed%d-case%d.json" % (args.seed, index)), "w") as f:
                json.dump(result, f, indent=1, default=str)
    header = ("cases", "drawn", "refused", "crashes", "hangs", "invariant", "X-refused", "seconds")
    print("\n" + " ".join("%-9s" % h for h in header))
    print(" ".join("%-9d" % v for v in (
        tally["cases"], tally["ok"], tally["error"], tally["crash"], tally["hang"],
        tally["invariant"], tally["refused-display"], elapsed)))
    print("(%d clean cases checked against the exact spheres, %d hostile; drawn: no error, "
          "invariants hold; refused: handled with an error message)" % (
              profiles["clean"], profiles["hostile"]))
    if classes:
        print("\nDistinct failures (count, first case):")
        for sig, entry in sorted(classes.items(), key=lambda e: -e[1]["count"]):
            print("  %4d  case %-6d %s" % (entry["count"], entry["first"], sig))
            print("        %s --seed %d --replay %d" % (script, args.seed, entry["first"]))
        print("Failing cases written to %s/; replay in this environment:\n  %s" % (args.out, env))
    return 1 if classes or tally["refused-display"] else 0


if __name__ == "__main__":
    sys.exit(main())
