// Crossings sent between processes. Translucent surfaces cast apart (each process over the cells
// it holds) travel as flat records of doubles, the form MPI gathers, and are read back as
// PixelLayers for compositeLayers. The VTK filter (each process's extent of the image) and the
// mapper (every process's crossings to process 0) exchange them in this one format.
#pragma once

#include "tetdsr/common/Messages.h"
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

/// A warning when `mismatched` of the `processes` cast a view of another size than process 0:
/// their translucent surfaces cannot be composited.
void describeMismatchedViews(int mismatched, int processes, Messages& messages);

/// The warning of a surface composited by depth across `processes` rendering processes while
/// the host composites their images in order, without depth (ParaView's ordered compositing,
/// chosen when another representation is translucent): the surface is drawn over that image,
/// so translucent geometry of others in front of it is hidden.
void describeOrderedCompositing(int processes, Messages& messages);

/// The error of images of processes that do not fit the extent asked for.
void describeCompositingFailure(Messages& messages);

} // namespace tetdsr
