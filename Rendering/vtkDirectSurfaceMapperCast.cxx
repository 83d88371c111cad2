// vtkDirectSurfaceMapper's view and cast: the frame path (Draw: level of detail, re-use of the
// last image, a still frame shown at once and refined in the background, the cast, its upload
// and drawing), the view a frame is cast from (Frame: viewport,
// matrices, lights), the stages every job shares (the input's blocks, the settings, each block's
// prepared mesh, the casters and their images: ImageCast) and the sample distance interactive
// frames are cast at, from the time the last cast took.
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfaceMapperInternals.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkInformationObjectBaseVectorKey.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkOpenGLRenderPass.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkProperty.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSMPTools.h"
#include "vtkScalarsToColors.h"
#include "vtkTimerLog.h"
#include "vtkUnstructuredGrid.h"

#include "vtkDirectSurfaceReporting.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace
{
/// A still frame in a window with an event loop is cast on the GUI thread only when its cast is
/// expected to take at most this long (a frame time the user does not notice as a stall); else a
/// coarse frame, sized to take about kCoarseFrameSeconds, is shown and refined behind it.
constexpr double kQuickStillSeconds = 0.15;
constexpr double kCoarseFrameSeconds = 0.05;

/// A switched-on VTK light as the core's, in world coordinates (the cast's are the actor's model
/// coordinates: Lighting::setModelToWorld shades in the world, as polygons are).
tetdsr::Light CoreLight(vtkLight* light)
{
  tetdsr::Light entry;
  double color[3], position[3], focalPoint[3];
  light->GetDiffuseColor(color);
  light->GetTransformedPosition(position);
  light->GetTransformedFocalPoint(focalPoint);
  entry.color = light->GetIntensity() * glm::dvec3(color[0], color[1], color[2]);
  entry.positional = light->GetPositional() != 0;
  entry.position = glm::dvec3(position[0], position[1], position[2]);
  entry.direction = tetdsr::unitVector(glm::dvec3(
    focalPoint[0] - position[0], focalPoint[1] - position[1], focalPoint[2] - position[2]));
  return entry;
}

/// The world-to-NDC matrix of the renderer's view. `eye`: the one the window's polygons are
/// drawn with in this render (vtkOpenGLCamera::GetKeyMatrices: the camera's projection, with the
/// stereo eye's shear when the window renders in stereo, times its model-view matrix). Else the
/// centre view VTK's pickers use: the camera's composite projection, which leaves the eye's shear
/// out, so that a frame cast with it would show the centre view to both eyes.
glm::dmat4 WorldToNdc(vtkRenderer* renderer, bool eye)
{
  vtkCamera* camera = renderer->GetActiveCamera();
  const double aspect = renderer->GetTiledAspectRatio();
  if (!eye)
  {
    return ToGlm(camera->GetCompositeProjectionTransformMatrix(aspect, -1.0, 1.0));
  }
  return ToGlm(camera->GetProjectionTransformMatrix(aspect, -1.0, 1.0)) *
    ToGlm(camera->GetModelViewTransformMatrix());
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
}

//------------------------------------------------------------------------------
bool vtkDirectSurfaceMapper::Frame::SetUpView(
  vtkRenderer* renderer, double sampleDistance, bool eye)
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
  const glm::dmat4 worldToNdc = WorldToNdc(renderer, eye);
  vtkCamera* camera = renderer->GetActiveCamera();
  this->Eye = eye && camera->GetStereo() && !camera->GetLeftEye() ? 1 : 0;
  this->Identity = this->Actor->GetIsIdentity() != 0;
  this->ModelToWorld = this->Identity ? glm::dmat4(1.0) : ToGlm(this->Actor->GetMatrix());
  this->WorldToModel = glm::inverse(this->ModelToWorld);
  this->ModelToNdc = worldToNdc * this->ModelToWorld;
  this->NdcToModel = glm::inverse(this->ModelToNdc);
  if (!tetdsr::checkProjection(this->NdcToModel, this->Messages))
  {
    return false; // (a singular projection: the caller reports it)
  }
  this->Rays = tetdsr::RayGenerator(this->NdcToModel, this->CastWidth, this->CastHeight);
  return true;
}

void vtkDirectSurfaceMapper::Frame::CollectAmbientOcclusion(vtkRenderer* renderer)
{
  // A render pass lists itself in the props' keys while it renders them (vtkOpenGLRenderPass);
  // vtkSSAOPass renders the opaque pass into its G-buffer.
  vtkInformation* keys = this->Actor->GetPropertyKeys();
  vtkInformationObjectBaseVectorKey* passKey = vtkOpenGLRenderPass::RenderPasses();
  const int passes = keys && keys->Has(passKey) ? keys->Length(passKey) : 0;
  this->AmbientOcclusion = false;
  for (int k = 0; k < passes && !this->Translucent; ++k)
  {
    vtkObjectBase* pass = keys->Get(passKey, k);
    this->AmbientOcclusion = this->AmbientOcclusion || (pass && pass->IsA("vtkSSAOPass"));
  }
  if (!this->AmbientOcclusion)
  {
    return;
  }
  // As vtkSSAOPass and the polygons see view space: the camera's model-view matrix and its
  // projection (with the stereo eye's shear, as SetUpView).
  vtkCamera* camera = renderer->GetActiveCamera();
  const glm::dmat4 modelToView =
    ToGlm(camera->GetModelViewTransformMatrix()) * this->ModelToWorld;
  this->ViewSpace.NdcToView = glm::inverse(
    ToGlm(camera->GetProjectionTransformMatrix(renderer->GetTiledAspectRatio(), -1.0, 1.0)));
  this->ViewSpace.NormalToView = glm::transpose(glm::inverse(glm::dmat3(modelToView)));
}

std::vector<double> vtkDirectSurfaceMapper::Frame::SelectionSignature() const
{
  std::vector<double> signature(
    this->Signature.begin(), this->Signature.begin() + this->CellSignatureSize);
  signature.insert(signature.end(),
    { static_cast<double>(this->CastWidth), static_cast<double>(this->CastHeight) });
  return signature;
}

void vtkDirectSurfaceMapper::Frame::CollectLights(vtkRenderer* renderer)
{
  tetdsr::Lighting& lighting = this->Settings.lighting;
  double eye[3];
  renderer->GetActiveCamera()->GetPosition(eye);
  lighting.hasEye = true;
  lighting.eye = glm::dvec3(eye[0], eye[1], eye[2]);
  if (!this->Identity)
  {
    lighting.setModelToWorld(this->ModelToWorld);
  }
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
    const tetdsr::Light entry = CoreLight(light);
    lighting.lights.push_back(entry);
    this->LightState.insert(this->LightState.end(),
      { entry.color.x, entry.color.y, entry.color.z, entry.direction.x, entry.direction.y,
        entry.direction.z, entry.position.x, entry.position.y, entry.position.z,
        entry.positional ? 1.0 : 0.0 });
  }
  lighting.headlightOnly = count == 1 && headlight;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::ImageCast::Resize(std::size_t pixels, bool severalBlocks)
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
    this->BlockNormals.resize(3 * pixels);
    this->BlockCellIds.resize(pixels);
  }
}

void vtkDirectSurfaceMapper::ImageCast::ComputeRayLimits(
  const Frame& frame, const std::vector<float>& opaqueDepth)
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

tetdsr::ImageView vtkDirectSurfaceMapper::ImageCast::BlockImage(const Frame& frame)
{
  const bool several = frame.SeveralBlocks();
  tetdsr::ImageView image;
  image.width = frame.CastWidth;
  image.height = frame.CastHeight;
  image.colors = several ? this->BlockColors.data() : this->Colors.data();
  image.depth = several ? this->BlockDepth.data() : this->Depth.data();
  image.normals = several ? this->BlockNormals.data() : this->Normals.data();
  image.cellIds = several ? this->BlockCellIds.data() : this->CellIds.data();
  image.rayLimits = frame.Translucent && !frame.CollectLayers ? this->RayLimits.data() : nullptr;
  if (frame.CollectLayers)
  {
    this->Layers.emplace_back(new std::vector<std::vector<tetdsr::PixelLayer>>);
    image.layers = this->Layers.back().get();
  }
  return image;
}

void vtkDirectSurfaceMapper::ImageCast::KeepNearest(std::size_t pixels, unsigned int block)
{
  const bool blocks = !this->PixelBlocks.empty();
  for (std::size_t p = 0; p < pixels; ++p)
  {
    if (this->BlockDepth[p] < this->Depth[p])
    {
      this->Depth[p] = this->BlockDepth[p];
      this->CellIds[p] = this->BlockCellIds[p];
      std::copy_n(&this->BlockColors[4 * p], 4, &this->Colors[4 * p]);
      std::copy_n(&this->BlockNormals[3 * p], 3, &this->Normals[3 * p]);
      if (blocks)
      {
        this->PixelBlocks[p] = block;
      }
    }
  }
}

void vtkDirectSurfaceMapper::ImageCast::ComputeSampleMasks(const tetdsr::RayGenerator& rays,
  int width, int height, const std::vector<glm::dvec2>& samplePositions, bool parallel)
{
  if (samplePositions.empty())
  {
    this->SampleMasks.clear();
    return;
  }
  this->SampleMasks.resize(static_cast<std::size_t>(width) * height);
  // The nearest surface over the blocks' casters, as the merged image shows.
  auto firstHit = [this](const tetdsr::Ray& ray) {
    double nearest = std::numeric_limits<double>::infinity();
    tetdsr::Pick pick;
    for (const auto& caster : this->Casters)
    {
      if (caster->pick(ray, pick, nearest))
      {
        nearest = std::min(nearest, pick.t);
      }
    }
    return nearest;
  };
  auto parallelFor = [parallel](tetdsr::NodeId count,
                       const std::function<void(tetdsr::NodeId, tetdsr::NodeId)>& body) {
    if (!parallel)
    {
      body(0, count);
      return;
    }
    vtkSMPTools::For(0, count, [&](vtkIdType begin, vtkIdType end) { body(begin, end); });
  };
  tetdsr::multisampleCoverage(rays, firstHit, samplePositions, width, height, this->Depth.data(),
    this->Colors.data(), this->Normals.data(), this->SampleMasks.data(), parallelFor);
}

void vtkDirectSurfaceMapper::ImageCast::ComputeWindowDepth(const tetdsr::RayGenerator& rays,
  const glm::dmat4& modelToNdc, int castWidth, int rowBegin, int rowEnd)
{
  tetdsr::windowDepths(rays, modelToNdc, this->Depth.data(), this->WindowDepth.data(),
    castWidth, rowBegin, rowEnd);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceMapper::Internals::CancelRefinements(const Frame* sameData)
{
  // (The modification times follow the 16 numbers of the matrix: ComputeSignature.)
  auto sameTimes = [sameData](const Refinement& refinement) {
    const std::size_t end = sameData->CellSignatureSize;
    return end > 16 && refinement.Signature.size() >= end && sameData->Signature.size() >= end &&
      std::equal(sameData->Signature.begin() + 16, sameData->Signature.begin() + end,
        refinement.Signature.begin() + 16);
  };
  for (const auto& view : this->Views)
  {
    if (view->Refining && !(sameData && sameTimes(*view->Refining)))
    {
      view->Refining.reset();
    }
  }
}

adapter::PreparedMesh& vtkDirectSurfaceMapper::Internals::MeshOf(unsigned int block)
{
  auto& mesh = this->Meshes[block];
  if (!mesh)
  {
    mesh.reset(new adapter::PreparedMesh);
  }
  return *mesh;
}

void vtkDirectSurfaceMapper::Internals::ComputeWindowDepth(const Frame& frame)
{
  vtkSMPTools::For(0, frame.CastHeight, [&](vtkIdType rowBegin, vtkIdType rowEnd) {
    this->Cast.ComputeWindowDepth(frame.Rays, frame.ModelToNdc, frame.CastWidth,
      static_cast<int>(rowBegin), static_cast<int>(rowEnd));
  });
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
    adapter::ReportMessages(this, frame.Messages);
    return; // an empty viewport, or a singular projection
  }
  frame.CollectLights(renderer);
  frame.CollectAmbientOcclusion(renderer);
  if (!translucent)
  {
    frame.SamplePositions = Internals::SamplePositions();
  }
  const vtkDirectSurfaceViewSpace* viewSpace =
    frame.AmbientOcclusion ? &frame.ViewSpace : nullptr;

  Internals& in = *this->Internal;
  Internals::ViewResources& gl = in.ResourcesOf(window, renderer, actor, frame.Eye);
  vtkRenderWindowInteractor* interactor = window->GetInteractor();
  const bool eventLoop =
    this->ProgressiveRefinement && interactor && this->EventLoopRuns(interactor);
  this->ComputeSignature(frame, true);
  this->LastRenderRefining = false;
  // The image this view holds: of the same scene (camera, data, settings), and of the size.
  const bool sameSize = gl.ImageSize[0] == frame.CastWidth && gl.ImageSize[1] == frame.CastHeight;
  auto drawImage = [&]() {
    Internals::Draw(gl, window, translucent, frame.Viewport, viewSpace);
    timer->StopTimer();
    this->TimeToDraw = timer->GetElapsedTime();
  };

  // This view's background cast: shown once finished, waited for while it runs (the image shown
  // drawn again), and dropped when the frame is anything else.
  if (gl.Refining)
  {
    if (distance == 1.0 && this->ShowRefinement(frame, renderer))
    {
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

  // A still frame in a window whose event loop can show a background cast: drawn at once and
  // refined behind (unless a full cast is quick, or a capture of the window needs it now).
  if (eventLoop && distance == 1.0 && !this->SynchronousStillRenders &&
    this->DrawThenRefine(frame, renderer, interactor, timer))
  {
    return;
  }

  if (!this->CastBlocks(frame))
  {
    return;
  }
  in.Cast.ComputeSampleMasks(frame.Rays, frame.CastWidth, frame.CastHeight,
    distance == 1.0 ? frame.SamplePositions : std::vector<glm::dvec2>(), true);
  in.ComputeWindowDepth(frame);
  Internals::Upload(
    gl, window, in.Cast, frame.CastWidth, frame.CastHeight, distance, frame.AmbientOcclusion);
  Internals::Draw(gl, window, translucent, frame.Viewport, viewSpace);
  gl.KeepForSelection(frame, in.Cast);
  gl.Signature = std::move(frame.Signature);
  timer->StopTimer();
  this->CastFinished(frame, distance, timer->GetElapsedTime());
}

bool vtkDirectSurfaceMapper::DrawThenRefine(
  Frame& frame, vtkRenderer* renderer, vtkRenderWindowInteractor* interactor, vtkTimerLog* timer)
{
  Internals& in = *this->Internal;
  Internals::ViewResources& gl = in.ResourcesOf(frame.Window, renderer, frame.Actor, frame.Eye);
  const vtkDirectSurfaceViewSpace* viewSpace =
    frame.AmbientOcclusion ? &frame.ViewSpace : nullptr;
  // Behind the last reduced image when it shows this scene (after interaction), else behind a
  // coarse cast of its own.
  const bool shown =
    gl.TexturesValid && gl.ImageSampleDistance > 1.0 && SameScene(gl.Signature, frame.Signature);
  if (!shown)
  {
    const double coarse = this->ChooseCoarseSampleDistance(frame);
    if (coarse == 1.0)
    {
      return false; // the full cast is quick: made on this thread
    }
    if (!frame.SetUpView(renderer, coarse) || !this->CastBlocks(frame))
    {
      return true; // nothing to draw
    }
    in.Cast.ComputeSampleMasks(frame.Rays, frame.CastWidth, frame.CastHeight, {}, true);
    in.ComputeWindowDepth(frame);
    Internals::Upload(gl, frame.Window, in.Cast, frame.CastWidth, frame.CastHeight, coarse,
      frame.AmbientOcclusion);
    Internals::Draw(gl, frame.Window, frame.Translucent, frame.Viewport, viewSpace);
    gl.Signature = frame.Signature;
    timer->StopTimer();
    this->CastFinished(frame, coarse, timer->GetElapsedTime());
    frame.Messages = adapter::Messages(); // (said once, by the coarse cast)
    frame.SetUpView(renderer, 1.0);
  }
  gl.Refining = this->StartRefinement(frame, interactor);
  this->LastRenderReusedImage = shown;
  this->LastRenderRefining = gl.Refining != nullptr;
  if (shown && gl.Refining)
  {
    Internals::Draw(gl, frame.Window, frame.Translucent, frame.Viewport, viewSpace);
    timer->StopTimer();
    this->TimeToDraw = timer->GetElapsedTime();
  }
  return true;
}

double vtkDirectSurfaceMapper::ExpectedFullCastSeconds(const Frame& frame) const
{
  // From the last cast's time per ray (preparing included: the estimate errs on the slow side).
  const Internals& in = *this->Internal;
  const double lastRays = static_cast<double>(this->LastCastSize[0]) * this->LastCastSize[1];
  const double fullRays = static_cast<double>(frame.Viewport[2]) * frame.Viewport[3];
  return in.LastCastSeconds > 0.0 && lastRays > 0.0 ? in.LastCastSeconds * fullRays / lastRays
                                                    : -1.0;
}

double vtkDirectSurfaceMapper::ChooseCoarseSampleDistance(const Frame& frame)
{
  // None yet (the first show): the coarsest cast, cheap whatever the mesh.
  if (this->MaximumImageSampleDistance < 2.0)
  {
    return 1.0; // (no reduced frames wanted)
  }
  const double expected = this->ExpectedFullCastSeconds(frame);
  if (expected < 0.0)
  {
    return this->MaximumImageSampleDistance;
  }
  if (expected <= kQuickStillSeconds)
  {
    return 1.0;
  }
  // The cast's time goes as its number of rays, 1 / distance^2.
  return vtkMath::ClampValue(
    std::sqrt(expected / kCoarseFrameSeconds), 2.0, this->MaximumImageSampleDistance);
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
  adapter::Messages messages;
  const bool drawable =
    tetdsr::checkBlocks(frame.Blocks.size(), static_cast<std::size_t>(otherBlocks), messages);
  adapter::ReportMessages(this, messages);
  return drawable;
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
  frame.CellSignatureSize = signature.size();
  if (!shading)
  {
    return;
  }
  // And what decides its colour: the lights, and the opaque depth translucent rays stop at.
  signature.push_back(frame.Settings.lighting.headlightOnly ? 1.0 : 0.0);
  signature.push_back(frame.AmbientOcclusion ? 1.0 : 0.0); // (the normals are loaded for it)
  for (const glm::dvec2& sample : frame.SamplePositions) // (the masks are made for them)
  {
    signature.insert(signature.end(), { sample.x, sample.y });
  }
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
