// tetdsr._core: the VTK-free core (Filters/Core) for Python, with numpy arrays in and out. The
// wheel's whole C++ binding is this file: the Python filter (tetdsr/filter.py) converts VTK data
// and settings, this module checks every size it is given against the arrays, keeps the arrays
// the core views alive, and renders image tiles on std::threads without the GIL.
#include "tetdsr/Camera.h"
#include "tetdsr/Renderer.h"
#include "tetdsr/SurfaceIndex.h"
#include "tetdsr/Scene.h"

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace nb = nanobind;
using namespace nb::literals;

namespace
{
static_assert(sizeof(std::int64_t) == sizeof(tetdsr::NodeId), "ids are 64-bit in the core");

template <typename T>
using Array = nb::ndarray<T, nb::c_contig, nb::device::cpu>;

glm::dvec3 Vec(const std::array<double, 3>& v)
{
  return glm::dvec3(v[0], v[1], v[2]);
}

int ThreadCount(int requested)
{
  const unsigned hardware = std::thread::hardware_concurrency();
  return requested > 0 ? requested : static_cast<int>(std::max(1u, hardware));
}

/// Runs body(begin, end) over [0, count) on `threads` std::threads (0: all cores), handing out
/// chunks of `grain` indices from a shared counter (tiles differ in cost). The first exception
/// thrown in any thread is rethrown here once all have stopped.
void ParallelFor(int threads, tetdsr::NodeId count, tetdsr::NodeId grain,
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
  for (int w = 1; w < workers; ++w)
  {
    pool.emplace_back(work);
  }
  work();
  for (std::thread& thread : pool)
  {
    thread.join();
  }
  if (failure)
  {
    std::rethrow_exception(failure);
  }
}

/// A Scene and the arrays it views (kept alive as long as it lives).
struct PyScene
{
  Array<const double> Points;
  Array<const std::int64_t> Cells;
  Array<const double> Values;
  std::unique_ptr<tetdsr::Scene> Scene;
  int Threads = 0;
  /// The surface index of the last iso-values rendered (as given), rebuilt when they change.
  std::shared_ptr<const tetdsr::SurfaceIndex> Surface;
  std::vector<double> SurfaceValues;
};

PyScene* MakeScene(Array<const double> points, Array<const std::int64_t> cells,
  Array<const double> values, double pointRounding, bool straightEdgeMarkers, int transverseMode,
  double widening, int threads)
{
  if (points.ndim() != 2 || points.shape(1) != 3)
  {
    throw nb::value_error("points must be an (n, 3) array of float64");
  }
  if (cells.ndim() != 2 || cells.shape(1) != 10)
  {
    throw nb::value_error("cells must be an (m, 10) array of int64 node ids");
  }
  const auto numberOfPoints = static_cast<tetdsr::NodeId>(points.shape(0));
  const auto numberOfCells = static_cast<tetdsr::NodeId>(cells.shape(0));
  if (values.ndim() != 1 || static_cast<tetdsr::NodeId>(values.shape(0)) < numberOfPoints)
  {
    throw nb::value_error(("values must be a 1-d float64 array with a value per point (" +
      std::to_string(numberOfPoints) + " points, " +
      std::to_string(values.ndim() == 1 ? values.shape(0) : 0) + " values)")
                            .c_str());
  }
  if (numberOfCells > tetdsr::Scene::kMaxCells)
  {
    throw nb::value_error("too many cells for one scene");
  }
  if (transverseMode != 0 && transverseMode != 1)
  {
    throw nb::value_error("transverse_mode must be 0 (Bernstein bound) or 1 (widened nodal range)");
  }
  if (!(pointRounding > 0.0) || !(widening >= 0.0))
  {
    throw nb::value_error("point_rounding must be positive and widening not negative");
  }
  auto* result = new PyScene{ points, cells, values, nullptr, threads, nullptr, {} };
  tetdsr::MeshView mesh;
  mesh.points = points.data();
  mesh.numberOfPoints = numberOfPoints;
  mesh.cellNodes = reinterpret_cast<const tetdsr::NodeId*>(cells.data());
  mesh.numberOfCells = numberOfCells;
  mesh.values = values.data();
  mesh.straightEdgeMarkers = straightEdgeMarkers;
  mesh.pointRounding = pointRounding;
  tetdsr::TransverseTest transverse;
  transverse.mode = transverseMode == 1 ? tetdsr::TransverseTest::Mode::WidenedNodalRange
                                        : tetdsr::TransverseTest::Mode::BernsteinBound;
  transverse.widening = widening;
  {
    nb::gil_scoped_release release;
    const tetdsr::NodeId grain = std::max<tetdsr::NodeId>(1024, numberOfCells / 256);
    result->Scene.reset(new tetdsr::Scene(
      mesh,
      [threads, grain](tetdsr::NodeId count,
        const std::function<void(tetdsr::NodeId, tetdsr::NodeId)>& body) {
        ParallelFor(threads, count, grain, body);
      },
      transverse));
  }
  return result;
}

tetdsr::Camera MakeCamera(const std::array<double, 3>& position,
  const std::array<double, 3>& focalPoint, const std::array<double, 3>& viewUp, double viewAngle,
  bool parallel, double parallelScale)
{
  tetdsr::Camera camera;
  camera.position = Vec(position);
  camera.focalPoint = Vec(focalPoint);
  camera.viewUp = Vec(viewUp);
  camera.viewAngleDegrees = viewAngle;
  camera.parallelProjection = parallel;
  camera.parallelScale = parallelScale;
  return camera;
}

/// One image being rendered: the renderer, the iso-values and settings it refers to, and the
/// arrays it reads and writes (kept alive as long as it lives).
struct PyRenderer
{
  nb::object SceneOwner; // the PyScene
  Array<std::uint8_t> Colors;
  Array<double> Depth;
  Array<double> Normals;
  Array<std::int64_t> CellIds;
  std::optional<Array<double>> ColorValues;
  std::optional<Array<const double>> ColorByValues;
  std::shared_ptr<const tetdsr::SurfaceIndex> Surface;
  std::unique_ptr<tetdsr::Renderer> Renderer;
  std::vector<bool> TileDone;
};

template <typename T>
void CheckSize(const Array<T>& array, std::size_t expected, const char* name)
{
  if (array.size() != expected)
  {
    throw nb::value_error((std::string(name) + " has " + std::to_string(array.size()) +
      " values; the image needs " + std::to_string(expected))
                            .c_str());
  }
}

/// Renderer.__init__: checks every argument, then constructs the renderer in place at `self`.
void InitRenderer(PyRenderer* self, nb::object sceneObject, const std::vector<double>& isoValues,
  const std::array<double, 3>& position, const std::array<double, 3>& focalPoint,
  const std::array<double, 3>& viewUp, double viewAngle, bool parallel, double parallelScale,
  int width, int height, Array<std::uint8_t> colors,
  Array<double> depth, Array<double> normals, Array<std::int64_t> cellIds,
  std::optional<Array<double>> colorValues, const std::array<double, 3>& surfaceColor,
  double ambient, double diffuse, double specular, double specularPower,
  const std::array<double, 3>& lightPosition, int normalMode, double relativeStep,
  Array<const double> isoStyles, std::optional<Array<const double>> colorByValues,
  int colorByComponents, int colorByComponent, double colorTableLo, double colorTableHi,
  Array<const double> colorTableColors, const std::array<double, 3>& nanColor,
  Array<const double> clipPlanes, int cap)
{
  const tetdsr::Camera camera =
    MakeCamera(position, focalPoint, viewUp, viewAngle, parallel, parallelScale);
  PyScene& scene = nb::cast<PyScene&>(sceneObject);
  if (isoValues.empty())
  {
    throw nb::value_error("no iso-value");
  }
  if (width <= 0 || height <= 0 ||
    static_cast<double>(width) * static_cast<double>(height) >= 2147483647.0)
  {
    throw nb::value_error("the image must have a positive width and height and fewer than 2^31 pixels");
  }
  const tetdsr::CameraProblem problem = tetdsr::RayGenerator::check(camera);
  if (problem != tetdsr::CameraProblem::None)
  {
    throw nb::value_error(tetdsr::describe(problem));
  }
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  CheckSize(colors, 4 * pixels, "colors");
  CheckSize(depth, pixels, "depth");
  CheckSize(normals, 3 * pixels, "normals");
  CheckSize(cellIds, pixels, "cell_ids");
  if (colorValues)
  {
    CheckSize(*colorValues, pixels, "color_values");
  }
  if (normalMode < 0 || normalMode > 3)
  {
    throw nb::value_error("normal_mode must be 0 to 3");
  }
  if (cap < 0 || cap > 2)
  {
    throw nb::value_error("cap must be 0 (none), 1 (below) or 2 (above the iso-value)");
  }
  if (isoStyles.ndim() != 2 || isoStyles.shape(1) != 4)
  {
    throw nb::value_error("iso_styles must be a (k, 4) array: red, green, blue, opacity");
  }
  if (clipPlanes.ndim() != 2 || clipPlanes.shape(1) != 6)
  {
    throw nb::value_error("clip_planes must be a (k, 6) array: origin, normal");
  }
  if (colorTableColors.ndim() != 2 || colorTableColors.shape(1) != 3 ||
    colorTableColors.shape(0) < 2)
  {
    throw nb::value_error("color_table_colors must be an (m, 3) array with m >= 2");
  }

  tetdsr::RenderSettings settings;
  settings.material.color = Vec(surfaceColor);
  settings.material.ambient = ambient;
  settings.material.diffuse = diffuse;
  settings.material.specular = specular;
  settings.material.specularPower = specularPower;
  tetdsr::Light light; // one white point light
  light.positional = true;
  light.position = Vec(lightPosition);
  settings.lighting.lights.push_back(light);
  settings.normals.mode = static_cast<tetdsr::NormalMode>(normalMode);
  settings.normals.relativeStep = relativeStep;
  for (std::size_t k = 0; k < isoStyles.shape(0); ++k)
  {
    const double* style = isoStyles.data() + 4 * k;
    settings.isoStyles.push_back({ glm::dvec3(style[0], style[1], style[2]), style[3] });
  }
  const tetdsr::NodeId numberOfPoints = scene.Scene->mesh().numberOfPoints;
  if (colorByValues)
  {
    if (colorByComponents < 1 || colorByComponent < -1 || colorByComponent >= colorByComponents)
    {
      throw nb::value_error("color_by_component must be -1 (magnitude) or a component of the colour array");
    }
    if (colorByValues->size() < static_cast<std::size_t>(numberOfPoints) * colorByComponents)
    {
      throw nb::value_error(("the colour array has " + std::to_string(colorByValues->size()) +
        " values for " + std::to_string(numberOfPoints) + " points of " +
        std::to_string(colorByComponents) + " components")
                              .c_str());
    }
    settings.colorBy.values = colorByValues->data();
    settings.colorBy.components = colorByComponents;
    settings.colorBy.component = colorByComponent;
  }
  settings.colorTable.lo = colorTableLo;
  settings.colorTable.hi = colorTableHi;
  settings.colorTable.colors.clear();
  for (std::size_t k = 0; k < colorTableColors.shape(0); ++k)
  {
    const double* c = colorTableColors.data() + 3 * k;
    settings.colorTable.colors.emplace_back(c[0], c[1], c[2]);
  }
  settings.colorTable.nanColor = Vec(nanColor);
  for (std::size_t k = 0; k < clipPlanes.shape(0); ++k)
  {
    const double* p = clipPlanes.data() + 6 * k;
    tetdsr::ClipPlane plane;
    plane.origin = glm::dvec3(p[0], p[1], p[2]);
    plane.normal = glm::dvec3(p[3], p[4], p[5]);
    if (!tetdsr::isFinite(plane.origin) || tetdsr::unitVector(plane.normal) == glm::dvec3(0.0))
    {
      throw nb::value_error("a clipping plane has a non-finite origin or a zero or non-finite normal");
    }
    settings.clipPlanes.push_back(plane);
  }
  settings.cap = static_cast<tetdsr::CapRegion>(cap);
  if (settings.normals.mode == tetdsr::NormalMode::NodalInterpolation &&
    !scene.Scene->hasNodalGradients())
  {
    nb::gil_scoped_release release;
    scene.Scene->computeNodalGradients(); // once per scene: kept with it
  }

  if (!scene.Surface || scene.SurfaceValues != isoValues)
  {
    nb::gil_scoped_release release;
    const int threads = scene.Threads;
    const tetdsr::NodeId grain =
      std::max<tetdsr::NodeId>(1024, scene.Scene->summary().validCells / 256);
    scene.Surface = std::make_shared<const tetdsr::SurfaceIndex>(*scene.Scene,
      tetdsr::IsoValues(isoValues),
      [threads, grain](tetdsr::NodeId count,
        const std::function<void(tetdsr::NodeId, tetdsr::NodeId)>& body) {
        ParallelFor(threads, count, grain, body);
      },
      scene.Surface.get());
    scene.SurfaceValues = isoValues;
  }
  PyRenderer made{ sceneObject, colors, depth, normals, cellIds, colorValues, colorByValues,
    scene.Surface, nullptr, {} };
  tetdsr::ImageView view;
  view.width = width;
  view.height = height;
  view.colors = colors.data();
  view.depth = depth.data();
  view.normals = normals.data();
  view.cellIds = reinterpret_cast<tetdsr::NodeId*>(cellIds.data());
  view.colorValues = colorValues ? colorValues->data() : nullptr;
  made.Renderer.reset(new tetdsr::Renderer(*made.Surface, camera, settings, view));
  made.TileDone.assign(static_cast<std::size_t>(made.Renderer->numberOfTiles()), false);
  new (self) PyRenderer(std::move(made));
}

void CheckTiles(const PyRenderer& renderer, tetdsr::NodeId begin, tetdsr::NodeId end)
{
  if (begin < 0 || end < begin || end > renderer.Renderer->numberOfTiles())
  {
    throw nb::index_error("tile range outside [0, number_of_tiles]");
  }
}
} // namespace

NB_MODULE(_core, m)
{
  m.doc() = "The VTK-free TetDSR core: scenes of 10-node tetrahedra and their ray-cast images.";
  // ParaView finalizes Python while its proxies still hold Python algorithms (and so scenes):
  // nanobind would list those as leaks at every pvpython exit.
  nb::set_leak_warnings(false);

  nb::class_<PyScene>(m, "Scene",
    "A validated mesh of 10-node tetrahedra (VTK node order) with its acceleration structure. "
    "Keeps the arrays it views alive.")
    .def(nb::new_(&MakeScene), "points"_a, "cells"_a, "values"_a,
      "point_rounding"_a = 0x1p-52, "straight_edge_markers"_a = false, "transverse_mode"_a = 0,
      "widening"_a = 0.25, "threads"_a = 0,
      "points: (n, 3) float64; cells: (m, 10) int64 node ids; values: float64, one per point. "
      "point_rounding: 2^-52 for coordinates given in double, 2^-23 in float. With "
      "straight_edge_markers a mid-edge id of -1 marks a straight edge (a linear tetrahedron).")
    .def_prop_ro("summary",
      [](const PyScene& s) {
        const tetdsr::PreprocessSummary& summary = s.Scene->summary();
        nb::dict d;
        d["valid"] = summary.validCells;
        d["inverted"] = summary.invertedCells;
        d["curved"] = summary.curvedCells;
        d["tangled"] = summary.tangledCells;
        d["degenerate"] = summary.degenerateCells;
        d["out_of_scale"] = summary.outOfScaleCells;
        d["non_finite"] = summary.nonFiniteCells;
        d["invalid_id"] = summary.invalidIdCells;
        return d;
      })
    .def("bounds",
      [](const PyScene& s) -> std::optional<std::array<double, 6>> {
        std::array<double, 6> box;
        if (!s.Scene->bounds(box.data()))
        {
          return std::nullopt;
        }
        return box;
      },
      "The box around the valid cells (xmin, xmax, ymin, ymax, zmin, zmax), or None.")
    .def("diagonal", [](const PyScene& s) { return s.Scene->diagonal(); })
    .def_prop_ro(
      "uncertified_hits", [](const PyScene& s) { return s.Scene->uncertifiedHits(); })
    .def_prop_ro("memory_bytes", [](const PyScene& s) { return s.Scene->memoryBytes(); })
    .def_prop_ro("number_of_points", [](const PyScene& s) { return s.Scene->mesh().numberOfPoints; })
    .def_prop_ro("number_of_cells", [](const PyScene& s) { return s.Scene->mesh().numberOfCells; });

  m.def("check_camera",
    [](const std::array<double, 3>& position, const std::array<double, 3>& focalPoint,
      const std::array<double, 3>& viewUp, double viewAngle, bool parallel,
      double parallelScale) -> std::optional<std::string> {
      const tetdsr::CameraProblem problem = tetdsr::RayGenerator::check(
        MakeCamera(position, focalPoint, viewUp, viewAngle, parallel, parallelScale));
      if (problem == tetdsr::CameraProblem::None)
      {
        return std::nullopt;
      }
      return std::string(tetdsr::describe(problem));
    },
    "position"_a, "focal_point"_a, "view_up"_a, "view_angle"_a, "parallel"_a, "parallel_scale"_a,
    "None for a camera that defines rays, else why it does not.");

  m.def("reset_camera",
    [](const std::array<double, 6>& bounds, double aspect) {
      const tetdsr::Camera camera = tetdsr::resetCamera(bounds.data(), aspect);
      nb::dict d;
      d["position"] = std::array<double, 3>{ camera.position.x, camera.position.y, camera.position.z };
      d["focal_point"] =
        std::array<double, 3>{ camera.focalPoint.x, camera.focalPoint.y, camera.focalPoint.z };
      d["view_up"] = std::array<double, 3>{ camera.viewUp.x, camera.viewUp.y, camera.viewUp.z };
      d["view_angle"] = camera.viewAngleDegrees;
      d["parallel_scale"] = camera.parallelScale;
      return d;
    },
    "bounds"_a, "aspect"_a,
    "The camera vtkRenderer::ResetCamera would place to see the box (looking down -z).");

  nb::class_<PyRenderer>(m, "Renderer",
    "One image of a Scene: rays from a camera, written into the given arrays tile by tile.")
    .def("__init__", &InitRenderer,
      "scene"_a, "iso_values"_a, "position"_a, "focal_point"_a, "view_up"_a, "view_angle"_a,
      "parallel"_a, "parallel_scale"_a, "width"_a, "height"_a,
      // The output arrays are written in place: never a converted temporary copy.
      "colors"_a.noconvert(), "depth"_a.noconvert(), "normals"_a.noconvert(),
      "cell_ids"_a.noconvert(), "color_values"_a.noconvert().none(), "surface_color"_a, "ambient"_a,
      "diffuse"_a, "specular"_a, "specular_power"_a, "light_position"_a, "normal_mode"_a,
      "relative_step"_a, "iso_styles"_a, "color_by_values"_a.none(), "color_by_components"_a,
      "color_by_component"_a, "color_table_lo"_a, "color_table_hi"_a, "color_table_colors"_a,
      "nan_color"_a, "clip_planes"_a, "cap"_a)
    .def_prop_ro(
      "number_of_tiles", [](const PyRenderer& r) { return r.Renderer->numberOfTiles(); })
    .def(
      "render_tiles",
      [](PyRenderer& r, tetdsr::NodeId begin, tetdsr::NodeId end, int threads) {
        CheckTiles(r, begin, end);
        {
          nb::gil_scoped_release release;
          // One tile at a time from a shared counter; pixels are independent, so the image is
          // the same bit for bit for any number of threads.
          ParallelFor(threads, end - begin, 1, [&](tetdsr::NodeId first, tetdsr::NodeId last) {
            r.Renderer->renderTiles(begin + first, begin + last);
          });
        }
        std::fill(r.TileDone.begin() + begin, r.TileDone.begin() + end, true);
      },
      "begin"_a, "end"_a, "threads"_a = 0,
      "Renders tiles [begin, end) on `threads` threads (0: all cores), without the GIL.")
    .def(
      "shade_from_depth",
      [](PyRenderer& r, int threads) {
        if (!std::all_of(r.TileDone.begin(), r.TileDone.end(), [](bool done) { return done; }))
        {
          throw nb::value_error("shade_from_depth needs every tile rendered first");
        }
        nb::gil_scoped_release release;
        ParallelFor(threads, r.Renderer->numberOfTiles(), 1,
          [&](tetdsr::NodeId first, tetdsr::NodeId last) { r.Renderer->shadeFromDepth(first, last); });
      },
      "threads"_a = 0,
      "Depth-buffer normals (normal_mode 3): re-shades the nearest surfaces from the depth image.");

  m.attr("TILE_SIZE") = tetdsr::Renderer::kTileSize;
  m.attr("MAX_CELLS") = tetdsr::Scene::kMaxCells;
}
