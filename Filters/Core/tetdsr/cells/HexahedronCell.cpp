#include "tetdsr/cells/HexahedronCell.h"

#include "tetdsr/cells/IsoparametricRay.h"
#include "tetdsr/cells/QuadraticTetCell.h"
#include "tetdsr/cells/SplitCells.h"
#include "tetdsr/math/TetBernstein.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

/// The world-to-local frame of a cell: origin its first control point, unit a power of two near
/// its extent (so the solves' numbers are near 1 whatever the mesh's size and position).
template <int P>
struct LocalGeometry
{
  static constexpr int N = tensor::count(P);
  glm::dvec3 origin{ 0.0 };
  double scale = 1.0;
  double control[3][N]; ///< coordinate a of control point k: control[a][k], local units

  static LocalGeometry fromNodes(const glm::dvec3* nodes)
  {
    LocalGeometry g;
    glm::dvec3 lo = nodes[0], hi = nodes[0];
    for (int k = 1; k < N; ++k)
    {
      lo = glm::min(lo, nodes[k]);
      hi = glm::max(hi, nodes[k]);
    }
    g.origin = nodes[0];
    g.scale = scaleFor(std::max({ hi.x - lo.x, hi.y - lo.y, hi.z - lo.z }));
    for (int k = 0; k < N; ++k)
    {
      const glm::dvec3 local = (nodes[k] - g.origin) * g.scale;
      for (int a = 0; a < 3; ++a)
      {
        g.control[a][k] = local[a];
      }
    }
    return g;
  }

  glm::dvec3 position(const double x[3], glm::dmat3* jacobian = nullptr) const
  {
    glm::dvec3 at;
    for (int a = 0; a < 3; ++a)
    {
      double d[3];
      at[a] = tensor::evaluate<P>(control[a], x, d);
      if (jacobian)
      {
        for (int c = 0; c < 3; ++c)
        {
          (*jacobian)[c][a] = d[c]; // column c: dX/dx_c
        }
      }
    }
    return at;
  }

  /// The form axis . X - offset.
  void component(const glm::dvec3& axis, double offset, double* out) const
  {
    for (int k = 0; k < N; ++k)
    {
      out[k] = axis.x * control[0][k] + axis.y * control[1][k] + axis.z * control[2][k] - offset;
    }
  }

  glm::dvec3 centroid() const
  {
    glm::dvec3 sum(0.0);
    for (int k = 0; k < N; ++k)
    {
      sum += glm::dvec3(control[0][k], control[1][k], control[2][k]);
    }
    return sum / static_cast<double>(N);
  }
};

/// The three forms X_a - target_a of a map's control points (`control[a]`, local units): their
/// common root is target's preimage.
template <int P>
void pointEquations(const double* const control[3], const glm::dvec3& target, double eq[3][tensor::count(P)])
{
  for (int a = 0; a < 3; ++a)
  {
    for (int k = 0; k < tensor::count(P); ++k)
    {
      eq[a][k] = control[a][k] - target[a];
    }
  }
}

// ---- det J's sign ------------------------------------------------------------------------------

/// A tensor Bernstein form with its own degree per axis (det J's pieces and products).
struct Poly
{
  int degree[3] = { 0, 0, 0 };
  std::vector<double> c;

  int at(int i, int j, int k) const { return i + (degree[0] + 1) * (j + (degree[1] + 1) * k); }
  static Poly zero(int dr, int ds, int dt)
  {
    Poly p;
    p.degree[0] = dr;
    p.degree[1] = ds;
    p.degree[2] = dt;
    p.c.assign(static_cast<std::size_t>((dr + 1) * (ds + 1) * (dt + 1)), 0.0);
    return p;
  }
};

/// The derivative along `axis` of a degree-P tensor form (degree P - 1 along it).
Poly derivativeOf(const double* c, int P, int axis)
{
  int d[3] = { P, P, P };
  d[axis] = P - 1;
  Poly out = Poly::zero(d[0], d[1], d[2]);
  const int step = tensor::stride(P, axis);
  for (int k = 0; k <= d[2]; ++k)
    for (int j = 0; j <= d[1]; ++j)
      for (int i = 0; i <= d[0]; ++i)
      {
        const int from = tensor::index(P, i, j, k);
        out.c[static_cast<std::size_t>(out.at(i, j, k))] = P * (c[from + step] - c[from]);
      }
  return out;
}

/// The product of two forms, in Bernstein form of the summed degrees: with each coefficient
/// times its binomials (the "scaled" Bernstein form) a product is a plain convolution.
Poly multiply(const Poly& f, const Poly& g)
{
  Poly out = Poly::zero(f.degree[0] + g.degree[0], f.degree[1] + g.degree[1], f.degree[2] + g.degree[2]);
  auto scaled = [](const Poly& p) {
    std::vector<double> c(p.c.size());
    for (int k = 0; k <= p.degree[2]; ++k)
      for (int j = 0; j <= p.degree[1]; ++j)
        for (int i = 0; i <= p.degree[0]; ++i)
        {
          const auto at = static_cast<std::size_t>(p.at(i, j, k));
          c[at] = p.c[at] * tensor::binomial(p.degree[0], i) * tensor::binomial(p.degree[1], j) *
            tensor::binomial(p.degree[2], k);
        }
    return c;
  };
  const std::vector<double> fs = scaled(f), gs = scaled(g);
  for (int k1 = 0; k1 <= f.degree[2]; ++k1)
    for (int j1 = 0; j1 <= f.degree[1]; ++j1)
      for (int i1 = 0; i1 <= f.degree[0]; ++i1)
      {
        const double a = fs[static_cast<std::size_t>(f.at(i1, j1, k1))];
        for (int k2 = 0; k2 <= g.degree[2]; ++k2)
          for (int j2 = 0; j2 <= g.degree[1]; ++j2)
          {
            double* row = out.c.data() + out.at(i1, j1 + j2, k1 + k2);
            const double* from = gs.data() + g.at(0, j2, k2);
            for (int i2 = 0; i2 <= g.degree[0]; ++i2)
            {
              row[i2] += a * from[i2];
            }
          }
      }
  for (int k = 0; k <= out.degree[2]; ++k)
    for (int j = 0; j <= out.degree[1]; ++j)
      for (int i = 0; i <= out.degree[0]; ++i)
      {
        out.c[static_cast<std::size_t>(out.at(i, j, k))] /= tensor::binomial(out.degree[0], i) *
          tensor::binomial(out.degree[1], j) * tensor::binomial(out.degree[2], k);
      }
  return out;
}

void accumulate(Poly& sum, const Poly& term, double sign)
{
  if (sum.c.empty())
  {
    sum = Poly::zero(term.degree[0], term.degree[1], term.degree[2]);
  }
  for (std::size_t k = 0; k < sum.c.size(); ++k)
  {
    sum.c[k] += sign * term.c[k];
  }
}

/// Halves a form along `axis` (de Casteljau at 1/2).
void halvePoly(const Poly& p, int axis, Poly& left, Poly& right)
{
  left = p;
  right = p;
  const int n = p.degree[axis];
  int other[2], o = 0;
  for (int a = 0; a < 3; ++a)
    if (a != axis)
      other[o++] = a;
  for (int b = 0; b <= p.degree[other[1]]; ++b)
    for (int a = 0; a <= p.degree[other[0]]; ++a)
    {
      std::vector<double> work(static_cast<std::size_t>(n + 1));
      auto slot = [&](int m) {
        int idx[3];
        idx[axis] = m;
        idx[other[0]] = a;
        idx[other[1]] = b;
        return static_cast<std::size_t>(p.at(idx[0], idx[1], idx[2]));
      };
      for (int m = 0; m <= n; ++m)
        work[static_cast<std::size_t>(m)] = p.c[slot(m)];
      for (int level = 0; level <= n; ++level)
      {
        left.c[slot(level)] = work[0];
        right.c[slot(n - level)] = work[static_cast<std::size_t>(n - level)];
        for (int m = 0; m < n - level; ++m)
          work[static_cast<std::size_t>(m)] = 0.5 * (work[static_cast<std::size_t>(m)] + work[static_cast<std::size_t>(m + 1)]);
      }
    }
}

/// det J's sign over the cube: +1 or -1 when proven (every coefficient of a sub-box beyond the
/// rounding pad, one sign on all), 0 when it changes, vanishes, or is not proven within the
/// subdivision limit (a corner coefficient is det J's value there: two of opposite signs prove a
/// change).
int determinantSign(const Poly& det)
{
  const double pad = 1e-12 * bernstein::magnitude(det.c.data(), static_cast<int>(det.c.size()));
  int sign = 0;
  std::vector<std::pair<Poly, int>> stack;
  stack.emplace_back(det, 0);
  int visited = 0;
  while (!stack.empty())
  {
    auto [piece, level] = std::move(stack.back());
    stack.pop_back();
    if (++visited > 4096)
    {
      return 0;
    }
    double lo, hi;
    bernstein::range(piece.c.data(), static_cast<int>(piece.c.size()), lo, hi);
    if (lo > pad || hi < -pad)
    {
      const int pieceSign = lo > pad ? 1 : -1;
      if (sign != 0 && pieceSign != sign)
      {
        return 0;
      }
      sign = pieceSign;
      continue;
    }
    // A corner's value of the wrong sign, or near zero: changes or vanishes.
    const double corner = piece.c[0];
    if (std::abs(corner) <= pad || (sign != 0 && (corner > 0.0 ? 1 : -1) != sign) || level >= 12)
    {
      return 0;
    }
    const int axis = level % 3;
    Poly left, right;
    halvePoly(piece, axis, left, right);
    stack.emplace_back(std::move(left), level + 1);
    stack.emplace_back(std::move(right), level + 1);
  }
  return sign;
}

/// The form divided by (1 - x_axis), which it has as a factor (a collapsed cell's det J): from
/// B_i^(n-1) (1 - x) = (n - i) / n B_i^n, the quotient's coefficient i is c_i n / (n - i), i < n
/// (c_n, zero up to rounding, is dropped).
void divideByOneMinus(Poly& p, int axis)
{
  const int n = p.degree[axis];
  if (n == 0)
  {
    return;
  }
  int degree[3] = { p.degree[0], p.degree[1], p.degree[2] };
  degree[axis] = n - 1;
  Poly q = Poly::zero(degree[0], degree[1], degree[2]);
  for (int k = 0; k <= degree[2]; ++k)
    for (int j = 0; j <= degree[1]; ++j)
      for (int i = 0; i <= degree[0]; ++i)
      {
        const int index[3] = { i, j, k };
        const int m = index[axis];
        q.c[static_cast<std::size_t>(q.at(i, j, k))] =
          p.c[static_cast<std::size_t>(p.at(i, j, k))] * n / static_cast<double>(n - m);
      }
  p = std::move(q);
}

/// det(dX/d(r, s, t)) as a tensor form (local coordinates).
template <int P>
Poly jacobianDeterminant(const LocalGeometry<P>& g)
{
  Poly d[3][3]; // d[a][c] = dX_a / dx_c
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c)
      d[a][c] = derivativeOf(g.control[a], P, c);
  Poly det;
  accumulate(det, multiply(d[0][0], multiply(d[1][1], d[2][2])), 1.0);
  accumulate(det, multiply(d[0][0], multiply(d[1][2], d[2][1])), -1.0);
  accumulate(det, multiply(d[0][1], multiply(d[1][2], d[2][0])), 1.0);
  accumulate(det, multiply(d[0][1], multiply(d[1][0], d[2][2])), -1.0);
  accumulate(det, multiply(d[0][2], multiply(d[1][0], d[2][1])), 1.0);
  accumulate(det, multiply(d[0][2], multiply(d[1][1], d[2][0])), -1.0);
  return det;
}

/// The record's numbers (HexahedronCell::kRecordCoefficients).
template <int P>
struct RecordView
{
  static constexpr int N = tensor::count(P);
  const double* c;
  glm::dvec3 origin() const { return { c[0], c[1], c[2] }; }
  double scale() const { return c[3]; }
  /// The affine frame X = X0 + A x (straight cells; local units): A column-major, X0.
  double a(int row, int col) const { return c[4 + 3 * col + row]; }
  double inverse(int row, int col) const { return c[13 + 3 * col + row]; }
  const double* control(int axis) const { return c + HexahedronCell<P, false>::kHeader + axis * N; }
  const double* field() const { return c + HexahedronCell<P, false>::kHeader + 3 * N; }
};

/// The field along a segment of the cube, from a to b: Bernstein coefficients of degree 3P in
/// the segment's parameter (each axis reparametrised, then the product rule
/// B_m B_n B_q = C(P,m) C(P,n) C(P,q) / C(3P, m+n+q) B_(m+n+q)).
template <int P>
void fieldOnSegment(const double* field, const double a[3], const double b[3], double out[3 * P + 1])
{
  constexpr int N = tensor::count(P);
  double work[2][N];
  const double* in = field;
  for (int axis = 0; axis < 3; ++axis)
  {
    double matrix[P + 1][P + 1];
    tensor::segmentMatrix<P>(a[axis], b[axis], matrix);
    tensor::transformAxis<P>(in, axis, matrix, work[axis % 2]);
    in = work[axis % 2];
  }
  std::fill(out, out + 3 * P + 1, 0.0);
  for (int k = 0; k <= P; ++k)
    for (int j = 0; j <= P; ++j)
      for (int i = 0; i <= P; ++i)
      {
        out[i + j + k] += in[tensor::index(P, i, j, k)] * tensor::binomial(P, i) *
          tensor::binomial(P, j) * tensor::binomial(P, k);
      }
  for (int l = 0; l <= 3 * P; ++l)
  {
    out[l] /= tensor::binomial(3 * P, l);
  }
}

} // namespace

// ---- The cell seam's steps ---------------------------------------------------------------------

template <int P, bool Curved>
std::uint16_t HexahedronCell<P, Curved>::validate(
  const glm::dvec3* nodes, const glm::dvec3* given, double pointRounding, const HexahedronNodes& table)
{
  const std::uint16_t flags = validateForm(nodes, given, pointRounding, table);
  // A mirrored type's well-formed cell has a map of negative orientation.
  return table.mirrored && (flags & kValid) ? static_cast<std::uint16_t>(flags ^ kInverted) : flags;
}

template <int P, bool Curved>
std::uint16_t HexahedronCell<P, Curved>::validateForm(
  const glm::dvec3* nodes, const glm::dvec3* given, double pointRounding, const HexahedronNodes& table)
{
  // The frame's tetrahedron: size, volume, orientation, and the curved tolerance (a pyramid's
  // from its tensor form's corners, the same points).
  const bool pyramid = table.frameNodes[0] < 0;
  glm::dvec3 frame[4];
  for (int k = 0; k < 4; ++k)
  {
    const int corner[4] = { tensor::index(P, 0, 0, 0), tensor::index(P, P, 0, 0), tensor::index(P, 0, P, 0),
      tensor::index(P, 0, 0, P) };
    frame[k] = pyramid ? nodes[corner[k]] : given[table.frameNodes[k]];
  }
  double curvedTolerance = 0.0;
  std::uint16_t flags = QuadraticTetCell::validateVertices(frame, pointRounding, curvedTolerance);
  if (!(flags & kValid))
  {
    return flags;
  }
  // Straight when every node as given lies where the frame's affine map puts its parametric
  // point (a wedge's (r, s, t), not its cube's).
  bool curved = pyramid;
  for (int n = 0; n < table.nodes && !curved; ++n)
  {
    double r[3];
    parametricPoint(table, table.nodePoints[static_cast<std::size_t>(n)].data(), r);
    const glm::dvec3 expected =
      frame[0] + r[0] * (frame[1] - frame[0]) + r[1] * (frame[2] - frame[0]) + r[2] * (frame[3] - frame[0]);
    curved = QuadraticTetCell::offItsPlace(given[n], expected, curvedTolerance);
  }
  if (!curved)
  {
    return flags;
  }
  Poly det = jacobianDeterminant(LocalGeometry<P>::fromNodes(nodes));
  for (int k = 0; k < table.collapsedPower; ++k)
  {
    divideByOneMinus(det, table.collapsedAxis);
  }
  const int sign = determinantSign(det);
  if (sign == 0)
  {
    return kTangled;
  }
  return static_cast<std::uint16_t>(kValid | kCurved | (sign < 0 ? kInverted : 0));
}

template <int P, bool Curved>
bool HexahedronCell<P, Curved>::extent(const glm::dvec3* nodes, glm::dvec3& lo, glm::dvec3& hi)
{
  lo = hi = nodes[0];
  for (int k = 1; k < kNodes; ++k)
  {
    lo = glm::min(lo, nodes[k]);
    hi = glm::max(hi, nodes[k]);
  }
  return isFinite(lo) && isFinite(hi);
}

template <int P, bool Curved>
void HexahedronCell<P, Curved>::record(
  const glm::dvec3* nodes, const double* values, CellRecord& cell, double* coefficients)
{
  const LocalGeometry<P> g = LocalGeometry<P>::fromNodes(nodes);
  double* c = coefficients;
  std::fill(c, c + kHeader, 0.0);
  c[0] = g.origin.x;
  c[1] = g.origin.y;
  c[2] = g.origin.z;
  c[3] = g.scale;
  // The affine frame (straight cells): X = X(0) + A x, A's columns the corner edges.
  double a[3][3];
  for (int row = 0; row < 3; ++row)
  {
    a[row][0] = g.control[row][tensor::index(P, P, 0, 0)] - g.control[row][0];
    a[row][1] = g.control[row][tensor::index(P, 0, P, 0)] - g.control[row][0];
    a[row][2] = g.control[row][tensor::index(P, 0, 0, P)] - g.control[row][0];
  }
  // (Validation proved the frame's volume well away from zero.)
  const glm::dmat3 frame(a[0][0], a[1][0], a[2][0], a[0][1], a[1][1], a[2][1], a[0][2], a[1][2], a[2][2]);
  const glm::dmat3 inverseFrame = glm::inverse(frame);
  double inverse[3][3];
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      inverse[row][col] = inverseFrame[col][row];
  for (int row = 0; row < 3; ++row)
  {
    for (int col = 0; col < 3; ++col)
    {
      c[4 + 3 * col + row] = a[row][col];
      c[13 + 3 * col + row] = inverse[row][col];
    }
  }
  cell.scale = unitScale(values, kNodes);
  double field[kNodes];
  for (int k = 0; k < kNodes; ++k)
  {
    field[k] = values[k] * cell.scale;
  }
  for (int form = 0; form < 4; ++form)
  {
    const double* from = form < 3 ? g.control[form] : field;
    double* to = c + kHeader + form * kNodes;
    if (Curved)
    {
      widen<P>(from, kBarycentricTolerance, to); // once here, not per ray
    }
    else
    {
      std::copy(from, from + kNodes, to);
    }
  }
  cell.coefficients = c;
  cell.order = static_cast<std::uint8_t>(P);
  cell.kind = Curved ? CellRecord::Kind::CurvedHexahedron : CellRecord::Kind::Hexahedron;
}

template <int P, bool Curved>
bool HexahedronCell<P, Curved>::intersect(const CellRecord& cell, const Ray& ray,
  const IsoValues& isoValues, std::size_t first, std::size_t last, double tMin, double tLimit,
  SurfaceHit& hit, bool& certified)
{
  certified = true;
  const RecordView<P> view{ cell.coefficients };
  const double s = view.scale();
  const double* field = view.field();
  const std::vector<double>& sorted = isoValues.sorted();
  // The ray in local units, re-origined near the cell: t_world = (tCentre + T) / s.
  const glm::dvec3 origin = (ray.origin - view.origin()) * s;
  const glm::dvec3& d = ray.direction;
  glm::dvec3 centre(0.0);
  for (int k : { tensor::index(P, 0, 0, 0), tensor::index(P, P, P, P) })
  {
    centre += 0.5 * glm::dvec3(view.control(0)[k], view.control(1)[k], view.control(2)[k]);
  }
  const double tCentre = glm::dot(centre - origin, d);
  const glm::dvec3 o = origin + tCentre * d;
  const double lo = tMin * s - tCentre;
  const double hi = tLimit * s - tCentre;
  double fieldLo, fieldHi;
  bernstein::range(field, kNodes, fieldLo, fieldHi);
  const bool constant = spreadWithin(fieldLo, fieldHi, kTensorFormConstantRoundings);

  if constexpr (!Curved)
  {
    // x(T) = A^-1 (o + T d - X(0)), X(0) = 0 in local units (origin is control point 0).
    glm::dvec3 x0, dx;
    for (int row = 0; row < 3; ++row)
    {
      x0[row] = view.inverse(row, 0) * o.x + view.inverse(row, 1) * o.y + view.inverse(row, 2) * o.z;
      dx[row] = view.inverse(row, 0) * d.x + view.inverse(row, 1) * d.y + view.inverse(row, 2) * d.z;
    }
    // Clip to the cube widened by kBarycentricTolerance (slabs).
    double enter = lo, leave = hi;
    for (int a = 0; a < 3; ++a)
    {
      const double low = -kBarycentricTolerance, high = 1.0 + kBarycentricTolerance;
      if (dx[a] == 0.0)
      {
        if (x0[a] < low || x0[a] > high)
        {
          return false;
        }
        continue;
      }
      double t0 = (low - x0[a]) / dx[a], t1 = (high - x0[a]) / dx[a];
      if (t0 > t1)
      {
        std::swap(t0, t1);
      }
      enter = std::max(enter, t0);
      leave = std::min(leave, t1);
    }
    if (!(enter <= leave))
    {
      return false;
    }
    if (constant)
    {
      return isoparametric::constantStretch(
        isoValues, fieldLo, fieldHi, cell.scale, tCentre, enter, leave, s, cell.cellId, hit);
    }
    const double a[3] = { x0.x + enter * dx.x, x0.y + enter * dx.y, x0.z + enter * dx.z };
    const double b[3] = { x0.x + leave * dx.x, x0.y + leave * dx.y, x0.z + leave * dx.z };
    double along[3 * P + 1];
    fieldOnSegment<P>(field, a, b, along);
    double nearest;
    if (!nearestBernsteinRoot<3 * P>(along, sorted, first, last, cell.scale, nearest, hit.isoIndex, certified))
    {
      return false;
    }
    const double T = enter + nearest * (leave - enter);
    const double x[3] = { x0.x + T * dx.x, x0.y + T * dx.y, x0.z + T * dx.z };
    double parametric[3];
    tensor::evaluate<P>(field, x, parametric);
    glm::dmat3 jacobian;
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col)
        jacobian[col][row] = view.a(row, col);
    hit.t = (tCentre + T) / s;
    hit.regionEnd = hit.t;
    hit.cellId = cell.cellId;
    hit.gradient = referenceToWorldGradient(jacobian, parametric, s, cell.scale);
    return true;
  }
  else
  {
    // The ray's two transverse equations and its depth, as forms of the cube.
    glm::dvec3 u, v;
    isoparametric::orthonormalPair(d, u, v);
    double e0[kNodes], e1[kNodes], depth[kNodes], third[kNodes];
    for (int k = 0; k < kNodes; ++k)
    {
      const glm::dvec3 X(view.control(0)[k], view.control(1)[k], view.control(2)[k]);
      const glm::dvec3 offset = X - o;
      e0[k] = glm::dot(u, offset);
      e1[k] = glm::dot(v, offset);
      depth[k] = glm::dot(d, offset);
    }
    BoxRoot root;
    bool found = false;
    if (constant)
    {
      // The field equals an iso-value throughout (or none): the crossing is the ray's stretch
      // inside the cell, from where it enters (a root on a face, the start if that is inside).
      std::size_t index;
      if (!isoparametric::constantIsoIndex(isoValues, fieldLo, fieldHi, cell.scale, index))
      {
        return false;
      }
      auto firstFaceCrossing = [&](double from, double to) {
        double nearestFace = std::numeric_limits<double>::infinity();
        for (int axis = 0; axis < 3; ++axis)
        {
          for (int side = 0; side <= P; side += P)
          {
            // The face x_axis = side / P as the form x_axis - side / P in the widened cube's
            // coordinates w: x = -tolerance + w (1 + 2 tolerance), w = sum (i / P) B_i.
            for (int k = 0; k < kNodes; ++k)
            {
              const int n[3] = { k % (P + 1), (k / (P + 1)) % (P + 1), k / ((P + 1) * (P + 1)) };
              third[k] = (1.0 + 2.0 * kBarycentricTolerance) * n[axis] / P - kBarycentricTolerance -
                static_cast<double>(side) / P;
            }
            const double* equations[3] = { e0, e1, third };
            BoxRoot faceRoot;
            if (solveOnUnitBox<P>(equations, depth, from, std::min(nearestFace, to), faceRoot))
            {
              nearestFace = std::min(nearestFace, faceRoot.value);
            }
          }
        }
        return nearestFace;
      };
      const bool startInside = std::isfinite(lo) && [&] {
        // Whether the ray's start lies in the cell: the map's equations at that point.
        const double* control[3] = { view.control(0), view.control(1), view.control(2) };
        double eq[3][kNodes];
        pointEquations<P>(control, o + lo * d, eq);
        const double* equations[3] = { eq[0], eq[1], eq[2] };
        BoxRoot inside;
        return solveOnUnitBox<P>(equations, nullptr, 0.0, 0.0, inside);
      }();
      const double enter = startInside ? lo : firstFaceCrossing(lo, hi);
      if (!std::isfinite(enter))
      {
        return false;
      }
      const double leave = firstFaceCrossing(enter + isoparametric::kExitSearchStep, hi);
      hit.isoIndex = index;
      hit.t = (tCentre + enter) / s;
      hit.regionEnd = std::isfinite(leave) ? (tCentre + leave) / s : hit.t;
      hit.cellId = cell.cellId;
      hit.gradient = glm::dvec3(0.0);
      return true;
    }
    double nearestDepth = hi;
    for (std::size_t k = first; k < last; ++k)
    {
      const double level = sorted[k] * cell.scale;
      for (int n = 0; n < kNodes; ++n)
      {
        third[n] = field[n] - level;
      }
      const double* equations[3] = { e0, e1, third };
      BoxRoot candidate;
      if (solveOnUnitBox<P>(equations, depth, lo, nearestDepth, candidate))
      {
        found = true;
        nearestDepth = candidate.value;
        root = candidate;
        hit.isoIndex = k;
      }
    }
    if (!found)
    {
      return false;
    }
    certified = root.certified;
    // The gradient from the widened forms at the root (their common factor 1 + 2 tolerance in
    // d/dw cancels between J and grad f).
    double parametric[3];
    tensor::evaluate<P>(field, root.x, parametric);
    glm::dmat3 jacobian;
    for (int a = 0; a < 3; ++a)
    {
      double dX[3];
      tensor::evaluate<P>(view.control(a), root.x, dX);
      for (int col = 0; col < 3; ++col)
        jacobian[col][a] = dX[col];
    }
    hit.t = (tCentre + root.value) / s;
    hit.regionEnd = hit.t;
    hit.cellId = cell.cellId;
    hit.gradient = referenceToWorldGradient(jacobian, parametric, s, cell.scale);
    return true;
  }
}

template <int P, bool Curved>
bool HexahedronCell<P, Curved>::contains(const glm::dvec3* nodes, const glm::dvec3& point, double L[4])
{
  const LocalGeometry<P> g = LocalGeometry<P>::fromNodes(nodes);
  const double* control[3] = { g.control[0], g.control[1], g.control[2] };
  double eq[3][kNodes];
  pointEquations<P>(control, (point - g.origin) * g.scale, eq);
  const double* equations[3] = { eq[0], eq[1], eq[2] };
  BoxRoot root;
  if (!solveOnCube<P>(equations, nullptr, 0.0, 0.0, kBarycentricTolerance, root))
  {
    return false;
  }
  L[0] = 0.0;
  std::copy(root.x, root.x + 3, L + 1);
  return true;
}

template <int P, bool Curved>
void HexahedronCell<P, Curved>::coordinates(const glm::dvec3* nodes, const glm::dvec3& point, double L[4])
{
  if (contains(nodes, point, L))
  {
    return;
  }
  const LocalGeometry<P> g = LocalGeometry<P>::fromNodes(nodes);
  const double* control[3] = { g.control[0], g.control[1], g.control[2] };
  double eq[3][kNodes];
  pointEquations<P>(control, (point - g.origin) * g.scale, eq);
  const double* equations[3] = { eq[0], eq[1], eq[2] };
  double x[3] = { 0.5, 0.5, 0.5 };
  L[0] = 0.0;
  if (newtonOnBox<P>(equations, x))
  {
    std::copy(x, x + 3, L + 1);
  }
  else
  {
    std::fill(L + 1, L + 4, 0.5);
  }
}

template <int P, bool Curved>
glm::dvec3 HexahedronCell<P, Curved>::gradient(const glm::dvec3* nodes, const double* values, const double L[4])
{
  const LocalGeometry<P> g = LocalGeometry<P>::fromNodes(nodes);
  const double x[3] = { L[1], L[2], L[3] };
  glm::dmat3 jacobian;
  g.position(x, &jacobian);
  const double scale = unitScale(values, kNodes);
  double c[kNodes];
  for (int k = 0; k < kNodes; ++k)
  {
    c[k] = values[k] * scale;
  }
  double parametric[3];
  tensor::evaluate<P>(c, x, parametric);
  return referenceToWorldGradient(jacobian, parametric, g.scale, scale);
}

template struct HexahedronCell<1, false>;
template struct HexahedronCell<2, false>;
template struct HexahedronCell<3, false>;
template struct HexahedronCell<4, false>;
template struct HexahedronCell<1, true>;
template struct HexahedronCell<2, true>;
template struct HexahedronCell<3, true>;
template struct HexahedronCell<4, true>;

} // namespace tetdsr
