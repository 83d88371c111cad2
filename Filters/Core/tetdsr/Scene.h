// A quadratic tetrahedral mesh prepared for ray casting: per-cell validation and rigorous
// value ranges, and a bounding volume hierarchy whose nodes carry the value interval of their
// subtree, so a ray skips every subtree that cannot reach an iso-value.
#pragma once

#include "tetdsr/Camera.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
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

  /// Validates every cell (in parallel through `parallelFor`) and builds the hierarchy. The
  /// mesh's arrays must outlive the scene, and hold the counts the view gives.
  explicit Scene(const MeshView& mesh, const ParallelFor& parallelFor = serialFor,
    const TransverseTest& transverseTest = TransverseTest());

  const PreprocessSummary& summary() const { return Summary_; }

  /// The first crossing of any iso-value along the ray with tMin <= t <= tMax; false if there
  /// is none.
  bool firstHit(const Ray& ray, const IsoValues& isoValues, SurfaceHit& hit, double tMin = 0.0,
    double tMax = std::numeric_limits<double>::infinity()) const;

  /// Point location: the valid cell containing `point` (the first found where cells share a
  /// face); false if no valid cell contains it.
  bool locate(const glm::dvec3& point, NodeId& cellId) const;

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

  /// Bytes this scene keeps (the mesh it views is not counted): 12 per valid cell plus the
  /// hierarchy's nodes (about one per 2 cells, 40 bytes each), plus 24 per point once nodal
  /// gradients are computed, plus 1 per input cell when any cell is curved.
  std::size_t memoryBytes() const;

  /// Barycentric tolerance by which a cell is widened when clipping a ray to it. Rounding in
  /// the two cells that share a face gives slightly different barycentric coordinates there;
  /// without overlap a ray through a shared edge or vertex could fall between them. A
  /// difference of 1e-10 of a cell's size between the neighbours' polynomials moves a hit by
  /// the same fraction of the cell, far below pixel size.
  static constexpr double kBarycentricTolerance = 1e-10;

private:
  // Boxes and value ranges are stored in float, rounded outward, so every test on them is
  // conservative; boxes are relative to Origin_ and in units of the scene's extent, so their
  // precision follows the scene's size, not its distance from the world origin or its scale. Exact (double) tests happen per cell.
  struct Node
  {
    float boxLo[3];
    float boxHi[3];
    float valueLo;
    float valueHi;
    std::uint32_t firstOrSecondChild; ///< leaf: first slot; interior: index of the second child
    std::uint32_t count; ///< leaf: number of cells (at most kLeafSize); interior: 0 (first child: next)
  };
  struct BuildItem;
  struct Bounds;

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
  std::uint8_t validate(NodeId cellId, BuildItem& item) const;
  /// Makes `node` for items [begin, end), whose bounds are given. Returns false for a leaf, or
  /// true with the items partitioned at `middle` and the two sides' bounds.
  bool split(std::vector<BuildItem>& items, std::size_t begin, std::size_t end, int depth,
    const Bounds& bounds, Node& node, std::size_t& middle, Bounds& left, Bounds& right);
  std::uint32_t build(std::vector<BuildItem>& items, std::size_t begin, std::size_t end,
    int depth, const Bounds& bounds, std::vector<Node>& nodes);
  void buildInParallel(std::vector<BuildItem>& items, const ParallelFor& parallelFor);
  bool intersectCell(NodeId cellId, const Ray& ray, const IsoValues& isoValues, double tMin,
    double tLimit, SurfaceHit& hit) const;

  MeshView Mesh_;
  TransverseTest Transverse_;
  glm::dvec3 Origin_{ 0.0 };
  double BoxScale_ = 1.0; ///< boxes hold (x - Origin_) * BoxScale_, a power of two
  PreprocessSummary Summary_;
  std::vector<Node> Nodes_;
  std::vector<std::uint32_t> SlotCell_; ///< cell id of each leaf slot
  std::vector<float> SlotRange_;        ///< outward-rounded Bernstein min and max per slot
  std::vector<glm::dvec3> NodalGradients_; ///< per point, once computed
  std::vector<std::uint8_t> Curved_; ///< per input cell, 1 if curved; empty when none is
  mutable std::atomic<NodeId> UncertifiedHits_{ 0 };
};

} // namespace tetdsr
