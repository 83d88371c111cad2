// Curved (isoparametric) 10-node tetrahedra: the cell is the image of the reference tet under the
// quadratic map x(L) of its 10 node positions, and the field is quadratic in L (not in x).
//
// Both are quadratic forms in the barycentric coordinates L of the reference tet, in Bernstein
// form like the field of a straight cell (QuadraticTet.h): x(L) = L^T P L with control points
// P_ii = x_i, P_ab = 2 x_ab - (x_a + x_b) / 2. A ray o + t d meets the isosurface f = c where
//   u . (x(L) - o) = 0,  v . (x(L) - o) = 0,  f(L) - c = 0     (u, v orthonormal, both _|_ d),
// three quadratic equations in L, and t = d . (x(L) - o) is a fourth quadratic form.
//
// solveOnSimplex finds such roots with a guarantee. On a sub-simplex of the reference tet, the
// Bernstein coefficients of a quadratic form are its blossom (polar form) at pairs of the
// sub-simplex's vertices, and the form lies between their min and max (convex hull): a piece
// where an equation's coefficients have one sign holds no root and is dropped; so is a piece whose
// depth coefficients all lie beyond the nearest root found so far. A piece that survives is put
// to a Krawczyk test on a box around it: with F(y) the equations in y = (L_1, ..., L_n), J(y) their
// Jacobian (affine in y, so its range over the box is exact), m the box's centre, r its half-widths
// and Y = J(m)^-1, if |Y F(m)| + (|I - Y J(m)| + |Y| R) r < r componentwise (R bounding
// |J(y) - J(m)| over the box), the box holds exactly one root, and Newton started at m converges
// to it. Otherwise the piece is bisected at its longest edge. Pieces reaching the depth limit
// (tangent or near-tangent roots, where no box around the root is contracting) are settled by
// Newton alone and the result is flagged uncertified.
#pragma once

#include "tetdsr/QuadraticTet.h"

#include <glm/glm.hpp>

namespace tetdsr
{

struct SimplexRoot
{
  double L[4] = { 0.0, 0.0, 0.0, 0.0 }; ///< barycentric coordinates 0..n
  double value = 0.0;                    ///< the objective there (0 without one)
  /// true when a Krawczyk test proved it the only root in a box around it; false when it was
  /// accepted by Newton alone at the subdivision limit (tangent or near-tangent roots).
  bool certified = true;
  int level = 0; ///< with Levels: which level the last equation was solved for
};

/// Several right-hand sides for the last equation: with `count` > 0 the last equation is
/// form - values[k] * scale for any k (values ascending), solved in one subdivision: a piece
/// keeps only the levels within its form's Bernstein range, so the work grows with the levels
/// the ray meets, not with their number.
struct Levels
{
  const double* values = nullptr;
  int count = 0;
  double scale = 1.0;
};

/// Work bounds of one solve: bisection depth (about 3 levels halve a piece; 36 levels reach
/// 1/4096 of the cell) and pieces visited.
struct SolveLimits
{
  int maxDepth = 36;
  int maxPieces = 2048;
};

/// Roots in the reference n-simplex (n = 2 or 3; within `tolerance` outside it, for
/// watertight neighbours) of the n quadratic `equations`. With an objective: the root whose
/// objective value is least within [lo, hi]; without (nullptr): any root. Returns false when
/// there is none. `pieces`, if given, receives the number of sub-simplices visited.
bool solveOnSimplex(int n, const BernsteinForm* equations, const BernsteinForm* objective,
  double lo, double hi, double tolerance, SimplexRoot& root, const SolveLimits& limits = {},
  int* pieces = nullptr, const Levels& levels = {});

/// The geometry of a curved 10-node tetrahedron (VTK node order) in local coordinates
/// X = (x - origin) * scale, origin its vertex 0 and scale a power of two near 1 / its size.
struct CurvedGeometry
{
  glm::dvec3 origin{ 0.0 };
  double scale = 1.0;
  glm::dvec3 control[4][4]; ///< Bernstein control points, local coordinates (symmetric)

  /// @param nodes the 10 node positions (world), VTK order.
  static CurvedGeometry fromNodes(const glm::dvec3 nodes[10], double scale);

  /// X(L), local coordinates.
  glm::dvec3 position(const double L[4]) const;
  /// dX/dy for y = (L_1, L_2, L_3), L_0 = 1 - L_1 - L_2 - L_3: column j - 1 is dX/dL_j - dX/dL_0.
  glm::dmat3 jacobian(const double L[4]) const;
  /// The form axis . X(L) - offset.
  BernsteinForm component(const glm::dvec3& axis, double offset) const;
  /// The three forms X_k(L) - target_k (local coordinates): their common root is target's
  /// preimage.
  void pointEquations(const glm::dvec3& target, BernsteinForm equations[3]) const;
  /// The box around the control points (world coordinates): it holds the cell.
  void box(glm::dvec3& lo, glm::dvec3& hi) const;
};

/// The field's gradient in local coordinates X at L: J^-T grad_y f, with grad_y f from the form
/// (its derivative along L_j - L_0). Zero where J is singular.
glm::dvec3 curvedGradient(const CurvedGeometry& geometry, const BernsteinForm& field,
  const double L[4]);

/// The sign of det(dX/dy) over the whole cell, from its Bernstein coefficients (a cubic in L)
/// on sub-simplices: Positive or Negative when proven; Changes when it changes sign or vanishes
/// somewhere (a tangled or degenerate cell), or could not be proven constant within the
/// subdivision limit.
enum class JacobianSign
{
  Positive,
  Negative,
  Changes
};
JacobianSign jacobianSign(const CurvedGeometry& geometry);

/// The unconstrained inverse map (the shape functions' extension beyond the cell): Newton on
/// X(L) = target from `L`; returns false if it does not converge.
bool inverseNewton(const CurvedGeometry& geometry, const glm::dvec3& target, double L[4]);

} // namespace tetdsr
