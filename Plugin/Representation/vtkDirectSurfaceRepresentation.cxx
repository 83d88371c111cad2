#include "vtkDirectSurfaceRepresentation.h"

#include "vtkActor.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataSet.h"
#include "vtkDirectSurfaceMapper.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPVRenderView.h"
#include "vtkPlane.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkTransform.h"
#include "vtkUnstructuredGrid.h"

vtkStandardNewMacro(vtkDirectSurfaceRepresentation);

//------------------------------------------------------------------------------
vtkDirectSurfaceRepresentation::vtkDirectSurfaceRepresentation()
{
  this->Actor->SetMapper(this->Mapper);
  this->Actor->SetProperty(this->Property);
  this->Piece = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkMath::UninitializeBounds(this->DataBounds);
}

vtkDirectSurfaceRepresentation::~vtkDirectSurfaceRepresentation() = default;

//------------------------------------------------------------------------------
int vtkDirectSurfaceRepresentation::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkDirectSurfaceRepresentation::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The piece is the input itself (a shallow copy, so that the pipeline may re-execute): the
  // mapper renders quadratic cells as they are, so there is nothing to extract or convert.
  vtkMath::UninitializeBounds(this->DataBounds);
  vtkDataObject* input = inputVector[0]->GetNumberOfInformationObjects() == 1
    ? vtkDataObject::GetData(inputVector[0], 0)
    : nullptr;
  if (input)
  {
    this->Piece.TakeReference(input->NewInstance());
    this->Piece->ShallowCopy(input);
    if (auto* dataSet = vtkDataSet::SafeDownCast(input))
    {
      dataSet->GetBounds(this->DataBounds);
    }
    else if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
    {
      composite->GetBounds(this->DataBounds);
    }
  }
  else
  {
    this->Piece = vtkSmartPointer<vtkUnstructuredGrid>::New();
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkDirectSurfaceRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request, inInfo, outInfo))
  {
    return 0;
  }
  if (request == vtkPVView::REQUEST_UPDATE())
  {
    vtkPVRenderView::SetPiece(inInfo, this, this->Piece);
    vtkNew<vtkMatrix4x4> matrix;
    this->Actor->GetMatrix(matrix);
    vtkPVRenderView::SetGeometryBounds(inInfo, this, this->DataBounds, matrix);
    // Render where the data is: never ship the mesh to the client or to another rank.
    vtkPVRenderView::SetRequiresDistributedRendering(inInfo, this, true);
  }
  else if (request == vtkPVView::REQUEST_UPDATE_LOD())
  {
    // No decimated stand-in: the mapper lowers its own resolution while interacting.
    vtkPVRenderView::SetRequiresDistributedRenderingLOD(inInfo, this, true);
  }
  else if (request == vtkPVView::REQUEST_RENDER())
  {
    this->Mapper->SetInputConnection(vtkPVRenderView::GetPieceProducer(inInfo, this));
    this->WarnIfTranslucencyIsLost();
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::WarnIfTranslucencyIsLost()
{
  // The mapper blends translucent surfaces after its renderer's passes; with several rendering
  // ranks ParaView has composited the ranks' images (IceT) by then, so they would not be seen.
  auto* view = vtkPVRenderView::SafeDownCast(this->GetView());
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const bool translucent =
    this->Property->GetOpacity() < 1.0 || this->Mapper->HasTranslucentPolygonalGeometry();
  if (translucent && !this->WarnedTranslucencyLost && view &&
    view->GetUseDistributedRenderingForRender() && controller &&
    controller->GetNumberOfProcesses() > 1)
  {
    vtkWarningMacro("Translucent Direct Surface (Opacity or an iso-value opacity below 1) is not "
                    "composited across the "
      << controller->GetNumberOfProcesses()
      << " rendering processes: it is not shown. Make it opaque, or render on one process.");
    this->WarnedTranslucencyLost = true;
  }
}

//------------------------------------------------------------------------------
bool vtkDirectSurfaceRepresentation::AddToView(vtkView* view)
{
  if (auto* renderView = vtkPVRenderView::SafeDownCast(view))
  {
    renderView->GetRenderer()->AddActor(this->Actor);
    return this->Superclass::AddToView(view);
  }
  return false;
}

bool vtkDirectSurfaceRepresentation::RemoveFromView(vtkView* view)
{
  if (auto* renderView = vtkPVRenderView::SafeDownCast(view))
  {
    renderView->GetRenderer()->RemoveActor(this->Actor);
    return this->Superclass::RemoveFromView(view);
  }
  return false;
}

void vtkDirectSurfaceRepresentation::SetVisibility(bool visible)
{
  this->Superclass::SetVisibility(visible);
  this->Actor->SetVisibility(visible ? 1 : 0);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::SetContourBy(
  int, int, int, int fieldAssociation, const char* name)
{
  this->Mapper->SetInputArrayToProcess(0, 0, 0, fieldAssociation, name);
}

void vtkDirectSurfaceRepresentation::SetContourValue(int i, double value)
{
  this->Mapper->SetValue(i, value);
}

void vtkDirectSurfaceRepresentation::SetNumberOfContours(int number)
{
  this->Mapper->SetNumberOfContours(number);
}

void vtkDirectSurfaceRepresentation::SetIsoValueColor(int i, double red, double green, double blue)
{
  this->Mapper->SetIsoValueColor(i, red, green, blue);
}

void vtkDirectSurfaceRepresentation::RemoveAllIsoValueColors()
{
  this->Mapper->RemoveAllIsoValueColors();
}

void vtkDirectSurfaceRepresentation::SetIsoValueOpacity(int i, double opacity)
{
  this->Mapper->SetIsoValueOpacity(i, opacity);
}

void vtkDirectSurfaceRepresentation::RemoveAllIsoValueOpacities()
{
  this->Mapper->RemoveAllIsoValueOpacities();
}

void vtkDirectSurfaceRepresentation::AddClipPlane(
  double x, double y, double z, double nx, double ny, double nz)
{
  vtkNew<vtkPlane> plane;
  plane->SetOrigin(x, y, z);
  plane->SetNormal(nx, ny, nz);
  this->Mapper->AddClippingPlane(plane);
}

void vtkDirectSurfaceRepresentation::RemoveAllClipPlanes()
{
  this->Mapper->RemoveAllClippingPlanes();
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::SetInputArrayToProcess(
  int index, int port, int connection, int fieldAssociation, const char* name)
{
  this->Superclass::SetInputArrayToProcess(index, port, connection, fieldAssociation, name);
  if (index != 0)
  {
    return;
  }
  const bool colored = name && name[0];
  this->Mapper->SetScalarVisibility(colored ? 1 : 0);
  this->Mapper->SelectColorArray(colored ? name : nullptr);
  this->Mapper->SetScalarMode(fieldAssociation == vtkDataObject::FIELD_ASSOCIATION_CELLS
      ? VTK_SCALAR_MODE_USE_CELL_FIELD_DATA
      : VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
  // ParaView rescales the lookup table itself (Color Map Editor, automatic rescaling).
  this->Mapper->SetUseLookupTableScalarRange(1);
}

void vtkDirectSurfaceRepresentation::SetLookupTable(vtkScalarsToColors* lookupTable)
{
  this->Mapper->SetLookupTable(lookupTable);
}

void vtkDirectSurfaceRepresentation::SetMapScalars(int map)
{
  this->Mapper->SetColorMode(map ? VTK_COLOR_MODE_MAP_SCALARS : VTK_COLOR_MODE_DIRECT_SCALARS);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::SetOpacity(double opacity)
{
  this->Property->SetOpacity(opacity);
}

void vtkDirectSurfaceRepresentation::SetAmbientColor(double red, double green, double blue)
{
  this->Property->SetAmbientColor(red, green, blue);
}

void vtkDirectSurfaceRepresentation::SetDiffuseColor(double red, double green, double blue)
{
  this->Property->SetDiffuseColor(red, green, blue);
}

void vtkDirectSurfaceRepresentation::SetSpecularColor(double red, double green, double blue)
{
  this->Property->SetSpecularColor(red, green, blue);
}

void vtkDirectSurfaceRepresentation::SetAmbient(double ambient)
{
  this->Property->SetAmbient(ambient);
}

void vtkDirectSurfaceRepresentation::SetDiffuse(double diffuse)
{
  this->Property->SetDiffuse(diffuse);
}

void vtkDirectSurfaceRepresentation::SetSpecular(double specular)
{
  this->Property->SetSpecular(specular);
}

void vtkDirectSurfaceRepresentation::SetSpecularPower(double power)
{
  this->Property->SetSpecularPower(power);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::SetPosition(double x, double y, double z)
{
  this->Actor->SetPosition(x, y, z);
}

void vtkDirectSurfaceRepresentation::SetOrientation(double x, double y, double z)
{
  this->Actor->SetOrientation(x, y, z);
}

void vtkDirectSurfaceRepresentation::SetOrigin(double x, double y, double z)
{
  this->Actor->SetOrigin(x, y, z);
}

void vtkDirectSurfaceRepresentation::SetScale(double x, double y, double z)
{
  this->Actor->SetScale(x, y, z);
}

void vtkDirectSurfaceRepresentation::SetUserTransform(const double matrix[16])
{
  vtkNew<vtkTransform> transform;
  transform->SetMatrix(matrix);
  this->Actor->SetUserTransform(transform);
}

void vtkDirectSurfaceRepresentation::SetPickable(int pickable)
{
  this->Actor->SetPickable(pickable);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mapper:\n";
  this->Mapper->PrintSelf(os, indent.GetNextIndent());
  os << indent << "Actor: " << this->Actor.GetPointer() << "\n";
  os << indent << "Property: " << this->Property.GetPointer() << "\n";
  os << indent << "Piece: " << this->Piece.GetPointer() << "\n";
  os << indent << "WarnedTranslucencyLost: " << this->WarnedTranslucencyLost << "\n";
  os << indent << "DataBounds: (" << this->DataBounds[0] << ", " << this->DataBounds[1] << ", "
     << this->DataBounds[2] << ", " << this->DataBounds[3] << ", " << this->DataBounds[4] << ", "
     << this->DataBounds[5] << ")\n";
}
