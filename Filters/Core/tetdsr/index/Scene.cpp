#include "tetdsr/index/Scene.h"

#include "tetdsr/cells/CellKinds.h"
#include "tetdsr/index/Hierarchy.h"
#include "tetdsr/cells/HigherOrderTetCell.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
// Preprocessing works in chunks of this many cells (merged in order: deterministic).
constexpr NodeId kChunkCells = 1 << 14;

/// Whether no point id appears twice in a cell (a repeated one collapses it).
/// The largest magnitude of a value or a point's coordinates.
double magnitudeOf(double value)
{
  return std::abs(value);
}
double magnitudeOf(const glm::dvec3& point)
{
  return std::max({ std::abs(point.x), std::abs(point.y), std::abs(point.z) });
}

bool distinctIds(const NodeId* ids, int count)
{
  for (int i = 0; i < count; ++i)
  {
    for (int j = i + 1; j < count; ++j)
    {
      if (ids[i] == ids[j])
      {
        return false;
      }
    }
  }
  return true;
}

/// Adds one cell's validation outcome to the counts.
void count(std::uint16_t flags, PreprocessSummary& summary)
{
  summary.validCells += (flags & kValid) != 0;
  summary.invertedCells += (flags & kInverted) != 0;
  summary.curvedCells += (flags & kCurved) != 0;
  summary.degenerateCells += (flags & kDegenerate) != 0;
  summary.nonFiniteCells += (flags & kNonFinite) != 0;
  summary.invalidIdCells += (flags & kInvalidId) != 0;
  summary.outOfScaleCells += (flags & kOutOfScale) != 0;
  summary.tangledCells += (flags & kTangled) != 0;
  summary.unsupportedCells += (flags & kUnsupported) != 0;
  summary.malformedCells += (flags & kMalformed) != 0;
  summary.orderTooHighCells += (flags & kOrderTooHigh) != 0;
  summary.rationalCells += (flags & kRational) != 0;
  summary.higherOrderCells += (flags & kHigherOrder) != 0;
  summary.ghostCells += (flags & kGhost) != 0;
}

/// Adds counts to a total.
void add(const PreprocessSummary& part, PreprocessSummary& total)
{
  total.validCells += part.validCells;
  total.invertedCells += part.invertedCells;
  total.curvedCells += part.curvedCells;
  total.degenerateCells += part.degenerateCells;
  total.nonFiniteCells += part.nonFiniteCells;
  total.invalidIdCells += part.invalidIdCells;
  total.outOfScaleCells += part.outOfScaleCells;
  total.tangledCells += part.tangledCells;
  total.unsupportedCells += part.unsupportedCells;
  total.malformedCells += part.malformedCells;
  total.orderTooHighCells += part.orderTooHighCells;
  total.rationalCells += part.rationalCells;
  total.higherOrderCells += part.higherOrderCells;
  total.ghostCells += part.ghostCells;
}

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

void TransverseTest::range(const double nodeValues[kCellNodes], double& lo, double& hi) const
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
  lo = *std::min_element(nodeValues, nodeValues + kCellNodes);
  hi = *std::max_element(nodeValues, nodeValues + kCellNodes);
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
  chooseBoxUnits(parallelFor);
  FillLaterVector<std::uint16_t> status;
  glm::dvec3 lo, hi;
  validateCells(parallelFor, status, lo, hi);
  keepValidCells(status);
  setSceneBox(lo, hi);
}

bool Scene::layoutOf(NodeId cell, CellLayout& layout) const
{
  const NodeId begin = Mesh_.offsets[cell];
  const NodeId end = Mesh_.offsets[cell + 1];
  return begin >= 0 && end >= begin && end <= Mesh_.connectivitySize &&
    cellLayout(Mesh_.cellTypes[cell], end - begin, layout) == 0;
}

void Scene::forChunks(const ParallelFor& parallelFor,
  const std::function<void(NodeId chunk, NodeId begin, NodeId end)>& body) const
{
  const NodeId cells = Mesh_.numberOfCells;
  parallelFor((cells + kChunkCells - 1) / kChunkCells, [&](NodeId first, NodeId last) {
    for (NodeId chunk = first; chunk < last; ++chunk)
    {
      body(chunk, chunk * kChunkCells, std::min(cells, (chunk + 1) * kChunkCells));
    }
  });
}

void Scene::chooseBoxUnits(const ParallelFor& parallelFor)
{
  const MeshView& mesh = Mesh_;
  // Any finite vertex of the mesh will do as the origin of the float boxes.
  for (NodeId cell = 0; cell < mesh.numberOfCells; ++cell)
  {
    const NodeId id = readable(cell) ? mesh.connectivity[mesh.offsets[cell]] : -1;
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
  // Per chunk, merged in chunk order: the outcome does not depend on the threads.
  std::vector<double> chunkExtent(static_cast<std::size_t>((mesh.numberOfCells + kChunkCells - 1) / kChunkCells), 0.0);
  forChunks(parallelFor, [&](NodeId chunk, NodeId begin, NodeId end) {
    double extent = 0.0;
    for (NodeId cell = begin; cell < end; ++cell)
    {
      if (!readable(cell))
      {
        continue;
      }
      const NodeId* ids = mesh.connectivity + mesh.offsets[cell];
      for (int k = 0; k < 4; ++k)
      {
        const NodeId id = ids[k];
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
}

void Scene::validateCells(const ParallelFor& parallelFor, FillLaterVector<std::uint16_t>& status,
  glm::dvec3& lo, glm::dvec3& hi)
{
  // Every cell writes only its own slots; counts and boxes are kept per chunk and merged in
  // chunk order (deterministic for any number of threads).
  const auto cells = static_cast<std::size_t>(Mesh_.numberOfCells);
  const auto chunks = (cells + kChunkCells - 1) / kChunkCells;
  ValidCells_.resize(cells);
  status.resize(cells);
  std::vector<PreprocessSummary> chunkSummary(chunks);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  std::vector<glm::dvec3> chunkLo(chunks, glm::dvec3(kInfinity));
  std::vector<glm::dvec3> chunkHi(chunks, glm::dvec3(-kInfinity));
  forChunks(parallelFor, [&](NodeId chunk, NodeId begin, NodeId end) {
    PreprocessSummary& summary = chunkSummary[static_cast<std::size_t>(chunk)];
    glm::dvec3& aroundLo = chunkLo[static_cast<std::size_t>(chunk)];
    glm::dvec3& aroundHi = chunkHi[static_cast<std::size_t>(chunk)];
    for (NodeId cell = begin; cell < end; ++cell)
    {
      const auto c = static_cast<std::size_t>(cell);
      glm::dvec3 cellLo, cellHi;
      const std::uint16_t flags = validate(cell, ValidCells_[c], cellLo, cellHi);
      if (flags & kValid)
      {
        aroundLo = glm::min(aroundLo, cellLo);
        aroundHi = glm::max(aroundHi, cellHi);
      }
      status[c] = flags;
      count(flags, summary);
    }
  });
  for (const PreprocessSummary& summary : chunkSummary)
  {
    add(summary, Summary_);
  }
  lo = glm::dvec3(kInfinity);
  hi = glm::dvec3(-kInfinity);
  for (std::size_t chunk = 0; chunk < chunks; ++chunk)
  {
    lo = glm::min(lo, chunkLo[chunk]);
    hi = glm::max(hi, chunkHi[chunk]);
  }
}

void Scene::keepValidCells(const FillLaterVector<std::uint16_t>& status)
{
  const std::size_t cells = status.size();
  std::size_t valid = 0;
  bool anyCurved = false;
  for (const std::uint16_t flags : status)
  {
    valid += (flags & kValid) != 0;
    anyCurved = anyCurved || ((flags & kValid) && (flags & kCurved));
  }
  if (anyCurved)
  {
    Curved_.assign(cells, 0);
    for (std::size_t cell = 0; cell < cells; ++cell)
    {
      Curved_[cell] = (status[cell] & kValid) && (status[cell] & kCurved);
    }
  }
  // The valid ones, in cell order (nothing moves when all are valid).
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
}

void Scene::setSceneBox(const glm::dvec3& lo, const glm::dvec3& hi)
{
  if (ValidCells_.empty())
  {
    return;
  }
  // Padded as cell boxes are (boxOf).
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

Scene::~Scene() = default;

BoxItem Scene::boxOf(const glm::dvec3& extentLo, const glm::dvec3& extentHi, double maxEdge) const
{
  // Pad boxes so that rounding in the slab test never drops a ray that the (widened) cell
  // clip accepts: relative to the cell size and to the coordinates' own magnitude.
  double magnitude = 0.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    magnitude = std::max({ magnitude, std::abs(extentLo[axis]), std::abs(extentHi[axis]) });
  }
  const double pad = 1e-8 * maxEdge + 16.0 * std::numeric_limits<double>::epsilon() * magnitude;
  BoxItem box;
  for (int axis = 0; axis < 3; ++axis)
  {
    box.lo[axis] = roundDown((extentLo[axis] - pad - Origin_[axis]) * BoxScale_);
    box.hi[axis] = roundUp((extentHi[axis] + pad - Origin_[axis]) * BoxScale_);
  }
  return box;
}

BoxItem Scene::cellBox(NodeId cellId) const
{
  glm::dvec3 nodes[kMaxCellNodes];
  glm::dvec3 lo, hi;
  const bool asValidated = loadNodes(cellId, nodes) &&
    forKind(kindOf(cellId), [&](auto cell) { return decltype(cell)::extent(nodes, lo, hi); });
  if (!asValidated)
  {
    lo = hi = Origin_; // edited since validation: a point box (its record is empty, never hit)
  }
  // (A hexahedron's tensor form does not start with its corners: its box's diagonal for size.)
  const double size = !asValidated ? 0.0
    : isHexahedronKind(kindOf(cellId)) ? glm::length(hi - lo)
                                       : longestEdge(nodes);
  BoxItem box = boxOf(lo, hi, size);
  box.id = static_cast<std::uint32_t>(cellId);
  return box;
}

std::uint16_t Scene::validate(
  NodeId cell, ValidCell& validCell, glm::dvec3& extentLo, glm::dvec3& extentHi) const
{
  if (Mesh_.cellGhosts &&
    (Mesh_.cellGhosts[cell] & (kGhostDuplicateCell | kGhostHiddenCell)) != 0)
  {
    return kGhost;
  }
  CellLayout layout;
  const NodeId* ids = nullptr;
  if (const std::uint16_t unreadable = checkIds(cell, layout, ids))
  {
    return unreadable;
  }
  glm::dvec3 nodes[kMaxCellNodes];
  double values[kMaxCellNodes];
  std::uint16_t flags = checkNodes(layout, ids, nodes, values);
  if (!(flags & kValid))
  {
    return flags;
  }
  // A curved cell's box (its control points') can be far larger than its vertices' edges: a
  // mid-edge node at 1e300 passes the size check and would give the scene an overflowing box.
  const CellKind kind = tetdsr::kindOf(layout, (flags & kCurved) != 0);
  if (!forKind(kind, [&](auto cell) { return decltype(cell)::extent(nodes, extentLo, extentHi); }) ||
    !(std::max({ extentHi.x - extentLo.x, extentHi.y - extentLo.y, extentHi.z - extentLo.z }) <=
      QuadraticTetCell::kMaxCellSize))
  {
    return kOutOfScale;
  }
  validCell.id = static_cast<std::uint32_t>(cell);
  double lo, hi;
  forKind(kind, [&](auto cell) { decltype(cell)::valueBound(values, Transverse_, lo, hi); });
  validCell.valueLo = roundDown(lo);
  validCell.valueHi = roundUp(hi);
  return static_cast<std::uint16_t>(flags | (layout.order > 2 ? kHigherOrder : 0));
}

std::uint16_t Scene::checkIds(NodeId cell, CellLayout& layout, const NodeId*& ids) const
{
  // The type and offsets first: nothing of the cell is read before they are trusted.
  const int type = Mesh_.cellTypes[cell];
  if (cellLayout(type, -1, layout) == kUnsupported)
  {
    return kUnsupported;
  }
  const NodeId begin = Mesh_.offsets[cell];
  const NodeId end = Mesh_.offsets[cell + 1];
  if (!(begin >= 0 && end >= begin && end <= Mesh_.connectivitySize))
  {
    return kMalformed;
  }
  if (const std::uint16_t unreadable = cellLayout(type, end - begin, layout))
  {
    return unreadable;
  }
  ids = Mesh_.connectivity + begin;
  return checkNodeIds(Mesh_, ids, layout.nodes, layout.bezier);
}

std::uint16_t checkNodeIds(const MeshView& mesh, const NodeId* ids, int count, bool bezier)
{
  for (int n = 0; n < count; ++n)
  {
    if (ids[n] < 0 || ids[n] >= mesh.numberOfPoints)
    {
      return kInvalidId;
    }
  }
  if (!distinctIds(ids, count))
  {
    return kDegenerate;
  }
  if (bezier && mesh.rationalWeights)
  {
    // Equal weights cancel in the rational form: the cell is the polynomial one.
    const double first = mesh.rationalWeights[ids[0]];
    if (!(first > 0.0) || !std::isfinite(first))
    {
      return kRational;
    }
    for (int n = 1; n < count; ++n)
    {
      if (!(mesh.rationalWeights[ids[n]] == first))
      {
        return kRational;
      }
    }
  }
  return 0;
}

std::uint16_t Scene::checkNodes(const CellLayout& layout, const NodeId* ids,
  glm::dvec3 nodes[kMaxCellNodes], double values[kMaxCellNodes]) const
{
  // Every node's value and coordinates, as given.
  const int count = layout.nodes;
  for (int n = 0; n < count; ++n)
  {
    nodes[n] = glm::dvec3(Mesh_.points[3 * ids[n]], Mesh_.points[3 * ids[n] + 1], Mesh_.points[3 * ids[n] + 2]);
    values[n] = Mesh_.values[ids[n]];
    if (!std::isfinite(values[n]) || !isFinite(nodes[n]))
    {
      return kNonFinite;
    }
  }
  if (layout.hexahedron)
  {
    // A hexahedron is checked on its nodes as given (straight or not) and its tensor form (det J).
    glm::dvec3 given[kMaxCellNodes];
    std::copy(nodes, nodes + count, given);
    toKindForm(layout, nodes);
    toKindForm(layout, values);
    for (int n = 0; n < tensor::count(layout.order); ++n)
    {
      if (!std::isfinite(values[n]) || !isFinite(nodes[n]))
      {
        return kOutOfScale; // Bernstein coefficients beyond double range
      }
    }
    return forHexahedronOrder(layout.order, [&](auto P) {
      return HexahedronCell<decltype(P)::value, false>::validate(
        nodes, given, Mesh_.pointRounding, *layout.hexahedron);
    });
  }
  // Orders 3 and 4 are checked on their nodes as given (where the affine map puts a node is
  // where a Lagrange node or a Bezier control point sits), orders 1 and 2 on the quadratic
  // tetrahedron's nodes that their steps take (toKindForm).
  std::uint16_t flags = layout.order <= 2 ? 0 : forHigherOrder(layout.order, [&](auto P) {
    return HigherOrderTetCell<decltype(P)::value>::validate(nodes, Mesh_.pointRounding);
  });
  toKindForm(layout, nodes);
  toKindForm(layout, values);
  if (layout.order <= 2)
  {
    flags = layout.order == 1 ? LinearTetCell::validate(nodes, Mesh_.pointRounding)
                              : QuadraticTetCell::validate(nodes, Mesh_.pointRounding);
  }
  if (!(flags & kValid))
  {
    return flags;
  }
  for (int n = 0; n < std::max(count, kCellNodes); ++n)
  {
    if (!std::isfinite(values[n]) || !isFinite(nodes[n]))
    {
      return kOutOfScale; // a Lagrange cell's Bernstein coefficients beyond double range
    }
  }
  // A cell found curved is the curved kind's: its Jacobian's sign.
  if (!(flags & kCurved) || layout.order < 2)
  {
    return flags;
  }
  return layout.order == 2 ? CurvedTetCell::validate(nodes, flags)
                           : forHigherOrder(layout.order, [&](auto P) {
                               return CurvedHigherOrderTetCell<decltype(P)::value>::validate(nodes, flags);
                             });
}

template <typename T>
void Scene::toKindForm(const CellLayout& layout, T items[kMaxCellNodes])
{
  if (layout.hexahedron)
  {
    toTensorForm(*layout.hexahedron, items);
  }
  else if (layout.order == 1)
  {
    LinearTetCell::complete(items);
  }
  else if (layout.order == 2 && layout.bezier)
  {
    QuadraticTetCell::fromBezier(items);
  }
  else if (layout.order >= 3 && !layout.bezier)
  {
    // Converted at a power of two's scale near 1 (exact), so that the conversion's sums (up to 35
    // times the largest node's magnitude) overflow only where the coefficients themselves do.
    double largest = 0.0;
    for (int n = 0; n < layout.nodes; ++n)
    {
      largest = std::max(largest, magnitudeOf(items[n]));
    }
    const double scale = scaleFor(largest);
    for (int n = 0; n < layout.nodes; ++n)
    {
      items[n] *= scale;
    }
    if (layout.order == 3)
    {
      HigherOrderTet<3>::toBezier(items);
    }
    else
    {
      HigherOrderTet<4>::toBezier(items);
    }
    for (int n = 0; n < layout.nodes; ++n)
    {
      items[n] /= scale;
    }
  }
}

const NodeId* Scene::nodeIds(NodeId cellId, CellLayout& layout) const
{
  if (!layoutOf(cellId, layout))
  {
    return nullptr;
  }
  const NodeId* ids = Mesh_.connectivity + Mesh_.offsets[cellId];
  for (int n = 0; n < layout.nodes; ++n)
  {
    if (ids[n] < 0 || ids[n] >= Mesh_.numberOfPoints)
    {
      return nullptr;
    }
  }
  return ids;
}

bool Scene::loadNodes(NodeId cellId, glm::dvec3 nodes[kMaxCellNodes], int needed) const
{
  CellLayout layout;
  const NodeId* ids = nodeIds(cellId, layout);
  return ids && loadNodes(layout, ids, nodes, needed);
}

bool Scene::loadNodes(const CellLayout& layout, const NodeId* ids, glm::dvec3 nodes[kMaxCellNodes], int needed) const
{
  const int count = std::min(needed, layout.nodes);
  for (int n = 0; n < count; ++n)
  {
    const double* p = Mesh_.points + 3 * ids[n];
    nodes[n] = glm::dvec3(p[0], p[1], p[2]);
  }
  // The vertices are the same in every form; the rest as the kind's steps take them.
  if (needed > 4)
  {
    toKindForm(layout, nodes);
  }
  return true;
}

bool Scene::loadValues(NodeId cellId, double values[kMaxCellNodes], const double* pointValues,
  int components, int component) const
{
  CellLayout layout;
  const NodeId* ids = nodeIds(cellId, layout);
  return ids && loadValues(layout, ids, values, pointValues, components, component);
}

bool Scene::loadValues(const CellLayout& layout, const NodeId* ids, double values[kMaxCellNodes],
  const double* pointValues, int components, int component) const
{
  for (int n = 0; n < layout.nodes; ++n)
  {
    values[n] = pointValues[components * ids[n] + component];
  }
  toKindForm(layout, values);
  return true;
}

bool Scene::inCell(NodeId cellId, const glm::dvec3& point, double L[4]) const
{
  glm::dvec3 nodes[kMaxCellNodes];
  if (!loadNodes(cellId, nodes))
  {
    return false; // (edited since validation)
  }
  return forKind(kindOf(cellId), [&](auto cell) { return decltype(cell)::contains(nodes, point, L); });
}

void Scene::cellCoordinates(NodeId cellId, const glm::dvec3& point, double L[4]) const
{
  glm::dvec3 nodes[kMaxCellNodes];
  if (!loadNodes(cellId, nodes))
  {
    std::fill(L, L + 4, std::numeric_limits<double>::quiet_NaN()); // (edited since validation)
    return;
  }
  forKind(kindOf(cellId), [&](auto cell) { decltype(cell)::coordinates(nodes, point, L); });
}

NodeId Scene::uncertifiedHits() const
{
  return UncertifiedHits_.load(std::memory_order_relaxed);
}

int Scene::recordCoefficients(NodeId cellId) const
{
  return forKind(kindOf(cellId), [](auto kind) { return decltype(kind)::kRecordCoefficients; });
}

void Scene::prepareCell(NodeId cellId, CellRecord& cell, double* coefficients) const
{
  cell.cellId = static_cast<std::uint32_t>(cellId);
  cell.kind = CellRecord::Kind::Empty;
  double values[kMaxCellNodes];
  if (!loadValues(cellId, values, Mesh_.values))
  {
    return; // edited since validation: an empty record, never hit
  }
  forKind(kindOf(cellId), [&](auto kind) {
    using Kind = decltype(kind);
    glm::dvec3 nodes[kMaxCellNodes];
    loadNodes(cellId, nodes, Kind::kRecordNodes); // only what the record is made from
    // The range the transverse test gives (which iso-values the cell can hold).
    Kind::valueBound(values, Transverse_, cell.valueLo, cell.valueHi);
    Kind::record(nodes, values, cell, coefficients);
  });
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
  double values[kMaxCellNodes];
  if (!loadValues(cellId, values, pointValues, components, component))
  {
    return std::numeric_limits<double>::quiet_NaN(); // (edited since validation)
  }
  double L[4];
  cellCoordinates(cellId, point, L); // valid cells only reach here
  return forKind(kindOf(cellId), [&](auto cell) { return decltype(cell)::interpolate(values, L); });
}

bool Scene::parametricCoordinates(NodeId cellId, const glm::dvec3& point, double pcoords[3]) const
{
  double L[4];
  cellCoordinates(cellId, point, L);
  CellLayout layout;
  if (layoutOf(cellId, layout) && layout.hexahedron)
  {
    parametricPoint(*layout.hexahedron, L + 1, pcoords); // (VTK's, from the tensor form's cube)
  }
  else
  {
    std::copy(L + 1, L + 4, pcoords);
  }
  return std::isfinite(L[0] + L[1] + L[2] + L[3]);
}

double Scene::cellSize(NodeId cellId) const
{
  glm::dvec3 nodes[kMaxCellNodes];
  return loadNodes(cellId, nodes, 4) ? longestEdge(nodes) : 0.0; // (0: edited since validation)
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
    double values[kMaxCellNodes];
    CellLayout layout;
    if (!nodeIds(valid.id, layout) || !loadValues(valid.id, values, Mesh_.values))
    {
      continue; // (edited since validation)
    }
    largest = std::max(largest, bernstein::magnitude(values, std::max(layout.nodes, kCellNodes)));
  }
  const double scale = scaleFor(largest);
  for (const ValidCell& valid : ValidCells_)
  {
    const std::uint32_t cell = valid.id;
    CellLayout layout;
    const NodeId* ids = nodeIds(cell, layout);
    glm::dvec3 nodes[kMaxCellNodes];
    double values[kMaxCellNodes];
    if (!ids || !loadNodes(layout, ids, nodes) || !loadValues(layout, ids, values, Mesh_.values))
    {
      continue; // (edited since validation)
    }
    for (double& value : values)
    {
      value *= scale;
    }
    const CellKind kind = kindOf(cell);
    // The cell's own nodes (a linear tet's completed mid-edge "nodes" are not points of the
    // mesh), each at its barycentric point.
    for (int n = 0; n < layout.nodes; ++n)
    {
      double L[4];
      if (layout.hexahedron)
      {
        const auto& at = layout.hexahedron->nodePoints[static_cast<std::size_t>(n)];
        L[0] = 0.0;
        std::copy(at.begin(), at.end(), L + 1);
      }
      else
      {
        tetNodePoint(layout.order, n, L);
      }
      sum[static_cast<std::size_t>(ids[n])] +=
        forKind(kind, [&](auto cell) { return decltype(cell)::gradient(nodes, values, L); });
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
  CellLayout layout;
  const NodeId* ids = nodeIds(cellId, layout);
  if (!ids || static_cast<NodeId>(NodalGradients_.size()) != Mesh_.numberOfPoints)
  {
    return glm::dvec3(0.0); // (edited since validation)
  }
  // The nodal gradients as nodal values of a field of the cell's order (a linear tet's mid-edge
  // ones the means of their edges': LinearTetCell::complete), interpolated with its shape
  // functions.
  glm::dvec3 nodal[kMaxCellNodes];
  for (int n = 0; n < layout.nodes; ++n)
  {
    nodal[n] = NodalGradients_[static_cast<std::size_t>(ids[n])];
  }
  if (layout.hexahedron)
  {
    toKindForm(layout, nodal);
    glm::dvec3 gradient(0.0);
    for (int a = 0; a < 3; ++a)
    {
      double component[kMaxCellNodes];
      for (int n = 0; n < tensor::count(layout.order); ++n)
      {
        component[n] = nodal[n][a];
      }
      gradient[a] = forHexahedronOrder(layout.order,
        [&](auto P) { return HexahedronCell<decltype(P)::value, false>::interpolate(component, L); });
    }
    return gradient;
  }
  if (layout.order <= 2)
  {
    if (layout.order == 1)
    {
      LinearTetCell::complete(nodal);
    }
    glm::dvec3 gradient(0.0);
    for (int k = 0; k < 4; ++k)
    {
      gradient += (L[k] * (2.0 * L[k] - 1.0)) * nodal[k];
    }
    for (int e = 0; e < 6; ++e)
    {
      gradient += (4.0 * L[kEdgeVertices[e][0]] * L[kEdgeVertices[e][1]]) * nodal[4 + e];
    }
    return gradient;
  }
  const CellLayout lagrange{ layout.order, false, layout.nodes };
  toKindForm(lagrange, nodal);
  glm::dvec3 gradient(0.0);
  for (int a = 0; a < 3; ++a)
  {
    double component[kMaxCellNodes];
    for (int n = 0; n < layout.nodes; ++n)
    {
      component[n] = nodal[n][a];
    }
    gradient[a] = forHigherOrder(layout.order,
      [&](auto P) { return HigherOrderTetCell<decltype(P)::value>::interpolate(component, L); });
  }
  return gradient;
}

} // namespace tetdsr
