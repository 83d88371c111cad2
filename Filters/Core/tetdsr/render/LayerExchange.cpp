#include "tetdsr/render/LayerExchange.h"

namespace tetdsr
{

void packLayer(const PixelLayer& layer, std::uint32_t pixel, std::vector<double>& packed)
{
  packed.insert(packed.end(), { static_cast<double>(pixel), layer.t, layer.color.x,
                                layer.color.y, layer.color.z, layer.opacity });
}

void packLayers(const std::vector<std::vector<PixelLayer>>& tiles, std::vector<double>& packed)
{
  for (const auto& tile : tiles)
  {
    for (const PixelLayer& layer : tile)
    {
      packLayer(layer, layer.pixel, packed);
    }
  }
}

void unpackLayers(const double* packed, std::size_t count, std::vector<PixelLayer>& layers)
{
  const std::size_t records = count / kPackedLayerSize;
  layers.reserve(layers.size() + records);
  for (std::size_t r = 0; r < records; ++r)
  {
    const double* v = packed + kPackedLayerSize * r;
    layers.push_back({ static_cast<std::uint32_t>(v[0]), v[1], glm::dvec3(v[2], v[3], v[4]), v[5] });
  }
}

void describeMismatchedViews(int mismatched, int processes, Messages& messages)
{
  if (mismatched > 0)
  {
    messages.warnings.push_back(text(mismatched, " of ", processes,
      " processes cast a view of another size: their translucent surfaces are not drawn."));
  }
}

void describeOrderedCompositing(int processes, Messages& messages)
{
  messages.warnings.push_back(text("Another representation in the view is translucent, so "
    "ParaView composites the images of its ", processes, " rendering processes in order, "
    "without depth (ordered compositing): this Direct Surface is composited by depth across "
    "them and drawn over that image, so translucent geometry of other representations in front "
    "of it is hidden. Make the other representations opaque to see it."));
}

void describeCompositingFailure(Messages& messages)
{
  messages.errors.push_back("Cannot composite the processes' images into the requested extent.");
}

} // namespace tetdsr
