// The node tables of the cells read as tensor-product forms (HexahedronCell.h's
// HexahedronNodes): every hexahedron type (a lattice permutation, or the 20- and 24-node shapes'
// bases at the lattice points), the wedges as collapsed cubes (their shapes' bases at the images
// of the lattice points) and VTK_PYRAMID; and toTensorForm, which applies them.
#include "tetdsr/HexahedronCell.h"

#include "tetdsr/SplitCells.h"

#include <algorithm>
#include <cmath>

namespace tetdsr
{

namespace
{
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

} // namespace


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

} // namespace tetdsr
