// Hexahedra solved in their own reference cube (HexahedronCell.h), against truth built here:
// - the Lagrange to Bernstein conversion against 1D Lagrange polynomials from their formula;
// - straight cells (parallelepipeds) holding a polynomial of Q_P: every hit against the first
//   root of the analytic field along the ray (sign scan and bisection in long double);
// - bent cells holding a linear field, which any isoparametric cell holds exactly: a ray aimed at
//   a point of the cell on the field's plane crosses the plane there only, so that point is the
//   hit; a ray aimed at the plane outside the cell misses;
// - contains / coordinates (the map's inverse), the exact gradient, and det J's sign: inverted
//   cells rendered, folded ones refused.
#include "tetdsr/cells/HexahedronCell.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace
{
using tetdsr::tensor::count;
using tetdsr::tensor::index;

/// The 1D Lagrange polynomial of equispaced node i of 0..P at x, from its formula.
long double lagrange(int P, int i, long double x)
{
  long double value = 1.0L;
  for (int m = 0; m <= P; ++m)
  {
    if (m != i)
    {
      value *= (P * x - m) / (i - m);
    }
  }
  return value;
}

/// A cell's tensor form from a map and a field given at the lattice points (a Lagrange cell),
/// through the core's conversion (toTensorForm with VTK_LAGRANGE_HEXAHEDRON's table, whose node
/// order comes from the lattice points themselves here).
template <int P>
struct Cell
{
  static constexpr int N = count(P);
  glm::dvec3 nodes[tetdsr::kMaxCellNodes];
  glm::dvec3 given[tetdsr::kMaxCellNodes]; ///< the nodes as given (VTK's order)
  double values[tetdsr::kMaxCellNodes];

  template <class Map, class Field>
  Cell(Map map, Field field)
  {
    const tetdsr::HexahedronNodes* table = nullptr;
    EXPECT_EQ(tetdsr::hexahedronNodesOf(72, N, table), 0);
    for (int n = 0; n < N; ++n)
    {
      const auto& r = table->nodePoints[static_cast<std::size_t>(n)];
      nodes[n] = given[n] = map(glm::dvec3(r[0], r[1], r[2]));
      values[n] = field(nodes[n]);
    }
    tetdsr::toTensorForm(*table, nodes);
    tetdsr::toTensorForm(*table, values);
  }

  /// The map at a parametric point, by the Lagrange nodes' formula (independent of the forms):
  /// sum over the lattice of map(lattice point) * product of 1D Lagrange polynomials.
  template <class Map>
  static glm::dvec3 lagrangeMap(Map map, const glm::dvec3& r)
  {
    glm::dvec3 x(0.0);
    for (int k = 0; k <= P; ++k)
      for (int j = 0; j <= P; ++j)
        for (int i = 0; i <= P; ++i)
        {
          const long double w = lagrange(P, i, r.x) * lagrange(P, j, r.y) * lagrange(P, k, r.z);
          x += static_cast<double>(w) * map(glm::dvec3(i, j, k) / static_cast<double>(P));
        }
    return x;
  }
};

glm::dvec3 bend(const glm::dvec3& x)
{
  // Bends the unit cube (0.06 of its size): every hexahedron of order >= 1 sampling it is curved.
  return glm::dvec3(x.x + 0.06 * std::sin(3.0 * x.y + 0.4), x.y + 0.05 * std::sin(2.5 * x.z),
    x.z + 0.06 * std::sin(2.0 * x.x + 1.0) + 0.3 * x.x);
}

template <int P, bool Curved>
bool intersect(const Cell<P>& cell, const tetdsr::Ray& ray, double iso, tetdsr::SurfaceHit& hit, bool& certified)
{
  std::vector<double> coefficients(tetdsr::HexahedronCell<P, Curved>::kRecordCoefficients);
  tetdsr::CellRecord record{};
  tetdsr::HexahedronCell<P, Curved>::record(cell.nodes, cell.values, record, coefficients.data());
  const tetdsr::IsoValues isoValues({ iso });
  return tetdsr::HexahedronCell<P, Curved>::intersect(record, ray, isoValues, 0, 1, 0.0, 1e300, hit, certified);
}

template <int P>
void conversionMatchesLagrange()
{
  // f = a polynomial of Q_P with every coefficient in play.
  auto field = [](const glm::dvec3& x) {
    return std::pow(x.x - 0.3, P) * (x.y + 0.2) - std::pow(x.y, P) * x.z + 0.7 * std::pow(x.z - 0.5, P) * x.x;
  };
  const Cell<P> cell([](const glm::dvec3& r) { return r; }, field);
  std::mt19937_64 random(P);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 50; ++trial)
  {
    const double x[3] = { unit(random), unit(random), unit(random) };
    const double got = tetdsr::tensor::evaluate<P>(cell.values, x);
    const double expected = field(glm::dvec3(x[0], x[1], x[2]));
    EXPECT_NEAR(got, expected, 1e-13) << "order " << P << ": the tensor form at a random point";
  }
}

TEST(Hexahedron, LagrangeToBernsteinConversion)
{
  conversionMatchesLagrange<1>();
  conversionMatchesLagrange<2>();
  conversionMatchesLagrange<3>();
  conversionMatchesLagrange<4>();
}

/// The first root in [from, to] of g along the ray (scan of 20,000 steps, then bisection in
/// long double); -1 if none.
template <class Field>
double firstRoot(Field g, const tetdsr::Ray& ray, double from, double to)
{
  const int steps = 20000;
  auto at = [&](long double t) { return static_cast<long double>(g(ray.origin + static_cast<double>(t) * ray.direction)); };
  long double previousT = from;
  long double previous = at(from);
  for (int k = 1; k <= steps; ++k)
  {
    const long double t = from + (to - from) * static_cast<long double>(k) / steps;
    const long double value = at(t);
    if ((previous <= 0.0L) != (value <= 0.0L))
    {
      long double a = previousT, b = t;
      for (int i = 0; i < 80; ++i)
      {
        const long double m = 0.5L * (a + b);
        ((at(m) <= 0.0L) == (previous <= 0.0L) ? a : b) = m;
      }
      return static_cast<double>(0.5L * (a + b));
    }
    previousT = t;
    previous = value;
  }
  return -1.0;
}

template <int P>
void straightCellHoldsItsPolynomial()
{
  // A parallelepiped: x = A r + b.
  const glm::dmat3 A(glm::dvec3(1.1, 0.1, -0.2), glm::dvec3(0.2, 0.9, 0.1), glm::dvec3(-0.1, 0.3, 1.2));
  const glm::dvec3 b(0.3, -0.2, 0.5);
  const glm::dmat3 inverse = glm::inverse(A);
  auto map = [&](const glm::dvec3& r) { return A * r + b; };
  // A polynomial of Q_P in r (a sphere-like level set bent by a degree-P term).
  auto inReference = [](const glm::dvec3& r) {
    const glm::dvec3 d = r - glm::dvec3(0.5, 0.45, 0.55);
    return (P >= 2 ? d.x * d.x + d.y * d.y + d.z * d.z : d.x * d.y * d.z + 0.4 * d.x - 0.2 * d.y) +
      0.3 * std::pow(d.x, P) * std::pow(d.y + 0.1, P - 1);
  };
  auto field = [&](const glm::dvec3& x) { return inReference(inverse * (x - b)); };
  const Cell<P> cell(map, field);
  const double iso = P >= 2 ? 0.09 : 0.01;
  std::mt19937_64 random(11 + P);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < 300; ++trial)
  {
    const glm::dvec3 target = map(glm::dvec3(unit(random), unit(random), unit(random)));
    const glm::dvec3 direction = glm::normalize(glm::dvec3(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5));
    const tetdsr::Ray ray{ target - 4.0 * direction, direction };
    // The truth: the first crossing of the field along the ray within the cell: the ray's
    // stretch in the parallelepiped (slabs in r), then a scan of the analytic field there.
    const glm::dvec3 r0 = inverse * (ray.origin - b), dr = inverse * ray.direction;
    double from = 0.0, to = 1e300;
    for (int a = 0; a < 3; ++a)
    {
      double t0 = -r0[a] / dr[a], t1 = (1.0 - r0[a]) / dr[a];
      if (t0 > t1)
        std::swap(t0, t1);
      from = std::max(from, t0);
      to = std::min(to, t1);
    }
    const double tg = from < to ? firstRoot([&](const glm::dvec3& x) { return field(x) - iso; }, ray, from, to) : -1.0;
    tetdsr::SurfaceHit hit;
    bool certified = true;
    const bool found = intersect<P, false>(cell, ray, iso, hit, certified);
    // (A root within 1e-6 of the stretch's ends is left out: the scan's and the cell's widening
    // differ there.)
    const bool clear = tg < 0.0 || (tg > from + 1e-6 && tg < to - 1e-6);
    if (!clear)
    {
      continue;
    }
    if (tg >= 0.0)
    {
      ++hits;
      ASSERT_TRUE(found) << "order " << P << " ray " << trial << ": expected a hit at t = " << tg;
      EXPECT_NEAR(hit.t, tg, 1e-10) << "order " << P << " ray " << trial;
      EXPECT_TRUE(certified);
      // The gradient: the analytic field's by central differences (the field is smooth).
      const glm::dvec3 p = ray.origin + hit.t * ray.direction;
      const double h6 = 1e-6;
      const glm::dvec3 numeric((field(p + glm::dvec3(h6, 0, 0)) - field(p - glm::dvec3(h6, 0, 0))) / (2 * h6),
        (field(p + glm::dvec3(0, h6, 0)) - field(p - glm::dvec3(0, h6, 0))) / (2 * h6),
        (field(p + glm::dvec3(0, 0, h6)) - field(p - glm::dvec3(0, 0, h6))) / (2 * h6));
      EXPECT_LT(glm::length(hit.gradient - numeric), 1e-6 * (1.0 + glm::length(numeric)));
    }
    else
    {
      ++misses;
      EXPECT_FALSE(found) << "order " << P << " ray " << trial << ": expected no hit, got t = " << hit.t;
    }
  }
  EXPECT_GT(hits, 50) << "order " << P;
  EXPECT_GT(misses, 20) << "order " << P;
}

TEST(Hexahedron, StraightCellsHoldTheirPolynomials)
{
  straightCellHoldsItsPolynomial<1>();
  straightCellHoldsItsPolynomial<2>();
  straightCellHoldsItsPolynomial<3>();
  straightCellHoldsItsPolynomial<4>();
}

template <int P>
void bentCellHoldsAPlane()
{
  std::mt19937_64 random(29 + P);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int hits = 0, misses = 0, uncertified = 0;
  for (int trial = 0; trial < 200; ++trial)
  {
    // A point of the cell (its parametric point inside, or 0.03 or more outside: then the map's
    // extension puts it outside the cell), a plane through it, and a ray aimed at it.
    const bool outside = trial % 4 == 3;
    glm::dvec3 r(unit(random), unit(random), unit(random));
    if (outside)
    {
      const int axis = trial % 3;
      r[axis] = r[axis] < 0.5 ? -0.03 - 0.1 * unit(random) : 1.03 + 0.1 * unit(random);
    }
    const glm::dvec3 p = Cell<P>::lagrangeMap(bend, r);
    const glm::dvec3 normal = glm::normalize(glm::dvec3(unit(random) - 0.5, unit(random) - 0.5, unit(random) + 0.2));
    const Cell<P> cell(bend, [&](const glm::dvec3& x) { return glm::dot(normal, x - p) + 0.25; });
    glm::dvec3 direction = glm::normalize(glm::dvec3(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5));
    if (std::abs(glm::dot(direction, normal)) < 0.05)
    {
      continue; // nearly in the plane
    }
    const tetdsr::Ray ray{ p - 3.0 * direction, direction };
    tetdsr::SurfaceHit hit;
    bool certified = true;
    const bool found = intersect<P, true>(cell, ray, 0.25, hit, certified);
    if (outside)
    {
      ++misses;
      EXPECT_FALSE(found) << "order " << P << " ray " << trial << ": expected no hit outside the cell";
      continue;
    }
    ++hits;
    ASSERT_TRUE(found) << "order " << P << " ray " << trial << ": expected the hit at the cell's point";
    EXPECT_NEAR(hit.t, 3.0, 1e-11) << "order " << P << " ray " << trial;
    EXPECT_LT(glm::length(glm::normalize(hit.gradient) - normal), 1e-10) << "order " << P;
    uncertified += !certified;
    // The map's inverse: contains gives r back.
    double L[4];
    glm::dvec3 nodes[tetdsr::kMaxCellNodes];
    std::copy(cell.nodes, cell.nodes + count(P), nodes);
    ASSERT_TRUE((tetdsr::HexahedronCell<P, true>::contains(nodes, p, L))) << "order " << P;
    EXPECT_LT(glm::length(glm::dvec3(L[1], L[2], L[3]) - r), 1e-9) << "order " << P;
  }
  EXPECT_GT(hits, 100);
  EXPECT_GT(misses, 30);
  EXPECT_EQ(uncertified, 0) << "order " << P << ": every hit certified";
}

TEST(Hexahedron, BentCellsHoldAPlane)
{
  bentCellHoldsAPlane<1>();
  bentCellHoldsAPlane<2>();
  bentCellHoldsAPlane<3>();
  bentCellHoldsAPlane<4>();
}

TEST(Hexahedron, JacobianSign)
{
  const tetdsr::HexahedronNodes* q2 = nullptr;
  const tetdsr::HexahedronNodes* q3 = nullptr;
  ASSERT_EQ(tetdsr::hexahedronNodesOf(72, 27, q2), 0);
  ASSERT_EQ(tetdsr::hexahedronNodesOf(72, 64, q3), 0);
  auto value = [](const glm::dvec3& x) { return x.x; };
  // Bent: valid and curved.
  const Cell<2> bent(bend, value);
  EXPECT_EQ((tetdsr::HexahedronCell<2, false>::validate(bent.nodes, bent.given, 0x1p-52, *q2)),
    tetdsr::kValid | tetdsr::kCurved);
  // Mirrored (x -> -x): inverted, still rendered.
  const Cell<2> mirrored([](const glm::dvec3& r) { const glm::dvec3 x = bend(r); return glm::dvec3(-x.x, x.y, x.z); }, value);
  EXPECT_EQ((tetdsr::HexahedronCell<2, false>::validate(mirrored.nodes, mirrored.given, 0x1p-52, *q2)),
    tetdsr::kValid | tetdsr::kCurved | tetdsr::kInverted);
  // Folded: the middle pushed through the face x = 1 (det J changes sign inside).
  const Cell<2> folded([](const glm::dvec3& r) {
    const double bump = 16.0 * r.x * (1.0 - r.x) * r.y * (1.0 - r.y) * r.z * (1.0 - r.z);
    return glm::dvec3(r.x + 1.5 * bump, r.y, r.z);
  }, value);
  EXPECT_EQ((tetdsr::HexahedronCell<2, false>::validate(folded.nodes, folded.given, 0x1p-52, *q2)), tetdsr::kTangled);
  // Straight: valid, not curved.
  const Cell<3> straight([](const glm::dvec3& r) { return 2.0 * r + glm::dvec3(0.1, 0.2, 0.3); }, value);
  EXPECT_EQ((tetdsr::HexahedronCell<3, false>::validate(straight.nodes, straight.given, 0x1p-52, *q3)), tetdsr::kValid);
}

} // namespace
