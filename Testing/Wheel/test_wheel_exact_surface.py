"""The exact isosurface as data (issue 37) through the wheel: tetdsr.vtkDirectSurfaceContour,
tetdsr.pyvista.exact_contour and tetdsr._core.extract_exact_surface, against analytic truth.

The mesh is [-1, 1]^3 as 6 straight quadratic tetrahedra holding f = |x - c|^2 - r^2, c the
centroid of cell 0 and r half its inradius: f is quadratic, so each cell holds it exactly, and its
zero set is a sphere strictly inside cell 0 with every nodal value positive (no sign change at
the nodes: vtkContourFilter finds nothing). The iso-value -3/4 r^2 gives the sphere of radius r/2.
Truth is the sphere's: its distance | |x - c| - R |, area 4 pi R^2, the volume 8 - 4/3 pi R^3 of
{f >= iso}, the integrals of x (c_x times the area, by symmetry) and of |x - c|^2 (R^2 times the
area) over it."""
import math

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkFiltersCore import vtkContourFilter

import scenes  # (puts Testing/Python, with shared_helpers, on the path)
from kuhn_lattice import lattice
from shared_helpers import Messages
from tetdsr import _core, vtkDirectSurfaceContour

CUBE_VOLUME, CUBE_DIAGONAL = 8.0, math.sqrt(12.0)
# A relative tolerance the conservative certified bound makes quick (the default, 1e-3, can take
# tens of seconds on curved surfaces).
QUICK = 1e-2


def sphere_in_one_cell():
    """The grid (fields "sphere", "x", "r2" = |x - c|^2), c and r."""
    points, cells = lattice(1)
    corners = points[cells[0, :4]]
    centre = corners.mean(axis=0)
    # Inradius of a tetrahedron: 3 V / (sum of its faces' areas).
    volume = abs(np.linalg.det(corners[1:] - corners[0])) / 6.0
    faces = sum(0.5 * np.linalg.norm(np.cross(corners[b] - corners[a], corners[c] - corners[a]))
                for a, b, c in ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2)))
    radius = 0.5 * 3.0 * volume / faces
    r2 = np.sum((points - centre) ** 2, axis=1)
    assert np.all(r2 - radius ** 2 > 0.0), "expected every nodal value above the iso-value 0"
    grid = scenes.grid(points, cells, {"sphere": r2 - radius ** 2, "x": points[:, 0].copy(), "r2": r2})
    return grid, centre, radius


def field_array(polydata, name):
    array = polydata.GetFieldData().GetArray(name)
    assert array is not None, f"expected field data {name!r}"
    return vtk_to_numpy(array).copy()


def run(grid, values, **settings):
    contour = vtkDirectSurfaceContour()
    contour.SetInputData(grid)
    for i, v in enumerate(values):
        contour.SetValue(i, v)
    for name, value in settings.items():
        getattr(contour, "Set" + name)(value)
    told = Messages(contour)
    contour.Update()
    return contour, contour.GetOutput(), told


def edge_counts(triangles):
    """How many triangles use each undirected edge."""
    edges = np.sort(triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    return np.unique(edges, axis=0, return_counts=True)[1]


def triangles_to_sphere(points, triangles, centre, radius, n=8):
    """The largest distance to the sphere of points of the triangles (a barycentric lattice of
    (n + 1)(n + 2)/2 points on each)."""
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    keep = i + j <= n
    w = np.column_stack([i[keep], j[keep], n - i[keep] - j[keep]]) / n
    samples = np.einsum("sk,tkd->tsd", w, points[triangles])
    return float(np.max(np.abs(np.linalg.norm(samples - centre, axis=2) - radius)))


def sphere_to_triangles(points, triangles, centre, radius, rays=1500):
    """A bound on the largest distance from the sphere to the triangles: rays from the centre
    (Fibonacci directions u) crossing the triangles at t (Moller-Trumbore); the sphere's point
    c + r u is within |t - r| of the crossing. Every ray must cross (the surface is closed around
    c)."""
    k = np.arange(rays) + 0.5
    polar, azimuth = np.arccos(1.0 - 2.0 * k / rays), math.pi * (1.0 + 5.0 ** 0.5) * k
    u = np.column_stack([np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)])
    a, b, c = (points[triangles[:, m]] for m in range(3))
    e1, e2, s = b - a, c - a, centre - a
    worst = 0.0
    for chunk in np.array_split(u, max(1, rays * len(triangles) // 200_000)):  # (memory)
        p = np.cross(chunk[:, None, :], e2[None])
        det = np.einsum("tkd,kd->tk", p, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            alpha = np.einsum("tkd,kd->tk", p, s) / det
            q = np.cross(s, e1)
            beta = np.einsum("td,kd->tk", chunk, q) / det
            t = np.einsum("kd,kd->k", e2, q)[None, :] / det
        eps = 1e-12
        inside = (alpha >= -eps) & (beta >= -eps) & (alpha + beta <= 1 + eps) & (t > 0)
        gap = np.where(inside, np.abs(t - radius), np.inf).min(axis=1)
        assert np.all(np.isfinite(gap)), f"expected every ray from the centre to cross the surface, " \
                                         f"{int(np.sum(~np.isfinite(gap)))} of {len(chunk)} did not"
        worst = max(worst, float(gap.max()))
    return worst


@pytest.mark.parametrize("absolute", [False, True], ids=["relative", "absolute"])
def test_sphere_inside_one_cell(absolute):
    grid, centre, radius = sphere_in_one_cell()
    radii = [radius, radius / 2]
    values = [0.0, -0.75 * radius ** 2]  # |x - c|^2 - r^2 = iso: spheres of radius r and r / 2
    # Tolerances the conservative certified bound makes quick (the lead's advice: 1e-2 or 2e-2).
    settings = dict(AbsoluteTolerance=0.05 * radius) if absolute else dict(Tolerance=QUICK)
    contour, out, told = run(grid, values, **settings)
    assert told.errors == [], f"expected no error, got {told.errors}"
    assert told.warnings == [], f"expected no warning, got {told.warnings}"
    points = vtk_to_numpy(out.GetPoints().GetData()).astype(np.float64)
    triangles = vtk_to_numpy(out.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    offsets = vtk_to_numpy(out.GetPolys().GetOffsetsArray())
    assert np.array_equal(offsets, np.arange(0, 3 * len(triangles) + 1, 3)), "expected triangles only"
    cell_ids = vtk_to_numpy(out.GetCellData().GetArray("vtkOriginalCellIds"))
    iso = vtk_to_numpy(out.GetCellData().GetArray("IsoValue"))
    assert out.GetCellData().GetArray("vtkOriginalCellIds").GetDataTypeAsString() == "idtype"
    assert np.all(cell_ids == 0), f"expected every triangle in cell 0, got cells {np.unique(cell_ids)}"
    assert np.array_equal(field_array(out, "IsoValues"), values)

    # The bound asked: the relative tolerance's default times the valid cells' diagonal, or the
    # absolute tolerance; every piece drawn within it.
    bound = float(field_array(out, "DistanceBound")[0])
    expected_bound = 0.05 * radius if absolute else QUICK * CUBE_DIAGONAL
    # (the core's box is single precision, rounded outward: up to 2^-22 above)
    assert expected_bound <= bound <= expected_bound * (1 + 2 ** -22), f"expected DistanceBound {expected_bound}, got {bound}"
    largest = float(field_array(out, "LargestCertifiedBound")[0])
    assert 0.0 < largest <= bound, f"expected 0 < LargestCertifiedBound <= {bound}, got {largest}"
    assert field_array(out, "Subcells")[0] > 0
    assert field_array(out, "SizeCertifiedSubcells")[0] >= 0
    for name in ("UnresolvedSubcells", "BoundaryEdges", "NonManifoldEdges"):
        assert field_array(out, name)[0] == 0, f"expected {name} 0, got {field_array(out, name)[0]}"

    normals = vtk_to_numpy(out.GetPointData().GetNormals())
    assert out.GetPointData().GetNormals().GetName() == "Normals"
    x_values = vtk_to_numpy(out.GetPointData().GetArray("x"))
    r2_values = vtk_to_numpy(out.GetPointData().GetArray("r2"))
    areas, volumes = field_array(out, "Area"), field_array(out, "Volume")
    area_errors, volume_errors = field_array(out, "AreaError"), field_array(out, "VolumeError")
    flat_areas = field_array(out, "FlatArea")
    x_integrals, x_errors = field_array(out, "x Integral"), field_array(out, "x IntegralError")
    r2_integrals, r2_errors = field_array(out, "r2 Integral"), field_array(out, "r2 IntegralError")
    for i, (value, r) in enumerate(zip(values, radii)):
        mine = triangles[iso == value]
        assert len(mine) >= 20, f"iso-value {i}: expected a surface, got {len(mine)} triangles"
        counts = edge_counts(mine)
        assert np.all(counts == 2), f"iso-value {i}: expected every edge in 2 triangles, got " \
                                    f"{np.bincount(counts).tolist()} edges by triangle count"
        used = np.unique(mine)
        p = points[used]
        on_sphere = float(np.max(np.abs(np.linalg.norm(p - centre, axis=1) - r))) / r
        assert on_sphere <= 1e-9, f"iso-value {i}: expected vertices on the sphere within 1e-9 r, got {on_sphere:.3g}"
        gradient = (p - centre) / np.linalg.norm(p - centre, axis=1, keepdims=True)
        normal_error = float(np.max(np.linalg.norm(normals[used] - gradient, axis=1)))
        assert normal_error <= 1e-9, f"iso-value {i}: expected the exact unit normals, got {normal_error:.3g} off"
        a, b, c = (points[mine[:, k]] for k in range(3))
        outward = np.einsum("ij,ij->i", np.cross(b - a, c - a), (a + b + c) / 3 - centre)
        assert np.all(outward > 0), f"iso-value {i}: expected triangles facing higher values (out)"
        # x and |x - c|^2 are held exactly by the cells: interpolated, they are the vertices' own.
        assert np.max(np.abs(x_values[used] - p[:, 0])) <= 1e-14, "expected x interpolated at the vertices"
        assert np.max(np.abs(r2_values[used] - np.sum((p - centre) ** 2, axis=1))) <= 1e-14, \
            "expected |x - c|^2 interpolated at the vertices"

        # Hausdorff distance, both ways, within the certified bound.
        there = triangles_to_sphere(points, mine, centre, r)
        back = sphere_to_triangles(points, mine, centre, r)
        assert max(there, back) <= largest * (1 + 1e-9), \
            f"iso-value {i}: expected the Hausdorff distance within {largest:.3g}, got {there:.3g} / {back:.3g}"

        # Integrals against the sphere's.
        area = 4 * math.pi * r * r
        checks = (("area", areas[i], area, area_errors[i]),
                  ("volume", volumes[i], CUBE_VOLUME - 4 / 3 * math.pi * r ** 3, volume_errors[i]),
                  ("integral of x", x_integrals[i], centre[0] * area, x_errors[i]),
                  ("integral of |x - c|^2", r2_integrals[i], r * r * area, r2_errors[i]))
        for what, got, exact, estimate in checks:
            scale = CUBE_VOLUME if what == "volume" else area
            assert abs(got - exact) <= estimate + 1e-9 * scale, \
                f"iso-value {i}: expected {what} {exact!r} within {estimate:.3g}, got {got!r} " \
                f"({abs(got - exact):.3g} off)"
        assert flat_areas[i] > 0, f"iso-value {i}: expected the triangles' area, got {flat_areas[i]}"
        assert contour.GetArea(i) == areas[i] and contour.GetVolume(i) == volumes[i]
        assert contour.GetAreaError(i) == area_errors[i] and contour.GetVolumeError(i) == volume_errors[i]
        print(f"{'absolute' if absolute else 'relative'} bound {bound:.3g}, iso-value {value:.4g}: "
              f"{len(mine)} triangles, Hausdorff {max(there, back):.3g} (certified {largest:.3g}), "
              f"area {abs(areas[i] - area) / area:.2g} off (estimate {area_errors[i] / area:.2g})")

    # Linear contouring of the same grid sees no sign change at any node: nothing.
    linear = vtkContourFilter()
    linear.SetInputData(grid)
    linear.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "sphere")
    linear.SetValue(0, 0.0)
    linear.Update()
    assert linear.GetOutput().GetNumberOfPoints() == 0, \
        f"expected vtkContourFilter to find nothing, got {linear.GetOutput().GetNumberOfPoints()} points"


def test_integrals_off_and_getters():
    grid, _, _ = sphere_in_one_cell()
    contour, out, told = run(grid, [0.0], ComputeIntegrals=False, Tolerance=QUICK)
    assert told.errors == [] and out.GetNumberOfPolys() > 0
    for name in ("Area", "Volume", "x Integral"):
        assert out.GetFieldData().GetArray(name) is None, f"expected no {name} without integrals"
    assert math.isnan(contour.GetArea(0)) and math.isnan(contour.GetVolume(5))
    assert contour.GetComputeIntegrals() is False and contour.GetTolerance() == QUICK
    assert vtkDirectSurfaceContour().GetTolerance() == _core.DEFAULT_RELATIVE_TOLERANCE


def core_error(**settings):
    """The core's sentence for these exact-surface settings."""
    checked, messages = _core.ExactSurfaceSettings(), _core.Messages()
    for name, value in settings.items():
        setattr(checked, name, value)
    assert not _core.check_exact_surface_settings(checked, messages)
    assert len(messages.errors) == 1, messages.errors
    return messages.errors[0]


@pytest.mark.parametrize("setter, value, core", [
    ("Tolerance", -1e-3, dict(iso_values=[0.0], relative_tolerance=-1e-3)),
    ("AbsoluteTolerance", -0.5, dict(iso_values=[0.0], tolerance=-0.5)),
    ("AbsoluteTolerance", math.inf, dict(iso_values=[0.0], tolerance=math.inf)),
    ("Value", math.nan, dict(iso_values=[math.nan])),
])
def test_bad_settings_give_the_core_error(setter, value, core):
    pv = pytest.importorskip("pyvista")
    from tetdsr.pyvista import exact_contour
    grid, _, _ = sphere_in_one_cell()
    expected = core_error(**core)
    contour = vtkDirectSurfaceContour()
    contour.SetInputData(grid)
    contour.SetValue(0, 0.0)
    if setter == "Value":
        contour.SetValue(0, value)
    else:
        getattr(contour, "Set" + setter)(value)
    told = Messages(contour)
    contour.Update()
    assert told.errors == [expected], f"expected {[expected]}, got {told.errors}"
    assert contour.GetOutput().GetNumberOfPoints() == 0, "expected an empty output"
    arguments = dict(isosurfaces=0.0) | {
        "Tolerance": dict(tolerance=value), "AbsoluteTolerance": dict(absolute_tolerance=value),
        "Value": dict(isosurfaces=[value])}[setter]
    with pytest.raises(ValueError) as raised:
        exact_contour(pv.wrap(grid), arguments.pop("isosurfaces"), "sphere", **arguments)
    assert str(raised.value) == expected, f"expected {expected!r}, got {str(raised.value)!r}"


def test_binding_refuses_settings_and_names_short_arrays():
    grid, _, _ = sphere_in_one_cell()
    mesh, messages = _core.PreparedMesh(), _core.Messages()
    points = vtk_to_numpy(grid.GetPoints().GetData())
    cells = grid.GetCells()
    field = vtk_to_numpy(grid.GetPointData().GetArray("sphere"))
    assert mesh.prepare(points, np.full(grid.GetNumberOfCells(), 24, np.uint8),  # VTK_QUADRATIC_TETRA
                        vtk_to_numpy(cells.GetOffsetsArray()), vtk_to_numpy(cells.GetConnectivityArray()),
                        field, field_name="sphere", messages=messages), messages.errors
    settings = _core.ExactSurfaceSettings()
    settings.iso_values = [0.0]
    settings.relative_tolerance = -1.0
    with pytest.raises(ValueError) as raised:
        _core.extract_exact_surface(mesh, settings, [], messages)
    assert str(raised.value) == core_error(iso_values=[0.0], relative_tolerance=-1.0)
    settings.relative_tolerance = QUICK
    surface = _core.extract_exact_surface(mesh, settings, [("short", field[:-1].copy())], messages)
    assert any("short" in text for text in messages.errors), \
        f"expected an error naming the array 'short', got {messages.errors}"
    messages.clear()
    surface = _core.extract_exact_surface(mesh, settings, [("f32", field.astype(np.float32))], messages)
    assert surface is not None and messages.errors == [], messages.errors
    assert surface.points.shape[1] == 3 and surface.triangles.dtype == np.int64
    assert surface.arrays[0].shape == (len(surface.points), 1)
    assert len(surface.integrals) == 1 and surface.cell_ids.shape == (len(surface.triangles),)


def test_pyvista_exact_contour_matches_the_filter():
    pv = pytest.importorskip("pyvista")
    from tetdsr.pyvista import exact_contour
    grid, centre, radius = sphere_in_one_cell()
    _, out, _ = run(grid, [0.0], Tolerance=QUICK)
    surface = exact_contour(pv.wrap(grid), 0.0, "sphere", tolerance=QUICK)
    assert isinstance(surface, pv.PolyData)
    assert surface.n_points == out.GetNumberOfPoints() and surface.n_points > 0, \
        f"expected {out.GetNumberOfPoints()} points, got {surface.n_points}"
    assert float(surface.field_data["Area"][0]) == pytest.approx(
        float(field_array(out, "Area")[0]), rel=1e-12)
    for name in ("Normals", "x", "r2", "sphere"):
        assert name in surface.point_data, f"expected point data {name!r}"
    for name in ("vtkOriginalCellIds", "IsoValue"):
        assert name in surface.cell_data, f"expected cell data {name!r}"
    several = exact_contour(pv.wrap(grid), [0.0, -0.75 * radius ** 2], tolerance=QUICK, integrals=False)
    assert list(several.field_data["IsoValues"]) == [0.0, -0.75 * radius ** 2]
    assert "Area" not in several.field_data
    with pytest.raises(ValueError, match="exact_contour: isosurfaces is an empty list"):
        exact_contour(pv.wrap(grid), [])
    with pytest.raises(TypeError, match="exact_contour: tolerance must be a number"):
        exact_contour(pv.wrap(grid), 0.0, tolerance="fine")
    with pytest.raises(ValueError, match="exact_contour: the grid is empty"):
        exact_contour(pv.UnstructuredGrid(), 0.0)
