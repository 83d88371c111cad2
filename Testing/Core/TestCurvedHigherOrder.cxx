// Curved (isoparametric) tetrahedra of order P = 3 and 4 (CurvedHigherOrderTetCell) against
// analytic truth.
//
// The cells: the map x(L) = A(L) + eps * bump(L), A affine and bump a polynomial of degree P in the
// barycentric coordinates L, and fields given as functions of L (linear in x, or polynomials of
// degree P in L). Interpolated at the cell's nodes and converted to Bernstein form
// (HigherOrderTet<P>::toBezier), they are represented exactly. The truth never uses the code
// under test: a world point's preimage is found by Newton on the analytic map (finite-difference
// Jacobian, exact residual), a linear field's isosurface is the plane a . x = c, and a field's
// crossings along a ray are found by dense sampling of f(x^-1(o + t d)) and bisection.
#include "tetdsr/cells/CurvedHigherOrderTetCell.h"
#include "tetdsr/cells/CurvedTetCell.h"
#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/math/QuadraticTet.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

namespace
{
using Map = std::function<glm::dvec3(const double L[4])>;
using Field = std::function<double(const double L[4])>;

/// A straight tetrahedron with edges about 1, positively oriented.
const glm::dvec3 kVertices[4] = { { 0.1, 0.2, 0.0 }, { 1.1, 0.1, 0.2 }, { 0.3, 1.0, 0.1 },
  { 0.2, 0.3, 1.05 } };

glm::dvec3 affine(const double L[4])
{
  glm::dvec3 x(0.0);
  for (int k = 0; k < 4; ++k)
    x += L[k] * kVertices[k];
  return x;
}

/// A bump of degree P in L, zero at the vertices.
template <int P>
glm::dvec3 bump(const double L[4])
{
  const double s = std::pow(L[0] + 2.0 * L[3], P - 2), t = std::pow(L[1] + 0.5 * L[2], P - 2),
               u = std::pow(L[0] + L[2], P - 2);
  return { 4.0 * L[1] * L[2] * s, 3.0 * L[0] * L[3] * t, -4.0 * L[1] * L[3] * u };
}

template <int P>
Map curvedMap(double eps)
{
  return [eps](const double L[4]) { return affine(L) + eps * bump<P>(L); };
}

/// A cell of order P: its control points and field coefficients (Bezier layout, VTK order).
template <int P>
struct Cell
{
  static constexpr int kNodes = tetdsr::latticeCount(P);
  glm::dvec3 nodes[kNodes];
  double values[kNodes];

  Cell(const Map& map, const Field& field)
  {
    for (int n = 0; n < kNodes; ++n)
    {
      double L[4];
      tetdsr::HigherOrderTet<P>::nodePoint(n, L);
      nodes[n] = map(L);
      values[n] = field(L);
    }
    tetdsr::HigherOrderTet<P>::toBezier(nodes);
    tetdsr::HigherOrderTet<P>::toBezier(values);
  }
};

/// The truth's inversion: Newton on map(L) = x from `L` (in place), y = (L_1, L_2, L_3), with a
/// central-difference Jacobian (the residual is exact, so the root is to rounding). False if it
/// does not converge.
bool invert(const Map& map, const glm::dvec3& x, double L[4])
{
  for (int iteration = 0; iteration < 60; ++iteration)
  {
    const glm::dvec3 residual = map(L) - x;
    glm::dmat3 J;
    const double h = 1e-6;
    for (int j = 1; j <= 3; ++j)
    {
      double plus[4] = { L[0] - h, L[1], L[2], L[3] }, minus[4] = { L[0] + h, L[1], L[2], L[3] };
      plus[j] += h;
      minus[j] -= h;
      J[j - 1] = (map(plus) - map(minus)) / (2.0 * h);
    }
    const glm::dvec3 step = glm::inverse(J) * residual;
    L[1] -= step.x;
    L[2] -= step.y;
    L[3] -= step.z;
    L[0] = 1.0 - L[1] - L[2] - L[3];
    if (!(glm::length(step) < 1e3))
      return false;
    if (glm::length(step) < 1e-15 && glm::length(map(L) - x) < 1e-13)
      return true;
  }
  return glm::length(map(L) - x) < 1e-13;
}

/// The preimage of x from the straight tet's guess; false if Newton fails.
bool preimage(const Map& map, const glm::dvec3& x, double L[4])
{
  tetdsr::TetFrame frame;
  tetdsr::TetFrame::fromVertices(kVertices, frame);
  frame.barycentric(x, L);
  if (invert(map, x, L))
    return true;
  double centre[4] = { 0.25, 0.25, 0.25, 0.25 };
  std::copy(centre, centre + 4, L);
  return invert(map, x, L);
}

double smallest(const double L[4])
{
  return std::min({ L[0], L[1], L[2], L[3] });
}

/// A random barycentric point (uniform on the simplex).
double randomPoint(std::mt19937& random, double L[4])
{
  std::exponential_distribution<double> e(1.0);
  double sum = 0.0;
  for (int k = 0; k < 4; ++k)
    sum += (L[k] = e(random));
  for (int k = 0; k < 4; ++k)
    L[k] /= sum;
  return sum;
}

/// A ray from 3 units away towards the image of a random point of the cell.
tetdsr::Ray rayThroughCell(const Map& map, std::mt19937& random)
{
  double L[4];
  randomPoint(random, L);
  std::normal_distribution<double> normal(0.0, 1.0);
  const glm::dvec3 d = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
  return { map(L) - 3.0 * d, d };
}

/// The truth along a ray: the first t in [tMin, tMax] where f(x^-1(o + t d)) - c changes sign
/// with both neighbouring samples inside the cell by more than `band` (barycentric), refined by
/// bisection; -1 if none. `ambiguous` is set when a sign change or a zero was seen with a sample
/// within the band (the truth cannot tell there).
double sampledCrossing(const Map& map, const Field& field, double c, const tetdsr::Ray& ray,
  double tMin, double tMax, double band, bool& ambiguous)
{
  constexpr int kSamples = 1500;
  ambiguous = false;
  double previousT = 0.0, previousG = 0.0, previousInside = -1.0;
  double L[4];
  bool havePrevious = false;
  for (int s = 0; s <= kSamples; ++s)
  {
    const double t = tMin + (tMax - tMin) * s / kSamples;
    const glm::dvec3 x = ray.origin + t * ray.direction;
    // From the straight tet's guess each time: far outside the cell the map's extension folds,
    // and a continuation along the ray can follow a branch that is not the cell's.
    if (!preimage(map, x, L))
    {
      havePrevious = false;
      continue;
    }
    const double inside = smallest(L);
    const double g = field(L) - c;
    if (havePrevious && (inside > -band || previousInside > -band) && (g <= 0.0) != (previousG <= 0.0))
    {
      if (inside <= band || previousInside <= band)
      {
        ambiguous = true;
        return -1.0;
      }
      // Bisection between the samples (both inside, so the segment is).
      double lo = previousT, hi = t, gLo = previousG;
      double M[4];
      std::copy(L, L + 4, M);
      for (int k = 0; k < 100; ++k)
      {
        const double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi))
          break;
        invert(map, ray.origin + mid * ray.direction, M);
        const double gm = field(M) - c;
        if ((gm <= 0.0) == (gLo <= 0.0))
        {
          lo = mid;
          gLo = gm;
        }
        else
          hi = mid;
      }
      return 0.5 * (lo + hi);
    }
    previousT = t;
    previousG = g;
    previousInside = inside;
    havePrevious = true;
  }
  return -1.0;
}

/// A fixed polynomial of degree P in L (not a function of x), values of order 1.
template <int P>
double polynomialField(const double L[4])
{
  return std::pow(L[0], P) + 2.0 * std::pow(L[1], P - 1) * L[2] - 1.5 * L[2] * std::pow(L[3], P - 1) +
    0.8 * L[1] * L[3] + 0.3 * L[2];
}

template <int P>
void planeAgainstRayPlaneIntersection(double eps, int rays, unsigned seed)
{
  const Map map = curvedMap<P>(eps);
  const glm::dvec3 a = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  const Cell<P> cell(map, [&](const double L[4]) { return glm::dot(a, map(L)); });
  EXPECT_EQ(tetdsr::CurvedHigherOrderTetCell<P>::validate(cell.nodes, tetdsr::kValid | tetdsr::kCurved),
    tetdsr::kValid | tetdsr::kCurved)
    << "P " << P << " eps " << eps << ": a mildly curved cell is valid and not inverted";
  std::mt19937 random(seed);
  int hits = 0, compared = 0, band = 0, misses = 0, falseHits = 0, uncertified = 0;
  double depthError = 0.0, gradientError = 0.0;
  for (int r = 0; r < rays; ++r)
  {
    const tetdsr::Ray ray = rayThroughCell(map, random);
    // An iso-value through a random point of the cell: the plane cuts it.
    double Lc[4];
    randomPoint(random, Lc);
    const double c = glm::dot(a, map(Lc));
    const double along = glm::dot(a, ray.direction);
    if (std::abs(along) < 1e-3)
      continue; // grazing: the plane point is ill-conditioned
    const double tTrue = (c - glm::dot(a, ray.origin)) / along;
    double L[4];
    if (!preimage(map, ray.origin + tTrue * ray.direction, L) || std::abs(smallest(L)) < 1e-7)
    {
      ++band;
      continue;
    }
    ++compared;
    const bool inside = smallest(L) > 0.0;
    tetdsr::SurfaceHit hit;
    bool certified = true;
    const bool found = tetdsr::CurvedHigherOrderTetCell<P>::intersect(cell.nodes, cell.values,
      tetdsr::IsoValues({ c }), 0, 1, ray, 0.0, 1e30, hit, certified);
    if (inside && !found)
    {
      ++misses;
      std::printf("  P %d missed: expected t %.17g (preimage min L %.3g), got none\n", P, tTrue, smallest(L));
    }
    else if (!inside && found)
    {
      ++falseHits;
      std::printf("  P %d false hit: expected none (preimage min L %.3g), got t %.17g\n", P, smallest(L), hit.t);
    }
    else if (found)
    {
      ++hits;
      uncertified += !certified;
      depthError = std::max(depthError, std::abs(hit.t - tTrue));
      gradientError = std::max(gradientError, glm::length(hit.gradient - a));
    }
  }
  std::printf("P %d eps %.2f plane: %d compared, %d in the band, %d hits (%d uncertified); "
              "max depth error %.2e, max gradient error %.2e\n",
    P, eps, compared, band, hits, uncertified, depthError, gradientError);
  EXPECT_EQ(misses, 0);
  EXPECT_EQ(falseHits, 0);
  EXPECT_GT(hits, rays / 4) << "expected most rays through the cell to meet the plane";
  EXPECT_LE(depthError, 1e-9) << "expected the ray/plane depth within 1e-9 of the cell's size";
  EXPECT_LE(gradientError, 1e-9) << "expected the world gradient a of the linear field";
}

/// A field of degree P in L, several iso-values, windows [tMin, tLimit] cutting through the cell.
template <int P>
void polynomialFieldAgainstSampling(double eps, int rays, unsigned seed)
{
  const Map map = curvedMap<P>(eps);
  const Field field = polynomialField<P>;
  const Cell<P> cell(map, field);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Three level sets through the cell (ascending, as IsoValues::sorted() has them).
  std::vector<double> levels;
  for (int k = 0; k < 3; ++k)
  {
    double L[4];
    randomPoint(random, L);
    levels.push_back(field(L));
  }
  std::sort(levels.begin(), levels.end());
  int hits = 0, compared = 0, ambiguousRays = 0, wrong = 0;
  double pointError = 0.0, fieldError = 0.0;
  for (int r = 0; r < rays; ++r)
  {
    const tetdsr::Ray ray = rayThroughCell(map, random);
    // Half of the rays start inside the cell (tMin past its entry), some end early (tLimit).
    const double tMin = r % 2 ? 3.0 - 0.5 * unit(random) : 0.0;
    const double tLimit = r % 3 == 0 ? 3.0 + 0.3 * unit(random) : 1e30;
    const bool several = r % 4 == 1;
    const std::size_t first = several ? 0 : static_cast<std::size_t>(r % 3), last = several ? 3 : first + 1;
    double tTrue = -1.0;
    std::size_t levelTrue = 0;
    bool ambiguous = false;
    for (std::size_t k = first; k < last; ++k)
    {
      bool unsure;
      const double t = sampledCrossing(
        map, field, levels[k], ray, std::max(tMin, 1.5), std::min(tLimit, 4.5), 1e-6, unsure);
      ambiguous = ambiguous || unsure;
      if (t >= 0.0 && (tTrue < 0.0 || t < tTrue))
      {
        tTrue = t;
        levelTrue = k;
      }
    }
    if (ambiguous)
    {
      ++ambiguousRays;
      continue;
    }
    ++compared;
    tetdsr::SurfaceHit hit;
    bool certified = true;
    const bool found = tetdsr::CurvedHigherOrderTetCell<P>::intersect(
      cell.nodes, cell.values, tetdsr::IsoValues(levels), first, last, ray, tMin, tLimit, hit, certified);
    if (found != (tTrue >= 0.0) || (found && (std::abs(hit.t - tTrue) > 1e-9 || hit.isoIndex != levelTrue)))
    {
      ++wrong;
      std::printf("  P %d ray %d [%.6g, %.6g] levels [%zu, %zu): expected %s t %.17g level %zu, got %s t %.17g level %zu\n",
        P, r, tMin, tLimit, first, last, tTrue >= 0.0 ? "hit" : "none", tTrue, levelTrue,
        found ? "hit" : "none", hit.t, hit.isoIndex);
      continue;
    }
    if (!found)
      continue;
    ++hits;
    // The point equations at the hit's preimage.
    const glm::dvec3 x = ray.origin + hit.t * ray.direction;
    double L[4];
    ASSERT_TRUE(preimage(map, x, L));
    pointError = std::max(pointError, glm::length(map(L) - x));
    fieldError = std::max(fieldError, std::abs(field(L) - levels[hit.isoIndex]));
    EXPECT_GE(smallest(L), -1e-9) << "expected the hit's preimage inside the cell";
    EXPECT_GE(hit.t, tMin);
    EXPECT_LE(hit.t, tLimit);
  }
  std::printf("P %d eps %.2f degree-%d field: %d compared, %d ambiguous, %d hits; "
              "max |X(L) - x| %.2e, max |f(L) - c| %.2e\n",
    P, eps, P, compared, ambiguousRays, hits, pointError, fieldError);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(hits, rays / 8);
  EXPECT_LE(fieldError, 1e-12) << "expected f(L_hit) = c to 1e-12 of the field's scale (about 1)";
  EXPECT_LE(pointError, 1e-12);
}

/// A straight cell of order P put through the curved path: the field along the ray is a
/// polynomial of degree P in t, whose first root in the cell's interval is found by sampling.
template <int P>
void straightCellAgainstAnalytic(int rays, unsigned seed)
{
  const Map map = curvedMap<P>(0.0);
  const Field field = polynomialField<P>;
  const Cell<P> cell(map, field);
  EXPECT_EQ(tetdsr::CurvedHigherOrderTetCell<P>::validate(cell.nodes, tetdsr::kValid), tetdsr::kValid);
  tetdsr::TetFrame frame;
  tetdsr::TetFrame::fromVertices(kVertices, frame);
  std::mt19937 random(seed);
  int hits = 0, wrong = 0;
  double depthError = 0.0;
  for (int r = 0; r < rays; ++r)
  {
    const tetdsr::Ray ray = rayThroughCell(map, random);
    double Lc[4];
    randomPoint(random, Lc);
    const double c = field(Lc); // a level set through the cell
    // The ray's interval in the tet: L(t) = L(o) + t dL, every L_k >= 0.
    double L0[4], dL[4];
    frame.barycentric(ray.origin, L0);
    frame.barycentricDirection(ray.direction, dL);
    double tIn = 0.0, tOut = 1e30;
    for (int k = 0; k < 4; ++k)
    {
      if (dL[k] != 0.0)
      {
        const double t = -L0[k] / dL[k];
        if (dL[k] > 0.0)
          tIn = std::max(tIn, t);
        else
          tOut = std::min(tOut, t);
      }
    }
    auto g = [&](double t) {
      const double L[4] = { L0[0] + t * dL[0], L0[1] + t * dL[1], L0[2] + t * dL[2], L0[3] + t * dL[3] };
      return field(L) - c;
    };
    double tTrue = -1.0;
    constexpr int kSamples = 4000;
    for (int s = 0; s < kSamples && tIn < tOut; ++s)
    {
      double lo = tIn + (tOut - tIn) * s / kSamples, hi = tIn + (tOut - tIn) * (s + 1) / kSamples;
      if ((g(lo) <= 0.0) != (g(hi) <= 0.0))
      {
        for (int k = 0; k < 200 && 0.5 * (lo + hi) > lo && 0.5 * (lo + hi) < hi; ++k)
          ((g(0.5 * (lo + hi)) <= 0.0) == (g(lo) <= 0.0) ? lo : hi) = 0.5 * (lo + hi);
        tTrue = 0.5 * (lo + hi);
        break;
      }
    }
    tetdsr::SurfaceHit hit;
    bool certified = true;
    const bool found = tetdsr::CurvedHigherOrderTetCell<P>::intersect(
      cell.nodes, cell.values, tetdsr::IsoValues({ c }), 0, 1, ray, 0.0, 1e30, hit, certified);
    if (tTrue < 0.0 && found && std::abs(g(hit.t)) < 1e-9 && hit.t >= tIn - 1e-9 && hit.t <= tOut + 1e-9)
      continue; // a tangent touch the sampling did not see as a sign change
    if (found != (tTrue >= 0.0) || (found && std::abs(hit.t - tTrue) > 1e-12))
    {
      ++wrong;
      std::printf("  P %d straight ray %d: expected %s t %.17g, got %s t %.17g\n", P, r,
        tTrue >= 0.0 ? "hit" : "none", tTrue, found ? "hit" : "none", hit.t);
      continue;
    }
    if (found)
    {
      ++hits;
      depthError = std::max(depthError, std::abs(hit.t - tTrue));
    }
  }
  std::printf("P %d straight cell, degree-%d field: %d rays, %d hits, max depth error %.2e\n", P,
    P, rays, hits, depthError);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(hits, rays / 5);
}

/// Constant fields: equal to the iso-value, the crossing is the ray's stretch in the cell (from
/// tMin when it starts inside); any other value, no crossing.
template <int P>
void constantFields()
{
  const Map map = curvedMap<P>(0.0);
  const Cell<P> cell(map, [](const double*) { return 0.75; });
  tetdsr::TetFrame frame;
  tetdsr::TetFrame::fromVertices(kVertices, frame);
  std::mt19937 random(11);
  for (int r = 0; r < 40; ++r)
  {
    const tetdsr::Ray ray = rayThroughCell(map, random);
    double L0[4], dL[4];
    frame.barycentric(ray.origin, L0);
    frame.barycentricDirection(ray.direction, dL);
    double tIn = 0.0, tOut = 1e30;
    for (int k = 0; k < 4; ++k)
    {
      const double t = -L0[k] / dL[k];
      (dL[k] > 0.0 ? tIn : tOut) = dL[k] > 0.0 ? std::max(tIn, t) : std::min(tOut, t);
    }
    tetdsr::SurfaceHit hit;
    bool certified;
    ASSERT_TRUE(tetdsr::CurvedHigherOrderTetCell<P>::intersect(cell.nodes, cell.values,
      tetdsr::IsoValues({ 0.5, 0.75 }), 0, 2, ray, 0.0, 1e30, hit, certified));
    EXPECT_EQ(hit.isoIndex, 1u);
    EXPECT_NEAR(hit.t, tIn, 1e-9) << "expected the entry";
    EXPECT_NEAR(hit.regionEnd, tOut, 1e-8) << "expected the exit";
    EXPECT_EQ(hit.gradient, glm::dvec3(0.0));
    const double tMin = 0.5 * (tIn + tOut);
    ASSERT_TRUE(tetdsr::CurvedHigherOrderTetCell<P>::intersect(cell.nodes, cell.values,
      tetdsr::IsoValues({ 0.75 }), 0, 1, ray, tMin, 1e30, hit, certified));
    EXPECT_NEAR(hit.t, tMin, 1e-12) << "expected the start inside the cell";
    EXPECT_NEAR(hit.regionEnd, tOut, 1e-8);
    EXPECT_FALSE(tetdsr::CurvedHigherOrderTetCell<P>::intersect(cell.nodes, cell.values,
      tetdsr::IsoValues({ 0.5 }), 0, 1, ray, 0.0, 1e30, hit, certified))
      << "a constant field 0.75 has no crossing of 0.5";
  }
}

/// Validation: a control point pushed through the opposite face folds the map (tangled); mirrored
/// cells are inverted, and a valid cell's kInverted is cleared.
template <int P>
void validation()
{
  using Cell_ = tetdsr::CurvedHigherOrderTetCell<P>;
  const Map map = curvedMap<P>(0.1);
  Cell<P> cell(map, [](const double*) { return 0.0; });
  const std::uint16_t valid = tetdsr::kValid | tetdsr::kCurved;
  EXPECT_EQ(Cell_::validate(cell.nodes, valid | tetdsr::kInverted), valid)
    << "expected kInverted cleared for a positive det J";
  // Mirrored: det J < 0 throughout.
  Cell<P> mirrored = cell;
  for (auto& node : mirrored.nodes)
    node.x = -node.x;
  EXPECT_EQ(Cell_::validate(mirrored.nodes, valid), valid | tetdsr::kInverted);
  // A control point next to vertex 0 on its edge to vertex 1 (VTK node 4), pushed through the
  // face opposite vertex 0 (beyond the face (1, 2, 3)).
  Cell<P> folded = cell;
  const glm::dvec3 faceCentre = (cell.nodes[1] + cell.nodes[2] + cell.nodes[3]) / 3.0;
  folded.nodes[4] = faceCentre + 0.5 * (faceCentre - cell.nodes[0]);
  EXPECT_EQ(Cell_::validate(folded.nodes, valid), tetdsr::kTangled);
  // A vertex's neighbours collapsed onto it: det J vanishes at the vertex.
  Cell<P> degenerate = cell;
  degenerate.nodes[4] = degenerate.nodes[0];
  EXPECT_EQ(Cell_::validate(degenerate.nodes, valid), tetdsr::kTangled)
    << "det J is 0 at vertex 0 when a neighbouring control point coincides with it";
  // The box: the control points'.
  glm::dvec3 lo, hi;
  ASSERT_TRUE(Cell_::extent(cell.nodes, lo, hi));
  for (const auto& node : cell.nodes)
  {
    EXPECT_TRUE(glm::all(glm::lessThanEqual(lo, node)) && glm::all(glm::lessThanEqual(node, hi)));
  }
  Cell<P> broken = cell;
  broken.nodes[5].y = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(Cell_::extent(broken.nodes, lo, hi));
}

/// Point location, the map's extension and the gradient against the analytic map.
template <int P>
void locationAndGradient(double eps)
{
  using Cell_ = tetdsr::CurvedHigherOrderTetCell<P>;
  const Map map = curvedMap<P>(eps);
  const glm::dvec3 a(0.3, -0.5, 0.8);
  const Cell<P> cell(map, [&](const double L[4]) { return glm::dot(a, map(L)) + 2.0; });
  std::mt19937 random(5);
  for (int trial = 0; trial < 60; ++trial)
  {
    double L[4];
    randomPoint(random, L);
    const glm::dvec3 x = map(L);
    double found[4];
    ASSERT_TRUE(Cell_::contains(cell.nodes, x, found)) << "expected a point of the cell inside";
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(found[k], L[k], 1e-10);
    EXPECT_LT(glm::length(Cell_::gradient(cell.nodes, cell.values, L) - a), 1e-10)
      << "expected the linear field's gradient a";
    // Outside: L moved past face 0, the preimage of the extension.
    double M[4] = { -0.05, 0.0, 0.0, 0.0 };
    const double rest = 1.05 / (L[1] + L[2] + L[3]);
    for (int k = 1; k < 4; ++k)
      M[k] = L[k] * rest;
    const glm::dvec3 y = map(M);
    EXPECT_FALSE(Cell_::contains(cell.nodes, y, found)) << "expected a point past face 0 outside";
    Cell_::coordinates(cell.nodes, y, found);
    EXPECT_LT(glm::length(map(found) - y), 1e-12) << "expected the map's extension's preimage";
  }
}
/// A quadratic map and field written at order P (degree-elevated, exactly): the same cell as the
/// 10-node curved tet, so the same hits as CurvedTetCell's.
template <int P>
void sameAsQuadratic(int rays, unsigned seed)
{
  const Map map = [](const double L[4]) {
    const glm::dvec3 x = affine(L);
    return glm::dvec3(x.x + 0.5 * x.y * x.y, x.y + 0.5 * x.z * x.z, x.z);
  };
  const Field field = [&](const double L[4]) {
    const glm::dvec3 q = affine(L) - glm::dvec3(0.5, 0.4, 0.3);
    return glm::dot(q, q);
  };
  const Cell<P> cell(map, field);
  glm::dvec3 quadraticNodes[10];
  double quadraticValues[10];
  for (int n = 0; n < 10; ++n)
  {
    double L[4] = { 0.0, 0.0, 0.0, 0.0 };
    if (n < 4)
      L[n] = 1.0;
    else
      L[tetdsr::kEdgeVertices[n - 4][0]] = L[tetdsr::kEdgeVertices[n - 4][1]] = 0.5;
    quadraticNodes[n] = map(L);
    quadraticValues[n] = field(L);
  }
  std::mt19937 random(seed);
  int hits = 0, wrong = 0;
  for (int r = 0; r < rays; ++r)
  {
    const tetdsr::Ray ray = rayThroughCell(map, random);
    const tetdsr::IsoValues iso({ 0.05 + 0.02 * (r % 5) });
    tetdsr::SurfaceHit expected, got;
    bool certified;
    const bool quadratic = tetdsr::CurvedTetCell::intersect(
      quadraticNodes, quadraticValues, iso, 0, 1, ray, 0.0, 1e30, expected, certified);
    const bool found = tetdsr::CurvedHigherOrderTetCell<P>::intersect(
      cell.nodes, cell.values, iso, 0, 1, ray, 0.0, 1e30, got, certified);
    if (found != quadratic || (found && (std::abs(got.t - expected.t) > 1e-12 ||
                                          glm::length(got.gradient - expected.gradient) >
                                            1e-10 * glm::length(expected.gradient))))
    {
      ++wrong;
      std::printf("  P %d ray %d: expected %s t %.17g (the quadratic cell's), got %s t %.17g\n", P,
        r, quadratic ? "hit" : "none", expected.t, found ? "hit" : "none", got.t);
    }
    hits += found;
  }
  std::printf("P %d as the quadratic cell: %d rays, %d hits\n", P, rays, hits);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(hits, rays / 4);
}
} // namespace

TEST(CurvedHigherOrderTet, DegreeElevatedQuadraticCellAsCurvedTetCell)
{
  sameAsQuadratic<3>(300, 9);
  sameAsQuadratic<4>(300, 10);
}

TEST(CurvedHigherOrderTet, PlaneAgainstRayPlaneIntersection)
{
  planeAgainstRayPlaneIntersection<3>(0.1, 400, 1);
  planeAgainstRayPlaneIntersection<3>(0.25, 400, 2);
  planeAgainstRayPlaneIntersection<4>(0.1, 400, 3);
  planeAgainstRayPlaneIntersection<4>(0.25, 400, 4);
}

TEST(CurvedHigherOrderTet, PolynomialFieldAgainstSampling)
{
  polynomialFieldAgainstSampling<3>(0.2, 150, 5);
  polynomialFieldAgainstSampling<4>(0.2, 150, 6);
}

TEST(CurvedHigherOrderTet, StraightCellsAgainstAnalytic)
{
  straightCellAgainstAnalytic<3>(300, 7);
  straightCellAgainstAnalytic<4>(300, 8);
}

TEST(CurvedHigherOrderTet, ConstantFields)
{
  constantFields<3>();
  constantFields<4>();
}

TEST(CurvedHigherOrderTet, TangledInvertedAndBox)
{
  validation<3>();
  validation<4>();
}

TEST(CurvedHigherOrderTet, LocationAndGradient)
{
  locationAndGradient<3>(0.2);
  locationAndGradient<4>(0.2);
}
