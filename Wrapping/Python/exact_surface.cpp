// tetdsr._core's exact surface as data (Filters/Core/tetdsr/surface/ExactSurface.h): its settings,
// extract_exact_surface on a PreparedMesh (module.h) without the GIL, and the surface it makes, its
// arrays moved into numpy arrays.
#include "module.h"

#include "tetdsr/surface/ExactSurface.h"

#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <utility>

using namespace nb::literals;

namespace tetdsr_python
{
namespace
{

/// What extract_exact_surface made: the core's ExactSurfaceMesh, its arrays moved into numpy
/// arrays (no copy).
struct PyExactSurface
{
  nb::object Points;     // (n, 3) float64
  nb::object Normals;    // (n, 3) float64
  nb::object Triangles;  // (m, 3) int64
  nb::object CellIds;    // (m,) int64
  nb::object IsoIndices; // (m,) int32
  std::vector<nb::object> Arrays; // per point array given: (n, k) float64
  std::vector<tetdsr::SurfaceIntegrals> Integrals;
  double Tolerance = 0.0;
  double LargestBound = 0.0;
  tetdsr::NodeId Subcells = 0;
  tetdsr::NodeId UnresolvedSubcells = 0;
  tetdsr::NodeId SizeCertifiedSubcells = 0;
  tetdsr::NodeId BoundaryEdges = 0;
  tetdsr::NodeId NonManifoldEdges = 0;
};

/// `values` moved into a new numpy array of shape (rows, columns), or (rows,) when columns is 0,
/// which owns them.
template <typename T>
nb::object NumpyOf(std::vector<T>&& values, std::size_t rows, std::size_t columns)
{
  if (values.size() != rows * std::max<std::size_t>(columns, 1))
  {
    throw std::logic_error("the core's surface arrays disagree with its vertex and triangle counts");
  }
  auto* owned = new std::vector<T>(std::move(values));
  owned->reserve(1); // (a non-null pointer for an empty array)
  nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  const std::size_t shape[2] = { rows, columns };
  return nb::cast(nb::ndarray<nb::numpy, T>(owned->data(), columns > 0 ? 2 : 1, shape, owner));
}

/// extract_exact_surface: the core's exact surface of the prepared mesh's field, with the point
/// arrays given (name, (n,) or (n, k) array of any number type) interpolated and integrated.
/// None, with the core's errors, when nothing can be made.
std::optional<PyExactSurface> ExtractExactSurface(const PyPreparedMesh& mesh,
  const tetdsr::ExactSurfaceSettings& settings,
  const std::vector<std::pair<std::string, AnyArray>>& pointArrays, tetdsr::Messages& messages,
  int threads)
{
  tetdsr::Messages refused;
  if (!tetdsr::checkExactSurfaceSettings(settings, refused))
  {
    ThrowFirstError(refused);
  }
  std::vector<tetdsr::ArrayView> views;
  for (const auto& [name, array] : pointArrays)
  {
    views.push_back(ViewOf(array, name, "point array"));
  }
  tetdsr::ExactSurfaceMesh surface;
  {
    nb::gil_scoped_release release;
    SharedLock sceneLock(mesh.SceneLock);
    if (!tetdsr::extractExactSurface(
          mesh.SceneOrThrow(), settings, views, surface, messages, CellsFor(threads, 1)))
    {
      return std::nullopt;
    }
  }
  const std::size_t vertices = surface.points.size() / 3;
  const std::size_t triangles = surface.triangles.size() / 3;
  PyExactSurface made;
  made.Points = NumpyOf(std::move(surface.points), vertices, 3);
  made.Normals = NumpyOf(std::move(surface.normals), vertices, 3);
  made.Triangles = NumpyOf(std::move(surface.triangles), triangles, 3);
  made.CellIds = NumpyOf(std::move(surface.cellIds), triangles, 0);
  made.IsoIndices = NumpyOf(std::move(surface.isoIndices), triangles, 0);
  for (std::size_t a = 0; a < surface.arrays.size() && a < views.size(); ++a)
  {
    made.Arrays.push_back(NumpyOf(std::move(surface.arrays[a]), vertices,
      static_cast<std::size_t>(views[a].components)));
  }
  made.Integrals = std::move(surface.integrals);
  made.Tolerance = surface.tolerance;
  made.LargestBound = surface.largestBound;
  made.Subcells = surface.subcells;
  made.UnresolvedSubcells = surface.unresolvedSubcells;
  made.SizeCertifiedSubcells = surface.sizeCertifiedSubcells;
  made.BoundaryEdges = surface.boundaryEdges;
  made.NonManifoldEdges = surface.nonManifoldEdges;
  return made;
}

} // namespace

/// The exact surface as data.
void BindExactSurface(nb::module_& m)
{
  m.attr("DEFAULT_RELATIVE_TOLERANCE") = tetdsr::kDefaultRelativeTolerance;
  m.attr("MAX_SURFACE_LEVELS") = tetdsr::kMaxSurfaceLevels;
  nb::class_<tetdsr::ExactSurfaceSettings>(m, "ExactSurfaceSettings",
    "What the exact surface is asked for, with the core's defaults (iso_values is a list: assign "
    "a new one).")
    .def(nb::init<>())
    .def_rw("iso_values", &tetdsr::ExactSurfaceSettings::isoValues)
    .def_rw("relative_tolerance", &tetdsr::ExactSurfaceSettings::relativeTolerance,
      "the distance bound relative to the diagonal of the valid cells' box (when tolerance is 0)")
    .def_rw("tolerance", &tetdsr::ExactSurfaceSettings::tolerance,
      "the distance bound in scene units; 0: relative_tolerance times the diagonal")
    .def_rw("integrals", &tetdsr::ExactSurfaceSettings::integrals,
      "compute the area, enclosed volume and point-array integrals");
  m.def("check_exact_surface_settings", &tetdsr::checkExactSurfaceSettings, "settings"_a,
    "messages"_a, "False, with an error naming the setting, for settings the core refuses.");
  nb::class_<tetdsr::SurfaceIntegrals>(m, "SurfaceIntegrals",
    "The integrals of one iso-value's surface (the *_error members estimate |computed - exact|).")
    .def_ro("iso_value", &tetdsr::SurfaceIntegrals::isoValue)
    .def_ro("area", &tetdsr::SurfaceIntegrals::area, "of the curved surface")
    .def_ro("area_error", &tetdsr::SurfaceIntegrals::areaError)
    .def_ro("volume", &tetdsr::SurfaceIntegrals::volume,
      "of the region of the valid cells where the field >= the iso-value")
    .def_ro("volume_error", &tetdsr::SurfaceIntegrals::volumeError)
    .def_ro("array_integrals", &tetdsr::SurfaceIntegrals::arrayIntegrals,
      "per point array given, per component, over the curved surface (arrays one after another)")
    .def_ro("array_errors", &tetdsr::SurfaceIntegrals::arrayErrors)
    .def_ro("flat_area", &tetdsr::SurfaceIntegrals::flatArea, "the triangles' area")
    .def_ro("triangles", &tetdsr::SurfaceIntegrals::triangles);
  nb::class_<PyExactSurface>(m, "ExactSurface",
    "The exact surface of extract_exact_surface: certified vertices on the surface, triangles "
    "(normals toward higher values) within `largest_bound` of it, and the integrals.")
    .def_ro("points", &PyExactSurface::Points, "(n, 3) float64")
    .def_ro("normals", &PyExactSurface::Normals, "(n, 3) float64: the field's unit gradient")
    .def_ro("triangles", &PyExactSurface::Triangles, "(m, 3) int64 vertex ids")
    .def_ro("cell_ids", &PyExactSurface::CellIds, "(m,) int64: the input cell of each triangle")
    .def_ro("iso_indices", &PyExactSurface::IsoIndices,
      "(m,) int32: each triangle's iso-value, its index in the settings")
    .def_ro("arrays", &PyExactSurface::Arrays,
      "per point array given: its values at the vertices, (n, k) float64")
    .def_ro("integrals", &PyExactSurface::Integrals,
      "per iso-value, the settings' order: SurfaceIntegrals (without `integrals`, only their "
      "iso_value, triangles and flat_area)")
    .def_ro("tolerance", &PyExactSurface::Tolerance, "the absolute distance bound asked")
    .def_ro("largest_bound", &PyExactSurface::LargestBound,
      "the largest certified distance bound of any piece drawn")
    .def_ro("subcells", &PyExactSurface::Subcells, "tetrahedra examined, all levels")
    .def_ro("unresolved_subcells", &PyExactSurface::UnresolvedSubcells,
      "tetrahedra left without a certificate after MAX_SURFACE_LEVELS bisections")
    .def_ro("size_certified_subcells", &PyExactSurface::SizeCertifiedSubcells,
      "tetrahedra certified by size alone: the surface within the bound of their triangles, its "
      "topology there (below the bound's scale) not certified")
    .def_ro("boundary_edges", &PyExactSurface::BoundaryEdges,
      "edges in one triangle (where the surface meets the mesh's boundary)")
    .def_ro("non_manifold_edges", &PyExactSurface::NonManifoldEdges,
      "edges in more than two triangles (none on a certified surface)");
  m.def("extract_exact_surface", &ExtractExactSurface, "mesh"_a, "settings"_a,
    "point_arrays"_a, "messages"_a, "threads"_a = 0,
    "The exact surface of a PreparedMesh's field (every valid cell) for `settings`, without the "
    "GIL on `threads` threads (0: all cores). point_arrays: (name, array) pairs, each (n,) or "
    "(n, k) of any number type with a tuple per point, interpolated at the vertices and "
    "integrated. An ExactSurface, or None with the core's errors; warnings count uncertified "
    "tetrahedra. Settings the core refuses raise ValueError (check_exact_surface_settings first).");
}

} // namespace tetdsr_python
