// The cell seam: the vocabulary every kind of cell shares, and the list of kinds.
//
// Each kind of cell lives in a file of its own and provides the same steps, which Scene and
// SurfaceIndex call through one switch on the kind (no virtual calls on the ray's hot path):
//   validate    geometry checks of a cell whose ids and values Scene has read (CellStatus bits)
//   valueBound  the transverse test's range of the field over the cell (which iso-values it holds)
//   extent      a box around every point of the cell
//   record      what a ray test needs, computed once per transverse cell (CellRecord), from its
//               first kRecordNodes nodes; with kRecordCoefficients more numbers kept beside it
//   intersect   the first crossing of an iso-value along a ray, within [tMin, tLimit]
//   contains    whether a point lies in the cell, and its barycentric coordinates there
//   coordinates a point's barycentric coordinates, outside the cell too (the map's extension)
//   interpolate a point array at barycentric coordinates (the cell's shape functions)
//   gradient    the field's exact gradient at barycentric coordinates
// The kinds (adding one: a file with these steps, a CellKind, a case in forKind (CellKinds.h) and
// in kindOf; a new VTK type is a row of kCellTypes, CellTypes.h):
//   LinearTetCell.h          order 1 (VTK_TETRA, and Lagrange or Bezier tetrahedra of 4 nodes):
//                            rendered as the exact quadratic it is
//   QuadraticTetCell.h       order 2 (VTK_QUADRATIC_TETRA, Lagrange or Bezier of 10 nodes) with
//                            straight edges: an affine map, a quadratic field
//   CurvedTetCell.h          order 2 with a mid-edge node off its edge: isoparametric
//   HigherOrderTetCell.h     orders 3 and 4 (Lagrange or Bezier, 20 and 35 nodes), straight: an
//                            affine map, a field of degree 3 or 4 along each ray
//   CurvedHigherOrderTetCell.h  orders 3 and 4, curved: isoparametric
//   HexahedronCell.h         every hexahedron type, orders 1 to 4 per axis, straight or curved:
//                            solved in its own reference cube
#pragma once

#include "tetdsr/common/Camera.h"
#include "tetdsr/common/CellTypes.h"
#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/math/QuadraticTet.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace tetdsr
{

/// Point and cell ids: 64-bit, the same type as VTK's vtkIdType, so VTK's connectivity can be
/// viewed without a copy.
using NodeId = long long;

/// The kinds of cell, as validation classifies them.
enum class CellKind : std::uint8_t
{
  LinearTet,              ///< LinearTetCell.h (order 1)
  QuadraticTet,           ///< QuadraticTetCell.h (order 2, straight)
  CurvedTet,              ///< CurvedTetCell.h (order 2, curved)
  CubicTet,               ///< HigherOrderTetCell<3> (straight)
  QuarticTet,             ///< HigherOrderTetCell<4> (straight)
  CurvedCubicTet,         ///< CurvedHigherOrderTetCell<3>
  CurvedQuarticTet,       ///< CurvedHigherOrderTetCell<4>
  /// HexahedronCell<P, false> and <P, true>: hexahedra of order P per axis, in their own
  /// reference space (HexahedronCell.h).
  Hexahedron1,
  Hexahedron2,
  Hexahedron3,
  Hexahedron4,
  CurvedHexahedron1,
  CurvedHexahedron2,
  CurvedHexahedron3,
  CurvedHexahedron4,
  /// WedgeCell<P>: straight wedges of order P per axis, triangle x segment (WedgeCell.h).
  Wedge1,
  Wedge2,
  Wedge3,
  Wedge4
};

/// Whether a kind is one of the hexahedra's (and the wedges' and pyramids' read as such).
inline bool isHexahedronKind(CellKind kind)
{
  return kind >= CellKind::Hexahedron1;
}

/// Outcome bits of a cell's validation; Scene counts them (PreprocessSummary).
enum CellStatus : std::uint16_t
{
  kValid = 1,
  kInverted = 2,
  kCurved = 4,
  kDegenerate = 8,
  kNonFinite = 16,
  kInvalidId = 32,
  kOutOfScale = 64,
  kTangled = 128,
  kUnsupported = 256,
  kMalformed = 512,
  kOrderTooHigh = 1024, ///< a Lagrange or Bezier tetrahedron of order above kMaxTetOrder
  kRational = 2048,     ///< a Bezier tetrahedron whose rational weights differ within it
  kHigherOrder = 4096,  ///< valid, of order 3 or more (hexahedra and wedges: their pieces)
  kGhost = 8192         ///< a ghost cell (MeshView::cellGhosts): another piece draws it
};

/// How a cell's node ids are read: the order of its polynomials and whether its nodes are
/// Bernstein control points (VTK_BEZIER_TETRAHEDRON) rather than nodal values.
struct HexahedronNodes;
struct CellLayout
{
  int order = 0; ///< 1..kMaxTetOrder (a hexahedron's: per axis, 1..4)
  bool bezier = false;
  int nodes = 0; ///< latticeCount(order); a hexahedron's: its type's id count
  /// A hexahedron's node table (HexahedronCell.h); null for tetrahedra.
  const HexahedronNodes* hexahedron = nullptr;
  /// A wedge's (its straight cells are WedgeCell kinds).
  bool wedge = false;
};

/// A cell's order by kCellTypes' rule for its id count (`order`), or why it cannot be read:
/// kUnsupported (a type the table does not read), kMalformed (a count that fits no order of the
/// type), kOrderTooHigh (above the table's highest).
inline std::uint16_t readOrder(const CellType* type, long long ids, int& order)
{
  if (!isRead(type))
  {
    return kUnsupported;
  }
  order = orderOf(*type, ids);
  if (order == 0)
  {
    return kMalformed;
  }
  return order > type->maxOrder ? kOrderTooHigh : 0;
}

/// cellLayout for a type read as a tensor-product cell (HexahedronTables.cpp): every hexahedron,
/// wedge and pyramid type of kCellTypes.
std::uint16_t hexahedronLayout(const CellType& type, long long ids, CellLayout& layout);

/// The layout of a cell of VTK type `vtkType` with `ids` node ids; 0 (kValid) if it can be read,
/// else the status saying why not: kUnsupported (a type kCellTypes does not read), kMalformed (an
/// id count that fits no order of the type), kOrderTooHigh (above the table's highest).
inline std::uint16_t cellLayout(int vtkType, long long ids, CellLayout& layout)
{
  const CellType* type = cellTypeOf(vtkType);
  if (isRead(type) && type->shape != CellShape::Tetrahedron)
  {
    return hexahedronLayout(*type, ids, layout);
  }
  int order = 0;
  if (const std::uint16_t status = readOrder(type, ids, order))
  {
    return status;
  }
  layout = { order, type->bezier, latticeCount(order) };
  return 0;
}

/// The kind of a valid cell of this layout, curved or not.
inline CellKind kindOf(const CellLayout& layout, bool curved)
{
  if (layout.hexahedron)
  {
    const CellKind first = curved ? CellKind::CurvedHexahedron1
      : layout.wedge              ? CellKind::Wedge1
                                  : CellKind::Hexahedron1;
    return static_cast<CellKind>(static_cast<int>(first) + (layout.order - 1));
  }
  switch (layout.order)
  {
    case 1:
      return CellKind::LinearTet;
    case 2:
      return curved ? CellKind::CurvedTet : CellKind::QuadraticTet;
    case 3:
      return curved ? CellKind::CurvedCubicTet : CellKind::CubicTet;
    default: // 4: cellLayout reads no other order (TestCellTypes: every cell read gets its own)
      return curved ? CellKind::CurvedQuarticTet : CellKind::QuarticTet;
  }
}

/// Every cell's nodes as the quadratic tetrahedron's ten, VTK_QUADRATIC_TETRA's order (vertices
/// 0..3, then the mid-edge nodes of kEdgeVertices), for the kinds of order 1 and 2: a cell with
/// fewer nodes (LinearTetCell) fills the rest from its own, a Bezier cell's control points are
/// converted to nodes. Cells of order 3 and 4 hold latticeCount(order) in Bezier layout
/// (HigherOrderTet.h); arrays that hold any cell's have kMaxCellNodes.
constexpr int kCellNodes = 10;

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

  void range(const double nodeValues[kCellNodes], double& lo, double& hi) const;
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

/// A cell prepared for ray tests (the kind's record step), whatever the iso-values: for a
/// straight cell, its barycentric map and the Bernstein coefficients of its field, so a test
/// reads 4 cache lines in a row instead of 10 node ids, 10 points and 10 values scattered over
/// the mesh.
struct alignas(64) CellRecord
{
  enum class Kind : std::uint8_t
  {
    Quadratic, ///< straight, the field a quadratic (QuadraticTetCell)
    Constant,  ///< straight, the field constant to rounding (QuadraticTetCell)
    HigherOrder, ///< straight, order 3 or 4 (HigherOrderTetCell): the field read from the mesh
    Hexahedron,  ///< a straight hexahedron (HexahedronCell): its forms kept beside the record
    Wedge,       ///< a straight wedge (WedgeCell): its field's triangle x segment form, the same
    CurvedHexahedron, ///< a curved hexahedron (HexahedronCell), the same
    Empty      ///< never hit (not a valid cell)
  };
  glm::dvec3 vertex0;
  glm::dvec3 vertex1;
  glm::dvec3 centroidOffset; ///< centroid - vertex0
  glm::dvec3 gradient[3];    ///< grad L_1, L_2, L_3 (grad L_0 is minus their sum)
  union
  {
    /// Bernstein coefficients of the field times `scale`: B_00, B_11, B_22, B_33, then B_ab of
    /// the edges in mid-edge node order (Quadratic and Constant records).
    double form[10];
    /// A HigherOrder record's: latticeCount(order) Bernstein coefficients of the field times
    /// `scale`, in TetBernstein.h's canonical order, kept beside the records (SurfaceIndex); a
    /// hexahedron's: HexahedronCell::kRecordCoefficients numbers.
    const double* coefficients;
  };
  double scale; ///< a power of two bringing the largest nodal magnitude near 1
  double valueLo; ///< the transverse test's range: which iso-values the cell can hold
  double valueHi;
  std::uint32_t cellId;
  Kind kind;
  std::uint8_t order; ///< the cell's order (HigherOrder records)
};
static_assert(sizeof(CellRecord) == 256, "a record is 4 cache lines");

struct SurfaceHit
{
  double t = 0.0; ///< ray parameter (distance along the unit direction)
  NodeId cellId = -1;
  /// Exact field gradient at the hit; for a field so large (or small) that it overflows (or
  /// underflows), the gradient scaled by a power of two (the same direction).
  glm::dvec3 gradient{ 0.0 };
  std::size_t isoIndex = 0;   ///< which iso-value was crossed, in IsoValues::sorted() order
  /// Where this crossing ends: t, or for a cell where the field equals the iso-value throughout,
  /// where the ray leaves that cell (the whole stretch is one crossing).
  double regionEnd = 0.0;
  /// The hit cell's entry in the SurfaceIndex that found it (kNoEntry: not known), which a
  /// later ray can be asked to test first (SurfaceIndex::firstHit's hint).
  std::uint32_t entry = 0xFFFFFFFFu;
};

/// No SurfaceIndex entry.
constexpr std::uint32_t kNoEntry = 0xFFFFFFFFu;

/// Barycentric tolerance by which a cell is widened when clipping a ray to it. Rounding in the
/// two cells that share a face gives slightly different barycentric coordinates there; without
/// overlap a ray through a shared edge or vertex could fall between them. A difference of 1e-10
/// of a cell's size between the neighbours' polynomials moves a hit by the same fraction of the
/// cell, far below pixel size.
constexpr double kBarycentricTolerance = 1e-10;

/// A power of two that brings `largest` (a magnitude) near 1; 1 for zero or non-finite.
/// Clamped so the factor itself stays a normal double.
inline double scaleFor(double largest)
{
  if (!(largest > 0.0) || !std::isfinite(largest))
  {
    return 1.0;
  }
  return std::ldexp(1.0, -std::clamp(std::ilogb(largest), -1020, 1020));
}

/// scaleFor the largest magnitude of a cell's nodal values (its first `count`).
inline double unitScale(const double values[], int count = kCellNodes)
{
  double largest = 0.0;
  for (int n = 0; n < count; ++n)
  {
    largest = std::max(largest, std::abs(values[n]));
  }
  return scaleFor(largest);
}

/// The longest edge of a tet. sqrt is monotonic and correctly rounded: one root of the largest
/// square is the largest length.
inline double longestEdge(const glm::dvec3 vertices[4])
{
  double longest2 = 0.0;
  for (const auto& edge : kEdgeVertices)
  {
    const glm::dvec3 d = vertices[edge[0]] - vertices[edge[1]];
    longest2 = std::max(longest2, glm::dot(d, d));
  }
  return std::sqrt(longest2);
}

/// A bound on HexahedronNodes::roundingGrowth, the worst-case growth of relative rounding in the
/// making of a tensor form from nodes (TestCellTypes checks every table: the largest, 12,015, is
/// the 75-node Lagrange wedge's).
constexpr double kMaxRoundingGrowth = 16384.0;
/// A tensor form (HexahedronCell.h, WedgeCell.h) of a constant field: its coefficients equal to
/// within the growth of the nodes' rounding and that of each of its making's steps (a weighted
/// sum, three axes' conversions; each step's own rounding grown by the steps after it).
constexpr double kTensorFormConstantRoundings = 8.0 + 4.0 * kMaxRoundingGrowth;

/// The roundings, relative to the largest nodal magnitude, by which a cell of this order's
/// Bernstein coefficients can spread for a constant field: 8 (their own rounding is 2-3), plus for
/// orders 3 and 4 the Lagrange conversion's (HigherOrderTet.h: a sum of N = 20 or 35 products
/// with weights of absolute sum at most 10 or 35, rounded by at most N times that; the fuzzer found
/// a constant order-4 field spread by 27 ulps, made a polynomial of rounding noise at 8).
constexpr double constantRoundings(int order)
{
  return order <= 2 ? 8.0 : order == 3 ? 8.0 + 20.0 * 10.0 : 8.0 + 35.0 * 35.0;
}

/// Whether a Bernstein bound [lo, hi] is within `roundings` roundings of its magnitude wide.
inline bool spreadWithin(double lo, double hi, double roundings)
{
  return hi - lo <= roundings * std::numeric_limits<double>::epsilon() * std::max(std::abs(lo), std::abs(hi));
}

/// Whether a field of this order whose Bernstein bound is [lo, hi] is constant over the cell to
/// rounding: the bound's width within constantRoundings(order) of its magnitude.
inline bool constantToRounding(double lo, double hi, int order = 2)
{
  return spreadWithin(lo, hi, constantRoundings(order));
}

/// A hit's gradient from one computed for the field scaled by `scale` (a power of two): unscaled
/// exactly, unless that overflows or underflows (a field near the ends of double range): then
/// the scaled one, whose direction is the same.
inline glm::dvec3 unscaledGradient(const glm::dvec3& scaled, double scale)
{
  const glm::dvec3 unscaled = scaled / scale;
  const double largest = std::max({ std::abs(unscaled.x), std::abs(unscaled.y), std::abs(unscaled.z) });
  const bool underflows = largest < std::numeric_limits<double>::min() &&
    (scaled.x != 0.0 || scaled.y != 0.0 || scaled.z != 0.0);
  return isFinite(unscaled) && !underflows ? unscaled : scaled;
}

} // namespace tetdsr
