#include "vtkPVDirectSurfaceRayCaster.h"

#include "vtkCamera.h"
#include "vtkObjectFactory.h"
#include "vtkPlane.h"

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

void vtkPVDirectSurfaceRayCaster::AddClipPlane(
  double x, double y, double z, double nx, double ny, double nz)
{
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
}
