"""The isosurface in a PyVista plotter: `add_isosurface(plotter, grid, value, ...)`; and the exact
isosurface as data: `exact_contour(grid, isosurfaces, ...)`, a pyvista.PolyData made by
tetdsr.vtkDirectSurfaceContour (at the end of this file).

The surface is cast by tetdsr.vtkDirectSurfaceRayCaster with the plotter's camera and its
renderer's size in pixels, and drawn by a quad actor in the plotter's renderer whose shaders
(vtkShaderProperty replacements) write each pixel's cast colour and the exact hit's window depth:
the plotter's meshes and the surface hide one another by depth. Before each frame the image is
cast again if the camera or the size changed (and its depth recomputed if the projection did);
while the mouse drags the camera the cast is made at `interactive_scale` of the resolution, and
at full resolution when the interaction ends. `DirectSurface.pick(x, y)` gives the exact hit at a
display position, and the interactor's picker (PyVista's enable_point_picking and
enable_surface_point_picking, with a point or cell picker) picks it exactly.

Limits of this route (the C++ build's vtkDirectSurfaceMapper has none of them): translucent
surfaces are drawn in VTK's translucent pass as one image, depth-tested at the nearest crossing
(an opaque mesh between two crossings is covered by the farther one's colour; not sorted per
pixel with other translucent props); with PyVista's enable_depth_peeling, translucent surfaces
are not drawn correctly (opaque ones are; seen with pip's VTK 9.7.2 through EGL, where PyVista's
own translucent meshes vanish too); the "hardware" picker and cell or mesh picking do not see
the surface; the renderer's camera is used through its position, focal point, view up, view
angle and parallel projection (no off-axis window centre, no stereo).

Several add_isosurface calls on one plotter share that image: each surface is cast with the same
camera and size, and the images are composited pixel by pixel by depth, so that they hide one
another (exactly for opaque surfaces; translucent ones of different calls are ordered by their
nearest hit).
"""
import math
import numbers
import warnings

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand, vtkLookupTable, vtkPoints
from vtkmodules.vtkCommonDataModel import (vtkCellArray, vtkCompositeDataSet, vtkDataObject,
                                           vtkImageData, vtkPlane, vtkPolyData, vtkUnstructuredGrid)
from vtkmodules.vtkRenderingCore import vtkActor, vtkCamera, vtkPolyDataMapper, vtkTexture
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the OpenGL mapper: shader replacements)

from . import _core
from .contour import vtkDirectSurfaceContour
from .filter import vtkDirectSurfaceRayCaster

_NORMAL_MODES = {"exact": 0, "central": 1, "nodal": 2, "depth": 3}
_CAPPING = {None: vtkDirectSurfaceRayCaster.NO_CAP,
            "below": vtkDirectSurfaceRayCaster.CAP_BELOW_ISO_VALUE,
            "above": vtkDirectSurfaceRayCaster.CAP_ABOVE_ISO_VALUE}


def _real(name, value, caller="add_isosurface"):
    """`value` as a float if it is a number (not a bool); a TypeError naming the argument
    otherwise."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{caller}: {name} must be a number, got {value!r}")
    return float(value)


def _number(name, value, lo=-math.inf, hi=math.inf, low_open=False):
    """`value` as a float if it is a finite number in [lo, hi] ((lo, hi] with low_open); a
    TypeError or ValueError naming the argument otherwise."""
    number = _real(name, value)
    if not math.isfinite(number) or number < lo or number > hi or (low_open and number == lo):
        bounds = f" in {'(' if low_open else '['}{lo:g}, {hi:g}]" if math.isfinite(hi - lo) else ""
        raise ValueError(f"add_isosurface: {name} must be a finite number{bounds}, got {value!r}")
    return number


# The rows of the core's settings table (Filters/Core/tetdsr/input/Settings.h) the arguments set.
_ROWS = {row.name: row for row in _core.SETTINGS}


def _shading(caster, **numbers):
    """Sets each shading number (argument name -> value: specular_power -> SetSpecularPower), a
    finite number within its row's range; a TypeError or ValueError naming the argument
    otherwise."""
    for argument, value in numbers.items():
        row = _ROWS["".join(word.title() for word in argument.split("_"))]
        getattr(caster, "Set" + row.name)(_number(argument, value, row.lo, row.hi))


def _fed(filter_, grid, values, scalars):
    """`filter_` given the grid, the iso-values and the field (`scalars`: a point array's name, or
    None for the active scalars), as both functions feed their filter."""
    filter_.SetInputData(grid)
    filter_.SetNumberOfContours(len(values))
    for i, v in enumerate(values):
        filter_.SetValue(i, v)
    if scalars is not None:
        filter_.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, scalars)
    return filter_


def _choice(name, value, choices):
    if value not in choices:
        raise ValueError(f"add_isosurface: {name} must be one of {', '.join(map(repr, choices))}, "
                         f"got {value!r}")
    return choices[value]


def _checked_grid(grid, caller="add_isosurface"):
    """The grid, if it is an unstructured grid with cells; a TypeError or ValueError saying what
    it is otherwise (VTK's culling would draw nothing and say nothing)."""
    if isinstance(grid, vtkCompositeDataSet):
        raise TypeError(f"{caller}: grid is a multiblock dataset (" + (
            "empty" if grid.GetNumberOfCells() == 0 else f"{grid.GetNumberOfCells()} cells") +
            "): pass one pyvista.UnstructuredGrid (e.g. multiblock.combine())")
    if not isinstance(grid, vtkUnstructuredGrid):
        raise TypeError(f"{caller}: grid must be a pyvista.UnstructuredGrid, "
                        f"got {type(grid).__name__}")
    if grid.GetNumberOfCells() == 0 or grid.GetNumberOfPoints() == 0:
        raise ValueError(f"{caller}: the grid is empty ({grid.GetNumberOfPoints()} points, "
                         f"{grid.GetNumberOfCells()} cells)")
    return grid


def _iso_values(value, caller, name, finite=False):
    """A number or a sequence of numbers as a list of floats (not empty; each finite with
    `finite`, else judged by the core); a TypeError or ValueError naming the argument otherwise."""
    values = [value] if np.ndim(value) == 0 else list(value)
    if not values:
        raise ValueError(f"{caller}: {name} is an empty list: give one iso-value or more")
    check = _number if finite else (lambda label, v: _real(label, v, caller))
    return [check(f"{name} {v!r}" if len(values) > 1 else name, v) for v in values]


def _rgb(color):
    """A colour as PyVista understands it (name, hex, RGB in [0, 1] or 0-255) as floats."""
    import pyvista
    return pyvista.Color(color).float_rgb


# The quad that draws the cast image among the plotter's props: its vertices are the corners of
# the surfaces' bounding box (so that VTK's culling and clipping ranges see the meshes), but the
# vertex shader puts its two triangles over the whole viewport, and the fragment shader writes
# each pixel's cast colour and exact window depth (packed in 24 bits), discarding pixels the rays
# miss. gl_VertexID gives the corner (the attribute names of texture coordinates differ between
# VTK versions).
_QUAD_VERTEX_DECLARATIONS = "//VTK::PositionVC::Dec\nout vec2 tetdsrUV;\n"
_QUAD_VERTEX = """
  tetdsrUV = vec2(gl_VertexID == 1 || gl_VertexID == 2 ? 1.0 : 0.0, gl_VertexID >= 2 ? 1.0 : 0.0);
  gl_Position = vec4(tetdsrUV * 2.0 - 1.0, 0.0, 1.0);
"""
_QUAD_FRAGMENT_DECLARATIONS = "//VTK::PositionVC::Dec\nin vec2 tetdsrUV;\n"
_QUAD_FRAGMENT = """
  vec4 tetdsrPacked = texture(tetdsrDepth, tetdsrUV);
  if (tetdsrPacked.a < 0.5) { discard; }
  gl_FragDepth = dot(tetdsrPacked.rgb, vec3(255.0 / 256.0, 255.0 / 65536.0, 255.0 / 16777216.0));
  gl_FragData[0] = texture(tetdsrColor, tetdsrUV);
"""


def _texture():
    image = vtkImageData()
    texture = vtkTexture()
    texture.SetInputData(image)
    texture.InterpolateOff()
    texture.MipmapOff()
    texture.RepeatOff()
    texture.SetColorModeToDirectScalars()
    return texture, image


def _set_pixels(image, pixels):
    """`pixels` ((height, width, components) uint8, row 0 the bottom) as the image's scalars."""
    height, width, components = pixels.shape
    image.SetDimensions(width, height, 1)
    array = numpy_to_vtk(pixels.reshape(-1, components), deep=1)
    array.SetName("pixels")
    image.GetPointData().SetScalars(array)
    image.Modified()


def _pack_depth(depth, covered):
    """Window depths in [0, 1] as 24-bit integers in the red, green and blue bytes (most
    significant first), alpha 255 where covered and 0 elsewhere: what the fragment shader reads
    back exactly (a depth buffer holds 24 bits)."""
    k = np.minimum(np.round(depth.astype(np.float64) * 16777216.0), 16777215.0).astype(np.int64)
    packed = np.empty(depth.shape + (4,), np.uint8)
    packed[..., 0] = k >> 16
    packed[..., 1] = (k >> 8) & 255
    packed[..., 2] = k & 255
    packed[..., 3] = np.where(covered, 255, 0)
    return packed


class _SharedImage:
    """The image every DirectSurface of one plotter renderer is shown in, drawn by one quad actor
    among the renderer's props with each pixel's exact window depth: each surface's caster casts
    with the renderer's camera and size, and the images are composited per pixel front to back
    by their Depth (the first hit along the same ray), so that surfaces of separate
    add_isosurface calls hide one another as they should; the nearest hit's window depth goes to
    the depth buffer. Exact for opaque surfaces; translucent surfaces of different calls are
    ordered by their nearest hit (one call with several values orders every layer)."""

    def __init__(self, plotter):
        scene = plotter.renderer
        self.scene_renderer = scene
        window = plotter.render_window if hasattr(plotter, "render_window") else plotter.ren_win
        self.window = window
        self.surfaces = []
        self.interacting = False
        self._view = None   # the camera parameters and size the casters were given
        self._shown = None  # what the textures hold: the casts' times and the projection
        self.color_texture, self.color_image = _texture()
        self.depth_texture, self.depth_image = _texture()
        self.points = vtkPoints()
        self.points.SetNumberOfPoints(4)
        quad = vtkPolyData()
        quad.SetPoints(self.points)
        cells = vtkCellArray()
        cells.InsertNextCell(3, [0, 1, 2])
        cells.InsertNextCell(3, [0, 2, 3])
        quad.SetPolys(cells)
        # (Texture coordinates make the mapper bind the textures; the shader does not read them.)
        tcoords = numpy_to_vtk(np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32), deep=1)
        tcoords.SetName("TCoords")
        quad.GetPointData().SetTCoords(tcoords)
        self.quad = quad
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(quad)
        mapper.ScalarVisibilityOff()
        self.actor = vtkActor()
        self.actor.SetMapper(mapper)
        self.actor.PickableOff()  # picks are exact: DirectSurface.pick and the pick proxy below
        self.actor.GetProperty().LightingOff()
        self.actor.GetProperty().SetTexture("tetdsrColor", self.color_texture)
        self.actor.GetProperty().SetTexture("tetdsrDepth", self.depth_texture)
        shaders = self.actor.GetShaderProperty()
        shaders.AddVertexShaderReplacement("//VTK::PositionVC::Dec", True,
                                           _QUAD_VERTEX_DECLARATIONS, False)
        shaders.AddVertexShaderReplacement("//VTK::PositionVC::Impl", True, _QUAD_VERTEX, False)
        shaders.AddFragmentShaderReplacement("//VTK::PositionVC::Dec", True,
                                             _QUAD_FRAGMENT_DECLARATIONS, False)
        shaders.AddFragmentShaderReplacement("//VTK::TCoord::Impl", True, _QUAD_FRAGMENT, False)
        self.actor.VisibilityOff()  # until something is cast
        scene.AddActor(self.actor)
        # What the interactor's picker (PyVista's enable_point_picking, the P key) finds: before
        # each pick a point at the exact hit under the mouse (and a small triangle through it
        # across the ray, for cell pickers), carrying every point array interpolated there. It
        # is never drawn (its fragments are discarded) but pickable.
        self.pick_proxy = vtkActor()
        self.pick_proxy.SetMapper(vtkPolyDataMapper())
        self.pick_proxy.GetMapper().SetInputData(vtkPolyData())
        self.pick_proxy.GetProperty().LightingOff()
        self.pick_proxy.GetShaderProperty().AddFragmentShaderReplacement(
            "//VTK::Light::Impl", True, "  discard;\n//VTK::Light::Impl", False)
        scene.AddActor(self.pick_proxy)
        self.last_pick = None  # the DirectSurfacePick of the last pick by the interactor's picker
        self._picker = None
        self._picker_tag = None
        self.plotter = plotter
        # Cast, if needed, just before the renderer draws, with the camera it draws with.
        self._tags = [(scene, scene.AddObserver(vtkCommand.StartEvent, self._update))]
        interactor = getattr(plotter, "iren", None)
        interactor = getattr(interactor, "interactor", None)
        if interactor is not None:
            self._tags += [
                (interactor, interactor.AddObserver(vtkCommand.StartInteractionEvent, self._start)),
                (interactor, interactor.AddObserver(vtkCommand.EndInteractionEvent, self._end))]
            # PyVista picks on these (and may have replaced the picker since the last render).
            for event in (vtkCommand.LeftButtonPressEvent, vtkCommand.RightButtonPressEvent,
                          vtkCommand.CharEvent, vtkCommand.KeyPressEvent):
                self._tags.append((interactor, interactor.AddObserver(
                    event, lambda *args: self._watch_picker(), 100.0)))

    @staticmethod
    def of(plotter):
        """The plotter renderer's shared image, made on first use."""
        scene = plotter.renderer
        shared = getattr(scene, "_tetdsr_shared_image", None)
        if shared is None:
            shared = _SharedImage(plotter)
            scene._tetdsr_shared_image = shared
        return shared

    def fit_bounds(self):
        """The quad's corners span the surfaces' meshes' bounding box (culling and clipping)."""
        boxes = np.array([s.caster.GetInputDataObject(0, 0).GetBounds() for s in self.surfaces])
        lo, hi = boxes[:, 0::2].min(axis=0), boxes[:, 1::2].max(axis=0)
        self.diagonal = float(np.linalg.norm(hi - lo))
        for k, corner in enumerate(((lo[0], lo[1], lo[2]), (hi[0], lo[1], lo[2]),
                                    (hi[0], hi[1], hi[2]), (lo[0], hi[1], hi[2]))):
            self.points.SetPoint(k, *corner)
        self.points.Modified()
        self.quad.Modified()

    def _start(self, *args):
        self.interacting = True

    def _end(self, *args):
        self.interacting = False
        self.window.Render()  # the still frame, at full resolution

    def _watch_picker(self):
        """Observes the interactor's current picker (PyVista replaces it when picking is
        enabled): its picks start with the proxy at the exact hit."""
        interactor = getattr(getattr(self.plotter, "iren", None), "interactor", None)
        picker = interactor.GetPicker() if interactor is not None else None
        if picker is self._picker:
            return
        if self._picker is not None:
            self._picker.RemoveObserver(self._picker_tag)
        self._picker = picker
        self._picker_tag = (picker.AddObserver(vtkCommand.StartPickEvent, self._place_proxy, 10.0)
                            if picker is not None else None)

    def _place_proxy(self, picker, event):
        point = picker.GetSelectionPoint()
        hit = self.pick(point[0], point[1]) if picker.GetRenderer() is self.scene_renderer else None
        self.last_pick = hit
        proxy = vtkPolyData()  # a new one each pick: a callback may keep the last
        if hit is not None:
            p = np.array(hit.position)
            camera = self.scene_renderer.GetActiveCamera()
            across = np.cross(np.array(camera.GetDirectionOfProjection()), camera.GetViewUp())
            across /= np.linalg.norm(across) or 1.0
            up = np.cross(across, camera.GetDirectionOfProjection())
            up /= np.linalg.norm(up) or 1.0
            size = 1e-3 * max(self.diagonal, 1e-300)
            corners = [p + size * (np.cos(a) * across + np.sin(a) * up)
                       for a in (0.0, 2.0944, 4.1888)]
            points = vtkPoints()
            points.SetDataTypeToDouble()
            for x in [p] + corners:
                points.InsertNextPoint(*x)
            proxy.SetPoints(points)
            vertices, triangles = vtkCellArray(), vtkCellArray()
            vertices.InsertNextCell(1, [0])
            triangles.InsertNextCell(3, [1, 2, 3])
            proxy.SetVerts(vertices)
            proxy.SetPolys(triangles)
            for name, value in hit.point_data.items():
                values = np.tile(np.atleast_1d(np.asarray(value, np.float64)), (4, 1))
                array = numpy_to_vtk(values, deep=1)
                array.SetName(name)
                proxy.GetPointData().AddArray(array)
        self.pick_proxy.GetMapper().SetInputData(proxy)

    def _update(self, *args):
        self._watch_picker()
        scene = self.scene_renderer
        camera = scene.GetActiveCamera()
        width, height = scene.GetSize()
        if width <= 0 or height <= 0 or not self.surfaces:
            return
        # One size for all (images are composited pixel by pixel): the coarsest asked for.
        scale = min(s.interactive_scale for s in self.surfaces) if self.interacting else 1.0
        size = (max(1, round(width * scale)), max(1, round(height * scale)))
        view = (camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
                camera.GetViewAngle(), camera.GetParallelProjection(), camera.GetParallelScale(),
                size)
        for surface in self.surfaces:
            if view != self._view:
                for name in ("Position", "FocalPoint", "ViewUp", "ViewAngle", "ParallelProjection",
                             "ParallelScale"):
                    getattr(surface._camera, "Set" + name)(getattr(camera, "Get" + name)())
                surface.caster.SetImageSize(*size)
            surface.caster.Update()
        self._view = view
        self.viewport_size = (width, height)
        # The window depth is that of the projection the renderer draws with now (its clipping
        # range changes as the camera moves).
        matrix = camera.GetCompositeProjectionTransformMatrix(scene.GetTiledAspectRatio(), -1, 1)
        projection = tuple(matrix.GetElement(r, c) for r in range(4) for c in range(4))
        outputs = [s.caster.GetOutput() for s in self.surfaces]
        shown = (tuple(id(s) for s in self.surfaces), tuple(o.GetMTime() for o in outputs),
                 projection, size)
        if shown == self._shown:
            return
        self._shown = shown
        self._show(size, np.array(projection).reshape(4, 4))

    def _show(self, size, projection):
        """The cast images composited front to back by depth into the colour texture, and the
        nearest hit's window depth into the depth texture."""
        pixels = size[0] * size[1]
        depths, colors, windows = [], [], []
        for surface in self.surfaces:
            output = surface.caster.GetOutput()
            data = output.GetPointData()
            rgba = data.GetArray("Colors") if output.GetNumberOfPoints() == pixels else None
            window = surface.caster.WindowDepth(projection) if rgba is not None else None
            if window is None:  # nothing cast (an error was reported): this surface adds nothing
                continue
            colors.append(vtk_to_numpy(rgba).astype(np.float64))
            depths.append(vtk_to_numpy(data.GetArray("Depth")))
            windows.append(window.reshape(-1))
        # Front to back: each layer adds its colour over what is left of the coverage.
        covered = np.zeros((pixels, 1))
        rgb = np.zeros((pixels, 3))
        nearest = np.ones(pixels, np.float32)
        if colors:
            order = np.argsort(np.stack(depths), axis=0, kind="stable")
            stacked = np.stack(colors)
            for k in range(len(colors)):
                layer = np.take_along_axis(stacked, order[k][None, :, None], axis=0)[0]
                alpha = layer[:, 3:] / 255.0
                rgb += (1.0 - covered) * (alpha * layer[:, :3])
                covered += (1.0 - covered) * alpha
            nearest = np.stack(windows).min(axis=0)
        hit = covered[:, 0] > 0.0
        opaque = bool(np.all(covered[hit] >= 1.0))
        with np.errstate(invalid="ignore", divide="ignore"):
            straight = np.where(hit[:, None], rgb / np.maximum(covered, 1e-300), 0.0)
        rgba = np.empty((pixels, 4), np.uint8)
        rgba[:, :3] = np.clip(np.round(straight), 0, 255)
        rgba[:, 3] = np.clip(np.round(covered[:, 0] * 255.0), 0, 255)
        shape = (size[1], size[0])
        _set_pixels(self.color_image, rgba.reshape(shape + (4,)))
        _set_pixels(self.depth_image, _pack_depth(nearest.reshape(shape), hit.reshape(shape)))
        # Opaque: drawn in the opaque pass, writing depth; translucent: blended in the
        # translucent pass, depth-tested against the opaque props.
        self.actor.SetForceOpaque(opaque)
        self.actor.SetForceTranslucent(not opaque)
        self.actor.SetVisibility(bool(hit.any()))

    def pick(self, x, y):
        """The nearest exact hit of the surfaces at the renderer's display position (x, y)."""
        if self._view is None:
            return None
        scene = self.scene_renderer
        origin = scene.GetOrigin()  # (the viewport's lower left, in display pixels)
        width, height = self.viewport_size
        size = self._view[-1]
        u = (x - origin[0]) * size[0] / width
        v = (y - origin[1]) * size[1] / height
        picks = [p for p in (s.caster.Pick(u, v) for s in self.surfaces) if p is not None]
        return min(picks, key=lambda p: p.ray_parameter) if picks else None

    def remove(self, surface):
        """Takes one surface out; the last one out takes the quad out of the plotter."""
        self.surfaces.remove(surface)
        self._shown = None
        if self.surfaces:
            self.fit_bounds()
            return
        for obj, tag in self._tags:
            obj.RemoveObserver(tag)
        self._tags = []
        if self._picker is not None:
            self._picker.RemoveObserver(self._picker_tag)
            self._picker = None
        self.scene_renderer.RemoveActor(self.actor)
        self.scene_renderer.RemoveActor(self.pick_proxy)
        self.scene_renderer._tetdsr_shared_image = None


class DirectSurface:
    """What add_isosurface adds to a plotter: `caster` (the filter: change its settings, then
    `plotter.render()`), `actor` (the quad that draws the cast image with its depth among the
    plotter's props; shared by every DirectSurface of the plotter's renderer) and `renderer`
    (the plotter's)."""

    def __init__(self, plotter, caster, interactive_scale):
        self.plotter = plotter
        self.caster = caster
        self.interactive_scale = interactive_scale
        self._camera = vtkCamera()  # a copy: the plotter's camera changes its clipping range every frame
        caster.SetCamera(self._camera)
        self._shared = _SharedImage.of(plotter)
        self._shared.surfaces.append(self)
        self._shared._view = None  # the new caster casts at the next frame
        self._shared.fit_bounds()
        self.renderer = self._shared.scene_renderer
        self.window = self._shared.window
        self.actor = self._shared.actor

    @property
    def interacting(self):
        return self._shared is not None and self._shared.interacting

    def pick(self, x, y):
        """The exact surface at display position (x, y) of the plotter's render window (VTK's
        convention: pixels from the bottom left, pixel (i, j)'s centre at (i + 0.5, j + 0.5)):
        a tetdsr.filter.DirectSurfacePick (position, normal, cell_id, parametric_coordinates,
        iso_value_index, value, point_data with every point array interpolated there, ...) of the
        nearest of the plotter's Direct Surfaces, or None where none is hit (or before the first
        render). Other props in front are not considered: the interactor's picker (PyVista's
        enable_point_picking or enable_surface_point_picking) weighs them."""
        return self._shared.pick(x, y) if self._shared is not None else None

    def remove(self):
        """Takes the surface out of the plotter."""
        if self._shared is not None:
            self._shared.remove(self)
            self._shared = None


def add_isosurface(plotter, grid, value, scalars=None, *, color="white", colors=None,
                   opacities=None, color_by=None, cmap=None, clim=None, clipping_planes=(),
                   capping=None, ambient=_ROWS["Ambient"].defaults[0],
                   diffuse=_ROWS["Diffuse"].defaults[0], specular=_ROWS["Specular"].defaults[0],
                   specular_power=_ROWS["SpecularPower"].defaults[0], normal_mode="exact",
                   threads=0, interactive_scale=0.25):
    """Adds the exact isosurface(s) `value` (a number or a list) of the point array `scalars`
    (default: the active scalars) of `grid` (a pyvista.UnstructuredGrid of tetrahedra, hexahedra,
    wedges and pyramids of orders 1 to 4: linear, quadratic, Lagrange, Bezier) to `plotter`, seen
    with its camera at its
    renderer's size. Returns a DirectSurface.

    color / colors: the surfaces' colour, or one per iso-value; opacities: one per iso-value
    (translucent nested surfaces); color_by: a point array interpolated on the surface and mapped
    through `cmap` (a matplotlib colour map name; default cool to warm) over `clim` (default the
    array's range); clipping_planes: (origin, normal) pairs, each keeping the side its normal
    points to; capping: None, "below" or "above" (the iso-value) for the cut's cap;
    normal_mode: "exact", "central", "nodal" or "depth"; threads: 0 for all cores.
    """
    grid = _checked_grid(grid)
    values = _iso_values(value, "add_isosurface", "value", finite=True)
    interactive_scale = _number("interactive_scale", interactive_scale, 0.0, 1.0, low_open=True)
    normal_mode = _choice("normal_mode", normal_mode, _NORMAL_MODES)
    capping = _choice("capping", capping, _CAPPING)
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral) or threads < 0:
        raise ValueError(f"add_isosurface: threads must be an integer >= 0 (0: all cores), got {threads!r}")
    caster = _fed(vtkDirectSurfaceRayCaster(), grid, values, scalars)
    caster.SetSurfaceColor(*_rgb(color))
    for i, c in enumerate(colors or ()):
        caster.SetIsoValueColor(i, *_rgb(c))
    for i, a in enumerate(opacities or ()):
        caster.SetIsoValueOpacity(i, a)
    if color_by is not None:
        caster.ColorByArrayOn()
        caster.SetInputArrayToProcess(1, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, color_by)
        if cmap is not None:
            import pyvista
            table = pyvista.LookupTable(cmap=cmap)
            lookup = vtkLookupTable()
            lookup.DeepCopy(table)
            lookup.SetRange(0.0, 1.0)
            caster.SetLookupTable(lookup)
        if clim is not None:
            caster.SetColorRange(*clim)
    for origin, normal in clipping_planes:
        plane = vtkPlane()
        plane.SetOrigin(*origin)
        plane.SetNormal(*normal)
        caster.AddClippingPlane(plane)
    caster.SetCapping(capping)
    _shading(caster, ambient=ambient, diffuse=diffuse, specular=specular,
             specular_power=specular_power)
    caster.SetNormalMode(normal_mode)
    caster.SetNumberOfThreads(int(threads))
    return DirectSurface(plotter, caster, interactive_scale)


def exact_contour(grid, isosurfaces, scalars=None, *, tolerance=_ROWS["Tolerance"].defaults[0],
                  absolute_tolerance=_ROWS["AbsoluteTolerance"].defaults[0], integrals=True):
    """The exact isosurface(s) `isosurfaces` (a number or a list) of the point array `scalars`
    (default: the active scalars) of `grid` (a pyvista.UnstructuredGrid of tetrahedra, hexahedra,
    wedges and pyramids of orders 1 to 4: linear, quadratic, Lagrange, Bezier) as a
    pyvista.PolyData: a watertight triangle surface whose vertices lie on the true surface (roots
    of each cell's own field, certified) and whose every triangle lies within a certified distance
    of it; every piece is found, also where no nodal value crosses the iso-value (where
    grid.contour finds nothing).

    tolerance: the largest distance between the triangles and the true surface, relative to the
    diagonal of the grid's valid cells' box; absolute_tolerance: the same in the grid's units
    (0: use tolerance); integrals: compute the area, the enclosed volume and the integral of every
    point array over the curved surface.

    The result holds point data "Normals" (the field's exact unit gradient) and every numeric
    point array of the grid interpolated at the vertices; cell data "vtkOriginalCellIds" and
    "IsoValue"; field data "IsoValues", and per iso-value "Area", "AreaError", "Volume" (of the
    region where the field >= the iso-value), "VolumeError", "FlatArea" (the triangles' area),
    "<name> Integral" and "<name> IntegralError" per point array (with `integrals`), and
    "DistanceBound", "LargestCertifiedBound", "Subcells", "UnresolvedSubcells",
    "SizeCertifiedSubcells", "BoundaryEdges" (edges of one triangle: where the surface meets the
    grid's boundary), "NonManifoldEdges".

    Settings the core refuses (a negative tolerance, a NaN iso-value, an array not found) raise
    ValueError with its message; its warnings (pieces left uncertified) are Python warnings.
    """
    grid = _checked_grid(grid, "exact_contour")
    values = _iso_values(isosurfaces, "exact_contour", "isosurfaces")
    contour = _fed(vtkDirectSurfaceContour(), grid, values, scalars)
    contour.SetTolerance(_real("tolerance", tolerance, "exact_contour"))
    contour.SetAbsoluteTolerance(_real("absolute_tolerance", absolute_tolerance, "exact_contour"))
    contour.SetComputeIntegrals(bool(integrals))
    told = {vtkCommand.ErrorEvent: [], vtkCommand.WarningEvent: []}
    for event, texts in told.items():
        contour.AddObserver(event, calldata_type(VTK_STRING)(
            lambda caller, name, text, texts=texts: texts.append(text)))
    contour.Update()
    for text in told[vtkCommand.WarningEvent]:
        warnings.warn(text, RuntimeWarning, stacklevel=2)
    if told[vtkCommand.ErrorEvent]:
        raise ValueError(told[vtkCommand.ErrorEvent][0])
    import pyvista
    return pyvista.PolyData(contour.GetOutput())
