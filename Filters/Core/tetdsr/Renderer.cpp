#include "tetdsr/Renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

glm::dvec3 shade(const Material& material, const glm::dvec3& hitPoint, const glm::dvec3& unitNormal,
  const glm::dvec3& viewDirection, const glm::dvec3& lightPosition)
{
  glm::dvec3 n = unitNormal;
  if (glm::dot(n, n) == 0.0)
  {
    n = -viewDirection; // critical point or constant field: no gradient, face the viewer
  }
  else if (glm::dot(n, viewDirection) > 0.0)
  {
    n = -n;
  }
  const glm::dvec3 toLight = glm::normalize(lightPosition - hitPoint);
  const double diffuse = std::max(0.0, glm::dot(n, toLight));
  const glm::dvec3 reflected = glm::reflect(-toLight, n);
  const double specular = diffuse > 0.0
    ? std::pow(std::max(0.0, glm::dot(reflected, -viewDirection)), material.specularPower)
    : 0.0;
  return (material.ambient + material.diffuse * diffuse) * material.color +
    glm::dvec3(material.specular * specular);
}

Renderer::Renderer(const Scene& scene, const Camera& camera, const IsoValues& isoValues,
  const Material& material, const glm::dvec3& lightPosition, const ImageView& image)
  : Scene_(scene)
  , Rays_(camera, image.width, image.height)
  , IsoValues_(isoValues)
  , Material_(material)
  , LightPosition_(lightPosition)
  , Image_(image)
  , TilesPerRow_((image.width + kTileSize - 1) / kTileSize)
{
}

NodeId Renderer::numberOfTiles() const
{
  return static_cast<NodeId>(TilesPerRow_) * ((Image_.height + kTileSize - 1) / kTileSize);
}

void Renderer::renderTiles(NodeId tileBegin, NodeId tileEnd) const
{
  for (NodeId tile = tileBegin; tile < tileEnd; ++tile)
  {
    const int i0 = static_cast<int>(tile % TilesPerRow_) * kTileSize;
    const int j0 = static_cast<int>(tile / TilesPerRow_) * kTileSize;
    for (int j = j0; j < std::min(j0 + kTileSize, Image_.height); ++j)
    {
      for (int i = i0; i < std::min(i0 + kTileSize, Image_.width); ++i)
      {
        renderPixel(i, j);
      }
    }
  }
}

void Renderer::renderPixel(int i, int j) const
{
  const std::size_t pixel = static_cast<std::size_t>(j) * Image_.width + i;
  const Ray ray = Rays_.pixelRay(i, j);
  SurfaceHit hit;
  if (!Scene_.firstHit(ray, IsoValues_, hit))
  {
    writeMiss(pixel);
    return;
  }
  std::uint8_t* rgba = Image_.colors + 4 * pixel;
  double* normal = Image_.normals + 3 * pixel;
  const double length = glm::length(hit.gradient);
  const glm::dvec3 unitNormal = length > 0.0 ? hit.gradient / length : glm::dvec3(0.0);
  const glm::dvec3 point = ray.origin + hit.t * ray.direction;
  const glm::dvec3 color = shade(Material_, point, unitNormal, ray.direction, LightPosition_);
  for (int c = 0; c < 3; ++c)
  {
    rgba[c] = static_cast<std::uint8_t>(std::clamp(color[c], 0.0, 1.0) * 255.0 + 0.5);
    normal[c] = unitNormal[c];
  }
  rgba[3] = 255;
  Image_.depth[pixel] = hit.t;
  Image_.cellIds[pixel] = hit.cellId;
}

void Renderer::writeMiss(std::size_t pixel) const
{
  std::uint8_t* rgba = Image_.colors + 4 * pixel;
  double* normal = Image_.normals + 3 * pixel;
  rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0;
  Image_.depth[pixel] = std::numeric_limits<double>::infinity();
  normal[0] = normal[1] = normal[2] = 0.0;
  Image_.cellIds[pixel] = -1;
}

} // namespace tetdsr
