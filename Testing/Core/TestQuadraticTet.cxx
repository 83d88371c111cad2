// Core tests against analytic truth: quadratic polynomials are reproduced exactly by the
// 10-node tet, so every expected value here comes from the polynomial itself, not from the core.
#include "LatticeMesh.h"
#include "StabilityCases.h"

#include "tetdsr/common/Camera.h"
#include "tetdsr/math/QuadraticTet.h"
#include "tetdsr/math/Roots.h"
#include "tetdsr/index/Scene.h"
#include "tetdsr/index/SurfaceIndex.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using tetdsr_test::LatticeMesh;
using tetdsr_test::makeLattice;
using tetdsr_test::Quadric;

namespace
{

/// Random point inside the tet with vertices v (uniform barycentric weights, normalised).
glm::dvec3 randomInside(std::mt19937_64& rng, const glm::dvec3 v[4], double L[4])
{
  std::exponential_distribution<double> e(1.0);
  double sum = 0.0;
  for (int k = 0; k < 4; ++k)
    sum += (L[k] = e(rng));
  glm::dvec3 p(0.0);
  for (int k = 0; k < 4; ++k)
    p += (L[k] /= sum) * v[k];
  return p;
}

void randomTet(std::mt19937_64& rng, glm::dvec3 v[4])
{
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  do
  {
    for (int k = 0; k < 4; ++k)
      v[k] = glm::dvec3(u(rng), u(rng), u(rng));
  } while (std::abs(glm::dot(v[1] - v[0], glm::cross(v[2] - v[0], v[3] - v[0]))) < 0.5);
}

/// A random well-shaped tet carrying a random quadric sampled at its 10 nodes.
struct RandomCell
{
  glm::dvec3 v[4];
  Quadric f;
  double values[10];
  tetdsr::BernsteinForm form;
  tetdsr::TetFrame frame;

  explicit RandomCell(std::mt19937_64& rng)
  {
    randomTet(rng, v);
    f = tetdsr_test::randomQuadric(rng, glm::dvec3(0.0), 1.0);
    for (int k = 0; k < 4; ++k)
      values[k] = f(v[k]);
    for (int e = 0; e < 6; ++e)
      values[4 + e] = f(0.5 * (v[tetdsr::kEdgeVertices[e][0]] + v[tetdsr::kEdgeVertices[e][1]]));
    form = tetdsr::BernsteinForm::fromNodeValues(values);
    EXPECT_TRUE(tetdsr::TetFrame::fromVertices(v, frame));
  }
};

double angleBetween(const glm::dvec3& a, const glm::dvec3& b)
{
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

} // namespace

TEST(QuadraticTet, BernsteinFormReproducesQuadraticsExactly)
{
  std::mt19937_64 rng(1);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial)
  {
    const RandomCell cell(rng);
    const auto& [v, f, values, form, frame] = cell;
    for (int s = 0; s < 20; ++s)
    {
      double weights[4], L[4];
      const glm::dvec3 p = randomInside(rng, v, weights);
      frame.barycentric(p, L);
      for (int k = 0; k < 4; ++k)
        EXPECT_NEAR(L[k], weights[k], 1e-12) << "barycentric coordinate " << k;
      worst = std::max(worst, std::abs(form.bilinear(L, L) - f(p)));
      const glm::dvec3 g = tetdsr::fieldGradient(form, frame, L);
      EXPECT_LT(glm::length(g - f.gradient(p)), 1e-11 * (1.0 + glm::length(f.gradient(p))))
        << "gradient: expected " << f.gradient(p).x << "," << f.gradient(p).y << ","
        << f.gradient(p).z << " got " << g.x << "," << g.y << "," << g.z;
    }
  }
  EXPECT_LT(worst, 1e-12) << "max |L^T B L - f(p)| over 4000 points";
}

TEST(QuadraticTet, BernsteinRangeBoundsTheField)
{
  std::mt19937_64 rng(2);
  for (int trial = 0; trial < 200; ++trial)
  {
    const RandomCell cell(rng);
    const auto& [v, f, values, form, frame] = cell;
    double lo, hi;
    form.range(lo, hi);
    double nodalLo = values[0], nodalHi = values[0];
    for (double x : values)
    {
      nodalLo = std::min(nodalLo, x);
      nodalHi = std::max(nodalHi, x);
    }
    EXPECT_LE(lo, nodalLo);
    EXPECT_GE(hi, nodalHi);
    for (int s = 0; s < 200; ++s)
    {
      double L[4];
      const double value = f(randomInside(rng, v, L));
      ASSERT_GE(value, lo - 1e-12) << "field below its Bernstein minimum";
      ASSERT_LE(value, hi + 1e-12) << "field above its Bernstein maximum";
    }
  }
}

TEST(QuadraticTet, ExactRangeMatchesDenseSampling)
{
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 100; ++trial)
  {
    const RandomCell cell(rng);
    double lo, hi, bernsteinLo, bernsteinHi;
    cell.form.exactRange(lo, hi);
    cell.form.range(bernsteinLo, bernsteinHi);
    EXPECT_LE(bernsteinLo, lo + 1e-12);
    EXPECT_GE(bernsteinHi, hi - 1e-12);
    // Dense barycentric lattice (step 1/40): samples stay inside [lo, hi] and come close to it.
    double sampledLo = std::numeric_limits<double>::infinity(), sampledHi = -sampledLo;
    const int steps = 40;
    for (int a = 0; a <= steps; ++a)
      for (int b = 0; a + b <= steps; ++b)
        for (int c = 0; a + b + c <= steps; ++c)
        {
          const double L[4] = { double(a) / steps, double(b) / steps, double(c) / steps,
            double(steps - a - b - c) / steps };
          const double value = cell.form.bilinear(L, L);
          sampledLo = std::min(sampledLo, value);
          sampledHi = std::max(sampledHi, value);
        }
    EXPECT_LE(lo, sampledLo + 1e-12);
    EXPECT_GE(hi, sampledHi - 1e-12);
    const double scale = hi - lo + 1e-300;
    EXPECT_LT((sampledLo - lo) / scale, 2e-3) << "exact minimum not approached by sampling";
    EXPECT_LT((hi - sampledHi) / scale, 2e-3) << "exact maximum not approached by sampling";
  }
}

TEST(QuadraticTet, RayQuadraticMatchesDirectEvaluation)
{
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    const RandomCell cell(rng);
    const auto& [v, f, values, form, frame] = cell;
    const glm::dvec3 origin(u(rng), u(rng), u(rng));
    const glm::dvec3 direction = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    double L[4], dL[4];
    frame.barycentric(origin, L);
    frame.barycentricDirection(direction, dL);
    const double a = form.bilinear(dL, dL);
    const double b = 2.0 * form.bilinear(L, dL);
    const double c = form.bilinear(L, L);
    // Closed form along the ray: f(o + t d) = (d.A d) t^2 + (2 d.A o + b.d) t + f(o).
    EXPECT_NEAR(a, glm::dot(direction, f.A * direction), 1e-11);
    EXPECT_NEAR(b, 2.0 * glm::dot(direction, f.A * origin) + glm::dot(f.b, direction), 1e-11);
    EXPECT_NEAR(c, f(origin), 1e-11);
    for (double t : { -1.5, -0.3, 0.0, 0.7, 2.0 })
      EXPECT_NEAR(a * t * t + b * t + c, f(origin + t * direction), 1e-10) << "t = " << t;
  }
}

TEST(Roots, StableFormulaKeepsBothRootsAccurate)
{
  // (s - 1e-8)(s - 1e8): the naive formula loses the small root to cancellation.
  double root;
  const double small = 1e-8, large = 1e8;
  ASSERT_TRUE(tetdsr::firstRootInInterval(1.0, -(small + large), small * large, 0.0, 1.0, root));
  EXPECT_NEAR(root, small, 1e-15 * small) << "expected 1e-8, got " << root;
  ASSERT_TRUE(tetdsr::firstRootInInterval(1.0, -(small + large), small * large, 1.0, 1e9, root));
  EXPECT_NEAR(root, large, 1e-15 * large);
  const double naive = (-(-(small + large)) - std::sqrt((small + large) * (small + large) -
                                                  4.0 * small * large)) / 2.0;
  EXPECT_GT(std::abs(naive - small), 1e-3 * small) << "the naive formula should fail here";
}

TEST(Roots, DegenerateCases)
{
  double root;
  // Linear (a = 0): 2s - 1 = 0.
  ASSERT_TRUE(tetdsr::firstRootInInterval(0.0, 2.0, -1.0, 0.0, 1.0, root));
  EXPECT_EQ(root, 0.5);
  // Constant equal to the iso-value: the segment's start.
  ASSERT_TRUE(tetdsr::firstRootInInterval(0.0, 0.0, 0.0, 0.25, 1.0, root));
  EXPECT_EQ(root, 0.25);
  // Constant different from the iso-value: none.
  EXPECT_FALSE(tetdsr::firstRootInInterval(0.0, 0.0, 1e-300, 0.0, 1.0, root));
  // Double root (s - 0.5)^2, exactly representable: found.
  ASSERT_TRUE(tetdsr::firstRootInInterval(1.0, -1.0, 0.25, 0.0, 1.0, root));
  EXPECT_EQ(root, 0.5);
  // No real root.
  EXPECT_FALSE(tetdsr::firstRootInInterval(1.0, 0.0, 1.0, -10.0, 10.0, root));
  // Roots exactly at the interval ends (s = 0 and s = 1): both ends are inclusive.
  ASSERT_TRUE(tetdsr::firstRootInInterval(1.0, -1.0, 0.0, 0.0, 1.0, root));
  EXPECT_EQ(root, 0.0);
  ASSERT_TRUE(tetdsr::firstRootInInterval(1.0, -1.0, 0.0, 0.5, 1.0, root));
  EXPECT_EQ(root, 1.0);
  // Both roots outside.
  EXPECT_FALSE(tetdsr::firstRootInInterval(1.0, -1.0, 0.0, 0.2, 0.8, root));
}

TEST(Roots, DiscriminantIsAccurateUnderCancellation)
{
  // Kahan's example: with b = 2 * 94906267, b^2 - 4ac = 4 * 1.890625 = 7.5625 exactly, while
  // the naive double evaluation returns 8.
  const double a = 94906265.625, b = 2.0 * 94906267.0, c = 94906268.375;
  EXPECT_EQ(tetdsr::discriminant(a, b, c), 7.5625);
  EXPECT_NE(b * b - 4.0 * a * c, 7.5625) << "the naive formula should be inexact here";
}

namespace
{
// Independent truth for f = |x - c|^2 with iso-value r^2: the ray/sphere intersection.
struct SphereTruth
{
  glm::dvec3 centre;
  double radius;
  // First t >= 0 on the sphere; `margin` = how far the ray's closest approach is from grazing.
  bool hit(const tetdsr::Ray& ray, double& t, double& margin) const
  {
    const glm::dvec3 oc = ray.origin - centre;
    const double half = glm::dot(ray.direction, oc);
    const double closest = glm::length(oc - half * ray.direction);
    margin = std::abs(closest - radius) / radius;
    if (closest > radius)
      return false;
    t = -half - std::sqrt(radius * radius - closest * closest);
    return t >= 0.0;
  }
};
} // namespace

TEST(Scene, SphereMatchesExactRaySphereIntersection)
{
  LatticeMesh mesh = makeLattice(4, glm::dvec3(0.0), 1.0);
  const SphereTruth sphere{ glm::dvec3(0.45, 0.52, 0.48), 0.31 };
  mesh.sample([&](const glm::dvec3& x) { return glm::dot(x - sphere.centre, x - sphere.centre); });
  const tetdsr::Scene scene(mesh.view());
  ASSERT_EQ(scene.summary().validCells, 4 * 4 * 4 * 6);
  const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ sphere.radius * sphere.radius }));
  const double diagonal = std::sqrt(3.0);

  for (bool parallel : { false, true })
  {
    tetdsr::Camera camera;
    camera.position = glm::dvec3(1.9, 1.4, 2.6);
    camera.focalPoint = glm::dvec3(0.5);
    camera.viewUp = glm::dvec3(0.0, 1.0, 0.0);
    camera.viewAngleDegrees = 25.0;
    camera.parallelProjection = parallel;
    camera.parallelScale = 0.45;
    const int width = 96, height = 80;
    const tetdsr::RayGenerator rays(camera, width, height);
    int covered = 0, excluded = 0, wrongCoverage = 0;
    double worstDepth = 0.0, worstAngle = 0.0;
    for (int j = 0; j < height; ++j)
      for (int i = 0; i < width; ++i)
      {
        const tetdsr::Ray ray = rays.pixelRay(i, j);
        double tTrue, margin;
        const bool expected = sphere.hit(ray, tTrue, margin);
        if (margin < 1e-6)
        {
          ++excluded; // within 1e-6 of the silhouette: grazing rays
          continue;
        }
        tetdsr::SurfaceHit hit;
        const bool got = surface.firstHit(ray, hit);
        if (got != expected)
        {
          ++wrongCoverage;
          continue;
        }
        if (!got)
          continue;
        ++covered;
        worstDepth = std::max(worstDepth, std::abs(hit.t - tTrue));
        const glm::dvec3 p = ray.origin + tTrue * ray.direction;
        worstAngle = std::max(worstAngle, angleBetween(hit.gradient, p - sphere.centre));
      }
    EXPECT_EQ(wrongCoverage, 0) << (parallel ? "parallel" : "perspective");
    EXPECT_GT(covered, 1000);
    EXPECT_LE(excluded, 4);
    EXPECT_LT(worstDepth, 1e-9 * diagonal) << "max depth error " << worstDepth;
    EXPECT_LT(worstAngle, 1e-6) << "max normal error (rad) " << worstAngle;
  }
}

TEST(Scene, RaysThroughSharedVerticesAndEdgesNeverFallThroughCracks)
{
  // A plane crossing the whole lattice, seen by parallel cameras whose pixel centres land on
  // the lattice's vertices and mid-edge nodes (where 4 to 24 cells meet). The lattice is offset
  // and scaled by numbers with no exact binary form, so the cells' barycentric coordinates
  // round differently on either side of a shared face.
  const int n = 5;
  const glm::dvec3 origin(0.1, -0.3, 0.7);
  const double size = 0.7;
  LatticeMesh mesh = makeLattice(n, origin, size);
  const double planeZ = origin.z + 0.37 * size;
  mesh.sample([&](const glm::dvec3& x) { return x.z - 0.1 * x.x + 0.05 * x.y; });
  const tetdsr::Scene scene(mesh.view());
  const double step = 0.5 * size / n;
  const int pixels = 2 * n + 1; // pixel pitch = step: centres at origin + k * step
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
      for (int i = 0; i < pixels; ++i)
      {
        const tetdsr::Ray ray = generator.pixelRay(i, j);
        const glm::dvec3 p = ray.origin;
        const double fieldOffset = -0.1 * p.x + 0.05 * p.y; // f = z + offset; iso planeZ + ...
        const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ planeZ + fieldOffset }));
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
  EXPECT_EQ(holes, 0) << "of " << rays << " rays through vertices and edges";
  EXPECT_LT(worstDepth, 1e-12);

  // Rays along the cells' shared diagonal faces and edges: direction (1, 1, 1) through vertices.
  int diagonalHoles = 0;
  for (int k = 1; k < 2 * n; ++k)
  {
    const glm::dvec3 onPlane = origin + glm::dvec3(k * step, k * step, 0.37 * size);
    const tetdsr::Ray ray{ onPlane - 0.1 * glm::dvec3(1.0), glm::normalize(glm::dvec3(1.0)) };
    const double value = onPlane.z - 0.1 * onPlane.x + 0.05 * onPlane.y;
    tetdsr::SurfaceHit hit;
    diagonalHoles += !tetdsr::SurfaceIndex(scene, tetdsr::IsoValues({ value })).firstHit(ray, hit);
  }
  EXPECT_EQ(diagonalHoles, 0);
}

TEST(Scene, InvertedCellsRenderIdenticallyAndAreCounted)
{
  LatticeMesh mesh = makeLattice(2, glm::dvec3(-1.0), 2.0);
  const SphereTruth sphere{ glm::dvec3(0.1, -0.05, 0.0), 0.6 };
  mesh.sample([&](const glm::dvec3& x) { return glm::dot(x - sphere.centre, x - sphere.centre); });
  LatticeMesh flipped = mesh;
  // Swap vertices 1 and 2 in every other cell, with the mid-edge nodes that follow them:
  // edges (0,1)<->(0,2) and (1,3)<->(2,3); (1,2) maps to itself.
  const tetdsr::NodeId cells = static_cast<tetdsr::NodeId>(mesh.cellNodes.size() / 10);
  for (tetdsr::NodeId c = 0; c < cells; c += 2)
  {
    tetdsr::NodeId* ids = flipped.cellNodes.data() + 10 * c;
    std::swap(ids[1], ids[2]);
    std::swap(ids[4], ids[6]);
    std::swap(ids[8], ids[9]);
  }
  const tetdsr::Scene original(mesh.view());
  const tetdsr::Scene mixed(flipped.view());
  EXPECT_EQ(original.summary().invertedCells, 0);
  EXPECT_EQ(mixed.summary().invertedCells, (cells + 1) / 2);
  EXPECT_EQ(mixed.summary().validCells, cells);

  const tetdsr::IsoValues iso({ sphere.radius * sphere.radius });
  const tetdsr::SurfaceIndex originalSurface(original, iso), mixedSurface(mixed, iso);
  tetdsr::Camera camera;
  camera.position = glm::dvec3(0.3, 0.2, 4.0);
  const tetdsr::RayGenerator rays(camera, 40, 40);
  int compared = 0;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i)
    {
      const tetdsr::Ray ray = rays.pixelRay(i, j);
      tetdsr::SurfaceHit a, b;
      const bool hitA = originalSurface.firstHit(ray, a);
      ASSERT_EQ(hitA, mixedSurface.firstHit(ray, b));
      if (!hitA)
        continue;
      ++compared;
      EXPECT_NEAR(a.t, b.t, 1e-12);
      EXPECT_LT(angleBetween(a.gradient, b.gradient), 1e-9) << "normals flipped by orientation";
    }
  EXPECT_GT(compared, 100);
}

TEST(Scene, BadCellsAreSkippedAndCounted)
{
  LatticeMesh mesh = makeLattice(1, glm::dvec3(0.0), 1.0); // 6 cells
  mesh.sample([](const glm::dvec3& x) { return x.x; });
  // Cell 3: zero volume, vertex 3 moved onto the plane of vertices 0, 1, 2 (a new point).
  const glm::dvec3 v0 = mesh.point(mesh.cellNodes[30]), v1 = mesh.point(mesh.cellNodes[31]),
                   v2 = mesh.point(mesh.cellNodes[32]);
  const glm::dvec3 flat = v0 + 0.3 * (v1 - v0) + 0.3 * (v2 - v0);
  mesh.points.insert(mesh.points.end(), { flat.x, flat.y, flat.z });
  mesh.values.push_back(flat.x);
  mesh.cellNodes[33] = static_cast<tetdsr::NodeId>(mesh.values.size() - 1);
  mesh.cellNodes[10 * 1 + 3] = mesh.cellNodes[10 * 1 + 0]; // cell 1: repeated vertex id
  mesh.cellNodes[10 * 2 + 5] = mesh.view().numberOfPoints;  // cell 2: id out of range
  const tetdsr::NodeId nanNode = mesh.cellNodes[10 * 4 + 7];
  mesh.values[static_cast<std::size_t>(nanNode)] = std::nan(""); // cell 4 (and its sharers): NaN
  // Expected counts, in the order the checks apply: ids in range, distinct ids, finite values,
  // non-zero volume.
  int nonFinite = 0;
  for (int c : { 0, 3, 4, 5 })
  {
    bool uses = false;
    for (int k = 0; k < 10; ++k)
      uses = uses || mesh.cellNodes[10 * c + k] == nanNode;
    nonFinite += uses;
  }
  const bool cell3UsesNaN = std::count(mesh.cellNodes.begin() + 30, mesh.cellNodes.begin() + 40,
                              nanNode) > 0;
  const tetdsr::Scene scene(mesh.view());
  const auto& summary = scene.summary();
  EXPECT_EQ(summary.invalidIdCells, 1);
  EXPECT_EQ(summary.degenerateCells, cell3UsesNaN ? 1 : 2);
  EXPECT_EQ(summary.nonFiniteCells, nonFinite);
  EXPECT_EQ(summary.validCells, 6 - summary.invalidIdCells - summary.degenerateCells - nonFinite);
  EXPECT_GE(nonFinite, 1);
}

TEST(Scene, WidenedNodalRangeHeuristicLeavesHolesTheBernsteinBoundDoesNot)
{
  // One cell, vertex values 1 and mid-edge values 0.9: with sum(L) = 1 the field is
  // f = 0.8 + 0.2 sum(L_i^2), 0.85 at the centroid. Nodal range [0.9, 1], widened by 25%:
  // [0.875, 1.025], so the iso-value 0.86, reached around the centroid, is never searched.
  LatticeMesh mesh;
  const glm::dvec3 v[4] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
  for (int k = 0; k < 10; ++k)
  {
    const glm::dvec3 p = k < 4 ? v[k]
                               : 0.5 * (v[tetdsr::kEdgeVertices[k - 4][0]] +
                                          v[tetdsr::kEdgeVertices[k - 4][1]]);
    mesh.points.insert(mesh.points.end(), { p.x, p.y, p.z });
    mesh.cellNodes.push_back(k);
    mesh.values.push_back(k < 4 ? 1.0 : 0.9);
  }
  double values[10];
  std::copy(mesh.values.begin(), mesh.values.end(), values);
  double lo, hi;
  tetdsr::BernsteinForm::fromNodeValues(values).exactRange(lo, hi);
  EXPECT_NEAR(lo, 0.85, 1e-15);
  EXPECT_NEAR(hi, 1.0, 1e-15);
  tetdsr::TransverseTest heuristic;
  heuristic.mode = tetdsr::TransverseTest::Mode::WidenedNodalRange;
  double heuristicLo, heuristicHi;
  heuristic.range(values, heuristicLo, heuristicHi);
  EXPECT_NEAR(heuristicLo, 0.875, 1e-15);

  const tetdsr::IsoValues iso({ 0.86 });
  const tetdsr::Scene exact(mesh.view());
  const tetdsr::Scene paper(mesh.view(), tetdsr::serialFor, heuristic);
  const glm::dvec3 centroid(0.25);
  const tetdsr::Ray ray{ centroid + glm::dvec3(0.0, 0.0, 3.0), glm::dvec3(0.0, 0.0, -1.0) };
  tetdsr::SurfaceHit hit;
  ASSERT_TRUE(tetdsr::SurfaceIndex(exact, iso).firstHit(ray, hit));
  // Truth along the ray: sum L^2 = 3 * (1/4)^2 + (1/4 + 3 - t)^2... solve f = 0.86 directly.
  // Along x = y = 1/4, z = 3.25 - t: L = (1/2 - z, 1/4, 1/4, z); f = 0.8 + 0.2 sum L^2.
  const double target = (0.86 - 0.8) / 0.2 - 2.0 / 16.0; // (1/2 - z)^2 + z^2
  const double z = 0.25 + std::sqrt(target / 2.0 - 1.0 / 16.0); // the root nearer the camera
  EXPECT_NEAR(hit.t, 3.25 - z, 1e-12);
  EXPECT_FALSE(tetdsr::SurfaceIndex(paper, iso).firstHit(ray, hit))
    << "the 25% heuristic leaves a hole here";
  heuristic.widening = 0.5; // [0.85, 1.05]: wide enough again
  const tetdsr::Scene wider(mesh.view(), tetdsr::serialFor, heuristic);
  EXPECT_TRUE(tetdsr::SurfaceIndex(wider, iso).firstHit(ray, hit));
}

TEST(Scene, CurvedCellsAreCounted)
{
  LatticeMesh mesh = makeLattice(2, glm::dvec3(0.0), 1.0);
  mesh.sample([](const glm::dvec3& x) { return x.x; });
  EXPECT_EQ(tetdsr::Scene(mesh.view()).summary().curvedCells, 0);
  // Push one mid-edge node off its edge by 1e-3 of the cell size: every cell using it is curved.
  const tetdsr::NodeId node = mesh.cellNodes[10 * 7 + 5];
  mesh.points[3 * node + 2] += 1e-3 * 0.5;
  const auto cells = static_cast<int>(mesh.cellNodes.size() / 10);
  int users = 0;
  for (int c = 0; c < cells; ++c)
    users += std::count(mesh.cellNodes.begin() + 10 * c, mesh.cellNodes.begin() + 10 * c + 10, node) > 0;
  const tetdsr::Scene scene(mesh.view());
  EXPECT_EQ(scene.summary().curvedCells, users);
  EXPECT_EQ(scene.summary().validCells, cells) << "curved cells are still rendered";
  EXPECT_GE(users, 1);
}

TEST(Scene, LinearTetEqualsQuadraticTetWithMidpointValues)
{
  LatticeMesh quadratic = makeLattice(2, glm::dvec3(0.0), 1.0);
  quadratic.sample([](const glm::dvec3& x) { return 0.3 * x.x - 0.5 * x.y + 0.8 * x.z; });
  // The same cells as VTK_TETRA: their 4 vertex ids only.
  std::vector<tetdsr::NodeId> vertexIds, offsets{ 0 };
  for (std::size_t c = 0; c < quadratic.cellNodes.size() / 10; ++c)
  {
    vertexIds.insert(vertexIds.end(), quadratic.cellNodes.begin() + 10 * c,
      quadratic.cellNodes.begin() + 10 * c + 4);
    offsets.push_back(static_cast<tetdsr::NodeId>(vertexIds.size()));
  }
  const std::vector<std::uint8_t> types(offsets.size() - 1, tetdsr::kVtkTetra);
  tetdsr::MeshView linearView = quadratic.view();
  linearView.cellTypes = types.data();
  linearView.offsets = offsets.data();
  linearView.connectivity = vertexIds.data();
  linearView.connectivitySize = static_cast<tetdsr::NodeId>(vertexIds.size());
  const tetdsr::Scene a(quadratic.view()), b(linearView);
  const tetdsr::IsoValues iso({ 0.2 });
  const tetdsr::SurfaceIndex surfaceA(a, iso), surfaceB(b, iso);
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.0, 1.5, 3.0);
  camera.focalPoint = glm::dvec3(0.5);
  const tetdsr::RayGenerator rays(camera, 32, 32);
  int hits = 0;
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i)
    {
      tetdsr::SurfaceHit ha, hb;
      const tetdsr::Ray ray = rays.pixelRay(i, j);
      const bool hitA = surfaceA.firstHit(ray, ha);
      ASSERT_EQ(hitA, surfaceB.firstHit(ray, hb));
      if (hitA)
      {
        ++hits;
        EXPECT_NEAR(ha.t, hb.t, 1e-12);
        EXPECT_NEAR(glm::length(ha.gradient - hb.gradient), 0.0, 1e-12);
      }
    }
  EXPECT_GT(hits, 100);
}

TEST(Scene, SeveralIsoValuesGiveTheNearestCrossingAndThinShellsTheFirstRoot)
{
  // One cell, f = |x - c|^2 with c outside the ray's near side: a ray through the cell crosses
  // iso-values r1^2 < r2^2 of two concentric spheres; the first crossing is the outer sphere.
  LatticeMesh mesh = makeLattice(1, glm::dvec3(-1.0), 2.0);
  mesh.sample([](const glm::dvec3& x) { return glm::dot(x, x); });
  const tetdsr::Scene scene(mesh.view());
  const tetdsr::Ray ray{ glm::dvec3(0.05, -0.02, 5.0), glm::dvec3(0.0, 0.0, -1.0) };
  const double r1 = 0.3, r2 = 0.7;
  const double rho2 = 0.05 * 0.05 + 0.02 * 0.02;
  tetdsr::SurfaceHit hit;
  ASSERT_TRUE(tetdsr::SurfaceIndex(scene, tetdsr::IsoValues({ r1 * r1, r2 * r2 })).firstHit(ray, hit));
  EXPECT_NEAR(hit.t, 5.0 - std::sqrt(r2 * r2 - rho2), 1e-12) << "outer sphere first";
  // A thin shell: both roots of one sphere lie within the cells; the first one is returned.
  ASSERT_TRUE(tetdsr::SurfaceIndex(scene, tetdsr::IsoValues({ r1 * r1 })).firstHit(ray, hit));
  EXPECT_NEAR(hit.t, 5.0 - std::sqrt(r1 * r1 - rho2), 1e-12);
  // A sphere of radius 1e-3 of the cell size, entirely inside one cell.
  const double tiny = 2e-3;
  const tetdsr::Ray centred{ glm::dvec3(0.0, 0.0, 5.0), glm::dvec3(0.0, 0.0, -1.0) };
  ASSERT_TRUE(tetdsr::SurfaceIndex(scene, tetdsr::IsoValues({ tiny * tiny })).firstHit(centred, hit));
  EXPECT_NEAR(hit.t, 5.0 - tiny, 1e-12);
}

TEST(Scene, RayWindowGivesEveryCrossingInOrderWithItsIsoValue)
{
  // The same concentric spheres, values given out of order: stepping the window past each hit
  // yields the four crossings in depth order, each naming the iso-value it crosses.
  LatticeMesh mesh = makeLattice(2, glm::dvec3(-1.0), 2.0);
  mesh.sample([](const glm::dvec3& x) { return glm::dot(x, x); });
  const tetdsr::Scene scene(mesh.view());
  const tetdsr::Ray ray{ glm::dvec3(0.05, -0.02, 5.0), glm::dvec3(0.0, 0.0, -1.0) };
  const double r1 = 0.3, r2 = 0.7, rho2 = 0.05 * 0.05 + 0.02 * 0.02;
  const tetdsr::IsoValues iso({ r2 * r2, r1 * r1 });
  const tetdsr::SurfaceIndex surface(scene, iso);
  EXPECT_EQ(iso.originalIndex(0), 1u) << "the smaller value was given second";
  EXPECT_EQ(iso.originalIndex(1), 0u);
  const double h1 = std::sqrt(r1 * r1 - rho2), h2 = std::sqrt(r2 * r2 - rho2);
  const double expected[4] = { 5.0 - h2, 5.0 - h1, 5.0 + h1, 5.0 + h2 };
  const std::size_t expectedValue[4] = { 1, 0, 0, 1 }; // sorted order: r1^2 first
  double from = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    tetdsr::SurfaceHit hit;
    ASSERT_TRUE(surface.firstHit(ray, hit, from)) << "crossing " << k;
    EXPECT_NEAR(hit.t, expected[k], 1e-12) << "crossing " << k;
    EXPECT_EQ(hit.isoIndex, expectedValue[k]) << "crossing " << k;
    from = hit.t + 1e-9;
  }
  tetdsr::SurfaceHit hit;
  EXPECT_FALSE(surface.firstHit(ray, hit, from)) << "no fifth crossing";
  EXPECT_FALSE(surface.firstHit(ray, hit, 0.0, expected[0] - 1e-9)) << "window ends before";
}

TEST(Scene, PointLocationAndInterpolationOfAnotherArray)
{
  // A second quadratic array is reproduced exactly wherever the point is located.
  LatticeMesh mesh = makeLattice(3, glm::dvec3(0.0), 1.0);
  mesh.sample([](const glm::dvec3& x) { return x.x; });
  std::vector<double> second;
  const auto g = [](const glm::dvec3& x) { return x.x * x.y - 2.0 * x.z * x.z + 0.5; };
  for (std::size_t p = 0; p < mesh.points.size() / 3; ++p)
  {
    second.push_back(g(mesh.point(static_cast<tetdsr::NodeId>(p))));
  }
  const tetdsr::Scene scene(mesh.view());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 200; ++k)
  {
    const glm::dvec3 x(u(rng), u(rng), u(rng));
    tetdsr::NodeId cell;
    ASSERT_TRUE(scene.locate(x, cell));
    EXPECT_NEAR(scene.interpolate(cell, x, second.data()), g(x), 1e-14);
  }
  tetdsr::NodeId cell;
  EXPECT_FALSE(scene.locate(glm::dvec3(1.5, 0.5, 0.5), cell)) << "outside the mesh";
}

// Hostile input at the core: many copies of one cell (leaves stay small; the traversal ends),
// and a field or mesh scaled across double range (the same hits, relative to the scale).
TEST(Scene, CopiesOfOneCellKeepLeavesSmallAndTraversalFinite)
{
  LatticeMesh one = makeLattice(1, glm::dvec3(0.0), 1.0);
  one.sample([](const glm::dvec3& x) { return glm::dot(x, x); });
  one.cellNodes.resize(10);
  const std::vector<tetdsr::NodeId> cell = one.cellNodes;
  for (int copy = 1; copy < 70000; ++copy) // beyond a 16-bit count
    one.cellNodes.insert(one.cellNodes.end(), cell.begin(), cell.end());
  const tetdsr::Scene scene(one.view());
  ASSERT_EQ(scene.summary().validCells, 70000);
  const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ 0.2 }));
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.0, 1.5, 3.0);
  camera.focalPoint = glm::dvec3(0.1);
  camera.viewAngleDegrees = 10.0;
  const tetdsr::RayGenerator rays(camera, 8, 8);
  int hits = 0;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i)
    {
      tetdsr::SurfaceHit hit;
      hits += surface.firstHit(rays.pixelRay(i, j), hit);
    }
  EXPECT_GT(hits, 0);
}

TEST(Scene, HitsDoNotDependOnTheScaleOfFieldOrCoordinates)
{
  LatticeMesh base = makeLattice(2, glm::dvec3(0.0), 1.0);
  base.sample([](const glm::dvec3& x) { return glm::dot(x - glm::dvec3(0.4), x - glm::dvec3(0.4)); });
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.0, 1.5, 3.0);
  camera.focalPoint = glm::dvec3(0.5);
  auto render = [&](const LatticeMesh& mesh, double fieldScale, double lengthScale) {
    tetdsr::Camera scaled = camera;
    scaled.position *= lengthScale;
    scaled.focalPoint *= lengthScale;
    const tetdsr::Scene scene(mesh.view());
    const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ 0.15 * fieldScale }));
    const tetdsr::RayGenerator rays(scaled, 16, 16);
    std::vector<double> depths;
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i)
      {
        tetdsr::SurfaceHit hit;
        const bool found = surface.firstHit(rays.pixelRay(i, j), hit);
        depths.push_back(found ? hit.t / lengthScale : -1.0);
      }
    return depths;
  };
  const std::vector<double> reference = render(base, 1.0, 1.0);
  ASSERT_GT(std::count_if(reference.begin(), reference.end(), [](double t) { return t > 0; }), 20);
  for (const double fieldScale : { 1e-300, 1e-200, 1e155, 1e300 })
  {
    LatticeMesh mesh = base;
    for (double& v : mesh.values)
      v *= fieldScale;
    const std::vector<double> depths = render(mesh, fieldScale, 1.0);
    for (std::size_t p = 0; p < depths.size(); ++p)
      EXPECT_NEAR(depths[p], reference[p], 1e-12) << "field scale " << fieldScale << " pixel " << p;
  }
  for (const double lengthScale : { 1e-90, 1e90 })
  {
    LatticeMesh mesh = base;
    for (double& x : mesh.points)
      x *= lengthScale;
    const std::vector<double> depths = render(mesh, 1.0, lengthScale);
    for (std::size_t p = 0; p < depths.size(); ++p)
      EXPECT_NEAR(depths[p], reference[p], 1e-9) << "length scale " << lengthScale << " pixel " << p;
  }
}

TEST(SurfaceIndex, RecordsMadeAsNeededAndSharedIndicesGiveTheSameHits)
{
  // A smooth non-polynomial field on a 6^3 lattice: the index with records, without them (the
  // memory limit at 0: each candidate's record made as it is tested), and one sharing the cells
  // of an index for another iso-value with the same transverse cells must give the same hits,
  // bit for bit, on every pixel.
  LatticeMesh mesh = makeLattice(6, glm::dvec3(0.0), 1.0);
  mesh.sample([](const glm::dvec3& x) { return std::sin(7.0 * x.x) * std::cos(5.0 * x.y) + std::sin(6.0 * x.z + 1.0); });
  const tetdsr::Scene scene(mesh.view());
  const tetdsr::IsoValues iso({ 0.3, -0.5 });
  const tetdsr::SurfaceIndex withRecords(scene, iso);
  const tetdsr::SurfaceIndex withoutRecords(scene, iso, tetdsr::serialFor, nullptr, 0);
  ASSERT_TRUE(withRecords.keepsRecords());
  ASSERT_FALSE(withoutRecords.keepsRecords());
  ASSERT_EQ(withRecords.transverseCells(), withoutRecords.transverseCells());
  // A nearby iso-value pair whose transverse cells are the same: the shared index must answer
  // for the new values (records do not depend on them).
  const tetdsr::IsoValues moved({ 0.3 + 1e-9, -0.5 - 1e-9 });
  const tetdsr::SurfaceIndex fresh(scene, moved);
  const tetdsr::SurfaceIndex shared(scene, moved, tetdsr::serialFor, &withRecords);
  ASSERT_EQ(fresh.transverseCells(), withRecords.transverseCells()) << "the test needs the same cells";
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.1, 1.6, 3.0);
  camera.focalPoint = glm::dvec3(0.5);
  const tetdsr::RayGenerator rays(camera, 48, 48);
  int hits = 0, differences = 0;
  auto same = [](bool foundA, const tetdsr::SurfaceHit& a, bool foundB, const tetdsr::SurfaceHit& b) {
    return foundA == foundB &&
      (!foundA ||
        (a.t == b.t && a.cellId == b.cellId && a.isoIndex == b.isoIndex && a.gradient == b.gradient));
  };
  for (int j = 0; j < 48; ++j)
    for (int i = 0; i < 48; ++i)
    {
      const tetdsr::Ray ray = rays.pixelRay(i, j);
      tetdsr::SurfaceHit a, b, c, d;
      const bool foundA = withRecords.firstHit(ray, a);
      const bool foundB = withoutRecords.firstHit(ray, b);
      const bool foundC = fresh.firstHit(ray, c);
      const bool foundD = shared.firstHit(ray, d);
      hits += foundA;
      differences += !same(foundA, a, foundB, b) + !same(foundC, c, foundD, d);
    }
  std::printf("record limit and shared cells: %d hits of 2304 rays, %d differences\n", hits, differences);
  EXPECT_GT(hits, 500);
  EXPECT_EQ(differences, 0);
}
