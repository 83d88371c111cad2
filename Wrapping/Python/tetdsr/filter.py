"""vtkDirectSurfaceRayCaster for any VTK Python (pip's `vtk` >= 9.3, ParaView's): the C++ filter's
interface and outputs (Filters/vtkDirectSurfaceRayCaster.h) on the pip build's core.

What it does, step by step as the C++ filter (and its adapter, Filters/vtkDirectSurfaceAdapter.cxx):
VTK's arrays are viewed through numpy without copies where their layout is the core's (float64
points, int64 connectivity of quadratic tets at offsets 0, 10, 20, ..., a float64 field), else
converted once; every size the input claims is checked before the core sees it; the scene
(validation and hierarchy) is kept until the mesh or the field changes; the image is cast tile by
tile on all cores, the core writing straight into the output's VTK arrays.

Not here (the C++ build has them): distributed rendering over a vtkMultiProcessController.
"""
import math
import os
import weakref

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import (VTK_FLOAT, VTK_UNSIGNED_CHAR, vtkCommand, vtkDataArray,
                                      vtkDoubleArray, vtkIdTypeArray, vtkOutputWindow,
                                      vtkUnsignedCharArray)
from vtkmodules.vtkCommonDataModel import (VTK_QUADRATIC_TETRA, VTK_TETRA, vtkDataObject,
                                           vtkDataSetAttributes, vtkImageData, vtkPlaneCollection,
                                           vtkUnstructuredGrid)
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm, vtkStreamingDemandDrivenPipeline
from vtkmodules.vtkCommonMisc import vtkContourValues
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction

from . import _core

# Bytes per output pixel, as the C++ filter counts them: Colors (4), Depth (8), Normals (24),
# CellId (8), ColorValues (8), and the depth-buffer normals' per-pixel record (64).
_BYTES_PER_PIXEL = 4 + 8 + 24 + 8 + 8 + 64
# Entries of the colour table sampled from a lookup table (the C++ adapter's kColorTableSize).
_COLOR_TABLE_SIZE = 1024
# Progress reports / abort checks per cast (the adapter's kProgressSteps).
_PROGRESS_STEPS = 32
# A camera farther than this many scene diagonals is refused (the adapter's kMaxCameraDistance).
_MAX_CAMERA_DISTANCE = 1e9
# Iso-value colour and opacity indices are refused at and beyond this (IsoValueStyles::kMaxIndex).
_MAX_STYLE_INDEX = 1 << 20
# A quadratic cell's negative id is invalid, not a straight edge: it is kept out of range.
_INVALID_ID = np.iinfo(np.int64).min


def _physical_memory():
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 0


def _name(array):
    return array.GetName() or "(unnamed)"


def _built_in_color_map(which):
    """One of the built-in colour maps over [0, 1] (the C++ filter's BuiltInColorMap)."""
    table = vtkColorTransferFunction()
    if which == vtkDirectSurfaceRayCaster.RAINBOW:
        table.SetColorSpaceToHSV()
        table.AddRGBPoint(0.0, 0.0, 0.0, 1.0)
        table.AddRGBPoint(1.0, 1.0, 0.0, 0.0)
    elif which == vtkDirectSurfaceRayCaster.GRAYSCALE:
        table.AddRGBPoint(0.0, 0.0, 0.0, 0.0)
        table.AddRGBPoint(1.0, 1.0, 1.0, 1.0)
    elif which == vtkDirectSurfaceRayCaster.BLACK_BODY:
        table.AddRGBPoint(0.0, 0.0, 0.0, 0.0)
        table.AddRGBPoint(0.4, 0.9, 0.0, 0.0)
        table.AddRGBPoint(0.8, 0.9, 0.9, 0.0)
        table.AddRGBPoint(1.0, 1.0, 1.0, 1.0)
    else:
        # Moreland's diverging map: blue (0.230, 0.299, 0.754) to red (0.706, 0.016, 0.150).
        table.SetColorSpaceToDiverging()
        table.AddRGBPoint(0.0, 0.230, 0.299, 0.754)
        table.AddRGBPoint(1.0, 0.706, 0.016, 0.150)
    table.SetNanColor(0.5, 0.5, 0.5)
    return table


def _sample_color_table(lookup_table, lo, hi):
    """`lookup_table` sampled over its own range into (lo, hi, colours, NaN colour)."""
    low, high = lookup_table.GetRange()
    colors = np.empty((_COLOR_TABLE_SIZE, 3))
    rgb = [0.0, 0.0, 0.0]
    for k in range(_COLOR_TABLE_SIZE):
        x = k / (_COLOR_TABLE_SIZE - 1)
        lookup_table.GetColor(low + x * (high - low), rgb)
        colors[k] = rgb
    lookup_table.GetColor(float("nan"), rgb)
    return lo, hi, colors, tuple(rgb)


def _finite_range(values, component):
    """The range of one component (-1: the magnitude) over finite values; [0, 1] if none is."""
    if component >= 0:
        x = values[:, component]
    else:
        with np.errstate(over="ignore", invalid="ignore"):
            x = np.sqrt(np.sum(values * values, axis=1))
    x = x[np.isfinite(x)]
    return (float(x.min()), float(x.max())) if x.size else (0.0, 1.0)


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


class _PreparedMesh:
    """The core's scene for a mesh and field, with the counts of cells left out before it and
    what it was built from (each object with its modification time, held so that no id is
    reused). The C++ adapter's PreparedMesh."""

    def __init__(self, stamp, scene, input_cell_ids, unsupported, malformed, number_of_points,
                 copies):
        self.stamp = stamp
        self.scene = scene
        self.input_cell_ids = input_cell_ids  # scene cell -> input cell; None: the identity
        self.unsupported = unsupported
        self.malformed = malformed
        self.number_of_points = number_of_points
        self.copies = copies  # arrays converted from VTK's layout
        self.color_array = None  # (array, mtime, values as float64)


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
             cells.GetConnectivityArray() if cells else None, _cell_types(grid), scalars]
    return tuple((part, part.GetMTime() if part is not None else 0) for part in parts) + (
        component, transverse)


def _same_stamp(a, b):
    return a is not None and len(a) == len(b) and all(
        (x[0] is y[0] and x[1] == y[1]) if isinstance(x, tuple) else x == y for x, y in zip(a, b))


class _Messages:
    def __init__(self):
        self.errors, self.warnings = [], []


class vtkDirectSurfaceRayCaster(VTKPythonAlgorithmBase):
    """Ray casts the exact isosurface of a quadratic tetrahedral field into an image.

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
    MaximumNumberOfClippingPlanes = 6

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=1, inputType="vtkUnstructuredGrid",
                                        nOutputPorts=1, outputType="vtkImageData")
        self.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS,
                                    vtkDataSetAttributes.SCALARS)
        self._contour_values = vtkContourValues()
        self._settings = dict(
            ImageSize=(512, 512), ArrayComponent=-1, SurfaceColor=(1.0, 1.0, 1.0), Ambient=0.1,
            Diffuse=0.7, Specular=0.2, SpecularPower=30.0, LightAtCamera=True,
            LightPosition=(0.0, 0.0, 1.0), NumberOfThreads=0, NormalMode=self.EXACT_GRADIENT,
            CentralDifferenceStep=1e-3, TransverseTest=self.BERNSTEIN_BOUND,
            NodalRangeWidening=0.25, ColorByArray=False, ColorArrayComponent=-1,
            ColorRange=(0.0, -1.0), ColorMap=self.COOL_TO_WARM, Capping=self.NO_CAP)
        self._camera = None
        self._lookup_table = None
        self._clipping_planes = None
        self._iso_colors = {}     # iso-value index -> (r, g, b)
        self._iso_opacities = {}  # iso-value index -> opacity
        self._observed = []       # (object, observer tag): edits of these re-execute the filter
        self._prepared = None
        self._counts = dict.fromkeys(
            ("Rendered", "Inverted", "Curved", "Degenerate", "Tangled", "NonFinite", "InvalidId",
             "Unsupported", "Malformed", "OutOfScale", "UncertifiedHits"), 0)
        # The contour values are an object of their own: their edits must reach this filter.
        self._observe(self._contour_values)

    # -- messages: as vtkErrorMacro / vtkWarningMacro, observable as ErrorEvent / WarningEvent
    def _report(self, messages):
        for text in messages.warnings:
            self._emit(vtkCommand.WarningEvent, "Warning", text)
        for text in messages.errors:
            self._emit(vtkCommand.ErrorEvent, "ERROR", text)
        messages.errors, messages.warnings = [], []

    def _error(self, text):
        self._emit(vtkCommand.ErrorEvent, "ERROR", text)

    def _emit(self, event, kind, text):
        if self.HasObserver(event):
            self.InvokeEvent(event, text)
        elif event == vtkCommand.ErrorEvent or self.GetGlobalWarningDisplay():
            line = f"{kind}: In tetdsr, vtkDirectSurfaceRayCaster ({hex(id(self))}): {text}\n\n"
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
                if isinstance(caller, vtkPlaneCollection):
                    filter_._observe_planes()
                filter_.Modified()

        self._observed.append((obj, obj.AddObserver(vtkCommand.ModifiedEvent, modified)))

    def _unobserve(self, obj):
        for observed, tag in [x for x in self._observed if x[0] is obj]:
            observed.RemoveObserver(tag)
        self._observed = [x for x in self._observed if x[0] is not obj]

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

    def _set(self, key, value):
        if self._settings[key] != value:
            self._settings[key] = value
            self.Modified()

    # -- the pipeline's convenience methods of VTK's C++ algorithms
    def SetInputData(self, data):
        self.SetInputDataObject(0, data)

    def GetOutput(self):
        return self.GetOutputDataObject(0)

    # -- iso-values, as vtkContourFilter
    def SetValue(self, i, value):
        self._contour_values.SetValue(i, value)

    def GetValue(self, i):
        return self._contour_values.GetValue(i)

    def GetValues(self):
        return tuple(self._contour_values.GetValue(i) for i in range(self.GetNumberOfContours()))

    def SetNumberOfContours(self, number):
        self._contour_values.SetNumberOfContours(number)

    def GetNumberOfContours(self):
        return self._contour_values.GetNumberOfContours()

    def GenerateValues(self, count, start, end=None):
        if end is None:
            start, end = start
        self._contour_values.GenerateValues(count, start, end)

    # -- camera and image
    def SetCamera(self, camera):
        """vtkCamera: position, focal point, view up, view angle (vertical), parallel projection
        and scale are used. None: a camera that sees the whole mesh (looking down -z)."""
        self._set_object("_camera", camera)

    def GetCamera(self):
        return self._camera

    def SetImageSize(self, width, height=None):
        if height is None:
            width, height = width
        self._set("ImageSize", (int(width), int(height)))

    def GetImageSize(self):
        return self._settings["ImageSize"]

    def SetArrayComponent(self, component):
        self._set("ArrayComponent", int(component))

    def GetArrayComponent(self):
        return self._settings["ArrayComponent"]

    # -- shading
    def SetSurfaceColor(self, red, green=None, blue=None):
        if green is None:
            red, green, blue = red
        self._set("SurfaceColor", (float(red), float(green), float(blue)))

    def GetSurfaceColor(self):
        return self._settings["SurfaceColor"]

    def _set_clamped(self, key, value, lo, hi):
        value = float(value)
        if math.isnan(value):
            self._error(f"{key} must be a number, got NaN.")
            return
        self._set(key, min(max(value, lo), hi))

    def SetAmbient(self, value):
        self._set_clamped("Ambient", value, 0.0, 1.0)

    def GetAmbient(self):
        return self._settings["Ambient"]

    def SetDiffuse(self, value):
        self._set_clamped("Diffuse", value, 0.0, 1.0)

    def GetDiffuse(self):
        return self._settings["Diffuse"]

    def SetSpecular(self, value):
        self._set_clamped("Specular", value, 0.0, 1.0)

    def GetSpecular(self):
        return self._settings["Specular"]

    def SetSpecularPower(self, value):
        self._set_clamped("SpecularPower", value, 0.0, 128.0)

    def GetSpecularPower(self):
        return self._settings["SpecularPower"]

    def SetLightAtCamera(self, on):
        self._set("LightAtCamera", bool(on))

    def GetLightAtCamera(self):
        return self._settings["LightAtCamera"]

    def LightAtCameraOn(self):
        self.SetLightAtCamera(True)

    def LightAtCameraOff(self):
        self.SetLightAtCamera(False)

    def SetLightPosition(self, x, y=None, z=None):
        if y is None:
            x, y, z = x
        self._set("LightPosition", (float(x), float(y), float(z)))

    def GetLightPosition(self):
        return self._settings["LightPosition"]

    def SetNormalMode(self, mode):
        self._set("NormalMode", min(max(int(mode), self.EXACT_GRADIENT), self.DEPTH_BUFFER))

    def GetNormalMode(self):
        return self._settings["NormalMode"]

    def SetCentralDifferenceStep(self, step):
        self._set_clamped("CentralDifferenceStep", step, 1e-12, 1.0)

    def GetCentralDifferenceStep(self):
        return self._settings["CentralDifferenceStep"]

    # -- per-iso-value colours and opacities
    def _style_index_ok(self, method, i):
        if not 0 <= i < _MAX_STYLE_INDEX:
            self._error(f"{method}: index {i} is outside [0, {_MAX_STYLE_INDEX}).")
            return False
        return True

    def SetIsoValueColor(self, i, red, green, blue):
        if self._style_index_ok("SetIsoValueColor", i):
            color = tuple(min(max(float(c), 0.0), 1.0) for c in (red, green, blue))
            if self._iso_colors.get(i) != color:
                self._iso_colors[i] = color
                self.Modified()

    def GetIsoValueColor(self, i):
        return self._iso_colors.get(i, self._settings["SurfaceColor"])

    def RemoveAllIsoValueColors(self):
        if self._iso_colors:
            self._iso_colors.clear()
            self.Modified()

    def SetIsoValueOpacity(self, i, opacity):
        if self._style_index_ok("SetIsoValueOpacity", i):
            opacity = min(max(float(opacity), 0.0), 1.0)
            if self._iso_opacities.get(i) != opacity:
                self._iso_opacities[i] = opacity
                self.Modified()

    def GetIsoValueOpacity(self, i):
        return self._iso_opacities.get(i, 1.0)

    def RemoveAllIsoValueOpacities(self):
        if self._iso_opacities:
            self._iso_opacities.clear()
            self.Modified()

    # -- colour by an array
    def SetColorByArray(self, on):
        self._set("ColorByArray", bool(on))

    def GetColorByArray(self):
        return self._settings["ColorByArray"]

    def ColorByArrayOn(self):
        self.SetColorByArray(True)

    def ColorByArrayOff(self):
        self.SetColorByArray(False)

    def SetColorArrayComponent(self, component):
        self._set("ColorArrayComponent", max(int(component), -1))

    def GetColorArrayComponent(self):
        return self._settings["ColorArrayComponent"]

    def SetColorRange(self, lo, hi=None):
        if hi is None:
            lo, hi = lo
        self._set("ColorRange", (float(lo), float(hi)))

    def GetColorRange(self):
        return self._settings["ColorRange"]

    def SetLookupTable(self, table):
        self._set_object("_lookup_table", table)

    def GetLookupTable(self):
        return self._lookup_table

    def SetColorMap(self, which):
        self._set("ColorMap", min(max(int(which), self.COOL_TO_WARM), self.BLACK_BODY))

    def GetColorMap(self):
        return self._settings["ColorMap"]

    # -- clipping and caps
    def AddClippingPlane(self, plane):
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
        self._set_object("_clipping_planes", planes)

    def GetClippingPlanes(self):
        return self._clipping_planes

    def SetCapping(self, mode):
        self._set("Capping", min(max(int(mode), self.NO_CAP), self.CAP_ABOVE_ISO_VALUE))

    def GetCapping(self):
        return self._settings["Capping"]

    # -- transverse test and threads
    def SetTransverseTest(self, mode):
        self._set("TransverseTest",
                  min(max(int(mode), self.BERNSTEIN_BOUND), self.WIDENED_NODAL_RANGE))

    def GetTransverseTest(self):
        return self._settings["TransverseTest"]

    def SetNodalRangeWidening(self, widening):
        self._set_clamped("NodalRangeWidening", widening, 0.0, np.finfo(float).max)

    def GetNodalRangeWidening(self):
        return self._settings["NodalRangeWidening"]

    def SetNumberOfThreads(self, threads):
        self._set("NumberOfThreads", max(int(threads), 0))

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

    def GetNumberOfOutOfScaleCells(self):
        return self._counts["OutOfScale"]

    def GetNumberOfUncertifiedHits(self):
        return self._counts["UncertifiedHits"]

    def GetPreprocessedBytes(self):
        """Bytes kept between executions: the scene and converted copies of input arrays."""
        prepared = self._prepared
        if prepared is None:
            return 0
        copies = sum(a.nbytes for a in prepared.copies)
        return prepared.scene.memory_bytes + copies

    # -- the pipeline
    def _check_image_size(self, messages):
        width, height = self._settings["ImageSize"]
        pixels = float(width) * float(height)
        size = pixels * _BYTES_PER_PIXEL
        memory = _physical_memory()
        fits_indices = pixels < 2147483647.0
        if width > 0 and height > 0 and fits_indices and not (memory > 0 and size > memory):
            return True
        text = f"ImageSize {width} x {height} pixels"
        if width > 0 and height > 0:
            text += f" needs {size / 2 ** 30:.3g} GiB"
            if memory > 0:
                text += f"; this machine has {memory / 2 ** 30:.3g} GiB"
            if not fits_indices:
                text += "; VTK images hold fewer than 2^31 pixels"
        messages.errors.append(text + ": choose a smaller size.")
        return False

    def RequestInformation(self, request, inInfo, outInfo):
        messages = _Messages()
        if not self._check_image_size(messages):
            self._report(messages)
            return 0
        width, height = self._settings["ImageSize"]
        info = outInfo.GetInformationObject(0)
        info.Set(vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT(),
                 (0, width - 1, 0, height - 1, 0, 0), 6)
        info.Set(vtkDataObject.SPACING(), (1.0, 1.0, 1.0), 3)
        info.Set(vtkDataObject.ORIGIN(), (0.0, 0.0, 0.0), 3)
        vtkDataObject.SetPointDataActiveScalarInfo(info, VTK_UNSIGNED_CHAR, 4)
        info.Set(vtkAlgorithm.CAN_PRODUCE_SUB_EXTENT(), 1)
        return 1

    def _point_array(self, index, inInfo):
        """Input array `index` (0: the field, 1: the colour array) and its association, or
        (None, None) after an error naming it."""
        info = self.GetInputArrayInformation(index)
        name = info.Get(vtkDataObject.FIELD_NAME()) if info.Has(vtkDataObject.FIELD_NAME()) else None
        array, association = _input_array(vtkUnstructuredGrid.GetData(inInfo[0]), info, name)
        if array is not None:
            return array, association
        if index == 0 and name:
            self._error(f"No point array named '{name}' in the input.")
        elif index == 0:
            self._error("No point scalars: the input has no active point scalars; choose an array "
                        "with SetInputArrayToProcess(0, 0, 0, FIELD_ASSOCIATION_POINTS, name).")
        else:
            which = (f"there is no point array named '{name}'" if name
                     else "no colour array is chosen")
            self._error(f"ColorByArray is on but {which}: choose one with "
                        "SetInputArrayToProcess(1, 0, 0, FIELD_ASSOCIATION_POINTS, name).")
        return None, None

    @staticmethod
    def _check_point_array(array, association, requested, allow_magnitude, setting, messages):
        """The component to use (-1: the magnitude), or None after an error."""
        name = _name(array)
        if association != vtkDataObject.FIELD_ASSOCIATION_POINTS:
            messages.errors.append(f"Array '{name}' is not a point array: the quadratic field "
                                   "needs values at the nodes.")
            return None
        components = array.GetNumberOfComponents()
        if requested >= components:
            messages.errors.append(f"{setting} {requested} is out of range: array '{name}' has "
                                   f"{components} components.")
            return None
        if requested >= 0 or components == 1:
            return max(requested, 0)
        if not allow_magnitude:
            messages.errors.append(f"Array '{name}' has {components} components: choose one "
                                   f"with {setting}.")
            return None
        return -1

    def _iso_values(self, messages):
        values = list(self.GetValues())
        if not values:
            messages.errors.append("No iso-value: set one with SetValue(0, value).")
            return None
        for value in values:
            if not math.isfinite(value):
                messages.errors.append(f"Iso-value {value} is not finite.")
                return None
        return values

    def _clip_planes(self, messages):
        planes = self._clipping_planes
        count = planes.GetNumberOfItems() if planes is not None else 0
        if count > self.MaximumNumberOfClippingPlanes:
            messages.errors.append(f"{count} clipping planes: at most "
                                   f"{self.MaximumNumberOfClippingPlanes} are supported.")
            return None
        rows = np.zeros((count, 6))
        for k in range(count):
            plane = planes.GetItem(k)
            rows[k, :3] = plane.GetOrigin()
            rows[k, 3:] = plane.GetNormal()
            if not np.all(np.isfinite(rows[k])):
                messages.errors.append(f"Clipping plane {k} has a NaN or Inf in its normal or origin.")
                return None
            if not np.any(rows[k, 3:] != 0.0):
                messages.errors.append(f"Clipping plane {k} has a zero normal: it keeps no side.")
                return None
        return rows

    def _prepare(self, grid, scalars, component, messages):
        """The scene for `grid` and its field: the last one while nothing it was built from
        changed, else converted and built afresh. None, with errors, when the input cannot be
        converted; with errors and its counts when no cell can be rendered. Warnings count the
        skipped cells once, when the scene is built."""
        transverse = (self._settings["TransverseTest"], self._settings["NodalRangeWidening"])
        stamp = _stamp(grid, scalars, component, transverse)
        prepared = self._prepared
        same = prepared is not None and _same_stamp(prepared.stamp, stamp)
        if not same:
            self._prepared = None
            prepared = self._convert(grid, scalars, component, transverse, stamp, messages)
            if prepared is None:
                return None
            self._prepared = prepared
        summary = prepared.scene.summary
        warnings = []
        if prepared.unsupported:
            warnings.append(f"Skipped {prepared.unsupported} cells whose type is neither "
                            "VTK_QUADRATIC_TETRA nor VTK_TETRA.")
        if prepared.malformed:
            warnings.append(f"Skipped {prepared.malformed} malformed cells: a number of node ids "
                            "that does not match the type (10 for VTK_QUADRATIC_TETRA, 4 for "
                            "VTK_TETRA), or offsets out of order or past the end of the "
                            "connectivity array.")
        if summary["tangled"]:
            warnings.append(f"Skipped {summary['tangled']} tangled curved cells (mid-edge nodes "
                            "so far off their edges that the cell folds: the Jacobian determinant "
                            "of its quadratic map changes sign or vanishes inside it).")
        if summary["degenerate"]:
            warnings.append(f"Skipped {summary['degenerate']} degenerate cells (flat or "
                            "needle-like: 6 x volume below 1e-13 of the longest edge cubed; or a "
                            "node id repeated within the cell).")
        if summary["out_of_scale"]:
            warnings.append(f"Skipped {summary['out_of_scale']} cells whose longest edge is "
                            "outside [1e-100, 1e+100]: their volumes would underflow or overflow "
                            "double precision.")
        if summary["non_finite"]:
            warnings.append(f"Skipped {summary['non_finite']} cells with NaN or Inf values of "
                            f"'{_name(scalars)}' or coordinates at their nodes.")
        if summary["invalid_id"]:
            warnings.append(f"Skipped {summary['invalid_id']} cells with node ids outside "
                            f"[0, {prepared.number_of_points}).")
        if not same:
            messages.warnings.extend(warnings)  # told when the scene is built, not every render
        if summary["valid"] == 0:
            messages.errors.append(f"No cell can be rendered: all {grid.GetNumberOfCells()} "
                                   "input cells were skipped.")
        return prepared

    def _convert(self, grid, scalars, component, transverse, stamp, messages):
        points = grid.GetPoints()
        cells = grid.GetCells()
        number_of_points = points.GetNumberOfPoints() if points is not None else 0
        number_of_cells = cells.GetNumberOfCells() if cells is not None else 0
        if number_of_points == 0 or number_of_cells == 0:
            messages.errors.append("The input mesh is empty: it has no cells or no points.")
            return None
        if number_of_cells > _core.MAX_CELLS:
            messages.errors.append(f"The input has {number_of_cells} cells; at most "
                                   f"{_core.MAX_CELLS} can be rendered.")
            return None
        types_array = _cell_types(grid)
        if (types_array is None or types_array.GetNumberOfTuples() < number_of_cells
                or types_array.GetNumberOfComponents() != 1):
            count = types_array.GetNumberOfValues() if types_array is not None else 0
            messages.errors.append(f"The input's cell types array has {count} values for "
                                   f"{number_of_cells} cells.")
            return None
        if scalars.GetNumberOfTuples() < number_of_points:
            messages.errors.append(f"Point array '{_name(scalars)}' has "
                                   f"{scalars.GetNumberOfTuples()} tuples for {number_of_points} points.")
            return None
        copies = []  # arrays converted from VTK's layout (counted in GetPreprocessedBytes)

        # Points: viewed when VTK stores them as doubles, else converted once. Mid-edge nodes
        # within rounding of their edges' midpoints are straight: float coordinates round at
        # 2^-24 relative.
        point_data = points.GetData()
        xyz = _as_numpy(point_data)[:number_of_points]
        if xyz.dtype != np.float64 or not xyz.flags.c_contiguous or xyz.shape[1] != 3:
            xyz = np.ascontiguousarray(xyz[:, :3], dtype=np.float64)
            copies.append(xyz)
        rounding = 2.0 ** -23 if point_data.GetDataType() == VTK_FLOAT else 2.0 ** -52

        field = _as_numpy(scalars)[:number_of_points, component]
        if field.dtype != np.float64 or not field.flags.c_contiguous:
            field = np.ascontiguousarray(field, dtype=np.float64)
            copies.append(field)

        # Connectivity: viewed when every cell is a quadratic tet at offsets 0, 10, 20, ...
        # (a .vtu may claim the type and give another count); else copied, each cell checked
        # against the arrays.
        types = vtk_to_numpy(types_array)[:number_of_cells]
        offsets = vtk_to_numpy(cells.GetOffsetsArray())
        connectivity = vtk_to_numpy(cells.GetConnectivityArray())
        unsupported = malformed = 0
        input_cell_ids = None
        regular = (connectivity.dtype == np.int64 and connectivity.size == 10 * number_of_cells
                   and np.all(types == VTK_QUADRATIC_TETRA)
                   and np.array_equal(offsets, np.arange(0, 10 * number_of_cells + 1, 10)))
        if regular:
            nodes = connectivity.reshape(number_of_cells, 10)
            straight_edge_markers = False
        else:
            begin = offsets[:-1].astype(np.int64)
            end = offsets[1:].astype(np.int64)
            quadratic = types == VTK_QUADRATIC_TETRA
            supported = quadratic | (types == VTK_TETRA)
            expected = np.where(quadratic, 10, 4)
            well_formed = supported & (begin >= 0) & (end <= connectivity.size) & (end - begin == expected)
            unsupported = int(np.count_nonzero(~supported))
            malformed = int(np.count_nonzero(supported & ~well_formed))
            input_cell_ids = np.flatnonzero(well_formed)
            if input_cell_ids.size == 0:
                messages.errors.append(
                    f"No cell can be rendered: none of the {number_of_cells} input cells is a "
                    f"well-formed VTK_QUADRATIC_TETRA or VTK_TETRA ({unsupported} of another "
                    f"type, {malformed} malformed).")
                return None
            first = begin[input_cell_ids]
            count = expected[input_cell_ids]
            # A linear tet's six mid-edge ids are the core's straight-edge marker, -1.
            nodes = np.full((input_cell_ids.size, 10), -1, dtype=np.int64)
            for n in range(10):
                rows = count > n
                ids = connectivity[first[rows] + n].astype(np.int64)
                nodes[rows, n] = np.where(ids < 0, _INVALID_ID, ids)
            straight_edge_markers = True
            copies.extend((nodes, input_cell_ids))

        scene = _core.Scene(xyz, nodes, field, point_rounding=rounding,
                            straight_edge_markers=straight_edge_markers,
                            transverse_mode=transverse[0], widening=transverse[1],
                            threads=self._settings["NumberOfThreads"])
        return _PreparedMesh(stamp, scene, input_cell_ids, unsupported, malformed,
                             number_of_points, copies)

    def _color_values(self, prepared, array, messages):
        """The colour array as float64 values (a view if VTK stores doubles), kept until the
        array changes; None, with an error, when it is shorter than the mesh."""
        if array.GetNumberOfTuples() < prepared.number_of_points:
            messages.errors.append(f"The colour array '{array.GetName() or ''}' has "
                                   f"{array.GetNumberOfTuples()} tuples for "
                                   f"{prepared.number_of_points} points.")
            return None
        cached = prepared.color_array
        if cached is not None and cached[0] is array and cached[1] == array.GetMTime():
            return cached[2]
        values = np.ascontiguousarray(_as_numpy(array)[:prepared.number_of_points], dtype=np.float64)
        prepared.color_array = (array, array.GetMTime(), values)
        return values

    def _core_camera(self, scene, aspect):
        camera = self._camera
        if camera is None:
            bounds = scene.bounds()
            return _core.reset_camera(bounds, aspect) | {"parallel": False}
        return dict(position=camera.GetPosition(), focal_point=camera.GetFocalPoint(),
                    view_up=camera.GetViewUp(), view_angle=camera.GetViewAngle(),
                    parallel=bool(camera.GetParallelProjection()),
                    parallel_scale=camera.GetParallelScale())

    @staticmethod
    def _check_camera(camera, scene, messages):
        problem = _core.check_camera(**camera)
        if problem is not None:
            messages.errors.append(f"Cannot render: {problem}.")
            return False
        bounds = scene.bounds()
        if bounds is not None:
            centre = np.array([bounds[0] + bounds[1], bounds[2] + bounds[3], bounds[4] + bounds[5]]) / 2
            # Compared in units of the diagonal, each component first, so nothing overflows.
            with np.errstate(over="ignore"):
                offset = (np.array(camera["position"]) - centre) / max(scene.diagonal(), 1e-300)
            largest = float(np.max(np.abs(offset)))
            if not largest <= _MAX_CAMERA_DISTANCE:
                messages.errors.append(
                    f"Cannot render: the camera is {largest:g} scene diagonals from the scene; "
                    f"beyond {_MAX_CAMERA_DISTANCE:g} double-precision rays cannot place hits "
                    "within 1e-7 of the scene.")
                return False
        return True

    def RequestData(self, request, inInfo, outInfo):
        grid = vtkUnstructuredGrid.GetData(inInfo[0])
        output = vtkImageData.GetData(outInfo)
        s = self._settings
        width, height = s["ImageSize"]
        messages = _Messages()
        if grid is None or grid.GetNumberOfCells() == 0 or grid.GetNumberOfPoints() == 0:
            self._error("The input mesh is empty: it has no cells or no points.")
            return 0

        # The field, its iso-values, the colour array and the clipping planes.
        scalars, association = self._point_array(0, inInfo)
        if scalars is None:
            return 0
        component = self._check_point_array(scalars, association, s["ArrayComponent"], False,
                                            "ArrayComponent", messages)
        values = self._iso_values(messages) if component is not None else None
        if values is None:
            self._report(messages)
            return 0
        color_array, color_component = None, -1
        if s["ColorByArray"]:
            color_array, color_association = self._point_array(1, inInfo)
            if color_array is None:
                return 0
            color_component = self._check_point_array(
                color_array, color_association, s["ColorArrayComponent"], True,
                "ColorArrayComponent", messages)
            if color_component is None:
                self._report(messages)
                return 0
        clip_planes = self._clip_planes(messages)
        if clip_planes is None:
            self._report(messages)
            return 0

        # Preprocess once per mesh, array and transverse test.
        prepared = self._prepare(grid, scalars, component, messages)
        summary = prepared.scene.summary if prepared is not None else None
        counts = self._counts
        counts["Rendered"] = summary["valid"] if prepared is not None and not messages.errors else 0
        for key, core_key in (("Inverted", "inverted"), ("Curved", "curved"),
                              ("Degenerate", "degenerate"), ("Tangled", "tangled"),
                              ("OutOfScale", "out_of_scale"), ("NonFinite", "non_finite"),
                              ("InvalidId", "invalid_id")):
            counts[key] = summary[core_key] if summary is not None else 0
        counts["Unsupported"] = prepared.unsupported if prepared is not None else 0
        counts["Malformed"] = prepared.malformed if prepared is not None else 0
        color_values = None
        if prepared is not None and color_array is not None:
            color_values = self._color_values(prepared, color_array, messages)
        if prepared is None or messages.errors:
            self._report(messages)
            return 0
        self._report(messages)  # the warnings
        scene = prepared.scene

        camera = self._core_camera(scene, width / height)
        if not self._check_camera(camera, scene, messages):
            self._report(messages)
            return 0

        # The output arrays, which the core writes in place (numpy views of VTK's memory).
        pixels = width * height
        color_mapped = s["ColorByArray"] or (s["Capping"] != self.NO_CAP and len(clip_planes) > 0)
        arrays = {}
        try:
            for name, array_type, components in (
                    ("Colors", vtkUnsignedCharArray, 4), ("Depth", vtkDoubleArray, 1),
                    ("Normals", vtkDoubleArray, 3), ("CellId", vtkIdTypeArray, 1),
                    ("ColorValues", vtkDoubleArray, 1)):
                if name == "ColorValues" and not color_mapped:
                    continue
                array = array_type()
                array.SetName(name)
                array.SetNumberOfComponents(components)
                array.SetNumberOfTuples(pixels)
                arrays[name] = array
            views = {name: vtk_to_numpy(array).reshape(-1) for name, array in arrays.items()}
        except MemoryError:
            self._error(f"Cannot allocate the {width} x {height} output image.")
            return 0

        # Shading, as the C++ filter's ShadingSettings: one white point light at the camera (or
        # at LightPosition), the iso-values' styles, the cap, the colour table.
        light = camera["position"] if s["LightAtCamera"] else s["LightPosition"]
        styles = np.array([list(self._iso_colors.get(i, s["SurfaceColor"]))
                           + [self._iso_opacities.get(i, 1.0)] for i in range(len(values))])
        table = (0.0, 1.0, np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]), (0.5, 0.5, 0.5))
        color_by = None
        color_components = 1
        if color_mapped:
            lo, hi = s["ColorRange"]
            if not (lo <= hi and math.isfinite(lo) and math.isfinite(hi)):
                # The colour array's finite range (-1: the magnitude's), else the field's.
                if color_array is not None:
                    lo, hi = _finite_range(color_values, color_component)
                else:
                    lo, hi = _finite_range(_as_numpy(scalars), component)
            if color_array is not None:
                color_by = color_values.reshape(-1)
                color_components = color_array.GetNumberOfComponents()
            lookup_table = self._lookup_table or _built_in_color_map(s["ColorMap"])
            table = _sample_color_table(lookup_table, lo, hi)

        renderer = _core.Renderer(
            scene, values, camera["position"], camera["focal_point"], camera["view_up"],
            camera["view_angle"], camera["parallel"], camera["parallel_scale"], width, height,
            views["Colors"], views["Depth"], views["Normals"], views["CellId"],
            views.get("ColorValues"), s["SurfaceColor"], s["Ambient"], s["Diffuse"],
            s["Specular"], s["SpecularPower"], tuple(light), s["NormalMode"],
            s["CentralDifferenceStep"], styles, color_by, color_components, color_component,
            table[0], table[1], table[2], table[3], clip_planes,
            {self.NO_CAP: 0, self.CAP_BELOW_ISO_VALUE: 1, self.CAP_ABOVE_ISO_VALUE: 2}[s["Capping"]])

        # Cast in steps, between which progress is told and abort asked.
        tiles = renderer.number_of_tiles
        step = max(1, tiles // _PROGRESS_STEPS)
        uncertified_before = scene.uncertified_hits
        done = 0
        while done < tiles and not self.CheckAbort():
            end = min(tiles, done + step)
            renderer.render_tiles(done, end, s["NumberOfThreads"])
            done = end
            self.UpdateProgress(done / tiles)
        counts["UncertifiedHits"] = scene.uncertified_hits - uncertified_before
        if done < tiles:
            self._emit(vtkCommand.WarningEvent, "Warning",
                       f"Aborted after {done} of {tiles} image tiles.")
            # The executive empties the output and marks it aborted.
            self.SetAbortOutput(True)
            return 1
        if s["NormalMode"] == self.DEPTH_BUFFER:
            renderer.shade_from_depth(s["NumberOfThreads"])

        # Scene cells back to input cell ids where cells were left out.
        if prepared.input_cell_ids is not None:
            ids = views["CellId"]
            hit = ids >= 0
            ids[hit] = prepared.input_cell_ids[ids[hit]]

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
        return 1
