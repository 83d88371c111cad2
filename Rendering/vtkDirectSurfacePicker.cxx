#include "vtkDirectSurfacePicker.h"

#include "vtkActor.h"
#include "vtkCell.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataSet.h"
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfacePick.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkTransform.h"

vtkStandardNewMacro(vtkDirectSurfacePicker);

vtkDirectSurfacePicker::vtkDirectSurfacePicker() = default;
vtkDirectSurfacePicker::~vtkDirectSurfacePicker() = default;

vtkDirectSurfacePick* vtkDirectSurfacePicker::GetLastPick()
{
  return this->LastPick;
}

void vtkDirectSurfacePicker::Initialize()
{
  this->Superclass::Initialize();
  this->LastPick->Initialize();
}

double vtkDirectSurfacePicker::IntersectWithLine(const double p1[3], const double p2[3],
  double tol, vtkAssemblyPath* path, vtkProp3D* prop, vtkAbstractMapper3D* m)
{
  auto* mapper = vtkDirectSurfaceMapper::SafeDownCast(m);
  auto* actor = vtkActor::SafeDownCast(prop);
  if (!mapper || !actor)
  {
    return this->Superclass::IntersectWithLine(p1, p2, tol, path, prop, m);
  }
  // p1, p2 are in the input's coordinates (vtkPicker applied the inverse of the prop's matrix);
  // the result is the fraction of the way from p1 to p2, as vtkCellPicker's.
  if (!mapper->PickSegment(p1, p2, actor, this->Candidate))
  {
    return VTK_DOUBLE_MAX;
  }
  const double tMin = this->Candidate->GetRayParameter();
  if (tMin < this->GlobalTMin)
  {
    this->GlobalTMin = tMin;
    this->SetPath(path);
    this->ClippingPlaneId = this->Candidate->GetClippingPlaneId();
    this->Candidate->GetMapperPosition(this->MapperPosition);
    this->Candidate->GetMapperNormal(this->MapperNormal);
    this->CellId = this->Candidate->GetCellId();
    this->SubId = 0;
    this->Candidate->GetParametricCoordinates(this->PCoords);
    if (!this->Candidate->GetHasParametricCoordinates())
    {
      this->PCoords[0] = this->PCoords[1] = this->PCoords[2] = 0.0;
    }
    this->Mapper = mapper;
    this->DataSet = this->Candidate->GetDataSet();
    this->CompositeDataSet = vtkCompositeDataSet::SafeDownCast(mapper->GetInputDataObject(0, 0));
    this->FlatBlockIndex = this->Candidate->GetFlatBlockIndex();
    // The hit cell's node nearest the hit.
    this->PointId = -1;
    if (this->DataSet && this->CellId >= 0 && this->CellId < this->DataSet->GetNumberOfCells())
    {
      vtkCell* cell = this->DataSet->GetCell(this->CellId);
      double nearest = VTK_DOUBLE_MAX;
      for (vtkIdType k = 0; k < cell->GetNumberOfPoints(); ++k)
      {
        double x[3];
        this->DataSet->GetPoint(cell->GetPointId(k), x);
        const double d = vtkMath::Distance2BetweenPoints(x, this->MapperPosition);
        if (d < nearest)
        {
          nearest = d;
          this->PointId = cell->GetPointId(k);
        }
      }
    }
    // Into world coordinates, as vtkCellPicker does.
    this->Transform->TransformPoint(this->MapperPosition, this->PickPosition);
    this->Transform->TransformNormal(this->MapperNormal, this->PickNormal);
    vtkMath::Normalize(this->PickNormal);
    this->LastPick->DeepCopyFrom(this->Candidate);
  }
  return tMin;
}

void vtkDirectSurfacePicker::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LastPick:\n";
  this->LastPick->PrintSelf(os, indent.GetNextIndent());
}
