// Benchmark: our ray hierarchy (tetdsr::SurfaceIndex, Hierarchy.h) against Embree 3's BVH over
// the same transverse cells as user geometry. Both select the same cells, prepare the same
// CellRecords (Scene::prepareCell) and test a ray against a cell with the same exact
// Scene::intersectCell; only the hierarchy, its traversal and its build differ. Every Embree image
// must equal ours (the same pixels hit, depths within 1e-12 of the scene diagonal): the program
// exits with 1 if one does not. Prints Markdown tables; progress goes to stderr.
//
//   tetdsr-embree-comparison [image size = 1024] [lattice n = 61] [field...]
//   (a lattice of n^3 cubes has 6 n^3 cells; fields: quadric wave bubbles, default all three)
//
// Embree runs in the scene's box units (Scene::toBoxUnits): the cells' float boxes as they are,
// padded for the float rays, and t' = t * Scene::boxScale(), a power of two, so t converts
// exactly. The exact double ray of each pixel is kept beside Embree's float ray, found by the
// ray's id; the callback tests the cell with it.
#include "BenchmarkLattice.h"
#include "tetdsr/common/Camera.h"
#include "tetdsr/index/Hierarchy.h"
#include "tetdsr/index/Scene.h"
#include "tetdsr/index/SurfaceIndex.h"

#include <embree3/rtcore.h>

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace
{
using tetdsr::NodeId;

constexpr int kTileSize = 16; // tiles of 16 x 16 pixels are what threads take, one at a time
constexpr int kTilePixels = kTileSize * kTileSize;
constexpr double kInfinity = std::numeric_limits<double>::infinity();


struct Field
{
  const char* name;
  double iso;
  std::vector<double> Lattice::*values;
};
const Field kFields[] = { { "quadric", 0.09, &Lattice::quadric }, { "wave", 0.3, &Lattice::wave },
  { "bubbles", 0.86, &Lattice::bubbles } };

/// The benchmark's camera (tetdsr_benchmark.cxx's SetCamera).
tetdsr::Camera benchmarkCamera()
{
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.1, 1.6, 3.0);
  camera.focalPoint = glm::dvec3(0.5, 0.5, 0.5);
  camera.viewUp = glm::dvec3(0.0, 1.0, 0.0);
  camera.viewAngleDegrees = 30.0;
  return camera;
}

/// Wall and CPU (user + system, all threads of the process) seconds of a piece of work.
struct Timing
{
  double wall = 0.0;
  double cpu = 0.0;
};

double cpuSeconds()
{
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
    1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

Timing timed(const std::function<void()>& work)
{
  const double cpuStart = cpuSeconds();
  const auto start = std::chrono::steady_clock::now();
  work();
  Timing timing;
  timing.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  timing.cpu = cpuSeconds() - cpuStart;
  return timing;
}

/// Each build and render runs this many times and the fastest (by wall time) counts: the machine
/// is shared, and the fastest run is the least disturbed one.
constexpr int kRuns = 3;

/// The fastest of kRuns runs of work, after prepare (untimed) before each.
Timing fastest(const std::function<void()>& prepare, const std::function<void()>& work)
{
  Timing best;
  best.wall = kInfinity;
  for (int run = 0; run < kRuns; ++run)
  {
    prepare();
    const Timing timing = timed(work);
    best = timing.wall < best.wall ? timing : best;
  }
  return best;
}

/// Runs work() on `threads` threads (this one and threads - 1 more) and waits for all.
void onThreads(int threads, const std::function<void()>& work)
{
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t)
  {
    helpers.emplace_back(work);
  }
  work();
  for (std::thread& helper : helpers)
  {
    helper.join();
  }
}

/// The core's ParallelFor on `threads` std::threads taking chunks from a shared counter (small
/// chunks, so the hierarchy build's few large tasks spread over the threads).
tetdsr::ParallelFor threadedFor(int threads)
{
  return [threads](NodeId count, const std::function<void(NodeId, NodeId)>& body) {
    if (threads == 1)
    {
      body(0, count);
      return;
    }
    const NodeId chunk = std::max<NodeId>(1, count / (16 * threads));
    std::atomic<NodeId> next{ 0 };
    onThreads(threads, [&] {
      for (NodeId begin = next.fetch_add(chunk); begin < count; begin = next.fetch_add(chunk))
      {
        body(begin, std::min(count, begin + chunk));
      }
    });
  };
}

/// Per pixel: whether a ray hit, and the ray parameter (world units from the camera) of its hit.
struct DepthImage
{
  DepthImage(int width, int height)
    : width(width)
    , height(height)
    , depth(static_cast<std::size_t>(width) * height, kInfinity)
    , hit(static_cast<std::size_t>(width) * height, 0)
  {
  }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * width + i; }

  int width, height;
  std::vector<double> depth;
  std::vector<std::uint8_t> hit;
};

/// A tile's pixels [x0, x1) x [y0, y1).
struct Tile
{
  int x0, y0, x1, y1;
};

/// Calls renderTile for every 16 x 16 tile of the image, the tiles shared out to `threads`
/// threads one at a time.
void forEachTile(int width, int height, int threads, const std::function<void(const Tile&)>& renderTile)
{
  const int tilesX = (width + kTileSize - 1) / kTileSize;
  const int tilesY = (height + kTileSize - 1) / kTileSize;
  std::atomic<int> next{ 0 };
  onThreads(threads, [&] {
    for (int t = next++; t < tilesX * tilesY; t = next++)
    {
      const int x0 = (t % tilesX) * kTileSize, y0 = (t / tilesX) * kTileSize;
      renderTile({ x0, y0, std::min(width, x0 + kTileSize), std::min(height, y0 + kTileSize) });
    }
  });
}

// ---------------------------------------------------------------------------------------------
// Embree: the transverse cells as one user geometry.

/// What the callbacks read: the cells (selected and prepared exactly as SurfaceIndex does, in cell
/// order), their boxes, and the pad by which the boxes grow.
struct EmbreeCells
{
  const tetdsr::Scene* scene = nullptr;
  const tetdsr::IsoValues* isoValues = nullptr;
  double boxScale = 1.0;
  float pad = 0.0f;
  std::vector<tetdsr::BoxItem> boxes;
  std::vector<tetdsr::CellRecord> records; ///< records[primID]
};

/// The exact ray of one pixel, and the nearest crossing found on it so far.
struct RayState
{
  tetdsr::Ray ray;
  double t; ///< tLimit of the next cell test: +inf, then the nearest hit so far
};

/// Embree's intersect context extended by the tile's rays (the callback gets the context back;
/// Embree's ray id indexes `rays`).
struct TileContext
{
  RTCIntersectContext embree; // first member: a pointer to it is a pointer to the whole
  RayState rays[kTilePixels];
  std::size_t cellTests = 0; ///< intersectCell calls (one per ray and cell)
};

float roundUpToFloat(double x)
{
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

void cellBounds(const RTCBoundsFunctionArguments* args)
{
  const auto& cells = *static_cast<const EmbreeCells*>(args->geometryUserPtr);
  const tetdsr::BoxItem& box = cells.boxes[args->primID];
  // box +- pad in float: the rounding of the subtraction (half a unit of the coordinate) is far
  // below the pad (2^-16 of the coordinates' magnitude).
  RTCBounds& bounds = *args->bounds_o;
  bounds.lower_x = box.lo[0] - cells.pad;
  bounds.lower_y = box.lo[1] - cells.pad;
  bounds.lower_z = box.lo[2] - cells.pad;
  bounds.upper_x = box.hi[0] + cells.pad;
  bounds.upper_y = box.hi[1] + cells.pad;
  bounds.upper_z = box.hi[2] + cells.pad;
}

/// The exact cell test for each active lane of a packet (N = 1 for rtcIntersect1): the same
/// call with the same limits as SurfaceIndex::firstHit's leaf visitor.
void intersectCell(const RTCIntersectFunctionNArguments* args)
{
  const auto& cells = *static_cast<const EmbreeCells*>(args->geometryUserPtr);
  auto* context = reinterpret_cast<TileContext*>(args->context);
  const tetdsr::CellRecord& record = cells.records[args->primID];
  const unsigned n = args->N;
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, n);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, n);
  for (unsigned lane = 0; lane < n; ++lane)
  {
    if (args->valid[lane] == 0)
    {
      continue;
    }
    RayState& state = context->rays[RTCRayN_id(rays, n, lane)];
    ++context->cellTests;
    tetdsr::SurfaceHit hit;
    if (!cells.scene->intersectCell(record, state.ray, *cells.isoValues, 0.0, state.t, hit))
    {
      continue;
    }
    state.t = hit.t;
    // Embree culls boxes entered beyond tfar: rounded up, it never culls one nearer than the hit.
    RTCRayN_tfar(rays, n, lane) = roundUpToFloat(hit.t * cells.boxScale);
    RTCHitN_primID(hits, n, lane) = args->primID;
    RTCHitN_geomID(hits, n, lane) = args->geomID;
    RTCHitN_instID(hits, n, lane, 0) = args->context->instID[0];
  }
}

/// The pad of every box (box units): the float ray (origin and direction each rounded by 2^-24
/// of their size) and Embree's float slab tests err by a few units of 2^-24 of the largest
/// coordinate the ray reaches over the scene, M = max(box coordinates, |origin| + distance to
/// the box's farthest corner); 2^-16 of M is 256 times that (Hierarchy pads its re-origined
/// rays the same way).
float boxPad(const tetdsr::Scene& scene, const glm::dvec3& cameraPosition)
{
  double bounds[6];
  scene.bounds(bounds);
  const glm::dvec3 origin = scene.toBoxUnits(cameraPosition);
  double magnitude = 0.0, farthest = 0.0;
  for (int corner = 0; corner < 8; ++corner)
  {
    const glm::dvec3 p = scene.toBoxUnits(glm::dvec3(
      bounds[corner & 1], bounds[2 + ((corner >> 1) & 1)], bounds[4 + ((corner >> 2) & 1)]));
    magnitude = std::max({ magnitude, std::abs(p.x), std::abs(p.y), std::abs(p.z) });
    farthest = std::max(farthest, glm::length(p - origin));
  }
  magnitude = std::max(magnitude, glm::length(origin) + farthest);
  return static_cast<float>(std::ldexp(magnitude, -16));
}

/// The transverse cells as SurfaceIndex selects them (the scene's value range holds an
/// iso-value), with their boxes and records, in cell order (records[primID]).
void selectCells(const tetdsr::Scene& scene, const tetdsr::IsoValues& isoValues,
  const tetdsr::ParallelFor& parallelFor, EmbreeCells& cells)
{
  const auto& valid = scene.validCells();
  std::vector<std::uint8_t> transverse(valid.size());
  parallelFor(static_cast<NodeId>(valid.size()), [&](NodeId begin, NodeId end) {
    for (auto c = static_cast<std::size_t>(begin); c < static_cast<std::size_t>(end); ++c)
    {
      transverse[c] = isoValues.anyWithin(valid[c].valueLo, valid[c].valueHi);
    }
  });
  std::vector<std::uint32_t> selection;
  for (std::size_t c = 0; c < valid.size(); ++c)
  {
    if (transverse[c])
    {
      selection.push_back(valid[c].id);
    }
  }
  cells.boxes.resize(selection.size());
  cells.records.resize(selection.size());
  parallelFor(static_cast<NodeId>(selection.size()), [&](NodeId begin, NodeId end) {
    for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k)
    {
      cells.boxes[k] = scene.cellBox(selection[k]);
      scene.prepareCell(selection[k], cells.records[k]);
    }
  });
}

struct EmbreeBuild
{
  const char* name;
  RTCSceneFlags flags;
  RTCBuildQuality quality;
};
const EmbreeBuild kBuilds[] = { { "robust, medium", RTC_SCENE_FLAG_ROBUST, RTC_BUILD_QUALITY_MEDIUM },
  { "default, medium", RTC_SCENE_FLAG_NONE, RTC_BUILD_QUALITY_MEDIUM },
  { "robust, high", RTC_SCENE_FLAG_ROBUST, RTC_BUILD_QUALITY_HIGH },
  { "default, high", RTC_SCENE_FLAG_NONE, RTC_BUILD_QUALITY_HIGH } };
constexpr int kMainBuild = 0; // conservative like ours: the one the packet modes use

/// The cells selected, prepared and committed as one user geometry (what Embree's build time
/// covers, as SurfaceIndex's constructor covers selection, boxes, records and hierarchy).
RTCScene buildEmbree(RTCDevice device, const EmbreeBuild& build, const tetdsr::ParallelFor& parallelFor,
  EmbreeCells& cells)
{
  selectCells(*cells.scene, *cells.isoValues, parallelFor, cells);
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, build.flags);
  rtcSetSceneBuildQuality(scene, build.quality);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryBuildQuality(geometry, build.quality);
  rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(cells.records.size()));
  rtcSetGeometryUserData(geometry, &cells);
  rtcSetGeometryBoundsFunction(geometry, cellBounds, nullptr);
  rtcSetGeometryIntersectFunction(geometry, intersectCell);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  return scene;
}

/// How the Embree image is traced: rtcIntersect1 per pixel, packets of 4 (2 x 2 pixels), 8
/// (4 x 2) or 16 (4 x 4), or a tile's rays as one stream (rtcIntersect1M).
enum class Mode
{
  Single,
  Packet4,
  Packet8,
  Packet16,
  Stream
};

const char* modeName(Mode mode)
{
  switch (mode)
  {
    case Mode::Single:
      return "rtcIntersect1";
    case Mode::Packet4:
      return "rtcIntersect4 (2x2)";
    case Mode::Packet8:
      return "rtcIntersect8 (4x2)";
    case Mode::Packet16:
      return "rtcIntersect16 (4x4)";
    case Mode::Stream:
    default:
      return "rtcIntersect1M (tile)";
  }
}

/// Embree's float ray for pixel state `id` in box units (t' = t * boxScale).
void setRay(const EmbreeCells& cells, const tetdsr::Ray& ray, unsigned id, RTCRayN* rays,
  RTCHitN* hits, unsigned n, unsigned lane)
{
  const glm::dvec3 origin = cells.scene->toBoxUnits(ray.origin);
  RTCRayN_org_x(rays, n, lane) = static_cast<float>(origin.x);
  RTCRayN_org_y(rays, n, lane) = static_cast<float>(origin.y);
  RTCRayN_org_z(rays, n, lane) = static_cast<float>(origin.z);
  RTCRayN_dir_x(rays, n, lane) = static_cast<float>(ray.direction.x);
  RTCRayN_dir_y(rays, n, lane) = static_cast<float>(ray.direction.y);
  RTCRayN_dir_z(rays, n, lane) = static_cast<float>(ray.direction.z);
  RTCRayN_tnear(rays, n, lane) = 0.0f;
  RTCRayN_tfar(rays, n, lane) = std::numeric_limits<float>::infinity();
  RTCRayN_time(rays, n, lane) = 0.0f;
  RTCRayN_mask(rays, n, lane) = 0xFFFFFFFFu;
  RTCRayN_id(rays, n, lane) = id;
  RTCRayN_flags(rays, n, lane) = 0;
  RTCHitN_geomID(hits, n, lane) = RTC_INVALID_GEOMETRY_ID;
  RTCHitN_instID(hits, n, lane, 0) = RTC_INVALID_GEOMETRY_ID;
}

/// Traces packets of K = blockX * blockY rays over the tile's pixel blocks; Packet is
/// RTCRayHit4/8/16 and intersect its rtcIntersectK.
template <typename Packet, int blockX, int blockY, typename Intersect>
void tracePackets(const EmbreeCells& cells, TileContext& context, const Tile& tile,
  unsigned hitGeometry[kTilePixels], Intersect intersect)
{
  constexpr unsigned k = blockX * blockY;
  for (int by = tile.y0; by < tile.y1; by += blockY)
    for (int bx = tile.x0; bx < tile.x1; bx += blockX)
    {
      alignas(64) Packet packet;
      alignas(64) int valid[k];
      auto* rayHit = reinterpret_cast<RTCRayHitN*>(&packet);
      RTCRayN* rays = RTCRayHitN_RayN(rayHit, k);
      RTCHitN* hits = RTCRayHitN_HitN(rayHit, k);
      for (unsigned lane = 0; lane < k; ++lane)
      {
        const int i = bx + static_cast<int>(lane) % blockX, j = by + static_cast<int>(lane) / blockX;
        valid[lane] = i < tile.x1 && j < tile.y1 ? -1 : 0;
        const unsigned id = valid[lane] ? (j - tile.y0) * kTileSize + (i - tile.x0) : 0;
        setRay(cells, context.rays[id].ray, id, rays, hits, k, lane);
      }
      intersect(valid, &context.embree, &packet);
      for (unsigned lane = 0; lane < k; ++lane)
      {
        if (valid[lane])
        {
          hitGeometry[RTCRayN_id(rays, k, lane)] = RTCHitN_geomID(hits, k, lane);
        }
      }
    }
}

/// Traces one tile into `image`; returns the number of cell tests.
std::size_t renderEmbreeTile(RTCScene scene, const EmbreeCells& cells, const tetdsr::RayGenerator& rays,
  Mode mode, const Tile& tile, DepthImage& image)
{
  TileContext context;
  rtcInitIntersectContext(&context.embree);
  if (mode != Mode::Single)
  {
    context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  }
  for (int j = tile.y0; j < tile.y1; ++j)
    for (int i = tile.x0; i < tile.x1; ++i)
    {
      RayState& state = context.rays[(j - tile.y0) * kTileSize + (i - tile.x0)];
      state.ray = rays.pixelRay(i, j);
      state.t = kInfinity;
    }
  unsigned hitGeometry[kTilePixels];
  switch (mode)
  {
    case Mode::Single:
      for (int j = tile.y0; j < tile.y1; ++j)
        for (int i = tile.x0; i < tile.x1; ++i)
        {
          const unsigned id = (j - tile.y0) * kTileSize + (i - tile.x0);
          RTCRayHit rayHit;
          setRay(cells, context.rays[id].ray, id, reinterpret_cast<RTCRayN*>(&rayHit.ray),
            reinterpret_cast<RTCHitN*>(&rayHit.hit), 1, 0);
          rtcIntersect1(scene, &context.embree, &rayHit);
          hitGeometry[id] = rayHit.hit.geomID;
        }
      break;
    case Mode::Packet4:
      tracePackets<RTCRayHit4, 2, 2>(cells, context, tile, hitGeometry,
        [scene](const int* valid, RTCIntersectContext* c, RTCRayHit4* p) { rtcIntersect4(valid, scene, c, p); });
      break;
    case Mode::Packet8:
      tracePackets<RTCRayHit8, 4, 2>(cells, context, tile, hitGeometry,
        [scene](const int* valid, RTCIntersectContext* c, RTCRayHit8* p) { rtcIntersect8(valid, scene, c, p); });
      break;
    case Mode::Packet16:
      tracePackets<RTCRayHit16, 4, 4>(cells, context, tile, hitGeometry,
        [scene](const int* valid, RTCIntersectContext* c, RTCRayHit16* p) { rtcIntersect16(valid, scene, c, p); });
      break;
    case Mode::Stream:
    {
      RTCRayHit stream[kTilePixels];
      unsigned count = 0;
      for (int j = tile.y0; j < tile.y1; ++j)
        for (int i = tile.x0; i < tile.x1; ++i, ++count)
        {
          const unsigned id = (j - tile.y0) * kTileSize + (i - tile.x0);
          setRay(cells, context.rays[id].ray, id, reinterpret_cast<RTCRayN*>(&stream[count].ray),
            reinterpret_cast<RTCHitN*>(&stream[count].hit), 1, 0);
        }
      rtcIntersect1M(scene, &context.embree, stream, count, sizeof(RTCRayHit));
      for (unsigned r = 0; r < count; ++r)
      {
        hitGeometry[stream[r].ray.id] = stream[r].hit.geomID;
      }
      break;
    }
  }
  for (int j = tile.y0; j < tile.y1; ++j)
    for (int i = tile.x0; i < tile.x1; ++i)
    {
      const unsigned id = (j - tile.y0) * kTileSize + (i - tile.x0);
      const bool hit = hitGeometry[id] != RTC_INVALID_GEOMETRY_ID;
      if (hit != std::isfinite(context.rays[id].t))
      {
        std::fprintf(stderr, "Embree's hit and the callback's disagree at pixel (%d, %d)\n", i, j);
        std::exit(1);
      }
      image.hit[image.index(i, j)] = hit;
      image.depth[image.index(i, j)] = context.rays[id].t;
    }
  return context.cellTests;
}

void embreeError(void*, RTCError code, const char* message)
{
  std::fprintf(stderr, "Embree error %d: %s\n", static_cast<int>(code), message);
  std::exit(2);
}

// ---------------------------------------------------------------------------------------------
// Measurements and tables.

/// How an image compares with ours: pixels whose hit/miss differs, hit pixels whose depths
/// differ by more than the tolerance, and the largest depth difference (relative to the scene
/// diagonal) over the pixels both hit.
struct Agreement
{
  std::size_t hits = 0;
  std::size_t maskDifferences = 0;
  std::size_t depthDifferences = 0;
  double largestDifference = 0.0;
  bool equal() const { return maskDifferences == 0 && depthDifferences == 0; }
};

Agreement compare(const DepthImage& ours, const DepthImage& other, double diagonal)
{
  Agreement agreement;
  for (std::size_t p = 0; p < ours.hit.size(); ++p)
  {
    agreement.hits += other.hit[p];
    if (ours.hit[p] != other.hit[p])
    {
      ++agreement.maskDifferences;
    }
    else if (ours.hit[p])
    {
      const double difference = std::abs(ours.depth[p] - other.depth[p]) / diagonal;
      agreement.largestDifference = std::max(agreement.largestDifference, difference);
      agreement.depthDifferences += difference > 1e-12;
    }
  }
  return agreement;
}

/// One traced image: how, how long, and whether it matches ours.
struct RenderRow
{
  std::string field;
  int threads;
  std::string method;
  Timing timing;
  Agreement agreement;
  double cellTestsPerRay; ///< Embree's (counted in the callback); NaN for ours (not counted)
};

struct BuildRow
{
  std::string field;
  int threads;
  NodeId transverseCells;
  Timing ours;
  Timing selection; ///< the part both builds share: selectCells alone
  Timing embree[std::size(kBuilds)];
};

double raysPerSecondPerCore(int width, int height, int threads, const Timing& timing)
{
  return static_cast<double>(width) * height / timing.wall / threads * 1e-6;
}

bool nativePackets(RTCDevice device, Mode mode)
{
  switch (mode)
  {
    case Mode::Packet4:
      return rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED) != 0;
    case Mode::Packet8:
      return rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0;
    case Mode::Packet16:
      return rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0;
    case Mode::Stream:
      return rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED) != 0;
    case Mode::Single:
    default:
      return true;
  }
}
} // namespace

int main(int argc, char* argv[])
{
  // --tsv <file>: also write the summary's one-thread rows as tab-separated values (report.py
  // joins them into the main benchmark table).
  std::string tsvPath;
  if (argc > 2 && std::strcmp(argv[1], "--tsv") == 0)
  {
    tsvPath = argv[2];
    argv += 2;
    argc -= 2;
  }
  const int size = argc > 1 ? std::atoi(argv[1]) : 1024;
  const int n = argc > 2 ? std::atoi(argv[2]) : 61;
  std::vector<const Field*> fields;
  for (int a = 3; a < argc; ++a)
  {
    const Field* field = std::find_if(std::begin(kFields), std::end(kFields),
      [&](const Field& f) { return std::strcmp(f.name, argv[a]) == 0; });
    if (field == std::end(kFields))
    {
      std::fprintf(stderr, "unknown field %s (quadric, wave or bubbles)\n", argv[a]);
      return 2;
    }
    fields.push_back(field);
  }
  if (fields.empty())
  {
    for (const Field& field : kFields)
    {
      fields.push_back(&field);
    }
  }
  if (size < 1 || n < 1)
  {
    std::fprintf(stderr, "usage: %s [image size] [lattice n] [field...]\n", argv[0]);
    return 2;
  }

  const Lattice lattice(n);
  const tetdsr::Camera camera = benchmarkCamera();
  const tetdsr::RayGenerator rays(camera, size, size);
  const Mode modes[] = { Mode::Single, Mode::Packet4, Mode::Packet8, Mode::Packet16, Mode::Stream };
  std::vector<BuildRow> builds;
  std::vector<RenderRow> renders;
  bool allEqual = true;
  std::string support;

  for (const int threads : { 1, 2 })
  {
    // One device per thread count: a device caps TBB's parallelism for the whole process (a
    // tbb::global_control) while it lives, so two devices at once would both get the smaller cap.
    const std::string config = "threads=" + std::to_string(threads);
    RTCDevice device = rtcNewDevice(config.c_str());
    if (device == nullptr)
    {
      std::fprintf(stderr, "rtcNewDevice failed: %d\n", static_cast<int>(rtcGetDeviceError(nullptr)));
      return 2;
    }
    rtcSetDeviceErrorFunction(device, embreeError, nullptr);
    if (support.empty())
    {
      for (const Mode mode : modes)
      {
        support += std::string(support.empty() ? "" : "; ") + modeName(mode) +
          (nativePackets(device, mode) ? ": native" : ": not native, skipped");
      }
    }
    const tetdsr::ParallelFor parallelFor = threadedFor(threads);
    for (const Field* field : fields)
    {
      const tetdsr::Scene scene(lattice.view(lattice.*(field->values)), threadedFor(2));
      const tetdsr::IsoValues isoValues({ field->iso });
      const double diagonal = scene.diagonal();
      BuildRow build{ field->name, threads, 0, {}, {}, {} };

      // Ours.
      DepthImage ours(size, size);
      {
        std::unique_ptr<tetdsr::SurfaceIndex> surface;
        build.ours = fastest([&] { surface.reset(); },
          [&] { surface.reset(new tetdsr::SurfaceIndex(scene, isoValues, parallelFor)); });
        build.transverseCells = surface->transverseCells();
        const Timing render = fastest([] {}, [&] {
          forEachTile(size, size, threads, [&](const Tile& tile) {
            for (int j = tile.y0; j < tile.y1; ++j)
              for (int i = tile.x0; i < tile.x1; ++i)
              {
                tetdsr::SurfaceHit hit;
                if (surface->firstHit(rays.pixelRay(i, j), hit))
                {
                  ours.hit[ours.index(i, j)] = 1;
                  ours.depth[ours.index(i, j)] = hit.t;
                }
              }
          });
        });
        renders.push_back({ field->name, threads, "ours (SurfaceIndex::firstHit)", render, compare(ours, ours, diagonal),
          std::nan("") });
        std::fprintf(stderr, "%s, %d thread(s): ours built in %.3f s, rendered in %.3f s\n", field->name,
          threads, build.ours.wall, render.wall);
      }

      // The selection and records alone (part of both builds), then Embree per build
      // configuration; the packet and stream modes on the main one.
      {
        EmbreeCells cells;
        cells.scene = &scene;
        cells.isoValues = &isoValues;
        build.selection = fastest(
          [&] {
            std::vector<tetdsr::BoxItem>().swap(cells.boxes);
            std::vector<tetdsr::CellRecord>().swap(cells.records);
          },
          [&] { selectCells(scene, isoValues, parallelFor, cells); });
      }
      for (std::size_t b = 0; b < std::size(kBuilds); ++b)
      {
        EmbreeCells cells;
        cells.scene = &scene;
        cells.isoValues = &isoValues;
        cells.boxScale = scene.boxScale();
        cells.pad = boxPad(scene, camera.position);
        RTCScene embreeScene = nullptr;
        build.embree[b] = fastest(
          [&] {
            if (embreeScene != nullptr)
            {
              rtcReleaseScene(embreeScene);
            }
            std::vector<tetdsr::BoxItem>().swap(cells.boxes);
            std::vector<tetdsr::CellRecord>().swap(cells.records);
          },
          [&] { embreeScene = buildEmbree(device, kBuilds[b], parallelFor, cells); });
        if (static_cast<NodeId>(cells.records.size()) != build.transverseCells)
        {
          std::fprintf(stderr, "the selections differ: ours %lld cells, Embree's %zu\n",
            build.transverseCells, cells.records.size());
          return 1;
        }
        for (const Mode mode : modes)
        {
          if ((b != kMainBuild && mode != Mode::Single) || !nativePackets(device, mode))
          {
            continue;
          }
          DepthImage image(size, size);
          std::atomic<std::size_t> cellTests{ 0 };
          const Timing render = fastest([&] { cellTests = 0; }, [&] {
            forEachTile(size, size, threads, [&](const Tile& tile) {
              cellTests += renderEmbreeTile(embreeScene, cells, rays, mode, tile, image);
            });
          });
          const Agreement agreement = compare(ours, image, diagonal);
          allEqual = allEqual && agreement.equal();
          renders.push_back({ field->name, threads,
            std::string("Embree ") + kBuilds[b].name + ", " + modeName(mode), render, agreement,
            static_cast<double>(cellTests) / (static_cast<double>(size) * size) });
          std::fprintf(stderr, "%s, %d thread(s): Embree %s built in %.3f s, %s in %.3f s, %s\n",
            field->name, threads, kBuilds[b].name, build.embree[b].wall, modeName(mode), render.wall,
            agreement.equal() ? "equal to ours" : "DIFFERS from ours");
        }
        rtcReleaseScene(embreeScene);
      }
      builds.push_back(build);
    }
    rtcReleaseDevice(device);
  }

  // Tables.
  std::printf("Lattice n = %d (%lld cells), %dx%d primary rays; Embree %s (%s). Times: the fastest of %d "
              "runs (wall), with that run's CPU time.\n\n",
    n, lattice.cells, size, size, RTC_VERSION_STRING, support.c_str(), kRuns);
  auto findRender = [&](const std::string& field, int threads, const std::string& method) -> const RenderRow* {
    for (const RenderRow& row : renders)
    {
      if (row.field == field && row.threads == threads && row.method == method)
      {
        return &row;
      }
    }
    return nullptr;
  };
  std::printf("Summary (Embree: %s build; packets: the fastest packet width):\n\n", kBuilds[kMainBuild].name);
  std::printf("| field | threads | transverse cells | build s ours / Embree | ours render s | ours M rays/s/core "
              "| Embree 1 render s | Embree 1 M rays/s/core | Embree packets render s | Embree packets M rays/s/core |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  FILE* tsv = tsvPath.empty() ? nullptr : std::fopen(tsvPath.c_str(), "w");
  if (tsv)
  {
    std::fprintf(tsv, "n\tfield\tours_Mrays_core\tembree_Mrays_core\tembree_packets_Mrays_core\t"
                      "ours_build_s\tembree_build_s\n");
  }
  for (const BuildRow& build : builds)
  {
    const RenderRow* ours = findRender(build.field, build.threads, "ours (SurfaceIndex::firstHit)");
    const std::string prefix = std::string("Embree ") + kBuilds[kMainBuild].name + ", ";
    const RenderRow* single = findRender(build.field, build.threads, prefix + modeName(Mode::Single));
    const RenderRow* packets = nullptr;
    for (const Mode mode : { Mode::Packet4, Mode::Packet8, Mode::Packet16 })
    {
      const RenderRow* row = findRender(build.field, build.threads, prefix + modeName(mode));
      if (row != nullptr && (packets == nullptr || row->timing.wall < packets->timing.wall))
      {
        packets = row;
      }
    }
    std::printf("| %s | %d | %lld | %.3f / %.3f | %.3f | %.2f | %.3f | %.2f |", build.field.c_str(), build.threads,
      build.transverseCells, build.ours.wall, build.embree[kMainBuild].wall, ours->timing.wall,
      raysPerSecondPerCore(size, size, build.threads, ours->timing), single->timing.wall,
      raysPerSecondPerCore(size, size, build.threads, single->timing));
    if (packets != nullptr)
    {
      std::printf(" %.3f (%s) | %.2f |\n", packets->timing.wall, packets->method.c_str() + prefix.size(),
        raysPerSecondPerCore(size, size, build.threads, packets->timing));
    }
    else
    {
      std::printf(" - | - |\n");
    }
    if (tsv && build.threads == 1)
    {
      std::fprintf(tsv, "%d\t%s\t%.2f\t%.2f\t%.2f\t%.3f\t%.3f\n", n, build.field.c_str(),
        raysPerSecondPerCore(size, size, 1, ours->timing), raysPerSecondPerCore(size, size, 1, single->timing),
        packets ? raysPerSecondPerCore(size, size, 1, packets->timing) : 0.0, build.ours.wall,
        build.embree[kMainBuild].wall);
    }
  }
  if (tsv)
  {
    std::fclose(tsv);
  }

  std::printf("\nBuilds (selection, boxes, records and hierarchy), wall s / CPU s; the first column is the "
              "selection, boxes and records alone, the same calls in both:\n\n| field | threads | transverse cells | "
              "selection + boxes + records | ours |");
  for (const EmbreeBuild& b : kBuilds)
  {
    std::printf(" Embree %s |", b.name);
  }
  std::printf("\n|---|---|---|---|---|");
  for (std::size_t b = 0; b < std::size(kBuilds); ++b)
  {
    std::printf("---|");
  }
  std::printf("\n");
  for (const BuildRow& build : builds)
  {
    std::printf("| %s | %d | %lld | %.3f / %.3f | %.3f / %.3f |", build.field.c_str(), build.threads,
      build.transverseCells, build.selection.wall, build.selection.cpu, build.ours.wall, build.ours.cpu);
    for (const Timing& timing : build.embree)
    {
      std::printf(" %.3f / %.3f |", timing.wall, timing.cpu);
    }
    std::printf("\n");
  }

  std::printf("\nRenders (every Embree image checked against ours: same hit pixels, depth within 1e-12 of the "
              "scene diagonal):\n\n| field | threads | method | wall s | CPU s | M rays/s/core | cell tests per ray | "
              "hit pixels | hit/miss differences | depth differences | largest depth difference / diagonal |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const RenderRow& row : renders)
  {
    char tests[32] = "-";
    if (!std::isnan(row.cellTestsPerRay))
    {
      std::snprintf(tests, sizeof(tests), "%.2f", row.cellTestsPerRay);
    }
    std::printf("| %s | %d | %s | %.3f | %.3f | %.2f | %s | %zu | %zu | %zu | %.1e |\n", row.field.c_str(),
      row.threads, row.method.c_str(), row.timing.wall, row.timing.cpu,
      raysPerSecondPerCore(size, size, row.threads, row.timing), tests, row.agreement.hits,
      row.agreement.maskDifferences, row.agreement.depthDifferences, row.agreement.largestDifference);
  }
  if (!allEqual)
  {
    std::printf("\nFAILED: an Embree image differs from ours (see the differences above).\n");
    return 1;
  }
  std::printf("\nEvery Embree image equals ours.\n");
  return 0;
}
