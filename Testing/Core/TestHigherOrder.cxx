// Core tests of the tetrahedra of orders 3 and 4 (and of orders 1 and 2 read as Lagrange and
// Bezier cells) against analytic truth: a polynomial of degree <= P is reproduced exactly by
// straight cells of order P, so along each ray the truth is the first root of the polynomial
// itself, found here by dense sampling and bisection of the analytic field (not of the mesh).
#include "HigherOrderLattice.h"

#include "tetdsr/common/Camera.h"
#include "tetdsr/input/MeshInput.h"
#include "tetdsr/index/Scene.h"
#include "tetdsr/index/SurfaceIndex.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <string>

using tetdsr_test::HigherOrderCell;
using tetdsr_test::HigherOrderLattice;
using tetdsr_test::makeHigherOrderLattice;

namespace
{
/// An analytic field with its gradient.
struct Field
{
  std::function<double(const glm::dvec3&)> value;
  std::function<glm::dvec3(const glm::dvec3&)> gradient;
  double isoValue;
  double scale; ///< a typical magnitude of the field near the surface (for the grazing band)
};

/// A sphere deformed by a cubic term: f = |x - c|^2 + k (x - c)_x^3 (degree 3), iso r^2.
Field cubicBlob()
{
  const glm::dvec3 c(0.48, 0.52, 0.5);
  const double k = 1.5;
  Field f;
  f.value = [=](const glm::dvec3& x) {
    const glm::dvec3 d = x - c;
    return glm::dot(d, d) + k * d.x * d.x * d.x;
  };
  f.gradient = [=](const glm::dvec3& x) {
    const glm::dvec3 d = x - c;
    return 2.0 * d + glm::dvec3(3.0 * k * d.x * d.x, 0.0, 0.0);
  };
  f.isoValue = 0.3 * 0.3;
  f.scale = 0.09;
  return f;
}

/// A torus (degree 4): f = (|x - c|^2 + R^2 - r^2)^2 - 4 R^2 ((x - c)_x^2 + (x - c)_y^2), iso 0.
Field torus()
{
  const glm::dvec3 c(0.5, 0.47, 0.52);
  const double R = 0.28, r = 0.11;
  Field f;
  f.value = [=](const glm::dvec3& x) {
    const glm::dvec3 d = x - c;
    const double s = glm::dot(d, d) + R * R - r * r;
    return s * s - 4.0 * R * R * (d.x * d.x + d.y * d.y);
  };
  f.gradient = [=](const glm::dvec3& x) {
    const glm::dvec3 d = x - c;
    const double s = glm::dot(d, d) + R * R - r * r;
    return 4.0 * s * d - 8.0 * R * R * glm::dvec3(d.x, d.y, 0.0);
  };
  f.isoValue = 0.0;
  f.scale = 4.0 * R * R * r * r;
  return f;
}

/// A linear field (exact in cells of every order).
Field plane()
{
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  Field f;
  f.value = [=](const glm::dvec3& x) { return glm::dot(n, x); };
  f.gradient = [=](const glm::dvec3&) { return n; };
  f.isoValue = glm::dot(n, glm::dvec3(0.41, 0.53, 0.47));
  f.scale = 1.0;
  return f;
}

/// The first crossing of the field's iso-value along the ray inside the unit cube (the mesh),
/// by sampling and bisection of the analytic field. `grazing` when the ray comes within the
/// band of the iso-value without crossing it there first (tangent rays: either answer is right).
bool truthHit(const Field& field, const tetdsr::Ray& ray, double& t, bool& grazing)
{
  // The ray's stretch in [0, 1]^3.
  double t0 = 0.0, t1 = 1e30;
  for (int a = 0; a < 3; ++a)
  {
    const double inverse = 1.0 / ray.direction[a];
    double near = (0.0 - ray.origin[a]) * inverse, far = (1.0 - ray.origin[a]) * inverse;
    if (near > far)
    {
      std::swap(near, far);
    }
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
  }
  grazing = false;
  if (!(t0 < t1))
  {
    return false;
  }
  const int samples = 4000;
  const double band = 1e-5 * field.scale;
  auto g = [&](double s) { return field.value(ray.origin + s * ray.direction) - field.isoValue; };
  auto at = [&](int k) { return t0 + (t1 - t0) * k / samples; };
  // A sample within the band at a local minimum of |g| without a sign change: a tangent ray.
  auto touches = [&](double a, double b, double c) {
    return std::abs(b) < band && (a < 0.0) == (b < 0.0) && (b < 0.0) == (c < 0.0) &&
      std::abs(b) <= std::abs(a) && std::abs(b) <= std::abs(c);
  };
  double previous = g(at(0));
  for (int k = 1; k <= samples; ++k)
  {
    const double value = g(at(k));
    if ((value < 0.0) != (previous < 0.0))
    {
      double lo = at(k - 1), hi = at(k), fLo = previous;
      for (int it = 0; it < 200; ++it)
      {
        const double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi))
        {
          break;
        }
        if ((g(mid) < 0.0) == (fLo < 0.0))
        {
          lo = mid;
        }
        else
        {
          hi = mid;
        }
      }
      t = 0.5 * (lo + hi);
      return true;
    }
    if (k < samples && touches(previous, value, g(at(k + 1))))
    {
      grazing = true;
    }
    previous = value;
  }
  return false;
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b)
{
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0));
}

struct Comparison
{
  int covered = 0, wrongCoverage = 0, grazing = 0;
  double worstDepth = 0.0, worstAngle = 0.0;
};

/// Every pixel of a perspective view of the mesh against truthHit.
Comparison compareWithTruth(const HigherOrderLattice& mesh, const Field& field, int pixels)
{
  const tetdsr::Scene scene(mesh.view());
  const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ field.isoValue }));
  tetdsr::Camera camera;
  camera.position = glm::dvec3(1.9, 1.3, 2.4);
  camera.focalPoint = glm::dvec3(0.5);
  camera.viewUp = glm::dvec3(0.0, 1.0, 0.0);
  camera.viewAngleDegrees = 24.0;
  const tetdsr::RayGenerator rays(camera, pixels, pixels);
  Comparison result;
  for (int j = 0; j < pixels; ++j)
  {
    for (int i = 0; i < pixels; ++i)
    {
      const tetdsr::Ray ray = rays.pixelRay(i, j);
      double tTrue = 0.0;
      bool grazing = false;
      const bool expected = truthHit(field, ray, tTrue, grazing);
      tetdsr::SurfaceHit hit;
      const bool got = surface.firstHit(ray, hit);
      if (grazing)
      {
        ++result.grazing;
        continue;
      }
      if (got != expected)
      {
        ++result.wrongCoverage;
        continue;
      }
      if (!got)
      {
        continue;
      }
      ++result.covered;
      result.worstDepth = std::max(result.worstDepth, std::abs(hit.t - tTrue));
      result.worstAngle = std::max(result.worstAngle,
        angleBetween(hit.gradient, field.gradient(ray.origin + tTrue * ray.direction)));
    }
  }
  return result;
}

HigherOrderCell lagrange(int order)
{
  return { tetdsr::kVtkLagrangeTetrahedron, order, false };
}

HigherOrderCell bezier(int order)
{
  return { tetdsr::kVtkBezierTetrahedron, order, true };
}

void expectExact(const Comparison& c, const std::string& what, int minimumCovered)
{
  const double diagonal = std::sqrt(3.0);
  std::cout << what << ": " << c.covered << " pixels covered, " << c.grazing
            << " grazing, max depth error " << c.worstDepth / diagonal << " of the diagonal, max normal error "
            << c.worstAngle << " rad\n";
  EXPECT_EQ(c.wrongCoverage, 0) << what << ": pixels missed or false";
  EXPECT_GT(c.covered, minimumCovered) << what;
  EXPECT_LT(c.grazing, c.covered / 20) << what << ": grazing rays excluded";
  EXPECT_LT(c.worstDepth, 1e-9 * diagonal) << what << ": max depth error " << c.worstDepth;
  EXPECT_LT(c.worstAngle, 1e-6) << what << ": max normal error (rad) " << c.worstAngle;
}
} // namespace

TEST(HigherOrder, CubicFieldIsExactInOrder3And4CellsOfBothLayouts)
{
  const Field field = cubicBlob();
  for (const HigherOrderCell kind : { lagrange(3), bezier(3), lagrange(4), bezier(4) })
  {
    const HigherOrderLattice mesh =
      makeHigherOrderLattice(3, glm::dvec3(0.0), 1.0, [&](int) { return kind; }, field.value);
    const std::string what = std::string(kind.bezier ? "Bezier" : "Lagrange") + " order " +
      std::to_string(kind.order);
    const tetdsr::Scene scene(mesh.view());
    EXPECT_EQ(scene.summary().validCells, 3 * 3 * 3 * 6) << what;
    EXPECT_EQ(scene.summary().higherOrderCells, 3 * 3 * 3 * 6) << what;
    EXPECT_EQ(scene.summary().curvedCells, 0) << what;
    expectExact(compareWithTruth(mesh, field, 64), what, 800);
  }
}

TEST(HigherOrder, TorusIsExactInOrder4Cells)
{
  const Field field = torus();
  for (const HigherOrderCell kind : { lagrange(4), bezier(4) })
  {
    const HigherOrderLattice mesh =
      makeHigherOrderLattice(3, glm::dvec3(0.0), 1.0, [&](int) { return kind; }, field.value);
    expectExact(compareWithTruth(mesh, field, 72), kind.bezier ? "Bezier torus" : "Lagrange torus", 600);
  }
}

TEST(HigherOrder, MixedOrdersAndTypesAreExactForALinearField)
{
  // Every kind of tetrahedron the core reads, at random, in one conforming mesh.
  const HigherOrderCell kinds[] = { { tetdsr::kVtkTetra, 1, false },
    { tetdsr::kVtkQuadraticTetra, 2, false }, lagrange(1), lagrange(2), lagrange(3), lagrange(4),
    bezier(1), bezier(2), bezier(3), bezier(4) };
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pick(0, 9);
  const Field field = plane();
  const HigherOrderLattice mesh = makeHigherOrderLattice(
    3, glm::dvec3(0.0), 1.0, [&](int) { return kinds[pick(rng)]; }, field.value);
  const tetdsr::Scene scene(mesh.view());
  EXPECT_EQ(scene.summary().validCells, 3 * 3 * 3 * 6);
  expectExact(compareWithTruth(mesh, field, 64), "mixed, linear field", 1500);
}

TEST(HigherOrder, QuadraticFieldInMixedOrders2To4)
{
  const HigherOrderCell kinds[] = { { tetdsr::kVtkQuadraticTetra, 2, false }, lagrange(2),
    lagrange(3), lagrange(4), bezier(2), bezier(3), bezier(4) };
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(0, 6);
  Field field;
  const glm::dvec3 c(0.45, 0.52, 0.48);
  field.value = [=](const glm::dvec3& x) { return glm::dot(x - c, x - c); };
  field.gradient = [=](const glm::dvec3& x) { return 2.0 * (x - c); };
  field.isoValue = 0.31 * 0.31;
  field.scale = field.isoValue;
  const HigherOrderLattice mesh = makeHigherOrderLattice(
    3, glm::dvec3(0.0), 1.0, [&](int) { return kinds[pick(rng)]; }, field.value);
  expectExact(compareWithTruth(mesh, field, 64), "mixed orders 2-4, sphere", 800);
}

TEST(HigherOrder, RaysThroughSharedNodesOfCellsOfDifferentOrdersNeverLeak)
{
  // A plane through the whole mixed mesh, seen by parallel cameras whose pixel centres land on
  // the fine lattice's points (where cells of different orders meet at vertices, edges, faces).
  const HigherOrderCell kinds[] = { { tetdsr::kVtkTetra, 1, false },
    { tetdsr::kVtkQuadraticTetra, 2, false }, lagrange(3), lagrange(4), bezier(3), bezier(4) };
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(0, 5);
  const int n = 2;
  const glm::dvec3 origin(0.1, -0.3, 0.7);
  const double size = 0.7;
  auto value = [](const glm::dvec3& x) { return x.z - 0.1 * x.x + 0.05 * x.y; };
  const HigherOrderLattice mesh =
    makeHigherOrderLattice(n, origin, size, [&](int) { return kinds[pick(rng)]; }, value);
  const tetdsr::Scene scene(mesh.view());
  const double planeZ = origin.z + 0.37 * size;
  const double step = size / (n * 12);
  const int pixels = n * 12 + 1;
  int holes = 0, rays = 0;
  double worstDepth = 0.0;
  for (const glm::dvec3& view : { glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0, 0.0, -1.0) })
  {
    tetdsr::Camera camera;
    camera.parallelProjection = true;
    camera.focalPoint = origin + glm::dvec3(0.5 * size, 0.5 * size, 0.0);
    camera.position = camera.focalPoint + 3.0 * view;
    camera.viewUp = glm::dvec3(0.0, 1.0, 0.0);
    camera.parallelScale = 0.5 * pixels * step;
    const tetdsr::RayGenerator generator(camera, pixels, pixels);
    for (int j = 0; j < pixels; ++j)
    {
      for (int i = 0; i < pixels; ++i)
      {
        const tetdsr::Ray ray = generator.pixelRay(i, j);
        const glm::dvec3 p = ray.origin;
        const tetdsr::SurfaceIndex surface(
          scene, tetdsr::IsoValues({ planeZ - 0.1 * p.x + 0.05 * p.y }));
        tetdsr::SurfaceHit hit;
        ++rays;
        if (!surface.firstHit(ray, hit))
        {
          ++holes;
          continue;
        }
        worstDepth = std::max(worstDepth, std::abs(hit.t - std::abs(p.z - planeZ)));
      }
    }
  }
  EXPECT_EQ(holes, 0) << "of " << rays << " rays through shared nodes";
  EXPECT_LT(worstDepth, 1e-12);
}

TEST(HigherOrder, InterpolationAndGradientsOfAnotherArrayAreExact)
{
  // Colour arrays and nodal normals go through the same shape functions: a cubic in order-3 and
  // order-4 cells of both layouts is reproduced exactly at random points.
  const Field field = cubicBlob();
  for (const HigherOrderCell kind : { lagrange(3), bezier(3), lagrange(4), bezier(4) })
  {
    const HigherOrderLattice mesh =
      makeHigherOrderLattice(2, glm::dvec3(0.0), 1.0, [&](int) { return kind; }, field.value);
    tetdsr::Scene scene(mesh.view());
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uniform(0.02, 0.98);
    double worst = 0.0;
    for (int k = 0; k < 200; ++k)
    {
      const glm::dvec3 p(uniform(rng), uniform(rng), uniform(rng));
      tetdsr::NodeId cell;
      ASSERT_TRUE(scene.locate(p, cell));
      worst = std::max(worst, std::abs(scene.interpolate(cell, p, mesh.values.data()) - field.value(p)));
    }
    EXPECT_LT(worst, 1e-14) << (kind.bezier ? "Bezier " : "Lagrange ") << kind.order;
  }
}

TEST(HigherOrder, UnreadableCellsAreSkippedAndCounted)
{
  // Order 5 (56 nodes), a 15-node "tetrahedron" (no tetrahedral number), rational weights that
  // differ within a Bezier cell, and one good cell of each layout.
  HigherOrderLattice mesh = makeHigherOrderLattice(
    1, glm::dvec3(0.0), 1.0, [&](int k) { return k % 2 ? bezier(3) : lagrange(4); },
    [](const glm::dvec3& x) { return x.x; });
  // Append an order-5 cell, a 15-node one reusing ids 0..55 / 0..14 (ids are in range), and one
  // of order 65 (50,116 ids: VTK reads any order; the fuzzer found it called malformed).
  const auto pointsBefore = static_cast<tetdsr::NodeId>(mesh.points.size() / 3);
  ASSERT_GE(pointsBefore, 56);
  for (int count : { 56, 15, 50116 })
  {
    for (int id = 0; id < count; ++id)
    {
      mesh.connectivity.push_back(id % 56);
    }
    mesh.offsets.push_back(static_cast<tetdsr::NodeId>(mesh.connectivity.size()));
    mesh.cellTypes.push_back(tetdsr::kVtkLagrangeTetrahedron);
  }
  std::vector<double> weights(mesh.points.size() / 3, 2.0); // equal weights: polynomial cells
  tetdsr::MeshView view = mesh.view();
  view.rationalWeights = weights.data();
  {
    const tetdsr::Scene scene(view);
    EXPECT_EQ(scene.summary().validCells, 6);
    EXPECT_EQ(scene.summary().orderTooHighCells, 2);
    EXPECT_EQ(scene.summary().malformedCells, 1);
    EXPECT_EQ(scene.summary().rationalCells, 0);
  }
  // A weight that differs within the Bezier cells (cell 1's last control point).
  const tetdsr::NodeId last = mesh.connectivity[static_cast<std::size_t>(mesh.offsets[2] - 1)];
  weights[static_cast<std::size_t>(last)] = 3.0;
  const tetdsr::Scene scene(view);
  EXPECT_EQ(scene.summary().rationalCells, 1);
  EXPECT_EQ(scene.summary().validCells, 5);
}

TEST(HigherOrder, HitsDoNotDependOnTheScaleOfFieldOrCoordinatesOrTheirOffset)
{
  // The torus in Lagrange order-4 cells with its field scaled to the ends of double range (the
  // conversion to Bernstein sums up to 35 times a node's magnitude), its coordinates scaled by
  // 1e-90 and 1e90, and offset by 1e6: the same hits as the unit scene.
  const Field field = torus();
  // (A lattice whose nodes have no short binary form: offset, they round.)
  const HigherOrderLattice base = makeHigherOrderLattice(
    2, glm::dvec3(0.0501, 0.0299, 0.0703), 0.93, [](int) { return lagrange(4); }, field.value);
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.0, 1.5, 3.0);
  camera.focalPoint = glm::dvec3(0.5);
  auto render = [&](const HigherOrderLattice& mesh, double fieldScale, double lengthScale,
                  const glm::dvec3& offset) {
    tetdsr::Camera moved = camera;
    moved.position = camera.position * lengthScale + offset;
    moved.focalPoint = camera.focalPoint * lengthScale + offset;
    const tetdsr::Scene scene(mesh.view());
    const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ field.isoValue * fieldScale }));
    const tetdsr::RayGenerator rays(moved, 24, 24);
    std::vector<double> depths;
    for (int j = 0; j < 24; ++j)
    {
      for (int i = 0; i < 24; ++i)
      {
        tetdsr::SurfaceHit hit;
        depths.push_back(surface.firstHit(rays.pixelRay(i, j), hit) ? hit.t / lengthScale : -1.0);
      }
    }
    return depths;
  };
  const std::vector<double> reference = render(base, 1.0, 1.0, glm::dvec3(0.0));
  ASSERT_GT(std::count_if(reference.begin(), reference.end(), [](double t) { return t > 0; }), 60);
  for (const double fieldScale : { 1e-300, 1e-200, 1e155, 1e300 })
  {
    HigherOrderLattice mesh = base;
    for (double& v : mesh.values)
    {
      v *= fieldScale;
    }
    const std::vector<double> depths = render(mesh, fieldScale, 1.0, glm::dvec3(0.0));
    for (std::size_t p = 0; p < depths.size(); ++p)
    {
      EXPECT_NEAR(depths[p], reference[p], 1e-12) << "field scale " << fieldScale << " pixel " << p;
    }
  }
  for (const double lengthScale : { 1e-90, 1e90 })
  {
    HigherOrderLattice mesh = base;
    for (double& x : mesh.points)
    {
      x *= lengthScale;
    }
    const std::vector<double> depths = render(mesh, 1.0, lengthScale, glm::dvec3(0.0));
    for (std::size_t p = 0; p < depths.size(); ++p)
    {
      EXPECT_NEAR(depths[p], reference[p], 1e-9) << "length scale " << lengthScale << " pixel " << p;
    }
  }
  // Offset by about 1e6 (by numbers with no short binary form, so that vertices and camera round
  // too): the node positions themselves round at 1e6 * 2^-53 = 1.1e-10, which moves the surface
  // by about that (the quadratic cells' hard case: 7.8e-10 of the diagonal).
  HigherOrderLattice mesh = base;
  const glm::dvec3 offset(1e6 / 3.0, -1e6 / 7.0, 1e6 / 1.1);
  for (std::size_t p = 0; p < mesh.points.size(); ++p)
  {
    mesh.points[p] += offset[static_cast<int>(p % 3)];
  }
  const std::vector<double> depths = render(mesh, 1.0, 1.0, offset);
  int coverage = 0;
  double worst = 0.0;
  for (std::size_t p = 0; p < depths.size(); ++p)
  {
    if ((depths[p] > 0) != (reference[p] > 0))
    {
      ++coverage;
    }
    else if (depths[p] > 0)
    {
      worst = std::max(worst, std::abs(depths[p] - reference[p]));
    }
  }
  std::cout << "torus offset by 1e6: " << coverage << " coverage differences, max depth difference "
            << worst << "\n";
  EXPECT_LE(coverage, 2) << "pixels whose coverage the offset changes (silhouette rays)";
  EXPECT_LT(worst, 1e-9);
}

TEST(HigherOrder, ConstantFieldsEqualToTheIsoValueCoverTheCellAsALinearTetDoes)
{
  // A constant field equal to the iso-value: every ray through the cell meets it where it enters,
  // for a constant of any value and scale. (Found by the fuzzer: the Lagrange conversion spreads
  // a constant's coefficients by tens of ulps, which the quadratic's 8-ulp test took for a
  // polynomial of rounding noise: hits on some pixels, all or none, depending on the value.)
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  tetdsr::Camera camera;
  camera.position = glm::dvec3(1.9, 1.4, 2.6);
  camera.focalPoint = glm::dvec3(0.5);
  auto covered = [&](const HigherOrderCell& kind, double c) {
    const HigherOrderLattice mesh = makeHigherOrderLattice(
      1, glm::dvec3(0.0), 1.0, [&](int) { return kind; }, [c](const glm::dvec3&) { return c; });
    const tetdsr::Scene scene(mesh.view());
    const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ c }));
    const tetdsr::RayGenerator rays(camera, 24, 24);
    int hits = 0;
    for (int j = 0; j < 24; ++j)
    {
      for (int i = 0; i < 24; ++i)
      {
        tetdsr::SurfaceHit hit;
        hits += surface.firstHit(rays.pixelRay(i, j), hit);
      }
    }
    return hits;
  };
  const HigherOrderCell linear{ tetdsr::kVtkTetra, 1, false };
  int wrong = 0;
  for (int k = 0; k < 40; ++k)
  {
    const double c = uniform(rng) * std::pow(10.0, static_cast<int>(uniform(rng) * 100));
    const int expected = covered(linear, c);
    ASSERT_GT(expected, 100);
    for (const HigherOrderCell kind : { lagrange(3), lagrange(4), bezier(3), bezier(4) })
    {
      wrong += covered(kind, c) != expected;
    }
  }
  EXPECT_EQ(wrong, 0) << "of 160 constant fields";
}

TEST(HigherOrder, NormalsSurviveAGradientBelowDoubleRange)
{
  // A field near 1e-280 on cells of size 1e93: the gradient (1e-373) underflows; the hit keeps
  // the scaled gradient, whose direction is the unit scene's (found by the fuzzer: zero normals).
  const Field field = cubicBlob();
  for (const HigherOrderCell kind : { HigherOrderCell{ tetdsr::kVtkQuadraticTetra, 2, false }, lagrange(3), lagrange(4) })
  {
    auto normals = [&](double fieldScale, double lengthScale) {
      HigherOrderLattice mesh =
        makeHigherOrderLattice(2, glm::dvec3(0.0), 1.0, [&](int) { return kind; }, field.value);
      for (double& v : mesh.values)
      {
        v *= fieldScale;
      }
      for (double& x : mesh.points)
      {
        x *= lengthScale;
      }
      const tetdsr::Scene scene(mesh.view());
      const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ field.isoValue * fieldScale }));
      tetdsr::Camera camera;
      camera.position = glm::dvec3(1.9, 1.3, 2.4) * lengthScale;
      camera.focalPoint = glm::dvec3(0.5) * lengthScale;
      const tetdsr::RayGenerator rays(camera, 16, 16);
      std::vector<glm::dvec3> gradients;
      for (int j = 0; j < 16; ++j)
      {
        for (int i = 0; i < 16; ++i)
        {
          tetdsr::SurfaceHit hit;
          gradients.push_back(surface.firstHit(rays.pixelRay(i, j), hit) ? hit.gradient : glm::dvec3(0.0));
        }
      }
      return gradients;
    };
    const std::vector<glm::dvec3> reference = normals(1.0, 1.0);
    const std::vector<glm::dvec3> tiny = normals(1e-280, 1e93);
    int hits = 0, zero = 0;
    double worst = 0.0;
    for (std::size_t p = 0; p < reference.size(); ++p)
    {
      if (glm::length(reference[p]) == 0.0)
      {
        continue;
      }
      ++hits;
      if (!(glm::length(tiny[p]) > 0.0))
      {
        ++zero;
        continue;
      }
      worst = std::max(worst, angleBetween(tiny[p], reference[p]));
    }
    EXPECT_GT(hits, 30) << "order " << kind.order;
    EXPECT_EQ(zero, 0) << "order " << kind.order << ": hits with a zero normal";
    EXPECT_LT(worst, 1e-6) << "order " << kind.order;
  }
}
