// vtkDirectSurfaceMapper's picking: the exact hit (point, cell, normal, every array interpolated
// there) under a display position in a still frame (Pick) or first along a segment (PickSegment,
// what vtkDirectSurfacePicker asks), nearest over the input's blocks.
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfaceMapperInternals.h"

#include "vtkActor.h"
#include "vtkCompositeDataSet.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkUnstructuredGrid.h"

#include "vtkDirectSurfacePick.h"
#include "vtkDirectSurfaceReporting.h"

#include <cmath>
#include <limits>

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
  if (!frame.SetUpView(renderer, 1.0, false)) // (the centre view, as VTK's pickers)
  {
    adapter::ReportMessages(this, frame.Messages); // (a singular projection's error)
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
