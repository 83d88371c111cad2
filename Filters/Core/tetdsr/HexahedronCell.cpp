#include "tetdsr/HexahedronCell.h"

#include "tetdsr/IsoparametricRay.h"
#include "tetdsr/QuadraticTetCell.h"
#include "tetdsr/SplitCells.h"
#include "tetdsr/TetBernstein.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

using Point = std::array<double, 3>;

/// A table whose nodes are lattice points of its order: each node's lattice index.
HexahedronNodes latticeTable(const char* name, int order, bool bezier, std::vector<Point> points)
{
  HexahedronNodes table;
  table.name = name;
  table.order = order;
  table.bezier = bezier;
  table.nodes = static_cast<int>(points.size());
  for (const Point& p : points)
  {
    table.lattice.push_back(tensor::index(order, static_cast<int>(std::lround(p[0] * order)),
      static_cast<int>(std::lround(p[1] * order)), static_cast<int>(std::lround(p[2] * order))));
  }
  table.nodePoints = std::move(points);
  return table;
}

/// A table whose space is a part of Q2 given by a split shape's nodal basis (20 and 24 nodes):
/// the basis at the 27 lattice points.
HexahedronNodes basisTable(const SplitShape& shape)
{
  HexahedronNodes table;
  table.name = shape.name;
  table.order = 2;
  table.nodes = shape.nodes;
  table.nodePoints = shape.nodePoints;
  table.weights.resize(static_cast<std::size_t>(tensor::count(2) * shape.nodes));
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
      {
        const double x[3] = { i / 2.0, j / 2.0, k / 2.0 };
        shape.basis(x, table.weights.data() + static_cast<std::size_t>(tensor::index(2, i, j, k) * shape.nodes));
      }
  return table;
}

/// A wedge type's table: its shape functions (SplitShape::basis) at the lattice points' images
/// r = u (1 - v), s = v (nodal values of the composite, a polynomial of degree `order` per axis).
HexahedronNodes wedgeTable(int vtkType, const SplitShape& shape)
{
  HexahedronNodes table;
  table.name = shape.name;
  table.order = shape.order;
  table.nodes = shape.nodes;
  table.collapsedAxis = 1;
  table.collapsedPower = 1;
  table.mirrored = mirroredType(vtkType);
  const int P = shape.order;
  const int N = tensor::count(P);
  table.weights.resize(static_cast<std::size_t>(N * shape.nodes));
  for (int k = 0; k <= P; ++k)
    for (int j = 0; j <= P; ++j)
      for (int i = 0; i <= P; ++i)
      {
        const double u = static_cast<double>(i) / P, v = static_cast<double>(j) / P;
        const double x[3] = { u * (1.0 - v), v, static_cast<double>(k) / P };
        shape.basis(x, table.weights.data() + static_cast<std::size_t>(tensor::index(P, i, j, k) * shape.nodes));
      }
  for (const auto& r : shape.nodePoints)
  {
    // (The collapsed vertex's u is any: its middle.)
    table.nodePoints.push_back({ r[1] < 1.0 ? r[0] / (1.0 - r[1]) : 0.5, r[1], r[2] });
  }
  return table;
}

/// A Lagrange or Bezier wedge's table of order `Order`, built on first use (a thread-safe static).
template <bool Bezier, int Order>
const HexahedronNodes& higherOrderWedgeTable()
{
  static const HexahedronNodes table = [] {
    const int type = Bezier ? kVtkBezierWedge : kVtkLagrangeWedge;
    const SplitShape* shape = nullptr;
    splitShapeOf(type, (Order + 1) * (Order + 1) * (Order + 2) / 2, shape);
    return wedgeTable(type, *shape);
  }();
  return table;
}

/// The table of a wedge type of fixed node count, built once from its one shape (a thread-safe
/// static).
template <int Type>
const HexahedronNodes& fixedWedgeTable(const SplitShape& shape)
{
  static const HexahedronNodes table = wedgeTable(Type, shape);
  return table;
}

/// The wedge tables, each built once (thread-safe statics) from the split's shapes.
const HexahedronNodes* wedgeTableOf(int vtkType, long long ids, std::uint16_t& status)
{
  const SplitShape* shape = nullptr;
  status = splitShapeOf(vtkType, ids, shape);
  if (status != 0)
  {
    return nullptr;
  }
  switch (vtkType)
  {
    case kVtkWedge:
      return &fixedWedgeTable<kVtkWedge>(*shape);
    case kVtkQuadraticLinearWedge:
      return &fixedWedgeTable<kVtkQuadraticLinearWedge>(*shape);
    case kVtkQuadraticWedge:
      return &fixedWedgeTable<kVtkQuadraticWedge>(*shape);
    case kVtkBiquadraticQuadraticWedge:
      return &fixedWedgeTable<kVtkBiquadraticQuadraticWedge>(*shape);
    default:
    {
      // Lagrange and Bezier wedges of orders 1 to 4 (the order from the shape), each built on
      // first use.
      using Builder = const HexahedronNodes& (*)();
      static constexpr Builder kBuilders[2][4] = {
        { higherOrderWedgeTable<false, 1>, higherOrderWedgeTable<false, 2>, higherOrderWedgeTable<false, 3>,
          higherOrderWedgeTable<false, 4> },
        { higherOrderWedgeTable<true, 1>, higherOrderWedgeTable<true, 2>, higherOrderWedgeTable<true, 3>,
          higherOrderWedgeTable<true, 4> }
      };
      return &kBuilders[vtkType == kVtkBezierWedge][shape->order - 1]();
    }
  }
}

/// VTK_PYRAMID's table: the base's four nodes at t = 0 (VTK_HEXAHEDRON's order), the apex at
/// the four corners of t = 1.
HexahedronNodes pyramidTable()
{
  HexahedronNodes table;
  table.name = "VTK_PYRAMID";
  table.order = 1;
  table.nodes = 5;
  table.collapsedAxis = 2;
  table.collapsedPower = 2;
  table.weights.assign(static_cast<std::size_t>(8 * 5), 0.0);
  const int baseNode[2][2] = { { 0, 3 }, { 1, 2 } }; // [i][j]
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i)
    {
      table.weights[static_cast<std::size_t>(tensor::index(1, i, j, 0) * 5 + baseNode[i][j])] = 1.0;
      table.weights[static_cast<std::size_t>(tensor::index(1, i, j, 1) * 5 + 4)] = 1.0;
    }
  table.nodePoints = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0.5, 0.5, 1 } };
  return table;
}

template <bool Bezier, int Order>
const HexahedronNodes& higherOrderTable()
{
  static const HexahedronNodes table = latticeTable(
    Bezier ? "VTK_BEZIER_HEXAHEDRON" : "VTK_LAGRANGE_HEXAHEDRON", Order, Bezier, hexahedronNodePoints(Order));
  return table;
}

const HexahedronNodes& splitShapeTable(int vtkType, int nodes)
{
  // (Built once per type: the 20- and 24-node shapes' nodal bases.)
  auto make = [](int type, int count) {
    const SplitShape* shape = nullptr;
    splitShapeOf(type, count, shape);
    return basisTable(*shape);
  };
  static const HexahedronNodes serendipity = make(kVtkQuadraticHexahedron, 20);
  static const HexahedronNodes biquadratic = make(kVtkBiquadraticQuadraticHexahedron, 24);
  return nodes == 20 && vtkType == kVtkQuadraticHexahedron ? serendipity : biquadratic;
}

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

bool invert3(const double a[3][3], double inverse[3][3])
{
  const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
  const double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
  const double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
  const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
  if (!(std::abs(det) > 0.0) || !std::isfinite(det))
  {
    return false;
  }
  const double s = 1.0 / det;
  inverse[0][0] = c00 * s;
  inverse[1][0] = c01 * s;
  inverse[2][0] = c02 * s;
  inverse[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * s;
  inverse[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * s;
  inverse[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * s;
  inverse[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * s;
  inverse[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * s;
  inverse[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * s;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(inverse[i][j]))
        return false;
  return true;
}

// ---- The box solve -----------------------------------------------------------------------------

template <int P>
struct Box
{
  static constexpr int N = tensor::count(P);
  double lo[3], hi[3];  ///< in the widened cube's unit coordinates
  double c[4][N];       ///< the three equations' and the objective's coefficients on the box
};

/// Newton on the equations (coefficients on the widened cube, unit coordinates) from x; true if
/// it converges (steps below rounding) with x finite.
template <int P>
bool newton(const double* const forms[3], double x[3])
{
  for (int iteration = 0; iteration < 16; ++iteration)
  {
    double f[3], j[3][3], inverse[3][3];
    for (int e = 0; e < 3; ++e)
    {
      f[e] = tensor::evaluate<P>(forms[e], x, j[e]);
    }
    if (!invert3(j, inverse))
    {
      return false;
    }
    double largest = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double step = inverse[a][0] * f[0] + inverse[a][1] * f[1] + inverse[a][2] * f[2];
      x[a] -= step;
      largest = std::max(largest, std::abs(step));
    }
    if (!(std::abs(x[0]) + std::abs(x[1]) + std::abs(x[2]) < 1e6))
    {
      return false;
    }
    if (largest <= 4.0 * kEpsilon)
    {
      return true;
    }
  }
  return true; // (the last steps within a few roundings: the caller checks where it landed)
}

/// What Krawczyk's test says of a box.
enum class Krawczyk
{
  None,    ///< no root in the box
  Unique,  ///< exactly one root, within `inner` (box unit coordinates)
  Unknown
};

/// Krawczyk's test in the box's own unit coordinates w (centre m = 1/2, radius 1/2): with Y the
/// inverse of the Jacobian at m, K = m - Y F(m) + (I - Y J(box)) (w - m); K inside the box's
/// interior proves a unique root (in K), K outside it proves none. J(box) is bounded entry by
/// entry by the coefficients' differences (tensor::derivativeRange).
template <int P>
Krawczyk krawczyk(const Box<P>& box, double inner[3][2], double scoreByAxis[3])
{
  const double m[3] = { 0.5, 0.5, 0.5 };
  double f[3], jm[3][3];
  double jLo[3][3], jHi[3][3];
  for (int e = 0; e < 3; ++e)
  {
    f[e] = tensor::evaluate<P>(box.c[e], m, jm[e]);
    for (int a = 0; a < 3; ++a)
    {
      tensor::derivativeRange<P>(box.c[e], a, jLo[e][a], jHi[e][a]);
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    scoreByAxis[a] = 0.0;
    for (int e = 0; e < 3; ++e)
    {
      scoreByAxis[a] += std::max(std::abs(jLo[e][a]), std::abs(jHi[e][a])) /
        (std::abs(jm[e][0]) + std::abs(jm[e][1]) + std::abs(jm[e][2]) + 1e-300);
    }
  }
  double y[3][3];
  if (!invert3(jm, y))
  {
    return Krawczyk::Unknown;
  }
  for (int i = 0; i < 3; ++i)
  {
    const double yf = y[i][0] * f[0] + y[i][1] * f[1] + y[i][2] * f[2];
    // |(I - Y J(box)) (w - m)|_i <= sum_a |I - Y Jc|_ia r + (|Y| Jr)_ia r, r = 1/2.
    double spread = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      double centre = i == a ? 1.0 : 0.0, radius = 0.0;
      for (int e = 0; e < 3; ++e)
      {
        centre -= y[i][e] * 0.5 * (jLo[e][a] + jHi[e][a]);
        radius += std::abs(y[i][e]) * 0.5 * (jHi[e][a] - jLo[e][a]);
      }
      spread += 0.5 * (std::abs(centre) + radius);
    }
    // Rounding of F, J and Y (numbers near 1 in the box's units): a relative margin.
    spread = spread * (1.0 + 1e-12) + 1e-13 + 64.0 * kEpsilon * std::abs(yf);
    if (!std::isfinite(spread) || !std::isfinite(yf))
    {
      return Krawczyk::Unknown;
    }
    inner[i][0] = 0.5 - yf - spread;
    inner[i][1] = 0.5 - yf + spread;
  }
  for (int i = 0; i < 3; ++i)
  {
    if (inner[i][0] > 1.0 || inner[i][1] < 0.0)
    {
      return Krawczyk::None;
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    if (!(inner[i][0] > 0.0 && inner[i][1] < 1.0))
    {
      return Krawczyk::Unknown;
    }
  }
  return Krawczyk::Unique;
}

/// Bezier clipping (Sederberg and Nishita): along `axis`, the form restricted to any line of
/// that axis is a univariate Bernstein polynomial whose coefficient i lies within [lo_i, hi_i] (the
/// least and largest coefficient of index i along the axis, widened by `pad`), so its roots lie
/// where the convex hull of the points (i / P, lo_i), (i / P, hi_i) meets zero: [from, to] in the
/// box's unit coordinates. False if it does not (no root in the box).
template <int P>
bool clipAxis(const double* c, int axis, double pad, double& from, double& to)
{
  double lo[P + 1], hi[P + 1];
  const int step = tensor::stride(P, axis);
  for (int i = 0; i <= P; ++i)
  {
    lo[i] = std::numeric_limits<double>::infinity();
    hi[i] = -lo[i];
  }
  for (int b = 0; b <= P; ++b)
  {
    for (int a = 0; a <= P; ++a)
    {
      const int base = axis == 0 ? tensor::index(P, 0, a, b) : axis == 1 ? tensor::index(P, a, 0, b) : tensor::index(P, a, b, 0);
      for (int i = 0; i <= P; ++i)
      {
        const double value = c[base + i * step];
        lo[i] = std::min(lo[i], value);
        hi[i] = std::max(hi[i], value);
      }
    }
  }
  // The hull meets zero between the least and largest zero crossing of a segment joining two of
  // its points of opposite signs (or a point that is zero within the pad).
  from = std::numeric_limits<double>::infinity();
  to = -from;
  double x[2 * P + 2], y[2 * P + 2];
  for (int i = 0; i <= P; ++i)
  {
    x[2 * i] = x[2 * i + 1] = static_cast<double>(i) / P;
    y[2 * i] = lo[i] - pad;
    y[2 * i + 1] = hi[i] + pad;
  }
  for (int p = 0; p < 2 * P + 2; ++p)
  {
    if (y[p] == 0.0)
    {
      from = std::min(from, x[p]);
      to = std::max(to, x[p]);
      continue;
    }
    for (int q = p + 1; q < 2 * P + 2; ++q)
    {
      if ((y[p] < 0.0) != (y[q] < 0.0) && y[q] != 0.0)
      {
        const double crossing = x[p] + (x[q] - x[p]) * (y[p] / (y[p] - y[q]));
        from = std::min(from, crossing);
        to = std::max(to, crossing);
      }
    }
  }
  if (!(from <= to))
  {
    return false;
  }
  // (Rounding of the crossings: a relative margin, then the box itself.)
  const double margin = 1e-12;
  from = std::max(0.0, from - margin);
  to = std::min(1.0, to + margin);
  return true;
}

/// A thread's stack of boxes, reused between solves.
template <int P>
std::vector<Box<P>>& boxStack()
{
  thread_local std::vector<Box<P>> stack;
  return stack;
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

/// The hit's world gradient from the field's (scaled) parametric gradient and the local Jacobian.
glm::dvec3 worldGradient(const glm::dmat3& jacobian, const double parametric[3], double geometryScale,
  double fieldScale)
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
} // namespace

// ---- Node tables -------------------------------------------------------------------------------

bool isTensorProductType(int vtkType)
{
  switch (vtkType)
  {
    case kVtkWedge:
    case kVtkQuadraticLinearWedge:
    case kVtkQuadraticWedge:
    case kVtkBiquadraticQuadraticWedge:
    case kVtkLagrangeWedge:
    case kVtkBezierWedge:
    case kVtkPyramid:
    case kVtkVoxel:
    case kVtkHexahedron:
    case kVtkQuadraticHexahedron:
    case kVtkBiquadraticQuadraticHexahedron:
    case kVtkTriquadraticHexahedron:
    case kVtkLagrangeHexahedron:
    case kVtkBezierHexahedron:
      return true;
    default:
      return false;
  }
}

std::uint16_t hexahedronNodesOf(int vtkType, long long ids, const HexahedronNodes*& table)
{
  static const HexahedronNodes hexahedron = latticeTable("VTK_HEXAHEDRON", 1, false, hexahedronNodePoints(1));
  static const HexahedronNodes voxel = latticeTable("VTK_VOXEL", 1, false,
    { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 }, { 1, 1, 1 } });
  static const HexahedronNodes triquadratic =
    latticeTable("VTK_TRIQUADRATIC_HEXAHEDRON", 2, false, hexahedronNodePoints(2));
  switch (vtkType)
  {
    case kVtkHexahedron:
      table = &hexahedron;
      return ids == 8 ? 0 : kMalformed;
    case kVtkVoxel:
      table = &voxel;
      return ids == 8 ? 0 : kMalformed;
    case kVtkQuadraticHexahedron:
      if (ids != 20)
        return kMalformed;
      table = &splitShapeTable(vtkType, 20);
      return 0;
    case kVtkBiquadraticQuadraticHexahedron:
      if (ids != 24)
        return kMalformed;
      table = &splitShapeTable(vtkType, 24);
      return 0;
    case kVtkTriquadraticHexahedron:
      table = &triquadratic;
      return ids == 27 ? 0 : kMalformed;
    case kVtkLagrangeHexahedron:
    case kVtkBezierHexahedron:
    {
      // VTK reads the order of these from the id count, a cube number (p + 1)^3.
      int order = 0;
      for (int p = 1; p <= 1 << 17; ++p)
      {
        const long long n = static_cast<long long>(p + 1) * (p + 1) * (p + 1);
        if (n >= ids)
        {
          order = n == ids ? p : 0;
          break;
        }
      }
      if (order == 0)
      {
        return kMalformed;
      }
      if (order > kMaxHexahedronOrder)
      {
        return kOrderTooHigh;
      }
      using Builder = const HexahedronNodes& (*)();
      static constexpr Builder kBuilders[2][4] = {
        { higherOrderTable<false, 1>, higherOrderTable<false, 2>, higherOrderTable<false, 3>, higherOrderTable<false, 4> },
        { higherOrderTable<true, 1>, higherOrderTable<true, 2>, higherOrderTable<true, 3>, higherOrderTable<true, 4> }
      };
      table = &kBuilders[vtkType == kVtkBezierHexahedron][order - 1]();
      return 0;
    }
    case kVtkPyramid:
    {
      static const HexahedronNodes pyramid = pyramidTable();
      table = &pyramid;
      return ids == 5 ? 0 : kMalformed;
    }
    case kVtkWedge:
    case kVtkQuadraticLinearWedge:
    case kVtkQuadraticWedge:
    case kVtkBiquadraticQuadraticWedge:
    case kVtkLagrangeWedge:
    case kVtkBezierWedge:
    {
      std::uint16_t status = 0;
      table = wedgeTableOf(vtkType, ids, status);
      return status;
    }
    default:
      return kUnsupported;
  }
}

std::uint16_t hexahedronLayout(int vtkType, long long ids, CellLayout& layout)
{
  const HexahedronNodes* table = nullptr;
  const std::uint16_t status = hexahedronNodesOf(vtkType, ids, table);
  if (status == 0)
  {
    layout.order = table->order;
    layout.bezier = table->bezier;
    layout.nodes = table->nodes;
    layout.hexahedron = table;
  }
  return status;
}

template <typename T>
void toTensorForm(const HexahedronNodes& table, T* items)
{
  forHexahedronOrder(table.order, [&](auto order) {
    constexpr int P = decltype(order)::value;
    constexpr int N = tensor::count(P);
    // Worked at a power of two's scale near 1 (exact), so the sums overflow only where the
    // coefficients themselves do.
    double largest = 0.0;
    for (int n = 0; n < table.nodes; ++n)
    {
      if constexpr (std::is_same_v<T, double>)
        largest = std::max(largest, std::abs(items[n]));
      else
        largest = std::max({ largest, std::abs(items[n].x), std::abs(items[n].y), std::abs(items[n].z) });
    }
    const double scale = scaleFor(largest);
    constexpr int kComponents = std::is_same_v<T, double> ? 1 : 3;
    double lattice[kComponents][N];
    auto component = [&](const T& item, int a) {
      if constexpr (std::is_same_v<T, double>)
        return item;
      else
        return item[a];
    };
    for (int a = 0; a < kComponents; ++a)
    {
      if (!table.lattice.empty())
      {
        for (int n = 0; n < table.nodes; ++n)
        {
          lattice[a][table.lattice[static_cast<std::size_t>(n)]] = component(items[n], a) * scale;
        }
      }
      else
      {
        for (int k = 0; k < N; ++k)
        {
          double sum = 0.0;
          const double* w = table.weights.data() + static_cast<std::size_t>(k * table.nodes);
          for (int n = 0; n < table.nodes; ++n)
          {
            sum += w[n] * component(items[n], a) * scale;
          }
          lattice[a][k] = sum;
        }
      }
      if (!table.bezier)
      {
        tensor::lagrangeToBernstein<P>(lattice[a]);
      }
    }
    for (int k = 0; k < N; ++k)
    {
      if constexpr (std::is_same_v<T, double>)
        items[k] = lattice[0][k] / scale;
      else
        items[k] = glm::dvec3(lattice[0][k], lattice[1][k], lattice[2][k]) / scale;
    }
  });
}

template void toTensorForm(const HexahedronNodes&, double*);
template void toTensorForm(const HexahedronNodes&, glm::dvec3*);

// ---- The box solve -----------------------------------------------------------------------------

template <int P>
void widen(const double* form, double tolerance, double* out)
{
  constexpr int N = tensor::count(P);
  double matrix[P + 1][P + 1];
  tensor::segmentMatrix<P>(-tolerance, 1.0 + tolerance, matrix);
  double work[N];
  tensor::transformAxis<P>(form, 0, matrix, out);
  tensor::transformAxis<P>(out, 1, matrix, work);
  tensor::transformAxis<P>(work, 2, matrix, out);
}

template <int P>
bool solveOnCube(const double* const equations[3], const double* objective, double lo, double hi,
  double tolerance, BoxRoot& root, const BoxSolveLimits& limits, int* pieces)
{
  // The forms on the cube widened by `tolerance` (roots on a face shared with a neighbour are
  // interior to both cells' boxes): x = -tolerance + w (1 + 2 tolerance), w in [0, 1].
  constexpr int N = tensor::count(P);
  double widened[4][N];
  for (int f = 0; f < (objective ? 4 : 3); ++f)
  {
    widen<P>(f < 3 ? equations[f] : objective, tolerance, widened[f]);
  }
  const double* forms[3] = { widened[0], widened[1], widened[2] };
  if (!solveOnUnitBox<P>(forms, objective ? widened[3] : nullptr, lo, hi, root, limits, pieces))
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    root.x[a] = -tolerance + root.x[a] * (1.0 + 2.0 * tolerance);
  }
  return true;
}

template <int P>
bool solveOnUnitBox(const double* const equations[3], const double* objective, double lo, double hi,
  BoxRoot& root, const BoxSolveLimits& limits, int* pieces)
{
  constexpr int N = tensor::count(P);
  const int forms = objective ? 4 : 3;
  const double* whole[3] = { equations[0], equations[1], equations[2] };
  // Coefficients within this of zero prove no sign: subdivision rounds each by about one
  // rounding a level (averages), evaluation by a few per degree.
  double pad[4];
  for (int f = 0; f < forms; ++f)
  {
    pad[f] = (64.0 + 16.0 * P) * kEpsilon * bernstein::magnitude(f < 3 ? equations[f] : objective, N);
  }
  std::vector<Box<P>>& stack = boxStack<P>();
  stack.clear();
  stack.emplace_back();
  Box<P>& first = stack.back();
  for (int a = 0; a < 3; ++a)
  {
    first.lo[a] = 0.0;
    first.hi[a] = 1.0;
  }
  for (int f = 0; f < forms; ++f)
  {
    const double* form = f < 3 ? equations[f] : objective;
    std::copy(form, form + N, first.c[f]);
  }
  bool found = false;
  double best = hi;
  int visited = 0;
  auto accept = [&](const double w[3], bool certified) {
    const double value = objective ? tensor::evaluate<P>(objective, w) : 0.0;
    if (objective && !(value >= lo && value <= best))
    {
      return;
    }
    found = true;
    best = value;
    root.value = value;
    root.certified = certified;
    std::copy(w, w + 3, root.x);
  };
  while (!stack.empty())
  {
    if (++visited > limits.maxPieces)
    {
      break;
    }
    Box<P> box = stack.back();
    stack.pop_back();
    // Exclusion: an equation of one sign on the box; depth beyond the nearest root or the range.
    bool excluded = false;
    for (int e = 0; e < 3 && !excluded; ++e)
    {
      double cLo, cHi;
      bernstein::range(box.c[e], N, cLo, cHi);
      excluded = cLo > pad[e] || cHi < -pad[e];
    }
    if (excluded)
    {
      continue;
    }
    // Bezier clipping while it shrinks the box well (its roots converge quadratically; a box it
    // cannot shrink goes on to Krawczyk's test and bisection).
    for (int round = 0; round < 4 && !excluded; ++round)
    {
      double from[3] = { 0.0, 0.0, 0.0 }, to[3] = { 1.0, 1.0, 1.0 };
      for (int e = 0; e < 3 && !excluded; ++e)
      {
        for (int a = 0; a < 3 && !excluded; ++a)
        {
          double f0, f1;
          excluded = !clipAxis<P>(box.c[e], a, pad[e], f0, f1);
          from[a] = std::max(from[a], f0);
          to[a] = std::min(to[a], f1);
          excluded = excluded || !(from[a] <= to[a]);
        }
      }
      double shrink = 0.0;
      for (int a = 0; a < 3; ++a)
      {
        shrink = std::max(shrink, to[a] - from[a]);
      }
      if (excluded || shrink > 0.7)
      {
        break;
      }
      // The forms on the clipped box (each axis reparametrised) and its place in the cube.
      for (int a = 0; a < 3; ++a)
      {
        if (from[a] == 0.0 && to[a] == 1.0)
        {
          continue;
        }
        double matrix[P + 1][P + 1];
        tensor::segmentMatrix<P>(from[a], to[a], matrix);
        for (int f = 0; f < forms; ++f)
        {
          double work[N];
          tensor::transformAxis<P>(box.c[f], a, matrix, work);
          std::copy(work, work + N, box.c[f]);
        }
        const double span = box.hi[a] - box.lo[a];
        const double lower = box.lo[a] + from[a] * span;
        box.hi[a] = box.lo[a] + to[a] * span;
        box.lo[a] = lower;
      }
    }
    if (excluded)
    {
      continue;
    }
    if (objective)
    {
      double dLo, dHi;
      bernstein::range(box.c[3], N, dLo, dHi);
      if (dLo > best + pad[3] || dHi < lo - pad[3])
      {
        continue;
      }
    }
    double inner[3][2], score[3];
    const Krawczyk test = krawczyk<P>(box, inner, score);
    if (test == Krawczyk::None)
    {
      continue;
    }
    double width = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      width = std::max(width, box.hi[a] - box.lo[a]);
    }
    if (test == Krawczyk::Unique || width <= limits.minWidth)
    {
      // Newton from the box's centre (or the Krawczyk box's) on the whole forms.
      double w[3];
      for (int a = 0; a < 3; ++a)
      {
        const double centre = test == Krawczyk::Unique ? 0.5 * (inner[a][0] + inner[a][1]) : 0.5;
        w[a] = box.lo[a] + centre * (box.hi[a] - box.lo[a]);
      }
      if (newton<P>(whole, w))
      {
        // Proven roots lie in K (inside the box); Newton's must land there (to rounding).
        bool inside = true;
        for (int a = 0; a < 3; ++a)
        {
          const double span = box.hi[a] - box.lo[a];
          const double margin = 1e-9 * span + 4.0 * kEpsilon;
          const double from = test == Krawczyk::Unique ? box.lo[a] + inner[a][0] * span : box.lo[a];
          const double to = test == Krawczyk::Unique ? box.lo[a] + inner[a][1] * span : box.hi[a];
          inside = inside && w[a] >= from - margin && w[a] <= to + margin;
        }
        if (inside)
        {
          accept(w, test == Krawczyk::Unique);
          if (!objective && found)
          {
            break;
          }
          continue;
        }
      }
      if (width <= limits.minWidth)
      {
        continue; // no root Newton can reach here
      }
    }
    // Bisect along the axis where the equations vary most over the box (relative to their
    // gradients' sizes), the nearer half (least depth bound) popped first.
    int axis = 0;
    for (int a = 1; a < 3; ++a)
    {
      if (score[a] * (box.hi[a] - box.lo[a]) > score[axis] * (box.hi[axis] - box.lo[axis]))
      {
        axis = a;
      }
    }
    if (!(score[axis] > 0.0))
    {
      axis = 0;
      for (int a = 1; a < 3; ++a)
      {
        if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis])
        {
          axis = a;
        }
      }
    }
    Box<P> halves[2];
    for (int h = 0; h < 2; ++h)
    {
      std::copy(box.lo, box.lo + 3, halves[h].lo);
      std::copy(box.hi, box.hi + 3, halves[h].hi);
    }
    const double middle = 0.5 * (box.lo[axis] + box.hi[axis]);
    halves[0].hi[axis] = middle;
    halves[1].lo[axis] = middle;
    for (int f = 0; f < forms; ++f)
    {
      tensor::halve<P>(box.c[f], axis, halves[0].c[f], halves[1].c[f]);
    }
    int nearer = 0;
    if (objective)
    {
      double lo0, hi0, lo1, hi1;
      bernstein::range(halves[0].c[3], N, lo0, hi0);
      bernstein::range(halves[1].c[3], N, lo1, hi1);
      nearer = lo1 < lo0 ? 1 : 0;
    }
    stack.push_back(halves[1 - nearer]);
    stack.push_back(halves[nearer]);
  }
  if (pieces)
  {
    *pieces = visited;
  }
  if (visited > limits.maxPieces && found)
  {
    root.certified = false; // boxes left unexplored might hold a nearer root
  }
  return found;
}

template void widen<1>(const double*, double, double*);
template void widen<2>(const double*, double, double*);
template void widen<3>(const double*, double, double*);
template void widen<4>(const double*, double, double*);
template bool solveOnUnitBox<1>(const double* const[3], const double*, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnUnitBox<2>(const double* const[3], const double*, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnUnitBox<3>(const double* const[3], const double*, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnUnitBox<4>(const double* const[3], const double*, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnCube<1>(const double* const[3], const double*, double, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnCube<2>(const double* const[3], const double*, double, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnCube<3>(const double* const[3], const double*, double, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnCube<4>(const double* const[3], const double*, double, double, double, BoxRoot&, const BoxSolveLimits&, int*);

// ---- The cell seam's steps ---------------------------------------------------------------------

template <int P, bool Curved>
std::uint16_t HexahedronCell<P, Curved>::validate(
  const glm::dvec3* nodes, double pointRounding, const HexahedronNodes& table)
{
  const std::uint16_t flags = validateForm(nodes, pointRounding, table);
  // A mirrored type's well-formed cell has a map of negative orientation.
  return table.mirrored && (flags & kValid) ? static_cast<std::uint16_t>(flags ^ kInverted) : flags;
}

template <int P, bool Curved>
std::uint16_t HexahedronCell<P, Curved>::validateForm(
  const glm::dvec3* nodes, double pointRounding, const HexahedronNodes& table)
{
  // The corners' tetrahedron: size, volume, orientation, and the curved tolerance.
  const glm::dvec3 frame[4] = { nodes[tensor::index(P, 0, 0, 0)], nodes[tensor::index(P, P, 0, 0)],
    nodes[tensor::index(P, 0, P, 0)], nodes[tensor::index(P, 0, 0, P)] };
  double curvedTolerance = 0.0;
  std::uint16_t flags = QuadraticTetCell::validateVertices(frame, pointRounding, curvedTolerance);
  if (!(flags & kValid))
  {
    return flags;
  }
  bool curved = false;
  for (int k = 0; k <= P && !curved; ++k)
    for (int j = 0; j <= P && !curved; ++j)
      for (int i = 0; i <= P && !curved; ++i)
      {
        const glm::dvec3 expected = frame[0] + (static_cast<double>(i) / P) * (frame[1] - frame[0]) +
          (static_cast<double>(j) / P) * (frame[2] - frame[0]) + (static_cast<double>(k) / P) * (frame[3] - frame[0]);
        curved = QuadraticTetCell::offItsPlace(nodes[tensor::index(P, i, j, k)], expected, curvedTolerance);
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
  double inverse[3][3] = {};
  invert3(a, inverse); // (validation proved the frame's volume well away from zero)
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
  const bool constant = constantToRounding(fieldLo, fieldHi, kMaxPieceOrder);

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
      std::size_t index;
      const auto it = std::lower_bound(sorted.begin() + static_cast<std::ptrdiff_t>(first),
        sorted.begin() + static_cast<std::ptrdiff_t>(last), fieldLo / cell.scale);
      index = static_cast<std::size_t>(it - sorted.begin());
      if (index >= last || !(sorted[index] <= fieldHi / cell.scale))
      {
        return false;
      }
      hit.isoIndex = index;
      hit.t = (tCentre + enter) / s;
      hit.regionEnd = (tCentre + leave) / s;
      hit.cellId = cell.cellId;
      hit.gradient = glm::dvec3(0.0);
      return true;
    }
    const double a[3] = { x0.x + enter * dx.x, x0.y + enter * dx.y, x0.z + enter * dx.z };
    const double b[3] = { x0.x + leave * dx.x, x0.y + leave * dx.y, x0.z + leave * dx.z };
    double along[3 * P + 1];
    fieldOnSegment<P>(field, a, b, along);
    double nearest = 2.0;
    for (std::size_t k = first; k < last; ++k)
    {
      double shifted[3 * P + 1];
      const double level = sorted[k] * cell.scale;
      for (int j = 0; j <= 3 * P; ++j)
      {
        shifted[j] = along[j] - level;
      }
      double u;
      bool rootCertified;
      if (firstBernsteinRoot<3 * P>(shifted, u, rootCertified) && u < nearest)
      {
        nearest = u;
        hit.isoIndex = k;
        certified = rootCertified;
      }
    }
    if (!(nearest <= 1.0))
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
    hit.gradient = worldGradient(jacobian, parametric, s, cell.scale);
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
      const auto it = std::lower_bound(sorted.begin() + static_cast<std::ptrdiff_t>(first),
        sorted.begin() + static_cast<std::ptrdiff_t>(last), fieldLo / cell.scale);
      index = static_cast<std::size_t>(it - sorted.begin());
      if (index >= last || !(sorted[index] <= fieldHi / cell.scale))
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
    hit.gradient = worldGradient(jacobian, parametric, s, cell.scale);
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
  if (newton<P>(equations, x))
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
  return worldGradient(jacobian, parametric, g.scale, scale);
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
