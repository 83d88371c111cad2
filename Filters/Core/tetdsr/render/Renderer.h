// Casts one ray per pixel into a Scene and shades the first hit (Phong, one point light).
#pragma once

#include "tetdsr/common/Camera.h"
#include "tetdsr/common/Messages.h"
#include "tetdsr/index/Scene.h"
#include "tetdsr/index/SurfaceIndex.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace tetdsr
{

struct Material
{
  glm::dvec3 color{ 1.0, 1.0, 1.0 }; ///< ambient and diffuse colour, unless colour-mapped
  glm::dvec3 specularColor{ 1.0, 1.0, 1.0 };
  double ambient = 0.1;
  double diffuse = 0.7;
  double specular = 0.2;
  double specularPower = 30.0;
};

/// A light as VTK's polygon shaders use it: a colour (diffuse colour x intensity) and either a
/// direction (the way the light travels) or a position (a point light, no attenuation).
struct Light
{
  glm::dvec3 color{ 1.0, 1.0, 1.0 };
  bool positional = false;
  glm::dvec3 direction{ 0.0, 0.0, -1.0 }; ///< unit; directional lights
  glm::dvec3 position{ 0.0, 0.0, 1.0 };   ///< positional lights
};

/// The lights of a scene, with VTK's three lighting models (vtkOpenGLPolyDataMapper): no light
/// (colour = (ambient + diffuse) x colour), a lone headlight (diffuse = n . v, specular =
/// (n . v)^power, v towards the viewer), and any others (Phong per light).
struct Lighting
{
  std::vector<Light> lights;
  bool headlightOnly = false; ///< lights[0] is a headlight and the only light
  /// Where the viewer is, for the Phong model's view vector (VTK: the camera position, in
  /// parallel projection too); when unset, the view vector is the ray's.
  bool hasEye = false;
  glm::dvec3 eye{ 0.0 };
  /// When the cast's coordinates are not the lights' (a mapper casts in its actor's model
  /// coordinates, and the actor's matrix may shear, scale unevenly or mirror): the affine map
  /// from the cast's coordinates to the lights' and the eye's, and its normal matrix (the inverse
  /// transpose of its linear part). Shading then happens in the lights' coordinates, as polygons
  /// are shaded in the world: a gradient maps by the normal matrix, points and rays by the map.
  bool hasModelToWorld = false;
  glm::dmat4 modelToWorld{ 1.0 };
  glm::dmat3 normalToWorld{ 1.0 };

  /// Lights and eye in the coordinates `modelToWorld` maps the cast's into.
  void setModelToWorld(const glm::dmat4& map)
  {
    hasModelToWorld = true;
    modelToWorld = map;
    normalToWorld = glm::transpose(glm::inverse(glm::dmat3(map)));
  }
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

/// A colour map sampled at evenly spaced values from `lo` to `hi` (the VTK adapter samples the
/// user's lookup table); values between samples are interpolated linearly, values outside are
/// clamped to the ends, NaN takes `nanColor`.
struct ColorTable
{
  double lo = 0.0;
  double hi = 1.0;
  std::vector<glm::dvec3> colors; ///< at least 2 entries
  glm::dvec3 nanColor{ 0.5, 0.5, 0.5 };

  glm::dvec3 map(double value) const;
};

/// A second point array that colours the surface, interpolated at the hit with the quadratic
/// shape functions of the hit cell.
struct ColorByArray
{
  const double* values = nullptr; ///< `components` values per point; null: no such colouring
  int components = 1;
  int component = 0; ///< -1: the magnitude of the interpolated vector
  /// The array holds colours, not values: components 0-2 (0-255) interpolated and used as red,
  /// green, blue without a colour table (VTK's direct scalars).
  bool directColors = false;
};

/// Keeps the half-space n . (x - origin) >= 0: the normal points to the side that stays, as for
/// VTK's mapper clipping planes. The normal need not be unit; it must not be zero.
struct ClipPlane
{
  glm::dvec3 origin{ 0.0 };
  glm::dvec3 normal{ 0.0, 0.0, 1.0 };
};

/// Which points of a clip plane inside the mesh are drawn as the cut's cap, coloured by the
/// field (or the colour array) through the colour table: those below the largest iso-value
/// (inside the surfaces of a field that grows outward, e.g. a distance) or above the smallest.
enum class CapRegion
{
  None,
  BelowIsoValue,
  AboveIsoValue
};

/// Colour and opacity of one iso-value's surface.
struct SurfaceStyle
{
  glm::dvec3 color{ 1.0, 1.0, 1.0 };
  double opacity = 1.0;
};

struct RenderSettings
{
  Material material;
  Lighting lighting;
  NormalSettings normals;
  /// Per iso-value, in the order the values were given to IsoValues; a value without an entry
  /// gets material.color, opaque. With any opacity below 1 the crossings along each ray are
  /// composited front to back (nested translucent surfaces).
  std::vector<SurfaceStyle> isoStyles;
  ColorByArray colorBy;  ///< when set, replaces the surfaces' colours
  ColorTable colorTable; ///< for colorBy, and for the caps
  std::vector<ClipPlane> clipPlanes;
  CapRegion cap = CapRegion::None;
};

/// A crossing of one pixel's ray with a surface, shaded: what translucent surfaces cast apart (by
/// several processes, each over the cells it holds) are composited from (compositeLayers).
struct PixelLayer
{
  std::uint32_t pixel = 0;
  double t = 0.0;          ///< along the pixel's ray
  glm::dvec3 color{ 0.0 }; ///< shaded, not premultiplied
  double opacity = 0.0;
};

/// What a ray sees first (Renderer::pick): the nearest crossing of a surface, or of a clipping
/// plane's cap, inside the clipping planes.
struct Pick
{
  double t = 0.0;           ///< along the ray
  glm::dvec3 point{ 0.0 };  ///< ray.origin + t ray.direction
  NodeId cellId = -1;       ///< the input's cell
  /// The iso-value crossed, as an index into the values given to IsoValues; -1 on a cap.
  int isoValue = -1;
  int clipPlane = -1; ///< a cap's clipping plane (its index); -1 on a surface
  /// Unit normal: along the field's exact gradient (towards increasing field) on a surface, the
  /// plane's normal on a cap.
  glm::dvec3 normal{ 0.0 };
  double value = 0.0; ///< the field interpolated at the point
  /// VTK's parametric coordinates in the cell (Scene::parametricCoordinates), when it has them.
  bool hasParametric = false;
  double parametric[3] = { 0.0, 0.0, 0.0 };
};

/// Output image, row-major with row 0 at the bottom; the buffers are owned by the caller.
/// `normals` holds the normal used for shading: along the field's gradient (towards increasing
/// field) for the first three modes, towards the viewer for DepthBuffer, the plane's normal on a
/// cap. Depth, normal, cell id and colour value are those of the nearest surface (or cap).
struct ImageView
{
  int width = 0;
  int height = 0;
  std::uint8_t* colors = nullptr; ///< RGBA, not premultiplied; background (0, 0, 0, 0)
  double* depth = nullptr;        ///< +inf on misses
  double* normals = nullptr;      ///< unit normal (x, y, z); 0 on misses
  NodeId* cellIds = nullptr;      ///< -1 on misses
  /// Optional: the value that was colour-mapped (colour array, or the field on a cap); NaN where
  /// none was.
  double* colorValues = nullptr;
  /// Optional input: per pixel, the ray parameter beyond which nothing is seen (opaque geometry
  /// drawn by others); +inf where nothing limits the ray.
  const double* rayLimits = nullptr;
  /// Optional output: per pixel, the SurfaceIndex entry of the nearest surface's cell
  /// (SurfaceHit::entry), kNoEntry on misses and caps; what reprojectHits takes.
  std::uint32_t* hitEntries = nullptr;
  /// Optional input: per pixel, an entry for the first ray to test first (reprojectHits). It
  /// changes how soon the nearest hit is found, not which it is.
  const std::uint32_t* entryHints = nullptr;
  /// Optional output: the crossings each pixel composited (caps included), front to back, in
  /// one list per tile (the Renderer sizes it to numberOfTiles(); a tile's list is written only
  /// by the thread rendering that tile).
  std::vector<std::vector<PixelLayer>>* layers = nullptr;
};

/// Composites crossings cast apart into one image as a Renderer composites one ray's: per pixel
/// front to back by t, those beyond rayLimits[pixel] (optional) dropped, a crossing within `gap`
/// of the last one taken dropped as the same surface found twice (where two pieces' cells
/// meet), until the pixel is opaque to 8 bits or Renderer::kMaxLayers are taken. Writes `pixels`
/// RGBA colours (not premultiplied; (0, 0, 0, 0) where nothing is taken). Sorts `layers`.
void compositeLayers(std::vector<PixelLayer>& layers, std::size_t pixels, double gap,
  const double* rayLimits, std::uint8_t* colors);

/// A translucent surface is blended over the finished frame, after the other translucent
/// geometry of its view (a renderer's depth peeling or order-independent translucency cannot
/// take its layers between theirs): warns, when `otherTranslucentProps` > 0, that where those lie
/// in front of the surface the picture is wrong, naming the view's translucency technique
/// (`technique`, e.g. "depth peeling").
void checkTranslucentNeighbours(
  int otherTranslucentProps, const char* technique, Messages& messages);

/// Frames that re-use the last one: the last frame's hits (its rays, its depth and hitEntries)
/// carried to the pixels of a new view, whose points `worldToNdc` takes to normalised device
/// coordinates (x, y in [-1, 1] across the image, z in [-1, 1] near to far; the rays' own
/// coordinates, e.g. a mapper's model coordinates). Each old hit marks the pixel it lands in
/// with its cell (the nearest where several land); a pixel none lands in takes a marked
/// neighbour's (3 x 3), else kNoEntry. `hints` has width x height entries.
void reprojectHits(const RayGenerator& lastRays, int lastWidth, int lastHeight,
  const double* lastDepth, const std::uint32_t* lastEntries, const glm::dmat4& worldToNdc,
  int width, int height, std::uint32_t* hints);

/// Shading of a hit seen along `viewDirection` (unit, camera to hit) with `color` as ambient and
/// diffuse colour. The normal is flipped towards the viewer, so the visible side of the surface
/// is the lit one whatever the field's sign.
glm::dvec3 shade(const Material& material, const glm::dvec3& color, const glm::dvec3& hitPoint,
  const glm::dvec3& unitNormal, const glm::dvec3& viewDirection, const Lighting& lighting);

class Renderer
{
public:
  /// Casts rays into `surface` (its scene and iso-values). NodalInterpolation needs
  /// scene.computeNodalGradients() to have run.
  Renderer(const SurfaceIndex& surface, const Camera& camera, const RenderSettings& settings,
    const ImageView& image);
  /// With any rays (e.g. from an inverse projection); `rays` must be for image's size.
  Renderer(const SurfaceIndex& surface, const RayGenerator& rays, const RenderSettings& settings,
    const ImageView& image);

  /// Square tiles of kTileSize pixels a side (clipped at the image's edges), row-major from the
  /// bottom left. Neighbouring rays visit the same cells, so a tile keeps them in cache.
  static constexpr int kTileSize = 16;
  NodeId numberOfTiles() const;

  /// Renders tiles [tileBegin, tileEnd). Pixels are independent, so any partition of the tiles
  /// over threads gives the same image bit for bit.
  void renderTiles(NodeId tileBegin, NodeId tileEnd) const;

  /// What `ray` (e.g. RayGenerator::displayRay at a display position) sees first, as a pixel's
  /// ray would: within the clipping planes, a cap where the ray enters the kept side inside the
  /// region the cap shows, else the nearest surface, no farther than tLimit. False when it sees
  /// nothing. Thread-safe.
  bool pick(const Ray& ray, Pick& pick,
    double tLimit = std::numeric_limits<double>::infinity()) const;

  /// DepthBuffer only, after every tile is rendered: replaces the normals (and shading) of the
  /// nearest surface in tiles [tileBegin, tileEnd) by ones from the depth image's differences.
  void shadeFromDepth(NodeId tileBegin, NodeId tileEnd) const;

  /// Crossings composited per ray at most (translucent surfaces). Bounds the work where a ray
  /// runs through a region where the field equals an iso-value (every point a crossing).
  static constexpr int kMaxLayers = 64;
  /// Crossings are composited until the opacity reaches this: the rest could not change an 8-bit
  /// colour.
  static constexpr double kOpaque = 1.0 - 1.0 / 512.0;
  /// Crossings nearer than this times the scene's diagonal are one surface.
  static constexpr double kLayerGap = 1e-9;

private:
  /// A pixel's nearest surface, kept for DepthBuffer's second pass: its unshaded colour and
  /// opacity, and what lies behind it, composited (premultiplied).
  struct NearestLayer
  {
    glm::dvec3 color{ 0.0 };
    double opacity = 0.0;
    glm::dvec3 behindColor{ 0.0 };
    double behindOpacity = 0.0;
  };

  template <typename PixelFunction>
  void forEachPixel(NodeId tileBegin, NodeId tileEnd, PixelFunction&& function) const;
  void renderPixel(int i, int j) const;
  /// Frustum culling's blocks (renderTiles): pixels [i0, i1) x [j0, j1).
  static constexpr int kBlockSize = 4;
  bool blockMayHit(int i0, int j0, int i1, int j1) const;
  void renderBlock(int i0, int j0, int i1, int j1, bool mayHit) const;
  bool clipInterval(const Ray& ray, double& tMin, double& tMax, int& enteringPlane) const;
  bool capAt(const Ray& ray, double t, int plane, std::size_t pixel) const;
  /// Whether a point of a clipping plane lies where the cap is shown (inside the mesh, on the
  /// capped side of the iso-value): its cell and field value then.
  bool capCovers(const glm::dvec3& point, NodeId& cellId, double& field) const;
  /// A vector along the field's gradient at the hit (only its direction is used).
  glm::dvec3 normalAt(const SurfaceHit& hit, const glm::dvec3& point) const;
  double colorValue(NodeId cellId, const glm::dvec3& point) const;
  glm::dvec3 directColor(NodeId cellId, const glm::dvec3& point) const;
  void writePixel(std::size_t pixel, const glm::dvec3& premultiplied, double opacity) const;
  /// Into ImageView::layers, when asked for.
  void addLayer(std::size_t pixel, double t, const glm::dvec3& color, double opacity) const;
  void writeMiss(std::size_t pixel) const;

  const SurfaceIndex& Surface_;
  const Scene& Scene_;
  RayGenerator Rays_;
  const IsoValues& IsoValues_;
  RenderSettings Settings_;
  std::vector<SurfaceStyle> SortedStyles_; ///< per IsoValues::sorted() entry
  bool Translucent_ = false;
  double LayerGap_ = 0.0;
  ImageView Image_;
  int TilesPerRow_;
  mutable std::vector<NearestLayer> Nearest_; ///< DepthBuffer only; one per pixel
};

} // namespace tetdsr
