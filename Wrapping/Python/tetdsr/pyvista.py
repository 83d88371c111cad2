"""The isosurface in a PyVista plotter: `add_isosurface(plotter, grid, value, ...)`.

The surface is cast by tetdsr.vtkDirectSurfaceRayCaster with the plotter's camera and its
renderer's size in pixels, and shown as an image in a renderer of its own under the plotter's
(render window layer 0; the plotter's renderer moves to layer 1 and draws its props over it).
Before each frame the image is cast again if the camera or the size changed; while the mouse
drags the camera the cast is made at `interactive_scale` of the resolution, and at full
resolution when the interaction ends.

Limits of this route (the C++ build's vtkDirectSurfaceMapper has none of them): the surface has no
depth in the plotter's scene, so the plotter's own meshes are always drawn over it; it is
composited over the renderer's (first) background colour, not a gradient or an image; the
renderer's camera is used through its position, focal point, view up, view angle and parallel
projection (no off-axis window centre, no stereo).

Several add_isosurface calls on one plotter share that image: each surface is cast with the same
camera and size, and the images are composited pixel by pixel by depth, so that they hide one
another (exactly for opaque surfaces; translucent ones of different calls are ordered by their
nearest hit).
"""
import math
import numbers

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand, vtkLookupTable
from vtkmodules.vtkCommonDataModel import (vtkCompositeDataSet, vtkDataObject, vtkImageData,
                                           vtkPlane, vtkUnstructuredGrid)
from vtkmodules.vtkRenderingCore import vtkCamera, vtkImageActor, vtkRenderer

from . import _core
from .filter import vtkDirectSurfaceRayCaster

_NORMAL_MODES = {"exact": 0, "central": 1, "nodal": 2, "depth": 3}
_CAPPING = {None: vtkDirectSurfaceRayCaster.NO_CAP,
            "below": vtkDirectSurfaceRayCaster.CAP_BELOW_ISO_VALUE,
            "above": vtkDirectSurfaceRayCaster.CAP_ABOVE_ISO_VALUE}


def _number(name, value, lo=-math.inf, hi=math.inf, low_open=False):
    """`value` as a float if it is a finite number in [lo, hi] ((lo, hi] with low_open); a
    TypeError or ValueError naming the argument otherwise."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"add_isosurface: {name} must be a number, got {value!r}")
    number = float(value)
    if not math.isfinite(number) or number < lo or number > hi or (low_open and number == lo):
        bounds = f" in {'(' if low_open else '['}{lo:g}, {hi:g}]" if math.isfinite(hi - lo) else ""
        raise ValueError(f"add_isosurface: {name} must be a finite number{bounds}, got {value!r}")
    return number


def _range(setting):
    """The core's range of a shading number (Filters/Core/tetdsr/Settings.h)."""
    number = _core.NUMBER_SETTINGS[setting]
    return number.lo, number.hi


def _choice(name, value, choices):
    if value not in choices:
        raise ValueError(f"add_isosurface: {name} must be one of {', '.join(map(repr, choices))}, "
                         f"got {value!r}")
    return choices[value]


def _checked_grid(grid):
    """The grid, if it is an unstructured grid with cells; a TypeError or ValueError saying what
    it is otherwise (VTK's culling would draw nothing and say nothing)."""
    if isinstance(grid, vtkCompositeDataSet):
        raise TypeError("add_isosurface: grid is a multiblock dataset (" + (
            "empty" if grid.GetNumberOfCells() == 0 else f"{grid.GetNumberOfCells()} cells") +
            "): pass one pyvista.UnstructuredGrid (e.g. multiblock.combine())")
    if not isinstance(grid, vtkUnstructuredGrid):
        raise TypeError(f"add_isosurface: grid must be a pyvista.UnstructuredGrid of quadratic "
                        f"tetrahedra, got {type(grid).__name__}")
    if grid.GetNumberOfCells() == 0 or grid.GetNumberOfPoints() == 0:
        raise ValueError(f"add_isosurface: the grid is empty ({grid.GetNumberOfPoints()} points, "
                         f"{grid.GetNumberOfCells()} cells)")
    return grid


def _rgb(color):
    """A colour as PyVista understands it (name, hex, RGB in [0, 1] or 0-255) as floats."""
    import pyvista
    return pyvista.Color(color).float_rgb


class _SharedImage:
    """The image every DirectSurface of one plotter renderer is shown in: each surface's caster
    casts with the same camera and size, and the images are composited per pixel front to back
    by their Depth (the first hit along the same ray), so that surfaces of separate
    add_isosurface calls hide one another as they should. Exact for opaque surfaces; translucent
    surfaces of different calls are ordered by their nearest hit (one call with several values
    orders every layer)."""

    def __init__(self, plotter):
        scene = plotter.renderer
        self.scene_renderer = scene
        window = plotter.render_window if hasattr(plotter, "render_window") else plotter.ren_win
        self.window = window
        self.surfaces = []
        self.interacting = False
        self._view = None   # the camera parameters and size of the image shown
        self._shown = None  # the casters' output times of the image shown
        self.image = vtkImageData()
        self.image_actor = vtkImageActor()
        self.image_actor.GetMapper().SetInputData(self.image)
        self.image_actor.GetMapper().BorderOn()  # whole pixels: the image covers the viewport
        self.image_actor.InterpolateOff()
        self.renderer = vtkRenderer()
        self.renderer.SetLayer(0)
        self.renderer.InteractiveOff()
        self.renderer.SetViewport(scene.GetViewport())
        self.renderer.AddViewProp(self.image_actor)
        self.renderer.GetActiveCamera().ParallelProjectionOn()
        window.SetNumberOfLayers(max(window.GetNumberOfLayers(), 2))
        scene.SetLayer(1)  # drawn over the image; layers above 0 keep the colour buffer
        window.AddRenderer(self.renderer)
        # Cast, if needed, just before the image's renderer draws (it draws first: layer 0).
        self._tags = [(self.renderer, self.renderer.AddObserver(vtkCommand.StartEvent, self._update))]
        interactor = getattr(plotter, "iren", None)
        interactor = getattr(interactor, "interactor", None)
        if interactor is not None:
            self._tags += [
                (interactor, interactor.AddObserver(vtkCommand.StartInteractionEvent, self._start)),
                (interactor, interactor.AddObserver(vtkCommand.EndInteractionEvent, self._end))]

    @staticmethod
    def of(plotter):
        """The plotter renderer's shared image, made on first use."""
        scene = plotter.renderer
        shared = getattr(scene, "_tetdsr_shared_image", None)
        if shared is None:
            shared = _SharedImage(plotter)
            scene._tetdsr_shared_image = shared
        return shared

    def _start(self, *args):
        self.interacting = True

    def _end(self, *args):
        self.interacting = False
        self.window.Render()  # the still frame, at full resolution

    def _update(self, *args):
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
        outputs = [s.caster.GetOutput() for s in self.surfaces]
        shown = (tuple(id(s) for s in self.surfaces), tuple(o.GetMTime() for o in outputs))
        if shown == self._shown and self.image.GetDimensions()[:2] == size:
            return
        self._shown = shown
        self._show(outputs, size, (width, height), scene.GetBackground())

    def _show(self, outputs, size, viewport, background):
        """The cast images composited front to back by depth over the background, fitted to the
        viewport's pixels."""
        pixels = size[0] * size[1]
        depths, colors = [], []
        for output in outputs:
            data = output.GetPointData()
            rgba = data.GetArray("Colors") if output.GetNumberOfPoints() == pixels else None
            if rgba is None:  # nothing cast (an error was reported): this surface adds nothing
                continue
            colors.append(vtk_to_numpy(rgba).astype(np.float64))
            depths.append(vtk_to_numpy(data.GetArray("Depth")))
        # Front to back: each layer adds its colour over what is left of the coverage.
        covered = np.zeros((pixels, 1))
        rgb = np.zeros((pixels, 3))
        if colors:
            order = np.argsort(np.stack(depths), axis=0, kind="stable")
            stacked = np.stack(colors)
            for k in range(len(colors)):
                layer = np.take_along_axis(stacked, order[k][None, :, None], axis=0)[0]
                alpha = layer[:, 3:] / 255.0
                rgb += (1.0 - covered) * (alpha * layer[:, :3])
                covered += (1.0 - covered) * alpha
        rgb = np.round(rgb + (1.0 - covered) * np.array(background) * 255.0).astype(np.uint8)
        self.image.SetDimensions(size[0], size[1], 1)
        spacing = (viewport[0] / size[0], viewport[1] / size[1], 1.0)
        self.image.SetSpacing(spacing)
        # Pixel k's centre at (k + 0.5) * spacing - 0.5, so whole pixels cover [-0.5, w - 0.5].
        self.image.SetOrigin(spacing[0] / 2 - 0.5, spacing[1] / 2 - 0.5, 0.0)
        array = numpy_to_vtk(rgb, deep=1)
        array.SetName("Colors")
        self.image.GetPointData().SetScalars(array)
        self.image.Modified()
        camera = self.renderer.GetActiveCamera()
        centre = ((viewport[0] - 1) / 2, (viewport[1] - 1) / 2)
        camera.SetFocalPoint(centre[0], centre[1], 0.0)
        camera.SetPosition(centre[0], centre[1], 1.0)
        camera.SetViewUp(0.0, 1.0, 0.0)
        camera.SetParallelScale(viewport[1] / 2)
        camera.SetClippingRange(0.5, 1.5)

    def remove(self, surface):
        """Takes one surface out; the last one out takes the image out of the plotter (its
        renderer goes back to layer 0)."""
        self.surfaces.remove(surface)
        self._shown = None
        if self.surfaces:
            return
        for obj, tag in self._tags:
            obj.RemoveObserver(tag)
        self._tags = []
        self.window.RemoveRenderer(self.renderer)
        self.scene_renderer.SetLayer(0)
        self.scene_renderer._tetdsr_shared_image = None


class DirectSurface:
    """What add_isosurface adds to a plotter: `caster` (the filter: change its settings, then
    `plotter.render()`), the background `renderer` holding the image, `image_actor` (both
    shared by every DirectSurface of the plotter's renderer)."""

    def __init__(self, plotter, caster, interactive_scale):
        self.plotter = plotter
        self.caster = caster
        self.interactive_scale = interactive_scale
        self._camera = vtkCamera()  # a copy: the plotter's camera changes its clipping range every frame
        caster.SetCamera(self._camera)
        self._shared = _SharedImage.of(plotter)
        self._shared.surfaces.append(self)
        self._shared._view = None  # the new caster casts at the next frame
        self.scene_renderer = self._shared.scene_renderer
        self.window = self._shared.window
        self.renderer = self._shared.renderer
        self.image = self._shared.image
        self.image_actor = self._shared.image_actor

    @property
    def interacting(self):
        return self._shared is not None and self._shared.interacting

    def remove(self):
        """Takes the surface out of the plotter (once the last is out, the plotter's renderer
        goes back to layer 0)."""
        if self._shared is not None:
            self._shared.remove(self)
            self._shared = None


def add_isosurface(plotter, grid, value, scalars=None, *, color="white", colors=None,
                   opacities=None, color_by=None, cmap=None, clim=None, clipping_planes=(),
                   capping=None, ambient=0.1, diffuse=0.7, specular=0.2, specular_power=30.0,
                   normal_mode="exact", threads=0, interactive_scale=0.25):
    """Adds the exact isosurface(s) `value` (a number or a list) of the point array `scalars`
    (default: the active scalars) of `grid` (a pyvista.UnstructuredGrid of tetrahedra of orders 1
    to 4: linear, quadratic, Lagrange, Bezier) to `plotter`, seen with its camera at its
    renderer's size. Returns a DirectSurface.

    color / colors: the surfaces' colour, or one per iso-value; opacities: one per iso-value
    (translucent nested surfaces); color_by: a point array interpolated on the surface and mapped
    through `cmap` (a matplotlib colour map name; default cool to warm) over `clim` (default the
    array's range); clipping_planes: (origin, normal) pairs, each keeping the side its normal
    points to; capping: None, "below" or "above" (the iso-value) for the cut's cap;
    normal_mode: "exact", "central", "nodal" or "depth"; threads: 0 for all cores.
    """
    grid = _checked_grid(grid)
    values = [value] if np.ndim(value) == 0 else list(value)
    if not values:
        raise ValueError("add_isosurface: value is an empty list: give one iso-value or more")
    values = [_number(f"value {v!r}" if len(values) > 1 else "value", v) for v in values]
    interactive_scale = _number("interactive_scale", interactive_scale, 0.0, 1.0, low_open=True)
    normal_mode = _choice("normal_mode", normal_mode, _NORMAL_MODES)
    capping = _choice("capping", capping, _CAPPING)
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral) or threads < 0:
        raise ValueError(f"add_isosurface: threads must be an integer >= 0 (0: all cores), got {threads!r}")
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(grid)
    caster.SetNumberOfContours(len(values))
    for i, v in enumerate(values):
        caster.SetValue(i, v)
    if scalars is not None:
        caster.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, scalars)
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
    caster.SetAmbient(_number("ambient", ambient, *_range("Ambient")))
    caster.SetDiffuse(_number("diffuse", diffuse, *_range("Diffuse")))
    caster.SetSpecular(_number("specular", specular, *_range("Specular")))
    caster.SetSpecularPower(_number("specular_power", specular_power, *_range("SpecularPower")))
    caster.SetNormalMode(normal_mode)
    caster.SetNumberOfThreads(int(threads))
    return DirectSurface(plotter, caster, interactive_scale)
