"""tetdsr.vtkDirectSurfaceRayCaster (the wheel: pip's VTK, the pip-built core) against analytic
truth (truth.py: exact ray/quadric intersection in numpy), and its behaviour on bad input."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPlane, vtkUnstructuredGrid

import scenes  # (puts Testing/Python, with shared_helpers, on the path)
import truth
from shared_helpers import Messages
from tetdsr import vtkDirectSurfaceRayCaster


def outputs(caster):
    caster.Update()
    pd = caster.GetOutput().GetPointData()
    return {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)).copy() for k in range(pd.GetNumberOfArrays())}


def rays(camera, width, height):
    return truth.pixel_rays(camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
                            camera.GetViewAngle(), width, height,
                            bool(camera.GetParallelProjection()), camera.GetParallelScale())


def compare(out, t, excluded, diagonal, normals_truth=None, min_pixels=1000):
    """Coverage, depth (relative to the diagonal) and normals against the truth."""
    ours = np.isfinite(out["Depth"])
    exact = np.isfinite(t)
    assert exact.sum() >= min_pixels, f"expected at least {min_pixels} surface pixels in the truth, got {exact.sum()}"
    wrong = int(np.count_nonzero((ours != exact) & ~excluded))
    assert wrong == 0, f"expected coverage {exact.sum()} pixels, got {ours.sum()} ({wrong} differ)"
    both = ours & exact & ~excluded
    depth = float(np.max(np.abs(out["Depth"][both] - t[both]))) / diagonal
    assert depth < 1e-12, f"expected depth within 1e-12 of the diagonal, got {depth:.3g}"
    if normals_truth is not None:
        n = normals_truth[both] / np.linalg.norm(normals_truth[both], axis=1, keepdims=True)
        angle = float(np.max(np.arccos(np.clip(np.einsum("ij,ij->i", out["Normals"][both], n), -1, 1))))
        assert angle < 1e-6, f"expected normals within 1e-6 rad of the gradient, got {angle:.3g}"
    assert np.all(out["Colors"][~ours] == 0), "expected a (0, 0, 0, 0) background"
    assert np.all(out["CellId"][~ours] == -1), "expected cell id -1 on misses"
    return int(both.sum()), depth


@pytest.mark.parametrize("parallel", [False, True])
def test_cube27_against_per_cell_quadrics(data, parallel):
    caster, keep, diagonal = scenes.cube(vtkDirectSurfaceRayCaster, data, parallel)
    mesh, camera = keep
    out = outputs(caster)
    points = vtk_to_numpy(mesh.GetPoints().GetData())
    cells = vtk_to_numpy(mesh.GetCells().GetConnectivityArray()).reshape(-1, 10)
    values = vtk_to_numpy(mesh.GetPointData().GetArray("distance"))
    origins, directions = rays(camera, 220, 180)
    t, cell, grazing = truth.first_hit_in_cells(truth.cell_quadrics(points, cells, values),
                                                origins, directions, 0.8)
    hit = np.isfinite(t) & ~grazing
    quadrics = truth.cell_quadrics(points, cells, values)
    gradients = np.zeros_like(origins)
    for c, (quadric, _, _) in enumerate(quadrics):
        here = hit & (cell == c)
        gradients[here] = quadric.gradient(origins[here] + t[here, None] * directions[here])
    compared, depth = compare(out, t, grazing, diagonal, np.where(hit[:, None], gradients, 1.0), 5000)
    assert np.array_equal(out["CellId"][hit], cell[hit]), "expected the cells the truth hits"
    assert caster.GetNumberOfRenderedCells() == 6
    print(f"cube27 {'parallel' if parallel else 'perspective'}: {compared} pixels, depth error {depth:.3g}")


@pytest.mark.parametrize("parallel", [False, True])
def test_sphere_inside_one_cell(data, parallel):
    caster, keep, diagonal = scenes.sphere_in_cell(vtkDirectSurfaceRayCaster, data)
    mesh, camera = keep
    if parallel:
        camera.ParallelProjectionOn()
        camera.SetParallelScale(0.3)
    fd = mesh.GetFieldData()
    centre = np.array([fd.GetArray("SphereCentre").GetValue(k) for k in range(3)])
    radius = fd.GetArray("SphereRadius").GetValue(0)
    sphere = truth.QuadraticQuadric(np.eye(3), np.zeros(3), -radius ** 2, centre)
    out = outputs(caster)
    origins, directions = rays(camera, 160, 120)
    t, unsure = truth.first_hit_in_box(sphere, origins, directions, 0.0, -1.0, 1.0)
    hits = np.where(np.isfinite(t)[:, None], origins + np.where(np.isfinite(t), t, 0)[:, None] * directions, 0)
    compared, depth = compare(out, t, unsure, diagonal, np.where(np.isfinite(t)[:, None], hits - centre, 1.0), 1000)
    assert np.all(out["CellId"][np.isfinite(out["Depth"])] == 0), "expected every hit in cell 0"
    print(f"sphere in a cell, {'parallel' if parallel else 'perspective'}: {compared} pixels, depth error {depth:.3g}")


def test_random_quadric_on_a_lattice():
    """A random indefinite quadric (seeded) held exactly by 162 cells: each iso-value's first
    crossing inside the box, several iso-values at once."""
    rng = np.random.default_rng(20)
    A = rng.normal(size=(3, 3))
    quadric = truth.QuadraticQuadric((A + A.T) / 2, rng.normal(size=3), 0.0)
    points, cells = scenes.lattice(3)
    mesh = scenes.grid(points, cells, {"q": quadric(points)})
    camera = scenes.camera((2.3, -1.7, 3.1), view_angle=35.0)
    camera.SetViewUp(0.1, 0.9, 0.2)
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(mesh)
    values = [0.2, -0.4]
    for i, v in enumerate(values):
        caster.SetValue(i, v)
    caster.SetCamera(camera)
    caster.SetImageSize(180, 150)
    out = outputs(caster)
    origins, directions = rays(camera, 180, 150)
    t = np.full(len(origins), np.inf)
    unsure = np.zeros(len(origins), bool)
    for v in values:
        tv, uv = truth.first_hit_in_box(quadric, origins, directions, v, -1.0, 1.0)
        t = np.minimum(t, tv)
        unsure |= uv
    hits = origins + np.where(np.isfinite(t), t, 0)[:, None] * directions
    compared, depth = compare(out, t, unsure, mesh.GetLength(),
                              np.where(np.isfinite(t)[:, None], quadric.gradient(hits), 1.0), 2000)
    assert caster.GetNumberOfRenderedCells() == 162
    print(f"random quadric: {compared} pixels, depth error {depth:.3g}")


def test_output_layout_threads_and_default_camera(data):
    caster, keep, _ = scenes.sphere_in_cell(vtkDirectSurfaceRayCaster, data)
    image = {}
    for threads in (1, 2, 0):
        caster.SetNumberOfThreads(threads)
        image[threads] = outputs(caster)
    for name in image[1]:
        assert np.array_equal(image[1][name], image[2][name]), f"{name}: expected the same image on 1 and 2 threads"
        assert np.array_equal(image[1][name], image[0][name]), f"{name}: expected the same image on all cores"
    result = caster.GetOutput()
    assert result.GetDimensions() == (160, 120, 1)
    pd = result.GetPointData()
    assert pd.GetScalars().GetName() == "Colors" and pd.GetScalars().GetNumberOfComponents() == 4
    assert pd.GetNormals().GetName() == "Normals"
    assert pd.GetArray("CellId").GetDataTypeAsString() == "idtype"
    # The default camera is ResetCamera's: down -z at the centre, at radius / sin(15 degrees).
    default = vtkDirectSurfaceRayCaster()
    default.SetInputData(keep[0])
    default.SetImageSize(160, 160)
    depth = outputs(default)["Depth"]
    mesh = keep[0]
    fd = mesh.GetFieldData()
    centre = np.array([fd.GetArray("SphereCentre").GetValue(k) for k in range(3)])
    radius = fd.GetArray("SphereRadius").GetValue(0)
    distance = np.sqrt(3.0) / np.sin(np.radians(15))
    origins, directions = truth.pixel_rays((0, 0, distance), (0, 0, 0), (0, 1, 0), 30.0, 160, 160)
    t, unsure = truth.first_hit_in_box(truth.QuadraticQuadric(np.eye(3), np.zeros(3), -radius ** 2, centre),
                                       origins, directions, 0.0, -1, 1)
    wrong = int(np.count_nonzero((np.isfinite(depth) != np.isfinite(t)) & ~unsure))
    assert wrong == 0 and np.isfinite(t).sum() > 100, f"expected coverage {np.isfinite(t).sum()}, got {np.isfinite(depth).sum()}"


def test_edits_re_execute(data):
    """Camera, plane and array edits in place must reach the filter (its pipeline time)."""
    caster, keep, _ = scenes.quadric_lattice(vtkDirectSurfaceRayCaster, data)
    mesh, camera, plane = keep
    first = outputs(caster)
    camera.Azimuth(10)
    moved = outputs(caster)
    assert not np.array_equal(first["Depth"], moved["Depth"]), "expected a new image after a camera edit"
    plane.SetOrigin(0.0, 0.0, -0.2)
    cut = outputs(caster)
    assert not np.array_equal(moved["Depth"], cut["Depth"]), "expected a new image after a plane edit"
    values = vtk_to_numpy(mesh.GetPointData().GetArray("quadric"))
    values += 0.1
    mesh.GetPointData().GetArray("quadric").Modified()
    shifted = outputs(caster)
    assert not np.array_equal(cut["Depth"], shifted["Depth"]), "expected a rebuilt scene after a field edit"


def bad(mesh, configure=None):
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(mesh)
    caster.SetValue(0, 0.0)
    caster.SetImageSize(40, 30)
    messages = Messages(caster)
    if configure:
        configure(caster)
    caster.Update()
    return caster, messages


def sphere_mesh(data):
    mesh = vtkUnstructuredGrid()
    mesh.DeepCopy(scenes.read(data, "sphere_in_cell.vtu"))
    return mesh


def test_errors_name_the_problem(data):
    cases = [
        (vtkUnstructuredGrid(), None, "The input mesh is empty"),
        (sphere_mesh(data), lambda c: c.SetInputArrayToProcess(0, 0, 0, 0, "pressure"), "No point array named 'pressure'"),
        (sphere_mesh(data), lambda c: c.SetNumberOfContours(0), "No iso-value"),
        (sphere_mesh(data), lambda c: c.SetImageSize(0, 30), "ImageSize 0 x 30 pixels"),
        (sphere_mesh(data), lambda c: c.SetImageSize(100000, 100000), "VTK images hold fewer than 2^31 pixels"),
        (sphere_mesh(data), lambda c: c.ColorByArrayOn(), "no colour array is chosen"),
        (sphere_mesh(data), lambda c: (c.ColorByArrayOn(), c.SetInputArrayToProcess(1, 0, 0, 0, "sphere"),
                                       c.SetColorArrayComponent(2)), "ColorArrayComponent 2 is out of range"),
        (sphere_mesh(data), lambda c: [c.AddClippingPlane(vtkPlane()) for _ in range(7)], "7 clipping planes: at most 6"),
        (sphere_mesh(data), lambda c: c.SetIsoValueColor(-1, 1, 0, 0), "index -1 is outside"),
    ]
    for mesh, configure, expected in cases:
        _, messages = bad(mesh, configure)
        assert any(expected in e for e in messages.errors), f"expected an error with '{expected}', got {messages.errors}"
    zero = vtkPlane()
    zero.SetNormal(0.0, 0.0, 0.0)
    _, messages = bad(sphere_mesh(data), lambda c: c.AddClippingPlane(zero))
    assert any("zero normal" in e for e in messages.errors), messages.errors
    mesh = sphere_mesh(data)
    mesh.GetPointData().SetActiveScalars(None)
    _, messages = bad(mesh)
    assert any("No point scalars" in e for e in messages.errors), messages.errors
    camera = scenes.camera((0.0, 0.0, 5.0))
    camera.SetViewUp(0.0, 0.0, 1.0)  # along the direction of view
    _, messages = bad(sphere_mesh(data), lambda c: c.SetCamera(camera))
    assert any("view up is zero or parallel" in e for e in messages.errors), messages.errors
    far = scenes.camera((0.0, 0.0, 1e12))
    _, messages = bad(sphere_mesh(data), lambda c: c.SetCamera(far))
    assert any("scene diagonals from the scene" in e for e in messages.errors), messages.errors


def test_hostile_meshes_are_counted_not_crashed(data):
    # Short field array.
    mesh = sphere_mesh(data)
    short = numpy_to_vtk(np.zeros(5))
    short.SetName("short")
    mesh.GetPointData().AddArray(short)
    _, messages = bad(mesh, lambda c: c.SetInputArrayToProcess(0, 0, 0, 0, "short"))
    assert any("has 5 tuples for 27 points" in e for e in messages.errors), messages.errors
    # Node ids out of range and negative: counted as invalid, never read.
    mesh = sphere_mesh(data)
    connectivity = vtk_to_numpy(mesh.GetCells().GetConnectivityArray())
    connectivity[3] = 10 ** 12
    connectivity[15] = -7
    mesh.GetCells().GetConnectivityArray().Modified()
    caster, messages = bad(mesh)
    assert caster.GetNumberOfInvalidIdCells() == 2, f"expected 2 invalid-id cells, got {caster.GetNumberOfInvalidIdCells()}"
    assert any("Skipped 2 cells with node ids outside [0, 27)" in w for w in messages.warnings), messages.warnings
    assert messages.errors == []
    # Offsets that claim other counts: malformed, counted.
    mesh = sphere_mesh(data)
    offsets = vtk_to_numpy(mesh.GetCells().GetOffsetsArray())
    offsets[1] = 9
    mesh.GetCells().GetOffsetsArray().Modified()
    caster, messages = bad(mesh)
    assert caster.GetNumberOfMalformedCells() == 2, f"expected 2 malformed cells, got {caster.GetNumberOfMalformedCells()}"
    assert caster.GetNumberOfRenderedCells() == 4
    # NaN values: cells skipped and counted.
    mesh = sphere_mesh(data)
    mesh.GetPointData().GetArray("sphere").SetValue(0, float("nan"))
    caster, messages = bad(mesh)
    users = int(np.count_nonzero(np.any(vtk_to_numpy(mesh.GetCells().GetConnectivityArray()).reshape(-1, 10) == 0, axis=1)))
    assert caster.GetNumberOfNonFiniteCells() == users, f"expected {users} non-finite cells, got {caster.GetNumberOfNonFiniteCells()}"
    # Every cell skipped: an error, no image.
    mesh = sphere_mesh(data)
    for p in range(mesh.GetNumberOfPoints()):
        mesh.GetPointData().GetArray("sphere").SetValue(p, float("inf"))
    _, messages = bad(mesh)
    assert any("all 6 input cells were skipped" in e for e in messages.errors), messages.errors


def test_float32_points_and_int32_connectivity_give_the_same_image(data):
    reference = scenes.read(data, "cube27.vtu")
    single = vtkUnstructuredGrid()
    single.DeepCopy(reference)
    points = vtkPoints()
    points.SetDataTypeToFloat()
    points.DeepCopy(reference.GetPoints())
    single.SetPoints(points)
    single.GetCells().ConvertTo32BitStorage()
    images = []
    for mesh in (reference, single):
        caster, messages = bad(mesh, lambda c: c.SetValue(0, 0.8))
        assert messages.errors == []
        images.append(outputs(caster))
    assert np.isfinite(images[0]["Depth"]).sum() > 100
    for name in images[0]:
        assert np.array_equal(images[0][name], images[1][name]), f"{name}: expected the same image"


def test_abort_empties_the_output(data):
    caster, keep, _ = scenes.sphere_in_cell(vtkDirectSurfaceRayCaster, data)
    messages = Messages(caster)

    def abort_halfway(obj, event):
        if obj.GetProgress() >= 0.5:
            obj.SetAbortExecute(1)

    progress = []
    caster.AddObserver(vtkCommand.ProgressEvent, lambda obj, event: progress.append(obj.GetProgress()))
    caster.AddObserver(vtkCommand.ProgressEvent, abort_halfway)
    caster.Update()
    assert any("Aborted after" in w for w in messages.warnings), messages.warnings
    assert caster.GetOutput().GetNumberOfPoints() == 0, "expected an emptied output after abort"
    assert len(progress) > 5, f"expected progress reports, got {progress}"


def test_pick_equals_the_image_at_pixel_centres(data):
    """Pick at pixel (i, j)'s centre is the hit the image shows there (depth, cell, normal), on the
    nested ellipsoids cut and capped by a plane; the point arrays interpolated at the hit; None
    off the surface; WindowDepth is the hit's through a projection; bad arguments raise."""
    caster, keep, diagonal = scenes.quadric_lattice(vtkDirectSurfaceRayCaster, data)
    assert caster.Pick(10.5, 10.5) is None, "expected no pick before an execution"
    out = outputs(caster)
    width, height = 200, 160
    rng = np.random.default_rng(5)
    caps = surfaces = misses = 0
    for i, j in zip(rng.integers(0, width, 600), rng.integers(0, height, 600)):
        p = j * width + i
        pick = caster.Pick(i + 0.5, j + 0.5)
        if not np.isfinite(out["Depth"][p]):
            assert pick is None, (i, j)
            misses += 1
            continue
        assert pick is not None, (i, j)
        assert pick.ray_parameter == out["Depth"][p] and pick.cell_id == out["CellId"][p], (i, j)
        assert np.allclose(pick.normal, out["Normals"][p], atol=1e-12), (i, j)
        assert abs(pick.point_data["x"] - pick.position[0]) < 1e-12  # x is held exactly
        if pick.clipping_plane_id >= 0:
            assert pick.iso_value_index == -1 and abs(pick.position[2] - 0.3) < 1e-12
            caps += 1
        else:
            assert pick.iso_value_index in (0, 1)
            assert abs(pick.value - (0.3, 0.8)[pick.iso_value_index]) < 1e-12
            surfaces += 1
    print(f"filter Pick at pixel centres: {surfaces} on a surface, {caps} on the cap, {misses} "
          f"misses, each equal to the image's pixel")
    assert caps > 20 and surfaces > 20 and misses > 20
    # WindowDepth: 0.5 z / w + 0.5 of each hit through a projection (here a plain perspective).
    camera = keep[1]
    matrix = camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1)
    window = caster.WindowDepth(matrix)
    assert window.shape == (height, width) and window.dtype == np.float32
    m = np.array([[matrix.GetElement(r, c) for c in range(4)] for r in range(4)])
    origins, directions = rays(camera, width, height)
    hit = np.isfinite(out["Depth"])
    points = origins[hit] + out["Depth"][hit, None] * directions[hit]
    clip = np.c_[points, np.ones(len(points))] @ m.T
    expected = 0.5 * clip[:, 2] / clip[:, 3] + 0.5
    assert np.abs(window.reshape(-1)[hit] - expected).max() < 1e-6
    assert np.all(window.reshape(-1)[~hit] == 1.0)
    with pytest.raises(TypeError):
        caster.Pick("a", 1.0)
    with pytest.raises(ValueError):
        caster.WindowDepth(np.eye(3))
    assert caster.Pick(float("nan"), 3.0) is None and caster.Pick(-5.0, 1e9) is None


def test_ghost_cells_are_left_out_and_counted(data):
    # sphere_in_cell's sphere lies inside cell 0: flagged as another piece's duplicate (VTK's
    # vtkGhostType DUPLICATECELL) it is not drawn, counted and not warned about; a flag that
    # describes a drawn cell (EXTERIORCELL) leaves it drawn; a ghost array of another type is an
    # error naming it.
    def with_ghosts(values, dtype=np.uint8):
        mesh = sphere_mesh(data)
        ghosts = numpy_to_vtk(np.array(values, dtype=dtype), deep=1)
        ghosts.SetName("vtkGhostType")
        mesh.GetCellData().AddArray(ghosts)
        return mesh

    caster, messages = bad(with_ghosts([1, 0, 0, 0, 0, 0]), lambda c: c.SetValue(0, 0.0))
    out = outputs(caster)
    assert caster.GetNumberOfGhostCells() == 1 and caster.GetNumberOfRenderedCells() == 5
    assert messages.errors == [] and messages.warnings == [], (messages.errors, messages.warnings)
    assert not np.isfinite(out["Depth"]).any(), "the sphere is in the ghost cell: nothing drawn"
    caster, messages = bad(with_ghosts([16, 0, 0, 0, 0, 0]))
    out = outputs(caster)
    assert caster.GetNumberOfGhostCells() == 0 and np.isfinite(out["Depth"]).sum() > 0
    caster, messages = bad(with_ghosts([0] * 6, np.int32))
    assert any("cell ghost array 'vtkGhostType'" in e and "unsigned 8-bit" in e
               for e in messages.errors), messages.errors
