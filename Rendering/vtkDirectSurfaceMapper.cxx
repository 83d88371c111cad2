#include "vtkDirectSurfaceMapper.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkHardwareSelector.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkCommunicator.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkOpenGLRenderUtilities.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLShaderCache.h"
#include "vtkOpenGLState.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
#include "vtkProperty.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkScalarsToColors.h"
#include "vtkShaderProgram.h"
#include "vtkSmartPointer.h"
#include "vtkTextureObject.h"
#include "vtkTimerLog.h"
#include "vtkWeakPointer.h"
#include "vtkCommand.h"
#include "vtkUnstructuredGrid.h"

#include "vtkDirectSurfaceAdapter.h"
#include "vtkDirectSurfacePick.h"
#include "vtkDirectSurfaceReporting.h"
#include "tetdsr/render/Upsampling.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <thread>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkDirectSurfaceMapper);

namespace
{
namespace adapter = tetdsr::vtkadapter;

/// How often the event loop asks whether a background cast is done: 25 times a second, so the
/// refined frame follows within a frame time of a fluid interaction.
constexpr unsigned long kRefinementPollMilliseconds = 40;

/// Whether two image signatures describe one scene up to rounding: a camera set again from its
/// own parameters (as ParaView does before a still render) moves the matrices and lights by an
/// ulp or two; 1e-12 of the numbers' size (at least 1) is far below a visible change, and keeps
/// modification times below 1e12 apart.
bool SameScene(const std::vector<double>& a, const std::vector<double>& b)
{
  if (a.size() != b.size())
  {
    return false;
  }
  for (std::size_t k = 0; k < a.size(); ++k)
  {
    if (!(std::abs(a[k] - b[k]) <= 1e-12 * std::max({ 1.0, std::abs(a[k]), std::abs(b[k]) })))
    {
      return false;
    }
  }
  return true;
}

/// Row-major vtkMatrix4x4 to glm's column-major matrix.
glm::dmat4 ToGlm(const vtkMatrix4x4* matrix)
{
  glm::dmat4 result;
  for (int row = 0; row < 4; ++row)
  {
    for (int column = 0; column < 4; ++column)
    {
      result[column][row] = matrix->GetElement(row, column);
    }
  }
  return result;
}

/// A world point, and a world direction (made unit), in model coordinates: rays are cast there.
glm::dvec3 ToModelPoint(const glm::dmat4& worldToModel, const double p[3])
{
  return glm::dvec3(worldToModel * glm::dvec4(p[0], p[1], p[2], 1.0));
}
glm::dvec3 ToModelDirection(const glm::dmat4& worldToModel, const glm::dvec3& d)
{
  return tetdsr::unitVector(glm::dvec3(worldToModel * glm::dvec4(d, 0.0)));
}

/// A switched-on VTK light as the core's, in model coordinates.
tetdsr::Light CoreLight(vtkLight* light, const glm::dmat4& worldToModel)
{
  tetdsr::Light entry;
  double color[3], position[3], focalPoint[3];
  light->GetDiffuseColor(color);
  light->GetTransformedPosition(position);
  light->GetTransformedFocalPoint(focalPoint);
  entry.color = light->GetIntensity() * glm::dvec3(color[0], color[1], color[2]);
  entry.positional = light->GetPositional() != 0;
  entry.position = ToModelPoint(worldToModel, position);
  entry.direction = ToModelDirection(worldToModel,
    glm::dvec3(
      focalPoint[0] - position[0], focalPoint[1] - position[1], focalPoint[2] - position[2]));
  return entry;
}

/// The colour of a block's surface from `mapper`'s scalars on `grid`, as a polygon mapper would
/// map them (direct colours, or through its lookup table and scalar range); none, with a
/// warning, for a cell array, which has no value at a hit.
void ChooseColors(vtkMapper* mapper, vtkUnstructuredGrid* grid, adapter::PreparedMesh& prepared,
  tetdsr::RenderSettings& settings, adapter::Messages& messages)
{
  settings.colorBy = tetdsr::ColorByArray();
  int cellFlag = 0;
  vtkDataArray* colors = mapper->GetScalarVisibility()
    ? vtkAbstractMapper::GetScalars(grid, mapper->GetScalarMode(), mapper->GetArrayAccessMode(),
        mapper->GetArrayId(), mapper->GetArrayName(), cellFlag)
    : nullptr;
  if (colors && cellFlag != 0)
  {
    messages.warnings.push_back(std::string("Cell array '") +
      (colors->GetName() ? colors->GetName() : "") +
      "' cannot colour the surface: it needs a point array; drawn in the actor's colour.");
    return;
  }
  if (!colors)
  {
    return;
  }
  vtkScalarsToColors* table = mapper->GetLookupTable();
  const int colorMode = mapper->GetColorMode();
  const bool direct = colorMode == VTK_COLOR_MODE_DIRECT_SCALARS ||
    (colorMode == VTK_COLOR_MODE_DEFAULT && colors->GetDataType() == VTK_UNSIGNED_CHAR);
  int colorComponent =
    table->GetVectorMode() == vtkScalarsToColors::COMPONENT ? table->GetVectorComponent() : -1;
  if (colors->GetNumberOfComponents() == 1)
  {
    colorComponent = 0;
  }
  const double* colorValues = prepared.PointArrayValues(colors, "colour array", messages);
  if (colorValues && colorComponent < colors->GetNumberOfComponents())
  {
    settings.colorBy.values = colorValues;
    settings.colorBy.components = colors->GetNumberOfComponents();
    settings.colorBy.component = colorComponent;
    settings.colorBy.directColors = direct;
    if (!direct)
    {
      const double* range =
        mapper->GetUseLookupTableScalarRange() ? table->GetRange() : mapper->GetScalarRange();
      table->Build();
      settings.colorTable = adapter::SampleColorTable(table, range[0], range[1]);
    }
  }
}

/// The colour and depth images drawn by full-screen quads: colour as RGBA8, window depth as
/// R32F; a depth of 1 (a miss) is discarded. An image of the viewport's size is drawn pixel for
/// pixel (kQuadFull); a smaller one (interaction) is upsampled without blending across
/// silhouettes, by the core's rule (tetdsr/render/Upsampling.h), in two draws: the blocks of
/// 2 x 2 cast pixels on one surface filtered bilinearly by the texture unit (kQuadSurface), then
/// the blocks with a silhouette or a miss, where each output pixel keeps only the corners on its
/// nearest cast pixel's surface (the masks' bits) and the nearest cast pixel decides coverage
/// (kQuadMixed). Three programs without branches between them: a software rasteriser (Mesa's
/// llvmpipe) runs both sides of a branch, so one program with all three cost an interactive
/// frame at 1024 x 1024 about 20 ms more than these.
const char* const kQuadDeclarations = R"(
uniform sampler2D colorTexture;
uniform sampler2D depthTexture;
)";
const char* const kQuadUpsampleDeclarations = R"(
uniform sampler2D colorTexture;
uniform sampler2D depthTexture;
uniform sampler2D maskTexture;
uniform sampler2D blockTexture;

int byteAt(sampler2D bytes, ivec2 p)
{
  return int(texelFetch(bytes, p, 0).r * 255.0 + 0.5);
}
)";
const char* const kQuadFull = R"(
  ivec2 nearest = min(ivec2(texCoord * vec2(textureSize(depthTexture, 0))),
    textureSize(depthTexture, 0) - 1);
  float depth = texelFetch(depthTexture, nearest, 0).r;
  if (depth >= 1.0) { discard; }
  gl_FragDepth = depth;
  gl_FragData[0] = texelFetch(colorTexture, nearest, 0);
)";
const char* const kQuadUpsample = R"(
  ivec2 size = textureSize(depthTexture, 0);
  vec2 castPoint = texCoord * vec2(size); // cast pixel k spans [k, k + 1)
  ivec2 corner = ivec2(floor(castPoint - 0.5));
  int block = byteAt(blockTexture, corner + 1);
  if (block == 2) { discard; } // every corner a miss
  // One surface (block 1): the texture unit's bilinear filter.
  vec4 color = texture(colorTexture, texCoord);
  float depth = texture(depthTexture, texCoord).r;
  // A silhouette or a miss among the corners (block 0): only the corners on the nearest cast
  // pixel's surface. (A loop run once or never, not an if: a software rasteriser such as Mesa's
  // llvmpipe runs both sides of an if for every pixel, but leaves a loop that no pixel of its
  // group enters.)
  for (int mixed = block == 0 ? 1 : 0; mixed > 0; --mixed)
  {
    ivec2 nearest = min(ivec2(castPoint), size - 1);
    float nearestDepth = texelFetch(depthTexture, nearest, 0).r;
    if (nearestDepth >= 1.0) { discard; }
    int mask = byteAt(maskTexture, nearest);
    vec2 f = castPoint - 0.5 - vec2(corner);
    color = vec4(0.0);
    depth = 0.0;
    float weight = 0.0;
    for (int k = 0; k < 4; ++k)
    {
      ivec2 offset = ivec2(k & 1, k >> 1);
      ivec2 p = clamp(corner + offset, ivec2(0), size - 1);
      ivec2 o = p - nearest; // each component in -1..1
      int bit = (o.y + 1) * 3 + (o.x + 1);
      if (bit == 4 || ((mask >> (bit < 4 ? bit : bit - 1)) & 1) != 0)
      {
        vec2 axes = mix(1.0 - f, f, vec2(offset));
        float w = axes.x * axes.y;
        color += w * texelFetch(colorTexture, p, 0);
        depth += w * texelFetch(depthTexture, p, 0).r;
        weight += w;
      }
    }
    // (weight > 0: the nearest cast pixel's bilinear weight is at least 1/4.)
    color /= weight;
    depth /= weight;
  }
  gl_FragDepth = depth;
  gl_FragData[0] = color;
)";
}

/// What one Draw works with, from stage to stage: the blocks, the view, the settings of the cast
/// and its messages.
struct vtkDirectSurfaceMapper::Frame
{
  Frame(vtkOpenGLRenderWindow* window, vtkActor* actor, bool translucent)
    : Window(window)
    , Actor(actor)
    , Translucent(translucent)
  {
  }

  vtkOpenGLRenderWindow* const Window;
  vtkActor* const Actor;
  const bool Translucent; ///< cast up to the opaque depth, drawn over the finished frame
  /// Every crossing kept (ImageCast::Layers) and no ray limits: for compositing across processes.
  bool CollectLayers = false;
  /// A hardware-selection pass: each pixel's block is kept (ImageCast::PixelBlocks).
  bool Selecting = false;
  vtkDataObject* Input = nullptr;
  std::vector<std::pair<unsigned int, vtkUnstructuredGrid*>> Blocks; ///< by flat index

  // The view: the viewport at full resolution (origin x, y, width, height), the cast's size, and
  // the model's matrices (rays are cast in model coordinates).
  int Viewport[4] = { 0, 0, 0, 0 };
  int CastWidth = 0;
  int CastHeight = 0;
  bool Identity = true; ///< the actor's matrix is the identity
  glm::dmat4 ModelToWorld{ 1.0 }, WorldToModel{ 1.0 }, ModelToNdc{ 1.0 }, NdcToModel{ 1.0 };
  tetdsr::RayGenerator Rays{ glm::dmat4(1.0), 1, 1 }; ///< set with the view

  std::vector<double> LightState; ///< the switched-on lights' parameters, for the signature
  std::vector<double> Signature;  ///< everything the image depends on
  std::vector<double> Values;     ///< the iso-values
  tetdsr::RenderSettings Settings;
  adapter::Messages Messages;

  std::size_t Pixels() const
  {
    return static_cast<std::size_t>(this->CastWidth) * this->CastHeight;
  }
  bool SeveralBlocks() const { return this->Blocks.size() > 1; }

  /// The viewport, cast at `sampleDistance` pixels a ray, and the actor seen through the active
  /// camera's composite projection (as the GL matrices use it, so explicit and tiled projections
  /// work). False for an empty viewport.
  bool SetUpView(vtkRenderer* renderer, double sampleDistance)
  {
    int width, height, originX, originY;
    renderer->GetTiledSizeAndOrigin(&width, &height, &originX, &originY);
    if (width <= 0 || height <= 0)
    {
      return false;
    }
    this->Viewport[0] = originX;
    this->Viewport[1] = originY;
    this->Viewport[2] = width;
    this->Viewport[3] = height;
    this->CastWidth = std::max(1, static_cast<int>(std::ceil(width / sampleDistance)));
    this->CastHeight = std::max(1, static_cast<int>(std::ceil(height / sampleDistance)));
    vtkCamera* camera = renderer->GetActiveCamera();
    const glm::dmat4 worldToNdc = ToGlm(
      camera->GetCompositeProjectionTransformMatrix(renderer->GetTiledAspectRatio(), -1.0, 1.0));
    this->Identity = this->Actor->GetIsIdentity() != 0;
    this->ModelToWorld = this->Identity ? glm::dmat4(1.0) : ToGlm(this->Actor->GetMatrix());
    this->WorldToModel = glm::inverse(this->ModelToWorld);
    this->ModelToNdc = worldToNdc * this->ModelToWorld;
    this->NdcToModel = glm::inverse(this->ModelToNdc);
    this->Rays = tetdsr::RayGenerator(this->NdcToModel, this->CastWidth, this->CastHeight);
    return true;
  }

  /// The renderer's lights, as vtkOpenGLRenderer hands them to the polygon shaders (none when
  /// the actor's property is unlit), with the camera position as the eye of the Phong model.
  void CollectLights(vtkRenderer* renderer)
  {
    tetdsr::Lighting& lighting = this->Settings.lighting;
    double eye[3];
    renderer->GetActiveCamera()->GetPosition(eye);
    lighting.hasEye = true;
    lighting.eye = ToModelPoint(this->WorldToModel, eye);
    if (!this->Actor->GetProperty()->GetLighting())
    {
      return;
    }
    vtkLightCollection* lights = renderer->GetLights();
    vtkCollectionSimpleIterator it;
    lights->InitTraversal(it);
    int count = 0;
    bool headlight = false;
    while (vtkLight* light = lights->GetNextLight(it))
    {
      if (!light->GetSwitch())
      {
        continue;
      }
      ++count;
      headlight = light->LightTypeIsHeadlight();
      const tetdsr::Light entry = CoreLight(light, this->WorldToModel);
      lighting.lights.push_back(entry);
      this->LightState.insert(this->LightState.end(),
        { entry.color.x, entry.color.y, entry.color.z, entry.direction.x, entry.direction.y,
          entry.direction.z, entry.position.x, entry.position.y, entry.position.z,
          entry.positional ? 1.0 : 0.0 });
    }
    lighting.headlightOnly = count == 1 && headlight;
  }
};

/// One cast: a caster per rendered block and the CPU images they write (cast size), merged over
/// blocks (a block's own image when there are several), and the ray limits under translucent
/// surfaces.
struct vtkDirectSurfaceMapper::ImageCast
{
  std::vector<std::unique_ptr<tetdsr::Renderer>> Casters; ///< in block order
  std::vector<std::uint8_t> Colors;
  std::vector<double> Depth;
  std::vector<double> Normals;
  std::vector<tetdsr::NodeId> CellIds;
  std::vector<float> WindowDepth;
  std::vector<std::uint8_t> BlockColors;
  std::vector<double> BlockDepth;
  std::vector<tetdsr::NodeId> BlockCellIds;
  std::vector<double> RayLimits;
  std::vector<unsigned int> CasterBlocks; ///< each caster's block (flat index)
  /// Per pixel, the flat index of the block it shows (only when sized: hardware selection).
  std::vector<unsigned int> PixelBlocks;
  /// Per block, per tile, the crossings (Frame::CollectLayers).
  std::vector<std::unique_ptr<std::vector<std::vector<tetdsr::PixelLayer>>>> Layers;

  /// Sizes the images for a cast of `pixels` rays; with several blocks the merged image starts
  /// empty (each block's nearer surfaces replace it) and each block has its own.
  void Resize(std::size_t pixels, bool severalBlocks)
  {
    this->Layers.clear();
    this->Colors.resize(4 * pixels);
    this->Depth.resize(pixels);
    this->Normals.resize(3 * pixels);
    this->CellIds.resize(pixels);
    this->WindowDepth.resize(pixels);
    if (severalBlocks)
    {
      std::fill(this->Depth.begin(), this->Depth.end(), std::numeric_limits<double>::infinity());
      std::fill(this->Colors.begin(), this->Colors.end(), 0);
      this->BlockColors.resize(4 * pixels);
      this->BlockDepth.resize(pixels);
      this->BlockCellIds.resize(pixels);
    }
  }

  /// Per cast pixel, the ray parameter of the opaque depth at its full-resolution pixel.
  void ComputeRayLimits(const Frame& frame, const std::vector<float>& opaqueDepth)
  {
    const int width = frame.Viewport[2], height = frame.Viewport[3];
    const int castWidth = frame.CastWidth, castHeight = frame.CastHeight;
    this->RayLimits.resize(frame.Pixels());
    vtkSMPTools::For(0, castHeight, [&](vtkIdType rowBegin, vtkIdType rowEnd) {
      for (int j = static_cast<int>(rowBegin); j < static_cast<int>(rowEnd); ++j)
      {
        const int fullJ = std::min(height - 1, static_cast<int>((j + 0.5) * height / castHeight));
        for (int i = 0; i < castWidth; ++i)
        {
          const int fullI = std::min(width - 1, static_cast<int>((i + 0.5) * width / castWidth));
          const double z = opaqueDepth[static_cast<std::size_t>(fullJ) * width + fullI];
          double limit = std::numeric_limits<double>::infinity();
          if (z < 1.0)
          {
            const tetdsr::Ray ray = frame.Rays.pixelRay(i, j);
            const glm::dvec4 ndc(2.0 * (i + 0.5) / castWidth - 1.0,
              2.0 * (j + 0.5) / castHeight - 1.0, 2.0 * z - 1.0, 1.0);
            const glm::dvec4 point = frame.NdcToModel * ndc;
            limit = glm::dot(glm::dvec3(point) / point.w - ray.origin, ray.direction);
          }
          this->RayLimits[static_cast<std::size_t>(j) * castWidth + i] = limit;
        }
      }
    });
  }

  /// The image a block is cast into: the merged image itself when it is the only block, else
  /// its own (KeepNearest merges it).
  tetdsr::ImageView BlockImage(const Frame& frame)
  {
    const bool several = frame.SeveralBlocks();
    tetdsr::ImageView image;
    image.width = frame.CastWidth;
    image.height = frame.CastHeight;
    image.colors = several ? this->BlockColors.data() : this->Colors.data();
    image.depth = several ? this->BlockDepth.data() : this->Depth.data();
    image.normals = this->Normals.data();
    image.cellIds = several ? this->BlockCellIds.data() : this->CellIds.data();
    image.rayLimits = frame.Translucent && !frame.CollectLayers ? this->RayLimits.data() : nullptr;
    if (frame.CollectLayers)
    {
      this->Layers.emplace_back(new std::vector<std::vector<tetdsr::PixelLayer>>);
      image.layers = this->Layers.back().get();
    }
    return image;
  }

  /// Keeps, per pixel, the nearest block's surface (and that block's flat index, when
  /// PixelBlocks is sized).
  void KeepNearest(std::size_t pixels, unsigned int block)
  {
    const bool blocks = !this->PixelBlocks.empty();
    for (std::size_t p = 0; p < pixels; ++p)
    {
      if (this->BlockDepth[p] < this->Depth[p])
      {
        this->Depth[p] = this->BlockDepth[p];
        this->CellIds[p] = this->BlockCellIds[p];
        std::copy_n(&this->BlockColors[4 * p], 4, &this->Colors[4 * p]);
        if (blocks)
        {
          this->PixelBlocks[p] = block;
        }
      }
    }
  }

  /// Window depth of each hit in rows [rowBegin, rowEnd) (the core's windowDepths).
  void ComputeWindowDepth(const tetdsr::RayGenerator& rays, const glm::dmat4& modelToNdc,
    int castWidth, int rowBegin, int rowEnd)
  {
    tetdsr::windowDepths(rays, modelToNdc, this->Depth.data(), this->WindowDepth.data(),
      castWidth, rowBegin, rowEnd);
  }
};

/// A full-resolution cast on worker threads after interaction (ProgressiveRefinement). It owns
/// its images and its casters (made on the GL thread, which prepared their meshes), so the GL
/// thread reads nothing it writes until Finished; its casters read the prepared meshes, which
/// the GL thread leaves alone until the cast is cancelled and joined (CancelRefinements).
/// Destroying it cancels it and waits for its threads (at most one image tile each).
struct vtkDirectSurfaceMapper::Refinement
{
  std::vector<double> Signature; ///< the view it casts
  int Width = 0;
  int Height = 0;
  tetdsr::RayGenerator Rays{ glm::dmat4(1.0), 1, 1 };
  glm::dmat4 ModelToNdc{ 1.0 };
  bool SeveralBlocks = false;
  ImageCast Cast;
  double Seconds = 0.0; ///< the cast's wall-clock time, once Finished

  std::atomic<bool> Cancelled{ false };
  std::atomic<bool> Finished{ false };
  std::thread Worker;

  // The render it asks for when Finished: the window's interactor polls it with one-shot timers
  // (one pending at a time; a fired one is forgotten by the interactor itself: VTK 9.2's X
  // interactor crashes when a timer is destroyed while it fires).
  vtkWeakPointer<vtkRenderWindowInteractor> Interactor;
  int TimerId = 0;

  ~Refinement()
  {
    this->Cancelled = true;
    if (this->Worker.joinable())
    {
      this->Worker.join();
    }
    if (this->Interactor && this->TimerId)
    {
      this->Interactor->DestroyTimer(this->TimerId);
    }
  }

  /// The worker: every block's tiles on `threads` threads, each taking the next tile until
  /// there are none or the cast is cancelled (checked before each tile); then the blocks'
  /// nearest surfaces and the window depth.
  void Run(int threads)
  {
    const auto start = std::chrono::steady_clock::now();
    for (const auto& caster : this->Cast.Casters)
    {
      const tetdsr::NodeId tiles = caster->numberOfTiles();
      std::atomic<tetdsr::NodeId> next{ 0 };
      auto castTiles = [&]() {
        tetdsr::NodeId tile;
        while (!this->Cancelled && (tile = next++) < tiles)
        {
          caster->renderTiles(tile, tile + 1);
        }
      };
      std::vector<std::thread> helpers;
      for (int t = 1; t < threads; ++t)
      {
        helpers.emplace_back(castTiles);
      }
      castTiles();
      for (std::thread& helper : helpers)
      {
        helper.join();
      }
      if (this->Cancelled)
      {
        return;
      }
      if (this->SeveralBlocks)
      {
        this->Cast.KeepNearest(this->Cast.Depth.size(), 0);
      }
    }
    this->Cast.ComputeWindowDepth(this->Rays, this->ModelToNdc, this->Width, 0, this->Height);
    this->Seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    this->Finished = true;
  }
};

/// Per-render state: the prepared meshes (one per block), the last images, background casts,
/// and the OpenGL resources.
struct vtkDirectSurfaceMapper::Internals
{
  adapter::IsoValueStyles Styles;
  vtkSmartPointer<vtkMultiProcessController> Controller; ///< DrawTranslucentAcrossProcesses'
  std::map<unsigned int, std::unique_ptr<adapter::PreparedMesh>> Meshes; ///< by block index

  // How long the last cast took at which sample distance.
  double SampleDistance = 1.0;
  double LastCastSeconds = 0.0;
  double LastRenderStart = 0.0; ///< wall-clock start of the last render (not re-used)
  bool LastWasInteractive = false;

  ImageCast Cast; ///< the last cast on the GL thread
  std::vector<float> OpaqueDepth; ///< under translucent surfaces, at full resolution

  // Translucent surfaces wait for their renderer's EndEvent: every actor of this mapper that
  // asked for them in that renderer's frame (one mapper may serve several actors and renderers).
  struct Deferred
  {
    vtkWeakPointer<vtkRenderer> Renderer;
    unsigned long ObserverTag = 0;
    std::vector<vtkWeakPointer<vtkActor>> Actors;
  };
  std::vector<Deferred> DeferredDraws;

  /// What one view (a window's renderer and an actor of this mapper) draws its image with:
  /// textures and quad (OpenGL objects belong to the window's context), the signature and size
  /// of the image the textures hold, so that each view re-uses its own, and its background cast.
  struct ViewResources
  {
    vtkWeakPointer<vtkOpenGLRenderWindow> Window;
    vtkWeakPointer<vtkRenderer> Renderer;
    vtkWeakPointer<vtkActor> Actor;
    vtkSmartPointer<vtkTextureObject> ColorTexture;
    vtkSmartPointer<vtkTextureObject> DepthTexture;
    /// For an image smaller than the viewport: per cast pixel its same-surface bits, per 2 x 2
    /// block its kind (tetdsr/render/Upsampling.h), and those as textures.
    tetdsr::UpsampleMaps Upsampling;
    vtkSmartPointer<vtkTextureObject> MaskTexture;
    vtkSmartPointer<vtkTextureObject> BlockTexture;
    bool UpsamplingValid = false;
    std::unique_ptr<vtkOpenGLQuadHelper> Quads[2]; ///< kQuadFull, kQuadUpsample
    bool TexturesValid = false;
    std::vector<double> Signature;
    int ImageSize[2] = { 0, 0 };
    double ImageSampleDistance = 1.0;
    std::unique_ptr<Refinement> Refining;

    /// Hardware selection: the last selection cast of this view (its signature, and per pixel
    /// the input's cell, the block's flat index, the window depth; the nearest point is found
    /// when a point pass asks), and the textures a pass draws its ids with.
    struct SelectionImage
    {
      std::vector<double> Signature;
      std::vector<double> FailedSignature; ///< of a cast that could not be made (reported once)
      int Width = 0, Height = 0;
      tetdsr::RayGenerator Rays{ glm::dmat4(1.0), 1, 1 };
      std::vector<tetdsr::NodeId> CellIds;
      std::vector<unsigned int> Blocks;
      std::vector<double> Depth;
      std::vector<float> WindowDepth;
      std::vector<tetdsr::NodeId> PointIds; ///< empty until a point pass
      vtkSmartPointer<vtkTextureObject> IdTexture;
      vtkSmartPointer<vtkTextureObject> DepthTexture;
      std::vector<std::uint8_t> Ids; ///< the pass's colours
    } Selection;

    void Release(vtkWindow* window)
    {
      this->Refining.reset();
      for (auto* texture : { &this->Selection.IdTexture, &this->Selection.DepthTexture })
      {
        if (*texture)
        {
          (*texture)->ReleaseGraphicsResources(window);
          *texture = nullptr;
        }
      }
      this->Selection.Signature.clear();
      for (auto& quad : this->Quads)
      {
        if (quad)
        {
          quad->ReleaseGraphicsResources(window);
          quad.reset();
        }
      }
      for (auto* texture :
        { &this->ColorTexture, &this->DepthTexture, &this->MaskTexture, &this->BlockTexture })
      {
        if (*texture)
        {
          (*texture)->ReleaseGraphicsResources(window);
          *texture = nullptr;
        }
      }
      this->TexturesValid = false;
      this->UpsamplingValid = false;
      this->Signature.clear();
    }
  };
  std::vector<std::unique_ptr<ViewResources>> Views;

  /// The interactors of the windows this mapper draws in, each observed for its TimerEvent
  /// (TimerFired), and whether its event loop runs: a one-shot timer set when it was first seen
  /// has fired. Only then can a background cast ask for the render that shows it; scripts that
  /// call Render without processing the interactor's events never fire it.
  struct EventLoop
  {
    vtkWeakPointer<vtkRenderWindowInteractor> Interactor;
    unsigned long ObserverTag = 0;
    int ProbeTimerId = 0;
    bool Runs = false;
  };
  std::vector<EventLoop> EventLoops;

  /// What the last report of an undrawable input (empty bounds) was made for.
  std::vector<std::uintptr_t> SilenceStamp;

  /// The resources of a view, made on first use. Entries of deleted windows, renderers or
  /// actors are dropped (a window releases its quads' and textures' OpenGL objects itself when
  /// it goes; those of a deleted renderer or actor are released here).
  ViewResources& ResourcesOf(vtkOpenGLRenderWindow* window, vtkRenderer* renderer, vtkActor* actor)
  {
    for (auto it = this->Views.begin(); it != this->Views.end();)
    {
      ViewResources& r = **it;
      if (!r.Window || !r.Renderer || !r.Actor)
      {
        if (r.Window)
        {
          r.Release(r.Window);
        }
        it = this->Views.erase(it);
      }
      else if (r.Window == window && r.Renderer == renderer && r.Actor == actor)
      {
        return r;
      }
      else
      {
        ++it;
      }
    }
    this->Views.emplace_back(new ViewResources);
    ViewResources& made = *this->Views.back();
    made.Window = window;
    made.Renderer = renderer;
    made.Actor = actor;
    return made;
  }

  /// Cancels every view's background cast and waits for its threads: a cast on the GL thread
  /// may rebuild the prepared meshes they read.
  void CancelRefinements()
  {
    for (const auto& view : this->Views)
    {
      view->Refining.reset();
    }
  }

  adapter::PreparedMesh& MeshOf(unsigned int block)
  {
    auto& mesh = this->Meshes[block];
    if (!mesh)
    {
      mesh.reset(new adapter::PreparedMesh);
    }
    return *mesh;
  }

  /// Reads what the opaque geometry left in the depth buffer (it bounds the translucent rays)
  /// and returns an order-sensitive sum of it, so that a moved prop changes the signature.
  double ReadOpaqueDepth(const Frame& frame)
  {
    const int* viewport = frame.Viewport;
    this->OpaqueDepth.resize(static_cast<std::size_t>(viewport[2]) * viewport[3]);
    {
      vtkOpenGLState::ScopedglEnableDisable savedScissor(frame.Window->GetState(), GL_SCISSOR_TEST);
      frame.Window->GetZbufferData(viewport[0], viewport[1], viewport[0] + viewport[2] - 1,
        viewport[1] + viewport[3] - 1, this->OpaqueDepth.data());
    }
    double sum = 0.0;
    for (float z : this->OpaqueDepth)
    {
      sum = sum * 1.000001 + z;
    }
    return sum;
  }

  /// The window depth of the GL thread's cast, its rows on vtkSMPTools' threads.
  void ComputeWindowDepth(const Frame& frame)
  {
    vtkSMPTools::For(0, frame.CastHeight, [&](vtkIdType rowBegin, vtkIdType rowEnd) {
      this->Cast.ComputeWindowDepth(frame.Rays, frame.ModelToNdc, frame.CastWidth,
        static_cast<int>(rowBegin), static_cast<int>(rowEnd));
    });
  }

  /// A texture of the window's context (made on first use), clamped to its edge, read as
  /// `filter` says.
  static void Ready(vtkSmartPointer<vtkTextureObject>& texture, vtkOpenGLRenderWindow* window,
    int filter = vtkTextureObject::Nearest)
  {
    if (!texture)
    {
      texture = vtkSmartPointer<vtkTextureObject>::New();
      texture->SetMinificationFilter(filter);
      texture->SetMagnificationFilter(filter);
      texture->SetWrapS(vtkTextureObject::ClampToEdge);
      texture->SetWrapT(vtkTextureObject::ClampToEdge);
    }
    texture->SetContext(window);
  }

  /// Loads an RGBA8 image and a float depth image of width x height into two textures of the
  /// window's context (made on first use; the quad reads them texel by texel, and filters them
  /// when `filter` is Linear and the image is upsampled).
  static void LoadTextures(vtkOpenGLRenderWindow* window, vtkSmartPointer<vtkTextureObject>& color,
    vtkSmartPointer<vtkTextureObject>& depth, int width, int height, const std::uint8_t* colors,
    const float* depths, int filter = vtkTextureObject::Nearest)
  {
    Ready(color, window, filter);
    Ready(depth, window, filter);
    // (Create2DFromRaw only reads the pixels; its parameter is not const.)
    color->Create2DFromRaw(width, height, 4, VTK_UNSIGNED_CHAR, const_cast<std::uint8_t*>(colors));
    depth->Create2DFromRaw(width, height, 1, VTK_FLOAT, const_cast<float*>(depths));
  }

  /// The upsampling's masks and blocks of the image just loaded (the core's rule, rows on
  /// vtkSMPTools' threads), as two byte textures.
  static void LoadUpsampling(ViewResources& gl, vtkOpenGLRenderWindow* window, const float* depth,
    int width, int height)
  {
    tetdsr::upsampleMaps(depth, width, height, gl.Upsampling,
      [](tetdsr::NodeId count, const std::function<void(tetdsr::NodeId, tetdsr::NodeId)>& body) {
        vtkSMPTools::For(0, count, [&](vtkIdType begin, vtkIdType end) { body(begin, end); });
      });
    Ready(gl.MaskTexture, window);
    Ready(gl.BlockTexture, window);
    gl.MaskTexture->Create2DFromRaw(
      width, height, 1, VTK_UNSIGNED_CHAR, gl.Upsampling.masks.data());
    gl.BlockTexture->Create2DFromRaw(
      width + 1, height + 1, 1, VTK_UNSIGNED_CHAR, gl.Upsampling.blocks.data());
    gl.UpsamplingValid = true;
  }

  static void Upload(ViewResources& gl, vtkOpenGLRenderWindow* window, const ImageCast& images,
    int width, int height, double sampleDistance)
  {
    LoadTextures(window, gl.ColorTexture, gl.DepthTexture, width, height, images.Colors.data(),
      images.WindowDepth.data(), vtkTextureObject::Linear);
    gl.UpsamplingValid = false;
    if (sampleDistance > 1.0) // (a cast of the viewport's size is drawn texel for texel)
    {
      LoadUpsampling(gl, window, images.WindowDepth.data(), width, height);
    }
    gl.TexturesValid = true;
    gl.ImageSize[0] = width;
    gl.ImageSize[1] = height;
    gl.ImageSampleDistance = sampleDistance;
  }

  static bool Draw(
    ViewResources& gl, vtkOpenGLRenderWindow* window, bool translucent, const int viewport[4])
  {
    // (An image of another size without its upsampling, which no Upload makes, is drawn from
    // its nearest cast pixels.)
    const bool upsample = gl.ImageSize[0] != viewport[2] || gl.ImageSize[1] != viewport[3];
    return DrawTextures(gl, window, translucent, viewport, gl.ColorTexture, gl.DepthTexture,
      upsample && gl.UpsamplingValid);
  }

  /// The quad drawing with `implementation` (made on first use); false if it does not compile.
  static bool ReadyQuad(std::unique_ptr<vtkOpenGLQuadHelper>& quad, vtkOpenGLRenderWindow* window,
    const char* declarations, const char* implementation)
  {
    if (!quad)
    {
      std::string fragment = vtkOpenGLRenderUtilities::GetFullScreenQuadFragmentShaderTemplate();
      vtkShaderProgram::Substitute(fragment, "//VTK::FSQ::Decl", declarations);
      vtkShaderProgram::Substitute(fragment, "//VTK::FSQ::Impl", implementation);
      quad.reset(new vtkOpenGLQuadHelper(window,
        vtkOpenGLRenderUtilities::GetFullScreenQuadVertexShader().c_str(), fragment.c_str(), ""));
    }
    return quad->Program && quad->Program->GetCompiled();
  }

  /// Draws `color` at `depth` (a texture each, of the viewport's size unless `upsample`) with
  /// the view's quad.
  static bool DrawTextures(ViewResources& gl, vtkOpenGLRenderWindow* window, bool translucent,
    const int viewport[4], vtkTextureObject* color, vtkTextureObject* depth, bool upsample)
  {
    const int k = upsample ? 1 : 0;
    if (!ReadyQuad(gl.Quads[k], window, upsample ? kQuadUpsampleDeclarations : kQuadDeclarations,
          upsample ? kQuadUpsample : kQuadFull))
    {
      return false;
    }
    vtkOpenGLState* state = window->GetState();
    vtkOpenGLState::ScopedglDepthFunc savedDepthFunc(state);
    vtkOpenGLState::ScopedglDepthMask savedDepthMask(state);
    vtkOpenGLState::ScopedglEnableDisable savedDepthTest(state, GL_DEPTH_TEST);
    vtkOpenGLState::ScopedglEnableDisable savedBlend(state, GL_BLEND);
    vtkOpenGLState::ScopedglBlendFuncSeparate savedBlendFunction(state);
    vtkOpenGLState::ScopedglViewport savedViewport(state);
    vtkOpenGLState::ScopedglEnableDisable savedScissor(state, GL_SCISSOR_TEST);
    if (translucent)
    {
      // Over the finished frame: already limited to the opaque depth, blended, no depth write.
      state->vtkglViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
      state->vtkglDisable(GL_SCISSOR_TEST);
      state->vtkglDisable(GL_DEPTH_TEST);
      state->vtkglDepthMask(GL_FALSE);
      state->vtkglEnable(GL_BLEND);
      state->vtkglBlendFuncSeparate(
        GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    }
    else
    {
      // In the opaque pass: depth-tested against, and written for, every other prop.
      state->vtkglEnable(GL_DEPTH_TEST);
      state->vtkglDepthFunc(GL_LEQUAL);
      state->vtkglDepthMask(GL_TRUE);
    }
    color->Activate();
    depth->Activate();
    if (upsample)
    {
      gl.MaskTexture->Activate();
      gl.BlockTexture->Activate();
    }
    // Full resolution is drawn texel for texel, exactly as cast.
    vtkShaderProgram* program = gl.Quads[k]->Program;
    window->GetShaderCache()->ReadyShaderProgram(program);
    program->SetUniformi("colorTexture", color->GetTextureUnit());
    program->SetUniformi("depthTexture", depth->GetTextureUnit());
    if (upsample)
    {
      program->SetUniformi("maskTexture", gl.MaskTexture->GetTextureUnit());
      program->SetUniformi("blockTexture", gl.BlockTexture->GetTextureUnit());
    }
    gl.Quads[k]->Render();
    if (upsample)
    {
      gl.BlockTexture->Deactivate();
      gl.MaskTexture->Deactivate();
    }
    depth->Deactivate();
    color->Deactivate();
    return true;
  }
};

//------------------------------------------------------------------------------
vtkDirectSurfaceMapper::vtkDirectSurfaceMapper()
  : Internal(new Internals)
{
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

vtkDirectSurfaceMapper::~vtkDirectSurfaceMapper()
{
  // Background casts read the prepared meshes: they stop before anything goes.
  this->Internal->CancelRefinements();
  for (const auto& loop : this->Internal->EventLoops)
  {
    if (loop.Interactor)
    {
      if (loop.ProbeTimerId)
      {
        loop.Interactor->DestroyTimer(loop.ProbeTimerId);
      }
      loop.Interactor->RemoveObserver(loop.ObserverTag);
    }
  }
  for (const auto& deferred : this->Internal->DeferredDraws)
  {
    if (deferred.Renderer)
    {
      deferred.Renderer->RemoveObserver(deferred.ObserverTag);
    }
  }
}

//------------------------------------------------------------------------------
bool vtkDirectSurfaceMapper::IsTranslucent(vtkActor* actor)
{
  if (actor && actor->GetProperty()->GetOpacity() < 1.0)
  {
    return true;
  }
  for (int i = 0; i < this->ContourValues->GetNumberOfContours(); ++i)
  {
    if (this->Internal->Styles.GetOpacity(i) < 1.0)
    {
      return true;
    }
  }
  return false;
}

bool vtkDirectSurfaceMapper::HasOpaqueGeometry()
{
  return !this->IsTranslucent(nullptr);
}

bool vtkDirectSurfaceMapper::HasTranslucentPolygonalGeometry()
{
  return this->IsTranslucent(nullptr);
}

void vtkDirectSurfaceMapper::DrawDeferred(vtkObject* object, unsigned long, void*)
{
  auto* renderer = static_cast<vtkRenderer*>(object);
  std::vector<vtkSmartPointer<vtkActor>> actors;
  for (auto& deferred : this->Internal->DeferredDraws)
  {
    if (deferred.Renderer == renderer)
    {
      for (const auto& actor : deferred.Actors)
      {
        if (actor)
        {
          actors.emplace_back(actor.GetPointer());
        }
      }
      deferred.Actors.clear();
    }
  }
  // Each is blended over the frame and writes no depth: the farthest first, so that nearer
  // surfaces are blended over farther ones (by the distance of the actors' centres).
  double eye[3];
  renderer->GetActiveCamera()->GetPosition(eye);
  auto distance = [&eye](vtkActor* actor) {
    const double* centre = actor->GetCenter();
    return centre ? vtkMath::Distance2BetweenPoints(centre, eye) : 0.0;
  };
  std::stable_sort(actors.begin(), actors.end(),
    [&](const vtkSmartPointer<vtkActor>& a, const vtkSmartPointer<vtkActor>& b) {
      return distance(a) > distance(b);
    });
  for (const auto& actor : actors)
  {
    this->Draw(renderer, actor, true);
  }
}

int vtkDirectSurfaceMapper::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  return 1;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::SetInputData(vtkDataObject* input)
{
  if (input && !vtkUnstructuredGrid::SafeDownCast(input) &&
    !vtkCompositeDataSet::SafeDownCast(input))
  {
    vtkErrorMacro("SetInputData: a " << input->GetClassName()
                                     << " cannot be drawn: give a vtkUnstructuredGrid of quadratic "
                                        "tetrahedra, or a composite dataset of them.");
    return;
  }
  this->SetInputDataInternal(0, input);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::SetMaximumImageSampleDistance(double distance)
{
  adapter::Messages messages;
  if (tetdsr::setClamped(
        tetdsr::kMaximumImageSampleDistance, distance, this->MaximumImageSampleDistance, messages))
  {
    this->Modified();
  }
  adapter::ReportMessages(this, messages);
}

void vtkDirectSurfaceMapper::SetInteractiveImageSampleDistance(double distance)
{
  adapter::Messages messages;
  if (tetdsr::setClamped(tetdsr::kInteractiveImageSampleDistance, distance,
        this->InteractiveImageSampleDistance, messages))
  {
    this->Modified();
  }
  adapter::ReportMessages(this, messages);
}

void vtkDirectSurfaceMapper::SetScalarRange(double lo, double hi)
{
  adapter::Messages messages;
  if (tetdsr::checkFiniteNumbers("ScalarRange", { lo, hi }, messages))
  {
    this->Superclass::SetScalarRange(lo, hi);
  }
  adapter::ReportMessages(this, messages);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::SetValue(int i, double value)
{
  this->ContourValues->SetValue(i, value);
}
double vtkDirectSurfaceMapper::GetValue(int i)
{
  return this->ContourValues->GetValue(i);
}
double* vtkDirectSurfaceMapper::GetValues()
{
  return this->ContourValues->GetValues();
}
void vtkDirectSurfaceMapper::GetValues(double* contourValues)
{
  this->ContourValues->GetValues(contourValues);
}
void vtkDirectSurfaceMapper::SetNumberOfContours(int number)
{
  this->ContourValues->SetNumberOfContours(number);
}
vtkIdType vtkDirectSurfaceMapper::GetNumberOfContours()
{
  return this->ContourValues->GetNumberOfContours();
}
void vtkDirectSurfaceMapper::GenerateValues(int numContours, double range[2])
{
  this->ContourValues->GenerateValues(numContours, range);
}
void vtkDirectSurfaceMapper::GenerateValues(int numContours, double rangeStart, double rangeEnd)
{
  this->ContourValues->GenerateValues(numContours, rangeStart, rangeEnd);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::SetIsoValueColor(int i, double red, double green, double blue)
{
  adapter::Messages messages;
  if (this->Internal->Styles.SetColor(i, red, green, blue, messages))
  {
    this->Modified();
  }
  adapter::ReportMessages(this, messages);
}

void vtkDirectSurfaceMapper::GetIsoValueColor(int i, double color[3])
{
  const double white[3] = { 1.0, 1.0, 1.0 };
  this->Internal->Styles.GetColor(i, white, color);
}

void vtkDirectSurfaceMapper::RemoveAllIsoValueColors()
{
  if (this->Internal->Styles.RemoveAllColors())
  {
    this->Modified();
  }
}

void vtkDirectSurfaceMapper::SetIsoValueOpacity(int i, double opacity)
{
  adapter::Messages messages;
  if (this->Internal->Styles.SetOpacity(i, opacity, messages))
  {
    this->Modified();
  }
  adapter::ReportMessages(this, messages);
}

double vtkDirectSurfaceMapper::GetIsoValueOpacity(int i)
{
  return this->Internal->Styles.GetOpacity(i);
}

void vtkDirectSurfaceMapper::RemoveAllIsoValueOpacities()
{
  if (this->Internal->Styles.RemoveAllOpacities())
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkMTimeType vtkDirectSurfaceMapper::GetMTime()
{
  vtkMTimeType time = std::max(this->Superclass::GetMTime(), this->ContourValues->GetMTime());
  if (this->ClippingPlanes)
  {
    for (int k = 0; k < this->ClippingPlanes->GetNumberOfItems(); ++k)
    {
      time = std::max(time, this->ClippingPlanes->GetItem(k)->GetMTime());
    }
  }
  return time;
}

double* vtkDirectSurfaceMapper::GetBounds()
{
  vtkMath::UninitializeBounds(this->Bounds);
  if (!this->GetNumberOfInputConnections(0) && !this->GetInputDataObject(0, 0))
  {
    return this->Bounds;
  }
  if (!this->Static)
  {
    this->Update();
  }
  vtkDataObject* input = this->GetInputDataObject(0, 0);
  if (auto* dataSet = vtkDataSet::SafeDownCast(input))
  {
    dataSet->GetBounds(this->Bounds);
  }
  else if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
  {
    composite->GetBounds(this->Bounds);
  }
  if (!vtkMath::AreBoundsInitialized(this->Bounds))
  {
    this->ReportWhyNothingIsDrawn();
  }
  return this->Bounds;
}

void vtkDirectSurfaceMapper::ReportWhyNothingIsDrawn()
{
  // Once per change: GetBounds is asked many times a frame.
  vtkDataObject* input = this->GetInputDataObject(0, 0);
  std::vector<std::uintptr_t> stamp{ reinterpret_cast<std::uintptr_t>(input),
    static_cast<std::uintptr_t>(this->GetMTime()),
    static_cast<std::uintptr_t>(input ? input->GetMTime() : 0) };
  auto stampGrid = [&stamp](vtkDataObject* object) {
    if (auto* grid = vtkUnstructuredGrid::SafeDownCast(object))
    {
      stamp.push_back(static_cast<std::uintptr_t>(adapter::MeshModifiedTime(grid)));
    }
  };
  stampGrid(input);
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      stampGrid(it->GetCurrentDataObject());
    }
  }
  if (stamp == this->Internal->SilenceStamp)
  {
    return;
  }
  this->Internal->SilenceStamp = stamp;
  this->Internal->CancelRefinements(); // (preparing may rebuild the meshes they read)
  Frame frame(nullptr, nullptr, false);
  if (!this->CollectBlocks(frame))
  {
    return; // (it said why)
  }
  for (const auto& block : frame.Blocks)
  {
    this->PrepareBlock(frame, block.first, block.second);
  }
  adapter::ReportMessages(this, frame.Messages);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  auto& views = this->Internal->Views;
  for (auto it = views.begin(); it != views.end();)
  {
    // (A null window: VTK asks every prop to let go of everything.)
    if (!window || (*it)->Window == window)
    {
      if ((*it)->Window)
      {
        (*it)->Release((*it)->Window);
      }
      it = views.erase(it);
    }
    else
    {
      ++it;
    }
  }
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::Render(vtkRenderer* renderer, vtkActor* actor)
{
  if (renderer && renderer->GetSelector())
  {
    // (vtkActor renders translucent actors in the selector's passes too, in its opaque pass.)
    this->DrawSelection(renderer, actor);
    return;
  }
  if (!this->IsTranslucent(actor))
  {
    this->Draw(renderer, actor, false);
    return;
  }
  vtkMultiProcessController* controller = this->Internal->Controller;
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    return; // drawn by DrawTranslucentAcrossProcesses
  }
  // Translucent: drawn once, after the renderer's passes (depth peeling and order-independent
  // translucency would otherwise call this in each of their passes with their own buffers).
  auto& draws = this->Internal->DeferredDraws;
  draws.erase(std::remove_if(draws.begin(), draws.end(),
                [](const Internals::Deferred& deferred) { return !deferred.Renderer; }),
    draws.end());
  auto entry = std::find_if(draws.begin(), draws.end(),
    [renderer](const Internals::Deferred& deferred) { return deferred.Renderer == renderer; });
  if (entry == draws.end())
  {
    Internals::Deferred deferred;
    deferred.Renderer = renderer;
    deferred.ObserverTag = renderer->AddObserver(
      vtkCommand::EndEvent, this, &vtkDirectSurfaceMapper::DrawDeferred, 1.0);
    draws.push_back(deferred);
    entry = draws.end() - 1;
  }
  const bool pending = std::any_of(entry->Actors.begin(), entry->Actors.end(),
    [actor](const vtkWeakPointer<vtkActor>& a) { return a == actor; });
  if (!pending)
  {
    entry->Actors.emplace_back(actor);
  }
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::DrawSelection(vtkRenderer* renderer, vtkActor* actor)
{
  vtkHardwareSelector* selector = renderer->GetSelector();
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(renderer->GetRenderWindow());
  if (!window || !actor)
  {
    return;
  }
  if (!this->Static)
  {
    this->Update();
  }
  Frame frame(window, actor, false);
  frame.Selecting = true;
  if (!this->CollectBlocks(frame) || !frame.SetUpView(renderer, 1.0))
  {
    return;
  }
  Internals& in = *this->Internal;
  Internals::ViewResources& gl = in.ResourcesOf(window, renderer, actor);
  auto& image = gl.Selection;

  // The passes of one selection share one cast: of the view, the data and the settings that
  // decide what each pixel shows (not its colour).
  this->ComputeSignature(frame, false);
  std::vector<double> signature = std::move(frame.Signature);
  signature.insert(
    signature.end(), { static_cast<double>(frame.CastWidth), static_cast<double>(frame.CastHeight) });
  vtkIdType maximumPointId = 0, maximumCellId = 0;
  for (const auto& block : frame.Blocks)
  {
    maximumPointId = std::max(maximumPointId, block.second->GetNumberOfPoints() - 1);
    maximumCellId = std::max(maximumCellId, block.second->GetNumberOfCells() - 1);
  }
  if (signature == image.FailedSignature)
  {
    return; // (said at this selection's first pass; the other passes say nothing more)
  }
  if (signature != image.Signature)
  {
    image.Signature.clear();
    image.FailedSignature = signature;
    if (!this->ConvertSettings(frame))
    {
      return;
    }
    in.CancelRefinements(); // (the cast may rebuild the prepared meshes they read)
    if (!this->CastBlocks(frame))
    {
      return;
    }
    image.FailedSignature.clear();
    in.ComputeWindowDepth(frame);
    ImageCast& cast = in.Cast;
    image.Width = frame.CastWidth;
    image.Height = frame.CastHeight;
    image.Rays = frame.Rays;
    image.CellIds = cast.CellIds;
    image.Depth = cast.Depth;
    image.WindowDepth = cast.WindowDepth;
    if (frame.SeveralBlocks())
    {
      image.Blocks = cast.PixelBlocks;
    }
    else
    {
      image.Blocks.assign(frame.Pixels(), frame.Blocks.front().first);
    }
    image.PointIds.clear();
    image.Signature = std::move(signature);
  }

  const int pass = selector->GetCurrentPass();
  const bool composite = vtkCompositeDataSet::SafeDownCast(frame.Input) != nullptr;
  if (pass == vtkHardwareSelector::ACTOR_PASS)
  {
    // The id passes of more than 24 bits are asked for from these.
    selector->UpdateMaximumCellId(maximumCellId);
    selector->UpdateMaximumPointId(maximumPointId);
  }
  if ((pass == vtkHardwareSelector::POINT_ID_LOW24 ||
        pass == vtkHardwareSelector::POINT_ID_HIGH24) &&
    image.PointIds.empty())
  {
    // A pixel's point: the node of its cell nearest to its hit.
    std::map<unsigned int, vtkUnstructuredGrid*> grids(frame.Blocks.begin(), frame.Blocks.end());
    image.PointIds.assign(image.CellIds.size(), -1);
    vtkNew<vtkIdList> nodes;
    for (int j = 0; j < image.Height; ++j)
    {
      for (int i = 0; i < image.Width; ++i)
      {
        const std::size_t p = static_cast<std::size_t>(j) * image.Width + i;
        const auto grid = grids.find(image.Blocks[p]);
        if (image.WindowDepth[p] >= 1.0f || image.CellIds[p] < 0 || grid == grids.end() ||
          image.CellIds[p] >= grid->second->GetNumberOfCells())
        {
          continue;
        }
        const tetdsr::Ray ray = image.Rays.pixelRay(i, j);
        const glm::dvec3 hit = ray.origin + image.Depth[p] * ray.direction;
        grid->second->GetCellPoints(image.CellIds[p], nodes);
        double nearest = std::numeric_limits<double>::infinity();
        for (vtkIdType k = 0; k < nodes->GetNumberOfIds(); ++k)
        {
          double x[3];
          grid->second->GetPoint(nodes->GetId(k), x);
          const double d = glm::distance(glm::dvec3(x[0], x[1], x[2]), hit);
          if (d < nearest)
          {
            nearest = d;
            image.PointIds[p] = nodes->GetId(k);
          }
        }
      }
    }
  }

  // This pass's value of each covered pixel, as vtkHardwareSelector reads it: 24 bits in the
  // red, green and blue bytes, low byte first.
  selector->BeginRenderProp();
  const float* propColor = selector->GetPropColorValue();
  std::uint8_t propBytes[3];
  for (int c = 0; c < 3; ++c)
  {
    propBytes[c] = static_cast<std::uint8_t>(std::lround(255.0 * propColor[c]));
  }
  const std::size_t pixels = image.CellIds.size();
  image.Ids.assign(4 * pixels, 0);
  // The id passes: the cells' or the points' ids, their low or high 24 bits.
  const bool cellPass =
    pass == vtkHardwareSelector::CELL_ID_LOW24 || pass == vtkHardwareSelector::CELL_ID_HIGH24;
  const bool pointPass =
    pass == vtkHardwareSelector::POINT_ID_LOW24 || pass == vtkHardwareSelector::POINT_ID_HIGH24;
  const int shift =
    pass == vtkHardwareSelector::CELL_ID_HIGH24 || pass == vtkHardwareSelector::POINT_ID_HIGH24 ? 24 : 0;
  const std::vector<tetdsr::NodeId>* ids =
    cellPass ? &image.CellIds : (pointPass ? &image.PointIds : nullptr);
  for (std::size_t p = 0; p < pixels; ++p)
  {
    std::uint8_t* rgba = &image.Ids[4 * p];
    rgba[3] = 255;
    long long value = 0;
    if (ids)
    {
      value = ((*ids)[p] >> shift) & 0xffffff;
    }
    else if (pass == vtkHardwareSelector::COMPOSITE_INDEX_PASS)
    {
      // (vtkCompositePolyDataMapper2's flat index of a block; 1 for a dataset, as VTK's
      // polygon mappers write it.)
      value = composite ? image.Blocks[p] : 1;
    }
    else // the actor's and the process's passes: the selector's colour
    {
      std::copy_n(propBytes, 3, rgba);
      continue;
    }
    rgba[0] = static_cast<std::uint8_t>(value & 0xff);
    rgba[1] = static_cast<std::uint8_t>((value >> 8) & 0xff);
    rgba[2] = static_cast<std::uint8_t>((value >> 16) & 0xff);
  }
  Internals::LoadTextures(window, image.IdTexture, image.DepthTexture, image.Width, image.Height,
    image.Ids.data(), image.WindowDepth.data());
  Internals::DrawTextures(
    gl, window, false, frame.Viewport, image.IdTexture, image.DepthTexture, false);
  selector->EndRenderProp();
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::SetController(vtkMultiProcessController* controller)
{
  if (this->Internal->Controller != controller)
  {
    this->Internal->Controller = controller;
    this->Modified();
  }
}

vtkMultiProcessController* vtkDirectSurfaceMapper::GetController()
{
  return this->Internal->Controller;
}

void vtkDirectSurfaceMapper::DrawTranslucentAcrossProcesses(vtkRenderer* renderer,
  vtkActor* actor, const float* compositedDepth, unsigned char* compositedColors,
  const int frameSize[2])
{
  const int* depthSize = frameSize;
  Internals& in = *this->Internal;
  vtkMultiProcessController* controller = in.Controller;
  if (!controller || controller->GetNumberOfProcesses() < 2 || !renderer || !actor)
  {
    return; // (the same on every process)
  }
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  const int processes = controller->GetNumberOfProcesses();
  const bool root = controller->GetLocalProcessId() == 0;
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(renderer->GetRenderWindow());
  const bool takesPart = window && !renderer->GetSelector() && actor->GetVisibility() &&
    this->IsTranslucent(actor);

  // Process 0 chooses the resolution (interaction lowers it) and every process casts at it.
  Frame frame(window, actor, true);
  frame.CollectLayers = true;
  double distance = root && takesPart ? this->ChooseSampleDistance(frame) : 1.0;
  controller->Broadcast(&distance, 1, 0);
  const bool hasView = takesPart && frame.SetUpView(renderer, distance);

  // This process's crossings, packed as (pixel, t, red, green, blue, opacity).
  std::vector<double> packed;
  double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
  double hi[3] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  if (hasView)
  {
    if (!this->Static)
    {
      this->Update();
    }
    auto* grid = vtkUnstructuredGrid::SafeDownCast(this->GetInputDataObject(0, 0));
    const bool empty = grid && grid->GetNumberOfCells() == 0; // a process without cells
    frame.CollectLights(renderer);
    if (!empty && this->CollectBlocks(frame) && this->ConvertSettings(frame))
    {
      in.CancelRefinements();
      ImageCast& cast = in.Cast;
      if (this->PrepareCast(frame, cast))
      {
        for (const auto& caster : cast.Casters)
        {
          adapter::Cast(*caster, false, this->NumberOfThreads, []() { return false; }, [](double) {});
        }
        for (const auto& block : cast.Layers)
        {
          for (const auto& tile : *block)
          {
            for (const tetdsr::PixelLayer& layer : tile)
            {
              packed.insert(packed.end(), { static_cast<double>(layer.pixel), layer.t,
                layer.color.x, layer.color.y, layer.color.z, layer.opacity });
            }
          }
        }
      }
      const double* bounds = this->GetBounds();
      if (bounds && vtkMath::AreBoundsInitialized(bounds))
      {
        for (int k = 0; k < 3; ++k)
        {
          lo[k] = bounds[2 * k];
          hi[k] = bounds[2 * k + 1];
        }
      }
    }
  }
  // Crossings nearer than the layer gap of the whole scene are one surface.
  double sceneLo[3], sceneHi[3];
  controller->AllReduce(lo, sceneLo, 3, vtkCommunicator::MIN_OP);
  controller->AllReduce(hi, sceneHi, 3, vtkCommunicator::MAX_OP);
  double diagonal = 0.0;
  if (sceneLo[0] <= sceneHi[0])
  {
    diagonal = std::sqrt(vtkMath::Distance2BetweenPoints(sceneLo, sceneHi));
  }

  // Every process's crossings to process 0, with the size of the cast they index.
  const vtkIdType header[3] = { static_cast<vtkIdType>(packed.size()),
    hasView ? frame.CastWidth : 0, hasView ? frame.CastHeight : 0 };
  std::vector<vtkIdType> headers(3 * static_cast<std::size_t>(processes));
  controller->Gather(header, headers.data(), 3, 0);
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(processes)), offsets(lengths.size());
  vtkIdType total = 0;
  for (std::size_t p = 0; p < lengths.size(); ++p)
  {
    lengths[p] = headers[3 * p];
    offsets[p] = total;
    total += lengths[p];
  }
  std::vector<double> all(root ? static_cast<std::size_t>(total) : 0);
  controller->GatherV(packed.data(), all.data(), header[0], lengths.data(), offsets.data(), 0);
  if (!root || !hasView)
  {
    return;
  }

  // Process 0: the crossings in front of the composited opaque depth, composited per pixel.
  std::vector<tetdsr::PixelLayer> layers;
  layers.reserve(static_cast<std::size_t>(total / 6));
  int mismatched = 0;
  for (std::size_t p = 0; p < lengths.size(); ++p)
  {
    if (headers[3 * p + 1] != frame.CastWidth || headers[3 * p + 2] != frame.CastHeight)
    {
      mismatched += lengths[p] > 0;
      continue; // a process whose view differs: its pixels are not these
    }
    for (vtkIdType k = offsets[p]; k + 6 <= offsets[p] + lengths[p]; k += 6)
    {
      const double* v = &all[static_cast<std::size_t>(k)];
      layers.push_back({ static_cast<std::uint32_t>(v[0]), v[1], glm::dvec3(v[2], v[3], v[4]), v[5] });
    }
  }
  if (mismatched > 0)
  {
    vtkWarningMacro(<< mismatched << " of " << processes
                    << " processes cast a view of another size: their translucent surfaces are "
                       "not drawn.");
  }
  const int* viewport = frame.Viewport;
  const std::size_t viewportPixels = static_cast<std::size_t>(viewport[2]) * viewport[3];
  if (compositedDepth && depthSize && depthSize[0] > 0 && depthSize[1] > 0)
  {
    in.OpaqueDepth.resize(viewportPixels);
    for (int j = 0; j < viewport[3]; ++j)
    {
      const int dj = std::min(depthSize[1] - 1, static_cast<int>((j + 0.5) * depthSize[1] / viewport[3]));
      for (int i = 0; i < viewport[2]; ++i)
      {
        const int di = std::min(depthSize[0] - 1, static_cast<int>((i + 0.5) * depthSize[0] / viewport[2]));
        in.OpaqueDepth[static_cast<std::size_t>(j) * viewport[2] + i] =
          compositedDepth[static_cast<std::size_t>(dj) * depthSize[0] + di];
      }
    }
  }
  else
  {
    in.ReadOpaqueDepth(frame);
  }
  ImageCast& cast = in.Cast;
  cast.Resize(frame.Pixels(), false);
  cast.ComputeRayLimits(frame, in.OpaqueDepth);
  tetdsr::compositeLayers(layers, frame.Pixels(), tetdsr::Renderer::kLayerGap * diagonal,
    cast.RayLimits.data(), cast.Colors.data());
  std::fill(cast.Depth.begin(), cast.Depth.end(), std::numeric_limits<double>::infinity());
  for (const tetdsr::PixelLayer& layer : layers) // sorted: each pixel's nearest first
  {
    if (layer.pixel < frame.Pixels() && layer.t <= cast.RayLimits[layer.pixel] &&
      !std::isfinite(cast.Depth[layer.pixel]))
    {
      cast.Depth[layer.pixel] = layer.t;
    }
  }
  if (compositedColors && depthSize && depthSize[0] > 0 && depthSize[1] > 0)
  {
    // Over the compositor's premultiplied image, each of its pixels taking the cast pixel it
    // lies in: colour = alpha * ours + (1 - alpha) * its, alpha = alpha + (1 - alpha) * its.
    const int castWidth = frame.CastWidth, castHeight = frame.CastHeight;
    for (int j = 0; j < depthSize[1]; ++j)
    {
      const int cj = std::min(castHeight - 1, static_cast<int>((j + 0.5) * castHeight / depthSize[1]));
      for (int i = 0; i < depthSize[0]; ++i)
      {
        const int ci = std::min(castWidth - 1, static_cast<int>((i + 0.5) * castWidth / depthSize[0]));
        const std::uint8_t* ours = &cast.Colors[4 * (static_cast<std::size_t>(cj) * castWidth + ci)];
        if (ours[3] == 0)
        {
          continue;
        }
        unsigned char* theirs = compositedColors + 4 * (static_cast<std::size_t>(j) * depthSize[0] + i);
        const double alpha = ours[3] / 255.0;
        for (int c = 0; c < 3; ++c)
        {
          theirs[c] = static_cast<unsigned char>(
            std::min(255.0, alpha * ours[c] + (1.0 - alpha) * theirs[c]) + 0.5);
        }
        theirs[3] = static_cast<unsigned char>(std::min(255.0, ours[3] + (1.0 - alpha) * theirs[3]) + 0.5);
      }
    }
  }
  else
  {
    in.ComputeWindowDepth(frame);
    Internals::ViewResources& gl = in.ResourcesOf(window, renderer, actor);
    gl.Refining.reset();
    Internals::Upload(gl, window, cast, frame.CastWidth, frame.CastHeight, distance);
    Internals::Draw(gl, window, true, frame.Viewport);
    gl.Signature.clear(); // not a cast of this process's own: never re-used as one
  }
  timer->StopTimer();
  this->CastFinished(frame, distance, timer->GetElapsedTime());
}

void vtkDirectSurfaceMapper::CastFinished(const Frame& frame, double sampleDistance, double seconds)
{
  this->Internal->LastCastSeconds = seconds;
  this->Internal->SampleDistance = sampleDistance;
  this->TimeToDraw = seconds;
  this->LastImageSampleDistance = sampleDistance;
  this->LastCastSize[0] = frame.CastWidth;
  this->LastCastSize[1] = frame.CastHeight;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::Draw(vtkRenderer* renderer, vtkActor* actor, bool translucent)
{
  vtkNew<vtkTimerLog> timer; // the cast's time sizes the next interactive frame's sample distance
  timer->StartTimer();
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(renderer->GetRenderWindow());
  if (!window || renderer->GetSelector())
  {
    return; // no OpenGL window, or a hardware-selection pass: nothing to draw
  }
  if (!this->Static)
  {
    this->Update();
  }
  Frame frame(window, actor, translucent);
  if (!this->CollectBlocks(frame))
  {
    return;
  }
  const double distance = this->ChooseSampleDistance(frame);
  if (!frame.SetUpView(renderer, distance))
  {
    return; // an empty viewport
  }
  frame.CollectLights(renderer);

  Internals& in = *this->Internal;
  Internals::ViewResources& gl = in.ResourcesOf(window, renderer, actor);
  vtkRenderWindowInteractor* interactor = window->GetInteractor();
  const bool eventLoop =
    this->ProgressiveRefinement && interactor && this->EventLoopRuns(interactor);
  this->ComputeSignature(frame, true);
  this->LastRenderRefining = false;
  // The image this view holds: of the same scene (camera, data, settings), and of the size.
  const bool sameSize = gl.ImageSize[0] == frame.CastWidth && gl.ImageSize[1] == frame.CastHeight;
  auto drawImage = [&]() {
    Internals::Draw(gl, window, translucent, frame.Viewport);
    timer->StopTimer();
    this->TimeToDraw = timer->GetElapsedTime();
  };

  // This view's background cast: shown once finished, waited for while it runs (the upscaled
  // image drawn again), and dropped when the frame is anything else.
  if (gl.Refining)
  {
    Refinement& refinement = *gl.Refining;
    if (SameScene(refinement.Signature, frame.Signature) && refinement.Width == frame.CastWidth &&
      refinement.Height == frame.CastHeight)
    {
      this->LastRenderReusedImage = !refinement.Finished;
      this->LastRenderRefining = !refinement.Finished;
      if (refinement.Finished)
      {
        refinement.Worker.join(); // (it has returned)
        Internals::Upload(
          gl, window, refinement.Cast, refinement.Width, refinement.Height, distance);
        gl.Signature = refinement.Signature;
        in.LastCastSeconds = refinement.Seconds;
        in.SampleDistance = distance;
        this->LastImageSampleDistance = distance;
        this->LastCastSize[0] = frame.CastWidth;
        this->LastCastSize[1] = frame.CastHeight;
        gl.Refining.reset();
      }
      drawImage();
      return;
    }
    gl.Refining.reset();
  }

  // Re-use the image this view holds when nothing it depends on changed.
  this->LastRenderReusedImage = gl.TexturesValid && sameSize && frame.Signature == gl.Signature;
  if (this->LastRenderReusedImage)
  {
    drawImage();
    return;
  }
  if (!this->ConvertSettings(frame))
  {
    return;
  }
  // Any cast below may rebuild the prepared meshes that background casts read.
  in.CancelRefinements();

  // A still frame of the scene the last interactive frame showed: that image, upscaled, until the
  // full resolution cast in the background is done, when the event loop can ask for the render
  // that shows it.
  if (eventLoop && gl.TexturesValid && gl.ImageSampleDistance > 1.0 && distance == 1.0 &&
    SameScene(gl.Signature, frame.Signature))
  {
    gl.Refining = this->StartRefinement(frame, interactor);
    if (gl.Refining)
    {
      this->LastRenderReusedImage = true;
      this->LastRenderRefining = true;
      drawImage();
    }
    return;
  }

  if (!this->CastBlocks(frame))
  {
    return;
  }
  in.ComputeWindowDepth(frame);
  Internals::Upload(gl, window, in.Cast, frame.CastWidth, frame.CastHeight, distance);
  Internals::Draw(gl, window, translucent, frame.Viewport);
  gl.Signature = std::move(frame.Signature);
  timer->StopTimer();
  this->CastFinished(frame, distance, timer->GetElapsedTime());
}

bool vtkDirectSurfaceMapper::CollectBlocks(Frame& frame)
{
  frame.Input = this->GetInputDataObject(0, 0);
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(frame.Input))
  {
    frame.Blocks.emplace_back(0, grid);
  }
  int otherBlocks = 0; // of a composite input, not drawn
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(frame.Input))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      if (auto* block = vtkUnstructuredGrid::SafeDownCast(it->GetCurrentDataObject()))
      {
        frame.Blocks.emplace_back(it->GetCurrentFlatIndex(), block);
      }
      else
      {
        ++otherBlocks;
      }
    }
    if (frame.Blocks.empty() && otherBlocks == 0)
    {
      adapter::Messages messages; // a composite dataset without blocks
      tetdsr::checkMeshNotEmpty(0, 0, messages);
      adapter::ReportMessages(this, messages);
      return false;
    }
  }
  // Scenes of blocks the input no longer has are dropped, with the arrays they keep alive
  // (after the background casts that read them).
  auto& meshes = this->Internal->Meshes;
  for (auto it = meshes.begin(); it != meshes.end();)
  {
    const bool kept = std::any_of(frame.Blocks.begin(), frame.Blocks.end(),
      [&](const auto& block) { return block.first == it->first; });
    if (!kept)
    {
      this->Internal->CancelRefinements();
    }
    it = kept ? std::next(it) : meshes.erase(it);
  }
  if (frame.Blocks.empty())
  {
    vtkErrorMacro("The input is neither a vtkUnstructuredGrid nor a composite dataset of them.");
    return false;
  }
  if (otherBlocks > 0)
  {
    vtkWarningMacro(<< otherBlocks << " of " << otherBlocks + frame.Blocks.size()
                    << " blocks of the composite input are not vtkUnstructuredGrid: not drawn.");
  }
  return true;
}

double vtkDirectSurfaceMapper::ChooseSampleDistance(const Frame& frame)
{
  Internals& in = *this->Internal;
  const double now = vtkTimerLog::GetUniversalTime();
  vtkRenderWindowInteractor* interactor = frame.Window->GetInteractor();
  const double stillRate = interactor ? interactor->GetStillUpdateRate() : 0.0001;
  // Interacting: a desired rate above the still one and of at least one frame a second (VTK's
  // interactor asks 15 while the camera moves and 0.0001 when it stops; ParaView's view 5 and
  // 0.002, with its interactor's still rate left at 0.0001).
  const double desired = frame.Window->GetDesiredUpdateRate();
  const bool interacting = desired > stillRate && desired >= 1.0;
  double distance = 1.0;
  if (interacting && !this->AutoAdjustSampleDistances)
  {
    distance = this->InteractiveImageSampleDistance;
  }
  else if (interacting)
  {
    // The frame must fit the actor's allocated time; what the rest of the last frame took
    // (other props, clearing, the window's swap: the time between two renders minus the cast)
    // is not the cast's to spend. A quarter of the allocation is always left to it.
    const double allocated = frame.Actor->GetAllocatedRenderTime();
    const double period = now - in.LastRenderStart;
    const double others =
      in.LastWasInteractive && period < 1.0 ? std::max(0.0, period - in.LastCastSeconds) : 0.0;
    const double budget = std::max(allocated - others, 0.25 * allocated);
    distance = in.SampleDistance;
    if (budget > 0.0 && in.LastCastSeconds > 0.0)
    {
      // The cast's time goes as its number of rays, 1 / distance^2.
      distance *= std::sqrt(in.LastCastSeconds / budget);
    }
    distance = vtkMath::ClampValue(distance, 1.0, this->MaximumImageSampleDistance);
  }
  in.LastRenderStart = now;
  in.LastWasInteractive = interacting;
  return distance;
}

void vtkDirectSurfaceMapper::ComputeSignature(Frame& frame, bool shading)
{
  // What decides which cell each pixel shows: the view, the mapper's, the property's, the
  // input's and the meshes' modification times.
  std::vector<double>& signature = frame.Signature;
  const glm::dmat4& modelToNdc = frame.ModelToNdc;
  signature.assign(&modelToNdc[0][0], &modelToNdc[0][0] + 16);
  signature.insert(signature.end(),
    { static_cast<double>(this->GetMTime()),
      static_cast<double>(frame.Actor->GetProperty()->GetMTime()),
      static_cast<double>(frame.Input->GetMTime()) });
  for (const auto& block : frame.Blocks)
  {
    signature.push_back(static_cast<double>(adapter::MeshModifiedTime(block.second)));
  }
  if (!shading)
  {
    return;
  }
  // And what decides its colour: the lights, and the opaque depth translucent rays stop at.
  signature.push_back(frame.Settings.lighting.headlightOnly ? 1.0 : 0.0);
  signature.insert(signature.end(), frame.LightState.begin(), frame.LightState.end());
  if (frame.Translucent)
  {
    signature.push_back(this->Internal->ReadOpaqueDepth(frame));
  }
}

bool vtkDirectSurfaceMapper::ConvertSettings(Frame& frame)
{
  std::vector<tetdsr::ClipPlane> clipPlanes;
  if (!adapter::ConvertIsoValues(this->ContourValues, frame.Values, frame.Messages) ||
    !adapter::ConvertClipPlanes(this->ClippingPlanes, clipPlanes, frame.Messages))
  {
    adapter::ReportMessages(this, frame.Messages);
    return false;
  }
  if (!frame.Identity)
  {
    // World planes n . (x - o) >= 0 become n' . (x_m - o') >= 0 with o' = M^-1 o, n' = M^T n.
    for (tetdsr::ClipPlane& plane : clipPlanes)
    {
      plane.origin = glm::dvec3(frame.WorldToModel * glm::dvec4(plane.origin, 1.0));
      plane.normal = glm::transpose(glm::dmat3(frame.ModelToWorld)) * plane.normal;
    }
  }
  tetdsr::RenderSettings& settings = frame.Settings;
  vtkProperty* property = frame.Actor->GetProperty();
  double diffuseColor[3], specularColor[3];
  property->GetDiffuseColor(diffuseColor);
  property->GetSpecularColor(specularColor);
  settings.material.color = glm::dvec3(diffuseColor[0], diffuseColor[1], diffuseColor[2]);
  settings.material.specularColor =
    glm::dvec3(specularColor[0], specularColor[1], specularColor[2]);
  settings.material.ambient = property->GetAmbient();
  settings.material.diffuse = property->GetDiffuse();
  settings.material.specular = property->GetSpecular();
  settings.material.specularPower = property->GetSpecularPower();
  settings.clipPlanes = std::move(clipPlanes);
  settings.isoStyles =
    this->Internal->Styles.Styles(frame.Values.size(), diffuseColor, property->GetOpacity());
  return true;
}

bool vtkDirectSurfaceMapper::PrepareCast(Frame& frame, ImageCast& cast)
{
  Internals& in = *this->Internal;
  cast.Resize(frame.Pixels(), frame.SeveralBlocks());
  cast.PixelBlocks.assign(frame.Selecting && frame.SeveralBlocks() ? frame.Pixels() : 0, 0);
  if (frame.Translucent && !frame.CollectLayers)
  {
    cast.ComputeRayLimits(frame, in.OpaqueDepth);
  }
  cast.Casters.clear();
  cast.CasterBlocks.clear();
  this->NumberOfRenderedCells = 0;
  for (const auto& block : frame.Blocks)
  {
    if (!this->PrepareBlock(frame, block.first, block.second))
    {
      continue; // skipped: the messages say why
    }
    adapter::PreparedMesh& prepared = in.MeshOf(block.first);
    this->NumberOfRenderedCells += prepared.GetSummary().validCells;
    ChooseColors(this, block.second, prepared, frame.Settings, frame.Messages);
    cast.Casters.emplace_back(
      new tetdsr::Renderer(prepared.GetSurface(frame.Values, this->NumberOfThreads), frame.Rays,
        frame.Settings, cast.BlockImage(frame)));
    cast.CasterBlocks.push_back(block.first);
  }
  adapter::ReportMessages(this, frame.Messages);
  return this->NumberOfRenderedCells > 0;
}

bool vtkDirectSurfaceMapper::CastBlocks(Frame& frame)
{
  ImageCast& cast = this->Internal->Cast;
  if (!this->PrepareCast(frame, cast))
  {
    return false;
  }
  vtkOpenGLRenderWindow* window = frame.Window;
  for (std::size_t k = 0; k < cast.Casters.size(); ++k)
  {
    tetdsr::Renderer* caster = cast.Casters[k].get();
    const tetdsr::NodeId done = adapter::Cast(
      *caster, false, this->NumberOfThreads, [window]() { return window->CheckAbortStatus() != 0; },
      [](double) {});
    if (done < caster->numberOfTiles())
    {
      return false;
    }
    if (frame.SeveralBlocks())
    {
      cast.KeepNearest(frame.Pixels(), cast.CasterBlocks[k]);
    }
  }
  return true;
}

bool vtkDirectSurfaceMapper::PrepareBlock(Frame& frame, unsigned int index, vtkUnstructuredGrid* grid)
{
  if (!tetdsr::checkMeshNotEmpty(grid->GetNumberOfPoints(), grid->GetNumberOfCells(), frame.Messages))
  {
    return false; // (before the field: an empty grid has none)
  }
  int association = -1;
  vtkDataArray* field = this->GetInputArrayToProcess(0, grid, association);
  int component = 0;
  if (!field)
  {
    frame.Messages.errors.push_back(
      "No scalar field: choose a point array with "
      "SetInputArrayToProcess(0, 0, 0, FIELD_ASSOCIATION_POINTS, name).");
  }
  adapter::PreparedMesh& prepared = this->Internal->MeshOf(index);
  return field &&
    adapter::CheckPointArray(field, association, -1, false, nullptr, component, frame.Messages) &&
    prepared.Prepare(
      grid, field, component, tetdsr::TransverseTest(), this->NumberOfThreads, frame.Messages);
}

std::unique_ptr<vtkDirectSurfaceMapper::Refinement> vtkDirectSurfaceMapper::StartRefinement(
  Frame& frame, vtkRenderWindowInteractor* interactor)
{
  std::unique_ptr<Refinement> refinement(new Refinement);
  if (!this->PrepareCast(frame, refinement->Cast))
  {
    return nullptr;
  }
  refinement->Signature = frame.Signature;
  refinement->Width = frame.CastWidth;
  refinement->Height = frame.CastHeight;
  refinement->Rays = frame.Rays;
  refinement->ModelToNdc = frame.ModelToNdc;
  refinement->SeveralBlocks = frame.SeveralBlocks();
  // The worker cannot render (the window's context belongs to this thread): the event loop
  // polls it.
  refinement->Interactor = interactor;
  refinement->TimerId = interactor->CreateOneShotTimer(kRefinementPollMilliseconds);
  const int threads = this->NumberOfThreads > 0
    ? this->NumberOfThreads
    : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  refinement->Worker = std::thread(&Refinement::Run, refinement.get(), threads);
  return refinement;
}

bool vtkDirectSurfaceMapper::EventLoopRuns(vtkRenderWindowInteractor* interactor)
{
  auto& loops = this->Internal->EventLoops;
  loops.erase(std::remove_if(loops.begin(), loops.end(),
                [](const Internals::EventLoop& loop) { return !loop.Interactor; }),
    loops.end());
  for (const auto& loop : loops)
  {
    if (loop.Interactor == interactor)
    {
      return loop.Runs;
    }
  }
  Internals::EventLoop loop;
  loop.Interactor = interactor;
  loop.ObserverTag =
    interactor->AddObserver(vtkCommand::TimerEvent, this, &vtkDirectSurfaceMapper::TimerFired);
  loop.ProbeTimerId = interactor->CreateOneShotTimer(1); // (forgotten by the interactor once fired)
  loops.push_back(loop);
  return false;
}

void vtkDirectSurfaceMapper::TimerFired(vtkObject* caller, unsigned long, void* callData)
{
  const int timerId = callData ? *static_cast<int*>(callData) : 0;
  if (timerId == 0)
  {
    return;
  }
  for (auto& loop : this->Internal->EventLoops)
  {
    if (loop.ProbeTimerId == timerId)
    {
      loop.Runs = true;
      loop.ProbeTimerId = 0;
      return;
    }
  }
  for (const auto& view : this->Internal->Views)
  {
    Refinement* refinement = view->Refining.get();
    if (refinement && refinement->TimerId == timerId)
    {
      auto* interactor = static_cast<vtkRenderWindowInteractor*>(caller);
      refinement->TimerId = 0; // (fired: the interactor forgets it)
      if (!refinement->Finished)
      {
        refinement->TimerId = interactor->CreateOneShotTimer(kRefinementPollMilliseconds);
        return;
      }
      // Asked once: the render shows it; if it does not draw this view, the view's next render
      // shows it, or a cast drops it.
      interactor->Render();
      return;
    }
  }
}

//------------------------------------------------------------------------------
bool vtkDirectSurfaceMapper::Pick(
  double x, double y, vtkRenderer* renderer, vtkActor* actor, vtkDirectSurfacePick* result)
{
  if (!result)
  {
    return false;
  }
  result->Initialize();
  if (!renderer || !actor || !std::isfinite(x) || !std::isfinite(y))
  {
    return false;
  }
  Frame frame(vtkOpenGLRenderWindow::SafeDownCast(renderer->GetRenderWindow()), actor, false);
  if (!frame.SetUpView(renderer, 1.0))
  {
    return false;
  }
  // Display coordinates as VTK's pickers take them: the still frame's pixel (i, j) of the
  // viewport is cast through (i + 0.5, j + 0.5).
  const tetdsr::Ray ray = frame.Rays.displayRay(x - frame.Viewport[0], y - frame.Viewport[1]);
  const double origin[3] = { ray.origin.x, ray.origin.y, ray.origin.z };
  const double direction[3] = { ray.direction.x, ray.direction.y, ray.direction.z };
  return this->PickRay(frame, origin, direction, std::numeric_limits<double>::infinity(), 1.0, result);
}

bool vtkDirectSurfaceMapper::PickSegment(
  const double p1[3], const double p2[3], vtkActor* actor, vtkDirectSurfacePick* result)
{
  if (!result)
  {
    return false;
  }
  result->Initialize();
  const glm::dvec3 a(p1[0], p1[1], p1[2]), b(p2[0], p2[1], p2[2]);
  const double length = glm::length(b - a);
  if (!actor || !tetdsr::isFinite(a) || !tetdsr::isFinite(b) || !(length > 0.0) ||
    !std::isfinite(length))
  {
    return false;
  }
  Frame frame(nullptr, actor, false);
  frame.Identity = actor->GetIsIdentity() != 0;
  frame.ModelToWorld = frame.Identity ? glm::dmat4(1.0) : ToGlm(actor->GetMatrix());
  frame.WorldToModel = glm::inverse(frame.ModelToWorld);
  const glm::dvec3 unit = (b - a) / length;
  const double direction[3] = { unit.x, unit.y, unit.z };
  return this->PickRay(frame, p1, direction, length, 1.0 / length, result);
}

bool vtkDirectSurfaceMapper::PickRay(Frame& frame, const double origin[3],
  const double direction[3], double tLimit, double scale, vtkDirectSurfacePick* result)
{
  if (!this->Static)
  {
    this->Update();
  }
  if (!this->CollectBlocks(frame) || !this->ConvertSettings(frame))
  {
    return false;
  }
  Internals& in = *this->Internal;
  in.CancelRefinements(); // preparing a block may rebuild what a background cast reads
  const tetdsr::Ray ray{ glm::dvec3(origin[0], origin[1], origin[2]),
    glm::dvec3(direction[0], direction[1], direction[2]) };
  tetdsr::Pick best;
  bool found = false;
  unsigned int bestBlock = 0;
  vtkUnstructuredGrid* bestGrid = nullptr;
  for (const auto& block : frame.Blocks)
  {
    if (!this->PrepareBlock(frame, block.first, block.second))
    {
      continue; // skipped: the messages say why
    }
    tetdsr::Pick pick;
    if (adapter::PickPrepared(in.MeshOf(block.first), frame.Values, frame.Settings, ray, tLimit,
          this->NumberOfThreads, pick) &&
      (!found || pick.t < best.t))
    {
      best = pick;
      found = true;
      bestBlock = block.first;
      bestGrid = block.second;
    }
  }
  if (found)
  {
    adapter::FillPick(best, bestGrid, in.MeshOf(bestBlock),
      vtkCompositeDataSet::SafeDownCast(frame.Input) ? static_cast<vtkIdType>(bestBlock) : -1,
      frame.ModelToWorld, scale, result, frame.Messages);
  }
  adapter::ReportMessages(this, frame.Messages);
  return found;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  this->ContourValues->PrintSelf(os, indent.GetNextIndent());
  os << indent << "Iso-value " << this->Internal->Styles.Describe() << "\n";
  os << indent << "AutoAdjustSampleDistances: " << this->AutoAdjustSampleDistances << "\n";
  os << indent << "MaximumImageSampleDistance: " << this->MaximumImageSampleDistance << "\n";
  os << indent << "InteractiveImageSampleDistance: " << this->InteractiveImageSampleDistance << "\n";
  os << indent << "ProgressiveRefinement: " << this->ProgressiveRefinement << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "LastImageSampleDistance: " << this->LastImageSampleDistance << "\n";
  os << indent << "LastRenderReusedImage: " << this->LastRenderReusedImage << "\n";
  os << indent << "LastRenderRefining: " << this->LastRenderRefining << "\n";
  os << indent << "LastCastSize: " << this->LastCastSize[0] << " x " << this->LastCastSize[1] << "\n";
  os << indent << "NumberOfRenderedCells: " << this->NumberOfRenderedCells << "\n";
}
