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
"""
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand, vtkLookupTable
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData, vtkPlane
from vtkmodules.vtkRenderingCore import vtkCamera, vtkImageActor, vtkRenderer

from .filter import vtkDirectSurfaceRayCaster

_CAPPING = {None: vtkDirectSurfaceRayCaster.NO_CAP,
            "below": vtkDirectSurfaceRayCaster.CAP_BELOW_ISO_VALUE,
            "above": vtkDirectSurfaceRayCaster.CAP_ABOVE_ISO_VALUE}


def _rgb(color):
    """A colour as PyVista understands it (name, hex, RGB in [0, 1] or 0-255) as floats."""
    import pyvista
    return pyvista.Color(color).float_rgb


class DirectSurface:
    """What add_isosurface adds to a plotter: `caster` (the filter: change its settings, then
    `plotter.render()`), the background `renderer` holding the image, `image_actor`."""

    def __init__(self, plotter, caster, interactive_scale):
        self.plotter = plotter
        self.caster = caster
        self.interactive_scale = float(interactive_scale)
        self.interacting = False
        self._view = None       # the camera parameters and size of the image shown
        self._output_time = -1  # the caster output's modification time of the image shown
        self._camera = vtkCamera()  # a copy: the plotter's camera changes its clipping range every frame
        caster.SetCamera(self._camera)

        scene = plotter.renderer
        self.scene_renderer = scene
        window = plotter.render_window if hasattr(plotter, "render_window") else plotter.ren_win
        self.window = window
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

    def _start(self, *args):
        self.interacting = True

    def _end(self, *args):
        self.interacting = False
        self.window.Render()  # the still frame, at full resolution

    def _update(self, *args):
        scene = self.scene_renderer
        camera = scene.GetActiveCamera()
        width, height = scene.GetSize()
        if width <= 0 or height <= 0:
            return
        scale = self.interactive_scale if self.interacting else 1.0
        size = (max(1, round(width * scale)), max(1, round(height * scale)))
        view = (camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
                camera.GetViewAngle(), camera.GetParallelProjection(), camera.GetParallelScale(),
                size)
        if view != self._view:
            self._view = view
            for name in ("Position", "FocalPoint", "ViewUp", "ViewAngle", "ParallelProjection",
                         "ParallelScale"):
                getattr(self._camera, "Set" + name)(getattr(camera, "Get" + name)())
            self.caster.SetImageSize(*size)
        self.caster.Update()
        output = self.caster.GetOutput()
        if output.GetMTime() == self._output_time and self.image.GetDimensions()[:2] == size:
            return
        self._output_time = output.GetMTime()
        self._show(output, size, (width, height), scene.GetBackground())

    def _show(self, output, size, viewport, background):
        """The cast image composited over the background, fitted to the viewport's pixels."""
        colors = output.GetPointData().GetArray("Colors") if output.GetNumberOfPoints() else None
        if colors is None:  # nothing cast (an error was reported): the background only
            rgb = np.tile(np.round(np.array(background) * 255).astype(np.uint8), (size[0] * size[1], 1))
        else:
            rgba = vtk_to_numpy(colors).astype(np.float64)
            alpha = rgba[:, 3:] / 255.0
            rgb = np.round(rgba[:, :3] * alpha + (1.0 - alpha) * np.array(background) * 255.0)
            rgb = rgb.astype(np.uint8)
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

    def remove(self):
        """Takes the surface out of the plotter (the plotter's renderer goes back to layer 0)."""
        for obj, tag in self._tags:
            obj.RemoveObserver(tag)
        self._tags = []
        self.window.RemoveRenderer(self.renderer)
        self.scene_renderer.SetLayer(0)


def add_isosurface(plotter, grid, value, scalars=None, *, color="white", colors=None,
                   opacities=None, color_by=None, cmap=None, clim=None, clipping_planes=(),
                   capping=None, ambient=0.1, diffuse=0.7, specular=0.2, specular_power=30.0,
                   normal_mode="exact", threads=0, interactive_scale=0.25):
    """Adds the exact isosurface(s) `value` (a number or a list) of the point array `scalars`
    (default: the active scalars) of `grid` (a pyvista.UnstructuredGrid of quadratic tets) to
    `plotter`, seen with its camera at its renderer's size. Returns a DirectSurface.

    color / colors: the surfaces' colour, or one per iso-value; opacities: one per iso-value
    (translucent nested surfaces); color_by: a point array interpolated on the surface and mapped
    through `cmap` (a matplotlib colour map name; default cool to warm) over `clim` (default the
    array's range); clipping_planes: (origin, normal) pairs, each keeping the side its normal
    points to; capping: None, "below" or "above" (the iso-value) for the cut's cap;
    normal_mode: "exact", "central", "nodal" or "depth"; threads: 0 for all cores.
    """
    caster = vtkDirectSurfaceRayCaster()
    caster.SetInputData(grid)
    values = [value] if np.ndim(value) == 0 else list(value)
    caster.SetNumberOfContours(len(values))
    for i, v in enumerate(values):
        caster.SetValue(i, float(v))
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
    caster.SetCapping(_CAPPING[capping])
    caster.SetAmbient(ambient)
    caster.SetDiffuse(diffuse)
    caster.SetSpecular(specular)
    caster.SetSpecularPower(specular_power)
    caster.SetNormalMode({"exact": 0, "central": 1, "nodal": 2, "depth": 3}[normal_mode])
    caster.SetNumberOfThreads(threads)
    return DirectSurface(plotter, caster, interactive_scale)
