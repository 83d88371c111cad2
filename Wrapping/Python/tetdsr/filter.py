"""vtkDirectSurfaceRayCaster for any VTK Python (pip's `vtk` >= 9.3, ParaView's): the C++ filter's
interface and outputs (Filters/vtkDirectSurfaceRayCaster.h) on the pip build's core.

This file is VTK plumbing only: it observes the objects whose edits re-execute it (camera, lookup
table, clipping planes), makes the output image's arrays and hands the core its settings. Every
check and every sentence is the core's (tetdsr._core, Filters/Core/tetdsr/input/Settings.h and
MeshInput.h), as for the C++ filter: the core checks every size the input claims, views its
arrays where their layout allows and converts them once where not, and casts the image tile by
tile on all cores, writing straight into the output's VTK arrays. The settings of the core's
settings table (ImageSize, SurfaceColor, Ambient, ..., NumberOfThreads) get their Set/Get methods
from its rows; what the filters of a field share (input array, iso-values, the prepared mesh,
messages) is _field_filter.py's _FieldFilter, which contour.py's vtkDirectSurfaceContour builds on
too.

Not here (the C++ build has them): distributed rendering over a vtkMultiProcessController.
"""
import math
import re

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import VTK_UNSIGNED_CHAR, vtkScalarsToColors
from vtkmodules.vtkCommonDataModel import (vtkDataObject, vtkImageData, vtkPlane,
                                           vtkPlaneCollection, vtkUnstructuredGrid)
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm, vtkStreamingDemandDrivenPipeline
from vtkmodules.vtkRenderingCore import vtkCamera, vtkColorTransferFunction

from . import _core
from ._field_filter import (_FieldFilter, _as_numpy, _reals, _same_stamp, _settings_from_table,
                            _stamp)


def _color_transfer_function(color_map):
    """One of the core's built-in colour maps (control points, colour space) as VTK's lookup
    table, as the C++ filter builds it."""
    table = vtkColorTransferFunction()
    {_core.ColorSpace.RGB: table.SetColorSpaceToRGB, _core.ColorSpace.HSV: table.SetColorSpaceToHSV,
     _core.ColorSpace.DIVERGING: table.SetColorSpaceToDiverging}[color_map.space]()
    for point in color_map.points:
        table.AddRGBPoint(point.x, *point.color)
    table.SetNanColor(*color_map.nan_color)
    return table


def _color_of(table):
    """`table`'s colour of a value, by GetColor(value, rgb): VTK 9.7's Python wrapping of
    vtkLookupTable has no one-argument GetColor."""
    def color(value):
        rgb = [0.0, 0.0, 0.0]
        table.GetColor(value, rgb)
        return tuple(rgb)
    return color


def _vtk_object(setter, value, cls, none=True):
    """`value` if it is a `cls` (or None, if `none`); a TypeError naming the setter at once
    otherwise (not a traceback from deep inside the next Update)."""
    if (none and value is None) or isinstance(value, cls):
        return value
    raise TypeError(f"{setter} takes a {cls.__name__}{' or None' if none else ''}, "
                    f"got {type(value).__name__}")


def _object_setting(key, cls):
    """Set<key> and Get<key> of an object setting (a `cls` or None, observed), kept in _<key>
    (LookupTable: _lookup_table)."""
    member = "_" + "_".join(word.lower() for word in re.findall("[A-Z][a-z]+", key))

    def setter(self, value):
        self._set_object(member, _vtk_object("Set" + key, value, cls))
    return setter, lambda self: getattr(self, member)


class DirectSurfacePick:
    """What vtkDirectSurfaceRayCaster.Pick found (the C++ build's vtkDirectSurfacePick): the
    nearest crossing of a surface, or of a cap, along the ray through a position of the image.

    position: the hit (world coordinates); normal: unit, along the field's exact gradient
    (towards increasing field) on a surface, the plane's normal on a cap; cell_id: the input's
    cell; parametric_coordinates: VTK's (r, s, t) in that cell, or None when the mesh has wedges
    (straight ones are rendered as tetrahedra, so none of that mesh's cells is the input's own);
    iso_value_index: the iso-value crossed (its index, as given to SetValue), -1 on a cap; clipping_plane_id: a cap's plane (its index), -1 on a surface;
    value: the contoured field at the hit (the iso-value, to rounding, on a surface);
    ray_parameter: the distance from the ray's start (the camera, or the camera plane in parallel
    projection); point_data: every point array of the grid interpolated at the hit with the
    cell's shape functions, by name (a float for one component, a tuple for more).
    """

    __slots__ = ("position", "normal", "cell_id", "parametric_coordinates", "iso_value_index",
                 "clipping_plane_id", "value", "ray_parameter", "point_data")

    def __init__(self, pick, point_data):
        for name, core_name in zip(self.__slots__[:-1], ("point", "normal", "cell_id", "parametric",
                                                          "iso_value", "clip_plane", "value", "t")):
            setattr(self, name, getattr(pick, core_name))
        self.point_data = point_data

    def __repr__(self):
        return (f"DirectSurfacePick(position={self.position}, cell_id={self.cell_id}, "
                f"iso_value_index={self.iso_value_index}, value={self.value!r})")


@_settings_from_table("ray_caster")
class vtkDirectSurfaceRayCaster(_FieldFilter):
    """Ray casts the exact isosurface of a higher-order finite-element field (tetrahedra,
    hexahedra, wedges and pyramids of orders 1 to 4, the types the core's table reads) into an
    image.

    The interface of the C++ vtkDirectSurfaceRayCaster: input array 0 is the field
    (SetInputArrayToProcess, default the active point scalars), iso-values as vtkContourFilter
    (SetValue, ...), SetCamera (default: one that sees the whole mesh, as ResetCamera places it),
    SetImageSize (default 512 x 512), Phong appearance, per-iso-value colours and opacities,
    colouring by input array 1, clipping planes and caps, normal modes, NumberOfThreads (0: all
    cores). The output is a vtkImageData with point arrays Colors (RGBA uchar, the scalars),
    Depth (distance along the unit ray from the camera, or from the camera plane in parallel
    projection; +inf on misses), Normals, CellId (-1 on misses) and, when colour-mapping,
    ColorValues.
    """

    # Normal modes, colour maps, capping and transverse tests: the C++ filter's enumerations.
    EXACT_GRADIENT, CENTRAL_DIFFERENCES, NODAL_INTERPOLATION, DEPTH_BUFFER = range(4)
    COOL_TO_WARM, RAINBOW, GRAYSCALE, BLACK_BODY = range(4)
    NO_CAP, CAP_BELOW_ISO_VALUE, CAP_ABOVE_ISO_VALUE = range(3)
    BERNSTEIN_BOUND, WIDENED_NODAL_RANGE = range(2)
    MaximumNumberOfClippingPlanes = _core.MAX_CLIP_PLANES

    _VTK_CLASS = "vtkDirectSurfaceRayCaster"

    def __init__(self):
        _FieldFilter.__init__(self, "vtkImageData")
        self._camera = None
        self._lookup_table = None
        self._clipping_planes = None
        self._styles = _core.IsoValueStyles()
        self._last_image = None  # (renderer, grid, stamp arguments) of the last image: for Pick
        self._counts = dict.fromkeys(self._COUNTS, 0)
        self._counts["UncertifiedHits"] = 0

    # -- the settings of the core's table (ImageSize, SurfaceColor, Ambient, ..., NumberOfThreads)
    #    are made by _settings_from_table, and the objects' Set/Get (Camera, LookupTable,
    #    ClippingPlanes) from _object_setting below the class. Camera: position, focal point, view up,
    #    view angle (vertical), parallel projection and scale are used; None (the default): a
    #    camera that sees the whole mesh (looking down -z).
    # -- per-iso-value colours and opacities (the core's IsoValueStyles)
    def SetIsoValueColor(self, i, red, green, blue):
        messages = _core.Messages()
        if self._styles.set_color(i, (red, green, blue), messages):
            self.Modified()
        self._report(messages)

    def GetIsoValueColor(self, i):
        return self._styles.color(i, self._settings["SurfaceColor"])

    def RemoveAllIsoValueColors(self):
        if self._styles.remove_all_colors():
            self.Modified()

    def SetIsoValueOpacity(self, i, opacity):
        messages = _core.Messages()
        if self._styles.set_opacity(i, opacity, messages):
            self.Modified()
        self._report(messages)

    def GetIsoValueOpacity(self, i):
        return self._styles.opacity(i)

    def RemoveAllIsoValueOpacities(self):
        if self._styles.remove_all_opacities():
            self.Modified()

    # -- clipping planes
    def AddClippingPlane(self, plane):
        _vtk_object("AddClippingPlane", plane, vtkPlane, none=False)
        if self._clipping_planes is None:
            self.SetClippingPlanes(vtkPlaneCollection())
        self._clipping_planes.AddItem(plane)  # (observed: re-executes)

    def RemoveAllClippingPlanes(self):
        planes = self._clipping_planes
        if planes is not None and planes.GetNumberOfItems() > 0:
            for k in range(planes.GetNumberOfItems()):
                self._unobserve(planes.GetItem(k))
            planes.RemoveAllItems()
            self.Modified()

    # -- what the last preprocessing found: GetNumberOf<X>Cells (made from _COUNTS below the
    #    class) and GetNumberOfUncertifiedHits
    _COUNTS = {"Rendered": "valid", "Inverted": "inverted", "Curved": "curved",
               "Degenerate": "degenerate", "Tangled": "tangled", "NonFinite": "non_finite",
               "InvalidId": "invalid_id", "Unsupported": "unsupported", "Malformed": "malformed",
               "OrderTooHigh": "order_too_high", "Rational": "rational",
               "HigherOrder": "higher_order", "OutOfScale": "out_of_scale",
               "Ghost": "ghost"}

    def GetNumberOfUncertifiedHits(self):
        return self._counts["UncertifiedHits"]

    # -- picking
    def Pick(self, x, y):
        """The exact surface at a position of the last output image, as the core picks it: pixel
        (i, j) (the output's point i + j * width; row 0 is the bottom, as in VTK's display
        coordinates) covers [i, i + 1) x [j, j + 1), and (i + 0.5, j + 0.5) gives exactly the hit
        that pixel shows. With the last execution's camera, iso-values and clipping planes (a cap
        included): a DirectSurfacePick, or None when nothing is hit there, before an execution
        that cast an image, or after the input changed."""
        x, y = _reals("Pick", (x, y))
        if self._last_image is None or not (math.isfinite(x) and math.isfinite(y)):
            return None
        renderer, grid, stamp_arguments, _ = self._last_image
        if not _same_stamp(self._prepared_stamp, _stamp(grid, *stamp_arguments)):
            return None
        # Every point array of the grid with a value per point, as the core converts it.
        messages = _core.Messages()
        names, arrays = [], []
        point_data = grid.GetPointData()
        for a in range(point_data.GetNumberOfArrays()):
            array = point_data.GetArray(a)
            if array is None or array.GetNumberOfTuples() < grid.GetNumberOfPoints():
                continue
            values = self._prepared.point_values(_as_numpy(array), array.GetName() or "",
                                                 array.GetMTime(), "point array", messages)
            if values is not None:
                names.append(array.GetName() or f"array {a}")
                arrays.append(values)
        self._report(messages)
        pick = renderer.pick(x, y, arrays)
        if pick is None:
            return None
        return DirectSurfacePick(pick, {
            name: (tuple_[0] if len(tuple_) == 1 else tuple(tuple_))
            for name, tuple_ in zip(names, pick.point_values)})

    def WindowDepth(self, matrix):
        """The last output image's hits as a render window's depth buffer holds them, for a view
        whose composite projection is `matrix` (4 x 4, from world to normalized device
        coordinates: a vtkMatrix4x4 or an array, e.g. vtkCamera.GetCompositeProjectionTransform
        Matrix(aspect, -1, 1)): a (height, width) float32 array of 0.5 z / w + 0.5, 1 where
        nothing is hit; None before an execution that cast an image, or after the input
        changed."""
        if self._last_image is None:
            return None
        renderer, grid, stamp_arguments, (width, height) = self._last_image
        if not _same_stamp(self._prepared_stamp, _stamp(grid, *stamp_arguments)):
            return None
        if hasattr(matrix, "GetElement"):
            matrix = [[matrix.GetElement(r, c) for c in range(4)] for r in range(4)]
        matrix = np.ascontiguousarray(matrix, dtype=np.float64)
        out = np.empty((height, width), np.float32)
        renderer.window_depth(matrix, out)
        return out

    def GetPreprocessedBytes(self):
        """Bytes kept between executions: the scene and converted copies of input arrays."""
        return self._prepared.memory_bytes if self._prepared is not None else 0

    # -- the pipeline
    def RequestInformation(self, request, inInfo, outInfo):
        messages = _core.Messages()
        if not self._check_composite_input(inInfo, messages):
            return self._report(messages)
        width, height = self._settings["ImageSize"]
        if not _core.check_image_size(width, height, messages):
            return self._report(messages)
        info = outInfo.GetInformationObject(0)
        info.Set(vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT(),
                 (0, width - 1, 0, height - 1, 0, 0), 6)
        info.Set(vtkDataObject.SPACING(), (1.0, 1.0, 1.0), 3)
        info.Set(vtkDataObject.ORIGIN(), (0.0, 0.0, 0.0), 3)
        vtkDataObject.SetPointDataActiveScalarInfo(info, VTK_UNSIGNED_CHAR, 4)
        info.Set(vtkAlgorithm.CAN_PRODUCE_SUB_EXTENT(), 1)
        return 1

    def _clip_planes(self):
        planes = self._clipping_planes
        count = planes.GetNumberOfItems() if planes is not None else 0
        return [_core.ClipPlane(planes.GetItem(k).GetOrigin(), planes.GetItem(k).GetNormal())
                for k in range(count)]

    def _core_camera(self, prepared, aspect):
        vtk_camera = self._camera
        if vtk_camera is None:
            return _core.reset_camera(prepared.bounds(), aspect)
        camera = _core.Camera()
        camera.position = vtk_camera.GetPosition()
        camera.focal_point = vtk_camera.GetFocalPoint()
        camera.view_up = vtk_camera.GetViewUp()
        camera.view_angle = vtk_camera.GetViewAngle()
        camera.parallel_projection = bool(vtk_camera.GetParallelProjection())
        camera.parallel_scale = vtk_camera.GetParallelScale()
        return camera

    def _render_settings(self, camera, number_of_values, clip_planes):
        """Shading, as the C++ filter's ShadingSettings: one white point light at the camera (or
        at LightPosition), the iso-values' styles, the clipping planes and the cap."""
        s = self._settings
        settings = _core.RenderSettings()
        material = settings.material
        material.color = s["SurfaceColor"]
        material.ambient = s["Ambient"]
        material.diffuse = s["Diffuse"]
        material.specular = s["Specular"]
        material.specular_power = s["SpecularPower"]
        light = _core.Light()
        light.positional = True
        light.position = camera.position if s["LightAtCamera"] else s["LightPosition"]
        settings.lighting.lights = [light]
        settings.normals.mode = _core.NormalMode(s["NormalMode"])
        settings.normals.relative_step = s["CentralDifferenceStep"]
        settings.iso_styles = self._styles.styles(number_of_values, s["SurfaceColor"], 1.0)
        settings.clip_planes = clip_planes
        settings.cap = _core.CapRegion(s["Capping"])
        return settings

    def RequestData(self, request, inInfo, outInfo):
        grid = vtkUnstructuredGrid.GetData(inInfo[0])
        output = vtkImageData.GetData(outInfo)
        s = self._settings
        width, height = s["ImageSize"]
        messages = _core.Messages()
        self._last_image = None  # until this execution's image is whole
        if not _core.check_mesh_not_empty(grid.GetNumberOfPoints() if grid else 0,
                                          grid.GetNumberOfCells() if grid else 0, messages):
            return self._report(messages)

        # The field, its iso-values, the colour array and the clipping planes.
        scalars, component = self._point_array(0, inInfo, s["ArrayComponent"], False,
                                               "ArrayComponent", messages)
        values = list(self.GetValues())
        if scalars is None or not _core.check_iso_values(values, messages):
            return self._report(messages)
        color_array, color_component = None, -1
        if s["ColorByArray"]:
            color_array, color_component = self._point_array(
                1, inInfo, s["ColorArrayComponent"], True, "ColorArrayComponent", messages)
            if color_array is None:
                return self._report(messages)
        clip_planes = self._clip_planes()
        if not _core.check_clip_planes(clip_planes, messages):
            return self._report(messages)

        # Preprocess once per mesh, array and transverse test.
        try:
            prepared = self._prepare(grid, scalars, component,
                                     (s["TransverseTest"], s["NodalRangeWidening"]),
                                     s["NumberOfThreads"], messages)
        except (MemoryError, RuntimeError) as error:
            self._prepared, self._prepared_stamp = None, None
            return self._fail(error, "prepare the mesh")
        summary = self._prepared.summary
        counts = self._counts
        for key, core_key in self._COUNTS.items():
            counts[key] = summary[core_key]
        if prepared is None:
            counts["Rendered"] = 0
        color_values = None
        if prepared is not None and color_array is not None:
            try:
                color_values = prepared.point_values(_as_numpy(color_array), color_array.GetName() or "",
                                                     color_array.GetMTime(), "colour array", messages)
            except MemoryError as error:
                return self._fail(error, "convert the colour array")
        if prepared is None or not messages.ok:
            return self._report(messages)
        self._report(messages)  # the warnings

        camera = self._core_camera(prepared, width / height)
        if not _core.check_camera(camera, prepared, messages):
            return self._report(messages)

        # The output arrays, which the core writes in place: allocated by numpy (a failure is a
        # MemoryError; pip VTK's SetNumberOfTuples would throw std::bad_alloc through its wrapper
        # and abort), then handed to VTK arrays that keep them.
        color_mapped = _core.is_color_mapped(s["ColorByArray"], s["Capping"] != self.NO_CAP,
                                             len(clip_planes))
        views = {}
        try:
            for name, dtype, components in (
                    ("Colors", np.uint8, 4), ("Depth", np.float64, 1), ("Normals", np.float64, 3),
                    ("CellId", np.int64, 1), ("ColorValues", np.float64, 1)):
                if name == "ColorValues" and not color_mapped:
                    continue
                views[name] = np.empty((height, width, components) if components > 1
                                       else (height, width), dtype)
        except MemoryError:
            _core.report_unallocated_image(width, height, messages)
            return self._report(messages)
        arrays = {name: (numpy_to_vtkIdTypeArray if name == "CellId" else numpy_to_vtk)(
            view.reshape(width * height, -1) if view.ndim == 3 else view.reshape(-1))
            for name, view in views.items()}
        for name, array in arrays.items():
            array.SetName(name)

        settings = self._render_settings(camera, len(values), clip_planes)
        if color_mapped:
            lo, hi = s["ColorRange"]
            if not _core.is_usable_color_range(lo, hi):
                # The colour array's finite range (-1: the magnitude's), else the field's.
                lo, hi = (_core.finite_range(_as_numpy(color_array), color_component)
                          if color_array is not None
                          else _core.finite_range(_as_numpy(scalars), component))
            if color_array is not None:
                settings.color_by = _core.ColorByArray(color_values, color_component)
            lookup_table = (self._lookup_table
                            or _color_transfer_function(_core.built_in_color_map(s["ColorMap"])))
            settings.color_table = _core.sample_color_table(
                _color_of(lookup_table), *lookup_table.GetRange(), lo, hi)

        # Cast in steps, between which progress is told and abort asked. What the binding
        # raises (memory that cannot be had, a thread that cannot start) becomes an error.
        uncertified_before = prepared.uncertified_hits
        try:
            renderer = _core.Renderer(prepared, values, camera, settings, views["Colors"],
                                      views["Depth"], views["Normals"], views["CellId"],
                                      views.get("ColorValues"), threads=s["NumberOfThreads"])
            done = renderer.cast(s["NumberOfThreads"], lambda: bool(self.CheckAbort()),
                                 self.UpdateProgress)
        except (MemoryError, RuntimeError) as error:
            return self._fail(error, f"cast the {width} x {height} image")
        counts["UncertifiedHits"] = prepared.uncertified_hits - uncertified_before
        if done < renderer.number_of_tiles:
            _core.report_aborted_cast(done, renderer.number_of_tiles, messages)
            self._report(messages)
            # The executive empties the output and marks it aborted.
            self.SetAbortOutput(True)
            return 1

        # The whole image, or the requested part of it.
        whole = (0, width - 1, 0, height - 1, 0, 0)
        info = outInfo.GetInformationObject(0)
        extent = list(whole)
        if info.Has(vtkStreamingDemandDrivenPipeline.UPDATE_EXTENT()):
            requested = info.Get(vtkStreamingDemandDrivenPipeline.UPDATE_EXTENT())
            for a in range(0, 6, 2):
                extent[a] = max(requested[a], whole[a])
                extent[a + 1] = min(requested[a + 1], whole[a + 1])
        output.SetExtent(whole)
        point_data = output.GetPointData()
        point_data.Initialize()
        for name, array in arrays.items():  # (Colors the scalars, Normals the normals)
            {"Colors": point_data.SetScalars, "Normals": point_data.SetNormals}.get(
                name, point_data.AddArray)(array)
        if tuple(extent) != whole:
            output.Crop(extent)
        self._last_image = (renderer, grid, (scalars, component,
                                             (s["TransverseTest"], s["NodalRangeWidening"])),
                            (width, height))
        return 1


for _key in vtkDirectSurfaceRayCaster._COUNTS:
    setattr(vtkDirectSurfaceRayCaster, f"GetNumberOf{_key}Cells",
            lambda self, key=_key: self._counts[key])

for _key, _cls in (("Camera", vtkCamera), ("LookupTable", vtkScalarsToColors),
                   ("ClippingPlanes", vtkPlaneCollection)):
    for _prefix, _method in zip(("Set", "Get"), _object_setting(_key, _cls)):
        setattr(vtkDirectSurfaceRayCaster, _prefix + _key, _method)
