#include "tetdsr/cells/SplitCells.h"

#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/common/Messages.h"
#include "tetdsr/cells/QuadraticTetCell.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
using Point = std::array<double, 3>;
using Corner = std::array<int, 3>;

/// The unit cube's corners in VTK_HEXAHEDRON's order, and the wedge's in VTK_WEDGE's.
constexpr Corner kCubeCorners[8] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 },
  { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } };
constexpr Corner kWedgeCorners[6] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 },
  { 1, 0, 1 }, { 0, 1, 1 } };

/// The hexahedron's edges (VTK_QUADRATIC_HEXAHEDRON's mid-edge node order) and the wedge's
/// (VTK_QUADRATIC_WEDGE's: the two triangles' edges, then the three vertical ones); the wedge's
/// quadrilateral faces (VTK_BIQUADRATIC_QUADRATIC_WEDGE's face nodes).
constexpr int kHexEdges[12][2] = { { 0, 1 }, { 1, 2 }, { 3, 2 }, { 0, 3 }, { 4, 5 }, { 5, 6 },
  { 7, 6 }, { 4, 7 }, { 0, 4 }, { 1, 5 }, { 2, 6 }, { 3, 7 } };
constexpr int kWedgeEdges[9][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 }, { 3, 4 }, { 4, 5 }, { 5, 3 },
  { 0, 3 }, { 1, 4 }, { 2, 5 } };
constexpr int kWedgeQuads[3][4] = { { 0, 1, 4, 3 }, { 1, 2, 5, 4 }, { 2, 0, 3, 5 } };


/// Monomials r^a s^b t^c with a <= ra, b <= sb, c <= tc (a tensor-product space), or, for a
/// wedge, a + b <= triangle and c <= axis.
std::vector<Corner> tensorMonomials(int ra, int sb, int tc)
{
  std::vector<Corner> m;
  for (int c = 0; c <= tc; ++c)
    for (int b = 0; b <= sb; ++b)
      for (int a = 0; a <= ra; ++a)
        m.push_back({ a, b, c });
  return m;
}
std::vector<Corner> wedgeMonomials(int triangle, int axis)
{
  std::vector<Corner> m;
  for (int c = 0; c <= axis; ++c)
    for (int b = 0; b <= triangle; ++b)
      for (int a = 0; a + b <= triangle; ++a)
        m.push_back({ a, b, c });
  return m;
}

long double monomialAt(const Corner& m, const Point& x)
{
  long double value = 1.0L;
  for (int a = 0; a < 3; ++a)
  {
    for (int k = 0; k < m[a]; ++k)
    {
      value *= static_cast<long double>(x[a]);
    }
  }
  return value;
}

double binomial(int n, int k)
{
  double b = 1.0;
  for (int i = 1; i <= k; ++i)
  {
    b = b * (n - k + i) / i;
  }
  return b;
}

/// Solves a x = b in place (n x n, row-major), Gaussian elimination with partial pivoting in
/// long double; the spaces here are small (n <= 20) and their Vandermonde matrices at the nodes
/// well conditioned.
void solve(std::vector<long double> a, std::vector<long double>& b, int n, int columns)
{
  for (int col = 0; col < n; ++col)
  {
    int pivot = col;
    for (int r = col + 1; r < n; ++r)
    {
      pivot = std::abs(a[r * n + col]) > std::abs(a[pivot * n + col]) ? r : pivot;
    }
    for (int c = 0; c < n; ++c)
    {
      std::swap(a[col * n + c], a[pivot * n + c]);
    }
    for (int c = 0; c < columns; ++c)
    {
      std::swap(b[col * columns + c], b[pivot * columns + c]);
    }
    for (int r = col + 1; r < n; ++r)
    {
      const long double factor = a[r * n + col] / a[col * n + col];
      for (int c = col; c < n; ++c)
      {
        a[r * n + c] -= factor * a[col * n + c];
      }
      for (int c = 0; c < columns; ++c)
      {
        b[r * columns + c] -= factor * b[col * columns + c];
      }
    }
  }
  for (int r = n - 1; r >= 0; --r)
  {
    for (int c = 0; c < columns; ++c)
    {
      long double sum = b[r * columns + c];
      for (int k = r + 1; k < n; ++k)
      {
        sum -= a[r * n + k] * b[k * columns + c];
      }
      b[r * columns + c] = sum / a[r * n + r];
    }
  }
}


/// A shape from its nodes and basis.
SplitShape makeShape(const char* name, bool wedge, std::vector<Point> nodePoints,
  SplitShape::Basis basisKind, int order, std::vector<Corner> monomials = {})
{
  SplitShape shape;
  shape.name = name;
  shape.wedge = wedge;
  shape.basisKind = basisKind;
  shape.order = order;
  shape.nodes = static_cast<int>(nodePoints.size());
  shape.nodePoints = std::move(nodePoints);
  const int n = shape.nodes;
  if (basisKind == SplitShape::Basis::Monomials)
  {
    // The nodal basis: weights(x) = V^-T m(x), V[node][monomial] = m(node).
    shape.monomials = std::move(monomials);
    std::vector<long double> transposed(static_cast<std::size_t>(n * n));
    std::vector<long double> identity(static_cast<std::size_t>(n * n), 0.0L);
    for (int j = 0; j < n; ++j)
    {
      for (int a = 0; a < n; ++a)
      {
        transposed[static_cast<std::size_t>(a * n + j)] =
          monomialAt(shape.monomials[static_cast<std::size_t>(a)], shape.nodePoints[static_cast<std::size_t>(j)]);
      }
      identity[static_cast<std::size_t>(j * n + j)] = 1.0L;
    }
    solve(transposed, identity, n, n);
    shape.inverseVandermonde.assign(identity.begin(), identity.end());
  }
  return shape;
}

/// VTK's Lagrange and Bezier hexahedron of order p (vtkHigherOrderHexahedron): the corners, each
/// edge's interior points from its first vertex to its second, the faces r = 0, r = 1 (s
/// fastest, then t), s = 0, s = 1 (r, then t), t = 0, t = 1 (r, then s), then the body (r, s,
/// then t).
std::vector<Point> hexahedronNodes(int p)
{
  std::vector<Point> points;
  auto put = [&](int i, int j, int k) {
    points.push_back({ i / static_cast<double>(p), j / static_cast<double>(p), k / static_cast<double>(p) });
  };
  for (const Corner& c : kCubeCorners)
  {
    put(p * c[0], p * c[1], p * c[2]);
  }
  for (const auto& edge : kHexEdges)
  {
    const Corner& a = kCubeCorners[edge[0]];
    const Corner& b = kCubeCorners[edge[1]];
    for (int m = 1; m < p; ++m)
    {
      put(p * a[0] + m * (b[0] - a[0]), p * a[1] + m * (b[1] - a[1]), p * a[2] + m * (b[2] - a[2]));
    }
  }
  for (const int side : { 0, p })
    for (int k = 1; k < p; ++k)
      for (int j = 1; j < p; ++j)
        put(side, j, k);
  for (const int side : { 0, p })
    for (int k = 1; k < p; ++k)
      for (int i = 1; i < p; ++i)
        put(i, side, k);
  for (const int side : { 0, p })
    for (int j = 1; j < p; ++j)
      for (int i = 1; i < p; ++i)
        put(i, j, side);
  for (int k = 1; k < p; ++k)
    for (int j = 1; j < p; ++j)
      for (int i = 1; i < p; ++i)
        put(i, j, k);
  return points;
}

/// VTK's Lagrange and Bezier wedge of order p (vtkHigherOrderWedge): the corners, the edges
/// (kWedgeEdges, first vertex to second), the triangles t = 0 and t = 1 (their interior, r
/// fastest), the quadrilaterals (kWedgeQuads: along their first edge fastest, then t), then the
/// body (the triangle's interior order, then t).
std::vector<Point> wedgeNodes(int p)
{
  std::vector<Point> points;
  auto put = [&](int i, int j, int k) {
    points.push_back({ i / static_cast<double>(p), j / static_cast<double>(p), k / static_cast<double>(p) });
  };
  for (const Corner& c : kWedgeCorners)
  {
    put(p * c[0], p * c[1], p * c[2]);
  }
  for (const auto& edge : kWedgeEdges)
  {
    const Corner& a = kWedgeCorners[edge[0]];
    const Corner& b = kWedgeCorners[edge[1]];
    for (int m = 1; m < p; ++m)
    {
      put(p * a[0] + m * (b[0] - a[0]), p * a[1] + m * (b[1] - a[1]), p * a[2] + m * (b[2] - a[2]));
    }
  }
  auto triangleInterior = [&](int k) {
    for (int j = 1; j < p; ++j)
      for (int i = 1; i + j < p; ++i)
        put(i, j, k);
  };
  triangleInterior(0);
  triangleInterior(p);
  for (const auto& quad : kWedgeQuads)
  {
    const Corner& a = kWedgeCorners[quad[0]];
    const Corner& b = kWedgeCorners[quad[1]];
    for (int k = 1; k < p; ++k)
      for (int m = 1; m < p; ++m)
        put(p * a[0] + m * (b[0] - a[0]), p * a[1] + m * (b[1] - a[1]), k);
  }
  for (int k = 1; k < p; ++k)
  {
    triangleInterior(k);
  }
  return points;
}

/// The first `count` nodes of a Lagrange cell of order 2: VTK's fixed quadratic hexahedra and
/// wedges order their nodes as it does, and stop early (the 20- and 24-node hexahedra; the 12-node
/// wedge without vertical edges, the 15-node one without faces).
std::vector<Point> firstNodes(std::vector<Point> nodes, int count)
{
  nodes.resize(static_cast<std::size_t>(count));
  return nodes;
}

/// The 20-node serendipity space: Q2's monomials with at most one exponent equal to 2 ... and
/// r^2 s t, r s^2 t, r s t^2 (those with one 2 and two 1s are in it).
std::vector<Corner> serendipity20()
{
  std::vector<Corner> m;
  for (const Corner& c : tensorMonomials(2, 2, 2))
  {
    if ((c[0] == 2) + (c[1] == 2) + (c[2] == 2) <= 1)
    {
      m.push_back(c);
    }
  }
  return m;
}

/// The 15-node quadratic wedge's space: P2(r, s) x P1(t), and t^2 times P1(r, s).
std::vector<Corner> quadraticWedge15()
{
  std::vector<Corner> m = wedgeMonomials(2, 1);
  for (const Corner& c : wedgeMonomials(1, 0))
  {
    m.push_back({ c[0], c[1], 2 });
  }
  return m;
}

/// Every shape the split reads, each built on first use (orders above 4 solve for their pieces'
/// Bernstein weights: up to a second for order 4 hexahedra).
using Basis = SplitShape::Basis;
const SplitShape& hexahedronShape()
{
  static const SplitShape shape = makeShape("VTK_HEXAHEDRON", false, hexahedronNodes(1), Basis::Monomials, 1, tensorMonomials(1, 1, 1));
  return shape;
}
const SplitShape& voxelShape()
{
  static const SplitShape shape = makeShape("VTK_VOXEL", false,
    { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 }, { 1, 1, 1 } },
    Basis::Monomials, 1, tensorMonomials(1, 1, 1));
  return shape;
}
const SplitShape& hexahedron20Shape()
{
  static const SplitShape shape = makeShape("VTK_QUADRATIC_HEXAHEDRON", false, firstNodes(hexahedronNodes(2), 20), Basis::Monomials, 2, serendipity20());
  return shape;
}
const SplitShape& hexahedron24Shape()
{
  // VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON: the 20 nodes and the centres of the faces r = 0, 1 and
  // s = 0, 1; its space is Q2's without r^2 s^2 t^c (c = 0, 1, 2), total degree 5.
  static const SplitShape shape = [] {
    std::vector<Corner> space;
    for (const Corner& c : tensorMonomials(2, 2, 2))
    {
      if (!(c[0] == 2 && c[1] == 2))
      {
        space.push_back(c);
      }
    }
    return makeShape("VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON", false, firstNodes(hexahedronNodes(2), 24), Basis::Monomials, 2, space);
  }();
  return shape;
}
const SplitShape& wedgeShape()
{
  static const SplitShape shape = makeShape("VTK_WEDGE", true, wedgeNodes(1), Basis::Monomials, 1, wedgeMonomials(1, 1));
  return shape;
}
const SplitShape& wedge12Shape()
{
  static const SplitShape shape = makeShape("VTK_QUADRATIC_LINEAR_WEDGE", true, firstNodes(wedgeNodes(2), 12), Basis::Monomials, 2, wedgeMonomials(2, 1));
  return shape;
}
const SplitShape& wedge15Shape()
{
  static const SplitShape shape = makeShape("VTK_QUADRATIC_WEDGE", true, firstNodes(wedgeNodes(2), 15), Basis::Monomials, 2, quadraticWedge15());
  return shape;
}
const SplitShape& wedge18Shape()
{
  static const SplitShape shape = makeShape("VTK_BIQUADRATIC_QUADRATIC_WEDGE", true, wedgeNodes(2), Basis::Monomials, 2, wedgeMonomials(2, 2));
  return shape;
}

/// A Lagrange or Bezier hexahedron or wedge of order 2 to 4, built on first use and once (a
/// static local: thread-safe). Those of order 4 take about a second (their pieces' Bernstein
/// weights are a solve of 455 equations), so none is built before a mesh has such a cell.
template <bool Wedge, bool Bezier, int Order>
const SplitShape& builtShape()
{
  static const SplitShape shape = makeShape(
    Wedge ? (Bezier ? "VTK_BEZIER_WEDGE" : "VTK_LAGRANGE_WEDGE")
          : (Bezier ? "VTK_BEZIER_HEXAHEDRON" : "VTK_LAGRANGE_HEXAHEDRON"),
    Wedge, Wedge ? wedgeNodes(Order) : hexahedronNodes(Order),
    Wedge ? (Bezier ? Basis::BezierWedge : Basis::LagrangeWedge)
          : (Bezier ? Basis::BezierHex : Basis::LagrangeHex),
    Order);
  return shape;
}

/// Lagrange and Bezier hexahedra of orders 2 to 4 (VTK_TRIQUADRATIC_HEXAHEDRON is the Lagrange
/// one of order 2: the same nodes), wedges of orders 2 to 4.
const SplitShape& higherOrderShape(bool wedge, bool bezier, int order)
{
  using Builder = const SplitShape& (*)();
  static constexpr Builder kBuilders[2][2][3] = {
    { { builtShape<false, false, 2>, builtShape<false, false, 3>, builtShape<false, false, 4> },
      { builtShape<false, true, 2>, builtShape<false, true, 3>, builtShape<false, true, 4> } },
    { { builtShape<true, false, 2>, builtShape<true, false, 3>, builtShape<true, false, 4> },
      { builtShape<true, true, 2>, builtShape<true, true, 3>, builtShape<true, true, 4> } }
  };
  return kBuilders[wedge][bezier][order - 2]();
}

/// The 1D Lagrange polynomial of equispaced node i (of 0..p) at x in [0, 1].
double lagrange1D(int p, int i, double x)
{
  double value = 1.0;
  for (int m = 0; m <= p; ++m)
  {
    if (m != i)
    {
      value *= (p * x - m) / (i - m);
    }
  }
  return value;
}

/// The triangle's Lagrange polynomial of lattice point (a, b, c), a + b + c = p, at barycentric
/// (l1, l2, l0): the product of (p l - m) / (m + 1) over m < its index, per coordinate.
double lagrangeTriangle(int p, int a, int b, double l1, double l2)
{
  const double l0 = 1.0 - l1 - l2;
  const int c = p - a - b;
  double value = 1.0;
  for (int m = 0; m < a; ++m)
    value *= (p * l1 - m) / (m + 1);
  for (int m = 0; m < b; ++m)
    value *= (p * l2 - m) / (m + 1);
  for (int m = 0; m < c; ++m)
    value *= (p * l0 - m) / (m + 1);
  return value;
}

double bernstein1D(int p, int i, double x)
{
  return binomial(p, i) * std::pow(x, i) * std::pow(1.0 - x, p - i);
}


} // namespace

void SplitShape::basis(const double parametric[3], double* weights) const
{
  const Point x{ parametric[0], parametric[1], parametric[2] };
  if (basisKind == Basis::Monomials)
  {
    const auto n = static_cast<std::size_t>(nodes);
    std::vector<long double> m(n);
    for (std::size_t a = 0; a < n; ++a)
    {
      m[a] = monomialAt(monomials[a], x);
    }
    for (std::size_t j = 0; j < n; ++j)
    {
      long double sum = 0.0L;
      for (std::size_t a = 0; a < n; ++a)
      {
        sum += static_cast<long double>(inverseVandermonde[j * n + a]) * m[a];
      }
      weights[j] = static_cast<double>(sum);
    }
    return;
  }
  const int p = order;
  for (int j = 0; j < nodes; ++j)
  {
    // The node's lattice point (i, k, l) / p.
    const Point& at = nodePoints[static_cast<std::size_t>(j)];
    const int i = static_cast<int>(std::lround(at[0] * p));
    const int k = static_cast<int>(std::lround(at[1] * p));
    const int l = static_cast<int>(std::lround(at[2] * p));
    switch (basisKind)
    {
      case Basis::LagrangeHex:
        weights[j] = lagrange1D(p, i, x[0]) * lagrange1D(p, k, x[1]) * lagrange1D(p, l, x[2]);
        break;
      case Basis::LagrangeWedge:
        weights[j] = lagrangeTriangle(p, i, k, x[0], x[1]) * lagrange1D(p, l, x[2]);
        break;
      case Basis::BezierHex:
        weights[j] = bernstein1D(p, i, x[0]) * bernstein1D(p, k, x[1]) * bernstein1D(p, l, x[2]);
        break;
      default: // BezierWedge: the triangle's Bernstein polynomial times the axis's
        weights[j] = binomial(p, i) * binomial(p - i, k) * std::pow(x[0], i) * std::pow(x[1], k) *
          std::pow(1.0 - x[0] - x[1], p - i - k) * bernstein1D(p, l, x[2]);
    }
  }
}

std::vector<std::array<double, 3>> hexahedronNodePoints(int order)
{
  return hexahedronNodes(order);
}

std::uint16_t splitShapeOf(int vtkType, long long ids, const SplitShape*& shape)
{
  const CellType* type = cellTypeOf(vtkType);
  int order = 0;
  if (type && type->shape != CellShape::Hexahedron && type->shape != CellShape::Wedge)
  {
    return kUnsupported;
  }
  if (const std::uint16_t status = readOrder(type, ids, order))
  {
    return status;
  }
  const bool bezier = type->bezier;
  switch (vtkType)
  {
    case kVtkVoxel:
      shape = &voxelShape();
      break;
    case kVtkHexahedron:
      shape = &hexahedronShape();
      break;
    case kVtkQuadraticHexahedron:
      shape = &hexahedron20Shape();
      break;
    case kVtkBiquadraticQuadraticHexahedron:
      shape = &hexahedron24Shape();
      break;
    case kVtkTriquadraticHexahedron:
      shape = &higherOrderShape(false, false, 2);
      break;
    case kVtkWedge:
      shape = &wedgeShape();
      break;
    case kVtkQuadraticLinearWedge:
      shape = &wedge12Shape();
      break;
    case kVtkQuadraticWedge:
      shape = &wedge15Shape();
      break;
    case kVtkBiquadraticQuadraticWedge:
      shape = &wedge18Shape();
      break;
    case kVtkLagrangeHexahedron:
    case kVtkBezierHexahedron:
      // (Order p is of total degree 3p.)
      shape = order == 1 ? &hexahedronShape() : &higherOrderShape(false, bezier, order);
      break;
    default:
      // Lagrange and Bezier wedges: order p is of total degree 2p.
      shape = order == 1 ? &wedgeShape()
        : order == 2 && !bezier ? &wedge18Shape()
                                : &higherOrderShape(true, bezier, order);
  }
  return 0;
}

} // namespace tetdsr
