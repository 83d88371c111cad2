"""vtkDirectSurfaceContour for any VTK Python (pip's `vtk` >= 9.3, ParaView's): the exact isosurface
as data (the C++ build's Filters/vtkDirectSurfaceContour.h) on the pip build's core.

From the grid the ray caster reads, a vtkPolyData holding the core's watertight triangle surface
(Filters/Core/tetdsr/surface/ExactSurface.h): vertices that are certified roots of each cell's own
polynomial field, triangles within a certified distance of the true surface (every piece found,
also where no nodal value crosses the iso-value), and the area, enclosed volume and point-array
integrals of the curved surface. As in filter.py, this file only moves arrays between VTK objects
and the core and passes the core's messages on.
"""
import math

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData, vtkUnstructuredGrid

from . import _core
from ._field_filter import _FieldFilter, _as_numpy, _integer, _settings_from_table


def _double_array(name, values, components=1):
    """`values` as a new vtkDoubleArray of `components` components, named."""
    flat = np.ascontiguousarray(values, dtype=np.float64).reshape(-1, components)
    array = numpy_to_vtk(flat if components > 1 else flat.reshape(-1), deep=1)
    array.SetName(name)
    return array


def _id_array(name, values):
    array = numpy_to_vtkIdTypeArray(np.ascontiguousarray(values, dtype=np.int64).reshape(-1), deep=1)
    array.SetName(name)
    return array


@_settings_from_table("contour")
class vtkDirectSurfaceContour(_FieldFilter):
    """The exact isosurface of a higher-order finite-element field (tetrahedra, hexahedra, wedges
    and pyramids of orders 1 to 4, the types the core's table reads) as a certified, watertight
    triangle surface with its integrals.

    The interface of the C++ vtkDirectSurfaceContour: input array 0 is the field
    (SetInputArrayToProcess, default the active point scalars; ArrayComponent as the ray
    caster's), iso-values as vtkContourFilter (SetValue, GetValue, SetNumberOfContours, ...),
    Tolerance (the distance bound relative to the diagonal of the valid cells' box, default 1e-3),
    AbsoluteTolerance (in scene units; 0, the default, uses Tolerance), ComputeIntegrals (default
    on) and NumberOfThreads (0, the default: all cores). Bad settings (a negative tolerance, a NaN
    iso-value) are refused at the next execution with the core's error and an empty output.

    The output vtkPolyData holds
    - points and triangles (each triangle's normal toward higher values); point data "Normals"
      (the field's exact unit gradient, the active normals) and every numeric point array of the
      input interpolated with the cell's shape functions (same names, as doubles);
    - cell data "vtkOriginalCellIds" (the input cell of each triangle) and "IsoValue";
    - field data "IsoValues"; with ComputeIntegrals, per iso-value (one tuple each) "Area",
      "AreaError", "Volume", "VolumeError" (of the region where the field >= the iso-value),
      "FlatArea" (the triangles' own area) and, per input point array, "<name> Integral" and
      "<name> IntegralError" (one component per the array's); always "DistanceBound" (the
      absolute bound asked), "LargestCertifiedBound", "Subcells", "UnresolvedSubcells",
      "SizeCertifiedSubcells" (pieces certified by size alone: within the bound, their topology
      below its scale not certified), "BoundaryEdges" and "NonManifoldEdges".
    GetArea(i), GetAreaError(i), GetVolume(i) and GetVolumeError(i) give the last execution's
    integrals of iso-value i (NaN for an i out of range or when none were computed);
    GetDistanceBound() and GetUnresolvedSubcells() its bound and uncertified pieces.
    """

    _VTK_CLASS = "vtkDirectSurfaceContour"

    def __init__(self):
        # Tolerance, AbsoluteTolerance, ComputeIntegrals, NumberOfThreads and ArrayComponent: the
        # core's settings table's rows of the contour (Set/Get made by _settings_from_table).
        _FieldFilter.__init__(self, "vtkPolyData")
        # The last execution's results (cleared when it fails).
        self._integrals = []  # SurfaceIntegrals, per iso-value
        self._distance_bound = 0.0
        self._unresolved_subcells = 0

    # -- the last execution's results
    def GetDistanceBound(self):
        """The absolute distance bound the surface was made with (0 before)."""
        return self._distance_bound

    def GetUnresolvedSubcells(self):
        """The pieces left uncertified after the most bisections (0 on a certified surface)."""
        return self._unresolved_subcells

    def _integral(self, i, member):
        i = _integer("Get" + member.title().replace("_", ""), i)
        return getattr(self._integrals[i], member) if 0 <= i < len(self._integrals) else math.nan

    def GetArea(self, i):
        """The area of iso-value i's curved surface."""
        return self._integral(i, "area")

    def GetAreaError(self, i):
        """An estimate of |GetArea(i) - the exact area|."""
        return self._integral(i, "area_error")

    def GetVolume(self, i):
        """The volume of the region of the valid cells where the field >= iso-value i."""
        return self._integral(i, "volume")

    def GetVolumeError(self, i):
        """An estimate of |GetVolume(i) - the exact volume|."""
        return self._integral(i, "volume_error")

    # -- the pipeline
    def RequestInformation(self, request, inInfo, outInfo):
        messages = _core.Messages()
        if not self._check_composite_input(inInfo, messages):
            return self._report(messages)
        return 1

    def RequestData(self, request, inInfo, outInfo):
        grid = vtkUnstructuredGrid.GetData(inInfo[0])
        output = vtkPolyData.GetData(outInfo)
        output.Initialize()  # empty, should this execution fail
        self._integrals, self._distance_bound, self._unresolved_subcells = [], 0.0, 0
        s = self._settings
        messages = _core.Messages()
        if not _core.check_mesh_not_empty(grid.GetNumberOfPoints() if grid else 0,
                                          grid.GetNumberOfCells() if grid else 0, messages):
            return self._report(messages)

        # The field and the settings, checked by the core.
        scalars, component = self._point_array(0, inInfo, s["ArrayComponent"], False,
                                               "ArrayComponent", messages)
        settings = _core.ExactSurfaceSettings()
        settings.iso_values = list(self.GetValues())
        settings.relative_tolerance = s["Tolerance"]
        settings.tolerance = s["AbsoluteTolerance"]
        settings.integrals = s["ComputeIntegrals"]
        if scalars is None or not _core.check_exact_surface_settings(settings, messages):
            return self._report(messages)

        # Preprocess once per mesh and field (the core's certified transverse test).
        default = _core.TransverseTest()
        try:
            prepared = self._prepare(grid, scalars, component,
                                     (default.mode.value, default.widening),
                                     s["NumberOfThreads"], messages)
        except (MemoryError, RuntimeError) as error:
            self._prepared, self._prepared_stamp = None, None
            return self._fail(error, "prepare the mesh")
        if prepared is None or not messages.ok:
            return self._report(messages)
        self._report(messages)  # the warnings

        # Every numeric point array, interpolated at the vertices and integrated.
        point_data = grid.GetPointData()
        names, arrays = [], []
        for a in range(point_data.GetNumberOfArrays()):
            array = point_data.GetArray(a)  # (None for a string array)
            if array is not None:
                names.append(array.GetName() or f"array {a}")
                arrays.append((names[-1], _as_numpy(array)))
        try:
            surface = _core.extract_exact_surface(prepared, settings, arrays, messages,
                                                  threads=s["NumberOfThreads"])
        except (MemoryError, RuntimeError) as error:
            return self._fail(error, "extract the exact surface")
        if surface is None:
            return self._report(messages)

        points = vtkPoints()
        points.SetData(_double_array("Points", surface.points, 3))
        output.SetPoints(points)
        triangles = vtkCellArray()
        count = len(surface.triangles)
        triangles.SetData(_id_array("offsets", np.arange(0, 3 * count + 1, 3)),
                          _id_array("connectivity", surface.triangles))
        output.SetPolys(triangles)
        out_points = output.GetPointData()
        for name, values in zip(names, surface.arrays):
            out_points.AddArray(_double_array(name, values, values.shape[1]))
        out_points.SetNormals(_double_array("Normals", surface.normals, 3))
        out_cells = output.GetCellData()
        out_cells.AddArray(_id_array("vtkOriginalCellIds", surface.cell_ids))
        iso_values = np.array(settings.iso_values, np.float64)
        out_cells.AddArray(_double_array("IsoValue", iso_values[surface.iso_indices]))

        field = output.GetFieldData()
        field.AddArray(_double_array("IsoValues", iso_values))
        # (the core fills the triangle counts and flat areas whether asked or not)
        integrals = surface.integrals if settings.integrals else []
        if integrals and len(integrals) == len(iso_values):
            for name, member in (("Area", "area"), ("AreaError", "area_error"),
                                 ("Volume", "volume"), ("VolumeError", "volume_error"),
                                 ("FlatArea", "flat_area")):
                field.AddArray(_double_array(name, [getattr(x, member) for x in integrals]))
            first = 0
            for name, values in zip(names, surface.arrays):
                k = values.shape[1]
                for suffix, member in ((" Integral", "array_integrals"),
                                       (" IntegralError", "array_errors")):
                    field.AddArray(_double_array(
                        name + suffix, [getattr(x, member)[first:first + k] for x in integrals], k))
                first += k
        field.AddArray(_double_array("DistanceBound", [surface.tolerance]))
        field.AddArray(_double_array("LargestCertifiedBound", [surface.largest_bound]))
        for name, value in (("Subcells", surface.subcells),
                            ("UnresolvedSubcells", surface.unresolved_subcells),
                            ("SizeCertifiedSubcells", surface.size_certified_subcells),
                            ("BoundaryEdges", surface.boundary_edges),
                            ("NonManifoldEdges", surface.non_manifold_edges)):
            field.AddArray(_id_array(name, [value]))
        self._integrals = list(integrals)
        self._distance_bound = surface.tolerance
        self._unresolved_subcells = surface.unresolved_subcells
        self._report(messages)  # the warnings (uncertified tetrahedra)
        return 1
