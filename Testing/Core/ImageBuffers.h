#pragma once
// An image the core renders into, with buffers it owns: the ImageView of the core's tests.
#include "tetdsr/render/Renderer.h"

#include <cstdint>
#include <vector>

namespace tetdsr_test
{
struct ImageBuffers
{
  ImageBuffers(int w, int h)
    : width(w)
    , height(h)
    , colors(4 * std::size_t(w) * h)
    , depth(std::size_t(w) * h)
    , normals(3 * std::size_t(w) * h)
    , cellIds(std::size_t(w) * h)
    , entries(std::size_t(w) * h)
  {
  }
  /// The view of the buffers, with the layers output when given.
  tetdsr::ImageView view(std::vector<std::vector<tetdsr::PixelLayer>>* layers = nullptr)
  {
    tetdsr::ImageView image;
    image.width = width;
    image.height = height;
    image.colors = colors.data();
    image.depth = depth.data();
    image.normals = normals.data();
    image.cellIds = cellIds.data();
    image.hitEntries = entries.data();
    image.layers = layers;
    return image;
  }
  int width, height;
  std::vector<std::uint8_t> colors;
  std::vector<double> depth, normals;
  std::vector<tetdsr::NodeId> cellIds;
  std::vector<std::uint32_t> entries;
};
} // namespace tetdsr_test
