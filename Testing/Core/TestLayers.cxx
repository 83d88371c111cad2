// Translucent surfaces cast apart, by several processes each over the cells it holds, must
// composite to the picture of the whole mesh: every crossing of every piece, sorted along each
// ray (compositeLayers), as one Renderer composites a ray's crossings.
#include "ImageBuffers.h"
#include "LatticeMesh.h"
#include "tetdsr/render/LayerExchange.h"
#include "tetdsr/render/Renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

using Image = tetdsr_test::ImageBuffers;
using tetdsr_test::LatticeMesh;
using tetdsr_test::makeLattice;

namespace
{
/// The wave field on a jittered 6^3 lattice: several nested translucent crossings per ray.
LatticeMesh waveLattice()
{
  LatticeMesh mesh = makeLattice(6, glm::dvec3(0.0), 1.0);
  std::mt19937 random(23);
  std::uniform_real_distribution<double> jitter(-1.0 / 18.0, 1.0 / 18.0);
  mesh.mapVertices([&](const glm::dvec3& x, const std::array<int, 3>& k) {
    const bool interior = k[0] > 0 && k[0] < 12 && k[1] > 0 && k[1] < 12 && k[2] > 0 && k[2] < 12;
    return interior ? x + glm::dvec3(jitter(random), jitter(random), jitter(random)) : x;
  });
  mesh.sample([](const glm::dvec3& x) { return std::sin(6.0 * x.x) * std::cos(5.0 * x.y) + std::sin(5.0 * x.z + 1.0); });
  return mesh;
}

/// The cells of `mesh` that `keep` chooses (all points kept).
LatticeMesh piece(const LatticeMesh& mesh, const std::function<bool(std::size_t)>& keep)
{
  LatticeMesh part = mesh;
  part.cellNodes.clear();
  for (std::size_t c = 0; c < mesh.cellNodes.size() / 10; ++c)
  {
    if (keep(c))
    {
      part.cellNodes.insert(part.cellNodes.end(), mesh.cellNodes.begin() + 10 * c, mesh.cellNodes.begin() + 10 * (c + 1));
    }
  }
  return part;
}

tetdsr::RenderSettings translucentSettings()
{
  tetdsr::RenderSettings settings;
  settings.lighting.lights.push_back(tetdsr::Light{});
  settings.lighting.headlightOnly = true;
  settings.isoStyles = { { glm::dvec3(0.9, 0.4, 0.2), 0.45 }, { glm::dvec3(0.2, 0.5, 0.9), 0.6 }, { glm::dvec3(0.8, 0.8, 0.3), 1.0 } };
  return settings;
}

/// Every tile's crossings in one list.
std::vector<tetdsr::PixelLayer> flatten(const std::vector<std::vector<tetdsr::PixelLayer>>& tiles)
{
  std::vector<tetdsr::PixelLayer> all;
  for (const auto& tile : tiles)
    all.insert(all.end(), tile.begin(), tile.end());
  return all;
}

int maxDifference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int& differing)
{
  int worst = 0;
  differing = 0;
  for (std::size_t p = 0; p < a.size() / 4; ++p)
  {
    int d = 0;
    for (int c = 0; c < 4; ++c)
    {
      d = std::max(d, std::abs(int(a[4 * p + c]) - int(b[4 * p + c])));
    }
    worst = std::max(worst, d);
    differing += d > 0;
  }
  return worst;
}
} // namespace

TEST(Layers, PiecesCompositeToTheWhole)
{
  const LatticeMesh mesh = waveLattice();
  const tetdsr::IsoValues iso({ 0.3, -0.4, 1.2 });
  const int width = 90, height = 70;
  tetdsr::Camera camera;
  camera.position = glm::dvec3(2.3, 1.7, 2.9);
  camera.focalPoint = glm::dvec3(0.5);
  const tetdsr::RayGenerator rays(camera, width, height);
  const tetdsr::RenderSettings settings = translucentSettings();

  const tetdsr::Scene wholeScene(mesh.view());
  const tetdsr::SurfaceIndex wholeSurface(wholeScene, iso);
  Image whole(width, height);
  std::vector<std::vector<tetdsr::PixelLayer>> wholeLayers;
  const tetdsr::Renderer wholeRenderer(wholeSurface, rays, settings, whole.view(&wholeLayers));
  wholeRenderer.renderTiles(0, wholeRenderer.numberOfTiles());
  std::size_t layerCount = 0, multiLayer = 0;
  {
    std::vector<int> perPixel(std::size_t(width) * height, 0);
    for (const auto& tile : wholeLayers)
      for (const tetdsr::PixelLayer& layer : tile)
        ++perPixel[layer.pixel], ++layerCount;
    multiLayer = std::size_t(std::count_if(perPixel.begin(), perPixel.end(), [](int n) { return n >= 3; }));
  }
  const double gap = tetdsr::Renderer::kLayerGap * wholeScene.diagonal();

  // The whole mesh's own layers composite to its image exactly.
  {
    std::vector<tetdsr::PixelLayer> all = flatten(wholeLayers);
    std::vector<std::uint8_t> colors(whole.colors.size());
    tetdsr::compositeLayers(all, std::size_t(width) * height, gap, nullptr, colors.data());
    int differing;
    EXPECT_EQ(maxDifference(colors, whole.colors, differing), 0);
  }

  // Pieces: cells alternating (every ray's crossings interleave between them), and two halves.
  const std::vector<std::function<bool(std::size_t)>> splits[] = {
    { [](std::size_t c) { return c % 2 == 0; }, [](std::size_t c) { return c % 2 == 1; } },
    { [](std::size_t c) { return c % 3 == 0; }, [](std::size_t c) { return c % 3 == 1; }, [](std::size_t c) { return c % 3 == 2; } },
  };
  for (const auto& split : splits)
  {
    std::vector<tetdsr::PixelLayer> all;
    std::vector<std::vector<std::uint8_t>> pieceColors;
    for (const auto& keep : split)
    {
      const LatticeMesh part = piece(mesh, keep);
      const tetdsr::Scene scene(part.view());
      const tetdsr::SurfaceIndex surface(scene, iso);
      Image image(width, height);
      std::vector<std::vector<tetdsr::PixelLayer>> layers;
      const tetdsr::Renderer renderer(surface, rays, settings, image.view(&layers));
      renderer.renderTiles(0, renderer.numberOfTiles());
      // As a process sends its crossings: packed into doubles, read back by the receiver.
      std::vector<double> packed;
      tetdsr::packLayers(layers, packed);
      tetdsr::unpackLayers(packed.data(), packed.size(), all);
      pieceColors.push_back(image.colors);
    }
    std::vector<std::uint8_t> colors(whole.colors.size());
    tetdsr::compositeLayers(all, std::size_t(width) * height, gap, nullptr, colors.data());
    int differing;
    const int worst = maxDifference(colors, whole.colors, differing);
    // What compositing each piece's finished colour would give instead (piece 0 over the rest):
    // the test must be able to fail.
    std::vector<std::uint8_t> naive(whole.colors.size());
    for (std::size_t p = 0; p < naive.size() / 4; ++p)
    {
      double c[3] = { 0, 0, 0 }, a = 0.0;
      for (const auto& image : pieceColors)
      {
        const double alpha = image[4 * p + 3] / 255.0;
        for (int k = 0; k < 3; ++k)
          c[k] += (1.0 - a) * alpha * image[4 * p + k] / 255.0;
        a += (1.0 - a) * alpha;
      }
      for (int k = 0; k < 3; ++k)
        naive[4 * p + k] = a > 0 ? std::uint8_t(std::min(c[k] / a, 1.0) * 255.0 + 0.5) : 0;
      naive[4 * p + 3] = std::uint8_t(a * 255.0 + 0.5);
    }
    int naiveDiffering;
    const int naiveWorst = maxDifference(naive, whole.colors, naiveDiffering);
    std::printf("%zu pieces: %zu crossings over %zu pixels with 3 or more; merged layers: %d pixels "
                "differ (max %d / 255); pieces' colours blended in piece order: %d pixels (max %d)\n",
      split.size(), layerCount, multiLayer, differing, worst, naiveDiffering, naiveWorst);
    EXPECT_GT(multiLayer, 400u);
    EXPECT_LE(worst, 1); // rounding of the sum's order only
    EXPECT_GT(naiveDiffering, 400);
  }
}

TEST(Layers, PackedCrossingsReadBackExactly)
{
  // Crossings with every field distinct, at pixels up to 2^32 - 1, renumbered and not.
  std::vector<std::vector<tetdsr::PixelLayer>> tiles(2);
  tiles[0].push_back({ 7u, 0.125, glm::dvec3(0.1, 0.2, 0.3), 0.45 });
  tiles[0].push_back({ 4294967295u, 1e300, glm::dvec3(1.0 / 3.0, 2.0 / 3.0, 1.0), 1.0 });
  tiles[1].push_back({ 0u, -0.0, glm::dvec3(0.0), 1e-300 });
  std::vector<double> packed;
  tetdsr::packLayers(tiles, packed);
  tetdsr::packLayer(tiles[0][0], 12345u, packed);
  ASSERT_EQ(packed.size(), 4 * tetdsr::kPackedLayerSize);
  packed.push_back(99.0); // a partial record: not read
  std::vector<tetdsr::PixelLayer> layers;
  tetdsr::unpackLayers(packed.data(), packed.size(), layers);
  ASSERT_EQ(layers.size(), 4u) << "expected 4 crossings, got " << layers.size();
  const tetdsr::PixelLayer expected[4] = { tiles[0][0], tiles[0][1], tiles[1][0],
    { 12345u, tiles[0][0].t, tiles[0][0].color, tiles[0][0].opacity } };
  for (int k = 0; k < 4; ++k)
  {
    EXPECT_EQ(layers[k].pixel, expected[k].pixel) << "crossing " << k;
    EXPECT_EQ(layers[k].t, expected[k].t) << "crossing " << k;
    EXPECT_EQ(layers[k].color, expected[k].color) << "crossing " << k;
    EXPECT_EQ(layers[k].opacity, expected[k].opacity) << "crossing " << k;
  }
}

TEST(Layers, RayLimitsAndDuplicates)
{
  // A crossing beyond the pixel's limit is dropped; one found twice (two pieces sharing a face)
  // counts once; an opaque crossing ends the pixel.
  std::vector<tetdsr::PixelLayer> layers = {
    { 0, 2.0, glm::dvec3(1.0, 0.0, 0.0), 0.5 }, { 0, 1.0, glm::dvec3(0.0, 1.0, 0.0), 0.5 },
    { 0, 1.0 + 1e-12, glm::dvec3(0.0, 1.0, 0.0), 0.5 }, // the same surface again
    { 1, 1.0, glm::dvec3(0.0, 0.0, 1.0), 1.0 }, { 1, 3.0, glm::dvec3(1.0, 0.0, 0.0), 0.5 },
    { 2, 5.0, glm::dvec3(1.0, 1.0, 1.0), 0.5 },
  };
  const double limits[3] = { 10.0, 10.0, 4.0 };
  std::uint8_t colors[12];
  tetdsr::compositeLayers(layers, 3, 1e-9, limits, colors);
  // Pixel 0: green 0.5 then red 0.5 behind: premultiplied (0.25, 0.5, 0), opacity 0.75.
  EXPECT_EQ(colors[0], 85);
  EXPECT_EQ(colors[1], 170);
  EXPECT_EQ(colors[2], 0);
  EXPECT_EQ(colors[3], 191);
  // Pixel 1: the opaque blue only.
  EXPECT_EQ(colors[4], 0);
  EXPECT_EQ(colors[6], 255);
  EXPECT_EQ(colors[7], 255);
  // Pixel 2: beyond its limit: nothing.
  EXPECT_EQ(colors[11], 0);
}

// What the faces say about compositing across processes is written here, once.
TEST(Layers, CompositingMessages)
{
  tetdsr::Messages messages;
  tetdsr::describeMismatchedViews(0, 4, messages);
  EXPECT_TRUE(messages.warnings.empty());
  tetdsr::describeMismatchedViews(1, 4, messages);
  ASSERT_EQ(messages.warnings.size(), 1u);
  EXPECT_EQ(messages.warnings[0].rfind("1 of 4 processes cast a view of another size", 0), 0u);
  tetdsr::describeOrderedCompositing(3, messages);
  ASSERT_EQ(messages.warnings.size(), 2u);
  EXPECT_NE(messages.warnings[1].find("composites the images of its 3 rendering processes in order"),
    std::string::npos);
  tetdsr::describeCompositingFailure(messages);
  EXPECT_EQ(messages.errors.size(), 1u);
}
