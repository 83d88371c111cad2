#include "tetdsr/render/Renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

glm::dvec3 ColorTable::map(double value) const
{
  if (std::isnan(value))
  {
    return nanColor;
  }
  const double last = static_cast<double>(colors.size() - 1);
  // (value - lo) / (hi - lo) is NaN for an infinite range or an infinite value at an infinite
  // end: such a value takes the nearer end's colour, and a degenerate range the first.
  double fraction = hi > lo ? (value - lo) / (hi - lo) : 0.0;
  if (std::isnan(fraction))
  {
    fraction = value > 0.5 * lo + 0.5 * hi ? 1.0 : 0.0;
  }
  const double x = std::clamp(fraction, 0.0, 1.0) * last;
  const std::size_t k = std::min(static_cast<std::size_t>(x), colors.size() - 2);
  const double w = x - static_cast<double>(k);
  return (1.0 - w) * colors[k] + w * colors[k + 1];
}

glm::dvec3 shade(const Material& material, const glm::dvec3& color, const glm::dvec3& castHitPoint,
  const glm::dvec3& unitNormal, const glm::dvec3& castViewDirection, const Lighting& lighting)
{
  if (lighting.lights.empty())
  {
    return (material.ambient + material.diffuse) * color; // unlit, as VTK's lighting off
  }
  // Into the lights' coordinates (Lighting::setModelToWorld): unit lengths and angles are not
  // kept by a shear or an uneven scale, so the normal is made unit there, not before.
  glm::dvec3 hitPoint = castHitPoint, viewDirection = castViewDirection, n = unitNormal;
  if (lighting.hasModelToWorld)
  {
    hitPoint = glm::dvec3(lighting.modelToWorld * glm::dvec4(castHitPoint, 1.0));
    viewDirection = unitVector(glm::dmat3(lighting.modelToWorld) * castViewDirection);
    n = unitVector(lighting.normalToWorld * unitNormal);
  }
  if (glm::dot(n, n) == 0.0)
  {
    n = -viewDirection; // critical point or constant field: no gradient, face the viewer
  }
  else if (glm::dot(n, viewDirection) > 0.0)
  {
    n = -n;
  }
  glm::dvec3 diffuse(0.0), specular(0.0);
  if (lighting.headlightOnly)
  {
    // VTK's headlight model: the light comes from the viewer; both terms use n . v.
    const Light& light = lighting.lights[0];
    const double facing = std::max(1e-6, -glm::dot(n, light.direction));
    diffuse = facing * light.color;
    if (material.specular != 0.0) // (pow is most of the shading's cost)
    {
      specular = std::pow(facing, material.specularPower) * light.color;
    }
  }
  else
  {
    const glm::dvec3 toViewer =
      lighting.hasEye ? unitVector(lighting.eye - hitPoint) : -viewDirection;
    for (const Light& light : lighting.lights)
    {
      const glm::dvec3 travel =
        light.positional ? unitVector(hitPoint - light.position) : light.direction;
      const double facing = std::max(0.0, -glm::dot(n, travel));
      diffuse += facing * light.color;
      if (facing > 0.0 && material.specular != 0.0)
      {
        const double highlight = std::max(0.0, glm::dot(glm::reflect(travel, n), toViewer));
        specular += std::pow(highlight, material.specularPower) * light.color;
      }
    }
  }
  return material.ambient * color + material.diffuse * diffuse * color +
    material.specular * specular * material.specularColor;
}

Renderer::Renderer(const SurfaceIndex& surface, const Camera& camera,
  const RenderSettings& settings, const ImageView& image)
  : Renderer(surface, RayGenerator(camera, image.width, image.height), settings, image)
{
}

Renderer::Renderer(const SurfaceIndex& surface, const RayGenerator& rays,
  const RenderSettings& settings, const ImageView& image)
  : Surface_(surface)
  , Scene_(surface.scene())
  , Rays_(rays)
  , IsoValues_(surface.isoValues())
  , Settings_(settings)
  , Image_(image)
  , TilesPerRow_((image.width + kTileSize - 1) / kTileSize)
{
  for (std::size_t k = 0; k < IsoValues_.sorted().size(); ++k)
  {
    const std::size_t original = IsoValues_.originalIndex(k);
    SurfaceStyle style{ settings.material.color, 1.0 };
    if (original < settings.isoStyles.size())
    {
      style = settings.isoStyles[original];
    }
    Translucent_ = Translucent_ || style.opacity < 1.0;
    SortedStyles_.push_back(style);
  }
  for (ClipPlane& plane : Settings_.clipPlanes)
  {
    plane.normal = unitVector(plane.normal); // normals as large as 1e300 are fine
  }
  // Crossings nearer than this are one: the same surface found again in the neighbouring cell
  // differs by rounding (~1e-15 of the scene), far below it; surfaces truly this close are
  // below any pixel's footprint.
  LayerGap_ = kLayerGap * Scene_.diagonal();
  if (Image_.layers)
  {
    Image_.layers->assign(static_cast<std::size_t>(numberOfTiles()), {});
  }
  if (settings.normals.mode == NormalMode::DepthBuffer)
  {
    Nearest_.resize(static_cast<std::size_t>(image.width) * image.height);
  }
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

bool Renderer::blockMayHit(int i0, int j0, int i1, int j1) const
{
  if (Settings_.cap != CapRegion::None || i1 - i0 < 2 || j1 - j0 < 2)
  {
    return true; // a cap can lie where no surface does; a strip is not worth a test
  }
  const Ray corners[4] = { Rays_.pixelRay(i0, j0), Rays_.pixelRay(i1 - 1, j0),
    Rays_.pixelRay(i1 - 1, j1 - 1), Rays_.pixelRay(i0, j1 - 1) };
  return Surface_.blockMayHit(corners);
}

void Renderer::renderBlock(int i0, int j0, int i1, int j1, bool mayHit) const
{
  for (int j = j0; j < j1; ++j)
  {
    for (int i = i0; i < i1; ++i)
    {
      if (mayHit)
      {
        renderPixel(i, j);
      }
      else
      {
        writeMiss(static_cast<std::size_t>(j) * Image_.width + i);
      }
    }
  }
}

void Renderer::renderTiles(NodeId tileBegin, NodeId tileEnd) const
{
  // Frustum culling: a tile whose rays can meet no transverse cell's box is all misses; else
  // each of its blocks of kBlockSize pixels a side is tested the same way before its rays are
  // cast. Only misses are skipped, so the image is the same as casting every ray.
  for (NodeId tile = tileBegin; tile < tileEnd; ++tile)
  {
    const int i0 = static_cast<int>(tile % TilesPerRow_) * kTileSize;
    const int j0 = static_cast<int>(tile / TilesPerRow_) * kTileSize;
    const int i1 = std::min(i0 + kTileSize, Image_.width);
    const int j1 = std::min(j0 + kTileSize, Image_.height);
    if (!blockMayHit(i0, j0, i1, j1))
    {
      renderBlock(i0, j0, i1, j1, false);
      continue;
    }
    for (int bj = j0; bj < j1; bj += kBlockSize)
    {
      for (int bi = i0; bi < i1; bi += kBlockSize)
      {
        const int bi1 = std::min(bi + kBlockSize, i1), bj1 = std::min(bj + kBlockSize, j1);
        renderBlock(bi, bj, bi1, bj1, blockMayHit(bi, bj, bi1, bj1));
      }
    }
  }
}

bool Renderer::clipInterval(const Ray& ray, double& tMin, double& tMax, int& enteringPlane) const
{
  tMin = 0.0;
  tMax = std::numeric_limits<double>::infinity();
  enteringPlane = -1;
  for (std::size_t k = 0; k < Settings_.clipPlanes.size(); ++k)
  {
    // n . (o + t d - p) >= 0 with s = n . (o - p), slope = n . d.
    const ClipPlane& plane = Settings_.clipPlanes[k];
    const double s = glm::dot(plane.normal, ray.origin - plane.origin);
    const double slope = glm::dot(plane.normal, ray.direction);
    if (slope > 0.0)
    {
      const double t = -s / slope;
      if (t > tMin)
      {
        tMin = t;
        enteringPlane = static_cast<int>(k);
      }
    }
    else if (slope < 0.0)
    {
      tMax = std::min(tMax, -s / slope);
    }
    else if (s < 0.0)
    {
      return false; // parallel to the plane, on the removed side
    }
  }
  return tMin <= tMax;
}

double Renderer::colorValue(NodeId cellId, const glm::dvec3& point) const
{
  const ColorByArray& by = Settings_.colorBy;
  if (!by.values)
  {
    return Scene_.interpolate(cellId, point, Scene_.mesh().values);
  }
  if (by.component >= 0)
  {
    return Scene_.interpolate(cellId, point, by.values, by.components, by.component);
  }
  double sum = 0.0;
  for (int c = 0; c < by.components; ++c)
  {
    const double v = Scene_.interpolate(cellId, point, by.values, by.components, c);
    sum += v * v;
  }
  return std::sqrt(sum);
}

glm::dvec3 Renderer::directColor(NodeId cellId, const glm::dvec3& point) const
{
  const ColorByArray& by = Settings_.colorBy;
  glm::dvec3 color(0.0);
  for (int c = 0; c < std::min(3, by.components); ++c)
  {
    color[c] = std::clamp(Scene_.interpolate(cellId, point, by.values, by.components, c) / 255.0, 0.0, 1.0);
  }
  return by.components < 3 ? glm::dvec3(color[0]) : color; // grey levels from one component
}

bool Renderer::capCovers(const glm::dvec3& point, NodeId& cellId, double& field) const
{
  if (!Scene_.locate(point, cellId))
  {
    return false; // the plane is outside the mesh here
  }
  field = Scene_.interpolate(cellId, point, Scene_.mesh().values);
  const std::vector<double>& iso = IsoValues_.sorted();
  // A point where the field equals the iso-value to rounding is on the surface, not inside it:
  // the cap's edge must not depend on how the interpolation rounds (e.g. a constant field).
  const double level = Settings_.cap == CapRegion::BelowIsoValue ? iso.back() : iso.front();
  const double tolerance =
    8.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(field), std::abs(level));
  return Settings_.cap == CapRegion::BelowIsoValue ? field < level - tolerance
                                                   : field > level + tolerance;
}

bool Renderer::capAt(const Ray& ray, double t, int plane, std::size_t pixel) const
{
  const glm::dvec3 point = ray.origin + t * ray.direction;
  NodeId cellId;
  double field;
  if (!capCovers(point, cellId, field))
  {
    return false;
  }
  const double value = colorValue(cellId, point);
  const glm::dvec3 color = Settings_.colorTable.map(value);
  const glm::dvec3& normal = Settings_.clipPlanes[static_cast<std::size_t>(plane)].normal;
  Image_.depth[pixel] = t;
  Image_.cellIds[pixel] = cellId;
  if (Image_.hitEntries)
  {
    Image_.hitEntries[pixel] = kNoEntry;
  }
  for (int c = 0; c < 3; ++c)
  {
    Image_.normals[3 * pixel + c] = normal[c];
  }
  if (Image_.colorValues)
  {
    Image_.colorValues[pixel] = value;
  }
  if (!Nearest_.empty())
  {
    Nearest_[pixel] = { color, 1.0, glm::dvec3(0.0), 0.0 };
  }
  const glm::dvec3 shaded =
    shade(Settings_.material, color, point, normal, ray.direction, Settings_.lighting);
  writePixel(pixel, shaded, 1.0);
  addLayer(pixel, t, shaded, 1.0);
  return true;
}

void Renderer::addLayer(std::size_t pixel, double t, const glm::dvec3& color, double opacity) const
{
  if (Image_.layers)
  {
    const std::size_t i = pixel % static_cast<std::size_t>(Image_.width);
    const std::size_t j = pixel / static_cast<std::size_t>(Image_.width);
    const std::size_t tile = (j / kTileSize) * static_cast<std::size_t>(TilesPerRow_) + i / kTileSize;
    (*Image_.layers)[tile].push_back({ static_cast<std::uint32_t>(pixel), t, color, opacity });
  }
}

void Renderer::renderPixel(int i, int j) const
{
  const std::size_t pixel = static_cast<std::size_t>(j) * Image_.width + i;
  const Ray ray = Rays_.pixelRay(i, j);
  double tMin, tMax;
  int enteringPlane;
  bool visible = clipInterval(ray, tMin, tMax, enteringPlane);
  if (visible && Image_.rayLimits)
  {
    tMax = std::min(tMax, Image_.rayLimits[pixel]);
    visible = tMin <= tMax;
  }
  if (!visible)
  {
    writeMiss(pixel);
    return;
  }
  // A cap lies where the ray enters the kept region, in front of every surface.
  if (Settings_.cap != CapRegion::None && enteringPlane >= 0 &&
    capAt(ray, tMin, enteringPlane, pixel))
  {
    return;
  }

  // Crossings front to back: colour += (1 - opacity) * alpha * shaded, opacity += (1 - opacity)
  // * alpha, until the rest could not change an 8-bit colour (opaque surfaces: one crossing).
  glm::dvec3 color(0.0);
  double opacity = 0.0;
  double tFrom = tMin;
  for (int layer = 0; layer < kMaxLayers && opacity < kOpaque; ++layer)
  {
    SurfaceHit hit;
    const std::uint32_t hint = layer == 0 && Image_.entryHints ? Image_.entryHints[pixel] : kNoEntry;
    if (!Surface_.firstHit(ray, hit, tFrom, tMax, hint))
    {
      break;
    }
    const glm::dvec3 point = ray.origin + hit.t * ray.direction;
    const glm::dvec3 normal = normalAt(hit, point);
    const glm::dvec3 unitNormal = unitVector(normal);
    const SurfaceStyle& style = SortedStyles_[hit.isoIndex];
    double value = std::numeric_limits<double>::quiet_NaN();
    glm::dvec3 base = style.color;
    if (Settings_.colorBy.values && Settings_.colorBy.directColors)
    {
      base = directColor(hit.cellId, point);
    }
    else if (Settings_.colorBy.values)
    {
      value = colorValue(hit.cellId, point);
      base = Settings_.colorTable.map(value);
    }
    const glm::dvec3 shaded =
      shade(Settings_.material, base, point, unitNormal, ray.direction, Settings_.lighting);
    if (layer == 0)
    {
      Image_.depth[pixel] = hit.t;
      Image_.cellIds[pixel] = hit.cellId;
      if (Image_.hitEntries)
      {
        Image_.hitEntries[pixel] = hit.entry;
      }
      for (int c = 0; c < 3; ++c)
      {
        Image_.normals[3 * pixel + c] = unitNormal[c];
      }
      if (Image_.colorValues)
      {
        Image_.colorValues[pixel] = value;
      }
      if (!Nearest_.empty())
      {
        Nearest_[pixel] = { base, style.opacity, glm::dvec3(0.0), 0.0 };
      }
    }
    else if (!Nearest_.empty())
    {
      NearestLayer& nearest = Nearest_[pixel];
      const double weight = (1.0 - nearest.behindOpacity) * style.opacity;
      nearest.behindColor += weight * shaded;
      nearest.behindOpacity += weight;
    }
    color += ((1.0 - opacity) * style.opacity) * shaded;
    opacity += (1.0 - opacity) * style.opacity;
    addLayer(pixel, hit.t, shaded, style.opacity);
    if (!Translucent_)
    {
      break;
    }
    // Past this crossing (a cell where the field equals the iso-value throughout is one).
    tFrom = hit.regionEnd + std::max(LayerGap_, 1e-12 * hit.regionEnd);
  }
  if (opacity == 0.0)
  {
    writeMiss(pixel);
    return;
  }
  writePixel(pixel, color, opacity);
}

bool Renderer::pick(const Ray& ray, Pick& pick, double tLimit) const
{
  pick = Pick();
  double tMin, tMax;
  int enteringPlane;
  if (!clipInterval(ray, tMin, tMax, enteringPlane) || tMin > tLimit)
  {
    return false;
  }
  tMax = std::min(tMax, tLimit);
  NodeId cellId = -1;
  double field = 0.0;
  if (Settings_.cap != CapRegion::None && enteringPlane >= 0 &&
    capCovers(ray.origin + tMin * ray.direction, cellId, field))
  {
    pick.t = tMin;
    pick.clipPlane = enteringPlane;
    pick.normal = Settings_.clipPlanes[static_cast<std::size_t>(enteringPlane)].normal;
    pick.value = field;
  }
  else
  {
    SurfaceHit hit;
    if (!Surface_.firstHit(ray, hit, tMin, tMax))
    {
      return false;
    }
    pick.t = hit.t;
    cellId = hit.cellId;
    pick.isoValue = static_cast<int>(IsoValues_.originalIndex(hit.isoIndex));
    pick.normal = unitVector(hit.gradient);
    pick.value = Scene_.interpolate(cellId, ray.origin + hit.t * ray.direction, Scene_.mesh().values);
  }
  pick.point = ray.origin + pick.t * ray.direction;
  pick.cellId = cellId;
  pick.hasParametric = Scene_.parametricCoordinates(cellId, pick.point, pick.parametric);
  return true;
}

glm::dvec3 Renderer::normalAt(const SurfaceHit& hit, const glm::dvec3& point) const
{
  switch (Settings_.normals.mode)
  {
    case NormalMode::CentralDifferences:
    {
      // Paper's eq. 11: each sample is evaluated in the cell that contains it; a sample outside
      // the mesh takes the hit cell's polynomial. The step is at least 1024 ulps of the point's
      // coordinates, so that point +- step differs from the point however far it is from the
      // origin. Only the direction is used: the differences are not divided by 2 step (which
      // could overflow for a field near the largest double).
      const double magnitude = std::max({ std::abs(point.x), std::abs(point.y), std::abs(point.z) });
      const double step = std::max(Settings_.normals.relativeStep * Scene_.cellSize(hit.cellId),
        1024.0 * std::numeric_limits<double>::epsilon() * magnitude);
      const double* field = Scene_.mesh().values;
      auto sample = [&](const glm::dvec3& q) {
        NodeId cellId;
        return Scene_.interpolate(Scene_.locate(q, cellId) ? cellId : hit.cellId, q, field);
      };
      glm::dvec3 difference;
      for (int axis = 0; axis < 3; ++axis)
      {
        glm::dvec3 offset(0.0);
        offset[axis] = step;
        difference[axis] = sample(point + offset) - sample(point - offset);
      }
      // Differences that vanish or overflow where the field varies (samples in neighbouring
      // constant cells, a field near the largest double): the exact gradient instead.
      return unitVector(difference) != glm::dvec3(0.0) ? difference : hit.gradient;
    }
    case NormalMode::NodalInterpolation:
    {
      // Where the interpolated nodal gradients cancel or underflow (a field spanning more than
      // double range between cells), the exact gradient instead.
      const glm::dvec3 gradient = Scene_.interpolateNodalGradient(hit.cellId, point);
      return unitVector(gradient) != glm::dvec3(0.0) ? gradient : hit.gradient;
    }
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
      // (unitVector: for a mesh of size 1e-80 the cross product's squared length underflows)
      const glm::dvec3 n = unitVector(glm::cross(du, dv));
      if (n != glm::dvec3(0.0))
      {
        normal = n;
      }
    }
    if (glm::dot(normal, ray.direction) > 0.0)
    {
      normal = -normal; // towards the viewer
    }
    for (int c = 0; c < 3; ++c)
    {
      Image_.normals[3 * pixel + c] = normal[c];
    }
    const NearestLayer& nearest = Nearest_[pixel];
    const glm::dvec3 shaded = shade(Settings_.material, nearest.color,
      ray.origin + Image_.depth[pixel] * ray.direction, normal, ray.direction,
      Settings_.lighting);
    writePixel(pixel, nearest.opacity * shaded + (1.0 - nearest.opacity) * nearest.behindColor,
      nearest.opacity + (1.0 - nearest.opacity) * nearest.behindOpacity);
  });
}

namespace
{
/// [0, 1] to a byte; NaN (a colour from a NaN lookup-table entry, say) becomes 0.
std::uint8_t toByte(double x)
{
  return x > 0.0 ? static_cast<std::uint8_t>(std::min(x, 1.0) * 255.0 + 0.5) : 0;
}
}

/// A composited colour (premultiplied) as 8-bit RGBA, not premultiplied.
static void writeRgba(std::uint8_t* rgba, const glm::dvec3& premultiplied, double opacity)
{
  for (int c = 0; c < 3; ++c)
  {
    // (an opaque pixel, the common case, needs no division: x / 1 is x)
    rgba[c] = toByte(opacity == 1.0 ? premultiplied[c] : premultiplied[c] / opacity);
  }
  rgba[3] = toByte(opacity);
}

void Renderer::writePixel(std::size_t pixel, const glm::dvec3& premultiplied, double opacity) const
{
  writeRgba(Image_.colors + 4 * pixel, premultiplied, opacity);
}

void checkTranslucentNeighbours(
  int otherTranslucentProps, const char* technique, Messages& messages)
{
  if (otherTranslucentProps > 0)
  {
    messages.warnings.push_back(text("The translucent surface is blended over the frame after ",
      "the view's ", otherTranslucentProps, " other translucent ",
      otherTranslucentProps == 1 ? "prop" : "props", ": ", technique,
      " cannot interleave their layers with the surface's, so where they lie in front of it, "
      "the surface wrongly covers them. Make them or the surface opaque for a correct picture."));
  }
}

void compositeLayers(std::vector<PixelLayer>& layers, std::size_t pixels, double gap,
  const double* rayLimits, std::uint8_t* colors)
{
  std::fill(colors, colors + 4 * pixels, std::uint8_t(0));
  std::stable_sort(layers.begin(), layers.end(), [](const PixelLayer& a, const PixelLayer& b) {
    return a.pixel != b.pixel ? a.pixel < b.pixel : a.t < b.t;
  });
  for (std::size_t first = 0; first < layers.size();)
  {
    const std::uint32_t pixel = layers[first].pixel;
    std::size_t last = first;
    while (last < layers.size() && layers[last].pixel == pixel)
    {
      ++last;
    }
    if (pixel < pixels)
    {
      const double limit =
        rayLimits ? rayLimits[pixel] : std::numeric_limits<double>::infinity();
      glm::dvec3 color(0.0);
      double opacity = 0.0;
      double previous = -std::numeric_limits<double>::infinity();
      int taken = 0;
      for (std::size_t k = first;
           k < last && taken < Renderer::kMaxLayers && opacity < Renderer::kOpaque; ++k)
      {
        const PixelLayer& layer = layers[k];
        if (layer.t > limit)
        {
          break;
        }
        if (layer.t < previous + std::max(gap, 1e-12 * std::abs(previous)))
        {
          continue; // the same surface, found by two pieces
        }
        color += ((1.0 - opacity) * layer.opacity) * layer.color;
        opacity += (1.0 - opacity) * layer.opacity;
        previous = layer.t;
        ++taken;
      }
      if (opacity > 0.0)
      {
        writeRgba(colors + 4 * static_cast<std::size_t>(pixel), color, opacity);
      }
    }
    first = last;
  }
}

void Renderer::writeMiss(std::size_t pixel) const
{
  std::uint8_t* rgba = Image_.colors + 4 * pixel;
  double* normal = Image_.normals + 3 * pixel;
  rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0;
  Image_.depth[pixel] = std::numeric_limits<double>::infinity();
  normal[0] = normal[1] = normal[2] = 0.0;
  Image_.cellIds[pixel] = -1;
  if (Image_.hitEntries)
  {
    Image_.hitEntries[pixel] = kNoEntry;
  }
  if (Image_.colorValues)
  {
    Image_.colorValues[pixel] = std::numeric_limits<double>::quiet_NaN();
  }
}

void reprojectHits(const RayGenerator& lastRays, int lastWidth, int lastHeight,
  const double* lastDepth, const std::uint32_t* lastEntries, const glm::dmat4& worldToNdc,
  int width, int height, std::uint32_t* hints)
{
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::fill(hints, hints + pixels, kNoEntry);
  std::vector<float> nearest(pixels, std::numeric_limits<float>::infinity());
  for (int j = 0; j < lastHeight; ++j)
  {
    for (int i = 0; i < lastWidth; ++i)
    {
      const std::size_t last = static_cast<std::size_t>(j) * lastWidth + i;
      if (lastEntries[last] == kNoEntry || !std::isfinite(lastDepth[last]))
      {
        continue;
      }
      const Ray ray = lastRays.pixelRay(i, j);
      const glm::dvec4 clip = worldToNdc * glm::dvec4(ray.origin + lastDepth[last] * ray.direction, 1.0);
      if (!(clip.w > 0.0))
      {
        continue; // behind the new eye
      }
      const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
      // Pixel i's centre is at ndc 2 (i + 0.5) / width - 1 (RayGenerator).
      const double x = std::floor(0.5 * (ndc.x + 1.0) * width);
      const double y = std::floor(0.5 * (ndc.y + 1.0) * height);
      if (!(x >= 0.0 && x < width && y >= 0.0 && y < height))
      {
        continue;
      }
      const std::size_t now = static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x);
      const auto z = static_cast<float>(ndc.z);
      if (z < nearest[now])
      {
        nearest[now] = z;
        hints[now] = lastEntries[last];
      }
    }
  }
  // Holes (the new view magnifies, or uncovers what was hidden): a marked neighbour's cell.
  std::vector<std::uint32_t> marked(hints, hints + pixels);
  for (int j = 0; j < height; ++j)
  {
    for (int i = 0; i < width; ++i)
    {
      std::uint32_t& hint = hints[static_cast<std::size_t>(j) * width + i];
      for (int dj = -1; dj <= 1 && hint == kNoEntry; ++dj)
      {
        for (int di = -1; di <= 1 && hint == kNoEntry; ++di)
        {
          const int ni = i + di, nj = j + dj;
          if (ni >= 0 && ni < width && nj >= 0 && nj < height)
          {
            hint = marked[static_cast<std::size_t>(nj) * width + ni];
          }
        }
      }
    }
  }
}

} // namespace tetdsr
