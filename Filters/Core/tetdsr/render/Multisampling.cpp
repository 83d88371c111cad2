#include "tetdsr/render/Multisampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
/// The 8 neighbours, edge neighbours first: the colour of a filled pixel comes from the first
/// that is a hit.
constexpr int kNeighbours[8][2] = { { -1, 0 }, { 1, 0 }, { 0, -1 }, { 0, 1 }, { -1, -1 },
  { 1, -1 }, { -1, 1 }, { 1, 1 } };
}

void multisampleCoverage(const RayGenerator& rays, const FirstHit& firstHit,
  const std::vector<glm::dvec2>& samples, int width, int height, double* depth,
  std::uint8_t* colors, double* normals, std::uint8_t* masks, const ParallelFor& parallelFor)
{
  const int count = std::min(static_cast<int>(samples.size()), kMaxCoverageSamples);
  const std::uint8_t all = static_cast<std::uint8_t>((1u << count) - 1u);
  // Which pixels the cast hit, before any is filled (filled pixels are not neighbours to copy).
  std::vector<std::uint8_t> hit(static_cast<std::size_t>(width) * height);
  for (std::size_t p = 0; p < hit.size(); ++p)
  {
    hit[p] = std::isfinite(depth[p]) ? 1 : 0;
  }
  auto at = [&](int i, int j) { return static_cast<std::size_t>(j) * width + i; };
  parallelFor(height, [&](NodeId rowBegin, NodeId rowEnd) {
    for (int j = static_cast<int>(rowBegin); j < static_cast<int>(rowEnd); ++j)
    {
      for (int i = 0; i < width; ++i)
      {
        const std::size_t p = at(i, j);
        // A silhouette pixel: a neighbour (inside the image) that differs from it.
        int firstHitNeighbour = -1;
        bool silhouette = false;
        for (int k = 0; k < 8; ++k)
        {
          const int ni = i + kNeighbours[k][0], nj = j + kNeighbours[k][1];
          if (ni < 0 || nj < 0 || ni >= width || nj >= height)
          {
            continue;
          }
          silhouette = silhouette || hit[at(ni, nj)] != hit[p];
          if (firstHitNeighbour < 0 && hit[at(ni, nj)])
          {
            firstHitNeighbour = static_cast<int>(at(ni, nj));
          }
        }
        if (!silhouette)
        {
          masks[p] = hit[p] ? all : 0;
          continue;
        }
        // One ray a sample; a missed pixel keeps its nearest covered sample's parameter.
        std::uint8_t mask = 0;
        double nearest = std::numeric_limits<double>::infinity();
        for (int k = 0; k < count; ++k)
        {
          const double t = firstHit(rays.displayRay(i + samples[k].x, j + samples[k].y));
          if (std::isfinite(t))
          {
            mask = static_cast<std::uint8_t>(mask | (1u << k));
            nearest = std::min(nearest, t);
          }
        }
        masks[p] = mask;
        if (!hit[p] && mask != 0 && firstHitNeighbour >= 0)
        {
          const std::size_t q = static_cast<std::size_t>(firstHitNeighbour);
          depth[p] = nearest;
          std::copy_n(colors + 4 * q, 4, colors + 4 * p);
          if (normals)
          {
            std::copy_n(normals + 3 * q, 3, normals + 3 * p);
          }
        }
      }
    }
  });
}

} // namespace tetdsr
