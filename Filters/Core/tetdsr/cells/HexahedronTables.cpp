// The node tables of the cells read as tensor-product forms (HexahedronCell.h's
// HexahedronNodes): every hexahedron type (a lattice permutation, or the 20- and 24-node shapes'
// bases at the lattice points), the wedges as collapsed cubes (their shapes' bases at the images
// of the lattice points) and VTK_PYRAMID; and toTensorForm, which applies them.
#include "tetdsr/cells/HexahedronCell.h"

#include "tetdsr/cells/SplitCells.h"

#include <algorithm>
#include <cmath>

namespace tetdsr
{

namespace
{
using Point = std::array<double, 3>;

/// The table finished: its roundingGrowth (the weights' largest absolute row sum, 1 for a lattice
/// permutation, times the Lagrange to Bernstein conversion's infinity norm per axis, cubed; 1 for
/// Bezier tables) and its frame's nodes (none for pyramids).
HexahedronNodes finished(HexahedronNodes table)
{
  if (table.collapsedAxis != 2)
  {
    const double corners[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    for (int n = 0; n < table.nodes; ++n)
    {
      double r[3];
      parametricPoint(table, table.nodePoints[static_cast<std::size_t>(n)].data(), r);
      for (int k = 0; k < 4; ++k)
      {
        if (r[0] == corners[k][0] && r[1] == corners[k][1] && r[2] == corners[k][2])
        {
          table.frameNodes[k] = n;
        }
      }
    }
  }
  double rows = 1.0;
  if (!table.weights.empty())
  {
    rows = 0.0;
    for (std::size_t k = 0; k < table.weights.size(); k += static_cast<std::size_t>(table.nodes))
    {
      double sum = 0.0;
      for (int n = 0; n < table.nodes; ++n)
      {
        sum += std::abs(table.weights[k + static_cast<std::size_t>(n)]);
      }
      rows = std::max(rows, sum);
    }
  }
  double conversion = 1.0;
  if (!table.bezier)
  {
    forHexahedronOrder(table.order, [&](auto order) {
      constexpr int P = decltype(order)::value;
      const auto& matrix = tensor::LagrangeToBernstein<P>::get().matrix;
      double norm = 0.0;
      for (int m = 0; m <= P; ++m)
      {
        double sum = 0.0;
        for (int i = 0; i <= P; ++i)
        {
          sum += std::abs(matrix[i][m]);
        }
        norm = std::max(norm, sum);
      }
      conversion = norm * norm * norm;
    });
  }
  table.roundingGrowth = rows * conversion;
  return table;
}

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
  return finished(std::move(table));
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
  return finished(std::move(table));
}

/// A wedge type's table: its shape functions (SplitShape::basis) at the lattice points' images
/// r = u (1 - v), s = v (nodal values of the composite, a polynomial of degree `order` per axis).
HexahedronNodes wedgeTable(int vtkType, const SplitShape& shape)
{
  HexahedronNodes table;
  table.name = cellTypeOf(vtkType)->name; // (a Lagrange wedge of order 1 or 2 has VTK_WEDGE's or the 18-node shape)
  table.order = shape.order;
  table.nodes = shape.nodes;
  table.collapsedAxis = 1;
  table.collapsedPower = 1;
  table.mirrored = cellTypeOf(vtkType)->mirrored;
  table.parametric = HexahedronNodes::Parametric::Wedge;
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
  return finished(std::move(table));
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

/// A pyramid's table before its weights: order `order` per axis in the cube whose face w = 1 is
/// collapsed onto the apex (det J = (1 - w)^2 times a form of the cell's sign), its weights zero.
HexahedronNodes pyramidShell(const char* name, int order, int nodes)
{
  HexahedronNodes table;
  table.name = name;
  table.order = order;
  table.nodes = nodes;
  table.collapsedAxis = 2;
  table.collapsedPower = 2;
  table.weights.assign(static_cast<std::size_t>(tensor::count(order) * nodes), 0.0);
  return table;
}

/// VTK_PYRAMID's table: the base's four nodes at t = 0 (VTK_HEXAHEDRON's order), the apex at
/// the four corners of t = 1.
HexahedronNodes pyramidTable()
{
  HexahedronNodes table = pyramidShell("VTK_PYRAMID", 1, 5);
  const int baseNode[2][2] = { { 0, 3 }, { 1, 2 } }; // [i][j]
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i)
    {
      table.weights[static_cast<std::size_t>(tensor::index(1, i, j, 0) * 5 + baseNode[i][j])] = 1.0;
      table.weights[static_cast<std::size_t>(tensor::index(1, i, j, 1) * 5 + 4)] = 1.0;
    }
  table.nodePoints = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0.5, 0.5, 1 } };
  return finished(std::move(table));
}

/// VTK_QUADRATIC_PYRAMID's table. Its shape functions are of degree 2 per axis in VTK's
/// parametric (r, s, t), the cube whose face t = 1 is collapsed onto the apex (measured against
/// vtkQuadraticPyramid's interpolation: TestSplitCellsNodeOrder), so they are given by their
/// values at the 27 lattice points: a node's own where the cell has one (the apex on all of
/// t = 1), else those of the cell's faces and centre: the 8-node quadrilateral's at the base's
/// centre (1/2 each mid-side node, -1/4 each corner), the 6-node triangle's at the middle of a
/// side face (1/2 each slanted mid-edge node, 1/4 the base's mid-edge node, -1/8 each base
/// corner), and at the centre 1/4 each mid-edge node and -1/4 each base corner.
HexahedronNodes quadraticPyramidTable()
{
  HexahedronNodes table = pyramidShell("VTK_QUADRATIC_PYRAMID", 2, 13);
  // The base's nodes at lattice (i, j) (-1: its centre), and the slanted edges' mid-edge nodes
  // over its corners.
  const int base[3][3] = { { 0, 8, 3 }, { 5, -1, 7 }, { 1, 6, 2 } };
  auto slanted = [&](int i, int j) { return 9 + base[i][j]; }; // (over corner node c: 9 + c)
  for (int k = 0; k <= 2; ++k)
    for (int j = 0; j <= 2; ++j)
      for (int i = 0; i <= 2; ++i)
      {
        double* w = table.weights.data() + static_cast<std::size_t>(tensor::index(2, i, j, k) * 13);
        const bool corner = i != 1 && j != 1;
        if (k == 2)
        {
          w[4] = 1.0;
        }
        else if (k == 0 && base[i][j] >= 0)
        {
          w[base[i][j]] = 1.0;
        }
        else if (corner)
        {
          w[slanted(i, j)] = 1.0;
        }
        else if (i == 1 && j == 1)
        {
          for (int c = 0; c < 4; ++c)
          {
            w[c] = -0.25;
            w[5 + c] = k == 0 ? 0.5 : 0.25;
            w[9 + c] = k == 0 ? 0.0 : 0.25;
          }
        }
        else
        {
          // The middle of a side face's line through its mid-edge nodes: the face's two base
          // corners, its base mid-edge node and the slanted edges over the corners.
          const int a[2] = { i == 1 ? 0 : i, j == 1 ? 0 : j }, b[2] = { i == 1 ? 2 : i, j == 1 ? 2 : j };
          w[base[a[0]][a[1]]] = w[base[b[0]][b[1]]] = -0.125;
          w[base[i][j]] = 0.25;
          w[slanted(a[0], a[1])] = w[slanted(b[0], b[1])] = 0.5;
        }
      }
  table.nodePoints = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0.5, 0.5, 1 }, { 0.5, 0, 0 },
    { 1, 0.5, 0 }, { 0.5, 1, 0 }, { 0, 0.5, 0 }, { 0, 0, 0.5 }, { 1, 0, 0.5 }, { 1, 1, 0.5 }, { 0, 1, 0.5 } };
  return finished(std::move(table));
}

/// VTK_TRIQUADRATIC_PYRAMID's shape functions (Browning's rational pyramid of 19 nodes, as VTK
/// 9.2 has it) at a point of the cube collapsed onto it: VTK's parametric point is
/// (1/2 + U z / 2, 1/2 + V z / 2, 1 - z / 2) with U = 2u - 1, V = 2v - 1, z = 1 - w (its base at
/// w = 0, its apex at w = 1). Composed with that map, the rational functions are polynomials of
/// degree 2 in u and v and 3 in w (derived from their formulas; TestSplitCellsNodeOrder checks
/// them against vtkTriQuadraticPyramid's interpolation). Per corner or edge, (a, b) are the signs
/// of its U and V (0 along the edge's own direction).
void triquadraticPyramidBasis(const double x[3], double* weights)
{
  const double U = 2.0 * x[0] - 1.0, V = 2.0 * x[1] - 1.0, z = 1.0 - x[2];
  const double UU = (U * U - 1.0), VV = (V * V - 1.0); // (vanish on the base's sides)
  const double corner[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
  for (int c = 0; c < 4; ++c)
  {
    const double a = corner[c][0], b = corner[c][1];
    const double side = (U + a) * (V + b), slant = b * U + a * V;
    // The base's corners, and the mid-edge nodes of the slanted edges over them.
    weights[c] = z * side * (2.0 * U * V * (3.0 * z * z - 3.0 * z + 1.0) - slant * (3.0 * z - 2.0) * (z - 1.0)) / 8.0;
    weights[9 + c] = -z * (z - 1.0) * side * (2.0 * U * V * (3.0 * z - 1.0) - slant * (3.0 * z - 2.0)) / 2.0;
  }
  // The base's mid-edge nodes (edges v = 0, u = 1, v = 1, u = 0) and the side faces' centres.
  const double edge[4][2] = { { 0, -1 }, { 1, 0 }, { 0, 1 }, { -1, 0 } };
  for (int e = 0; e < 4; ++e)
  {
    const double a = edge[e][0], b = edge[e][1];
    const double across = a == 0.0 ? UU * V * (V + b) : VV * U * (U + a);
    weights[5 + e] = -across * z * z * (3.0 * z - 2.0) / 2.0;
    weights[14 + e] = 27.0 * across * z * z * (z - 1.0) / 8.0;
  }
  weights[4] = (z - 1.0) *
    (18.0 * U * U * V * V * z * z - 8.0 * U * U * V * V * z - 9.0 * (U * U + V * V) * z * z +
      8.0 * (U * U + V * V) * z + 16.0 * z - 12.0) / 12.0;
  weights[13] = z * UU * VV * (4.0 * z - 3.0);
  weights[18] = -16.0 * z * (z - 1.0) * UU * VV / 3.0;
}

/// VTK_TRIQUADRATIC_PYRAMID's table: triquadraticPyramidBasis at the lattice points of order 3.
HexahedronNodes triquadraticPyramidTable()
{
  HexahedronNodes table = pyramidShell("VTK_TRIQUADRATIC_PYRAMID", 3, 19);
  table.parametric = HexahedronNodes::Parametric::CentredPyramid;
  for (int k = 0; k <= 3; ++k)
    for (int j = 0; j <= 3; ++j)
      for (int i = 0; i <= 3; ++i)
      {
        const double x[3] = { i / 3.0, j / 3.0, k / 3.0 };
        triquadraticPyramidBasis(x, table.weights.data() + static_cast<std::size_t>(tensor::index(3, i, j, k) * 19));
      }
  const double third = 1.0 / 3.0;
  table.nodePoints = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0.5, 0.5, 1 }, { 0.5, 0, 0 },
    { 1, 0.5, 0 }, { 0.5, 1, 0 }, { 0, 0.5, 0 }, { 0, 0, 0.5 }, { 1, 0, 0.5 }, { 1, 1, 0.5 }, { 0, 1, 0.5 },
    { 0.5, 0.5, 0 }, { 0.5, 0, third }, { 1, 0.5, third }, { 0.5, 1, third }, { 0, 0.5, third },
    { 0.5, 0.5, 0.25 } };
  return finished(std::move(table));
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

} // namespace


std::uint16_t hexahedronNodesOf(int vtkType, long long ids, const HexahedronNodes*& table)
{
  const CellType* type = cellTypeOf(vtkType);
  int order = 0;
  if (type && type->shape == CellShape::Tetrahedron)
  {
    return kUnsupported;
  }
  if (const std::uint16_t status = readOrder(type, ids, order))
  {
    return status;
  }
  static const HexahedronNodes hexahedron = latticeTable("VTK_HEXAHEDRON", 1, false, hexahedronNodePoints(1));
  static const HexahedronNodes voxel = latticeTable("VTK_VOXEL", 1, false,
    { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 0, 0, 1 }, { 1, 0, 1 }, { 0, 1, 1 }, { 1, 1, 1 } });
  static const HexahedronNodes triquadratic =
    latticeTable("VTK_TRIQUADRATIC_HEXAHEDRON", 2, false, hexahedronNodePoints(2));
  switch (vtkType)
  {
    case kVtkHexahedron:
      table = &hexahedron;
      return 0;
    case kVtkVoxel:
      table = &voxel;
      return 0;
    case kVtkQuadraticHexahedron:
    case kVtkBiquadraticQuadraticHexahedron:
      table = &splitShapeTable(vtkType, static_cast<int>(ids));
      return 0;
    case kVtkTriquadraticHexahedron:
      table = &triquadratic;
      return 0;
    case kVtkLagrangeHexahedron:
    case kVtkBezierHexahedron:
    {
      using Builder = const HexahedronNodes& (*)();
      static constexpr Builder kBuilders[2][kMaxHexahedronOrder] = {
        { higherOrderTable<false, 1>, higherOrderTable<false, 2>, higherOrderTable<false, 3>, higherOrderTable<false, 4> },
        { higherOrderTable<true, 1>, higherOrderTable<true, 2>, higherOrderTable<true, 3>, higherOrderTable<true, 4> }
      };
      table = &kBuilders[type->bezier][order - 1]();
      return 0;
    }
    case kVtkPyramid:
    {
      static const HexahedronNodes pyramid = pyramidTable();
      table = &pyramid;
      return 0;
    }
    case kVtkQuadraticPyramid:
    {
      static const HexahedronNodes pyramid = quadraticPyramidTable();
      table = &pyramid;
      return 0;
    }
    case kVtkTriquadraticPyramid:
    {
      static const HexahedronNodes pyramid = triquadraticPyramidTable();
      table = &pyramid;
      return 0;
    }
    default:
    {
      // The wedges (kCellTypes' rows of that shape).
      std::uint16_t status = 0;
      table = wedgeTableOf(vtkType, ids, status);
      return status;
    }
  }
}

std::uint16_t hexahedronLayout(const CellType& type, long long ids, CellLayout& layout)
{
  const HexahedronNodes* table = nullptr;
  const std::uint16_t status = hexahedronNodesOf(type.vtkType, ids, table);
  if (status == 0)
  {
    layout.order = table->order;
    layout.bezier = type.bezier; // (its ids' rational weights are checked; table->bezier: its form's)
    layout.nodes = table->nodes;
    layout.hexahedron = table;
    layout.wedge = type.shape == CellShape::Wedge;
  }
  return status;
}

void parametricPoint(const HexahedronNodes& table, const double cube[3], double parametric[3])
{
  switch (table.parametric)
  {
    case HexahedronNodes::Parametric::Cube:
      std::copy(cube, cube + 3, parametric);
      return;
    case HexahedronNodes::Parametric::Wedge:
      parametric[0] = cube[0] * (1.0 - cube[1]);
      parametric[1] = cube[1];
      parametric[2] = cube[2];
      return;
    case HexahedronNodes::Parametric::CentredPyramid:
      parametric[0] = 0.5 + (cube[0] - 0.5) * (1.0 - cube[2]);
      parametric[1] = 0.5 + (cube[1] - 0.5) * (1.0 - cube[2]);
      parametric[2] = 0.5 * (1.0 + cube[2]);
      return;
  }
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

} // namespace tetdsr
