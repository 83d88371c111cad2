// Per-sample coverage of a cast's silhouettes (tetdsr/render/Multisampling.h) against brute
// force: a sphere seen by a perspective camera, the cast one ray a pixel centre, then every
// pixel's mask against one ray per sample position cast here for every pixel; the images of
// pixels whose centre sees the sphere unchanged; a pixel whose centre misses it but some samples
// see it filled with the nearest covered sample's ray parameter and its first hit neighbour's
// colour and normal (edge neighbours first); more sample positions than a mask holds cut to 8.
#include "tetdsr/render/Multisampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace
{
constexpr int kWidth = 48, kHeight = 36;
constexpr double kRadius = 0.7;
const double kInf = std::numeric_limits<double>::infinity();

/// The sphere |x - (0.1, -0.05, 0)| = kRadius's first hit along a ray, +inf on a miss.
double sphereHit(const tetdsr::Ray& ray)
{
  const glm::dvec3 oc = ray.origin - glm::dvec3(0.1, -0.05, 0.0);
  const double b = glm::dot(oc, ray.direction);
  const double disc = b * b - (glm::dot(oc, oc) - kRadius * kRadius);
  return disc >= 0.0 ? -b - std::sqrt(disc) : kInf;
}

struct Cast
{
  tetdsr::RayGenerator rays;
  std::vector<double> depth, normals;
  std::vector<std::uint8_t> colors, masks;

  Cast()
    : rays(camera(), kWidth, kHeight)
    , depth(kWidth * kHeight)
    , normals(3 * kWidth * kHeight)
    , colors(4 * kWidth * kHeight)
    , masks(kWidth * kHeight, 0xAA)
  {
    for (int j = 0; j < kHeight; ++j)
    {
      for (int i = 0; i < kWidth; ++i)
      {
        const std::size_t p = static_cast<std::size_t>(j) * kWidth + i;
        depth[p] = sphereHit(rays.pixelRay(i, j));
        const bool hit = std::isfinite(depth[p]);
        for (int c = 0; c < 4; ++c) // (each hit pixel's own colour and normal; misses zero)
        {
          colors[4 * p + c] = hit ? static_cast<std::uint8_t>((p * 7 + c * 31) % 251 + 1) : 0;
        }
        for (int c = 0; c < 3; ++c)
        {
          normals[3 * p + c] = hit ? static_cast<double>(p) + 0.25 * c : 0.0;
        }
      }
    }
  }
  static tetdsr::Camera camera()
  {
    tetdsr::Camera c;
    c.position = { 0.3, 0.2, 3.0 };
    return c;
  }
  void cover(const std::vector<glm::dvec2>& samples)
  {
    // (Rows in parts of 5, as threads would split them.)
    tetdsr::multisampleCoverage(rays, sphereHit, samples, kWidth, kHeight, depth.data(),
      colors.data(), normals.data(), masks.data(), [](tetdsr::NodeId count, const auto& body) {
        for (tetdsr::NodeId begin = 0; begin < count; begin += 5)
        {
          body(begin, std::min<tetdsr::NodeId>(begin + 5, count));
        }
      });
  }
};

// Mesa's and Direct3D's standard 4-sample positions.
const std::vector<glm::dvec2> kFour = { { 0.375, 0.125 }, { 0.875, 0.375 }, { 0.125, 0.625 },
  { 0.625, 0.875 } };
} // namespace

TEST(Multisampling, MasksEqualOneRayPerSampleEverywhere)
{
  Cast before, cast;
  cast.cover(kFour);
  int partial = 0, filled = 0;
  for (int j = 0; j < kHeight; ++j)
  {
    for (int i = 0; i < kWidth; ++i)
    {
      const std::size_t p = static_cast<std::size_t>(j) * kWidth + i;
      std::uint8_t expected = 0;
      double nearest = kInf;
      for (std::size_t k = 0; k < kFour.size(); ++k)
      {
        const double t = sphereHit(cast.rays.displayRay(i + kFour[k].x, j + kFour[k].y));
        if (std::isfinite(t))
        {
          expected = static_cast<std::uint8_t>(expected | (1u << k));
          nearest = std::min(nearest, t);
        }
      }
      ASSERT_EQ(cast.masks[p], expected) << "pixel " << i << ", " << j;
      partial += expected != 0 && expected != 0xF;
      if (std::isfinite(before.depth[p]))
      {
        // A hit pixel keeps its cast: depth, colour and normal.
        EXPECT_EQ(cast.depth[p], before.depth[p]);
        for (int c = 0; c < 4; ++c)
        {
          EXPECT_EQ(cast.colors[4 * p + c], before.colors[4 * p + c]);
        }
        continue;
      }
      if (expected == 0)
      {
        EXPECT_FALSE(std::isfinite(cast.depth[p]));
        continue;
      }
      // Filled: the nearest covered sample's parameter, the first hit neighbour's colour.
      ++filled;
      EXPECT_EQ(cast.depth[p], nearest);
      constexpr int order[8][2] = { { -1, 0 }, { 1, 0 }, { 0, -1 }, { 0, 1 }, { -1, -1 },
        { 1, -1 }, { -1, 1 }, { 1, 1 } };
      std::size_t from = p;
      for (const auto& d : order)
      {
        const int ni = i + d[0], nj = j + d[1];
        if (ni >= 0 && nj >= 0 && ni < kWidth && nj < kHeight &&
          std::isfinite(before.depth[static_cast<std::size_t>(nj) * kWidth + ni]))
        {
          from = static_cast<std::size_t>(nj) * kWidth + ni;
          break;
        }
      }
      ASSERT_NE(from, p);
      for (int c = 0; c < 4; ++c)
      {
        EXPECT_EQ(cast.colors[4 * p + c], before.colors[4 * from + c]);
      }
      for (int c = 0; c < 3; ++c)
      {
        EXPECT_EQ(cast.normals[3 * p + c], before.normals[3 * from + c]);
      }
    }
  }
  // The sphere spans about 20 pixels: a silhouette of some 60 pixels, partly covered.
  EXPECT_GT(partial, 40);
  EXPECT_GT(filled, 10);
}

TEST(Multisampling, AtMostEightSamples)
{
  std::vector<glm::dvec2> twelve;
  for (int k = 0; k < 12; ++k)
  {
    twelve.emplace_back((k + 0.5) / 12.0, std::fmod(0.37 * k + 0.1, 1.0));
  }
  Cast cast;
  cast.cover(twelve);
  bool full = false;
  for (std::uint8_t mask : cast.masks)
  {
    full = full || mask == 0xFF; // (interior pixels: all 8 bits, no more exist)
  }
  EXPECT_TRUE(full);
}
