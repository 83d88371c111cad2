"""Grids of VTK's arbitrary-order tetrahedra (VTK_LAGRANGE_TETRAHEDRON, VTK_BEZIER_TETRAHEDRON) and
the polynomial truth the face tests compare with, for both routes (ParaView's VTK 9.2 and pip's
VTK): only VTK API common to both, and none of TetDSR's code.

- Node positions come from VTK itself (each cell class's GetParametricCoords, the authority for
  node order), mapped affinely onto the straight cells of a Kuhn lattice of [lo, hi]^3.
- A Bezier cell's control values are Bernstein coefficients: the solve of B c = f(nodes) with
  B[i, j] = VTK's vtkBezierTetra.InterpolateFunctions (basis j) at node i.
- The truth: polynomial fields given analytically (value and gradient), the first crossing along
  each pixel ray found by dense sampling and bisection of the analytic field (not of the mesh),
  with a grazing band of rays that pass near the surface without a clear crossing."""
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import (VTK_BEZIER_TETRAHEDRON, VTK_LAGRANGE_TETRAHEDRON,
                                           VTK_QUADRATIC_TETRA, vtkBezierTetra, vtkCellArray,
                                           vtkLagrangeTetra, vtkQuadraticTetra,
                                           vtkUnstructuredGrid)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Wheel"))
from kuhn_lattice import kuhn_tets  # noqa: E402,F401 (the lattice's tets; also for the tests)
from truth import pixel_rays  # noqa: E402,F401  (the filter's documented pixel convention)


def _higher_order_cell(vtk_type, order):
    cell = vtkBezierTetra() if vtk_type == VTK_BEZIER_TETRAHEDRON else vtkLagrangeTetra()
    nodes = (order + 1) * (order + 2) * (order + 3) // 6
    cell.GetPointIds().SetNumberOfIds(nodes)
    cell.GetPoints().SetNumberOfPoints(nodes)
    for n in range(nodes):
        cell.GetPointIds().SetId(n, n)
        cell.GetPoints().SetPoint(n, 0.0, 0.0, 0.0)
    cell.Initialize()
    return cell, nodes


def node_parametric(vtk_type, order):
    """(nodes, 3) parametric coordinates of a cell's nodes in VTK's order."""
    if vtk_type == VTK_QUADRATIC_TETRA:
        return np.array(vtkQuadraticTetra().GetParametricCoords()).reshape(10, 3)
    cell, nodes = _higher_order_cell(vtk_type, order)
    return np.array(cell.GetParametricCoords()).reshape(nodes, 3)


def bernstein_at_nodes(order):
    """B[i, j]: VTK's Bernstein basis function j of order `order` at node i."""
    cell, nodes = _higher_order_cell(VTK_BEZIER_TETRAHEDRON, order)
    pcoords = node_parametric(VTK_BEZIER_TETRAHEDRON, order)
    B = np.zeros((nodes, nodes))
    for i, pc in enumerate(pcoords):
        weights = [0.0] * nodes
        cell.InterpolateFunctions(list(pc), weights)
        B[i] = weights
    return B


def grid(n, vtk_type, order, fields, lo=0.0, hi=1.0, cells=None, weights=None):
    """[lo, hi]^3 as 6 n^3 straight tets of one type and order; fields {name: f(points)} (the
    first is the active scalars). Nodes at the same place are shared. A Bezier grid holds each
    field's Bernstein coefficients; `weights` (per point, or None) become the RationalWeights
    attribute.
    `cells` picks a subset of the Kuhn tets (indices)."""
    if vtk_type == VTK_QUADRATIC_TETRA:
        order = 2
    pcoords = node_parametric(vtk_type, order)
    bary = np.c_[1.0 - pcoords.sum(axis=1), pcoords]  # (nodes, 4): L0 = 1 - r - s - t
    tets = kuhn_tets(n)
    if cells is not None:
        tets = tets[cells]
    # Integer keys on the lattice refined `order` times: shared nodes get one point.
    keys = np.rint(np.einsum("nk,ckd->cnd", bary * order, tets)).astype(np.int64)
    unique, inverse = np.unique(keys.reshape(-1, 3), axis=0, return_inverse=True)
    inverse = inverse.reshape(keys.shape[:2])
    points = lo + (hi - lo) * unique / (n * order)
    ug = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=1))
    ug.SetPoints(p)
    nodes = pcoords.shape[0]
    ca = vtkCellArray()
    ca.SetData(numpy_to_vtkIdTypeArray(np.arange(0, nodes * len(tets) + 1, nodes, dtype=np.int64), deep=1),
               numpy_to_vtkIdTypeArray(np.ascontiguousarray(inverse.ravel(), dtype=np.int64), deep=1))
    ug.SetCells(numpy_to_vtk(np.full(len(tets), vtk_type, np.uint8), deep=1), ca)
    solve = None
    if vtk_type == VTK_BEZIER_TETRAHEDRON:
        B = bernstein_at_nodes(order)
        solve = lambda nodal: np.linalg.solve(B, nodal.T).T  # noqa: E731  per cell, (cells, nodes)
    for k, (name, function) in enumerate(fields.items()):
        values = np.asarray(function(points), dtype=np.float64)
        if solve is not None:
            per_cell = solve(values[inverse])
            values = np.empty(len(points))
            values[inverse.ravel()] = per_cell.ravel()  # a shared node: the same coefficient
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=1)
        array.SetName(name)
        ug.GetPointData().AddArray(array)
        if k == 0:
            ug.GetPointData().SetActiveScalars(name)
    if weights is not None:
        array = numpy_to_vtk(np.ascontiguousarray(weights, dtype=np.float64), deep=1)
        array.SetName("RationalWeights")
        ug.GetPointData().SetRationalWeights(array)  # VTK reads the attribute, not the name
    return ug


class Field:
    """An analytic field: value(points), gradient(points), the iso-value, its polynomial degree."""

    def __init__(self, value, gradient, iso, degree):
        self.value, self.gradient, self.iso, self.degree = value, gradient, iso, degree


def torus(c=(0.5, 0.47, 0.52), R=0.28, r=0.11):
    """(|x - c|^2 + R^2 - r^2)^2 - 4 R^2 ((x - c)_x^2 + (x - c)_y^2) = 0: degree 4."""
    c = np.asarray(c)

    def value(x):
        d = x - c
        s = np.sum(d * d, axis=-1) + R * R - r * r
        return s * s - 4 * R * R * (d[..., 0] ** 2 + d[..., 1] ** 2)

    def gradient(x):
        d = x - c
        s = np.sum(d * d, axis=-1) + R * R - r * r
        g = 4 * s[..., None] * d
        g[..., :2] -= 8 * R * R * d[..., :2]
        return g

    return Field(value, gradient, 0.0, 4)


def cubic_blob(c=(0.48, 0.52, 0.5), k=1.5, radius=0.3):
    """|x - c|^2 + k (x - c)_x^3 = radius^2: a sphere deformed by a cubic term (degree 3)."""
    c = np.asarray(c)

    def value(x):
        d = x - c
        return np.sum(d * d, axis=-1) + k * d[..., 0] ** 3

    def gradient(x):
        d = x - c
        g = 2 * d
        g[..., 0] += 3 * k * d[..., 0] ** 2
        return g

    return Field(value, gradient, radius * radius, 3)


def sphere(c, radius):
    """|x - c|^2 = radius^2 (degree 2)."""
    c = np.asarray(c)
    return Field(lambda x: np.sum((x - c) ** 2, axis=-1), lambda x: 2 * (x - c), radius * radius, 2)


def first_crossing(field, origins, directions, lo=0.0, hi=1.0, samples=800, band=4e-3, chunk=2048):
    """first_crossing_chunk over chunks of rays (bounded memory)."""
    parts = [first_crossing_chunk(field, origins[k:k + chunk], directions[k:k + chunk], lo, hi, samples, band)
             for k in range(0, len(origins), chunk)]
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def first_crossing_chunk(field, origins, directions, lo, hi, samples, band):
    """Per ray: the first t >= 0 inside [lo, hi]^3 where the field crosses its iso-value (inf if
    none), and whether the ray lies in the grazing band (not to be compared): the crossing is
    nearly tangent (|cos(ray, gradient)| < 1e-3), or before it (or anywhere, without one) the ray
    comes within about `band` (world units) of the surface, a local minimum of |f - iso| / |grad f|
    below `band`, where a tangent pair of roots could hide between samples."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / directions
        t_a = (lo - origins) * inv
        t_b = (hi - origins) * inv
    t_near = np.max(np.minimum(t_a, t_b), axis=1).clip(min=0.0)
    t_far = np.min(np.maximum(t_a, t_b), axis=1)
    inside = t_far > t_near
    t = np.full(len(origins), np.inf)
    grazing = np.zeros(len(origins), bool)
    rows = np.flatnonzero(inside)
    s = np.linspace(0.0, 1.0, samples)
    ts = t_near[rows, None] + s[None, :] * (t_far - t_near)[rows, None]
    x = origins[rows, None, :] + ts[..., None] * directions[rows, None, :]
    f = field.value(x) - field.iso
    distance = np.abs(f) / np.linalg.norm(field.gradient(x), axis=-1)
    change = np.signbit(f[:, :-1]) != np.signbit(f[:, 1:])
    has = change.any(axis=1)
    first = np.argmax(change, axis=1)
    # Bisection of the analytic field in the first sign-change interval.
    a = ts[np.arange(len(rows)), first]
    b = ts[np.arange(len(rows)), first + 1]
    fa = f[np.arange(len(rows)), first]
    o, d = origins[rows], directions[rows]
    for _ in range(60):
        m = 0.5 * (a + b)
        fm = field.value(o + m[:, None] * d) - field.iso
        left = np.signbit(fm) != np.signbit(fa)
        b = np.where(left, m, b)
        a = np.where(left, a, m)
        fa = np.where(left, fa, fm)
    root = 0.5 * (a + b)
    # The grazing band: near misses before the crossing (or along the whole ray without one),
    # local minima of the distance estimate below the band (the crossing's own minimum lies in
    # its sign-change interval, at `first` or `first + 1`).
    dip = np.zeros_like(distance, dtype=bool)
    dip[:, 1:-1] = (distance[:, 1:-1] <= distance[:, :-2]) & (distance[:, 1:-1] <= distance[:, 2:])
    before = np.where(has, first, samples)[:, None] > np.arange(samples)[None, :]
    near_miss = np.any(dip & before & (distance < band), axis=1)
    g = field.gradient(o + root[:, None] * d)
    cos = np.abs(np.einsum("ij,ij->i", g, d)) / np.linalg.norm(g, axis=1)
    tangent = has & (cos < 1e-3)
    t[rows[has]] = root[has]
    grazing[rows] = near_miss | tangent
    return t, grazing


def triangle_hits(surface_points, triangles, origins, directions, block=64):
    """Which rays hit any of the triangles (Moller-Trumbore, t > 0): vtkContourFilter's
    coverage of the pixels, without a per-ray locator call."""
    a = surface_points[triangles[:, 0]]
    e1 = surface_points[triangles[:, 1]] - a
    e2 = surface_points[triangles[:, 2]] - a
    hit = np.zeros(len(origins), bool)
    for k in range(0, len(origins), block):
        o, d = origins[k:k + block, None, :], directions[k:k + block, None, :]
        p = np.cross(d, e2)
        det = np.einsum("rtk,tk->rt", p, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            s = o - a
            u = np.einsum("rtk,rtk->rt", s, p) * inv
            q = np.cross(s, e1)
            v = np.einsum("rtk,rtk->rt", d, q) * inv
            t = np.einsum("tk,rtk->rt", e2, q) * inv
        hit[k:k + block] = np.any((u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & (det != 0), axis=1)
    return hit
