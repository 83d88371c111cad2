// Test meshes of tetrahedra of any order 1..4 (VTK_TETRA, VTK_QUADRATIC_TETRA, and
// VTK_LAGRANGE_TETRAHEDRON / VTK_BEZIER_TETRAHEDRON of 4, 10, 20 or 35 nodes), built independently
// of the scene: the Kuhn lattice of LatticeMesh.h, each cell's nodes at alpha / P of its vertices
// on a fine integer lattice (12 steps per cube edge, so nodes of every order up to 4 land on it and
// neighbours of any orders share the points they have in common: a conforming mesh, watertight
// where the field is of a degree every cell holds).
//
// Node order: HigherOrderTet<P>'s (checked against VTK's own cells in Testing/Cxx). A Bezier
// cell's coefficients come from its nodal values by this file's own solve of the interpolation
// system (Bernstein basis at the nodes, Gaussian elimination), not by the core's conversion.
#pragma once

#include "LatticeMesh.h" // forEachKuhnTet
#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/index/Scene.h"

#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <utility>
#include <vector>

namespace tetdsr_test
{

/// The Bernstein basis polynomial of multi-index alpha (degree sum alpha) at L, from its formula.
inline double bernsteinBasis(const int alpha[4], const double L[4])
{
  int degree = 0;
  double value = 1.0;
  for (int k = 0; k < 4; ++k)
  {
    for (int j = 1; j <= alpha[k]; ++j)
    {
      ++degree;
      value *= static_cast<double>(degree) / j * L[k]; // builds degree! / prod alpha_k! * L^alpha
    }
  }
  return value;
}

struct HigherOrderCell
{
  int vtkType;
  int order;
  bool bezier;
};

struct HigherOrderLattice
{
  std::vector<double> points; // xyz
  std::vector<tetdsr::NodeId> connectivity;
  std::vector<tetdsr::NodeId> offsets{ 0 };
  std::vector<std::uint8_t> cellTypes;
  std::vector<double> values;
  std::vector<HigherOrderCell> cells;
  /// Each cell's vertex positions (world) and its nodes' barycentric points.
  std::vector<std::array<glm::dvec3, 4>> vertices;

  tetdsr::MeshView view() const
  {
    tetdsr::MeshView mesh;
    mesh.points = points.data();
    mesh.numberOfPoints = static_cast<tetdsr::NodeId>(points.size() / 3);
    mesh.numberOfCells = static_cast<tetdsr::NodeId>(cellTypes.size());
    mesh.cellTypes = cellTypes.data();
    mesh.offsets = offsets.data();
    mesh.connectivity = connectivity.data();
    mesh.connectivitySize = static_cast<tetdsr::NodeId>(connectivity.size());
    mesh.values = values.data();
    return mesh;
  }
};

/// The barycentric point of node n of a cell of order P in VTK order (the core's table, checked
/// against VTK's cells by Testing/Cxx/TestHigherOrderNodeOrder).
inline void nodeBarycentric(int order, int n, double L[4])
{
  tetdsr::tetNodePoint(order, n, L);
}

/// The Bernstein coefficients (VTK order) of the polynomial of degree `order` with these nodal
/// values (VTK order): the interpolation system B_b(node_a) c = values, solved here.
inline std::vector<double> bezierCoefficients(int order, const std::vector<double>& nodal)
{
  const int count = static_cast<int>(nodal.size());
  std::vector<std::vector<double>> a(count, std::vector<double>(count + 1));
  for (int row = 0; row < count; ++row)
  {
    double L[4];
    nodeBarycentric(order, row, L);
    for (int col = 0; col < count; ++col)
    {
      double at[4];
      nodeBarycentric(order, col, at);
      int alpha[4];
      for (int k = 0; k < 4; ++k)
      {
        alpha[k] = static_cast<int>(std::lround(at[k] * order));
      }
      a[row][col] = bernsteinBasis(alpha, L);
    }
    a[row][count] = nodal[row];
  }
  for (int col = 0; col < count; ++col)
  {
    int pivot = col;
    for (int r = col + 1; r < count; ++r)
    {
      if (std::abs(a[r][col]) > std::abs(a[pivot][col]))
      {
        pivot = r;
      }
    }
    std::swap(a[col], a[pivot]);
    for (int r = 0; r < count; ++r)
    {
      if (r != col)
      {
        const double factor = a[r][col] / a[col][col];
        for (int c = col; c <= count; ++c)
        {
          a[r][c] -= factor * a[col][c];
        }
      }
    }
  }
  std::vector<double> c(count);
  for (int r = 0; r < count; ++r)
  {
    c[r] = a[r][count] / a[r][r];
  }
  return c;
}

/// Cubes of side size / n filling [origin, origin + size]^3, 6 Kuhn tets each; cell k gets
/// pick(k)'s type, order and layout. Node values from `field` (for Bezier cells, converted to
/// coefficients: such a cell's nodes are not shared, since a control point is not a point of the
/// field); the node positions on the straight cell (warp, if given, moves every point after).
inline HigherOrderLattice makeHigherOrderLattice(int n, const glm::dvec3& origin, double size,
  const std::function<HigherOrderCell(int)>& pick, const std::function<double(const glm::dvec3&)>& field)
{
  constexpr int kSteps = 12; // per cube edge: a multiple of every order 1..4
  HigherOrderLattice mesh;
  std::map<std::array<int, 3>, tetdsr::NodeId> shared;
  auto position = [&](const std::array<int, 3>& key) {
    return origin + (size / (n * kSteps)) * glm::dvec3(key[0], key[1], key[2]);
  };
  auto newPoint = [&](const glm::dvec3& p, double value) {
    const auto id = static_cast<tetdsr::NodeId>(mesh.points.size() / 3);
    mesh.points.insert(mesh.points.end(), { p.x, p.y, p.z });
    mesh.values.push_back(value);
    return id;
  };
  int cell = 0;
  forEachKuhnTet(n, kSteps, CubeOrder::ZFastest, [&](const std::array<LatticeKey, 4>& v) {
    const HigherOrderCell kind = pick(cell++);
    const int count = tetdsr::latticeCount(kind.order);
    std::vector<std::array<int, 3>> keys(count);
    std::vector<double> nodal(count);
    for (int node = 0; node < count; ++node)
    {
      double L[4];
      nodeBarycentric(kind.order, node, L);
      for (int a = 0; a < 3; ++a)
      {
        int sum = 0;
        for (int q = 0; q < 4; ++q)
        {
          sum += static_cast<int>(std::lround(L[q] * kind.order)) * v[q][a];
        }
        keys[node][a] = sum / kind.order;
      }
      nodal[node] = field(position(keys[node]));
    }
    std::array<glm::dvec3, 4> corners;
    for (int q = 0; q < 4; ++q)
    {
      corners[q] = position(v[q]);
    }
    mesh.vertices.push_back(corners);
    const std::vector<double> coefficients =
      kind.bezier ? bezierCoefficients(kind.order, nodal) : nodal;
    for (int node = 0; node < count; ++node)
    {
      // Vertices are shared by every cell; other nodes only between nodal (non-Bezier) cells.
      const bool vertex = node < 4;
      if (!kind.bezier || vertex)
      {
        auto it = shared.find(keys[node]);
        if (it == shared.end())
        {
          it = shared.emplace(keys[node], newPoint(position(keys[node]), nodal[node])).first;
        }
        mesh.connectivity.push_back(it->second);
      }
      else
      {
        mesh.connectivity.push_back(newPoint(position(keys[node]), coefficients[node]));
      }
    }
    mesh.offsets.push_back(static_cast<tetdsr::NodeId>(mesh.connectivity.size()));
    mesh.cellTypes.push_back(static_cast<std::uint8_t>(kind.vtkType));
    mesh.cells.push_back(kind);
  });
  return mesh;
}

} // namespace tetdsr_test
