"""Cracks where cells of different kinds meet (run with /usr/bin/python3): a conforming mesh of the
unit cube in which VTK_QUADRATIC_TETRA cells meet the triangles of VTK_QUADRATIC_WEDGE and
VTK_BIQUADRATIC_QUADRATIC_WEDGE cells, and the wedges' quadrilaterals meet VTK_QUADRATIC_HEXAHEDRON
quadrilaterals and each other's (shared nodes). Rays are aimed exactly (to rounding) through the
shared nodes, points of shared edges and points of shared faces, and along the lattice's lines
(inside shared faces): every ray the analytic truth says hits must hit at the truth's depth, and
every ray it says misses (iso-surfaces passing 1e-6 beside the ray) must miss. Straight cells
hold a plane and a sphere; curved cells (hex_wedge_grids.bulge) a plane.

The cube's 2 x 2 x 2 blocks of side 1/2, for each of the two y layers:

    z in [1/2, 1]:  6 Kuhn tetrahedra    | 2 wedges along x (triangles in x = const)
    z in [0, 1/2]:  2 wedges along z     | 1 hexahedron
                    x in [0, 1/2]          x in [1/2, 1]

so the tetrahedra meet wedge triangles above (z = 1/2) and beside (x = 1/2), and the hexahedra
meet wedge quadrilaterals beside (x = 1/2) and above (z = 1/2); the four kinds share the edge
x = z = 1/2. The wedges are 15-node in one y layer and 18-node in the other where they lie along
z, the other way round along x, so 15- and 18-node quadrilaterals meet too (y = 1/2). An 18-node
wedge's quadrilateral has a centre node its 8-node neighbours lack: curved, that node is placed
where the 8-node face puts its centre (so both sides are the same surface); straight, it is the
centre anyway (hex_wedge_grids.mixed_mesh builds it)."""
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import reference
from vtkmodules.vtkCommonDataModel import (VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_QUADRATIC_HEXAHEDRON,
                                           VTK_QUADRATIC_TETRA, VTK_QUADRATIC_WEDGE)
from vtkmodules.vtkRenderingCore import vtkCamera

import hex_wedge_grids as hw
import higher_order_grids as hog
from shared_helpers import Messages
from tetdsr import vtkDirectSurfaceRayCaster

PLANE_NORMAL = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
SPHERE_CENTRE = np.array([0.47, 0.53, 0.51])
NEAR = 1e-6  # how far (in field value) a missing iso-surface passes beside a ray


def mixed_mesh(warp=None):
    """hex_wedge_grids.mixed_mesh with point arrays of the plane, the sphere's |x - c|^2 and the
    coordinates x, y, z."""
    return hw.mixed_mesh(warp, {"plane": lambda x: x @ PLANE_NORMAL,
                                "sphere": lambda x: np.sum((x - SPHERE_CENTRE) ** 2, axis=1),
                                "x": lambda x: x[:, 0], "y": lambda x: x[:, 1], "z": lambda x: x[:, 2]})


def in_domain(x, margin=1e-9):
    """Inside the unit cube by more than `margin` (else the hit is on the boundary: not judged)."""
    return np.all((x > margin) & (x < 1.0 - margin), axis=-1)


def on_boundary(x, margin=1e-9):
    return np.all((x > -margin) & (x < 1.0 + margin), axis=-1) & ~in_domain(x, margin)


def first_hit(origins, directions, field, iso):
    """The exact first crossing inside the unit cube of the plane n.x or the sphere |x - c|^2 (in
    closed form), inf for none; and the rays not to judge: a crossing on the cube's boundary, or a
    tangent one."""
    if field == "plane":
        with np.errstate(divide="ignore", invalid="ignore"):
            roots = ((iso - origins @ PLANE_NORMAL) / (directions @ PLANE_NORMAL))[:, None]
        tangent = np.abs(directions @ PLANE_NORMAL) < 1e-9
    else:
        q = origins - SPHERE_CENTRE
        b = np.einsum("ij,ij->i", q, directions)
        disc = b * b - (np.sum(q * q, axis=1) - iso)
        with np.errstate(invalid="ignore"):
            root = np.sqrt(disc)
        roots = np.c_[-b - root, -b + root]
        tangent = np.abs(disc) < 1e-12
    t = np.full(len(origins), np.inf)
    unclear = tangent.copy()
    for k in range(roots.shape[1]):
        r = roots[:, k]
        valid = np.isfinite(r) & (r >= 0)
        x = origins + np.where(valid, r, 0.0)[:, None] * directions
        unclear |= valid & on_boundary(x) & np.isinf(t)
        t = np.where(valid & in_domain(x) & np.isinf(t), r, t)
    return t, unclear


def targets(mesh):
    """Points on what cells share, strictly inside the cube, by VTK's own edge and face cells:
    nodes, two points on each edge, and the centre and an off-centre point of each face."""
    points = vtk_to_numpy(mesh.GetPoints().GetData())
    found = {"node": [p for p in points]}
    found["edge"], found["face"] = [], []
    for c in range(mesh.GetNumberOfCells()):
        cell = mesh.GetCell(c)
        for e in range(cell.GetNumberOfEdges()):
            for s in (0.3, 0.61):
                found["edge"].append(location(cell.GetEdge(e), (s, 0.0, 0.0)))
        for f in range(cell.GetNumberOfFaces()):
            face = cell.GetFace(f)
            triangle = face.GetNumberOfPoints() == 6
            for pc in (((1 / 3, 1 / 3, 0.0), (0.2, 0.55, 0.0)) if triangle else ((0.5, 0.5, 0.0), (0.3, 0.65, 0.0))):
                found["face"].append(location(face, pc))
    out = {}
    for name, where in found.items():
        where = np.array(where)
        where = where[in_domain(where, 1e-6)]
        out[name] = np.unique(np.round(where, 12), axis=0)
    return out


def location(cell, pcoords):
    x, weights = [0.0, 0.0, 0.0], [0.0] * cell.GetNumberOfPoints()
    cell.EvaluateLocation(reference(0), list(pcoords), x, weights)
    return np.array(x)


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


# Directions: along the axes (inside the lattice's faces), along face diagonals (inside the
# wedges' and Kuhn tetrahedra's diagonal faces), along the cube's diagonal, and two generic.
DIRECTIONS = [unit(d) for d in ((0, 0, -1), (0, 0, 1), (-1, 0, 0), (1, 0, 0), (0, -1, 0), (0, 1, 0),
                                (-1, -1, 0), (0, -1, -1), (-1, 0, -1), (1, -1, 0), (-1, -1, -1),
                                (-0.31, -0.52, -0.79), (0.7, -0.2, -0.4))]


class PixelCaster:
    """One caster of one pixel: the ray from `position` through the pixel's centre, the focal point."""

    def __init__(self, mesh, array):
        self.camera = vtkCamera()
        self.caster = vtkDirectSurfaceRayCaster()
        self.caster.SetInputData(mesh)
        self.caster.SetInputArrayToProcess(0, 0, 0, 0, array)
        self.caster.SetCamera(self.camera)
        self.caster.SetImageSize(1, 1)
        self.caster.SetNumberOfThreads(1)  # (one ray: no thread pool)
        self.messages = Messages(self.caster)

    def depth(self, target, direction, iso, distance=2.5):
        position = target - distance * direction
        self.camera.SetPosition(*position)
        self.camera.SetFocalPoint(*target)
        self.camera.SetViewUp(*((1.0, 0.0, 0.0) if abs(direction[1]) > 0.9 else (0.0, 1.0, 0.0)))
        self.caster.SetValue(0, iso)
        self.caster.Update()
        return float(vtk_to_numpy(self.caster.GetOutput().GetPointData().GetArray("Depth"))[0]), position


class Cracks(unittest.TestCase):
    def aimed_rays(self, mesh, fields, label):
        """Rays through every target: per field, a hit there (the iso-surface through the
        target, crossed transversally) and near misses (iso-surfaces 1e-6 beside the ray)."""
        where = targets(mesh)
        casters = {field: PixelCaster(mesh, field) for field in fields}
        report = []
        for name, points in where.items():
            rays = holes = false = 0
            worst = 0.0
            for q in points:
                for field in fields:
                    caster = casters[field]
                    if field == "plane":
                        iso = float(q @ PLANE_NORMAL)
                        hits = [d for d in DIRECTIONS if abs(d @ PLANE_NORMAL) > 0.05]
                        # Directions in the plane: the field is the iso-value +-1e-6 all along.
                        misses = [unit(np.cross(PLANE_NORMAL, a)) for a in ((1, 0, 0), (0, 0, 1))]
                        miss_isos = (iso + NEAR, iso - NEAR)
                    else:
                        radial = q - SPHERE_CENTRE
                        iso = float(radial @ radial)
                        # Entering the sphere at q: against the outward radial direction.
                        hits = [d if d @ radial < 0 else -d for d in DIRECTIONS
                                if abs(d @ unit(radial)) > 0.05]
                        # Tangent at q: a sphere 1e-6 (in |x - c|^2) smaller is missed.
                        misses = [unit(np.cross(radial, a)) for a in ((1, 0, 0), (0, 0, 1))]
                        miss_isos = (iso - NEAR,)
                    for d in hits:
                        depth, position = caster.depth(q, d, iso)
                        expected, unclear = first_hit(position[None], d[None], field, iso)
                        self.assertFalse(unclear[0])
                        self.assertTrue(np.isclose(expected[0], 2.5, rtol=1e-12), "the truth hits at the target")
                        rays += 1
                        if not np.isfinite(depth):
                            holes += 1
                            if holes <= 3:
                                print(f"  hole: {field} through {name} {q} along {d}")
                            continue
                        worst = max(worst, abs(depth - expected[0]))
                    for d in misses:
                        for miss_iso in miss_isos:
                            depth, position = caster.depth(q, d, miss_iso)
                            expected, _ = first_hit(position[None], d[None], field, miss_iso)
                            self.assertTrue(np.isinf(expected[0]), "the truth misses")
                            rays += 1
                            if np.isfinite(depth):
                                false += 1
                                if false <= 3:
                                    print(f"  false hit: {field} iso {miss_iso} through {name} {q} along {d}")
            report.append((name, len(points), rays, holes, false, worst / np.sqrt(3.0)))
        for name, count, rays, holes, false, worst in report:
            print(f"{label}, rays through {count} shared {name} points ({', '.join(fields)}): {rays} rays, "
                  f"{holes} holes, {false} false hits, max depth error {worst:.3g} of the diagonal")
        for caster in casters.values():
            self.assertEqual(caster.messages.errors + caster.messages.warnings, [])
            self.assertEqual(caster.caster.GetNumberOfRenderedCells(), mesh.GetNumberOfCells())
        for name, count, rays, holes, false, worst in report:
            self.assertEqual(holes, 0, f"{label}: expected 0 holes through shared {name} points, got {holes} of {rays}")
            self.assertEqual(false, 0, f"{label}: expected 0 false hits through shared {name} points, got {false}")
            self.assertLess(worst, 1e-9, f"{label}: expected depth within 1e-9 of the diagonal, got {worst:.3g}")
        return report

    def lattice_views(self, mesh, fields, label):
        """Parallel views along the axes whose pixel centres lie on the lines x, y = k / 16 (the
        shared faces' and edges' lines, and between them), the coordinate planes at 1/4, 1/2,
        3/4 (the middle one the blocks' shared faces) and the other fields."""
        m, pitch = 21, 1.0 / 16.0
        rays = holes = false = unclear_count = 0
        worst = 0.0
        for axis in range(3):
            for sign in (-1.0, 1.0):
                direction = np.zeros(3)
                direction[axis] = sign
                up = np.eye(3)[(axis + 1) % 3]
                cam = vtkCamera()
                cam.ParallelProjectionOn()
                cam.SetFocalPoint(0.5, 0.5, 0.5)
                cam.SetPosition(*(np.full(3, 0.5) - 2.5 * direction))
                cam.SetViewUp(*up)
                cam.SetParallelScale(0.5 * m * pitch)
                origins, directions = hog.pixel_rays(cam.GetPosition(), cam.GetFocalPoint(), cam.GetViewUp(),
                                                     30.0, m, m, parallel=True, parallel_scale=cam.GetParallelScale())
                # (The rays' lines lie on the cube's boundary faces where a coordinate is 0 or 1.)
                across = np.delete(origins, axis, axis=1)
                self.assertLess(np.abs(across * 16 - np.rint(across * 16)).max(), 1e-12, "rays on the lattice lines")
                boundary = np.any(np.isclose(across, 0.0, atol=1e-12) | np.isclose(across, 1.0, atol=1e-12), axis=1)
                cases = [("xyz"[axis], v) for v in (0.25, 0.5, 0.75)] + [(f, None) for f in fields]
                for field, iso in cases:
                    caster = vtkDirectSurfaceRayCaster()
                    caster.SetInputData(mesh)
                    caster.SetInputArrayToProcess(0, 0, 0, 0, field)
                    caster.SetCamera(cam)
                    caster.SetImageSize(m, m)
                    if iso is None:
                        iso = 0.8 if field == "plane" else 0.12
                    caster.SetValue(0, iso)
                    messages = Messages(caster)
                    caster.Update()
                    self.assertEqual(messages.errors + messages.warnings, [])
                    depth = vtk_to_numpy(caster.GetOutput().GetPointData().GetArray("Depth"))
                    if field in "xyz":
                        inside = np.all((across > 0) & (across < 1), axis=1)
                        t = np.where(inside, np.abs(iso - origins[:, axis]), np.inf)
                        unclear = boundary
                    else:
                        t, unclear = first_hit(origins, directions, field, iso)
                        unclear = unclear | boundary
                    judged = ~unclear
                    rays += int(judged.sum())
                    unclear_count += int(unclear.sum())
                    exact, ours = np.isfinite(t), np.isfinite(depth)
                    holes += int(np.sum(judged & exact & ~ours))
                    false += int(np.sum(judged & ~exact & ours))
                    both = judged & exact & ours
                    worst = max(worst, float(np.max(np.abs(depth[both] - t[both]), initial=0.0)))
        worst /= np.sqrt(3.0)
        print(f"{label}, lattice views (6 directions, planes x/y/z = 1/4, 1/2, 3/4 and {', '.join(fields)}): "
              f"{rays} rays judged ({unclear_count} on the cube's boundary), {holes} holes, {false} false hits, "
              f"max depth error {worst:.3g} of the diagonal")
        self.assertGreater(rays, 5000)
        self.assertEqual(holes, 0, f"{label}: expected 0 holes, got {holes}")
        self.assertEqual(false, 0, f"{label}: expected 0 false hits, got {false}")
        self.assertLess(worst, 1e-9, f"{label}: expected depth within 1e-9 of the diagonal, got {worst:.3g}")

    def test_straight(self):
        mesh = mixed_mesh()
        counts = np.bincount(vtk_to_numpy(mesh.GetCellTypesArray()), minlength=40)
        print(f"straight mixed mesh: {mesh.GetNumberOfCells()} cells ({counts[VTK_QUADRATIC_TETRA]} quadratic "
              f"tetrahedra, {counts[VTK_QUADRATIC_WEDGE]} 15-node and {counts[VTK_BIQUADRATIC_QUADRATIC_WEDGE]} "
              f"18-node wedges, {counts[VTK_QUADRATIC_HEXAHEDRON]} 20-node hexahedra), "
              f"{mesh.GetNumberOfPoints()} points")
        self.aimed_rays(mesh, ("plane", "sphere"), "straight")
        self.lattice_views(mesh, ("plane", "sphere"), "straight")

    def test_curved(self):
        mesh = mixed_mesh(hw.bulge())
        caster = vtkDirectSurfaceRayCaster()
        caster.SetInputData(mesh)
        caster.SetInputArrayToProcess(0, 0, 0, 0, "plane")
        caster.SetValue(0, 0.8)
        caster.SetImageSize(4, 4)
        caster.Update()
        print(f"curved mixed mesh: {caster.GetNumberOfCurvedCells()} of {mesh.GetNumberOfCells()} cells curved")
        self.assertGreater(caster.GetNumberOfCurvedCells(), 0.5 * mesh.GetNumberOfCells())
        self.aimed_rays(mesh, ("plane",), "curved")
        self.lattice_views(mesh, ("plane",), "curved")


if __name__ == "__main__":
    unittest.main(verbosity=2)
