// vtkDirectSurfaceMapper's translucent surfaces across processes: each process casts the
// crossings of the cells it holds, process 0 gathers them (packed by the core's LayerExchange),
// composites them per pixel in front of the composited opaque depth as one process holding every
// cell would, and blends the result over the compositor's image or its own frame.
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

#include "tetdsr/render/LayerExchange.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

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
