"""The wheel's filter on VTK_LAGRANGE_TETRAHEDRON and VTK_BEZIER_TETRAHEDRON grids (straight cells
of orders 3 and 4, built on pip's VTK's own node positions by Testing/Python/higher_order_grids.py)
against the analytic first root of the polynomial field along each pixel's ray."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import VTK_BEZIER_TETRAHEDRON, VTK_LAGRANGE_TETRAHEDRON

import scenes  # noqa: F401  (puts Testing/Python on the path)
import higher_order_grids as hog
from shared_helpers import Messages
from tetdsr import vtkDirectSurfaceRayCaster

W, H = 160, 120
CAMERA = ((1.7, 1.35, 2.5), (0.5, 0.5, 0.5), 22.0)
KINDS = {"Lagrange": VTK_LAGRANGE_TETRAHEDRON, "Bezier": VTK_BEZIER_TETRAHEDRON}


def render(mesh, iso, configure=None):
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(mesh)
    caster.SetValue(0, iso)
    caster.SetCamera(scenes.camera(CAMERA[0], CAMERA[1], view_angle=CAMERA[2]))
    caster.SetImageSize(W, H)
    if configure:
        configure(caster)
    messages = Messages(caster)
    caster.Update()
    pd = caster.GetOutputDataObject(0).GetPointData()
    return caster, messages, {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)).copy()
                              for k in range(pd.GetNumberOfArrays())}


@pytest.mark.parametrize("kind", list(KINDS))
@pytest.mark.parametrize("name,order", [("torus", 4), ("cubic_blob", 3)])
def test_against_the_polynomial(kind, name, order):
    field = getattr(hog, name)()
    mesh = hog.grid(2, KINDS[kind], order, {"f": field.value, "colour": lambda x: x[..., 0] ** 3 - x[..., 1] * x[..., 2]})

    def colour(caster):
        caster.ColorByArrayOn()
        caster.SetInputArrayToProcess(1, 0, 0, 0, "colour")

    caster, messages, out = render(mesh, field.iso, colour)
    origins, directions = hog.pixel_rays(CAMERA[0], CAMERA[1], (0.0, 1.0, 0.0), CAMERA[2], W, H)
    t, grazing = hog.first_crossing(field, origins, directions)
    ours, exact = np.isfinite(out["Depth"]), np.isfinite(t)
    wrong = int(((ours != exact) & ~grazing).sum())
    both = ours & exact & ~grazing
    depth = float(np.abs(out["Depth"][both] - t[both]).max()) / np.sqrt(3.0)
    points = origins[both] + t[both, None] * directions[both]
    values = float(np.abs(out["ColorValues"][both] - (points[:, 0] ** 3 - points[:, 1] * points[:, 2])).max())
    print(f"\nwheel, {kind} order {order} {name}: {int(both.sum())} pixels ({int(grazing.sum())} grazing), "
          f"{wrong} differ in coverage, depth within {depth:.3g} of the diagonal, colour values within {values:.3g}")
    assert both.sum() > 4000, f"expected a visible surface, got {both.sum()} pixels"
    assert wrong == 0, f"expected the exact coverage, got {wrong} pixels differing"
    assert depth < 1e-9, f"expected depth within 1e-9 of the diagonal, got {depth:.3g}"
    assert values < 1e-9, f"expected the analytic colour values, got an error of {values:.3g}"
    assert caster.GetNumberOfHigherOrderCells() == 48, f"expected 48, got {caster.GetNumberOfHigherOrderCells()}"
    assert caster.GetNumberOfRenderedCells() == 48
    assert messages.errors == [] and messages.warnings == [], (messages.errors, messages.warnings)


def test_rational_weights():
    field = hog.cubic_blob()
    plain = hog.grid(2, VTK_BEZIER_TETRAHEDRON, 3, {"f": field.value})
    count = plain.GetNumberOfPoints()
    _, _, reference = render(plain, field.iso)
    caster, messages, unit = render(hog.grid(2, VTK_BEZIER_TETRAHEDRON, 3, {"f": field.value},
                                             weights=np.ones(count)), field.iso)
    for name in reference:
        np.testing.assert_array_equal(unit[name], reference[name], err_msg=name)
    assert caster.GetNumberOfRationalCells() == 0 and messages.warnings == []
    weights = np.ones(count)
    point = int(plain.GetCell(0).GetPointId(12))
    weights[point] = 1.5
    users = sum(1 for c in range(plain.GetNumberOfCells())
                if point in [plain.GetCell(c).GetPointId(k) for k in range(20)])
    caster, messages, _ = render(hog.grid(2, VTK_BEZIER_TETRAHEDRON, 3, {"f": field.value}, weights=weights),
                                 field.iso)
    assert caster.GetNumberOfRationalCells() == users, f"expected {users}, got {caster.GetNumberOfRationalCells()}"
    assert caster.GetNumberOfRenderedCells() == 48 - users
    text = " ".join(messages.warnings)
    assert f"Skipped {users} rational Bezier cells" in text, text
