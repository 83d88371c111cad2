"""Hardware selection of the exact surface (vtkHardwareSelector, as ParaView's Select Cells /
Points On and hovering use it, and vtkPropPicker) against the hits the rays make: the sphere
|x|^2 = 0.5 held exactly by quadratic cells, seen through a moved actor and cut by a clipping
plane (test_mapper_pick's scene), with an opaque box in front of part of it.

Truth per pixel: the mapper's exact pick through the pixel's centre (checked against the
analytic ray/sphere hit in test_mapper_pick.py) gives the cell, the block and the hit; the
surface shows at the pixel where that hit's window depth is nearer than the box's (the depth
buffer of a frame without the surface). A node is the one of the hit cell nearest the hit."""
import unittest

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkMultiBlockDataSet
from vtkmodules.vtkFiltersSources import vtkCubeSource
from vtkmodules.vtkRenderingCore import vtkHardwareSelector, vtkPropPicker
from vtkmodules.vtkCommonCore import vtkIdList

from test_mapper import W, H, grid, matrix, polygon_actor, window_depth, zbuffer
from test_mapper_pick import DIAGONAL, actor_matrix, exact_hit, scene
from tetdsr import vtkDirectSurfacePick

CELLS = vtkDataObject.FIELD_ASSOCIATION_CELLS
POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS


def add_box(renderer):
    """An opaque box in front of the sphere's lower left (world coordinates)."""
    cube = vtkCubeSource()
    cube.SetBounds(0.3, 1.0, -0.9, -0.1, 0.4, 1.1)
    box = polygon_actor(cube, (0.9, 0.3, 0.2))
    renderer.AddActor(box)
    return box


def truth(window, renderer, mapper, actor):
    """Per pixel, what the surface shows there in front of the other props: {(i, j): (block flat
    index, cell id, nearest node id)}; with the number of pixels the surface hits behind them."""
    actor.VisibilityOff()
    window.Render()
    others = zbuffer(window)
    actor.VisibilityOn()
    window.Render()
    composite = matrix(renderer)
    result = vtkDirectSurfacePick()
    nodes = vtkIdList()
    shown, hidden = {}, 0
    for j in range(H):
        for i in range(W):
            if not mapper.Pick(i + 0.5, j + 0.5, renderer, actor, result):
                continue
            z = window_depth(composite, np.array([result.GetPosition()]))[0]
            if z >= others[j, i]:
                hidden += 1
                continue
            data = result.GetDataSet()
            data.GetCellPoints(result.GetCellId(), nodes)
            hit = np.array(result.GetMapperPosition())
            ids = [nodes.GetId(k) for k in range(nodes.GetNumberOfIds())]
            nearest = min(ids, key=lambda k: np.linalg.norm(np.array(data.GetPoint(k)) - hit))
            shown[(i, j)] = (result.GetFlatBlockIndex(), result.GetCellId(), nearest)
    return shown, hidden


def select(renderer, association, area=(0, 0, W - 1, H - 1)):
    """vtkHardwareSelector's selection of `area`: {prop: {(composite index, id)}}."""
    selector = vtkHardwareSelector()
    selector.SetRenderer(renderer)
    selector.SetArea(*area)
    selector.SetFieldAssociation(association)
    selection = selector.Select()
    found = {}
    for n in range(selection.GetNumberOfNodes()):
        node = selection.GetNode(n)
        properties = node.GetProperties()
        prop = properties.Get(node.PROP())
        index = properties.Get(node.COMPOSITE_INDEX())
        ids = node.GetSelectionList()
        found.setdefault(prop, set()).update(
            (index, ids.GetValue(k)) for k in range(ids.GetNumberOfTuples()))
    return found


class TestSelection(unittest.TestCase):
    def check(self, window, renderer, mapper, actor, box, composite, label):
        shown, hidden = truth(window, renderer, mapper, actor)
        self.assertGreater(len(shown), 1000, label)
        self.assertGreater(hidden, 200, label)  # the box hides part of the surface
        block = (lambda b: b) if composite else (lambda b: 1)  # a dataset's composite index is 1

        # The whole window: the cells and nodes every pixel shows, no more, no fewer.
        cells = select(renderer, CELLS)
        expected_cells = {(block(b), c) for b, c, _ in shown.values()}
        self.assertIn(box, cells, label)
        self.assertEqual(cells.get(actor), expected_cells, label)
        points = select(renderer, POINTS)
        expected_points = {(block(b), p) for b, _, p in shown.values()}
        self.assertEqual(points.get(actor), expected_points, label)

        # Single pixels: the selection there is the pixel's own cell (or the box in front).
        rng = np.random.default_rng(11)
        singles = 0
        pixels = list(shown)
        samples = [pixels[k] for k in rng.choice(len(pixels), 30, replace=False)] + list(
            zip(rng.integers(0, W, 30), rng.integers(0, H, 30)))
        for i, j in samples:
            found = select(renderer, CELLS, (int(i), int(j), int(i), int(j)))
            if (i, j) in shown:
                b, c, _ = shown[(i, j)]
                self.assertEqual(found, {actor: {(block(b), c)}}, (label, i, j))
                singles += 1
            else:
                self.assertNotIn(actor, found, (label, i, j))
        print(f"{label}: {len(shown)} pixels show the surface ({hidden} hidden by the box): "
              f"{len(expected_cells)} cells and {len(expected_points)} nodes selected exactly as "
              f"the rays hit them; {singles} single-pixel selections equal the pixel's cell")
        return shown

    def test_cells_and_points_of_a_dataset(self):
        window, renderer, mapper, actor = scene()
        box = add_box(renderer)
        self.check(window, renderer, mapper, actor, box, False, "dataset")

    def test_translucent_surface(self):
        window, renderer, mapper, actor = scene()
        box = add_box(renderer)
        actor.GetProperty().SetOpacity(0.5)
        self.check(window, renderer, mapper, actor, box, False, "translucent")

    def test_blocks_of_a_composite_dataset(self):
        window, renderer, mapper, actor = scene()
        whole = mapper.GetInput()
        cells = whole.GetNumberOfCells()
        blocks = vtkMultiBlockDataSet()
        for k, (lo, hi) in enumerate(((0, cells // 2), (cells // 2, cells))):
            part = grid(4, cell_range=(lo, hi))
            part.GetPointData().AddArray(whole.GetPointData().GetArray("g"))
            blocks.SetBlock(k, part)
        mapper.SetInputData(blocks)
        box = add_box(renderer)
        shown = self.check(window, renderer, mapper, actor, box, True, "composite")
        self.assertEqual({b for b, _, _ in shown.values()}, {1, 2})

    def test_prop_picker(self):
        """vtkPropPicker: the actor, and the point its depth buffer gives (24-bit depth)."""
        window, renderer, mapper, actor = scene()
        add_box(renderer)
        shown, _ = truth(window, renderer, mapper, actor)
        composite, model = matrix(renderer), actor_matrix(actor)
        picker = vtkPropPicker()
        rng = np.random.default_rng(5)
        error, picks = 0.0, 0
        pixels = list(shown)
        for k in rng.choice(len(pixels), 80, replace=False):
            i, j = pixels[k]
            # (At the pixel's centre, whose depth the pixel holds: at (i, j), its corner, the
            # depth buffer's value would be the centre's.)
            self.assertTrue(picker.PickProp(i + 0.5, j + 0.5, renderer))
            self.assertIs(picker.GetViewProp(), actor)
            expected, margin = exact_hit(composite, model, i + 0.5, j + 0.5)
            if expected is None or margin < 1e-3:
                continue
            picks += 1
            error = max(error, np.linalg.norm(np.array(picker.GetPickPosition()) - expected))
        print(f"vtkPropPicker: {picks} picks on the surface, position within "
              f"{error / DIAGONAL:.1e} of the diagonal (the depth buffer's precision)")
        self.assertGreater(picks, 40)
        self.assertLess(error / DIAGONAL, 1e-4)

    def test_what_cannot_be_drawn_selects_nothing_and_says_so_once(self):
        """A field that is not there, a non-finite iso-value, an empty grid or composite: the
        selection has nothing of the actor, and each selection reports the problem once (not
        once per pass)."""
        from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkUnstructuredGrid
        from shared_helpers import Messages
        cases = {
            "no such field": lambda m: (m.SetInputArrayToProcess(0, 0, 0, 0, "nope"), m.SetValue(0, 0.5)),
            "a NaN iso-value": lambda m: m.SetValue(0, float("nan")),
            "an empty grid": lambda m: (m.SetInputData(vtkUnstructuredGrid()), m.SetValue(0, 0.5)),
            "an empty composite": lambda m: (m.SetInputData(vtkMultiBlockDataSet()), m.SetValue(0, 0.5)),
        }
        for name, spoil in cases.items():
            window, renderer, mapper, actor = scene()
            spoil(mapper)
            messages = Messages(mapper)
            window.Render()
            rendered = len(messages.errors)
            for association in (CELLS, POINTS):
                self.assertNotIn(actor, select(renderer, association), name)
            during = len(messages.errors) - rendered
            self.assertGreaterEqual(rendered, 1, name)
            self.assertLessEqual(during, 2, f"{name}: {during} errors in two selections")


if __name__ == "__main__":
    unittest.main()
