"""Fuzzer of vtkDirectSurfaceRayCaster: random and hostile meshes, fields, cameras and options.

Every case is made from (seed, case index) alone, so any case can be replayed. Cases run in
worker processes (each runs many cases; a crash or a hang costs one restart), and every output
pixel is checked:
  miss: Depth +inf, CellId -1, Normals 0, Colors (0, 0, 0, 0), ColorValues NaN;
  hit:  finite Depth >= 0, CellId of an input cell that is not obviously invalid (type and id
        count, ids in range and distinct, finite coordinates and values), unit normal (zero
        only where the cell's nodal values are all equal);
  an Update without an error message gives the full image of the asked size, renders at least
  one cell and counts every input cell once (rendered or skipped for some reason);
  the skip counters and warnings, and the refusals, are those higher_order_cases.predict gives
  from the input alone (Unsupported, Malformed, OrderTooHigh, InvalidId, Rational, NonFinite
  exactly; Degenerate at least), and a refusal for the cells is the one predicted. Meshes include
  Lagrange and Bezier tetrahedra of orders 1-5, straight hexahedra and wedges of every kind the
  core reads, and (hostile) cells given hexahedron, wedge and pyramid types with any id count.
Errors are allowed (hostile input may be refused); crashes, sanitizer reports, hangs and broken
invariants are failures. Some cases also render the mesh scaled by a power of ten and compare.

A case is a list of "knobs" (mesh, mutations, camera, options), each drawn from its own random
stream, so a failing case shrinks by switching knobs off (--without); failures found are shrunk
automatically, one per distinct signature, and written to --out as JSON with a replay command.

Usage (PYTHONPATH must reach the `tetdsr` package; run with /usr/bin/python3):
  fuzz_filter.py [--seed S] [--cases N | --minutes M] [--timeout T] [--jobs J] [--out DIR]
  fuzz_filter.py --seed S --replay I [--without knob,knob]   (one case, in this process)
Exit status: 0 when every case was rendered or refused with an error, 1 otherwise.
"""
import argparse
import json
import os
import re
import signal
import sys
import time

import numpy as np

import higher_order_cases as ho
from fuzz_common import SANITIZER, Case as BaseCase, case_output, counter, pick, serve
from fuzz_common import run_tasks as run_workers

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
from kuhn_lattice import lattice  # noqa: E402

VTK_TETRA, VTK_HEXAHEDRON, VTK_QUADRATIC_TETRA, VTK_LAGRANGE_TETRAHEDRON = 10, 12, 24, 71
# Node pairs of the six mid-edge nodes of a VTK quadratic tet (nodes 4..9).
MID_EDGES = np.array([(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)])
HUGE_ID = 2 ** 62

# Knobs in the order they are applied, with the probability that a case switches each on
# ("mesh" is always on; the HOSTILE ones only in hostile cases).
KNOBS = {
    "mesh": 1.0,
    "higher_order": 0.3,
    "hex_wedge": 0.2,
    "transform": 0.5,
    "curved": 0.1,
    "inverted": 0.15,
    "scale_coords": 0.12,
    "scale_field": 0.12,
    "unused_points": 0.12,
    "nonfinite_coords": 0.1,
    "nonfinite_field": 0.1,
    "flat_cells": 0.1,
    "ho_bend": 0.5,
    "ho_values": 0.15,
    "ho_counts": 0.12,
    "split_types": 0.12,
    "ho_weights": 0.25,
    "conn_garbage": 0.15,
    "cell_types": 0.15,
    "cell_sizes": 0.1,
    "offsets": 0.08,
    "types_length": 0.04,
    "duplicate_cells": 0.01,
    "points_float32": 0.08,
    "storage32": 0.1,
    "array_layout": 0.15,
    "scalar_array": 0.15,
    "iso_values": 0.5,
    "camera": 0.7,
    "image_size": 0.6,
    "normals": 0.4,
    "clipping": 0.25,
    "iso_styles": 0.25,
    "color_by": 0.25,
    "shading": 0.2,
    "transverse": 0.15,
    "threads": 0.3,
    "reupdate": 0.1,
}
# Knobs that break the mesh itself; off in "clean" and "scale check" cases.
HOSTILE = {"scale_coords", "scale_field", "unused_points", "nonfinite_coords", "nonfinite_field",
           "flat_cells", "ho_bend", "ho_values", "ho_counts", "split_types", "ho_weights", "conn_garbage", "cell_types", "cell_sizes", "offsets", "types_length",
           "duplicate_cells", "points_float32", "scalar_array", "reupdate"}


class Case(BaseCase):
    """A case's choices (fuzz_common.Case): a profile, then one random stream per knob."""

    KNOBS = KNOBS

    def __init__(self, seed, index, without=()):
        super().__init__(seed, index, without)
        profile = np.random.default_rng([seed, index, 0]).random()
        # 25% clean (valid mesh, random options), 10% scale check, the rest hostile.
        self.profile = "clean" if profile < 0.25 else "scale" if profile < 0.35 else "hostile"

    def allows(self, name):
        if name in HOSTILE and self.profile != "hostile":
            return False
        # The scale check edits the arrays in place through numpy.
        return not (name == "array_layout" and self.profile == "scale")


# ---------------------------------------------------------------------------------------------
# Meshes as numpy arrays

class Mesh:
    """Raw arrays, before they become a vtkUnstructuredGrid: nothing here is validated."""

    def __init__(self, points, cells):
        self.points = np.asarray(points, dtype=np.float64)
        cells = np.asarray(cells, dtype=np.int64)
        self.conn = cells.ravel().copy()
        self.offsets = np.arange(0, cells.size + 1, cells.shape[1], dtype=np.int64)
        self.types = np.full(len(cells), VTK_QUADRATIC_TETRA, dtype=np.uint8)
        self.field = None
        self.field_name = "field"
        self.point_dtype = np.float64
        self.storage32 = False
        self.soa_points = False  # points in a structure-of-arrays layout
        self.field_layout = None  # None (float64, AOS) or a vtkSOADataArrayTemplate type name
        self.orders = np.full(len(cells), 2)  # each cell's order as made (higher_order_cases)
        self.weights = None  # a RationalWeights array (numpy), or None
        self.curved_cost = 0  # cells of order 3-4 bent off their straight places
        self.bent = False  # whether any cell was bent by the higher-order knobs

    def ten_ids(self):
        """Whether every cell has 10 ids, one after another (what the quadratic knobs edit)."""
        return len(self.offsets) == len(self.types) + 1 and np.array_equal(
            self.offsets, np.arange(0, 10 * len(self.types) + 1, 10))

    def cell_nodes(self, c):
        return self.conn[self.offsets[c]:self.offsets[c + 1]]

    def cells(self):
        """Cells as lists of ids (only for well-formed offsets)."""
        return [self.conn[a:b] for a, b in zip(self.offsets[:-1], self.offsets[1:])]


def quadratic_nodes(vertices):
    """The 10 nodes (VTK order) of a straight-sided tet with the given 4 vertices."""
    mids = 0.5 * (vertices[MID_EDGES[:, 0]] + vertices[MID_EDGES[:, 1]])
    return np.vstack([vertices, mids])


def lattice_mesh(n):
    """A cube [0, 1]^3 of n^3 boxes, each cut into 6 tets around its main diagonal, with shared nodes."""
    return Mesh(*lattice(n, 0.0, 1.0))


def soup_mesh(count, rng):
    """Independent random tets (each with its own 10 nodes); they may overlap."""
    points, cells = [], []
    for c in range(count):
        centre = rng.uniform(-1, 1, 3)
        verts = centre + rng.normal(0, 0.4, (4, 3))
        points.append(quadratic_nodes(verts))
        cells.append(np.arange(10) + 10 * c)
    return Mesh(np.vstack(points), cells)


def random_field(kind, points, rng):
    if kind == "quadratic":
        a = rng.normal(size=(3, 3))
        return points @ rng.normal(size=3) + np.einsum("ij,jk,ik->i", points, a + a.T, points)
    if kind == "sphere":
        return np.sum((points - rng.uniform(0.2, 0.8, 3)) ** 2, axis=1)
    if kind == "linear":
        return points @ rng.normal(size=3) + rng.normal()
    if kind == "noise":
        return rng.normal(size=len(points))
    return np.full(len(points), float(rng.normal()))  # constant


def apply_mesh_knobs(case):
    """Builds the Mesh and the iso-values; returns (mesh, values, nominal box)."""
    rng = case.knob("mesh")
    kind = pick(rng, ["lattice", "lattice", "lattice", "soup", "single"])
    if kind == "lattice":
        n = int(rng.integers(1, 4))
        mesh = lattice_mesh(n)
    else:
        n = 1 if kind == "single" else int(rng.integers(2, 12))
        mesh = soup_mesh(n, rng)
    field_kind = pick(rng, ["quadratic", "quadratic", "sphere", "linear", "noise", "constant"])
    case.note("mesh: %s n=%d field=%s" % (kind, n, field_kind))
    if (ho_rng := case.knob("higher_order")):
        # The same straight cells as Lagrange and Bezier tetrahedra of orders 1 to 4 (5 in
        # hostile cases), alone or mixed with VTK_TETRA and VTK_QUADRATIC_TETRA, each with nodes
        # of its own; some bent a little off their straight places (curved, valid).
        vertices = mesh.points[mesh.conn.reshape(-1, 10)[:, :4]]
        made, what = ho.make_mesh(ho_rng, vertices, case.profile == "hostile")
        mesh.points, mesh.types, mesh.offsets, mesh.conn = made.points, made.types, \
            made.offsets, made.conn
        mesh.orders = made.orders
        if ho_rng.random() < 0.4:
            moved = ho.bend(ho_rng, mesh, float(pick(ho_rng, [1e-3, 0.01, 0.03])), 0.5)
            mesh.curved_cost += ho.curved_cost_cells(mesh, moved)
            mesh.bent = mesh.bent or bool(moved)
            what += ", %d cells bent" % len(moved)
        case.note("higher_order: " + what)
    if (hw_rng := case.knob("hex_wedge")):
        # Some cells (or all) replaced by straight hexahedra and wedges of the kinds the core
        # reads (split into tetrahedra), on nodes of their own.
        what, _ = ho.straight_split_cells(hw_rng, mesh, float(pick(hw_rng, [0.2, 0.5, 1.0])))
        case.note("hex_wedge: " + what)
    mesh.field = random_field(field_kind, mesh.points, rng)
    inner = np.quantile(mesh.field, rng.uniform(0.05, 0.95, int(rng.integers(1, 3))))
    values = [float(v) for v in inner]

    if (rng := case.knob("transform")):
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        scale = np.exp(rng.uniform(-1, 1, 3))
        shift = rng.normal(size=3) * pick(rng, [1.0, 10.0, 1e6, 1e9])
        mesh.points = (mesh.points * scale) @ q.T + shift
        case.note("transform: shift %.3g" % np.linalg.norm(shift))
    if (rng := case.knob("curved")) and mesh.ten_ids():  # mid-edge nodes moved off their edges
        mids = np.unique(mesh.conn.reshape(-1, 10)[:, 4:])
        who = rng.choice(mids, int(rng.integers(1, len(mids) + 1)))
        mesh.points[who] += rng.normal(0, 0.05, (len(who), 3)) * np.ptp(mesh.points, axis=0).max()
        case.note("curved: moved %d mid-edge nodes" % len(who))
    if (rng := case.knob("inverted")) and mesh.ten_ids():
        flip = rng.random(len(mesh.types)) < 0.5
        cells = mesh.conn.reshape(-1, 10)
        cells[flip] = cells[flip][:, [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]]
        case.note("inverted: %d cells" % flip.sum())
    lo, hi = np.min(mesh.points, axis=0), np.max(mesh.points, axis=0)
    return mesh, values, (lo, hi)


def apply_hostile_knobs(case, mesh, values, box):
    """Scales, non-finite numbers and broken structure. Returns (values, box)."""
    if (rng := case.knob("scale_coords")):
        s = 10.0 ** int(rng.integers(-150, 151))
        mesh.points *= s
        box = (box[0] * s, box[1] * s)
        case.note("scale_coords: x %g" % s)
    if (rng := case.knob("scale_field")):
        s = 10.0 ** int(rng.integers(-150, 151))
        mesh.field = mesh.field * s
        values = [v * s for v in values]
        case.note("scale_field: x %g" % s)
    if (rng := case.knob("unused_points")):
        extra = rng.normal(size=(int(rng.integers(1, 5)), 3)) * pick(rng, [1.0, 1e3, 1e300])
        if rng.random() < 0.5:
            extra[0, int(rng.integers(3))] = pick(rng, [np.nan, np.inf, -np.inf])
        mesh.points = np.vstack([mesh.points, extra])
        mesh.field = np.append(mesh.field, rng.normal(size=len(extra)))
        case.note("unused_points: %d, first %s" % (len(extra), extra[0]))
    if (rng := case.knob("nonfinite_coords")):
        count = int(rng.integers(1, 4))
        for _ in range(count):
            mesh.points[int(rng.integers(len(mesh.points))), int(rng.integers(3))] = \
                pick(rng, [np.nan, np.inf, -np.inf, 1e308])
        case.note("nonfinite_coords: %d entries" % count)
    if (rng := case.knob("nonfinite_field")):
        count = int(rng.integers(1, 4))
        where = rng.integers(0, len(mesh.field), count)
        mesh.field[where] = [pick(rng, [np.nan, np.inf, -np.inf, 1e308]) for _ in where]
        case.note("nonfinite_field: points %s" % where.tolist())
    if (rng := case.knob("ho_bend")) and "higher_order" in case.active:
        # Nodes moved by small to huge amounts: curved, tangled, inverted, out of scale,
        # non-finite (the vertices too in some cases).
        amplitude = float(pick(rng, [1e-15, 1e-6, 0.05, 0.3, 1.0, 10.0, 1e6, 1e150, 1e300,
                                     np.nan, np.inf]))
        moved = ho.bend(rng, mesh, amplitude, float(rng.uniform(0.1, 1.0)),
                        vertices_too=rng.random() < 0.3)
        mesh.curved_cost += ho.curved_cost_cells(mesh, moved)
        mesh.bent = mesh.bent or bool(moved)
        case.note("ho_bend: %d cells by %g" % (len(moved), amplitude))
    if (rng := case.knob("ho_values")):
        # A field near the largest double (a Lagrange cell's Bernstein coefficients sum up to 35
        # times a node's magnitude) or spanning the whole double range.
        top = float(pick(rng, [1.7976931348623157e308, 1e308, 1e308 / 35, 5e306, 1e-300]))
        largest = np.nanmax(np.abs(np.where(np.isfinite(mesh.field), mesh.field, 0.0)))
        factor = top / largest if largest > 0 else 1.0
        mesh.field = mesh.field * factor
        values = [v * factor for v in values]
        if rng.random() < 0.3:  # a few nodes at +-max, the rest as they were
            where = rng.integers(0, len(mesh.field), int(rng.integers(1, 4)))
            mesh.field[where] = pick(rng, [1.7976931348623157e308, -1.7976931348623157e308])
        case.note("ho_values: largest %g" % np.nanmax(np.abs(mesh.field)))
    if (rng := case.knob("flat_cells")) and mesh.ten_ids():
        # Vertices moved onto (or next to) the plane, line or point of others: zero volume,
        # slivers and needles, with the mid-edge nodes kept at the midpoints.
        cells = mesh.conn.reshape(-1, 10)
        for c in rng.integers(0, len(cells), int(rng.integers(1, 4))):
            v = mesh.points[cells[c, :4]].copy()
            kind = pick(rng, ["coplanar", "collinear", "coincident", "needle", "sliver"])
            if kind == "coplanar":
                v[3] = v[0] + rng.random() * (v[1] - v[0]) + rng.random() * (v[2] - v[0])
            elif kind == "collinear":
                v[2] = v[0] + rng.random() * (v[1] - v[0])
                v[3] = v[0] + rng.random() * (v[1] - v[0])
            elif kind == "coincident":
                v[1:] = v[0]
            elif kind == "needle":
                v[3] = v[0] + (v[3] - v[0]) * pick(rng, [1e6, 1e12])
            else:
                v[3] = v[0] + 0.5 * (v[1] - v[0]) + 0.5 * (v[2] - v[0]) + 1e-12 * (v[3] - v[0])
            # New points, so that the neighbours keep their shape.
            ids = len(mesh.points) + np.arange(10)
            mesh.points = np.vstack([mesh.points, quadratic_nodes(v)])
            mesh.field = np.append(mesh.field, mesh.field[cells[c]])
            cells[c] = ids
            case.note("flat_cells: cell %d %s" % (c, kind))
    if (rng := case.knob("duplicate_cells")) and mesh.ten_ids():
        copies = pick(rng, [65535, 65536, 70000])
        cells = mesh.conn.reshape(-1, 10)
        finite = np.all(np.isfinite(mesh.points[cells]), axis=(1, 2)) & \
            np.all(np.isfinite(mesh.field[cells]), axis=1)
        first = cells[int(np.argmax(finite))]
        mesh.conn = np.tile(first, copies)
        mesh.offsets = np.arange(0, 10 * copies + 1, 10, dtype=np.int64)
        mesh.types = np.full(copies, VTK_QUADRATIC_TETRA, dtype=np.uint8)
        mesh.orders = np.full(copies, 2)
        case.note("duplicate_cells: %d copies of cell %d" % (copies, np.argmax(finite)))
    if (rng := case.knob("cell_types")):
        count = int(rng.integers(1, len(mesh.types) + 1))
        who = rng.integers(0, len(mesh.types), count)
        # VTK_TETRA (with 10 ids), hexahedron, empty cell, quadratic hexahedron, Lagrange
        # tetrahedron, wedges, pyramids, Lagrange and Bezier hexahedra and wedges, the
        # pentagonal prism, and a type VTK does not have, with the ids they had (mostly 10: a
        # malformed hexahedron or wedge, an unsupported pyramid). (Not VTK_POLYHEDRON:
        # vtkUnstructuredGrid itself crashes on one without faces.)
        mesh.types[who] = [pick(rng, [VTK_TETRA, VTK_TETRA, VTK_HEXAHEDRON, 0, 25, 71, 78, 255,
                                      11, 13, 14, 15, 26, 27, 29, 31, 32, 33, 72, 73, 74, 79, 80,
                                      81]) for _ in who]
        case.note("cell_types: %s" % sorted(set(zip(who.tolist(), mesh.types[who].tolist())))[:6])
    if (rng := case.knob("cell_sizes")):
        # Some cells get 4, 9 or 11 ids (a 4-id VTK_TETRA is valid: its 4 vertices).
        cells = [list(c) for c in mesh.cells()]
        npts = len(mesh.points)
        for c in rng.integers(0, len(cells), int(rng.integers(1, len(cells) + 1))):
            size = pick(rng, [4, 4, 9, 11])
            cells[c] = (cells[c] + [int(rng.integers(npts))])[:size]
            if size == 4 and rng.random() < 0.5:
                mesh.types[c] = VTK_TETRA
        mesh.conn = np.array([i for c in cells for i in c], dtype=np.int64)
        mesh.offsets = np.concatenate([[0], np.cumsum([len(c) for c in cells])]).astype(np.int64)
        case.note("cell_sizes: sizes %s" % sorted(set(len(c) for c in cells)))
    if (rng := case.knob("ho_counts")):
        case.note("ho_counts: " + ho.hostile_counts(rng, mesh, int(rng.integers(1, 4))))
    if (rng := case.knob("split_types")):
        # Cells given a hexahedron's, wedge's or pyramid's type and any number of ids (of the
        # mesh's points): malformed, of too high an order, unsupported, or read (then mostly
        # tangled, degenerate or curved: their nodes are anywhere).
        what, cost = ho.hostile_split_cells(rng, mesh, int(rng.integers(1, 5)))
        mesh.curved_cost += cost
        mesh.bent = mesh.bent or cost > 0
        case.note("split_types: " + what)
    if (rng := case.knob("conn_garbage")) and len(mesh.conn) > 1:
        count = int(rng.integers(1, 6))
        for _ in range(count):
            at = int(rng.integers(len(mesh.conn)))
            kind = pick(rng, ["-1", "huge", "npts", "repeat", "int32"])
            mesh.conn[at] = {"-1": -1, "huge": HUGE_ID, "npts": len(mesh.points),
                             "int32": 2 ** 31 + 5,
                             "repeat": mesh.conn[at - 1] if at else mesh.conn[1]}[kind]
            case.note("conn_garbage: conn[%d] (cell %d) = %s (%s)" % (
                at, max(0, np.searchsorted(mesh.offsets, at, "right") - 1), mesh.conn[at], kind))
    if (rng := case.knob("offsets")):
        kind = pick(rng, ["swap", "short", "long", "first", "equal", "past_end"])
        o = mesh.offsets
        if kind == "swap" and len(o) > 2:
            i = int(rng.integers(1, len(o) - 1))
            o[i], o[i + 1] = o[i + 1], o[i]
        elif kind == "short" and len(o) > 2:
            mesh.offsets = o[:-1]  # the last cell disappears; its ids stay in conn
        elif kind == "long":
            mesh.offsets = np.append(o, o[-1] + 10)
        elif kind == "first":
            o[0] = 3
        elif kind == "equal":
            o[1:-1] = o[1]
        else:
            o[-1] += int(rng.integers(1, 20))
        case.note("offsets: %s" % kind)
    if (rng := case.knob("types_length")):
        delta = pick(rng, [-1, 1, 5])
        mesh.types = (mesh.types[:delta] if delta < 0 else
                      np.append(mesh.types, np.full(delta, VTK_QUADRATIC_TETRA, np.uint8)))
        case.note("types_length: %+d" % delta)
    if (rng := case.knob("ho_weights")):
        bezier = [c for c in range(len(mesh.types)) if mesh.types[c] in ho.BEZIER_TYPES]
        mesh.weights, kind = ho.rational_weights(rng, len(mesh.points), bezier, mesh)
        mesh.weights_soa = rng.random() < 0.15
        case.note("ho_weights: %s, %s %s" % (kind, mesh.weights.dtype, mesh.weights.shape))
    if case.knob("points_float32"):
        mesh.point_dtype = np.float32
        case.note("points_float32")
    if case.knob("storage32"):
        mesh.storage32 = True
        case.note("storage32")
    return values, box


def apply_layout_knob(case, mesh):
    """Valid input in other memory layouts and types: the filter views some, copies others."""
    if (rng := case.knob("array_layout")) and len(mesh.points) < 20000:
        mesh.soa_points = rng.random() < 0.5
        mesh.field_layout = pick(rng, [None, "float64", "float32", "int64", "int8", "uint16"])
        case.note("array_layout: SOA points %s, SOA field %s" % (mesh.soa_points,
                                                                 mesh.field_layout))


# ---------------------------------------------------------------------------------------------
# VTK objects (imported in workers and in --replay only)

def vtk_modules():
    """VTK and the filter, as one namespace (the parent process never imports them)."""
    from types import SimpleNamespace
    from vtkmodules.util import numpy_support
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand, vtkIdList, vtkLookupTable, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPlane, vtkUnstructuredGrid
    from vtkmodules.vtkRenderingCore import vtkCamera, vtkColorTransferFunction
    from tetdsr import vtkDirectSurfaceRayCaster
    return SimpleNamespace(
        numpy_support=numpy_support, calldata_type=calldata_type, VTK_STRING=VTK_STRING,
        vtkCommand=vtkCommand, vtkIdList=vtkIdList, vtkLookupTable=vtkLookupTable, vtkPoints=vtkPoints,
        vtkCellArray=vtkCellArray, vtkPlane=vtkPlane, vtkUnstructuredGrid=vtkUnstructuredGrid,
        vtkCamera=vtkCamera, vtkColorTransferFunction=vtkColorTransferFunction,
        vtkDirectSurfaceRayCaster=vtkDirectSurfaceRayCaster)


def to_soa(values, dtype, name=None):
    """A vtkSOADataArrayTemplate (one buffer per component) holding `values`."""
    from vtkmodules.vtkCommonCore import vtkSOADataArrayTemplate
    values = np.asarray(values)
    table = values.reshape(len(values), values.shape[1] if values.ndim == 2 else 1)
    array = vtkSOADataArrayTemplate[dtype]()
    array.SetNumberOfComponents(table.shape[1])
    array.SetNumberOfTuples(len(table))
    for i, row in enumerate(table.astype(np.float64)):
        array.SetTuple(i, row)
    if name:
        array.SetName(name)
    return array


def as_numpy(V, array):
    """An array's values as float64 (n, components), whatever its memory layout."""
    if array.GetNumberOfTuples() == 0:
        return np.zeros((0, array.GetNumberOfComponents()))
    if array.HasStandardMemoryLayout():
        values = V.numpy_support.vtk_to_numpy(array).astype(np.float64)
        return values.reshape(array.GetNumberOfTuples(), -1)
    return np.array([array.GetTuple(i) for i in range(array.GetNumberOfTuples())],
                    dtype=np.float64).reshape(array.GetNumberOfTuples(), -1)


def to_vtk(values, name=None):
    from vtkmodules.util.numpy_support import numpy_to_vtk
    array = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
    if name:
        array.SetName(name)
    return array


def make_grid(V, mesh):
    from vtkmodules.util.numpy_support import numpy_to_vtkIdTypeArray
    grid = V.vtkUnstructuredGrid()
    points = V.vtkPoints()
    if mesh.soa_points:
        points.SetData(to_soa(mesh.points, np.dtype(mesh.point_dtype).name))
    else:
        points.SetData(to_vtk(mesh.points.astype(mesh.point_dtype).reshape(-1, 3)))
    grid.SetPoints(points)
    cells = V.vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(mesh.offsets.copy(), deep=1),
                  numpy_to_vtkIdTypeArray(mesh.conn.copy(), deep=1))
    if mesh.storage32 and np.all(np.abs(mesh.conn) < 2 ** 31):
        cells.ConvertTo32BitStorage()
    grid.SetCells(to_vtk(mesh.types), cells)
    if mesh.weights is not None:
        weights = (to_soa(mesh.weights, "float64", "RationalWeights")
                   if getattr(mesh, "weights_soa", False) and len(mesh.weights) else
                   to_vtk(mesh.weights, "RationalWeights"))
        grid.GetPointData().SetRationalWeights(weights)
    return grid


class Messages:
    def __init__(self, V, algorithm):
        self.errors, self.warnings = [], []

        @V.calldata_type(V.VTK_STRING)
        def on_error(obj, event, text):
            self.errors.append(text.strip())

        @V.calldata_type(V.VTK_STRING)
        def on_warning(obj, event, text):
            self.warnings.append(text.strip())

        algorithm.AddObserver(V.vtkCommand.ErrorEvent, on_error)
        algorithm.AddObserver(V.vtkCommand.WarningEvent, on_warning)


def add_field(V, case, grid, mesh, caster):
    """Adds the scalar array (possibly hostile); returns the values the filter should render
    (None when there are none)."""
    pd = grid.GetPointData()
    rng = case.knob("scalar_array")
    if not rng and mesh.field_layout:
        array = to_soa(mesh.field, mesh.field_layout, mesh.field_name)
        pd.SetScalars(array)
        return as_numpy(V, array)[:, 0]
    if not rng:
        pd.SetScalars(to_vtk(mesh.field, mesh.field_name))
        return mesh.field
    kind = pick(rng, ["short", "long", "float32", "int32", "uint8", "components", "component_bad",
                      "cell_data", "by_name", "missing_name", "empty"])
    case.note("scalar_array: %s" % kind)
    field = mesh.field
    if kind == "short":
        field = field[:int(rng.integers(0, len(field)))]
    elif kind == "long":
        field = np.append(field, rng.normal(size=7))
    elif kind == "float32":
        field = field.astype(np.float32)
    elif kind == "int32":
        field = np.clip(np.nan_to_num(field * 100), -2e9, 2e9).astype(np.int32)
    elif kind == "uint8":
        field = np.clip(np.nan_to_num(field * 50 + 128), 0, 255).astype(np.uint8)
    elif kind in ("components", "component_bad"):
        k = int(rng.integers(2, 4))
        comp = int(rng.integers(k))
        stacked = rng.normal(size=(len(field), k))
        stacked[:, comp] = field
        field = stacked
        caster.SetArrayComponent(comp if kind == "components" else pick(rng, [k, k + 5, -1]))
    elif kind == "empty":
        field = field[:0]
    array = to_vtk(field, mesh.field_name)
    if kind == "cell_data":
        grid.GetCellData().SetScalars(to_vtk(field[:grid.GetNumberOfCells()], mesh.field_name))
        caster.SetInputArrayToProcess(0, 0, 0, 1, mesh.field_name)
        return None
    if kind == "by_name":
        pd.AddArray(array)
        caster.SetInputArrayToProcess(0, 0, 0, 0, mesh.field_name)
    elif kind == "missing_name":
        pd.AddArray(array)
        caster.SetInputArrayToProcess(0, 0, 0, 0, "no such array")
    else:
        pd.SetScalars(array)
    if field.ndim == 2:
        comp = caster.GetArrayComponent()
        return field[:, comp] if 0 <= comp < field.shape[1] else None
    return field


def camera_knob(V, case, box):
    rng = case.knob("camera")
    if not rng:
        case.note("camera: default")
        return None
    lo, hi = box
    centre = 0.5 * (lo + hi)
    radius = max(0.5 * float(np.linalg.norm(hi - lo)), 1e-300)
    kind = pick(rng, ["perspective"] * 10 + ["parallel"] * 4 + ["inside", "far", "grazing"] * 2 +
                ["coincident", "up_parallel", "up_zero", "angle", "scale", "nan"])
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    camera = V.vtkCamera()
    focal = centre + rng.normal(0, 0.2, 3) * radius
    position = focal + direction * radius * rng.uniform(1.5, 6)
    up = rng.normal(size=3)
    if kind == "inside":
        position = centre + rng.normal(0, 0.1, 3) * radius
    elif kind == "far":
        position = focal + direction * radius * pick(rng, [1e6, 1e12, 1e300])
    elif kind == "coincident":
        position = focal.copy()
    elif kind == "up_parallel":
        up = direction.copy()
    elif kind == "up_zero":
        up = np.zeros(3)
    elif kind == "nan":
        position[int(rng.integers(3))] = pick(rng, [np.nan, np.inf])
    elif kind == "grazing":
        focal = lo.copy()  # look at a corner, along an axis
        position = focal + np.eye(3)[int(rng.integers(3))] * radius * 3
    camera.SetFocalPoint(*focal)
    camera.SetPosition(*position)
    camera.SetViewUp(*up)
    camera.SetViewAngle(pick(rng, [1e-6, 0.0, 179.9, 180.0, np.nan]) if kind == "angle"
                        else float(rng.uniform(5, 80)))
    if kind in ("parallel", "scale") or rng.random() < 0.1:
        camera.ParallelProjectionOn()
        camera.SetParallelScale(pick(rng, [0.0, -1.0, np.nan, np.inf, 1e-300]) if kind == "scale"
                                else radius * rng.uniform(0.3, 2))
    case.note("camera: %s" % kind)
    return camera


def set_options(V, case, caster, values, box, grid, field_range):
    """Everything but the mesh and the camera."""
    if (rng := case.knob("iso_values")):
        kind = pick(rng, ["several"] * 6 + ["duplicate", "outside", "generate", "extreme"] * 2 +
                    ["nonfinite", "none", "many"])
        if kind == "several":
            values = values + [float(v) for v in rng.choice(values, int(rng.integers(1, 4)))
                               * (1 + rng.normal(0, 0.2))]
        elif kind == "duplicate":
            values = values + values
        elif kind == "outside":
            values = [values[0] + pick(rng, [1e300, -1e300, 1e3 * (abs(values[0]) + 1)])]
        elif kind == "nonfinite":
            values = values + [pick(rng, [np.nan, np.inf, -np.inf])]
        elif kind == "none":
            values = []
        elif kind == "extreme":  # tangent surfaces at the field's extremes
            values = [float(np.nanmin(field_range)), float(np.nanmax(field_range))]
        elif kind == "many":  # many translucent surfaces along each ray
            values = list(np.linspace(min(values) - 1, max(values) + 1, 300))
            for i in range(0, 300, 3):
                caster.SetIsoValueOpacity(i, 0.2)
        case.note("iso_values: %s %s" % (kind, values[:6]))
        if kind == "generate":
            caster.GenerateValues(int(rng.integers(1, 6)), min(values), max(values) + 1e-3)
            values = None
    if values is not None:
        caster.SetNumberOfContours(len(values))
        for i, v in enumerate(values):
            caster.SetValue(i, v)

    if (rng := case.knob("normals")):
        caster.SetNormalMode(int(rng.integers(-1, 5)))
        caster.SetCentralDifferenceStep(pick(rng, [1e-3, 1e-12, 1.0, 1e-20, np.nan]))
        case.note("normals: mode %d step %g" % (caster.GetNormalMode(),
                                                caster.GetCentralDifferenceStep()))
    if (rng := case.knob("clipping")):
        lo, hi = box
        for k in range(int(rng.integers(1, 7)) if rng.random() < 0.95 else 7):
            plane = V.vtkPlane()
            plane.SetOrigin(*(lo + rng.random(3) * (hi - lo)))
            normal = rng.normal(size=3)
            if rng.random() < 0.03:
                normal = pick(rng, [np.zeros(3), np.array([np.nan, 0, 1]),
                                    np.array([1e-320, 0, 0])])
            plane.SetNormal(*normal)
            caster.AddClippingPlane(plane)
        caster.SetCapping(int(rng.integers(0, 3)))
        case.note("clipping: %d planes, capping %d" % (
            caster.GetClippingPlanes().GetNumberOfItems(), caster.GetCapping()))
    if (rng := case.knob("iso_styles")):
        for _ in range(int(rng.integers(1, 5))):
            i = pick(rng, [0, 0, 1, 2, 5, -1, 1000])
            if case.profile == "hostile" and rng.random() < 0.05:
                i = 2 ** 31 - 1
            if rng.random() < 0.5:
                colour = rng.uniform(-1, 2, 3)
                if rng.random() < 0.2:
                    colour[int(rng.integers(3))] = np.nan
                case.note("iso_styles: colour %d %s" % (i, colour))
                caster.SetIsoValueColor(i, *colour)
            else:
                opacity = pick(rng, [0.0, 0.3, 0.5, 1.0, 2.0, -1.0, np.nan])
                case.note("iso_styles: opacity %d %s" % (i, opacity))
                caster.SetIsoValueOpacity(i, opacity)
    if (rng := case.knob("color_by")):
        npts = grid.GetNumberOfPoints()
        k = pick(rng, [1, 1, 3, 4])
        n = pick(rng, [npts, npts, npts, int(rng.integers(0, max(npts, 1))), npts + 3])
        colours = rng.normal(size=(n, k)) * pick(rng, [1.0, 1e200, 1e-200])
        if rng.random() < 0.3 and n:
            colours[int(rng.integers(n)), int(rng.integers(k))] = pick(rng, [np.nan, np.inf])
        colours = colours.astype(pick(rng, [np.float64, np.float64, np.float32, np.int16]))
        soa = rng.random() < 0.2
        caster.ColorByArrayOn()
        caster.SetColorArrayComponent(int(rng.integers(-1, k)) if rng.random() < 0.9 else
                                      pick(rng, [-2, k, k + 1, 2 ** 31 - 1]))
        caster.SetColorMap(int(rng.integers(-1, 5)))
        if rng.random() < 0.5:
            caster.SetColorRange(*pick(rng, [(0.0, 1.0), (1.0, 1.0), (np.nan, 1.0),
                                              (-np.inf, np.inf), (0.0, 1e308), (1.0, -1.0)]))
        if rng.random() < 0.3:
            table = pick(rng, [V.vtkLookupTable, V.vtkColorTransferFunction])()
            if table.IsA("vtkLookupTable"):
                table.SetRange(*pick(rng, [(0.0, 1.0), (5.0, 5.0), (1.0, 0.0)]))
                table.Build()
            caster.SetLookupTable(table)
        case.note("color_by: %d x %d %s, component %d" % (n, k, colours.dtype,
                                                          caster.GetColorArrayComponent()))
        colours = colours.squeeze(axis=1) if k == 1 else colours
        grid.GetPointData().AddArray(to_soa(colours, "float64", "colour") if soa else
                                     to_vtk(colours, "colour"))
        caster.SetInputArrayToProcess(1, 0, 0, 0, "colour")
    else:
        colours = None
    if (rng := case.knob("shading")):
        colour = rng.uniform(-1, 2, 3)
        if rng.random() < 0.2:
            colour[0] = np.nan
        caster.SetSurfaceColor(*colour)
        caster.SetAmbient(rng.uniform(-1, 2))
        caster.SetDiffuse(rng.uniform(-1, 2))
        caster.SetSpecular(rng.uniform(-1, 2))
        caster.SetSpecularPower(pick(rng, [0.0, 1.0, 30.0, 128.0, 1e9]))
        if rng.random() < 0.5:
            caster.LightAtCameraOff()
            caster.SetLightPosition(*pick(rng, [rng.normal(size=3), np.array([np.nan, 0, 0]),
                                                np.array([0.0, 0.0, 1e308])]))
        case.note("shading: colour %s" % colour)
    return colours


def set_more_options(case, caster):
    if (rng := case.knob("transverse")):
        caster.SetTransverseTest(int(rng.integers(0, 3)))
        caster.SetNodalRangeWidening(pick(rng, [0.0, 0.25, 1e300, np.inf, np.nan]))
        case.note("transverse: %d widening %g" % (caster.GetTransverseTest(),
                                                  caster.GetNodalRangeWidening()))
    if (rng := case.knob("threads")):
        caster.SetNumberOfThreads(int(rng.integers(1, 5)))


# Ray tests of curved cells of order 3 and 4 a case may cost: each is a subdivision solve, about
# 100-300 us in the release build and 5 times that under ASan, so 3,000 of them take at most ~5 s
# there. A case renders up to 3 times (first update, re-update, scale check); every ray is
# counted as testing every bent order-3/4 cell (an upper bound: a ray tests the cells whose
# boxes it meets), so rays <= 3000 / (3 x bent cells).
CURVED_HIGHER_ORDER_TESTS = 3000


def ray_budget(case, size, mesh):
    """The image size, capped where every ray tests 65,536+ coincident cells (the cost docs/reliability-and-limits.md
    states): a few rays exercise the hierarchy's counts as well as many, within the hang timeout
    under ASan."""
    if "duplicate_cells" in case.active and min(size) > 0:
        size = (min(size[0], 8), min(size[1], 8))
        if "curved" in case.active or mesh.bent:
            # A curved copy costs a subdivision solve per ray, not a closed form: 1 to 6 s per
            # ray for 65,536 copies in the release build (docs/reliability-and-limits.md), about 5 times that
            # under ASan: one ray.
            size = (min(size[0], 1), min(size[1], 1))
    if mesh.curved_cost and min(size) > 0:
        rays = max(1, CURVED_HIGHER_ORDER_TESTS // (3 * mesh.curved_cost))
        while size[0] * size[1] > rays:
            size = (max(1, size[0] // 2), max(1, size[1] // 2))
    return size


def image_size_knob(case):
    rng = case.knob("image_size")
    if not rng:
        return 24, 24
    kind = pick(rng, ["random"] * 16 + ["one", "thin"] * 2 + ["zero", "negative", "huge"])
    if kind == "huge" and case.profile != "hostile":
        kind = "random"
    size = {"one": (1, 1), "thin": pick(rng, [(1, 64), (64, 1)]), "zero": (0, 8),
            "negative": (-4, 8), "huge": (1 << 20, 1 << 20)}.get(
        kind, (int(rng.integers(1, 49)), int(rng.integers(1, 49))))
    case.note("image_size: %s" % (size,))
    return size


# ---------------------------------------------------------------------------------------------
# Invariants

# The filter's skip counters (GetNumberOf<name>Cells); later versions may add some. Which cells
# must be skipped, and why, higher_order_cases.predict says.
SKIP_COUNTERS = ["Degenerate", "NonFinite", "InvalidId", "Unsupported", "Malformed", "OutOfScale",
                 "Tangled", "OrderTooHigh", "Rational"]


# Reference coordinates of VTK's 10 quadratic-tetra nodes, and the quadratic monomials in them.
_REF_NODES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [.5, 0, 0], [.5, .5, 0],
                       [0, .5, 0], [0, 0, .5], [.5, 0, .5], [0, .5, .5]])


def _monomials(x):
    return np.array([1, x[0], x[1], x[2], x[0] * x[0], x[1] * x[1], x[2] * x[2],
                     x[0] * x[1], x[1] * x[2], x[0] * x[2]])


_MONOMIAL_FIT = np.linalg.inv(np.array([_monomials(x) for x in _REF_NODES]))


def critical_value_at(nodal, isos, rel=1e-12):
    """True when the cell's quadratic (in reference coordinates, where its gradient vanishes
    exactly where the world gradient does) has a critical point whose value lies within `rel` of
    the largest nodal magnitude from one of the iso-values: there the exact gradient at a hit is
    zero to double precision (e.g. f = 4 K L1 L2 with iso-value c, |c| / |K| < 1e-16: the computed
    surface runs along the critical edge L1 = L2 = 0)."""
    top = np.max(np.abs(nodal))
    if not np.isfinite(top) or top == 0:
        return True
    c = _MONOMIAL_FIT @ (nodal / top)
    g = c[1:4]
    H = np.array([[2 * c[4], c[7], c[9]], [c[7], 2 * c[5], c[8]], [c[9], c[8], 2 * c[6]]])
    x, *_ = np.linalg.lstsq(H, -g, rcond=1e-14)
    if np.linalg.norm(H @ x + g) > 1e-9 * (1 + np.linalg.norm(g)):
        return False  # no critical point: the gradient vanishes nowhere
    value = _monomials(x) @ c
    return any(abs(value - iso / top) <= rel for iso in isos)


def invalid_cells(V, grid, field):
    """Per input cell: the reason the filter must skip it ("" if none), the cell's largest
    node id, and whether the field varies over its nodes; and the error the input must be
    refused with (None if none is predicted). (None, None, None, None) when the offsets or the
    types array are not sane."""
    vtk_to_numpy = V.numpy_support.vtk_to_numpy
    cells = grid.GetCells()
    offsets = vtk_to_numpy(cells.GetOffsetsArray()).astype(np.int64)
    conn = vtk_to_numpy(cells.GetConnectivityArray()).astype(np.int64)
    types = vtk_to_numpy(grid.GetCellTypesArray())
    points = as_numpy(V, grid.GetPoints().GetData())
    npts = len(points)
    values = None
    if field is not None:
        values = np.full(npts, np.nan)
        n = min(npts, len(field))
        values[:n] = np.asarray(field, dtype=np.float64)[:n]
    weights = grid.GetPointData().GetRationalWeights()
    reasons, error = ho.predict(types, offsets, conn, points, values,
                                None if weights is None else as_numpy(V, weights))
    if reasons is None:
        return None, None, None, None
    largest = np.full(len(types), -1, dtype=np.int64)
    varying = np.zeros(len(types), dtype=bool)
    known = values if values is not None else np.full(npts, np.nan)
    for c in range(len(types)):
        ids = conn[offsets[c]:offsets[c + 1]]
        largest[c] = ids.max() if len(ids) else -1
        inside = ids[(ids >= 0) & (ids < npts)]
        varying[c] = len(inside) > 0 and np.ptp(known[inside]) > 0
    return reasons, largest, varying, error


def nodal_quadratic(V, grid, cell, field):
    """The 10 nodal values of a cell of order 2 (a Bezier cell's control values converted:
    mid-edge value = (b_a + b_b) / 4 + b_ab / 2), or None for other cells."""
    ids = V.vtkIdList()
    grid.GetCellPoints(cell, ids)
    if ids.GetNumberOfIds() != 10:
        return None
    nodal = np.array([field[ids.GetId(i)] for i in range(10)], dtype=np.float64)
    if grid.GetCellType(cell) == ho.VTK_BEZIER_TETRAHEDRON:
        nodal[4:] = 0.25 * (nodal[MID_EDGES[:, 0]] + nodal[MID_EDGES[:, 1]]) + 0.5 * nodal[4:]
    return nodal


def check_output(V, caster, msgs, size, grid, field, colours, warnings=True):
    """Broken invariants as {name: detail}; the skip warnings are checked when `warnings`
    (an Update that prepared the mesh anew: a reused scene does not warn again)."""
    vtk_to_numpy = V.numpy_support.vtk_to_numpy
    broken = {}
    ncells = grid.GetNumberOfCells()
    if msgs.errors:
        if any(ho.NO_CELL in e for e in msgs.errors):
            reasons, _, _, expected_error = invalid_cells(V, grid, field)
            if reasons is not None:
                ho.check_refusal(expected_error, msgs.errors, broken)
        return broken
    reasons, largest, varying, expected_error = invalid_cells(V, grid, field)
    if expected_error:
        broken["error-missing: " + expected_error] = "no error, %d cells rendered" % (
            caster.GetNumberOfRenderedCells())
        return broken
    warnings = msgs.warnings if warnings else None
    image = caster.GetOutput()
    w, h = size
    pd = image.GetPointData()
    names = ("Colors", "Depth", "Normals", "CellId")
    arrays = {n: pd.GetArray(n) for n in names}
    if tuple(image.GetDimensions()) != (w, h, 1) or any(a is None for a in arrays.values()):
        broken["incomplete-output"] = "dims %s, arrays %s" % (
            image.GetDimensions(), [n for n in names if arrays[n] is not None])
        return broken
    a = {n: vtk_to_numpy(arrays[n]) for n in names}
    shapes = {"Colors": (w * h, 4), "Depth": (w * h,), "Normals": (w * h, 3), "CellId": (w * h,)}
    for n in names:
        if a[n].shape != shapes[n]:
            broken["incomplete-output"] = "%s shape %s" % (n, a[n].shape)
            return broken
    cid, depth, normal, rgba = a["CellId"], a["Depth"], a["Normals"], a["Colors"]
    miss = cid == -1
    hit = ~miss
    length = np.linalg.norm(normal, axis=1)

    def fail(name, mask, what):
        if mask.any():
            k = int(np.flatnonzero(mask)[0])
            broken[name] = "%d pixels, first %d: cell %d depth %r |n| %r rgba %s %s" % (
                mask.sum(), k, cid[k], depth[k], length[k], rgba[k].tolist(), what)

    fail("miss-not-clean", miss & ~((depth == np.inf) & (length == 0) & np.all(rgba == 0, axis=1)),
         "")
    fail("hit-cell-out-of-range", hit & ((cid < 0) | (cid >= ncells)), "ncells %d" % ncells)
    fail("hit-bad-depth", hit & ~(np.isfinite(depth) & (depth >= 0)), "")
    fail("hit-bad-normal", hit & ~((np.abs(length - 1) < 1e-6) | (length == 0)), "")
    values = pd.GetArray("ColorValues")
    if values is not None:
        v = vtk_to_numpy(values)
        fail("miss-color-value", miss & ~np.isnan(v), "")
    if reasons is not None:
        safe = hit & (cid >= 0) & (cid < ncells)
        hit_cells = cid[safe]
        if caster.GetNormalMode() != 3:  # (DEPTH_BUFFER normals face the viewer)
            # A zero gradient is expected only where the field is constant.
            flat = np.zeros_like(hit)
            flat[safe] = (length[safe] == 0) & varying[hit_cells] & (reasons[hit_cells] == "")
            if flat.any():  # unless the iso-value is a critical value (to rounding) of the cell
                isos = [caster.GetValue(i) for i in range(caster.GetNumberOfContours())]
                for k in np.flatnonzero(flat):
                    nodal = nodal_quadratic(V, grid, int(cid[k]), field)
                    if nodal is not None and critical_value_at(nodal, isos):
                        flat[k] = False
            fail("hit-zero-normal-on-varying-field", flat, "")
        on_invalid = np.zeros_like(hit)
        on_invalid[safe] = reasons[hit_cells] != ""
        if on_invalid.any():
            why = sorted(set(reasons[cid[on_invalid]]))
            fail("hit-on-invalid-cell: " + ", ".join(why), on_invalid, "")
        rendered = caster.GetNumberOfRenderedCells()
        if np.sum(reasons != "") > ncells - rendered:
            broken["invalid-cell-rendered"] = "%d cells to skip, %d of %d rendered" % (
                np.sum(reasons != ""), rendered, ncells)
        counts = {k: getattr(caster, "GetNumberOf%sCells" % k)() for k in SKIP_COUNTERS}
        ho.check_counts(reasons, counts, warnings, broken)
        if colours is not None and caster.GetColorByArray():
            # A hit in a cell with nodes beyond a short colour array reads values that do not
            # exist.
            beyond = np.zeros_like(hit)
            beyond[safe] = largest[hit_cells] >= len(colours)
            fail("hit-reads-past-color-array", beyond, "(%d colour tuples)" % len(colours))
    counts = {k: getattr(caster, "GetNumberOf%sCells" % k)() for k in ["Rendered"] + SKIP_COUNTERS
              if hasattr(caster, "GetNumberOf%sCells" % k)}
    if counts["Rendered"] <= 0 or sum(counts.values()) != ncells:
        broken["cell-counts"] = "%s for %d cells" % (counts, ncells)
    return broken


# ---------------------------------------------------------------------------------------------
# One case

def run_case(V, seed, index, without=(), verbose=False):
    """Builds and renders one case; returns a result dict (status ok, error or invariant)."""
    case = Case(seed, index, without)
    mesh, values, box = apply_mesh_knobs(case)
    values, box = apply_hostile_knobs(case, mesh, values, box)
    apply_layout_knob(case, mesh)
    grid = make_grid(V, mesh)
    caster = V.vtkDirectSurfaceRayCaster()
    msgs = Messages(V, caster)
    caster.SetInputData(grid)
    field = add_field(V, case, grid, mesh, caster)
    camera = camera_knob(V, case, box)
    if camera is not None:
        caster.SetCamera(camera)
    size = ray_budget(case, image_size_knob(case), mesh)
    caster.SetImageSize(*size)
    finite = mesh.field[np.isfinite(mesh.field)]
    colours = set_options(V, case, caster, values, box, grid,
                          finite if len(finite) else np.zeros(1))
    set_more_options(case, caster)
    if verbose:
        print("profile %s, knobs %s" % (case.profile, " ".join(Case.active_knobs(
            seed, index, without))))
        print("\n".join("  " + line for line in case.log), flush=True)
    result = dict(index=index, without=sorted(case.without), active=case.active, broken={})
    msgs.errors.clear()  # setters may refuse arguments (a negative index): that is fine
    msgs.warnings.clear()
    started = time.time()
    caster.Update()
    result["seconds"] = round(time.time() - started, 3)
    result["broken"] = check_output(V, caster, msgs, size, grid, field, colours)
    result["errors"] = msgs.errors[:3]

    if (rng := case.knob("reupdate")) and not msgs.errors:
        kind = pick(rng, ["ids_invalid", "ids_invalid_cells", "field", "points", "iso", "size",
                          "camera", "weights", "types"])
        weights = grid.GetPointData().GetRationalWeights()
        vtk_to_numpy = V.numpy_support.vtk_to_numpy
        if kind.startswith("ids_invalid"):  # every id out of range, the array marked modified
            conn = grid.GetCells().GetConnectivityArray()
            vtk_to_numpy(conn)[:] = 10 ** 9
            conn.Modified()
            if kind == "ids_invalid_cells":
                grid.GetCells().Modified()
        elif kind == "field" and grid.GetPointData().GetScalars() is not None:
            scalars = grid.GetPointData().GetScalars()  # any layout: through the API
            for i in range(scalars.GetNumberOfTuples()):
                for k in range(scalars.GetNumberOfComponents()):
                    scalars.SetComponent(i, k, -scalars.GetComponent(i, k))
            scalars.Modified()
            field = None if field is None else -np.asarray(field, dtype=np.float64)
        elif kind == "weights" and weights is not None and weights.GetNumberOfTuples():
            for i in range(weights.GetNumberOfTuples()):  # differing within most cells
                weights.SetComponent(i, 0, 1.0 + i % 3)
            weights.Modified()
        elif kind == "weights":  # weights where there were none
            grid.GetPointData().SetRationalWeights(to_vtk(
                1.0 + np.arange(grid.GetNumberOfPoints()) % 2, "RationalWeights"))
        elif kind == "types":  # every cell's type toggled between Lagrange and Bezier
            types = grid.GetCellTypesArray()
            t = vtk_to_numpy(types)
            # (Lagrange 71-74 and Bezier 78-81 tetrahedron, hexahedron, wedge, pyramid.)
            t[:] = np.where((t >= 71) & (t <= 74), t + 7, np.where((t >= 78) & (t <= 81), t - 7, t))
            types.Modified()
        elif kind == "points":
            data = grid.GetPoints().GetData()
            data.SetComponent(0, 0, np.nan)
            data.Modified()
        elif kind == "size":
            size = ray_budget(case, (int(rng.integers(1, 40)), int(rng.integers(1, 40))), mesh)
            caster.SetImageSize(*size)
        elif kind == "camera":
            camera = V.vtkCamera()
            camera.SetPosition(*rng.normal(size=3) * 5)
            caster.SetCamera(camera)
        else:
            caster.SetValue(0, caster.GetValue(0) * 0.5)
        case.note("reupdate: %s" % kind)
        if verbose:
            print("  " + case.log[-1], flush=True)
        msgs.errors.clear()
        # VTK's pipeline does not see arrays edited in place (the grid's time stays): make the
        # filter execute, so that what is tested is its own cache of the prepared mesh.
        caster.Modified()
        caster.Update()
        broken = check_output(V, caster, msgs, size, grid, field, colours, warnings=False)
        result["broken"].update({"after-reupdate:" + k: v for k, v in broken.items()})
        result["errors"] += msgs.errors[:3]

    if case.profile == "scale" and not msgs.errors and not result["broken"]:
        compare_scaled(V, case, grid, caster, msgs, camera, result)
    result["status"] = "invariant" if result["broken"] else "error" if result["errors"] else "ok"
    result["log"] = case.log
    return result


def compare_scaled(V, case, grid, caster, msgs, camera, result):
    """The same scene with coordinates and field scaled by powers of ten: the same pixels must
    be hit (a few may differ on silhouettes), or the filter must say why not."""
    rng = np.random.default_rng([case.seed, case.index, 1])
    sx_exp = int(rng.integers(-150, 151))
    sf = 10.0 ** int(rng.integers(-150, 151))
    if camera is not None:
        # vtkCamera itself moves the focal point when it is closer than 1e-20 to the position.
        sx_exp = max(sx_exp, int(np.ceil(np.log10(1e-12 / camera.GetDistance()))))
    sx = 10.0 ** sx_exp
    vtk_to_numpy = V.numpy_support.vtk_to_numpy
    before = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("CellId")).copy()
    points = grid.GetPoints().GetData()
    vtk_to_numpy(points)[:] *= sx
    points.Modified()
    scalars = grid.GetPointData().GetScalars()
    vtk_to_numpy(scalars)[:] *= sf
    scalars.Modified()
    for i in range(caster.GetNumberOfContours()):
        caster.SetValue(i, caster.GetValue(i) * sf)
    if camera is not None:
        camera.SetFocalPoint(*(np.array(camera.GetFocalPoint()) * sx))
        camera.SetPosition(*(np.array(camera.GetPosition()) * sx))
        camera.SetParallelScale(camera.GetParallelScale() * sx)
    planes = caster.GetClippingPlanes()
    for k in range(planes.GetNumberOfItems() if planes else 0):
        plane = planes.GetItem(k)
        plane.SetOrigin(*(np.array(plane.GetOrigin()) * sx))
    if not caster.GetLightAtCamera():
        caster.SetLightPosition(*(np.array(caster.GetLightPosition()) * sx))
    msgs.warnings.clear()
    caster.Update()
    case.note("scale check: coordinates x %g, field x %g" % (sx, sf))
    if msgs.errors or msgs.warnings:
        return
    after = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("CellId"))
    if after.shape != before.shape:
        result["broken"]["scale-variance"] = "image size changed"
        return
    differ = int(np.sum((before >= 0) != (after >= 0)))
    if differ > max(2, 0.02 * before.size):
        result["broken"]["scale-variance"] = (
            "x %g, field x %g: hits %d -> %d, %d of %d pixels differ, no message" % (
                sx, sf, (before >= 0).sum(), (after >= 0).sum(), differ, before.size))


# ---------------------------------------------------------------------------------------------
# Workers and the parent

def worker_main(seed):
    """A worker (fuzz_common.serve): "index<TAB>without" lines in, one result each out."""
    modules = []

    def run(line):
        index, without = line.split("\t")
        without = [k for k in without.split(",") if k]
        try:
            return run_case(modules[0], seed, int(index), without)
        except Exception as error:  # a bug of the fuzzer itself
            import traceback
            return dict(index=int(index), without=without, status="harness",
                        broken={"harness": "%s: %s" % (type(error).__name__, error)},
                        trace=traceback.format_exc())

    serve(lambda: modules.append(vtk_modules()), run)


FRAME = re.compile(r"#\d+ 0x[0-9a-f]+ in (.+?) (/\S+?:\d+)")


def crash_signature(stderr, returncode):
    """A short stable description of a crash, and the lines that matter."""
    lines = case_output(stderr)
    kind, frame = None, None
    for k, line in enumerate(lines):
        m = SANITIZER.search(line)
        if m and kind is None:
            kind = m.group(2) or ("UB: " + re.sub(r"0x[0-9a-f]+|\d+", "N", m.group(3))[:80])
            for follow in lines[k:k + 40]:
                f = FRAME.search(follow)
                if f and ("tetdsr" in follow or "DirectSurface" in follow):
                    name = re.sub(r"\(.*", "", f.group(1))
                    frame = "%s %s" % (name, os.path.basename(f.group(2)))
                    break
                if f and not frame and "libsanitizer" not in follow:
                    frame = re.sub(r"\(.*", "", f.group(1))
            break
        if "terminate called" in line and kind is None:
            kind = line.strip()
    if kind is None:
        if returncode is not None and returncode < 0:
            kind = "signal %s" % signal.Signals(-returncode).name
        else:
            kind = "exit %s" % returncode
        for line in lines:  # faulthandler prints the innermost Python frame first
            if line.startswith('  File "') and "fuzz_filter.py" in line:
                frame = "fuzz_filter.py:" + line.split(", line ")[-1].split(" in ")[0]
                break
    report = [line for line in lines if line.strip()]
    return "%s in %s" % (kind, frame or "?"), report[-60:]


def run_tasks(tasks, seed, jobs, timeout, on_result, stop_at=None):
    """Runs (index, without) tasks on `jobs` worker processes (fuzz_common.run_tasks); calls
    on_result(task, result), a crash or a hang described by crash_signature."""
    def crashed(worker):
        signature, report = crash_signature(worker.stderr_text(), worker.proc.returncode)
        return dict(status="crash", signature=signature, stderr=report,
                    returncode=worker.proc.returncode)

    def hung(worker):
        report = crash_signature(worker.stderr_text(), None)[1]
        where = [line.strip() for line in report if line.startswith('  File "')][:1]
        return dict(status="hang", signature="hang (> %g s)%s" % (
            timeout, " in " + where[0].split(", ")[-1] if where else ""), stderr=report[-30:])

    run_workers(tasks, jobs, timeout, on_result, stop_at,
                command=[sys.executable, os.path.abspath(__file__), "--worker", "--seed", str(seed)],
                encode=lambda task: "%d\t%s" % (task[0], ",".join(task[1])),
                startup=max(120.0, timeout), crashed=crashed, hung=hung)


PRIORITY = ["incomplete-output", "miss-not-clean", "hit-cell-out-of-range", "hit-bad-depth",
            "hit-bad-normal", "hit-zero-normal-on-varying-field", "miss-color-value", "hit-on-invalid-cell", "invalid-cell-rendered",
            "hit-reads-past-color-array", "error-missing", "wrong-refusal", "skip-counts", "warning-missing",
            "cell-counts", "scale-variance"]


def signature_of(result):
    """Crashes and hangs by their report; broken invariants by the most telling one."""
    if result["status"] in ("crash", "hang"):
        return result["signature"]

    def rank(name):
        plain = name.split(":", 1)[1] if name.startswith("after-reupdate:") else name
        return (name != plain, PRIORITY.index(plain.split(":")[0]), name)
    return "invariant: " + min(result["broken"], key=rank)


def shrink(seed, index, result, timeout):
    """Switches knobs off one by one (last applied first) while the failure keeps its
    signature. Returns the knobs switched off."""
    target = signature_of(result)
    state = dict(without=list(result.get("without", [])))
    outcome = {}

    def trials():
        for knob in reversed(Case.active_knobs(seed, index, state["without"])):
            if knob == "mesh":
                continue
            outcome.clear()
            trial = state["without"] + [knob]
            yield index, trial
            if outcome.get("status") in ("crash", "hang", "invariant") and \
                    signature_of(outcome) == target:
                state["without"] = trial

    run_tasks(trials(), seed, 1, timeout, lambda task, r: outcome.update(r))
    return state["without"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=None)
    parser.add_argument("--cases", type=int, default=None)
    parser.add_argument("--minutes", type=float, default=None)
    parser.add_argument("--timeout", type=float, default=30.0, help="seconds per case")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes")
    parser.add_argument("--first", type=int, default=0, help="index of the first case")
    parser.add_argument("--out", default="fuzz-failures", help="folder for failing cases")
    parser.add_argument("--no-shrink", action="store_true")
    parser.add_argument("--replay", type=int, default=None, help="run one case in this process")
    parser.add_argument("--without", default="", help="knobs to switch off, comma-separated")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.seed is None:
        args.seed = int(time.time()) % 1000000
    if args.worker:
        return worker_main(args.seed)
    if args.replay is not None:
        V = vtk_modules()
        np.seterr(all="ignore")
        without = [k for k in args.without.split(",") if k]
        result = run_case(V, args.seed, args.replay, without, verbose=True)
        print(json.dumps({k: result[k] for k in ("status", "broken", "errors", "seconds")},
                         indent=1, default=str))
        return 3 if result["status"] == "invariant" else 0

    stop_at = time.time() + 60 * args.minutes if args.minutes else None
    count = args.cases if args.cases is not None else (None if stop_at else 100)
    first = args.first
    indices = range(first, first + count) if count is not None else counter(first)
    switched_off = [k for k in args.without.split(",") if k]
    tasks = ((i, switched_off) for i in indices)
    tally = dict(cases=0, ok=0, error=0, crash=0, hang=0, invariant=0, harness=0)
    classes, refusals = {}, {}
    failures = []
    # Replays need this run's environment (the module's path, the sanitizer runtime).
    env = " ".join("%s=%s" % (k, os.environ[k]) for k in
                   ("PYTHONPATH", "LD_PRELOAD", "ASAN_OPTIONS", "UBSAN_OPTIONS") if k in os.environ)
    script = "%s %s" % (sys.executable, os.path.abspath(__file__))

    def on_result(task, result):
        index = task[0]
        result.setdefault("without", task[1])
        tally["cases"] += 1
        tally[result["status"]] += 1
        result.setdefault("index", index)
        if result["status"] == "error":
            reason = re.sub(r"\(0x[0-9a-f]+\)|-?\d[\d.e+-]*|'[^']*'", "#",
                            result["errors"][0].split("\n")[-1])[:90]
            refusals[reason] = refusals.get(reason, 0) + 1
        if result["status"] in ("ok", "error"):
            return
        sig = signature_of(result) if result["status"] != "harness" else \
            "harness: " + result["broken"]["harness"]
        entry = classes.setdefault(sig, dict(count=0, first=index))
        entry["count"] += 1
        failures.append((index, sig, result))
        print("case %d: %s" % (index, sig), flush=True)

    started = time.time()
    print("fuzz_filter: seed %d, %s, timeout %g s, %d job(s)" % (
        args.seed, "%d cases" % count if count is not None else "%g minutes" % args.minutes,
        args.timeout, args.jobs), flush=True)
    run_tasks(tasks, args.seed, args.jobs, args.timeout, on_result, stop_at)
    elapsed = time.time() - started

    if failures:
        os.makedirs(args.out, exist_ok=True)
    shrunk = {}
    for index, sig, result in failures:
        without = []
        if sig not in shrunk and not args.no_shrink and result["status"] != "harness":
            without = shrink(args.seed, index, result, args.timeout)
            shrunk[sig] = True
            result = dict(result, shrunk_without=without,
                          shrunk_active=Case.active_knobs(args.seed, index, without))
            classes[sig]["replay"] = "%s --seed %d --replay %d%s" % (
                script, args.seed, index, " --without " + ",".join(without) if without else "")
        result.update(seed=args.seed, signature=sig, replay="%s %s --seed %d --replay %d" % (
            env, script, args.seed, index))
        with open(os.path.join(args.out, "seed%d-case%d.json" % (args.seed, index)), "w") as f:
            json.dump(result, f, indent=1, default=str)

    header = ("cases", "rendered", "refused", "crashes", "hangs", "invariant", "harness", "seconds")
    print("\n" + " ".join("%-9s" % h for h in header))
    print(" ".join("%-9d" % v for v in (
        tally["cases"], tally["ok"], tally["error"], tally["crash"], tally["hang"],
        tally["invariant"], tally["harness"], elapsed)))
    print("(rendered: no error, invariants hold; refused: handled with an error message; "
          "invariant: broken invariants; harness: a bug of the fuzzer)")
    print("\nRefusals by message:")
    for reason, n in sorted(refusals.items(), key=lambda e: -e[1])[:12]:
        print("  %5d  %s" % (n, reason))
    if classes:
        print("\nDistinct failures (count, first case, shrunk replay):")
        for sig, entry in sorted(classes.items(), key=lambda e: -e[1]["count"]):
            print("  %4d  case %-6d %s" % (entry["count"], entry["first"], sig))
            if "replay" in entry:
                print("        %s" % entry["replay"])
        print("Failing cases written to %s/; replay in this environment:\n  %s" % (args.out, env))
    return 1 if classes else 0


if __name__ == "__main__":
    sys.exit(main())
