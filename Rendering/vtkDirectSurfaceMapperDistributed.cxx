// vtkDirectSurfaceMapper's translucent surfaces across processes: each process casts the
// crossings of the cells it holds, process 0 gathers them (packed by the core's LayerExchange),
// composites them per pixel in front of the composited opaque depth (the compositor's, or the
// processes' own depth buffers composited here) as one process holding every cell would, and
// blends the result over the compositor's image or its own frame.
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfaceMapperInternals.h"

#include "vtkActor.h"
#include "vtkCommunicator.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"
#include "vtkUnstructuredGrid.h"

#include "vtkDirectSurfaceReporting.h"

#include "tetdsr/render/LayerExchange.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace
{
/// Every process's packed crossings, gathered on process 0, with the size of the cast each
/// process's pixels index.
struct GatheredCrossings
{
  std::vector<vtkIdType> Headers; ///< per process: doubles sent, cast width, cast height
  std::vector<vtkIdType> Lengths; ///< per process: doubles sent
  std::vector<vtkIdType> Offsets; ///< per process: where its doubles start in Packed
  std::vector<double> Packed;     ///< on process 0 only
};

/// Collective: `packed` (this process's crossings in a cast of `castWidth` x `castHeight`
/// pixels, 0 x 0 when it has no view) from every process to process 0.
GatheredCrossings GatherCrossings(vtkMultiProcessController* controller,
  const std::vector<double>& packed, int castWidth, int castHeight)
{
  const std::size_t processes = static_cast<std::size_t>(controller->GetNumberOfProcesses());
  const bool root = controller->GetLocalProcessId() == 0;
  GatheredCrossings gathered;
  const vtkIdType header[3] = { static_cast<vtkIdType>(packed.size()), castWidth, castHeight };
  gathered.Headers.resize(3 * processes);
  controller->Gather(header, gathered.Headers.data(), 3, 0);
  gathered.Lengths.resize(processes);
  gathered.Offsets.resize(processes);
  vtkIdType total = 0;
  for (std::size_t p = 0; p < processes; ++p)
  {
    gathered.Lengths[p] = gathered.Headers[3 * p];
    gathered.Offsets[p] = total;
    total += gathered.Lengths[p];
  }
  gathered.Packed.resize(root ? static_cast<std::size_t>(total) : 0);
  controller->GatherV(packed.data(), gathered.Packed.data(), header[0], gathered.Lengths.data(),
    gathered.Offsets.data(), 0);
  return gathered;
}

/// Collective: the diagonal of the union of every process's bounds (`lo`, `hi`; empty on a
/// process without any), 0 when no process has any.
double SceneDiagonal(vtkMultiProcessController* controller, const double lo[3], const double hi[3])
{
  double sceneLo[3], sceneHi[3];
  controller->AllReduce(lo, sceneLo, 3, vtkCommunicator::MIN_OP);
  controller->AllReduce(hi, sceneHi, 3, vtkCommunicator::MAX_OP);
  return sceneLo[0] <= sceneHi[0] ? std::sqrt(vtkMath::Distance2BetweenPoints(sceneLo, sceneHi))
                                  : 0.0;
}

/// Process 0: the crossings of every process whose cast has `castWidth` x `castHeight` pixels;
/// `mismatched` counts the processes of another size that sent some (their pixels are not
/// these).
std::vector<tetdsr::PixelLayer> ReadCrossings(
  const GatheredCrossings& gathered, int castWidth, int castHeight, int& mismatched)
{
  std::vector<tetdsr::PixelLayer> layers;
  layers.reserve(gathered.Packed.size() / tetdsr::kPackedLayerSize);
  mismatched = 0;
  for (std::size_t p = 0; p < gathered.Lengths.size(); ++p)
  {
    if (gathered.Headers[3 * p + 1] != castWidth || gathered.Headers[3 * p + 2] != castHeight)
    {
      mismatched += gathered.Lengths[p] > 0;
      continue;
    }
    tetdsr::unpackLayers(gathered.Packed.data() + gathered.Offsets[p],
      static_cast<std::size_t>(gathered.Lengths[p]), layers);
  }
  return layers;
}

/// The compositor's depth (`depthSize` pixels) at the viewport's pixels: each takes the
/// compositor's pixel its centre lies in.
void ResampleDepth(const float* compositedDepth, const int depthSize[2], const int viewport[4],
  std::vector<float>& opaqueDepth)
{
  opaqueDepth.resize(static_cast<std::size_t>(viewport[2]) * viewport[3]);
  for (int j = 0; j < viewport[3]; ++j)
  {
    const int dj =
      std::min(depthSize[1] - 1, static_cast<int>((j + 0.5) * depthSize[1] / viewport[3]));
    for (int i = 0; i < viewport[2]; ++i)
    {
      const int di =
        std::min(depthSize[0] - 1, static_cast<int>((i + 0.5) * depthSize[0] / viewport[2]));
      opaqueDepth[static_cast<std::size_t>(j) * viewport[2] + i] =
        compositedDepth[static_cast<std::size_t>(dj) * depthSize[0] + di];
    }
  }
}

/// Collective: whether process 0 needs the processes' own opaque depth composited (its
/// compositor gave none, or of no size) and the viewport size it casts, as process 0 says.
bool NeedsOwnDepths(vtkMultiProcessController* controller, bool wanted, const int viewport[4],
  int size[2])
{
  int message[3] = { wanted ? 1 : 0, viewport[2], viewport[3] };
  controller->Broadcast(message, 3, 0);
  size[0] = message[1];
  size[1] = message[2];
  return message[0] != 0;
}

/// Collective: per pixel, the nearest of every process's `local` depth (window coordinates, the
/// same number of pixels on each), on process 0 (`composited`): the processes' opaque depth as a
/// z-buffer compositor would composite it.
void NearestOverProcesses(vtkMultiProcessController* controller, const std::vector<float>& local,
  std::vector<float>& composited)
{
  std::vector<float> nearest(local.size());
  controller->Reduce(local.data(), nearest.data(), static_cast<vtkIdType>(local.size()),
    vtkCommunicator::MIN_OP, 0);
  if (controller->GetLocalProcessId() == 0)
  {
    composited.swap(nearest);
  }
}

/// Per cast pixel, the ray parameter of its nearest crossing within its ray limit (+inf where
/// there is none); `layers` sorted by pixel, each pixel's nearest first (compositeLayers).
void NearestCrossings(const std::vector<tetdsr::PixelLayer>& layers,
  const std::vector<double>& rayLimits, std::vector<double>& depth)
{
  std::fill(depth.begin(), depth.end(), std::numeric_limits<double>::infinity());
  for (const tetdsr::PixelLayer& layer : layers)
  {
    if (layer.pixel < depth.size() && layer.t <= rayLimits[layer.pixel] &&
      !std::isfinite(depth[layer.pixel]))
    {
      depth[layer.pixel] = layer.t;
    }
  }
}

/// Blends the cast's colours (`castWidth` x `castHeight`, not premultiplied) over the
/// compositor's premultiplied image of `size` pixels, each of its pixels taking the cast pixel
/// it lies in: colour = alpha * ours + (1 - alpha) * its, alpha = alpha + (1 - alpha) * its.
void BlendOverComposited(const std::vector<std::uint8_t>& castColors, int castWidth,
  int castHeight, unsigned char* compositedColors, const int size[2])
{
  for (int j = 0; j < size[1]; ++j)
  {
    const int cj = std::min(castHeight - 1, static_cast<int>((j + 0.5) * castHeight / size[1]));
    for (int i = 0; i < size[0]; ++i)
    {
      const int ci = std::min(castWidth - 1, static_cast<int>((i + 0.5) * castWidth / size[0]));
      const std::uint8_t* ours = &castColors[4 * (static_cast<std::size_t>(cj) * castWidth + ci)];
      if (ours[3] == 0)
      {
        continue;
      }
      unsigned char* theirs = compositedColors + 4 * (static_cast<std::size_t>(j) * size[0] + i);
      const double alpha = ours[3] / 255.0;
      for (int c = 0; c < 3; ++c)
      {
        theirs[c] = static_cast<unsigned char>(
          std::min(255.0, alpha * ours[c] + (1.0 - alpha) * theirs[c]) + 0.5);
      }
      theirs[3] =
        static_cast<unsigned char>(std::min(255.0, ours[3] + (1.0 - alpha) * theirs[3]) + 0.5);
    }
  }
}
}

//------------------------------------------------------------------------------
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
    (this->IsTranslucent(actor) || this->CompositeOpaqueAcrossProcesses);

  // Process 0 chooses the resolution (interaction lowers it) and every process casts at it.
  Frame frame(window, actor, true);
  frame.CollectLayers = true;
  double distance = root && takesPart ? this->ChooseSampleDistance(frame) : 1.0;
  controller->Broadcast(&distance, 1, 0);
  const bool hasView = takesPart && frame.SetUpView(renderer, distance);

  // This process's crossings, packed, and its bounds.
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
          adapter::Cast(
            *caster, false, this->NumberOfThreads, []() { return false; }, [](double) {});
        }
        for (const auto& block : cast.Layers)
        {
          tetdsr::packLayers(*block, packed);
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
  const double diagonal = SceneDiagonal(controller, lo, hi);
  const GatheredCrossings gathered = GatherCrossings(
    controller, packed, hasView ? frame.CastWidth : 0, hasView ? frame.CastHeight : 0);
  // The opaque depth the rays stop at: the compositor's; without it (plain VTK, or ParaView's
  // ordered compositing, which blends the processes' images without depth) each process's own
  // depth buffer, the nearest of each pixel kept.
  const bool composited = depthSize && depthSize[0] > 0 && depthSize[1] > 0;
  int size[2];
  if (NeedsOwnDepths(
        controller, root && hasView && !(compositedDepth && composited), frame.Viewport, size))
  {
    std::vector<float> own(static_cast<std::size_t>(size[0]) * size[1], 1.0f);
    if (hasView && frame.Viewport[2] == size[0] && frame.Viewport[3] == size[1])
    {
      in.ReadOpaqueDepth(frame);
      own.swap(in.OpaqueDepth);
    }
    NearestOverProcesses(controller, own, in.OpaqueDepth);
  }
  else if (root && hasView)
  {
    ResampleDepth(compositedDepth, depthSize, frame.Viewport, in.OpaqueDepth);
  }
  if (!root || !hasView)
  {
    return;
  }

  // Process 0: the crossings in front of the composited opaque depth, composited per pixel.
  int mismatched = 0;
  std::vector<tetdsr::PixelLayer> layers =
    ReadCrossings(gathered, frame.CastWidth, frame.CastHeight, mismatched);
  adapter::Messages messages;
  tetdsr::describeMismatchedViews(mismatched, processes, messages);
  adapter::ReportMessages(this, messages);
  ImageCast& cast = in.Cast;
  cast.Resize(frame.Pixels(), false);
  cast.ComputeRayLimits(frame, in.OpaqueDepth);
  tetdsr::compositeLayers(layers, frame.Pixels(), tetdsr::Renderer::kLayerGap * diagonal,
    cast.RayLimits.data(), cast.Colors.data());
  NearestCrossings(layers, cast.RayLimits, cast.Depth);
  if (compositedColors && composited)
  {
    BlendOverComposited(
      cast.Colors, frame.CastWidth, frame.CastHeight, compositedColors, depthSize);
  }
  else
  {
    in.ComputeWindowDepth(frame);
    Internals::ViewResources& gl = in.ResourcesOf(window, renderer, actor, frame.Eye);
    gl.Refining.reset();
    Internals::Upload(gl, window, cast, frame.CastWidth, frame.CastHeight, distance);
    Internals::Draw(gl, window, true, frame.Viewport);
    gl.Signature.clear(); // not a cast of this process's own: never re-used as one
  }
  timer->StopTimer();
  this->CastFinished(frame, distance, timer->GetElapsedTime());
}
