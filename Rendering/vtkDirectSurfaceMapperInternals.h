// The private parts of vtkDirectSurfaceMapper that its implementation files share (not
// installed): what one frame works with (Frame), one cast's images (ImageCast), a background
// cast (Refinement), and what is kept between renders (Internals: the prepared meshes, each
// view's OpenGL resources and selection image, the interactors' event loops). The files, by job:
//   vtkDirectSurfaceMapper.cxx             the public API and settings, the Render entry
//   vtkDirectSurfaceMapperCast.cxx         the view, level of detail, the cast and the frame path
//   vtkDirectSurfaceMapperRefinement.cxx   the full-resolution cast in the background, its timers
//   vtkDirectSurfaceMapperDrawing.cxx      OpenGL: per-view textures and quad, the quad's shader
//   vtkDirectSurfaceMapperSelection.cxx    hardware selection's passes
//   vtkDirectSurfaceMapperDistributed.cxx  translucent surfaces composited across processes
//   vtkDirectSurfaceMapperPicking.cxx      the exact hit under a pixel or along a segment
#ifndef vtkDirectSurfaceMapperInternals_h
#define vtkDirectSurfaceMapperInternals_h

#include "vtkDirectSurfaceMapper.h"

#include "vtkMatrix4x4.h"
#include "vtkMultiProcessController.h"
#include "vtkOpenGLFXAAFilter.h"
#include "vtkOpenGLQuadHelper.h"
#include "vtkSmartPointer.h"
#include "vtkTextureObject.h"
#include "vtkWeakPointer.h"

#include "vtkDirectSurfaceAdapter.h"
#include "tetdsr/render/Multisampling.h"
#include "tetdsr/render/Upsampling.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <thread>
#include <utility>
#include <vector>

class vtkActor;
class vtkOpenGLRenderWindow;
class vtkRenderer;
class vtkRenderWindowInteractor;
class vtkUnstructuredGrid;

namespace
{
namespace adapter = tetdsr::vtkadapter;

/// Row-major vtkMatrix4x4 to glm's column-major matrix.
inline glm::dmat4 ToGlm(const vtkMatrix4x4* matrix)
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

/// Whether two image signatures describe one scene up to rounding: a camera set again from its
/// own parameters (as ParaView does before a still render) moves the matrices and lights by an
/// ulp or two; 1e-12 of the numbers' size (at least 1) is far below a visible change, and keeps
/// modification times below 1e12 apart.
inline bool SameScene(const std::vector<double>& a, const std::vector<double>& b)
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
}

/// What screen-space ambient occlusion reads besides colour and depth: each pixel's view-space
/// position and normal, in the extra colour attachments of vtkSSAOPass's G-buffer (written by
/// vtkOpenGLPolyDataMapper under that pass). The quad makes them from the window depth and the
/// cast's normals with these: the inverse of the view's projection, and the model-to-view
/// matrix of normals.
struct vtkDirectSurfaceViewSpace
{
  glm::dmat4 NdcToView{ 1.0 };
  glm::dmat3 NormalToView{ 1.0 };
};

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
  /// The stereo eye the frame is cast for: 1 the right eye of a stereo render, else 0 (each eye
  /// keeps its own image: ViewResources).
  int Eye = 0;
  bool Identity = true; ///< the actor's matrix is the identity
  glm::dmat4 ModelToWorld{ 1.0 }, WorldToModel{ 1.0 }, ModelToNdc{ 1.0 }, NdcToModel{ 1.0 };
  tetdsr::RayGenerator Rays{ glm::dmat4(1.0), 1, 1 }; ///< set with the view

  /// The renderer draws its opaque pass into vtkSSAOPass's G-buffer (the actor carries the
  /// pass): the quad writes position and normal too (ViewSpace).
  bool AmbientOcclusion = false;
  vtkDirectSurfaceViewSpace ViewSpace;
  /// An opaque frame into a multisampled framebuffer: its sample positions (within a pixel;
  /// empty for one sample a pixel, or more than a mask holds). Silhouettes of a full-resolution
  /// cast are then covered sample by sample (ImageCast::SampleMasks).
  std::vector<glm::dvec2> SamplePositions;

  std::vector<double> LightState; ///< the switched-on lights' parameters, for the signature
  std::vector<double> Signature;  ///< everything the image depends on
  /// The leading part of Signature that decides which cell each pixel shows (not its colour).
  std::size_t CellSignatureSize = 0;
  std::vector<double> Values;     ///< the iso-values
  tetdsr::RenderSettings Settings;
  adapter::Messages Messages;

  std::size_t Pixels() const
  {
    return static_cast<std::size_t>(this->CastWidth) * this->CastHeight;
  }
  bool SeveralBlocks() const { return this->Blocks.size() > 1; }

  /// What a hardware selection's passes share one cast by: the part of the signature that
  /// decides which cell each pixel shows, and the cast's size.
  std::vector<double> SelectionSignature() const;

  /// Whether a selection of this view may take its cast's cells and depths: a single block (a
  /// selection keeps each pixel's block only when it casts itself), opaque (translucent casts stop
  /// at the opaque depth), at full resolution.
  bool ServesSelection() const
  {
    return !this->SeveralBlocks() && !this->Translucent && !this->CollectLayers &&
      this->CastWidth == this->Viewport[2] && this->CastHeight == this->Viewport[3];
  }

  /// The viewport, cast at `sampleDistance` pixels a ray, and the actor seen through the active
  /// camera's projection: with `eye`, as the GL matrices of this render use it (so explicit and
  /// tiled projections and each stereo eye work); else the centre view of VTK's pickers. False
  /// for an empty viewport.
  bool SetUpView(vtkRenderer* renderer, double sampleDistance, bool eye = true);

  /// Whether an opaque frame is drawn under screen-space ambient occlusion (AmbientOcclusion)
  /// and, if so, its ViewSpace (after SetUpView, with the same eye).
  void CollectAmbientOcclusion(vtkRenderer* renderer);

  /// The renderer's lights, as vtkOpenGLRenderer hands them to the polygon shaders (none when
  /// the actor's property is unlit), with the camera position as the eye of the Phong model.
  void CollectLights(vtkRenderer* renderer);
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
  /// Per pixel, the samples that see a surface (Frame::SamplePositions; empty without them).
  std::vector<std::uint8_t> SampleMasks;
  std::vector<std::uint8_t> BlockColors;
  std::vector<double> BlockDepth;
  std::vector<double> BlockNormals;
  std::vector<tetdsr::NodeId> BlockCellIds;
  std::vector<double> RayLimits;
  std::vector<unsigned int> CasterBlocks; ///< each caster's block (flat index)
  /// Per pixel, the flat index of the block it shows (only when sized: hardware selection).
  std::vector<unsigned int> PixelBlocks;
  /// Per block, per tile, the crossings (Frame::CollectLayers).
  std::vector<std::unique_ptr<std::vector<std::vector<tetdsr::PixelLayer>>>> Layers;

  /// Sizes the images for a cast of `pixels` rays; with several blocks the merged image starts
  /// empty (each block's nearer surfaces replace it) and each block has its own.
  void Resize(std::size_t pixels, bool severalBlocks);

  /// Per cast pixel, the ray parameter of the opaque depth at its full-resolution pixel.
  void ComputeRayLimits(const Frame& frame, const std::vector<float>& opaqueDepth);

  /// The image a block is cast into: the merged image itself when it is the only block, else
  /// its own (KeepNearest merges it).
  tetdsr::ImageView BlockImage(const Frame& frame);

  /// Keeps, per pixel, the nearest block's surface (and that block's flat index, when
  /// PixelBlocks is sized).
  void KeepNearest(std::size_t pixels, unsigned int block);

  /// SampleMasks of a full-resolution cast (the core's multisampleCoverage, the nearest hit over
  /// the casters), when `samplePositions` has any; else none. Before the window depth.
  void ComputeSampleMasks(const tetdsr::RayGenerator& rays, int width, int height,
    const std::vector<glm::dvec2>& samplePositions, bool parallel);

  /// Window depth of each hit in rows [rowBegin, rowEnd) (the core's windowDepths).
  void ComputeWindowDepth(const tetdsr::RayGenerator& rays, const glm::dmat4& modelToNdc,
    int castWidth, int rowBegin, int rowEnd);
};

/// A full-resolution cast on worker threads after interaction (ProgressiveRefinement). It owns
/// its images and its casters (made on the GL thread, which prepared their meshes), so the GL
/// thread reads nothing it writes until Finished; its casters read the prepared meshes, which
/// the GL thread leaves alone until the cast is cancelled and joined (CancelRefinements).
/// Destroying it cancels it and waits for its threads (at most one image tile each).
struct vtkDirectSurfaceMapper::Refinement
{
  std::vector<double> Signature; ///< the view it casts
  int Viewport[2] = { 0, 0 };    ///< the size of the viewport it casts
  /// Its frame's SelectionSignature when the frame ServesSelection (else empty): a selection of
  /// the same view waits for this cast instead of casting again.
  std::vector<double> SelectionSignature;
  int Width = 0;
  int Height = 0;
  tetdsr::RayGenerator Rays{ glm::dmat4(1.0), 1, 1 };
  glm::dmat4 ModelToNdc{ 1.0 };
  bool SeveralBlocks = false;
  std::vector<glm::dvec2> SamplePositions; ///< Frame::SamplePositions
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

  ~Refinement();

  /// The worker: every block's tiles on `threads` threads, each taking the next tile until
  /// there are none or the cast is cancelled (checked before each tile); then the blocks'
  /// nearest surfaces and the window depth.
  void Run(int threads);
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

  // FXAA after the translucent surfaces (PostponeFXAA): per renderer whose FXAA this mapper
  // switched off for a frame, the EndEvent observer that applies it over the finished frame,
  // the filter it applies (OpenGL objects of the renderer's window) and whether it is due.
  struct PostponedFXAA
  {
    vtkWeakPointer<vtkRenderer> Renderer;
    unsigned long ObserverTag = 0;
    vtkSmartPointer<vtkOpenGLFXAAFilter> Filter;
    bool Due = false;
  };
  std::vector<PostponedFXAA> PostponedFXAAs;

  /// What one view (a window's renderer, an actor of this mapper, a stereo eye) draws its image
  /// with: textures and quad (OpenGL objects belong to the window's context), the signature and
  /// size of the image the textures hold, so that each view re-uses its own, and its background
  /// cast.
  struct ViewResources
  {
    vtkWeakPointer<vtkOpenGLRenderWindow> Window;
    vtkWeakPointer<vtkRenderer> Renderer;
    vtkWeakPointer<vtkActor> Actor;
    int Eye = 0; ///< Frame::Eye
    vtkSmartPointer<vtkTextureObject> ColorTexture;
    vtkSmartPointer<vtkTextureObject> DepthTexture;
    /// The cast's normals (model coordinates), loaded only for ambient occlusion.
    vtkSmartPointer<vtkTextureObject> NormalTexture;
    bool NormalsValid = false;
    /// The cast's sample masks (multisampled framebuffers, full-resolution casts only).
    vtkSmartPointer<vtkTextureObject> SampleMaskTexture;
    bool SampleMasksValid = false;
    /// For an image smaller than the viewport: per cast pixel its same-surface bits, per 2 x 2
    /// block its kind (tetdsr/render/Upsampling.h), and those as textures.
    tetdsr::UpsampleMaps Upsampling;
    vtkSmartPointer<vtkTextureObject> MaskTexture;
    vtkSmartPointer<vtkTextureObject> BlockTexture;
    bool UpsamplingValid = false;
    /// kQuadFull, kQuadUpsample; those writing the G-buffer of ambient occlusion too (+2); and
    /// those writing a sample mask (+4, full resolution only).
    std::unique_ptr<vtkOpenGLQuadHelper> Quads[8];
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

      /// Keeps what `frame`'s cast shows at each pixel (cell, block, depth), for every pass of
      /// the selection whose `signature` it is.
      void Keep(const Frame& frame, const ImageCast& cast, std::vector<double> signature);
      /// A point pass's ids: each covered pixel's node of its cell nearest to its hit (once per
      /// cast).
      void FindNearestPoints(
        const std::vector<std::pair<unsigned int, vtkUnstructuredGrid*>>& blocks);
      /// Ids: each pixel's value in `pass` as vtkHardwareSelector reads it (24 bits in the red,
      /// green and blue bytes, low byte first): the cell's or the point's id (low or high 24
      /// bits), the block's flat index (`composite`; else 1), or the selector's colour for the
      /// actor's and the process's passes (`propColor`).
      void EncodePass(int pass, const float* propColor, bool composite);
    } Selection;

    /// Keeps a full-resolution cast of this view (when its frame ServesSelection) for the next
    /// selection of the same view, so that hovering or selecting casts nothing more.
    void KeepForSelection(const Frame& frame, const ImageCast& cast);

    void Release(vtkWindow* window);
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
  /// What the last check of translucent neighbours was made for (renderer, count, technique).
  std::vector<std::uintptr_t> NeighbourStamp;

  /// The resources of a view, made on first use. Entries of deleted windows, renderers or
  /// actors are dropped (a window releases its quads' and textures' OpenGL objects itself when
  /// it goes; those of a deleted renderer or actor are released here).
  ViewResources& ResourcesOf(
    vtkOpenGLRenderWindow* window, vtkRenderer* renderer, vtkActor* actor, int eye);

  /// Cancels every view's background cast and waits for its threads: a cast on the GL thread
  /// may rebuild the prepared meshes they read. Not those of the data and settings of
  /// `sameData`'s frame (its signature's modification times): a cast of them rebuilds nothing.
  void CancelRefinements(const Frame* sameData = nullptr);

  adapter::PreparedMesh& MeshOf(unsigned int block);

  /// Reads what the opaque geometry left in the depth buffer (it bounds the translucent rays)
  /// and returns an order-sensitive sum of it, so that a moved prop changes the signature.
  double ReadOpaqueDepth(const Frame& frame);

  /// The window depth of the GL thread's cast, its rows on vtkSMPTools' threads.
  void ComputeWindowDepth(const Frame& frame);

  /// The sample positions of the bound draw framebuffer (within a pixel), if it has 2 to
  /// tetdsr::kMaxCoverageSamples samples and the context has GL_ARB_sample_shading (which the
  /// quad's gl_SampleMask needs); else none.
  static std::vector<glm::dvec2> SamplePositions();

  /// A texture of the window's context (made on first use), clamped to its edge, read as
  /// `filter` says.
  static void Ready(vtkSmartPointer<vtkTextureObject>& texture, vtkOpenGLRenderWindow* window,
    int filter = vtkTextureObject::Nearest);

  /// Loads an RGBA8 image and a float depth image of width x height into two textures of the
  /// window's context (made on first use; the quad reads them texel by texel, and filters them
  /// when `filter` is Linear and the image is upsampled).
  static void LoadTextures(vtkOpenGLRenderWindow* window, vtkSmartPointer<vtkTextureObject>& color,
    vtkSmartPointer<vtkTextureObject>& depth, int width, int height, const std::uint8_t* colors,
    const float* depths, int filter = vtkTextureObject::Nearest);

  /// The upsampling's masks and blocks of the image just loaded (the core's rule, rows on
  /// vtkSMPTools' threads), as two byte textures.
  static void LoadUpsampling(ViewResources& gl, vtkOpenGLRenderWindow* window, const float* depth,
    int width, int height);

  /// Loads a cast's images into the view's textures (its normals too with `normals`).
  static void Upload(ViewResources& gl, vtkOpenGLRenderWindow* window, const ImageCast& images,
    int width, int height, double sampleDistance, bool normals = false);

  /// Draws the view's image; with `viewSpace`, into the G-buffer of ambient occlusion too.
  static bool Draw(ViewResources& gl, vtkOpenGLRenderWindow* window, bool translucent,
    const int viewport[4], const vtkDirectSurfaceViewSpace* viewSpace = nullptr);

  /// The quad drawing with `declarations` and `implementation` (made on first use; `system`, if
  /// any, replaces the template's //VTK::System::Dec, keeping it first); false if it does not
  /// compile.
  static bool ReadyQuad(std::unique_ptr<vtkOpenGLQuadHelper>& quad, vtkOpenGLRenderWindow* window,
    const char* declarations, const char* implementation, const char* system = nullptr);

  /// Draws `color` at `depth` (a texture each, of the viewport's size unless `upsample`: then
  /// with the view's upsampling maps) with the view's quad; with `viewSpace`, each pixel's
  /// view-space position and normal (from the view's NormalTexture) into colour attachments 1
  /// and 2, as vtkSSAOPass reads them; with `sampleMask` (full resolution), each pixel's samples
  /// from the view's SampleMaskTexture.
  static bool DrawTextures(ViewResources& gl, vtkOpenGLRenderWindow* window, bool translucent,
    const int viewport[4], vtkTextureObject* color, vtkTextureObject* depth, bool upsample,
    const vtkDirectSurfaceViewSpace* viewSpace = nullptr, bool sampleMask = false);
};

#endif
