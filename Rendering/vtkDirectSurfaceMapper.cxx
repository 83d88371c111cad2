// vtkDirectSurfaceMapper, the public class: its settings (iso-values and their styles, level of
// detail, threads, the controller), its bounds and modification time, and the Render entry that
// sends each call to its job: an opaque frame (Draw), translucent surfaces deferred to the
// renderer's EndEvent (DrawDeferred), or a hardware-selection pass (DrawSelection). The jobs'
// files are listed in vtkDirectSurfaceMapperInternals.h.
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfaceMapperInternals.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkContourValues.h"
#include "vtkDataSetAttributes.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
#include "vtkProp3D.h"
#include "vtkPropCollection.h"
#include "vtkProperty.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkUnstructuredGrid.h"

#include "vtkDirectSurfaceReporting.h"

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkDirectSurfaceMapper);

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
  for (const auto& postponed : this->Internal->PostponedFXAAs)
  {
    if (postponed.Renderer)
    {
      postponed.Renderer->RemoveObserver(postponed.ObserverTag);
      if (postponed.Due)
      {
        postponed.Renderer->SetUseFXAA(true); // (gone before the frame ended)
      }
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
  if (!actors.empty())
  {
    this->CheckTranslucentNeighbours(renderer);
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

void vtkDirectSurfaceMapper::CheckTranslucentNeighbours(vtkRenderer* renderer)
{
  // The renderer's other translucent 3D props (not this kind's deferred surfaces, which are
  // sorted among themselves; not 2D annotations, drawn over everything): their layers are in
  // the frame already.
  int others = 0;
  vtkPropCollection* props = renderer->GetViewProps();
  vtkCollectionSimpleIterator it;
  props->InitTraversal(it);
  while (vtkProp* prop = props->GetNextProp(it))
  {
    auto* actor = vtkActor::SafeDownCast(prop);
    const bool deferred = actor && vtkDirectSurfaceMapper::SafeDownCast(actor->GetMapper());
    others += vtkProp3D::SafeDownCast(prop) && prop->GetVisibility() && !deferred &&
        prop->HasTranslucentPolygonalGeometry()
      ? 1
      : 0;
  }
  // Once per change of the count or the technique in this renderer, not every frame.
  const bool peeling = renderer->GetUseDepthPeeling() != 0;
  std::vector<std::uintptr_t> stamp{ reinterpret_cast<std::uintptr_t>(renderer),
    static_cast<std::uintptr_t>(others), peeling ? 1u : 0u };
  if (stamp == this->Internal->NeighbourStamp)
  {
    return;
  }
  this->Internal->NeighbourStamp = stamp;
  adapter::Messages messages;
  tetdsr::checkTranslucentNeighbours(
    others, peeling ? "depth peeling" : "order-independent translucency", messages);
  adapter::ReportMessages(this, messages);
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
  adapter::Messages messages;
  if (input &&
    !tetdsr::checkInputKind(
      vtkUnstructuredGrid::SafeDownCast(input) || vtkCompositeDataSet::SafeDownCast(input),
      input->GetClassName(), messages))
  {
    adapter::ReportMessages(this, messages);
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
  for (auto& postponed : this->Internal->PostponedFXAAs)
  {
    if (postponed.Filter && postponed.Renderer &&
      (!window || postponed.Renderer->GetRenderWindow() == window))
    {
      postponed.Filter->ReleaseGraphicsResources();
      postponed.Filter = nullptr; // (made again on its next use)
    }
  }
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
  vtkMultiProcessController* controller = this->Internal->Controller;
  const bool distributed = controller && controller->GetNumberOfProcesses() > 1;
  if (!this->IsTranslucent(actor) && !(distributed && this->CompositeOpaqueAcrossProcesses))
  {
    this->Draw(renderer, actor, false);
    return;
  }
  this->PostponeFXAA(renderer);
  if (distributed)
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
  os << indent << "SynchronousStillRenders: " << this->SynchronousStillRenders << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "CompositeOpaqueAcrossProcesses: " << this->CompositeOpaqueAcrossProcesses
     << "\n";
  os << indent << "LastImageSampleDistance: " << this->LastImageSampleDistance << "\n";
  os << indent << "LastRenderReusedImage: " << this->LastRenderReusedImage << "\n";
  os << indent << "LastRenderRefining: " << this->LastRenderRefining << "\n";
  os << indent << "LastCastSize: " << this->LastCastSize[0] << " x " << this->LastCastSize[1] << "\n";
  os << indent << "NumberOfRenderedCells: " << this->NumberOfRenderedCells << "\n";
}
