// The benchmarks' mesh (tetdsr_benchmark.cxx and embree_comparison.cxx): a lattice of quadratic
// tets with three fields sampled at its nodes.
#pragma once

#include "LatticeMesh.h" // forEachKuhnTet
#include "tetdsr/index/Scene.h"

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

/// n^3 cubes over [0,1]^3, 6 positively oriented quadratic tets each, nodes on the half-step
/// lattice, in the core's types (tetdsr_benchmark.cxx copies it into VTK arrays). Fields:
/// "quadric" = |x - c|^2 (exactly quadratic), "wave" (smooth, not polynomial), "bubbles" (1 at
/// vertex nodes, 0.9 at mid-edge nodes: in every cell f = 0.8 + 0.2 sum L_i^2, dipping to 0.85 at
/// the centroid; at iso 0.86 each cell holds a closed surface that no nodal value straddles: the
/// paper's widened nodal range [0.875, 1.025] and vtkContourFilter miss all of them), "blobs"
/// (a sum of 12 Gaussians of width 0.09 at fixed spread-out centres: at iso 0.4 a ray crosses
/// several separate surfaces and many transverse cells before its first hit).
struct Lattice
{
  explicit Lattice(int n)
  {
    const int m = 2 * n + 1;
    auto id = [m](int i, int j, int k) { return static_cast<tetdsr::NodeId>(i + m * (j + m * k)); };
    const std::size_t count = static_cast<std::size_t>(m) * m * m;
    points.resize(3 * count);
    quadric.resize(count);
    wave.resize(count);
    bubbles.resize(count);
    blobs.resize(count);
    // Centres: a fixed scrambled lattice of 12 points in [0.15, 0.85]^3.
    double centres[12][3];
    for (int b = 0; b < 12; ++b)
    {
      centres[b][0] = 0.15 + 0.7 * ((b * 5) % 12) / 11.0;
      centres[b][1] = 0.15 + 0.7 * ((b * 7 + 3) % 12) / 11.0;
      centres[b][2] = 0.15 + 0.7 * ((b * 11 + 6) % 12) / 11.0;
    }
    for (int k = 0; k < m; ++k)
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i)
        {
          const double x = i / (m - 1.0), y = j / (m - 1.0), z = k / (m - 1.0);
          const auto p = static_cast<std::size_t>(id(i, j, k));
          points[3 * p] = x;
          points[3 * p + 1] = y;
          points[3 * p + 2] = z;
          quadric[p] = (x - 0.5) * (x - 0.5) + (y - 0.45) * (y - 0.45) + (z - 0.52) * (z - 0.52);
          wave[p] = std::sin(7.0 * x) * std::cos(5.0 * y) + std::sin(6.0 * z + 1.0);
          const bool vertexNode = i % 2 == 0 && j % 2 == 0 && k % 2 == 0;
          bubbles[p] = vertexNode ? 1.0 : 0.9;
          double sum = 0.0;
          for (const double* c : centres)
          {
            const double r2 = (x - c[0]) * (x - c[0]) + (y - c[1]) * (y - c[1]) + (z - c[2]) * (z - c[2]);
            sum += std::exp(-r2 / (2.0 * 0.09 * 0.09));
          }
          blobs[p] = sum;
        }
    // The Kuhn lattice (Testing/Core/LatticeMesh.h) with the point ids above, cubes with x fastest.
    cells = 6LL * n * n * n;
    cellNodes.reserve(static_cast<std::size_t>(10 * cells));
    tetdsr_test::forEachKuhnTet(n, 2, tetdsr_test::CubeOrder::XFastest,
      [&](const std::array<tetdsr_test::LatticeKey, 4>& vertices) {
        for (const auto& key : tetdsr_test::quadraticTetKeys(vertices))
        {
          cellNodes.push_back(id(key[0], key[1], key[2]));
        }
      });
    // VTK's layout: every cell a VTK_QUADRATIC_TETRA at offsets 0, 10, 20, ...
    cellTypes.assign(static_cast<std::size_t>(cells), tetdsr::kVtkQuadraticTetra);
    offsets.resize(static_cast<std::size_t>(cells) + 1);
    for (tetdsr::NodeId c = 0; c <= cells; ++c)
      offsets[static_cast<std::size_t>(c)] = 10 * c;
  }

  tetdsr::MeshView view(const std::vector<double>& values) const
  {
    tetdsr::MeshView mesh;
    mesh.points = points.data();
    mesh.numberOfPoints = static_cast<tetdsr::NodeId>(values.size());
    mesh.numberOfCells = cells;
    mesh.cellTypes = cellTypes.data();
    mesh.offsets = offsets.data();
    mesh.connectivity = cellNodes.data();
    mesh.connectivitySize = static_cast<tetdsr::NodeId>(cellNodes.size());
    mesh.values = values.data();
    return mesh;
  }

  std::vector<double> points;
  std::vector<tetdsr::NodeId> cellNodes;
  std::vector<std::uint8_t> cellTypes;
  std::vector<tetdsr::NodeId> offsets;
  tetdsr::NodeId cells = 0;
  std::vector<double> quadric, wave, bubbles, blobs;
};
