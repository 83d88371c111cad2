#include "tetdsr/SplitCells.h"

#include "tetdsr/HigherOrderTet.h"
#include "tetdsr/Messages.h"

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

Point corner(const Corner& c)
{
  return { static_cast<double>(c[0]), static_cast<double>(c[1]), static_cast<double>(c[2]) };
}

/// The mean of some corners (an edge's or face's centre).
template <std::size_t N>
Point centre(const Corner* corners, const int (&which)[N])
{
  Point p{ 0.0, 0.0, 0.0 };
  for (const int v : which)
  {
    for (int a = 0; a < 3; ++a)
    {
      p[a] += corners[v][a] / static_cast<double>(N);
    }
  }
  return p;
}

/// The pieces' corners: Kuhn's six tetrahedra of the cube (from (0,0,0) to (1,1,1) along the
/// axes in each order), the wedge's three; each ordered for a positive volume.
std::vector<std::array<Corner, 4>> pieceCorners(bool wedge)
{
  std::vector<std::array<Corner, 4>> pieces;
  if (wedge)
  {
    // The triangle (0, 1, 2) under corner 3, then the pyramid (1, 2, 5, 4; 3) halved.
    constexpr int kPieces[3][4] = { { 0, 1, 2, 3 }, { 1, 2, 5, 3 }, { 1, 5, 4, 3 } };
    for (const auto& piece : kPieces)
    {
      pieces.push_back({ kWedgeCorners[piece[0]], kWedgeCorners[piece[1]],
        kWedgeCorners[piece[2]], kWedgeCorners[piece[3]] });
    }
  }
  else
  {
    int axes[3] = { 0, 1, 2 };
    do
    {
      std::array<Corner, 4> piece{};
      for (int step = 0; step < 3; ++step)
      {
        piece[step + 1] = piece[step];
        piece[step + 1][axes[step]] = 1;
      }
      pieces.push_back(piece);
    } while (std::next_permutation(axes, axes + 3));
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

/// A shape from its nodes and space: the nodal basis's inverse Vandermonde matrix, the pieces
/// and their lattice points, and the weights of the new points.
SplitShape makeShape(const char* name, bool wedge, std::vector<Point> nodePoints,
  std::vector<Corner> monomials, int bezierTriangle = 0, int bezierAxis = 0)
{
  SplitShape shape;
  shape.name = name;
  shape.wedge = wedge;
  shape.nodes = static_cast<int>(nodePoints.size());
  shape.nodePoints = std::move(nodePoints);
  shape.bezier = monomials.empty();
  shape.bezierTriangle = bezierTriangle;
  shape.bezierAxis = bezierAxis;
  const int n = shape.nodes;
  if (shape.bezier)
  {
    shape.degree = bezierTriangle + bezierAxis;
  }
  else
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
  const int D = shape.degree;
  shape.pieceNodes = latticeCount(D);
  const auto corners = pieceCorners(wedge);
  shape.pieces = static_cast<int>(corners.size());
  // Lattice points of the cell at spacing 1/D, keyed i + (D + 1) (j + (D + 1) k).
  const int side = D + 1;
  shape.latticeNode.assign(static_cast<std::size_t>(side * side * side), -1);
  shape.latticeNew.assign(static_cast<std::size_t>(side * side * side), -1);
  for (const auto& piece : corners)
  {
    for (int node = 0; node < shape.pieceNodes; ++node)
    {
      double L[4];
      tetNodePoint(D, node, L);
      Corner q{ 0, 0, 0 };
      for (int k = 0; k < 4; ++k)
      {
        const int alpha = static_cast<int>(std::lround(L[k] * D));
        for (int a = 0; a < 3; ++a)
        {
          q[a] += alpha * piece[static_cast<std::size_t>(k)][a];
        }
      }
      const int key = q[0] + side * (q[1] + side * q[2]);
      shape.pieceLattice.push_back(key);
      if (shape.latticeNode[static_cast<std::size_t>(key)] >= 0 ||
        shape.latticeNew[static_cast<std::size_t>(key)] >= 0)
      {
        continue; // (a point pieces share)
      }
      const Point x{ q[0] / static_cast<double>(D), q[1] / static_cast<double>(D),
        q[2] / static_cast<double>(D) };
      // A point at a node takes that node (shared with the neighbours); a Bezier cell's
      // values are the polynomials' only at its corners (its other nodes are control points).
      const int cornersOnly = wedge ? 6 : 8;
      for (int j = 0; j < (shape.bezier ? cornersOnly : n); ++j)
      {
        const Point& p = shape.nodePoints[static_cast<std::size_t>(j)];
        if (std::abs(p[0] * D - q[0]) < 1e-9 && std::abs(p[1] * D - q[1]) < 1e-9 &&
          std::abs(p[2] * D - q[2]) < 1e-9)
        {
          shape.latticeNode[static_cast<std::size_t>(key)] = j;
        }
      }
      if (shape.latticeNode[static_cast<std::size_t>(key)] < 0)
      {
        shape.latticeNew[static_cast<std::size_t>(key)] = shape.newPointCount();
        shape.newPoints.push_back(x);
        std::vector<double> weights(static_cast<std::size_t>(n));
        shape.basis(x.data(), weights.data());
        shape.newWeights.insert(shape.newWeights.end(), weights.begin(), weights.end());
      }
    }
  }
  return shape;
}

std::vector<Point> cornersOf(const Corner* corners, int count)
{
  std::vector<Point> points;
  for (int v = 0; v < count; ++v)
  {
    points.push_back(corner(corners[v]));
  }
  return points;
}

std::vector<Point> hexahedron20Nodes()
{
  std::vector<Point> points = cornersOf(kCubeCorners, 8);
  for (const auto& edge : kHexEdges)
  {
    points.push_back(centre(kCubeCorners, edge));
  }
  return points;
}

std::vector<Point> wedgeWithEdges(bool vertical, bool quads)
{
  std::vector<Point> points = cornersOf(kWedgeCorners, 6);
  for (int e = 0; e < (vertical ? 9 : 6); ++e)
  {
    points.push_back(centre(kWedgeCorners, kWedgeEdges[e]));
  }
  if (quads)
  {
    for (const auto& quad : kWedgeQuads)
    {
      points.push_back(centre(kWedgeCorners, quad));
    }
  }
  return points;
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

/// Every shape the split reads, built once.
struct Shapes
{
  SplitShape hexahedron = makeShape("VTK_HEXAHEDRON", false, cornersOf(kCubeCorners, 8), tensorMonomials(1, 1, 1));
  SplitShape voxel = makeShape("VTK_VOXEL", false,
    { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 }, { 1, 1, 1 } },
    tensorMonomials(1, 1, 1));
  SplitShape hexahedron20 = makeShape("VTK_QUADRATIC_HEXAHEDRON", false, hexahedron20Nodes(), serendipity20());
  SplitShape wedge = makeShape("VTK_WEDGE", true, cornersOf(kWedgeCorners, 6), wedgeMonomials(1, 1));
  SplitShape wedge12 = makeShape("VTK_QUADRATIC_LINEAR_WEDGE", true, wedgeWithEdges(false, false), wedgeMonomials(2, 1));
  SplitShape wedge15 = makeShape("VTK_QUADRATIC_WEDGE", true, wedgeWithEdges(true, false), quadraticWedge15());
  SplitShape wedge18 = makeShape("VTK_BIQUADRATIC_QUADRATIC_WEDGE", true, wedgeWithEdges(true, true), wedgeMonomials(2, 2));
  SplitShape bezierWedge18 = makeShape("VTK_BEZIER_WEDGE", true, wedgeWithEdges(true, true), {}, 2, 2);
};

const Shapes& shapes()
{
  static const Shapes all;
  return all;
}

/// (p + 1)^3 == ids for some p >= 1, or 0.
int cubeOrder(long long ids)
{
  for (int p = 1; p <= 1 << 17; ++p)
  {
    const long long n = static_cast<long long>(p + 1) * (p + 1) * (p + 1);
    if (n >= ids)
    {
      return n == ids ? p : 0;
    }
  }
  return 0;
}

/// (p + 1)^2 (p + 2) / 2 == ids for some p >= 1 (VTK's Lagrange and Bezier wedges), or 0.
int wedgeOrder(long long ids)
{
  for (int p = 1; p <= 1 << 17; ++p)
  {
    const long long n = static_cast<long long>(p + 1) * (p + 1) * (p + 2) / 2;
    if (n >= ids)
    {
      return n == ids ? p : 0;
    }
  }
  return 0;
}
} // namespace

void SplitShape::basis(const double parametric[3], double* weights) const
{
  const Point x{ parametric[0], parametric[1], parametric[2] };
  if (bezier)
  {
    // A Bezier wedge: the triangle's Bernstein polynomial of the node's lattice point times the
    // axis's.
    for (int j = 0; j < nodes; ++j)
    {
      const Point& p = nodePoints[static_cast<std::size_t>(j)];
      const int a = static_cast<int>(std::lround(p[0] * bezierTriangle));
      const int b = static_cast<int>(std::lround(p[1] * bezierTriangle));
      const int c = bezierTriangle - a - b;
      const int k = static_cast<int>(std::lround(p[2] * bezierAxis));
      const double u = 1.0 - x[0] - x[1];
      weights[j] = binomial(bezierTriangle, a) * binomial(bezierTriangle - a, b) *
        std::pow(x[0], a) * std::pow(x[1], b) * std::pow(u, c) * binomial(bezierAxis, k) *
        std::pow(x[2], k) * std::pow(1.0 - x[2], bezierAxis - k);
    }
    return;
  }
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
}

bool isSplitType(int vtkType)
{
  switch (vtkType)
  {
    case kVtkVoxel:
    case kVtkHexahedron:
    case kVtkWedge:
    case kVtkPyramid:
    case kVtkQuadraticHexahedron:
    case kVtkQuadraticWedge:
    case kVtkQuadraticPyramid:
    case kVtkTriquadraticHexahedron:
    case kVtkQuadraticLinearWedge:
    case kVtkBiquadraticQuadraticWedge:
    case kVtkBiquadraticQuadraticHexahedron:
    case kVtkTriquadraticPyramid:
    case kVtkLagrangeHexahedron:
    case kVtkLagrangeWedge:
    case kVtkLagrangePyramid:
    case kVtkBezierHexahedron:
    case kVtkBezierWedge:
    case kVtkBezierPyramid:
      return true;
    default:
      return false;
  }
}

std::uint16_t splitShapeOf(int vtkType, long long ids, const SplitShape*& shape)
{
  const Shapes& all = shapes();
  auto fixed = [&](const SplitShape& s) -> std::uint16_t {
    shape = &s;
    return ids == s.nodes ? 0 : kMalformed;
  };
  switch (vtkType)
  {
    case kVtkVoxel:
      return fixed(all.voxel);
    case kVtkHexahedron:
      return fixed(all.hexahedron);
    case kVtkQuadraticHexahedron:
      return fixed(all.hexahedron20);
    case kVtkWedge:
      return fixed(all.wedge);
    case kVtkQuadraticLinearWedge:
      return fixed(all.wedge12);
    case kVtkQuadraticWedge:
      return fixed(all.wedge15);
    case kVtkBiquadraticQuadraticWedge:
      return fixed(all.wedge18);
    case kVtkTriquadraticHexahedron:
      // Triquadratic: total degree 6.
      return ids == 27 ? kOrderTooHigh : kMalformed;
    case kVtkBiquadraticQuadraticHexahedron:
      // Biquadratic in (r, s) with quadratic terms in t: total degree above 4.
      return ids == 24 ? kOrderTooHigh : kMalformed;
    case kVtkLagrangeHexahedron:
    case kVtkBezierHexahedron:
    {
      // VTK reads the order of these from the id count (a cube number); order p is of total
      // degree 3p: order 1 only, as the trilinear hexahedron.
      const int order = cubeOrder(ids);
      if (order == 0)
      {
        return kMalformed;
      }
      shape = &all.hexahedron;
      return order == 1 ? 0 : kOrderTooHigh;
    }
    case kVtkLagrangeWedge:
    case kVtkBezierWedge:
    {
      // Order p is of total degree 2p: orders 1 and 2 (VTK's 21-node wedge is not read).
      const int order = wedgeOrder(ids);
      if (order == 0)
      {
        return kMalformed;
      }
      if (order > 2)
      {
        return kOrderTooHigh;
      }
      shape = order == 1 ? &all.wedge : vtkType == kVtkBezierWedge ? &all.bezierWedge18 : &all.wedge18;
      return 0;
    }
    default:
      return kUnsupported; // pyramids: their rational (VTK_PYRAMID: degenerate) maps are not read
  }
}

struct SplitMesh::Arrays
{
  std::vector<double> Points;
  std::vector<double> Values;
  std::vector<double> Weights;
  std::vector<std::uint8_t> Types;
  std::vector<NodeId> Offsets;
  std::vector<NodeId> Connectivity;
  std::vector<NodeId> SourceCells;
  std::vector<NodeId> SourceOffsets;
  std::vector<std::uint16_t> SourceStatus;
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
      const std::uint16_t unreadable = cellLayout(type, -1, layout) == kUnsupported ? kUnsupported
        : !readable                                                                ? kMalformed
                                                    : cellLayout(type, end - begin, layout);
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
      out.SourceStatus[c] = kMalformed;
      continue;
    }
    const SplitShape* shape = nullptr;
    std::uint16_t status = splitShapeOf(type, end - begin, shape);
    if (status == 0)
    {
      status = checkNodeIds(input, input.connectivity + begin, shape->nodes,
        type == kVtkBezierHexahedron || type == kVtkBezierWedge);
    }
    if (status != 0)
    {
      out.SourceStatus[c] = status;
      continue;
    }
    out.Shape[c] = shape;
    out.IdsAt[c] = copiedIds;
    copiedIds += shape->nodes;
    pieces += shape->pieces;
    newPoints += shape->newPointCount();
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
  if (input.rationalWeights)
  {
    // Pieces are Lagrange cells: their new points' weights are never read.
    out.Weights.assign(totalPoints, 1.0);
    std::copy(input.rationalWeights, input.rationalWeights + input.numberOfPoints, out.Weights.begin());
  }
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
        static_cast<std::uint8_t>(shape.degree == 2 ? kVtkQuadraticTetra : kVtkLagrangeTetrahedron);
      for (int k = 0; k < shape.pieces; ++k, ++piece)
      {
        out.Types[static_cast<std::size_t>(piece)] = pieceType;
        out.SourceCells[static_cast<std::size_t>(piece)] = cell;
        out.Offsets[static_cast<std::size_t>(piece)] = at;
        for (int n = 0; n < shape.pieceNodes; ++n)
        {
          const auto lattice = static_cast<std::size_t>(shape.pieceLattice[static_cast<std::size_t>(k * shape.pieceNodes + n)]);
          const int node = shape.latticeNode[lattice];
          out.Connectivity[static_cast<std::size_t>(at++)] =
            node >= 0 ? ids[node] : out.FirstNew[c] + shape.latticeNew[lattice];
        }
      }
      // The new points: the cell's map and field there.
      for (int p = 0; p < shape.newPointCount(); ++p)
      {
        const double* w = shape.newWeights.data() + static_cast<std::size_t>(p) * shape.nodes;
        const auto point = static_cast<std::size_t>(out.FirstNew[c] + p);
        double x = 0.0, y = 0.0, z = 0.0, value = 0.0;
        for (int j = 0; j < shape.nodes; ++j)
        {
          const double* q = input.points + 3 * ids[j];
          x += w[j] * q[0];
          y += w[j] * q[1];
          z += w[j] * q[2];
          value += w[j] * input.values[ids[j]];
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
  View_.rationalWeights = input.rationalWeights ? out.Weights.data() : nullptr;
  View_.pointRounding = input.pointRounding;
  View_.sourceCells = out.SourceCells.data();
  View_.sourceOffsets = out.SourceOffsets.data();
  View_.sourceStatus = out.SourceStatus.data();
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
    for (int p = 0; p < shape->newPointCount(); ++p)
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
  return sizeof(double) * (a.Points.capacity() + a.Values.capacity() + a.Weights.capacity()) +
    a.Types.capacity() + a.SourceStatus.capacity() * sizeof(std::uint16_t) +
    sizeof(NodeId) *
    (a.Offsets.capacity() + a.Connectivity.capacity() + a.SourceCells.capacity() +
      a.SourceOffsets.capacity() + a.FirstNew.capacity() + a.IdsAt.capacity() + a.Ids.capacity()) +
    sizeof(void*) * a.Shape.capacity();
}

} // namespace tetdsr
