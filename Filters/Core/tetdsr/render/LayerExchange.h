// Crossings sent between processes. Translucent surfaces cast apart (each process over the cells
// it holds) travel as flat records of doubles, the form MPI gathers, and are read back as
// PixelLayers for compositeLayers. The VTK filter (each process's extent of the image) and the
// mapper (every process's crossings to process 0) exchange them in this one format.
#pragma once

#include "tetdsr/render/Renderer.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tetdsr
{

/// Doubles a packed crossing takes: pixel, t, colour (red, green, blue), opacity.
constexpr std::size_t kPackedLayerSize = 6;

/// Appends `layer` to `packed` as a crossing of `pixel` (the receiver's numbering of its pixels;
/// a double holds every pixel index below 2^32 exactly).
void packLayer(const PixelLayer& layer, std::uint32_t pixel, std::vector<double>& packed);

/// Appends every crossing of a cast (one list per tile, as a Renderer writes ImageView::layers),
/// each at its own pixel.
void packLayers(const std::vector<std::vector<PixelLayer>>& tiles, std::vector<double>& packed);

/// Appends to `layers` the crossings packed in the `count` doubles at `packed` (whole records
/// only: a partial record at the end is not read).
void unpackLayers(const double* packed, std::size_t count, std::vector<PixelLayer>& layers);

} // namespace tetdsr
