"""tetdsr.pyvista.add_isosurface in an off-screen pyvista.Plotter: the window's pixels against the
analytic sphere (inside one cell) seen by the plotter's camera, before and after the camera moves,
and the reduced-resolution cast while the mouse interacts."""
import os

import numpy as np
import pytest

pv = pytest.importorskip("pyvista")
import truth  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonCore import vtkFloatArray  # noqa: E402
from tetdsr.pyvista import add_isosurface  # noqa: E402

pv.OFF_SCREEN = True
W, H = 240, 180


@pytest.fixture()
def sphere(data):
    grid = pv.read(os.path.join(data, "sphere_in_cell.vtu"))
    centre = np.array(grid.field_data["SphereCentre"])
    radius = float(grid.field_data["SphereRadius"][0])
    return grid, centre, radius


def covered(shot, background):
    """Pixels (row i + j * W from the bottom, as the filter numbers them) unlike the background."""
    bottom_up = shot[::-1].reshape(-1, shot.shape[2])[:, :3]
    return np.any(bottom_up != np.array(background), axis=1)


def sphere_coverage(camera, centre, radius):
    origins, directions = truth.pixel_rays(camera.position, camera.focal_point, camera.up,
                                           camera.view_angle, W, H)
    quadric = truth.QuadraticQuadric(np.eye(3), np.zeros(3), -radius ** 2, centre)
    t, unsure = truth.first_hit_in_box(quadric, origins, directions, 0.0, -1.0, 1.0)
    return np.isfinite(t), unsure


def test_plotter_shows_the_exact_sphere_and_follows_the_camera(sphere):
    grid, centre, radius = sphere
    plotter = pv.Plotter(window_size=(W, H))
    plotter.set_background("black")
    surface = add_isosurface(plotter, grid, 0.0, "sphere", color="orange")
    plotter.camera.focal_point = centre
    plotter.camera.position = centre + np.array([0.4, -0.7, 1.3])
    plotter.camera.up = (0.0, 1.0, 0.0)
    plotter.camera.view_angle = 18.0
    first = plotter.screenshot(return_img=True)
    assert first.shape[:2] == (H, W), f"expected a {W} x {H} screenshot, got {first.shape}"
    expected, unsure = sphere_coverage(plotter.camera, centre, radius)
    ours = covered(first, (0, 0, 0))
    wrong = int(np.count_nonzero((ours != expected) & ~unsure))
    assert expected.sum() > 2000, f"expected the sphere on more than 2000 pixels, got {expected.sum()}"
    assert wrong == 0, f"expected the sphere on {expected.sum()} pixels, got {ours.sum()} ({wrong} differ)"
    # The window shows the cast image pixel for pixel (composited over the background).
    colors = surface.caster.GetOutput().GetPointData().GetArray("Colors")
    rgba = np.array([colors.GetTuple4(k) for k in range(W * H)])
    composited = np.round(rgba[:, :3] * rgba[:, 3:] / 255.0).astype(np.uint8)
    bottom_up = first[::-1].reshape(-1, 3)
    assert np.array_equal(bottom_up, composited), "expected the cast image in the window unchanged"
    # Orange, lit: red above green above blue on the surface.
    lit = bottom_up[ours].astype(int)
    assert np.all(lit[:, 0] >= lit[:, 1]) and np.all(lit[:, 1] >= lit[:, 2])

    plotter.camera.azimuth = 50.0
    plotter.camera.elevation = -20.0
    plotter.camera.focal_point = centre + np.array([0.06, 0.04, 0.0])  # the sphere moves off centre
    plotter.render()  # (PyVista's screenshot renders only the first time)
    second = plotter.screenshot(return_img=True)
    expected2, unsure2 = sphere_coverage(plotter.camera, centre, radius)
    ours2 = covered(second, (0, 0, 0))
    wrong = int(np.count_nonzero((ours2 != expected2) & ~unsure2))
    assert wrong == 0, f"after the camera move expected {expected2.sum()} pixels, got {ours2.sum()} ({wrong} differ)"
    assert np.count_nonzero(ours2 != ours) > 100, "expected the image to follow the camera"
    plotter.close()


def test_interaction_casts_coarse_then_full(sphere):
    grid, centre, radius = sphere
    plotter = pv.Plotter(window_size=(W, H))
    surface = add_isosurface(plotter, grid, 0.0, "sphere", interactive_scale=0.25)
    plotter.camera.focal_point = centre
    plotter.camera.position = centre + np.array([0.0, 0.0, 2.0])
    plotter.camera.up = (0.0, 1.0, 0.0)
    plotter.screenshot(return_img=True)  # the first render (PyVista's render() waits for it)
    assert tuple(surface.caster.GetImageSize()) == (W, H)
    interactor = plotter.iren.interactor
    interactor.InvokeEvent("StartInteractionEvent")
    plotter.camera.azimuth = 30.0
    plotter.render()
    assert tuple(surface.caster.GetImageSize()) == (W // 4, H // 4), (
        f"expected a {W // 4} x {H // 4} cast while interacting, got {surface.caster.GetImageSize()}")
    interactor.InvokeEvent("EndInteractionEvent")  # renders the still frame
    assert tuple(surface.caster.GetImageSize()) == (W, H), (
        f"expected a full {W} x {H} cast when the interaction ends, got {surface.caster.GetImageSize()}")
    shot = plotter.screenshot(return_img=True)
    expected, unsure = sphere_coverage(plotter.camera, centre, radius)
    background = tuple(int(round(255 * c)) for c in plotter.renderer.GetBackground())
    wrong = int(np.count_nonzero((covered(shot, background) != expected) & ~unsure))
    assert expected.sum() > 1000, f"expected the sphere on more than 1000 pixels, got {expected.sum()}"
    assert wrong == 0, f"expected the full-resolution sphere after the interaction, {wrong} pixels differ"
    surface.remove()
    assert plotter.renderer.GetLayer() == 0
    plotter.close()


# -- among the plotter's meshes, by depth; exact picks -----------------------------------------
DIAGONAL = np.sqrt(12.0)  # of sphere_in_cell.vtu's mesh, [-1, 1]^3


def display_rays(camera, xy):
    """Rays through display positions (x, y) (pixel (i, j)'s centre at (i + 0.5, j + 0.5)), by
    the filter's documented camera convention."""
    position = np.asarray(camera.position, float)
    forward = np.asarray(camera.focal_point, float) - position
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, camera.up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = np.tan(np.radians(camera.view_angle) / 2)
    x = ((2 * xy[:, :1] / W - 1) * half * W / H)
    y = ((2 * xy[:, 1:] / H - 1) * half)
    directions = forward + x * right + y * up
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return np.tile(position, (len(xy), 1)), directions


def box_hits(origins, directions, lo, hi):
    """The first t > 0 of each ray in the box [lo, hi] (inf on a miss), by slabs."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t1, t2 = (lo - origins) / directions, (hi - origins) / directions
        near = np.nanmax(np.minimum(t1, t2), axis=1)
        far = np.nanmin(np.maximum(t1, t2), axis=1)
    return np.where((near <= far) & (far > 0), np.maximum(near, 0.0), np.inf)


def right_clicks_on(plotter, quadric, rng, picked):
    """Right clicks at 40 random positions of the plotter (PyVista's picking), each after
    emptying `picked`; yields (x, y, exact hit, ray origin, ray direction, ray parameter) of those
    whose ray surely hits the analytic sphere, once the click has picked something."""
    for x, y in zip(rng.integers(60, 180, 40), rng.integers(40, 140, 40)):
        del picked[:]
        plotter.iren._mouse_right_button_click(int(x), int(y))
        origin, direction = display_rays(plotter.camera, np.array([[x, y]], float))
        t, unsure = truth.first_hit_in_box(quadric, origin, direction, 0.0, -1.0, 1.0)
        if unsure[0] or not np.isfinite(t[0]):
            continue
        assert picked, f"expected a pick at ({x}, {y})"
        yield x, y, origin[0] + t[0] * direction[0], origin, direction, t[0]


def with_linear_array(grid):
    """The grid with g = x + 2y - z, which its quadratic cells hold exactly."""
    grid = grid.copy()
    grid.point_data["g"] = grid.points @ np.array([1.0, 2.0, -1.0])
    return grid


def sphere_and_box_plotter(sphere):
    grid, centre, radius = sphere
    plotter = pv.Plotter(window_size=(W, H))
    plotter.set_background("black")
    # An unlit pure blue box cutting into the sphere: in front of it in some pixels, behind it in
    # others.
    lo, hi = centre + radius * np.array([0.3, -0.6, -1.4]), centre + radius * np.array([1.6, 0.5, 0.35])
    plotter.add_mesh(pv.Box(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2])), color=(0, 0, 255),
                     lighting=False)
    surface = add_isosurface(plotter, with_linear_array(grid), 0.0, "sphere", color="orange")
    plotter.camera.focal_point = centre
    plotter.camera.position = centre + np.array([0.4, -0.7, 1.3])
    plotter.camera.up = (0.0, 1.0, 0.0)
    plotter.camera.view_angle = 30.0
    return plotter, surface, lo, hi


def test_box_and_sphere_hide_each_other_by_exact_depth(sphere):
    grid, centre, radius = sphere
    plotter, surface, lo, hi = sphere_and_box_plotter(sphere)
    shot = plotter.screenshot(return_img=True)
    camera = plotter.camera
    origins, directions = truth.pixel_rays(camera.position, camera.focal_point, camera.up,
                                           camera.view_angle, W, H)
    quadric = truth.QuadraticQuadric(np.eye(3), np.zeros(3), -radius ** 2, centre)
    t_sphere, unsure = truth.first_hit_in_box(quadric, origins, directions, 0.0, -1.0, 1.0)
    t_box = box_hits(origins, directions, lo, hi)
    # Truth per pixel: 0 nothing, 1 the box, 2 the sphere (whichever is nearer).
    label = np.where(np.isfinite(t_sphere) & (t_sphere < t_box), 2, np.where(np.isfinite(t_box), 1, 0))
    pixels = shot[::-1].reshape(-1, 3).astype(int)
    seen = np.where(np.all(pixels == 0, axis=1), 0, np.where(np.all(pixels == [0, 0, 255], axis=1), 1, 2))
    # Pixels next to a change of the truth (silhouettes, the box's edges, where the two meet) are
    # shared by both sides (the box's edges are anti-aliased): not compared.
    grid2 = label.reshape(H, W)
    edge = np.zeros((H, W), bool)
    for dj in (-1, 0, 1):
        for di in (-1, 0, 1):
            shifted = np.roll(np.roll(grid2, dj, axis=0), di, axis=1)
            edge |= shifted != grid2
    compared = ~edge.reshape(-1) & ~unsure
    wrong = int(np.count_nonzero((seen != label) & compared))
    in_front = int(np.count_nonzero((label == 2) & np.isfinite(t_box) & compared))
    behind = int(np.count_nonzero((label == 1) & np.isfinite(t_sphere) & compared))
    # The window depth where the sphere shows: its exact hit through the plotter's projection.
    z = vtkFloatArray()
    plotter.render_window.GetZbufferData(0, 0, W - 1, H - 1, z)
    z = vtk_to_numpy(z).astype(np.float64)
    m = camera.GetCompositeProjectionTransformMatrix(plotter.renderer.GetTiledAspectRatio(), -1, 1)
    matrix = np.array([[m.GetElement(r, c) for c in range(4)] for r in range(4)])
    sphere_pixels = (label == 2) & compared
    hits = origins[sphere_pixels] + t_sphere[sphere_pixels, None] * directions[sphere_pixels]
    clip = np.c_[hits, np.ones(len(hits))] @ matrix.T
    depth = np.abs(z[sphere_pixels] - (0.5 * clip[:, 2] / clip[:, 3] + 0.5)).max()
    print(f"PyVista, box cutting into the exact sphere: {int(compared.sum())} pixels compared, "
          f"{wrong} wrong; the sphere in front of the box at {in_front}, behind it at {behind}; "
          f"window depth within {depth:.1e} of the exact hit's")
    assert in_front > 300 and behind > 100, "expected the box and the sphere to hide each other"
    assert wrong == 0, f"{wrong} pixels show the wrong prop"
    assert depth < 1e-4
    plotter.close()


def test_picks_at_random_positions_are_the_exact_hits(sphere):
    grid, centre, radius = sphere
    plotter, surface, lo, hi = sphere_and_box_plotter(sphere)
    plotter.screenshot(return_img=True)  # (casts)
    rng = np.random.default_rng(7)
    xy = np.c_[rng.uniform(0, W, 400), rng.uniform(0, H, 400)]
    origins, directions = display_rays(plotter.camera, xy)
    quadric = truth.QuadraticQuadric(np.eye(3), np.zeros(3), -radius ** 2, centre)
    t, unsure = truth.first_hit_in_box(quadric, origins, directions, 0.0, -1.0, 1.0)
    hits = misses = 0
    position = value = g = normal = 0.0
    for k, (x, y) in enumerate(xy):
        pick = surface.pick(x, y)
        if unsure[k]:
            continue
        assert (pick is not None) == bool(np.isfinite(t[k])), (x, y)
        if pick is None:
            misses += 1
            continue
        hits += 1
        exact = origins[k] + t[k] * directions[k]
        position = max(position, np.linalg.norm(np.array(pick.position) - exact) / DIAGONAL)
        value = max(value, abs(pick.value))  # the field |x - c|^2 - r^2 there: 0
        g = max(g, abs(pick.point_data["g"] - exact @ [1.0, 2.0, -1.0]))
        gradient = (exact - centre) / np.linalg.norm(exact - centre)
        normal = max(normal, np.linalg.norm(np.array(pick.normal) - gradient))
        assert pick.cell_id >= 0 and pick.iso_value_index == 0
    print(f"DirectSurface.pick: {hits} hits and {misses} misses at random display positions; "
          f"position within {position:.1e} of the diagonal, field value {value:.1e}, g {g:.1e}, "
          f"normal {normal:.1e}")
    assert hits > 50 and misses > 50
    assert position < 1e-9 and value < 1e-12 and g < 1e-12 and normal < 1e-9

    # PyVista's own point picking (right click, its default vtkPointPicker) gets the exact hit,
    # and the picked mesh holds the values there.
    picked = []
    plotter.enable_point_picking(
        callback=lambda point, picker: picked.append((point, picker.GetDataSet(), picker.GetPointId())),
        use_picker=True, show_message=False, show_point=False)
    error, clicks = 0.0, 0
    for x, y, exact, origin, direction, _ in right_clicks_on(plotter, quadric, rng, picked):
        point, mesh, point_id = picked[-1]
        if mesh is None or mesh.GetPointData().GetArray("g") is None:
            # Only a vertex of the box (vtkPointPicker picks points) within the picker's tolerance.
            assert np.isfinite(box_hits(origin, direction, lo, hi)[0]), (x, y)
            continue
        clicks += 1
        error = max(error, np.linalg.norm(point - exact) / DIAGONAL)
        g = mesh.GetPointData().GetArray("g").GetValue(point_id)
        assert abs(g - exact @ [1.0, 2.0, -1.0]) < 1e-12
    print(f"enable_point_picking: {clicks} clicks on the sphere, within {error:.1e} of the diagonal")
    assert clicks > 10 and error < 1e-9
    plotter.close()


def test_a_translucent_sphere_among_opaque_boxes(sphere):
    """A translucent surface is blended in VTK's translucent pass, depth-tested against the
    opaque props at its nearest crossing: where the box is in front of the sphere the window is
    the box's colour; where the whole sphere (both crossings) lies in front of the box or of the
    background, the cast image composited over it. (A box between the two crossings is the
    documented limit: not compared.)"""
    grid, centre, radius = sphere
    plotter = pv.Plotter(window_size=(W, H))
    plotter.set_background("black")
    # One box cutting into the sphere, one wholly behind it.
    boxes = [(centre + radius * np.array([0.3, -0.6, -1.4]), centre + radius * np.array([1.6, 0.5, 0.35])),
             (centre + radius * np.array([-1.0, -0.2, -3.0]), centre + radius * np.array([-0.1, 1.2, -1.2]))]
    for lo, hi in boxes:
        plotter.add_mesh(pv.Box(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2])),
                         color=(0, 0, 255), lighting=False)
    surface = add_isosurface(plotter, grid, 0.0, "sphere", color="orange", opacities=[0.5])
    plotter.camera.focal_point = centre
    plotter.camera.position = centre + np.array([0.4, -0.7, 1.3])
    plotter.camera.up = (0.0, 1.0, 0.0)
    plotter.camera.view_angle = 30.0
    shot = plotter.screenshot(return_img=True)
    assert surface.actor.GetForceTranslucent(), "expected the translucent surface in the translucent pass"
    camera = plotter.camera
    origins, directions = truth.pixel_rays(camera.position, camera.focal_point, camera.up,
                                           camera.view_angle, W, H)
    # Both crossings of the analytic sphere (the sphere lies inside the mesh's box).
    quadric = truth.QuadraticQuadric(np.eye(3), np.zeros(3), -radius ** 2, centre)
    t0, t1, relative = truth._roots(*quadric.along(origins, directions, 0.0))
    near, far = np.fmin(t0, t1), np.fmax(t0, t1)
    near, far = np.where(np.isfinite(near), near, np.inf), np.where(np.isfinite(far), far, np.inf)
    t_box = np.min([box_hits(origins, directions, lo, hi) for lo, hi in boxes], axis=0)
    # Truth per pixel: 0 background, 1 a box in front of the sphere (or no sphere), 2 the sphere
    # over the background, 3 the sphere wholly in front of a box, 4 a box between the crossings.
    label = np.select([np.isinf(t_box) & np.isinf(near), t_box < near, np.isinf(t_box),
                       far < t_box], [0, 1, 2, 3], 4)
    label2 = label.reshape(H, W)
    edge = np.zeros((H, W), bool)
    for dj in (-1, 0, 1):
        for di in (-1, 0, 1):
            edge |= np.roll(np.roll(label2, dj, axis=0), di, axis=1) != label2
    compared = ~edge.reshape(-1) & (relative > 1e-6) & (label != 4)
    colors = surface.caster.GetOutput().GetPointData().GetArray("Colors")
    cast = vtk_to_numpy(colors).astype(float)
    alpha = cast[:, 3:] / 255.0
    under = np.where((label == 3)[:, None] | (label == 1)[:, None], [0.0, 0.0, 255.0], 0.0)
    expected = np.where((label == 1)[:, None], under, cast[:, :3] * alpha + (1.0 - alpha) * under)
    pixels = shot[::-1].reshape(-1, 3).astype(float)
    error = np.abs(pixels - expected).max(axis=1)
    counts = {k: int(np.count_nonzero((label == k) & compared)) for k in range(4)}
    wrong = int(np.count_nonzero((error > 1.0) & compared))
    print(f"translucent sphere among opaque boxes: {int(compared.sum())} pixels compared (box in "
          f"front {counts[1]}, sphere over the background {counts[2]}, over a box {counts[3]}), "
          f"{wrong} off by more than 1 / 255 (largest {error[compared].max():.2f} / 255)")
    assert counts[1] > 300 and counts[2] > 300 and counts[3] > 300
    assert wrong == 0, f"expected every compared pixel within 1 / 255, got {wrong} beyond"
    plotter.close()


def test_surface_point_picking_is_exact(sphere):
    """PyVista's enable_surface_point_picking (its default vtkCellPicker) lands on the exact hit
    under the mouse."""
    grid, centre, radius = sphere
    plotter, surface, lo, hi = sphere_and_box_plotter(sphere)
    plotter.screenshot(return_img=True)
    picked = []
    plotter.enable_surface_point_picking(callback=lambda point: picked.append(np.array(point)),
                                         show_message=False, show_point=False)
    quadric = truth.QuadraticQuadric(np.eye(3), np.zeros(3), -radius ** 2, centre)
    rng = np.random.default_rng(11)
    error, clicks = 0.0, 0
    for x, y, exact, origin, direction, t in right_clicks_on(plotter, quadric, rng, picked):
        if box_hits(origin, direction, lo, hi)[0] < t:
            continue  # the box in front of the sphere (the cell picker picks the box)
        clicks += 1
        error = max(error, np.linalg.norm(picked[-1] - exact) / DIAGONAL)
    print(f"enable_surface_point_picking: {clicks} clicks on the sphere, within {error:.1e} of the diagonal")
    assert clicks > 10 and error < 1e-9
    plotter.close()


def test_a_matplotlib_colour_map(sphere):
    """cmap: a PyVista lookup table maps the colour array (x, held exactly) on the surface."""
    grid, centre, radius = sphere
    grid = with_linear_array(grid)
    plotter = pv.Plotter(window_size=(W, H))
    plotter.set_background("black")
    surface = add_isosurface(plotter, grid, 0.0, "sphere", color_by="g", cmap="viridis",
                             clim=(-1.0, 1.0), ambient=1.0, diffuse=0.0, specular=0.0)
    plotter.camera.focal_point = centre
    plotter.camera.position = centre + np.array([0.0, 0.0, 1.5])
    plotter.camera.up = (0.0, 1.0, 0.0)
    shot = plotter.screenshot(return_img=True)
    pixels = shot[::-1].reshape(-1, 3).astype(int)
    lit = np.any(pixels != 0, axis=1)
    assert lit.sum() > 1000, f"expected the coloured sphere on more than 1000 pixels, got {lit.sum()}"
    # Unlit: each pixel is viridis at g of its pick, within a colour table step.
    table = pv.LookupTable(cmap="viridis")
    rng = np.random.default_rng(3)
    worst = 0
    for k in rng.choice(np.nonzero(lit)[0], 60, replace=False):
        j, i = divmod(int(k), W)
        pick = surface.pick(i + 0.5, j + 0.5)
        rgb = [0.0, 0.0, 0.0]
        table.SetRange(-1.0, 1.0)
        table.GetColor(pick.point_data["g"], rgb)
        worst = max(worst, int(np.abs(np.round(np.array(rgb) * 255) - pixels[k]).max()))
    print(f"cmap viridis: {int(lit.sum())} pixels, colour within {worst} / 255 of the map at the pick")
    assert worst <= 3
    plotter.close()
