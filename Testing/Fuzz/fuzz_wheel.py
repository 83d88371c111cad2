"""Fuzzer of the wheel: the binding tetdsr._core and the Python filter tetdsr.vtkDirectSurfaceRayCaster.

Every case is made from (seed, case index) alone, so any case can be replayed. Cases run in
worker processes (each runs many cases; a crash or a hang costs one restart). A case is either
  core:   PreparedMesh.prepare with arrays of every dtype (bool, float16..float64, int8..uint64,
          complex, object), layout (C, Fortran order, strided views, 0-d and 3-d), length and
          value (NaN, inf, ids out of range, negative offsets); then Renderers with hostile
          output arrays, settings, cameras and iso-values, calls out of order (cast after
          another prepare, point_values before one, arrays edited in place after prepare) and
          Python threads making and casting Renderers on one mesh while another prepares it;
  filter: the filter on meshes with hostile arrays and every setter given hostile values (NaN,
          inf, strings, floats for integers, huge integers, wrong VTK types, None), arrays
          edited in place without Modified() between Updates.
Both also take meshes of Lagrange and Bezier tetrahedra of orders 1-5 mixed with VTK_TETRA and
VTK_QUADRATIC_TETRA and straight hexahedra and wedges (higher_order_cases.py): hostile id counts,
cells given hexahedron, wedge and pyramid types with any id count, nodes bent by small to huge
amounts or NaN, fields near the largest double, RationalWeights of every kind and length, and
weights, types or points edited after prepare; where their arrays are otherwise untouched, the
skip counts, warnings and refusals must be those higher_order_cases.predict gives (so must the
filter's refusal of a grid whose cells are all of types or id counts it does not read).
Allowed: an image, or a refusal (a Python exception of the binding's kinds: TypeError,
ValueError, RuntimeError, MemoryError, OverflowError; or the filter's error message). Failures:
a crash, a hang, a Python traceback printed from inside VTK's pipeline, an exception of another
kind, and broken invariants of a cast image:
  miss: depth +inf, cell id -1;  hit: finite depth >= 0, a cell id of the mesh;
  the filter without an error: the whole image of the asked size.

Usage (run with the venv's python where `pip install .` put the wheel):
  fuzz_wheel.py [--seed S] [--cases N | --minutes M] [--timeout T] [--jobs J] [--out DIR]
  fuzz_wheel.py --seed S --replay I      (one case, in this process, telling its steps)
Exit status: 0 when every case was rendered or refused, 1 otherwise.
"""
import argparse
import json
import os
import signal
import sys
import threading
import time
import traceback

import numpy as np

import higher_order_cases as ho
from fuzz_common import Case as BaseCase, case_output, counter, pick, serve
from fuzz_common import run_tasks as run_workers

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
from kuhn_lattice import lattice  # noqa: E402

VTK_TETRA, VTK_HEXAHEDRON, VTK_HEXAGONAL_PRISM, VTK_PENTAGONAL_PRISM, VTK_QUADRATIC_TETRA = 10, 12, 16, 15, 24
ALLOWED = (TypeError, ValueError, RuntimeError, MemoryError, OverflowError)
DTYPES = [np.bool_, np.float16, np.float32, np.float64, np.int8, np.uint8, np.int16, np.uint16,
          np.int32, np.uint32, np.int64, np.uint64, np.complex64, object]


class Case(BaseCase):
    """A case's choices (fuzz_common.Case): one random stream per named step, no knobs."""

    def __init__(self, seed, index):
        super().__init__(seed, index)
        self.kind = "core" if np.random.default_rng([seed, index, 0]).random() < 0.6 else "filter"


def base_mesh(case):
    rng = case.rng("mesh")
    n = int(rng.integers(1, 4))
    points, cells = lattice(n, oriented=False)  # (as walked: the odd tets inverted)
    centre = rng.uniform(-0.5, 0.5, 3)
    field = np.sum((points - centre) ** 2, axis=1)
    case.note("mesh: lattice %d (%d cells), field |x - c|^2" % (n, len(cells)))
    return points, cells, field


# Ray tests of bent order-3/4 cells a case may cost (each a subdivision solve of 100-300 us; see
# fuzz_filter.py's CURVED_HIGHER_ORDER_TESTS): a case casts up to 3 renderers, each ray counted
# as testing every bent order-3/4 cell, so rays <= 3000 / (3 x bent cells).
CURVED_HIGHER_ORDER_TESTS = 3000


def higher_order_mesh(case, hostile):
    """The lattice's cells as Lagrange and Bezier tetrahedra of orders 1-5 (mixed with VTK_TETRA
    and VTK_QUADRATIC_TETRA), some bent (a little, or by hostile amounts), some with hostile id
    counts, and RationalWeights. Returns (points, types, offsets, connectivity, field, weights,
    rays allowed per renderer)."""
    rng = case.rng("higher_order")
    points, cells, _ = base_mesh(case)
    mesh, what = ho.make_mesh(rng, points[cells[:, :4]], hostile)
    amplitude = float(pick(rng, [0.0, 0.0, 1e-3, 0.03] + ([0.3, 3.0, 1e150, 1e300, np.nan]
                                                          if hostile else [])))
    if rng.random() < 0.3:  # straight hexahedra and wedges (split into tetrahedra by the core)
        what += ", " + ho.straight_split_cells(rng, mesh, float(pick(rng, [0.2, 0.5, 1.0])))[0]
    moved = ho.bend(rng, mesh, amplitude, 0.5, vertices_too=hostile and rng.random() < 0.2) \
        if amplitude else []
    what += ", %d cells bent by %g" % (len(moved), amplitude)
    cost = ho.curved_cost_cells(mesh, moved)
    if hostile and rng.random() < 0.3:
        what += ", " + ho.hostile_counts(rng, mesh, int(rng.integers(1, 3)))
    if hostile and rng.random() < 0.3:  # hexahedron, wedge and pyramid types, any id count
        made, split_cost = ho.hostile_split_cells(rng, mesh, int(rng.integers(1, 4)))
        what += ", " + made
        cost += split_cost
    centre = rng.uniform(-0.5, 0.5, 3)
    with np.errstate(all="ignore"):
        field = np.sum((mesh.points - centre) ** 2, axis=1)
    if hostile and rng.random() < 0.2:  # near the largest double
        field *= float(pick(rng, [1.7976931348623157e308, 1e308 / 35])) / np.nanmax(field)
    weights = None
    if rng.random() < 0.4:
        bezier = [c for c in range(len(mesh.types)) if mesh.types[c] in ho.BEZIER_TYPES]
        weights, kind = ho.rational_weights(rng, len(mesh.points), bezier, mesh)
        what += ", weights %s %s %s" % (kind, weights.dtype, weights.shape)
    case.note("higher order: " + what)
    rays = max(1, CURVED_HIGHER_ORDER_TESTS // (3 * cost)) if cost else None
    return mesh.points, mesh.types, mesh.offsets, mesh.conn, field, weights, rays


def shrink_to(h, w, rays):
    while rays and h * w > rays:
        h, w = max(1, h // 2), max(1, w // 2)
    return h, w


def check_prepare(case, arrays, ready, messages, summary, broken):
    """The oracle on a prepare of unmodified higher-order arrays: the predicted error, or the
    skip counts and warnings higher_order_cases.predict gives."""
    weights = arrays.get("rational_weights")
    reasons, error = ho.predict(arrays["cell_types"], arrays["offsets"], arrays["connectivity"],
                                np.asarray(arrays["points"], np.float64),
                                np.asarray(arrays["field"], np.float64), weights)
    if reasons is None:
        return
    ho.check_refusal(error, list(messages.errors), broken, "prepare:")
    if error:  # (an earlier error, e.g. of the component asked for, may come instead)
        if ready or not messages.errors:
            broken["prepare:error-missing: " + error] = "ready %s, errors %s" % (
                ready, [e[:120] for e in messages.errors[:2]])
        return
    if not ready:
        return  # refused for what the oracle does not predict (geometry)
    counts = {name: summary[key] for name, key in ho.SUMMARY_KEY.items()}
    ho.check_counts(reasons, counts, list(messages.warnings), broken, "prepare:")
    if counts["Rendered"] + sum(counts[k] for k in ho.SUMMARY_KEY if k != "Rendered") != \
            len(arrays["cell_types"]):
        broken["prepare:cell-counts"] = "%s for %d cells" % (counts, len(arrays["cell_types"]))


def hostile_array(case, rng, array, name, ids=False):
    """`array` with its dtype, layout, length or values changed (or unchanged)."""
    what = pick(rng, ["same"] * 3 + ["dtype", "fortran", "strided", "ndim", "length", "values"])
    if what == "dtype":
        dtype = pick(rng, DTYPES)
        with np.errstate(all="ignore"):
            array = array.astype(dtype)
    elif what == "fortran" and array.ndim == 2:
        array = np.asfortranarray(array)
    elif what == "strided":
        wide = np.repeat(array, 2, axis=0)
        array = wide[::2]
    elif what == "ndim":
        array = pick(rng, [np.asarray(array.ravel()[0] if array.size else 0),
                           array.reshape(array.shape[0], -1, 1) if array.size else array[None],
                           array.ravel()])
    elif what == "length":
        keep = int(rng.integers(0, max(1, array.shape[0] if array.ndim else 1) + 2))
        array = array[:keep] if array.ndim else array
    elif what == "values" and array.size:
        array = array.astype(np.float64 if not ids else np.int64).copy()
        flat = array.reshape(-1)
        k = rng.integers(0, flat.size, size=int(rng.integers(1, 4)))
        if ids:
            flat[k] = pick(rng, [-1, 10 ** 12, 2 ** 62, -2 ** 63, flat.size])
        else:
            flat[k] = pick(rng, [np.nan, np.inf, -np.inf, 1e300, -1e300, 0.0])
    case.note("%s: %s -> dtype %s shape %s %s" % (name, what, array.dtype, array.shape,
                                                  "C" if array.flags.c_contiguous else "not C"))
    return array


# ---------------------------------------------------------------------------------------------
# The binding

def check_image(out, ncells, broken, where):
    depth, ids = out["depth"], out["cell_ids"]
    miss = ~np.isfinite(depth)
    if np.any(depth[miss] != np.inf) or np.any(ids[miss] != -1):
        broken[where + ":miss-not-clean"] = "%d misses with depth or id set" % int(
            np.count_nonzero((depth[miss] != np.inf) | (ids[miss] != -1)))
    hit = ~miss
    if np.any(depth[hit] < 0) or np.any((ids[hit] < 0) | (ids[hit] >= ncells)):
        broken[where + ":hit-bad"] = "depth %s, ids %s for %d cells" % (
            depth[hit].min() if hit.any() else None, np.unique(ids[hit])[:5], ncells)


def out_arrays(case, rng, h, w, colour):
    out = dict(colors=np.zeros((h, w, 4), np.uint8), depth=np.zeros((h, w)),
               normals=np.zeros((h, w, 3)), cell_ids=np.zeros((h, w), np.int64))
    if colour:
        out["color_values"] = np.zeros((h, w))
    if rng.random() < 0.25:
        name = pick(rng, sorted(out))
        out[name] = hostile_array(case, rng, out[name], "output " + name)
    return out


def make_settings(core, case, rng, mesh, npoints):
    settings = core.RenderSettings()
    settings.normals.mode = pick(rng, list(core.NormalMode.__members__.values()))
    if rng.random() < 0.3:
        settings.normals.relative_step = float(pick(rng, [1e-3, 0.0, -1.0, np.nan, 1e300]))
    colour = rng.random() < 0.4
    if colour:
        values = np.random.default_rng(1).normal(size=(npoints, int(rng.integers(1, 4))))
        values = hostile_array(case, rng, values, "colour array")
        result = mesh.point_values(values, "c", int(rng.integers(0, 3)), "colour array", core.Messages())
        if result is not None:
            settings.color_by = core.ColorByArray(result, int(rng.integers(-2, 3)),
                                                  bool(rng.random() < 0.2))
        if rng.random() < 0.9:
            settings.color_table = core.sample_color_table(lambda v: (0.5, v % 1, 0.2), 0.0, 1.0,
                                                           float(rng.normal()), float(rng.normal()))
    if rng.random() < 0.3:
        settings.clip_planes = [core.ClipPlane(tuple(rng.normal(size=3)), tuple(pick(
            rng, [rng.normal(size=3), np.zeros(3), np.full(3, np.nan)]))) for _ in range(
            int(rng.integers(0, 8)))]
        settings.cap = pick(rng, list(core.CapRegion.__members__.values()))
    if rng.random() < 0.2:
        settings.iso_styles = core.IsoValueStyles().styles(int(rng.integers(0, 5)), (1, 0, 0),
                                                           float(pick(rng, [1.0, 0.5, np.nan])))
    return settings, colour


def make_camera(core, rng):
    camera = core.Camera()
    camera.position = tuple(pick(rng, [rng.normal(size=3) * 4, np.array([0.0, 0.0, 5.0]),
                                       np.full(3, np.nan), np.full(3, 1e300)]))
    camera.focal_point = tuple(rng.normal(size=3) * 0.2)
    camera.view_up = tuple(pick(rng, [np.array([0.0, 1.0, 0.0]), np.zeros(3), rng.normal(size=3)]))
    camera.view_angle = float(pick(rng, [30.0, 30.0, 0.0, 180.0, np.nan, -5.0]))
    camera.parallel_projection = bool(rng.random() < 0.3)
    camera.parallel_scale = float(pick(rng, [1.0, 1.0, 0.0, np.inf]))
    return camera


def refused(call, case, what):
    """Runs call(); an exception of an allowed kind is a refusal (returns None)."""
    try:
        return call()
    except ALLOWED as error:
        case.note("%s refused: %s: %s" % (what, type(error).__name__, str(error)[:120]))
        return None


def run_core(case):
    from tetdsr import _core as core
    broken = {}
    rng = case.rng("arrays")
    rays = None
    if case.rng("kind").random() < 0.4:
        points, types, offsets, connectivity, field, weights, rays = higher_order_mesh(
            case, case.rng("kind").random() < 0.6)
        ncells = len(types)
        cells = None
    else:
        points, cells, field = base_mesh(case)
        types = np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8)
        offsets = np.arange(0, cells.size + 1, 10, dtype=np.int64)
        connectivity = cells.ravel().copy()
        weights = None
        ncells = len(cells)
    arrays = dict(points=points, cell_types=types, offsets=offsets, connectivity=connectivity,
                  field=field)
    if weights is not None:
        arrays["rational_weights"] = weights
    as_made = dict(arrays)
    for name in list(arrays):
        if rng.random() < (0.35 if cells is not None else 0.15):
            arrays[name] = hostile_array(case, rng, arrays[name], name,
                                         ids=name in ("offsets", "connectivity"))
    pristine = cells is None and all(arrays[k] is as_made[k] for k in arrays)
    mesh = core.PreparedMesh()
    order = case.rng("order")
    if order.random() < 0.15:  # before any prepare
        refused(lambda: mesh.point_values(field, "f", 0, "colour array", core.Messages()), case,
                "point_values before prepare")
        refused(lambda: mesh.bounds(), case, "bounds before prepare")
    messages = core.Messages()
    ready = refused(lambda: mesh.prepare(**arrays, field_name="f",
                                         component=int(pick(rng, [0, 0, 0, 1, -1, 5])),
                                         threads=int(pick(rng, [0, 1, 2, 3])), messages=messages),
                    case, "prepare")
    case.note("prepare: %s, errors %s" % (ready, messages.errors[:1]))
    if pristine and ready is not None:
        check_prepare(case, arrays, ready, messages, mesh.summary, broken)
    if order.random() < 0.3:  # an in-place edit of the caller's arrays, after validation
        target = arrays[pick(order, sorted(arrays))]
        if target.size and target.flags.writeable and target.dtype != object:
            value = pick(order, [10 ** 6, -1, 0])
            try:
                with np.errstate(all="ignore"):
                    target.reshape(-1)[order.integers(0, target.size)] = value
                case.note("edited an input array in place after prepare (%d)" % value)
            except (OverflowError, ValueError):  # a value the dtype cannot hold: no edit
                pass
    renderers = []
    steps = int(order.integers(1, 4))
    for step in range(steps):
        srng = case.rng("renderer%d" % step)
        h, w = shrink_to(int(srng.integers(1, 40)), int(srng.integers(1, 40)), rays)
        settings, colour = refused(lambda: make_settings(core, case, srng, mesh, len(points)), case,
                                   "settings") or (core.RenderSettings(), False)
        isos = pick(srng, [[0.3], [0.1, 0.5], [], [np.nan], list(np.linspace(0, 2, 50)), [1e300]])
        out = out_arrays(case, srng, h, w, colour and srng.random() < 0.8)
        renderer = refused(lambda: core.Renderer(mesh, isos, make_camera(core, srng), settings,
                                                 **out, threads=int(srng.integers(0, 4))),
                           case, "Renderer")
        if renderer is not None:
            renderers.append((renderer, out))
        if order.random() < 0.2:  # prepare again: every earlier Renderer must refuse
            refused(lambda: mesh.prepare(points, types, offsets, connectivity, field,
                                         messages=core.Messages(), rational_weights=weights),
                    case, "prepare again")
            case.note("prepared again")
        for r, o in renderers:
            done = refused(lambda: r.cast(int(srng.integers(0, 4))), case, "cast")
            if done is not None and done == r.number_of_tiles:
                check_image(o, ncells, broken, "step%d" % step)
            if srng.random() < 0.5:  # picks and window depths, with hostile arguments
                x, y = pick(srng, [(0.5, 0.5), (np.nan, 1.0), (1e308, -1e308), (w / 2, h / 2),
                                   (-3.0, 2.0), (np.inf, 0.0)])
                values = pick(srng, [[], [field], [np.zeros(1)], [np.ones((len(points), 3))],
                                     [np.ones((len(points), 0))], [field.astype(np.float32)]])
                refused(lambda: r.pick(x, y, values), case, "pick")
                matrix = pick(srng, [np.eye(4), np.full((4, 4), np.nan), np.eye(3),
                                     np.zeros((4, 4)), np.ones((4, 4)) * 1e308])
                depth = pick(srng, [np.empty((h, w), np.float32), np.empty((w + 1, h), np.float32),
                                    np.empty((h, w), np.float64)])
                refused(lambda: r.window_depth(matrix, depth), case, "window_depth")
    if order.random() < 0.3 and cells is not None:
        concurrent_renderers(core, case, points, cells, field, broken)
    return broken


def concurrent_renderers(core, case, points, cells, field, broken):
    """Threads making and casting Renderers on one mesh, one thread preparing it again."""
    rng = case.rng("threads")
    mesh = core.PreparedMesh()
    mesh.prepare(points, np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8),
                 np.arange(0, cells.size + 1, 10), cells.ravel(), field, messages=core.Messages())
    errors = []
    unexpected = []

    def worker(k):
        local = np.random.default_rng([case.seed, case.index, 99, k])
        for _ in range(int(rng.integers(3, 15))):
            try:
                if k == 0 and local.random() < 0.3:
                    mesh.prepare(points, np.full(len(cells), VTK_QUADRATIC_TETRA, np.uint8),
                                 np.arange(0, cells.size + 1, 10), cells.ravel(), field,
                                 messages=core.Messages())
                    continue
                out = dict(colors=np.zeros((8, 8, 4), np.uint8), depth=np.zeros((8, 8)),
                           normals=np.zeros((8, 8, 3)), cell_ids=np.zeros((8, 8), np.int64))
                settings = core.RenderSettings()
                settings.normals.mode = pick(local, list(core.NormalMode.__members__.values()))
                camera = core.Camera()
                camera.position = (2.2, 1.6, 3.0)
                r = core.Renderer(mesh, [float(local.uniform(0.05, 2.0))], camera, settings, **out)
                if r.cast(int(local.integers(1, 3))) == r.number_of_tiles:
                    check_image(out, len(cells), broken, "threads")
            except ALLOWED as error:
                errors.append(str(error))
            except Exception as error:  # noqa: BLE001 (what the fuzzer looks for)
                unexpected.append("%s: %s" % (type(error).__name__, error))

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(int(rng.integers(2, 6)))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    case.note("threads: %d, refusals %d %s" % (len(threads), len(errors), sorted(set(errors))[:2]))
    if unexpected:
        broken["threads:unexpected-exception"] = unexpected[0]


# ---------------------------------------------------------------------------------------------
# The filter

HOSTILE_VALUES = [float("nan"), float("inf"), -1e300, 2.7, -3, 0, 10 ** 9, 2 ** 31 - 1, 10 ** 12,
                  2 ** 64, "x", None,
                  (1, 2), True, np.float32(0.5), np.int64(2)]
SETTERS = {  # setter: how many arguments
    "SetValue": 2, "SetNumberOfContours": 1, "GenerateValues": 3, "SetImageSize": 2,
    "SetArrayComponent": 1, "SetSurfaceColor": 3, "SetAmbient": 1, "SetDiffuse": 1,
    "SetSpecular": 1, "SetSpecularPower": 1, "SetLightAtCamera": 1, "SetLightPosition": 3,
    "SetNormalMode": 1, "SetCentralDifferenceStep": 1, "SetIsoValueColor": 4,
    "SetIsoValueOpacity": 2, "SetColorByArray": 1, "SetColorArrayComponent": 1,
    "SetColorRange": 2, "SetColorMap": 1, "SetCapping": 1, "SetTransverseTest": 1,
    "SetNodalRangeWidening": 1, "SetNumberOfThreads": 1, "SetCamera": 1, "SetLookupTable": 1,
    "SetClippingPlanes": 1, "AddClippingPlane": 1,
}


def run_filter(case):
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
    from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand, vtkPoints
    from vtkmodules.vtkCommonDataModel import (vtkCellArray, vtkMultiBlockDataSet, vtkPlane,
                                               vtkUnstructuredGrid)
    from vtkmodules.vtkRenderingCore import vtkCamera
    from tetdsr import vtkDirectSurfaceRayCaster

    broken = {}
    points, cells, field = base_mesh(case)
    rng = case.rng("grid")
    grid = vtkUnstructuredGrid()
    what = pick(rng, ["plain"] * 5 + ["higher-order"] * 4 +
                ["empty", "all-nan", "no-cells", "multiblock", "unread"])
    case.note("grid: %s" % what)
    rays = None
    warnings = []
    if what == "higher-order":
        points, types, offsets, conn, field, weights, rays = higher_order_mesh(
            case, rng.random() < 0.6)
        p = vtkPoints()
        p.SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=1))
        grid.SetPoints(p)
        ca = vtkCellArray()
        ca.SetData(numpy_to_vtkIdTypeArray(offsets.copy(), deep=1),
                   numpy_to_vtkIdTypeArray(conn.copy(), deep=1))
        grid.SetCells(numpy_to_vtk(types, deep=1), ca)
        for name, v in (("f", field), ("g", points.copy())):
            array = numpy_to_vtk(np.ascontiguousarray(v), deep=1)
            array.SetName(name)
            grid.GetPointData().AddArray(array)
        grid.GetPointData().SetActiveScalars("f")
        if weights is not None:
            array = numpy_to_vtk(np.ascontiguousarray(weights), deep=1)
            array.SetName("RationalWeights")
            grid.GetPointData().SetRationalWeights(array)
        cells = np.zeros((len(types), 0))  # (only its length is used below)
    elif what == "multiblock":
        grid = vtkMultiBlockDataSet()
    elif what != "empty":
        p = vtkPoints()
        p.SetData(numpy_to_vtk(points, deep=1))
        grid.SetPoints(p)
        if what != "no-cells":
            ca = vtkCellArray()
            ca.SetData(numpy_to_vtkIdTypeArray(np.arange(0, cells.size + 1, 10), deep=1),
                       numpy_to_vtkIdTypeArray(cells.ravel().copy(), deep=1))
            # "unread": every cell (10 ids) of a type not read (a hexagonal or pentagonal prism) or
            # of an id count its type is not read with (a hexahedron): refused.
            unread = pick(rng, [VTK_HEXAGONAL_PRISM, VTK_PENTAGONAL_PRISM, VTK_HEXAHEDRON])
            types = np.full(len(cells), unread if what == "unread" else VTK_QUADRATIC_TETRA,
                            np.uint8)
            if what == "unread":
                case.note("unread: every cell of type %d" % unread)
            grid.SetCells(numpy_to_vtk(types, deep=1), ca)
        values = np.full_like(field, np.nan) if what == "all-nan" else field
        for name, v in (("f", values), ("g", points.copy())):
            array = numpy_to_vtk(np.ascontiguousarray(v), deep=1)
            array.SetName(name)
            grid.GetPointData().AddArray(array)
        grid.GetPointData().SetActiveScalars("f")
    caster = vtkDirectSurfaceRayCaster()
    errors = []
    caster.AddObserver(vtkCommand.ErrorEvent, lambda o, e, *a: errors.append(e))
    error_texts = []

    @calldata_type(VTK_STRING)
    def on_error(obj, event, text):
        error_texts.append(str(text))

    caster.AddObserver(vtkCommand.ErrorEvent, on_error)
    caster.SetInputDataObject(0, grid)
    caster.SetValue(0, 0.4)
    caster.AddObserver(vtkCommand.WarningEvent, lambda o, e, *a: warnings.append(
        o.GetLastWarning() if hasattr(o, "GetLastWarning") else ""))
    caster.SetImageSize(*shrink_to(int(rng.integers(1, 48)), int(rng.integers(1, 48)), rays))
    camera = vtkCamera()
    camera.SetPosition(2.2, 1.6, 3.0)
    caster.SetCamera(camera)
    srng = case.rng("setters")
    for _ in range(int(srng.integers(0, 8))):
        name = pick(srng, sorted(SETTERS))
        args = []
        for k in range(SETTERS[name]):
            if name in ("SetCamera", "SetLookupTable", "SetClippingPlanes", "AddClippingPlane"):
                args.append(pick(srng, [None, vtkCamera(), vtkPlane(), grid, 3, "x"]))
            else:
                args.append(pick(srng, HOSTILE_VALUES) if srng.random() < 0.7
                            else float(srng.normal()))
        if name == "SetColorByArray" and srng.random() < 0.5:
            caster.SetInputArrayToProcess(1, 0, 0, 0, pick(srng, ["g", "f", "none"]))
        refused(lambda: getattr(caster, name)(*args), case, "%s%r" % (name, tuple(args)))
    errors.clear()
    error_texts.clear()
    caster.Update()
    check_filter(caster, errors, broken, "first", vtk_to_numpy, len(cells))
    if what == "higher-order":
        check_filter_counts(caster, grid, vtk_to_numpy, broken, "first:", errors, error_texts)
    if what == "unread":  # refused, and (if for the cells) as predicted: none is read
        if not errors:
            broken["unread:not-refused"] = "no error, %d cells rendered" % (
                caster.GetNumberOfRenderedCells())
        ho.check_refusal(ho.NO_CELL + ": none of the", error_texts, broken, "unread:")
    refused_first = bool(errors)
    if what == "higher-order" and rng.random() < 0.5:  # edits after prepare, with Modified()
        edit = pick(rng, ["weights", "types", "points"])
        if edit == "weights" or grid.GetPointData().GetRationalWeights() is None:
            array = numpy_to_vtk(1.0 + np.arange(grid.GetNumberOfPoints()) % 3.0, deep=1)
            array.SetName("RationalWeights")
            grid.GetPointData().SetRationalWeights(array)
        elif edit == "types":
            t = vtk_to_numpy(grid.GetCellTypesArray())
            t[:] = np.where((t >= 71) & (t <= 73), t + 7, t)  # Lagrange -> Bezier tet, hex, wedge
            grid.GetCellTypesArray().Modified()
        else:
            vtk_to_numpy(grid.GetPoints().GetData())[:5] = np.nan
            grid.GetPoints().GetData().Modified()
        case.note("edited %s after prepare, Modified()" % edit)
        caster.Modified()  # the pipeline does not see an array's Modified(): the filter's own check
        errors.clear()
        error_texts.clear()
        caster.Update()
        check_filter(caster, errors, broken, "edited", vtk_to_numpy, len(cells))
        check_filter_counts(caster, grid, vtk_to_numpy, broken, "edited:", errors, error_texts)
    if what == "plain" and rng.random() < 0.5:  # edited in place without Modified()
        edit = pick(rng, ["ids", "points", "field"])
        if edit == "ids":
            vtk_to_numpy(grid.GetCells().GetConnectivityArray())[:] = pick(rng, [10 ** 12, -5])
        elif edit == "points":
            vtk_to_numpy(grid.GetPoints().GetData())[:3] = np.nan
        else:
            vtk_to_numpy(grid.GetPointData().GetArray("f"))[:] = -1.0
        change = pick(rng, ["ColorByArrayOn", "SetNormalMode", "SetValue", "Modified"])
        if change == "ColorByArrayOn":
            caster.ColorByArrayOn()
            caster.SetInputArrayToProcess(1, 0, 0, 0, "g")
        elif change == "SetNormalMode":
            caster.SetNormalMode(int(rng.integers(0, 4)))
        elif change == "SetValue":
            caster.SetValue(0, 0.7)
        else:
            caster.Modified()
        case.note("edited %s without Modified(), then %s" % (edit, change))
        if refused_first:  # else an unchanged filter does not execute (nor say again why)
            caster.Modified()
        errors.clear()
        caster.Update()
        check_filter(caster, errors, broken, "after-edit", vtk_to_numpy, len(cells))
    return broken


def check_filter_counts(caster, grid, vtk_to_numpy, broken, where, errors, error_texts):
    """The filter's skip counters against higher_order_cases.predict on its input (after an
    Update without errors), or its refusal for the cells (after one with)."""
    cells = grid.GetCells()
    weights = grid.GetPointData().GetRationalWeights()
    reasons, error = ho.predict(
        vtk_to_numpy(grid.GetCellTypesArray()), vtk_to_numpy(cells.GetOffsetsArray()),
        vtk_to_numpy(cells.GetConnectivityArray()).astype(np.int64),
        vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64),
        vtk_to_numpy(grid.GetPointData().GetArray("f")).astype(np.float64),
        None if weights is None else vtk_to_numpy(weights))
    if reasons is None:
        return
    if errors:
        ho.check_refusal(error, error_texts, broken, where)
        return
    if error:
        broken[where + "error-missing: " + error] = "no error"
        return
    counts = {name: getattr(caster, "GetNumberOf%sCells" % name)() for name in ho.SUMMARY_KEY
              if name != "Rendered"}
    ho.check_counts(reasons, counts, None, broken, where)


def check_filter(caster, errors, broken, where, vtk_to_numpy, ncells):
    if errors:
        return
    output = caster.GetOutput()
    width, height = caster.GetImageSize()
    if output.GetNumberOfPoints() != width * height:
        broken[where + ":incomplete-output"] = "%d points for %d x %d, no error" % (
            output.GetNumberOfPoints(), width, height)
        return
    data = output.GetPointData()
    if data.GetArray("Depth") is None or data.GetArray("CellId") is None:
        broken[where + ":incomplete-output"] = "no Depth or CellId array, no error"
        return
    out = dict(depth=vtk_to_numpy(data.GetArray("Depth")),
               cell_ids=vtk_to_numpy(data.GetArray("CellId")))
    check_image(out, ncells, broken, where)


# ---------------------------------------------------------------------------------------------
# One case, workers and the parent

def run_case(seed, index, verbose=False):
    case = Case(seed, index)
    result = dict(index=index, kind=case.kind)
    try:
        broken = run_core(case) if case.kind == "core" else run_filter(case)
        result["status"] = "invariant" if broken else "ok"
        result["broken"] = broken
    except ALLOWED as error:
        result["status"] = "refused-late"  # an allowed exception where the harness expected none
        result["broken"] = {}
        case.note("%s: %s" % (type(error).__name__, error))
    except Exception as error:  # noqa: BLE001
        result["status"] = "unexpected"
        result["broken"] = {"unexpected": "%s: %s" % (type(error).__name__, error)}
        result["trace"] = traceback.format_exc()[-1500:]
    result["log"] = case.log
    if verbose:
        print("case %d (%s)\n  %s" % (index, case.kind, "\n  ".join(case.log)), flush=True)
    return result


def worker_main(seed):
    """A worker (fuzz_common.serve): case indices in, one result each out."""
    def setup():
        import tetdsr.filter  # noqa: F401 (imports VTK once, before the first case)

    serve(setup, lambda line: run_case(seed, int(line)))


def last_lines(text, n=25):
    return [line for line in case_output(text) if line.strip()][-n:]


def run_tasks(indices, seed, jobs, timeout, on_result, stop_at=None):
    """Runs cases on `jobs` worker processes (fuzz_common.run_tasks); calls on_result(index,
    result). A case that printed a Python traceback (a callback's exception, which VTK only
    prints) fails as "traceback"."""
    def crashed(worker):
        code = worker.proc.returncode
        kind = "signal %s" % signal.Signals(-code).name if code < 0 else "exit %d" % code
        return dict(status="crash", signature=kind, stderr=last_lines(worker.stderr_text()))

    def hung(worker):
        return dict(status="hang", signature="hang (> %g s)" % timeout,
                    stderr=last_lines(worker.stderr_text()))

    def answered(worker, result):
        text = worker.stderr_text()
        if "Traceback (most recent call last)" in text:
            result["status"] = "traceback"
            result["broken"]["traceback"] = last_lines(text, 12)[-1]
            result["stderr"] = last_lines(text)
        return result

    run_workers(indices, jobs, timeout, on_result, stop_at,
                command=[sys.executable, os.path.abspath(__file__), "--worker", "--seed", str(seed)],
                encode=str, startup=120.0, crashed=crashed, hung=hung, answered=answered)


def signature_of(result):
    if result["status"] in ("crash", "hang"):
        return result["signature"] + " in " + (result.get("stderr") or ["?"])[-1][:100]
    return "%s: %s" % (result["status"], sorted(result["broken"].items())[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=None)
    parser.add_argument("--cases", type=int, default=None)
    parser.add_argument("--minutes", type=float, default=None)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per case")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes")
    parser.add_argument("--first", type=int, default=0, help="index of the first case")
    parser.add_argument("--out", default="fuzz-wheel-failures", help="folder for failing cases")
    parser.add_argument("--replay", type=int, default=None, help="run one case in this process")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.seed is None:
        args.seed = int(time.time()) % 1000000
    if args.worker:
        return worker_main(args.seed)
    if args.replay is not None:
        np.seterr(all="ignore")
        result = run_case(args.seed, args.replay, verbose=True)
        print(json.dumps({k: result.get(k) for k in ("status", "broken", "trace")}, indent=1))
        return 0 if result["status"] in ("ok", "refused-late") else 3

    stop_at = time.time() + 60 * args.minutes if args.minutes else None
    count = args.cases if args.cases is not None else (None if stop_at else 100)
    indices = range(args.first, args.first + count) if count is not None else counter(args.first)
    tally = dict(cases=0, core=0, filter=0)
    statuses = {}
    classes = {}
    failures = []

    def on_result(index, result):
        tally["cases"] += 1
        tally[result.get("kind", "core")] = tally.get(result.get("kind", "core"), 0) + 1
        statuses[result["status"]] = statuses.get(result["status"], 0) + 1
        if result["status"] in ("ok", "refused-late"):
            return
        sig = signature_of(result)
        entry = classes.setdefault(sig, dict(count=0, first=index))
        entry["count"] += 1
        failures.append((index, sig, result))
        print("case %d: %s" % (index, sig), flush=True)

    print("fuzz_wheel: seed %d, %s, timeout %g s, %d job(s)" % (
        args.seed, "%d cases" % count if count is not None else "%g minutes" % args.minutes,
        args.timeout, args.jobs), flush=True)
    started = time.time()
    run_tasks(indices, args.seed, args.jobs, args.timeout, on_result, stop_at)
    elapsed = time.time() - started
    script = "%s %s" % (sys.executable, os.path.abspath(__file__))
    if failures:
        os.makedirs(args.out, exist_ok=True)
        for index, sig, result in failures:
            result.update(seed=args.seed, signature=sig,
                          replay="%s --seed %d --replay %d" % (script, args.seed, index))
            with open(os.path.join(args.out, "seed%d-case%d.json" % (args.seed, index)), "w") as f:
                json.dump(result, f, indent=1, default=str)
    print("\ncases %d (core %d, filter %d) in %.0f s; %s" % (
        tally["cases"], tally.get("core", 0), tally.get("filter", 0), elapsed,
        ", ".join("%s %d" % kv for kv in sorted(statuses.items()))))
    print("(ok: cast or refused with a message or an exception of the binding's kinds)")
    if classes:
        print("\nDistinct failures (count, first case, replay):")
        for sig, entry in sorted(classes.items(), key=lambda e: -e[1]["count"]):
            print("  %4d  case %-6d %s\n        %s --seed %d --replay %d" % (
                entry["count"], entry["first"], sig, script, args.seed, entry["first"]))
    return 1 if classes else 0


if __name__ == "__main__":
    sys.exit(main())
