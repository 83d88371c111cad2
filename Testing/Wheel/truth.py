"""Independent truth for the wheel's tests (numpy only; none of TetDSR's code): pixel rays from
a camera by the filter's documented convention, and the exact first crossing of an iso-value of
a quadratic field, per cell (a monomial fit of the 10 nodal values, exact for a field that is
quadratic in each straight-sided cell) or for one global quadric."""
import math

import numpy as np


def pixel_rays(position, focal_point, view_up, view_angle, width, height, parallel=False,
               parallel_scale=1.0):
    """Rays through pixel centres: pixel (i, j), j = 0 the bottom row, is row i + j * width."""
    position = np.asarray(position, float)
    forward = np.asarray(focal_point, float) - position
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, view_up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = parallel_scale if parallel else math.tan(math.radians(view_angle) / 2)
    i, j = np.meshgrid(np.arange(width), np.arange(height))
    x = ((2 * (i + 0.5) / width - 1) * half * width / height).reshape(-1, 1)
    y = ((2 * (j + 0.5) / height - 1) * half).reshape(-1, 1)
    offset = x * right + y * up
    if parallel:
        return position + offset, np.tile(forward, (len(offset), 1))
    directions = forward + offset
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return np.tile(position, (len(offset), 1)), directions


def _roots(a, b, c):
    """Both roots of a t^2 + b t + c (NaN where there is none), by the stable formula, and the
    relative discriminant |b^2 - 4ac| / (b^2 + |4ac|) (near 0: a tangent ray)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = b * b - 4 * a * c
        relative = np.abs(disc) / (b * b + np.abs(4 * a * c))
        q = -0.5 * (b + np.copysign(np.sqrt(disc), b))
        linear = a == 0
        t0 = np.where(linear, -c / b, q / a)
        t1 = np.where(linear, np.nan, c / q)
    return t0, t1, relative


class QuadraticQuadric:
    """f(x) = x^T M x + g . x + k0 about `centre`."""

    def __init__(self, matrix, gradient, constant, centre=(0.0, 0.0, 0.0)):
        self.M = np.asarray(matrix, float)
        self.g = np.asarray(gradient, float)
        self.k0 = float(constant)
        self.centre = np.asarray(centre, float)

    def __call__(self, x):
        p = np.asarray(x, float) - self.centre
        return np.einsum("...i,ij,...j->...", p, self.M, p) + p @ self.g + self.k0

    def gradient(self, x):
        p = np.asarray(x, float) - self.centre
        return 2 * p @ self.M + self.g

    def along(self, origins, directions, iso):
        q = origins - self.centre
        MD = directions @ self.M
        a = np.einsum("ij,ij->i", directions, MD)
        b = directions @ self.g + 2 * np.einsum("ij,ij->i", q, MD)
        c = self(origins) - iso
        return a, b, c


def first_hit_in_box(quadric, origins, directions, iso, lo, hi, margin=1e-7):
    """First t >= 0 where the global quadric equals iso inside the box [lo, hi]^3 (inf if none),
    and a mask of rays too close to call (tangent, or the hit within `margin` of the box)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t_lo = (lo - origins) / directions
        t_hi = (hi - origins) / directions
    enter = np.max(np.minimum(t_lo, t_hi), axis=1)
    leave = np.min(np.maximum(t_lo, t_hi), axis=1)
    a, b, c = quadric.along(origins, directions, iso)
    t0, t1, relative = _roots(a, b, c)
    best = np.full(len(origins), np.inf)
    unsure = relative < 1e-6
    for t in (t0, t1):
        ok = np.isfinite(t) & (t >= np.maximum(enter, 0)) & (t <= leave)
        best = np.where(ok & (t < best), t, best)
        near = np.isfinite(t) & ((np.abs(t - enter) < margin) | (np.abs(t - leave) < margin))
        unsure |= near
    return best, unsure


_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]


def cell_quadrics(points, cells, values):
    """Per 10-node cell (VTK order, straight-sided): its quadric fitted to the 10 nodal values,
    and the inverse of its barycentric frame."""
    result = []
    for ids in cells:
        nodes = points[ids]
        centre = nodes[:4].mean(axis=0)
        p = nodes - centre
        rows = np.column_stack([np.ones(10), p, p[:, 0] ** 2, p[:, 1] ** 2, p[:, 2] ** 2,
                                p[:, 0] * p[:, 1], p[:, 1] * p[:, 2], p[:, 0] * p[:, 2]])
        k = np.linalg.solve(rows, values[ids])
        M = np.array([[k[4], k[7] / 2, k[9] / 2], [k[7] / 2, k[5], k[8] / 2],
                      [k[9] / 2, k[8] / 2, k[6]]])
        frame = np.linalg.inv(np.column_stack([nodes[1] - nodes[0], nodes[2] - nodes[0],
                                               nodes[3] - nodes[0]]))
        result.append((QuadraticQuadric(M, k[1:4], k[0], centre), nodes[0], frame))
    return result


def _inside(points, origin, frame, tolerance):
    L = (points - origin) @ frame.T
    return np.all(L >= -tolerance, axis=1) & (L.sum(axis=1) <= 1 + tolerance)


def first_hit_in_cells(quadrics, origins, directions, iso):
    """First t >= 0 on the iso-surface of the piecewise quadratic field (inf if none), the cell
    hit, and a mask of tangent rays (relative discriminant < 1e-6 with the vertex in a cell)."""
    best = np.full(len(origins), np.inf)
    cell = np.full(len(origins), -1)
    grazing = np.zeros(len(origins), bool)
    for c, (quadric, origin, frame) in enumerate(quadrics):
        a, b, cc = quadric.along(origins, directions, iso)
        t0, t1, relative = _roots(a, b, cc)
        with np.errstate(divide="ignore", invalid="ignore"):
            vertex = origins - (b / (2 * a))[:, None] * directions
        grazing |= (relative < 1e-6) & _inside(vertex, origin, frame, 1e-6)
        for t in (t0, t1):
            ok = np.isfinite(t) & (t >= 0) & (t < best)
            hit = origins + np.where(ok, t, 0)[:, None] * directions
            ok &= _inside(hit, origin, frame, 1e-9)
            best = np.where(ok, t, best)
            cell = np.where(ok, c, cell)
    return best, cell, grazing
