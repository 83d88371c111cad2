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
//
// The same holds for the isoparametric tetrahedra of order P (Lagrange and Bezier cells, P = 3,
// 4): their map and field are polynomials of degree P in L (PolynomialForm<P>, coefficients in
// TetBernstein.h's canonical order), a sub-simplex's coefficients are carried down the bisection
// (bernstein::bisect), and only the Krawczyk test's R changes: the Jacobian is then not affine,
// and R is bounded by the Bernstein range of its entries (degree P - 1) over a simplex holding the
// box. solveOnSimplex, curvedGradient and inverseNewton are each one template over the form
// (BernsteinForm or PolynomialForm<P>) and its geometry (CurvedGeometry or
// IsoparametricGeometry<P>); jacobianSign's subdivision is one template over det J's pieces.
#pragma once

#include "tetdsr/math/QuadraticTet.h"
#include "tetdsr/math/TetBernstein.h"

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

/// A polynomial of degree D in the barycentric coordinates of a simplex in Bernstein form, its
/// coefficients in canonical lattice order (TetBernstein.h): on a tetrahedron (n = 3) all
/// latticeCount(D) of them, on a triangle (n = 2) the first faceLatticeCount(D) (a_3 = 0; the
/// rest unused). The curved cells of order D's map coordinates, field and ray equations.
template <int D>
struct PolynomialForm
{
  static constexpr int kDegree = D;
  static constexpr int kCount = latticeCount(D);
  double c[kCount];

  /// The form minus a constant (the B_a sum to 1, so a constant is c in every coefficient).
  PolynomialForm minus(double value) const
  {
    PolynomialForm form = *this;
    for (double& coefficient : form.c)
    {
      coefficient -= value;
    }
    return form;
  }

  /// Its restriction to the face opposite vertex `omit` of a tetrahedron (n = 3 -> 2): the
  /// face's barycentric coordinates are the other three, in order.
  PolynomialForm face(int omit) const
  {
    PolynomialForm form{};
    const auto& alpha = Lattice<D>::kTables.alpha;
    for (int a = 0; a < kCount; ++a)
    {
      if (alpha[a][omit] == 0)
      {
        int kept[3], count = 0;
        for (int k = 0; k < 4; ++k)
        {
          if (k != omit)
          {
            kept[count++] = alpha[a][k];
          }
        }
        form.c[latticeIndex(D, kept[1], kept[2], 0)] = c[a];
      }
    }
    return form;
  }
};

/// T, where a call's arguments do not deduce it (C++20's std::type_identity): an objective given
/// as nullptr takes the equations' form.
template <class T>
struct NotDeduced
{
  using type = T;
};

/// Roots in the reference n-simplex (n = 2 or 3; within `tolerance` outside it, for
/// watertight neighbours) of the n `equations` (Form: BernsteinForm, or PolynomialForm<3> or
/// <4>). With an objective: the root whose objective value is least within [lo, hi]; without
/// (nullptr): any root. Returns false when there is none. `pieces`, if given, receives the
/// number of sub-simplices visited.
template <class Form>
bool solveOnSimplex(int n, const Form* equations, const typename NotDeduced<Form>::type* objective,
  double lo, double hi,
  double tolerance, SimplexRoot& root, const SolveLimits& limits = {}, int* pieces = nullptr,
  const Levels& levels = {});

/// The geometry of a curved 10-node tetrahedron (VTK node order) in local coordinates
/// X = (x - origin) * scale, origin its vertex 0 and scale a power of two near 1 / its size.
struct CurvedGeometry
{
  using Form = BernsteinForm;
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
  /// The mean of the control points (the 16 entries of `control`), local coordinates.
  glm::dvec3 centroid() const;
};

/// The geometry of a curved tetrahedron of order P (VTK_LAGRANGE_TETRAHEDRON or
/// VTK_BEZIER_TETRAHEDRON, as Bernstein control points: HigherOrderTet.h's "Bezier layout") in
/// local coordinates X = (x - origin) * scale, origin its vertex 0 and scale a power of two near
/// 1 / its size: CurvedGeometry's steps for a map of degree P (instantiated for P = 3 and 4).
template <int P>
struct IsoparametricGeometry
{
  using Form = PolynomialForm<P>;
  static constexpr int kCount = latticeCount(P);
  glm::dvec3 origin{ 0.0 };
  double scale = 1.0;
  /// Bernstein control points, local coordinates: coordinate k of control point a (canonical
  /// order) is control[k].c[a].
  Form control[3];

  /// @param nodes the latticeCount(P) control points (world), VTK node order.
  static IsoparametricGeometry fromNodes(const glm::dvec3* nodes, double scale);

  glm::dvec3 position(const double L[4]) const;
  glm::dmat3 jacobian(const double L[4]) const;
  Form component(const glm::dvec3& axis, double offset) const;
  void pointEquations(const glm::dvec3& target, Form equations[3]) const;
  glm::dvec3 centroid() const;
};

/// The field's gradient in local coordinates X at L: J^-T grad_y f, with grad_y f from the form
/// (its derivative along L_j - L_0). Zero where J is singular.
template <class Geometry>
glm::dvec3 curvedGradient(const Geometry& geometry, const typename Geometry::Form& field,
  const double L[4]);

/// The sign of det(dX/dy) over the whole cell, from its Bernstein coefficients (a polynomial of
/// degree 3 (P - 1) in L: a cubic for the quadratic cell) on sub-simplices: Positive or Negative
/// when proven; Changes when it changes sign or vanishes somewhere (a tangled or degenerate
/// cell), or could not be proven constant within the subdivision limit.
enum class JacobianSign
{
  Positive,
  Negative,
  Changes
};
JacobianSign jacobianSign(const CurvedGeometry& geometry);
template <int P>
JacobianSign jacobianSign(const IsoparametricGeometry<P>& geometry);

/// The unconstrained inverse map (the shape functions' extension beyond the cell): Newton on
/// X(L) = target from `L`; returns false if it does not converge.
template <class Geometry>
bool inverseNewton(const Geometry& geometry, const glm::dvec3& target, double L[4]);

} // namespace tetdsr
