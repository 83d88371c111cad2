// A quadratic tetrahedral mesh prepared for ray casting: per-cell validation, rigorous value
// ranges and boxes. Rays are cast into a SurfaceIndex (SurfaceIndex.h): the cells whose ranges
// hold one of a set of iso-values, with a hierarchy over them.
#pragma once

#include "tetdsr/Camera.h"
#include "tetdsr/QuadraticTet.h"
#include "tetdsr/Roots.h"

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

/// Point and cell ids: 64-bit, the same type as VTK's vtkIdType, so VTK's connectivity can be
/// viewed without a copy.
using NodeId = long long;

/// Non-owning view of a mesh of 10-node tetrahedra (VTK node order).
struct MeshView
{
  const double* points = nullptr; ///< x, y, z per point
  NodeId numberOfPoints = 0;
  /// 10 node ids per cell (exactly 10 * numberOfCells entries).
  const NodeId* cellNodes = nullptr;
  NodeId numberOfCells = 0; ///< at most Scene::kMaxCells
  const double* values = nullptr; ///< one scalar per point (numberOfPoints entries)
  /// When true, a mid-edge id of kStraightEdge marks a straight edge whose mid-edge value is the
  /// mean of its ends: that is how a linear tetrahedron enters as an exact quadratic one. When
  /// false (a mesh of 10-node cells as given), such an id is out of range like any other.
  bool straightEdgeMarkers = false;
  /// The relative rounding of the coordinates as given (2^-52 for double, 2^-23 for float): a
  /// mid-edge node farther from its edge's midpoint than 64 times this, relative to the larger of
  /// the cell's longest edge and its coordinates' magnitude, makes the cell curved
  /// (isoparametric); closer ones are rounding.
  double pointRounding = 0x1p-52;
};

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

/// The mid-edge id of a straight edge (MeshView::straightEdgeMarkers).
constexpr NodeId kStraightEdge = -1;

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
};

/// How a cell is judged able to contain an iso-value (a "transverse" cell).
struct TransverseTest
{
  enum class Mode
  {
    /// The min and max of the Bernstein coefficients: a guaranteed bound of the field.
    BernsteinBound,
    /// The paper's heuristic: the nodal min and max, each moved outward by `widening` times
    /// their difference. Not a bound: cells whose field dips past it are missed (holes).
    WidenedNodalRange
  };
  Mode mode = Mode::BernsteinBound;
  double widening = 0.25;

  void range(const double nodeValues[10], double& lo, double& hi) const;
};

/// Iso-values sorted ascending, with the test "does [lo, hi] contain any of them".
class IsoValues
{
public:
  explicit IsoValues(const std::vector<double>& values);

  bool anyWithin(double lo, double hi) const
  {
    if (Sorted_.size() == 1)
    {
      return lo <= Sorted_[0] && Sorted_[0] <= hi; // the common case, without a search
    }
    const auto it = std::lower_bound(Sorted_.begin(), Sorted_.end(), lo);
    return it != Sorted_.end() && *it <= hi;
  }

  const std::vector<double>& sorted() const { return Sorted_; }

  /// The sorted() positions [first, last) of the values within [lo, hi]; false if none is.
  bool within(double lo, double hi, std::size_t& first, std::size_t& last) const
  {
    if (Sorted_.size() == 1)
    {
      first = 0; // the common case, without a search
      last = lo <= Sorted_[0] && Sorted_[0] <= hi ? 1 : 0;
      return last == 1;
    }
    first = static_cast<std::size_t>(
      std::lower_bound(Sorted_.begin(), Sorted_.end(), lo) - Sorted_.begin());
    last = static_cast<std::size_t>(
      std::upper_bound(Sorted_.begin(), Sorted_.end(), hi) - Sorted_.begin());
    return first < last;
  }

  /// The position, in the list given to the constructor, of the k-th smallest value.
  std::size_t originalIndex(std::size_t k) const { return OriginalIndex_[k]; }

private:
  std::vector<double> Sorted_;
  std::vector<std::size_t> OriginalIndex_;
};

class Hierarchy;
struct BoxItem;

/// A cell prepared for ray tests (Scene::prepareCell), whatever the iso-values: for a straight
/// cell, its barycentric map and the Bernstein coefficients of its field, so a test reads 4
/// cache lines in a row instead of 10 node ids, 10 points and 10 values scattered over the mesh.
struct alignas(64) CellRecord
{
  enum class Kind : std::uint8_t
  {
    Quadratic, ///< straight, the field a quadratic
    Constant,  ///< straight, the field constant to rounding
    Curved,    ///< isoparametric: solved from the mesh
    Empty      ///< never hit (not a valid cell)
  };
  glm::dvec3 vertex0;
  glm::dvec3 vertex1;
  glm::dvec3 centroidOffset; ///< centroid - vertex0
  glm::dvec3 gradient[3];    ///< grad L_1, L_2, L_3 (grad L_0 is minus their sum)
  /// Bernstein coefficients of the field times `scale`: B_00, B_11, B_22, B_33, then B_ab of
  /// the edges in mid-edge node order.
  double form[10];
  double scale; ///< a power of two bringing the largest nodal magnitude near 1
  double valueLo; ///< the transverse test's range: which iso-values the cell can hold
  double valueHi;
  std::uint32_t cellId;
  Kind kind;
};

struct SurfaceHit
{
  double t = 0.0; ///< ray parameter (distance along the unit direction)
  NodeId cellId = -1;
  /// Exact field gradient at the hit; for a field so large that it overflows, the gradient
  /// scaled down by a power of two (the same direction).
  glm::dvec3 gradient{ 0.0 };
  std::size_t isoIndex = 0;   ///< which iso-value was crossed, in IsoValues::sorted() order
  /// Where this crossing ends: t, or for a cell where the field equals the iso-value throughout,
  /// where the ray leaves that cell (the whole stretch is one crossing).
  double regionEnd = 0.0;
};

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
  /// The range of cell sizes (longest edge) whose barycentric frames stay within double
  /// precision: the volume (size^3) and its inverse times size^2 stay far from under- and
  /// overflow. Cells outside it are skipped and counted (outOfScaleCells).
  static constexpr double kMinCellSize = 1e-100;
  static constexpr double kMaxCellSize = 1e100;

  /// Validates every cell (in parallel through `parallelFor`). The mesh's arrays must outlive
  /// the scene, and hold the counts the view gives.
  explicit Scene(const MeshView& mesh, const ParallelFor& parallelFor = serialFor,
    const TransverseTest& transverseTest = TransverseTest());
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  const PreprocessSummary& summary() const { return Summary_; }

  /// What a valid cell's ray test needs, computed once.
  void prepareCell(NodeId cellId, CellRecord& cell) const;

  /// The first crossing along the ray, with tMin <= t <= tLimit, of one of the iso-values in
  /// one prepared cell; false if there is none there.
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
  /// `point` with the quadratic shape functions of one cell (their extension, if the point is
  /// outside). The scene's own field is interpolate(cell, point, mesh.values).
  double interpolate(NodeId cellId, const glm::dvec3& point, const double* pointValues,
    int components = 1, int component = 0) const;

  const MeshView& mesh() const { return Mesh_; }

  /// The diagonal of the box around the valid cells (0 when there is none).
  double diagonal() const;

  /// The box around the valid cells (xmin, xmax, ymin, ymax, zmin, zmax), slightly padded;
  /// false when there is no valid cell.
  bool bounds(double box[6]) const;

  /// The longest edge of a cell.
  double cellSize(NodeId cellId) const;

  /// Whether a valid cell is rendered curved (isoparametric).
  bool isCurved(NodeId cellId) const
  {
    return !Curved_.empty() && Curved_[static_cast<std::size_t>(cellId)] != 0;
  }

  /// Rays whose hit in a curved cell was accepted at the subdivision limit without a Krawczyk
  /// certificate (tangent or near-tangent roots), since the scene was built. Counted, not
  /// guaranteed; thread-safe.
  NodeId uncertifiedHits() const;

  /// Nodal gradients (the paper's "nodal normals"): at each node, the mean of the exact
  /// gradients there of the valid cells that use it, for the whole field scaled by one power of
  /// two (directions exact; magnitudes finite for any field in double range). Computed once, on the first call; the
  /// interpolation below needs them.
  void computeNodalGradients();
  bool hasNodalGradients() const { return !NodalGradients_.empty(); }

  /// The nodal gradients of a cell interpolated at `point` with the quadratic shape functions
  /// (paper's eq. 2).
  glm::dvec3 interpolateNodalGradient(NodeId cellId, const glm::dvec3& point) const;

  /// Bytes this scene keeps (the mesh it views is not counted): 12 per valid cell (id and
  /// range), the point-location hierarchy once built, 24 per point once nodal gradients are
  /// computed, and 1 per input cell when any cell is curved.
  std::size_t memoryBytes() const;

  /// Barycentric tolerance by which a cell is widened when clipping a ray to it. Rounding in
  /// the two cells that share a face gives slightly different barycentric coordinates there;
  /// without overlap a ray through a shared edge or vertex could fall between them. A
  /// difference of 1e-10 of a cell's size between the neighbours' polynomials moves a hit by
  /// the same fraction of the cell, far below pixel size.
  static constexpr double kBarycentricTolerance = 1e-10;

private:
  /// A cell's 4 vertices.
  void loadVertices(NodeId cellId, glm::dvec3 vertices[4]) const;
  /// A cell's vertices and the values at its 10 nodes of a point array (a missing mid-edge node
  /// takes the mean of its edge's ends).
  void loadCell(NodeId cellId, glm::dvec3 vertices[4], double values[10]) const
  {
    loadCell(cellId, vertices, values, Mesh_.values, 1, 0);
  }
  void loadCell(NodeId cellId, glm::dvec3 vertices[4], double values[10],
    const double* pointValues, int components, int component) const;
  /// A cell's 10 node positions (a missing mid-edge node at its edge's midpoint).
  void loadNodes(NodeId cellId, glm::dvec3 nodes[10]) const;
  /// The barycentric coordinates of `point` in a valid cell (for a curved cell, of its preimage
  /// under the cell's map; outside the cell, of the shape functions' extension as far as Newton
  /// finds it).
  void cellCoordinates(NodeId cellId, const glm::dvec3& point, double L[4]) const;
  /// Whether `point` lies in a valid cell (within kBarycentricTolerance), and where.
  bool inCell(NodeId cellId, const glm::dvec3& point, double L[4]) const;
  bool intersectCurvedCell(NodeId cellId, const Ray& ray, const IsoValues& isoValues, double tMin,
    double tLimit, SurfaceHit& hit) const;
  /// Checks a cell; for a valid one, fills its entry and its extent (vertices' box, or for a
  /// curved cell its control points').
  std::uint8_t validate(
    NodeId cellId, ValidCell& validCell, glm::dvec3& extentLo, glm::dvec3& extentHi) const;
  /// The box (box units) of a cell with these nodes and longest edge; false if not finite.
  bool boxOf(const glm::dvec3 nodes[10], double maxEdge, bool curved, BoxItem& box) const;

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
  if (cell.kind == CellRecord::Kind::Curved)
  {
    return intersectCurvedCell(cell.cellId, ray, isoValues, tMin, tLimit, hit);
  }
  TetFrame frame;
  for (int k = 0; k < 3; ++k)
  {
    frame.gradient[k + 1] = cell.gradient[k];
  }
  frame.gradient[0] = -(frame.gradient[1] + frame.gradient[2] + frame.gradient[3]);
  // Re-origin the ray at its point nearest the cell centroid: the barycentric coordinates and the
  // quadratic's coefficients are then of the cell's own scale, not of the camera distance.
  // The point is formed as offsets from the cell's vertices (origin - vertex first, both of the
  // scene's magnitude, then the small step): never rounded at the coordinates' own magnitude.
  const glm::dvec3 fromVertex0 = ray.origin - cell.vertex0;
  const double tCentre = glm::dot(cell.centroidOffset - fromVertex0, ray.direction);
  double L[4], dL[4];
  frame.barycentricOfOffsets(fromVertex0 + tCentre * ray.direction,
    (ray.origin - cell.vertex1) + tCentre * ray.direction, L);
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
  BernsteinForm form;
  for (int i = 0; i < 4; ++i)
  {
    form.b[i][i] = cell.form[i];
  }
  for (int e = 0; e < 6; ++e)
  {
    const int a = kEdgeVertices[e][0], c = kEdgeVertices[e][1];
    form.b[a][c] = form.b[c][a] = cell.form[4 + e];
  }
  if (cell.kind == CellRecord::Kind::Constant)
  {
    // The field constant over the cell (to rounding) and equal to an iso-value: the whole cell
    // is on the "surface"; the ray meets it where it enters, with no gradient. Rounding would
    // otherwise scatter the roots of a quadratic whose coefficients are all noise.
    double boundLo, boundHi;
    form.range(boundLo, boundHi);
    std::size_t equal, beyond;
    if (!isoValues.within(boundLo / cell.scale, boundHi / cell.scale, equal, beyond))
    {
      return false;
    }
    hit.t = tCentre + sEntry;
    hit.regionEnd = tCentre + sExit;
    hit.cellId = cell.cellId;
    hit.gradient = glm::dvec3(0.0);
    hit.isoIndex = equal;
    return true;
  }
  // The field along the ray, exactly: f(s) = a s^2 + b s + c (see QuadraticTet.h).
  const double a = form.bilinear(dL, dL);
  const double b = 2.0 * form.bilinear(L, dL);
  const double c = form.bilinear(L, L);

  const std::vector<double>& sorted = isoValues.sorted();
  bool found = false;
  double sHit = sExit;
  for (std::size_t k = first; k < last; ++k)
  {
    double s;
    if (firstRootInInterval(a, b, c - sorted[k] * cell.scale, sEntry, sHit, s))
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
  hit.cellId = cell.cellId;
  // Unscaled exactly (a power of two), unless that overflows (a field near the largest double):
  // then the scaled gradient, whose direction is the same.
  const glm::dvec3 gradient = fieldGradient(form, frame, LHit);
  hit.gradient = isFinite(gradient / cell.scale) ? gradient / cell.scale : gradient;
  return true;
}

} // namespace tetdsr
