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
constexpr int kBorder = 2; // the padded image's border: n - o and n + 2o stay inside it

/// The four forward offsets; the rule is symmetric (sameSurface(b, n, t, a) ==
/// sameSurface(a, t, n, b)), so the other four are their neighbours' bits.
constexpr int kForward[4][2] = { { 1, 0 }, { -1, 1 }, { 0, 1 }, { 1, 1 } };
} // namespace

void upsampleMaps(
  const float* depth, int width, int height, UpsampleMaps& maps, const ParallelFor& parallelFor)
{
  const std::size_t w = static_cast<std::size_t>(width), h = static_cast<std::size_t>(height);
  const std::size_t pw = w + 2 * kBorder;
  maps.padded.assign(pw * (h + 2 * kBorder), 2.0f);
  maps.forward.resize(w * h);
  maps.masks.resize(w * h);
  maps.blocks.resize((w + 1) * (h + 1));
  float* const padded = maps.padded.data();
  std::uint8_t* const forward = maps.forward.data();
  std::uint8_t* const masks = maps.masks.data();
  const auto at = [pw](std::ptrdiff_t i, std::ptrdiff_t j) {
    return static_cast<std::size_t>(j + kBorder) * pw + static_cast<std::size_t>(i + kBorder);
  };
  parallelFor(static_cast<NodeId>(height), [&](NodeId begin, NodeId end) {
    for (NodeId j = begin; j < end; ++j)
    {
      std::copy_n(depth + static_cast<std::size_t>(j) * w, w, padded + at(0, j));
    }
  });
  // The forward directions' bits (n and n + o both hits, one surface).
  parallelFor(static_cast<NodeId>(height), [&](NodeId begin, NodeId end) {
    for (std::ptrdiff_t j = begin; j < end; ++j)
    {
      for (std::ptrdiff_t i = 0; i < width; ++i)
      {
        const std::size_t n = at(i, j);
        const float dn = padded[n];
        std::uint8_t bits = 0;
        if (dn < 1.0f)
        {
          for (int k = 0; k < 4; ++k)
          {
            const std::ptrdiff_t o = kForward[k][1] * static_cast<std::ptrdiff_t>(pw) + kForward[k][0];
            const std::size_t t = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(n) + o);
            if (padded[t] < 1.0f && sameSurface(padded[n - o], dn, padded[t], padded[t + o]))
            {
              bits = static_cast<std::uint8_t>(bits | (1u << k));
            }
          }
        }
        forward[static_cast<std::size_t>(j) * w + static_cast<std::size_t>(i)] = bits;
      }
    }
  });
  // All eight: the forward four, and each backward one from the neighbour it points to.
  parallelFor(static_cast<NodeId>(height), [&](NodeId begin, NodeId end) {
    for (std::ptrdiff_t j = begin; j < end; ++j)
    {
      for (std::ptrdiff_t i = 0; i < width; ++i)
      {
        std::uint8_t mask = 0;
        const std::uint8_t own = forward[static_cast<std::size_t>(j) * w + static_cast<std::size_t>(i)];
        for (int k = 0; k < 4; ++k)
        {
          const int dx = kForward[k][0], dy = kForward[k][1];
          if ((own >> k) & 1u)
          {
            mask = static_cast<std::uint8_t>(mask | (1u << neighbourBit(dx, dy)));
          }
          const std::ptrdiff_t bi = i - dx, bj = j - dy; // the neighbour at -o, looking at us
          if (bi >= 0 && bj >= 0 && bi < width && bj < height &&
            ((forward[static_cast<std::size_t>(bj) * w + static_cast<std::size_t>(bi)] >> k) & 1u))
          {
            mask = static_cast<std::uint8_t>(mask | (1u << neighbourBit(-dx, -dy)));
          }
        }
        masks[static_cast<std::size_t>(j) * w + static_cast<std::size_t>(i)] = mask;
      }
    }
  });
  // The blocks: whichever corner is nearest, every other corner kept (itself, or joined).
  parallelFor(static_cast<NodeId>(height + 1), [&](NodeId begin, NodeId end) {
    for (std::ptrdiff_t row = begin; row < end; ++row)
    {
      const int j = static_cast<int>(row) - 1;
      std::uint8_t* const out = maps.blocks.data() + static_cast<std::size_t>(row) * (w + 1);
      for (int i = -1; i < width; ++i)
      {
        UpsampleBlock kind = UpsampleBlock::Mixed;
        if (i >= 0 && j >= 0 && i + 1 < width && j + 1 < height)
        {
          // Four distinct corners c0 (i, j), c1 (i + 1, j), c2 (i, j + 1), c3 (i + 1, j + 1):
          // all joined when their six pairs are (the rule is symmetric), read from the forward
          // bits: c0 to c1, c2, c3; c1 to c2, c3; c2 to c3.
          const std::size_t c0 = static_cast<std::size_t>(j) * w + static_cast<std::size_t>(i);
          const std::size_t c2 = c0 + w;
          const bool joined = (forward[c0] & 0b1101u) == 0b1101u &&
            (forward[c0 + 1] & 0b0110u) == 0b0110u && (forward[c2] & 0b0001u) == 0b0001u;
          if (joined)
          {
            kind = UpsampleBlock::Surface;
          }
          else if (depth[c0] >= 1.0f && depth[c0 + 1] >= 1.0f && depth[c2] >= 1.0f &&
            depth[c2 + 1] >= 1.0f)
          {
            kind = UpsampleBlock::Miss;
          }
        }
        else
        {
          int ci[4], cj[4];
          for (int k = 0; k < 4; ++k) // the corners, clamped to the image as the draw's reads are
          {
            ci[k] = std::min(std::max(i + (k & 1), 0), width - 1);
            cj[k] = std::min(std::max(j + (k >> 1), 0), height - 1);
          }
          int hits = 0;
          bool joined = true;
          for (int n = 0; n < 4; ++n)
          {
            const std::size_t pn =
              static_cast<std::size_t>(cj[n]) * w + static_cast<std::size_t>(ci[n]);
            hits += depth[pn] < 1.0f;
            for (int p = 0; p < 4 && joined; ++p)
            {
              const int dx = ci[p] - ci[n], dy = cj[p] - cj[n];
              joined = (dx == 0 && dy == 0) || ((masks[pn] >> neighbourBit(dx, dy)) & 1u);
            }
          }
          kind = hits == 0         ? UpsampleBlock::Miss
            : (hits == 4 && joined) ? UpsampleBlock::Surface
                                    : UpsampleBlock::Mixed;
        }
        out[i + 1] = static_cast<std::uint8_t>(kind);
      }
    }
  });
}

} // namespace tetdsr
