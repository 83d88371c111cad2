"""What the wheel's filters of a field share (filter.py's vtkDirectSurfaceRayCaster, contour.py's
vtkDirectSurfaceContour): numpy views of VTK's arrays, the input array as VTK chooses it, the
stamps that decide when the mesh is prepared again, the settings of the core's settings table as
Set/Get methods (_settings_from_table), and _FieldFilter: the input, iso-values, the core's
prepared mesh and the core's messages as VTK's events.
"""
import numbers
import weakref

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import vtkCollection, vtkCommand, vtkDataArray, vtkOutputWindow
from vtkmodules.vtkCommonDataModel import (vtkCompositeDataSet, vtkDataObject,
                                           vtkDataSetAttributes, vtkUnstructuredGrid)
from vtkmodules.vtkCommonMisc import vtkContourValues

from . import _core


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


def _cell_ghosts(grid):
    """The grid's cell ghost flags: any array named vtkGhostType (the core checks its type and
    size), or None."""
    return grid.GetCellData().GetArray("vtkGhostType")


def _stamp(grid, scalars, component, transverse):
    points = grid.GetPoints()
    cells = grid.GetCells()
    parts = [grid, points, points.GetData() if points else None, cells,
             cells.GetOffsetsArray() if cells else None,
             cells.GetConnectivityArray() if cells else None, _cell_types(grid), scalars,
             grid.GetPointData().GetRationalWeights(), _cell_ghosts(grid)]
    return tuple((part, part.GetMTime() if part is not None else 0) for part in parts) + (
        component, transverse)


def _integer(setter, value):
    """An integer argument (bool and numpy integers too), as VTK's wrappers take one for an int;
    a TypeError naming the setter for anything else (a float is not truncated)."""
    if isinstance(value, numbers.Integral):
        return int(value)
    raise TypeError(f"{setter} takes an integer, got {value!r}")


def _reals(setter, values):
    """Numbers (numpy's too) as floats; a TypeError naming the setter for anything else."""
    if all(isinstance(v, numbers.Real) for v in values):
        return tuple(float(v) for v in values)
    raise TypeError(f"{setter} takes numbers, got {values!r}")


def _stored(row, values):
    """A row's values as the filter keeps and its getter returns them: a bool, int or float, or a
    tuple of them for a vector."""
    kind = {_core.SettingType.BOOL: bool, _core.SettingType.INT: int}.get(row.type, float)
    values = tuple(kind(v) for v in values)
    return values if row.components > 1 else values[0]


def _table_setter(row):
    """Set<Name> of a row of the core's settings table: the arguments (the components, or one
    sequence of them) typed as the C++ setter takes them, then checked by the core as the row says
    (its messages passed on); stored when the core accepts them."""
    name = "Set" + row.name

    def setter(self, *values):
        if len(values) == 1 and row.components > 1:
            values = tuple(values[0])
        if len(values) != row.components:
            raise TypeError(f"{name} takes {row.components} numbers, got {len(values)}")
        if row.type == _core.SettingType.DOUBLE:
            given = _reals(name, values)
        else:  # (within +-2^63 first: a float of any Python int, for the core to clamp)
            given = tuple(float(min(max(_integer(name, v), -2 ** 63), 2 ** 63)) for v in values)
        messages = _core.Messages()
        used = _core.check_setting(row, given, messages)
        self._report(messages)
        if used is not None:
            self._set(row.name, _stored(row, used))

    setter.__name__ = name
    setter.__doc__ = (f"{row.name}: {row.components} {row.type.name.lower()} value(s), default "
                      f"{_stored(row, row.defaults)!r} (the core's settings table).")
    return setter


def _settings_from_table(face):
    """A class decorator: Set/Get (and On/Off for switches) of every row of the core's settings
    table that the filter `face` ("ray_caster" or "contour") has, unless the class defines its own."""
    def install(cls):
        for row in _core.SETTINGS:
            if not getattr(row, face):
                continue
            methods = {"Set": _table_setter(row),
                       "Get": lambda self, key=row.name: self._settings[key]}
            if row.type == _core.SettingType.BOOL:
                methods["On"] = lambda self, key=row.name: getattr(self, "Set" + key)(True)
                methods["Off"] = lambda self, key=row.name: getattr(self, "Set" + key)(False)
            for prefix, method in methods.items():
                method_name = row.name + prefix if prefix in ("On", "Off") else prefix + row.name
                if method_name not in cls.__dict__:
                    method.__name__ = method_name
                    setattr(cls, method_name, method)
        cls._TABLE_FACE = face
        return cls
    return install


def _same_stamp(a, b):
    return a is not None and len(a) == len(b) and all(
        (x[0] is y[0] and x[1] == y[1]) if isinstance(x, tuple) else x == y for x, y in zip(a, b))


class _FieldFilter(VTKPythonAlgorithmBase):
    """What the wheel's filters of a field share (the C++ build's vtkDirectSurfaceAdapter and
    vtkDirectSurfaceReporting): an unstructured grid in, input array 0 the field (default the
    active point scalars) and its ArrayComponent, iso-values as vtkContourFilter's, the core's
    prepared mesh kept while the input is unchanged, and the core's messages as VTK's events
    (ErrorEvent / WarningEvent, else the output window, naming the class `_VTK_CLASS`)."""

    _VTK_CLASS = "vtkAlgorithm"

    _TABLE_FACE = None  # which filter's rows of the core's settings table (_settings_from_table)

    def __init__(self, output_type):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=1, inputType="vtkUnstructuredGrid",
                                        nOutputPorts=1, outputType=output_type)
        self.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS,
                                    vtkDataSetAttributes.SCALARS)
        self._contour_values = vtkContourValues()
        # The settings, with the defaults of the core's settings table.
        self._settings = {row.name: _stored(row, row.defaults) for row in _core.SETTINGS
                          if getattr(row, self._TABLE_FACE)}
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
        if isinstance(caller, vtkCollection):
            self._observe_items(caller)  # (an item added to the collection is observed too)
        self.Modified()

    def _observe_items(self, collection):
        for k in range(collection.GetNumberOfItems()):
            item = collection.GetItemAsObject(k)
            if not any(x[0] is item for x in self._observed):
                self._observe(item)

    def _set_object(self, attribute, value):
        """An object setting (`attribute`: its member), observed, and its items if a collection
        (a vtkPlaneCollection's planes), so that their edits re-execute the filter."""
        old = getattr(self, attribute)
        if old is value:
            return
        if old is not None:
            self._unobserve(old)
            for k in range(old.GetNumberOfItems() if isinstance(old, vtkCollection) else 0):
                self._unobserve(old.GetItemAsObject(k))
        setattr(self, attribute, value)
        if value is not None:
            self._observe(value)
            if isinstance(value, vtkCollection):
                self._observe_items(value)
        self.Modified()

    def _unobserve(self, obj):
        for observed, tag in [x for x in self._observed if x[0] is obj]:
            observed.RemoveObserver(tag)
        self._observed = [x for x in self._observed if x[0] is not obj]

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
        ghosts = _cell_ghosts(grid)
        prepared = _core.PreparedMesh()
        self._prepared, self._prepared_stamp = prepared, stamp
        ready = prepared.prepare(
            _as_numpy(grid.GetPoints().GetData()), _as_numpy(_cell_types(grid)),
            _as_numpy(cells.GetOffsetsArray()), _as_numpy(cells.GetConnectivityArray()),
            _as_numpy(scalars), field_name=scalars.GetName() or "", component=component,
            transverse=transverse, threads=threads, messages=messages,
            rational_weights=_as_numpy(weights) if weights is not None else None,
            cell_ghosts=_as_numpy(ghosts) if ghosts is not None else None)
        return prepared if ready else None
