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

// Slab test of the ray against an axis-aligned box, clipped to [tLo, tHi].
bool rayBox(const Ray& ray, const glm::dvec3& inverseDirection, const double lo[3],
  const double hi[3], double tLo, double tHi, double& tEnter)
{
  for (int axis = 0; axis < 3; ++axis)
  {
    if (ray.direction[axis] == 0.0)
    {
      if (ray.origin[axis] < lo[axis] || ray.origin[axis] > hi[axis])
      {
        return false;
      }
      continue;
    }
    double t0 = (lo[axis] - ray.origin[axis]) * inverseDirection[axis];
    double t1 = (hi[axis] - ray.origin[axis]) * inverseDirection[axis];
    if (t0 > t1)
    {
      std::swap(t0, t1);
    }
    tLo = std::max(tLo, t0);
    tHi = std::min(tHi, t1);
    if (tLo > tHi)
    {
      return false;
    }
  }
  tEnter = tLo;
  return true;
}
} // namespace

IsoValues::IsoValues(std::vector<double> values)
  : Sorted_(std::move(values))
{
  std::sort(Sorted_.begin(), Sorted_.end());
}

bool IsoValues::anyWithin(double lo, double hi) const
{
  const auto it = std::lower_bound(Sorted_.begin(), Sorted_.end(), lo);
  return it != Sorted_.end() && *it <= hi;
}

struct Scene::BuildItem
{
  double boxLo[3];
  double boxHi[3];
  double centroid[3];
  double valueLo;
  double valueHi;
  NodeId cellId;
};

Scene::Scene(const MeshView& mesh)
  : Mesh_(mesh)
{
  std::vector<BuildItem> items;
  items.reserve(static_cast<std::size_t>(mesh.numberOfCells));
  for (NodeId cell = 0; cell < mesh.numberOfCells; ++cell)
  {
    const NodeId* ids = mesh.cellNodes + 10 * cell;
    bool idsInRange = true;
    for (int n = 0; n < 10; ++n)
    {
      const bool optional = n >= 4 && ids[n] == -1;
      idsInRange = idsInRange && (optional || (ids[n] >= 0 && ids[n] < mesh.numberOfPoints));
    }
    if (!idsInRange)
    {
      ++Summary_.invalidIdCells;
      continue;
    }
    if (!distinctIds(ids))
    {
      ++Summary_.degenerateCells;
      continue;
    }
    glm::dvec3 vertices[4];
    double values[10];
    loadCell(cell, vertices, values);
    bool finite = true;
    for (int n = 0; n < 10; ++n)
    {
      finite = finite && std::isfinite(values[n]);
    }
    for (int k = 0; k < 4; ++k)
    {
      finite = finite && std::isfinite(vertices[k].x) && std::isfinite(vertices[k].y) &&
        std::isfinite(vertices[k].z);
    }
    if (!finite)
    {
      ++Summary_.nonFiniteCells;
      continue;
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
      ++Summary_.degenerateCells;
      continue;
    }
    if (frame.orientedVolume6 < 0.0)
    {
      ++Summary_.invertedCells;
    }
    for (int e = 0; e < 6; ++e)
    {
      if (ids[4 + e] < 0)
      {
        continue;
      }
      const double* p = mesh.points + 3 * ids[4 + e];
      const glm::dvec3 midpoint =
        0.5 * (vertices[kEdgeVertices[e][0]] + vertices[kEdgeVertices[e][1]]);
      if (glm::length(glm::dvec3(p[0], p[1], p[2]) - midpoint) > kCurvedTolerance * maxEdge)
      {
        ++Summary_.curvedCells;
        break;
      }
    }
    ++Summary_.validCells;

    BuildItem item;
    item.cellId = cell;
    BernsteinForm::fromNodeValues(values).range(item.valueLo, item.valueHi);
    // Pad boxes so that rounding in the slab test never drops a ray that the (widened) cell
    // clip accepts: relative to the cell size and to the coordinates' own magnitude.
    double magnitude = 0.0;
    for (int axis = 0; axis < 3; ++axis)
    {
      item.boxLo[axis] = item.boxHi[axis] = vertices[0][axis];
      for (int k = 1; k < 4; ++k)
      {
        item.boxLo[axis] = std::min(item.boxLo[axis], vertices[k][axis]);
        item.boxHi[axis] = std::max(item.boxHi[axis], vertices[k][axis]);
      }
      magnitude = std::max({ magnitude, std::abs(item.boxLo[axis]), std::abs(item.boxHi[axis]) });
    }
    const double pad = 1e-8 * maxEdge + 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
    for (int axis = 0; axis < 3; ++axis)
    {
      item.boxLo[axis] -= pad;
      item.boxHi[axis] += pad;
      item.centroid[axis] = 0.5 * (item.boxLo[axis] + item.boxHi[axis]);
    }
    items.push_back(item);
  }

  SlotCell_.resize(items.size());
  SlotRange_.resize(2 * items.size());
  if (!items.empty())
  {
    Nodes_.reserve(2 * items.size() / kLeafSize + 1);
    build(items, 0, items.size(), 0);
  }
  for (std::size_t slot = 0; slot < items.size(); ++slot)
  {
    SlotCell_[slot] = items[slot].cellId;
    SlotRange_[2 * slot] = items[slot].valueLo;
    SlotRange_[2 * slot + 1] = items[slot].valueHi;
  }
  Nodes_.shrink_to_fit();
}

NodeId Scene::build(
  std::vector<BuildItem>& items, std::size_t begin, std::size_t end, int depth)
{
  const NodeId index = static_cast<NodeId>(Nodes_.size());
  Nodes_.emplace_back();
  Node node{};
  double centroidLo[3], centroidHi[3];
  for (int axis = 0; axis < 3; ++axis)
  {
    node.boxLo[axis] = centroidLo[axis] = kInfinity;
    node.boxHi[axis] = centroidHi[axis] = -kInfinity;
  }
  node.valueLo = kInfinity;
  node.valueHi = -kInfinity;
  for (std::size_t i = begin; i < end; ++i)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      node.boxLo[axis] = std::min(node.boxLo[axis], items[i].boxLo[axis]);
      node.boxHi[axis] = std::max(node.boxHi[axis], items[i].boxHi[axis]);
      centroidLo[axis] = std::min(centroidLo[axis], items[i].centroid[axis]);
      centroidHi[axis] = std::max(centroidHi[axis], items[i].centroid[axis]);
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
  const double extent = centroidHi[axis] - centroidLo[axis];
  if (count <= static_cast<std::size_t>(kLeafSize) || extent <= 0.0)
  {
    node.firstOrSecondChild = static_cast<NodeId>(begin);
    node.count = static_cast<std::int32_t>(count);
    node.axis = axis;
    Nodes_[static_cast<std::size_t>(index)] = node;
    return index;
  }

  std::size_t middle = begin + count / 2;
  bool split = false;
  if (depth < kMaxSahDepth)
  {
    // Binned surface area heuristic over centroids: cost of a split = area * count per side.
    struct Bin
    {
      double lo[3] = { kInfinity, kInfinity, kInfinity };
      double hi[3] = { -kInfinity, -kInfinity, -kInfinity };
      std::size_t count = 0;
    } bins[kBins];
    const double scale = kBins / extent;
    auto binOf = [&](const BuildItem& item) {
      return std::min(kBins - 1, static_cast<int>((item.centroid[axis] - centroidLo[axis]) * scale));
    };
    for (std::size_t i = begin; i < end; ++i)
    {
      Bin& bin = bins[binOf(items[i])];
      ++bin.count;
      for (int a = 0; a < 3; ++a)
      {
        bin.lo[a] = std::min(bin.lo[a], items[i].boxLo[a]);
        bin.hi[a] = std::max(bin.hi[a], items[i].boxHi[a]);
      }
    }
    auto area = [](const double lo[3], const double hi[3]) {
      const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
      return dx * dy + dy * dz + dz * dx;
    };
    double rightArea[kBins];
    std::size_t rightCount[kBins];
    Bin accumulated;
    for (int b = kBins - 1; b > 0; --b)
    {
      accumulated.count += bins[b].count;
      for (int a = 0; a < 3; ++a)
      {
        accumulated.lo[a] = std::min(accumulated.lo[a], bins[b].lo[a]);
        accumulated.hi[a] = std::max(accumulated.hi[a], bins[b].hi[a]);
      }
      rightArea[b] = accumulated.count ? area(accumulated.lo, accumulated.hi) : 0.0;
      rightCount[b] = accumulated.count;
    }
    Bin left;
    double bestCost = kInfinity;
    int bestBin = -1;
    for (int b = 1; b < kBins; ++b)
    {
      left.count += bins[b - 1].count;
      for (int a = 0; a < 3; ++a)
      {
        left.lo[a] = std::min(left.lo[a], bins[b - 1].lo[a]);
        left.hi[a] = std::max(left.hi[a], bins[b - 1].hi[a]);
      }
      if (left.count == 0 || rightCount[b] == 0)
      {
        continue;
      }
      const double cost = area(left.lo, left.hi) * left.count + rightArea[b] * rightCount[b];
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
      [axis](const BuildItem& x, const BuildItem& y) { return x.centroid[axis] < y.centroid[axis]; });
  }
  node.count = 0;
  node.axis = axis;
  build(items, begin, middle, depth + 1);
  node.firstOrSecondChild = build(items, middle, end, depth + 1);
  Nodes_[static_cast<std::size_t>(index)] = node;
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
  form.range(cellLo, cellHi);

  bool found = false;
  double sHit = sExit;
  for (double isoValue : isoValues.sorted())
  {
    if (isoValue < cellLo || isoValue > cellHi)
    {
      continue; // Bernstein bound: this iso-value is not reached inside the cell
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
  if (Nodes_.empty())
  {
    return false;
  }
  const glm::dvec3 inverseDirection = 1.0 / ray.direction;
  struct Entry
  {
    NodeId node;
    double tEnter;
  } stack[kStackSize];
  int top = 0;
  double best = kInfinity;
  double tEnter;
  if (rayBox(ray, inverseDirection, Nodes_[0].boxLo, Nodes_[0].boxHi, 0.0, best, tEnter))
  {
    stack[top++] = { 0, tEnter };
  }
  bool found = false;
  while (top > 0)
  {
    const Entry entry = stack[--top];
    const Node& node = Nodes_[static_cast<std::size_t>(entry.node)];
    if (entry.tEnter > best || !isoValues.anyWithin(node.valueLo, node.valueHi))
    {
      continue;
    }
    if (node.count > 0)
    {
      for (NodeId slot = node.firstOrSecondChild; slot < node.firstOrSecondChild + node.count;
           ++slot)
      {
        const auto s = static_cast<std::size_t>(slot);
        if (isoValues.anyWithin(SlotRange_[2 * s], SlotRange_[2 * s + 1]) &&
          intersectCell(SlotCell_[s], ray, isoValues, best, hit))
        {
          best = hit.t;
          found = true;
        }
      }
      continue;
    }
    // Visit the nearer child first: push it last.
    const NodeId children[2] = { entry.node + 1, node.firstOrSecondChild };
    double enter[2];
    bool hits[2];
    for (int c = 0; c < 2; ++c)
    {
      const Node& child = Nodes_[static_cast<std::size_t>(children[c])];
      hits[c] = rayBox(ray, inverseDirection, child.boxLo, child.boxHi, 0.0, best, enter[c]);
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
  return Nodes_.capacity() * sizeof(Node) + SlotCell_.capacity() * sizeof(NodeId) +
    SlotRange_.capacity() * sizeof(double);
}

} // namespace tetdsr
