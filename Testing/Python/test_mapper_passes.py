"""vtkDirectSurfaceMapper under the window's and the renderer's passes: every stereo type, screen-
space ambient occlusion, depth peeling, FXAA and multisampling. Each mode draws the exact sphere
|x|^2 = 0.5 (quadratic tetrahedra hold it exactly) cut by a polygon plane, and then, in the same
window with the same settings, a fine polygon sphere of the same shape in its place: the two
pictures must agree (a count of the pixels that differ). Where a mode shows one eye, the window
depth is also compared with the analytic hit of each pixel's ray, the eye's projection built here
from the camera's parameters (vtkPerspectiveTransform::Stereo's shear). Prints a table of mode ->
result."""
import sys
import unittest

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)

from shared_helpers import Messages
from test_mapper import grid, rgba, window_depth, zbuffer
from tetdsr import vtkDirectSurfaceMapper

W, H = 200, 150
RADIUS2 = 0.5
SPHERE_COLOR = (1.0, 0.5, 0.0)
PLANE_COLOR = (0.1, 0.3, 1.0)
# The plane's corner and its two edges' ends: through the sphere, 37 degrees to the view.
PLANE = ((-1.2, -1.1, -0.85), (1.2, -1.1, 0.95), (-1.2, 1.1, -0.85))
EYE_ANGLE = 8.0  # degrees; ParaView's default is 2 (both are run)
# A channel may differ by rounding between the mapper's colour (8-bit image) and the polygons'.
COLOR_TOLERANCE = 3
# The polygon sphere (512 x 256 facets) is within 1.4e-5 of the sphere, 1e-3 of a pixel here, but
# its silhouette is rasterised from facets: a pixel centre that close to the silhouette may fall
# on either side, and FXAA and multisampling blend the silhouette pixels of the two a little
# differently. Counted per picture; the failures this test guards against are hundreds.
SILHOUETTE_PIXELS = 6
DEPTH_TOLERANCE = 4 * 2.0 ** -24  # the depth image is float, written with gl_FragDepth

RESULTS = []  # (mode, result) rows of the table


def report(mode, text):
    RESULTS.append((mode, text))
    print("%-34s %s" % (mode, text), flush=True)


class Scene:
    """One window (one X connection) holding a renderer with the sphere (the mapper's or the
    polygons') and the plane, flat colours (no lighting: a pixel's colour says which surface it
    shows), the camera's focal point behind the sphere (so that the stereo eyes' views differ
    there)."""

    mesh = grid()

    def __init__(self, multisamples=0, quad_buffer=False):
        self.window = vtkRenderWindow()
        self.window.SetSize(W, H)
        self.window.SetMultiSamples(multisamples)
        if quad_buffer:  # (asks X for a stereo visual: on screen)
            self.window.StereoCapableWindowOn()
        else:
            self.window.OffScreenRenderingOn()

    def render(self, exact, configure=None, opacity=1.0, plane_opacity=1.0, lighting=False,
               mesh=None):
        """Renders the scene with the mapper's sphere (`exact`) or the polygon sphere; returns
        (rgba, window depth, the eyes' world-to-NDC matrices: eye_matrix by -1, 0, 1). `mesh`:
        the mapper's input, if not the lattice."""
        renderers = self.window.GetRenderers()
        while renderers.GetNumberOfItems():
            self.window.RemoveRenderer(renderers.GetFirstRenderer())
        renderer = vtkRenderer()
        renderer.SetBackground(0.0, 0.0, 0.0)
        sphere = vtkActor()
        if exact:
            mapper = vtkDirectSurfaceMapper()
            mapper.SetInputData(self.mesh if mesh is None else mesh)
            mapper.SetValue(0, RADIUS2)
            mapper.ScalarVisibilityOff()
            self.messages = Messages(mapper)
            self.mapper = mapper
        else:
            source = vtkSphereSource()
            source.SetRadius(np.sqrt(RADIUS2))
            source.SetThetaResolution(512)
            source.SetPhiResolution(256)
            mapper = vtkPolyDataMapper()
            mapper.SetInputConnection(source.GetOutputPort())
        sphere.SetMapper(mapper)
        plane_source = vtkPlaneSource()
        plane_source.SetOrigin(*PLANE[0])
        plane_source.SetPoint1(*PLANE[1])
        plane_source.SetPoint2(*PLANE[2])
        plane_mapper = vtkPolyDataMapper()
        plane_mapper.SetInputConnection(plane_source.GetOutputPort())
        plane = vtkActor()
        plane.SetMapper(plane_mapper)
        for actor, color, alpha in ((sphere, SPHERE_COLOR, opacity),
                                    (plane, PLANE_COLOR, plane_opacity)):
            actor.GetProperty().SetColor(*color)
            actor.GetProperty().SetLighting(lighting)
            actor.GetProperty().SetAmbient(0.3)
            actor.GetProperty().SetDiffuse(0.7)
            actor.GetProperty().SetOpacity(alpha)
            renderer.AddActor(actor)
        camera = renderer.GetActiveCamera()
        camera.SetPosition(0.4, 0.5, 3.4)
        camera.SetFocalPoint(-0.1, -0.1, -1.6)
        camera.SetViewUp(0, 1, 0)
        camera.SetViewAngle(32)
        camera.SetEyeAngle(EYE_ANGLE)
        camera.SetClippingRange(1.0, 8.0)
        self.window.StereoRenderOff()
        self.window.SetDesiredUpdateRate(0.0001)  # (still frames unless `configure` says)
        if configure:
            configure(self.window, renderer)
        self.window.AddRenderer(renderer)
        self.window.Render()
        eyes = {eye: eye_matrix(renderer, eye) for eye in (-1, 0, 1)}
        return rgba(self.window), zbuffer(self.window), eyes


def differing_pixels(a, b):
    return int((np.abs(a[..., :3] - b[..., :3]).max(axis=2) > COLOR_TOLERANCE).sum())


def eye_matrix(renderer, eye):
    """World to NDC of one eye (-1 left, +1 right, 0 the centre view), built from the camera's
    parameters: the centre view's projection P and view V, and the stereo shear of view
    coordinates vtkPerspectiveTransform::Stereo(eye * angle / 2, distance) makes:
    x' = x - tan(eye * angle / 2) (z + distance), zero in the focal plane."""
    camera = renderer.GetActiveCamera()
    # (The camera's composite projection leaves the eye out, whatever the window renders.)
    m = camera.GetCompositeProjectionTransformMatrix(renderer.GetTiledAspectRatio(), -1, 1)
    composite = np.array([[m.GetElement(r, c) for c in range(4)] for r in range(4)])
    v = camera.GetViewTransformMatrix()
    view = np.array([[v.GetElement(r, c) for c in range(4)] for r in range(4)])
    t = np.tan(np.radians(eye * camera.GetEyeAngle() / 2))
    shear = np.eye(4)
    shear[0, 2] = -t
    shear[0, 3] = -camera.GetDistance() * t
    return composite @ np.linalg.inv(view) @ shear @ view


def sphere_depth(composite):
    """Window depth of each pixel ray's first hit with |x|^2 = RADIUS2 (1 on a miss) and how far
    each ray is from grazing it (|discriminant| / radius^2)."""
    origin, direction = pixel_rays(composite)
    b = np.sum(origin * direction, axis=1)
    disc = b * b - (np.sum(origin * origin, axis=1) - RADIUS2)
    hit = disc >= 0
    depth = np.ones(len(b))
    t = -b[hit] - np.sqrt(disc[hit])
    depth[hit] = window_depth(composite, origin[hit] + t[:, None] * direction[hit])
    return depth.reshape(H, W), (np.abs(disc) / RADIUS2).reshape(H, W)


def pixel_rays(composite):
    """Each pixel's ray (origin on the near plane, unit direction), from the inverse projection."""
    inverse = np.linalg.inv(composite)
    i, j = np.meshgrid(np.arange(W), np.arange(H))
    x = 2 * (i.ravel() + 0.5) / W - 1
    y = 2 * (j.ravel() + 0.5) / H - 1

    def unproject(z):
        p = np.c_[x, y, np.full_like(x, z), np.ones_like(x)] @ inverse.T
        return p[:, :3] / p[:, 3:]
    origin = unproject(-1.0)
    direction = unproject(1.0) - origin
    return origin, direction / np.linalg.norm(direction, axis=1)[:, None]


def sphere_and_plane(origin, direction):
    """Per pixel (H x W): the ray parameters of the sphere's walls (NaN on a miss) and of the
    scene's plane."""
    b = np.sum(origin * direction, axis=1)
    disc = b * b - (np.sum(origin * origin, axis=1) - RADIUS2)
    root = np.sqrt(np.where(disc > 1e-3 * RADIUS2, disc, np.nan))
    normal = np.cross(np.subtract(PLANE[1], PLANE[0]), np.subtract(PLANE[2], PLANE[0]))
    tp = (np.subtract(PLANE[0], origin) @ normal) / (direction @ normal)
    return [a.reshape(H, W) for a in (-b - root, -b + root, tp)]


def plane_edges(origin, direction):
    """Pixels (H x W) along the plane's outline: their 3 x 3 neighbourhood has pixel centres on
    the plane and off it (the plane's two edge vectors are orthogonal)."""
    *_, tp = sphere_and_plane(origin, direction)
    point = origin + tp.ravel()[:, None] * direction - np.array(PLANE[0])
    inside = np.ones(len(point), bool)
    for corner in PLANE[1:]:
        edge = np.subtract(corner, PLANE[0])
        u = point @ edge / (edge @ edge)
        inside &= (u >= 0) & (u <= 1)
    inside = inside.reshape(H, W) & (tp > 0)
    return dilate(inside) & dilate(~inside)


def dilate(mask):
    """Each pixel and its 8 neighbours."""
    padded = np.pad(mask, 1)
    return np.any([padded[1 + dj:H + 1 + dj, 1 + di:W + 1 + di]
                   for dj in (-1, 0, 1) for di in (-1, 0, 1)], axis=0)


def stereo(kind, angle=EYE_ANGLE):
    def configure(window, renderer):
        renderer.GetActiveCamera().SetEyeAngle(angle)
        if kind is None:
            window.StereoRenderOff()
            return
        getattr(window, "SetStereoTypeTo" + kind)()
        window.StereoRenderOn()
    return configure


class Passes(unittest.TestCase):
    scene = None

    @classmethod
    def setUpClass(cls):
        cls.scene = Scene()

    def pair(self, configure=None, **kwargs):
        exact, exact_z, eyes = self.scene.render(True, configure, **kwargs)
        self.assertEqual(self.scene.messages.errors, [])
        polygons, polygon_z, _ = self.scene.render(False, configure, **kwargs)
        return exact, exact_z, polygons, polygon_z, eyes

    def check_one_eye(self, kind, eye, angle):
        """A stereo type showing one eye: the sphere's depth where it is in front of the plane
        against the eye's analytic hit; the picture against the polygon sphere's."""
        exact, z, polygons, _, eyes = self.pair(stereo(kind, angle))
        truth, margin = sphere_depth(eyes[eye])
        sphere = np.all(np.abs(exact[..., :3] - np.array(SPHERE_COLOR) * 255) <= COLOR_TOLERANCE + 1,
                        axis=2)
        # Where the sphere shows, its depth is the eye's exact hit; where the sphere is hit but
        # not shown, the plane is in front of it.
        shown = sphere & (truth < 1)
        error = float(np.abs(z - truth)[shown].max())
        wrong = int((shown & (np.abs(z - truth) > DEPTH_TOLERANCE)).sum())
        expected = (truth < 1) & (margin > 1e-6)
        hidden_or_false = int((sphere & (truth == 1) & (margin > 1e-6)).sum())
        differ = differing_pixels(exact, polygons)
        hidden = int((expected & ~sphere).sum())
        report("stereo %s (eye angle %g)" % (kind or "off", angle),
               "%d sphere pixels (%d behind the plane), max |depth - exact| %.1e, %d beyond "
               "tolerance, %d outside the sphere; %d differ from polygons"
               % (shown.sum(), hidden, error, wrong, hidden_or_false, differ))
        self.assertGreater(shown.sum(), 0.2 * expected.sum())
        self.assertGreater(hidden, 0.05 * expected.sum())
        self.assertEqual(wrong, 0)
        self.assertEqual(hidden_or_false, 0)
        self.assertLessEqual(differ, SILHOUETTE_PIXELS)

    def test_stereo_off(self):
        self.check_one_eye(None, 0, EYE_ANGLE)

    def test_stereo_left_right(self):
        for angle in (2.0, EYE_ANGLE):
            for kind, eye in (("Left", -1), ("Right", 1)):
                with self.subTest(kind=kind, angle=angle):
                    self.check_one_eye(kind, eye, angle)

    def test_stereo_composited(self):
        """Types that combine the two eyes' pictures (or show one after rendering both): the
        combination against the polygon sphere's, and against the mapper's own picture with
        the eye angle 0 (a picture that would pass if both eyes were drawn the same)."""
        for kind in ("RedBlue", "Anaglyph", "Interlaced", "Checkerboard", "Dresden",
                     "SplitViewportHorizontal", "Fake", "Emulate"):
            exact, _, polygons, _, _ = self.pair(stereo(kind))
            flat, _, _ = self.scene.render(True, stereo(kind, 0.0))
            differ = differing_pixels(exact, polygons)
            parallax = differing_pixels(exact, flat)
            report("stereo %s" % kind, "%d pixels differ from polygons (%d from the eye angle "
                   "0 picture)" % (differ, parallax))
            with self.subTest(kind=kind):
                self.assertLessEqual(differ, SILHOUETTE_PIXELS)
                self.assertGreater(parallax, 100)
        # Each eye keeps its own image: a second frame casts neither.
        self.scene.render(True, stereo("RedBlue"))
        self.scene.window.Render()
        self.assertTrue(self.scene.mapper.GetLastRenderReusedImage())

    def test_stereo_crystal_eyes(self):
        """Crystal eyes needs a quad-buffer visual, which Xvfb does not offer. In a window made
        without asking for one VTK refuses to turn stereo on (a warning) and renders the centre
        view; in one that asks, X gives a visual without it (the window then reports itself not
        stereo capable) and VTK renders both eyes anyway: the right eye's glDrawBuffer
        (GL_BACK_RIGHT) fails (OpenGL: invalid operation, logged by VTK) and the window shows
        the left eye. The mapper's picture equals the polygons' in both."""
        stereo_on = []

        def configure(window, renderer):
            window.SetStereoTypeToCrystalEyes()
            window.StereoRenderOn()
            stereo_on.append(bool(window.GetStereoRender()))
        exact, _, polygons, _, _ = self.pair(configure)
        differ = differing_pixels(exact, polygons)
        report("stereo CrystalEyes", "stereo render turned on: %s; %d pixels differ from "
               "polygons (the centre view)" % (stereo_on[0], differ))
        self.assertFalse(stereo_on[0])
        self.assertLessEqual(differ, SILHOUETTE_PIXELS)

        quad_buffer = Scene(quad_buffer=True)
        exact, _, _ = quad_buffer.render(True, configure)
        capable = bool(quad_buffer.window.GetStereoCapableWindow())
        polygons, _, _ = quad_buffer.render(False, configure)
        eyes = [differing_pixels(exact, self.scene.render(True, stereo(kind))[0])
                for kind in ("Left", "Right")]
        differ = differing_pixels(exact, polygons)
        report("stereo CrystalEyes, asked for", "stereo capable: %s; %d pixels differ from "
               "polygons, %d from the left eye's picture, %d from the right eye's"
               % (capable, differ, eyes[0], eyes[1]))
        self.assertFalse(capable)
        self.assertLessEqual(differ, SILHOUETTE_PIXELS)
        self.assertLessEqual(min(eyes), SILHOUETTE_PIXELS)


    def test_ambient_occlusion(self):
        """Screen-space ambient occlusion darkens where the plane meets the sphere: the
        mapper's picture against the polygon sphere's (no blotches: the pass reads each pixel's
        view-space position and normal, which the mapper writes as the polygons do)."""
        def configure(window, renderer):
            renderer.UseSSAOOn()
            renderer.SetSSAORadius(0.15)
            renderer.SetSSAOBias(0.002)
            renderer.SetSSAOBlur(True)
        exact, _, polygons, _, _ = self.pair(configure, lighting=True)
        plain, _, _ = self.scene.render(False, lighting=True)
        differ = differing_pixels(exact, polygons)
        darkened = differing_pixels(polygons, plain)
        worst = int(np.abs(exact[..., :3] - polygons[..., :3]).max())
        report("ambient occlusion", "%d pixels differ from polygons (largest channel "
               "difference %d); the pass darkens %d pixels of the polygon picture"
               % (differ, worst, darkened))
        self.assertGreater(darkened, 100)  # (the pass does something to compare)
        self.assertLessEqual(differ, SILHOUETTE_PIXELS)

        # The mesh as two blocks of a multiblock dataset: each pixel's normal is its nearest
        # block's, and the picture is the one grid's.
        blocks = vtkMultiBlockDataSet()
        cells = Scene.mesh.GetNumberOfCells()
        for b, cell_range in enumerate([(0, cells // 2), (cells // 2, cells)]):
            blocks.SetBlock(b, grid(cell_range=cell_range))
        composite, _, _ = self.scene.render(True, configure, lighting=True, mesh=blocks)
        report("ambient occlusion, two blocks", "%d pixels differ from the one grid's picture"
               % differing_pixels(composite, exact))
        self.assertEqual(differing_pixels(composite, exact), 0)

        # An interactive frame (cast at half resolution, upsampled): its normals are the nearest
        # cast pixel's; it differs from the still picture along the silhouette and the plane's
        # crossing, where the upsampled coverage steps, and by a few levels of shading and of the
        # occlusion the steps cast on the plane (up to 12 measured).
        def interactive(window, renderer):
            configure(window, renderer)
            window.SetDesiredUpdateRate(15)
            self.scene.mapper.AutoAdjustSampleDistancesOff()
            self.scene.mapper.SetInteractiveImageSampleDistance(2)
        reduced, _, eyes = self.scene.render(True, interactive, lighting=True)
        self.assertEqual(self.scene.mapper.GetLastImageSampleDistance(), 2.0)
        t0, _, tp = sphere_and_plane(*pixel_rays(eyes[0]))
        hit = np.isfinite(t0)
        edges = dilate(dilate(dilate(hit) & dilate(~hit)) |
                       dilate(dilate(hit & (tp < t0)) & dilate(hit & (tp > t0))))
        reduced_gap = np.abs(reduced[..., :3] - polygons[..., :3]).max(axis=2)
        reduced_differ = reduced_gap > 16
        report("ambient occlusion, interactive frame",
               "%d pixels differ from the polygons' still picture by more than 16 away from the "
               "silhouette and the crossing (%d along them)"
               % ((reduced_differ & ~edges).sum(), (reduced_differ & edges).sum()))
        self.assertLessEqual(int((reduced_differ & ~edges).sum()), SILHOUETTE_PIXELS)

    def test_fxaa(self):
        """FXAA smooths the finished frame's edges: the mapper's sphere as the polygons'."""
        def configure(window, renderer):
            renderer.UseFXAAOn()
        exact, z, polygons, polygon_z, _ = self.pair(configure, lighting=True)
        plain, _, _ = self.scene.render(False, lighting=True)
        differ = differing_pixels(exact, polygons)
        report("FXAA", "%d pixels differ from polygons (largest channel difference %d); FXAA "
               "changes %d pixels of the polygon picture" % (
                   differ, int(np.abs(exact[..., :3] - polygons[..., :3]).max()),
                   differing_pixels(polygons, plain)))
        self.assertGreater(differing_pixels(polygons, plain), 50)
        self.assertLessEqual(differ, SILHOUETTE_PIXELS)

    def multisampled(self):
        """The sphere (mapper's and polygons') in a window of 8 samples a pixel (llvmpipe gives
        4), flat colours, and the pixel classes: hit (the pixel centre's ray meets the sphere),
        silhouette, crossing (where the plane crosses the sphere, wider where that meets the
        silhouette) and away from both."""
        scene = Scene(multisamples=8)
        exact, z, eyes = scene.render(True)
        self.assertEqual(scene.messages.errors, [])
        scene.eyes = eyes
        polygons, _, _ = scene.render(False)
        truth, margin = sphere_depth(eyes[0])
        t0, _, tp = sphere_and_plane(*pixel_rays(eyes[0]))
        hit = truth < 1
        silhouette = dilate(hit) & dilate(~hit)
        core = dilate(hit & (tp < t0)) & dilate(hit & (tp > t0))
        crossing = dilate(dilate(core))
        for _ in range(3):  # (where it meets the silhouette, a little wider)
            core = dilate(core)
        crossing |= core & dilate(dilate(silhouette))
        return scene, exact, z, polygons, truth, margin, t0, tp, hit, silhouette, crossing

    def test_multisampling(self):
        """A window of 8 samples a pixel, flat colours: a pixel on the sphere's silhouette is the
        blend of the surfaces its samples see, as for polygons (the mapper casts a ray per sample
        there, at the framebuffer's sample positions, and writes the pixel's sample mask). Each
        silhouette pixel's sphere coverage (its colour solved as a blend of the sphere, the
        plane and the background) against the polygons' pixel by pixel and summed; the mapper's
        one-ray-a-pixel picture (a single-sampled window: the picture before per-sample rays) as
        the count to beat. Covered samples keep the exact depth: a pixel whose centre sees the
        sphere writes the centre's exact hit to its covered samples. Where the plane crosses the
        sphere the quad's one depth a pixel meets the plane's depth at each sample: smoothed,
        but not as the polygons' per-sample depths (not compared, nor where the crossing meets
        the silhouette). Elsewhere the pictures agree and the depth is the exact hit's."""
        single, _, _ = self.scene.render(True)
        (scene, exact, z, polygons, truth, margin, t0, tp, hit, silhouette,
         crossing) = self.multisampled()
        away = ~silhouette & ~crossing
        differ = np.abs(exact[..., :3] - polygons[..., :3]).max(axis=2) > COLOR_TOLERANCE
        sphere = hit & away & (tp > t0)
        error = float(np.abs(z - truth)[sphere].max())

        def coverage(image):
            """The sphere's share of each pixel: colour = a sphere + b plane + c black solved
            for a (the sphere has no blue: b = B / 255, a = (R - 0.1 B) / 255)."""
            return (image[..., 0] - PLANE_COLOR[0] * image[..., 2]) / 255.0
        edge = silhouette & ~crossing
        shares = {name: coverage(image)[edge] for name, image in
                  (("exact", exact), ("polygons", polygons), ("single", single))}
        # (one sample of 8 is 0.125 of a pixel; rounding of the 8-bit channels is within 0.01)
        off = {name: int((np.abs(shares[name] - shares["polygons"]) > 1 / 16).sum())
               for name in ("exact", "single")}
        total = {name: float(shares[name].sum()) for name in shares}
        quanta = np.unique(np.round(shares["polygons"] * 8) / 8)
        report("multisampling (8)", "%d pixels differ from polygons away from the silhouette and "
               "the crossing; silhouette off the crossing: %d pixels, sphere coverage differs from "
               "the polygons' in %d (one ray a pixel: %d), summed coverage %.2f pixels (polygons "
               "%.2f, one ray a pixel %.2f); %d of %d crossing pixels differ; max |depth - exact| "
               "%.1e on %d pixels"
               % ((differ & away).sum(), edge.sum(), off["exact"], off["single"], total["exact"],
                  total["polygons"], total["single"], (differ & crossing).sum(), crossing.sum(),
                  error, sphere.sum()))
        self.assertLessEqual(int((differ & away).sum()), SILHOUETTE_PIXELS)
        self.assertLessEqual(off["exact"], SILHOUETTE_PIXELS)
        self.assertGreater(off["single"], 10 * SILHOUETTE_PIXELS)  # (the test can fail)
        self.assertGreater(len(quanta), 3)  # (the polygons' silhouette is smoothed)
        self.assertLess(abs(total["exact"] - total["polygons"]), 0.01 * edge.sum())
        self.assertLess(error, DEPTH_TOLERANCE)
        self.assertGreater(sphere.sum(), 0.5 * hit.sum())

        # The depth on the silhouette: the resolved depth is one sample's, which may be the
        # plane's behind or the background's. A pixel whose centre sees the sphere writes that
        # exact hit to its covered samples; a pixel whose centre misses it but some samples see
        # it, its nearest covered sample's ray parameter along the centre's ray: between its
        # sphere neighbours' depths and the rim's (the centre ray's closest approach to the
        # sphere's centre: a grazing sample's hit is as deep). Anything else is wrong.
        origin, direction = pixel_rays(scene.eyes[0])
        plane_z = window_depth(scene.eyes[0], origin + tp.reshape(-1, 1) * direction)
        plane_z = plane_z.reshape(H, W)
        step = np.abs(np.gradient(plane_z)).sum(axis=0)  # (a pixel's change)
        background = (z == 1) | (np.abs(z - plane_z) <= step)
        clear = edge & ~dilate(dilate(hit & ~(tp > t0))) & (margin > 1e-6)
        centre = clear & hit & ~background
        centre_wrong = int((centre & (np.abs(z - truth) > DEPTH_TOLERANCE)).sum())
        padded = np.pad(np.where(hit, truth, np.nan), 1, constant_values=np.nan)
        around = np.stack([padded[1 + dj:H + 1 + dj, 1 + di:W + 1 + di]
                           for dj in (-1, 0, 1) for di in (-1, 0, 1)])
        with np.errstate(all="ignore"):
            low, high = np.nanmin(around, axis=0), np.nanmax(around, axis=0)
        spread = high - low
        rim = window_depth(scene.eyes[0], origin - np.sum(origin * direction, axis=1)[:, None]
                           * direction).reshape(H, W)
        high = np.maximum(high, rim)
        filled = clear & ~hit & ~background
        outside = filled & ~((z >= low - spread) & (z <= high + spread))
        report("multisampling (8), silhouette depth",
               "%d pixels whose centre sees the sphere show a covered sample's depth: %d not the "
               "exact hit; %d filled (centre misses): %d outside their sphere neighbours' and "
               "rim's depths"
               % (centre.sum(), centre_wrong, filled.sum(), outside.sum()))
        self.assertGreater(int(centre.sum()), 50)
        self.assertEqual(centre_wrong, 0)
        self.assertEqual(int(outside.sum()), 0)

    def test_single_sampled_pixel_centres(self):
        """In a single-sampled window nothing changes: one ray a pixel centre, no sample masks.
        Every pixel's coverage is its centre's analytic hit (rays grazing the sphere within 1e-6
        left out), silhouette included, and its depth that hit's, as before per-sample rays."""
        exact, z, eyes = self.scene.render(True)
        truth, margin = sphere_depth(eyes[0])
        origin, direction = pixel_rays(eyes[0])
        *_, tp = sphere_and_plane(origin, direction)
        b = np.sum(origin * direction, axis=1)
        disc = b * b - (np.sum(origin * origin, axis=1) - RADIUS2)
        t0 = (-b - np.sqrt(np.maximum(disc, 0))).reshape(H, W)  # (grazing rays too)
        clear = (margin > 1e-6) & (np.abs(tp - t0) > 1e-3)
        sphere = np.all(np.abs(exact[..., :3] - np.array(SPHERE_COLOR) * 255) <= COLOR_TOLERANCE,
                        axis=2)
        expected = (truth < 1) & (tp > t0)
        wrong = int(((sphere != expected) & clear).sum())
        error = float(np.abs(z - truth)[sphere & clear].max())
        silhouette = dilate(truth < 1) & dilate(truth == 1)
        report("single-sampled", "%d pixels' coverage differs from the pixel centre's analytic hit "
               "(%d silhouette pixels); max |depth - exact| %.1e on %d pixels"
               % (wrong, (silhouette & clear).sum(), error, (sphere & clear).sum()))
        self.assertEqual(wrong, 0)
        self.assertLess(error, DEPTH_TOLERANCE)

    def test_multisampling_interactive_and_translucent(self):
        """A multisampled window's frames that get no per-sample rays: an interactive frame
        (cast at half resolution, upsampled) and a translucent sphere (drawn over the finished
        frame). Each equals the same frame in a single-sampled window away from the sphere's
        silhouette, the crossing and the plane's outline (smoothed there in the multisampled
        window), and on the silhouette too: a pixel is the sphere's or not, not smoothed, as
        before per-sample rays (the polygons' picture, for scale, is smoothed there)."""
        (scene, _, _, polygons, truth, _, t0, tp, hit, silhouette,
         crossing) = self.multisampled()
        origin, direction = pixel_rays(scene.eyes[0])
        _, t1, _ = sphere_and_plane(origin, direction)
        back = dilate(dilate(hit & (tp < t1)) & dilate(hit & (tp > t1)))  # (seen through)
        away = ~silhouette & ~crossing & ~back & ~plane_edges(origin, direction)
        edge = silhouette & ~crossing & ~dilate(dilate(hit & ~(tp > t0)))

        def interactive(target):
            def configure(window, renderer):
                window.SetDesiredUpdateRate(15)
                target.mapper.AutoAdjustSampleDistancesOff()
                target.mapper.SetInteractiveImageSampleDistance(2)
            return configure
        one_ray, _, _ = self.scene.render(True)
        for name, many, one in (
                ("interactive", lambda: scene.render(True, interactive(scene)),
                 lambda: self.scene.render(True, interactive(self.scene))),
                ("translucent", lambda: scene.render(True, opacity=0.5),
                 lambda: self.scene.render(True, opacity=0.5))):
            many, one = many()[0], one()[0]
            self.assertEqual(scene.messages.errors, [])
            if name == "interactive":
                self.assertEqual(scene.mapper.GetLastImageSampleDistance(), 2.0)
                self.assertEqual(self.scene.mapper.GetLastImageSampleDistance(), 2.0)
            gap = np.abs(many[..., :3] - one[..., :3]).max(axis=2) > COLOR_TOLERANCE
            report("multisampling (8), " + name, "%d of %d pixels differ from the single-sampled "
                   "window's frame away from the silhouette, the crossing and the plane's "
                   "outline; %d of %d silhouette pixels (polygons' still picture: %d)"
                   % ((gap & away).sum(), away.sum(), (gap & edge).sum(), edge.sum(),
                      differing_pixels(np.where(edge[..., None], polygons, 0),
                                       np.where(edge[..., None], one_ray, 0))))
            self.assertLessEqual(int((gap & away).sum()), SILHOUETTE_PIXELS)
            self.assertLessEqual(int((gap & edge).sum()), SILHOUETTE_PIXELS)

    def test_multisampling_background_refinement(self):
        """In a multisampled window with an event loop, the still frame after interaction is
        cast in the background (a full-resolution cast): its silhouette gets its per-sample rays
        there too, and the frame the loop shows equals a synchronous still frame's, which is
        smoothed (a flat-coloured sphere: silhouette pixels blending it with the background)."""
        import time
        from vtkmodules.vtkRenderingCore import vtkRenderWindowInteractor
        from test_mapper import scene as mapper_scene
        window = vtkRenderWindow()  # on screen, as an event loop's window is
        window.SetMultiSamples(8)
        window.SetSize(W, H)
        window, renderer, mapper, actor = mapper_scene(self.scene.mesh, window=window)
        actor.GetProperty().SetColor(*SPHERE_COLOR)
        actor.GetProperty().LightingOff()
        mapper.AutoAdjustSampleDistancesOff()
        mapper.SetInteractiveImageSampleDistance(2)
        interactor = vtkRenderWindowInteractor()
        interactor.SetRenderWindow(window)
        interactor.SetStillUpdateRate(0.0001)
        interactor.Initialize()

        def process_events(until, seconds):
            end = time.perf_counter() + seconds
            while not until() and time.perf_counter() < end:
                interactor.ProcessEvents()
                time.sleep(0.005)
            return until()
        window.SetDesiredUpdateRate(0.0001)
        window.Render()
        process_events(lambda: False, 0.2)  # (the loop runs: the mapper's timer fires)
        renderer.GetActiveCamera().Azimuth(10)
        window.SetDesiredUpdateRate(15)
        window.Render()
        window.SetDesiredUpdateRate(0.0001)
        window.Render()
        self.assertTrue(mapper.GetLastRenderRefining(), "the full frame is cast in the background")
        self.assertTrue(process_events(lambda: tuple(mapper.GetLastCastSize()) == (W, H), 60))
        refined = rgba(window), zbuffer(window)
        mapper.ProgressiveRefinementOff()  # (a changed setting: cast again, synchronously)
        window.Render()
        self.assertFalse(mapper.GetLastRenderReusedImage())
        still = rgba(window), zbuffer(window)
        sphere = np.array(SPHERE_COLOR) * 255
        share = still[0][..., 0] / 255.0  # (the background is black)
        blended = (np.abs(still[0][..., :3] - share[..., None] * sphere).max(axis=2) <= 3) & \
            (share > 0.05) & (share < 0.95)
        report("multisampling (8), background refinement",
               "%d pixels differ from the synchronous still frame; %d silhouette pixels blended"
               % (differing_pixels(refined[0], still[0]), blended.sum()))
        np.testing.assert_array_equal(refined[1], still[1])
        np.testing.assert_array_equal(refined[0], still[0])
        self.assertGreater(int(blended.sum()), 50)
        interactor.TerminateApp()
        window.Finalize()

    def test_depth_peeling(self):
        """Depth peeling (VTK's and ParaView's way to draw translucent geometry). A translucent
        sphere (opacity 0.5) alone: against the polygon sphere's picture. With the opaque plane
        through it: against the blend composed from pictures of one surface each (the opaque
        sphere O, the plane P, the translucent sphere alone S), chosen per pixel by where the
        pixel's ray meets the plane (t_p) and the sphere (t_0 < t_1): P before the sphere,
        O / 2 + P / 2 between its walls, S + P / 4 behind both. (The polygon sphere's picture is
        reported against the same blend: VTK 9.2's peeling drops its far wall where the plane is
        just behind it.)"""
        def peeling(plane=True, sphere=True):
            def configure(window, renderer):
                renderer.UseDepthPeelingOn()
                renderer.SetMaximumNumberOfPeels(8)
                renderer.SetOcclusionRatio(0.0)
                actors = renderer.GetActors()
                if not plane:
                    renderer.RemoveActor(actors.GetLastActor())
                if not sphere:
                    renderer.RemoveActor(actors.GetItemAsObject(0))
            return configure
        lit = dict(lighting=True)
        alone, _, polygons, _, _ = self.pair(peeling(plane=False), opacity=0.5, **lit)
        differ = differing_pixels(alone, polygons)
        report("depth peeling, sphere alone", "%d pixels differ from polygons" % differ)
        self.assertLessEqual(differ, SILHOUETTE_PIXELS)

        rays = pixel_rays(self.scene.render(True, peeling(plane=False), **lit)[2][0])
        t0, t1, tp = sphere_and_plane(*rays)
        clear = np.isfinite(t0) & (np.minimum(np.abs(tp - t0), np.abs(tp - t1)) > 0.02)
        for exact in (True, False):
            opaque = self.scene.render(exact, peeling(plane=False), **lit)[0][..., :3]
            plane = self.scene.render(exact, peeling(sphere=False), **lit)[0][..., :3]
            single = self.scene.render(exact, peeling(plane=False), opacity=0.5, **lit)[0][..., :3]
            both = self.scene.render(exact, peeling(), opacity=0.5, **lit)[0][..., :3]
            blend = np.where((tp < t0)[..., None], plane, np.where(
                (tp < t1)[..., None], (opaque + plane) / 2, single + plane / 4))
            wrong = int(((np.abs(both - blend).max(axis=2) > COLOR_TOLERANCE + 2) & clear).sum())
            report("depth peeling, opaque plane" + ("" if exact else " (polygons)"),
                   "%d of %d pixels differ from the composed blend" % (wrong, clear.sum()))
            if exact:
                self.assertEqual(wrong, 0)

    def test_translucent_neighbours(self):
        """A translucent sphere with a translucent plane: the sphere is blended over the frame
        after the plane, which neither depth peeling nor order-independent translucency can
        interleave with it: a warning naming the technique and the count of such props, once
        per change (none with the plane opaque)."""
        def translucency(peeling):
            def configure(window, renderer):
                renderer.SetUseDepthPeeling(peeling)
            return configure
        expected = {True: "depth peeling", False: "order-independent translucency"}
        for peeling in (True, False):
            for plane_opacity in (1.0, 0.5):
                self.scene.render(True, translucency(peeling), opacity=0.5,
                                  plane_opacity=plane_opacity)
                warnings = [w for w in self.scene.messages.warnings if "translucent" in w]
                report("translucent plane (%s), plane opacity %g" % (expected[peeling],
                                                                     plane_opacity),
                       "%d warnings%s" % (len(warnings), ": " + warnings[0].split("): ")[-1].strip()
                                          if warnings else ""))
                self.assertEqual(len(warnings), 1 if plane_opacity < 1 else 0)
                if warnings:
                    self.assertIn("after the view's 1 other translucent prop: "
                                  + expected[peeling] + " cannot interleave", warnings[0])
                    self.scene.window.Render()  # (again: no new warning)
                    self.assertEqual(
                        len([w for w in self.scene.messages.warnings if "translucent" in w]), 1)

if __name__ == "__main__":
    result = unittest.main(exit=False, verbosity=2).result
    print("\nmode -> result")
    for mode, text in RESULTS:
        print("  %-34s %s" % (mode, text))
    sys.exit(0 if result.wasSuccessful() else 1)
