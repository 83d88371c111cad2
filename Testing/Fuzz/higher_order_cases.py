"""Lagrange and Bezier tetrahedra for the fuzzers (fuzz_filter.py, fuzz_wheel.py), and the oracle
that predicts, from a mesh's raw arrays alone, which cells TetDSR must skip and why.

Node positions come from VTK itself (Testing/Python/higher_order_grids.py: each cell class's
GetParametricCoords), so this module is imported in the fuzzers' workers only, where a VTK is.

The oracle follows the order in which the core reads a cell (docs/reliability-and-limits.md,
"What is checked"): its type; its id count (4 for VTK_TETRA, 10 for VTK_QUADRATIC_TETRA, a
tetrahedral number for Lagrange and Bezier tetrahedra: orders 1 to 4 read, any higher order
skipped as "order too high", any other count malformed; the hexahedra and wedges the core splits
into tetrahedra (SplitCells.cpp, splitShapeOf): fixed counts, cube numbers for Lagrange and Bezier
hexahedra and (p + 1)^2 (p + 2) / 2 for Lagrange and Bezier wedges (orders 1 to 4 read, higher
skipped as "order too high"); pyramids of a type not read); ids in range; ids distinct; a Bezier cell's rational weights (when
the point data has them) equal, positive and finite; then finite coordinates and values at every
node of the cell (a split cell's own nodes). Geometry (degenerate shapes, tangled or out-of-scale
cells) is not predicted: those cells are allowed to be skipped, never required to be."""
import os
import sys
from functools import lru_cache

import numpy as np

VTK_TETRA, VTK_QUADRATIC_TETRA = 10, 24
VTK_LAGRANGE_TETRAHEDRON, VTK_BEZIER_TETRAHEDRON = 71, 78
READ_TYPES = (VTK_TETRA, VTK_QUADRATIC_TETRA, VTK_LAGRANGE_TETRAHEDRON, VTK_BEZIER_TETRAHEDRON)
MAX_ORDER = 4
# Hexahedra, wedges and pyramids (VTK_PYRAMID, VTK_QUADRATIC_PYRAMID, VTK_TRIQUADRATIC_PYRAMID read;
# the Lagrange and Bezier pyramids not: VTK 9.2 has no cell class of them).
VTK_VOXEL, VTK_HEXAHEDRON, VTK_WEDGE, VTK_PYRAMID, VTK_PENTAGONAL_PRISM = 11, 12, 13, 14, 15
VTK_QUADRATIC_HEXAHEDRON, VTK_QUADRATIC_WEDGE, VTK_QUADRATIC_PYRAMID = 25, 26, 27
VTK_TRIQUADRATIC_HEXAHEDRON, VTK_QUADRATIC_LINEAR_WEDGE = 29, 31
VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON = 32, 33
VTK_TRIQUADRATIC_PYRAMID = 37
VTK_LAGRANGE_HEXAHEDRON, VTK_LAGRANGE_WEDGE, VTK_LAGRANGE_PYRAMID = 72, 73, 74
VTK_BEZIER_HEXAHEDRON, VTK_BEZIER_WEDGE, VTK_BEZIER_PYRAMID = 79, 80, 81
# The id count each fixed-size type the core splits is read with.
SPLIT_FIXED = {VTK_VOXEL: 8, VTK_HEXAHEDRON: 8, VTK_QUADRATIC_HEXAHEDRON: 20,
               VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON: 24, VTK_TRIQUADRATIC_HEXAHEDRON: 27, VTK_WEDGE: 6,
               VTK_QUADRATIC_LINEAR_WEDGE: 12, VTK_QUADRATIC_WEDGE: 15,
               VTK_BIQUADRATIC_QUADRATIC_WEDGE: 18}
# The highest order of Lagrange and Bezier hexahedra ((p + 1)^3 ids) and wedges
# ((p + 1)^2 (p + 2) / 2 ids) read (order p: total degree 3p and 2p); higher: order too high.
MAX_HEX_ORDER, MAX_WEDGE_ORDER = 4, 4
BEZIER_TYPES = (VTK_BEZIER_TETRAHEDRON, VTK_BEZIER_HEXAHEDRON, VTK_BEZIER_WEDGE)
PYRAMID_NODES = {VTK_PYRAMID: 5, VTK_QUADRATIC_PYRAMID: 13, VTK_TRIQUADRATIC_PYRAMID: 19}
PYRAMIDS = (VTK_PYRAMID, VTK_QUADRATIC_PYRAMID, VTK_TRIQUADRATIC_PYRAMID, VTK_LAGRANGE_PYRAMID,
            VTK_BEZIER_PYRAMID)
# Every type the core reads, and the id counts worth trying on the hexahedra, wedges and
# pyramids: each type's own, its neighbours', higher orders' and none.
SPLIT_TYPES = tuple(SPLIT_FIXED) + (
    VTK_LAGRANGE_HEXAHEDRON, VTK_BEZIER_HEXAHEDRON, VTK_LAGRANGE_WEDGE, VTK_BEZIER_WEDGE)
SPLIT_COUNTS = [0, 1, 4, 5, 6, 7, 8, 9, 10, 12, 13, 14, 15, 18, 19, 20, 21, 24, 27, 40, 64, 75, 125]

# Why a cell must be skipped, in the order the core checks, with its counter's name
# (GetNumberOf<name>Cells in the filters, the binding's summary key).
UNSUPPORTED, MALFORMED, ORDER_TOO_HIGH = "unsupported type", "malformed", "order too high"
INVALID_ID, REPEATED_ID, RATIONAL = "id out of range", "repeated id", "rational weights"
NONFINITE = "non-finite coordinate or value"
NO_CELL = "No cell can be rendered"  # the refusals for cells (MeshInput.cpp describeSkipped)
COUNTER_OF = {UNSUPPORTED: "Unsupported", MALFORMED: "Malformed", ORDER_TOO_HIGH: "OrderTooHigh",
              INVALID_ID: "InvalidId", REPEATED_ID: "Degenerate", RATIONAL: "Rational",
              NONFINITE: "NonFinite"}
SUMMARY_KEY = {"Unsupported": "unsupported", "Malformed": "malformed",
               "OrderTooHigh": "order_too_high", "InvalidId": "invalid_id",
               "Degenerate": "degenerate", "Rational": "rational", "NonFinite": "non_finite",
               "OutOfScale": "out_of_scale", "Tangled": "tangled", "Rendered": "valid"}
# Counters the oracle predicts exactly (the first checks of a cell, made before any geometry);
# Degenerate also counts flat and needle-like cells, so it is only bounded below.
EXACT = ("Unsupported", "Malformed", "OrderTooHigh", "InvalidId", "Rational", "NonFinite")
# The warning each counter gives (MeshInput.cpp), as "Skipped <count><this>".
WARNING_OF = {"Unsupported": " cells of a type TetDSR does not read",
              "OrderTooHigh": " cells of an order TetDSR does not read",
              "Malformed": " malformed cells",
              "InvalidId": " cells with node ids outside",
              "Rational": " rational Bezier cells",
              "NonFinite": " cells with NaN or Inf values"}
# Id counts no tetrahedron of orders 1-4 has (or of order 5 and 6: 56, 84), and huge ones:
# 47905 (order 64), 50116 (order 65), 10^6 (no tetrahedral number).
HOSTILE_COUNTS = [0, 1, 3, 5, 15, 19, 21, 34, 36, 56, 84]
HUGE_COUNTS = [47905, 50116, 10 ** 6]


def lattice_count(order):
    return (order + 1) * (order + 2) * (order + 3) // 6


def order_of(count, nodes=lattice_count):
    """The order P of a cell of `count` nodes (count = nodes(P), P >= 1), 0 if none: a
    tetrahedron's by default."""
    p = 1
    while nodes(p) < count:
        p += 1
    return p if nodes(p) == count else 0


def hexahedron_count(order):
    return (order + 1) ** 3


def wedge_count(order):
    return (order + 1) ** 2 * (order + 2) // 2


def read_status(vtk_type, count):
    """What reading a cell of this type and id count gives, as the core does (Cells.h cellLayout
    for tetrahedra, HexahedronCell.cpp hexahedronNodesOf for the others): "" (read) or UNSUPPORTED,
    MALFORMED, ORDER_TOO_HIGH."""
    if vtk_type in READ_TYPES:
        order = {VTK_TETRA: 1 if count == 4 else 0,
                 VTK_QUADRATIC_TETRA: 2 if count == 10 else 0}.get(vtk_type, order_of(count))
        return MALFORMED if order == 0 else ORDER_TOO_HIGH if order > MAX_ORDER else ""
    if vtk_type in SPLIT_FIXED:
        return "" if count == SPLIT_FIXED[vtk_type] else MALFORMED
    if vtk_type in PYRAMID_NODES:  # read as collapsed hexahedra (HexahedronCell.h)
        return "" if count == PYRAMID_NODES[vtk_type] else MALFORMED
    if vtk_type in (VTK_LAGRANGE_HEXAHEDRON, VTK_BEZIER_HEXAHEDRON):
        order = order_of(count, hexahedron_count)
        return MALFORMED if order == 0 else ORDER_TOO_HIGH if order > MAX_HEX_ORDER else ""
    if vtk_type in (VTK_LAGRANGE_WEDGE, VTK_BEZIER_WEDGE):
        order = order_of(count, wedge_count)  # (VTK's 21-node wedge: malformed)
        return MALFORMED if order == 0 else ORDER_TOO_HIGH if order > MAX_WEDGE_ORDER else ""
    return UNSUPPORTED  # the higher-order pyramids (not read) and every other type


@lru_cache(maxsize=None)
def barycentric_nodes(vtk_type, order):
    """(nodes, 4) barycentric coordinates of a cell's nodes in VTK's order, from VTK."""
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, os.path.join(here, "..", "Python"))
    import higher_order_grids  # noqa: E402 (VTK, in the workers only)
    if vtk_type == VTK_TETRA:
        return np.eye(4)
    pc = higher_order_grids.node_parametric(vtk_type, order)
    return np.c_[1.0 - pc.sum(axis=1), pc]


def pick(rng, choices):
    return choices[int(rng.integers(len(choices)))]


class HigherOrderMesh:
    """Cells of every type the core reads (each with nodes of its own), as raw arrays."""

    def __init__(self, points, types, offsets, conn, orders):
        self.points, self.types, self.offsets, self.conn = points, types, offsets, conn
        self.orders = orders  # the order each cell was made with (0: not a tetrahedron)
        self.weights = None   # the RationalWeights array, when the case has one

    def cell_nodes(self, c):
        return self.conn[self.offsets[c]:self.offsets[c + 1]]


def make_mesh(rng, vertices, hostile):
    """Straight tetrahedra on the (cells, 4, 3) vertices, each given a type and an order: one
    kind for the whole mesh or a mix (with VTK_TETRA and VTK_QUADRATIC_TETRA), orders 1 to 5
    (order 5, 56 nodes, is above what the core reads). Returns (HigherOrderMesh, description)."""
    mix = pick(rng, ["lagrange", "bezier", "mixed", "mixed", "one"])
    kinds = {"lagrange": [VTK_LAGRANGE_TETRAHEDRON], "bezier": [VTK_BEZIER_TETRAHEDRON],
             "mixed": [VTK_TETRA, VTK_QUADRATIC_TETRA, VTK_LAGRANGE_TETRAHEDRON,
                       VTK_BEZIER_TETRAHEDRON], "one": [pick(rng, [VTK_LAGRANGE_TETRAHEDRON,
                                                                    VTK_BEZIER_TETRAHEDRON])]}[mix]
    order_weights = np.array([1, 1, 2, 2, 0.3 if hostile else 0.0])
    one_order = int(rng.choice(np.arange(1, 6), p=order_weights / order_weights.sum()))
    points, types, conn, offsets, orders = [], [], [], [0], []
    total = 0
    for v in vertices:
        vtk_type = pick(rng, kinds)
        order = {VTK_TETRA: 1, VTK_QUADRATIC_TETRA: 2}.get(vtk_type, one_order if mix == "one" else
                                                           int(rng.choice(np.arange(1, 6),
                                                               p=order_weights / order_weights.sum())))
        nodes = barycentric_nodes(vtk_type, order) @ v
        conn.extend(range(total, total + len(nodes)))
        total += len(nodes)
        points.append(nodes)
        offsets.append(len(conn))
        types.append(vtk_type)
        orders.append(order)
    mesh = HigherOrderMesh(np.vstack(points), np.array(types, np.uint8),
                           np.array(offsets, np.int64), np.array(conn, np.int64),
                           np.array(orders))
    return mesh, "%s, orders %s" % (mix, sorted(set(orders)))


def bend(rng, mesh, amplitude, fraction, vertices_too=False):
    """Moves the non-vertex nodes (and the vertices too, if asked) of a `fraction` of the cells by
    `amplitude` times the cell's size (a number, NaN or Inf). Returns the cells moved."""
    moved = []
    for c in range(len(mesh.types)):
        ids = mesh.cell_nodes(c)
        if len(ids) <= 4 and not vertices_too or rng.random() >= fraction:
            continue
        size = np.ptp(mesh.points[ids], axis=0).max()
        who = ids if vertices_too else ids[4:]
        with np.errstate(all="ignore"):
            mesh.points[who] += rng.normal(0, 1, (len(who), 3)) * amplitude * size
        moved.append(c)
    return moved


def curved_pieces(vtk_type, count):
    """What a curved cell of this type and id count costs a ray, in curved cells of order 3 or 4
    (one box solve each, HexahedronCell.h): 1 for a Lagrange or Bezier tetrahedron, hexahedron or
    wedge of order 3 or 4, else 0 (lower orders cost a fraction of that)."""
    if read_status(vtk_type, count):
        return 0
    if vtk_type in READ_TYPES:
        order = order_of(count)
    elif vtk_type in (VTK_LAGRANGE_HEXAHEDRON, VTK_BEZIER_HEXAHEDRON):
        order = order_of(count, hexahedron_count)
    elif vtk_type in (VTK_LAGRANGE_WEDGE, VTK_BEZIER_WEDGE):
        order = order_of(count, wedge_count)
    else:
        return 0
    return 1 if order in (3, 4) else 0


def curved_cost_cells(mesh, moved):
    """How many curved tetrahedra of order 3 or 4 the moved cells cost (curved_pieces): each ray
    test of such a tetrahedron is a subdivision solve, 100-300 us in the release build and about 5
    times that under ASan."""
    return sum(curved_pieces(int(mesh.types[c]), len(mesh.cell_nodes(c))) for c in moved)


def set_cells(mesh, cells):
    """The mesh's connectivity and offsets from a list of cells' id lists."""
    mesh.conn = np.array([i for c in cells for i in c], dtype=np.int64)
    mesh.offsets = np.concatenate([[0], np.cumsum([len(c) for c in cells])]).astype(np.int64)


def hostile_split_cells(rng, mesh, count):
    """`count` cells (ids of the mesh's) given a hexahedron's, wedge's or pyramid's type (or a
    pentagonal prism's), half of them also a number of ids of another type's or none's (padded
    with valid ids of the mesh, or cut): malformed, of too high an order, unsupported or read
    (then most are tangled or degenerate: their nodes are other cells'). Returns (description,
    how many tetrahedra of order 3-4 the read ones become: curved_cost_cells)."""
    if len(mesh.offsets) != len(mesh.types) + 1 or len(mesh.types) == 0:
        return "no cells", 0
    cells = [list(mesh.cell_nodes(c)) for c in range(len(mesh.types))]
    npts = len(mesh.points)
    made, cost = [], 0
    for c in rng.integers(0, len(cells), count):
        vtk_type = pick(rng, list(SPLIT_TYPES) + list(PYRAMIDS) + [VTK_PENTAGONAL_PRISM])
        if rng.random() < 0.5:
            size = pick(rng, SPLIT_COUNTS) if rng.random() < 0.98 else pick(rng, HUGE_COUNTS)
        else:
            size = SPLIT_FIXED.get(vtk_type, pick(rng, [5, 6, 8, 13, 14, 18]))
        cells[c] = (cells[c] + list(rng.integers(0, max(npts, 1), max(0, size - len(cells[c])))))[:size]
        mesh.types[c] = vtk_type
        if len(mesh.orders) == len(cells):
            mesh.orders[c] = 0
        cost += curved_pieces(vtk_type, size)
        made.append((int(vtk_type), size))
    set_cells(mesh, cells)
    return "hexahedra, wedges, pyramids (type, ids) %s" % sorted(made)[:8], cost


@lru_cache(maxsize=None)
def split_nodes(vtk_type, count):
    """(count, 3) parametric coordinates of a hexahedron's or wedge's nodes in VTK's order, from
    VTK (Testing/Python/hex_wedge_grids.py)."""
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path.insert(0, os.path.join(here, "..", "Python"))
    import hex_wedge_grids  # noqa: E402 (VTK, in the workers only)
    return hex_wedge_grids.node_parametric(vtk_type, count)


# Every (type, id count) the core reads as a hexahedron or wedge.
READ_SPLIT = [(t, n) for t, n in SPLIT_FIXED.items()] + [
    (t, hexahedron_count(p)) for t in (VTK_LAGRANGE_HEXAHEDRON, VTK_BEZIER_HEXAHEDRON)
    for p in range(1, MAX_HEX_ORDER + 1)] + [
    (t, wedge_count(p)) for t in (VTK_LAGRANGE_WEDGE, VTK_BEZIER_WEDGE) for p in range(1, MAX_WEDGE_ORDER + 1)]


def straight_split_cells(rng, mesh, fraction):
    """A `fraction` of the cells replaced by straight (affine) hexahedra and wedges of the kinds
    the core reads, on nodes of their own: the parametric cell mapped by the affine map of the
    cell's first four nodes (its vertices), so positive where the tetrahedron was; they overlap
    their neighbours. Returns (description, cells made)."""
    if len(mesh.offsets) != len(mesh.types) + 1:
        return "no cells", []
    cells = [list(mesh.cell_nodes(c)) for c in range(len(mesh.types))]
    points = [mesh.points]
    total = next_id = len(mesh.points)
    kind = pick(rng, ["one", "mixed"])
    one = pick(rng, READ_SPLIT)
    made = []
    for c in range(len(cells)):
        ids = np.asarray(cells[c])
        if rng.random() >= fraction or len(ids) < 4 or np.any((ids[:4] < 0) | (ids[:4] >= total)):
            continue
        vtk_type, count = one if kind == "one" else pick(rng, READ_SPLIT)
        v = mesh.points[ids[:4]]
        pc = split_nodes(vtk_type, count)
        nodes = v[0] + pc @ (v[1:] - v[0])
        cells[c] = list(range(next_id, next_id + count))
        next_id += count
        points.append(nodes)
        mesh.types[c] = vtk_type
        if len(mesh.orders) == len(cells):
            mesh.orders[c] = 0
        made.append(c)
    mesh.points = np.vstack(points)
    set_cells(mesh, cells)
    return "%d straight hexahedra and wedges (%s)" % (
        len(made), one if kind == "one" else "mixed"), made


def hostile_counts(rng, mesh, count):
    """`count` cells made Lagrange or Bezier tetrahedra with a hostile number of ids (padded with
    valid ids of the mesh). Returns a description."""
    cells = [list(mesh.cell_nodes(c)) for c in range(len(mesh.types))]
    if len(mesh.orders) != len(cells):
        mesh.orders = np.zeros(len(cells), dtype=int)
    npts = len(mesh.points)
    made = []
    for c in rng.integers(0, len(cells), count):
        size = pick(rng, HOSTILE_COUNTS) if rng.random() < 0.97 else pick(rng, HUGE_COUNTS)
        cells[c] = (cells[c] + list(rng.integers(0, npts, max(0, size - len(cells[c])))))[:size]
        mesh.types[c] = pick(rng, [VTK_LAGRANGE_TETRAHEDRON, VTK_BEZIER_TETRAHEDRON])
        mesh.orders[c] = 0
        made.append(size)
    set_cells(mesh, cells)
    return "id counts %s" % sorted(made)


def rational_weights(rng, npts, bezier_cells, mesh):
    """A RationalWeights array (numpy; None for none) and its description: equal, differing in
    one cell or everywhere, zero, negative, NaN or Inf, short, empty, long, two components, and
    of other dtypes."""
    kind = pick(rng, ["equal", "equal", "one_cell", "differ", "zero", "negative", "nan", "inf",
                      "short", "empty", "long", "components", "int_equal", "float32"])
    w = np.full(npts, float(pick(rng, [1.0, 0.5, 7.0, 1e-300, 1e300])))
    # (Cells that other knobs' offsets still hold: a truncated offsets array drops the last ones.)
    bezier_cells = [c for c in bezier_cells if c + 1 < len(mesh.offsets)]
    if kind in ("one_cell", "zero", "negative", "nan", "inf") and bezier_cells:
        ids = mesh.cell_nodes(int(pick(rng, bezier_cells)))
        node = ids[int(rng.integers(len(ids)))] if len(ids) else 0
        node = node if 0 <= node < npts else 0  # (ids made garbage by other knobs)
        w[node] = {"one_cell": w[node] * 1.5, "zero": 0.0, "negative": -w[node],
                   "nan": np.nan, "inf": np.inf}[kind]
    elif kind == "differ":
        w = rng.uniform(0.5, 2.0, npts)
    elif kind == "short":
        w = w[:max(0, npts - int(rng.integers(1, 3)))]
    elif kind == "empty":
        w = w[:0]
    elif kind == "long":
        w = np.append(w, rng.normal(size=3))
    elif kind == "components":
        w = np.c_[w, w]
    elif kind == "int_equal":
        # (astype: -2 wraps to 254 in uint8, where numpy 2's np.full refuses it.)
        w = np.full(npts, int(pick(rng, [1, 3, 0, -2]))).astype(pick(rng, [np.int32, np.uint8, np.int64]))
    elif kind == "float32":
        w = w.astype(np.float32)  # 1e300 and 1e-300 become Inf and 0
    return w, kind


def predict(types, offsets, conn, points, values, weights):
    """Per cell, the reason the core must skip it ("" when none is known), and the error the
    whole input must be refused with (None when none is predicted), from the raw arrays:
    types (m,), offsets (m + 1,), conn, points (n, 3) float64, values (n,) float64 or None (no
    usable field), weights (n', k) float64 or None. Returns (None, None) for offsets or a types
    array that do not describe the cells (the filters refuse or skip those in other ways)."""
    types = np.asarray(types)
    offsets = np.asarray(offsets, dtype=np.int64)
    if (len(offsets) < 1 or offsets[0] != 0 or np.any(np.diff(offsets) < 0)
            or offsets[-1] != len(conn) or len(types) != len(offsets) - 1):
        return None, None
    npts = len(points)
    finite_point = np.all(np.isfinite(points), axis=1)
    finite_value = np.isfinite(values[:npts]) if values is not None else np.ones(npts, bool)
    if values is not None and len(values) < npts:
        finite_value = np.r_[finite_value, np.zeros(npts - len(values), bool)]
    error = None
    w = None
    if weights is not None:
        weights = np.asarray(weights, dtype=np.float64)
        weights = weights.reshape(len(weights), -1) if weights.size else weights.reshape(0, 1)
        if len(weights) < npts or weights.shape[1] != 1:
            error = "The rational weights array"
        else:
            w = weights[:npts, 0]
    reasons = np.full(len(types), "", dtype=object)
    for c in range(len(types)):
        ids = conn[offsets[c]:offsets[c + 1]]
        t = int(types[c])
        # (A read cell's id count is its node count: the checks below take all its ids.)
        if (read := read_status(t, len(ids))):
            reasons[c] = read
        elif np.any((ids < 0) | (ids >= npts)):
            reasons[c] = INVALID_ID
        elif len(np.unique(ids)) != len(ids):
            reasons[c] = REPEATED_ID
        elif t in BEZIER_TYPES and w is not None and not (
                np.isfinite(w[ids[0]]) and w[ids[0]] > 0 and np.all(w[ids] == w[ids[0]])):
            reasons[c] = RATIONAL
        elif not (np.all(finite_point[ids]) and np.all(finite_value[ids])):
            # (A split cell's pieces take its map and field at new points too: any non-finite
            # node of its own makes them all non-finite, and nothing else may.)
            reasons[c] = NONFINITE
    if error is None and len(types) and np.all(np.isin(reasons, [UNSUPPORTED, MALFORMED,
                                                                 ORDER_TOO_HIGH])):
        error = NO_CELL + ": none of the"
    elif error is None and len(types) and np.all(reasons != ""):
        error = NO_CELL + ": all"
    return reasons, error


def check_refusal(expected, errors, broken, where=""):
    """A refusal of the mesh for its cells ("No cell can be rendered: ...", among the error texts
    `errors`) must be the one predicted: "none of the" when no cell is of a type and id count
    read, "all" when every cell was skipped for some other reason too (and no refusal of either
    kind says that a cell is readable when none is). Other errors may come first."""
    told = [e for e in errors if NO_CELL in e]
    if not told or (expected and not expected.startswith(NO_CELL)):
        return
    none_of = NO_CELL + ": none of the"
    if expected == none_of and not any(none_of in e for e in told) or \
            expected != none_of and any(none_of in e for e in told):
        broken[where + "wrong-refusal: expected %s" % (expected or "none or 'all'")] = \
            told[0][told[0].find(NO_CELL):][:160]


def check_counts(reasons, counts, warnings, broken, where=""):
    """Compares the skip counters (a dict by counter name) and the warnings (texts; None: not
    checked) with the reasons predicted; adds what differs to `broken`."""
    expected = {}
    for reason in reasons[reasons != ""]:
        expected[COUNTER_OF[reason]] = expected.get(COUNTER_OF[reason], 0) + 1
    wrong = []
    for name in EXACT:
        if name in counts and counts[name] != expected.get(name, 0):
            wrong.append("%s %d, expected %d" % (name, counts[name], expected.get(name, 0)))
    if "Degenerate" in counts and counts["Degenerate"] < expected.get("Degenerate", 0):
        wrong.append("Degenerate %d, expected at least %d" % (counts["Degenerate"],
                                                              expected["Degenerate"]))
    if wrong:
        why = sorted(set(r for r in reasons if r and COUNTER_OF[r] in
                         [w.split()[0] for w in wrong]))
        broken[where + "skip-counts: " + ", ".join(why or ["none predicted"])] = "; ".join(wrong)
    if warnings is None:
        return
    for name, text in WARNING_OF.items():
        n = expected.get(name, 0)
        told = any(w.find("Skipped %d%s" % (n, text)) >= 0 for w in warnings)
        if n and not told:
            broken[where + "warning-missing: " + name] = "expected 'Skipped %d%s', got %s" % (
                n, text, [w[-160:] for w in warnings][:4])
