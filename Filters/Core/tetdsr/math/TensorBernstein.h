// Tensor-product Bernstein polynomials on the unit cube: the form of a hexahedron's map and field.
//
// A polynomial of degree P in each of r, s, t is f = sum_ijk c_ijk B_i(r) B_j(s) B_k(t) with the
// Bernstein polynomials B_i(x) = C(P, i) x^i (1 - x)^(P - i); c_ijk is at index
// i + (P + 1) (j + (P + 1) k). The facts used (Farin, "Curves and Surfaces for CAGD", ch. 5-6 and
// 15): f lies between its least and largest coefficient (the B's are non-negative and sum to 1);
// f on a sub-box has coefficients from de Casteljau's algorithm along each axis; its derivative
// along r is P sum (c_(i+1)jk - c_ijk) B_i^(P-1)(r) B_j(s) B_k(t); a product of univariate
// Bernstein polynomials is B_m^P B_n^Q = C(P, m) C(Q, n) / C(P + Q, m + n) B_(m+n)^(P+Q).
//
// The least and largest coefficient and the largest magnitude are bernstein::range and
// bernstein::magnitude (TetBernstein.h): a form's coefficients are a plain array.
#pragma once

#include "tetdsr/math/TetBernstein.h"

#include <algorithm>
#include <limits>
#include <array>
#include <cmath>

namespace tetdsr
{
namespace tensor
{

/// Coefficients of a form of degree P per axis.
constexpr int count(int P)
{
  return (P + 1) * (P + 1) * (P + 1);
}

constexpr int index(int P, int i, int j, int k)
{
  return i + (P + 1) * (j + (P + 1) * k);
}

/// The distance between neighbours along `axis` in the coefficient array.
constexpr int stride(int P, int axis)
{
  return axis == 0 ? 1 : axis == 1 ? P + 1 : (P + 1) * (P + 1);
}

/// The largest degree a binomial is looked up for: det J of an order-4 hexahedron is of degree
/// 3 * 4 - 1 per axis, the field along a ray of degree 3 * 4.
constexpr int kMaxBinomial = 12;

/// C(n, k) for 0 <= k <= n <= kMaxBinomial (exact doubles), tabulated.
struct BinomialTable
{
  double value[kMaxBinomial + 1][kMaxBinomial + 1] = {};
  constexpr BinomialTable()
  {
    for (int n = 0; n <= kMaxBinomial; ++n)
    {
      value[n][0] = 1.0;
      for (int k = 1; k <= n; ++k)
      {
        value[n][k] = value[n - 1][k - 1] + (k <= n - 1 ? value[n - 1][k] : 0.0);
      }
    }
  }
};
inline constexpr BinomialTable kBinomials{};

constexpr double binomial(int n, int k)
{
  return kBinomials.value[n][k];
}

/// The univariate Bernstein coefficients (degree P) on [0, 1] of u -> B_i^P(a + u (b - a)), for
/// every i: row i of `matrix` ((P + 1) x (P + 1)). They are the blossom of B_i^P at
/// (a^(P - m), b^m): a sum over how many of the i "x" factors take b, non-negative for a, b in
/// [0, 1] (a stable reparametrisation).
template <int P>
inline void segmentMatrix(double a, double b, double matrix[P + 1][P + 1])
{
  // Powers of a, 1 - a, b, 1 - b up to P.
  double pa[P + 1], qa[P + 1], pb[P + 1], qb[P + 1];
  pa[0] = qa[0] = pb[0] = qb[0] = 1.0;
  for (int k = 1; k <= P; ++k)
  {
    pa[k] = pa[k - 1] * a;
    qa[k] = qa[k - 1] * (1.0 - a);
    pb[k] = pb[k - 1] * b;
    qb[k] = qb[k - 1] * (1.0 - b);
  }
  for (int i = 0; i <= P; ++i)
  {
    for (int m = 0; m <= P; ++m)
    {
      // Of the P arguments, P - m are a and m are b; choose q of the b's and i - q of the a's to
      // give the factor x, the rest (1 - x).
      double sum = 0.0;
      for (int q = std::max(0, i - (P - m)); q <= std::min(i, m); ++q)
      {
        sum += binomial(P - m, i - q) * binomial(m, q) * pa[i - q] * qa[P - m - (i - q)] * pb[q] * qb[m - q];
      }
      matrix[i][m] = sum;
    }
  }
}

/// out = the form with every fibre along `axis` multiplied by `matrix` (row i: old coefficient,
/// column m: new one): the form on a sub-interval of that axis (segmentMatrix) or a basis change.
template <int P>
inline void transformAxis(const double* in, int axis, const double matrix[P + 1][P + 1], double* out)
{
  const int step = stride(P, axis);
  for (int a = 0; a <= P; ++a)
  {
    for (int b = 0; b <= P; ++b)
    {
      // The fibre's first coefficient: the other two axes at (a, b).
      const int base = axis == 0 ? index(P, 0, a, b) : axis == 1 ? index(P, a, 0, b) : index(P, a, b, 0);
      for (int m = 0; m <= P; ++m)
      {
        double sum = 0.0;
        for (int i = 0; i <= P; ++i)
        {
          sum += matrix[i][m] * in[base + i * step];
        }
        out[base + m * step] = sum;
      }
    }
  }
}

/// Halves a form along `axis` (de Casteljau at 1/2): `left` on [0, 1/2], `right` on [1/2, 1] of
/// that axis. Averages of neighbours: exact to one rounding a level.
template <int P>
inline void halve(const double* c, int axis, double* left, double* right)
{
  const int step = stride(P, axis);
  for (int a = 0; a <= P; ++a)
  {
    for (int b = 0; b <= P; ++b)
    {
      const int base = axis == 0 ? index(P, 0, a, b) : axis == 1 ? index(P, a, 0, b) : index(P, a, b, 0);
      double work[P + 1];
      for (int i = 0; i <= P; ++i)
      {
        work[i] = c[base + i * step];
      }
      for (int level = 0; level <= P; ++level)
      {
        left[base + level * step] = work[0];
        right[base + (P - level) * step] = work[P - level];
        for (int i = 0; i < P - level; ++i)
        {
          work[i] = 0.5 * (work[i] + work[i + 1]);
        }
      }
    }
  }
}

/// f at (r, s, t) and its partial derivatives (de Casteljau along t, then s, then r; the last
/// step of each gives the derivative along it). `gradient` may be null.
template <int P>
inline double evaluate(const double* c, const double x[3], double* gradient = nullptr)
{
  // Reduce along t: for each (i, j), the value and the t-derivative at t.
  double plane[(P + 1) * (P + 1)], planeT[(P + 1) * (P + 1)];
  for (int ij = 0; ij < (P + 1) * (P + 1); ++ij)
  {
    double work[P + 1];
    for (int k = 0; k <= P; ++k)
    {
      work[k] = c[ij + (P + 1) * (P + 1) * k];
    }
    for (int level = P; level > 1; --level)
    {
      for (int k = 0; k < level; ++k)
      {
        work[k] = (1.0 - x[2]) * work[k] + x[2] * work[k + 1];
      }
    }
    if constexpr (P == 0)
    {
      plane[ij] = work[0];
      planeT[ij] = 0.0;
    }
    else
    {
      plane[ij] = (1.0 - x[2]) * work[0] + x[2] * work[1];
      planeT[ij] = P * (work[1] - work[0]);
    }
  }
  // Along s, for the value and the t-derivative; the s-derivative from the value's last step.
  double line[P + 1], lineS[P + 1], lineT[P + 1];
  for (int i = 0; i <= P; ++i)
  {
    double work[P + 1], workT[P + 1];
    for (int j = 0; j <= P; ++j)
    {
      work[j] = plane[i + (P + 1) * j];
      workT[j] = planeT[i + (P + 1) * j];
    }
    for (int level = P; level > 1; --level)
    {
      for (int j = 0; j < level; ++j)
      {
        work[j] = (1.0 - x[1]) * work[j] + x[1] * work[j + 1];
        workT[j] = (1.0 - x[1]) * workT[j] + x[1] * workT[j + 1];
      }
    }
    line[i] = (1.0 - x[1]) * work[0] + x[1] * work[1];
    lineS[i] = P * (work[1] - work[0]);
    lineT[i] = (1.0 - x[1]) * workT[0] + x[1] * workT[1];
  }
  // Along r, for all three.
  double work[P + 1], workS[P + 1], workT[P + 1];
  std::copy(line, line + P + 1, work);
  std::copy(lineS, lineS + P + 1, workS);
  std::copy(lineT, lineT + P + 1, workT);
  for (int level = P; level > 1; --level)
  {
    for (int i = 0; i < level; ++i)
    {
      work[i] = (1.0 - x[0]) * work[i] + x[0] * work[i + 1];
      workS[i] = (1.0 - x[0]) * workS[i] + x[0] * workS[i + 1];
      workT[i] = (1.0 - x[0]) * workT[i] + x[0] * workT[i + 1];
    }
  }
  if (gradient)
  {
    gradient[0] = P * (work[1] - work[0]);
    gradient[1] = (1.0 - x[0]) * workS[0] + x[0] * workS[1];
    gradient[2] = (1.0 - x[0]) * workT[0] + x[0] * workT[1];
  }
  return (1.0 - x[0]) * work[0] + x[0] * work[1];
}

/// The range of f's partial derivative along `axis` over the box the coefficients are on (in that
/// box's own unit coordinates): P times the least and largest difference of neighbours.
template <int P>
inline void derivativeRange(const double* c, int axis, double& lo, double& hi)
{
  const int step = stride(P, axis);
  lo = hi = P * (c[step] - c[0]);
  for (int k = 0; k <= P; ++k)
  {
    for (int j = 0; j <= P; ++j)
    {
      for (int i = 0; i <= P; ++i)
      {
        const int n[3] = { i, j, k };
        if (n[axis] == P)
        {
          continue;
        }
        const int at = index(P, i, j, k);
        const double d = P * (c[at + step] - c[at]);
        lo = std::min(lo, d);
        hi = std::max(hi, d);
      }
    }
  }
}

/// The range of the directional derivative sum_i scale[i] d f / d t_i over the box the
/// coefficients are on (t: that box's own unit coordinates): each partial's coefficients (P times
/// neighbours' differences, of degree P - 1 along its axis) raised to degree P along it, summed
/// coefficient by coefficient, least and largest. Tighter than combining the partials' ranges,
/// whose extremes need not fall together.
template <int P>
inline void directionalRange(const double* c, const double scale[3], double& lo, double& hi)
{
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (int k = 0; k <= P; ++k)
    for (int j = 0; j <= P; ++j)
      for (int i = 0; i <= P; ++i)
      {
        const int n[3] = { i, j, k };
        const int at = index(P, i, j, k);
        double sum = 0.0;
        for (int axis = 0; axis < 3; ++axis)
        {
          if (scale[axis] == 0.0)
            continue;
          const int step = stride(P, axis);
          const int m = n[axis];
          // Degree elevation: e_m = (m / P) q_{m-1} + (1 - m / P) q_m, q_m = P (c_{m+1} - c_m).
          double e = 0.0;
          if (m > 0)
            e += m * (c[at] - c[at - step]);
          if (m < P)
            e += (P - m) * (c[at + step] - c[at]);
          sum += scale[axis] * e;
        }
        lo = std::min(lo, sum);
        hi = std::max(hi, sum);
      }
}

/// The inverse of the matrix B_j^P(i / P) (rows i: equispaced points), computed once per P: nodal
/// values on the equispaced lattice times it (along each axis) give Bernstein coefficients. Its
/// infinity norm (largest absolute row sum) is 1, 3, 5.7, 15.2 for P = 1..4 (Lagrange to Bernstein
/// conversion; HexahedronNodes::roundingGrowth takes it per axis).
template <int P>
struct LagrangeToBernstein
{
  double matrix[P + 1][P + 1]; ///< row i: nodal value i, column m: coefficient m

  static const LagrangeToBernstein& get()
  {
    static const LagrangeToBernstein table = [] {
      LagrangeToBernstein t{};
      long double a[P + 1][2 * (P + 1)] = {};
      for (int i = 0; i <= P; ++i)
      {
        const long double x = static_cast<long double>(i) / P;
        for (int j = 0; j <= P; ++j)
        {
          a[i][j] = static_cast<long double>(binomial(P, j)) * std::pow(x, j) * std::pow(1.0L - x, P - j);
        }
        a[i][P + 1 + i] = 1.0L;
      }
      // Gauss-Jordan with partial pivoting, long double: a -> [I | V^-1].
      for (int col = 0; col <= P; ++col)
      {
        int pivot = col;
        for (int row = col + 1; row <= P; ++row)
        {
          if (std::abs(a[row][col]) > std::abs(a[pivot][col]))
          {
            pivot = row;
          }
        }
        for (int j = 0; j < 2 * (P + 1); ++j)
        {
          std::swap(a[col][j], a[pivot][j]);
        }
        const long double diagonal = a[col][col];
        for (int j = 0; j < 2 * (P + 1); ++j)
        {
          a[col][j] /= diagonal;
        }
        for (int row = 0; row <= P; ++row)
        {
          if (row != col)
          {
            const long double factor = a[row][col];
            for (int j = 0; j < 2 * (P + 1); ++j)
            {
              a[row][j] -= factor * a[col][j];
            }
          }
        }
      }
      // coefficients c = V^-1 l: c_m = sum_i V^-1[m][i] l_i, so matrix[i][m] = V^-1[m][i].
      for (int i = 0; i <= P; ++i)
      {
        for (int m = 0; m <= P; ++m)
        {
          t.matrix[i][m] = static_cast<double>(a[m][P + 1 + i]);
        }
      }
      return t;
    }();
    return table;
  }
};

/// Nodal values on the equispaced lattice of degree P made Bernstein coefficients, in place
/// (LagrangeToBernstein along each axis).
template <int P>
inline void lagrangeToBernstein(double* form)
{
  constexpr int N = count(P);
  const auto& matrix = LagrangeToBernstein<P>::get().matrix;
  double work[N];
  transformAxis<P>(form, 0, matrix, work);
  transformAxis<P>(work, 1, matrix, form);
  transformAxis<P>(form, 2, matrix, work);
  std::copy(work, work + N, form);
}

} // namespace tensor
} // namespace tetdsr
