"""Helpers the Python tests of both routes share: the C++ build's (Testing/Python, ParaView's VTK
9.2) and the wheel's (Testing/Wheel, pip's VTK). Only VTK API common to both is used."""
import numpy as np
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand


class Messages:
    """Collects an algorithm's error and warning texts."""

    def __init__(self, algorithm):
        self.errors, self.warnings = [], []
        algorithm.GetExecutive()  # make sure events go through the algorithm itself

        @calldata_type(VTK_STRING)
        def on_error(obj, event, text):
            self.errors.append(text)

        @calldata_type(VTK_STRING)
        def on_warning(obj, event, text):
            self.warnings.append(text)

        algorithm.AddObserver(vtkCommand.ErrorEvent, on_error)
        algorithm.AddObserver(vtkCommand.WarningEvent, on_warning)


def pick_landing_error(caster, grid, depth, step):
    """Picks every `step`-th pixel of `caster`'s last image that `depth` (rows x columns) says is
    a hit, and maps each pick's parametric coordinates through VTK's own map of the picked cell
    (EvaluateLocation): (picks checked, largest distance from the pick's position). Every pick
    must hit and have parametric coordinates (asserted)."""
    from tetdsr import vtkDirectSurfacePick
    from vtkmodules.vtkCommonCore import mutable
    pick = vtkDirectSurfacePick()
    checked, worst = 0, 0.0
    height, width = depth.shape
    for j in range(0, height, step):
        for i in range(0, width, step):
            if not np.isfinite(depth[j, i]):
                continue
            assert caster.Pick(i + 0.5, j + 0.5, pick), (i, j)
            assert pick.GetHasParametricCoordinates(), (i, j)
            cell = grid.GetCell(pick.GetCellId())
            x = [0.0, 0.0, 0.0]
            weights = [0.0] * cell.GetNumberOfPoints()
            cell.EvaluateLocation(mutable(0), pick.GetParametricCoordinates(), x, weights)
            worst = max(worst, float(np.linalg.norm(np.array(x) - pick.GetPosition())))
            checked += 1
    return checked, worst
