// The straight wedge kinds: their record (the field's triangle x segment form) and ray test.
#include "tetdsr/cells/WedgeCell.h"

#include "tetdsr/cells/IsoparametricRay.h"
#include "tetdsr/math/TetBernstein.h"

#include <algorithm>
#include <cmath>

namespace tetdsr
{

namespace
{

/// The inverse of the matrix B_j(x_i) of a triangle's Bernstein polynomials of degree P at its
/// equispaced lattice points x_i = (a / P, b / P) (both in WedgeCell's triangle order), computed
/// once per P in long double: nodal values times it give Bernstein coefficients.
template <int P>
struct TriangleLagrangeToBernstein
{
  static constexpr int n = WedgeCell<P>::kTriangle;
  double matrix[n][n]; ///< row i: nodal value i, column m: coefficient m

  static const TriangleLagrangeToBernstein& get()
  {
    static const TriangleLagrangeToBernstein table = [] {
      TriangleLagrangeToBernstein t{};
      long double a[n][2 * n] = {};
      for (int bi = 0; bi <= P; ++bi)
        for (int ai = 0; ai + bi <= P; ++ai)
        {
          const int row = WedgeCell<P>::triangleIndex(ai, bi);
          const long double r = static_cast<long double>(ai) / P, s = static_cast<long double>(bi) / P;
          for (int bj = 0; bj <= P; ++bj)
            for (int aj = 0; aj + bj <= P; ++aj)
            {
              const int c = P - aj - bj;
              a[row][WedgeCell<P>::triangleIndex(aj, bj)] = static_cast<long double>(tensor::binomial(P, aj)) *
                tensor::binomial(P - aj, bj) * std::pow(r, aj) * std::pow(s, bj) * std::pow(1.0L - r - s, c);
            }
          a[row][n + row] = 1.0L;
        }
      // Gauss-Jordan with partial pivoting: a -> [I | V^-1].
      for (int col = 0; col < n; ++col)
      {
        int pivot = col;
        for (int row = col + 1; row < n; ++row)
        {
          if (std::abs(a[row][col]) > std::abs(a[pivot][col]))
          {
            pivot = row;
          }
        }
        for (int j = 0; j < 2 * n; ++j)
        {
          std::swap(a[col][j], a[pivot][j]);
        }
        const long double diagonal = a[col][col];
        for (int j = 0; j < 2 * n; ++j)
        {
          a[col][j] /= diagonal;
        }
        for (int row = 0; row < n; ++row)
        {
          if (row != col)
          {
            const long double factor = a[row][col];
            for (int j = 0; j < 2 * n; ++j)
            {
              a[row][j] -= factor * a[col][j];
            }
          }
        }
      }
      for (int i = 0; i < n; ++i)
      {
        for (int m = 0; m < n; ++m)
        {
          t.matrix[i][m] = static_cast<double>(a[m][n + i]);
        }
      }
      return t;
    }();
    return table;
  }
};

/// One de Casteljau step on a triangle form of degree q (WedgeCell's order for that degree), in
/// place: the form of degree q - 1 whose value at any point is the blossom with L as one argument.
inline void triangleStep(double* c, int q, const double L[3])
{
  auto at = [](int degree, int a, int b) { return b * (degree + 1) - b * (b - 1) / 2 + a; };
  for (int b = 0; b < q; ++b)
  {
    for (int a = 0; a + b < q; ++a)
    {
      // (Written at or before every coefficient still to be read: in place.)
      c[at(q - 1, a, b)] = L[0] * c[at(q, a, b)] + L[1] * c[at(q, a + 1, b)] + L[2] * c[at(q, a, b + 1)];
    }
  }
}

/// The Bernstein coefficients (degree P) along the chord from A to B (barycentric) of a triangle
/// form of degree P: out[m] = its blossom at (A^(P - m), B^m).
template <int P>
void triangleOnChord(const double* form, const double A[3], const double B[3], double out[P + 1])
{
  constexpr int n = WedgeCell<P>::kTriangle;
  double prefix[n];
  std::copy(form, form + n, prefix);
  // prefix: the form after j steps with A (degree P - j); out[P - j] takes j more with B.
  for (int j = 0; j <= P; ++j)
  {
    double tail[n];
    std::copy(prefix, prefix + n, tail);
    for (int q = P - j; q > 0; --q)
    {
      triangleStep(tail, q, B);
    }
    out[P - j] = tail[0];
    if (j < P)
    {
      triangleStep(prefix, P - j, A);
    }
  }
}

/// A triangle form of degree P and its r and s derivatives at barycentric L.
template <int P>
double triangleWithGradient(const double* form, const double L[3], double& dr, double& ds)
{
  constexpr int n = WedgeCell<P>::kTriangle;
  double work[n];
  std::copy(form, form + n, work);
  for (int q = P; q > 1; --q)
  {
    triangleStep(work, q, L);
  }
  // Degree 1: d0 (L0), d1 (r), d2 (s) at indices 0, 1, 2.
  dr = P * (work[1] - work[0]);
  ds = P * (work[2] - work[0]);
  return L[0] * work[0] + L[1] * work[1] + L[2] * work[2];
}

} // namespace

template <int P>
void WedgeCell<P>::record(const glm::dvec3* nodes, const double* values, CellRecord& cell, double* coefficients)
{
  constexpr int N = Base::kNodes, H = Base::kHeader;
  // The hexahedron's record of the collapsed tensor form: its header (the frame of a wedge's
  // collapsed form is that of (r, s, t)) and the scaled field.
  double tensorRecord[Base::kRecordCoefficients];
  Base::record(nodes, values, cell, tensorRecord);
  std::copy(tensorRecord, tensorRecord + H, coefficients);
  const double* field = tensorRecord + H + 3 * N;
  // The field at the triangle x segment lattice (r, s, t) = (a, b, k) / P, the cube's (u, v, t)
  // = (a / (P - b), b / P, k / P) (any u on the collapsed edge), then made Bernstein along t and
  // on the triangle.
  double* form = coefficients + H;
  const auto& alongT = tensor::LagrangeToBernstein<P>::get().matrix;
  const auto& onTriangle = TriangleLagrangeToBernstein<P>::get().matrix;
  double nodal[P + 1][kTriangle];
  for (int k = 0; k <= P; ++k)
    for (int b = 0; b <= P; ++b)
      for (int a = 0; a + b <= P; ++a)
      {
        const double x[3] = { b < P ? static_cast<double>(a) / (P - b) : 0.5, static_cast<double>(b) / P,
          static_cast<double>(k) / P };
        nodal[k][triangleIndex(a, b)] = tensor::evaluate<P>(field, x);
      }
  for (int k = 0; k <= P; ++k)
  {
    for (int m = 0; m < kTriangle; ++m)
    {
      double sum = 0.0;
      for (int i = 0; i < kTriangle; ++i)
      {
        for (int l = 0; l <= P; ++l)
        {
          sum += onTriangle[i][m] * alongT[l][k] * nodal[l][i];
        }
      }
      form[m + kTriangle * k] = sum;
    }
  }
  cell.coefficients = coefficients;
  cell.kind = CellRecord::Kind::Wedge;
}

template <int P>
bool WedgeCell<P>::intersect(const CellRecord& cell, const Ray& ray, const IsoValues& isoValues,
  std::size_t first, std::size_t last, double tMin, double tLimit, SurfaceHit& hit, bool& certified)
{
  certified = true;
  const double* c = cell.coefficients;
  const double s = c[3];
  const double* form = c + Base::kHeader;
  auto frame = [&](int row, int col) { return c[4 + 3 * col + row]; };
  auto inverse = [&](int row, int col) { return c[13 + 3 * col + row]; };
  // The ray in local units (the wedge's corner (0, 0, 0) at the origin), re-origined near its
  // centre (1/3, 1/3, 1/2): t_world = (tCentre + T) / s.
  const glm::dvec3 origin = (ray.origin - glm::dvec3(c[0], c[1], c[2])) * s;
  const glm::dvec3& d = ray.direction;
  glm::dvec3 centre;
  for (int row = 0; row < 3; ++row)
  {
    centre[row] = frame(row, 0) / 3.0 + frame(row, 1) / 3.0 + frame(row, 2) / 2.0;
  }
  const double tCentre = glm::dot(centre - origin, d);
  const glm::dvec3 o = origin + tCentre * d;
  glm::dvec3 x0, dx;
  for (int row = 0; row < 3; ++row)
  {
    x0[row] = inverse(row, 0) * o.x + inverse(row, 1) * o.y + inverse(row, 2) * o.z;
    dx[row] = inverse(row, 0) * d.x + inverse(row, 1) * d.y + inverse(row, 2) * d.z;
  }
  // Clip to the wedge widened by kBarycentricTolerance: g0 + T g1 >= 0 for r, s, 1 - r - s, t
  // and 1 - t.
  double enter = tMin * s - tCentre, leave = tLimit * s - tCentre;
  const double w = kBarycentricTolerance;
  const double planes[5][2] = { { x0.x + w, dx.x }, { x0.y + w, dx.y }, { 1.0 + w - x0.x - x0.y, -dx.x - dx.y },
    { x0.z + w, dx.z }, { 1.0 + w - x0.z, -dx.z } };
  for (const auto& g : planes)
  {
    if (g[1] == 0.0)
    {
      if (g[0] < 0.0)
      {
        return false;
      }
      continue;
    }
    const double at = -g[0] / g[1];
    (g[1] > 0.0 ? enter : leave) = g[1] > 0.0 ? std::max(enter, at) : std::min(leave, at);
  }
  if (!(enter <= leave))
  {
    return false;
  }
  constexpr int n = kTriangle * (P + 1);
  double fieldLo, fieldHi;
  bernstein::range(form, n, fieldLo, fieldHi);
  if (spreadWithin(fieldLo, fieldHi, kTensorFormConstantRoundings))
  {
    return isoparametric::constantStretch(
      isoValues, fieldLo, fieldHi, cell.scale, tCentre, enter, leave, s, cell.cellId, hit);
  }
  // The chord's ends: barycentric on the triangle, and t.
  const glm::dvec3 a = x0 + enter * dx, b = x0 + leave * dx;
  const double A[3] = { 1.0 - a.x - a.y, a.x, a.y }, B[3] = { 1.0 - b.x - b.y, b.x, b.y };
  double segment[P + 1][P + 1];
  tensor::segmentMatrix<P>(a.z, b.z, segment);
  // along = sum_k T_k(chord) B_k(t(chord)): products of degree P and P (Bernstein: the product
  // rule's binomial weights).
  double along[2 * P + 1] = {};
  for (int k = 0; k <= P; ++k)
  {
    double onChord[P + 1];
    triangleOnChord<P>(form + kTriangle * k, A, B, onChord);
    for (int i = 0; i <= P; ++i)
    {
      const double weighted = onChord[i] * tensor::binomial(P, i);
      for (int j = 0; j <= P; ++j)
      {
        along[i + j] += weighted * segment[k][j] * tensor::binomial(P, j);
      }
    }
  }
  for (int l = 0; l <= 2 * P; ++l)
  {
    along[l] /= tensor::binomial(2 * P, l);
  }
  double nearest;
  if (!nearestBernsteinRoot<2 * P>(along, isoValues.sorted(), first, last, cell.scale, nearest, hit.isoIndex, certified))
  {
    return false;
  }
  const double T = enter + nearest * (leave - enter);
  const glm::dvec3 x = x0 + T * dx;
  // The gradient in (r, s, t): each T_k and its r, s derivatives at the hit, then along t.
  const double L[3] = { 1.0 - x.x - x.y, x.x, x.y };
  double values[P + 1], dr[P + 1], ds[P + 1];
  for (int k = 0; k <= P; ++k)
  {
    values[k] = triangleWithGradient<P>(form + kTriangle * k, L, dr[k], ds[k]);
  }
  double parametric[3], value;
  evaluateBernsteinWithDerivative<P>(values, x.z, value, parametric[2]);
  parametric[0] = evaluateBernstein<P>(dr, x.z);
  parametric[1] = evaluateBernstein<P>(ds, x.z);
  glm::dmat3 jacobian;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      jacobian[col][row] = frame(row, col);
  hit.t = (tCentre + T) / s;
  hit.regionEnd = hit.t;
  hit.cellId = cell.cellId;
  hit.gradient = referenceToWorldGradient(jacobian, parametric, s, cell.scale);
  return true;
}

template struct WedgeCell<1>;
template struct WedgeCell<2>;
template struct WedgeCell<3>;
template struct WedgeCell<4>;

} // namespace tetdsr
