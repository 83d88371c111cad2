#include "vtkPVDirectSurfaceRayCaster.h"

#include "vtkCamera.h"
#include "vtkObjectFactory.h"
#include "vtkPlane.h"

vtkStandardNewMacro(vtkPVDirectSurfaceRayCaster);

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

void vtkPVDirectSurfaceRayCaster::AddClipPlane(
  double x, double y, double z, double nx, double ny, double nz)
{
  vtkNew<vtkPlane> plane;
  plane->SetOrigin(x, y, z);
  plane->SetNormal(nx, ny, nz);
  this->AddClippingPlane(plane);
}

void vtkPVDirectSurfaceRayCaster::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FitCameraToMesh: " << this->FitCameraToMesh << "\n";
  os << indent << "PropertyCamera:\n";
  this->PropertyCamera->PrintSelf(os, indent.GetNextIndent());
}
