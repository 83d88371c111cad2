// Hexahedra in their own reference space: every VTK hexahedron (VTK_HEXAHEDRON, VTK_VOXEL, the
// 20-, 24- and 27-node ones, VTK_LAGRANGE_HEXAHEDRON and VTK_BEZIER_HEXAHEDRON of orders 1 to 4)
// as tensor-product Bernstein forms of degree P per axis on the unit cube (TensorBernstein.h):
// map X(r, s, t) and field f(r, s, t). The 20- and 24-node spaces lie in Q2, so P = 2 holds them
// exactly; a Lagrange cell's nodes are converted along each axis (LagrangeToBernstein), a Bezier
// cell's are its coefficients.
//
// Straight cells (the map affine: a parallelepiped) take the ray to a line in (r, s, t): it is
// clipped to the cube, and the field along it is a polynomial of degree 3P in the ray parameter,
// whose Bernstein coefficients come from the cell's by a stable reparametrisation of each axis
// (segmentMatrix) and the product rule; its first root is certified by firstBernsteinRoot.
// Curved cells are solved in the cube: with u, v orthonormal and both perpendicular to the ray's
// direction d, the hit is the common root of
//   u . (X(r) - o) = 0,   v . (X(r) - o) = 0,   f(r) - c = 0
// with the least depth d . (X(r) - o): a subdivision of the cube into boxes (each equation's
// coefficients on a box bound it there: a box where one has one sign is dropped, so is one whose
// depth bound lies beyond the nearest root found), and on each box Krawczyk's test (the box's
// Jacobian bounded by its coefficients' differences) proves a unique root, which Newton then
// reaches. A box that reaches the size limit unproven (a ray tangent to the surface) is settled
// by Newton alone and its hit flagged uncertified.
//
// The cell seam's steps (Cells.h). `nodes` and `values` arrive as the tensor form's coefficients
// (count(P) of them, world coordinates and field; Scene::toKindForm makes them). The parametric
// point of a hit or a located point is (r, s, t) in L[1..3] (L[0] unused: 0), VTK's parametric
// coordinates.
#pragma once

#include "tetdsr/common/Camera.h"
#include "tetdsr/cells/Cells.h"
#include "tetdsr/math/TensorBernstein.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace tetdsr
{

/// The highest order per axis of the hexahedra the core reads.
constexpr int kMaxHexahedronOrder = kMaxReadOrder;

/// How a cell type's nodes (VTK's order) become its tensor form: a permutation onto the lattice
/// of its order when its nodes are the lattice's (Lagrange, Bezier, VTK_HEXAHEDRON, VTK_VOXEL, 27
/// nodes), else the cell's shape functions at the lattice points (20 and 24 nodes, and the
/// collapsed cells below).
///
/// Wedges and VTK_PYRAMID are read as collapsed hexahedra. A wedge's polynomials (of P_p(r, s) x
/// P_q(t) and its relatives) composed with r = u (1 - v), s = v are of degree p per axis in (u,
/// v, t): the unit cube maps onto the wedge with its face v = 1 collapsed onto the edge through
/// the triangle's vertex (0, 1), and det J = (1 - v) det J_wedge. VTK_PYRAMID's map and field
/// (1 - t) (its base's bilinear ones) + t (the apex's) are trilinear with the face t = 1
/// collapsed onto the apex: det J = (1 - t)^2 times a polynomial whose sign is the cell's.
struct HexahedronNodes
{
  const char* name = "";
  int order = 1;
  bool bezier = false;
  int nodes = 0;
  /// The axis whose face at 1 is collapsed (wedges: 1, VTK_PYRAMID: 2; -1: none), and the power
  /// of (1 - x) det J has as a factor there.
  int collapsedAxis = -1;
  int collapsedPower = 0;
  /// VTK orders the type's nodes so that a well-formed cell's map reverses the parametric
  /// orientation (kCellTypes' CellType::mirrored): its inversion is the reverse of its map's sign.
  bool mirrored = false;
  /// Per node, its lattice index (tensor::index); empty when `weights` is used.
  std::vector<int> lattice;
  /// count(order) x nodes: the nodal values at lattice point k are sum_n weights[k][n] node[n].
  std::vector<double> weights;
  /// How the cube's point maps to VTK's parametric point: the same (hexahedra, VTK_PYRAMID,
  /// VTK_QUADRATIC_PYRAMID), (u (1 - v), v, t) (wedges), or VTK_TRIQUADRATIC_PYRAMID's pyramid
  /// (1/2 + (u - 1/2) (1 - w), 1/2 + (v - 1/2) (1 - w), (1 + w) / 2).
  enum class Parametric : std::uint8_t
  {
    Cube,
    Wedge,
    CentredPyramid
  };
  Parametric parametric = Parametric::Cube;
  /// How much the tensor form's making (the weights' largest absolute row sum, times the Lagrange
  /// to Bernstein conversion's infinity norm per axis) can grow the nodes' relative rounding (a
  /// worst case: the bound kTensorFormConstantRoundings rests on).
  double roundingGrowth = 1.0;
  /// The nodes at VTK's parametric (0, 0, 0), (1, 0, 0), (0, 1, 0) and (0, 0, 1) (the affine
  /// frame a straight cell's nodes are placed by); -1 for pyramids, never taken as straight
  /// (their cube is not their parametric cell).
  int frameNodes[4] = { -1, -1, -1, -1 };
  /// Each node's point in the tensor form's cube (VTK's parametric point for hexahedra; (u, v,
  /// t) for collapsed cells).
  std::vector<std::array<double, 3>> nodePoints;
};

/// VTK's parametric point of a point of a table's cube (HexahedronNodes::parametric).
void parametricPoint(const HexahedronNodes& table, const double cube[3], double parametric[3]);

/// The node table of a hexahedron type with `ids` node ids (CellLayout's hexahedron part); 0 if
/// read, else kMalformed (an id count that does not fit the type) or kOrderTooHigh.
std::uint16_t hexahedronNodesOf(int vtkType, long long ids, const HexahedronNodes*& table);


/// A hexahedron's nodes (or a point array's values at them) made its tensor form's count(order)
/// coefficients, in place (`items` holds kMaxCellNodes).
template <typename T>
void toTensorForm(const HexahedronNodes& table, T* items);

/// A tetrahedron's map and field, polynomials of degree P in its barycentric coordinates L, as
/// the tensor form of degree P of the cube collapsed onto it (Duffy's map): L_3 = w,
/// L_2 = v (1 - w), L_1 = u (1 - v) (1 - w), L_0 = (1 - u) (1 - v) (1 - w). A monomial
/// L_0^a L_1^b L_2^c L_3^d becomes (1 - u)^a u^b (1 - v)^(a+b) v^c (1 - w)^(a+b+c) w^d, of degree
/// at most P per axis; det J = (1 - v) (1 - w)^2 det J_tet. `interpolate(items, L)` is the cell
/// kind's own (its shape functions on its nodes or control points); `nodes` and `values` in its
/// kind form (count of them: `count`). Curved tetrahedra are solved in this form
/// (CurvedTetCell, CurvedHigherOrderTetCell: their record step), by HexahedronCell's box solve.
/// Returns the power of two the tensor values are scaled by (unitScale of `values`): the record
/// made from them multiplies its CellRecord::scale by it.
template <int P, class Interpolate>
double collapsedTetrahedron(Interpolate interpolate, const glm::dvec3* nodes, const double* values,
  int count, glm::dvec3* tensorNodes, double* tensorValues)
{
  constexpr int N = tensor::count(P);
  double coordinate[3][kMaxCellNodes];
  // The field at a power of two's scale near 1 (exact) from the start: its interpolation and
  // conversion overflow nowhere, even for nodal values near the top of double range (whose
  // Bernstein coefficients may lie beyond it); the tensor values stay at that scale.
  const double fieldScale = unitScale(values, count);
  double field[kMaxCellNodes];
  for (int n = 0; n < count; ++n)
  {
    for (int a = 0; a < 3; ++a)
    {
      coordinate[a][n] = nodes[n][a];
    }
    field[n] = values[n] * fieldScale;
  }
  double lattice[4][N];
  for (int k = 0; k <= P; ++k)
    for (int j = 0; j <= P; ++j)
      for (int i = 0; i <= P; ++i)
      {
        const double u = static_cast<double>(i) / P, v = static_cast<double>(j) / P, w = static_cast<double>(k) / P;
        const double L[4] = { (1.0 - u) * (1.0 - v) * (1.0 - w), u * (1.0 - v) * (1.0 - w), v * (1.0 - w), w };
        const int at = tensor::index(P, i, j, k);
        for (int a = 0; a < 3; ++a)
        {
          lattice[a][at] = interpolate(coordinate[a], L);
        }
        lattice[3][at] = interpolate(field, L);
      }
  for (int a = 0; a < 3; ++a)
  {
    double* form = lattice[a];
    // At a power of two's scale near 1 (exact): the conversion's sums overflow only where the
    // coefficients themselves do (coordinates: far inside double range, kMaxCellSize).
    const double scale = scaleFor(bernstein::magnitude(form, N));
    for (int k = 0; k < N; ++k)
    {
      form[k] *= scale;
    }
    tensor::lagrangeToBernstein<P>(form);
    for (int k = 0; k < N; ++k)
    {
      form[k] /= scale;
    }
  }
  tensor::lagrangeToBernstein<P>(lattice[3]);
  for (int k = 0; k < N; ++k)
  {
    tensorNodes[k] = glm::dvec3(lattice[0][k], lattice[1][k], lattice[2][k]);
    tensorValues[k] = lattice[3][k];
  }
  return fieldScale;
}

/// Runs `step` with std::integral_constant<int, P> for a hexahedron's order P = 1..4.
template <typename Step>
decltype(auto) forHexahedronOrder(int order, Step&& step)
{
  switch (order)
  {
    case 1:
      return step(std::integral_constant<int, 1>{});
    case 2:
      return step(std::integral_constant<int, 2>{});
    case 3:
      return step(std::integral_constant<int, 3>{});
    default: // 4: no table has another order (kMaxHexahedronOrder; TestCellTypes checks each)
      static_assert(kMaxHexahedronOrder == 4, "a case per order");
      return step(std::integral_constant<int, 4>{});
  }
}

/// One hexahedron kind: order P, straight (the map affine) or curved.
template <int P, bool Curved>
struct HexahedronCell
{
  static constexpr int kNodes = tensor::count(P);
  /// The nodes its record is made from: all of its tensor form.
  static constexpr int kRecordNodes = kNodes;
  /// What its record keeps beside it: kHeader numbers (origin, scale, affine frame and its
  /// inverse), the map's control points in local coordinates (3 kNodes) and the scaled field; a
  /// curved cell's on the cube widened by kBarycentricTolerance (its solve's domain).
  static constexpr int kHeader = 24;
  static constexpr int kRecordCoefficients = kHeader + 4 * kNodes;

  /// validate: the frame's checks (QuadraticTetCell's on the tetrahedron of the nodes at
  /// parametric (0,0,0), (1,0,0), (0,1,0), (0,0,1)); kCurved when a node as given (`given`,
  /// VTK's order) is off where the frame's affine map puts it (a node's tolerance, as for every
  /// cell: the tensor form's making would grow its rounding); for a curved cell the sign of det J
  /// over the whole cube, from the tensor form `nodes` (kTangled when it changes or vanishes,
  /// kInverted when negative; a collapsed cell's with its factor (1 - x)^power divided out; a
  /// mirrored type's sign reversed). Pyramids are curved.
  static std::uint16_t validate(
    const glm::dvec3* nodes, const glm::dvec3* given, double pointRounding, const HexahedronNodes& table);
  /// validate without the mirrored type's reversal.
  static std::uint16_t validateForm(
    const glm::dvec3* nodes, const glm::dvec3* given, double pointRounding, const HexahedronNodes& table);

  static void valueBound(const double values[], const TransverseTest&, double& lo, double& hi)
  {
    bernstein::range(values, kNodes, lo, hi);
  }

  /// extent: the control points' box (the cell lies in their convex hull).
  static bool extent(const glm::dvec3* nodes, glm::dvec3& lo, glm::dvec3& hi);

  static void record(const glm::dvec3* nodes, const double* values, CellRecord& cell, double* coefficients);

  static bool intersect(const CellRecord& cell, const Ray& ray, const IsoValues& isoValues,
    std::size_t first, std::size_t last, double tMin, double tLimit, SurfaceHit& hit, bool& certified);

  /// contains: whether `point` lies in the cell (within kBarycentricTolerance of the cube), and
  /// its parametric point (L[1..3]).
  static bool contains(const glm::dvec3* nodes, const glm::dvec3& point, double L[4]);
  /// coordinates: contains' parametric point, or outside the cell the map's polynomial extension's
  /// as far as Newton finds it from the cube's centre.
  static void coordinates(const glm::dvec3* nodes, const glm::dvec3& point, double L[4]);

  static double interpolate(const double values[], const double L[4])
  {
    const double x[3] = { L[1], L[2], L[3] };
    const double scale = unitScale(values, kNodes);
    double c[kNodes];
    for (int k = 0; k < kNodes; ++k)
    {
      c[k] = values[k] * scale;
    }
    return tensor::evaluate<P>(c, x) / scale;
  }

  /// gradient: J^-T grad_(r,s,t) f at the parametric point L[1..3] (zero where J is singular).
  static glm::dvec3 gradient(const glm::dvec3* nodes, const double* values, const double L[4]);
};

/// A hit's world gradient from the field's (scaled) gradient in a cell's reference coordinates and
/// the map's Jacobian there (local units: X = (x - origin) geometryScale; the field scaled by
/// fieldScale); zero where the Jacobian is singular.
inline glm::dvec3 referenceToWorldGradient(const glm::dmat3& jacobian, const double parametric[3],
  double geometryScale, double fieldScale)
{
  const glm::dmat3 inverse = glm::inverse(glm::transpose(jacobian));
  const glm::dvec3 local = inverse * glm::dvec3(parametric[0], parametric[1], parametric[2]);
  if (!isFinite(local))
  {
    return glm::dvec3(0.0);
  }
  // grad_x f = s grad_X f (X = (x - origin) s); unscaled exactly unless that overflows.
  return unscaledGradient(local * geometryScale, fieldScale);
}

/// The most numbers any kind's record keeps beside it (a curved tetrahedron of the highest piece
/// order's coefficients, an order-4 hexahedron's forms).
constexpr int kMaxRecordCoefficients =
  std::max(kMaxCellNodes, HexahedronCell<kMaxHexahedronOrder, true>::kRecordCoefficients);

extern template struct HexahedronCell<1, false>;
extern template struct HexahedronCell<2, false>;
extern template struct HexahedronCell<3, false>;
extern template struct HexahedronCell<4, false>;
extern template struct HexahedronCell<1, true>;
extern template struct HexahedronCell<2, true>;
extern template struct HexahedronCell<3, true>;
extern template struct HexahedronCell<4, true>;

/// Work bounds of one box solve: boxes visited (a ray lying in the surface visits them all: 4096
/// boxes of order 4 take about 20 ms; a hit found within the budget is then uncertified), and the
/// width (of the cube) below which an unproven box is settled by Newton alone.
struct BoxSolveLimits
{
  int maxPieces = 4096;
  double minWidth = 0x1p-24;
};

/// A root of a box solve: its parametric point, its objective value, whether proven.
struct BoxRoot
{
  double x[3] = { 0.0, 0.0, 0.0 };
  double value = 0.0;
  bool certified = true;
};

/// The common root in the unit box of the three tensor forms of degree P `equations` with the
/// least `objective` value within [lo, hi] (objective null: any root), found by subdivision with
/// Krawczyk's test (HexahedronCell.h's header); root.x in the box's coordinates. False if there is
/// none. `pieces`, if given, receives the boxes visited.
template <int P>
bool solveOnUnitBox(const double* const equations[3], const double* objective, double lo, double hi,
  BoxRoot& root, const BoxSolveLimits& limits = {}, int* pieces = nullptr);

/// Newton's method on three tensor forms of degree P from x (the forms' unit coordinates): true
/// if it converges (steps down to rounding) to a finite x; the caller checks where it landed.
template <int P>
bool newtonOnBox(const double* const equations[3], double x[3]);

/// A form on the unit cube made a form on the cube widened by `tolerance` on every side, in
/// that cube's unit coordinates w (x = -tolerance + w (1 + 2 tolerance)).
template <int P>
void widen(const double* form, double tolerance, double* out);

/// solveOnUnitBox on the unit cube widened by `tolerance` (the equations and objective given on
/// the unit cube); root.x in the unit cube's coordinates.
template <int P>
bool solveOnCube(const double* const equations[3], const double* objective, double lo, double hi,
  double tolerance, BoxRoot& root, const BoxSolveLimits& limits = {}, int* pieces = nullptr);

} // namespace tetdsr
