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
  const Material& material, const glm::dvec3& lightPosition, const ImageView& image,
  const NormalSettings& normals)
  : Scene_(scene)
  , Rays_(camera, image.width, image.height)
  , IsoValues_(isoValues)
  , Material_(material)
  , LightPosition_(lightPosition)
  , Image_(image)
  , Normals_(normals)
  , TilesPerRow_((image.width + kTileSize - 1) / kTileSize)
{
}

NodeId Renderer::numberOfTiles() const
{
  return static_cast<NodeId>(TilesPerRow_) * ((Image_.height + kTileSize - 1) / kTileSize);
}

template <typename PixelFunction>
void Renderer::forEachPixel(NodeId tileBegin, NodeId tileEnd, PixelFunction&& function) const
{
  for (NodeId tile = tileBegin; tile < tileEnd; ++tile)
  {
    const int i0 = static_cast<int>(tile % TilesPerRow_) * kTileSize;
    const int j0 = static_cast<int>(tile / TilesPerRow_) * kTileSize;
    for (int j = j0; j < std::min(j0 + kTileSize, Image_.height); ++j)
    {
      for (int i = i0; i < std::min(i0 + kTileSize, Image_.width); ++i)
      {
        function(i, j);
      }
    }
  }
}

void Renderer::renderTiles(NodeId tileBegin, NodeId tileEnd) const
{
  forEachPixel(tileBegin, tileEnd, [this](int i, int j) { renderPixel(i, j); });
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
  const glm::dvec3 point = ray.origin + hit.t * ray.direction;
  const glm::dvec3 normal = normalAt(hit, point);
  const double length = glm::length(normal);
  writeHit(pixel, ray, hit.t, length > 0.0 ? normal / length : glm::dvec3(0.0));
  Image_.cellIds[pixel] = hit.cellId;
}

glm::dvec3 Renderer::normalAt(const SurfaceHit& hit, const glm::dvec3& point) const
{
  switch (Normals_.mode)
  {
    case NormalMode::CentralDifferences:
    {
      // Paper's eq. 11: each sample is evaluated in the cell that contains it; a sample outside
      // the mesh takes the hit cell's polynomial.
      const double step = Normals_.relativeStep * Scene_.cellSize(hit.cellId);
      auto sample = [&](const glm::dvec3& q) {
        double value;
        return Scene_.evaluate(q, value) ? value : Scene_.evaluateInCell(hit.cellId, q);
      };
      glm::dvec3 gradient;
      for (int axis = 0; axis < 3; ++axis)
      {
        glm::dvec3 offset(0.0);
        offset[axis] = step;
        gradient[axis] = (sample(point + offset) - sample(point - offset)) / (2.0 * step);
      }
      return gradient;
    }
    case NormalMode::NodalInterpolation:
      return Scene_.interpolateNodalGradient(hit.cellId, point);
    case NormalMode::ExactGradient:
    case NormalMode::DepthBuffer: // replaced by shadeFromDepth once all depths are known
    default:
      return hit.gradient;
  }
}

void Renderer::shadeFromDepth(NodeId tileBegin, NodeId tileEnd) const
{
  auto pointAt = [this](int i, int j, glm::dvec3& point) {
    const double depth = Image_.depth[static_cast<std::size_t>(j) * Image_.width + i];
    if (!std::isfinite(depth))
    {
      return false;
    }
    const Ray ray = Rays_.pixelRay(i, j);
    point = ray.origin + depth * ray.direction;
    return true;
  };
  forEachPixel(tileBegin, tileEnd, [&](int i, int j) {
    const std::size_t pixel = static_cast<std::size_t>(j) * Image_.width + i;
    glm::dvec3 centre;
    if (!pointAt(i, j, centre))
    {
      return;
    }
    // Per direction, the neighbour whose depth is closer (the one-sided difference less likely
    // to straddle a silhouette); none: no tangent in that direction.
    auto tangent = [&](int di, int dj, glm::dvec3& result) {
      glm::dvec3 ahead, behind;
      const bool hasAhead = i + di < Image_.width && j + dj < Image_.height &&
        pointAt(i + di, j + dj, ahead);
      const bool hasBehind = i - di >= 0 && j - dj >= 0 && pointAt(i - di, j - dj, behind);
      if (hasAhead && (!hasBehind || glm::length(ahead - centre) <= glm::length(centre - behind)))
      {
        result = ahead - centre;
        return true;
      }
      if (hasBehind)
      {
        result = centre - behind;
        return true;
      }
      return false;
    };
    const Ray ray = Rays_.pixelRay(i, j);
    glm::dvec3 du, dv, normal = -ray.direction;
    if (tangent(1, 0, du) && tangent(0, 1, dv))
    {
      const glm::dvec3 n = glm::cross(du, dv);
      if (glm::length(n) > 0.0)
      {
        normal = glm::normalize(n);
      }
    }
    if (glm::dot(normal, ray.direction) > 0.0)
    {
      normal = -normal; // towards the viewer
    }
    writeHit(pixel, ray, Image_.depth[pixel], normal);
  });
}

void Renderer::writeHit(
  std::size_t pixel, const Ray& ray, double t, const glm::dvec3& unitNormal) const
{
  std::uint8_t* rgba = Image_.colors + 4 * pixel;
  double* normal = Image_.normals + 3 * pixel;
  const glm::dvec3 point = ray.origin + t * ray.direction;
  const glm::dvec3 color = shade(Material_, point, unitNormal, ray.direction, LightPosition_);
  for (int c = 0; c < 3; ++c)
  {
    rgba[c] = static_cast<std::uint8_t>(std::clamp(color[c], 0.0, 1.0) * 255.0 + 0.5);
    normal[c] = unitNormal[c];
  }
  rgba[3] = 255;
  Image_.depth[pixel] = t;
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
