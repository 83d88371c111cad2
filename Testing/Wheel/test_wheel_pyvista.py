"""tetdsr.pyvista.add_isosurface in an off-screen pyvista.Plotter: the window's pixels against the
analytic sphere (inside one cell) seen by the plotter's camera, before and after the camera moves,
and the reduced-resolution cast while the mouse interacts."""
import os

import numpy as np
import pytest

pv = pytest.importorskip("pyvista")
import truth  # noqa: E402
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
