#include "vtkDirectSurfaceRepresentation.h"

#include "vtkActor.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCameraPass.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"
#include "vtkIceTCompositePass.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDirectSurfaceMapper.h"
#include "vtkDirectSurfaceReporting.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPVRenderView.h"
#include "vtkPointData.h"
#include "vtkPlane.h"
#include "vtkProperty.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkTransform.h"
#include "vtkUnstructuredGrid.h"

#include "tetdsr/input/MeshInput.h"
#include "tetdsr/render/LayerExchange.h"
#include "tetdsr/input/Settings.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkDirectSurfaceRepresentation);

namespace
{
using tetdsr::Messages;
using tetdsr::NumberSetting;

/// Whether `view` is between PrepareForScreenshot and CleanupAfterScreenshot (ParaView 5.11 keeps
/// the getter protected: reached through a member pointer named in a subclass's scope).
bool TakingScreenshot(vtkPVView* view)
{
  struct Access : vtkPVView
  {
    static bool Of(vtkPVView* view) { return (view->*(&Access::GetInCaptureScreenshot))(); }
  };
  return Access::Of(view);
}

/// The unstructured grids of an input (itself, or a composite's blocks).
std::vector<vtkUnstructuredGrid*> GridsOf(vtkDataObject* input)
{
  std::vector<vtkUnstructuredGrid*> grids;
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(input))
  {
    grids.push_back(grid);
  }
  else if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      if (auto* block = vtkUnstructuredGrid::SafeDownCast(it->GetCurrentDataObject()))
      {
        grids.push_back(block);
      }
    }
  }
  return grids;
}

/// `value` checked against `setting` by the core (clamped with a warning; NaN refused): true,
/// with the value to use in `used`, unless refused. The messages are reported as `object`'s.
bool CheckNumber(vtkObject* object, const NumberSetting& setting, double value, double& used)
{
  Messages messages;
  const bool ok = tetdsr::checkNumber(setting, value, used, messages);
  tetdsr::vtkadapter::ReportMessages(object, messages);
  return ok;
}

/// The same for three numbers (a colour, a position): refused if any is.
bool CheckNumbers(vtkObject* object, const NumberSetting& setting, const double values[3],
  double used[3])
{
  bool ok = true;
  for (int k = 0; k < 3; ++k)
  {
    ok = CheckNumber(object, setting, values[k], used[k]) && ok;
  }
  return ok;
}

constexpr double kHuge = 1.7976931348623157e308; // DBL_MAX: any finite number
}

//------------------------------------------------------------------------------
vtkDirectSurfaceRepresentation::vtkDirectSurfaceRepresentation()
{
  this->Actor->SetMapper(this->Mapper);
  this->Actor->SetProperty(this->Property);
  // Translucent surfaces are composited across the rendering processes (DrawTranslucent).
  this->Mapper->SetController(vtkMultiProcessController::GetGlobalController());
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
  this->InputTime = input ? input->GetMTime() : 0;
  this->HasInput = input != nullptr;
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::CheckInput()
{
  // What the check depends on besides the input: Contour By and the iso-values (to the bit).
  std::vector<double> isoValues(this->Mapper->GetNumberOfContours());
  std::ostringstream key;
  key.precision(17);
  key << this->ContourByAssociation << ":" << this->ContourByName;
  for (std::size_t k = 0; k < isoValues.size(); ++k)
  {
    isoValues[k] = this->Mapper->GetValue(static_cast<int>(k));
    key << " " << isoValues[k];
  }
  const std::string contourBy = key.str();
  if (!this->HasInput)
  {
    // Nothing connected (the client's copy in client-server mode, where the servers render the
    // data): nothing to say, and nothing to draw (its mapper would find an empty piece).
    this->InputDrawable = false;
    this->UpdateActorVisibility();
    return;
  }
  if (this->InputTime == this->CheckedInputTime && contourBy == this->CheckedContourBy)
  {
    return; // said once already
  }
  this->CheckedInputTime = this->InputTime;
  this->CheckedContourBy = contourBy;

  Messages messages;
  const std::vector<vtkUnstructuredGrid*> grids = GridsOf(this->Piece);
  vtkIdType points = 0, cells = 0;
  for (vtkUnstructuredGrid* grid : grids)
  {
    points += grid->GetNumberOfPoints();
    cells += grid->GetNumberOfCells();
  }
  // With several processes a piece may be empty while others hold the data: only the whole
  // input is empty, and this process cannot tell.
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const bool alone = !controller || controller->GetNumberOfProcesses() <= 1;
  const bool finite = vtkMath::AreBoundsInitialized(this->DataBounds) &&
    std::isfinite(this->DataBounds[0] + this->DataBounds[1] + this->DataBounds[2] +
      this->DataBounds[3] + this->DataBounds[4] + this->DataBounds[5]);
  bool ok = !alone ||
    (tetdsr::checkMeshNotEmpty(points, cells, messages) &&
      tetdsr::checkMeshHasFinitePoints(finite, cells, messages));
  ok = ok && cells > 0;
  if (ok && !this->ContourByName.empty())
  {
    // The first block that has the array decides (ParaView's array list is their union).
    vtkDataArray* array = nullptr;
    bool isPointArray = true;
    double lo = VTK_DOUBLE_MAX, hi = -VTK_DOUBLE_MAX; // the finite range over every block
    for (vtkUnstructuredGrid* grid : grids)
    {
      if (vtkDataArray* values = grid->GetPointData()->GetArray(this->ContourByName.c_str()))
      {
        double range[2];
        values->GetFiniteRange(range, 0);
        lo = std::min(lo, range[0]);
        hi = std::max(hi, range[1]);
      }
    }
    for (vtkUnstructuredGrid* grid : grids)
    {
      if ((array = grid->GetPointData()->GetArray(this->ContourByName.c_str())))
      {
        break;
      }
      if ((array = grid->GetCellData()->GetArray(this->ContourByName.c_str())))
      {
        isPointArray = false;
        break;
      }
    }
    int component = 0;
    if (!array)
    {
      tetdsr::reportMissingArray(tetdsr::InputArray::Field, this->ContourByName.c_str(), messages);
      ok = false;
    }
    else
    {
      ok = tetdsr::choosePointArrayComponent(this->ContourByName,
        isPointArray && this->ContourByAssociation != vtkDataObject::FIELD_ASSOCIATION_CELLS,
        array->GetNumberOfComponents(), -1, false,
        "an Extract Component filter (Contour By takes one)", component, messages);
      // A field constant at an iso-value draws nothing: say so (NaN-only fields are the
      // mapper's to report, cell by cell). A piece of several cannot tell.
      if (ok && alone && lo <= hi)
      {
        tetdsr::checkFieldNotConstantAtIsoValue(isoValues, lo, hi, this->ContourByName, messages);
      }
    }
  }
  tetdsr::vtkadapter::ReportMessages(this, messages);
  this->InputDrawable = ok;
  this->UpdateActorVisibility();
}

void vtkDirectSurfaceRepresentation::UpdateActorVisibility()
{
  this->Actor->SetVisibility(this->Visible && this->InputDrawable && this->DeliveredDrawable ? 1 : 0);
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
    this->CheckInput();
    // A screenshot is read back right after its render: exact then, shown at once and refined in
    // the background otherwise (in the GUI).
    auto* view = vtkPVView::SafeDownCast(inInfo->Get(vtkPVView::VIEW()));
    this->Mapper->SetSynchronousStillRenders(view && TakingScreenshot(view));
    vtkAlgorithmOutput* producer = vtkPVRenderView::GetPieceProducer(inInfo, this);
    this->Mapper->SetInputConnection(producer);
    // What the view delivered this render: a grid without cells (before the first delivery, as
    // ParaView Catalyst's first step showed, or a process's empty share) is not drawn, and not
    // reported again by the mapper (CheckInput spoke for the input).
    vtkDataObject* delivered = producer && producer->GetProducer()
      ? producer->GetProducer()->GetOutputDataObject(producer->GetIndex())
      : nullptr;
    auto* grid = vtkUnstructuredGrid::SafeDownCast(delivered);
    this->DeliveredDrawable = !grid || grid->GetNumberOfCells() > 0;
    this->UpdateActorVisibility();
    this->FollowOrderedCompositing();
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::FollowOrderedCompositing()
{
  // With another representation translucent, ParaView on several processes composites in order,
  // without depth (ordered compositing): the processes' pieces of an opaque surface would show
  // over each other whatever their depth, so the mapper composites them by depth itself.
  auto* view = vtkPVRenderView::SafeDownCast(this->GetView());
  const bool ordered = view && view->GetUseOrderedCompositing();
  this->Mapper->SetCompositeOpaqueAcrossProcesses(ordered);
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const bool warn = ordered && this->Visible && !this->IsTranslucent() && controller &&
    controller->GetLocalProcessId() == 0;
  if (warn && !this->WarnedOrderedCompositing)
  {
    tetdsr::Messages messages;
    tetdsr::describeOrderedCompositing(controller->GetNumberOfProcesses(), messages);
    tetdsr::vtkadapter::ReportMessages(this, messages);
  }
  this->WarnedOrderedCompositing = warn;
}

//------------------------------------------------------------------------------
bool vtkDirectSurfaceRepresentation::IsTranslucent()
{
  return this->Property->GetOpacity() < 1.0 || this->Mapper->HasTranslucentPolygonalGeometry();
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::DrawTranslucent(vtkObject* caller, unsigned long, void*)
{
  // After IceT has composited the processes' opaque images by depth (inside the renderer's
  // passes), before its image is shown or sent: every rendering process sends its crossings,
  // process 0 sorts them along each ray against the composited depth and blends them into the
  // composited image. Every process of the view renders each frame, and what is tested here is
  // the same on all of them (the proxies' properties), so all take part or none.
  vtkMultiProcessController* controller = this->Mapper->GetController();
  auto* renderer = vtkRenderer::SafeDownCast(caller);
  if (!renderer || !controller || controller->GetNumberOfProcesses() < 2 || !this->Visible ||
    !(this->IsTranslucent() || this->Mapper->GetCompositeOpaqueAcrossProcesses()))
  {
    return;
  }
  // The composited depth, on process 0: IceT's, behind the renderer's camera pass.
  vtkRenderPass* pass = renderer->GetPass();
  if (auto* camera = vtkCameraPass::SafeDownCast(pass))
  {
    pass = camera->GetDelegatePass();
  }
  // Its image (premultiplied RGBA, shared with the pass) is what process 0 shows and what a
  // client is sent: the surfaces are blended into it before either happens.
  const float* depth = nullptr;
  unsigned char* colors = nullptr;
  int size[2] = { 0, 0 };
  if (auto* icet = vtkIceTCompositePass::SafeDownCast(pass))
  {
    vtkSynchronizedRenderers::vtkRawImage tile;
    icet->GetLastRenderedTile(tile);
    const vtkIdType pixels = static_cast<vtkIdType>(tile.GetWidth()) * tile.GetHeight();
    if (tile.IsValid() && tile.GetRawPtr()->GetNumberOfComponents() == 4 &&
      tile.GetRawPtr()->GetNumberOfTuples() >= pixels) // (a reduced image keeps the buffer)
    {
      colors = tile.GetRawPtr()->GetPointer(0);
      size[0] = tile.GetWidth();
      size[1] = tile.GetHeight();
      // No depth when IceT blends the processes' images in order (ParaView's ordered
      // compositing, when another representation is translucent): the mapper composites the
      // processes' own opaque depth then.
      vtkFloatArray* depths = icet->GetLastRenderedDepths();
      depth = depths && depths->GetNumberOfTuples() == pixels ? depths->GetPointer(0) : nullptr;
    }
  }
  this->Mapper->DrawTranslucentAcrossProcesses(renderer, this->Actor, depth, colors, size);
}

//------------------------------------------------------------------------------
bool vtkDirectSurfaceRepresentation::AddToView(vtkView* view)
{
  if (auto* renderView = vtkPVRenderView::SafeDownCast(view))
  {
    renderView->GetRenderer()->AddActor(this->Actor);
    // Selection (Select Cells / Points On, hovering): the actor's pixels name this representation.
    renderView->RegisterPropForHardwareSelection(this, this->Actor);
    this->Renderer = renderView->GetRenderer();
    if (vtkPVView::GetUseGenericOpenGLRenderWindow())
    {
      // The GUI (pqApplicationCore asks for windows embedded in its widgets): the interactor's
      // event loop runs, so that even the first render of the surface is shown at once and
      // refined in the background.
      this->Mapper->DeclareEventLoopRuns(renderView->GetInteractor());
    }
    // Before the synchronized renderers' own EndEvent observers (priority 0), which put IceT's
    // composited image on process 0's screen and send it to a client.
    this->DrawTranslucentTag = this->Renderer->AddObserver(
      vtkCommand::EndEvent, this, &vtkDirectSurfaceRepresentation::DrawTranslucent, 1.0);
    return this->Superclass::AddToView(view);
  }
  return false;
}

bool vtkDirectSurfaceRepresentation::RemoveFromView(vtkView* view)
{
  if (auto* renderView = vtkPVRenderView::SafeDownCast(view))
  {
    renderView->GetRenderer()->RemoveActor(this->Actor);
    renderView->UnRegisterPropForHardwareSelection(this, this->Actor);
    if (this->Renderer)
    {
      this->Renderer->RemoveObserver(this->DrawTranslucentTag);
      this->Renderer = nullptr;
    }
    return this->Superclass::RemoveFromView(view);
  }
  return false;
}

void vtkDirectSurfaceRepresentation::SetVisibility(bool visible)
{
  this->Superclass::SetVisibility(visible);
  this->Visible = visible;
  this->UpdateActorVisibility();
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::SetContourBy(
  int, int, int, int fieldAssociation, const char* name)
{
  this->Mapper->SetInputArrayToProcess(0, 0, 0, fieldAssociation, name);
  this->ContourByAssociation = fieldAssociation;
  this->ContourByName = name ? name : "";
}

void vtkDirectSurfaceRepresentation::SetContourValue(int i, double value)
{
  this->Mapper->SetValue(i, value);
}

void vtkDirectSurfaceRepresentation::SetNumberOfContours(int number)
{
  this->Mapper->SetNumberOfContours(number);
}

void vtkDirectSurfaceRepresentation::SetIsoValueColorsCount(int count)
{
  Messages messages;
  this->IsoValueColorsRefused = !tetdsr::checkGroupedCount(
    "IsoValueColors", count, 3, "iso-value: red, green, blue", messages);
  tetdsr::vtkadapter::ReportMessages(this, messages);
}

void vtkDirectSurfaceRepresentation::SetIsoValueColor(int i, double red, double green, double blue)
{
  const double color[3] = { red, green, blue };
  double used[3];
  if (!this->IsoValueColorsRefused &&
    CheckNumbers(this, NumberSetting{ "IsoValueColors", 0.0, 1.0 }, color, used))
  {
    this->Mapper->SetIsoValueColor(i, used[0], used[1], used[2]);
  }
}

void vtkDirectSurfaceRepresentation::RemoveAllIsoValueColors()
{
  this->Mapper->RemoveAllIsoValueColors();
}

void vtkDirectSurfaceRepresentation::SetIsoValueOpacity(int i, double opacity)
{
  double used;
  if (CheckNumber(this, NumberSetting{ "IsoValueOpacities", 0.0, 1.0 }, opacity, used))
  {
    this->Mapper->SetIsoValueOpacity(i, used);
  }
}

void vtkDirectSurfaceRepresentation::RemoveAllIsoValueOpacities()
{
  this->Mapper->RemoveAllIsoValueOpacities();
}

void vtkDirectSurfaceRepresentation::SetClipPlanesCount(int count)
{
  Messages messages;
  this->ClipPlanesRefused = !tetdsr::checkGroupedCount(
    "ClipPlanes", count, 6, "plane: a point and a normal", messages);
  tetdsr::vtkadapter::ReportMessages(this, messages);
}

void vtkDirectSurfaceRepresentation::AddClipPlane(
  double x, double y, double z, double nx, double ny, double nz)
{
  if (this->ClipPlanesRefused)
  {
    return;
  }
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
void vtkDirectSurfaceRepresentation::SetAutoAdjustSampleDistances(int adjust)
{
  this->Mapper->SetAutoAdjustSampleDistances(adjust != 0);
}

void vtkDirectSurfaceRepresentation::SetInteractiveImageSampleDistance(double distance)
{
  this->Mapper->SetInteractiveImageSampleDistance(distance);
}

double vtkDirectSurfaceRepresentation::GetLastImageSampleDistance()
{
  return this->Mapper->GetLastImageSampleDistance();
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::SetOpacity(double opacity)
{
  double used;
  if (CheckNumber(this, tetdsr::kOpacity, opacity, used))
  {
    this->Property->SetOpacity(used);
  }
}

void vtkDirectSurfaceRepresentation::SetAmbientColor(double red, double green, double blue)
{
  const double color[3] = { red, green, blue };
  double used[3];
  if (CheckNumbers(this, NumberSetting{ "AmbientColor", 0.0, 1.0 }, color, used))
  {
    this->Property->SetAmbientColor(used);
  }
}

void vtkDirectSurfaceRepresentation::SetDiffuseColor(double red, double green, double blue)
{
  const double color[3] = { red, green, blue };
  double used[3];
  if (CheckNumbers(this, NumberSetting{ "DiffuseColor", 0.0, 1.0 }, color, used))
  {
    this->Property->SetDiffuseColor(used);
  }
}

void vtkDirectSurfaceRepresentation::SetSpecularColor(double red, double green, double blue)
{
  const double color[3] = { red, green, blue };
  double used[3];
  if (CheckNumbers(this, NumberSetting{ "SpecularColor", 0.0, 1.0 }, color, used))
  {
    this->Property->SetSpecularColor(used);
  }
}

void vtkDirectSurfaceRepresentation::SetAmbient(double ambient)
{
  double used;
  if (CheckNumber(this, tetdsr::kAmbient, ambient, used))
  {
    this->Property->SetAmbient(used);
  }
}

void vtkDirectSurfaceRepresentation::SetDiffuse(double diffuse)
{
  double used;
  if (CheckNumber(this, tetdsr::kDiffuse, diffuse, used))
  {
    this->Property->SetDiffuse(used);
  }
}

void vtkDirectSurfaceRepresentation::SetSpecular(double specular)
{
  double used;
  if (CheckNumber(this, tetdsr::kSpecular, specular, used))
  {
    this->Property->SetSpecular(used);
  }
}

void vtkDirectSurfaceRepresentation::SetSpecularPower(double power)
{
  double used;
  if (CheckNumber(this, tetdsr::kSpecularPower, power, used))
  {
    this->Property->SetSpecularPower(used);
  }
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRepresentation::SetPosition(double x, double y, double z)
{
  const double values[3] = { x, y, z };
  double used[3];
  if (CheckNumbers(this, NumberSetting{ "Position", -kHuge, kHuge }, values, used))
  {
    this->Actor->SetPosition(used);
  }
}

void vtkDirectSurfaceRepresentation::SetOrientation(double x, double y, double z)
{
  const double values[3] = { x, y, z };
  double used[3];
  if (CheckNumbers(this, NumberSetting{ "Orientation", -kHuge, kHuge }, values, used))
  {
    this->Actor->SetOrientation(used);
  }
}

void vtkDirectSurfaceRepresentation::SetOrigin(double x, double y, double z)
{
  const double values[3] = { x, y, z };
  double used[3];
  if (CheckNumbers(this, NumberSetting{ "Origin", -kHuge, kHuge }, values, used))
  {
    this->Actor->SetOrigin(used);
  }
}

void vtkDirectSurfaceRepresentation::SetScale(double x, double y, double z)
{
  const double values[3] = { x, y, z };
  double used[3];
  if (CheckNumbers(this, NumberSetting{ "Scale", -kHuge, kHuge }, values, used))
  {
    this->Actor->SetScale(used);
  }
}

void vtkDirectSurfaceRepresentation::SetUserTransform(const double matrix[16])
{
  double used[16];
  bool ok = true;
  for (int k = 0; k < 16; ++k)
  {
    ok = CheckNumber(this, NumberSetting{ "UserTransform", -kHuge, kHuge }, matrix[k], used[k]) &&
      ok;
  }
  if (!ok)
  {
    return;
  }
  vtkNew<vtkTransform> transform;
  transform->SetMatrix(used);
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
  os << indent << "Visible: " << this->Visible << "\n";
  os << indent << "ContourBy: " << this->ContourByAssociation << " '" << this->ContourByName
     << "'\n";
  os << indent << "InputDrawable: " << this->InputDrawable << "\n";
  os << indent << "IsoValueColorsRefused: " << this->IsoValueColorsRefused << "\n";
  os << indent << "ClipPlanesRefused: " << this->ClipPlanesRefused << "\n";
  os << indent << "DataBounds: (" << this->DataBounds[0] << ", " << this->DataBounds[1] << ", "
     << this->DataBounds[2] << ", " << this->DataBounds[3] << ", " << this->DataBounds[4] << ", "
     << this->DataBounds[5] << ")\n";
}
