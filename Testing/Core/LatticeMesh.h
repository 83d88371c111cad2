// Test meshes built independently of the filter: an n x n x n lattice of cubes, each split
// into 6 tetrahedra around its main diagonal (Kuhn), with mid-edge nodes, in VTK node order.
// forEachKuhnTet is the one walk over the lattice's tetrahedra that every C++ test and benchmark
// mesh of this kind uses (HigherOrderLattice.h, Testing/Benchmark, Testing/Cxx); the Python twin
// is Testing/Python/kuhn_lattice.py.
#pragma once

#include "tetdsr/index/Scene.h"

#include <glm/glm.hpp>

#include <array>
#include <functional>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

namespace tetdsr_test
{

/// Integer coordinates of a lattice node, in steps of (cube edge / steps per edge).
using LatticeKey = std::array<int, 3>;

/// The order in which forEachKuhnTet visits the cubes: cube (i, j, k) with k fastest (i outer),
/// or with i fastest (k outer, the order of VTK's image data and of the benchmarks' point ids).
enum class CubeOrder
{
  ZFastest,
  XFastest
};

/// Calls visit(vertices) for each of the 6 n^3 tetrahedra of the lattice, cube after cube in
/// `order`, a cube's 6 in the order of the axis permutations (012, 021, 102, 120, 201, 210): tet
/// p walks from the cube's lowest corner along the axes in permutation p's order. Vertices are in
/// steps of 1 / stepsPerEdge of a cube's edge, and positively oriented (the odd permutations get
/// vertices 1 and 2 swapped: a walk's orientation is its permutation's sign).
template <typename Visit>
void forEachKuhnTet(int n, int stepsPerEdge, CubeOrder order, Visit&& visit)
{
  static const int permutations[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 },
    { 2, 0, 1 }, { 2, 1, 0 } };
  static const bool odd[6] = { false, true, true, false, false, true };
  for (int outer = 0; outer < n; ++outer)
    for (int middle = 0; middle < n; ++middle)
      for (int inner = 0; inner < n; ++inner)
      {
        const LatticeKey cube = order == CubeOrder::ZFastest ? LatticeKey{ outer, middle, inner }
                                                             : LatticeKey{ inner, middle, outer };
        for (int p = 0; p < 6; ++p)
        {
          std::array<LatticeKey, 4> v;
          for (int a = 0; a < 3; ++a)
          {
            v[0][a] = stepsPerEdge * cube[a];
          }
          for (int s = 0; s < 3; ++s)
          {
            v[s + 1] = v[s];
            v[s + 1][permutations[p][s]] += stepsPerEdge;
          }
          if (odd[p])
          {
            std::swap(v[1], v[2]);
          }
          visit(static_cast<const std::array<LatticeKey, 4>&>(v));
        }
      }
}

/// The 10 nodes of a quadratic tet in VTK order (vertices, then the mid-edge nodes of edges 01,
/// 12, 02, 03, 13, 23), from vertices on the half-step lattice (stepsPerEdge 2).
inline std::array<LatticeKey, 10> quadraticTetKeys(const std::array<LatticeKey, 4>& v)
{
  static const int edges[6][2] = { { 0, 1 }, { 1, 2 }, { 0, 2 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };
  std::array<LatticeKey, 10> keys;
  for (int c = 0; c < 4; ++c)
  {
    keys[c] = v[c];
  }
  for (int e = 0; e < 6; ++e)
  {
    for (int a = 0; a < 3; ++a)
    {
      keys[4 + e][a] = (v[edges[e][0]][a] + v[edges[e][1]][a]) / 2;
    }
  }
  return keys;
}

struct LatticeMesh
{
  std::vector<double> points; // xyz
  std::vector<tetdsr::NodeId> cellNodes;
  std::vector<double> values;
  /// Integer half-step lattice key of each point (vertices have even coordinates).
  std::vector<std::array<int, 3>> keys;
  /// VTK's layout of the cells, made by view(): every cell a VTK_QUADRATIC_TETRA at offsets
  /// 0, 10, 20, ... into cellNodes.
  mutable std::vector<std::uint8_t> cellTypes;
  mutable std::vector<tetdsr::NodeId> offsets;

  tetdsr::MeshView view() const
  {
    const auto cells = static_cast<tetdsr::NodeId>(cellNodes.size() / 10);
    cellTypes.assign(static_cast<std::size_t>(cells), tetdsr::kVtkQuadraticTetra);
    offsets.resize(static_cast<std::size_t>(cells) + 1);
    for (tetdsr::NodeId c = 0; c <= cells; ++c)
    {
      offsets[static_cast<std::size_t>(c)] = 10 * c;
    }
    tetdsr::MeshView mesh;
    mesh.points = points.data();
    mesh.numberOfPoints = static_cast<tetdsr::NodeId>(points.size() / 3);
    mesh.numberOfCells = cells;
    mesh.cellTypes = cellTypes.data();
    mesh.offsets = offsets.data();
    mesh.connectivity = cellNodes.data();
    mesh.connectivitySize = static_cast<tetdsr::NodeId>(cellNodes.size());
    mesh.values = values.data();
    return mesh;
  }

  glm::dvec3 point(tetdsr::NodeId id) const
  {
    return { points[3 * id], points[3 * id + 1], points[3 * id + 2] };
  }

  void setPoint(tetdsr::NodeId id, const glm::dvec3& p)
  {
    points[3 * id] = p.x;
    points[3 * id + 1] = p.y;
    points[3 * id + 2] = p.z;
  }

  /// Moves every point by `map`, then puts mid-edge nodes back on their edges' midpoints.
  void mapVertices(const std::function<glm::dvec3(const glm::dvec3&, const std::array<int, 3>&)>& map)
  {
    for (std::size_t p = 0; p < keys.size(); ++p)
    {
      setPoint(static_cast<tetdsr::NodeId>(p), map(point(static_cast<tetdsr::NodeId>(p)), keys[p]));
    }
    static const int edges[6][2] = { { 0, 1 }, { 1, 2 }, { 0, 2 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };
    for (std::size_t c = 0; c < cellNodes.size() / 10; ++c)
    {
      const tetdsr::NodeId* ids = cellNodes.data() + 10 * c;
      for (int e = 0; e < 6; ++e)
      {
        setPoint(ids[4 + e], 0.5 * (point(ids[edges[e][0]]) + point(ids[edges[e][1]])));
      }
    }
  }

  void sample(const std::function<double(const glm::dvec3&)>& field)
  {
    values.resize(points.size() / 3);
    for (std::size_t p = 0; p < values.size(); ++p)
    {
      values[p] = field(point(static_cast<tetdsr::NodeId>(p)));
    }
  }
};

/// Cubes of side `size / n` filling [origin, origin + size]^3 (cubes with z fastest); point ids
/// in the order the tets first reach them.
inline LatticeMesh makeLattice(int n, const glm::dvec3& origin, double size)
{
  LatticeMesh mesh;
  // Nodes live on the half-step lattice; key them by integer coordinates (2n + 1 per axis).
  std::map<LatticeKey, tetdsr::NodeId> index;
  const double half = 0.5 * size / n;
  auto node = [&](const LatticeKey& k) {
    auto it = index.find(k);
    if (it != index.end())
    {
      return it->second;
    }
    const tetdsr::NodeId id = static_cast<tetdsr::NodeId>(mesh.points.size() / 3);
    for (int a = 0; a < 3; ++a)
    {
      mesh.points.push_back(origin[a] + half * k[a]);
    }
    mesh.keys.push_back(k);
    index.emplace(k, id);
    return id;
  };
  forEachKuhnTet(n, 2, CubeOrder::ZFastest, [&](const std::array<LatticeKey, 4>& vertices) {
    for (const LatticeKey& key : quadraticTetKeys(vertices))
    {
      mesh.cellNodes.push_back(node(key));
    }
  });
  return mesh;
}

} // namespace tetdsr_test
