// What makes primary rays cheaper must not change a single pixel: the face test before a cell's
// record, the frustum culling of pixel blocks, and hints from the last frame (reprojection).
// Each is checked against the plain per-ray answer, bit for bit, on irregular meshes and
// cameras near and far.
#include "ImageBuffers.h"
#include "LatticeMesh.h"
#include "tetdsr/render/Renderer.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using Image = tetdsr_test::ImageBuffers;
using tetdsr_test::LatticeMesh;
using tetdsr_test::makeLattice;

namespace
{
/// A 7^3 lattice with every interior vertex moved at random by up to a third of a step (tets of
/// every shape, slivers included; mid-edge nodes kept at the midpoints: straight cells), with the
/// wave field: many transverse cells, several surfaces along a ray.
LatticeMesh jitteredWaveLattice()
{
  LatticeMesh mesh = makeLattice(7, glm::dvec3(0.0), 1.0);
  std::mt19937 random(17);
  std::uniform_real_distribution<double> jitter(-1.0 / 21.0, 1.0 / 21.0);
  mesh.mapVertices([&](const glm::dvec3& x, const std::array<int, 3>& k) {
    const bool interior = k[0] > 0 && k[0] < 14 && k[1] > 0 && k[1] < 14 && k[2] > 0 && k[2] < 14;
    const bool vertex = k[0] % 2 == 0 && k[1] % 2 == 0 && k[2] % 2 == 0;
    return vertex && interior ? x + glm::dvec3(jitter(random), jitter(random), jitter(random)) : x;
  });
  mesh.sample([](const glm::dvec3& x) { return std::sin(7.0 * x.x) * std::cos(5.0 * x.y) + std::sin(6.0 * x.z + 1.0); });
  return mesh;
}

bool sameHit(bool foundA, const tetdsr::SurfaceHit& a, bool foundB, const tetdsr::SurfaceHit& b)
{
  return foundA == foundB &&
    (!foundA || (a.t == b.t && a.cellId == b.cellId && a.isoIndex == b.isoIndex && a.gradient == b.gradient));
}

tetdsr::RenderSettings headlight()
{
  tetdsr::RenderSettings settings;
  settings.lighting.lights.push_back(tetdsr::Light{});
  settings.lighting.headlightOnly = true;
  return settings;
}
} // namespace

TEST(Coherence, FaceTestKeepsEveryHit)
{
  // The index with records tests each cell's faces in float before its record; the one without
  // records (memory limit 0) has no faces and tests every cell whose box the ray meets.
  const LatticeMesh mesh = jitteredWaveLattice();
  const tetdsr::Scene scene(mesh.view());
  ASSERT_EQ(scene.summary().validCells, 7 * 7 * 7 * 6);
  const tetdsr::IsoValues iso({ 0.3, -0.5 });
  const tetdsr::SurfaceIndex culled(scene, iso);
  const tetdsr::SurfaceIndex plain(scene, iso, tetdsr::serialFor, nullptr, 0);
  ASSERT_TRUE(culled.keepsRecords());
  ASSERT_FALSE(plain.keepsRecords());
  // Cameras near (inside the mesh), at a usual distance, and 1e6 mesh sizes away; rays at
  // random, many grazing cell faces.
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int hits = 0, differences = 0;
  for (const double distance : { 0.3, 3.0, 1e6 })
  {
    for (int r = 0; r < 4000; ++r)
    {
      const glm::dvec3 target(unit(random), unit(random), unit(random));
      glm::dvec3 from(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5);
      from = glm::dvec3(0.5) + distance * glm::normalize(from);
      const tetdsr::Ray ray{ from, glm::normalize(target - from) };
      tetdsr::SurfaceHit a, b;
      const bool foundA = culled.firstHit(ray, a);
      const bool foundB = plain.firstHit(ray, b);
      hits += foundA;
      differences += !sameHit(foundA, a, foundB, b);
    }
  }
  std::printf("face test: %d hits of 12000 rays, %d differences\n", hits, differences);
  EXPECT_GT(hits, 6000);
  EXPECT_EQ(differences, 0);
}

TEST(Coherence, HintsNeverChangeTheHit)
{
  // Any entry as a hint (the right cell, a neighbour, a cell far off, an entry out of range)
  // gives the same nearest hit as no hint.
  const LatticeMesh mesh = jitteredWaveLattice();
  const tetdsr::Scene scene(mesh.view());
  const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ 0.3 }));
  ASSERT_GT(surface.entries(), 100u);
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.1, 1.6, 3.0);
  camera.focalPoint = glm::dvec3(0.5);
  const tetdsr::RayGenerator rays(camera, 64, 64);
  std::mt19937 random(9);
  int hits = 0, hintedHits = 0, differences = 0;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i)
    {
      const tetdsr::Ray ray = rays.pixelRay(i, j);
      tetdsr::SurfaceHit plain;
      const bool found = surface.firstHit(ray, plain);
      hits += found;
      const std::uint32_t hints[] = { found ? plain.entry : 0u,
        static_cast<std::uint32_t>(random() % surface.entries()), surface.entries(), tetdsr::kNoEntry };
      for (const std::uint32_t hint : hints)
      {
        tetdsr::SurfaceHit hinted;
        const bool foundHinted = surface.firstHit(ray, hinted, 0.0, std::numeric_limits<double>::infinity(), hint);
        differences += !sameHit(found, plain, foundHinted, hinted);
        hintedHits += foundHinted && hinted.entry == plain.entry;
      }
      // A window that ends before the hint's crossing: that crossing is not taken.
      if (found)
      {
        tetdsr::SurfaceHit early;
        differences += surface.firstHit(ray, early, 0.0, 0.999 * plain.t, plain.entry) &&
          early.t >= 0.999 * plain.t;
      }
    }
  std::printf("hints: %d hits of 4096 rays, %d differences\n", hits, differences);
  EXPECT_GT(hits, 1000);
  EXPECT_EQ(differences, 0);
  EXPECT_EQ(hintedHits, 4 * hits);
}

TEST(Coherence, FrustumCulledBlocksAreExactlyTheMisses)
{
  // Every pixel of the renderer (which skips blocks whose frustum meets no transverse box) must
  // equal the per-ray query, for cameras that see the mesh in part, from inside, from far away,
  // in parallel projection and through a projection matrix.
  const LatticeMesh mesh = jitteredWaveLattice();
  const tetdsr::Scene scene(mesh.view());
  const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ 0.3, -0.5 }));
  std::vector<tetdsr::RayGenerator> generators;
  const int width = 83, height = 61; // tiles and blocks cut at the edges
  for (const auto& [position, angle, parallel] :
    { std::make_tuple(glm::dvec3(2.1, 1.6, 3.0), 30.0, false), std::make_tuple(glm::dvec3(0.9, 0.8, 1.1), 60.0, false),
      std::make_tuple(glm::dvec3(0.5, 0.4, 0.45), 90.0, false), std::make_tuple(glm::dvec3(1.5e6, 1.2e6, 2.0e6), 4e-5, false),
      std::make_tuple(glm::dvec3(2.1, 1.6, 3.0), 0.0, true) })
  {
    tetdsr::Camera camera;
    camera.position = position;
    camera.focalPoint = glm::dvec3(0.7, 0.6, 0.5); // off centre: the mesh in part of the image
    camera.viewAngleDegrees = parallel ? 30.0 : angle;
    camera.parallelProjection = parallel;
    camera.parallelScale = 0.4;
    generators.emplace_back(camera, width, height);
  }
  const glm::dmat4 worldToNdc = glm::perspective(glm::radians(40.0), double(width) / height, 0.5, 20.0) *
    glm::lookAt(glm::dvec3(-1.2, 2.0, 2.2), glm::dvec3(0.8, 0.3, 0.6), glm::dvec3(0.0, 1.0, 0.0));
  generators.emplace_back(glm::inverse(worldToNdc), width, height);
  int covered = 0, missed = 0, differences = 0;
  for (const tetdsr::RayGenerator& rays : generators)
  {
    Image image(width, height);
    const tetdsr::Renderer renderer(surface, rays, headlight(), image.view());
    renderer.renderTiles(0, renderer.numberOfTiles());
    for (int j = 0; j < height; ++j)
      for (int i = 0; i < width; ++i)
      {
        tetdsr::SurfaceHit hit;
        const bool found = surface.firstHit(rays.pixelRay(i, j), hit);
        const std::size_t p = std::size_t(j) * width + i;
        covered += found;
        missed += !found;
        differences += found ? !(image.depth[p] == hit.t && image.cellIds[p] == hit.cellId)
                             : !(std::isinf(image.depth[p]) && image.cellIds[p] == -1 && image.colors[4 * p + 3] == 0);
      }
  }
  std::printf("frustum culling: %d covered and %d missed pixels, %d differences\n", covered, missed, differences);
  EXPECT_GT(covered, 5000);
  EXPECT_GT(missed, 5000);
  EXPECT_EQ(differences, 0);
}

TEST(Coherence, ReprojectedHintsGiveTheSameImage)
{
  // An orbit of 3-degree steps through projection matrices (as the mapper casts): each frame
  // cast with the last frame's hits reprojected as hints equals the frame cast without, and most
  // hints name the very cell the pixel's ray hits.
  const LatticeMesh mesh = jitteredWaveLattice();
  const tetdsr::Scene scene(mesh.view());
  const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ 0.3 }));
  const int width = 96, height = 80;
  const glm::dmat4 projection = glm::perspective(glm::radians(30.0), double(width) / height, 1.0, 10.0);
  auto worldToNdc = [&](int frame) {
    const double a = glm::radians(3.0 * frame);
    const glm::dvec3 eye(0.5 + 2.6 * std::sin(a), 1.7, 0.5 + 2.6 * std::cos(a));
    return projection * glm::lookAt(eye, glm::dvec3(0.5), glm::dvec3(0.0, 1.0, 0.0));
  };
  Image last(width, height), plain(width, height), hinted(width, height);
  {
    const tetdsr::Renderer first(surface, tetdsr::RayGenerator(glm::inverse(worldToNdc(0)), width, height),
      headlight(), last.view());
    first.renderTiles(0, first.numberOfTiles());
  }
  std::vector<std::uint32_t> hints(std::size_t(width) * height);
  int covered = 0, hintedPixels = 0, rightCell = 0, differences = 0;
  for (int frame = 1; frame <= 4; ++frame)
  {
    const tetdsr::RayGenerator rays(glm::inverse(worldToNdc(frame)), width, height);
    tetdsr::reprojectHits(tetdsr::RayGenerator(glm::inverse(worldToNdc(frame - 1)), width, height), width,
      height, last.depth.data(), last.entries.data(), worldToNdc(frame), width, height, hints.data());
    tetdsr::ImageView hintedView = hinted.view();
    hintedView.entryHints = hints.data();
    const tetdsr::Renderer withHints(surface, rays, headlight(), hintedView);
    withHints.renderTiles(0, withHints.numberOfTiles());
    const tetdsr::Renderer without(surface, rays, headlight(), plain.view());
    without.renderTiles(0, without.numberOfTiles());
    differences += plain.depth != hinted.depth || plain.colors != hinted.colors || plain.normals != hinted.normals ||
      plain.cellIds != hinted.cellIds;
    for (std::size_t p = 0; p < hints.size(); ++p)
    {
      if (std::isfinite(plain.depth[p]))
      {
        ++covered;
        hintedPixels += hints[p] != tetdsr::kNoEntry;
        rightCell += hints[p] == plain.entries[p];
      }
    }
    std::swap(last, hinted);
  }
  std::printf("reprojection: %d covered pixels, %d with a hint, %d hints the hit cell, %d frames differ\n",
    covered, hintedPixels, rightCell, differences);
  EXPECT_EQ(differences, 0);
  EXPECT_GT(covered, 4 * 1500);
  EXPECT_GT(hintedPixels, 0.9 * covered);
  EXPECT_GT(rightCell, 0.5 * covered);
}
