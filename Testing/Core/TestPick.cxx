// Picking: what the ray through a display position sees first, against the exact ray/sphere
// hit of a field the cells hold exactly (|x - c|^2 is quadratic), with and without a capped
// clipping plane; and picks at pixel centres against the rendered image, bit for bit.
#include "ImageBuffers.h"
#include "LatticeMesh.h"
#include "tetdsr/render/Renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

using tetdsr_test::LatticeMesh;
using tetdsr_test::makeLattice;

namespace
{
const glm::dvec3 kCentre(0.5, 0.5, 0.5);
constexpr double kRadius = 0.3;

/// The exact crossings of the sphere (false if the ray misses it).
bool sphereCrossings(const tetdsr::Ray& ray, double& near, double& far)
{
  const double b = glm::dot(ray.direction, ray.origin - kCentre);
  const double c = glm::dot(ray.origin - kCentre, ray.origin - kCentre) - kRadius * kRadius;
  const double disc = b * b - c;
  if (disc < 0.0)
  {
    return false;
  }
  near = -b - std::sqrt(disc);
  far = -b + std::sqrt(disc);
  return true;
}

LatticeMesh sphereLattice()
{
  LatticeMesh mesh = makeLattice(4, glm::dvec3(0.0), 1.0);
  mesh.sample([](const glm::dvec3& x) { return glm::dot(x - kCentre, x - kCentre); });
  return mesh;
}

tetdsr::RenderSettings lit()
{
  tetdsr::RenderSettings settings;
  settings.lighting.lights.push_back(tetdsr::Light{});
  settings.lighting.headlightOnly = true;
  return settings;
}

/// The point given by VTK parametric coordinates in an (affine) cell of the lattice.
glm::dvec3 fromParametric(const LatticeMesh& mesh, tetdsr::NodeId cell, const double r[3])
{
  const glm::dvec3 v0 = mesh.point(mesh.cellNodes[10 * cell]);
  glm::dvec3 p = v0;
  for (int k = 0; k < 3; ++k)
  {
    p += r[k] * (mesh.point(mesh.cellNodes[10 * cell + k + 1]) - v0);
  }
  return p;
}
} // namespace

TEST(Pick, ExactSphereAtRandomDisplayPositions)
{
  const LatticeMesh mesh = sphereLattice();
  const tetdsr::Scene scene(mesh.view());
  const tetdsr::IsoValues iso({ 2.0, kRadius * kRadius }); // the first far outside: no surface
  const tetdsr::SurfaceIndex surface(scene, iso);
  tetdsr::Camera camera;
  camera.position = glm::dvec3(1.3, 1.1, 1.6);
  camera.focalPoint = kCentre;
  const int width = 64, height = 48;
  const tetdsr::RayGenerator rays(camera, width, height);
  tetdsr_test::ImageBuffers image(width, height);
  const tetdsr::Renderer renderer(surface, rays, lit(), image.view());
  renderer.renderTiles(0, renderer.numberOfTiles());
  const double diagonal = std::sqrt(3.0);

  std::mt19937 random(31);
  std::uniform_real_distribution<double> x(0.0, width), y(0.0, height);
  int hits = 0, misses = 0;
  double depthError = 0.0, normalError = 0.0, valueError = 0.0, parametricError = 0.0;
  for (int k = 0; k < 4000; ++k)
  {
    const tetdsr::Ray ray = rays.displayRay(x(random), y(random));
    double near, far;
    const bool exact = sphereCrossings(ray, near, far);
    tetdsr::Pick pick;
    const bool found = renderer.pick(ray, pick);
    // Grazing rays (within 1e-6 of the silhouette) may go either way.
    const double b = glm::dot(ray.direction, ray.origin - kCentre);
    const double grazing = std::abs(b * b - (glm::dot(ray.origin - kCentre, ray.origin - kCentre) - kRadius * kRadius));
    if (grazing < 1e-6)
    {
      continue;
    }
    ASSERT_EQ(found, exact);
    if (!found)
    {
      ++misses;
      continue;
    }
    ++hits;
    EXPECT_EQ(pick.isoValue, 1);
    depthError = std::max(depthError, std::abs(pick.t - near) / diagonal);
    normalError = std::max(normalError, glm::length(pick.normal - glm::normalize(pick.point - kCentre)));
    valueError = std::max(valueError, std::abs(pick.value - kRadius * kRadius));
    ASSERT_TRUE(pick.hasParametric);
    parametricError = std::max(parametricError, glm::length(fromParametric(mesh, pick.cellId, pick.parametric) - pick.point));
  }
  std::printf("picks: %d hits, %d misses; depth within %.1e of the diagonal, normal %.1e, value "
              "%.1e, point from parametric coordinates %.1e\n",
    hits, misses, depthError, normalError, valueError, parametricError);
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 1000);
  EXPECT_LT(depthError, 1e-9);
  EXPECT_LT(normalError, 1e-9);
  EXPECT_LT(valueError, 1e-12);
  EXPECT_LT(parametricError, 1e-12);

  // At pixel centres a pick is the pixel's hit, bit for bit.
  int differences = 0;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
    {
      const std::size_t p = std::size_t(j) * width + i;
      tetdsr::Pick pick;
      const bool found = renderer.pick(rays.displayRay(i + 0.5, j + 0.5), pick);
      differences += found != std::isfinite(image.depth[p]) ||
        (found && (pick.t != image.depth[p] || pick.cellId != image.cellIds[p]));
    }
  EXPECT_EQ(differences, 0);
}

TEST(Pick, CapOfAClippedSphere)
{
  // Keep z <= 0.5 (the camera above): rays enter the kept side on the plane, where the cap
  // covers the disc inside the sphere; elsewhere they see the sphere beyond the plane.
  const LatticeMesh mesh = sphereLattice();
  const tetdsr::Scene scene(mesh.view());
  const tetdsr::IsoValues iso({ kRadius * kRadius });
  const tetdsr::SurfaceIndex surface(scene, iso);
  tetdsr::RenderSettings settings = lit();
  settings.clipPlanes.push_back({ kCentre, glm::dvec3(0.0, 0.0, -2.0) });
  settings.cap = tetdsr::CapRegion::BelowIsoValue;
  tetdsr::Camera camera;
  camera.position = glm::dvec3(1.4, 0.6, 1.0);
  camera.focalPoint = kCentre;
  const tetdsr::RayGenerator rays(camera, 64, 64);
  tetdsr_test::ImageBuffers image(64, 64);
  const tetdsr::Renderer renderer(surface, rays, settings, image.view());
  std::mt19937 random(7);
  std::uniform_real_distribution<double> x(0.0, 64.0);
  int caps = 0, surfaces = 0, wrong = 0;
  double error = 0.0;
  for (int k = 0; k < 3000; ++k)
  {
    const tetdsr::Ray ray = rays.displayRay(x(random), x(random));
    const double tPlane = (kCentre.z - ray.origin.z) / ray.direction.z;
    const glm::dvec3 onPlane = ray.origin + tPlane * ray.direction;
    const double inside = kRadius * kRadius - glm::dot(onPlane - kCentre, onPlane - kCentre);
    double near, far;
    const bool crosses = sphereCrossings(ray, near, far);
    if (std::abs(inside) < 1e-9 || (crosses && std::abs(far - tPlane) < 1e-9))
    {
      continue; // on the disc's edge
    }
    tetdsr::Pick pick;
    const bool found = renderer.pick(ray, pick);
    if (inside > 0.0)
    {
      ++caps;
      wrong += !found || pick.isoValue != -1;
      if (found)
      {
        error = std::max(error, std::abs(pick.t - tPlane));
        error = std::max(error, glm::length(pick.normal - glm::dvec3(0.0, 0.0, -1.0)));
        error = std::max(error, std::abs(pick.value - glm::dot(onPlane - kCentre, onPlane - kCentre)));
      }
    }
    else if (crosses && far >= tPlane)
    {
      ++surfaces;
      const double expected = near >= tPlane ? near : far; // (near < tPlane: cut away)
      wrong += !found || pick.isoValue != 0;
      if (found)
      {
        error = std::max(error, std::abs(pick.t - expected));
      }
    }
    else
    {
      wrong += found;
    }
  }
  std::printf("clipped sphere: %d cap picks, %d surface picks, %d wrong, largest error %.1e\n",
    caps, surfaces, wrong, error);
  EXPECT_GT(caps, 300);
  EXPECT_GT(surfaces, 100);
  EXPECT_EQ(wrong, 0);
  EXPECT_LT(error, 1e-9);
}
