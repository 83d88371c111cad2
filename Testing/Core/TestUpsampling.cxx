// The upsampling rule (tetdsr/render/Upsampling.h) on window-depth images with known surfaces:
// a sloped plane is one surface everywhere; a step between two planes, a one-pixel-wide ridge in
// front of a plane, and a silhouette against the background are never joined across; a curved
// surface (a sphere's depths) is joined inside its silhouette; blocks are Surface, Mixed and Miss
// exactly where their corners say.
#include "tetdsr/render/Upsampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <functional>
#include <vector>

namespace
{
using tetdsr::UpsampleBlock;

struct Image
{
  int width, height;
  std::vector<float> depth;
  tetdsr::UpsampleMaps maps;

  Image(int w, int h, const std::function<float(int, int)>& depthAt)
    : width(w)
    , height(h)
    , depth(static_cast<std::size_t>(w) * h)
  {
    for (int j = 0; j < h; ++j)
    {
      for (int i = 0; i < w; ++i)
      {
        depth[static_cast<std::size_t>(j) * w + i] = depthAt(i, j);
      }
    }
    // (Rows in parts of 3, as threads would split them.)
    tetdsr::upsampleMaps(depth.data(), w, h, maps, [](tetdsr::NodeId count, const auto& body) {
      for (tetdsr::NodeId begin = 0; begin < count; begin += 3)
      {
        body(begin, std::min<tetdsr::NodeId>(begin + 3, count));
      }
    });
  }
  /// Whether pixel (i, j) is joined to (i + dx, j + dy).
  bool joined(int i, int j, int dx, int dy) const
  {
    return (maps.masks[static_cast<std::size_t>(j) * width + i] >> tetdsr::neighbourBit(dx, dy)) & 1u;
  }
  UpsampleBlock block(int i, int j) const // lower-left corner (i, j), -1 <= i, j
  {
    return static_cast<UpsampleBlock>(maps.blocks[static_cast<std::size_t>(j + 1) * (width + 1) + i + 1]);
  }
};

constexpr int kOffsets[8][2] = { { -1, -1 }, { 0, -1 }, { 1, -1 }, { -1, 0 }, { 1, 0 }, { -1, 1 },
  { 0, 1 }, { 1, 1 } };
} // namespace

TEST(Upsampling, NeighbourBitsFollowTheOffsets)
{
  for (int k = 0; k < 8; ++k)
  {
    EXPECT_EQ(tetdsr::neighbourBit(kOffsets[k][0], kOffsets[k][1]), k);
    EXPECT_EQ(tetdsr::kNeighbourOffsets[k][0], kOffsets[k][0]);
    EXPECT_EQ(tetdsr::kNeighbourOffsets[k][1], kOffsets[k][1]);
  }
  EXPECT_EQ(tetdsr::neighbourBit(0, 0), -1);
  EXPECT_EQ(tetdsr::neighbourBit(2, 0), -1);
}

TEST(Upsampling, APlaneIsOneSurface)
{
  const Image image(16, 12, [](int i, int j) { return 0.3f + 0.01f * i + 0.004f * j; });
  for (int j = 0; j < image.height; ++j)
  {
    for (int i = 0; i < image.width; ++i)
    {
      for (const auto& o : kOffsets)
      {
        // Joined when the neighbour is in the image and a pixel beside the pair (before or
        // after it on their line) is too: with neither, only equal depths would be.
        const auto in = [&](int a, int b) {
          return a >= 0 && b >= 0 && a < image.width && b < image.height;
        };
        const bool judged = in(i + o[0], j + o[1]) &&
          (in(i - o[0], j - o[1]) || in(i + 2 * o[0], j + 2 * o[1]));
        EXPECT_EQ(image.joined(i, j, o[0], o[1]), judged) << i << " " << j;
      }
    }
  }
  // Blocks: one surface, but where a diagonal pair at an image corner cannot be judged.
  int surface = 0;
  for (int j = -1; j < image.height; ++j)
  {
    for (int i = -1; i < image.width; ++i)
    {
      const bool corner = (i >= image.width - 2 || i <= 0) && (j >= image.height - 2 || j <= 0);
      if (!corner)
      {
        EXPECT_EQ(image.block(i, j), UpsampleBlock::Surface) << i << " " << j;
      }
      EXPECT_NE(image.block(i, j), UpsampleBlock::Miss);
      surface += image.block(i, j) == UpsampleBlock::Surface;
    }
  }
  EXPECT_GE(surface, (image.width + 1) * (image.height + 1) - 4 * 9);
}

TEST(Upsampling, AStepBetweenTwoPlanesIsNeverJoined)
{
  // Columns 0-7 on a plane at 0.4, 8-15 on a parallel plane 0.05 behind; both slope along i.
  const Image image(16, 8, [](int i, int) { return 0.4f + 0.002f * i + (i >= 8 ? 0.05f : 0.0f); });
  for (int j = 0; j < image.height; ++j)
  {
    for (int dy = -1; dy <= 1; ++dy)
    {
      if (j + dy < 0 || j + dy >= image.height)
      {
        continue;
      }
      EXPECT_FALSE(image.joined(7, j, 1, dy));
      EXPECT_FALSE(image.joined(8, j, -1, dy));
      EXPECT_TRUE(image.joined(6, j, 1, dy));
      EXPECT_TRUE(image.joined(9, j, 1, dy));
    }
  }
  // The blocks across the step are Mixed, the others one surface (but where a diagonal pair at
  // an image corner cannot be judged).
  int mixedAcross = 0;
  for (int j = -1; j < image.height; ++j)
  {
    for (int i = -1; i < image.width; ++i)
    {
      const bool corner = (i >= image.width - 2 || i <= 0) && (j >= image.height - 2 || j <= 0);
      if (i == 7)
      {
        EXPECT_EQ(image.block(i, j), UpsampleBlock::Mixed) << i << " " << j;
        ++mixedAcross;
      }
      else if (!corner)
      {
        EXPECT_EQ(image.block(i, j), UpsampleBlock::Surface) << i << " " << j;
      }
    }
  }
  EXPECT_EQ(mixedAcross, image.height + 1);
}

TEST(Upsampling, ARidgeOnePixelWideStaysApart)
{
  // Column 5 is a ridge 0.1 in front of a flat plane at 0.5.
  const Image image(12, 6, [](int i, int) { return i == 5 ? 0.4f : 0.5f; });
  for (int j = 1; j < image.height - 1; ++j)
  {
    EXPECT_FALSE(image.joined(5, j, -1, 0));
    EXPECT_FALSE(image.joined(5, j, 1, 0));
    EXPECT_FALSE(image.joined(4, j, 1, 0));
    EXPECT_FALSE(image.joined(6, j, -1, 0));
    EXPECT_TRUE(image.joined(5, j, 0, 1)); // along the ridge
    EXPECT_TRUE(image.joined(3, j, 1, 0));
  }
}

TEST(Upsampling, ASphereIsJoinedInsideItsSilhouette)
{
  // A sphere's window depths (orthographic) over the background (1).
  const int n = 64;
  const double c = 31.5, r = 24.0;
  const auto inside = [&](int i, int j) { return std::hypot(i - c, j - c) < r; };
  const Image image(n, n, [&](int i, int j) {
    const double q = r * r - (i - c) * (i - c) - (j - c) * (j - c);
    return q > 0 ? static_cast<float>(0.5 - 0.01 * std::sqrt(q)) : 1.0f;
  });
  int surface = 0, mixed = 0, miss = 0;
  for (int j = -1; j < n; ++j)
  {
    for (int i = -1; i < n; ++i)
    {
      int hits = 0;
      for (int k = 0; k < 4; ++k)
      {
        const int ci = std::min(std::max(i + (k & 1), 0), n - 1);
        const int cj = std::min(std::max(j + (k >> 1), 0), n - 1);
        hits += inside(ci, cj);
      }
      const UpsampleBlock kind = image.block(i, j);
      if (hits == 0)
      {
        EXPECT_EQ(kind, UpsampleBlock::Miss);
      }
      else if (hits < 4)
      {
        EXPECT_EQ(kind, UpsampleBlock::Mixed);
      }
      surface += kind == UpsampleBlock::Surface;
      mixed += kind == UpsampleBlock::Mixed;
      miss += kind == UpsampleBlock::Miss;
    }
  }
  // Every block wholly inside the silhouette but the rim's steepest is one surface.
  int interior = 0;
  for (int j = 0; j < n - 1; ++j)
  {
    for (int i = 0; i < n - 1; ++i)
    {
      if (std::hypot(i + 0.5 - c, j + 0.5 - c) < r - 3.0)
      {
        ++interior;
        EXPECT_EQ(image.block(i, j), UpsampleBlock::Surface) << i << " " << j;
      }
    }
  }
  std::printf("sphere: %d surface, %d mixed, %d miss blocks (%d interior)\n", surface, mixed, miss,
    interior);
  EXPECT_GT(interior, 1000);
  EXPECT_GT(mixed, 100);
}
