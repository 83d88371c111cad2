// Test meshes built independently of the filter: an n x n x n lattice of cubes, each split
// into 6 tetrahedra around its main diagonal (Kuhn), with mid-edge nodes, in VTK node order.
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

/// Cubes of side `size / n` filling [origin, origin + size]^3.
inline LatticeMesh makeLattice(int n, const glm::dvec3& origin, double size)
{
  static const int edges[6][2] = { { 0, 1 }, { 1, 2 }, { 0, 2 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };
  LatticeMesh mesh;
  // Nodes live on the half-step lattice; key them by integer coordinates (2n + 1 per axis).
  std::map<std::array<int, 3>, tetdsr::NodeId> index;
  const double half = 0.5 * size / n;
  auto node = [&](const std::array<int, 3>& k) {
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
  // Axis orders of the 6 Kuhn tets; the orientation of each is the sign of its permutation, so
  // the odd ones get vertices 1 and 2 swapped: every cell is positively oriented.
  const int permutations[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 },
    { 2, 1, 0 } };
  const bool odd[6] = { false, true, true, false, false, true };
  int which = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        for (const auto& perm : permutations)
        {
          const bool swap12 = odd[which++ % 6];
          std::array<std::array<int, 3>, 4> v;
          v[0] = { 2 * i, 2 * j, 2 * k };
          for (int s = 0; s < 3; ++s)
          {
            v[s + 1] = v[s];
            v[s + 1][perm[s]] += 2;
          }
          if (swap12)
          {
            std::swap(v[1], v[2]);
          }
          for (int e = 0; e < 4; ++e)
          {
            mesh.cellNodes.push_back(node(v[e]));
          }
          for (const auto& edge : edges)
          {
            std::array<int, 3> m;
            for (int a = 0; a < 3; ++a)
            {
              m[a] = (v[edge[0]][a] + v[edge[1]][a]) / 2;
            }
            mesh.cellNodes.push_back(node(m));
          }
        }
  return mesh;
}

} // namespace tetdsr_test
