#include "tetdsr/SplitCells.h"

#include "tetdsr/HigherOrderTet.h"
#include "tetdsr/Messages.h"
#include "tetdsr/QuadraticTetCell.h"

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

/// The pieces' corners: the wedge's three tetrahedra, each ordered for a positive volume.
std::vector<std::array<Corner, 4>> pieceCorners()
{
  std::vector<std::array<Corner, 4>> pieces;
  // The triangle (0, 1, 2) under corner 3, then the pyramid (1, 2, 5, 4; 3) halved.
  constexpr int kPieces[3][4] = { { 0, 1, 2, 3 }, { 1, 2, 5, 3 }, { 1, 5, 4, 3 } };
  for (const auto& piece : kPieces)
  {
    pieces.push_back({ kWedgeCorners[piece[0]], kWedgeCorners[piece[1]], kWedgeCorners[piece[2]],
      kWedgeCorners[piece[3]] });
  }
  for (auto& piece : pieces)
  {
    // 6 x the volume, exact in integers: swap two corners of a negative one.
    int e[3][3];
    for (int k = 0; k < 3; ++k)
    {
      for (int a = 0; a < 3; ++a)
      {
        e[k][a] = piece[k + 1][a] - piece[0][a];
      }
    }
    const int det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
      e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
      e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    if (det < 0)
    {
      std::swap(piece[1], piece[2]);
    }
  }
  return pieces;
}

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

/// Solves a X = b for the Bernstein coefficients X of functions given by their values b at a
/// tetrahedron's lattice points (a: the Bernstein polynomials there), in long double.
std::vector<long double> bernsteinCoefficients(int degree, std::vector<long double> values, int columns)
{
  const int count = latticeCount(degree);
  std::vector<int> alpha(static_cast<std::size_t>(4 * count));
  for (int node = 0; node < count; ++node)
  {
    double L[4];
    tetNodePoint(degree, node, L);
    for (int k = 0; k < 4; ++k)
    {
      alpha[static_cast<std::size_t>(4 * node + k)] = static_cast<int>(std::lround(L[k] * degree));
    }
  }
  std::vector<long double> a(static_cast<std::size_t>(count * count));
  for (int row = 0; row < count; ++row)
  {
    for (int col = 0; col < count; ++col)
    {
      // B_alpha(L) = degree! / prod alpha_k! * prod L_k^alpha_k, at L = alpha_row / degree.
      long double value = 1.0L;
      int placed = 0;
      for (int k = 0; k < 4; ++k)
      {
        const int power = alpha[static_cast<std::size_t>(4 * col + k)];
        const long double L = static_cast<long double>(alpha[static_cast<std::size_t>(4 * row + k)]) / degree;
        for (int m = 1; m <= power; ++m)
        {
          value *= L * static_cast<long double>(placed + m) / m;
        }
        placed += power;
      }
      a[static_cast<std::size_t>(row * count + col)] = value;
    }
  }
  solve(std::move(a), values, count, columns);
  return values;
}

/// A shape from its nodes and basis: its pieces, their nodes, and the weights of its new points.
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
  const bool bezierCell =
    basisKind == SplitShape::Basis::BezierHex || basisKind == SplitShape::Basis::BezierWedge;
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
    for (const Corner& m : shape.monomials)
    {
      shape.degree = std::max(shape.degree, m[0] + m[1] + m[2]);
    }
  }
  else
  {
    shape.degree = (wedge ? 2 : 3) * order;
  }
  if (!wedge)
  {
    return shape; // (hexahedra are not split: their nodes and basis serve HexahedronCell.h's tables)
  }
  const int D = shape.degree;
  shape.pieceNodes = latticeCount(D);
  shape.bezierPieces = D > kMaxTetOrder;
  const auto corners = pieceCorners();
  shape.pieces = static_cast<int>(corners.size());
  // The cell's node at a parametric point, or -1. A Bezier cell's values are the polynomials'
  // only at its corners (its other nodes are control points).
  const int cornerCount = wedge ? 6 : 8;
  auto nodeAt = [&](const Corner& q, int scale) {
    for (int j = 0; j < (bezierCell ? cornerCount : n); ++j)
    {
      const Point& p = shape.nodePoints[static_cast<std::size_t>(j)];
      if (std::abs(p[0] * scale - q[0]) < 1e-9 && std::abs(p[1] * scale - q[1]) < 1e-9 &&
        std::abs(p[2] * scale - q[2]) < 1e-9)
      {
        return j;
      }
    }
    return -1;
  };
  auto addNewPoint = [&](const std::vector<double>& weights, const Point& x) {
    shape.newWeights.insert(shape.newWeights.end(), weights.begin(), weights.end());
    shape.newPoints.push_back(x);
    return shape.newPointCount++;
  };
  // The affine frame: the nodes at the origin and the unit points of r, s and t (corners).
  for (int axis = 0; axis < 4; ++axis)
  {
    shape.frame[axis] = nodeAt({ axis == 1, axis == 2, axis == 3 }, 1);
  }
  // Each piece node's lattice point of the cell (spacing 1/D) and parametric point.
  auto latticePoint = [&](const std::array<Corner, 4>& piece, int node, Corner& q, Point& x) {
    double L[4];
    tetNodePoint(D, node, L);
    q = { 0, 0, 0 };
    for (int k = 0; k < 4; ++k)
    {
      const int alpha = static_cast<int>(std::lround(L[k] * D));
      for (int a = 0; a < 3; ++a)
      {
        q[a] += alpha * piece[static_cast<std::size_t>(k)][a];
      }
    }
    x = { q[0] / static_cast<double>(D), q[1] / static_cast<double>(D), q[2] / static_cast<double>(D) };
  };
  if (!shape.bezierPieces)
  {
    // Lagrange pieces: the cell's map and field at their lattice points, shared by the pieces
    // (keyed i + (D + 1) (j + (D + 1) k)).
    const int side = D + 1;
    std::vector<int> atKey(static_cast<std::size_t>(side * side * side), 0);
    for (const auto& piece : corners)
    {
      for (int node = 0; node < shape.pieceNodes; ++node)
      {
        Corner q;
        Point x;
        latticePoint(piece, node, q, x);
        int& known = atKey[static_cast<std::size_t>(q[0] + side * (q[1] + side * q[2]))];
        if (known == 0)
        {
          const int j = nodeAt(q, D);
          if (j >= 0)
          {
            known = j + 1;
          }
          else
          {
            std::vector<double> weights(static_cast<std::size_t>(n));
            shape.basis(x.data(), weights.data());
            known = -1 - addNewPoint(weights, x);
          }
        }
        shape.pieceNode.push_back(known > 0 ? known - 1 : known);
      }
    }
    return shape;
  }
  // Bezier pieces: the Bernstein coefficients of the cell's shape functions on each piece (the
  // solve of B X = their values at the piece's lattice points), each piece's own new points.
  for (const auto& piece : corners)
  {
    std::vector<long double> values(static_cast<std::size_t>(shape.pieceNodes * n));
    std::vector<double> weights(static_cast<std::size_t>(n));
    // The piece's parametric map is affine, so its control points (those of the cell's map
    // where that is affine too) are the lattice points' images.
    std::vector<Point> lattice(static_cast<std::size_t>(shape.pieceNodes));
    for (int node = 0; node < shape.pieceNodes; ++node)
    {
      Corner q;
      Point& x = lattice[static_cast<std::size_t>(node)];
      latticePoint(piece, node, q, x);
      shape.basis(x.data(), weights.data());
      std::copy(weights.begin(), weights.end(), values.begin() + static_cast<std::ptrdiff_t>(node * n));
    }
    const std::vector<long double> coefficients = bernsteinCoefficients(D, std::move(values), n);
    for (int node = 0; node < shape.pieceNodes; ++node)
    {
      if (node < 4)
      {
        // A vertex: a corner of the cell, where coefficient and value agree.
        shape.pieceNode.push_back(nodeAt(piece[static_cast<std::size_t>(node)], 1));
        continue;
      }
      for (int j = 0; j < n; ++j)
      {
        weights[static_cast<std::size_t>(j)] =
          static_cast<double>(coefficients[static_cast<std::size_t>(node * n + j)]);
      }
      shape.pieceNode.push_back(-1 - addNewPoint(weights, lattice[static_cast<std::size_t>(node)]));
    }
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

/// Whether a cell's map is affine (every node where the affine map through its frame nodes puts
/// it, within the rounding a straight tetrahedron's nodes are allowed: QuadraticTetCell's
/// tolerance for the frame's tetrahedron), and that map: origin frame[0], axes frame[1..3].
bool affineFrame(const SplitShape& shape, const MeshView& input, const NodeId* ids, glm::dvec3 frame[4])
{
  auto node = [&](int j) {
    const double* q = input.points + 3 * ids[j];
    return glm::dvec3(q[0], q[1], q[2]);
  };
  glm::dvec3 vertices[4];
  for (int k = 0; k < 4; ++k)
  {
    vertices[k] = node(shape.frame[k]);
  }
  double tolerance = 0.0;
  if (!(QuadraticTetCell::validateVertices(vertices, input.pointRounding, tolerance) & kValid))
  {
    return false; // its pieces say why (degenerate, out of scale)
  }
  frame[0] = vertices[0];
  for (int k = 1; k < 4; ++k)
  {
    frame[k] = vertices[k] - vertices[0];
  }
  for (int j = 0; j < shape.nodes; ++j)
  {
    const auto& r = shape.nodePoints[static_cast<std::size_t>(j)];
    const glm::dvec3 expected = frame[0] + r[0] * frame[1] + r[1] * frame[2] + r[2] * frame[3];
    const glm::dvec3 at = node(j);
    // (A non-finite node is off its place: the weights then make its cell's points non-finite,
    // and the cell is told as such.)
    if (!isFinite(at) || QuadraticTetCell::offItsPlace(at, expected, tolerance))
    {
      return false;
    }
  }
  return true;
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

bool isSplitType(int vtkType)
{
  (void)vtkType;
  return false; // (every wedge is solved as itself now)
}

std::uint16_t splitShapeOf(int vtkType, long long ids, const SplitShape*& shape)
{
  const CellType* type = cellTypeOf(vtkType);
  if (!isRead(type) || (type->shape != CellShape::Hexahedron && type->shape != CellShape::Wedge))
  {
    return kUnsupported;
  }
  const int order = orderOf(*type, ids);
  if (order == 0)
  {
    return kMalformed;
  }
  if (order > type->maxOrder)
  {
    return kOrderTooHigh;
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

struct SplitMesh::Arrays
{
  std::vector<double> Points;
  std::vector<double> Values;
  std::vector<std::uint8_t> Types;
  std::vector<NodeId> Offsets;
  std::vector<NodeId> Connectivity;
  std::vector<NodeId> SourceCells;
  std::vector<NodeId> SourceOffsets;
  std::vector<std::uint16_t> SourceStatus;
  /// Per input cell that is split: its order per axis (0 for cells kept as they are).
  std::vector<std::uint8_t> SourceOrders;
  /// Per input cell: 1 for a type whose VTK node order reverses the parametric orientation.
  std::vector<std::uint8_t> SourceMirrored;
  /// Per input cell that is split: its shape, its first new point (after the input's points)
  /// and its node ids (copied: the input may be edited later).
  std::vector<const SplitShape*> Shape;
  std::vector<NodeId> FirstNew;
  std::vector<NodeId> IdsAt;
  std::vector<NodeId> Ids;
  NodeId InputPoints = 0;
};

SplitMesh::SplitMesh() = default;
SplitMesh::~SplitMesh() = default;

bool SplitMesh::needed(const MeshView& input)
{
  for (NodeId cell = 0; cell < input.numberOfCells; ++cell)
  {
    if (isSplitType(input.cellTypes[cell]))
    {
      return true;
    }
  }
  return false;
}

bool SplitMesh::split(const MeshView& input, const ParallelFor& parallelFor, std::string& error)
{
  Data_.reset(new Arrays);
  Arrays& out = *Data_;
  const auto cells = static_cast<std::size_t>(input.numberOfCells);
  out.InputPoints = input.numberOfPoints;
  out.SourceOffsets.resize(cells + 1);
  out.SourceStatus.assign(cells, 0);
  out.SourceOrders.assign(cells, 0);
  out.SourceMirrored.assign(cells, 0);
  out.Shape.assign(cells, nullptr);
  out.FirstNew.assign(cells, 0);
  out.IdsAt.assign(cells, 0);
  // First, serially: each cell's reading (its type, offsets and ids), its pieces and new points.
  NodeId pieces = 0, newPoints = 0, connectivity = 0, copiedIds = 0;
  std::vector<NodeId> connectivityAt(cells);
  for (std::size_t c = 0; c < cells; ++c)
  {
    out.SourceOffsets[c] = pieces;
    out.FirstNew[c] = input.numberOfPoints + newPoints;
    connectivityAt[c] = connectivity;
    const int type = input.cellTypes[c];
    const NodeId begin = input.offsets[c];
    const NodeId end = input.offsets[c + 1];
    const bool readable = begin >= 0 && end >= begin && end <= input.connectivitySize;
    if (!isSplitType(type))
    {
      // A tetrahedron (or a type the scene refuses) is kept as it is, unless its reading fails
      // here already (as the scene's would: the type, then the offsets, then the id count), so
      // that no hostile offsets make the copy larger than the cells can be.
      CellLayout layout;
      std::uint16_t unreadable = cellLayout(type, -1, layout) == kUnsupported ? kUnsupported
        : !readable                                                          ? kMalformed
                                              : cellLayout(type, end - begin, layout);
      if (!unreadable)
      {
        // Its ids too (the split mesh has no rational weights: its Bezier pieces are polynomial
        // by construction, so a kept Bezier tetrahedron's weights are checked here).
        unreadable = checkNodeIds(input, input.connectivity + begin, layout.nodes, layout.bezier);
      }
      if (unreadable)
      {
        out.SourceStatus[c] = unreadable;
        continue;
      }
      pieces += 1;
      connectivity += end - begin;
      continue;
    }
    if (!readable)
    {
      // The type first, as the scene reads any cell: a pyramid is unsupported whatever its
      // offsets.
      const SplitShape* ignored = nullptr;
      out.SourceStatus[c] = splitShapeOf(type, -1, ignored) == kUnsupported ? kUnsupported : kMalformed;
      continue;
    }
    const SplitShape* shape = nullptr;
    std::uint16_t status = splitShapeOf(type, end - begin, shape);
    if (status == 0)
    {
      status = checkNodeIds(input, input.connectivity + begin, shape->nodes,
        cellTypeOf(type)->bezier);
    }
    if (status != 0)
    {
      out.SourceStatus[c] = status;
      continue;
    }
    out.SourceOrders[c] = static_cast<std::uint8_t>(shape->order);
    glm::dvec3 frame[4];
    if (!affineFrame(*shape, input, input.connectivity + begin, frame))
    {
      // A curved wedge is solved as itself (HexahedronCell.h's collapsed hexahedron): kept as it
      // is, its own validation telling its orientation.
      pieces += 1;
      connectivity += end - begin;
      continue;
    }
    out.Shape[c] = shape;
    out.SourceMirrored[c] = cellTypeOf(type)->mirrored;
    out.IdsAt[c] = copiedIds;
    copiedIds += shape->nodes;
    pieces += shape->pieces;
    newPoints += shape->newPointCount;
    connectivity += static_cast<NodeId>(shape->pieces) * shape->pieceNodes;
  }
  out.SourceOffsets[cells] = pieces;
  if (pieces > Scene::kMaxCells)
  {
    error = text("The input's hexahedra and wedges split into ", pieces,
      " tetrahedra; at most ", Scene::kMaxCells, " can be rendered.");
    return false;
  }
  const auto totalPoints = static_cast<std::size_t>(input.numberOfPoints + newPoints);
  out.Points.resize(3 * totalPoints);
  out.Values.resize(totalPoints);
  std::copy(input.points, input.points + 3 * input.numberOfPoints, out.Points.begin());
  std::copy(input.values, input.values + input.numberOfPoints, out.Values.begin());
  out.Types.resize(static_cast<std::size_t>(pieces));
  out.Offsets.resize(static_cast<std::size_t>(pieces) + 1);
  out.Connectivity.resize(static_cast<std::size_t>(connectivity));
  out.SourceCells.resize(static_cast<std::size_t>(pieces));
  out.Ids.resize(static_cast<std::size_t>(copiedIds));
  out.Offsets[static_cast<std::size_t>(pieces)] = connectivity;
  // Then each cell's pieces and new points, in parallel: every cell writes only its own slots.
  parallelFor(input.numberOfCells, [&](NodeId first, NodeId last) {
    for (NodeId cell = first; cell < last; ++cell)
    {
      const auto c = static_cast<std::size_t>(cell);
      NodeId piece = out.SourceOffsets[c];
      NodeId at = connectivityAt[c];
      const NodeId begin = input.offsets[c];
      if (out.SourceStatus[c] != 0)
      {
        continue;
      }
      if (!out.Shape[c])
      {
        // Kept as it is (its reading checked above).
        out.Types[static_cast<std::size_t>(piece)] = input.cellTypes[c];
        out.SourceCells[static_cast<std::size_t>(piece)] = cell;
        out.Offsets[static_cast<std::size_t>(piece)] = at;
        std::copy(input.connectivity + begin, input.connectivity + input.offsets[c + 1],
          out.Connectivity.begin() + at);
        continue;
      }
      const SplitShape& shape = *out.Shape[c];
      const NodeId* ids = input.connectivity + begin;
      std::copy(ids, ids + shape.nodes, out.Ids.begin() + out.IdsAt[c]);
      const std::uint8_t pieceType =
        static_cast<std::uint8_t>(shape.bezierPieces ? kVtkBezierTetrahedron
            : shape.degree == 2                     ? kVtkQuadraticTetra
                                                    : kVtkLagrangeTetrahedron);
      for (int k = 0; k < shape.pieces; ++k, ++piece)
      {
        out.Types[static_cast<std::size_t>(piece)] = pieceType;
        out.SourceCells[static_cast<std::size_t>(piece)] = cell;
        out.Offsets[static_cast<std::size_t>(piece)] = at;
        for (int n = 0; n < shape.pieceNodes; ++n)
        {
          const int node = shape.pieceNode[static_cast<std::size_t>(k * shape.pieceNodes + n)];
          out.Connectivity[static_cast<std::size_t>(at++)] =
            node >= 0 ? ids[node] : out.FirstNew[c] + (-1 - node);
        }
      }
      // The new points: the cell's map and field there (the map as the affine one where the
      // cell is straight).
      glm::dvec3 frame[4];
      const bool affine = affineFrame(shape, input, ids, frame);
      for (int p = 0; p < shape.newPointCount; ++p)
      {
        const double* w = shape.newWeights.data() + static_cast<std::size_t>(p) * shape.nodes;
        const auto point = static_cast<std::size_t>(out.FirstNew[c] + p);
        double x = 0.0, y = 0.0, z = 0.0, value = 0.0;
        for (int j = 0; j < shape.nodes; ++j)
        {
          value += w[j] * input.values[ids[j]];
        }
        if (affine)
        {
          const auto& r = shape.newPoints[static_cast<std::size_t>(p)];
          const glm::dvec3 at = frame[0] + r[0] * frame[1] + r[1] * frame[2] + r[2] * frame[3];
          x = at.x;
          y = at.y;
          z = at.z;
        }
        else
        {
          for (int j = 0; j < shape.nodes; ++j)
          {
            const double* q = input.points + 3 * ids[j];
            x += w[j] * q[0];
            y += w[j] * q[1];
            z += w[j] * q[2];
          }
        }
        if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z) && std::isfinite(value)))
        {
          // Finite nodes whose polynomial leaves double range between them (a field near the
          // largest double) are out of scale, as a tetrahedron's Bernstein coefficients are;
          // non-finite nodes are told as such.
          bool finiteNodes = true;
          for (int j = 0; j < shape.nodes; ++j)
          {
            const double* q = input.points + 3 * ids[j];
            finiteNodes = finiteNodes && std::isfinite(q[0]) && std::isfinite(q[1]) &&
              std::isfinite(q[2]) && std::isfinite(input.values[ids[j]]);
          }
          out.SourceStatus[c] = finiteNodes ? kOutOfScale : kNonFinite;
        }
        out.Points[3 * point] = x;
        out.Points[3 * point + 1] = y;
        out.Points[3 * point + 2] = z;
        out.Values[point] = value;

      }
    }
  });
  View_ = MeshView();
  View_.points = out.Points.data();
  View_.numberOfPoints = static_cast<NodeId>(totalPoints);
  View_.numberOfCells = pieces;
  View_.cellTypes = out.Types.data();
  View_.offsets = out.Offsets.data();
  View_.connectivity = out.Connectivity.data();
  View_.connectivitySize = connectivity;
  View_.values = out.Values.data();
  View_.rationalWeights = nullptr; // (checked above, per input cell)
  View_.pointRounding = input.pointRounding;
  View_.sourceCells = out.SourceCells.data();
  View_.sourceOffsets = out.SourceOffsets.data();
  View_.sourceStatus = out.SourceStatus.data();
  View_.sourceOrders = out.SourceOrders.data();
  View_.sourceMirrored = out.SourceMirrored.data();
  View_.numberOfSourceCells = input.numberOfCells;
  return true;
}

void SplitMesh::extend(const double* input, int components, std::vector<double>& out) const
{
  const Arrays& in = *Data_;
  const auto width = static_cast<std::size_t>(components);
  out.assign(static_cast<std::size_t>(View_.numberOfPoints) * width, 0.0);
  std::copy(input, input + static_cast<std::size_t>(in.InputPoints) * width, out.begin());
  for (std::size_t c = 0; c < in.Shape.size(); ++c)
  {
    const SplitShape* shape = in.Shape[c];
    if (!shape)
    {
      continue;
    }
    const NodeId* ids = in.Ids.data() + in.IdsAt[c];
    for (int p = 0; p < shape->newPointCount; ++p)
    {
      const double* w = shape->newWeights.data() + static_cast<std::size_t>(p) * shape->nodes;
      const auto point = static_cast<std::size_t>(in.FirstNew[c] + p);
      for (std::size_t k = 0; k < width; ++k)
      {
        double sum = 0.0;
        for (int j = 0; j < shape->nodes; ++j)
        {
          sum += w[j] * input[static_cast<std::size_t>(ids[j]) * width + k];
        }
        out[point * width + k] = sum;
      }
    }
  }
}

std::size_t SplitMesh::memoryBytes() const
{
  if (!Data_)
  {
    return 0;
  }
  const Arrays& a = *Data_;
  return sizeof(double) * (a.Points.capacity() + a.Values.capacity()) +
    a.Types.capacity() + a.SourceOrders.capacity() + a.SourceMirrored.capacity() + a.SourceStatus.capacity() * sizeof(std::uint16_t) +
    sizeof(NodeId) *
    (a.Offsets.capacity() + a.Connectivity.capacity() + a.SourceCells.capacity() +
      a.SourceOffsets.capacity() + a.FirstNew.capacity() + a.IdsAt.capacity() + a.Ids.capacity()) +
    sizeof(void*) * a.Shape.capacity();
}

} // namespace tetdsr
