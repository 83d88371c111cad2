"""Hexahedral results written by real FE codes through the VTK filter (run with /usr/bin/python3):

- Data/mfem_hex_q3.vtu: MFEM's own ParaView writer (PyMFEM 4.10), 64 curved VTK_LAGRANGE_HEXAHEDRON
  cells of order 3 on the unit cube bent by T(q) = q + 0.1 (sin(pi y) sin(pi z), ...), each cell
  with its own copy of its nodes (Scripts/make_mfem_hex.py). Its array "x" is the physical x
  coordinate, which the isoparametric cells hold exactly: the isosurface x = c is the plane inside
  the bent cube. Truth: per pixel the ray/plane point, inside the mesh when its preimage under T
  (Newton on the analytic map, none of TetDSR's code) lies in the unit cube; pixels within 1e-3 of
  the cube's boundary in the preimage (the mesh's boundary is T's Q3 interpolant) are left out.
- Data/calculix_bracket.vtu: a CalculiX 2.20 static analysis of a steel bracket in 20-node C3D20R
  hexahedra, converted by ccx2paraview (float32 points, as users get them;
  Scripts/make_calculix_bracket.py). Every cell is read and rendered; a linear field a . x put on
  its nodes (exact in any isoparametric cell) against the plane, coverage checked where the plane
  point is far (in pixels) from where TetDSR's and the plane's coverage may differ, the mesh's
  silhouette; the von Mises stress against vtkContourFilter on the same iso-value.

Usage: test_real_hexahedra.py <Data folder>
"""
import os
import sys
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import VTK_LAGRANGE_HEXAHEDRON, VTK_QUADRATIC_HEXAHEDRON, vtkUnstructuredGrid
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkCamera

from shared_helpers import Messages, pick_landing_error
from tetdsr import vtkDirectSurfaceRayCaster

DATA = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "Data")


def read(name):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(DATA, name))
    reader.Update()
    return reader.GetOutput()


def camera_on(bounds, direction=(1.6, -1.1, 1.3), angle=30.0):
    lo, hi = np.array(bounds[0::2]), np.array(bounds[1::2])
    centre = 0.5 * (lo + hi)
    camera = vtkCamera()
    camera.SetFocalPoint(*centre)
    camera.SetPosition(*(centre + np.array(direction) * np.linalg.norm(hi - lo)))
    camera.SetViewUp(0.0, 0.0, 1.0)
    camera.SetViewAngle(angle)
    return camera


def cast(grid, array, iso, camera, size):
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(grid)
    caster.SetInputArrayToProcess(0, 0, 0, 0, array)
    caster.SetValue(0, iso)
    caster.SetImageSize(*size)
    caster.SetCamera(camera)
    messages = Messages(caster)
    caster.Update()
    out = caster.GetOutput().GetPointData()
    depth = vtk_to_numpy(out.GetArray("Depth")).reshape(size[1], size[0])
    return caster, messages, depth


def pixel_rays(camera, width, height):
    """Unit ray directions through the pixel centres (row 0 at the bottom), from the camera."""
    position = np.array(camera.GetPosition())
    forward = np.array(camera.GetFocalPoint()) - position
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, np.array(camera.GetViewUp()))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = np.tan(np.radians(camera.GetViewAngle()) / 2)
    i, j = np.meshgrid((np.arange(width) + 0.5) / width * 2 - 1, (np.arange(height) + 0.5) / height * 2 - 1)
    d = forward + (i * half * width / height)[..., None] * right + (j * half)[..., None] * up
    return position, d / np.linalg.norm(d, axis=-1, keepdims=True)


def bend(q):
    s = np.sin(np.pi * q)
    return q + 0.1 * np.stack([s[..., 1] * s[..., 2], s[..., 2] * s[..., 0], s[..., 0] * s[..., 1]], axis=-1)


def unbend(p):
    """T's inverse by Newton from p (T is a small perturbation of the identity)."""
    q = p.copy()
    for _ in range(30):
        s, c = np.sin(np.pi * q), np.cos(np.pi * q)
        jacobian = np.zeros(q.shape + (3,))
        jacobian[..., 0, 0] = jacobian[..., 1, 1] = jacobian[..., 2, 2] = 1.0
        jacobian[..., 0, 1] = 0.1 * np.pi * c[..., 1] * s[..., 2]
        jacobian[..., 0, 2] = 0.1 * np.pi * s[..., 1] * c[..., 2]
        jacobian[..., 1, 2] = 0.1 * np.pi * c[..., 2] * s[..., 0]
        jacobian[..., 1, 0] = 0.1 * np.pi * s[..., 2] * c[..., 0]
        jacobian[..., 2, 0] = 0.1 * np.pi * c[..., 0] * s[..., 1]
        jacobian[..., 2, 1] = 0.1 * np.pi * s[..., 0] * c[..., 1]
        q = q - np.linalg.solve(jacobian, (bend(q) - p)[..., None])[..., 0]
    return q


class MfemQ3(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.grid = read("mfem_hex_q3.vtu")

    def test_every_cell_read_curved(self):
        types = {self.grid.GetCellType(c) for c in range(self.grid.GetNumberOfCells())}
        self.assertEqual(types, {VTK_LAGRANGE_HEXAHEDRON})
        caster, messages, _ = cast(self.grid, "u", 0.5, camera_on(self.grid.GetBounds()), (8, 8))
        cells = self.grid.GetNumberOfCells()
        self.assertEqual(caster.GetNumberOfRenderedCells(), cells)
        self.assertEqual(caster.GetNumberOfCurvedCells(), cells)
        self.assertEqual(caster.GetNumberOfHigherOrderCells(), cells)
        self.assertEqual(messages.errors, [])
        self.assertEqual(messages.warnings, [])

    def test_planes_of_the_linear_field(self):
        width, height = 200, 150
        camera = camera_on(self.grid.GetBounds())
        origin, directions = pixel_rays(camera, width, height)
        diagonal = np.linalg.norm(np.array(self.grid.GetBounds()[1::2]) - self.grid.GetBounds()[0::2])
        for iso in (0.3, 0.55, 0.8):
            caster, messages, depth = cast(self.grid, "x", iso, camera, (width, height))
            t = (iso - origin[0]) / directions[..., 0]
            points = origin + t[..., None] * directions
            q = unbend(points)
            margin = np.min(np.minimum(q, 1.0 - q), axis=-1)
            exact = (t > 0) & (margin > 0.0)
            band = np.abs(margin) < 1e-3
            ours = np.isfinite(depth)
            missed = int(np.sum(exact & ~ours & ~band))
            false = int(np.sum(ours & ~exact & ~band))
            both = ours & exact
            error = float(np.max(np.abs(depth[both] - t[both]), initial=0.0)) / diagonal
            print(f"MFEM Q3, x = {iso}: {int(exact.sum())} pixels ({int(band.sum())} in the boundary band), "
                  f"{missed} missed, {false} false, depth within {error:.3g} of the diagonal")
            self.assertGreater(exact.sum(), 1500)
            self.assertEqual(missed, 0, f"x = {iso}: expected 0 missed pixels, got {missed}")
            self.assertEqual(false, 0, f"x = {iso}: expected 0 false pixels, got {false}")
            self.assertLess(error, 1e-9, f"x = {iso}: expected depth within 1e-9 of the diagonal, got {error:.3g}")
            self.assertEqual(caster.GetNumberOfUncertifiedHits(), 0, "expected every hit certified")
            self.assertEqual(messages.warnings, [])

    def test_picks_give_vtks_parametric_coordinates(self):
        # A pick's (r, s, t) through VTK's own map of the cell (vtkLagrangeHexahedron's
        # EvaluateLocation, its forward map: exact) lands on the picked point.
        width, height = 64, 48
        caster, _, depth = cast(self.grid, "u", 0.5, camera_on(self.grid.GetBounds()), (width, height))
        checked, worst = pick_landing_error(caster, self.grid, depth, 2)
        print(f"MFEM Q3, picks: {checked} checked, VTK's map at the pick's (r, s, t) within {worst:.3g} of the pick")
        self.assertGreater(checked, 20)
        self.assertLess(worst, 1e-12)


def contour_depth(grid, array, iso, camera, size):
    """vtkContourFilter's triangles of the same iso-value, rendered by VTK with the same camera:
    their window depth as the ray parameter per pixel (NaN where none), via the z-buffer."""
    from vtkmodules.vtkFiltersCore import vtkContourFilter
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
    contour = vtkContourFilter()
    contour.SetInputData(grid)
    contour.SetInputArrayToProcess(0, 0, 0, 0, array)
    contour.SetValue(0, iso)
    contour.Update()
    triangles = contour.GetOutput().GetNumberOfCells()
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(contour.GetOutputPort())
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetActiveCamera(camera)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(*size)
    renderer.ResetCameraClippingRange()
    window.Render()
    z = window.GetZbufferData(0, 0, size[0] - 1, size[1] - 1)
    from vtkmodules.vtkCommonCore import vtkFloatArray
    buffer = vtkFloatArray()
    window.GetZbufferData(0, 0, size[0] - 1, size[1] - 1, buffer)
    covered = vtk_to_numpy(buffer).reshape(size[1], size[0]) < 1.0
    window.Finalize()
    del z
    return triangles, covered


class CalculiXBracket(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.grid = read("calculix_bracket.vtu")
        cls.camera = camera_on(cls.grid.GetBounds(), direction=(0.75, -0.9, 0.6), angle=30.0)

    def test_every_cell_read(self):
        cells = self.grid.GetNumberOfCells()
        types = {self.grid.GetCellType(c) for c in range(cells)}
        self.assertEqual(types, {VTK_QUADRATIC_HEXAHEDRON})
        caster, messages, _ = cast(self.grid, "S_Mises", 100.0, self.camera, (8, 8))
        print(f"CalculiX bracket: {cells} cells, {caster.GetNumberOfRenderedCells()} rendered, "
              f"{caster.GetNumberOfCurvedCells()} curved, {caster.GetNumberOfInvertedCells()} inverted")
        self.assertEqual(caster.GetNumberOfRenderedCells(), cells)
        self.assertEqual(caster.GetNumberOfInvertedCells(), 0)
        self.assertEqual(messages.errors, [])
        self.assertEqual(messages.warnings, [])

    def test_a_linear_field_is_its_plane(self):
        # a . x on the nodes (float32 coordinates taken exactly): every isoparametric cell holds it.
        mesh = vtkUnstructuredGrid()
        mesh.DeepCopy(self.grid)
        x = vtk_to_numpy(mesh.GetPoints().GetData()).astype(np.float64)
        a = np.array([0.3, 0.5, -0.8]) / np.linalg.norm([0.3, 0.5, -0.8])
        array = numpy_to_vtk(np.ascontiguousarray(x @ a), deep=1)
        array.SetName("linear")
        mesh.GetPointData().AddArray(array)
        iso = float(np.median(x @ a))
        size = (320, 240)
        caster, messages, depth = cast(mesh, "linear", iso, self.camera, size)
        origin, directions = pixel_rays(self.camera, *size)
        t = (iso - origin @ a) / (directions @ a)
        ours = np.isfinite(depth)
        diagonal = np.linalg.norm(np.array(mesh.GetBounds()[1::2]) - mesh.GetBounds()[0::2])
        error = float(np.max(np.abs(depth[ours] - t[ours]), initial=0.0)) / diagonal
        triangles, contour = contour_depth(mesh, "linear", iso, self.camera, size)
        # Coverage against vtkContourFilter's plane pieces (the same plane, cut by the mesh's cells
        # with straight sub-cells): they may differ only along the mesh's boundary, where its curved
        # faces and the contour's straight ones part; pixels off by more than one from a differing
        # pixel of the silhouette would be a missing or extra piece.
        differ = ours != contour

        def edge(mask):
            """Pixels next to (or on) a change of the mask: its boundary, one pixel wide on each side."""
            grown = np.zeros_like(mask)
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    grown |= np.roll(np.roll(mask, dy, 0), dx, 1) != mask
            return grown

        inside = differ & ~edge(ours) & ~edge(contour)
        print(f"CalculiX bracket, a . x = {iso:.4g}: TetDSR {int(ours.sum())} pixels, depth within {error:.3g} "
              f"of the diagonal; vtkContourFilter {triangles} triangles, {int(contour.sum())} pixels, "
              f"{int(differ.sum())} differ, {int(inside.sum())} of them away from either's silhouette")
        self.assertGreater(ours.sum(), 1500)
        self.assertLess(error, 1e-9, f"expected every hit on the plane, got {error:.3g} of the diagonal")
        self.assertEqual(int(inside.sum()), 0, "expected the contour's coverage but along the silhouettes")
        self.assertEqual(caster.GetNumberOfUncertifiedHits(), 0)
        self.assertEqual(messages.warnings, [])

    def test_von_mises_stress(self):
        size = (240, 180)
        for iso in (20.0, 100.0, 200.0):
            caster, messages, depth = cast(self.grid, "S_Mises", iso, self.camera, size)
            triangles, contour = contour_depth(self.grid, "S_Mises", iso, self.camera, size)
            ours = np.isfinite(depth)
            print(f"CalculiX bracket, von Mises = {iso:g} MPa: TetDSR {int(ours.sum())} pixels, "
                  f"{caster.GetNumberOfUncertifiedHits()} uncertified; vtkContourFilter {triangles} triangles, "
                  f"{int(contour.sum())} pixels, {int(np.sum(ours & ~contour))} only TetDSR's, "
                  f"{int(np.sum(contour & ~ours))} only the contour's")
            self.assertGreater(ours.sum(), 50)
            self.assertEqual(caster.GetNumberOfUncertifiedHits(), 0)
            self.assertEqual(messages.errors, [])
            self.assertEqual(messages.warnings, [])


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
