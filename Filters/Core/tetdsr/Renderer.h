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

/// How the surface normal at a hit is obtained (the paper's section 2.5, and the exact one).
enum class NormalMode
{
  ExactGradient,      ///< the analytic gradient of the cell's quadratic (default)
  CentralDifferences, ///< six samples at +-step, each in the cell that contains it
  NodalInterpolation, ///< gradients at the nodes, interpolated with the shape functions
  DepthBuffer         ///< from the depth image's differences (second pass)
};

struct NormalSettings
{
  NormalMode mode = NormalMode::ExactGradient;
  /// Central differences' step as a fraction of the hit cell's longest edge. For a quadratic
  /// field central differences are exact within one cell; 1e-3 keeps the samples close to the
  /// hit while rounding (~1e-16 |f| / step) stays near 1e-13 of the gradient.
  double relativeStep = 1e-3;
};

/// Output image, row-major with row 0 at the bottom; the buffers are owned by the caller.
/// `normals` holds the normal used for shading: along the field's gradient (towards increasing
/// field) for the first three modes, towards the viewer for DepthBuffer.
struct ImageView
{
  int width = 0;
  int height = 0;
  std::uint8_t* colors = nullptr; ///< RGBA; background (0, 0, 0, 0)
  double* depth = nullptr;        ///< +inf on misses
  double* normals = nullptr;      ///< unit normal (x, y, z); 0 on misses
  NodeId* cellIds = nullptr; ///< -1 on misses
};

/// Phong shading of a hit seen along `viewDirection` (unit, camera to hit). The normal is flipped
/// towards the viewer, so the visible side of the surface is the lit one whatever the field's sign.
glm::dvec3 shade(const Material& material, const glm::dvec3& hitPoint, const glm::dvec3& unitNormal,
  const glm::dvec3& viewDirection, const glm::dvec3& lightPosition);

class Renderer
{
public:
  /// NodalInterpolation needs scene.computeNodalGradients() to have run.
  Renderer(const Scene& scene, const Camera& camera, const IsoValues& isoValues,
    const Material& material, const glm::dvec3& lightPosition, const ImageView& image,
    const NormalSettings& normals = NormalSettings());

  /// Square tiles of kTileSize pixels a side (clipped at the image's edges), row-major from the
  /// bottom left. Neighbouring rays visit the same cells, so a tile keeps them in cache.
  static constexpr int kTileSize = 16;
  NodeId numberOfTiles() const;

  /// Renders tiles [tileBegin, tileEnd). Pixels are independent, so any partition of the tiles
  /// over threads gives the same image bit for bit.
  void renderTiles(NodeId tileBegin, NodeId tileEnd) const;

  /// DepthBuffer only, after every tile is rendered: replaces the normals (and shading) of the
  /// hits in tiles [tileBegin, tileEnd) by ones from the depth image's differences.
  void shadeFromDepth(NodeId tileBegin, NodeId tileEnd) const;

private:
  template <typename PixelFunction>
  void forEachPixel(NodeId tileBegin, NodeId tileEnd, PixelFunction&& function) const;
  void renderPixel(int i, int j) const;
  glm::dvec3 normalAt(const SurfaceHit& hit, const glm::dvec3& point) const;
  void writeHit(std::size_t pixel, const Ray& ray, double t, const glm::dvec3& unitNormal) const;
  void writeMiss(std::size_t pixel) const;

  const Scene& Scene_;
  RayGenerator Rays_;
  const IsoValues& IsoValues_;
  Material Material_;
  glm::dvec3 LightPosition_;
  ImageView Image_;
  NormalSettings Normals_;
  int TilesPerRow_;
};

} // namespace tetdsr
