// The exact surface as data (ExactSurface.h) against analytic truth, in the core: spheres of a
// quadratic field on straight quadratic tetrahedra (held exactly), one inside a single cell with
// no sign change at its nodes, and a plane in 27-node hexahedra bent by a quadratic map (a
// linear field is held exactly by curved cells).
#include "LatticeMesh.h"

#include "tetdsr/surface/ExactSurface.h"
#include "tetdsr/index/Scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <set>

namespace
{

using tetdsr::NodeId;
constexpr double kPi = 3.14159265358979323846;

tetdsr::ExactSurfaceMesh extract(const tetdsr::Scene& scene, std::vector<double> isoValues, double relative,
  std::vector<tetdsr::ArrayView> arrays = {})
{
  tetdsr::ExactSurfaceSettings settings;
  settings.isoValues = std::move(isoValues);
  settings.relativeTolerance = relative;
  tetdsr::ExactSurfaceMesh surface;
  tetdsr::Messages messages;
  EXPECT_TRUE(tetdsr::extractExactSurface(scene, settings, arrays, surface, messages));
  EXPECT_TRUE(messages.errors.empty());
  EXPECT_EQ(surface.unresolvedSubcells, 0);
  return surface;
}

glm::dvec3 vertex(const tetdsr::ExactSurfaceMesh& s, NodeId v)
{
  return { s.points[3 * v], s.points[3 * v + 1], s.points[3 * v + 2] };
}

/// The largest distance from points sampled on every triangle to the analytic surface.
double triangleToSurface(const tetdsr::ExactSurfaceMesh& s, const std::function<double(const glm::dvec3&)>& distance)
{
  double worst = 0.0;
  const int n = 6;
  for (std::size_t t = 0; t < s.triangles.size() / 3; ++t)
  {
    const glm::dvec3 a = vertex(s, s.triangles[3 * t]), b = vertex(s, s.triangles[3 * t + 1]),
                     c = vertex(s, s.triangles[3 * t + 2]);
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
      {
        const double u = double(i) / n, v = double(j) / n;
        worst = std::max(worst, distance(a + u * (b - a) + v * (c - a)));
      }
  }
  return worst;
}

/// Connected components of the triangles (sharing vertices).
int components(const tetdsr::ExactSurfaceMesh& s)
{
  std::vector<NodeId> parent(s.points.size() / 3);
  for (std::size_t i = 0; i < parent.size(); ++i)
    parent[i] = static_cast<NodeId>(i);
  std::function<NodeId(NodeId)> find = [&](NodeId x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
  for (std::size_t t = 0; t < s.triangles.size() / 3; ++t)
  {
    parent[find(s.triangles[3 * t + 1])] = find(s.triangles[3 * t]);
    parent[find(s.triangles[3 * t + 2])] = find(s.triangles[3 * t]);
  }
  std::set<NodeId> roots;
  for (std::size_t t = 0; t < s.triangles.size() / 3; ++t)
    roots.insert(find(s.triangles[3 * t]));
  return static_cast<int>(roots.size());
}

TEST(ExactSurface, SpheresOnQuadraticTetrahedra)
{
  // |x - c|^2 on straight quadratic tetrahedra: exact. Two nested spheres (two iso-values).
  auto mesh = tetdsr_test::makeLattice(3, glm::dvec3(0.0), 1.0);
  const glm::dvec3 centre(0.52, 0.47, 0.49);
  mesh.sample([&](const glm::dvec3& p) { return -glm::dot(p - centre, p - centre); });
  const tetdsr::MeshView view = mesh.view();
  tetdsr::Scene scene(view);
  const double radii[2] = { 0.21, 0.37 };
  // An array x + 2y (exact in the cells): its integral over a sphere is 4 pi r^2 (cx + 2 cy).
  std::vector<double> linear(mesh.points.size() / 3);
  for (std::size_t p = 0; p < linear.size(); ++p)
    linear[p] = mesh.points[3 * p] + 2.0 * mesh.points[3 * p + 1];
  tetdsr::ArrayView array;
  array.data = linear.data();
  array.tuples = static_cast<NodeId>(linear.size());
  array.name = "linear";
  const auto surface = extract(scene, { -radii[0] * radii[0], -radii[1] * radii[1] }, 2e-2, { array });
  ASSERT_GT(surface.triangles.size(), 0u);
  EXPECT_EQ(surface.boundaryEdges, 0);
  EXPECT_EQ(surface.nonManifoldEdges, 0);
  EXPECT_EQ(components(surface), 2);
  EXPECT_LE(surface.largestBound, surface.tolerance);
  for (std::size_t v = 0; v < surface.points.size() / 3; ++v)
  {
    const double r = glm::length(vertex(surface, static_cast<NodeId>(v)) - centre);
    EXPECT_TRUE(std::abs(r - radii[0]) < 1e-12 || std::abs(r - radii[1]) < 1e-12) << r;
    const glm::dvec3 n(surface.normals[3 * v], surface.normals[3 * v + 1], surface.normals[3 * v + 2]);
    // Toward higher values: inward.
    EXPECT_NEAR(glm::dot(n, glm::normalize(centre - vertex(surface, static_cast<NodeId>(v)))), 1.0, 1e-12);
    EXPECT_NEAR(surface.arrays[0][v], surface.points[3 * v] + 2.0 * surface.points[3 * v + 1], 1e-12);
  }
  const double hausdorff = triangleToSurface(surface, [&](const glm::dvec3& p) {
    const double r = glm::length(p - centre);
    return std::min(std::abs(r - radii[0]), std::abs(r - radii[1]));
  });
  EXPECT_LE(hausdorff, surface.tolerance);
  for (int k = 0; k < 2; ++k)
  {
    const auto& I = surface.integrals[static_cast<std::size_t>(k)];
    const double r = radii[k];
    const double area = 4.0 * kPi * r * r;
    EXPECT_LE(std::abs(I.area - area), I.areaError + 1e-12) << "area " << I.area << " vs " << area;
    EXPECT_LT(I.areaError, 1e-4 * area);
    const double volume = 4.0 / 3.0 * kPi * r * r * r; // field >= -r^2: inside
    EXPECT_LE(std::abs(I.volume - volume), I.volumeError + 1e-12) << "volume " << I.volume << " vs " << volume;
    EXPECT_LT(I.volumeError, 1e-2 * volume);
    EXPECT_NEAR(I.arrayIntegrals[0], area * (centre.x + 2.0 * centre.y), I.arrayErrors[0] + 1e-12);
    // The flat triangles' area is smaller than the sphere's, by more than the curved one's error.
    EXPECT_LT(I.flatArea, area - I.areaError);
  }
}

TEST(ExactSurface, SphereInsideOneCell)
{
  // One quadratic tetrahedron whose nodes all lie outside a small sphere: no sign change at its
  // nodes, a closed surface inside it.
  auto mesh = tetdsr_test::makeLattice(1, glm::dvec3(0.0), 1.0);
  const glm::dvec3 centre(0.55, 0.3, 0.18); // inside one of the six
  const double r = 0.05;
  mesh.sample([&](const glm::dvec3& p) { return glm::dot(p - centre, p - centre); });
  for (std::size_t p = 0; p < mesh.values.size(); ++p)
    ASSERT_GT(mesh.values[p], r * r);
  const tetdsr::MeshView view = mesh.view();
  tetdsr::Scene scene(view);
  const auto surface = extract(scene, { r * r }, 1e-2);
  EXPECT_EQ(components(surface), 1);
  EXPECT_EQ(surface.boundaryEdges, 0);
  EXPECT_EQ(surface.nonManifoldEdges, 0);
  const auto& I = surface.integrals[0];
  EXPECT_LE(std::abs(I.area - 4.0 * kPi * r * r), I.areaError + 1e-14);
  // field >= r^2: the cube outside the ball.
  EXPECT_LE(std::abs(I.volume - (1.0 - 4.0 / 3.0 * kPi * r * r * r)), I.volumeError + 1e-12);
  EXPECT_LE(triangleToSurface(surface, [&](const glm::dvec3& p) { return std::abs(glm::length(p - centre) - r); }),
    surface.tolerance);
}

TEST(ExactSurface, Settings)
{
  tetdsr::Messages messages;
  tetdsr::ExactSurfaceSettings settings;
  settings.isoValues = { 0.0 };
  settings.tolerance = -1.0;
  EXPECT_FALSE(tetdsr::checkExactSurfaceSettings(settings, messages));
  ASSERT_EQ(messages.errors.size(), 1u);
  EXPECT_NE(messages.errors[0].find("absolute tolerance"), std::string::npos);
  messages = {};
  settings.tolerance = 0.0;
  settings.relativeTolerance = std::nan("");
  EXPECT_FALSE(tetdsr::checkExactSurfaceSettings(settings, messages));
  messages = {};
  settings.relativeTolerance = 1e-3;
  settings.isoValues = { std::nan("") };
  EXPECT_FALSE(tetdsr::checkExactSurfaceSettings(settings, messages));
}

} // namespace
