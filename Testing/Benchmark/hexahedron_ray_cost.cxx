// What one ray test costs in a hexahedron of order P = 1..4 solved in its own reference cube
// (HexahedronCell<P, Curved>): random rays aimed at random points of one cell, on one core.
// Prints a Markdown table: straight and bent cells, the time per ray-cell test, the boxes the
// bent cell's solve visits per test (mean and largest, from solveOnCube on the same equations),
// the hits and the share of them certified.
//
//   tetdsr-hexahedron-ray-cost [rays per case]
//
// The cell: the unit cube's control net moved by a smooth bend of `bend` (0 for the straight
// cell, 0.03 as tetdsr-benchmark --kinds bends its lattices), the field |x - c|^2 + 0.8 x at the
// control points (a Bezier cell: any net is one), its iso-value halfway through their range.
#include "tetdsr/cells/HexahedronCell.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

namespace
{
glm::dvec3 bent(const glm::dvec3& x, double bend)
{
  return x + bend * glm::dvec3(std::sin(3.0 * x.y + 1.0), std::sin(2.0 * x.z + 0.5), std::sin(2.5 * x.x));
}

template <int P, bool Curved>
void run(int rays, double bend)
{
  using Cell = tetdsr::HexahedronCell<P, Curved>;
  constexpr int N = tetdsr::tensor::count(P);
  glm::dvec3 nodes[N];
  double values[N];
  for (int k = 0; k <= P; ++k)
    for (int j = 0; j <= P; ++j)
      for (int i = 0; i <= P; ++i)
      {
        const int at = tetdsr::tensor::index(P, i, j, k);
        nodes[at] = bent(glm::dvec3(i, j, k) / static_cast<double>(P), bend);
        const glm::dvec3 d = nodes[at] - glm::dvec3(0.45, 0.5, 0.55);
        values[at] = glm::dot(d, d) + 0.8 * nodes[at].x;
      }
  std::vector<double> coefficients(Cell::kRecordCoefficients);
  tetdsr::CellRecord record{};
  Cell::record(nodes, values, record, coefficients.data());
  record.valueLo = -1e300;
  record.valueHi = 1e300;
  // The iso-value halfway through the coefficients' range: a surface through the cell.
  const double level = 0.5 * (*std::min_element(values, values + N) + *std::max_element(values, values + N));
  const tetdsr::IsoValues iso({ level });
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<tetdsr::Ray> rayList;
  for (int r = 0; r < rays; ++r)
  {
    const glm::dvec3 target = bent(glm::dvec3(unit(random), unit(random), unit(random)), bend);
    glm::dvec3 direction(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5);
    direction = glm::normalize(direction);
    rayList.push_back({ target - 3.0 * direction, direction });
  }
  int hits = 0, certified = 0;
  const auto start = std::chrono::steady_clock::now();
  for (const tetdsr::Ray& ray : rayList)
  {
    tetdsr::SurfaceHit hit;
    bool rootCertified = true;
    if (Cell::intersect(record, ray, iso, 0, 1, 0.0, 1e300, hit, rootCertified))
    {
      ++hits;
      certified += rootCertified;
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The boxes of the bent cell's solve, on the unit cube's equations built here.
  double meanPieces = 0.0;
  int mostPieces = 0;
  if (Curved)
  {
    for (const tetdsr::Ray& ray : rayList)
    {
      const glm::dvec3 d = ray.direction;
      const glm::dvec3 helper = std::abs(d.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
      const glm::dvec3 u = glm::normalize(glm::cross(d, helper)), v = glm::cross(d, u);
      double e0[N], e1[N], f[N], depth[N];
      for (int k = 0; k < N; ++k)
      {
        const glm::dvec3 offset = nodes[k] - ray.origin;
        e0[k] = glm::dot(u, offset);
        e1[k] = glm::dot(v, offset);
        depth[k] = glm::dot(d, offset);
        f[k] = values[k] - level;
      }
      const double* equations[3] = { e0, e1, f };
      tetdsr::BoxRoot root;
      int pieces = 0;
      tetdsr::solveOnCube<P>(equations, depth, 0.0, 1e300, tetdsr::kBarycentricTolerance, root, {}, &pieces);
      meanPieces += pieces;
      mostPieces = std::max(mostPieces, pieces);
    }
    meanPieces /= rays;
  }
  std::printf("| Q%d | %s %.2g | %d | %.2f | %.0f | %d | %d | %.1f%% |\n", P, Curved ? "bent" : "straight", bend, rays,
    1e6 * seconds / rays, meanPieces, mostPieces, hits, hits ? 100.0 * certified / hits : 100.0);
}
} // namespace

int main(int argc, char* argv[])
{
  const int rays = argc > 1 ? std::max(1, std::atoi(argv[1])) : 2000;
  std::printf("| order | cell | rays | us per test | boxes per test (mean) | (most) | hits | certified |\n"
              "|---|---|---|---|---|---|---|---|\n");
  run<1, false>(rays, 0.0);
  run<2, false>(rays, 0.0);
  run<3, false>(rays, 0.0);
  run<4, false>(rays, 0.0);
  run<1, true>(rays, 0.03);
  run<2, true>(rays, 0.03);
  run<3, true>(rays, 0.03);
  run<4, true>(rays, 0.03);
  // Bent ten times as much (0.3 of the cube).
  run<2, true>(rays, 0.3);
  run<4, true>(rays, 0.3);
  return EXIT_SUCCESS;
}
