#include "vtkDirectSurfacePick.h"

#include "vtkDataSet.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"

vtkStandardNewMacro(vtkDirectSurfacePick);

vtkDirectSurfacePick::vtkDirectSurfacePick() = default;
vtkDirectSurfacePick::~vtkDirectSurfacePick() = default;

void vtkDirectSurfacePick::Initialize()
{
  this->Hit = false;
  for (int k = 0; k < 3; ++k)
  {
    this->Position[k] = this->MapperPosition[k] = this->Normal[k] = this->MapperNormal[k] = 0.0;
    this->ParametricCoordinates[k] = 0.0;
  }
  this->CellId = -1;
  this->FlatBlockIndex = -1;
  this->HasParametricCoordinates = false;
  this->IsoValueIndex = -1;
  this->ClippingPlaneId = -1;
  this->Value = 0.0;
  this->RayParameter = 0.0;
  this->DataSet = nullptr;
  this->PointData->Initialize();
  this->Modified();
}

void vtkDirectSurfacePick::DeepCopyFrom(vtkDirectSurfacePick* other)
{
  if (!other || other == this)
  {
    return;
  }
  this->Hit = other->Hit;
  for (int k = 0; k < 3; ++k)
  {
    this->Position[k] = other->Position[k];
    this->MapperPosition[k] = other->MapperPosition[k];
    this->Normal[k] = other->Normal[k];
    this->MapperNormal[k] = other->MapperNormal[k];
    this->ParametricCoordinates[k] = other->ParametricCoordinates[k];
  }
  this->CellId = other->CellId;
  this->FlatBlockIndex = other->FlatBlockIndex;
  this->HasParametricCoordinates = other->HasParametricCoordinates;
  this->IsoValueIndex = other->IsoValueIndex;
  this->ClippingPlaneId = other->ClippingPlaneId;
  this->Value = other->Value;
  this->RayParameter = other->RayParameter;
  this->DataSet = other->DataSet;
  this->PointData->DeepCopy(other->PointData);
  this->Modified();
}

void vtkDirectSurfacePick::SetDataSet(vtkDataSet* dataSet)
{
  this->DataSet = dataSet;
}

void vtkDirectSurfacePick::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Hit: " << this->Hit << "\n";
  os << indent << "Position: (" << this->Position[0] << ", " << this->Position[1] << ", "
     << this->Position[2] << ")\n";
  os << indent << "Normal: (" << this->Normal[0] << ", " << this->Normal[1] << ", "
     << this->Normal[2] << ")\n";
  os << indent << "CellId: " << this->CellId << "\n";
  os << indent << "FlatBlockIndex: " << this->FlatBlockIndex << "\n";
  os << indent << "HasParametricCoordinates: " << this->HasParametricCoordinates << "\n";
  os << indent << "ParametricCoordinates: (" << this->ParametricCoordinates[0] << ", "
     << this->ParametricCoordinates[1] << ", " << this->ParametricCoordinates[2] << ")\n";
  os << indent << "IsoValueIndex: " << this->IsoValueIndex << "\n";
  os << indent << "ClippingPlaneId: " << this->ClippingPlaneId << "\n";
  os << indent << "Value: " << this->Value << "\n";
  os << indent << "RayParameter: " << this->RayParameter << "\n";
  os << indent << "PointData arrays: " << this->PointData->GetNumberOfArrays() << "\n";
}
