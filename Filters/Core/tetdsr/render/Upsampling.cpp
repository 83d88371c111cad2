// Upsampling a small cast: same-surface masks per pixel and the kind of each 2 x 2 block.
#include "tetdsr/render/Upsampling.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace tetdsr
{

bool sameSurface(float before, float dn, float dt, float after)
{
  if (dt >= 1.0f)
  {
    return false;
  }
  const float step = dt - dn;
  float besideStep = 0.0f; // (0 when neither side tells: then only equal depths pass)
  if (before < 1.0f && after < 1.0f)
  {
    besideStep = std::min(std::fabs(dn - before), std::fabs(after - dt));
  }
  else if (before < 1.0f)
  {
    besideStep = std::fabs(dn - before);
  }
  else if (after < 1.0f)
  {
    besideStep = std::fabs(after - dt);
  }
  if (std::fabs(step) <= 2.0f * besideStep + 1.0f / 1048576.0f)
  {
    return true;
  }
  if (before >= 1.0f || after >= 1.0f)
  {
    return false;
  }
  const float curveBefore = step - (dn - before);
  const float curveAfter = (after - dt) - step;
  return curveBefore * curveAfter > 0.0f &&
    std::fabs(curveAfter - curveBefore) <= 0.5f * (std::fabs(curveBefore) + std::fabs(curveAfter));
}

namespace
{
/// The window depth of cast pixel (i, j); 2 outside the image.
float depthAt(const float* depth, int width, int height, int i, int j)
{
  if (i < 0 || j < 0 || i >= width || j >= height)
  {
    return 2.0f;
  }
  return depth[static_cast<std::size_t>(j) * static_cast<std::size_t>(width) +
    static_cast<std::size_t>(i)];
}
} // namespace

void sameSurfaceMasks(
  const float* depth, int width, int height, std::uint8_t* masks, int rowBegin, int rowEnd)
{
  for (int j = rowBegin; j < rowEnd; ++j)
  {
    for (int i = 0; i < width; ++i)
    {
      const float dn = depthAt(depth, width, height, i, j);
      std::uint8_t mask = 0;
      if (dn < 1.0f)
      {
        for (int k = 0; k < 8; ++k)
        {
          const int dx = kNeighbourOffsets[k][0], dy = kNeighbourOffsets[k][1];
          const float dt = depthAt(depth, width, height, i + dx, j + dy);
          if (dt < 1.0f &&
            sameSurface(depthAt(depth, width, height, i - dx, j - dy), dn, dt,
              depthAt(depth, width, height, i + 2 * dx, j + 2 * dy)))
          {
            mask = static_cast<std::uint8_t>(mask | (1u << k));
          }
        }
      }
      masks[static_cast<std::size_t>(j) * static_cast<std::size_t>(width) +
        static_cast<std::size_t>(i)] = mask;
    }
  }
}

void upsampleBlocks(const float* depth, const std::uint8_t* masks, int width, int height,
  std::uint8_t* blocks, int rowBegin, int rowEnd)
{
  const auto at = [&](int i, int j) {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(width) +
      static_cast<std::size_t>(i);
  };
  for (int row = rowBegin; row < rowEnd; ++row)
  {
    const int j = row - 1;
    for (int i = -1; i < width; ++i)
    {
      // The block's corners, clamped to the image as the draw's reads are.
      int ci[4], cj[4];
      for (int k = 0; k < 4; ++k)
      {
        ci[k] = std::min(std::max(i + (k & 1), 0), width - 1);
        cj[k] = std::min(std::max(j + (k >> 1), 0), height - 1);
      }
      int hits = 0;
      bool joined = true;
      for (int n = 0; n < 4; ++n)
      {
        if (depth[at(ci[n], cj[n])] < 1.0f)
        {
          ++hits;
        }
        // Whichever corner is nearest, every other corner is kept (itself, or on its surface).
        for (int p = 0; p < 4 && joined; ++p)
        {
          const int dx = ci[p] - ci[n], dy = cj[p] - cj[n];
          joined = (dx == 0 && dy == 0) || ((masks[at(ci[n], cj[n])] >> neighbourBit(dx, dy)) & 1u);
        }
      }
      UpsampleBlock kind = UpsampleBlock::Mixed;
      if (hits == 0)
      {
        kind = UpsampleBlock::Miss;
      }
      else if (hits == 4 && joined)
      {
        kind = UpsampleBlock::Surface;
      }
      blocks[static_cast<std::size_t>(row) * static_cast<std::size_t>(width + 1) +
        static_cast<std::size_t>(i + 1)] = static_cast<std::uint8_t>(kind);
    }
  }
}

} // namespace tetdsr
