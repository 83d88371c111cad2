#include "tetdsr/Scene.h"

#include "tetdsr/CurvedTet.h"
#include "tetdsr/Hierarchy.h"
#include "tetdsr/QuadraticTet.h"
#include "tetdsr/Roots.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
// Preprocessing works in chunks of this many cells (merged in order: deterministic).
constexpr NodeId kChunkCells = 1 << 14;

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

/// The longest edge of a tet. sqrt is monotonic and correctly rounded: one root of the largest
/// square is the largest length.
double longestEdge(const glm::dvec3 vertices[4])
{
  double longest2 = 0.0;
  for (const auto& edge : kEdgeVertices)
  {
    const glm::dvec3 d = vertices[edge[0]] - vertices[edge[1]];
    longest2 = std::max(longest2, glm::dot(d, d));
  }
  return std::sqrt(longest2);
}

/// A cell's extent: its vertices' box, or for a curved cell its control points' (the curved cell
/// lies in their convex hull); false if that is not finite.
bool cellExtent(const glm::dvec3 nodes[10], double maxEdge, bool curved, glm::dvec3& lo, glm::dvec3& hi)
{
  lo = glm::min(glm::min(nodes[0], nodes[1]), glm::min(nodes[2], nodes[3]));
  hi = glm::max(glm::max(nodes[0], nodes[1]), glm::max(nodes[2], nodes[3]));
  if (curved)
  {
    CurvedGeometry::fromNodes(nodes, scaleFor(maxEdge)).box(lo, hi);
  }
  return isFinite(lo) && isFinite(hi);
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
    // The min and max of the Bernstein coefficients (BernsteinForm), without forming the matrix.
    lo = hi = nodeValues[0];
    for (int i = 1; i < 4; ++i)
    {
      lo = std::min(lo, nodeValues[i]);
      hi = std::max(hi, nodeValues[i]);
    }
    for (int e = 0; e < 6; ++e)
    {
      const double coefficient = 2.0 * nodeValues[4 + e] -
        0.5 * (nodeValues[kEdgeVertices[e][0]] + nodeValues[kEdgeVertices[e][1]]);
      lo = std::min(lo, coefficient);
      hi = std::max(hi, coefficient);
    }
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
  // Work in fixed chunks of cells, each chunk's results merged in chunk order: the outcome does
  // not depend on how parallelFor spreads the chunks over threads.
  const NodeId chunks = (mesh.numberOfCells + kChunkCells - 1) / kChunkCells;
  auto forChunks = [&](const std::function<void(NodeId chunk, NodeId begin, NodeId end)>& body) {
    parallelFor(chunks, [&](NodeId first, NodeId last) {
      for (NodeId chunk = first; chunk < last; ++chunk)
      {
        body(chunk, chunk * kChunkCells, std::min(mesh.numberOfCells, (chunk + 1) * kChunkCells));
      }
    });
  };

  // The boxes' unit: a power of two near the extent of the cells' vertices around Origin_, so
  // float boxes resolve scenes of any size in double range (float alone stops near 1e-38).
  std::vector<double> chunkExtent(static_cast<std::size_t>(chunks), 0.0);
  forChunks([&](NodeId chunk, NodeId begin, NodeId end) {
    double extent = 0.0;
    for (NodeId cell = begin; cell < end; ++cell)
    {
      for (int k = 0; k < 4; ++k)
      {
        const NodeId id = mesh.cellNodes[10 * cell + k];
        if (id >= 0 && id < mesh.numberOfPoints)
        {
          for (int a = 0; a < 3; ++a)
          {
            const double offset = std::abs(mesh.points[3 * id + a] - Origin_[a]);
            extent = std::isfinite(offset) ? std::max(extent, offset) : extent;
          }
        }
      }
    }
    chunkExtent[static_cast<std::size_t>(chunk)] = extent;
  });
  double extent = 0.0;
  for (const double chunk : chunkExtent)
  {
    extent = std::max(extent, chunk);
  }
  BoxScale_ = scaleFor(extent);

  // Validate every cell, each writing only its own slot, and count per chunk...
  const auto cells = static_cast<std::size_t>(mesh.numberOfCells);
  ValidCells_.resize(cells);
  FillLaterVector<std::uint8_t> status(cells);
  std::vector<PreprocessSummary> chunkSummary(static_cast<std::size_t>(chunks));
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  std::vector<glm::dvec3> chunkLo(static_cast<std::size_t>(chunks), glm::dvec3(kInfinity));
  std::vector<glm::dvec3> chunkHi(static_cast<std::size_t>(chunks), glm::dvec3(-kInfinity));
  forChunks([&](NodeId chunk, NodeId begin, NodeId end) {
    PreprocessSummary& summary = chunkSummary[static_cast<std::size_t>(chunk)];
    glm::dvec3& aroundLo = chunkLo[static_cast<std::size_t>(chunk)];
    glm::dvec3& aroundHi = chunkHi[static_cast<std::size_t>(chunk)];
    for (NodeId cell = begin; cell < end; ++cell)
    {
      const auto c = static_cast<std::size_t>(cell);
      glm::dvec3 lo, hi;
      const std::uint8_t flags = validate(cell, ValidCells_[c], lo, hi);
      if (flags & kValid)
      {
        aroundLo = glm::min(aroundLo, lo);
        aroundHi = glm::max(aroundHi, hi);
      }
      status[c] = flags;
      summary.validCells += (flags & kValid) != 0;
      summary.invertedCells += (flags & kInverted) != 0;
      summary.curvedCells += (flags & kCurved) != 0;
      summary.degenerateCells += (flags & kDegenerate) != 0;
      summary.nonFiniteCells += (flags & kNonFinite) != 0;
      summary.invalidIdCells += (flags & kInvalidId) != 0;
      summary.outOfScaleCells += (flags & kOutOfScale) != 0;
      summary.tangledCells += (flags & kTangled) != 0;
    }
  });
  for (const PreprocessSummary& summary : chunkSummary)
  {
    Summary_.validCells += summary.validCells;
    Summary_.invertedCells += summary.invertedCells;
    Summary_.curvedCells += summary.curvedCells;
    Summary_.degenerateCells += summary.degenerateCells;
    Summary_.nonFiniteCells += summary.nonFiniteCells;
    Summary_.invalidIdCells += summary.invalidIdCells;
    Summary_.outOfScaleCells += summary.outOfScaleCells;
    Summary_.tangledCells += summary.tangledCells;
  }
  if (Summary_.curvedCells > 0)
  {
    Curved_.assign(cells, 0);
    for (std::size_t cell = 0; cell < cells; ++cell)
    {
      Curved_[cell] = (status[cell] & kValid) && (status[cell] & kCurved);
    }
  }
  // ...then keep the valid ones, in cell order (nothing moves when all are valid).
  const auto valid = static_cast<std::size_t>(Summary_.validCells);
  if (valid < cells)
  {
    std::size_t kept = 0;
    for (std::size_t cell = 0; cell < cells; ++cell)
    {
      if (status[cell] & kValid)
      {
        ValidCells_[kept++] = ValidCells_[cell];
      }
    }
    ValidCells_.resize(valid);
    ValidCells_.shrink_to_fit();
  }
  // The box around every valid cell (box units), padded as cell boxes are (boxOf).
  glm::dvec3 lo(kInfinity), hi(-kInfinity);
  for (std::size_t chunk = 0; chunk < chunkLo.size(); ++chunk)
  {
    lo = glm::min(lo, chunkLo[chunk]);
    hi = glm::max(hi, chunkHi[chunk]);
  }
  if (valid > 0)
  {
    double magnitude = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      magnitude = std::max({ magnitude, std::abs(lo[a]), std::abs(hi[a]) });
    }
    const double pad =
      1e-8 * glm::length(hi - lo) + 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
    for (int a = 0; a < 3; ++a)
    {
      BoxLo_[a] = roundDown((lo[a] - pad - Origin_[a]) * BoxScale_);
      BoxHi_[a] = roundUp((hi[a] + pad - Origin_[a]) * BoxScale_);
    }
  }
}

Scene::~Scene() = default;

bool Scene::boxOf(const glm::dvec3 nodes[10], double maxEdge, bool curved, BoxItem& box) const
{
  glm::dvec3 extentLo, extentHi;
  if (!cellExtent(nodes, maxEdge, curved, extentLo, extentHi))
  {
    return false;
  }
  // Pad boxes so that rounding in the slab test never drops a ray that the (widened) cell
  // clip accepts: relative to the cell size and to the coordinates' own magnitude.
  double magnitude = 0.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    magnitude = std::max({ magnitude, std::abs(extentLo[axis]), std::abs(extentHi[axis]) });
  }
  const double pad = 1e-8 * maxEdge + 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
  for (int axis = 0; axis < 3; ++axis)
  {
    box.lo[axis] = roundDown((extentLo[axis] - pad - Origin_[axis]) * BoxScale_);
    box.hi[axis] = roundUp((extentHi[axis] + pad - Origin_[axis]) * BoxScale_);
  }
  return true;
}

BoxItem Scene::cellBox(NodeId cellId) const
{
  glm::dvec3 nodes[10];
  loadNodes(cellId, nodes);
  BoxItem box;
  boxOf(nodes, longestEdge(nodes), isCurved(cellId), box); // succeeded when validated
  box.id = static_cast<std::uint32_t>(cellId);
  return box;
}

std::uint8_t Scene::validate(
  NodeId cell, ValidCell& validCell, glm::dvec3& extentLo, glm::dvec3& extentHi) const
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
  // Every node's value and coordinates (a missing mid-edge node: its edge's midpoint and mean).
  glm::dvec3 nodes[10];
  double values[10];
  for (int n = 0; n < 10; ++n)
  {
    const NodeId id = ids[n];
    if (id >= 0)
    {
      nodes[n] = glm::dvec3(Mesh_.points[3 * id], Mesh_.points[3 * id + 1], Mesh_.points[3 * id + 2]);
      values[n] = Mesh_.values[id];
    }
    else
    {
      const int a = kEdgeVertices[n - 4][0], b = kEdgeVertices[n - 4][1];
      nodes[n] = 0.5 * (nodes[a] + nodes[b]);
      values[n] = 0.5 * (values[a] + values[b]);
    }
  }
  for (int n = 0; n < 10; ++n)
  {
    if (!std::isfinite(values[n]) || (ids[n] >= 0 && !isFinite(nodes[n])))
    {
      return kNonFinite;
    }
  }
  const glm::dvec3* vertices = nodes;
  const double maxEdge = longestEdge(vertices);
  if (!(maxEdge >= kMinCellSize && maxEdge <= kMaxCellSize)) // also an overflowed (Inf) length
  {
    return kOutOfScale;
  }
  // 6 x the signed volume, as TetFrame::fromVertices computes it (its frame is not needed here).
  const glm::dvec3 e1 = vertices[1] - vertices[0];
  const double volume6 =
    glm::dot(e1, glm::cross(vertices[2] - vertices[0], vertices[3] - vertices[0]));
  if (!std::isfinite(volume6) ||
    std::abs(volume6) <= kDegenerateVolumeRatio * maxEdge * maxEdge * maxEdge)
  {
    return kDegenerate;
  }
  std::uint8_t flags = kValid;
  if (volume6 < 0.0)
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
    const glm::dvec3 offset =
      nodes[4 + e] - 0.5 * (vertices[kEdgeVertices[e][0]] + vertices[kEdgeVertices[e][1]]);
    // Components within half the tolerance put the length within it (sqrt(3) / 2 < 1): the
    // length is only needed for the rare others.
    const double largest = std::max({ std::abs(offset.x), std::abs(offset.y), std::abs(offset.z) });
    if (largest > 0.5 * curvedTolerance && glm::length(offset) > curvedTolerance)
    {
      flags |= kCurved;
      break;
    }
  }
  if (flags & kCurved)
  {
    const JacobianSign sign = jacobianSign(CurvedGeometry::fromNodes(nodes, scaleFor(maxEdge)));
    if (sign == JacobianSign::Changes)
    {
      return kTangled;
    }
    flags = static_cast<std::uint8_t>((flags & ~kInverted) | (sign == JacobianSign::Negative ? kInverted : 0));
  }
  if (!cellExtent(nodes, maxEdge, (flags & kCurved) != 0, extentLo, extentHi))
  {
    return kOutOfScale;
  }
  validCell.id = static_cast<std::uint32_t>(cell);
  double lo, hi;
  Transverse_.range(values, lo, hi);
  validCell.valueLo = roundDown(lo);
  validCell.valueHi = roundUp(hi);
  return flags;
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
BernsteinForm scaledFieldForm(double values[10], double& scale, double& lo, double& hi)
{
  scale = unitScale(values);
  for (int n = 0; n < 10; ++n)
  {
    values[n] *= scale;
  }
  const BernsteinForm form = BernsteinForm::fromNodeValues(values);
  form.range(lo, hi);
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
  BernsteinForm equations[3];
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
  BernsteinForm equations[3];
  equations[0] = geometry.component(u, glm::dot(u, o));
  equations[1] = geometry.component(v, glm::dot(v, o));
  const BernsteinForm depth = geometry.component(d, glm::dot(d, o));
  const double lo = tMin * s - tCentre;
  const double hi = tLimit * s - tCentre;

  double scale, boundLo, boundHi;
  const BernsteinForm field = scaledFieldForm(values, scale, boundLo, boundHi);
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
        const BernsteinForm faceEquations[2] = { equations[0].face(face), equations[1].face(face) };
        const BernsteinForm faceDepth = depth.face(face);
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

void Scene::prepareCell(NodeId cellId, CellRecord& cell) const
{
  cell.cellId = static_cast<std::uint32_t>(cellId);
  cell.kind = CellRecord::Kind::Empty;
  glm::dvec3 vertices[4];
  double values[10];
  loadCell(cellId, vertices, values);
  // The range the transverse test gives (which iso-values the cell can hold).
  Transverse_.range(values, cell.valueLo, cell.valueHi);
  if (isCurved(cellId))
  {
    cell.kind = CellRecord::Kind::Curved; // solved from the mesh (intersectCurvedCell)
    return;
  }
  TetFrame frame;
  if (!TetFrame::fromVertices(vertices, frame))
  {
    return; // (not for a valid cell)
  }
  cell.vertex0 = vertices[0];
  cell.vertex1 = vertices[1];
  cell.centroidOffset =
    0.25 * ((vertices[1] - vertices[0]) + (vertices[2] - vertices[0]) + (vertices[3] - vertices[0]));
  for (int k = 0; k < 3; ++k)
  {
    cell.gradient[k] = frame.gradient[k + 1];
  }
  // Scale the field by a power of two (exact) so that its largest nodal magnitude is about 1:
  // the products in the quadratic's coefficients and its discriminant (field^2) then neither
  // overflow nor underflow, whatever the field's scale within double range.
  cell.scale = unitScale(values);
  for (double& value : values)
  {
    value *= cell.scale;
  }
  const BernsteinForm form = BernsteinForm::fromNodeValues(values);
  for (int i = 0; i < 4; ++i)
  {
    cell.form[i] = form.b[i][i];
  }
  for (int e = 0; e < 6; ++e)
  {
    cell.form[4 + e] = form.b[kEdgeVertices[e][0]][kEdgeVertices[e][1]];
  }
  // A field constant over the cell (to rounding): the Bernstein bound (a true bound whatever
  // the transverse test) is within rounding of one value.
  double boundLo, boundHi;
  form.range(boundLo, boundHi);
  cell.kind = constantToRounding(boundLo, boundHi) ? CellRecord::Kind::Constant
                                                   : CellRecord::Kind::Quadratic;
}


std::size_t Scene::memoryBytes() const
{
  return ValidCells_.capacity() * sizeof(ValidCell) +
    (Locator_ ? Locator_->memoryBytes() : 0) + NodalGradients_.capacity() * sizeof(glm::dvec3) +
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
  return longestEdge(vertices);
}

bool Scene::locate(const glm::dvec3& point, NodeId& cellId) const
{
  if (ValidCells_.empty())
  {
    return false;
  }
  std::call_once(LocatorBuilt_, [this] {
    std::vector<BoxItem> boxes(ValidCells_.size());
    for (std::size_t k = 0; k < boxes.size(); ++k)
    {
      boxes[k] = cellBox(ValidCells_[k].id);
    }
    Locator_ = std::make_unique<Hierarchy>();
    Locator_->build(std::move(boxes), serialFor);
  });
  const std::vector<std::uint32_t>& ids = Locator_->ids();
  return Locator_->containing(toBoxUnits(point), [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t k = first; k < first + count; ++k)
    {
      double L[4];
      if (inCell(ids[k], point, L))
      {
        cellId = ids[k];
        return true;
      }
    }
    return false;
  });
}

bool Scene::bounds(double box[6]) const
{
  if (ValidCells_.empty())
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    box[2 * a] = Origin_[a] + static_cast<double>(BoxLo_[a]) / BoxScale_;
    box[2 * a + 1] = Origin_[a] + static_cast<double>(BoxHi_[a]) / BoxScale_;
  }
  return true;
}

double Scene::diagonal() const
{
  if (ValidCells_.empty())
  {
    return 0.0;
  }
  return glm::length(glm::dvec3(BoxHi_[0] - BoxLo_[0], BoxHi_[1] - BoxLo_[1],
           BoxHi_[2] - BoxLo_[2])) / BoxScale_;
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
  for (const ValidCell& valid : ValidCells_)
  {
    const std::uint32_t cell = valid.id;
    glm::dvec3 vertices[4];
    double values[10];
    loadCell(cell, vertices, values);
    for (const double value : values)
    {
      largest = std::max(largest, std::abs(value));
    }
  }
  const double scale = scaleFor(largest);
  for (const ValidCell& valid : ValidCells_)
  {
    const std::uint32_t cell = valid.id;
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
    if (curved)
    {
      glm::dvec3 nodes[10];
      loadNodes(cell, nodes);
      geometry = localGeometry(nodes);
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
        ? curvedGradient(geometry, form, L) * geometry.scale
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
