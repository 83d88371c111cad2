// VTK is the authority for the node order, parametric coordinates and shape functions of its
// hexahedra, wedges and pyramids. For every (type, id count) whose shape the core builds
// (tetdsr::splitShapeOf returns 0), against VTK's own cell of that type and count:
// 1. SplitShape::nodePoints equal the cell's GetParametricCoords (to 1e-15);
// 2. SplitShape::basis equals the cell's InterpolateFunctions at 200 random parametric points
//    inside the cell (unit cube, or unit triangle x [0, 1]) (to 1e-12).
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

#include "tetdsr/cells/HexahedronCell.h"
#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/cells/SplitCells.h"

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

struct Worst
{
  double nodes = 0.0, basis = 0.0;
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
  std::cout << label << ": " << ids << " nodes, max node difference " << nodeError
            << ", max basis difference " << basisError << "\n";
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
    // Every id count up to that of order-6 Lagrange hexahedra: the shapes built (every one read).
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
            << worst.basis << "\n";
  if (failures != 0)
  {
    std::cerr << "FAILED: " << failures << " expectations\n";
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
