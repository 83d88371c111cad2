// tetdsr._core: the VTK-free core (Filters/Core) for Python. This file binds the core's settings
// structs once as classes, its settings table and checks as functions writing the core's
// Messages, its PreparedMesh fed with copies of numpy arrays of the dtypes VTK hands over (shared
// by Python threads under a lock), and a Renderer that checks every size against the arrays,
// keeps the surface it casts into and the arrays it writes alive, and casts on std::threads
// without the GIL; exact_surface.cpp binds the exact surface as data, and module.h holds what the
// two share. The Python filters (tetdsr/filter.py, contour.py) only get arrays out of VTK objects
// and pass the messages on.
#include "module.h"

#include "tetdsr/common/Camera.h"
#include "tetdsr/surface/ExactSurface.h"
#include "tetdsr/input/MeshInput.h"
#include "tetdsr/common/Messages.h"
#include "tetdsr/render/Renderer.h"
#include "tetdsr/index/Scene.h"
#include "tetdsr/input/Settings.h"
#include "tetdsr/index/SurfaceIndex.h"

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/function.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <functional>
#include <limits>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

using namespace tetdsr_python;
using namespace nb::literals;

// glm::dvec3 <-> any sequence of 3 numbers (tuple, list, numpy array); given back as a tuple.
namespace nanobind
{
namespace detail
{
template <>
struct type_caster<glm::dvec3>
{
  NB_TYPE_CASTER(glm::dvec3, const_name("tuple[float, float, float]"))

  bool from_python(handle src, uint8_t, cleanup_list*) noexcept
  {
    if (!PySequence_Check(src.ptr()) || PySequence_Size(src.ptr()) != 3)
    {
      PyErr_Clear();
      return false;
    }
    for (Py_ssize_t k = 0; k < 3; ++k)
    {
      PyObject* item = PySequence_GetItem(src.ptr(), k);
      const double number = item ? PyFloat_AsDouble(item) : -1.0;
      Py_XDECREF(item);
      if (number == -1.0 && PyErr_Occurred())
      {
        PyErr_Clear();
        return false;
      }
      value[static_cast<int>(k)] = number;
    }
    return true;
  }

  static handle from_cpp(const glm::dvec3& v, rv_policy, cleanup_list*) noexcept
  {
    PyObject* tuple = PyTuple_New(3);
    for (Py_ssize_t k = 0; k < 3; ++k)
    {
      PyTuple_SET_ITEM(tuple, k, PyFloat_FromDouble(v[static_cast<int>(k)]));
    }
    return tuple;
  }
};
} // namespace detail
} // namespace nanobind

namespace
{
static_assert(sizeof(std::int64_t) == sizeof(tetdsr::NodeId), "ids are 64-bit in the core");

int ThreadCount(int requested)
{
  const unsigned hardware = std::thread::hardware_concurrency();
  return requested > 0 ? requested : static_cast<int>(std::max(1u, hardware));
}

/// Runs body(begin, end) over [0, count) on `threads` std::threads (0: all cores), handing out
/// chunks of `grain` indices from a shared counter (tiles differ in cost). The first exception
/// thrown in any thread is rethrown here once all have stopped; a thread that cannot start
/// (std::system_error: a pids or memory limit) stops the others and becomes a RuntimeError
/// naming it, never an abort from a joinable std::thread destroyed.
void ThreadedFor(int threads, tetdsr::NodeId count, tetdsr::NodeId grain,
  const std::function<void(tetdsr::NodeId, tetdsr::NodeId)>& body)
{
  if (count <= 0)
  {
    return;
  }
  grain = std::max<tetdsr::NodeId>(1, grain);
  const int workers = static_cast<int>(
    std::min<tetdsr::NodeId>(ThreadCount(threads), (count + grain - 1) / grain));
  std::atomic<tetdsr::NodeId> next{ 0 };
  std::exception_ptr failure;
  std::atomic<bool> failed{ false };
  auto work = [&]() {
    try
    {
      for (tetdsr::NodeId begin = next.fetch_add(grain); begin < count && !failed;
           begin = next.fetch_add(grain))
      {
        body(begin, std::min(count, begin + grain));
      }
    }
    catch (...)
    {
      if (!failed.exchange(true))
      {
        failure = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(workers)); // (a std::bad_alloc here: before any start)
  std::string notStarted;
  for (int w = 1; w < workers && notStarted.empty(); ++w)
  {
    try
    {
      pool.emplace_back(work);
    }
    catch (const std::system_error& error)
    {
      failed = true; // the threads started stop at their next chunk
      notStarted = "Could not start thread " + std::to_string(w + 1) + " of " +
        std::to_string(workers) + " (" + error.what() + "): ask for fewer threads.";
    }
  }
  if (notStarted.empty())
  {
    work();
  }
  for (std::thread& thread : pool)
  {
    thread.join();
  }
  if (!notStarted.empty())
  {
    throw std::runtime_error(notStarted);
  }
  if (failure)
  {
    std::rethrow_exception(failure);
  }
}

} // namespace

namespace tetdsr_python
{
tetdsr::ParallelFor CellsFor(int threads, tetdsr::NodeId minimumChunk)
{
  return [threads, minimumChunk](tetdsr::NodeId count,
           const std::function<void(tetdsr::NodeId, tetdsr::NodeId)>& body) {
    ThreadedFor(threads, count, std::max<tetdsr::NodeId>(minimumChunk, count / 256), body);
  };
}

void ThrowFirstError(const tetdsr::Messages& messages)
{
  throw nb::value_error(messages.errors.front().c_str());
}

tetdsr::ArrayView ViewOf(const AnyArray& array, const std::string& name, const char* what)
{
  tetdsr::ArrayView view;
  const nb::dlpack::dtype type = array.dtype();
  static const std::pair<nb::dlpack::dtype, tetdsr::NumberType> kTypes[] = {
    { nb::dtype<float>(), tetdsr::NumberType::Float32 },
    { nb::dtype<double>(), tetdsr::NumberType::Float64 },
    { nb::dtype<std::int8_t>(), tetdsr::NumberType::Int8 },
    { nb::dtype<std::uint8_t>(), tetdsr::NumberType::UInt8 },
    { nb::dtype<std::int16_t>(), tetdsr::NumberType::Int16 },
    { nb::dtype<std::uint16_t>(), tetdsr::NumberType::UInt16 },
    { nb::dtype<std::int32_t>(), tetdsr::NumberType::Int32 },
    { nb::dtype<std::uint32_t>(), tetdsr::NumberType::UInt32 },
    { nb::dtype<std::int64_t>(), tetdsr::NumberType::Int64 },
    { nb::dtype<std::uint64_t>(), tetdsr::NumberType::UInt64 },
  };
  const auto* found = std::find_if(std::begin(kTypes), std::end(kTypes),
    [&](const auto& entry) { return entry.first == type; });
  if (found == std::end(kTypes) || array.ndim() < 1 || array.ndim() > 2)
  {
    throw nb::type_error((std::string(what) +
      " must be a 1- or 2-d array of a float or integer type (8 to 64 bits)")
                           .c_str());
  }
  view.type = found->second;
  view.data = array.data();
  view.tuples = static_cast<tetdsr::NodeId>(array.shape(0));
  view.components = array.ndim() == 2 ? static_cast<int>(array.shape(1)) : 1;
  view.name = name;
  return view;
}
} // namespace tetdsr_python

namespace
{

/// Casts running in this thread (whose abort / progress callbacks run Python): a prepare from
/// one of them would wait forever for the cast's own lock.
thread_local int tCasts = 0;

/// The view of a copy of `array`'s bytes, kept in `store`.
tetdsr::ArrayView CopyOf(const AnyArray& array, const char* what, std::vector<unsigned char>& store)
{
  tetdsr::ArrayView view = ViewOf(array, "", what);
  store.resize(array.nbytes());
  if (!store.empty())
  {
    std::memcpy(store.data(), array.data(), store.size());
  }
  view.data = store.data();
  return view;
}

bool Prepare(PyPreparedMesh& self, AnyArray points, AnyArray cellTypes, AnyArray offsets,
  AnyArray connectivity, AnyArray field, const std::string& fieldName, int component,
  const tetdsr::TransverseTest& transverse, int threads, tetdsr::Messages& messages,
  std::optional<AnyArray> rationalWeights, std::optional<AnyArray> cellGhosts)
{
  if (tCasts > 0)
  {
    throw nb::value_error("prepare was called from a cast's abort or progress callback: prepare "
                          "once the cast has returned");
  }
  ExclusiveLock lock = LockWithoutGil<ExclusiveLock>(self.SceneLock);
  ++self.Generation; // every Renderer made before refuses to cast from now on
  self.Surface.reset();
  self.SurfaceValues.clear();
  std::vector<std::vector<unsigned char>> copies(7);
  tetdsr::MeshArrays arrays;
  arrays.points = CopyOf(points, "points", copies[0]);
  arrays.cellTypes = CopyOf(cellTypes, "cell_types", copies[1]);
  arrays.offsets = CopyOf(offsets, "offsets", copies[2]);
  arrays.connectivity = CopyOf(connectivity, "connectivity", copies[3]);
  arrays.field = CopyOf(field, "field", copies[4]);
  arrays.field.name = fieldName;
  arrays.fieldComponent = component;
  if (rationalWeights)
  {
    arrays.rationalWeights = CopyOf(*rationalWeights, "rational_weights", copies[5]);
    arrays.hasRationalWeights = true;
    arrays.rationalWeights.name = "RationalWeights";
  }
  if (cellGhosts)
  {
    arrays.cellGhosts = CopyOf(*cellGhosts, "cell_ghosts", copies[6]);
    arrays.hasCellGhosts = true;
    arrays.cellGhosts.name = "vtkGhostType";
  }
  self.Copied = std::move(copies);
  nb::gil_scoped_release release;
  return self.Core.prepare(arrays, transverse, CellsFor(threads), messages);
}

/// A colour array for RenderSettings: (n,) or (n, k) float64 values (PreparedMesh.point_values),
/// kept alive with the settings.
struct PyColorBy
{
  Array<const double> Values;
  tetdsr::ColorByArray Core;
};

PyColorBy MakeColorBy(Array<const double> values, int component, bool directColors)
{
  if (values.ndim() < 1 || values.ndim() > 2)
  {
    throw nb::value_error("values must be an (n,) or (n, k) array of float64");
  }
  PyColorBy colorBy{ values, {} };
  colorBy.Core.values = values.data();
  colorBy.Core.components = values.ndim() == 2 ? static_cast<int>(values.shape(1)) : 1;
  colorBy.Core.component = component;
  colorBy.Core.directColors = directColors;
  if (component < -1 || component >= colorBy.Core.components)
  {
    throw nb::value_error("component must be -1 (magnitude) or a component of the values");
  }
  if (directColors && colorBy.Core.components < 3)
  {
    throw nb::value_error("direct colours need 3 or 4 components (red, green, blue)");
  }
  return colorBy;
}

/// The core's RenderSettings, and the colour array its colorBy views.
struct PySettings
{
  tetdsr::RenderSettings Core;
  std::optional<PyColorBy> ColorBy;
};

/// One image being rendered: the renderer, the settings it refers to, and the arrays it reads
/// and writes (kept alive as long as it lives).
struct PyRenderer
{
  nb::object MeshOwner; // the PyPreparedMesh
  std::uint64_t Generation = 0;
  std::shared_ptr<const tetdsr::SurfaceIndex> Surface; // what Renderer casts into
  std::unique_ptr<std::mutex> Casting = std::make_unique<std::mutex>(); // one cast at a time
  PySettings Settings;
  Array<std::uint8_t> Colors;
  Array<double> Depth;
  Array<double> Normals;
  Array<std::int64_t> CellIds;
  std::optional<Array<double>> ColorValues;
  std::unique_ptr<tetdsr::Renderer> Renderer;
  tetdsr::Camera Camera; // with the image's size: the rays of pick's display positions
  int Width = 0, Height = 0;
};

/// What Renderer.pick found: the core's Pick, and the point arrays asked for interpolated there.
struct PyPick
{
  tetdsr::Pick Core;
  std::vector<std::vector<double>> PointValues;
};

/// Checks that `array` has `shape` (height, width[, components]).
template <typename T>
void CheckShape(const Array<T>& array, std::size_t height, std::size_t width, std::size_t components,
  const char* name)
{
  const bool ok = array.ndim() == (components > 1 ? 3u : 2u) && array.shape(0) == height &&
    array.shape(1) == width && (components == 1 || array.shape(2) == components);
  if (!ok)
  {
    std::string expected = "(" + std::to_string(height) + ", " + std::to_string(width);
    expected += components > 1 ? ", " + std::to_string(components) + ")" : std::string(")");
    throw nb::value_error((std::string(name) + " must have the shape " + expected +
      " of the depth image, C-contiguous")
                            .c_str());
  }
}

/// The surface index of `mesh` for `isoValues`: the last one if they are the same, else built
/// (sharing the last one's hierarchy where it selects the same cells). Under mesh.CacheLock.
std::shared_ptr<const tetdsr::SurfaceIndex> SurfaceFor(
  PyPreparedMesh& mesh, const std::vector<double>& isoValues, int threads)
{
  if (!mesh.Surface || mesh.SurfaceValues != isoValues)
  {
    mesh.Surface = std::make_shared<const tetdsr::SurfaceIndex>(*mesh.Core.scene(),
      tetdsr::IsoValues(isoValues), CellsFor(threads), mesh.Surface.get());
    mesh.SurfaceValues = isoValues;
  }
  return mesh.Surface;
}

/// Renderer.__init__: checks every argument, then constructs the renderer in place at `self`.
void InitRenderer(PyRenderer* self, nb::object meshObject, const std::vector<double>& isoValues,
  const tetdsr::Camera& camera, const PySettings& settings, Array<std::uint8_t> colors,
  Array<double> depth, Array<double> normals, Array<std::int64_t> cellIds,
  std::optional<Array<double>> colorValues, int threads)
{
  PyPreparedMesh& mesh = nb::cast<PyPreparedMesh&>(meshObject);
  tetdsr::Messages messages;
  if (!tetdsr::checkIsoValues(isoValues, messages) || !tetdsr::checkCamera(camera, messages) ||
    !tetdsr::checkClipPlanes(settings.Core.clipPlanes, messages))
  {
    ThrowFirstError(messages);
  }
  // The image's size is the depth array's shape: (height, width).
  if (depth.ndim() != 2 || depth.shape(0) == 0 || depth.shape(1) == 0 ||
    static_cast<double>(depth.shape(0)) * static_cast<double>(depth.shape(1)) >= 2147483647.0)
  {
    throw nb::value_error("depth must be a (height, width) array with fewer than 2^31 pixels");
  }
  const std::size_t height = depth.shape(0), width = depth.shape(1);
  CheckShape(colors, height, width, 4, "colors");
  CheckShape(normals, height, width, 3, "normals");
  CheckShape(cellIds, height, width, 1, "cell_ids");
  if (colorValues)
  {
    CheckShape(*colorValues, height, width, 1, "color_values");
  }
  const tetdsr::RenderSettings& core = settings.Core;
  const bool mapped = (settings.ColorBy && !settings.ColorBy->Core.directColors) ||
    (core.cap != tetdsr::CapRegion::None && !core.clipPlanes.empty());

  // The arrays are referenced (with the GIL) before the scene is looked at (without it).
  PyRenderer made{ meshObject, 0, nullptr, std::make_unique<std::mutex>(), settings, colors, depth,
    normals, cellIds, colorValues, nullptr, camera, static_cast<int>(width), static_cast<int>(height) };
  made.Settings.Core.colorBy = settings.ColorBy ? settings.ColorBy->Core : tetdsr::ColorByArray();
  tetdsr::ImageView view;
  view.width = static_cast<int>(width);
  view.height = static_cast<int>(height);
  view.colors = colors.data();
  view.depth = depth.data();
  view.normals = normals.data();
  view.cellIds = reinterpret_cast<tetdsr::NodeId*>(cellIds.data());
  view.colorValues = colorValues ? colorValues->data() : nullptr;
  const std::size_t colorTuples = settings.ColorBy ? settings.ColorBy->Values.shape(0) : 0;
  {
    nb::gil_scoped_release release;
    SharedLock sceneLock(mesh.SceneLock);
    tetdsr::Scene* scene = mesh.Core.scene();
    if (!scene)
    {
      throw nb::value_error("the PreparedMesh has no scene: its last prepare failed");
    }
    tetdsr::Messages farCamera;
    if (!tetdsr::checkCamera(camera, *scene, farCamera)) // (too far from this scene's cells)
    {
      ThrowFirstError(farCamera);
    }
    const auto points = static_cast<std::size_t>(scene->mesh().numberOfPoints);
    if (settings.ColorBy && colorTuples < points)
    {
      throw nb::value_error(("the colour array has " + std::to_string(colorTuples) +
        " tuples for " + std::to_string(points) + " points")
                              .c_str());
    }
    if (mapped && core.colorTable.colors.size() < 2)
    {
      throw nb::value_error("colour mapping needs a color_table with at least 2 colours");
    }
    std::lock_guard<std::mutex> cacheLock(mesh.CacheLock);
    if (core.normals.mode == tetdsr::NormalMode::NodalInterpolation && !scene->hasNodalGradients())
    {
      scene->computeNodalGradients(); // once per scene: kept with it
    }
    made.Surface = SurfaceFor(mesh, isoValues, threads);
    made.Generation = mesh.Generation;
    made.Renderer.reset(new tetdsr::Renderer(*made.Surface, camera, made.Settings.Core, view));
  }
  new (self) PyRenderer(std::move(made));
}

/// Renderer.pick: the core's pick along the ray through (x, y) of the image, and the point
/// arrays interpolated at the hit with its cell's shape functions.
std::optional<PyPick> PickAt(const PyRenderer& r, double x, double y,
  const std::vector<Array<const double>>& pointArrays, double tLimit)
{
  if (!std::isfinite(x) || !std::isfinite(y) || std::isnan(tLimit))
  {
    throw nb::value_error("pick: x and y must be finite numbers and t_limit a number");
  }
  for (const Array<const double>& values : pointArrays)
  {
    if (values.ndim() < 1 || values.ndim() > 2 || (values.ndim() == 2 && values.shape(1) == 0))
    {
      throw nb::value_error("pick: point_arrays must be (n,) or (n, k) float64 arrays");
    }
  }
  PyPreparedMesh& mesh = nb::cast<PyPreparedMesh&>(r.MeshOwner);
  nb::gil_scoped_release release;
  SharedLock sceneLock(mesh.SceneLock);
  if (mesh.Generation != r.Generation)
  {
    throw nb::value_error("the PreparedMesh was prepared again since this Renderer was made: make a new one");
  }
  const tetdsr::Scene& scene = mesh.SceneOrThrow();
  const auto points = static_cast<std::size_t>(scene.mesh().numberOfPoints);
  for (const Array<const double>& values : pointArrays)
  {
    if (values.shape(0) < points)
    {
      throw nb::value_error(("pick: a point array has " + std::to_string(values.shape(0)) +
        " tuples for " + std::to_string(points) + " points")
                              .c_str());
    }
  }
  const tetdsr::RayGenerator rays(r.Camera, r.Width, r.Height);
  PyPick found;
  if (!r.Renderer->pick(rays.displayRay(x, y), found.Core, tLimit))
  {
    return std::nullopt;
  }
  for (const Array<const double>& values : pointArrays)
  {
    const int components = values.ndim() == 2 ? static_cast<int>(values.shape(1)) : 1;
    std::vector<double>& tuple = found.PointValues.emplace_back(static_cast<std::size_t>(components));
    for (int c = 0; c < components; ++c)
    {
      tuple[static_cast<std::size_t>(c)] =
        scene.interpolate(found.Core.cellId, found.Core.point, values.data(), components, c);
    }
  }
  return found;
}

/// Renderer.window_depth: the depth image as the depth buffer of a view with the composite
/// projection `matrix` (4 x 4, row-major, from the rays' coordinates to normalized device
/// coordinates) would hold it, written into `out` (height, width) float32.
void WindowDepthOf(PyRenderer& r, const Array<const double>& matrix, Array<float> out)
{
  if (matrix.ndim() != 2 || matrix.shape(0) != 4 || matrix.shape(1) != 4)
  {
    throw nb::value_error("window_depth: matrix must be a 4 x 4 float64 array");
  }
  CheckShape(out, static_cast<std::size_t>(r.Height), static_cast<std::size_t>(r.Width), 1, "out");
  glm::dmat4 toNdc;
  for (int row = 0; row < 4; ++row)
  {
    for (int column = 0; column < 4; ++column)
    {
      const double value = matrix.data()[4 * row + column];
      if (!std::isfinite(value))
      {
        throw nb::value_error("window_depth: matrix has a non-finite entry");
      }
      toNdc[column][row] = value; // (glm: columns first)
    }
  }
  std::unique_lock<std::mutex> casting(*r.Casting, std::try_to_lock); // (a cast writes depth)
  if (!casting.owns_lock())
  {
    throw nb::value_error("window_depth: this Renderer is casting (in another thread, or this is "
                          "its own callback): ask when the cast is done");
  }
  nb::gil_scoped_release release;
  const tetdsr::RayGenerator rays(r.Camera, r.Width, r.Height);
  tetdsr::windowDepths(rays, toNdc, r.Depth.data(), out.data(), r.Width, 0, r.Height);
}

nb::dict SummaryOf(const tetdsr::PreprocessSummary& summary)
{
  nb::dict d;
  d["valid"] = summary.validCells;
  d["inverted"] = summary.invertedCells;
  d["curved"] = summary.curvedCells;
  d["tangled"] = summary.tangledCells;
  d["degenerate"] = summary.degenerateCells;
  d["out_of_scale"] = summary.outOfScaleCells;
  d["non_finite"] = summary.nonFiniteCells;
  d["invalid_id"] = summary.invalidIdCells;
  d["unsupported"] = summary.unsupportedCells;
  d["malformed"] = summary.malformedCells;
  d["order_too_high"] = summary.orderTooHighCells;
  d["rational"] = summary.rationalCells;
  d["higher_order"] = summary.higherOrderCells;
  d["ghost"] = summary.ghostCells;
  return d;
}

/// One of RenderSettings' members as a property: by reference, so that
/// settings.material.ambient = 0.3 changes the settings (lists are copies: assign a new one).
template <typename T>
void Member(nb::class_<PySettings>& settings, const char* name, T tetdsr::RenderSettings::*member)
{
  settings.def_prop_rw(
    name, [member](PySettings& s) -> T& { return s.Core.*member; },
    [member](PySettings& s, const T& value) { s.Core.*member = value; });
}

// The module, part by part.

/// The core's messages.
void BindMessages(nb::module_& m)
{
  nb::class_<tetdsr::Messages>(m, "Messages",
    "What the core tells a user: errors (nothing rendered) and warnings (something skipped).")
    .def(nb::init<>())
    .def_ro("errors", &tetdsr::Messages::errors)
    .def_ro("warnings", &tetdsr::Messages::warnings)
    .def_prop_ro("ok", &tetdsr::Messages::ok)
    .def("clear", [](tetdsr::Messages& messages) { messages = tetdsr::Messages(); });
}

/// The enumerations of the settings.
void BindEnumerations(nb::module_& m)
{
  nb::enum_<tetdsr::NormalMode>(m, "NormalMode")
    .value("EXACT_GRADIENT", tetdsr::NormalMode::ExactGradient)
    .value("CENTRAL_DIFFERENCES", tetdsr::NormalMode::CentralDifferences)
    .value("NODAL_INTERPOLATION", tetdsr::NormalMode::NodalInterpolation)
    .value("DEPTH_BUFFER", tetdsr::NormalMode::DepthBuffer);
  nb::enum_<tetdsr::CapRegion>(m, "CapRegion")
    .value("NONE", tetdsr::CapRegion::None)
    .value("BELOW_ISO_VALUE", tetdsr::CapRegion::BelowIsoValue)
    .value("ABOVE_ISO_VALUE", tetdsr::CapRegion::AboveIsoValue);
  nb::enum_<tetdsr::TransverseTest::Mode>(m, "TransverseMode")
    .value("BERNSTEIN_BOUND", tetdsr::TransverseTest::Mode::BernsteinBound)
    .value("WIDENED_NODAL_RANGE", tetdsr::TransverseTest::Mode::WidenedNodalRange);
  nb::enum_<tetdsr::ColorSpace>(m, "ColorSpace")
    .value("RGB", tetdsr::ColorSpace::RGB)
    .value("HSV", tetdsr::ColorSpace::HSV)
    .value("DIVERGING", tetdsr::ColorSpace::Diverging);
  nb::enum_<tetdsr::InputArray>(m, "InputArray")
    .value("FIELD", tetdsr::InputArray::Field)
    .value("COLOR", tetdsr::InputArray::Color);
}

/// The settings structs, with the core's defaults.
void BindSettings(nb::module_& m)
{
  nb::class_<tetdsr::Camera>(m, "Camera", "vtkCamera's frame and projection.")
    .def(nb::init<>())
    .def_rw("position", &tetdsr::Camera::position)
    .def_rw("focal_point", &tetdsr::Camera::focalPoint)
    .def_rw("view_up", &tetdsr::Camera::viewUp)
    .def_rw("view_angle", &tetdsr::Camera::viewAngleDegrees, "vertical, in degrees")
    .def_rw("parallel_projection", &tetdsr::Camera::parallelProjection)
    .def_rw("parallel_scale", &tetdsr::Camera::parallelScale);
  nb::class_<tetdsr::Material>(m, "Material")
    .def(nb::init<>())
    .def_rw("color", &tetdsr::Material::color)
    .def_rw("specular_color", &tetdsr::Material::specularColor)
    .def_rw("ambient", &tetdsr::Material::ambient)
    .def_rw("diffuse", &tetdsr::Material::diffuse)
    .def_rw("specular", &tetdsr::Material::specular)
    .def_rw("specular_power", &tetdsr::Material::specularPower);
  nb::class_<tetdsr::Light>(m, "Light")
    .def(nb::init<>())
    .def_rw("color", &tetdsr::Light::color)
    .def_rw("positional", &tetdsr::Light::positional)
    .def_rw("direction", &tetdsr::Light::direction)
    .def_rw("position", &tetdsr::Light::position);
  nb::class_<tetdsr::Lighting>(m, "Lighting", "lights is a list: assign a new one to change it.")
    .def(nb::init<>())
    .def_rw("lights", &tetdsr::Lighting::lights)
    .def_rw("headlight_only", &tetdsr::Lighting::headlightOnly)
    .def_rw("has_eye", &tetdsr::Lighting::hasEye)
    .def_rw("eye", &tetdsr::Lighting::eye);
  nb::class_<tetdsr::NormalSettings>(m, "NormalSettings")
    .def(nb::init<>())
    .def_rw("mode", &tetdsr::NormalSettings::mode)
    .def_rw("relative_step", &tetdsr::NormalSettings::relativeStep);
  nb::class_<tetdsr::TransverseTest>(m, "TransverseTest", "Which cells are searched for an iso-value.")
    .def(nb::init<>())
    .def_rw("mode", &tetdsr::TransverseTest::mode)
    .def_rw("widening", &tetdsr::TransverseTest::widening,
      "WIDENED_NODAL_RANGE: the nodal range's widening on each side, a fraction of it");
  nb::class_<tetdsr::ColorTable>(m, "ColorTable")
    .def(nb::init<>())
    .def_rw("lo", &tetdsr::ColorTable::lo)
    .def_rw("hi", &tetdsr::ColorTable::hi)
    .def_rw("colors", &tetdsr::ColorTable::colors)
    .def_rw("nan_color", &tetdsr::ColorTable::nanColor)
    .def("map", &tetdsr::ColorTable::map, "value"_a);
  nb::class_<tetdsr::ClipPlane>(m, "ClipPlane", "Keeps the side the normal points to.")
    .def(nb::init<>())
    .def(
      "__init__",
      [](tetdsr::ClipPlane* self, const glm::dvec3& origin, const glm::dvec3& normal) {
        new (self) tetdsr::ClipPlane{ origin, normal };
      },
      "origin"_a, "normal"_a)
    .def_rw("origin", &tetdsr::ClipPlane::origin)
    .def_rw("normal", &tetdsr::ClipPlane::normal);
  nb::class_<tetdsr::SurfaceStyle>(m, "SurfaceStyle")
    .def(nb::init<>())
    .def_rw("color", &tetdsr::SurfaceStyle::color)
    .def_rw("opacity", &tetdsr::SurfaceStyle::opacity);
  nb::class_<PyColorBy>(m, "ColorByArray",
    "A point array that colours the surfaces: (n,) or (n, k) float64 values, one tuple per point "
    "(PreparedMesh.point_values), its component (-1: the magnitude), or direct RGB colours.")
    .def(nb::new_(&MakeColorBy), "values"_a, "component"_a = 0, "direct_colors"_a = false)
    .def_prop_ro("values", [](const PyColorBy& c) { return c.Values; })
    .def_prop_ro("components", [](const PyColorBy& c) { return c.Core.components; })
    .def_prop_ro("component", [](const PyColorBy& c) { return c.Core.component; })
    .def_prop_ro("direct_colors", [](const PyColorBy& c) { return c.Core.directColors; });
  nb::class_<PySettings> settings(m, "RenderSettings",
    "Everything a Renderer shades with, with the core's defaults (no light, no colour array). "
    "Nested settings change in place (settings.material.ambient = 0.3); lists by assignment.");
  settings.def(nb::init<>());
  Member(settings, "material", &tetdsr::RenderSettings::material);
  Member(settings, "lighting", &tetdsr::RenderSettings::lighting);
  Member(settings, "normals", &tetdsr::RenderSettings::normals);
  Member(settings, "iso_styles", &tetdsr::RenderSettings::isoStyles);
  Member(settings, "color_table", &tetdsr::RenderSettings::colorTable);
  Member(settings, "clip_planes", &tetdsr::RenderSettings::clipPlanes);
  Member(settings, "cap", &tetdsr::RenderSettings::cap);
  settings.def_rw("color_by", &PySettings::ColorBy, nb::arg().none(), "a ColorByArray, or None");
}

/// Constants every face shares.
void BindConstants(nb::module_& m)
{
  m.attr("BYTES_PER_PIXEL") = tetdsr::kBytesPerPixel;
  m.attr("COLOR_TABLE_SIZE") = tetdsr::kColorTableSize;
  m.attr("PROGRESS_STEPS") = tetdsr::kProgressSteps;
  m.attr("MAX_CAMERA_DISTANCE") = tetdsr::kMaxCameraDistance;
  m.attr("MAX_CLIP_PLANES") = tetdsr::kMaxClipPlanes;
  m.attr("MAX_STYLE_INDEX") = tetdsr::IsoValueStyles::kMaxIndex;
  m.attr("TILE_SIZE") = tetdsr::Renderer::kTileSize;
  m.attr("MAX_CELLS") = tetdsr::Scene::kMaxCells;
}

/// The core's settings table (tetdsr::kSettings), from which the Python filters make their Set/Get
/// methods and the ParaView Python plugin its properties, and its check.
void BindSettingsTable(nb::module_& m)
{
  nb::enum_<tetdsr::SettingType>(m, "SettingType")
    .value("BOOL", tetdsr::SettingType::Bool)
    .value("INT", tetdsr::SettingType::Int)
    .value("DOUBLE", tetdsr::SettingType::Double);
  nb::enum_<tetdsr::SettingCheck>(m, "SettingCheck")
    .value("CLAMP", tetdsr::SettingCheck::Clamp)
    .value("FINITE", tetdsr::SettingCheck::Finite)
    .value("AT_EXECUTION", tetdsr::SettingCheck::AtExecution);
  nb::class_<tetdsr::Setting>(m, "Setting",
    "One row of the settings table: name, type, check, components, each component's range [lo, "
    "hi] (+-DBL_MAX, INT_MIN / INT_MAX: none), defaults, and which filters have it.")
    .def_prop_ro("name", [](const tetdsr::Setting& s) { return std::string(s.name); })
    .def_ro("type", &tetdsr::Setting::type)
    .def_ro("check", &tetdsr::Setting::check)
    .def_ro("components", &tetdsr::Setting::components)
    .def_ro("lo", &tetdsr::Setting::lo)
    .def_ro("hi", &tetdsr::Setting::hi)
    .def_prop_ro("defaults",
      [](const tetdsr::Setting& s) {
        return std::vector<double>(s.defaults, s.defaults + s.components);
      })
    .def_prop_ro("choices",
      [](const tetdsr::Setting& s) {
        std::vector<std::string> names;
        for (const char* at = s.choices; at && *at;)
        {
          const char* end = std::strchr(at, '|');
          names.emplace_back(at, end ? end : at + std::strlen(at));
          at = end ? end + 1 : nullptr;
        }
        return names;
      },
      "an enumeration's choices, lo to hi, as the panels name them; [] for a number")
    .def_prop_ro("ray_caster",
      [](const tetdsr::Setting& s) { return (s.filters & tetdsr::kRayCasterSetting) != 0; })
    .def_prop_ro(
      "contour", [](const tetdsr::Setting& s) { return (s.filters & tetdsr::kContourSetting) != 0; });
  nb::list rows;
  for (const tetdsr::Setting* row : tetdsr::kSettings)
  {
    rows.append(nb::cast(row, nb::rv_policy::reference));
  }
  m.attr("SETTINGS") = rows;
  m.def(
    "check_setting",
    [](const tetdsr::Setting& row, const std::vector<double>& given,
      tetdsr::Messages& messages) -> std::optional<std::vector<double>> {
      if (given.size() != static_cast<std::size_t>(row.components))
      {
        throw nb::value_error((std::string(row.name) + " takes " + std::to_string(row.components) +
          " numbers").c_str());
      }
      std::vector<double> used(given.size());
      if (!tetdsr::checkSetting(row, given.data(), used.data(), messages))
      {
        return std::nullopt;
      }
      return used;
    },
    "setting"_a, "given"_a, "messages"_a,
    "The values a setter stores (clamped as the row says, with a warning for an integer), or "
    "None after the row's error (the setting keeps its value).");

  // The older form of the clamped numbers (the table's clamped double rows).
  nb::class_<tetdsr::NumberSetting>(m, "NumberSetting", "A number clamped into [lo, hi]; NaN refused.")
    .def_prop_ro("name", [](const tetdsr::NumberSetting& s) { return std::string(s.name); })
    .def_ro("lo", &tetdsr::NumberSetting::lo)
    .def_ro("hi", &tetdsr::NumberSetting::hi);
  nb::dict numbers;
  for (const tetdsr::Setting* row : tetdsr::kSettings)
  {
    if (row->type == tetdsr::SettingType::Double && row->check == tetdsr::SettingCheck::Clamp)
    {
      numbers[row->name] = nb::cast(tetdsr::NumberSetting(*row));
    }
  }
  m.attr("NUMBER_SETTINGS") = numbers;
  m.def(
    "set_clamped",
    [](const tetdsr::NumberSetting& setting, double value, double member, tetdsr::Messages& messages) {
      const bool changed = tetdsr::setClamped(setting, value, member, messages);
      return std::make_pair(changed, member);
    },
    "setting"_a, "value"_a, "member"_a, "messages"_a,
    "(changed, new value): `value` clamped into the setting's range; NaN keeps `member`, with an error.");
}

/// The checks, writing the core's messages.
void BindChecks(nb::module_& m)
{
  m.def("check_mesh_not_empty", &tetdsr::checkMeshNotEmpty, "number_of_points"_a,
    "number_of_cells"_a, "messages"_a);
  m.def("check_iso_values", &tetdsr::checkIsoValues, "values"_a, "messages"_a);
  m.def("check_clip_planes", &tetdsr::checkClipPlanes, "planes"_a, "messages"_a);
  m.def("check_image_size", &tetdsr::checkImageSize, "width"_a, "height"_a, "messages"_a,
    "False, with an error, for an ImageSize that cannot be allocated (BYTES_PER_PIXEL each).");
  m.def("report_unallocated_image", &tetdsr::reportUnallocatedImage, "width"_a, "height"_a,
    "messages"_a);
  m.def(
    "check_camera",
    [](const tetdsr::Camera& camera, const PyPreparedMesh* mesh, tetdsr::Messages& messages) {
      return mesh && mesh->Core.scene() ? tetdsr::checkCamera(camera, *mesh->Core.scene(), messages)
                                        : tetdsr::checkCamera(camera, messages);
    },
    "camera"_a, "mesh"_a.none(), "messages"_a,
    "False, with an error, for a camera that defines no rays, or (with a prepared mesh) one too "
    "far from it.");
  m.def(
    "report_missing_array",
    [](tetdsr::InputArray which, const std::optional<std::string>& name, tetdsr::Messages& messages) {
      tetdsr::reportMissingArray(which, name ? name->c_str() : nullptr, messages);
    },
    "which"_a, "name"_a.none(), "messages"_a,
    "The error for an input array not found: by name, or (None) as the active scalars / none chosen.");
  m.def(
    "choose_point_array_component",
    [](const std::string& name, bool isPointArray, int components, int requested,
      bool allowMagnitude, const std::string& setting,
      tetdsr::Messages& messages) -> std::optional<int> {
      int component = 0;
      if (!tetdsr::choosePointArrayComponent(name, isPointArray, components, requested,
            allowMagnitude, setting.c_str(), component, messages))
      {
        return std::nullopt;
      }
      return component;
    },
    "name"_a, "is_point_array"_a, "components"_a, "requested_component"_a, "allow_magnitude"_a,
    "component_setting"_a, "messages"_a,
    "The component of a field or colour array to use (-1: the magnitude), or None after an error.");
  m.def(
    "finite_range",
    [](Array<const double> values, int component) {
      const int components = values.ndim() == 2 ? static_cast<int>(values.shape(1)) : 1;
      if (values.ndim() < 1 || values.ndim() > 2 || component < -1 || component >= components)
      {
        throw nb::value_error("values must be (n,) or (n, k) and component in [-1, k)");
      }
      tetdsr::FiniteRange finite;
      finite.add(values.data(), static_cast<tetdsr::NodeId>(values.shape(0)), components, component);
      std::array<double, 2> range;
      finite.get(range.data());
      return range;
    },
    "values"_a, "component"_a,
    "(lo, hi) of one component (-1: the magnitude) over finite values; (0, 1) if none is.");

  nb::class_<tetdsr::IsoValueStyles>(m, "IsoValueStyles",
    "Per-iso-value colours and opacities (index i: the i-th iso-value as given).")
    .def(nb::init<>())
    .def("set_color", &tetdsr::IsoValueStyles::setColor, "i"_a, "color"_a, "messages"_a,
      "True when it changed; False (with an error for an index out of range) otherwise.")
    .def("set_opacity", &tetdsr::IsoValueStyles::setOpacity, "i"_a, "opacity"_a, "messages"_a)
    .def("color", &tetdsr::IsoValueStyles::color, "i"_a, "fallback"_a)
    .def("opacity", &tetdsr::IsoValueStyles::opacity, "i"_a)
    .def("remove_all_colors", &tetdsr::IsoValueStyles::removeAllColors)
    .def("remove_all_opacities", &tetdsr::IsoValueStyles::removeAllOpacities)
    .def("styles", &tetdsr::IsoValueStyles::styles, "count"_a, "fallback"_a, "opacity_factor"_a)
    .def("describe", &tetdsr::IsoValueStyles::describe);

  BindSettingsTable(m);

  nb::class_<tetdsr::ColorMapPoint>(m, "ColorMapPoint")
    .def_ro("x", &tetdsr::ColorMapPoint::x)
    .def_ro("color", &tetdsr::ColorMapPoint::color);
  nb::class_<tetdsr::ColorMap>(m, "ColorMap", "Control points over [0, 1] and their colour space.")
    .def_ro("space", &tetdsr::ColorMap::space)
    .def_ro("points", &tetdsr::ColorMap::points)
    .def_ro("nan_color", &tetdsr::ColorMap::nanColor);
  m.def("is_color_mapped", &tetdsr::isColorMapped, "color_by_array"_a, "capping"_a,
    "clip_planes"_a, "Whether the image has colour values: colouring by an array, or caps.");
  m.def("is_usable_color_range", &tetdsr::isUsableColorRange, "lo"_a, "hi"_a,
    "Whether a colour range the user set is used as it is (else the data's finite range).");
  m.def("built_in_color_map", &tetdsr::builtInColorMap, "which"_a, nb::rv_policy::reference,
    "0 cool to warm (also any unknown number), 1 rainbow, 2 grayscale, 3 black body.");
  m.def("sample_color_table", &tetdsr::sampleColorTable, "color_of"_a, "table_lo"_a, "table_hi"_a,
    "lo"_a, "hi"_a,
    "A ColorTable for lo..hi from color_of(value) (a lookup table spanning table_lo..table_hi), "
    "sampled at COLOR_TABLE_SIZE values, and color_of(nan).");
  m.def("report_aborted_cast", &tetdsr::reportAbortedCast, "done"_a, "tiles"_a, "messages"_a);
  m.def(
    "reset_camera",
    [](const std::array<double, 6>& bounds, double aspect) {
      return tetdsr::resetCamera(bounds.data(), aspect);
    },
    "bounds"_a, "aspect"_a,
    "The camera vtkRenderer::ResetCamera would place to see the box (looking down -z).");
}

/// The mesh.
void BindMesh(nb::module_& m)
{
  nb::class_<PyPreparedMesh>(m, "PreparedMesh",
    "A mesh as VTK holds it, copied, checked and validated cell by cell into the core's scene "
    "(edits of the arrays given do not reach it: prepare again).")
    .def(nb::init<>())
    .def("prepare", &Prepare, "points"_a, "cell_types"_a, "offsets"_a, "connectivity"_a,
      "field"_a, "field_name"_a = "", "component"_a = 0,
      "transverse"_a = tetdsr::TransverseTest(), "threads"_a = 0, "messages"_a,
      "rational_weights"_a = nb::none(), "cell_ghosts"_a = nb::none(),
      "points: (n, 3) float32/float64; cell_types: (m,) uint8 VTK cell types; offsets: (m + 1,) "
      "and connectivity int32/int64; field: (n,) or (n, k) of any number type, `component` "
      "contoured; rational_weights: (n,) VTK's rational weights of Bezier cells, or None; "
      "cell_ghosts: (m,) uint8 VTK's cell ghost flags (vtkGhostType): cells flagged duplicate or "
      "hidden are left out, or None. False, "
      "with errors, when nothing can be rendered; warnings count skipped cells.")
    .def(
      "reuse",
      [](const PyPreparedMesh& p, tetdsr::Messages& messages) {
        SharedLock lock = LockWithoutGil<SharedLock>(p.SceneLock);
        return p.Core.reuse(messages);
      },
      "messages"_a, "For an unchanged input: the last prepare's errors again; False if it failed.")
    .def_prop_ro("ready",
      [](const PyPreparedMesh& p) {
        SharedLock lock = LockWithoutGil<SharedLock>(p.SceneLock);
        return p.Core.scene() != nullptr;
      })
    .def_prop_ro("summary",
      [](const PyPreparedMesh& p) {
        SharedLock lock = LockWithoutGil<SharedLock>(p.SceneLock);
        return SummaryOf(p.Core.summary());
      })
    .def(
      "bounds",
      [](const PyPreparedMesh& p) -> std::optional<std::array<double, 6>> {
        SharedLock lock = LockWithoutGil<SharedLock>(p.SceneLock);
        std::array<double, 6> box;
        if (!p.SceneOrThrow().bounds(box.data()))
        {
          return std::nullopt;
        }
        return box;
      },
      "The box around the valid cells (xmin, xmax, ymin, ymax, zmin, zmax), or None.")
    .def("diagonal",
      [](const PyPreparedMesh& p) {
        SharedLock lock = LockWithoutGil<SharedLock>(p.SceneLock);
        return p.SceneOrThrow().diagonal();
      })
    .def_prop_ro("uncertified_hits",
      [](const PyPreparedMesh& p) {
        SharedLock lock = LockWithoutGil<SharedLock>(p.SceneLock);
        return p.Core.scene() ? p.Core.scene()->uncertifiedHits() : 0;
      })
    .def_prop_ro("memory_bytes",
      [](const PyPreparedMesh& p) {
        SharedLock lock = LockWithoutGil<SharedLock>(p.SceneLock);
        std::size_t bytes = p.Core.memoryBytes();
        for (const std::vector<unsigned char>& copy : p.Copied)
        {
          bytes += copy.size();
        }
        return bytes;
      })
    .def(
      "point_values",
      [](PyPreparedMesh& p, AnyArray array, const std::string& name, std::uint64_t stamp,
        const std::string& role, tetdsr::Messages& messages) -> nb::object {
        const tetdsr::ArrayView view = ViewOf(array, name, "point array");
        std::unique_ptr<double[]> copy;
        std::size_t shape[2] = { 0, static_cast<std::size_t>(view.components) };
        {
          nb::gil_scoped_release release;
          SharedLock sceneLock(p.SceneLock);
          std::lock_guard<std::mutex> cacheLock(p.CacheLock);
          const double* values = p.Core.pointValues(view, stamp, role.c_str(), messages);
          if (values)
          {
            // A copy: the core's converted values live only until the next call.
            shape[0] = static_cast<std::size_t>(p.SceneOrThrow().mesh().numberOfPoints);
            copy.reset(new double[shape[0] * shape[1]]);
            std::copy(values, values + shape[0] * shape[1], copy.get());
          }
        }
        if (!copy)
        {
          return nb::none();
        }
        double* data = copy.release();
        nb::capsule owner(data, [](void* d) noexcept { delete[] static_cast<double*>(d); });
        return nb::cast(nb::ndarray<nb::numpy, double, nb::ndim<2>>(data, 2, shape, owner));
      },
      "array"_a, "name"_a, "stamp"_a, "role"_a, "messages"_a,
      "A point array's values as a new (n, k) float64 array (converted once per array and stamp, "
      "then copied). None, with an error naming `role`, when it has fewer tuples than the mesh "
      "has points.");
}

/// Images.
void BindImages(nb::module_& m)
{
  nb::class_<PyPick>(m, "Pick",
    "What a ray sees first (Renderer.pick): the nearest crossing of a surface, or of a clipping "
    "plane's cap, inside the clipping planes.")
    .def_prop_ro("t", [](const PyPick& p) { return p.Core.t; }, "along the ray")
    .def_prop_ro("point", [](const PyPick& p) { return p.Core.point; })
    .def_prop_ro("cell_id", [](const PyPick& p) { return p.Core.cellId; }, "the input's cell")
    .def_prop_ro("iso_value", [](const PyPick& p) { return p.Core.isoValue; },
      "the iso-value crossed (its index as given); -1 on a cap")
    .def_prop_ro("clip_plane", [](const PyPick& p) { return p.Core.clipPlane; },
      "a cap's clipping plane (its index); -1 on a surface")
    .def_prop_ro("normal", [](const PyPick& p) { return p.Core.normal; },
      "unit: along the field's exact gradient on a surface, the plane's normal on a cap")
    .def_prop_ro("value", [](const PyPick& p) { return p.Core.value; }, "the field at the point")
    .def_prop_ro("parametric",
      [](const PyPick& p) -> std::optional<std::array<double, 3>> {
        if (!p.Core.hasParametric)
        {
          return std::nullopt;
        }
        return std::array<double, 3>{ p.Core.parametric[0], p.Core.parametric[1], p.Core.parametric[2] };
      },
      "VTK's parametric coordinates in the cell, or None (hexahedra and wedges)")
    .def_ro("point_values", &PyPick::PointValues, "the point arrays asked for, one tuple each");
  nb::class_<PyRenderer>(m, "Renderer",
    "One image of a PreparedMesh: rays from a camera, written into the given arrays, whose "
    "shapes give the size: depth (height, width), colors (height, width, 4) uint8, normals "
    "(height, width, 3), cell_ids (height, width) int64, color_values (height, width) or None.")
    .def("__init__", &InitRenderer, "mesh"_a, "iso_values"_a, "camera"_a, "settings"_a,
      // The output arrays are written in place: never a converted temporary copy.
      "colors"_a.noconvert(), "depth"_a.noconvert(), "normals"_a.noconvert(),
      "cell_ids"_a.noconvert(), "color_values"_a.noconvert().none() = nb::none(), "threads"_a = 0)
    .def_prop_ro(
      "number_of_tiles", [](const PyRenderer& r) { return r.Renderer->numberOfTiles(); })
    .def(
      "cast",
      [](PyRenderer& r, int threads, std::optional<std::function<bool()>> abort,
        std::optional<std::function<void(double)>> progress) {
        PyPreparedMesh& mesh = nb::cast<PyPreparedMesh&>(r.MeshOwner);
        SharedLock sceneLock = LockWithoutGil<SharedLock>(mesh.SceneLock); // held throughout
        if (mesh.Generation != r.Generation)
        {
          throw nb::value_error("the PreparedMesh was prepared again since this Renderer was made: make a new one");
        }
        std::unique_lock<std::mutex> casting(*r.Casting, std::try_to_lock);
        if (!casting.owns_lock())
        {
          throw nb::value_error("this Renderer is casting already (in another thread, or this "
                                "is its own callback): make one Renderer per thread");
        }
        struct CastCount
        {
          CastCount() { ++tCasts; }
          ~CastCount() { --tCasts; }
        } counted;
        // Python is called between steps only, with the GIL; tiles are cast without it.
        auto askAbort = [&]() {
          nb::gil_scoped_acquire acquire;
          return abort && (*abort)();
        };
        auto tell = [&](double fraction) {
          nb::gil_scoped_acquire acquire;
          if (progress)
          {
            (*progress)(fraction);
          }
        };
        // One tile at a time from a shared counter; pixels are independent, so the image is the
        // same bit for bit for any number of threads.
        const tetdsr::ParallelFor tilesFor = [threads](tetdsr::NodeId count,
                                               const std::function<void(tetdsr::NodeId, tetdsr::NodeId)>& body) {
          ThreadedFor(threads, count, 1, body);
        };
        nb::gil_scoped_release release;
        return tetdsr::castInSteps(*r.Renderer,
          r.Settings.Core.normals.mode == tetdsr::NormalMode::DepthBuffer, tilesFor, askAbort, tell);
      },
      "threads"_a = 0, "abort"_a.none() = nb::none(), "progress"_a.none() = nb::none(),
      "Casts every tile in PROGRESS_STEPS steps on `threads` threads (0: all cores) without the "
      "GIL, asking abort() before each step and telling progress(fraction) after it; then the "
      "depth-buffer normals' pass (NormalMode.DEPTH_BUFFER). Returns the tiles cast.")
    .def("pick", &PickAt, "x"_a, "y"_a, "point_arrays"_a = std::vector<Array<const double>>(),
      "t_limit"_a = std::numeric_limits<double>::infinity(),
      "What the image shows at (x, y) in pixels ((i + 0.5, j + 0.5): pixel (i, j)'s centre, "
      "exactly its hit), as the core picks it: a Pick, or None when the ray sees nothing no "
      "farther than t_limit. point_arrays: (n,) or (n, k) float64 arrays, one tuple per point "
      "(PreparedMesh.point_values), interpolated at the hit into Pick.point_values.")
    .def("window_depth", &WindowDepthOf, "matrix"_a, "out"_a,
      "Writes into out ((height, width) float32) the window depth of each pixel's hit as a view "
      "with this composite projection (4 x 4 float64, row-major, as VTK's camera gives it) holds "
      "it in its depth buffer: 0.5 z / w + 0.5 in [0, 1], 1 where the ray sees nothing.");
}

} // namespace

NB_MODULE(_core, m)
{
  m.doc() = "The VTK-free TetDSR core: meshes of tetrahedra (VTK_TETRA, VTK_QUADRATIC_TETRA, "
            "VTK_LAGRANGE_TETRAHEDRON, VTK_BEZIER_TETRAHEDRON), hexahedra (VTK_HEXAHEDRON, VTK_VOXEL, "
            "VTK_QUADRATIC_HEXAHEDRON, VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON, VTK_TRIQUADRATIC_HEXAHEDRON, "
            "VTK_LAGRANGE_HEXAHEDRON, VTK_BEZIER_HEXAHEDRON), wedges (VTK_WEDGE, VTK_QUADRATIC_LINEAR_WEDGE, "
            "VTK_QUADRATIC_WEDGE, VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_LAGRANGE_WEDGE, VTK_BEZIER_WEDGE) and "
            "pyramids (VTK_PYRAMID, VTK_QUADRATIC_PYRAMID, VTK_TRIQUADRATIC_PYRAMID), Lagrange and Bezier "
            "cells of orders 1 to 4; the settings every face shares with their checks and messages; and "
            "ray-cast images.";
  // ParaView finalizes Python while its proxies still hold Python algorithms (and so meshes):
  // nanobind would list those as leaks at every pvpython exit.
  nb::set_leak_warnings(false);
  BindMessages(m);
  BindEnumerations(m);
  BindSettings(m);
  BindConstants(m);
  BindChecks(m);
  BindMesh(m);
  BindImages(m);
  BindExactSurface(m);
}
