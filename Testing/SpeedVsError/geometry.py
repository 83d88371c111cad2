"""Numpy geometry for the speed-vs-error report, written without the filter's code: lattice meshes
of tetrahedra, pixel rays with TetDSR's convention, the exact first hit of a quadric along each
ray, the first hit on a triangle surface along the same rays, and how many tets of a lattice a
ray crosses."""
import itertools
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Python"))
from kuhn_lattice import kuhn_vertices  # noqa: E402

# VTK_QUADRATIC_TETRA's mid-edge nodes, in VTK's order.
QUADRATIC_TETRA_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))


def kuhn_lattice(n, quadratic, lo=(0.0, 0.0, 0.0), hi=(1.0, 1.0, 1.0)):
    """The box [lo, hi] cut into n^3 cells of 6 tets each (Kuhn's triangulation: tet p of a cell
    walks from the cell's lowest corner along the axes in the order of permutation p, so the tets
    are exactly the regions between the planes x_a = integer and x_a - x_b = integer in lattice
    units). Quadratic: 10 nodes per tet on the half-step lattice, in VTK's node order.
    Returns points (P, 3) and connectivity (cells, 4 or 10), point id = i + m (j + m k)."""
    step = 2 if quadratic else 1
    m = step * n + 1
    tets = []
    for vertices in kuhn_vertices(np.indices((n, n, n)).reshape(3, -1).T, step):
        if quadratic:
            vertices += [(vertices[a] + vertices[b]) // 2 for a, b in QUADRATIC_TETRA_EDGES]
        tets.append(np.stack([v[:, 0] + m * (v[:, 1] + m * v[:, 2]) for v in vertices], axis=1))
    connectivity = np.stack(tets, axis=1).reshape(-1, 10 if quadratic else 4)
    unit = np.linspace(0.0, 1.0, m)
    grid = np.stack(np.meshgrid(unit, unit, unit, indexing="ij"), axis=-1)
    points = grid.transpose(2, 1, 0, 3).reshape(-1, 3)  # x fastest, as the ids above
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    return lo + points * (hi - lo), connectivity


class PixelRays:
    """One ray per pixel centre: pixel (i, j), id i + j * width, j = 0 the bottom row, NDC
    x = 2 (i + 0.5) / width - 1, y = 2 (j + 0.5) / height - 1, from the camera position
    (perspective; vtkCamera's vertical view angle). Directions are unit, in float64 and, for the
    truth, long double."""

    def __init__(self, position, focal_point, view_up, view_angle_degrees, width, height):
        self.width, self.height = width, height
        self.origin = np.asarray(position, dtype=np.longdouble)
        forward = np.asarray(focal_point, dtype=np.longdouble) - self.origin
        forward /= np.sqrt(forward @ forward)
        right = np.cross(forward, np.asarray(view_up, dtype=np.longdouble))
        right /= np.sqrt(right @ right)
        up = np.cross(right, forward)
        self.half_height = np.tan(np.radians(np.longdouble(view_angle_degrees)) / 2)
        self.half_width = self.half_height * width / height
        j, i = np.mgrid[0:height, 0:width]
        x = ((2 * (i.ravel() + np.longdouble(0.5)) / width - 1) * self.half_width)[:, None]
        y = ((2 * (j.ravel() + np.longdouble(0.5)) / height - 1) * self.half_height)[:, None]
        directions = forward + x * right + y * up
        self.directions_exact = directions / np.sqrt((directions * directions).sum(axis=1))[:, None]
        self.directions = self.directions_exact.astype(np.float64)
        self.frame = np.array([forward, right, up], dtype=np.float64)

    def pixel_coordinates(self, points):
        """Continuous pixel coordinates (pixel centres at integers) and depth along the view
        axis of points in front of the camera."""
        offset = points - self.origin.astype(np.float64)
        depth = offset @ self.frame[0]
        x = (offset @ self.frame[1]) / (depth * float(self.half_width))
        y = (offset @ self.frame[2]) / (depth * float(self.half_height))
        return (x + 1) * self.width / 2 - 0.5, (y + 1) * self.height / 2 - 0.5, depth

    def box_interval(self, lo, hi):
        """Entry and exit parameters of each ray in the box [lo, hi] (entry > exit: a miss)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            near = (np.asarray(lo, np.longdouble) - self.origin) / self.directions_exact
            far = (np.asarray(hi, np.longdouble) - self.origin) / self.directions_exact
        entry = np.maximum(np.minimum(near, far).max(axis=1), 0)
        return entry, np.maximum(near, far).min(axis=1)


class Quadric:
    """f(x) = (x - centre)^T A (x - centre): a quadratic polynomial, so quadratic tets with
    straight edges whose nodes sample it represent it exactly."""

    def __init__(self, matrix, centre):
        self.matrix = np.asarray(matrix, dtype=np.longdouble)
        self.centre = np.asarray(centre, dtype=np.longdouble)

    def values(self, points):
        offset = points - self.centre.astype(np.float64)
        return np.einsum("pi,ij,pj->p", offset, self.matrix.astype(np.float64), offset)

    def first_hit(self, rays, iso, lo, hi, ambiguity):
        """Per ray: the first t where f = iso inside the box (inf: none), the unit gradient there,
        and whether the pixel is too ill-conditioned to compare: the ray within `ambiguity`
        (relative discriminant) of tangency, or a root within `ambiguity` of the box's diagonal
        from where the ray enters or leaves the box."""
        d = rays.directions_exact
        o = rays.origin - self.centre
        # f(o + t d) - iso = a t^2 + b t + c, in long double.
        a = np.einsum("pi,ij,pj->p", d, self.matrix, d)
        b = 2 * (d @ (self.matrix @ o))
        c = o @ self.matrix @ o - iso  # one origin: the same for all rays
        entry, exit_ = rays.box_interval(lo, hi)
        discriminant = b * b - 4 * a * c
        real = discriminant >= 0
        root = np.sqrt(np.where(real, discriminant, 0))
        # Stable quadratic formula: q = -(b + sign(b) sqrt(disc)) / 2, roots q / a and c / q.
        q = -0.5 * (b + np.copysign(root, b))
        with np.errstate(divide="ignore", invalid="ignore"):
            roots = np.stack([np.where(a != 0, q / a, -c / b), np.where(q != 0, c / q, np.nan)], axis=1)
            roots[~real] = np.nan
            # One Newton step polishes each root.
            slope = 2 * a[:, None] * roots + b[:, None]
            roots = np.where(slope != 0, roots - ((a[:, None] * roots + b[:, None]) * roots + c) / slope, roots)
        roots.sort(axis=1)  # NaN last
        inside = (roots >= entry[:, None]) & (roots <= exit_[:, None])
        first = np.where(inside[:, 0], roots[:, 0], np.where(inside[:, 1], roots[:, 1], np.inf))

        diagonal = float(np.linalg.norm(np.subtract(hi, lo)))
        crosses = exit_ >= entry
        scale = b * b + np.abs(4 * a * c)
        with np.errstate(divide="ignore", invalid="ignore"):
            tangent = (np.abs(discriminant) <= ambiguity * scale) & (a != 0)
            apex = -b / (2 * a)
        tangent &= (apex >= entry - ambiguity * diagonal) & (apex <= exit_ + ambiguity * diagonal)
        near_boundary = ((np.abs(roots - entry[:, None]) <= ambiguity * diagonal) |
                         (np.abs(roots - exit_[:, None]) <= ambiguity * diagonal)).any(axis=1)
        ambiguous = crosses & (tangent | near_boundary)

        hit = np.isfinite(first)
        points = (rays.origin + first[hit, None] * d[hit]) - self.centre
        gradient = np.zeros((len(first), 3))
        gradient[hit] = (2 * points @ self.matrix).astype(np.float64)
        gradient[hit] /= np.linalg.norm(gradient[hit], axis=1)[:, None]
        return first.astype(np.float64), gradient, ambiguous


def cast_triangles(points, triangles, point_normals, rays, pairs_per_batch=4_000_000):
    """First hit of every pixel ray on a triangle surface: depth t (inf: miss) and the shading
    normal there (the point normals interpolated with the hit's barycentric coordinates when the
    surface has them, as the renderer shades it; else the face normal). Candidate pixels of a
    triangle are those whose centres fall in its projected bounding box; each candidate is then
    tested exactly on its own ray (Moller-Trumbore, in float64)."""
    count = rays.width * rays.height
    depth = np.full(count, np.inf)
    normal = np.zeros((count, 3))
    if len(triangles) == 0:
        return depth, normal
    x, y, view_depth = rays.pixel_coordinates(points)
    if (view_depth[triangles] <= 0).any():
        raise ValueError("a triangle reaches behind the camera: place the camera outside the mesh")
    xs, ys = x[triangles], y[triangles]
    i0 = np.clip(np.ceil(xs.min(axis=1)), 0, rays.width).astype(np.int64)
    i1 = np.clip(np.floor(xs.max(axis=1)), -1, rays.width - 1).astype(np.int64)
    j0 = np.clip(np.ceil(ys.min(axis=1)), 0, rays.height).astype(np.int64)
    j1 = np.clip(np.floor(ys.max(axis=1)), -1, rays.height - 1).astype(np.int64)
    columns = np.maximum(i1 - i0 + 1, 0)
    candidates = columns * np.maximum(j1 - j0 + 1, 0)
    origin = rays.origin.astype(np.float64)
    best_triangle = np.full(count, -1)
    best_uv = np.zeros((count, 2))
    cumulative = np.cumsum(candidates)
    start = 0
    while start < len(triangles):
        # A batch of whole triangles with at most pairs_per_batch candidates (at least one triangle).
        limit = (cumulative[start - 1] if start else 0) + pairs_per_batch
        stop = max(start + 1, int(np.searchsorted(cumulative, limit, side="right")))
        batch = np.arange(start, stop)
        per = candidates[batch]
        tri = np.repeat(batch, per)
        local = np.arange(per.sum()) - np.repeat(np.cumsum(per) - per, per)
        pixel = (i0[tri] + local % columns[tri]) + (j0[tri] + local // columns[tri]) * rays.width
        start = stop
        if len(tri) == 0:
            continue
        v0 = points[triangles[tri, 0]]
        edge1 = points[triangles[tri, 1]] - v0
        edge2 = points[triangles[tri, 2]] - v0
        d = rays.directions[pixel]
        p = np.cross(d, edge2)
        determinant = (edge1 * p).sum(axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inverse = 1.0 / determinant
            s = origin - v0
            u = (s * p).sum(axis=1) * inverse
            qv = np.cross(s, edge1)
            v = (d * qv).sum(axis=1) * inverse
            t = (edge2 * qv).sum(axis=1) * inverse
        # Inclusive edges (with 1e-12 of slack in barycentric units) so that rays through an edge
        # shared by two triangles cannot fall between them.
        slack = 1e-12
        hit = (determinant != 0) & (u >= -slack) & (v >= -slack) & (u + v <= 1 + slack) & (t > 0)
        pixel, t, tri, u, v = pixel[hit], t[hit], tri[hit], u[hit], v[hit]
        np.minimum.at(depth, pixel, t)
        nearest = t == depth[pixel]
        best_triangle[pixel[nearest]] = tri[nearest]
        best_uv[pixel[nearest]] = np.stack([u[nearest], v[nearest]], axis=1)
    hit = best_triangle >= 0
    corners = triangles[best_triangle[hit]]
    if point_normals is None:
        a, b, c = points[corners[:, 0]], points[corners[:, 1]], points[corners[:, 2]]
        shading = np.cross(b - a, c - a)
    else:
        u, v = best_uv[hit, 0:1], best_uv[hit, 1:2]
        shading = ((1 - u - v) * point_normals[corners[:, 0]] + u * point_normals[corners[:, 1]] +
                   v * point_normals[corners[:, 2]])
    normal[hit] = shading / np.linalg.norm(shading, axis=1)[:, None]
    return depth, normal


def kuhn_tets_crossed(rays, lo, hi, n):
    """Per ray, the number of tets of kuhn_lattice(n, ...) over [lo, hi] that it crosses (0 when it
    misses the box): one more than the planes x_a = integer and x_a - x_b = integer (lattice
    units) crossed between entry and exit, counted by the change of their floor."""
    entry, exit_ = rays.box_interval(lo, hi)
    crosses = exit_ > entry
    length = np.where(crosses, exit_ - entry, 0)
    scale = n / (np.asarray(hi, np.longdouble) - np.asarray(lo, np.longdouble))

    def lattice_point(t):
        return (rays.origin + t[:, None] * rays.directions_exact - np.asarray(lo, np.longdouble)) * scale

    # Points just inside the box, so its own faces are not counted.
    first = lattice_point(entry + 1e-9 * length)
    last = lattice_point(exit_ - 1e-9 * length)
    planes = np.abs(np.floor(last) - np.floor(first)).sum(axis=1)
    for a, b in itertools.combinations(range(3), 2):
        planes += np.abs(np.floor(last[:, a] - last[:, b]) - np.floor(first[:, a] - first[:, b]))
    return np.where(crosses, planes + 1, 0).astype(np.int64)
