"""Ghost cells (the vtkGhostType cell array) as a distributed writer leaves them: DOLFINx's VTKFile
on 2 ranks (Testing/Data/dolfinx_ghosts, Scripts/make_dolfinx_ghosts.py) writes in each piece the
cells of the other rank that share a facet with its own, flagged DUPLICATECELL. Read in one
process, the .pvtu's 448 cells are 384 cells of the mesh plus 64 duplicates.

A duplicate is not drawn, not composited twice when translucent and never named: the filter's
cell ids, the mapper's picks and hardware selections name only cells of their own piece, and every
picture equals the one of the same grid with its ghost cells removed. Truth: the field
u = |x - c|^2 (c the cube's centre) is held exactly by the P2 cells, so every pixel's depth is the
ray/sphere root. The same grid without its ghost array (the duplicates then drawn) shows the test
can fail: picks name duplicates there."""
import os
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkDataObject, vtkUnstructuredGrid
from vtkmodules.vtkIOXML import vtkXMLPUnstructuredGridReader
from vtkmodules.vtkRenderingCore import vtkActor, vtkCamera, vtkHardwareSelector, vtkRenderer

from test_mapper import DEPTH_TOLERANCE, W, H, matrix, rgba, shared_window, window_depth, zbuffer
from tetdsr import vtkDirectSurfaceMapper, vtkDirectSurfacePick, vtkDirectSurfaceRayCaster

DATA = os.path.join(os.path.dirname(__file__), "..", "Data", "dolfinx_ghosts", "ball000000.pvtu")
CENTRE = np.array([0.5, 0.5, 0.5])
ISO = 0.1  # a sphere of radius 0.316 about the centre: cut by both pieces
DUPLICATE, HIDDEN = 1, 32


def read():
    reader = vtkXMLPUnstructuredGridReader()
    reader.SetFileName(DATA)
    reader.Update()
    grid = vtkUnstructuredGrid()
    grid.ShallowCopy(reader.GetOutput())
    return grid


def ghost_flags(grid):
    return vtk_to_numpy(grid.GetCellData().GetArray("vtkGhostType")).astype(int)


def without_ghost_array(grid):
    """The same cells with no vtkGhostType cell array: the duplicates are drawn."""
    copy = vtkUnstructuredGrid()
    copy.DeepCopy(grid)
    copy.GetCellData().RemoveArray("vtkGhostType")
    return copy


def owned_cells(grid):
    """The grid's own cells only (the ghost cells removed; the points, and so the point ids, kept),
    without a ghost array. (Made here: VTK 9.2's vtkExtractCells crashes on this grid now and
    then.)"""
    own = np.flatnonzero((ghost_flags(grid) & (DUPLICATE | HIDDEN)) == 0)
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray()).astype(np.int64)
    ids = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).astype(np.int64)
    kept = np.concatenate([ids[offsets[c]:offsets[c + 1]] for c in own])
    sizes = offsets[own + 1] - offsets[own]
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(np.r_[0, np.cumsum(sizes)], deep=1),
                  numpy_to_vtkIdTypeArray(kept, deep=1))
    types = vtk_to_numpy(grid.GetCellTypesArray())[own]
    result = vtkUnstructuredGrid()
    result.SetPoints(grid.GetPoints())
    result.SetCells(numpy_to_vtk(np.ascontiguousarray(types), deep=1), cells)
    result.GetPointData().ShallowCopy(grid.GetPointData())
    return result


def camera_at(camera):
    camera.SetPosition(1.9, 1.4, 2.3)
    camera.SetFocalPoint(0.5, 0.5, 0.5)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(30)
    camera.SetClippingRange(0.5, 5.0)


def sphere_truth(composite):
    """Each pixel's exact first hit with |x - c|^2 = ISO as window depth (1 on a miss), and its
    margin from grazing."""
    inverse = np.linalg.inv(composite)
    i, j = np.meshgrid(np.arange(W), np.arange(H))
    x, y = 2 * (i.ravel() + 0.5) / W - 1, 2 * (j.ravel() + 0.5) / H - 1
    near, far = (np.c_[x, y, np.full_like(x, z), np.ones_like(x)] @ inverse.T for z in (-1.0, 1.0))
    origin = near[:, :3] / near[:, 3:]
    direction = far[:, :3] / far[:, 3:] - origin
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    o = origin - CENTRE
    b = np.sum(o * direction, axis=1)
    disc = b * b - (np.sum(o * o, axis=1) - ISO)
    t = -b - np.sqrt(np.maximum(disc, 0))
    depth = np.ones(len(t))
    hit = disc >= 0
    depth[hit] = window_depth(composite, origin[hit] + t[hit, None] * direction[hit])
    return depth.reshape(H, W), np.abs(disc).reshape(H, W) / ISO


def mapper_scene(grid, opacity=1.0):
    mapper = vtkDirectSurfaceMapper()
    mapper.SetInputData(grid)
    mapper.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "u")
    mapper.SetValue(0, ISO)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetOpacity(opacity)
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetBackground(0.1, 0.2, 0.3)
    window = shared_window()
    window.AddRenderer(renderer)
    camera_at(renderer.GetActiveCamera())
    window.Render()
    return window, renderer, mapper, actor


def picked_cells(renderer, mapper, actor):
    """Per pixel centre, the cell the mapper's pick names (-1 where it sees nothing)."""
    result = vtkDirectSurfacePick()
    cells = np.full((H, W), -1)
    for j in range(H):
        for i in range(W):
            if mapper.Pick(i + 0.5, j + 0.5, renderer, actor, result):
                cells[j, i] = result.GetCellId()
    return cells


def selected_cells(renderer):
    selector = vtkHardwareSelector()
    selector.SetRenderer(renderer)
    selector.SetArea(0, 0, W - 1, H - 1)
    selector.SetFieldAssociation(vtkDataObject.FIELD_ASSOCIATION_CELLS)
    selection = selector.Select()
    ids = set()
    for n in range(selection.GetNumberOfNodes()):
        array = selection.GetNode(n).GetSelectionList()
        ids.update(array.GetValue(k) for k in range(array.GetNumberOfTuples()))
    return ids


class TestGhostCells(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.grid = read()
        cls.flags = ghost_flags(cls.grid)
        cls.ghost = (cls.flags & (DUPLICATE | HIDDEN)) != 0
        cls.original = vtk_to_numpy(cls.grid.GetCellData().GetArray("vtkOriginalCellIds"))

    def test_the_data_has_duplicates(self):
        # Each duplicate repeats a cell another piece owns: same original id, same nodes.
        self.assertEqual(self.grid.GetNumberOfCells(), 448)
        self.assertEqual(int(self.ghost.sum()), 64)
        self.assertEqual(len(set(self.original[~self.ghost])), 384)
        self.assertTrue(set(self.original[self.ghost]) <= set(self.original[~self.ghost]))

    def test_filter_counts_and_names_only_own_cells(self):
        def cast(grid):
            caster = vtkDirectSurfaceRayCaster()
            caster.SetInputData(grid)
            caster.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "u")
            caster.SetValue(0, ISO)
            caster.SetImageSize(W, H)
            camera = vtkCamera()
            camera_at(camera)
            caster.SetCamera(camera)
            caster.Update()
            out = caster.GetOutput().GetPointData()
            return (caster, vtk_to_numpy(out.GetArray("Depth")).copy(),
                    vtk_to_numpy(out.GetArray("CellId")).astype(int).copy())

        caster, depth, cells = cast(self.grid)
        self.assertEqual(caster.GetNumberOfGhostCells(), 64)
        self.assertEqual(caster.GetNumberOfRenderedCells(), 384)
        hit = cells >= 0
        self.assertGreater(hit.sum(), 2000)
        named_ghosts = int(self.ghost[cells[hit]].sum())
        _, plain_depth, plain_cells = cast(without_ghost_array(self.grid))
        plain_ghosts = int(self.ghost[plain_cells[plain_cells >= 0]].sum())
        _, own_depth, _ = cast(owned_cells(self.grid))
        print(f"filter: {caster.GetNumberOfGhostCells()} ghost cells left out, "
              f"{caster.GetNumberOfRenderedCells()} rendered; pixels naming a duplicate: "
              f"{named_ghosts} (without the ghost array: {plain_ghosts})")
        self.assertEqual(named_ghosts, 0)
        self.assertGreater(plain_ghosts, 0, "the duplicates must be seen when not flagged")
        np.testing.assert_array_equal(np.isfinite(depth), np.isfinite(own_depth))
        finite = np.isfinite(depth)
        self.assertLess(np.max(np.abs(depth[finite] - own_depth[finite])), 1e-12)

    def test_mapper_picks_and_selections_name_only_own_cells(self):
        window, renderer, mapper, actor = mapper_scene(self.grid)
        z = zbuffer(window)
        truth, margin = sphere_truth(matrix(renderer))
        clear = margin > 1e-6
        coverage = int(((z < 1) != (truth < 1))[clear].sum())
        both = (z < 1) & (truth < 1)
        depth_error = float(np.max(np.abs(z - truth)[both]))
        self.assertEqual(mapper.GetNumberOfRenderedCells(), 384)
        picks = picked_cells(renderer, mapper, actor)
        named_ghosts = int(self.ghost[picks[picks >= 0]].sum())
        selected = selected_cells(renderer)
        selected_ghosts = sum(1 for c in selected if self.ghost[c])
        selected_originals = {int(self.original[c]) for c in selected}

        window, renderer, mapper, actor = mapper_scene(without_ghost_array(self.grid))
        plain_picks = picked_cells(renderer, mapper, actor)
        plain_ghosts = int(self.ghost[plain_picks[plain_picks >= 0]].sum())
        plain_selected = selected_cells(renderer)
        print(f"mapper: {int((picks >= 0).sum())} pixels picked, {named_ghosts} name a duplicate "
              f"(without the ghost array: {plain_ghosts}); {len(selected)} cells selected, "
              f"{selected_ghosts} duplicates (without: "
              f"{sum(1 for c in plain_selected if self.ghost[c])}); coverage vs the exact "
              f"sphere: {coverage} pixels differ, window depth within {depth_error:.1e}")
        self.assertEqual(coverage, 0)
        self.assertLess(depth_error, DEPTH_TOLERANCE)
        self.assertGreater(int((picks >= 0).sum()), 2000)
        self.assertEqual(named_ghosts, 0)
        self.assertEqual(selected_ghosts, 0)
        self.assertGreater(plain_ghosts, 0, "the duplicates must be picked when not flagged")
        # The cells selected are the mesh's cells the surface shows, each once: as many as their
        # original ids (the flagless grid selects some through their duplicates).
        self.assertEqual(len(selected_originals), len(selected))
        self.assertEqual(selected_originals,
                         {int(self.original[c]) for c in plain_selected})

    def test_translucent_pictures_equal_those_without_ghost_cells(self):
        results = {}
        for name, grid in (("ghosts", self.grid), ("own", owned_cells(self.grid))):
            window, renderer, mapper, actor = mapper_scene(grid, opacity=0.4)
            results[name] = rgba(window)
        difference = np.abs(results["ghosts"] - results["own"]).max(axis=2)
        covered = int((np.abs(results["own"] - results["own"][0, 0]).max(axis=2) > 0).sum())
        print(f"translucent: {int((difference > 2).sum())} of {covered} covered pixels differ by "
              f"more than 2/255 from the picture without ghost cells")
        self.assertGreater(covered, 2000)
        self.assertEqual(int((difference > 2).sum()), 0)


if __name__ == "__main__":
    unittest.main()
