// Coverage of a cast's silhouettes at a multisampled framebuffer's sample positions: which
// samples of each pixel see a surface, so that a face can draw the exact surface with its
// silhouettes smoothed (a sample mask per pixel) as the window smooths polygons'. One ray a
// sample, cast only for pixels next to a silhouette.
#pragma once

#include "tetdsr/common/Camera.h"
#include "tetdsr/index/Scene.h" // ParallelFor

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace tetdsr
{

/// The most samples a pixel's mask holds (one byte).
constexpr int kMaxCoverageSamples = 8;

/// The first surface along a ray: its ray parameter, +inf when the ray sees none. Thread-safe.
using FirstHit = std::function<double(const Ray& ray)>;

/// Per pixel of a full-resolution cast (width x height; `depth` its ray parameters, +inf on a
/// miss; `colors` RGBA; `normals` xyz, may be null), the mask of `samples` (positions in [0, 1)^2
/// of the pixel, at most kMaxCoverageSamples) that see a surface: bit k for sample k. A pixel
/// whose 3 x 3 neighbourhood is all hits takes every bit, all misses none; the others (along a
/// silhouette) cast one ray a sample (rays.displayRay at i + x, j + y). A missed pixel with
/// covered samples is filled so that it can be drawn: the nearest covered sample's ray parameter,
/// and the colour (and normal) of its first hit neighbour, edge neighbours before corners. Rows
/// on `parallelFor`'s threads.
void multisampleCoverage(const RayGenerator& rays, const FirstHit& firstHit,
  const std::vector<glm::dvec2>& samples, int width, int height, double* depth,
  std::uint8_t* colors, double* normals, std::uint8_t* masks, const ParallelFor& parallelFor);

} // namespace tetdsr
