// VTK is the authority for the node order, parametric coordinates and shape functions of its
// hexahedra and wedges. For every (type, id count) the core's split reads (tetdsr::splitShapeOf
// returns 0), against VTK's own cell of that type and count:
// 1. SplitShape::nodePoints equal the cell's GetParametricCoords (to 1e-15);
// 2. SplitShape::basis equals the cell's InterpolateFunctions at 200 random parametric points
//    inside the cell (unit cube, or unit triangle x [0, 1]) (to 1e-12);
// 3. (wedges) the pieces tile the parametric cell: each piece's vertices lie in the cell with a positive
//    volume, the volumes sum to the cell's (1 or 1/2), and 1000 random points inside the cell lie
//    in exactly one piece (away from the pieces' faces);
// 4. (wedges) each piece node lies where VTK's (and the core's) tetrahedron order puts it: at the
//    barycentric point tetNodePoint(D, n) of the piece's vertices; a Lagrange piece's new node's
//    weights are VTK's shape functions there, and a Bezier piece (order above 4), evaluated as a
//    Bernstein tetrahedron, equals VTK's interpolation of random node values at random points
//    (to 1e-12).
// The cell's nodes sit at their parametric coordinates, so its map is the identity: a piece node's
// position is its weights applied to nodePoints (the cell's own node when it is one).
// And for every (type, id count) the core reads as a tensor-product cell (tetdsr::hexahedronNodesOf:
// every hexahedron, wedge and pyramid), the tensor form toTensorForm makes of random node
// values, evaluated at the image of a random parametric point (a wedge's (r, s, t) is the
// collapsed cube's (r / (1 - s), s, t)), equals VTK's InterpolateFunctions applied to them there,
// and its nodes' points are VTK's parametric coordinates (tetdsr::parametricPoint).
#include "vtkCell.h"
#include "vtkCellType.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkUnstructuredGrid.h"

#include "tetdsr/HexahedronCell.h"
#include "tetdsr/HigherOrderTet.h"
#include "tetdsr/SplitCells.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>
#include <vector>

namespace
{
using Point = std::array<double, 3>;

/// VTK's cell of a type with `nodes` points (a one-cell grid's, so that Lagrange and Bezier
/// cells take their order from the count, as VTK reads files), nodes at the origin.
vtkCell* vtkCellOf(vtkUnstructuredGrid* grid, int type, int nodes)
{
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(nodes);
  std::vector<vtkIdType> ids(static_cast<std::size_t>(nodes));
  for (int n = 0; n < nodes; ++n)
  {
    points->SetPoint(n, 0.0, 0.0, 0.0);
    ids[static_cast<std::size_t>(n)] = n;
  }
  grid->SetPoints(points);
  grid->Allocate(1);
  grid->InsertNextCell(type, nodes, ids.data());
  return grid->GetCell(0);
}

/// 6 x the signed volume of the tetrahedron (a, b, c, d).
double sixVolume(const Point& a, const Point& b, const Point& c, const Point& d)
{
  const Point u{ b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const Point v{ c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  const Point w{ d[0] - a[0], d[1] - a[1], d[2] - a[2] };
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
    u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/// Barycentric coordinates of x in the tetrahedron (a, b, c, d) (Cramer's rule).
std::array<double, 4> barycentric(const std::array<Point, 4>& v, const Point& x)
{
  const double whole = sixVolume(v[0], v[1], v[2], v[3]);
  return { sixVolume(x, v[1], v[2], v[3]) / whole, sixVolume(v[0], x, v[2], v[3]) / whole,
    sixVolume(v[0], v[1], x, v[3]) / whole, sixVolume(v[0], v[1], v[2], x) / whole };
}

bool insideCell(const Point& x, bool wedge, double tolerance)
{
  for (const double c : x)
  {
    if (c < -tolerance || c > 1.0 + tolerance)
    {
      return false;
    }
  }
  return !wedge || x[0] + x[1] <= 1.0 + tolerance;
}

Point randomPoint(bool wedge, std::mt19937& random)
{
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Point x{ unit(random), unit(random), unit(random) };
  while (wedge && x[0] + x[1] > 1.0)
  {
    x[0] = unit(random);
    x[1] = unit(random);
  }
  return x;
}

/// The Bernstein tetrahedron of order D with coefficients c (VTK's node order) at L.
double bernstein(int D, const std::vector<double>& c, const std::array<double, 4>& L)
{
  double sum = 0.0;
  for (std::size_t n = 0; n < c.size(); ++n)
  {
    double node[4];
    tetdsr::tetNodePoint(D, static_cast<int>(n), node);
    double term = std::tgamma(D + 1.0);
    for (int k = 0; k < 4; ++k)
    {
      const int alpha = static_cast<int>(std::lround(node[k] * D));
      term *= std::pow(L[static_cast<std::size_t>(k)], alpha) / std::tgamma(alpha + 1.0);
    }
    sum += c[n] * term;
  }
  return sum;
}

struct Worst
{
  double nodes = 0.0, basis = 0.0, lattice = 0.0, pieces = 0.0;
};

/// Checks one shape; returns the number of failed expectations.
int checkShape(int type, int ids, const tetdsr::SplitShape& shape, std::mt19937& random, Worst& worst)
{
  int failures = 0;
  const std::string label = std::string(shape.name) + " (" + std::to_string(ids) + " ids)";
  vtkNew<vtkUnstructuredGrid> grid;
  vtkCell* cell = vtkCellOf(grid, type, ids);
  if (shape.nodes != ids || static_cast<int>(shape.nodePoints.size()) != ids)
  {
    std::cerr << label << ": expected " << ids << " nodes, got " << shape.nodes << "\n";
    return 1;
  }

  // 1. Node positions.
  const double* pcoords = cell->GetParametricCoords();
  double nodeError = 0.0;
  for (int n = 0; n < ids; ++n)
  {
    for (int a = 0; a < 3; ++a)
    {
      nodeError = std::max(nodeError,
        std::abs(shape.nodePoints[static_cast<std::size_t>(n)][static_cast<std::size_t>(a)] - pcoords[3 * n + a]));
    }
    if (nodeError > 1e-15)
    {
      std::cerr << label << " node " << n << ": expected parametric (" << pcoords[3 * n] << ", "
                << pcoords[3 * n + 1] << ", " << pcoords[3 * n + 2] << ") (VTK), got ("
                << shape.nodePoints[static_cast<std::size_t>(n)][0] << ", "
                << shape.nodePoints[static_cast<std::size_t>(n)][1] << ", "
                << shape.nodePoints[static_cast<std::size_t>(n)][2] << ") (SplitShape::nodePoints)\n";
      ++failures;
      break;
    }
  }
  worst.nodes = std::max(worst.nodes, nodeError);

  // 2. Shape functions.
  std::vector<double> ours(static_cast<std::size_t>(ids)), theirs(static_cast<std::size_t>(ids));
  double basisError = 0.0;
  for (int sample = 0; sample < 200; ++sample)
  {
    Point x = randomPoint(shape.wedge, random);
    shape.basis(x.data(), ours.data());
    cell->InterpolateFunctions(x.data(), theirs.data());
    double error = 0.0;
    for (int n = 0; n < ids; ++n)
    {
      error = std::max(error, std::abs(ours[static_cast<std::size_t>(n)] - theirs[static_cast<std::size_t>(n)]));
    }
    basisError = std::max(basisError, error);
    if (!(error <= 1e-12))
    {
      std::cerr << label << " at (" << x[0] << ", " << x[1] << ", " << x[2] << "): expected VTK's "
                << "InterpolateFunctions, got SplitShape::basis off by " << error << "\n";
      ++failures;
      break;
    }
  }
  worst.basis = std::max(worst.basis, basisError);
  if (!shape.wedge)
  {
    // Hexahedra are not split (their tensor forms are checked below, in the test's body).
    if (shape.pieces != 0)
    {
      std::cerr << label << ": expected no pieces for a hexahedron, got " << shape.pieces << "\n";
      ++failures;
    }
    std::cout << label << ": " << ids << " nodes, max node difference " << nodeError
              << ", max basis difference " << basisError << "\n";
    return failures;
  }

  // 3 and 4. The pieces: a node's position (the identity map), vertices, volumes, lattice.
  auto position = [&](int node) {
    if (node >= 0)
    {
      return shape.nodePoints[static_cast<std::size_t>(node)];
    }
    const double* w = shape.newWeights.data() + static_cast<std::size_t>(-1 - node) * static_cast<std::size_t>(ids);
    Point x{ 0.0, 0.0, 0.0 };
    for (int j = 0; j < ids; ++j)
    {
      for (int a = 0; a < 3; ++a)
      {
        x[static_cast<std::size_t>(a)] += w[j] * shape.nodePoints[static_cast<std::size_t>(j)][static_cast<std::size_t>(a)];
      }
    }
    return x;
  };
  const int D = shape.degree;
  std::vector<std::array<Point, 4>> vertices(static_cast<std::size_t>(shape.pieces));
  double volume = 0.0, latticeError = 0.0;
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<double> nodeValues(static_cast<std::size_t>(ids));
  for (double& v : nodeValues)
  {
    v = value(random);
  }
  for (int k = 0; k < shape.pieces; ++k)
  {
    const int* nodes = shape.pieceNode.data() + static_cast<std::size_t>(k) * static_cast<std::size_t>(shape.pieceNodes);
    auto& v = vertices[static_cast<std::size_t>(k)];
    for (int i = 0; i < 4; ++i)
    {
      v[static_cast<std::size_t>(i)] = position(nodes[i]);
      if (!insideCell(v[static_cast<std::size_t>(i)], shape.wedge, 1e-15))
      {
        std::cerr << label << " piece " << k << ": expected its vertex " << i << " inside the cell\n";
        ++failures;
      }
    }
    const double six = sixVolume(v[0], v[1], v[2], v[3]);
    if (!(six > 0.0))
    {
      std::cerr << label << " piece " << k << ": expected a positive volume, got " << six / 6 << "\n";
      ++failures;
    }
    volume += six / 6.0;
    std::vector<double> coefficients(static_cast<std::size_t>(shape.pieceNodes));
    for (int n = 0; n < shape.pieceNodes; ++n)
    {
      double L[4];
      tetdsr::tetNodePoint(D, n, L);
      Point expected{ 0.0, 0.0, 0.0 };
      for (int i = 0; i < 4; ++i)
      {
        for (int a = 0; a < 3; ++a)
        {
          expected[static_cast<std::size_t>(a)] += L[i] * v[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)];
        }
      }
      const Point got = position(nodes[n]);
      double error = 0.0;
      for (int a = 0; a < 3; ++a)
      {
        error = std::max(error, std::abs(got[static_cast<std::size_t>(a)] - expected[static_cast<std::size_t>(a)]));
      }
      latticeError = std::max(latticeError, error);
      // A Bezier piece's nodes are made by conversion weights (row sums up to
      // SplitShape::kMaxCoefficientWeight): their rounding reaches 3.7e-12 at order 12.
      if (!(error <= (shape.bezierPieces ? 1e-11 : 1e-13)))
      {
        std::cerr << label << " piece " << k << " node " << n << ": expected at (" << expected[0] << ", "
                  << expected[1] << ", " << expected[2] << ") (tetNodePoint of the piece's vertices), got ("
                  << got[0] << ", " << got[1] << ", " << got[2] << ")\n";
        ++failures;
      }
      // The node's value from random node values: a Lagrange piece's is VTK's interpolation at
      // the node; a Bezier piece's are Bernstein coefficients, checked below.
      const double* w = nodes[n] >= 0 ? nullptr
                                      : shape.newWeights.data() + static_cast<std::size_t>(-1 - nodes[n]) * static_cast<std::size_t>(ids);
      double c = 0.0;
      for (int j = 0; j < ids; ++j)
      {
        c += (w ? w[j] : (j == nodes[n] ? 1.0 : 0.0)) * nodeValues[static_cast<std::size_t>(j)];
      }
      coefficients[static_cast<std::size_t>(n)] = c;
      if (!shape.bezierPieces)
      {
        cell->InterpolateFunctions(expected.data(), theirs.data());
        double vtkValue = 0.0;
        for (int j = 0; j < ids; ++j)
        {
          vtkValue += theirs[static_cast<std::size_t>(j)] * nodeValues[static_cast<std::size_t>(j)];
        }
        worst.basis = std::max(worst.basis, std::abs(c - vtkValue));
        if (!(std::abs(c - vtkValue) <= 1e-12))
        {
          std::cerr << label << " piece " << k << " node " << n << ": expected the value " << vtkValue
                    << " (VTK's interpolation there), got " << c << " (SplitShape::newWeights)\n";
          ++failures;
        }
      }
    }
    if (shape.bezierPieces)
    {
      for (int sample = 0; sample < 20; ++sample)
      {
        std::array<double, 4> L{};
        double sum = 0.0;
        for (double& l : L)
        {
          l = -std::log(std::uniform_real_distribution<double>(1e-12, 1.0)(random));
          sum += l;
        }
        Point x{ 0.0, 0.0, 0.0 };
        for (int i = 0; i < 4; ++i)
        {
          L[static_cast<std::size_t>(i)] /= sum;
          for (int a = 0; a < 3; ++a)
          {
            x[static_cast<std::size_t>(a)] += L[static_cast<std::size_t>(i)] * v[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)];
          }
        }
        cell->InterpolateFunctions(x.data(), theirs.data());
        double vtkValue = 0.0;
        for (int j = 0; j < ids; ++j)
        {
          vtkValue += theirs[static_cast<std::size_t>(j)] * nodeValues[static_cast<std::size_t>(j)];
        }
        const double got = bernstein(D, coefficients, L);
        worst.basis = std::max(worst.basis, std::abs(got - vtkValue));
        if (!(std::abs(got - vtkValue) <= 1e-12))
        {
          std::cerr << label << " Bezier piece " << k << ": expected " << vtkValue << " (VTK's "
                    << "interpolation), got " << got << " (the piece's Bernstein form)\n";
          ++failures;
          break;
        }
      }
    }
  }
  worst.lattice = std::max(worst.lattice, latticeError);
  const double cellVolume = shape.wedge ? 0.5 : 1.0;
  worst.pieces = std::max(worst.pieces, std::abs(volume - cellVolume));
  if (!(std::abs(volume - cellVolume) <= 1e-14))
  {
    std::cerr << label << ": expected the pieces' volumes to sum to " << cellVolume << ", got " << volume << "\n";
    ++failures;
  }
  int uncovered = 0, overlapped = 0;
  for (int sample = 0; sample < 1000; ++sample)
  {
    const Point x = randomPoint(shape.wedge, random);
    int in = 0, clearlyIn = 0;
    for (const auto& v : vertices)
    {
      const auto L = barycentric(v, x);
      in += *std::min_element(L.begin(), L.end()) > -1e-12;
      clearlyIn += *std::min_element(L.begin(), L.end()) > 1e-9;
    }
    uncovered += in == 0;
    overlapped += clearlyIn > 1;
  }
  if (uncovered || overlapped)
  {
    std::cerr << label << ": expected the pieces to tile the cell, got " << uncovered
              << " of 1000 random points in no piece and " << overlapped << " in two\n";
    ++failures;
  }
  std::cout << label << ": " << ids << " nodes, degree " << D << ", " << shape.pieces << " pieces ("
            << (shape.bezierPieces ? "Bezier" : "Lagrange") << "), " << shape.newPointCount
            << " new points; max node difference " << nodeError << ", max basis difference "
            << basisError << ", max lattice difference " << latticeError << ", volume "
            << volume << "\n";
  return failures;
}

/// The tensor form of a type's cells against VTK's interpolation (see the header); failures.
int checkTensorForm(int type, int ids, const tetdsr::HexahedronNodes& table, std::mt19937& random, double& worst)
{
  vtkNew<vtkUnstructuredGrid> grid;
  vtkCell* cell = vtkCellOf(grid, type, ids);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> values(static_cast<std::size_t>(ids));
  for (double& v : values)
  {
    v = unit(random);
  }
  double form[tetdsr::kMaxCellNodes];
  std::copy(values.begin(), values.end(), form);
  tetdsr::toTensorForm(table, form);
  const bool wedge = table.collapsedAxis == 1;
  std::vector<double> weights(static_cast<std::size_t>(ids));
  double error = 0.0;
  for (int trial = 0; trial < 200; ++trial)
  {
    // A random point of VTK's parametric cell, and the cube's point there: a wedge's (r, s, t) is
    // the collapsed cube's (r / (1 - s), s, t); the triquadratic pyramid's parametric cell is the
    // pyramid with base [0, 1]^2 at t = 1/2 and apex (1/2, 1/2, 1), the cube's (u, v, w) at
    // (1/2 + (u - 1/2) (1 - w), 1/2 + (v - 1/2) (1 - w), (1 + w) / 2).
    Point x = randomPoint(wedge, random);
    double cube[3] = { wedge ? (x[1] < 1.0 ? x[0] / (1.0 - x[1]) : 0.0) : x[0], x[1], x[2] };
    if (type == VTK_TRIQUADRATIC_PYRAMID)
    {
      x = { 0.5 + (cube[0] - 0.5) * (1.0 - cube[2]), 0.5 + (cube[1] - 0.5) * (1.0 - cube[2]), 0.5 * (1.0 + cube[2]) };
    }
    cell->InterpolateFunctions(x.data(), weights.data());
    double theirs = 0.0;
    for (int n = 0; n < ids; ++n)
    {
      theirs += weights[static_cast<std::size_t>(n)] * values[static_cast<std::size_t>(n)];
    }
    const double ours = tetdsr::forHexahedronOrder(table.order, [&](auto P) {
      return tetdsr::tensor::evaluate<decltype(P)::value>(form, cube);
    });
    error = std::max(error, std::abs(ours - theirs));
  }
  // Each node's point in the cube is where VTK puts the node (tetdsr::parametricPoint), but on
  // the collapsed face, where every point of the cube is the same point of the cell.
  const double* theirPoints = cell->GetParametricCoords();
  for (int n = 0; n < ids; ++n)
  {
    const auto& at = table.nodePoints[static_cast<std::size_t>(n)];
    if (table.collapsedAxis >= 0 && at[static_cast<std::size_t>(table.collapsedAxis)] == 1.0)
    {
      continue;
    }
    double parametric[3];
    tetdsr::parametricPoint(table, at.data(), parametric);
    for (int a = 0; a < 3; ++a)
    {
      error = std::max(error, std::abs(parametric[a] - theirPoints[3 * n + a]));
    }
  }
  worst = std::max(worst, error);
  if (!(error < 1e-12))
  {
    std::cerr << table.name << " (" << ids << " ids): expected the tensor form and its nodes' points to equal VTK's, "
              << "got a difference of " << error << "\n";
    return 1;
  }
  return 0;
}

} // namespace

int TestSplitCellsNodeOrder(int, char*[])
{
  const int types[] = { VTK_HEXAHEDRON, VTK_VOXEL, VTK_QUADRATIC_HEXAHEDRON, VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON,
    VTK_TRIQUADRATIC_HEXAHEDRON, VTK_LAGRANGE_HEXAHEDRON, VTK_BEZIER_HEXAHEDRON, VTK_WEDGE,
    VTK_QUADRATIC_LINEAR_WEDGE, VTK_QUADRATIC_WEDGE, VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_LAGRANGE_WEDGE,
    VTK_BEZIER_WEDGE };
  std::mt19937 random(20261202);
  int failures = 0, shapes = 0;
  Worst worst;
  for (const int type : types)
  {
    // Every id count up to that of order-6 Lagrange hexahedra: the shapes the split builds
    // (every one it reads).
    for (int ids = 1; ids <= 343; ++ids)
    {
      const tetdsr::SplitShape* shape = nullptr;
      if (tetdsr::splitShapeOf(type, ids, shape) != 0)
      {
        continue;
      }
      ++shapes;
      failures += checkShape(type, ids, *shape, random, worst);
    }
  }
  // The tensor forms of every type read as a tensor-product cell.
  int tensorTypes = 0;
  double tensorWorst = 0.0;
  for (const int type : { VTK_HEXAHEDRON, VTK_VOXEL, VTK_QUADRATIC_HEXAHEDRON, VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON,
         VTK_TRIQUADRATIC_HEXAHEDRON, VTK_LAGRANGE_HEXAHEDRON, VTK_BEZIER_HEXAHEDRON, VTK_WEDGE,
         VTK_QUADRATIC_LINEAR_WEDGE, VTK_QUADRATIC_WEDGE, VTK_BIQUADRATIC_QUADRATIC_WEDGE, VTK_LAGRANGE_WEDGE,
         VTK_BEZIER_WEDGE, VTK_PYRAMID, VTK_QUADRATIC_PYRAMID, VTK_TRIQUADRATIC_PYRAMID })
  {
    for (int ids = 1; ids <= 125; ++ids)
    {
      const tetdsr::HexahedronNodes* table = nullptr;
      if (tetdsr::hexahedronNodesOf(type, ids, table) != 0)
      {
        continue;
      }
      ++tensorTypes;
      failures += checkTensorForm(type, ids, *table, random, tensorWorst);
    }
  }
  std::cout << tensorTypes << " tensor forms: max difference from VTK's interpolation " << tensorWorst << "\n";
  if (tensorTypes != 28)
  {
    std::cerr << "expected 28 (type, id count) read as tensor-product cells, got " << tensorTypes << "\n";
    ++failures;
  }
  // The kinds TetDSR documents as read (commit 2ed0cd8) must be among them.
  const int required[][2] = { { VTK_HEXAHEDRON, 8 }, { VTK_VOXEL, 8 }, { VTK_QUADRATIC_HEXAHEDRON, 20 },
    { VTK_LAGRANGE_HEXAHEDRON, 8 }, { VTK_BEZIER_HEXAHEDRON, 8 }, { VTK_WEDGE, 6 },
    { VTK_QUADRATIC_LINEAR_WEDGE, 12 }, { VTK_QUADRATIC_WEDGE, 15 }, { VTK_BIQUADRATIC_QUADRATIC_WEDGE, 18 },
    { VTK_LAGRANGE_WEDGE, 6 }, { VTK_LAGRANGE_WEDGE, 18 }, { VTK_BEZIER_WEDGE, 6 }, { VTK_BEZIER_WEDGE, 18 } };
  for (const auto& kind : required)
  {
    const tetdsr::SplitShape* shape = nullptr;
    if (tetdsr::splitShapeOf(kind[0], kind[1], shape) != 0)
    {
      std::cerr << "expected type " << kind[0] << " with " << kind[1] << " ids to be read, got a refusal\n";
      ++failures;
    }
  }
  std::cout << shapes << " shapes: max node difference " << worst.nodes << ", max basis difference "
            << worst.basis << ", max lattice difference " << worst.lattice << ", max volume difference "
            << worst.pieces << "\n";
  if (failures != 0)
  {
    std::cerr << "FAILED: " << failures << " expectations\n";
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
