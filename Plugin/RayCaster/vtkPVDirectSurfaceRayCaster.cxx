#include "vtkPVDirectSurfaceRayCaster.h"

#include "vtkCamera.h"
#include "vtkObjectFactory.h"
#include "vtkPlane.h"

#include "vtkDirectSurfaceReporting.h"
#include "tetdsr/input/Settings.h"

vtkStandardNewMacro(vtkPVDirectSurfaceRayCaster);

vtkPVDirectSurfaceRayCaster::vtkPVDirectSurfaceRayCaster()
{
  this->SetProgressText("Direct Surface Ray Cast");
}

// The superclass's GetMTime includes the camera in use, so edits of the property camera
// re-execute the filter only while it is the one in use.
void vtkPVDirectSurfaceRayCaster::SetFitCameraToMesh(bool fit)
{
  if (fit != this->FitCameraToMesh)
  {
    this->FitCameraToMesh = fit;
    this->Modified();
  }
  this->SetCamera(fit ? nullptr : this->PropertyCamera.GetPointer());
}

void vtkPVDirectSurfaceRayCaster::SetCameraPosition(double x, double y, double z)
{
  this->PropertyCamera->SetPosition(x, y, z);
}

void vtkPVDirectSurfaceRayCaster::SetCameraFocalPoint(double x, double y, double z)
{
  this->PropertyCamera->SetFocalPoint(x, y, z);
}

void vtkPVDirectSurfaceRayCaster::SetCameraViewUp(double x, double y, double z)
{
  this->PropertyCamera->SetViewUp(x, y, z);
}

void vtkPVDirectSurfaceRayCaster::SetCameraViewAngle(double degrees)
{
  this->PropertyCamera->SetViewAngle(degrees);
}

void vtkPVDirectSurfaceRayCaster::SetCameraParallelProjection(bool parallel)
{
  this->PropertyCamera->SetParallelProjection(parallel);
}

void vtkPVDirectSurfaceRayCaster::SetCameraParallelScale(double scale)
{
  this->PropertyCamera->SetParallelScale(scale);
}

// The interactive plane's origin and normal are followed through the superclass's GetMTime
// (it includes its planes'), so only switching it or replacing it rebuilds the collection.
void vtkPVDirectSurfaceRayCaster::SetClipWithPlane(bool clip)
{
  if (clip != this->ClipWithPlane)
  {
    this->ClipWithPlane = clip;
    this->UpdateClippingPlanes();
  }
}

void vtkPVDirectSurfaceRayCaster::SetInteractiveClipPlane(vtkPlane* plane)
{
  if (plane != this->InteractivePlane)
  {
    this->InteractivePlane = plane;
    this->UpdateClippingPlanes();
  }
}

void vtkPVDirectSurfaceRayCaster::SetIsoValueColorsCount(int count)
{
  tetdsr::Messages messages;
  this->IsoValueColorsRefused = !tetdsr::checkGroupedCount(
    "IsoValueColors", count, 3, "iso-value: red, green, blue", messages);
  tetdsr::vtkadapter::ReportMessages(this, messages);
}

void vtkPVDirectSurfaceRayCaster::SetClipPlanesCount(int count)
{
  tetdsr::Messages messages;
  this->ClipPlanesRefused = !tetdsr::checkGroupedCount(
    "ClipPlanes", count, 6, "plane: a point and a normal", messages);
  tetdsr::vtkadapter::ReportMessages(this, messages);
}

void vtkPVDirectSurfaceRayCaster::SetIsoValueColor(int i, double red, double green, double blue)
{
  if (this->IsoValueColorsRefused)
  {
    return;
  }
  const tetdsr::NumberSetting setting{ "IsoValueColors", 0.0, 1.0 };
  const double color[3] = { red, green, blue };
  double used[3];
  tetdsr::Messages messages;
  bool ok = true;
  for (int k = 0; k < 3; ++k)
  {
    ok = tetdsr::checkNumber(setting, color[k], used[k], messages) && ok;
  }
  tetdsr::vtkadapter::ReportMessages(this, messages);
  if (ok)
  {
    this->Superclass::SetIsoValueColor(i, used[0], used[1], used[2]);
  }
}

void vtkPVDirectSurfaceRayCaster::SetIsoValueOpacity(int i, double opacity)
{
  double used;
  tetdsr::Messages messages;
  const bool ok =
    tetdsr::checkNumber(tetdsr::NumberSetting{ "IsoValueOpacities", 0.0, 1.0 }, opacity, used, messages);
  tetdsr::vtkadapter::ReportMessages(this, messages);
  if (ok)
  {
    this->Superclass::SetIsoValueOpacity(i, used);
  }
}

void vtkPVDirectSurfaceRayCaster::AddClipPlane(
  double x, double y, double z, double nx, double ny, double nz)
{
  if (this->ClipPlanesRefused)
  {
    return;
  }
  auto plane = vtkSmartPointer<vtkPlane>::New();
  plane->SetOrigin(x, y, z);
  plane->SetNormal(nx, ny, nz);
  this->ListedPlanes.push_back(plane);
  this->UpdateClippingPlanes();
}

void vtkPVDirectSurfaceRayCaster::RemoveAllClipPlanes()
{
  if (!this->ListedPlanes.empty())
  {
    this->ListedPlanes.clear();
    this->UpdateClippingPlanes();
  }
}

void vtkPVDirectSurfaceRayCaster::UpdateClippingPlanes()
{
  this->RemoveAllClippingPlanes();
  if (this->ClipWithPlane && this->InteractivePlane)
  {
    this->AddClippingPlane(this->InteractivePlane);
  }
  for (vtkPlane* plane : this->ListedPlanes)
  {
    this->AddClippingPlane(plane);
  }
  this->Modified();
}

void vtkPVDirectSurfaceRayCaster::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FitCameraToMesh: " << this->FitCameraToMesh << "\n";
  os << indent << "PropertyCamera:\n";
  this->PropertyCamera->PrintSelf(os, indent.GetNextIndent());
  os << indent << "ClipWithPlane: " << this->ClipWithPlane << "\n";
  os << indent << "InteractivePlane: " << this->InteractivePlane.GetPointer() << "\n";
  os << indent << "ListedPlanes: " << this->ListedPlanes.size() << "\n";
  os << indent << "IsoValueColorsRefused: " << this->IsoValueColorsRefused << "\n";
  os << indent << "ClipPlanesRefused: " << this->ClipPlanesRefused << "\n";
}
