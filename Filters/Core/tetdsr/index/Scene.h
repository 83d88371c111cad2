// A mesh of the core's cell kinds (Cells.h) prepared for ray casting: per-cell validation,
// rigorous value ranges and boxes, and each step of a cell dispatched to its kind's file. Rays are cast into a SurfaceIndex (SurfaceIndex.h): the cells whose ranges
// hold one of a set of iso-values, with a hierarchy over them.
#pragma once

#include "tetdsr/common/Camera.h"
#include "tetdsr/cells/Cells.h"
#include "tetdsr/cells/HexahedronCell.h"
#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/cells/HigherOrderTetCell.h"
#include "tetdsr/cells/QuadraticTetCell.h"
#include "tetdsr/cells/WedgeCell.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

namespace tetdsr
{

/// Non-owning view of a mesh in VTK's layout (vtkUnstructuredGrid's arrays). Only its counts
/// are trusted (MeshInput checks them against the arrays); every cell's type, offsets and ids
/// are checked by the scene.
struct MeshView
{
  const double* points = nullptr; ///< x, y, z per point
  NodeId numberOfPoints = 0;
  NodeId numberOfCells = 0; ///< at most Scene::kMaxCells
  const std::uint8_t* cellTypes = nullptr; ///< one VTK cell type code per cell
  const NodeId* offsets = nullptr;         ///< numberOfCells + 1 entries into connectivity
  const NodeId* connectivity = nullptr;    ///< connectivitySize point ids
  NodeId connectivitySize = 0;
  const double* values = nullptr; ///< one scalar per point (numberOfPoints entries)
  /// VTK's "RationalWeights" of Bezier cells, one per point; null when the mesh has none.
  const double* rationalWeights = nullptr;
  /// VTK's cell ghost flags ("vtkGhostType"), one byte per cell; null when the mesh has none. A
  /// cell flagged kGhostDuplicateCell or kGhostHiddenCell is left out (kGhost).
  const std::uint8_t* cellGhosts = nullptr;
  /// The relative rounding of the coordinates as given (2^-52 for double, 2^-23 for float): a
  /// mid-edge node farther from its edge's midpoint than 64 times this, relative to the larger of
  /// the cell's longest edge and its coordinates' magnitude, makes the cell curved
  /// (isoparametric); closer ones are rounding.
  double pointRounding = 0x1p-52;
};

/// The bits of VTK's cell ghost flags (vtkDataSetAttributes::CellGhostTypes) that leave a cell
/// out: a duplicate of a cell another piece owns (distributed writers and ghost-cell generators
/// add them around each piece), or a cell kept only for connectivity whose values are to be
/// ignored. The other bits describe a cell that is drawn.
constexpr std::uint8_t kGhostDuplicateCell = 1;
constexpr std::uint8_t kGhostHiddenCell = 32;

/// The checks of a cell's node ids that every reader of cells makes, in this order: kInvalidId
/// (an id outside [0, numberOfPoints)), kDegenerate (an id repeated), kRational (a Bezier cell
/// whose rational weights differ or are not positive and finite); 0 if it passes.
std::uint16_t checkNodeIds(const MeshView& mesh, const NodeId* ids, int count, bool bezier);

/// An allocator that leaves new elements default-initialised (for plain structs: unwritten), so
/// that large arrays are first written, and their pages first touched, by the parallel loops
/// that fill them rather than zeroed serially beforehand.
template <typename T>
struct DefaultInitAllocator : std::allocator<T>
{
  template <typename U>
  struct rebind
  {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <typename U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept
  {
  }
  template <typename U>
  void construct(U* p) noexcept
  {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args)
  {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <typename T>
using FillLaterVector = std::vector<T, DefaultInitAllocator<T>>;

/// What preprocessing found. Cells that are not valid are left out of the hierarchy.
struct PreprocessSummary
{
  NodeId validCells = 0;
  NodeId invertedCells = 0;   ///< valid, negative orientation (rendered the same way)
  /// valid, a mid-edge node off its edge's midpoint: rendered as the isoparametric image of the
  /// reference tet (CurvedTet.h)
  NodeId curvedCells = 0;
  /// curved, with a Jacobian determinant that changes sign or vanishes inside (tangled or
  /// folded): skipped
  NodeId tangledCells = 0;
  /// flat or needle-like (volume below 1e-13 of the longest edge cubed), or a node id repeated
  /// within the cell
  NodeId degenerateCells = 0;
  /// longest edge outside [kMinCellSize, kMaxCellSize]: its volume and barycentric frame would
  /// underflow or overflow double precision
  NodeId outOfScaleCells = 0;
  NodeId nonFiniteCells = 0;  ///< a NaN or Inf nodal value or coordinate
  NodeId invalidIdCells = 0;  ///< a node id outside [0, numberOfPoints)
  NodeId unsupportedCells = 0; ///< a cell type the core does not read (Cells.h)
  /// a number of ids that does not match the type, or offsets out of order or past the end of
  /// the connectivity
  NodeId malformedCells = 0;
  /// a Lagrange or Bezier cell of order above kCellTypes' highest
  NodeId orderTooHighCells = 0;
  NodeId rationalCells = 0; ///< a Bezier tetrahedron whose rational weights differ within it
  /// valid, of order 3 or more (HigherOrderTetCell, CurvedHigherOrderTetCell; a hexahedron or
  /// wedge whose polynomials are of total degree 3 or more)
  NodeId higherOrderCells = 0;
  /// a ghost cell (MeshView::cellGhosts): drawn by the piece that owns it, left out here
  NodeId ghostCells = 0;
};

class Hierarchy;
struct BoxItem;

/// Runs body(begin, end) over a partition of [0, count), possibly concurrently; the parts must
/// cover every index exactly once. Lets the caller supply its threads (VTK's vtkSMPTools).
using ParallelFor =
  std::function<void(NodeId count, const std::function<void(NodeId begin, NodeId end)>& body)>;

/// The serial ParallelFor.
inline void serialFor(NodeId count, const std::function<void(NodeId, NodeId)>& body)
{
  body(0, count);
}

class Scene
{
public:
  /// Cells a scene can index (32-bit slots); a larger mesh gives an empty scene.
  static constexpr NodeId kMaxCells = 0xFFFFFFFFLL;

  /// Validates every cell (in parallel through `parallelFor`). The mesh's arrays must outlive
  /// the scene, and hold the counts the view gives.
  explicit Scene(const MeshView& mesh, const ParallelFor& parallelFor = serialFor,
    const TransverseTest& transverseTest = TransverseTest());
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  const PreprocessSummary& summary() const { return Summary_; }

  /// The record step of a valid cell's kind: what its ray test needs, computed once; the
  /// recordCoefficients(cellId) numbers it keeps beside the record go to `coefficients`.
  void prepareCell(NodeId cellId, CellRecord& cell, double* coefficients = nullptr) const;
  /// How many numbers a valid cell's record keeps beside it (kRecordCoefficients of its kind).
  int recordCoefficients(NodeId cellId) const;

  /// The first crossing along the ray, with tMin <= t <= tLimit, of one of the iso-values in
  /// one prepared cell; false if there is none there. Dispatches to the record's kind.
  bool intersectCell(const CellRecord& cell, const Ray& ray, const IsoValues& isoValues,
    double tMin, double tLimit, SurfaceHit& hit) const;

  /// Point location: the valid cell containing `point` (the first found where cells share a
  /// face); false if no valid cell contains it. The first call builds a hierarchy over every
  /// valid cell (serially; thread-safe), which only point location needs.
  bool locate(const glm::dvec3& point, NodeId& cellId) const;

  /// A valid cell: its id and its value range (the transverse test's, rounded outward to float).
  struct ValidCell
  {
    float valueLo;
    float valueHi;
    std::uint32_t id;
  };
  /// The valid cells, in cell order.
  const FillLaterVector<ValidCell>& validCells() const { return ValidCells_; }

  /// A valid cell's box in box units (see toBoxUnits), padded and rounded outward: every
  /// point of the cell, widened by kBarycentricTolerance, lies in it. Its id is the cell's.
  BoxItem cellBox(NodeId cellId) const;

  /// A point in box units: boxes hold (x - origin) * boxScale(), a power of two that brings
  /// the scene's extent near 1 (so float boxes resolve scenes of any size and position in
  /// double range).
  glm::dvec3 toBoxUnits(const glm::dvec3& point) const { return (point - Origin_) * BoxScale_; }
  double boxScale() const { return BoxScale_; }

  /// A point array (`components` values per point, this one's `component`) interpolated at
  /// `point` with the shape functions of one valid cell (their extension, if the point is
  /// outside). The scene's own field is interpolate(cell, point, mesh.values).
  double interpolate(NodeId cellId, const glm::dvec3& point, const double* pointValues,
    int components = 1, int component = 0) const;

  const MeshView& mesh() const { return Mesh_; }

  /// VTK's parametric coordinates (r, s, t) of `point` in a valid cell: the reference
  /// tetrahedron's, vertex 0 at the origin and vertices 1, 2, 3 at r, s, t = 1 (through the
  /// inverse of a curved cell's map). False for the tetrahedra a hexahedron or wedge is split
  /// into (their coordinates are not the source cell's) and for a cell edited since validation.
  bool parametricCoordinates(NodeId cellId, const glm::dvec3& point, double pcoords[3]) const;

  /// The diagonal of the box around the valid cells (0 when there is none).
  double diagonal() const;

  /// The box around the valid cells (xmin, xmax, ymin, ymax, zmin, zmax), slightly padded;
  /// false when there is no valid cell.
  bool bounds(double box[6]) const;

  /// The longest edge of a valid cell.
  double cellSize(NodeId cellId) const;

  /// The kind of a valid cell, as validation classified it.
  CellKind kindOf(NodeId cellId) const
  {
    CellLayout layout;
    layoutOf(cellId, layout);
    return tetdsr::kindOf(layout, !Curved_.empty() && Curved_[static_cast<std::size_t>(cellId)] != 0);
  }

  /// Rays whose hit was accepted without a certificate (in a curved cell: at the subdivision limit
  /// without a Krawczyk test; in a straight cell of order 3 or 4: a root that does not separate
  /// from its neighbour, a tangent one), since the scene was built. Counted, not
  /// guaranteed; thread-safe.
  NodeId uncertifiedHits() const;

  /// Nodal gradients (the paper's "nodal normals"): at each node, the mean of the exact
  /// gradients there of the valid cells that use it, for the whole field scaled by one power of
  /// two (directions exact; magnitudes finite for any field in double range). Computed once, on
  /// the first call; the interpolation below needs them.
  void computeNodalGradients();
  bool hasNodalGradients() const { return !NodalGradients_.empty(); }

  /// The nodal gradients of a cell interpolated at `point` with the quadratic shape functions
  /// (paper's eq. 2).
  glm::dvec3 interpolateNodalGradient(NodeId cellId, const glm::dvec3& point) const;

  /// Bytes this scene keeps (the mesh it views is not counted): 12 per valid cell (id and
  /// range), the point-location hierarchy once built, 24 per point once nodal gradients are
  /// computed, and 1 per input cell when any cell is curved.
  std::size_t memoryBytes() const;

private:
  // The constructor's steps.
  /// The origin and unit of the float boxes (box units) from the cells' vertices.
  void chooseBoxUnits(const ParallelFor& parallelFor);
  /// Validates every cell: its status, entry and counts, and the box around the valid ones.
  void validateCells(const ParallelFor& parallelFor, FillLaterVector<std::uint16_t>& status,
    glm::dvec3& lo, glm::dvec3& hi);
  /// Keeps the valid cells' entries, in cell order, and marks the curved ones.
  void keepValidCells(const FillLaterVector<std::uint16_t>& status);
  /// The box around every valid cell (box units), padded.
  void setSceneBox(const glm::dvec3& lo, const glm::dvec3& hi);
  /// Whether a cell's type and offsets can be trusted to read its ids (validate counts the rest),
  /// and how they are read.
  bool layoutOf(NodeId cellId, CellLayout& layout) const;
  bool readable(NodeId cellId) const
  {
    CellLayout layout;
    return layoutOf(cellId, layout);
  }
  /// Runs body(chunk, begin, end) over fixed chunks of cells through parallelFor.
  void forChunks(const ParallelFor& parallelFor,
    const std::function<void(NodeId chunk, NodeId begin, NodeId end)>& body) const;

  /// A valid cell's point ids, read again from the mesh: null when its type, offsets or ids no
  /// longer pass validation's checks. The scene views the caller's arrays, which may be edited in
  /// place after validation (VTK's contract says Modified(), numpy makes it easy to forget): every
  /// later read goes through here, so such an edit gives a stale or missing cell, never a read out
  /// of bounds. A few comparisons per read; the rays' hot path reads records, not the mesh.
  const NodeId* nodeIds(NodeId cellId, CellLayout& layout) const;
  /// A cell's node positions as its kind's steps take them (Cells.h, kCellNodes: 10 for orders
  /// 1 and 2, a linear tet completed and a Bezier cell's control points made nodes; Bezier layout
  /// for orders 3 and 4), or only its first `needed` (its vertices, for 4); false if its ids were
  /// edited out of range (nodeIds).
  bool loadNodes(NodeId cellId, glm::dvec3 nodes[kMaxCellNodes], int needed = kMaxCellNodes) const;
  /// A point array's values at a cell's nodes, in the same form; false as loadNodes.
  bool loadValues(NodeId cellId, double values[kMaxCellNodes], const double* pointValues,
    int components = 1, int component = 0) const;
  /// The same with ids already checked by nodeIds (one check for several reads).
  bool loadNodes(const CellLayout& layout, const NodeId* ids, glm::dvec3 nodes[kMaxCellNodes],
    int needed = kMaxCellNodes) const;
  bool loadValues(const CellLayout& layout, const NodeId* ids, double values[kMaxCellNodes],
    const double* pointValues, int components = 1, int component = 0) const;
  /// A cell's nodes (points or values) as read, in place made as its kind's steps take them:
  /// a linear tet completed, an order-2 Bezier cell's control points made nodes, an order 3-4
  /// Lagrange cell's nodes made Bernstein coefficients (Bezier layout).
  template <typename T>
  static void toKindForm(const CellLayout& layout, T items[kMaxCellNodes]);
  /// The barycentric coordinates of `point` in a valid cell (the kind's coordinates step).
  void cellCoordinates(NodeId cellId, const glm::dvec3& point, double L[4]) const;
  /// Whether `point` lies in a valid cell (within kBarycentricTolerance), and where.
  bool inCell(NodeId cellId, const glm::dvec3& point, double L[4]) const;
  /// Counts a hit accepted without a certificate.
  void countUncertified(bool certified) const
  {
    if (!certified)
    {
      UncertifiedHits_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  /// Checks a cell: its type, offsets and ids, its values, then its kind's validate step; for a
  /// valid one, fills its entry and its extent (the kind's). CellStatus bits.
  std::uint16_t validate(
    NodeId cellId, ValidCell& validCell, glm::dvec3& extentLo, glm::dvec3& extentHi) const;
  /// validate's first step: the cell's type, offsets and ids (its layout, and where its ids
  /// are); 0 if they can be read, else the status saying why not.
  std::uint16_t checkIds(NodeId cellId, CellLayout& layout, const NodeId*& ids) const;
  /// validate's second: the nodes' values and coordinates, then the order's and kind's geometry
  /// checks; the nodes in the form the kind's steps take (toKindForm). CellStatus bits.
  std::uint16_t checkNodes(const CellLayout& layout, const NodeId* ids,
    glm::dvec3 nodes[kMaxCellNodes], double values[kMaxCellNodes]) const;
  /// The box (box units) of a cell with this extent and longest edge.
  BoxItem boxOf(const glm::dvec3& extentLo, const glm::dvec3& extentHi, double maxEdge) const;

  MeshView Mesh_;
  TransverseTest Transverse_;
  glm::dvec3 Origin_{ 0.0 };
  double BoxScale_ = 1.0; ///< boxes hold (x - Origin_) * BoxScale_, a power of two
  PreprocessSummary Summary_;
  FillLaterVector<ValidCell> ValidCells_;
  float BoxLo_[3] = { 0.0f, 0.0f, 0.0f }; ///< around every valid cell (box units)
  float BoxHi_[3] = { 0.0f, 0.0f, 0.0f };
  mutable std::once_flag LocatorBuilt_;
  mutable std::unique_ptr<Hierarchy> Locator_;
  std::vector<glm::dvec3> NodalGradients_; ///< per point, once computed
  std::vector<std::uint8_t> Curved_; ///< per input cell, 1 if curved; empty when none is
  mutable std::atomic<NodeId> UncertifiedHits_{ 0 };
};

// Inline: the innermost test of every ray (the traversal inlines it).
inline bool Scene::intersectCell(const CellRecord& cell, const Ray& ray, const IsoValues& isoValues,
  double tMin, double tLimit, SurfaceHit& hit) const
{
  // The iso-values this cell can hold: sorted()[first, last).
  std::size_t first, last;
  if (cell.kind == CellRecord::Kind::Empty || !isoValues.within(cell.valueLo, cell.valueHi, first, last))
  {
    return false;
  }
  if (cell.kind == CellRecord::Kind::Hexahedron || cell.kind == CellRecord::Kind::CurvedHexahedron)
  {
    bool certified = true;
    const bool curved = cell.kind == CellRecord::Kind::CurvedHexahedron;
    const bool found = forHexahedronOrder(cell.order, [&](auto P) {
      return curved ? HexahedronCell<decltype(P)::value, true>::intersect(
                        cell, ray, isoValues, first, last, tMin, tLimit, hit, certified)
                    : HexahedronCell<decltype(P)::value, false>::intersect(
                        cell, ray, isoValues, first, last, tMin, tLimit, hit, certified);
    });
    if (found)
    {
      countUncertified(certified);
    }
    return found;
  }
  if (cell.kind == CellRecord::Kind::Wedge)
  {
    bool certified = true;
    const bool found = forHexahedronOrder(cell.order, [&](auto P) {
      return WedgeCell<decltype(P)::value>::intersect(cell, ray, isoValues, first, last, tMin, tLimit, hit, certified);
    });
    if (found)
    {
      countUncertified(certified);
    }
    return found;
  }
  if (cell.kind == CellRecord::Kind::HigherOrder)
  {
    bool certified = true;
    const bool found = forHigherOrder(cell.order, [&](auto P) {
      return HigherOrderTetCell<decltype(P)::value>::intersect(
        cell, ray, isoValues, first, last, tMin, tLimit, hit, certified);
    });
    if (found)
    {
      countUncertified(certified);
    }
    return found;
  }
  return QuadraticTetCell::intersect(cell, ray, isoValues, first, last, tMin, tLimit, hit);
}

} // namespace tetdsr
