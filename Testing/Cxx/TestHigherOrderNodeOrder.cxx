// VTK is the authority for the node order of its arbitrary-order tetrahedra: for orders 1..4 and
// both vtkLagrangeTetra and vtkBezierTetra, the core's HigherOrderTet<P>::nodePoint must give
// every node's parametric coordinates as VTK's GetParametricCoords does, and the core's
// interpolation of a cell's node values (nodal values for Lagrange, Bernstein coefficients for
// Bezier) must equal VTK's InterpolateFunctions at random parametric points. The cell sits on
// the unit tetrahedron, so world = parametric coordinates (r, s, t) and L0 = 1 - r - s - t.
#include "vtkBezierTetra.h"
#include "vtkCellType.h"
#include "vtkHigherOrderTetra.h"
#include "vtkLagrangeTetra.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkIdList.h"

#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/index/Scene.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <random>
#include <vector>

namespace
{

/// The barycentric point of node n of a cell of order p, from the core.
void corePoint(int p, int n, double L[4])
{
  tetdsr::tetNodePoint(p, n, L);
}

/// VTK's cell of order p with nodes at its own parametric coordinates (the unit tetrahedron).
void placeNodes(vtkHigherOrderTetra* cell, int nodes)
{
  cell->GetPointIds()->SetNumberOfIds(nodes);
  cell->GetPoints()->SetNumberOfPoints(nodes);
  for (int n = 0; n < nodes; ++n)
  {
    cell->GetPointIds()->SetId(n, n);
    cell->GetPoints()->SetPoint(n, 0.0, 0.0, 0.0);
  }
  cell->Initialize();
  const double* pcoords = cell->GetParametricCoords();
  for (int n = 0; n < nodes; ++n)
  {
    cell->GetPoints()->SetPoint(n, pcoords + 3 * n);
  }
}

/// Checks one VTK class at one order; returns the number of failed expectations.
int checkOrder(vtkHigherOrderTetra* cell, int vtkType, const char* name, int p, std::mt19937& random)
{
  int failures = 0;
  const int nodes = tetdsr::latticeCount(p);
  placeNodes(cell, nodes);
  if (cell->GetOrder() != p)
  {
    std::cerr << name << " order " << p << ": expected VTK to read order " << p << " from "
              << nodes << " points, got " << cell->GetOrder() << "\n";
    return 1;
  }

  // 1. Every node's parametric coordinates: VTK's against the core's alpha / P.
  const double* pcoords = cell->GetParametricCoords();
  double worst = 0.0;
  for (int n = 0; n < nodes; ++n)
  {
    double L[4];
    corePoint(p, n, L);
    const double ours[3] = { L[1], L[2], L[3] };
    const double sum = L[0] + L[1] + L[2] + L[3];
    for (int a = 0; a < 3; ++a)
    {
      const double error = std::abs(ours[a] - pcoords[3 * n + a]);
      worst = std::max(worst, error);
      if (error > 1e-14 || std::abs(sum - 1.0) > 1e-14)
      {
        std::cerr << name << " order " << p << " node " << n << ": expected parametric ("
                  << pcoords[3 * n] << ", " << pcoords[3 * n + 1] << ", " << pcoords[3 * n + 2]
                  << ") (VTK), got (" << ours[0] << ", " << ours[1] << ", " << ours[2]
                  << ") from HigherOrderTet<" << p << ">::nodePoint\n";
        ++failures;
        break;
      }
    }
  }

  // 2. Interpolation: random node values in a one-cell scene (the same positions), evaluated by
  // the core at random points inside, against VTK's shape functions.
  std::vector<double> points(3 * nodes), values(nodes);
  std::vector<tetdsr::NodeId> connectivity(nodes);
  std::uniform_real_distribution<double> unit(0.0, 1.0), value(-1.0, 1.0);
  for (int n = 0; n < nodes; ++n)
  {
    std::copy(pcoords + 3 * n, pcoords + 3 * n + 3, points.begin() + 3 * n);
    values[n] = value(random);
    connectivity[n] = n;
  }
  const std::uint8_t type = static_cast<std::uint8_t>(vtkType);
  const tetdsr::NodeId offsets[2] = { 0, nodes };
  tetdsr::MeshView mesh;
  mesh.points = points.data();
  mesh.numberOfPoints = nodes;
  mesh.numberOfCells = 1;
  mesh.cellTypes = &type;
  mesh.offsets = offsets;
  mesh.connectivity = connectivity.data();
  mesh.connectivitySize = nodes;
  mesh.values = values.data();
  tetdsr::Scene scene(mesh);
  if (scene.summary().validCells != 1)
  {
    std::cerr << name << " order " << p << ": expected the cell on VTK's own node positions to be "
              << "valid, got " << scene.summary().validCells << " valid (" << scene.summary().curvedCells
              << " curved, " << scene.summary().tangledCells << " tangled)\n";
    return failures + 1;
  }
  if (scene.summary().curvedCells != 0)
  {
    std::cerr << name << " order " << p << ": expected a straight cell (nodes at VTK's parametric "
              << "coordinates), got a curved one\n";
    ++failures;
  }
  double worstValue = 0.0;
  std::vector<double> weights(nodes);
  for (int sample = 0; sample < 200; ++sample)
  {
    double r, s, t;
    do
    {
      r = unit(random);
      s = unit(random);
      t = unit(random);
    } while (r + s + t > 1.0);
    const double pc[3] = { r, s, t };
    cell->InterpolateFunctions(pc, weights.data());
    double expected = 0.0;
    for (int n = 0; n < nodes; ++n)
    {
      expected += weights[n] * values[n];
    }
    const double got = scene.interpolate(0, glm::dvec3(r, s, t), values.data());
    const double error = std::abs(got - expected);
    worstValue = std::max(worstValue, error);
    if (!(error <= 1e-12))
    {
      std::cerr << name << " order " << p << " at (" << r << ", " << s << ", " << t
                << "): expected " << expected << " (VTK's InterpolateFunctions), got " << got
                << " (tetdsr::Scene::interpolate)\n";
      ++failures;
      break;
    }
  }
  std::cout << name << " order " << p << ": " << nodes << " nodes, max parametric difference "
            << worst << ", max interpolation difference " << worstValue << " over 200 points\n";
  return failures;
}

} // namespace

int TestHigherOrderNodeOrder(int, char*[])
{
  std::mt19937 random(20240611);
  int failures = 0;
  for (int p = 1; p <= tetdsr::kMaxTetOrder; ++p)
  {
    vtkNew<vtkLagrangeTetra> lagrange;
    failures += checkOrder(lagrange, VTK_LAGRANGE_TETRAHEDRON, "vtkLagrangeTetra", p, random);
    vtkNew<vtkBezierTetra> bezier;
    failures += checkOrder(bezier, VTK_BEZIER_TETRAHEDRON, "vtkBezierTetra", p, random);
  }
  if (failures != 0)
  {
    std::cerr << "FAILED: " << failures << " expectations\n";
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
