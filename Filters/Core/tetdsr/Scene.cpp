#include "tetdsr/Scene.h"

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
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr float kFloatInfinity = std::numeric_limits<float>::infinity();

// A mid-edge node farther than this fraction of the longest edge from its edge's midpoint makes
// the cell curved (isoparametric); we render it straight-sided and count it.
constexpr double kCurvedTolerance = 1e-6;

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

IsoValues::IsoValues(std::vector<double> values)
  : Sorted_(std::move(values))
{
  std::sort(Sorted_.begin(), Sorted_.end());
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
  kInvalidId = 32
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
    Nodes_.reserve(2 * items.size() / kLeafSize + 1);
    build(items, 0, items.size(), 0);
    Nodes_.shrink_to_fit();
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
    const bool optional = n >= 4 && ids[n] == -1;
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
  for (int k = 0; k < 4; ++k)
  {
    if (!std::isfinite(vertices[k].x) || !std::isfinite(vertices[k].y) ||
      !std::isfinite(vertices[k].z))
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
  for (int e = 0; e < 6; ++e)
  {
    if (ids[4 + e] >= 0)
    {
      const double* p = Mesh_.points + 3 * ids[4 + e];
      const glm::dvec3 midpoint =
        0.5 * (vertices[kEdgeVertices[e][0]] + vertices[kEdgeVertices[e][1]]);
      if (glm::length(glm::dvec3(p[0], p[1], p[2]) - midpoint) > kCurvedTolerance * maxEdge)
      {
        flags |= kCurved;
        break;
      }
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
    boxLo[axis] = boxHi[axis] = vertices[0][axis];
    for (int k = 1; k < 4; ++k)
    {
      boxLo[axis] = std::min(boxLo[axis], vertices[k][axis]);
      boxHi[axis] = std::max(boxHi[axis], vertices[k][axis]);
    }
    magnitude = std::max({ magnitude, std::abs(boxLo[axis]), std::abs(boxHi[axis]) });
  }
  const double pad = 1e-8 * maxEdge + 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
  for (int axis = 0; axis < 3; ++axis)
  {
    item.boxLo[axis] = roundDown(boxLo[axis] - pad - Origin_[axis]);
    item.boxHi[axis] = roundUp(boxHi[axis] + pad - Origin_[axis]);
  }
  return flags;
}

std::uint32_t Scene::build(
  std::vector<BuildItem>& items, std::size_t begin, std::size_t end, int depth)
{
  const auto index = static_cast<std::uint32_t>(Nodes_.size());
  Nodes_.emplace_back();
  Node node{};
  float centroidLo[3], centroidHi[3];
  for (int axis = 0; axis < 3; ++axis)
  {
    node.boxLo[axis] = centroidLo[axis] = kFloatInfinity;
    node.boxHi[axis] = centroidHi[axis] = -kFloatInfinity;
  }
  node.valueLo = kFloatInfinity;
  node.valueHi = -kFloatInfinity;
  for (std::size_t i = begin; i < end; ++i)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      node.boxLo[axis] = std::min(node.boxLo[axis], items[i].boxLo[axis]);
      node.boxHi[axis] = std::max(node.boxHi[axis], items[i].boxHi[axis]);
      centroidLo[axis] = std::min(centroidLo[axis], items[i].centroid(axis));
      centroidHi[axis] = std::max(centroidHi[axis], items[i].centroid(axis));
    }
    node.valueLo = std::min(node.valueLo, items[i].valueLo);
    node.valueHi = std::max(node.valueHi, items[i].valueHi);
  }
  const std::size_t count = end - begin;
  int axis = 0;
  for (int a = 1; a < 3; ++a)
  {
    if (centroidHi[a] - centroidLo[a] > centroidHi[axis] - centroidLo[axis])
    {
      axis = a;
    }
  }
  const float extent = centroidHi[axis] - centroidLo[axis];
  if (count <= static_cast<std::size_t>(kLeafSize) || !(extent > 0.0f))
  {
    node.firstOrSecondChild = static_cast<std::uint32_t>(begin);
    node.count = static_cast<std::uint16_t>(count);
    node.axis = static_cast<std::uint16_t>(axis);
    Nodes_[index] = node;
    return index;
  }

  std::size_t middle = begin + count / 2;
  bool split = false;
  if (depth < kMaxSahDepth)
  {
    // Binned surface area heuristic over centroids: cost of a split = area * count per side.
    struct Bin
    {
      float lo[3] = { kFloatInfinity, kFloatInfinity, kFloatInfinity };
      float hi[3] = { -kFloatInfinity, -kFloatInfinity, -kFloatInfinity };
      std::size_t count = 0;
      void grow(const float boxLo[3], const float boxHi[3])
      {
        for (int a = 0; a < 3; ++a)
        {
          lo[a] = std::min(lo[a], boxLo[a]);
          hi[a] = std::max(hi[a], boxHi[a]);
        }
      }
      double area() const
      {
        const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
        return count ? dx * dy + dy * dz + dz * dx : 0.0;
      }
    } bins[kBins];
    const float scale = kBins / extent;
    const float lo = centroidLo[axis];
    auto binOf = [&](const BuildItem& item) {
      return std::min(kBins - 1, static_cast<int>((item.centroid(axis) - lo) * scale));
    };
    for (std::size_t i = begin; i < end; ++i)
    {
      Bin& bin = bins[binOf(items[i])];
      ++bin.count;
      bin.grow(items[i].boxLo, items[i].boxHi);
    }
    double rightCost[kBins];
    Bin accumulated;
    for (int b = kBins - 1; b > 0; --b)
    {
      accumulated.count += bins[b].count;
      accumulated.grow(bins[b].lo, bins[b].hi);
      rightCost[b] = accumulated.area() * accumulated.count;
    }
    Bin left;
    double bestCost = std::numeric_limits<double>::infinity();
    int bestBin = -1;
    for (int b = 1; b < kBins; ++b)
    {
      left.count += bins[b - 1].count;
      left.grow(bins[b - 1].lo, bins[b - 1].hi);
      if (left.count == 0 || left.count == count)
      {
        continue;
      }
      const double cost = left.area() * left.count + rightCost[b];
      if (cost < bestCost)
      {
        bestCost = cost;
        bestBin = b;
      }
    }
    if (bestBin > 0)
    {
      const auto it = std::partition(items.begin() + begin, items.begin() + end,
        [&](const BuildItem& item) { return binOf(item) < bestBin; });
      middle = static_cast<std::size_t>(it - items.begin());
      split = middle > begin && middle < end;
    }
  }
  if (!split)
  {
    middle = begin + count / 2;
    std::nth_element(items.begin() + begin, items.begin() + middle, items.begin() + end,
      [axis](const BuildItem& x, const BuildItem& y) { return x.centroid(axis) < y.centroid(axis); });
  }
  node.count = 0;
  node.axis = static_cast<std::uint16_t>(axis);
  build(items, begin, middle, depth + 1);
  node.firstOrSecondChild = build(items, middle, end, depth + 1);
  Nodes_[index] = node;
  return index;
}

void Scene::loadCell(NodeId cellId, glm::dvec3 vertices[4], double values[10]) const
{
  const NodeId* ids = Mesh_.cellNodes + 10 * cellId;
  for (int k = 0; k < 4; ++k)
  {
    const double* p = Mesh_.points + 3 * ids[k];
    vertices[k] = glm::dvec3(p[0], p[1], p[2]);
    values[k] = Mesh_.values[ids[k]];
  }
  for (int e = 0; e < 6; ++e)
  {
    const NodeId id = ids[4 + e];
    values[4 + e] = id >= 0
      ? Mesh_.values[id]
      : 0.5 * (values[kEdgeVertices[e][0]] + values[kEdgeVertices[e][1]]);
  }
}

bool Scene::intersectCell(NodeId cellId, const Ray& ray, const IsoValues& isoValues,
  double tLimit, SurfaceHit& hit) const
{
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
  const glm::dvec3 centroid = 0.25 * (vertices[0] + vertices[1] + vertices[2] + vertices[3]);
  const double tCentre = glm::dot(centroid - ray.origin, ray.direction);
  const glm::dvec3 local = ray.origin + tCentre * ray.direction;
  double L[4], dL[4];
  frame.barycentric(local, L);
  frame.barycentricDirection(ray.direction, dL);

  // Entry and exit: the tet is {L_k >= 0}; each L_k(s) = L_k + s dL_k is affine in s.
  double sEntry = -tCentre; // t >= 0
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

  // The field along the ray, exactly: f(s) = a s^2 + b s + c (see QuadraticTet.h).
  const BernsteinForm form = BernsteinForm::fromNodeValues(values);
  const double a = form.bilinear(dL, dL);
  const double b = 2.0 * form.bilinear(L, dL);
  const double c = form.bilinear(L, L);
  double cellLo, cellHi;
  Transverse_.range(values, cellLo, cellHi);

  bool found = false;
  double sHit = sExit;
  for (double isoValue : isoValues.sorted())
  {
    if (isoValue < cellLo || isoValue > cellHi)
    {
      continue; // not transverse for this iso-value
    }
    double s;
    if (firstRootInInterval(a, b, c - isoValue, sEntry, sHit, s))
    {
      found = true;
      sHit = s;
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
  hit.cellId = cellId;
  hit.gradient = fieldGradient(form, frame, LHit);
  return true;
}

bool Scene::firstHit(const Ray& ray, const IsoValues& isoValues, SurfaceHit& hit) const
{
  if (Nodes_.empty() || !isoValues.anyWithin(Nodes_[0].valueLo, Nodes_[0].valueHi))
  {
    return false;
  }
  // Boxes are relative to Origin_; cells are tested in world coordinates.
  const glm::dvec3 origin = ray.origin - Origin_;
  const glm::dvec3 inverse = rayInverse(ray.direction);
  struct Entry
  {
    std::uint32_t node;
    double tEnter;
  } stack[kStackSize];
  int top = 0;
  double best = kInfinity;
  double tEnter;
  if (rayBox(origin, inverse, Nodes_[0].boxLo, Nodes_[0].boxHi, 0.0, best, tEnter))
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
          intersectCell(SlotCell_[slot], ray, isoValues, best, hit))
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
        rayBox(origin, inverse, child.boxLo, child.boxHi, 0.0, best, enter[c]);
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
    SlotRange_.capacity() * sizeof(float);
}

} // namespace tetdsr
