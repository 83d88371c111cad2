// vtkDirectSurfaceMapper's progressive refinement: a still frame in a window with an event loop
// shows an image at once (the last reduced one after interaction, or a coarse cast) while the full
// resolution is cast on worker threads (Refinement); the interactor's one-shot timers tell whether
// its event loop runs at all (known process-wide once seen), and poll the worker, to ask for the
// render that shows the finished image.
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfaceMapperInternals.h"

#include "vtkCommand.h"
#include "vtkRenderWindowInteractor.h"

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

namespace
{
/// How often the event loop asks whether a background cast is done: 25 times a second, so the
/// refined frame follows within a frame time of a fluid interaction.
constexpr unsigned long kRefinementPollMilliseconds = 40;

/// The interactors whose event loop some mapper of this process has seen run (on the GUI
/// thread, as every render): a mapper drawing in one of them for the first time (a new
/// representation in ParaView's GUI) need not wait for its own timer to fire.
std::vector<vtkWeakPointer<vtkRenderWindowInteractor>>& RunningEventLoops()
{
  static std::vector<vtkWeakPointer<vtkRenderWindowInteractor>> loops;
  loops.erase(std::remove_if(loops.begin(), loops.end(),
                [](const vtkWeakPointer<vtkRenderWindowInteractor>& loop) { return !loop; }),
    loops.end());
  return loops;
}
}

vtkDirectSurfaceMapper::Refinement::~Refinement()
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

void vtkDirectSurfaceMapper::Refinement::Run(int threads)
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
  this->Cast.ComputeSampleMasks(this->Rays, this->Width, this->Height, this->SamplePositions,
    false); // (this worker's thread: vtkSMPTools may be busy on the GL thread)
  this->Cast.ComputeWindowDepth(this->Rays, this->ModelToNdc, this->Width, 0, this->Height);
  this->Seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  this->Finished = true;
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
  refinement->Viewport[0] = frame.Viewport[2];
  refinement->Viewport[1] = frame.Viewport[3];
  if (frame.ServesSelection())
  {
    refinement->SelectionSignature = frame.SelectionSignature();
  }
  refinement->Width = frame.CastWidth;
  refinement->Height = frame.CastHeight;
  refinement->Rays = frame.Rays;
  refinement->ModelToNdc = frame.ModelToNdc;
  refinement->SeveralBlocks = frame.SeveralBlocks();
  refinement->SamplePositions = frame.SamplePositions; // (a refinement is a full-resolution cast)
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

bool vtkDirectSurfaceMapper::ShowRefinement(Frame& frame, vtkRenderer* renderer)
{
  Internals& in = *this->Internal;
  Internals::ViewResources& gl = in.ResourcesOf(frame.Window, renderer, frame.Actor, frame.Eye);
  Refinement& refinement = *gl.Refining;
  if (!SameScene(refinement.Signature, frame.Signature) ||
    refinement.Viewport[0] != frame.Viewport[2] || refinement.Viewport[1] != frame.Viewport[3])
  {
    return false;
  }
  if (this->SynchronousStillRenders && refinement.Worker.joinable())
  {
    refinement.Worker.join(); // (a capture needs the full frame now: no sooner cast again)
  }
  this->LastRenderReusedImage = !refinement.Finished;
  this->LastRenderRefining = !refinement.Finished;
  if (!refinement.Finished)
  {
    return true;
  }
  if (refinement.Worker.joinable())
  {
    refinement.Worker.join(); // (it has returned; a selection may have joined it)
  }
  Internals::Upload(gl, frame.Window, refinement.Cast, refinement.Width, refinement.Height, 1.0,
    frame.AmbientOcclusion);
  gl.KeepForSelection(frame, refinement.Cast);
  gl.Signature = refinement.Signature;
  in.LastCastSeconds = refinement.Seconds;
  in.SampleDistance = 1.0;
  this->LastImageSampleDistance = 1.0;
  this->LastCastSize[0] = refinement.Width;
  this->LastCastSize[1] = refinement.Height;
  gl.Refining.reset();
  return true;
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
  const auto& running = RunningEventLoops();
  loop.Runs = std::find(running.begin(), running.end(), interactor) != running.end();
  if (!loop.Runs)
  {
    loop.ProbeTimerId = interactor->CreateOneShotTimer(1); // (forgotten by the interactor once fired)
  }
  loops.push_back(loop);
  return loop.Runs;
}

void vtkDirectSurfaceMapper::DeclareEventLoopRuns(vtkRenderWindowInteractor* interactor)
{
  if (!interactor || this->EventLoopRuns(interactor))
  {
    return;
  }
  for (auto& loop : this->Internal->EventLoops)
  {
    if (loop.Interactor == interactor)
    {
      loop.Runs = true;
      RunningEventLoops().emplace_back(interactor);
    }
  }
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
      RunningEventLoops().emplace_back(loop.Interactor);
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
