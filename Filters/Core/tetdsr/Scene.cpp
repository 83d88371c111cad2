#include "tetdsr/Scene.h"

#include "tetdsr/CurvedTet.h"
#include "tetdsr/QuadraticTet.h"
#include "tetdsr/Roots.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
constexpr int kLeafSize = 4;
constexpr int kBins = 16;
constexpr int kMaxSahDepth = 48; // below this, split at the median: depth stays < 48 + log2(n)
// Traversal keeps at most one pending sibling per level; the tree depth is below
// kMaxSahDepth + 64, so this stack cannot overflow.
constexpr int kStackSize = kMaxSahDepth + 64;
// Subtrees below this depth, or smaller than this, are built as one task each.
constexpr int kParallelBuildDepth = 4;
constexpr std::size_t kSerialBuildSize = 4096;
constexpr float kFloatInfinity = std::numeric_limits<float>::infinity();

// A mid-edge node farther than this many times the coordinates' rounding (MeshView::
// pointRounding), relative to the cell's longest edge, from its edge's midpoint makes the cell
// curved (isoparametric). Treating a cell straight moves its surface by about the offset: below
// this, by less than 1e-13 of the cell for double coordinates.
constexpr double kCurvedRoundings = 64.0;

// Below this fraction of max-edge^3, 6*volume is treated as zero: the barycentric frame would
// amplify rounding by more than 1e13. Slivers and needles of aspect ratio 1e4 stay far above it.
constexpr double kDegenerateVolumeRatio = 1e-13;

bool distinctIds(const NodeId ids[10])
{
  for (int i = 0; i < 10; ++i)
  {
    for (int j = i + 1; j < 10; ++j)
    {
      if (ids[i] >= 0 && ids[i] == ids[j])
      {
        return false;
      }
    }
  }
  return true;
}

// Slab test of the ray against an axis-aligned box, clipped to [tLo, tHi]. `inverse` holds
// 1/direction with zero components replaced by +-1e300 (see rayInverse): a ray parallel to a slab
// then gets t = +-huge outside it and an unbounded interval inside it, without a branch, and
// never 0 * inf = NaN.
inline bool rayBox(const glm::dvec3& origin, const glm::dvec3& inverse, const float lo[3],
  const float hi[3], double tLo, double tHi, double& tEnter)
{
  for (int axis = 0; axis < 3; ++axis)
  {
    const double t0 = (static_cast<double>(lo[axis]) - origin[axis]) * inverse[axis];
    const double t1 = (static_cast<double>(hi[axis]) - origin[axis]) * inverse[axis];
    tLo = std::max(tLo, std::min(t0, t1));
    tHi = std::min(tHi, std::max(t0, t1));
  }
  tEnter = tLo;
  return tLo <= tHi;
}

/// A power of two that brings `largest` (a magnitude) near 1; 1 for zero or non-finite.
/// Clamped so the factor itself stays a normal double.
double scaleFor(double largest)
{
  if (!(largest > 0.0) || !std::isfinite(largest))
  {
    return 1.0;
  }
  return std::ldexp(1.0, -std::clamp(std::ilogb(largest), -1020, 1020));
}

/// scaleFor the largest magnitude of 10 nodal values.
double unitScale(const double values[10])
{
  double largest = 0.0;
  for (int n = 0; n < 10; ++n)
  {
    largest = std::max(largest, std::abs(values[n]));
  }
  return scaleFor(largest);
}

glm::dvec3 rayInverse(const glm::dvec3& direction)
{
  glm::dvec3 inverse;
  for (int axis = 0; axis < 3; ++axis)
  {
    inverse[axis] = direction[axis] != 0.0 ? 1.0 / direction[axis]
                                           : std::copysign(1e300, direction[axis]);
  }
  return inverse;
}
} // namespace

IsoValues::IsoValues(const std::vector<double>& values)
  : OriginalIndex_(values.size())
{
  for (std::size_t k = 0; k < values.size(); ++k)
  {
    OriginalIndex_[k] = k;
  }
  std::stable_sort(OriginalIndex_.begin(), OriginalIndex_.end(),
    [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  for (const std::size_t k : OriginalIndex_)
  {
    Sorted_.push_back(values[k]);
  }
}

struct Scene::BuildItem
{
  float boxLo[3]; ///< relative to Origin_, rounded outward
  float boxHi[3];
  float valueLo; ///< Bernstein range, rounded outward
  float valueHi;
  std::uint32_t cellId;

  float centroid(int axis) const { return 0.5f * (boxLo[axis] + boxHi[axis]); }
};

struct Scene::Bounds
{
  float boxLo[3] = { kFloatInfinity, kFloatInfinity, kFloatInfinity };
  float boxHi[3] = { -kFloatInfinity, -kFloatInfinity, -kFloatInfinity };
  float centroidLo[3] = { kFloatInfinity, kFloatInfinity, kFloatInfinity };
  float centroidHi[3] = { -kFloatInfinity, -kFloatInfinity, -kFloatInfinity };
  float valueLo = kFloatInfinity;
  float valueHi = -kFloatInfinity;

  void grow(const BuildItem& item)
  {
    for (int a = 0; a < 3; ++a)
    {
      boxLo[a] = std::min(boxLo[a], item.boxLo[a]);
      boxHi[a] = std::max(boxHi[a], item.boxHi[a]);
      centroidLo[a] = std::min(centroidLo[a], item.centroid(a));
      centroidHi[a] = std::max(centroidHi[a], item.centroid(a));
    }
    valueLo = std::min(valueLo, item.valueLo);
    valueHi = std::max(valueHi, item.valueHi);
  }

  void merge(const Bounds& other)
  {
    for (int a = 0; a < 3; ++a)
    {
      boxLo[a] = std::min(boxLo[a], other.boxLo[a]);
      boxHi[a] = std::max(boxHi[a], other.boxHi[a]);
      centroidLo[a] = std::min(centroidLo[a], other.centroidLo[a]);
      centroidHi[a] = std::max(centroidHi[a], other.centroidHi[a]);
    }
    valueLo = std::min(valueLo, other.valueLo);
    valueHi = std::max(valueHi, other.valueHi);
  }

  /// Half the surface area of the box; 0 when empty.
  double area() const
  {
    if (!(boxLo[0] <= boxHi[0]))
    {
      return 0.0;
    }
    const double dx = boxHi[0] - boxLo[0], dy = boxHi[1] - boxLo[1], dz = boxHi[2] - boxLo[2];
    return dx * dy + dy * dz + dz * dx;
  }

  static Bounds of(const std::vector<BuildItem>& items, std::size_t begin, std::size_t end)
  {
    Bounds bounds;
    for (std::size_t i = begin; i < end; ++i)
    {
      bounds.grow(items[i]);
    }
    return bounds;
  }
};

namespace
{
// Cell validation outcome, as bits.
enum : std::uint8_t
{
  kValid = 1,
  kInverted = 2,
  kCurved = 4,
  kDegenerate = 8,
  kNonFinite = 16,
  kInvalidId = 32,
  kOutOfScale = 64,
  kTangled = 128
};

float roundDown(double x)
{
  float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

float roundUp(double x)
{
  float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}
} // namespace

void TransverseTest::range(const double nodeValues[10], double& lo, double& hi) const
{
  if (mode == Mode::BernsteinBound)
  {
    BernsteinForm::fromNodeValues(nodeValues).range(lo, hi);
    return;
  }
  lo = *std::min_element(nodeValues, nodeValues + 10);
  hi = *std::max_element(nodeValues, nodeValues + 10);
  const double margin = widening * (hi - lo);
  lo -= margin;
  hi += margin;
}

Scene::Scene(const MeshView& mesh, const ParallelFor& parallelFor, const TransverseTest& transverseTest)
  : Mesh_(mesh)
  , Transverse_(transverseTest)
{
  if (mesh.numberOfCells < 0 || mesh.numberOfCells > kMaxCells || mesh.numberOfPoints < 0)
  {
    Mesh_.numberOfCells = 0; // cannot be indexed: an empty scene (the caller reports it)
    return;
  }
  // Any finite vertex of the mesh will do as the origin of the float boxes.
  for (NodeId cell = 0; cell < mesh.numberOfCells; ++cell)
  {
    const NodeId id = mesh.cellNodes[10 * cell];
    if (id >= 0 && id < mesh.numberOfPoints)
    {
      const glm::dvec3 p(mesh.points[3 * id], mesh.points[3 * id + 1], mesh.points[3 * id + 2]);
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      {
        Origin_ = p;
        break;
      }
    }
  }
  // The boxes' unit: a power of two near the extent of the cells' vertices around Origin_, so
  // float boxes resolve scenes of any size in double range (float alone stops near 1e-38).
  double extent = 0.0;
  for (NodeId n = 0; n < 10 * mesh.numberOfCells; ++n)
  {
    const NodeId id = mesh.cellNodes[n];
    if (n % 10 < 4 && id >= 0 && id < mesh.numberOfPoints)
    {
      for (int a = 0; a < 3; ++a)
      {
        const double offset = std::abs(mesh.points[3 * id + a] - Origin_[a]);
        extent = std::isfinite(offset) ? std::max(extent, offset) : extent;
      }
    }
  }
  BoxScale_ = scaleFor(extent);

  // Validate every cell in parallel, each writing only its own slot...
  std::vector<BuildItem> items(static_cast<std::size_t>(mesh.numberOfCells));
  std::vector<std::uint8_t> status(static_cast<std::size_t>(mesh.numberOfCells));
  parallelFor(mesh.numberOfCells, [&](NodeId begin, NodeId end) {
    for (NodeId cell = begin; cell < end; ++cell)
    {
      status[static_cast<std::size_t>(cell)] = validate(cell, items[static_cast<std::size_t>(cell)]);
    }
  });
  // ...then count and keep the valid ones, in cell order.
  std::size_t valid = 0;
  for (std::size_t cell = 0; cell < status.size(); ++cell)
  {
    const std::uint8_t flags = status[cell];
    Summary_.invertedCells += (flags & kInverted) != 0;
    Summary_.curvedCells += (flags & kCurved) != 0;
    Summary_.degenerateCells += (flags & kDegenerate) != 0;
    Summary_.nonFiniteCells += (flags & kNonFinite) != 0;
    Summary_.invalidIdCells += (flags & kInvalidId) != 0;
    Summary_.outOfScaleCells += (flags & kOutOfScale) != 0;
    Summary_.tangledCells += (flags & kTangled) != 0;
    if ((flags & kValid) && (flags & kCurved))
    {
      if (Curved_.empty())
      {
        Curved_.assign(status.size(), 0);
      }
      Curved_[cell] = 1;
    }
    if (flags & kValid)
    {
      items[valid++] = items[cell];
    }
  }
  Summary_.validCells = static_cast<NodeId>(valid);
  items.resize(valid);
  std::vector<std::uint8_t>().swap(status);

  if (!items.empty())
  {
    buildInParallel(items, parallelFor);
  }
  SlotCell_.resize(items.size());
  SlotRange_.resize(2 * items.size());
  for (std::size_t slot = 0; slot < items.size(); ++slot)
  {
    SlotCell_[slot] = items[slot].cellId;
    SlotRange_[2 * slot] = items[slot].valueLo;
    SlotRange_[2 * slot + 1] = items[slot].valueHi;
  }
}

std::uint8_t Scene::validate(NodeId cell, BuildItem& item) const
{
  const NodeId* ids = Mesh_.cellNodes + 10 * cell;
  for (int n = 0; n < 10; ++n)
  {
    const bool optional = n >= 4 && Mesh_.straightEdgeMarkers && ids[n] == kStraightEdge;
    if (!optional && (ids[n] < 0 || ids[n] >= Mesh_.numberOfPoints))
    {
      return kInvalidId;
    }
  }
  if (!distinctIds(ids))
  {
    return kDegenerate;
  }
  glm::dvec3 vertices[4];
  double values[10];
  loadCell(cell, vertices, values);
  for (int n = 0; n < 10; ++n)
  {
    if (!std::isfinite(values[n]))
    {
      return kNonFinite;
    }
  }
  for (int n = 0; n < 10; ++n)
  {
    // Every node's coordinates, mid-edge ones too (they are not used: cells render
    // straight-sided; but a NaN there is as broken an input as at a vertex).
    if (ids[n] >= 0 &&
      !isFinite(glm::dvec3(Mesh_.points[3 * ids[n]], Mesh_.points[3 * ids[n] + 1],
        Mesh_.points[3 * ids[n] + 2])))
    {
      return kNonFinite;
    }
  }
  TetFrame frame;
  double maxEdge = 0.0;
  for (const auto& edge : kEdgeVertices)
  {
    maxEdge = std::max(maxEdge, glm::length(vertices[edge[0]] - vertices[edge[1]]));
  }
  if (!(maxEdge >= kMinCellSize && maxEdge <= kMaxCellSize)) // also an overflowed (Inf) length
  {
    return kOutOfScale;
  }
  if (!TetFrame::fromVertices(vertices, frame) ||
    std::abs(frame.orientedVolume6) <= kDegenerateVolumeRatio * maxEdge * maxEdge * maxEdge)
  {
    return kDegenerate;
  }
  std::uint8_t flags = kValid;
  if (frame.orientedVolume6 < 0.0)
  {
    flags |= kInverted;
  }
  // Rounding is relative to the coordinates' magnitude (a float coordinate near 2.5e6 rounds by
  // 0.25), so it is measured against the larger of the cell's size and its distance from 0.
  double reach = maxEdge;
  for (int k = 0; k < 4; ++k)
  {
    for (int a = 0; a < 3; ++a)
    {
      reach = std::max(reach, std::abs(vertices[k][a]));
    }
  }
  const double curvedTolerance = kCurvedRoundings * Mesh_.pointRounding * reach;
  for (int e = 0; e < 6; ++e)
  {
    if (ids[4 + e] >= 0)
    {
      const double* p = Mesh_.points + 3 * ids[4 + e];
      const glm::dvec3 midpoint =
        0.5 * (vertices[kEdgeVertices[e][0]] + vertices[kEdgeVertices[e][1]]);
      if (glm::length(glm::dvec3(p[0], p[1], p[2]) - midpoint) > curvedTolerance)
      {
        flags |= kCurved;
        break;
      }
    }
  }
  // The cell's extent: its vertices' box, or for a curved cell its control points' (the curved
  // cell lies in their convex hull).
  glm::dvec3 extentLo = vertices[0], extentHi = vertices[0];
  for (int k = 1; k < 4; ++k)
  {
    extentLo = glm::min(extentLo, vertices[k]);
    extentHi = glm::max(extentHi, vertices[k]);
  }
  if (flags & kCurved)
  {
    glm::dvec3 nodes[10];
    loadNodes(cell, nodes);
    const CurvedGeometry geometry = CurvedGeometry::fromNodes(nodes, scaleFor(maxEdge));
    const JacobianSign sign = jacobianSign(geometry);
    if (sign == JacobianSign::Changes)
    {
      return kTangled;
    }
    flags = static_cast<std::uint8_t>((flags & ~kInverted) | (sign == JacobianSign::Negative ? kInverted : 0));
    geometry.box(extentLo, extentHi);
    if (!isFinite(extentLo) || !isFinite(extentHi))
    {
      return kOutOfScale;
    }
  }

  item.cellId = static_cast<std::uint32_t>(cell);
  double lo, hi;
  Transverse_.range(values, lo, hi);
  item.valueLo = roundDown(lo);
  item.valueHi = roundUp(hi);
  // Pad boxes so that rounding in the slab test never drops a ray that the (widened) cell
  // clip accepts: relative to the cell size and to the coordinates' own magnitude.
  double boxLo[3], boxHi[3], magnitude = 0.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    boxLo[axis] = extentLo[axis];
    boxHi[axis] = extentHi[axis];
    magnitude = std::max({ magnitude, std::abs(boxLo[axis]), std::abs(boxHi[axis]) });
  }
  const double pad = 1e-8 * maxEdge + 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
  for (int axis = 0; axis < 3; ++axis)
  {
    item.boxLo[axis] = roundDown((boxLo[axis] - pad - Origin_[axis]) * BoxScale_);
    item.boxHi[axis] = roundUp((boxHi[axis] + pad - Origin_[axis]) * BoxScale_);
  }
  return flags;
}

bool Scene::split(std::vector<BuildItem>& items, std::size_t begin, std::size_t end, int depth,
  const Bounds& bounds, Node& node, std::size_t& middle, Bounds& left, Bounds& right)
{
  node = Node{};
  for (int a = 0; a < 3; ++a)
  {
    node.boxLo[a] = bounds.boxLo[a];
    node.boxHi[a] = bounds.boxHi[a];
  }
  node.valueLo = bounds.valueLo;
  node.valueHi = bounds.valueHi;
  const std::size_t count = end - begin;
  int axis = 0;
  for (int a = 1; a < 3; ++a)
  {
    if (bounds.centroidHi[a] - bounds.centroidLo[a] >
      bounds.centroidHi[axis] - bounds.centroidLo[axis])
    {
      axis = a;
    }
  }
  const float extent = bounds.centroidHi[axis] - bounds.centroidLo[axis];
  if (count <= static_cast<std::size_t>(kLeafSize))
  {
    node.firstOrSecondChild = static_cast<std::uint32_t>(begin);
    node.count = static_cast<std::uint32_t>(count);
    return false;
  }
  node.count = 0;

  // Cells whose centroids coincide (extent 0) are split at the median too: leaves never hold
  // more than kLeafSize cells, however many copies of a cell the mesh has.
  if (depth < kMaxSahDepth && extent > 0.0f)
  {
    // Binned surface area heuristic over centroids: cost of a split = area * count per side.
    // The bins also collect each side's bounds, so children need no pass of their own.
    Bounds bins[kBins];
    std::size_t binCount[kBins] = {};
    const float scale = kBins / extent;
    const float lo = bounds.centroidLo[axis];
    auto binOf = [&](const BuildItem& item) {
      return std::min(kBins - 1, static_cast<int>((item.centroid(axis) - lo) * scale));
    };
    for (std::size_t i = begin; i < end; ++i)
    {
      const int bin = binOf(items[i]);
      ++binCount[bin];
      bins[bin].grow(items[i]);
    }
    Bounds rightOf[kBins];
    std::size_t rightCount[kBins];
    Bounds accumulated;
    std::size_t accumulatedCount = 0;
    for (int b = kBins - 1; b > 0; --b)
    {
      accumulated.merge(bins[b]);
      accumulatedCount += binCount[b];
      rightOf[b] = accumulated;
      rightCount[b] = accumulatedCount;
    }
    Bounds leftOf;
    std::size_t leftCount = 0;
    double bestCost = std::numeric_limits<double>::infinity();
    int bestBin = -1;
    Bounds bestLeft;
    for (int b = 1; b < kBins; ++b)
    {
      leftOf.merge(bins[b - 1]);
      leftCount += binCount[b - 1];
      if (leftCount == 0 || rightCount[b] == 0)
      {
        continue;
      }
      const double cost = leftOf.area() * leftCount + rightOf[b].area() * rightCount[b];
      if (cost < bestCost)
      {
        bestCost = cost;
        bestBin = b;
        bestLeft = leftOf;
      }
    }
    if (bestBin > 0)
    {
      const auto it = std::partition(items.begin() + begin, items.begin() + end,
        [&](const BuildItem& item) { return binOf(item) < bestBin; });
      middle = static_cast<std::size_t>(it - items.begin());
      if (middle > begin && middle < end)
      {
        left = bestLeft;
        right = rightOf[bestBin];
        return true;
      }
    }
  }
  // Median split (deep trees, or no useful SAH split).
  middle = begin + count / 2;
  std::nth_element(items.begin() + begin, items.begin() + middle, items.begin() + end,
    [axis](const BuildItem& x, const BuildItem& y) { return x.centroid(axis) < y.centroid(axis); });
  left = Bounds::of(items, begin, middle);
  right = Bounds::of(items, middle, end);
  return true;
}

std::uint32_t Scene::build(std::vector<BuildItem>& items, std::size_t begin, std::size_t end,
  int depth, const Bounds& bounds, std::vector<Node>& nodes)
{
  const auto index = static_cast<std::uint32_t>(nodes.size());
  nodes.emplace_back();
  Node node;
  std::size_t middle;
  Bounds left, right;
  if (split(items, begin, end, depth, bounds, node, middle, left, right))
  {
    build(items, begin, middle, depth + 1, left, nodes);
    node.firstOrSecondChild = build(items, middle, end, depth + 1, right, nodes);
  }
  nodes[index] = node;
  return index;
}

void Scene::buildInParallel(std::vector<BuildItem>& items, const ParallelFor& parallelFor)
{
  // The top levels are split serially; the subtrees below them (disjoint ranges of `items`)
  // are built concurrently, each into its own node list, then laid out in preorder.
  struct TopNode
  {
    Node node;
    int left = -1;  ///< top-level children, or -1
    int right = -1;
    int task = -1;  ///< >= 0: this node is the subtree built by that task
  };
  struct Task
  {
    std::size_t begin, end;
    int depth;
    Bounds bounds;
  };
  std::vector<TopNode> top;
  std::vector<Task> tasks;
  std::function<int(std::size_t, std::size_t, int, const Bounds&)> splitTop =
    [&](std::size_t begin, std::size_t end, int depth, const Bounds& bounds) {
      const int index = static_cast<int>(top.size());
      top.emplace_back();
      if (depth == kParallelBuildDepth || end - begin <= kSerialBuildSize)
      {
        top[index].task = static_cast<int>(tasks.size());
        tasks.push_back({ begin, end, depth, bounds });
        return index;
      }
      Node node;
      std::size_t middle;
      Bounds leftBounds, rightBounds;
      const bool interior =
        split(items, begin, end, depth, bounds, node, middle, leftBounds, rightBounds);
      top[index].node = node;
      if (interior)
      {
        const int left = splitTop(begin, middle, depth + 1, leftBounds);
        const int right = splitTop(middle, end, depth + 1, rightBounds);
        top[index].left = left;
        top[index].right = right;
      }
      return index;
    };
  splitTop(0, items.size(), 0, Bounds::of(items, 0, items.size()));

  std::vector<std::vector<Node>> subtrees(tasks.size());
  parallelFor(static_cast<NodeId>(tasks.size()), [&](NodeId first, NodeId last) {
    for (NodeId t = first; t < last; ++t)
    {
      const Task& task = tasks[static_cast<std::size_t>(t)];
      build(items, task.begin, task.end, task.depth, task.bounds,
        subtrees[static_cast<std::size_t>(t)]);
    }
  });

  std::size_t total = top.size();
  for (const auto& subtree : subtrees)
  {
    total += subtree.size();
  }
  Nodes_.reserve(total);
  std::function<std::uint32_t(int)> emit = [&](int t) {
    const auto index = static_cast<std::uint32_t>(Nodes_.size());
    if (top[t].task >= 0)
    {
      for (Node node : subtrees[static_cast<std::size_t>(top[t].task)])
      {
        if (node.count == 0)
        {
          node.firstOrSecondChild += index; // interior: child indices were subtree-relative
        }
        Nodes_.push_back(node);
      }
      std::vector<Node>().swap(subtrees[static_cast<std::size_t>(top[t].task)]);
      return index;
    }
    Nodes_.push_back(top[t].node);
    if (top[t].left >= 0)
    {
      emit(top[t].left);
      Nodes_[index].firstOrSecondChild = emit(top[t].right);
    }
    return index;
  };
  emit(0);
}

void Scene::loadVertices(NodeId cellId, glm::dvec3 vertices[4]) const
{
  const NodeId* ids = Mesh_.cellNodes + 10 * cellId;
  for (int k = 0; k < 4; ++k)
  {
    const double* p = Mesh_.points + 3 * ids[k];
    vertices[k] = glm::dvec3(p[0], p[1], p[2]);
  }
}

void Scene::loadCell(NodeId cellId, glm::dvec3 vertices[4], double values[10],
  const double* pointValues, int components, int component) const
{
  loadVertices(cellId, vertices);
  const NodeId* ids = Mesh_.cellNodes + 10 * cellId;
  for (int k = 0; k < 4; ++k)
  {
    values[k] = pointValues[components * ids[k] + component];
  }
  for (int e = 0; e < 6; ++e)
  {
    const NodeId id = ids[4 + e];
    values[4 + e] = id >= 0
      ? pointValues[components * id + component]
      : 0.5 * (values[kEdgeVertices[e][0]] + values[kEdgeVertices[e][1]]);
  }
}

void Scene::loadNodes(NodeId cellId, glm::dvec3 nodes[10]) const
{
  loadVertices(cellId, nodes);
  const NodeId* ids = Mesh_.cellNodes + 10 * cellId;
  for (int e = 0; e < 6; ++e)
  {
    const NodeId id = ids[4 + e];
    nodes[4 + e] = id >= 0
      ? glm::dvec3(Mesh_.points[3 * id], Mesh_.points[3 * id + 1], Mesh_.points[3 * id + 2])
      : 0.5 * (nodes[kEdgeVertices[e][0]] + nodes[kEdgeVertices[e][1]]);
  }
}

namespace
{
/// The curved cell's geometry in its local frame (origin its vertex 0, unit near its size).
CurvedGeometry localGeometry(const glm::dvec3 nodes[10])
{
  double size = 0.0;
  for (const auto& edge : kEdgeVertices)
  {
    size = std::max(size, glm::length(nodes[edge[0]] - nodes[edge[1]]));
  }
  return CurvedGeometry::fromNodes(nodes, scaleFor(size));
}

/// Whether a field whose Bernstein bound is [lo, hi] is constant over the cell to rounding.
bool constantToRounding(double lo, double hi)
{
  return hi - lo <= 8.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(lo), std::abs(hi));
}

/// For a constant field with Bernstein bound [lo, hi] (field scaled by `scale`): the sorted()
/// position of an iso-value it equals; false if it equals none.
bool constantIsoIndex(const IsoValues& isoValues, double lo, double hi, double scale, std::size_t& index)
{
  const std::vector<double>& sorted = isoValues.sorted();
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), lo / scale);
  index = static_cast<std::size_t>(it - sorted.begin());
  return it != sorted.end() && *it <= hi / scale;
}

/// The field's form scaled by a power of two (returned in `scale`) to a largest magnitude near 1,
/// and its Bernstein bound [lo, hi] (scaled).
QuadraticForm scaledFieldForm(double values[10], double& scale, double& lo, double& hi)
{
  scale = unitScale(values);
  for (int n = 0; n < 10; ++n)
  {
    values[n] *= scale;
  }
  const BernsteinForm bernstein = BernsteinForm::fromNodeValues(values);
  bernstein.range(lo, hi);
  QuadraticForm form;
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      form.b[i][j] = bernstein.b[i][j];
    }
  }
  return form;
}

/// Two unit vectors orthogonal to the unit vector d and to each other.
void orthonormalPair(const glm::dvec3& d, glm::dvec3& u, glm::dvec3& v)
{
  const glm::dvec3 helper = std::abs(d.x) < 0.6 ? glm::dvec3(1.0, 0.0, 0.0)
    : std::abs(d.y) < 0.6                       ? glm::dvec3(0.0, 1.0, 0.0)
                                                : glm::dvec3(0.0, 0.0, 1.0);
  u = glm::normalize(glm::cross(d, helper));
  v = glm::cross(d, u);
}
} // namespace

bool Scene::inCell(NodeId cellId, const glm::dvec3& point, double L[4]) const
{
  if (!isCurved(cellId))
  {
    glm::dvec3 vertices[4];
    loadVertices(cellId, vertices);
    TetFrame frame;
    TetFrame::fromVertices(vertices, frame);
    frame.barycentricOfOffsets(point - vertices[0], point - vertices[1], L);
    return L[0] >= -kBarycentricTolerance && L[1] >= -kBarycentricTolerance &&
      L[2] >= -kBarycentricTolerance && L[3] >= -kBarycentricTolerance;
  }
  glm::dvec3 nodes[10];
  loadNodes(cellId, nodes);
  const CurvedGeometry geometry = localGeometry(nodes);
  QuadraticForm equations[3];
  geometry.pointEquations((point - geometry.origin) * geometry.scale, equations);
  SimplexRoot root;
  if (!solveOnSimplex(3, equations, nullptr, 0.0, 0.0, kBarycentricTolerance, root))
  {
    return false;
  }
  std::copy(root.L, root.L + 4, L);
  return true;
}

void Scene::cellCoordinates(NodeId cellId, const glm::dvec3& point, double L[4]) const
{
  if (inCell(cellId, point, L) || !isCurved(cellId))
  {
    return; // (a straight cell's coordinates are exact outside it too)
  }
  // Outside a curved cell: the extension of its map, from the straight tet's guess.
  glm::dvec3 nodes[10];
  loadNodes(cellId, nodes);
  TetFrame frame;
  TetFrame::fromVertices(nodes, frame);
  frame.barycentricOfOffsets(point - nodes[0], point - nodes[1], L);
  const CurvedGeometry geometry = localGeometry(nodes);
  double guess[4] = { L[0], L[1], L[2], L[3] };
  if (inverseNewton(geometry, (point - geometry.origin) * geometry.scale, guess))
  {
    std::copy(guess, guess + 4, L);
  }
}

bool Scene::intersectCurvedCell(NodeId cellId, const Ray& ray, const IsoValues& isoValues,
  double tMin, double tLimit, SurfaceHit& hit) const
{
  glm::dvec3 nodes[10];
  loadNodes(cellId, nodes);
  double values[10];
  {
    glm::dvec3 vertices[4];
    loadCell(cellId, vertices, values);
  }
  double cellLo, cellHi;
  Transverse_.range(values, cellLo, cellHi);
  const std::vector<double>& sorted = isoValues.sorted();
  std::size_t first, last;
  if (!isoValues.within(cellLo, cellHi, first, last))
  {
    return false;
  }
  const CurvedGeometry geometry = localGeometry(nodes);
  const double s = geometry.scale;
  // The ray in local units, re-origined at its point nearest the cell's control points' mean:
  // t_world = (tCentre + T) / s, with T the local depth form below.
  const glm::dvec3 origin = (ray.origin - geometry.origin) * s;
  glm::dvec3 centroid(0.0);
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      centroid += geometry.control[i][j] / 16.0;
    }
  }
  const glm::dvec3& d = ray.direction;
  const double tCentre = glm::dot(centroid - origin, d);
  const glm::dvec3 o = origin + tCentre * d;
  glm::dvec3 u, v;
  orthonormalPair(d, u, v);
  QuadraticForm equations[3];
  equations[0] = geometry.component(u, glm::dot(u, o));
  equations[1] = geometry.component(v, glm::dot(v, o));
  const QuadraticForm depth = geometry.component(d, glm::dot(d, o));
  const double lo = tMin * s - tCentre;
  const double hi = tLimit * s - tCentre;

  double scale, boundLo, boundHi;
  const QuadraticForm field = scaledFieldForm(values, scale, boundLo, boundHi);
  SimplexRoot root;
  if (constantToRounding(boundLo, boundHi))
  {
    // Constant and equal to an iso-value: the crossing is the stretch of the ray inside the
    // cell, from where it enters (a root on a face, or the start if that is inside the cell) to
    // where it next leaves.
    std::size_t index;
    if (!constantIsoIndex(isoValues, boundLo, boundHi, scale, index))
    {
      return false;
    }
    double startL[4];
    // The nearest crossing of the cell's boundary with local depth in [from, to] (+inf if none).
    auto firstFaceCrossing = [&](double from, double to) {
      double nearest = std::numeric_limits<double>::infinity();
      for (int face = 0; face < 4; ++face)
      {
        const QuadraticForm faceEquations[2] = { equations[0].face(face), equations[1].face(face) };
        const QuadraticForm faceDepth = depth.face(face);
        SimplexRoot faceRoot;
        if (solveOnSimplex(2, faceEquations, &faceDepth, from, std::min(nearest, to),
              kBarycentricTolerance, faceRoot))
        {
          nearest = std::min(nearest, faceRoot.value);
        }
      }
      return nearest;
    };
    const double enter = std::isfinite(lo) && inCell(cellId, ray.origin + tMin * d, startL)
      ? lo
      : firstFaceCrossing(lo, hi);
    if (!std::isfinite(enter))
    {
      return false;
    }
    const double leave = firstFaceCrossing(enter + 1e-9, hi);
    hit.isoIndex = index;
    hit.t = (tCentre + enter) / s;
    hit.regionEnd = std::isfinite(leave) ? (tCentre + leave) / s : hit.t;
    hit.cellId = cellId;
    hit.gradient = glm::dvec3(0.0);
    return true;
  }
  // Every iso-value the cell's bound admits, in one subdivision (Levels); one, directly.
  Levels levels;
  if (last - first == 1)
  {
    equations[2] = field.minus(sorted[first] * scale);
  }
  else
  {
    equations[2] = field;
    levels.values = sorted.data() + first;
    levels.count = static_cast<int>(std::min<std::size_t>(last - first, 1u << 30));
    levels.scale = scale;
  }
  if (!solveOnSimplex(3, equations, &depth, lo, hi, kBarycentricTolerance, root, SolveLimits(),
        nullptr, levels))
  {
    return false;
  }
  hit.isoIndex = first + static_cast<std::size_t>(root.level);
  if (!root.certified)
  {
    UncertifiedHits_.fetch_add(1, std::memory_order_relaxed);
  }
  hit.t = (tCentre + root.value) / s;
  hit.regionEnd = hit.t;
  hit.cellId = cellId;
  // grad_x f = s grad_X f; unscaled exactly (a power of two) unless that overflows.
  const glm::dvec3 gradient = curvedGradient(geometry, field, root.L) * s;
  hit.gradient = isFinite(gradient / scale) ? gradient / scale : gradient;
  return true;
}

NodeId Scene::uncertifiedHits() const
{
  return UncertifiedHits_.load(std::memory_order_relaxed);
}

bool Scene::intersectCell(NodeId cellId, const Ray& ray, const IsoValues& isoValues, double tMin,
  double tLimit, SurfaceHit& hit) const
{
  if (isCurved(cellId))
  {
    return intersectCurvedCell(cellId, ray, isoValues, tMin, tLimit, hit);
  }
  glm::dvec3 vertices[4];
  double values[10];
  loadCell(cellId, vertices, values);
  TetFrame frame;
  if (!TetFrame::fromVertices(vertices, frame))
  {
    return false;
  }
  // Re-origin the ray at its point nearest the cell centroid: the barycentric coordinates and the
  // quadratic's coefficients are then of the cell's own scale, not of the camera distance.
  // The point is formed as offsets from the cell's vertices (origin - vertex first, both of the
  // scene's magnitude, then the small step): never rounded at the coordinates' own magnitude.
  const glm::dvec3 fromVertex0 = ray.origin - vertices[0];
  const glm::dvec3 centroidOffset =
    0.25 * ((vertices[1] - vertices[0]) + (vertices[2] - vertices[0]) + (vertices[3] - vertices[0]));
  const double tCentre = glm::dot(centroidOffset - fromVertex0, ray.direction);
  double L[4], dL[4];
  frame.barycentricOfOffsets(fromVertex0 + tCentre * ray.direction,
    (ray.origin - vertices[1]) + tCentre * ray.direction, L);
  frame.barycentricDirection(ray.direction, dL);

  // Entry and exit: the tet is {L_k >= 0}; each L_k(s) = L_k + s dL_k is affine in s.
  double sEntry = tMin - tCentre;
  double sExit = tLimit - tCentre;
  for (int k = 0; k < 4; ++k)
  {
    const double bound = (-kBarycentricTolerance - L[k]);
    if (dL[k] > 0.0)
    {
      sEntry = std::max(sEntry, bound / dL[k]);
    }
    else if (dL[k] < 0.0)
    {
      sExit = std::min(sExit, bound / dL[k]);
    }
    else if (L[k] < -kBarycentricTolerance)
    {
      return false; // parallel to face k and outside it
    }
  }
  if (!(sEntry <= sExit))
  {
    return false;
  }

  double cellLo, cellHi;
  Transverse_.range(values, cellLo, cellHi);
  const std::vector<double>& sorted = isoValues.sorted();
  // The iso-values this cell can contain: sorted[first, last).
  std::size_t first, last;
  if (!isoValues.within(cellLo, cellHi, first, last))
  {
    return false;
  }

  // Scale the field by a power of two (exact) so that its largest nodal magnitude is about 1:
  // the products in the quadratic's coefficients and its discriminant (field^2) then neither
  // overflow nor underflow, whatever the field's scale within double range.
  const double scale = unitScale(values);
  for (double& value : values)
  {
    value *= scale;
  }
  const BernsteinForm form = BernsteinForm::fromNodeValues(values);

  // A field constant over the cell (to rounding) and equal to an iso-value: the whole cell is on
  // the "surface"; the ray meets it where it enters, with no gradient. Rounding would otherwise
  // scatter the roots of a quadratic whose coefficients are all noise. (The Bernstein bound, a
  // true bound whatever the transverse test.)
  double boundLo, boundHi;
  form.range(boundLo, boundHi);
  if (constantToRounding(boundLo, boundHi))
  {
    if (!constantIsoIndex(isoValues, boundLo, boundHi, scale, hit.isoIndex))
    {
      return false;
    }
    hit.t = tCentre + sEntry;
    hit.regionEnd = tCentre + sExit;
    hit.cellId = cellId;
    hit.gradient = glm::dvec3(0.0);
    return true;
  }

  // The field along the ray, exactly: f(s) = a s^2 + b s + c (see QuadraticTet.h).
  const double a = form.bilinear(dL, dL);
  const double b = 2.0 * form.bilinear(L, dL);
  const double c = form.bilinear(L, L);

  bool found = false;
  double sHit = sExit;
  for (std::size_t k = first; k < last; ++k)
  {
    double s;
    if (firstRootInInterval(a, b, c - sorted[k] * scale, sEntry, sHit, s))
    {
      found = true;
      sHit = s;
      hit.isoIndex = k;
    }
  }
  if (!found)
  {
    return false;
  }
  double LHit[4];
  for (int k = 0; k < 4; ++k)
  {
    LHit[k] = L[k] + sHit * dL[k];
  }
  hit.t = tCentre + sHit;
  hit.regionEnd = hit.t;
  hit.cellId = cellId;
  // Unscaled exactly (a power of two), unless that overflows (a field near the largest double):
  // then the scaled gradient, whose direction is the same.
  const glm::dvec3 gradient = fieldGradient(form, frame, LHit);
  hit.gradient = isFinite(gradient / scale) ? gradient / scale : gradient;
  return true;
}

bool Scene::firstHit(
  const Ray& ray, const IsoValues& isoValues, SurfaceHit& hit, double tMin, double tMax) const
{
  if (Nodes_.empty() || !isoValues.anyWithin(Nodes_[0].valueLo, Nodes_[0].valueHi))
  {
    return false;
  }
  // Boxes are relative to Origin_ in units of 1 / BoxScale_; scaling the direction too keeps
  // the slab test's t in world units. Cells are tested in world coordinates.
  const glm::dvec3 origin = (ray.origin - Origin_) * BoxScale_;
  const glm::dvec3 inverse = rayInverse(ray.direction * BoxScale_);
  struct Entry
  {
    std::uint32_t node;
    double tEnter;
  } stack[kStackSize];
  int top = 0;
  double best = tMax;
  double tEnter;
  if (rayBox(origin, inverse, Nodes_[0].boxLo, Nodes_[0].boxHi, tMin, best, tEnter))
  {
    stack[top++] = { 0, tEnter };
  }
  bool found = false;
  while (top > 0)
  {
    const Entry entry = stack[--top];
    if (entry.tEnter > best)
    {
      continue; // a hit nearer than this subtree's box was found meanwhile
    }
    const Node& node = Nodes_[entry.node];
    if (node.count > 0)
    {
      for (std::uint32_t slot = node.firstOrSecondChild; slot < node.firstOrSecondChild + node.count;
           ++slot)
      {
        if (isoValues.anyWithin(SlotRange_[2 * slot], SlotRange_[2 * slot + 1]) &&
          intersectCell(SlotCell_[slot], ray, isoValues, tMin, best, hit))
        {
          best = hit.t;
          found = true;
        }
      }
      continue;
    }
    // Children whose value range misses every iso-value are skipped before their boxes are
    // tested; the nearer of the others is visited first (pushed last): front to back.
    const std::uint32_t children[2] = { entry.node + 1, node.firstOrSecondChild };
    double enter[2];
    bool hits[2];
    for (int c = 0; c < 2; ++c)
    {
      const Node& child = Nodes_[children[c]];
      hits[c] = isoValues.anyWithin(child.valueLo, child.valueHi) &&
        rayBox(origin, inverse, child.boxLo, child.boxHi, tMin, best, enter[c]);
    }
    const int nearer = (hits[0] && hits[1] && enter[1] < enter[0]) ? 1 : 0;
    for (int c : { 1 - nearer, nearer })
    {
      if (hits[c])
      {
        stack[top++] = { children[c], enter[c] };
      }
    }
  }
  return found;
}

std::size_t Scene::memoryBytes() const
{
  return Nodes_.capacity() * sizeof(Node) + SlotCell_.capacity() * sizeof(std::uint32_t) +
    SlotRange_.capacity() * sizeof(float) + NodalGradients_.capacity() * sizeof(glm::dvec3) +
    Curved_.capacity();
}

double Scene::interpolate(NodeId cellId, const glm::dvec3& point, const double* pointValues,
  int components, int component) const
{
  glm::dvec3 vertices[4];
  double values[10];
  loadCell(cellId, vertices, values, pointValues, components, component);
  double L[4];
  cellCoordinates(cellId, point, L); // valid cells only reach here
  // Scaled (exactly) so that the Bernstein coefficients cannot overflow for values near the
  // largest double; the result is unscaled, and overflows only if the value itself does.
  const double scale = unitScale(values);
  for (double& value : values)
  {
    value *= scale;
  }
  return BernsteinForm::fromNodeValues(values).bilinear(L, L) / scale;
}

double Scene::cellSize(NodeId cellId) const
{
  glm::dvec3 vertices[4];
  loadVertices(cellId, vertices);
  double size = 0.0;
  for (const auto& edge : kEdgeVertices)
  {
    size = std::max(size, glm::length(vertices[edge[0]] - vertices[edge[1]]));
  }
  return size;
}

bool Scene::locate(const glm::dvec3& point, NodeId& cellId) const
{
  if (Nodes_.empty())
  {
    return false;
  }
  const glm::dvec3 relative = (point - Origin_) * BoxScale_;
  auto contains = [&](const Node& node) {
    for (int a = 0; a < 3; ++a)
    {
      if (relative[a] < node.boxLo[a] || relative[a] > node.boxHi[a])
      {
        return false;
      }
    }
    return true;
  };
  std::uint32_t stack[kStackSize];
  int top = 0;
  if (contains(Nodes_[0]))
  {
    stack[top++] = 0;
  }
  while (top > 0)
  {
    const std::uint32_t index = stack[--top];
    const Node& node = Nodes_[index];
    if (node.count == 0)
    {
      for (const std::uint32_t child : { index + 1, node.firstOrSecondChild })
      {
        if (contains(Nodes_[child]))
        {
          stack[top++] = child;
        }
      }
      continue;
    }
    for (std::uint32_t slot = node.firstOrSecondChild; slot < node.firstOrSecondChild + node.count;
         ++slot)
    {
      double L[4];
      if (inCell(SlotCell_[slot], point, L))
      {
        cellId = SlotCell_[slot];
        return true;
      }
    }
  }
  return false;
}

bool Scene::bounds(double box[6]) const
{
  if (Nodes_.empty())
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    box[2 * a] = Origin_[a] + static_cast<double>(Nodes_[0].boxLo[a]) / BoxScale_;
    box[2 * a + 1] = Origin_[a] + static_cast<double>(Nodes_[0].boxHi[a]) / BoxScale_;
  }
  return true;
}

double Scene::diagonal() const
{
  if (Nodes_.empty())
  {
    return 0.0;
  }
  const Node& root = Nodes_[0];
  return glm::length(glm::dvec3(root.boxHi[0] - root.boxLo[0], root.boxHi[1] - root.boxLo[1],
           root.boxHi[2] - root.boxLo[2])) / BoxScale_;
}

void Scene::computeNodalGradients()
{
  if (hasNodalGradients())
  {
    return;
  }
  std::vector<glm::dvec3> sum(static_cast<std::size_t>(Mesh_.numberOfPoints), glm::dvec3(0.0));
  std::vector<std::uint32_t> count(static_cast<std::size_t>(Mesh_.numberOfPoints), 0);
  // One power of two for the whole field (from the valid cells' nodal values), so that
  // gradients of a field near the largest double do not overflow: only directions are used.
  double largest = 0.0;
  for (const std::uint32_t cell : SlotCell_)
  {
    glm::dvec3 vertices[4];
    double values[10];
    loadCell(cell, vertices, values);
    for (const double value : values)
    {
      largest = std::max(largest, std::abs(value));
    }
  }
  const double scale = scaleFor(largest);
  for (const std::uint32_t cell : SlotCell_)
  {
    glm::dvec3 vertices[4];
    double values[10];
    loadCell(cell, vertices, values);
    for (double& value : values)
    {
      value *= scale;
    }
    TetFrame frame;
    TetFrame::fromVertices(vertices, frame);
    const BernsteinForm form = BernsteinForm::fromNodeValues(values);
    const bool curved = isCurved(cell);
    CurvedGeometry geometry;
    QuadraticForm curvedField{};
    if (curved)
    {
      glm::dvec3 nodes[10];
      loadNodes(cell, nodes);
      geometry = localGeometry(nodes);
      for (int i = 0; i < 4; ++i)
      {
        for (int j = 0; j < 4; ++j)
        {
          curvedField.b[i][j] = form.b[i][j];
        }
      }
    }
    const NodeId* ids = Mesh_.cellNodes + 10 * cell;
    for (int n = 0; n < 10; ++n)
    {
      if (ids[n] < 0)
      {
        continue; // a linear edge has no mid-edge node
      }
      double L[4] = { 0.0, 0.0, 0.0, 0.0 };
      if (n < 4)
      {
        L[n] = 1.0;
      }
      else
      {
        L[kEdgeVertices[n - 4][0]] = L[kEdgeVertices[n - 4][1]] = 0.5;
      }
      sum[static_cast<std::size_t>(ids[n])] += curved
        ? curvedGradient(geometry, curvedField, L) * geometry.scale
        : fieldGradient(form, frame, L);
      ++count[static_cast<std::size_t>(ids[n])];
    }
  }
  for (std::size_t p = 0; p < sum.size(); ++p)
  {
    if (count[p] > 0)
    {
      sum[p] /= static_cast<double>(count[p]);
    }
  }
  NodalGradients_ = std::move(sum);
}

glm::dvec3 Scene::interpolateNodalGradient(NodeId cellId, const glm::dvec3& point) const
{
  double L[4];
  cellCoordinates(cellId, point, L);
  const NodeId* ids = Mesh_.cellNodes + 10 * cellId;
  glm::dvec3 gradient(0.0);
  for (int k = 0; k < 4; ++k)
  {
    gradient += (L[k] * (2.0 * L[k] - 1.0)) * NodalGradients_[static_cast<std::size_t>(ids[k])];
  }
  for (int e = 0; e < 6; ++e)
  {
    const int a = kEdgeVertices[e][0], b = kEdgeVertices[e][1];
    const glm::dvec3 mid = ids[4 + e] >= 0
      ? NodalGradients_[static_cast<std::size_t>(ids[4 + e])]
      : 0.5 * (NodalGradients_[static_cast<std::size_t>(ids[a])] +
                NodalGradients_[static_cast<std::size_t>(ids[b])]);
    gradient += (4.0 * L[a] * L[b]) * mid;
  }
  return gradient;
}

} // namespace tetdsr
