// Casts one ray per pixel into a Scene and shades the first hit (Phong, one point light).
#pragma once

#include "tetdsr/Camera.h"
#include "tetdsr/Scene.h"

#include <glm/glm.hpp>

#include <cstdint>

namespace tetdsr
{

struct Material
{
  glm::dvec3 color{ 1.0, 1.0, 1.0 };
  double ambient = 0.1;
  double diffuse = 0.7;
  double specular = 0.2;
  double specularPower = 30.0;
};

/// Output image, row-major with row 0 at the bottom; the buffers are owned by the caller.
struct ImageView
{
  int width = 0;
  int height = 0;
  std::uint8_t* colors = nullptr; ///< RGBA; background (0, 0, 0, 0)
  double* depth = nullptr;        ///< +inf on misses
  double* normals = nullptr;      ///< unit gradient (x, y, z); 0 on misses
  NodeId* cellIds = nullptr; ///< -1 on misses
};

/// Phong shading of a hit seen along `viewDirection` (unit, camera to hit). The normal is flipped
/// towards the viewer, so the visible side of the surface is the lit one whatever the field's sign.
glm::dvec3 shade(const Material& material, const glm::dvec3& hitPoint, const glm::dvec3& unitNormal,
  const glm::dvec3& viewDirection, const glm::dvec3& lightPosition);

class Renderer
{
public:
  Renderer(const Scene& scene, const Camera& camera, const IsoValues& isoValues,
    const Material& material, const glm::dvec3& lightPosition, const ImageView& image);

  /// Square tiles of kTileSize pixels a side (clipped at the image's edges), row-major from the
  /// bottom left. Neighbouring rays visit the same cells, so a tile keeps them in cache.
  static constexpr int kTileSize = 16;
  NodeId numberOfTiles() const;

  /// Renders tiles [tileBegin, tileEnd). Pixels are independent, so any partition of the tiles
  /// over threads gives the same image bit for bit.
  void renderTiles(NodeId tileBegin, NodeId tileEnd) const;

private:
  void renderPixel(int i, int j) const;
  void writeMiss(std::size_t pixel) const;

  const Scene& Scene_;
  RayGenerator Rays_;
  const IsoValues& IsoValues_;
  Material Material_;
  glm::dvec3 LightPosition_;
  ImageView Image_;
  int TilesPerRow_;
};

} // namespace tetdsr
