"""vtkDirectSurfaceContour (the exact surface as data) against analytic truth (run with
/usr/bin/python3), on every cell kind TetDSR reads, straight and curved, beside vtkContourFilter.

Truth comes from exactness: a polynomial field of degree <= p is held exactly by straight order-p
cells (a sphere |x - c|^2 in quadratic cells, a torus in order-4 cells, each kind's own space from
test_hex_wedge.SPACES), and a linear field (a plane) by curved cells of any kind (hex_wedge_grids.bulge,
which keeps the unit cube's faces flat). Grids are built on VTK's own node positions
(higher_order_grids, hex_wedge_grids, vtkCellTypeSource). None of TetDSR's code is used for truth.

Each case asserts:
- pieces: the connected pieces of each iso-value's triangles, against the analytic count (closed
  forms, or a fine marching-cubes sampling of the analytic field on a 97^3 image);
- distance: triangles sampled densely (sample_triangles) -> the analytic surface, and points of the
  analytic surface inside the mesh (roots of the field along lines through it) -> the triangles
  (vtkStaticCellLocator), both <= the DistanceBound the filter states;
- watertight: no edge used by more than two triangles, every edge used once lies in a face of the
  mesh's boundary, and the filter's BoundaryEdges / NonManifoldEdges agree with the count here;
- vertices on the analytic surface (1e-9 of the diagonal), normals along the analytic gradient;
- Area within AreaError (+1e-9 relative) of the analytic area, Volume (where field >= iso) within
  VolumeError of the analytic volume, where they are known (spheres, cut spheres, torus, plane
  through the cube); FlatArea equal to the triangles' own area;
- a second polynomial point array of the cell's space interpolated exactly at the vertices, and
  its integral over full spheres against the closed form;
- vtkContourFilter on the same grids: the pieces it loses (a sphere inside one cell, the smallest of
  nested spheres) and its distance to the truth, asserted where it is the point."""
import os
import sys
import time
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import (
    VTK_BEZIER_TETRAHEDRON, VTK_LAGRANGE_HEXAHEDRON, VTK_LAGRANGE_TETRAHEDRON, VTK_PYRAMID,
    VTK_QUADRATIC_HEXAHEDRON, VTK_QUADRATIC_PYRAMID, VTK_QUADRATIC_TETRA, VTK_TETRA, VTK_TRIQUADRATIC_PYRAMID,
    vtkDataObject, vtkImageData)
from vtkmodules.vtkFiltersCore import vtkContourFilter, vtkFlyingEdges3D

import hex_wedge_grids as hw
import higher_order_grids as hog
import surface_measures as sm
from shared_helpers import Messages
from tetdsr import vtkDirectSurfaceContour
from test_hex_wedge import MIXED, PLANE, SPACE_OF, SPACES, linear_colour, type_source_mesh
from test_higher_order import max_angle

SAMPLE_LEVEL = 6      # sample_triangles' steps per triangle edge (28 points a triangle)
ON_SURFACE = 1e-9     # vertices' distance to the analytic surface, of the diagonal
INTERPOLATION = 1e-9  # point arrays at the vertices, of the array's magnitude there
ROUNDING = 1e-12      # slack on a stated bound, of the diagonal: the measurement's own rounding
# The kinds' sweeps ask a coarser tolerance than the default (1e-3, which the hard cases use): every
# check is against the bound stated, and the sweep stays within the test's time.
SWEEP_TOLERANCE = 1e-2


# --- Where the mesh is -------------------------------------------------------------------------

class Domain:
    """A convex polyhedron {x : normals x <= offsets}, the union of a mesh's cells (straight or
    bent by hex_wedge_grids.bulge, which keeps the unit cube's faces)."""

    def __init__(self, normals, offsets):
        self.normals = np.asarray(normals, float)
        self.offsets = np.asarray(offsets, float)
        corners = self.corners()
        self.lo, self.hi = corners.min(axis=0), corners.max(axis=0)
        self.diagonal = float(np.linalg.norm(self.hi - self.lo))

    def corners(self):
        """The vertices: every three face planes' meeting point that is inside."""
        found = []
        k = len(self.normals)
        for a in range(k):
            for b in range(a + 1, k):
                for c in range(b + 1, k):
                    m = self.normals[[a, b, c]]
                    if abs(np.linalg.det(m)) < 1e-12:
                        continue
                    x = np.linalg.solve(m, self.offsets[[a, b, c]])
                    if np.all(self.normals @ x <= self.offsets + 1e-12):
                        found.append(x)
        return np.array(found)

    def inside(self, x, slack=0.0):
        return np.all(x @ self.normals.T <= self.offsets + slack, axis=-1)

    def on_one_face(self, a, b, tolerance):
        """Per pair of points (rows of a and b): both lie in one face plane."""
        gap = np.maximum(np.abs(a @ self.normals.T - self.offsets), np.abs(b @ self.normals.T - self.offsets))
        return np.any(gap <= tolerance, axis=1)


UNIT_CUBE = Domain(np.r_[np.eye(3), -np.eye(3)], np.r_[np.ones(3), np.zeros(3)])


def tetrahedron_domain(corners):
    normals, offsets = [], []
    for skip in range(4):
        face = [corners[k] for k in range(4) if k != skip]
        n = np.cross(face[1] - face[0], face[2] - face[0])
        if n @ (corners[skip] - face[0]) > 0:
            n = -n
        n /= np.linalg.norm(n)
        normals.append(n)
        offsets.append(n @ face[0])
    return Domain(normals, offsets)


# --- Analytic truth ----------------------------------------------------------------------------

class Truth:
    """An analytic field (value, gradient) and iso-values, with per iso-value what is known of its
    surface inside the domain: pieces, area, volume where the field >= iso, and the integral of the
    second array (None where not known in closed form; pieces are then sampled). `distance`
    (points, iso) is the closed-form distance to the surface, else Newton projection onto it."""

    def __init__(self, name, field, isos, domain, distance=None, pieces=None, areas=None, volumes=None,
                 integrals=None):
        self.name, self.field, self.isos, self.domain = name, field, list(isos), domain
        self.closed_distance = distance
        count = len(self.isos)
        self.pieces = pieces or [None] * count
        self.areas = areas or [None] * count
        self.volumes = volumes or [None] * count
        self.integrals = integrals or [None] * count
        self.pieces = [p if p is not None else sampled_pieces(field, iso, domain)
                       for p, iso in zip(self.pieces, self.isos)]

    def distance(self, points, iso):
        if self.closed_distance is not None:
            return self.closed_distance(points, iso)
        # Newton's projection x <- x - (f - iso) g / |g|^2 lands on the surface: the distance to
        # that point bounds the distance to the surface from above.
        x = np.array(points, float)
        for _ in range(40):
            g = self.field.gradient(x)
            step = ((self.field.value(x) - iso) / np.einsum("ij,ij->i", g, g))[:, None] * g
            x -= step
            if np.abs(step).max(initial=0.0) < 1e-17:
                break
        return np.linalg.norm(x - points, axis=1)

    def surface_points(self, iso, lines=32, samples=480):
        """Points of the analytic surface inside the domain: every sign change of the field along
        lines x, y and z through a lines x lines grid over the domain's box, bisected to rounding."""
        lo, hi = self.domain.lo, self.domain.hi
        found = []
        for axis in range(3):
            u, v = [a for a in range(3) if a != axis]
            cu = lo[u] + (np.arange(lines) + 0.5) / lines * (hi[u] - lo[u])
            cv = lo[v] + (np.arange(lines) + 0.5) / lines * (hi[v] - lo[v])
            U, V = (m.ravel() for m in np.meshgrid(cu, cv, indexing="ij"))
            t = np.linspace(lo[axis], hi[axis], samples)

            def at(line, s):
                x = np.empty(np.broadcast(line, s).shape + (3,))
                x[..., u], x[..., v], x[..., axis] = U[line], V[line], s
                return x

            f = self.field.value(at(np.arange(len(U))[:, None], t[None, :])) - iso
            line, k = np.nonzero(np.signbit(f[:, :-1]) != np.signbit(f[:, 1:]))
            a, b, fa = t[k], t[k + 1], f[line, k]
            for _ in range(60):
                m = 0.5 * (a + b)
                fm = self.field.value(at(line, m)) - iso
                left = np.signbit(fm) != np.signbit(fa)
                b, a, fa = np.where(left, m, b), np.where(left, a, m), np.where(left, fa, fm)
            found.append(at(line, 0.5 * (a + b)))
        x = np.concatenate(found)
        return x[self.domain.inside(x)]


def sampled_pieces(field, iso, domain, n=97):
    """Connected pieces of the analytic surface in the domain's box, from marching cubes on the
    field sampled at n^3 points (for fields whose pieces have no closed form)."""
    image = vtkImageData()
    image.SetDimensions(n, n, n)
    spacing = (domain.hi - domain.lo) / (n - 1)
    image.SetOrigin(*domain.lo)
    image.SetSpacing(*spacing)
    g = [domain.lo[a] + spacing[a] * np.arange(n) for a in range(3)]
    x = np.stack(np.meshgrid(*g, indexing="ij"), axis=-1).transpose(2, 1, 0, 3).reshape(-1, 3)  # x fastest
    values = numpy_to_vtk(np.ascontiguousarray(field.value(x)), deep=1)
    values.SetName("f")
    image.GetPointData().SetScalars(values)
    marching = vtkFlyingEdges3D()
    marching.SetInputData(image)
    marching.SetValue(0, iso)
    marching.Update()
    return sm.components(marching.GetOutput())


def sphere(centre, radii, domain, second=None):
    """|x - c|^2 at the iso-values r^2 in the unit cube (or a domain holding every sphere whole):
    area 4 pi r^2 less the caps the cube's faces cut (no two caps may meet: asserted), volume
    outside the ball; `second` (value, integral(c, r)) gives the integral over whole spheres."""
    c = np.asarray(centre, float)
    field = hog.sphere(c, 1.0)
    areas, volumes, integrals = [], [], []
    whole_volume = domain_volume(domain)
    for r in radii:
        if domain is UNIT_CUBE:
            depths = np.r_[c, 1.0 - c]          # distance from c to each face
            heights = np.clip(r - depths, 0.0, None)  # the caps' heights
            # Caps stay apart when the sphere misses every edge of the cube.
            for a in range(3):
                for b in range(a + 1, 3):
                    for da in (c[a], 1 - c[a]):
                        for db in (c[b], 1 - c[b]):
                            assert da * da + db * db > r * r, "caps meet: no closed form here"
        else:
            heights = np.zeros(1)
            assert domain.inside(np.array([c]), -r).all(), "the sphere must lie inside the domain"
        areas.append(4 * np.pi * r * r - float(np.sum(2 * np.pi * r * heights)))
        ball = 4 / 3 * np.pi * r ** 3 - float(np.sum(np.pi * heights ** 2 * (3 * r - heights) / 3))
        volumes.append(whole_volume - ball)
        integrals.append(second(c, r) if second is not None and not heights.any() else None)
    return Truth(f"sphere c = {tuple(np.round(c, 3))}", field, [r * r for r in radii], domain,
                 distance=lambda x, iso: np.abs(np.linalg.norm(x - c, axis=1) - np.sqrt(iso)),
                 pieces=[1] * len(radii), areas=areas, volumes=volumes, integrals=integrals)


def domain_volume(domain):
    if domain is UNIT_CUBE:
        return 1.0
    a, b, c, d = domain.corners()
    return abs(np.linalg.det(np.array([b - a, c - a, d - a]))) / 6.0


def torus(centre=(0.5, 0.47, 0.52), R=0.28, r=0.11):
    """hog.torus (degree 4) in the unit cube: area 4 pi^2 R r, the field >= 0 outside its tube."""
    c = np.asarray(centre)

    def distance(x, iso):
        d = x - c
        return np.abs(np.hypot(np.hypot(d[:, 0], d[:, 1]) - R, d[:, 2]) - r)

    return Truth("torus", hog.torus(c, R, r), [0.0], UNIT_CUBE, distance=distance, pieces=[1],
                 areas=[4 * np.pi ** 2 * R * r], volumes=[1.0 - 2 * np.pi ** 2 * R * r * r])


def plane(field=PLANE):
    """a.x = iso (every a_i > 0) in the unit cube: the volume where a.x <= c is
    sum over the cube's corners v of (-1)^|v| max(c - a.v, 0)^3 / (6 a1 a2 a3), and the cut's area
    |a| times its derivative in c."""
    a = field.gradient(np.zeros((1, 3)))[0]
    assert np.all(a > 0)
    corners = np.array([(i, j, k) for i in (0, 1) for j in (0, 1) for k in (0, 1)], float)
    signs = (-1.0) ** corners.sum(axis=1)
    reach = np.clip(field.iso - corners @ a, 0.0, None)
    below = float(signs @ reach ** 3) / (6 * np.prod(a))
    area = np.linalg.norm(a) * float(signs @ reach ** 2) / (2 * np.prod(a))
    return Truth("plane", field, [field.iso], UNIT_CUBE,
                 distance=lambda x, iso: np.abs(x @ a - iso) / np.linalg.norm(a),
                 pieces=[1], areas=[area], volumes=[1.0 - below])


def polynomial(name, field, domain=UNIT_CUBE):
    """A field of a cell's space without closed forms: pieces sampled, distance by projection."""
    return Truth(name, field, [field.iso], domain)


# --- The filters -------------------------------------------------------------------------------

def exact_surface(grid, isos, relative=None, absolute=None, array="f"):
    contour = vtkDirectSurfaceContour()
    contour.SetInputData(grid)
    contour.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, array)
    contour.SetNumberOfContours(len(isos))
    for i, v in enumerate(isos):
        contour.SetValue(i, v)
    if relative is not None:
        contour.SetTolerance(relative)
    if absolute is not None:
        contour.SetAbsoluteTolerance(absolute)
    contour.SetComputeIntegrals(True)
    messages = Messages(contour)
    start = time.perf_counter()
    contour.Update()
    return contour, contour.GetOutput(), messages, time.perf_counter() - start


def linear_contour(grid, isos, array="f"):
    contour = vtkContourFilter()
    contour.SetInputData(grid)
    contour.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, array)
    for i, v in enumerate(isos):
        contour.SetValue(i, v)
    contour.ComputeScalarsOn()
    contour.Update()
    return sm.as_triangles(contour.GetOutput())


def field_data(out, name):
    array = out.GetFieldData().GetArray(name)
    assert array is not None, f"field data {name!r} missing; has " + ", ".join(
        out.GetFieldData().GetArrayName(k) for k in range(out.GetFieldData().GetNumberOfArrays()))
    return vtk_to_numpy(array).astype(np.float64).ravel()


def point_array(out, name):
    array = out.GetPointData().GetArray(name)
    assert array is not None, f"point array {name!r} missing"
    return vtk_to_numpy(array).astype(np.float64)


def grid_diagonal(grid):
    b = np.array(grid.GetBounds())
    return float(np.linalg.norm(b[1::2] - b[0::2]))


# --- The checks --------------------------------------------------------------------------------

def check(test, label, grid, truth, second=None, relative=None, absolute=None, quiet=False):
    """Runs vtkDirectSurfaceContour on `grid` (point array "f" the field; `second` = (name,
    function) a point array to check at the vertices) and asserts everything the module
    docstring lists. Returns the measures (dict) for comparisons."""
    contour, out, messages, seconds = exact_surface(grid, truth.isos, relative, absolute)
    test.assertEqual(messages.errors, [], f"{label}: errors")
    diagonal = grid_diagonal(grid)
    points, triangles = sm.triangles_of(out)
    test.assertGreater(len(triangles), 0, f"{label}: no triangles")

    # The stated bound: the tolerance asked (relative: of the valid cells' box, here the grid's;
    # the core's box is single precision, rounded outward: up to 2^-23 larger).
    bound = field_data(out, "DistanceBound")[0]
    asked = absolute if absolute is not None else (relative if relative is not None else 1e-3) * diagonal
    test.assertTrue(asked <= bound <= asked * (1 + 2.0 ** -22),
                    f"{label}: DistanceBound expected {asked} (up to 2^-22 more), got {bound}")
    largest = field_data(out, "LargestCertifiedBound")[0]
    test.assertLessEqual(largest, bound, f"{label}: LargestCertifiedBound {largest} above the bound {bound}")
    unresolved = int(field_data(out, "UnresolvedSubcells")[0])
    test.assertEqual(unresolved, 0, f"{label}: expected 0 unresolved subcells, got {unresolved} "
                                    f"(of {int(field_data(out, 'Subcells')[0])}); warnings {messages.warnings}")
    test.assertEqual(messages.warnings, [], f"{label}: warnings")
    np.testing.assert_array_equal(field_data(out, "IsoValues"), truth.isos, f"{label}: IsoValues")

    # Watertight: edges used by one triangle lie in the mesh's boundary, none by three or more.
    edges, uses = sm.edge_uses(triangles)
    once = edges[uses == 1]
    on_boundary = truth.domain.on_one_face(points[once[:, 0]], points[once[:, 1]], ON_SURFACE * diagonal)
    test.assertEqual(int(np.sum(uses > 2)), 0, f"{label}: edges used by more than two triangles")
    test.assertTrue(on_boundary.all(), f"{label}: {int((~on_boundary).sum())} of {len(once)} edges used once "
                                       f"are not in the mesh's boundary, e.g. {points[once[~on_boundary][:1]]}")
    test.assertEqual(int(field_data(out, "BoundaryEdges")[0]), len(once), f"{label}: BoundaryEdges")
    test.assertEqual(int(field_data(out, "NonManifoldEdges")[0]), 0, f"{label}: NonManifoldEdges")

    # Per triangle: its iso-value and its cell.
    iso_of = vtk_to_numpy(out.GetCellData().GetArray("IsoValue"))
    cells = vtk_to_numpy(out.GetCellData().GetArray("vtkOriginalCellIds"))
    test.assertTrue(np.all((cells >= 0) & (cells < grid.GetNumberOfCells())), f"{label}: vtkOriginalCellIds")
    test.assertTrue(np.all(np.isin(iso_of, truth.isos)), f"{label}: IsoValue not one of the iso-values")

    normals = point_array(out, "Normals")
    values = point_array(out, "f")
    areas, area_errors = field_data(out, "Area"), field_data(out, "AreaError")
    volumes, volume_errors = field_data(out, "Volume"), field_data(out, "VolumeError")
    flat_areas = field_data(out, "FlatArea")
    measures = {"triangles": len(triangles), "bound": bound, "seconds": seconds, "forward": 0.0, "backward": 0.0,
                "area_error": [], "pieces": []}
    for i, iso in enumerate(truth.isos):
        mine = triangles[iso_of == iso]
        used = np.unique(mine)
        pieces = sm.components(sm.polydata(points, mine))
        measures["pieces"].append(pieces)
        test.assertEqual(pieces, truth.pieces[i], f"{label}, iso {iso:g}: pieces expected {truth.pieces[i]}, got {pieces}")
        # Vertices: on the surface, normals along the gradient, the field's own value.
        on = truth.distance(points[used], iso).max(initial=0.0)
        test.assertLessEqual(on, ON_SURFACE * diagonal, f"{label}, iso {iso:g}: vertices off the surface by {on:.3e}")
        angle = max_angle(normals[used], truth.field.gradient(points[used]))
        test.assertLess(angle, 1e-8, f"{label}, iso {iso:g}: normals off the gradient by {angle:.3e} rad")
        scale = max(1.0, abs(iso))
        test.assertLess(np.abs(values[used] - iso).max(), INTERPOLATION * scale, f"{label}: field at vertices")
        # Distance, both ways.
        forward = truth.distance(sm.sample_triangles(points, mine, SAMPLE_LEVEL), iso).max(initial=0.0)
        reference = truth.surface_points(iso)
        test.assertGreater(len(reference), 100, f"{label}: too few truth samples")
        backward = sm.NearestTriangle(sm.polydata(points, mine)).distances(reference).max(initial=0.0)
        measures["forward"], measures["backward"] = max(measures["forward"], forward), max(measures["backward"], backward)
        test.assertLessEqual(forward, bound + ROUNDING * diagonal,
                             f"{label}, iso {iso:g}: triangles -> surface {forward:.3e} above the bound {bound:.3e}")
        test.assertLessEqual(backward, bound + ROUNDING * diagonal,
                             f"{label}, iso {iso:g}: surface -> triangles {backward:.3e} above the bound {bound:.3e}")
        # Integrals.
        flat = sm.flat_area(points, mine)
        test.assertAlmostEqual(flat_areas[i] / flat, 1.0, delta=1e-9, msg=f"{label}: FlatArea expected {flat}, got {flat_areas[i]}")
        if truth.areas[i] is not None:
            error = abs(areas[i] - truth.areas[i])
            measures["area_error"].append((error, area_errors[i], abs(flat - truth.areas[i])))
            test.assertLessEqual(error, area_errors[i] + 1e-9 * truth.areas[i],
                                 f"{label}, iso {iso:g}: Area expected {truth.areas[i]:.12g}, got {areas[i]:.12g} "
                                 f"(error {error:.3e}, AreaError {area_errors[i]:.3e})")
        if truth.volumes[i] is not None:
            error = abs(volumes[i] - truth.volumes[i])
            test.assertLessEqual(error, volume_errors[i] + 1e-9 * domain_volume(truth.domain),
                                 f"{label}, iso {iso:g}: Volume expected {truth.volumes[i]:.12g}, got {volumes[i]:.12g} "
                                 f"(error {error:.3e}, VolumeError {volume_errors[i]:.3e})")
        if second is not None and truth.integrals[i] is not None:
            integral = field_data(out, f"{second[0]} Integral")[i]
            integral_error = field_data(out, f"{second[0]} IntegralError")[i]
            test.assertLessEqual(abs(integral - truth.integrals[i]), integral_error + 1e-9 * abs(truth.integrals[i]),
                                 f"{label}, iso {iso:g}: {second[0]} Integral expected {truth.integrals[i]:.12g}, "
                                 f"got {integral:.12g} (IntegralError {integral_error:.3e})")
    # Every vertex of a triangle; a second array of the cell's space exact there.
    if second is not None:
        name, function = second
        got = point_array(out, name)
        expected = function(points)
        scale = max(1.0, float(np.abs(expected).max()))
        worst = float(np.abs(got - expected).max())
        test.assertLess(worst, INTERPOLATION * scale, f"{label}: {name} at the vertices off by {worst:.3e}")
    if not quiet:
        area_text = ", ".join(f"area error {e:.1e} (AreaError {s:.1e}, flat {f:.1e})" for e, s, f in measures["area_error"])
        print(f"{label}: {len(triangles)} triangles in {seconds:.2f} s; bound {bound:.2e}, measured "
              f"{measures['forward']:.2e} / {measures['backward']:.2e}; pieces {measures['pieces']}; {area_text}",
              flush=True)
    return measures


def contour_measures(grid, truth):
    """vtkContourFilter's triangles per iso-value: pieces, area error, distance both ways."""
    surface = linear_contour(grid, truth.isos)
    points, triangles = sm.triangles_of(surface)
    scalars = vtk_to_numpy(surface.GetPointData().GetArray("f")) if len(triangles) else np.zeros(0)
    result = []
    for i, iso in enumerate(truth.isos):
        mine = triangles[np.all(np.abs(scalars[triangles] - iso) <= 1e-9 * max(1.0, abs(iso)), axis=1)] \
            if len(triangles) else triangles
        reference = truth.surface_points(iso)
        backward = sm.NearestTriangle(sm.polydata(points, mine)).distances(reference).max(initial=0.0)
        forward = truth.distance(sm.sample_triangles(points, mine, SAMPLE_LEVEL), iso).max(initial=0.0) \
            if len(mine) else 0.0
        area = sm.flat_area(points, mine)
        result.append({"pieces": sm.components(sm.polydata(points, mine)), "forward": forward, "backward": backward,
                       "area_error": abs(area - truth.areas[i]) if truth.areas[i] is not None else None,
                       "triangles": len(mine)})
    return result


def print_contour(label, measures):
    for m in measures:
        area = f", area error {m['area_error']:.1e}" if m["area_error"] is not None else ""
        print(f"  vtkContourFilter on {label}: {m['triangles']} triangles, pieces {m['pieces']}, measured "
              f"{m['forward']:.2e} / {m['backward']:.2e}{area}", flush=True)


# --- Grids -------------------------------------------------------------------------------------

def with_fields(grid, fields, warp=None):
    """The grid's points moved by `warp` (if given), then point arrays {name: f(points)} (the first
    active). Right for Bezier cells only for linear fields (their control values are then the
    field at the control points)."""
    x = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    if warp is not None:
        x = warp(x)
        grid.GetPoints().SetData(numpy_to_vtk(np.ascontiguousarray(x), deep=1))
    for k, (name, function) in enumerate(fields.items()):
        array = numpy_to_vtk(np.ascontiguousarray(function(x), dtype=np.float64), deep=1)
        array.SetName(name)
        grid.GetPointData().AddArray(array)
        if k == 0:
            grid.GetPointData().SetActiveScalars(name)
    return grid


def quadratic_second(x):
    return x[:, 0] * x[:, 1] - x[:, 2] ** 2 + x[:, 0]


def sphere_integral_of_quadratic_second(c, r):
    """The integral of quadratic_second over the sphere |x - c| = r: by symmetry the mean of
    x y is c_x c_y, of z^2 is c_z^2 + r^2 / 3, of x is c_x."""
    return 4 * np.pi * r * r * (c[0] * c[1] - c[2] ** 2 - r * r / 3 + c[0])


def cubic_second(x):
    return x[:, 0] * x[:, 1] * x[:, 2] + x[:, 1] ** 3 - x[:, 0]


def quartic_second(x):
    return x[:, 0] ** 2 * x[:, 1] * x[:, 2] - x[:, 2] ** 3 * x[:, 0] + x[:, 1]


# Straight tetrahedra of order p hold every polynomial of degree <= p: a field and a second array
# of that degree per order.
TET_ORDERS = {1: (lambda: plane(), linear_colour),
              2: (lambda: sphere((0.48, 0.52, 0.5), [0.3], UNIT_CUBE), quadratic_second),
              3: (lambda: polynomial("cubic blob", hog.cubic_blob()), cubic_second),
              4: (lambda: torus(), quartic_second)}
TET_KINDS = [("VTK_TETRA", VTK_TETRA, 1), ("VTK_QUADRATIC_TETRA", VTK_QUADRATIC_TETRA, 2)] + [
    (f"VTK_{kind}_TETRAHEDRON order {p}", vtk_type, p)
    for kind, vtk_type in (("LAGRANGE", VTK_LAGRANGE_TETRAHEDRON), ("BEZIER", VTK_BEZIER_TETRAHEDRON))
    for p in (2, 3, 4)]
PYRAMIDS = [("VTK_PYRAMID", VTK_PYRAMID), ("VTK_QUADRATIC_PYRAMID", VTK_QUADRATIC_PYRAMID),
            ("VTK_TRIQUADRATIC_PYRAMID", VTK_TRIQUADRATIC_PYRAMID)]


# --- The cases ---------------------------------------------------------------------------------

class HardCases(unittest.TestCase):
    """The cases the issue names: a sphere inside one quadratic cell, a torus in order-4 cells, nested
    spheres, and a tighter tolerance."""

    def test_sphere_inside_one_quadratic_cell(self):
        # One Kuhn tetrahedron of the unit cube (VTK_QUADRATIC_TETRA) and one 20-node hexahedron:
        # a sphere about the tetrahedron's incentre (the cube's centre), smaller than the cell, so
        # every nodal value lies above the iso-value.
        tet = hog.grid(1, VTK_QUADRATIC_TETRA, 2, {}, cells=[0])
        corners = vtk_to_numpy(tet.GetPoints().GetData())[[tet.GetCell(0).GetPointId(k) for k in range(4)]]
        domain = tetrahedron_domain(corners)
        faces = [np.linalg.norm(np.cross(*(corners[[k for k in range(4) if k != s][1:]] -
                                           corners[[k for k in range(4) if k != s][0]]))) / 2 for s in range(4)]
        centre = np.einsum("k,kd->d", faces, corners) / np.sum(faces)
        inradius = 3 * domain_volume(domain) / np.sum(faces)
        cases = [("one VTK_QUADRATIC_TETRA", tet, sphere(centre, [0.7 * inradius], domain, sphere_integral_of_quadratic_second)),
                 ("one VTK_QUADRATIC_HEXAHEDRON", hw.grid(1, VTK_QUADRATIC_HEXAHEDRON, 20, {}),
                  sphere((0.47, 0.52, 0.5), [0.3], UNIT_CUBE, sphere_integral_of_quadratic_second))]
        for label, grid, truth in cases:
            with self.subTest(label):
                with_fields(grid, {"f": truth.field.value, "g": quadratic_second})
                nodal = vtk_to_numpy(grid.GetPointData().GetArray("f"))
                self.assertTrue(np.all(nodal > truth.isos[0]), "every node outside the sphere")
                check(self, f"sphere inside {label}", grid, truth, ("g", quadratic_second))
                linear = contour_measures(grid, truth)
                print_contour(label, linear)
                self.assertEqual(linear[0]["pieces"], 0, "vtkContourFilter finds no sign change, no triangle")

    def test_torus_in_order_four_cells(self):
        # At 3e-2 of the diagonal in the suite (order-4 tetrahedra took 74 s and 55,010 triangles
        # on 2 cores, hexahedra 21 s); the Bezier tetrahedra and the default 1e-3 with
        # TETDSR_SLOW_TESTS=1 (the certified bound is conservative: many more triangles).
        truth = torus()
        slow = bool(os.environ.get("TETDSR_SLOW_TESTS"))
        fields = {"f": truth.field.value, "g": quartic_second}
        cases = [("VTK_LAGRANGE_TETRAHEDRON order 4", lambda: hog.grid(2, VTK_LAGRANGE_TETRAHEDRON, 4, fields)),
                 ("VTK_LAGRANGE_HEXAHEDRON order 4", lambda: hw.grid(2, VTK_LAGRANGE_HEXAHEDRON, 125, fields))]
        if slow:
            cases.insert(1, ("VTK_BEZIER_TETRAHEDRON order 4", lambda: hog.grid(2, VTK_BEZIER_TETRAHEDRON, 4, fields)))
        for label, make in cases:
            with self.subTest(label):
                grid = make()
                mine = check(self, f"torus, {label}", grid, truth, ("g", quartic_second),
                             relative=None if slow else 3e-2)
                linear = contour_measures(grid, truth)
                print_contour(label, linear)
                # The linear contour of the nodal values is farther from the torus than the exact
                # surface measures (and, at the default tolerance, than the bound it keeps).
                self.assertGreater(max(linear[0]["forward"], linear[0]["backward"]),
                                   max(mine["forward"], mine["backward"]))
                if slow:
                    self.assertGreater(max(linear[0]["forward"], linear[0]["backward"]), mine["bound"])

    @unittest.skipUnless(os.environ.get("TETDSR_SLOW_TESTS"),
                         "the torus at three tolerances took over 6 minutes (with the previous test) on 2 cores: "
                         "run with TETDSR_SLOW_TESTS=1")
    def test_tighter_tolerances(self):
        # The torus at a coarse tolerance, a third of it, and an absolute one (the certified bound
        # is conservative: a tenth of the default would take minutes here).
        truth = torus()
        grid = hog.grid(2, VTK_LAGRANGE_TETRAHEDRON, 4, {"f": truth.field.value, "g": quartic_second})
        coarse = check(self, "torus, order-4 tetrahedra, tolerance 1e-2", grid, truth, ("g", quartic_second),
                       relative=1e-2, quiet=True)
        fine = check(self, "torus, order-4 tetrahedra, tolerance 3e-3", grid, truth, ("g", quartic_second), relative=3e-3)
        check(self, "torus, order-4 tetrahedra, absolute tolerance 1e-2", grid, truth, ("g", quartic_second), absolute=1e-2)
        self.assertGreater(fine["triangles"], coarse["triangles"], "a tighter tolerance takes more triangles")
        self.assertLess(fine["area_error"][0][0], coarse["area_error"][0][1], "and the area converges")

    def test_nested_spheres(self):
        # Four concentric spheres of one field in 162 straight quadratic tetrahedra (node spacing
        # 1/6); the smallest (r = 0.1) holds no node, the largest is cut by three faces of the cube.
        radii = [0.1, 0.2, 0.3, 0.5]
        truth = sphere((0.42, 0.41, 0.59), radii, UNIT_CUBE, sphere_integral_of_quadratic_second)
        grid = hog.grid(3, VTK_QUADRATIC_TETRA, 2, {"f": truth.field.value, "g": quadratic_second})
        self.assertTrue(np.all(vtk_to_numpy(grid.GetPointData().GetArray("f")) > radii[0] ** 2))
        mine = check(self, "nested spheres, VTK_QUADRATIC_TETRA", grid, truth, ("g", quadratic_second))
        self.assertEqual(mine["pieces"], [1, 1, 1, 1])
        linear = contour_measures(grid, truth)
        print_contour("nested spheres", linear)
        self.assertEqual(linear[0]["pieces"], 0, "vtkContourFilter loses the smallest sphere")
        self.assertEqual([m["pieces"] for m in linear[1:]], [1, 1, 1])


class StraightCells(unittest.TestCase):
    """Every kind, straight, with a field its space holds exactly."""

    def test_tetrahedra(self):
        for label, vtk_type, order in TET_KINDS:
            with self.subTest(label):
                truth, second = TET_ORDERS[order][0](), TET_ORDERS[order][1]
                grid = hog.grid(2, vtk_type, order, {"f": truth.field.value, "g": second})
                check(self, f"straight {label}, {truth.name}", grid, truth, ("g", second), relative=SWEEP_TOLERANCE)

    def test_hexahedra_and_wedges(self):
        for label, vtk_type, nodes in hw.KINDS:
            with self.subTest(label):
                space = SPACE_OF[(vtk_type, nodes)][0]
                field, second = SPACES[space]
                grid = hw.grid(2, vtk_type, nodes, {"f": field.value, "g": second})
                check(self, f"straight {label}, {space}", grid, polynomial(space, field), ("g", second), relative=SWEEP_TOLERANCE)

    def test_pyramids(self):
        for label, vtk_type in PYRAMIDS:
            with self.subTest(label):
                check(self, f"straight {label}, plane", type_source_mesh(vtk_type, 1, None, PLANE), plane(),
                      relative=SWEEP_TOLERANCE)


class CurvedCells(unittest.TestCase):
    """Every kind of order 2 and more, bent (hex_wedge_grids.bulge: the unit cube's faces stay), with
    a plane: a linear field is exact in any isoparametric cell."""

    def test_tetrahedra(self):
        truth = plane()
        for label, vtk_type, order in TET_KINDS[1:]:
            with self.subTest(label):
                grid = with_fields(hog.grid(2, vtk_type, order, {}), {"f": truth.field.value, "g": linear_colour},
                                   hw.bulge())
                check(self, f"curved {label}, plane", grid, truth, ("g", linear_colour), relative=SWEEP_TOLERANCE)

    def test_hexahedra_and_wedges(self):
        truth = plane()
        for label, vtk_type, nodes in hw.KINDS:
            with self.subTest(label):
                grid = hw.grid(2, vtk_type, nodes, {"f": truth.field.value, "g": linear_colour}, hw.bulge())
                check(self, f"curved {label}, plane", grid, truth, ("g", linear_colour), relative=SWEEP_TOLERANCE)

    def test_pyramids(self):
        for label, vtk_type in PYRAMIDS:
            with self.subTest(label):
                check(self, f"curved {label}, plane", type_source_mesh(vtk_type, 1, hw.bulge(), PLANE), plane(),
                      relative=SWEEP_TOLERANCE)

    def test_plane_through_strongly_bent_hexahedra(self):
        # The plane through Q3 hexahedra bent twice as much. (vtkContourFilter is exact here too:
        # a linear field's nodal values, interpolated linearly along the node lattice's straight
        # sub-edges, put its vertices and so its flat pieces on the plane; printed for the record.)
        truth = plane()
        grid = hw.grid(2, VTK_LAGRANGE_HEXAHEDRON, 64, {"f": truth.field.value, "g": linear_colour}, hw.bulge(0.12))
        check(self, "plane through bent VTK_LAGRANGE_HEXAHEDRON order 3 (bulge 0.12)", grid, truth, ("g", linear_colour))
        print_contour("bent Q3 hexahedra", contour_measures(grid, truth))


if __name__ == "__main__":
    unittest.main(verbosity=2, argv=sys.argv[:1])
