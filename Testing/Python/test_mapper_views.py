"""vtkDirectSurfaceMapper under every camera and view set-up VTK offers (issue 39): perspective
and parallel, clipping ranges up to a far / near ratio of 1e17 and an explicit infinite-far-plane
projection, explicit and off-axis projections (head-tracked, and a CAVE's walls as renderers of
one window), viewports side by side and a renderer on layer 1 over layer 0, tiled and magnified
images (vtkWindowToImageFilter's scales, vtkRenderLargeImage), actor matrices that shear, mirror
and scale unevenly and a part inside a vtkAssembly, windows resized between renders, and the
camera inside the sphere and exactly on it.

Each set-up is drawn twice in the same window: once with the mapper's sphere (the level set
|x|^2 = 0.5 of quadratic tetrahedra, which hold it exactly), once with a fine vtkSphereSource
(400 x 400 facets). Truth per pixel is the exact ray/sphere root of the ray through the pixel
centre, the ray made from the renderer's composite projection (and the actor's matrix) by
unprojecting NDC z = -1 and z = 0 (both finite for every camera, whatever its far plane), its
window depth 0.5 z / w + 0.5. Compared: coverage (only pixels within one pixel of the true
silhouette may differ), the mapper's window depth tightly against the truth, the polygons'
loosely (llvmpipe rasterises polygon depth to about 1e-3). A table of set-up -> mismatched pixels
and worst depth errors is printed at the end.

Beside the table: picks, vtkDirectSurfacePicker, hardware selection, translucency over opaque
geometry and a level-of-detail frame through the infinite far plane; lit actor matrices against
the polygons' shading; a singular projection's error; and the filter (vtkDirectSurfaceRayCaster),
whose rays follow only a camera's position, focal point, view up and angle, refusing a camera that
holds more."""
import math
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkFiltersHybrid import vtkRenderLargeImage
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkCommonTransforms import vtkTransform
from vtkmodules.vtkRenderingCore import (vtkActor, vtkAssembly, vtkCamera, vtkHardwareSelector,
                                         vtkPolyDataMapper, vtkRenderer, vtkRenderWindowInteractor,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)

from shared_helpers import Messages
from test_mapper import H, RADIUS2, W, grid, rgba, shared_window, zbuffer
from tetdsr import (vtkDirectSurfaceMapper, vtkDirectSurfacePick, vtkDirectSurfacePicker,
                    vtkDirectSurfaceRayCaster)

MESH = grid()
RADIUS = math.sqrt(RADIUS2)
# The mapper writes gl_FragDepth from a float texture into a 24- or 32-bit depth buffer: 4 units
# of 2^-24 cover both roundings (Testing/Python/test_mapper.py's tolerance).
DEPTH_TOLERANCE = 4 * 2.0 ** -24
# The polygons: llvmpipe's rasterised depth (up to ~1e-3) and the facets' sag (r (1 - cos(pi /
# 400)) = 2e-5 of the radius), largest at the silhouette where depth is steep: 3.6e-3 measured
# in the parallel view.
POLYGON_DEPTH_TOLERANCE = 5e-3
EYE = (2.2, 1.6, 3.0)
CENTRE = (0.05, -0.03, 0.02)
RED, GREEN = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)
# Actor matrices (rows): a shear, a mirror (det < 0) and an uneven scale.
SHEAR = [[1, 0.4, 0, 0.1], [0, 1, 0.3, -0.05], [0.2, 0, 1, 0], [0, 0, 0, 1]]
MIRROR = [[-1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, -0.1], [0, 0, 0, 1]]
SCALE = [[1.6, 0, 0, 0], [0, 0.5, 0, 0.05], [0, 0, 1.1, 0], [0, 0, 0, 1]]
RESULTS = []


# --- The two spheres ----------------------------------------------------------------------------
def sphere_actor(kind, color=RED, flat=True):
    """The exact sphere (kind "mapper") or the polygonal one ("polygons"), unlit in a pure colour
    when `flat` (so a pixel's colour says which sphere covers it)."""
    if kind == "mapper":
        mapper = vtkDirectSurfaceMapper()
        mapper.SetInputData(MESH)
        mapper.SetValue(0, RADIUS2)
        mapper.ScalarVisibilityOff()
    else:
        source = vtkSphereSource()
        source.SetRadius(RADIUS)
        source.SetThetaResolution(400)
        source.SetPhiResolution(400)
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(source.GetOutputPort())
        mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*color)
    if flat:
        actor.GetProperty().SetAmbient(1.0)
        actor.GetProperty().SetDiffuse(0.0)
        actor.GetProperty().SetSpecular(0.0)
    return actor


def add_renderer(window, actor, viewport=(0.0, 0.0, 1.0, 1.0), eye=EYE, layer=0):
    renderer = vtkRenderer()
    renderer.SetViewport(*viewport)
    renderer.SetLayer(layer)
    renderer.SetBackground(0.0, 0.0, 0.0)
    renderer.AddActor(actor)
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*eye)
    camera.SetFocalPoint(*CENTRE)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(30)
    # (Fixed: the mapper's input, the lattice, is bigger than the polygon sphere, and
    # ResetCameraClippingRange would give the two different depths.)
    camera.SetClippingRange(0.5, 8.0)
    return renderer


def as_array(matrix):
    return np.array([[matrix.GetElement(r, c) for c in range(4)] for r in range(4)])


def as_vtk(array):
    matrix = vtkMatrix4x4()
    for r in range(4):
        for c in range(4):
            matrix.SetElement(r, c, float(array[r][c]))
    return matrix


def model_to_ndc(renderer, actor, aspect=None):
    """The actor's model coordinates to normalised device coordinates, as the renderer's last
    frame drew them (the camera after the render: renderers reset clipping ranges)."""
    if aspect is None:
        width, height = renderer.GetSize()
        aspect = width / height
    camera = renderer.GetActiveCamera()
    return as_array(camera.GetCompositeProjectionTransformMatrix(aspect, -1, 1)) @ \
        as_array(actor.GetMatrix())


# --- Truth ----------------------------------------------------------------------------------------
def sphere_depth(to_ndc, width, height):
    """Per pixel of a width x height image seen through `to_ndc` (model to NDC), the window depth
    of the ray's first crossing of |x|^2 = RADIUS2 at or beyond the near plane (1: none, or beyond
    the far plane). The ray runs from the point at NDC z = -1 through the one at z = 0."""
    inverse = np.linalg.inv(to_ndc)
    i, j = np.meshgrid(np.arange(width), np.arange(height))
    x = 2 * (i.ravel() + 0.5) / width - 1
    y = 2 * (j.ravel() + 0.5) / height - 1

    def unproject(z):
        p = np.c_[x, y, np.full_like(x, z), np.ones_like(x)] @ inverse.T
        return p[:, :3] / p[:, 3:]
    origin = unproject(-1.0)
    direction = unproject(0.0) - origin
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    b = np.sum(origin * direction, axis=1)
    c = np.sum(origin * origin, axis=1) - RADIUS2
    disc = b * b - c
    root = np.sqrt(np.maximum(disc, 0.0))
    t = np.where(-b - root >= 0.0, -b - root, -b + root)  # the far crossing from inside
    hit = (disc >= 0.0) & (t >= 0.0)
    depth = np.ones(len(t))
    points = origin[hit] + t[hit, None] * direction[hit]
    clip = np.c_[points, np.ones(len(points))] @ to_ndc.T
    depth[hit] = 0.5 * clip[:, 2] / clip[:, 3] + 0.5
    depth[depth > 1.0] = 1.0  # beyond the far plane: clipped
    return depth.reshape(height, width)


def place(image, region, part):
    """`part` written into `image` at region (x, y, width, height), bottom-up rows."""
    x, y, w, h = region
    image[y:y + h, x:x + w] = part


def view_truth(renderer, actor, size, scale=(1, 1)):
    """The truth of one renderer's viewport in an image of `size` (the window's size times
    `scale`: a tiled image); 1 outside the viewport."""
    width, height = size[0] * scale[0], size[1] * scale[1]
    x0, y0, x1, y1 = renderer.GetViewport()
    # vtkViewport's pixel rounding of a normalised viewport.
    lo = (int(x0 * width + 0.5), int(y0 * height + 0.5))
    hi = (int(x1 * width + 0.5), int(y1 * height + 0.5))
    w, h = hi[0] - lo[0], hi[1] - lo[1]
    depth = np.ones((height, width))
    place(depth, (lo[0], lo[1], w, h), sphere_depth(model_to_ndc(renderer, actor, w / h), w, h))
    return depth


def near_silhouette(covered):
    """Pixels within one pixel (3 x 3) of a change of coverage."""
    edge = np.zeros_like(covered)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            shifted = np.roll(np.roll(covered, dy, 0), dx, 1)
            edge |= shifted != covered
    # (np.roll wraps around: the image's border rows and columns compare with the far side; a
    # viewport's border is no silhouette of ours.)
    return edge


def rendered_depth(window):
    window.Render()
    return zbuffer(window)


# --- Comparison -----------------------------------------------------------------------------------
class Views(unittest.TestCase):
    def compare(self, name, truth, mapper_z, polygon_z, depth=True, minimum_pixels=500):
        """Coverage of the mapper and of the polygons against the truth away from the true
        silhouette; the mapper's depth tightly, the polygons' loosely, where both cover."""
        expected = truth < 1
        away = ~near_silhouette(expected)
        row = {"name": name, "covered": int(expected.sum())}
        for kind, z in (("mapper", mapper_z), ("polygons", polygon_z)):
            covered = z < 1
            row[kind + " wrong"] = int(((covered != expected) & away).sum())
            both = covered & expected & away
            row[kind + " depth"] = float(np.abs(z - truth)[both].max()) if depth and both.any() \
                else float("nan")
        RESULTS.append(row)
        print("%-44s %6d px  mapper: %4d wrong, depth %.1e   polygons: %4d wrong, depth %.1e"
              % (name, row["covered"], row["mapper wrong"], row["mapper depth"],
                 row["polygons wrong"], row["polygons depth"]))
        self.assertGreater(row["covered"], minimum_pixels, "the set-up must show the sphere")
        self.assertEqual(row["polygons wrong"], 0, "the polygon reference must pass")
        self.assertEqual(row["mapper wrong"], 0,
                         "%s: expected the exact sphere's %d pixels, got %d pixels wrong"
                         % (name, row["covered"], row["mapper wrong"]))
        if depth:
            self.assertLess(row["polygons depth"], POLYGON_DEPTH_TOLERANCE)
            self.assertLess(row["mapper depth"], DEPTH_TOLERANCE,
                            "%s: expected window depth within %.1e of the exact, got %.1e"
                            % (name, DEPTH_TOLERANCE, row["mapper depth"]))

    def both(self, build, capture=rendered_depth, truth=None):
        """build(window, kind) -> [(renderer, actor)], drawn by capture(window) once with the
        mapper and once with the polygons; the truth of the mapper's views (after its frame),
        nearest over views unless `truth` says otherwise. Returns truth, mapper and polygon
        images; no error or warning may be reported."""
        images = {}
        for kind in ("mapper", "polygons"):
            window = shared_window()
            views = build(window, kind)
            messages = Messages(views[0][1].GetMapper()) if kind == "mapper" else None
            images[kind] = capture(window)
            if kind == "mapper":
                self.assertEqual(messages.errors + messages.warnings, [])
                size = window.GetSize()
                scale = (images[kind].shape[1] // size[0], images[kind].shape[0] // size[1])
                exact = truth(views, size, scale) if truth else \
                    np.min([view_truth(r, a, size, scale) for r, a in views], axis=0)
        return exact, images["mapper"], images["polygons"]

    def single(self, name, configure=None, actor_matrix=None, eye=EYE, minimum_pixels=500):
        """One renderer filling the window, its camera (and actor) set by the callbacks."""
        def build(window, kind):
            actor = sphere_actor(kind)
            if actor_matrix is not None:
                actor.SetUserMatrix(as_vtk(actor_matrix))
            renderer = add_renderer(window, actor, eye=eye)
            if configure:
                configure(renderer.GetActiveCamera())
            return [(renderer, actor)]
        self.compare(name, *self.both(build), minimum_pixels=minimum_pixels)

    # --- Projections --------------------------------------------------------------------------
    def test_perspective(self):
        self.single("perspective")

    def test_parallel(self):
        def parallel(camera):
            camera.ParallelProjectionOn()
            camera.SetParallelScale(0.9)
        self.single("parallel", parallel)

    def test_clipping_range_ratio_1e8(self):
        self.single("clipping range 1e-5 .. 1e3", lambda c: c.SetClippingRange(1e-5, 1e3))

    def test_clipping_range_ratio_1e17(self):
        # At far / near = 1e17 vtkCamera's matrix rounds to the infinite-far-plane one.
        self.single("clipping range 1e-3 .. 1e14", lambda c: c.SetClippingRange(1e-3, 1e14))

    def test_parallel_clipping_range_ratio_1e17(self):
        def parallel(camera):
            camera.ParallelProjectionOn()
            camera.SetParallelScale(0.9)
            camera.SetClippingRange(1e-3, 1e14)
        self.single("parallel, clipping range 1e-3 .. 1e14", parallel)

    def test_explicit_infinite_far_plane(self):
        def infinite(camera):
            near, aspect = 0.5, W / H
            f = 1.0 / math.tan(math.radians(camera.GetViewAngle()) / 2)
            projection = [[f / aspect, 0, 0, 0], [0, f, 0, 0], [0, 0, -1, -2 * near],
                          [0, 0, -1, 0]]
            camera.SetExplicitProjectionTransformMatrix(as_vtk(projection))
            camera.UseExplicitProjectionTransformMatrixOn()
        self.single("explicit infinite far plane", infinite)

    def test_explicit_asymmetric_frustum(self):
        def frustum(camera):
            # glFrustum(l, r, b, t, n, f) with the window shifted right and down.
            left, right, bottom, top, near, far = -0.1, 0.35, -0.25, 0.08, 0.6, 40.0
            projection = [
                [2 * near / (right - left), 0, (right + left) / (right - left), 0],
                [0, 2 * near / (top - bottom), (top + bottom) / (top - bottom), 0],
                [0, 0, -(far + near) / (far - near), -2 * far * near / (far - near)],
                [0, 0, -1, 0]]
            camera.SetExplicitProjectionTransformMatrix(as_vtk(projection))
            camera.UseExplicitProjectionTransformMatrixOn()
        self.single("explicit asymmetric frustum", frustum)

    def test_explicit_orthographic(self):
        def orthographic(camera):
            # glOrtho(l, r, b, t, n, f), off centre.
            left, right, bottom, top, near, far = -0.7, 1.3, -0.9, 0.6, 0.5, 30.0
            projection = [[2 / (right - left), 0, 0, -(right + left) / (right - left)],
                          [0, 2 / (top - bottom), 0, -(top + bottom) / (top - bottom)],
                          [0, 0, -2 / (far - near), -(far + near) / (far - near)],
                          [0, 0, 0, 1]]
            camera.SetExplicitProjectionTransformMatrix(as_vtk(projection))
            camera.UseExplicitProjectionTransformMatrixOn()
        self.single("explicit orthographic, off centre", orthographic)

    def test_camera_model_and_user_transforms(self):
        def transforms(camera):
            model = vtkMatrix4x4()
            model.SetElement(0, 1, 0.25)  # a sheared world
            model.SetElement(1, 3, 0.1)
            camera.SetModelTransformMatrix(model)
            user = vtkTransform()  # applied to the projection: an uneven zoom and a shift
            user.Translate(0.1, -0.05, 0.0)
            user.Scale(1.2, 0.9, 1.0)
            camera.SetUserTransform(user)
        self.single("camera model and user transforms", transforms)

    def test_window_centre_and_view_shear(self):
        def shifted(camera):
            camera.SetWindowCenter(0.3, -0.2)
            camera.SetViewShear(0.15, -0.1, 1.0)  # about the focal point (1 x the distance)
        self.single("window centre and view shear", shifted)

    def test_off_axis_head_tracked(self):
        def head_tracked(camera):
            # A 1.6 x 1.2 screen in the plane z = 1.2 facing +z, the eye off its axis.
            camera.UseOffAxisProjectionOn()
            camera.SetScreenBottomLeft(-0.9, -0.7, 1.2)
            camera.SetScreenBottomRight(0.7, -0.7, 1.2)
            camera.SetScreenTopRight(0.7, 0.5, 1.2)
            camera.SetEyePosition([0.6, 0.4, 3.1])
            camera.SetClippingRange(0.5, 20.0)
        self.single("off-axis, head-tracked eye", head_tracked)

    def test_pick_and_translucency_through_an_infinite_far_plane(self):
        # The mapper's Pick (the ray through a display position) and the ray limits of a
        # translucent sphere over opaque geometry both unproject through the view's matrix.
        window = shared_window()
        actor = sphere_actor("mapper", flat=False)
        renderer = add_renderer(window, actor)
        camera = renderer.GetActiveCamera()
        camera.SetClippingRange(1e-3, 1e14)
        window.Render()
        to_ndc = model_to_ndc(renderer, actor)
        truth = sphere_depth(to_ndc, W, H)
        pick = vtkDirectSurfacePick()
        worst, picked = 0.0, 0
        for j in range(0, H, 7):
            for i in range(0, W, 7):
                if near_silhouette(truth < 1)[j, i]:
                    continue
                found = actor.GetMapper().Pick(i + 0.5, j + 0.5, renderer, actor, pick)
                self.assertEqual(found, bool(truth[j, i] < 1), "pixel (%d, %d)" % (i, j))
                if found:
                    picked += 1
                    p = np.array(pick.GetPosition())
                    worst = max(worst, abs(np.dot(p, p) - RADIUS2))
                    clip = to_ndc @ np.r_[p, 1.0]
                    self.assertLess(abs(0.5 * clip[2] / clip[3] + 0.5 - truth[j, i]), 1e-9)
        print("picks at 1e-3 .. 1e14: %d hits, worst | |p|^2 - r^2 | = %.1e" % (picked, worst))
        self.assertGreater(picked, 60)
        self.assertLess(worst, 1e-9)
        # vtkDirectSurfacePicker (a segment from VTK's picking frustum) there too.
        picker = vtkDirectSurfacePicker()
        for x, y in ((80, 60), (70, 55), (90, 65), (85, 50)):
            self.assertTrue(picker.Pick(x, y, 0, renderer), "picker at (%d, %d)" % (x, y))
            p = np.array(picker.GetPickPosition())
            self.assertLess(abs(np.dot(p, p) - RADIUS2), 1e-9)

        # A translucent sphere over an opaque plane through its centre: the same picture at the
        # clipping ranges [0.5, 8] and [1e-3, 1e14] (the opaque depth bounds the rays; at the
        # infinite far plane the depth buffer resolves distance to ~1e-3 here: only pixels next
        # to the plane's cut through the sphere may differ).
        def translucent(clipping_range):
            window = shared_window()
            sphere = sphere_actor("mapper", flat=False)
            sphere.GetProperty().SetOpacity(0.5)
            plane = vtkPlaneSource()
            plane.SetOrigin(-1.5, -1.5, 0.0)
            plane.SetPoint1(1.5, -1.5, 0.0)
            plane.SetPoint2(-1.5, 1.5, 0.0)
            plane_mapper = vtkPolyDataMapper()
            plane_mapper.SetInputConnection(plane.GetOutputPort())
            wall = vtkActor()
            wall.SetMapper(plane_mapper)
            wall.GetProperty().SetColor(0.2, 0.3, 1.0)
            renderer = add_renderer(window, sphere)
            renderer.AddActor(wall)
            renderer.GetActiveCamera().SetClippingRange(*clipping_range)
            window.Render()
            return rgba(window)[..., :3]
        usual, infinite = translucent((0.5, 8.0)), translucent((1e-3, 1e14))
        differ = np.abs(usual - infinite).max(axis=2) > 3
        print("translucent over opaque: %d of %d pixels differ by more than 3 / 255"
              % (differ.sum(), differ.size))
        self.assertGreater(int((usual.sum(axis=2) > 0).sum()), 5000)
        self.assertLess(int(differ.sum()), 40)

    def test_singular_projection_reported(self):
        # An explicit projection matrix that cannot be inverted defines no rays: polygons vanish
        # (VTK says nothing); the mapper draws nothing either, and says why, once per render.
        window = shared_window()
        actor = sphere_actor("mapper")
        renderer = add_renderer(window, actor)
        flat = vtkMatrix4x4()
        flat.SetElement(2, 2, 0.0)  # every depth projects to z = 0: singular
        renderer.GetActiveCamera().SetExplicitProjectionTransformMatrix(flat)
        renderer.GetActiveCamera().UseExplicitProjectionTransformMatrixOn()
        messages = Messages(actor.GetMapper())
        window.Render()
        covered = int((zbuffer(window) < 1).sum())
        window.Render()
        print("singular projection: %d pixels drawn, errors: %s" % (covered, messages.errors))
        self.assertEqual(covered, 0)
        self.assertEqual(len(messages.errors), 2)
        self.assertIn("projection matrix is singular or not finite", messages.errors[0])
        pick = vtkDirectSurfacePick()
        self.assertFalse(actor.GetMapper().Pick(80.5, 60.5, renderer, actor, pick))
        self.assertEqual(len(messages.errors), 3)

    def test_hardware_selection_through_an_infinite_far_plane(self):
        # vtkHardwareSelector's cells of the whole window: the same at the clipping ranges
        # [0.5, 8] and [1e-3, 1e14] (the same rays), and the cells the pixels' picks hit.
        selected = {}
        for clipping_range in ((0.5, 8.0), (1e-3, 1e14)):
            window = shared_window()
            actor = sphere_actor("mapper")
            renderer = add_renderer(window, actor)
            renderer.GetActiveCamera().SetClippingRange(*clipping_range)
            window.Render()
            selector = vtkHardwareSelector()
            selector.SetRenderer(renderer)
            selector.SetArea(0, 0, W - 1, H - 1)
            selector.SetFieldAssociation(vtkDataObject.FIELD_ASSOCIATION_CELLS)
            selection = selector.Select()
            cells = set()
            for n in range(selection.GetNumberOfNodes()):
                ids = selection.GetNode(n).GetSelectionList()
                cells.update(ids.GetValue(k) for k in range(ids.GetNumberOfTuples()))
            selected[clipping_range[1]] = cells
        pick = vtkDirectSurfacePick()
        picked = set()
        for j in range(0, H, 3):
            for i in range(0, W, 3):
                if actor.GetMapper().Pick(i + 0.5, j + 0.5, renderer, actor, pick):
                    picked.add(pick.GetCellId())
        print("hardware selection: %d cells at far 8, %d at far 1e14; picks on every third pixel "
              "hit %d of them" % (len(selected[8.0]), len(selected[1e14]), len(picked)))
        self.assertGreater(len(selected[1e14]), 20)
        self.assertEqual(selected[1e14], selected[8.0])
        self.assertLessEqual(picked, selected[1e14])

    def test_interactive_frame_through_an_infinite_far_plane(self):
        # A frame cast at 2 pixels a ray (level of detail) through the 1e17 clipping range: the
        # same picture as the still frame of a window of the cast's size (same rays).
        window = shared_window()
        actor = sphere_actor("mapper")
        renderer = add_renderer(window, actor)
        renderer.GetActiveCamera().SetClippingRange(1e-3, 1e14)
        mapper = actor.GetMapper()
        mapper.AutoAdjustSampleDistancesOff()
        mapper.SetInteractiveImageSampleDistance(2)
        interactor = vtkRenderWindowInteractor()  # (no event loop: a still frame is cast at once)
        interactor.SetRenderWindow(window)
        interactor.SetStillUpdateRate(0.0001)
        window.SetDesiredUpdateRate(15)
        window.Render()
        self.assertEqual(tuple(mapper.GetLastCastSize()), (W // 2, H // 2))
        interactive = zbuffer(window) < 1
        window.SetDesiredUpdateRate(0.0001)
        window.SetSize(W // 2, H // 2)
        window.Render()
        cast = zbuffer(window) < 1
        truth = sphere_depth(model_to_ndc(renderer, actor), W // 2, H // 2) < 1
        upscaled = np.repeat(np.repeat(cast, 2, axis=0), 2, axis=1)
        away = ~near_silhouette(np.repeat(np.repeat(truth, 2, axis=0), 2, axis=1))
        wrong = int(((interactive != upscaled) & away).sum())
        print("interactive frame at 1e-3 .. 1e14: %d covered, %d differ from the cast upscaled; "
              "the cast %d wrong" % (interactive.sum(), wrong, ((cast != truth) & ~near_silhouette(truth)).sum()))
        self.assertGreater(int(interactive.sum()), 1000)
        self.assertEqual(wrong, 0)
        self.assertEqual(int(((cast != truth) & ~near_silhouette(truth)).sum()), 0)

    # --- Several renderers ---------------------------------------------------------------------
    def test_viewports_side_by_side(self):
        def build(window, kind):
            views = []
            for viewport, eye in (((0.0, 0.0, 0.5, 1.0), EYE), ((0.5, 0.0, 1.0, 1.0), (-2.5, 0.4, 2.2))):
                actor = sphere_actor(kind)
                views.append((add_renderer(window, actor, viewport, eye), actor))
            return views
        self.compare("two viewports side by side", *self.both(build))

    def test_cave_walls(self):
        def build(window, kind):
            # Two walls of a CAVE: the front wall (z = -1.5) and the left wall (x = -1.5), each a
            # renderer with an off-axis camera from one tracked eye.
            eye = [0.6, 0.2, 0.9]  # the sphere straddles the walls' corner
            walls = (((0.0, 0.0, 0.5, 1.0), [(-1.5, -1.0, 1.5), (-1.5, -1.0, -1.5), (-1.5, 1.0, -1.5)]),
                     ((0.5, 0.0, 1.0, 1.0), [(-1.5, -1.0, -1.5), (1.5, -1.0, -1.5), (1.5, 1.0, -1.5)]))
            views = []
            for viewport, (bottom_left, bottom_right, top_right) in walls:
                actor = sphere_actor(kind)
                renderer = add_renderer(window, actor, viewport)
                camera = renderer.GetActiveCamera()
                camera.SetPosition(0, 0, 0)
                camera.SetFocalPoint(0, 0, -1)
                camera.UseOffAxisProjectionOn()
                camera.SetScreenBottomLeft(*bottom_left)
                camera.SetScreenBottomRight(*bottom_right)
                camera.SetScreenTopRight(*top_right)
                camera.SetEyePosition(eye)
                camera.SetClippingRange(0.05, 20.0)
                views.append((renderer, actor))
            return views
        exact, mine, polygons = self.both(build)
        for wall, half in (("left", exact[:, :W // 2]), ("front", exact[:, W // 2:])):
            self.assertGreater(int((half < 1).sum()), 500, "the %s wall shows the sphere" % wall)
        self.compare("CAVE: front and left walls, off-axis", exact, mine, polygons)

    def test_layer_over_layer(self):
        # A second renderer on layer 1 (a green sphere seen from elsewhere) over layer 0 (red):
        # per pixel, layer 1's sphere where it covers, else layer 0's. Compared by colour.
        def build(window, kind):
            window.SetNumberOfLayers(2)
            below, above = sphere_actor(kind, RED), sphere_actor(kind, GREEN)
            base = add_renderer(window, below)
            top = add_renderer(window, above, (0.3, 0.1, 0.9, 0.8), (-2.5, 0.4, 2.2), layer=1)
            return [(base, below), (top, above)]

        def shown(window):
            window.Render()
            image = rgba(window)
            window.SetNumberOfLayers(1)
            # 1 (as depth 0) where green shows, 0.5 where red shows, 1 elsewhere: a "depth"
            # image whose coverage classes compare() counts.
            code = np.ones(image.shape[:2])
            code[(image[..., 0] > 200) & (image[..., 1] < 50)] = 0.5
            code[(image[..., 1] > 200) & (image[..., 0] < 50)] = 0.0
            return code

        def truth(views, size, scale):
            code = np.ones((size[1], size[0]))
            code[view_truth(*views[0], size) < 1] = 0.5
            code[view_truth(*views[1], size) < 1] = 0.0
            return code
        exact, mine, polygons = self.both(build, shown, truth)
        for colour, value in (("red (layer 0)", 0.5), ("green (layer 1)", 0.0)):
            self.compare("layers: %s" % colour, np.where(exact == value, 0.0, 1.0),
                         np.where(mine == value, 0.0, 1.0), np.where(polygons == value, 0.0, 1.0),
                         depth=False)

    # --- Tiled and magnified images --------------------------------------------------------------
    @staticmethod
    def grab(scale):
        """A capture of the window's depth tiled at `scale` by vtkWindowToImageFilter."""
        def capture(window):
            grab = vtkWindowToImageFilter()
            grab.SetInput(window)
            grab.SetScale(*scale)
            grab.SetInputBufferTypeToZBuffer()
            grab.ReadFrontBufferOff()
            grab.Update()
            image = grab.GetOutput()
            width, height, _ = image.GetDimensions()
            return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width).astype(float)
        return capture

    def tiled(self, name, scale):
        def build(window, kind):
            actor = sphere_actor(kind)
            return [(add_renderer(window, actor), actor)]
        self.compare(name, *self.both(build, self.grab(scale)))

    def test_window_to_image_scale_2(self):
        self.tiled("vtkWindowToImageFilter scale 2", (2, 2))

    def test_window_to_image_two_viewports_parallel(self):
        # Tiles cut across two viewports, one of them parallel.
        def build(window, kind):
            views = []
            for viewport, eye in (((0.0, 0.0, 0.45, 1.0), EYE), ((0.45, 0.0, 1.0, 1.0), (-2.5, 0.4, 2.2))):
                actor = sphere_actor(kind)
                views.append((add_renderer(window, actor, viewport, eye), actor))
            views[1][0].GetActiveCamera().ParallelProjectionOn()
            views[1][0].GetActiveCamera().SetParallelScale(0.9)
            return views
        self.compare("vtkWindowToImageFilter scale 3, two viewports", *self.both(build, self.grab((3, 3))))

    def test_window_to_image_scale_3_2(self):
        self.tiled("vtkWindowToImageFilter scale 3 x 2", (3, 2))

    def test_render_large_image(self):
        def build(window, kind):
            actor = sphere_actor(kind)
            return [(add_renderer(window, actor), actor)]

        def capture(window):
            window.Render()
            large = vtkRenderLargeImage()
            large.SetInput(window.GetRenderers().GetFirstRenderer())
            large.SetMagnification(3)
            large.Update()
            image = large.GetOutput()
            width, height, _ = image.GetDimensions()
            colors = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width, -1)
            return np.where(colors[..., 0] > 128, 0.0, 1.0)  # red: covered
        # vtkRenderLargeImage narrows each tile's view angle by asin(sin(angle / 2) / 3), not
        # atan(tan(angle / 2) / 3): its picture is not the camera's image at 3 times the size (the
        # sphere 2 pixels wider here), so the polygons' picture is the reference.
        _, mine, polygons = self.both(build, capture)
        self.compare("vtkRenderLargeImage magnification 3 (vs polygons)", polygons, mine, polygons,
                     depth=False)

    # --- Actor matrices --------------------------------------------------------------------------
    def test_actor_shear(self):
        self.single("actor matrix: shear", actor_matrix=SHEAR)

    def test_actor_mirror(self):
        self.single("actor matrix: mirror (det < 0)", actor_matrix=MIRROR)

    def test_actor_non_uniform_scale(self):
        self.single("actor matrix: scale 1.6, 0.5, 1.1", actor_matrix=SCALE)

    def test_actor_matrix_lighting(self):
        # Lit (the renderer's headlight, with a highlight): the surface is shaded in the world, as
        # polygons are, whatever the actor's matrix does to lengths and angles. A mirror makes
        # vtkPolyDataMapper's sphere black (its facets turn their backs: VTK's two-sided
        # lighting flips their normals away), so the mirrored sphere is compared with the
        # polygons of the sphere it is: the same sphere moved by the mirror's translation.
        cases = (("shear", SHEAR, SHEAR), ("scale 1.6, 0.5, 1.1", SCALE, SCALE),
                 ("mirror", MIRROR, [[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, -0.1], [0, 0, 0, 1]]))
        for name, mine, reference in cases:
            pictures = {}
            for kind, matrix in (("mapper", mine), ("polygons", reference)):
                window = shared_window()
                actor = sphere_actor(kind, flat=False)
                actor.GetProperty().SetSpecular(0.3)
                actor.GetProperty().SetSpecularPower(20)
                actor.SetUserMatrix(as_vtk(matrix))
                add_renderer(window, actor)
                pictures[kind] = rendered_depth(window) < 1, rgba(window)[..., :3]
            covered = pictures["polygons"][0]
            compared = covered & pictures["mapper"][0] & ~near_silhouette(covered)
            error = np.abs(pictures["mapper"][1] - pictures["polygons"][1]).max(axis=2)[compared]
            print("lit, actor matrix %s: %d pixels, colour differs by up to %d / 255 (%d over 4)"
                  % (name, compared.sum(), error.max(), (error > 4).sum()))
            self.assertGreater(int(compared.sum()), 3000)
            self.assertLessEqual(int(error.max()), 4, "%s: expected the polygons' shading" % name)

    def test_assembly_part_with_its_own_transform(self):
        def build(window, kind):
            part = sphere_actor(kind)
            part.SetUserMatrix(as_vtk([[1.3, 0.2, 0, 0.1], [0, 0.8, 0, 0], [0, 0, 1, -0.2],
                                       [0, 0, 0, 1]]))
            assembly = vtkAssembly()
            assembly.AddPart(part)
            assembly.SetPosition(-0.2, 0.15, 0.1)
            assembly.RotateY(25)
            assembly.SetScale(0.9, 1.1, 1.0)
            renderer = add_renderer(window, sphere_actor(kind))  # (replaced below)
            renderer.RemoveAllViewProps()
            renderer.AddActor(assembly)
            return [(renderer, part)]

        def truth(views, size, scale):
            renderer, part = views[0]
            # The part is drawn through the assembly's path: assembly matrix times its own.
            assembly = renderer.GetActors()
            assembly.InitTraversal()
            whole = renderer.GetViewProps().GetItemAsObject(0)
            full = as_array(whole.GetMatrix()) @ as_array(part.GetUserMatrix())
            camera = renderer.GetActiveCamera()
            width, height = renderer.GetSize()
            to_ndc = as_array(camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1)) @ full
            return sphere_depth(to_ndc, size[0], size[1])
        self.compare("vtkAssembly part with its own transform", *self.both(build, truth=truth))

    # --- Windows resized between renders ---------------------------------------------------------
    def resized(self, name, size):
        def build(window, kind):
            actor = sphere_actor(kind)
            views = [(add_renderer(window, actor), actor)]
            window.Render()
            window.SetSize(*size)
            return views
        self.compare(name, *self.both(build))

    def test_window_resized_bigger(self):
        self.resized("window resized 160x120 -> 250x190", (250, 190))

    def test_window_resized_smaller(self):
        self.resized("window resized 160x120 -> 97x131", (97, 131))

    # --- The camera inside and on the sphere -----------------------------------------------------
    def test_camera_inside(self):
        def inside(camera):
            camera.SetPosition(0.2, -0.1, 0.3)
            camera.SetFocalPoint(-0.4, 0.0, -0.5)
            camera.SetViewAngle(60)
            camera.SetClippingRange(0.01, 10)
        self.single("camera inside the sphere", inside)

    def test_camera_on_sphere(self):
        def on(camera):
            position = np.array([0.3, 0.4, 0.5])
            camera.SetPosition(*(RADIUS * position / np.linalg.norm(position)))
            camera.SetFocalPoint(0.0, 0.0, 0.0)
            camera.SetViewAngle(60)
            camera.SetClippingRange(0.01, 10)
        self.single("camera exactly on the sphere", on)


class FilterCamera(unittest.TestCase):
    """vtkDirectSurfaceRayCaster's rays follow a camera's position, focal point, view up and view
    angle (or parallel scale) only: a camera holding more is refused, naming what it holds, where
    it drew a different picture without a word before."""

    def cast(self, configure):
        camera = vtkCamera()
        camera.SetPosition(*EYE)
        camera.SetFocalPoint(*CENTRE)
        camera.SetViewUp(0, 1, 0)
        configure(camera)
        caster = vtkDirectSurfaceRayCaster()
        caster.SetInputData(MESH)
        caster.SetValue(0, RADIUS2)
        caster.SetImageSize(W, H)
        caster.SetCamera(camera)
        messages = Messages(caster)
        caster.Update()
        depth = caster.GetOutput().GetPointData().GetArray("Depth")
        hits = int(np.isfinite(vtk_to_numpy(depth)).sum()) if depth else 0
        return messages.errors, hits

    def test_extras_refused(self):
        errors, hits = self.cast(lambda camera: None)
        self.assertEqual(errors, [])
        self.assertGreater(hits, 1000)
        identity = vtkMatrix4x4()
        shifted = vtkMatrix4x4()
        shifted.SetElement(0, 3, 0.2)
        transform = vtkTransform()
        transform.Scale(1.0, 2.0, 1.0)
        cases = {
            "an explicit projection matrix": lambda c: (
                c.SetExplicitProjectionTransformMatrix(identity),
                c.UseExplicitProjectionTransformMatrixOn()),
            "an off-axis projection": lambda c: c.UseOffAxisProjectionOn(),
            "a window centre other than (0, 0)": lambda c: c.SetWindowCenter(0.3, 0.0),
            "a view shear": lambda c: c.SetViewShear(0.2, 0.0, 1.0),
            "a user transform, user view transform or model transform matrix": lambda c:
                c.SetModelTransformMatrix(shifted),
        }
        for name, configure in cases.items():
            errors, hits = self.cast(configure)
            print("filter camera with %s: %s" % (name, errors))
            self.assertEqual(len(errors), 1, name)
            self.assertIn("the camera uses %s;" % name, errors[0])
            self.assertEqual(hits, 0, "%s: no picture" % name)
        errors, _ = self.cast(lambda c: c.SetUserTransform(transform))
        self.assertIn("user transform", errors[0] if errors else "")


def tearDownModule():
    print("\n%-44s %8s %14s %14s %14s %14s" % ("set-up", "pixels", "mapper wrong", "mapper depth",
                                               "polygons wrong", "polygons depth"))
    for row in RESULTS:
        print("%-44s %8d %14d %14.1e %14d %14.1e"
              % (row["name"], row["covered"], row["mapper wrong"], row["mapper depth"],
                 row["polygons wrong"], row["polygons depth"]))


if __name__ == "__main__":
    unittest.main(verbosity=2)
