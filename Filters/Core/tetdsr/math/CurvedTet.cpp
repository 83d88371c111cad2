#include "tetdsr/math/CurvedTet.h"

#include "tetdsr/math/HigherOrderTet.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Rounding: the solver's tolerances, each once (the pivot tolerance of its inverses: invert()).

/// A form's Bernstein coefficient on a piece (its blossom at two of the piece's vertices) is two
/// nested sums of at most 4 products with weights in [0, 1] summing to 1, rounded by at most about
/// 8 eps of the form's largest coefficient M. Within 64 eps M of 0 (that, with a margin of 8 for
/// the rounding the coefficients bring from their own evaluation) a coefficient proves no sign.
constexpr double kBlossomRounding = 64.0 * kEpsilon;
/// A blossom of degree D is D nested sums (de Casteljau steps), so its rounding grows with D:
/// kBlossomRounding scaled by D / 2 (128 eps for degree 4: 6 roundings of at most 4 eps each in
/// a step of 4 products, with the same margin).
constexpr double blossomRounding(int degree)
{
  return kBlossomRounding * (degree / 2.0);
}
/// The Krawczyk operator's bounds are widened by this relative margin for their own rounding (sums
/// of at most 3 products, a few eps each where J is well conditioned, as where a test is tried).
/// A margin far below 1 costs no proving power, so it is a million times that.
constexpr double kKrawczykMargin = 1e-9;
/// A contracted box's half-widths stay above this (of the reference cell): an equation linear in
/// y_i contracts its width to zero, and a box of zero width could never be proven to hold its
/// root. A million times the rounding of the root's position (~1e-15), far below the smallest
/// piece (2^-12 at the default depth limit).
constexpr double kMinimumHalfWidth = 1e-9;
/// An uncertified root (at the limit) is this piece's when it lies within this many half-widths
/// of its box (plus the solve's tolerance): a tangent root spreads over neighbouring pieces, but
/// a root Newton jumped to from far away is someone else's, found (or not) by its own pieces.
constexpr double kUncertifiedReach = 2.0;
/// Newton has converged when a step moves no coordinate (all of size about 1 or less) by more
/// than a few ulps: the iterate is then the root to rounding.
constexpr double kNewtonConverged = 4.0 * kEpsilon;
/// Newton has diverged when a step exceeds this: the cell spans 1 in L, so the iterate has left
/// it for good, on its way out of double range.
constexpr double kNewtonDiverged = 1e6;
/// A bound on Newton's work, not a tolerance: from a piece's centre it converges quadratically in
/// about 6 steps; the rest allows a slow (linear) approach to a near-double root. An iterate that
/// has not converged by then is not used.
constexpr int kNewtonIterations = 40;
/// det J's Bernstein coefficients (blossoms of a cubic: 3 x 3 determinants of sums of differences
/// of control points; for order P, of degree 3 (P - 1): products of the columns' coefficients,
/// carried down the bisection) are rounded by a few tens (for order P, hundreds) of eps of the
/// product of the columns' lengths, about the largest coefficient in a well-shaped cell.
/// Coefficients within 1e-12 of the largest (orders of magnitude more, for cells less well
/// shaped) prove no sign, and a cell whose det J comes that close to 0 at a corner is taken as
/// degenerate.
constexpr double kDeterminantTolerance = 1e-12;

/// The subdivision's depth never exceeds this (whatever SolveLimits asks): its stack holds one
/// pending sibling per level. 64 levels reach 2^-21 of a tetrahedron, far below any useful limit.
constexpr int kDepthCap = 64;

/// How far (relative to a form's largest coefficient) its coefficients on a piece may be off by
/// rounding. The quadratic's are blossoms at the piece's vertices (kBlossomRounding). Those of
/// degree D are carried down the bisection (bernstein::bisect): each level a convex combination
/// of at most D + 1 coefficients, rounded by at most (D + 1) eps of the largest, for at most
/// kDepthCap levels, on top of the blossom's rounding (5e-14 for degree 4: still no sign lost).
template <class Form>
struct Rounding;
template <>
struct Rounding<BernsteinForm>
{
  static constexpr double kOnPiece = kBlossomRounding;
};
template <int D>
struct Rounding<PolynomialForm<D>>
{
  static constexpr double kOnPiece = blossomRounding(D) + kDepthCap * (D + 1) * kEpsilon;
};

// Work: the results depend on none of these (a Krawczyk test not tried, or a found root's box not
// grown, only costs bisections), only the time.

/// A Krawczyk test is tried when each preconditioned equation's coefficients spread over at most
/// this many half-widths of the box (3 widths): close to linear there, where the test can succeed.
constexpr double kNearLinearSpread = 6.0;
/// Rounds of Krawczyk contraction on a piece, while each shrinks the box to at most kUsefulShrink
/// of its width.
constexpr int kContractionRounds = 8;
constexpr double kUsefulShrink = 0.7;
/// A certified root's box is grown by kRootBoxGrowth, at most kRootBoxGrowths times (130-fold),
/// while a Krawczyk test still proves the root its only one.
constexpr int kRootBoxGrowths = 12;
constexpr double kRootBoxGrowth = 1.5;
/// The found roots' boxes kept; once there are this many, a new one replaces the one at the
/// number of pieces visited modulo this (the boxes that matter are those of the roots just found).
constexpr int kKnownBoxes = 8;

/// What a piece carries down the bisection besides its vertices: nothing for quadratic forms,
/// whose coefficients on a piece are computed from its vertices (blossoms) when asked.
struct Uncarried
{
  void splitAt(int, int, Uncarried&, Uncarried&) const {}
};

/// The Bernstein coefficients on the piece of `Slots` polynomials of degree D, split with it
/// (bernstein::bisect): cheaper than a degree-D blossom at every piece, and a preconditioned
/// combination of equations is then the combination of their coefficients (tetdsr-curved-ray-cost:
/// a ray test 1.85 times faster for degree 4, 1.4 for degree 3, than blossoms at each piece).
template <int D, int Slots>
struct Carried
{
  double c[Slots][latticeCount(D)];

  /// The halves' coefficients at the midpoint of edge (a, b): `keepA` keeps vertex a.
  void splitAt(int a, int b, Carried& keepA, Carried& keepB) const
  {
    for (int slot = 0; slot < Slots; ++slot)
    {
      bernstein::bisect<D>(c[slot], a, b, keepA.c[slot], keepB.c[slot]);
    }
  }
};

/// A sub-simplex: its n + 1 vertices in barycentric coordinates of the reference simplex, and
/// what it carries (an empty base for the quadratic: no space).
template <class Carry>
struct PieceOf : Carry
{
  double V[4][4];
  int depth;
  int levelLo = 0, levelHi = 1; ///< candidate levels [levelLo, levelHi) (Levels)

  /// Makes this the whole reference simplex (its vertices the unit points), at depth 0.
  void makeWhole()
  {
    for (int i = 0; i < 4; ++i)
    {
      for (int j = 0; j < 4; ++j)
      {
        V[i][j] = i == j ? 1.0 : 0.0;
      }
    }
    depth = 0;
  }
};

/// A solve's pieces carry, for PolynomialForm<D>, the coefficients of its n equations (the
/// field's without a level: Levels) in slots 0..n-1 and of its objective in slot 3.
template <class Form>
struct CarriedBy
{
  using type = Uncarried;
};
template <int D>
struct CarriedBy<PolynomialForm<D>>
{
  using type = Carried<D, 4>;
};
constexpr int kObjectiveSlot = 3;
template <class Form>
using PieceFor = PieceOf<typename CarriedBy<Form>::type>;
using Piece = PieceFor<BernsteinForm>;

// The forms' operations, one overload per kind of form: BernsteinForm (quadratic, blossoms at
// pairs of vertices) and PolynomialForm<D> (degree D, TetBernstein.h). SimplexSearch and the
// rest are written once over them.

template <int D>
constexpr int coefficientsOn(int n)
{
  return n == 3 ? latticeCount(D) : faceLatticeCount(D);
}

template <int n>
double magnitude(const BernsteinForm& form)
{
  double m = 0.0;
  for (int i = 0; i <= n; ++i)
  {
    for (int j = 0; j <= n; ++j)
    {
      m = std::max(m, std::abs(form.b[i][j]));
    }
  }
  return m;
}

/// Min and max of the form's Bernstein coefficients on the piece (its blossom at vertex pairs).
template <int n>
void coefficientRange(const BernsteinForm& form, const Piece& piece, double& lo, double& hi)
{
  // B V_j for each vertex j once; then each coefficient is one dot product.
  double bv[4][4];
  for (int j = 0; j <= n; ++j)
  {
    for (int a = 0; a <= n; ++a)
    {
      double sum = 0.0;
      for (int b = 0; b <= n; ++b)
      {
        sum += form.b[a][b] * piece.V[j][b];
      }
      bv[j][a] = sum;
    }
  }
  lo = kInfinity;
  hi = -kInfinity;
  for (int i = 0; i <= n; ++i)
  {
    for (int j = i; j <= n; ++j)
    {
      double c = 0.0;
      for (int a = 0; a <= n; ++a)
      {
        c += piece.V[i][a] * bv[j][a];
      }
      lo = std::min(lo, c);
      hi = std::max(hi, c);
    }
  }
}

template <int n, int D>
double magnitude(const PolynomialForm<D>& form)
{
  return bernstein::magnitude(form.c, coefficientsOn<D>(n));
}

/// Min and max of a solve's form's Bernstein coefficients on the piece: `form` itself, or what
/// the piece carries in `slot` minus `shift` (a level: the carried field has none).
template <int n>
void pieceRange(const BernsteinForm& form, const Piece& piece, int, double, double& lo, double& hi)
{
  coefficientRange<n>(form, piece, lo, hi);
}

template <int n, int D>
void pieceRange(const PolynomialForm<D>&, const PieceFor<PolynomialForm<D>>& piece, int slot,
  double shift, double& lo, double& hi)
{
  bernstein::range(piece.c[slot], coefficientsOn<D>(n), lo, hi);
  lo -= shift;
  hi -= shift;
}

/// The first piece's carried coefficients: the equations' and the objective's own.
template <int n>
void carryWhole(Piece&, const BernsteinForm*, const BernsteinForm*)
{
}

template <int n, int D>
void carryWhole(PieceFor<PolynomialForm<D>>& piece, const PolynomialForm<D>* equations,
  const PolynomialForm<D>* objective)
{
  for (int slot = 0; slot < 4; ++slot)
  {
    const PolynomialForm<D>* form = slot < n ? &equations[slot]
      : slot == kObjectiveSlot               ? objective
                                             : nullptr;
    for (int a = 0; a < latticeCount(D); ++a)
    {
      piece.c[slot][a] = form ? form->c[a] : 0.0;
    }
  }
}

/// The range on the piece of the combination sum_k weight_k equations_k (k < n; the piece's slot
/// k minus shift_k), and the combination's largest coefficient (for its rounding pad).
template <int n>
void combinedRange(const BernsteinForm* equations, const Piece& piece, const double weight[3],
  const double*, double& lo, double& hi, double& largest)
{
  BernsteinForm combined{};
  for (int k = 0; k < n; ++k)
  {
    for (int a = 0; a <= n; ++a)
    {
      for (int b = 0; b <= n; ++b)
      {
        combined.b[a][b] += weight[k] * equations[k].b[a][b];
      }
    }
  }
  coefficientRange<n>(combined, piece, lo, hi);
  largest = magnitude<n>(combined);
}

template <int n, int D>
void combinedRange(const PolynomialForm<D>*, const PieceFor<PolynomialForm<D>>& piece,
  const double weight[3], const double shift[3], double& lo, double& hi, double& largest)
{
  double combined[latticeCount(D)];
  const int count = coefficientsOn<D>(n);
  for (int a = 0; a < count; ++a)
  {
    double sum = 0.0;
    for (int k = 0; k < n; ++k)
    {
      sum += weight[k] * (piece.c[k][a] - shift[k]);
    }
    combined[a] = sum;
  }
  bernstein::range(combined, count, lo, hi);
  largest = bernstein::magnitude(combined, count);
}

/// The form's value at L.
template <int n>
double valueAt(const BernsteinForm& form, const double L[4])
{
  return form.bilinear<n>(L, L);
}

template <int n, int D>
double valueAt(const PolynomialForm<D>& form, const double L[4])
{
  return bernstein::evaluate<D>(form.c, L, n + 1);
}

/// (B L)_j - (B L)_0 for j = 1..n, times 2: the derivative along y_j = L_j (L_0 = 1 - sum y).
template <int n>
void formGradient(const BernsteinForm& form, const double L[4], double g[3])
{
  double bl[4];
  for (int i = 0; i <= n; ++i)
  {
    bl[i] = 0.0;
    for (int j = 0; j <= n; ++j)
    {
      bl[i] += form.b[i][j] * L[j];
    }
  }
  for (int j = 1; j <= n; ++j)
  {
    g[j - 1] = 2.0 * (bl[j] - bl[0]);
  }
}

/// df/dL_j - df/dL_0 for j = 1..n: the derivative along y_j = L_j (L_0 = 1 - sum y).
template <int n, int D>
void formGradient(const PolynomialForm<D>& form, const double L[4], double g[3])
{
  double d[4];
  bernstein::partials<D>(form.c, L, d, n + 1);
  for (int j = 1; j <= n; ++j)
  {
    g[j - 1] = d[j] - d[0];
  }
}

/// Inverse of an n x n matrix (n <= 3); false if singular to rounding.
template <int n>
bool invert(const double a[3][3], double inverse[3][3])
{
  // [a | I], reduced to [I | a^-1].
  double m[3][6];
  for (int r = 0; r < n; ++r)
  {
    for (int c = 0; c < n; ++c)
    {
      m[r][c] = a[r][c];
      m[r][n + c] = r == c ? 1.0 : 0.0;
    }
  }
  // Pivots at rounding level (solveLinearSystem: k^2 2^(k-1) eps = 36 eps = 8.0e-15 for 3 x 3,
  // so 1e-14): no inverse. The callers need no accuracy from it (a Krawczyk test is sound for
  // any preconditioner, Newton's result is checked), only no rounding noise; a refusal costs a
  // bisection.
  constexpr double kJacobianPivotTolerance = 1e-14;
  if (!solveLinearSystem(m, n, n, kJacobianPivotTolerance))
  {
    return false;
  }
  for (int r = 0; r < n; ++r)
  {
    for (int c = 0; c < n; ++c)
    {
      inverse[r][c] = m[r][n + c];
    }
  }
  return true;
}

/// The equations linearised at a point: their values F, Jacobian J (in y = L_1..L_n) and J^-1.
struct Linearisation
{
  double F[3], J[3][3], inverse[3][3];
};

/// F, J and J^-1 at L; false (inverse unset) where J is singular to rounding.
template <int n, class Form>
bool linearise(const Form* equations, const double L[4], Linearisation& at)
{
  for (int k = 0; k < n; ++k)
  {
    at.F[k] = valueAt<n>(equations[k], L);
    formGradient<n>(equations[k], L, at.J[k]);
  }
  return invert<n>(at.J, at.inverse);
}

/// Newton's method on the equations from L (in place). Converged when a step moves no coordinate
/// by more than a few ulps; false if it does not converge (or leaves double range).
template <int n, class Form>
bool newton(const Form* equations, double L[4])
{
  for (int iteration = 0; iteration < kNewtonIterations; ++iteration)
  {
    Linearisation at;
    if (!linearise<n>(equations, L, at))
    {
      return false;
    }
    double largest = 0.0;
    double sum = 0.0;
    for (int j = 1; j <= n; ++j)
    {
      double step = 0.0;
      for (int k = 0; k < n; ++k)
      {
        step += at.inverse[j - 1][k] * at.F[k];
      }
      L[j] -= step;
      sum += L[j];
      largest = std::max(largest, std::abs(step));
    }
    L[0] = 1.0 - sum;
    if (!std::isfinite(largest) || largest > kNewtonDiverged)
    {
      return false;
    }
    if (largest <= kNewtonConverged)
    {
      return true;
    }
  }
  return false; // oscillating at rounding level: the last iterate is as good as any, but unproven
}

/// R[j - 1] bounds |dF/dy_j (y) - dF/dy_j (m)| over the box m +- r (in y), for one equation F.
/// A quadratic's dF/dy_j is affine in y with slope a_ji: the bound is exact.
template <int n>
void jacobianDeviation(const BernsteinForm& form, const double*, const double r[3], const double*,
  double R[3])
{
  const auto& b = form.b;
  for (int j = 1; j <= n; ++j)
  {
    double sum = 0.0;
    for (int i = 1; i <= n; ++i)
    {
      const double slope = 2.0 * ((b[j][i] - b[0][i]) - (b[j][0] - b[0][0]));
      sum += std::abs(slope) * r[i - 1];
    }
    R[j - 1] = sum;
  }
}

/// For degree D, dF/dy_j is a polynomial of degree D - 1 (bernstein::derivative along
/// L_j - L_0), bounded by its Bernstein coefficients on a simplex holding the box: vertices
/// m - r and m - r + 2 n r_i e_i (in y; the box's corner simplex scaled n-fold: its points
/// z = y - (m - r) with sum_i z_i / (2 n r_i) <= 1 include every z_i <= 2 r_i). `Jm` is dF/dy at m
/// (the Krawczyk operator's own, from linearise): R = max(hi - Jm, Jm - lo).
template <int n, int D>
void jacobianDeviation(const PolynomialForm<D>& form, const double m[4], const double r[3],
  const double Jm[3], double R[3])
{
  double V[4][4] = {};
  double weight = 0.0; // the largest sum |L_k| of a vertex: how much a step can amplify rounding
  for (int v = 0; v <= n; ++v)
  {
    double sum = 0.0;
    for (int i = 1; i <= n; ++i)
    {
      V[v][i] = m[i] - r[i - 1] + (v == i ? 2.0 * n * r[i - 1] : 0.0);
      sum += V[v][i];
    }
    V[v][0] = 1.0 - sum;
    double absolute = 0.0;
    for (int k = 0; k <= n; ++k)
    {
      absolute += std::abs(V[v][k]);
    }
    weight = std::max(weight, absolute);
  }
  // The sub-simplex coefficients' rounding: D - 1 steps, each amplifying by at most `weight`,
  // of coefficients whose own rounding is one subtraction: blossomRounding's argument, with
  // the weights no longer summing to 1.
  const double amplification = std::pow(weight, D - 1);
  for (int j = 1; j <= n; ++j)
  {
    double derivative[latticeCount(D - 1)], onBox[latticeCount(D - 1)];
    bernstein::derivative<D>(form.c, j, 0, derivative);
    bernstein::onSubSimplex<D - 1>(derivative, V, n, onBox);
    double lo, hi;
    bernstein::range(onBox, coefficientsOn<D - 1>(n), lo, hi);
    const double pad = blossomRounding(D) * amplification *
      bernstein::magnitude(derivative, coefficientsOn<D - 1>(n));
    R[j - 1] = std::max(hi - Jm[j - 1], Jm[j - 1] - lo) + pad;
  }
}

enum class Krawczyk
{
  Unique,  ///< exactly one root in the box
  None,    ///< no root in the box
  Unknown
};

/// The Krawczyk operator K(X) = m - Y F(m) + (I - Y J(X)) (X - m) on the box X = m +- r
/// (coordinates y_1..y_n), Y = J(m)^-1: every root in X lies in K(X); K(X) inside X proves
/// exactly one root in X, K(X) disjoint from X proves none. Evaluated in double, its bounds
/// widened by kKrawczykMargin.
template <int n, class Form>
Krawczyk krawczyk(const Form* equations, const double m[4], const double r[3],
  double image[3][2], const Linearisation* centre = nullptr)
{
  // F(m), J(m) and Y = J(m)^-1: given, or computed here.
  Linearisation at;
  if (centre)
  {
    at = *centre;
  }
  else if (!linearise<n>(equations, m, at))
  {
    return Krawczyk::Unknown;
  }
  const auto& F = at.F;
  const auto& J = at.J;
  const auto& Y = at.inverse;
  // R[k][j] bounds |J_kj(y) - J_kj(m)| over the box.
  double R[3][3];
  for (int k = 0; k < n; ++k)
  {
    jacobianDeviation<n>(equations[k], m, r, J[k], R[k]);
  }
  bool inside = true;
  for (int i = 0; i < n; ++i)
  {
    double yf = 0.0;
    for (int k = 0; k < n; ++k)
    {
      yf += Y[i][k] * F[k];
    }
    double spread = 0.0;
    for (int j = 0; j < n; ++j)
    {
      double identityMinusYJ = i == j ? 1.0 : 0.0;
      double absYR = 0.0;
      for (int k = 0; k < n; ++k)
      {
        identityMinusYJ -= Y[i][k] * J[k][j];
        absYR += std::abs(Y[i][k]) * R[k][j];
      }
      spread += (std::abs(identityMinusYJ) + absYR) * r[j];
    }
    image[i][0] = m[i + 1] - yf - spread * (1.0 + kKrawczykMargin);
    image[i][1] = m[i + 1] - yf + spread * (1.0 + kKrawczykMargin);
    if (std::abs(yf) > (spread + r[i]) * (1.0 + kKrawczykMargin))
    {
      return Krawczyk::None; // K(X) misses X along y_i
    }
    inside = inside && (std::abs(yf) + spread) * (1.0 + kKrawczykMargin) < r[i];
  }
  return inside ? Krawczyk::Unique : Krawczyk::Unknown;
}

template <int n>
bool insideSimplex(const double L[4], double tolerance)
{
  for (int i = 0; i <= n; ++i)
  {
    if (!(L[i] >= -tolerance))
    {
      return false;
    }
  }
  return true;
}

/// The two halves of a piece, split at the midpoint of its longest edge (in barycentric
/// coordinates); they inherit its depth + 1 and its candidate levels.
template <int n, class PieceType>
void bisect(const PieceType& piece, PieceType children[2])
{
  int ea = 0, eb = 1;
  double longest = -1.0;
  for (int a = 0; a <= n; ++a)
  {
    for (int b = a + 1; b <= n; ++b)
    {
      double length = 0.0;
      for (int i = 0; i <= n; ++i)
      {
        const double d = piece.V[a][i] - piece.V[b][i];
        length += d * d;
      }
      if (length > longest)
      {
        longest = length;
        ea = a;
        eb = b;
      }
    }
  }
  children[0] = children[1] = piece;
  for (int i = 0; i <= n; ++i)
  {
    const double mid = 0.5 * (piece.V[ea][i] + piece.V[eb][i]);
    children[0].V[eb][i] = mid;
    children[1].V[ea][i] = mid;
  }
  piece.splitAt(ea, eb, children[0], children[1]);
  children[0].depth = children[1].depth = piece.depth + 1;
}

/// A piece's centre m (barycentric) and, if wanted, the half-widths r of the box around it in
/// y = (L_1..L_n).
template <int n, class PieceType>
void centreOf(const PieceType& piece, double m[4], double* r = nullptr)
{
  for (int i = 0; i < 4; ++i)
  {
    m[i] = 0.0;
  }
  for (int v = 0; v <= n; ++v)
  {
    for (int i = 0; i <= n; ++i)
    {
      m[i] += piece.V[v][i] / (n + 1);
    }
  }
  if (r)
  {
    for (int i = 0; i < n; ++i)
    {
      r[i] = 0.0;
      for (int v = 0; v <= n; ++v)
      {
        r[i] = std::max(r[i], std::abs(piece.V[v][i + 1] - m[i + 1]));
      }
    }
  }
}

/// Pushes the two halves, the one whose centre has the smaller objective last (popped first).
template <int n, class Form, class PieceType>
void pushNearerLast(PieceType* stack, int& top, const PieceType children[2], const Form* objective)
{
  int nearer = 0;
  if (objective)
  {
    double centre[2][4];
    centreOf<n>(children[0], centre[0]);
    centreOf<n>(children[1], centre[1]);
    nearer = valueAt<n>(*objective, centre[1]) < valueAt<n>(*objective, centre[0]);
  }
  stack[top++] = children[1 - nearer];
  stack[top++] = children[nearer];
}

/// Boxes proven to hold exactly one root, each already found: a piece inside one holds no other
/// root, so it is dropped (without them, the pieces next to a root, which cannot be certified
/// because the root is not theirs and cannot be excluded because they touch it, are bisected
/// level after level).
struct KnownBox
{
  double lo[3], hi[3];
  int level;
};

/// Whether L, a root Newton found from the centre m of a box of half-widths r, is this box's
/// (within twice its half-widths): an uncertified root is only accepted where it was looked for.
template <int n>
bool nearBox(const double L[4], const double m[4], const double r[3], double tolerance)
{
  bool near = true;
  for (int i = 1; i <= n; ++i)
  {
    near = near && std::abs(L[i] - m[i]) <= kUncertifiedReach * r[i - 1] + tolerance;
  }
  return near;
}

/// Intersects the box m +- r (in y) with its Krawczyk image, which holds all of its roots too,
/// and returns how much that shrank it: the largest ratio of new to old width.
template <int n>
double shrinkToImage(double m[4], double r[3], const double image[3][2])
{
  double shrink = 0.0, sum = 0.0;
  for (int i = 0; i < n; ++i)
  {
    const double lo = std::max(m[i + 1] - r[i], image[i][0]);
    const double hi = std::min(m[i + 1] + r[i], image[i][1]);
    shrink = std::max(shrink, (hi - lo) / (2.0 * r[i]));
    m[i + 1] = 0.5 * (lo + hi);
    r[i] = std::max(0.5 * (hi - lo), kMinimumHalfWidth);
    sum += m[i + 1];
  }
  m[0] = 1.0 - sum;
  return shrink;
}

/// Interval Newton on the box m +- r (shrunk in place): the Krawczyk test, and while it decides
/// nothing the box shrunk to its image, for at most `rounds` rounds and while that helps
/// (quadratically, near a simple root). `centre`, if given, is the linearisation at m.
template <int n, class Form>
Krawczyk contract(const Form* equations, double m[4], double r[3], int rounds,
  const Linearisation* centre)
{
  Krawczyk test = Krawczyk::Unknown;
  for (int round = 0; round < rounds; ++round)
  {
    double image[3][2];
    test = krawczyk<n>(equations, m, r, image, round == 0 ? centre : nullptr);
    if (test != Krawczyk::Unknown || shrinkToImage<n>(m, r, image) > kUsefulShrink)
    {
      break;
    }
  }
  return test;
}

/// One solveOnSimplex: a depth-first subdivision of the reference simplex, nearer child first,
/// each piece put through visit()'s stages.
template <int n, class Form>
class SimplexSearch
{
  using Piece = PieceFor<Form>;

public:
  SimplexSearch(const Form* given, const Form* objective, double lo, double hi,
    double tolerance, const SolveLimits& limits, const Levels& levels, SimplexRoot& root)
    : Given_(given)
    , Objective_(objective)
    , Lo_(lo)
    , Tolerance_(tolerance)
    , Levels_(levels)
    , Root_(root)
    , MultiLevel_(levels.count > 0)
    , MaxDepth_(std::min(limits.maxDepth, kDepthCap))
    // Separating many levels takes pieces along the ray: the budget grows with them (to 64 x).
    , MaxPieces_(limits.maxPieces * (MultiLevel_ ? std::min(levels.count, 64) : 1))
    , CurrentLevel_(MultiLevel_ ? -1 : 0)
    , Best_(hi)
  {
    for (int k = 0; k < n; ++k)
    {
      Equations_[k] = given[k];
      Pad_[k] = Rounding<Form>::kOnPiece * magnitude<n>(Equations_[k]);
    }
    LevelPad_ = Pad_[n - 1];
    ObjectivePad_ = objective ? Rounding<Form>::kOnPiece * magnitude<n>(*objective) : 0.0;
  }

  /// Runs the subdivision; true if a root was kept. `pieces`, if given, gets the pieces visited.
  bool run(int* pieces)
  {
    Piece& first = Stack_[Top_++];
    first.makeWhole();
    first.levelLo = 0;
    first.levelHi = MultiLevel_ ? Levels_.count : 1;
    carryWhole<n>(first, Given_, Objective_);
    while (Top_ > 0)
    {
      Piece piece = Stack_[--Top_];
      ++Visited_;
      const bool last = piece.depth >= MaxDepth_ || Visited_ >= MaxPieces_;
      if (visit(piece, last))
      {
        break; // any root will do
      }
    }
    if (pieces)
    {
      *pieces = Visited_;
    }
    return Found_;
  }

private:
  /// One piece, `last` when it may not be bisected: dropped, settled or bisected. True to stop.
  bool visit(Piece& piece, bool last)
  {
    // Level partition: with several levels, a piece goes on only once it keeps exactly one.
    if (MultiLevel_ && !partitionLevels(piece, last))
    {
      return false;
    }
    // Exclusion: inside a found root's box, an equation of one sign, depth outside the window.
    if (covered(piece) || signFixed(piece, n) || outsideWindow(piece))
    {
      return false;
    }
    // The piece's centre and the half-widths of the box around it, in y = (L_1..L_n).
    double m[4], r[3];
    centreOf<n>(piece, m, r);
    Linearisation centre;
    const bool haveCentre = linearise<n>(Equations_, m, centre);
    // Exclusion by the preconditioned equations, which also say whether contraction may succeed.
    bool promising = false;
    if (haveCentre && preconditionedExclusion(piece, centre, r, promising))
    {
      return false;
    }
    // Contraction: the Krawczyk test proves one root in the box, or none.
    const Krawczyk test = contract<n>(Equations_, m, r,
      (promising || last) ? kContractionRounds : 0, haveCentre ? &centre : nullptr);
    if (test == Krawczyk::None)
    {
      return false;
    }
    // Acceptance: of the proven root, or at the limit of whatever Newton finds near the piece.
    if (test == Krawczyk::Unique || last)
    {
      return settle(m, r, test == Krawczyk::Unique);
    }
    split(piece);
    return false;
  }

  /// With several levels: narrows the piece's candidates to those within its field's Bernstein
  /// range, and while several remain bisects it (or, at the limit, tries each). True when the
  /// piece goes on with exactly one, now the current level.
  bool partitionLevels(Piece& piece, bool last)
  {
    // The equations other than the field's first (they do not depend on the level).
    if (signFixed(piece, n - 1))
    {
      return false;
    }
    double fLo, fHi;
    pieceRange<n>(Given_[n - 1], piece, n - 1, 0.0, fLo, fHi);
    const double* begin = Levels_.values + piece.levelLo;
    const double* end = Levels_.values + piece.levelHi;
    piece.levelLo = static_cast<int>(
      std::lower_bound(begin, end, (fLo - LevelPad_) / Levels_.scale) - Levels_.values);
    piece.levelHi = static_cast<int>(
      std::upper_bound(begin, end, (fHi + LevelPad_) / Levels_.scale) - Levels_.values);
    if (piece.levelLo >= piece.levelHi)
    {
      return false;
    }
    if (piece.levelHi - piece.levelLo > 1)
    {
      if (outsideWindow(piece))
      {
        return false;
      }
      if (!last)
      {
        split(piece); // until each piece keeps one level (or none)
      }
      else
      {
        settleLevelsAtLimit(piece);
      }
      return false;
    }
    setLevel(piece.levelLo);
    return true;
  }

  /// At the limit with several levels: Newton for each from the piece's centre, uncertified.
  void settleLevelsAtLimit(const Piece& piece)
  {
    double m[4], r[3];
    centreOf<n>(piece, m, r);
    for (int level = piece.levelLo; level < piece.levelHi; ++level)
    {
      setLevel(level);
      double L[4] = { m[0], m[1], m[2], m[3] };
      if (newton<n>(Equations_, L) && nearBox<n>(L, m, r, Tolerance_) &&
        insideSimplex<n>(L, Tolerance_))
      {
        keep(L, false);
      }
    }
  }

  /// Whether the piece lies in the box of a root already found at the current level.
  bool covered(const Piece& piece) const
  {
    for (int b = 0; b < KnownCount_; ++b)
    {
      bool inside = Known_[b].level == CurrentLevel_;
      for (int v = 0; v <= n && inside; ++v)
      {
        for (int i = 1; i <= n; ++i)
        {
          inside = inside && piece.V[v][i] >= Known_[b].lo[i - 1] &&
            piece.V[v][i] <= Known_[b].hi[i - 1];
        }
      }
      if (inside)
      {
        return true;
      }
    }
    return false;
  }

  /// Whether one of equations [0, count) has Bernstein coefficients of one sign on the piece.
  bool signFixed(const Piece& piece, int count) const
  {
    for (int k = 0; k < count; ++k)
    {
      double cLo, cHi;
      pieceRange<n>(Equations_[k], piece, k, levelShift(k), cLo, cHi);
      if (cLo > Pad_[k] || cHi < -Pad_[k])
      {
        return true;
      }
    }
    return false;
  }

  /// Whether the piece's depth bound lies beyond the nearest root found, or before the window.
  bool outsideWindow(const Piece& piece) const
  {
    if (!Objective_)
    {
      return false;
    }
    double oLo, oHi;
    pieceRange<n>(*Objective_, piece, kObjectiveSlot, 0.0, oLo, oHi);
    return oLo > Best_ + ObjectivePad_ || oHi < Lo_ - ObjectivePad_;
  }

  /// The sign test on the equations preconditioned by the inverse Jacobian at the piece's centre
  /// (Y F, a combination of forms is a form): near a simple root each is about one coordinate's
  /// distance to it, so their convex hulls shut out far more than the raw ones. Sets `promising`
  /// when each varies over the piece by little more than the piece's own width (it is then close
  /// to linear there, and a Krawczyk test is worth its cost).
  bool preconditionedExclusion(
    const Piece& piece, const Linearisation& centre, const double r[3], bool& promising) const
  {
    promising = true;
    for (int i = 0; i < n; ++i)
    {
      double combinedPad = 0.0, shift[3];
      for (int k = 0; k < n; ++k)
      {
        combinedPad += std::abs(centre.inverse[i][k]) * Pad_[k];
        shift[k] = levelShift(k);
      }
      double cLo, cHi, combinedLargest;
      combinedRange<n>(Equations_, piece, centre.inverse[i], shift, cLo, cHi, combinedLargest);
      // The equations' pads carried through Y, twice: the second copy covers forming the
      // combination (at most 3 eps of sum |Y_ik| M_k, far below one pad); then the combined
      // form's own blossom rounding.
      combinedPad = 2.0 * combinedPad + Rounding<Form>::kOnPiece * combinedLargest;
      if (cLo > combinedPad || cHi < -combinedPad)
      {
        return true;
      }
      promising = promising && cHi - cLo <= kNearLinearSpread * r[i];
    }
    return false;
  }

  /// Acceptance: Newton from the contracted box's centre m, to the root the box was proven to
  /// hold (`certified`) or, at the limit, to one near it. True to stop (any root will do).
  bool settle(const double m[4], const double r[3], bool certified)
  {
    double L[4] = { m[0], m[1], m[2], m[3] };
    bool converged = newton<n>(Equations_, L);
    if (converged && !certified)
    {
      converged = nearBox<n>(L, m, r, Tolerance_);
    }
    if (converged && certified)
    {
      rememberRoot(L, m, r);
    }
    return converged && insideSimplex<n>(L, Tolerance_) && keep(L, certified) && !Objective_;
  }

  /// The cache: the largest box around the certified root L (from the box m +- r, growing by
  /// half while a Krawczyk test still proves the root the only one), for covered().
  void rememberRoot(const double L[4], const double m[4], const double r[3])
  {
    KnownBox box;
    box.level = CurrentLevel_;
    double radius = 0.0;
    for (int i = 0; i < n; ++i)
    {
      box.lo[i] = m[i + 1] - r[i];
      box.hi[i] = m[i + 1] + r[i];
      radius = std::max(radius, r[i]);
    }
    for (int grow = 0; grow < kRootBoxGrowths; ++grow)
    {
      radius *= kRootBoxGrowth;
      double c[4] = { L[0], L[1], L[2], L[3] }, rr[3] = { radius, radius, radius }, image[3][2];
      if (krawczyk<n>(Equations_, c, rr, image) != Krawczyk::Unique)
      {
        break;
      }
      for (int i = 0; i < n; ++i)
      {
        box.lo[i] = L[i + 1] - radius;
        box.hi[i] = L[i + 1] + radius;
      }
    }
    Known_[KnownCount_ < kKnownBoxes ? KnownCount_++ : (Visited_ % kKnownBoxes)] = box;
  }

  /// Keeps L (a root of the current level inside the simplex) if it is the nearest so far.
  bool keep(const double L[4], bool certified)
  {
    const double value = Objective_ ? valueAt<n>(*Objective_, L) : 0.0;
    if (Objective_ && !(value >= Lo_ && value <= Best_))
    {
      return false;
    }
    Found_ = true;
    Best_ = value;
    for (int i = 0; i < 4; ++i)
    {
      Root_.L[i] = i <= n ? L[i] : 0.0;
    }
    Root_.value = value;
    Root_.certified = certified;
    Root_.level = CurrentLevel_;
    return true;
  }

  /// What equation k's carried coefficients lack: the current level (Levels), for the last.
  double levelShift(int k) const
  {
    return k == n - 1 && MultiLevel_ && CurrentLevel_ >= 0
      ? Levels_.values[CurrentLevel_] * Levels_.scale
      : 0.0;
  }

  /// Makes the last equation the field minus `level` (Levels).
  void setLevel(int level)
  {
    if (level != CurrentLevel_)
    {
      Equations_[n - 1] = Given_[n - 1].minus(Levels_.values[level] * Levels_.scale);
      Pad_[n - 1] = Rounding<Form>::kOnPiece * magnitude<n>(Equations_[n - 1]);
      CurrentLevel_ = level;
    }
  }

  /// Subdivision: the piece's two halves onto the stack, the nearer popped first.
  void split(const Piece& piece)
  {
    Piece children[2];
    bisect<n>(piece, children);
    pushNearerLast<n>(Stack_, Top_, children, Objective_);
  }

  const Form* Given_;
  const Form* Objective_;
  const double Lo_; ///< the window's start (its end: Best_)
  const double Tolerance_;
  const Levels& Levels_;
  SimplexRoot& Root_;
  const bool MultiLevel_;
  const int MaxDepth_;
  const int MaxPieces_;
  /// The equations being solved; with levels, the last is the given form minus the current level.
  Form Equations_[3];
  double Pad_[3]; ///< per equation: its coefficients within this of 0 prove no sign
  double LevelPad_;    ///< the field's pad, for the level partition
  double ObjectivePad_;
  int CurrentLevel_;
  bool Found_ = false;
  double Best_; ///< the objective of the nearest root kept, or the window's end
  Piece Stack_[kDepthCap + 2]; ///< depth-first: at most one pending sibling per level
  int Top_ = 0;
  int Visited_ = 0;
  KnownBox Known_[kKnownBoxes];
  int KnownCount_ = 0;
};
} // namespace

template <class Form>
bool solveOnSimplex(int n, const Form* equations, const typename NotDeduced<Form>::type* objective,
  double lo, double hi,
  double tolerance, SimplexRoot& root, const SolveLimits& limits, int* pieces, const Levels& levels)
{
  return n == 2
    ? SimplexSearch<2, Form>(equations, objective, lo, hi, tolerance, limits, levels, root).run(pieces)
    : SimplexSearch<3, Form>(equations, objective, lo, hi, tolerance, limits, levels, root).run(pieces);
}

template bool solveOnSimplex(int, const BernsteinForm*, const BernsteinForm*, double, double,
  double, SimplexRoot&, const SolveLimits&, int*, const Levels&);
template bool solveOnSimplex(int, const PolynomialForm<3>*, const PolynomialForm<3>*, double,
  double, double, SimplexRoot&, const SolveLimits&, int*, const Levels&);
template bool solveOnSimplex(int, const PolynomialForm<4>*, const PolynomialForm<4>*, double,
  double, double, SimplexRoot&, const SolveLimits&, int*, const Levels&);

CurvedGeometry CurvedGeometry::fromNodes(const glm::dvec3 nodes[10], double scale)
{
  CurvedGeometry g;
  g.origin = nodes[0];
  g.scale = scale;
  glm::dvec3 local[10];
  for (int k = 0; k < 10; ++k)
  {
    local[k] = (nodes[k] - nodes[0]) * scale;
  }
  for (int i = 0; i < 4; ++i)
  {
    g.control[i][i] = local[i];
  }
  for (int e = 0; e < 6; ++e)
  {
    const int a = kEdgeVertices[e][0], b = kEdgeVertices[e][1];
    g.control[a][b] = g.control[b][a] = 2.0 * local[4 + e] - 0.5 * (local[a] + local[b]);
  }
  return g;
}

glm::dvec3 CurvedGeometry::position(const double L[4]) const
{
  glm::dvec3 x(0.0);
  for (int i = 0; i < 4; ++i)
  {
    glm::dvec3 row(0.0);
    for (int j = 0; j < 4; ++j)
    {
      row += L[j] * control[i][j];
    }
    x += L[i] * row;
  }
  return x;
}

glm::dmat3 CurvedGeometry::jacobian(const double L[4]) const
{
  glm::dvec3 pl[4];
  for (int i = 0; i < 4; ++i)
  {
    pl[i] = glm::dvec3(0.0);
    for (int j = 0; j < 4; ++j)
    {
      pl[i] += L[j] * control[i][j];
    }
  }
  return glm::dmat3(2.0 * (pl[1] - pl[0]), 2.0 * (pl[2] - pl[0]), 2.0 * (pl[3] - pl[0]));
}

BernsteinForm CurvedGeometry::component(const glm::dvec3& axis, double offset) const
{
  BernsteinForm form{};
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      form.b[i][j] = glm::dot(axis, control[i][j]) - offset;
    }
  }
  return form;
}

void CurvedGeometry::pointEquations(const glm::dvec3& target, BernsteinForm equations[3]) const
{
  for (int k = 0; k < 3; ++k)
  {
    glm::dvec3 axis(0.0);
    axis[k] = 1.0;
    equations[k] = component(axis, target[k]);
  }
}

void CurvedGeometry::box(glm::dvec3& lo, glm::dvec3& hi) const
{
  lo = glm::dvec3(kInfinity);
  hi = glm::dvec3(-kInfinity);
  for (int i = 0; i < 4; ++i)
  {
    for (int j = i; j < 4; ++j)
    {
      lo = glm::min(lo, control[i][j]);
      hi = glm::max(hi, control[i][j]);
    }
  }
  lo = origin + lo / scale;
  hi = origin + hi / scale;
}

glm::dvec3 CurvedGeometry::centroid() const
{
  glm::dvec3 centroid(0.0);
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      centroid += control[i][j] / 16.0;
    }
  }
  return centroid;
}

template <int P>
IsoparametricGeometry<P> IsoparametricGeometry<P>::fromNodes(const glm::dvec3* nodes, double scale)
{
  IsoparametricGeometry g;
  g.origin = nodes[0];
  g.scale = scale;
  for (int node = 0; node < kCount; ++node)
  {
    const glm::dvec3 local = (nodes[node] - nodes[0]) * scale;
    const int at = HigherOrderTet<P>::kLatticeOfNode[node];
    for (int k = 0; k < 3; ++k)
    {
      g.control[k].c[at] = local[k];
    }
  }
  return g;
}

template <int P>
glm::dvec3 IsoparametricGeometry<P>::position(const double L[4]) const
{
  return { bernstein::evaluate<P>(control[0].c, L), bernstein::evaluate<P>(control[1].c, L),
    bernstein::evaluate<P>(control[2].c, L) };
}

template <int P>
glm::dmat3 IsoparametricGeometry<P>::jacobian(const double L[4]) const
{
  glm::dmat3 J;
  for (int k = 0; k < 3; ++k)
  {
    double g[3];
    formGradient<3>(control[k], L, g);
    for (int j = 0; j < 3; ++j)
    {
      J[j][k] = g[j]; // glm is column-major: column j is dX/dy_j
    }
  }
  return J;
}

template <int P>
PolynomialForm<P> IsoparametricGeometry<P>::component(const glm::dvec3& axis, double offset) const
{
  Form form;
  for (int a = 0; a < kCount; ++a)
  {
    form.c[a] = axis.x * control[0].c[a] + axis.y * control[1].c[a] + axis.z * control[2].c[a] - offset;
  }
  return form;
}

template <int P>
void IsoparametricGeometry<P>::pointEquations(const glm::dvec3& target, Form equations[3]) const
{
  for (int k = 0; k < 3; ++k)
  {
    equations[k] = control[k].minus(target[k]);
  }
}

template <int P>
glm::dvec3 IsoparametricGeometry<P>::centroid() const
{
  glm::dvec3 centroid(0.0);
  for (int a = 0; a < kCount; ++a)
  {
    centroid += glm::dvec3(control[0].c[a], control[1].c[a], control[2].c[a]) / double(kCount);
  }
  return centroid;
}

template struct IsoparametricGeometry<3>;
template struct IsoparametricGeometry<4>;

template <class Geometry>
glm::dvec3 curvedGradient(const Geometry& geometry, const typename Geometry::Form& field,
  const double L[4])
{
  double g[3];
  formGradient<3>(field, L, g);
  const glm::dmat3 J = geometry.jacobian(L);
  const double det = glm::determinant(J);
  if (!(det != 0.0) || !std::isfinite(det))
  {
    return glm::dvec3(0.0);
  }
  // grad_y f = J^T grad_X f.
  return glm::inverse(glm::transpose(J)) * glm::dvec3(g[0], g[1], g[2]);
}

template glm::dvec3 curvedGradient(const CurvedGeometry&, const BernsteinForm&, const double[4]);
template glm::dvec3 curvedGradient(
  const IsoparametricGeometry<3>&, const PolynomialForm<3>&, const double[4]);
template glm::dvec3 curvedGradient(
  const IsoparametricGeometry<4>&, const PolynomialForm<4>&, const double[4]);

namespace
{
/// Column j (1..3) of the Jacobian evaluated at U (linear in U).
glm::dvec3 jacobianColumn(const CurvedGeometry& g, int j, const double U[4])
{
  glm::dvec3 c(0.0);
  for (int a = 0; a < 4; ++a)
  {
    c += (2.0 * U[a]) * (g.control[j][a] - g.control[0][a]);
  }
  return c;
}

/// The blossom of det J (a cubic) at U, V, W: the mean over the 6 ways of giving them to the
/// three columns.
double determinantBlossom(const CurvedGeometry& g, const double* U, const double* V, const double* W)
{
  const double* args[3] = { U, V, W };
  static constexpr int kPermutations[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 },
    { 2, 0, 1 }, { 2, 1, 0 } };
  double sum = 0.0;
  for (const auto& p : kPermutations)
  {
    sum += glm::determinant(glm::dmat3(jacobianColumn(g, 1, args[p[0]]),
      jacobianColumn(g, 2, args[p[1]]), jacobianColumn(g, 3, args[p[2]])));
  }
  return sum / 6.0;
}

/// det J of the quadratic cell on a piece: its coefficients there are blossoms at the piece's
/// vertices (computed for each piece), its corner values the blossoms at one vertex thrice.
struct QuadraticDeterminant
{
  using Piece = tetdsr::Piece;
  const CurvedGeometry& geometry;

  Piece whole() const
  {
    Piece first;
    first.makeWhole();
    return first;
  }

  void bound(const Piece& piece, double& lo, double& hi, double& largest) const
  {
    lo = kInfinity;
    hi = -kInfinity;
    largest = 0.0;
    for (int a = 0; a < 4; ++a)
    {
      for (int b = a; b < 4; ++b)
      {
        for (int c = b; c < 4; ++c)
        {
          const double coefficient =
            determinantBlossom(geometry, piece.V[a], piece.V[b], piece.V[c]);
          lo = std::min(lo, coefficient);
          hi = std::max(hi, coefficient);
          largest = std::max(largest, std::abs(coefficient));
        }
      }
    }
  }

  void corners(const Piece& piece, double& lo, double& hi) const
  {
    lo = kInfinity;
    hi = -kInfinity;
    for (int a = 0; a < 4; ++a)
    {
      const double value = determinantBlossom(geometry, piece.V[a], piece.V[a], piece.V[a]);
      lo = std::min(lo, value);
      hi = std::max(hi, value);
    }
  }

  void split(const Piece& piece, Piece children[2]) const { bisect<3>(piece, children); }
};

/// det J of a cell of order P, a polynomial of degree K = 3 (P - 1): its coefficients on the
/// whole cell from the columns' (bernstein::derivative) products, det = c_1 . (c_2 x c_3); on a
/// piece carried down the bisection (Carried). Its corner values are the coefficients K e_k.
template <int P>
struct PolynomialDeterminant
{
  static constexpr int K = 3 * (P - 1);
  static constexpr int kCount = latticeCount(K);
  using Piece = PieceOf<Carried<K, 1>>;
  const IsoparametricGeometry<P>& geometry;

  Piece whole() const
  {
    constexpr int kColumn = latticeCount(P - 1), kPair = latticeCount(2 * (P - 1));
    double column[3][3][kColumn]; // [j][coordinate]: d X_coordinate / d y_j
    for (int j = 0; j < 3; ++j)
    {
      for (int k = 0; k < 3; ++k)
      {
        bernstein::derivative<P>(geometry.control[k].c, j + 1, 0, column[j][k]);
      }
    }
    // (c_2 x c_3)_k = c_2[k + 1] c_3[k + 2] - c_2[k + 2] c_3[k + 1], then its dot with c_1.
    Piece first{};
    for (int k = 0; k < 3; ++k)
    {
      double plus[kPair], minus[kPair], cross[kPair], term[kCount];
      bernstein::multiply<P - 1, P - 1>(column[1][(k + 1) % 3], column[2][(k + 2) % 3], plus);
      bernstein::multiply<P - 1, P - 1>(column[1][(k + 2) % 3], column[2][(k + 1) % 3], minus);
      for (int a = 0; a < kPair; ++a)
      {
        cross[a] = plus[a] - minus[a];
      }
      bernstein::multiply<P - 1, 2 * (P - 1)>(column[0][k], cross, term);
      for (int a = 0; a < kCount; ++a)
      {
        first.c[0][a] += term[a];
      }
    }
    first.makeWhole();
    return first;
  }

  void bound(const Piece& piece, double& lo, double& hi, double& largest) const
  {
    bernstein::range(piece.c[0], kCount, lo, hi);
    largest = bernstein::magnitude(piece.c[0], kCount);
  }

  void corners(const Piece& piece, double& lo, double& hi) const
  {
    lo = kInfinity;
    hi = -kInfinity;
    for (int k = 0; k < 4; ++k)
    {
      const double value = piece.c[0][latticeIndex(K, k == 1 ? K : 0, k == 2 ? K : 0, k == 3 ? K : 0)];
      lo = std::min(lo, value);
      hi = std::max(hi, value);
    }
  }

  void split(const Piece& piece, Piece children[2]) const { bisect<3>(piece, children); }
};

/// The sign of det J over the cell by subdivision of `determinant`'s pieces: a piece whose
/// coefficients have one sign (beyond the tolerance) has it throughout; corner values (values of
/// det J) of opposite signs, or one near zero, prove a change.
template <class Determinant>
JacobianSign signBySubdivision(const Determinant& determinant)
{
  using DeterminantPiece = typename Determinant::Piece;
  // The bisection depth: 5 halvings of every edge (3 levels halve a piece), 1/32 of the cell.
  constexpr int kMaxDepth = 15;
  DeterminantPiece stack[kMaxDepth + 2];
  int top = 0;
  stack[top++] = determinant.whole();
  double tolerance = -1.0; // relative to the whole cell's coefficients
  int sign = 0;
  while (top > 0)
  {
    const DeterminantPiece piece = stack[--top];
    double lo, hi, largest;
    determinant.bound(piece, lo, hi, largest);
    if (!std::isfinite(lo) || !std::isfinite(hi))
    {
      return JacobianSign::Changes;
    }
    if (tolerance < 0.0)
    {
      tolerance = kDeterminantTolerance * largest;
    }
    int pieceSign = lo > tolerance ? 1 : hi < -tolerance ? -1 : 0;
    if (pieceSign != 0)
    {
      if (sign != 0 && pieceSign != sign)
      {
        return JacobianSign::Changes;
      }
      sign = pieceSign;
      continue;
    }
    // Values at the corners are values of det J: opposite signs (or a zero) prove a change.
    double cornerLo, cornerHi;
    determinant.corners(piece, cornerLo, cornerHi);
    if (cornerLo <= tolerance && cornerHi >= -tolerance)
    {
      return JacobianSign::Changes;
    }
    if ((sign > 0 && cornerHi < 0.0) || (sign < 0 && cornerLo > 0.0) || piece.depth >= kMaxDepth)
    {
      return JacobianSign::Changes;
    }
    DeterminantPiece children[2];
    determinant.split(piece, children);
    stack[top++] = children[0];
    stack[top++] = children[1];
  }
  return sign > 0 ? JacobianSign::Positive : JacobianSign::Negative;
}
} // namespace

JacobianSign jacobianSign(const CurvedGeometry& geometry)
{
  return signBySubdivision(QuadraticDeterminant{ geometry });
}

template <int P>
JacobianSign jacobianSign(const IsoparametricGeometry<P>& geometry)
{
  return signBySubdivision(PolynomialDeterminant<P>{ geometry });
}

template JacobianSign jacobianSign(const IsoparametricGeometry<3>&);
template JacobianSign jacobianSign(const IsoparametricGeometry<4>&);

template <class Geometry>
bool inverseNewton(const Geometry& geometry, const glm::dvec3& target, double L[4])
{
  typename Geometry::Form equations[3];
  geometry.pointEquations(target, equations);
  return newton<3>(equations, L);
}

template bool inverseNewton(const CurvedGeometry&, const glm::dvec3&, double[4]);
template bool inverseNewton(const IsoparametricGeometry<3>&, const glm::dvec3&, double[4]);
template bool inverseNewton(const IsoparametricGeometry<4>&, const glm::dvec3&, double[4]);

} // namespace tetdsr
