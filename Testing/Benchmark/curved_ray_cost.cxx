// What one ray test costs in a curved (isoparametric) tetrahedron of order P = 2, 3, 4: random
// rays aimed at random points of one cell, through its record's ray test (CurvedTetCell for
// P = 2, CurvedHigherOrderTetCell<P> for 3 and 4, recorded once as the collapsed cube's forms and
// solved by HexahedronCell<P, true>), on one core. Prints a Markdown table: the time per ray-cell
// test, the boxes the solve visits per test (mean and largest), the hits and the share of them
// certified by a Krawczyk test.
//
//   tetdsr-curved-ray-cost [rays per case]
//
// The cells: a straight tet under the quadratic map W(x, y, z) = (x + a y^2, y + a z^2, z), the
// same cell at every order (W is a polynomial of degree 2 in L, represented exactly by the order-P
// nodes), with the field |q - c|^2 of the preimage q (quadratic in L): the cost of the degree
// alone. Then a map and field of full degree P (a bump of degree P in L).
#include "tetdsr/cells/CurvedHigherOrderTetCell.h"
#include "tetdsr/math/CurvedTet.h"
#include "tetdsr/cells/CurvedTetCell.h"
#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/cells/HexahedronCell.h"
#include "tetdsr/cells/IsoparametricRay.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <type_traits>
#include <vector>

namespace
{
using Map = std::function<glm::dvec3(const double L[4])>;
using Field = std::function<double(const double L[4])>;

const glm::dvec3 kStraight[4] = { { 0.1, 0.2, 0.0 }, { 0.9, 0.1, 0.2 }, { 0.3, 0.8, 0.1 },
  { 0.2, 0.3, 0.9 } };

glm::dvec3 straightPoint(const double L[4])
{
  glm::dvec3 x(0.0);
  for (int k = 0; k < 4; ++k)
    x += L[k] * kStraight[k];
  return x;
}

struct Case
{
  const char* name;
  Map map;
  Field field;
};

/// One cell of order P sampled from the map and field (Lagrange nodes, then Bezier for P > 2).
template <int P>
struct Cell
{
  static constexpr int kNodes = tetdsr::latticeCount(P);
  glm::dvec3 nodes[kNodes];
  double values[kNodes];

  explicit Cell(const Case& c)
  {
    for (int n = 0; n < kNodes; ++n)
    {
      double L[4];
      tetdsr::HigherOrderTet<P>::nodePoint(n, L);
      nodes[n] = c.map(L);
      values[n] = c.field(L);
    }
    if (P > 2)
    {
      tetdsr::HigherOrderTet<P>::toBezier(nodes);
      tetdsr::HigherOrderTet<P>::toBezier(values);
    }
  }
};

struct Result
{
  double microseconds = 0.0, meanPieces = 0.0;
  int maxPieces = 0, hits = 0, certified = 0;
};

/// The cell's record, made once (as the scene makes it for a transverse cell): the collapsed
/// cube's forms (HexahedronCell.h).
template <int P>
struct Recorded
{
  using Kind = std::conditional_t<P == 2, tetdsr::CurvedTetCell, tetdsr::CurvedHigherOrderTetCell<P>>;
  tetdsr::CellRecord record{};
  std::vector<double> coefficients = std::vector<double>(Kind::kRecordCoefficients);
  explicit Recorded(const Cell<P>& cell) { Kind::record(cell.nodes, cell.values, record, coefficients.data()); }
};

/// The boxes one test visits: the record's forms as the cell's ray test builds its equations
/// (its local frame, re-origined ray, unit field), solved by solveOnUnitBox with a counter.
template <int P>
int piecesOf(const Recorded<P>& recorded, double iso, const tetdsr::Ray& ray)
{
  constexpr int N = tetdsr::tensor::count(P);
  constexpr int H = tetdsr::HexahedronCell<P, true>::kHeader;
  const double* c = recorded.coefficients.data();
  const glm::dvec3 origin = (ray.origin - glm::dvec3(c[0], c[1], c[2])) * c[3];
  const glm::dvec3 d = ray.direction;
  glm::dvec3 u, v;
  tetdsr::isoparametric::orthonormalPair(d, u, v);
  double e0[N], e1[N], f[N], depth[N];
  for (int k = 0; k < N; ++k)
  {
    const glm::dvec3 offset = glm::dvec3(c[H + k], c[H + N + k], c[H + 2 * N + k]) - origin;
    e0[k] = glm::dot(u, offset);
    e1[k] = glm::dot(v, offset);
    depth[k] = glm::dot(d, offset);
    f[k] = c[H + 3 * N + k] - iso * recorded.record.scale;
  }
  const double* equations[3] = { e0, e1, f };
  tetdsr::BoxRoot root;
  int pieces = 0;
  tetdsr::solveOnUnitBox<P>(equations, depth, 0.0, 1e300, root, {}, &pieces);
  return pieces;
}

template <int P>
Result measure(const Case& c, double iso, int rays)
{
  const Cell<P> cell(c);
  const Recorded<P> recorded(cell);
  const tetdsr::IsoValues isoValues({ iso });
  std::mt19937 random(7);
  std::exponential_distribution<double> e(1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<tetdsr::Ray> list;
  for (int r = 0; r < rays; ++r)
  {
    double L[4], sum = 0.0;
    for (double& l : L)
      sum += (l = e(random));
    for (double& l : L)
      l /= sum;
    const glm::dvec3 d = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
    list.push_back({ c.map(L) - 3.0 * d, d });
  }
  Result result;
  constexpr int kRepeats = 3;
  const auto start = std::chrono::steady_clock::now();
  for (int repeat = 0; repeat < kRepeats; ++repeat)
  {
    for (const tetdsr::Ray& ray : list)
    {
      tetdsr::SurfaceHit hit;
      bool certified = true;
      if (tetdsr::HexahedronCell<P, true>::intersect(recorded.record, ray, isoValues, 0, 1, 0.0, 1e30, hit, certified) &&
        repeat == 0)
      {
        ++result.hits;
        result.certified += certified;
      }
    }
  }
  result.microseconds =
    std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() /
    (kRepeats * rays);
  long long total = 0;
  for (const tetdsr::Ray& ray : list)
  {
    const int pieces = piecesOf<P>(recorded, iso, ray);
    total += pieces;
    result.maxPieces = std::max(result.maxPieces, pieces);
  }
  result.meanPieces = static_cast<double>(total) / rays;
  return result;
}

void row(int order, const char* name, const Result& r, int rays)
{
  std::printf("| %d | %s | %.2f | %.1f | %d | %d / %d | %.4f |\n", order, name, r.microseconds,
    r.meanPieces, r.maxPieces, r.hits, rays, r.hits ? static_cast<double>(r.certified) / r.hits : 1.0);
}
} // namespace

int main(int argc, char** argv)
{
  const int rays = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20000;
  std::printf("| P | cell | us per ray-cell test | boxes visited (mean) | (largest) | hits | certified share |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  const glm::dvec3 centre(0.4, 0.35, 0.3);
  for (double alpha : { 0.3, 0.7 })
  {
    char name[96];
    std::snprintf(name, sizeof name, "quadratic map W (a = %.1f), sphere field", alpha);
    const Case c{ name,
      [alpha](const double L[4]) {
        const glm::dvec3 x = straightPoint(L);
        return glm::dvec3(x.x + alpha * x.y * x.y, x.y + alpha * x.z * x.z, x.z);
      },
      [centre](const double L[4]) {
        const glm::dvec3 q = straightPoint(L) - centre;
        return glm::dot(q, q);
      } };
    row(2, name, measure<2>(c, 0.06, rays), rays);
    row(3, name, measure<3>(c, 0.06, rays), rays);
    row(4, name, measure<4>(c, 0.06, rays), rays);
  }
  // Full degree: a bump of degree P in L on the map, a field of degree P.
  auto fullDegree = [&](auto order) {
    constexpr int P = decltype(order)::value;
    const Case c{ "map and field of full degree P",
      [](const double L[4]) {
        const double s = std::pow(L[0] + 2.0 * L[3], P - 2), t = std::pow(L[1] + 0.5 * L[2], P - 2);
        return straightPoint(L) + 0.2 * glm::dvec3(4.0 * L[1] * L[2] * s, 3.0 * L[0] * L[3] * t,
                                          -4.0 * L[1] * L[3] * std::pow(L[0] + L[2], P - 2));
      },
      [](const double L[4]) {
        return std::pow(L[0], P) + 2.0 * std::pow(L[1], P - 1) * L[2] -
          1.5 * L[2] * std::pow(L[3], P - 1) + 0.8 * L[1] * L[3] + 0.3 * L[2];
      } };
    row(P, c.name, measure<P>(c, 0.3, rays), rays);
  };
  fullDegree(std::integral_constant<int, 2>());
  fullDegree(std::integral_constant<int, 3>());
  fullDegree(std::integral_constant<int, 4>());
  return 0;
}
