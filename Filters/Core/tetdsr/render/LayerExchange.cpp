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

} // namespace tetdsr
