// Polynomials of any degree D on a simplex in Bernstein-Bezier form: the fields and maps of the
// higher-order tetrahedra (VTK_LAGRANGE_TETRAHEDRON and VTK_BEZIER_TETRAHEDRON of orders 3 and
// 4, HigherOrderTetCell.h), and the determinant of a curved cell's Jacobian (degree 3 (D - 1)).
//
// A polynomial of degree D in the barycentric coordinates L_0..L_3 of a tetrahedron is
//   f(L) = sum_{|a| = D} c_a B_a(L),  B_a(L) = D! / (a_0! a_1! a_2! a_3!) L_0^a_0 L_1^a_1 L_2^a_2 L_3^a_3,
// over the multi-indices a of the lattice {a_k >= 0, sum a_k = D}. The facts used:
// - the B_a are non-negative and sum to 1 on the simplex, so f lies between the least and the
//   largest c_a there (convex hull); a sub-simplex's coefficients are f's blossom at its vertices
//   (de Casteljau), so the bound tightens as pieces shrink;
// - one de Casteljau step at a point U, c'_b = sum_k U_k c_{b + e_k} (|b| = D - 1), gives the
//   blossom with one argument U; D steps at L give f(L), D - 1 steps the derivatives:
//   df/dL_k = D c''_{e_k} (f taken as homogeneous of degree D, so df/dL_k are its partials);
// - along a segment from P to Q (barycentric points) f is a univariate polynomial of degree D
//   whose Bernstein coefficients on [0, 1] are the blossoms f[P^(D-k), Q^k], k = 0..D.
//
// Lattice order ("canonical"): a_3 slowest, then a_2, then a_1 (a_0 = D - the rest). Its first
// (D + 1)(D + 2) / 2 entries are those with a_3 = 0: a polynomial on the face L_3 = 0 (a triangle
// in L_0..L_2) is the same array with the rest unused.
#pragma once

#include <algorithm>
#include <vector>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace tetdsr
{

/// The number of multi-indices of degree d in 4 variables: the tetrahedral number.
constexpr int latticeCount(int d)
{
  return d < 0 ? 0 : (d + 1) * (d + 2) * (d + 3) / 6;
}

/// The number of multi-indices of degree d in 3 variables (a_3 = 0): the triangular number.
constexpr int faceLatticeCount(int d)
{
  return d < 0 ? 0 : (d + 1) * (d + 2) / 2;
}

/// The canonical position of the multi-index (d - a1 - a2 - a3, a1, a2, a3).
constexpr int latticeIndex(int d, int a1, int a2, int a3)
{
  int position = 0;
  for (int t = 0; t < a3; ++t)
  {
    position += faceLatticeCount(d - t);
  }
  for (int s = 0; s < a2; ++s)
  {
    position += d - a3 - s + 1;
  }
  return position + a1;
}

/// The lattice of degree D: its multi-indices in canonical order, and for each multi-index b of
/// degree D - 1 the positions of b + e_k (the de Casteljau step's four inputs).
template <int D>
struct Lattice
{
  static constexpr int kCount = latticeCount(D);
  static constexpr int kFaceCount = faceLatticeCount(D);

  struct Tables
  {
    std::int8_t alpha[kCount > 0 ? kCount : 1][4];
    std::uint16_t raise[latticeCount(D - 1) > 0 ? latticeCount(D - 1) : 1][4];
    double multinomial[kCount > 0 ? kCount : 1]; ///< D! / (a_0! a_1! a_2! a_3!)
    /// latticeIndex(D, 0, a2, a3) at [a3][a2]: the position of (.., a1, a2, a3) is this + a1.
    std::uint16_t rowStart[D + 1][D + 1];
  };

  static constexpr Tables makeTables()
  {
    Tables t{};
    for (int a3 = 0; a3 <= D; ++a3)
    {
      for (int a2 = 0; a2 <= D - a3; ++a2)
      {
        for (int a1 = 0; a1 <= D - a3 - a2; ++a1)
        {
          const int at = latticeIndex(D, a1, a2, a3);
          t.alpha[at][0] = static_cast<std::int8_t>(D - a1 - a2 - a3);
          t.alpha[at][1] = static_cast<std::int8_t>(a1);
          t.alpha[at][2] = static_cast<std::int8_t>(a2);
          t.alpha[at][3] = static_cast<std::int8_t>(a3);
          double m = 1.0;
          int k = 0;
          const int parts[4] = { D - a1 - a2 - a3, a1, a2, a3 };
          for (int v = 0; v < 4; ++v)
          {
            for (int j = 1; j <= parts[v]; ++j)
            {
              ++k;
              m = m * k / j; // D! / prod(a_v!) built as a product of exact binomials
            }
          }
          t.multinomial[at] = m;
        }
        t.rowStart[a3][a2] = static_cast<std::uint16_t>(latticeIndex(D, 0, a2, a3));
      }
    }
    for (int b3 = 0; b3 <= D - 1; ++b3)
    {
      for (int b2 = 0; b2 <= D - 1 - b3; ++b2)
      {
        for (int b1 = 0; b1 <= D - 1 - b3 - b2; ++b1)
        {
          const int at = latticeIndex(D - 1, b1, b2, b3);
          t.raise[at][0] = static_cast<std::uint16_t>(latticeIndex(D, b1, b2, b3));
          t.raise[at][1] = static_cast<std::uint16_t>(latticeIndex(D, b1 + 1, b2, b3));
          t.raise[at][2] = static_cast<std::uint16_t>(latticeIndex(D, b1, b2 + 1, b3));
          t.raise[at][3] = static_cast<std::uint16_t>(latticeIndex(D, b1, b2, b3 + 1));
        }
      }
    }
    return t;
  }

  static constexpr Tables kTables = makeTables();
};

namespace bernstein
{

/// One de Casteljau step at U: `out` (degree D - 1) from `in` (degree D). `variables` is 4 on
/// a tetrahedron, 3 on a triangle (U_3 unused: the coefficients with a_3 > 0 are not read).
template <int D>
inline void step(const double* in, const double U[4], double* out, int variables = 4)
{
  const auto& raise = Lattice<D>::kTables.raise;
  const int count = variables == 4 ? latticeCount(D - 1) : faceLatticeCount(D - 1);
  for (int b = 0; b < count; ++b)
  {
    double sum = U[0] * in[raise[b][0]] + U[1] * in[raise[b][1]] + U[2] * in[raise[b][2]];
    if (variables == 4)
    {
      sum += U[3] * in[raise[b][3]];
    }
    out[b] = sum;
  }
}

/// The blossom f[U_0, ..., U_{D-1}] (D points, barycentric).
template <int D>
inline double blossom(const double* c, const double (*points)[4], int variables = 4)
{
  if constexpr (D == 0)
  {
    return c[0];
  }
  else
  {
    double reduced[latticeCount(D - 1)];
    step<D>(c, points[0], reduced, variables);
    return blossom<D - 1>(reduced, points + 1, variables);
  }
}

/// f(L).
template <int D>
inline double evaluate(const double* c, const double L[4], int variables = 4)
{
  double points[D > 0 ? D : 1][4];
  for (int k = 0; k < D; ++k)
  {
    std::copy(L, L + 4, points[k]);
  }
  return blossom<D>(c, points, variables);
}

/// D - 1 de Casteljau steps at the given points: the 4 (or 3) coefficients of degree 1 left.
template <int D>
inline void reduceTo1(const double* c, const double (*points)[4], double* out, int variables)
{
  if constexpr (D <= 1)
  {
    std::copy(c, c + 4, out);
  }
  else if constexpr (D == 2)
  {
    step<2>(c, points[0], out, variables);
  }
  else
  {
    double reduced[latticeCount(D - 1)];
    step<D>(c, points[0], reduced, variables);
    reduceTo1<D - 1>(reduced, points + 1, out, variables);
  }
}

/// The partial derivatives df/dL_k of f as a homogeneous polynomial of degree D, k = 0..3
/// (or 0..2 on a triangle), at L; and f(L) itself.
template <int D>
inline double partials(const double* c, const double L[4], double d[4], int variables = 4)
{
  if constexpr (D == 0)
  {
    d[0] = d[1] = d[2] = d[3] = 0.0;
    return c[0];
  }
  else
  {
    // D - 1 steps leave the 4 coefficients of degree 1: f = sum_k L_k g_k, df/dL_k = D g_k.
    double g[4];
    if constexpr (D == 1)
    {
      std::copy(c, c + (variables == 4 ? 4 : 3), g);
    }
    else
    {
      double points[D - 1][4];
      for (int k = 0; k < D - 1; ++k)
      {
        std::copy(L, L + 4, points[k]);
      }
      reduceTo1<D>(c, points, g, variables);
    }
    double value = 0.0;
    for (int k = 0; k < variables; ++k)
    {
      d[k] = D * g[k];
      value += L[k] * g[k];
    }
    if (variables == 3)
    {
      d[3] = 0.0;
    }
    return value;
  }
}

namespace detail
{
/// The blossoms f[P^(D - k), Q^k] of a polynomial already given `taken` arguments (its degree
/// D left, its coefficients in `c`), k counted from `first`: de Casteljau steps at P and at Q
/// arranged as a triangle, each intermediate shared by the two blossoms that need it (the
/// polynomial reduced at P^a Q^b is one array for any order of the steps).
template <int Total, int D>
inline void segmentLevel(const double* const* level, const double P[4], const double Q[4], double* out)
{
  constexpr int count = Total - D + 1; // arrays at this level
  if constexpr (D == 0)
  {
    for (int k = 0; k < count; ++k)
    {
      out[k] = level[k][0];
    }
  }
  else
  {
    // count arrays of degree D (the polynomial reduced at P^(count - 1 - k) Q^k) give count + 1
    // arrays of degree D - 1: the first reduced at P once more, the others at Q.
    double next[count + 1][latticeCount(D - 1)];
    const double* nextLevel[count + 1];
    step<D>(level[0], P, next[0]);
    for (int k = 0; k < count; ++k)
    {
      step<D>(level[k], Q, next[k + 1]);
    }
    for (int k = 0; k <= count; ++k)
    {
      nextLevel[k] = next[k];
    }
    segmentLevel<Total, D - 1>(nextLevel, P, Q, out);
  }
}
} // namespace detail

/// The univariate Bernstein coefficients on [0, 1] of f along the segment from P to Q:
/// out[k] = f[P^(D - k), Q^k].
template <int D>
inline void onSegment(const double* c, const double P[4], const double Q[4], double out[D + 1])
{
  const double* level[1] = { c };
  detail::segmentLevel<D, D>(level, P, Q, out);
}

namespace detail
{
/// Fills the coefficients on the sub-simplex with vertices V[0..n] for the multi-indices that
/// give vertex `next` and beyond the remaining `D` arguments; `partial` has taken the others
/// (their counts in `taken`).
template <int D>
inline void subSimplex(const double* partial, const double (*V)[4], int n, int next, int taken[4],
  int total, double* out)
{
  if constexpr (D == 0)
  {
    out[latticeIndex(total, taken[1], taken[2], taken[3])] = partial[0];
  }
  else
  {
    for (int v = next; v <= n; ++v)
    {
      double reduced[latticeCount(D - 1)];
      step<D>(partial, V[v], reduced, n + 1);
      ++taken[v];
      subSimplex<D - 1>(reduced, V, n, v, taken, total, out);
      --taken[v];
    }
  }
}
} // namespace detail

/// f's Bernstein coefficients on the sub-simplex with vertices V[0..n] (barycentric points of
/// this simplex; n = 3, or n = 2 for a triangle), in canonical order over those vertices.
template <int D>
inline void onSubSimplex(const double* c, const double V[4][4], int n, double* out)
{
  int taken[4] = { 0, 0, 0, 0 };
  detail::subSimplex<D>(c, V, n, 0, taken, D, out);
}

/// The least and largest of `count` coefficients.
inline void range(const double* c, int count, double& lo, double& hi)
{
  lo = hi = c[0];
  for (int k = 1; k < count; ++k)
  {
    lo = std::min(lo, c[k]);
    hi = std::max(hi, c[k]);
  }
}

/// The largest magnitude of `count` coefficients.
inline double magnitude(const double* c, int count)
{
  double m = 0.0;
  for (int k = 0; k < count; ++k)
  {
    m = std::max(m, std::abs(c[k]));
  }
  return m;
}

/// The coefficients (degree D - 1) of the derivative along L_j - L_i (the direction in which
/// L_j grows and L_i shrinks, the rest fixed): D (c_{b + e_j} - c_{b + e_i}).
template <int D>
inline void derivative(const double* c, int j, int i, double* out)
{
  const auto& raise = Lattice<D>::kTables.raise;
  for (int b = 0; b < latticeCount(D - 1); ++b)
  {
    out[b] = D * (c[raise[b][j]] - c[raise[b][i]]);
  }
}

/// The product of f (degree A) and g (degree B): (f g)_c = sum_{a + b = c} C(a) C(b) / C(c)
/// f_a g_b, C the multinomials. Each coefficient a weighted mean of products.
template <int A, int B>
inline void multiply(const double* f, const double* g, double* out)
{
  constexpr int C = A + B;
  const auto& la = Lattice<A>::kTables;
  const auto& lb = Lattice<B>::kTables;
  const auto& lc = Lattice<C>::kTables;
  std::fill(out, out + latticeCount(C), 0.0);
  for (int a = 0; a < latticeCount(A); ++a)
  {
    for (int b = 0; b < latticeCount(B); ++b)
    {
      const int at = latticeIndex(C, la.alpha[a][1] + lb.alpha[b][1], la.alpha[a][2] + lb.alpha[b][2],
        la.alpha[a][3] + lb.alpha[b][3]);
      out[at] += la.multinomial[a] * lb.multinomial[b] * f[a] * g[b];
    }
  }
  for (int k = 0; k < latticeCount(C); ++k)
  {
    out[k] /= lc.multinomial[k];
  }
}

/// The two halves of f's simplex split at the midpoint M of its edge (a, b): `keepA` on the
/// half that keeps vertex a (b replaced by M), `keepB` on the other. The blossom is affine in
/// each argument, so replacing k copies of V_b by (V_a + V_b) / 2 gives
/// 2^-k sum_j C(k, j) c_{beta + j (e_a - e_b)}.
template <int D>
inline void bisect(const double* c, int a, int b, double* keepA, double* keepB)
{
  const auto& t = Lattice<D>::kTables;
  // 2^-copies, exactly (the same as ldexp's scaling, without its call).
  double halves[D + 1];
  halves[0] = 1.0;
  for (int copies = 1; copies <= D; ++copies)
  {
    halves[copies] = 0.5 * halves[copies - 1];
  }
  for (int k = 0; k < latticeCount(D); ++k)
  {
    for (int side = 0; side < 2; ++side)
    {
      const int from = side == 0 ? b : a; // the vertex replaced by M
      const int to = side == 0 ? a : b;
      int beta[4] = { t.alpha[k][0], t.alpha[k][1], t.alpha[k][2], t.alpha[k][3] };
      const int copies = beta[from];
      double sum = 0.0, binomial = 1.0;
      for (int j = 0; j <= copies; ++j)
      {
        sum += binomial * c[t.rowStart[beta[3]][beta[2]] + beta[1]];
        binomial = binomial * (copies - j) / (j + 1);
        --beta[from];
        ++beta[to];
      }
      (side == 0 ? keepA : keepB)[k] = sum * halves[copies];
    }
  }
}

} // namespace bernstein

/// f(u) for univariate Bernstein coefficients b[0..D] on [0, 1] (de Casteljau: stable).
template <int D>
inline double evaluateBernstein(const double b[D + 1], double u)
{
  double work[D + 1];
  std::copy(b, b + D + 1, work);
  for (int level = D; level > 0; --level)
  {
    for (int k = 0; k < level; ++k)
    {
      work[k] = (1.0 - u) * work[k] + u * work[k + 1];
    }
  }
  return work[0];
}

/// f(u) and f'(u) for univariate Bernstein coefficients b[0..D] on [0, 1]: de Casteljau down to
/// the two values a, c of degree 1, then f = (1 - u) a + u c and f' = D (c - a).
template <int D>
inline void evaluateBernsteinWithDerivative(const double b[D + 1], double u, double& f, double& derivative)
{
  double work[D + 1];
  std::copy(b, b + D + 1, work);
  for (int level = D; level > 1; --level)
  {
    for (int k = 0; k < level; ++k)
    {
      work[k] = (1.0 - u) * work[k] + u * work[k + 1];
    }
  }
  f = (1.0 - u) * work[0] + u * work[1];
  derivative = D * (work[1] - work[0]);
}

/// The root in [lo, hi] of f, whose values at lo and hi differ in sign (or are zero): Newton's
/// method kept inside the bracket, which each step's sign narrows; a step leaving it, or one that
/// would not at least halve the step before last (a slow or wandering Newton), bisects instead.
/// Converged when |f| is within the rounding of its own evaluation (de Casteljau: about D eps
/// times the largest coefficient), a step moves by a few ulps of the unit interval, or the bracket
/// holds no double between its ends: the root to rounding of f's evaluation, in about 6 steps
/// (the earlier rule, which bisected whenever the bracket did not halve in two steps, also when
/// Newton closed in from one side, took 31 on random quartics).
template <int D>
double refineBernsteinRoot(const double b[D + 1], double lo, double hi)
{
  const double fLo = evaluateBernstein<D>(b, lo), fHi = evaluateBernstein<D>(b, hi);
  if (fLo == 0.0)
  {
    return lo;
  }
  if (fHi == 0.0)
  {
    return hi;
  }
  const double rounding = 2.0 * D * std::numeric_limits<double>::epsilon() * bernstein::magnitude(b, D + 1);
  const bool negativeAtLo = fLo < 0.0;
  // The secant of the ends as the first iterate.
  double x = lo + fLo * (lo - hi) / (fHi - fLo);
  if (!(x > lo && x < hi))
  {
    x = 0.5 * (lo + hi);
  }
  double stepBefore = hi - lo, step = stepBefore;
  for (int iteration = 0; iteration < 128; ++iteration)
  {
    double f, derivative;
    evaluateBernsteinWithDerivative<D>(b, x, f, derivative);
    if (std::abs(f) <= rounding)
    {
      return x;
    }
    ((f < 0.0) == negativeAtLo ? lo : hi) = x;
    double next = x - f / derivative;
    if (!(next > lo && next < hi) || std::abs(2.0 * f) > std::abs(stepBefore * derivative))
    {
      next = 0.5 * (lo + hi);
    }
    stepBefore = step;
    step = next - x;
    if (!(next > lo && next < hi))
    {
      return x; // the bracket holds no double between its ends
    }
    if (std::abs(step) <= 4.0 * std::numeric_limits<double>::epsilon())
    {
      return next;
    }
    x = next;
  }
  return x;
}

namespace detail
{
/// An interval [lo, hi] of [0, 1] and the polynomial's Bernstein coefficients on it.
template <int D>
struct RootInterval
{
  double lo, hi;
  double c[D + 1];
};

/// The two halves of an interval, by de Casteljau at its middle.
template <int D>
void halve(const RootInterval<D>& piece, RootInterval<D>& left, RootInterval<D>& right)
{
  left.lo = piece.lo;
  left.hi = right.lo = 0.5 * (piece.lo + piece.hi);
  right.hi = piece.hi;
  double work[D + 1];
  std::copy(piece.c, piece.c + D + 1, work);
  for (int level = 0; level <= D; ++level)
  {
    left.c[level] = work[0];
    right.c[D - level] = work[D - level];
    for (int k = 0; k < D - level; ++k)
    {
      work[k] = 0.5 * (work[k] + work[k + 1]);
    }
  }
}

/// What an interval's coefficients say about its roots.
enum class RootTest
{
  None,     ///< one sign (beyond the pad): no root
  One,      ///< exactly one root, bracketed by the ends' signs
  Unknown   ///< to be halved
};

template <int D>
RootTest rootTest(const RootInterval<D>& piece, double pad)
{
  double lo, hi;
  bernstein::range(piece.c, D + 1, lo, hi);
  if (lo > pad || hi < -pad)
  {
    return RootTest::None;
  }
  int changes = 0;
  for (int k = 0; k < D; ++k)
  {
    changes += (piece.c[k] < 0.0) != (piece.c[k + 1] < 0.0);
  }
  // One sign change proves exactly one root (Descartes' rule of signs in Bernstein form).
  return changes == 1 && (piece.c[0] < 0.0) != (piece.c[D] < 0.0) ? RootTest::One : RootTest::Unknown;
}
} // namespace detail

/// Certified first root on [0, 1] of a univariate polynomial of degree D given by its Bernstein
/// coefficients b[0..D] (b[0] = f(0), b[D] = f(1)). Coefficients of one sign exclude a root (the
/// convex hull); exactly one sign change in them proves exactly one root (Descartes' rule in
/// Bernstein form), which is then bracketed by the polynomial's own values at the interval's ends
/// and refined to rounding. Otherwise the interval is halved (de Casteljau), the left half first.
/// An interval narrower than kRootWidth whose coefficients still straddle 0 (a tangent or
/// near-tangent root: several sign changes that never separate) is taken as a root at its
/// middle, flagged uncertified. Returns false if there is no root.
template <int D>
bool firstBernsteinRoot(const double b[D + 1], double& root, bool& certified)
{
  /// Below this width (of the cell's chord) roots that do not separate are one tangent root:
  /// 2^-40, about 1e-12 of the cell, far below a pixel and far above rounding of the positions.
  constexpr double kRootWidth = 0x1p-40;
  /// Coefficients within this of the largest (relative) prove no sign: each is a de Casteljau
  /// combination of the cell's coefficients, rounded by a few eps per step.
  constexpr double kCoefficientRounding = 16.0 * D * std::numeric_limits<double>::epsilon();
  const double largest = bernstein::magnitude(b, D + 1);
  if (!(largest > 0.0) || !std::isfinite(largest))
  {
    return false;
  }
  const double pad = kCoefficientRounding * largest;
  // Depth-first, left half first: the first interval settled holds the first root.
  constexpr int kMaxDepth = 64;
  detail::RootInterval<D> stack[kMaxDepth + 2];
  int top = 0;
  stack[top].lo = 0.0;
  stack[top].hi = 1.0;
  std::copy(b, b + D + 1, stack[top].c);
  ++top;
  while (top > 0)
  {
    const detail::RootInterval<D> piece = stack[--top];
    const detail::RootTest test = detail::rootTest(piece, pad);
    if (test == detail::RootTest::None)
    {
      continue;
    }
    certified = true;
    if (piece.lo == 0.0 && std::abs(piece.c[0]) <= pad)
    {
      root = 0.0; // f(0) is zero to rounding: the root is the start
      return true;
    }
    const bool endsDiffer = (piece.c[0] < 0.0) != (piece.c[D] < 0.0);
    if (test == detail::RootTest::One ||
      ((piece.hi - piece.lo <= kRootWidth || top >= kMaxDepth) && endsDiffer))
    {
      // A sign change of f itself at the ends: a root in the interval.
      root = refineBernsteinRoot<D>(b, piece.lo, piece.hi);
      return true;
    }
    if (piece.hi - piece.lo <= kRootWidth || top >= kMaxDepth)
    {
      root = 0.5 * (piece.lo + piece.hi);
      certified = false;
      return true;
    }
    // Halve: the right half pushed first, the left popped first.
    detail::halve(piece, stack[top + 1], stack[top]);
    top += 2;
  }
  return false;
}

/// The first root in [0, 1], over the iso-values sorted[first, last) (times `scale`), of the
/// field with Bernstein coefficients `along` (degree D) on [0, 1]: each iso-value subtracted from
/// every coefficient (the Bernstein polynomials sum to 1), its first root certified
/// (firstBernsteinRoot); `index` the iso-value's, `certified` its root's. False if none has a root.
template <int D>
bool nearestBernsteinRoot(const double along[D + 1], const std::vector<double>& sorted, std::size_t first,
  std::size_t last, double scale, double& nearest, std::size_t& index, bool& certified)
{
  nearest = 2.0;
  certified = true;
  for (std::size_t k = first; k < last; ++k)
  {
    double shifted[D + 1];
    const double level = sorted[k] * scale;
    for (int j = 0; j <= D; ++j)
    {
      shifted[j] = along[j] - level;
    }
    double u;
    bool rootCertified;
    if (firstBernsteinRoot<D>(shifted, u, rootCertified) && u < nearest)
    {
      nearest = u;
      index = k;
      certified = rootCertified;
    }
  }
  return nearest <= 1.0;
}

} // namespace tetdsr
