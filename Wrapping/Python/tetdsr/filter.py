"""vtkDirectSurfaceRayCaster for any VTK Python (pip's `vtk` >= 9.3, ParaView's): the C++ filter's
interface and outputs (Filters/vtkDirectSurfaceRayCaster.h) on the pip build's core.

This file is VTK plumbing only: it gets arrays out of VTK objects (numpy views of VTK's memory),
keeps the stamps that decide when the mesh is prepared again, observes the objects whose edits
re-execute it, makes the output image's arrays and turns the core's messages into VTK's events.
Every check and every sentence is the core's (tetdsr._core, Filters/Core/tetdsr/input/Settings.h and
MeshInput.h), as for the C++ filter: the core checks every size the input claims, views its
arrays where their layout allows and converts them once where not, and casts the image tile by
tile on all cores, writing straight into the output's VTK arrays.

What the filters of a field share (input array, iso-values, the prepared mesh, messages) is
_FieldFilter, which contour.py's vtkDirectSurfaceContour builds on too.

Not here (the C++ build has them): distributed rendering over a vtkMultiProcessController.
"""
import math
import numbers
import weakref

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import (VTK_UNSIGNED_CHAR, vtkCommand, vtkDataArray, vtkOutputWindow,
                                      vtkScalarsToColors)
from vtkmodules.vtkCommonDataModel import (vtkCompositeDataSet, vtkDataObject,
                                           vtkDataSetAttributes, vtkImageData, vtkPlane,
                                           vtkPlaneCollection, vtkUnstructuredGrid)
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm, vtkStreamingDemandDrivenPipeline
from vtkmodules.vtkCommonMisc import vtkContourValues
from vtkmodules.vtkRenderingCore import vtkCamera, vtkColorTransferFunction

from . import _core


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


def _as_numpy(array):
    """A vtkDataArray as an (n, components) numpy array: a view where VTK allows one."""
    try:
        values = vtk_to_numpy(array)
    except (AttributeError, TypeError, ValueError):  # a type numpy cannot view (bit arrays)
        values = np.array([array.GetTuple(p) for p in range(array.GetNumberOfTuples())])
    return values.reshape(array.GetNumberOfTuples(), array.GetNumberOfComponents())


def _input_array(grid, info, name):
    """The array SetInputArrayToProcess chose (by name, or by attribute type) and its association,
    as vtkAlgorithm::GetInputArrayToProcess finds it (protected in C++, so not wrapped)."""
    association = (info.Get(vtkDataObject.FIELD_ASSOCIATION())
                   if info.Has(vtkDataObject.FIELD_ASSOCIATION())
                   else vtkDataObject.FIELD_ASSOCIATION_POINTS)
    points_then_cells = vtkDataObject.FIELD_ASSOCIATION_POINTS_THEN_CELLS
    if association == points_then_cells:
        candidates = ((vtkDataObject.FIELD_ASSOCIATION_POINTS, grid.GetPointData()),
                      (vtkDataObject.FIELD_ASSOCIATION_CELLS, grid.GetCellData()))
    elif association == vtkDataObject.FIELD_ASSOCIATION_POINTS:
        candidates = ((association, grid.GetPointData()),)
    elif association == vtkDataObject.FIELD_ASSOCIATION_CELLS:
        candidates = ((association, grid.GetCellData()),)
    elif association == vtkDataObject.FIELD_ASSOCIATION_NONE:
        candidates = ((association, grid.GetFieldData()),)
    else:
        candidates = ()
    for where, data in candidates:
        if name:
            array = data.GetArray(name)
        elif info.Has(vtkDataObject.FIELD_ATTRIBUTE_TYPE()) and hasattr(data, "GetAttribute"):
            array = data.GetAttribute(info.Get(vtkDataObject.FIELD_ATTRIBUTE_TYPE()))
        else:
            array = None
        if array is not None:
            return array, where
    return None, association


def _cell_types(grid):
    """The grid's cell types array (VTK 9.6 renamed GetCellTypesArray to GetCellTypes)."""
    try:
        types = grid.GetCellTypes()
        if isinstance(types, vtkDataArray):
            return types
    except TypeError:  # before 9.6: GetCellTypes(vtkCellTypes) fills a list of the types
        pass
    return grid.GetCellTypesArray()


def _stamp(grid, scalars, component, transverse):
    points = grid.GetPoints()
    cells = grid.GetCells()
    parts = [grid, points, points.GetData() if points else None, cells,
             cells.GetOffsetsArray() if cells else None,
             cells.GetConnectivityArray() if cells else None, _cell_types(grid), scalars,
             grid.GetPointData().GetRationalWeights()]
    return tuple((part, part.GetMTime() if part is not None else 0) for part in parts) + (
        component, transverse)


def _integer(setter, value):
    """An integer argument (bool and numpy integers too), as VTK's wrappers take one for an int;
    a TypeError naming the setter for anything else (a float is not truncated)."""
    if isinstance(value, numbers.Integral):
        return int(value)
    raise TypeError(f"{setter} takes an integer, got {value!r}")


def _color_of(table):
    """`table`'s colour of a value, by GetColor(value, rgb): VTK 9.7's Python wrapping of
    vtkLookupTable has no one-argument GetColor."""
    def color(value):
        rgb = [0.0, 0.0, 0.0]
        table.GetColor(value, rgb)
        return tuple(rgb)
    return color


def _reals(setter, values):
    """Numbers (numpy's too) as floats; a TypeError naming the setter for anything else."""
    if all(isinstance(v, numbers.Real) for v in values):
        return tuple(float(v) for v in values)
    raise TypeError(f"{setter} takes numbers, got {values!r}")


def _vtk_object(setter, value, cls, none=True):
    """`value` if it is a `cls` (or None, if `none`); a TypeError naming the setter at once
    otherwise (not a traceback from deep inside the next Update)."""
    if (none and value is None) or isinstance(value, cls):
        return value
    raise TypeError(f"{setter} takes a {cls.__name__}{' or None' if none else ''}, "
                    f"got {type(value).__name__}")


def _same_stamp(a, b):
    return a is not None and len(a) == len(b) and all(
        (x[0] is y[0] and x[1] == y[1]) if isinstance(x, tuple) else x == y for x, y in zip(a, b))


class DirectSurfacePick:
    """What vtkDirectSurfaceRayCaster.Pick found (the C++ build's vtkDirectSurfacePick): the
    nearest crossing of a surface, or of a cap, along the ray through a position of the image.

    position: the hit (world coordinates); normal: unit, along the field's exact gradient
    (towards increasing field) on a surface, the plane's normal on a cap; cell_id: the input's
    cell; parametric_coordinates: VTK's (r, s, t) in that cell, or None when the mesh has wedges
    (straight ones are rendered as tetrahedra, so none of that mesh's cells is the input's own); iso_value_index: the iso-value crossed (its index, as given
    to SetValue), -1 on a cap; clipping_plane_id: a cap's plane (its index), -1 on a surface;
    value: the contoured field at the hit (the iso-value, to rounding, on a surface);
    ray_parameter: the distance from the ray's start (the camera, or the camera plane in parallel
    projection); point_data: every point array of the grid interpolated at the hit with the
    cell's shape functions, by name (a float for one component, a tuple for more).
    """

    __slots__ = ("position", "normal", "cell_id", "parametric_coordinates", "iso_value_index",
                 "clipping_plane_id", "value", "ray_parameter", "point_data")

    def __init__(self, pick, point_data):
        self.position = pick.point
        self.normal = pick.normal
        self.cell_id = pick.cell_id
        self.parametric_coordinates = pick.parametric
        self.iso_value_index = pick.iso_value
        self.clipping_plane_id = pick.clip_plane
        self.value = pick.value
        self.ray_parameter = pick.t
        self.point_data = point_data

    def __repr__(self):
        return (f"DirectSurfacePick(position={self.position}, cell_id={self.cell_id}, "
                f"iso_value_index={self.iso_value_index}, value={self.value!r})")


class _FieldFilter(VTKPythonAlgorithmBase):
    """What the wheel's filters of a field share (the C++ build's vtkDirectSurfaceAdapter and
    vtkDirectSurfaceReporting): an unstructured grid in, input array 0 the field (default the
    active point scalars) and its ArrayComponent, iso-values as vtkContourFilter's, the core's
    prepared mesh kept while the input is unchanged, and the core's messages as VTK's events
    (ErrorEvent / WarningEvent, else the output window, naming the class `_VTK_CLASS`)."""

    _VTK_CLASS = "vtkAlgorithm"

    def __init__(self, output_type, settings):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=1, inputType="vtkUnstructuredGrid",
                                        nOutputPorts=1, outputType=output_type)
        self.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS,
                                    vtkDataSetAttributes.SCALARS)
        self._contour_values = vtkContourValues()
        self._settings = dict(ArrayComponent=-1, **settings)
        self._observed = []  # (object, observer tag): edits of these re-execute the filter
        self._prepared = None  # the core's PreparedMesh
        self._prepared_stamp = None  # what it was prepared from
        # The contour values are an object of their own: their edits must reach this filter.
        self._observe(self._contour_values)

    # -- messages: as vtkErrorMacro / vtkWarningMacro, observable as ErrorEvent / WarningEvent
    def _report(self, messages):
        """Passes the core's messages on (warnings first) and empties them; returns 0, what a
        failed request returns."""
        for text in messages.warnings:
            self._emit(vtkCommand.WarningEvent, "Warning", text)
        for text in messages.errors:
            self._emit(vtkCommand.ErrorEvent, "ERROR", text)
        messages.clear()
        return 0

    def _fail(self, error, doing):
        """An exception of the binding (no memory, a thread that could not start) as an error;
        returns 0."""
        if isinstance(error, MemoryError):
            text = f"Not enough memory to {doing} ({error or 'std::bad_alloc'})."
        else:
            text = str(error)
        self._emit(vtkCommand.ErrorEvent, "ERROR", text)
        return 0

    def _emit(self, event, kind, text):
        if self.HasObserver(event):
            self.InvokeEvent(event, text)
        elif event == vtkCommand.ErrorEvent or self.GetGlobalWarningDisplay():
            line = f"{kind}: In tetdsr, {self._VTK_CLASS} ({hex(id(self))}): {text}\n\n"
            window = vtkOutputWindow.GetInstance()
            if event == vtkCommand.ErrorEvent:
                window.DisplayErrorText(line)
            else:
                window.DisplayWarningText(line)

    # -- objects whose edits re-execute the filter (the C++ filter's GetMTime)
    def _observe(self, obj):
        this = weakref.ref(self)

        def modified(caller, event):
            filter_ = this()
            if filter_ is not None:
                filter_._observed_modified(caller)

        self._observed.append((obj, obj.AddObserver(vtkCommand.ModifiedEvent, modified)))

    def _observed_modified(self, caller):
        self.Modified()

    def _unobserve(self, obj):
        for observed, tag in [x for x in self._observed if x[0] is obj]:
            observed.RemoveObserver(tag)
        self._observed = [x for x in self._observed if x[0] is not obj]

    def _set(self, key, value):
        if self._settings[key] != value:
            self._settings[key] = value
            self.Modified()

    def _set_clamped_integer(self, key, value, lo, hi):
        """An integer setting clamped into [lo, hi] as the C++ filter's vtkSetClampMacro does,
        with a warning saying so."""
        number = _integer("Set" + key, value)
        clamped = min(max(number, lo), hi)
        if clamped != number:
            self._emit(vtkCommand.WarningEvent, "Warning",
                       f"{key} {number} is outside [{lo}, {hi}]: {clamped} is used.")
        self._set(key, clamped)

    # -- the pipeline's convenience methods of VTK's C++ algorithms
    def SetInputData(self, data):
        self.SetInputDataObject(0, data)

    def GetOutput(self):
        return self.GetOutputDataObject(0)

    # -- iso-values, as vtkContourFilter
    def _iso_value_count(self, setter, what, n, last):
        """Whether `n` (an index when `last`, else a count) keeps the iso-values within the
        core's per-iso-value index range; an error otherwise (vtkContourValues would try to
        allocate them all: 10^9 values are 8 GB)."""
        n = _integer(setter, n)
        limit = _core.MAX_STYLE_INDEX
        if 0 <= n < limit + (0 if last else 1):
            return True
        self._emit(vtkCommand.ErrorEvent, "ERROR",
                   f"{setter}: {what} {n} is outside [0, {limit}{')' if last else ']'}.")
        return False

    def SetValue(self, i, value):
        if self._iso_value_count("SetValue", "index", i, True):
            self._contour_values.SetValue(i, value)

    def GetValue(self, i):
        return self._contour_values.GetValue(i)

    def GetValues(self):
        return tuple(self._contour_values.GetValue(i) for i in range(self.GetNumberOfContours()))

    def SetNumberOfContours(self, number):
        if self._iso_value_count("SetNumberOfContours", "number", number, False):
            self._contour_values.SetNumberOfContours(number)

    def GetNumberOfContours(self):
        return self._contour_values.GetNumberOfContours()

    def GenerateValues(self, count, start, end=None):
        if end is None:
            start, end = start
        if self._iso_value_count("GenerateValues", "count", count, False):
            self._contour_values.GenerateValues(count, start, end)

    def SetArrayComponent(self, component):
        self._set("ArrayComponent", _integer("SetArrayComponent", component))

    def GetArrayComponent(self):
        return self._settings["ArrayComponent"]

    def _check_composite_input(self, inInfo, messages):
        """False, with the core's error, for a multiblock input without cells: it is executed
        block by block, so it would execute nothing and say nothing."""
        data = (inInfo[0].GetInformationObject(0).Get(vtkDataObject.DATA_OBJECT())
                if inInfo[0].GetNumberOfInformationObjects() else None)
        return not isinstance(data, vtkCompositeDataSet) or _core.check_mesh_not_empty(
            data.GetNumberOfPoints(), data.GetNumberOfCells(), messages)

    def _point_array(self, index, inInfo, requested, allow_magnitude, setting, messages):
        """Input array `index` (0: the field, 1: the colour array) and the component the core
        chose of it, or (None, None) with the core's error."""
        info = self.GetInputArrayInformation(index)
        name = info.Get(vtkDataObject.FIELD_NAME()) if info.Has(vtkDataObject.FIELD_NAME()) else None
        array, association = _input_array(vtkUnstructuredGrid.GetData(inInfo[0]), info, name)
        if array is None:
            _core.report_missing_array(_core.InputArray.FIELD if index == 0 else _core.InputArray.COLOR,
                                       name, messages)
            return None, None
        component = _core.choose_point_array_component(
            array.GetName() or "", association == vtkDataObject.FIELD_ASSOCIATION_POINTS,
            array.GetNumberOfComponents(), requested, allow_magnitude, setting, messages)
        return (array, component) if component is not None else (None, None)

    def _prepare(self, grid, scalars, component, transverse_test, threads, messages):
        """The core's prepared mesh for `grid` and its field (with the transverse test (mode,
        widening)): the last one while nothing it was built from changed (its errors told again),
        else prepared afresh from numpy views of VTK's arrays. None, with the core's errors, when
        nothing can be rendered."""
        stamp = _stamp(grid, scalars, component, transverse_test)
        if self._prepared is not None and _same_stamp(self._prepared_stamp, stamp):
            return self._prepared if self._prepared.reuse(messages) else None
        transverse = _core.TransverseTest()
        transverse.mode = _core.TransverseMode(transverse_test[0])
        transverse.widening = transverse_test[1]
        cells = grid.GetCells()
        weights = grid.GetPointData().GetRationalWeights()
        prepared = _core.PreparedMesh()
        self._prepared, self._prepared_stamp = prepared, stamp
        ready = prepared.prepare(
            _as_numpy(grid.GetPoints().GetData()), _as_numpy(_cell_types(grid)),
            _as_numpy(cells.GetOffsetsArray()), _as_numpy(cells.GetConnectivityArray()),
            _as_numpy(scalars), field_name=scalars.GetName() or "", component=component,
            transverse=transverse, threads=threads, messages=messages,
            rational_weights=_as_numpy(weights) if weights is not None else None)
        return prepared if ready else None


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
        # The core's defaults for what it shades and tests with.
        material, normals, transverse = _core.Material(), _core.NormalSettings(), _core.TransverseTest()
        _FieldFilter.__init__(self, "vtkImageData", dict(
            ImageSize=(512, 512), SurfaceColor=material.color,
            Ambient=material.ambient, Diffuse=material.diffuse, Specular=material.specular,
            SpecularPower=material.specular_power, LightAtCamera=True,
            LightPosition=(0.0, 0.0, 1.0), NumberOfThreads=0, NormalMode=normals.mode.value,
            CentralDifferenceStep=normals.relative_step, TransverseTest=transverse.mode.value,
            NodalRangeWidening=transverse.widening, ColorByArray=False, ColorArrayComponent=-1,
            ColorRange=(0.0, -1.0), ColorMap=self.COOL_TO_WARM, Capping=self.NO_CAP))
        self._camera = None
        self._lookup_table = None
        self._clipping_planes = None
        self._styles = _core.IsoValueStyles()
        self._last_image = None  # (renderer, grid, stamp arguments) of the last image: for Pick
        self._counts = dict.fromkeys(
            ("Rendered", "Inverted", "Curved", "Degenerate", "Tangled", "NonFinite", "InvalidId",
             "Unsupported", "Malformed", "OrderTooHigh", "Rational", "HigherOrder", "OutOfScale",
             "UncertifiedHits"), 0)

    def _observed_modified(self, caller):
        if isinstance(caller, vtkPlaneCollection):
            self._observe_planes()  # (a plane added to the collection is observed too)
        self.Modified()

    def _observe_planes(self):
        planes = self._clipping_planes
        if planes is None:
            return
        for k in range(planes.GetNumberOfItems()):
            plane = planes.GetItem(k)
            if not any(x[0] is plane for x in self._observed):
                self._observe(plane)

    def _set_object(self, attribute, value):
        old = getattr(self, attribute)
        if old is value:
            return
        if old is not None:
            self._unobserve(old)
            if attribute == "_clipping_planes":
                for k in range(old.GetNumberOfItems()):
                    self._unobserve(old.GetItem(k))
        setattr(self, attribute, value)
        if value is not None:
            self._observe(value)
            if attribute == "_clipping_planes":
                self._observe_planes()
        self.Modified()

    def _set_finite(self, key, values):
        """A tuple of numbers, refused with an error (the setting kept) unless all are finite."""
        numbers_ = _reals("Set" + key, values)
        if not all(math.isfinite(v) for v in numbers_):
            self._emit(vtkCommand.ErrorEvent, "ERROR", f"{key} must be finite numbers, got "
                       f"({', '.join(repr(v) for v in numbers_)}): {key} is unchanged.")
            return
        self._set(key, numbers_)

    # -- camera and image
    def SetCamera(self, camera):
        """vtkCamera: position, focal point, view up, view angle (vertical), parallel projection
        and scale are used. None: a camera that sees the whole mesh (looking down -z)."""
        self._set_object("_camera", _vtk_object("SetCamera", camera, vtkCamera))

    def GetCamera(self):
        return self._camera

    def SetImageSize(self, width, height=None):
        if height is None:
            width, height = width
        # (into C int range: the core's check then says what a size beyond memory needs)
        size = [min(max(_integer("SetImageSize", v), -2 ** 31), 2 ** 31 - 1) for v in (width, height)]
        self._set("ImageSize", tuple(size))

    def GetImageSize(self):
        return self._settings["ImageSize"]

    # -- shading
    def SetSurfaceColor(self, red, green=None, blue=None):
        if green is None:
            red, green, blue = red
        self._set_finite("SurfaceColor", (red, green, blue))

    def GetSurfaceColor(self):
        return self._settings["SurfaceColor"]

    def _set_number(self, key, value):
        """A shading number, clamped into the core's range for it; NaN refused with its error."""
        messages = _core.Messages()
        (number,) = _reals("Set" + key, (value,))
        changed, number = _core.set_clamped(_core.NUMBER_SETTINGS[key], number,
                                            self._settings[key], messages)
        self._report(messages)
        if changed:
            self._settings[key] = number
            self.Modified()

    def SetAmbient(self, value):
        self._set_number("Ambient", value)

    def GetAmbient(self):
        return self._settings["Ambient"]

    def SetDiffuse(self, value):
        self._set_number("Diffuse", value)

    def GetDiffuse(self):
        return self._settings["Diffuse"]

    def SetSpecular(self, value):
        self._set_number("Specular", value)

    def GetSpecular(self):
        return self._settings["Specular"]

    def SetSpecularPower(self, value):
        self._set_number("SpecularPower", value)

    def GetSpecularPower(self):
        return self._settings["SpecularPower"]

    def SetLightAtCamera(self, on):
        self._set("LightAtCamera", bool(_integer("SetLightAtCamera", on)))

    def GetLightAtCamera(self):
        return self._settings["LightAtCamera"]

    def LightAtCameraOn(self):
        self.SetLightAtCamera(True)

    def LightAtCameraOff(self):
        self.SetLightAtCamera(False)

    def SetLightPosition(self, x, y=None, z=None):
        if y is None:
            x, y, z = x
        self._set_finite("LightPosition", (x, y, z))

    def GetLightPosition(self):
        return self._settings["LightPosition"]

    def SetNormalMode(self, mode):
        self._set_clamped_integer("NormalMode", mode, self.EXACT_GRADIENT, self.DEPTH_BUFFER)

    def GetNormalMode(self):
        return self._settings["NormalMode"]

    def SetCentralDifferenceStep(self, step):
        self._set_number("CentralDifferenceStep", step)

    def GetCentralDifferenceStep(self):
        return self._settings["CentralDifferenceStep"]

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

    # -- colour by an array
    def SetColorByArray(self, on):
        self._set("ColorByArray", bool(_integer("SetColorByArray", on)))

    def GetColorByArray(self):
        return self._settings["ColorByArray"]

    def ColorByArrayOn(self):
        self.SetColorByArray(True)

    def ColorByArrayOff(self):
        self.SetColorByArray(False)

    def SetColorArrayComponent(self, component):
        self._set_clamped_integer("ColorArrayComponent", component, -1, 2 ** 31 - 1)

    def GetColorArrayComponent(self):
        return self._settings["ColorArrayComponent"]

    def SetColorRange(self, lo, hi=None):
        if hi is None:
            lo, hi = lo
        self._set_finite("ColorRange", (lo, hi))

    def GetColorRange(self):
        return self._settings["ColorRange"]

    def SetLookupTable(self, table):
        self._set_object("_lookup_table", _vtk_object("SetLookupTable", table, vtkScalarsToColors))

    def GetLookupTable(self):
        return self._lookup_table

    def SetColorMap(self, which):
        self._set_clamped_integer("ColorMap", which, self.COOL_TO_WARM, self.BLACK_BODY)

    def GetColorMap(self):
        return self._settings["ColorMap"]

    # -- clipping and caps
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

    def SetClippingPlanes(self, planes):
        self._set_object("_clipping_planes", _vtk_object("SetClippingPlanes", planes, vtkPlaneCollection))

    def GetClippingPlanes(self):
        return self._clipping_planes

    def SetCapping(self, mode):
        self._set_clamped_integer("Capping", mode, self.NO_CAP, self.CAP_ABOVE_ISO_VALUE)

    def GetCapping(self):
        return self._settings["Capping"]

    # -- transverse test and threads
    def SetTransverseTest(self, mode):
        self._set_clamped_integer("TransverseTest", mode, self.BERNSTEIN_BOUND,
                                  self.WIDENED_NODAL_RANGE)

    def GetTransverseTest(self):
        return self._settings["TransverseTest"]

    def SetNodalRangeWidening(self, widening):
        self._set_number("NodalRangeWidening", widening)

    def GetNodalRangeWidening(self):
        return self._settings["NodalRangeWidening"]

    def SetNumberOfThreads(self, threads):
        self._set_clamped_integer("NumberOfThreads", threads, 0, 2 ** 31 - 1)

    def GetNumberOfThreads(self):
        return self._settings["NumberOfThreads"]

    # -- what the last preprocessing found
    def GetNumberOfRenderedCells(self):
        return self._counts["Rendered"]

    def GetNumberOfInvertedCells(self):
        return self._counts["Inverted"]

    def GetNumberOfCurvedCells(self):
        return self._counts["Curved"]

    def GetNumberOfDegenerateCells(self):
        return self._counts["Degenerate"]

    def GetNumberOfTangledCells(self):
        return self._counts["Tangled"]

    def GetNumberOfNonFiniteCells(self):
        return self._counts["NonFinite"]

    def GetNumberOfInvalidIdCells(self):
        return self._counts["InvalidId"]

    def GetNumberOfUnsupportedCells(self):
        return self._counts["Unsupported"]

    def GetNumberOfMalformedCells(self):
        return self._counts["Malformed"]

    def GetNumberOfOrderTooHighCells(self):
        return self._counts["OrderTooHigh"]

    def GetNumberOfRationalCells(self):
        return self._counts["Rational"]

    def GetNumberOfHigherOrderCells(self):
        return self._counts["HigherOrder"]

    def GetNumberOfOutOfScaleCells(self):
        return self._counts["OutOfScale"]

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
        counts["Rendered"] = summary["valid"] if prepared is not None else 0
        for key, core_key in (("Inverted", "inverted"), ("Curved", "curved"),
                              ("Degenerate", "degenerate"), ("Tangled", "tangled"),
                              ("OutOfScale", "out_of_scale"), ("NonFinite", "non_finite"),
                              ("InvalidId", "invalid_id"), ("Unsupported", "unsupported"),
                              ("Malformed", "malformed"), ("OrderTooHigh", "order_too_high"),
                              ("Rational", "rational"), ("HigherOrder", "higher_order")):
            counts[key] = summary[core_key]
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
        arrays = {}
        for name, view in views.items():
            flat = view.reshape(width * height, -1) if view.ndim == 3 else view.reshape(-1)
            array = numpy_to_vtkIdTypeArray(flat) if name == "CellId" else numpy_to_vtk(flat)
            array.SetName(name)
            arrays[name] = array

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
        point_data.SetScalars(arrays["Colors"])
        point_data.AddArray(arrays["Depth"])
        point_data.SetNormals(arrays["Normals"])
        point_data.AddArray(arrays["CellId"])
        if "ColorValues" in arrays:
            point_data.AddArray(arrays["ColorValues"])
        if tuple(extent) != whole:
            output.Crop(extent)
        self._last_image = (renderer, grid, (scalars, component,
                                             (s["TransverseTest"], s["NodalRangeWidening"])),
                            (width, height))
        return 1
