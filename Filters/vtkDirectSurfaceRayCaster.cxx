#include "vtkDirectSurfaceRayCaster.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkColorTransferFunction.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include "vtkDirectSurfaceAdapter.h"

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

static_assert(std::is_same<vtkIdType, tetdsr::NodeId>::value,
  "TetDSR needs VTK built with 64-bit ids (VTK_USE_64BIT_IDS)");

vtkStandardNewMacro(vtkDirectSurfaceRayCaster);
vtkCxxSetObjectMacro(vtkDirectSurfaceRayCaster, Camera, vtkCamera);
vtkCxxSetObjectMacro(vtkDirectSurfaceRayCaster, LookupTable, vtkScalarsToColors);
vtkCxxSetObjectMacro(vtkDirectSurfaceRayCaster, ClippingPlanes, vtkPlaneCollection);

/// The prepared mesh (see vtkDirectSurfaceAdapter.h), kept across updates.
struct vtkDirectSurfaceRayCaster::Cache
{
  tetdsr::vtkadapter::PreparedMesh Mesh;
  tetdsr::vtkadapter::IsoValueStyles Styles;
};

namespace
{
namespace adapter = tetdsr::vtkadapter;

// Bytes per output pixel: Colors (4), Depth (8), Normals (24), CellId (8), ColorValues (8), and
// the depth-buffer normals' per-pixel record (64).
constexpr double kBytesPerPixel = 4 + 8 + 24 + 8 + 8 + 64;

/// One of the built-in colour maps over [0, 1].
vtkSmartPointer<vtkScalarsToColors> BuiltInColorMap(int which)
{
  auto map = vtkSmartPointer<vtkColorTransferFunction>::New();
  switch (which)
  {
    case vtkDirectSurfaceRayCaster::RAINBOW:
      map->SetColorSpaceToHSV();
      map->AddRGBPoint(0.0, 0.0, 0.0, 1.0);
      map->AddRGBPoint(1.0, 1.0, 0.0, 0.0);
      break;
    case vtkDirectSurfaceRayCaster::GRAYSCALE:
      map->AddRGBPoint(0.0, 0.0, 0.0, 0.0);
      map->AddRGBPoint(1.0, 1.0, 1.0, 1.0);
      break;
    case vtkDirectSurfaceRayCaster::BLACK_BODY:
      map->AddRGBPoint(0.0, 0.0, 0.0, 0.0);
      map->AddRGBPoint(0.4, 0.9, 0.0, 0.0);
      map->AddRGBPoint(0.8, 0.9, 0.9, 0.0);
      map->AddRGBPoint(1.0, 1.0, 1.0, 1.0);
      break;
    case vtkDirectSurfaceRayCaster::COOL_TO_WARM:
    default:
      // Moreland's diverging map: blue (0.230, 0.299, 0.754) to red (0.706, 0.016, 0.150).
      map->SetColorSpaceToDiverging();
      map->AddRGBPoint(0.0, 0.230, 0.299, 0.754);
      map->AddRGBPoint(1.0, 0.706, 0.016, 0.150);
      break;
  }
  map->SetNanColor(0.5, 0.5, 0.5);
  return map;
}

/// Reports the adapter's messages through this algorithm's error and warning macros.
#define REPORT_MESSAGES(messages)                                                                  \
  do                                                                                               \
  {                                                                                                \
    for (const std::string& text : (messages).warnings)                                            \
    {                                                                                              \
      vtkWarningMacro(<< text);                                                                    \
    }                                                                                              \
    for (const std::string& text : (messages).errors)                                              \
    {                                                                                              \
      vtkErrorMacro(<< text);                                                                      \
    }                                                                                              \
    (messages) = adapter::Messages();                                                              \
  } while (false)
}

//------------------------------------------------------------------------------
vtkDirectSurfaceRayCaster::vtkDirectSurfaceRayCaster()
  : ContourValues(vtkContourValues::New())
  , Prepared(new Cache)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS,
    vtkDataSetAttributes::SCALARS);
}

//------------------------------------------------------------------------------
vtkDirectSurfaceRayCaster::~vtkDirectSurfaceRayCaster()
{
  this->ContourValues->Delete();
  this->SetCamera(nullptr);
  this->SetLookupTable(nullptr);
  this->SetClippingPlanes(nullptr);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRayCaster::SetIsoValueColor(int i, double red, double green, double blue)
{
  adapter::Messages messages;
  if (this->Prepared->Styles.SetColor(i, red, green, blue, messages))
  {
    this->Modified();
  }
  REPORT_MESSAGES(messages);
}

void vtkDirectSurfaceRayCaster::GetIsoValueColor(int i, double color[3])
{
  this->Prepared->Styles.GetColor(i, this->SurfaceColor, color);
}

void vtkDirectSurfaceRayCaster::RemoveAllIsoValueColors()
{
  if (this->Prepared->Styles.RemoveAllColors())
  {
    this->Modified();
  }
}

void vtkDirectSurfaceRayCaster::SetIsoValueOpacity(int i, double opacity)
{
  adapter::Messages messages;
  if (this->Prepared->Styles.SetOpacity(i, opacity, messages))
  {
    this->Modified();
  }
  REPORT_MESSAGES(messages);
}

double vtkDirectSurfaceRayCaster::GetIsoValueOpacity(int i)
{
  return this->Prepared->Styles.GetOpacity(i);
}

void vtkDirectSurfaceRayCaster::RemoveAllIsoValueOpacities()
{
  if (this->Prepared->Styles.RemoveAllOpacities())
  {
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRayCaster::AddClippingPlane(vtkPlane* plane)
{
  if (!this->ClippingPlanes)
  {
    vtkNew<vtkPlaneCollection> planes;
    this->SetClippingPlanes(planes);
  }
  this->ClippingPlanes->AddItem(plane);
  this->Modified();
}

void vtkDirectSurfaceRayCaster::RemoveAllClippingPlanes()
{
  if (this->ClippingPlanes && this->ClippingPlanes->GetNumberOfItems() > 0)
  {
    this->ClippingPlanes->RemoveAllItems();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRayCaster::SetValue(int i, double value)
{
  this->ContourValues->SetValue(i, value);
}
double vtkDirectSurfaceRayCaster::GetValue(int i)
{
  return this->ContourValues->GetValue(i);
}
double* vtkDirectSurfaceRayCaster::GetValues()
{
  return this->ContourValues->GetValues();
}
void vtkDirectSurfaceRayCaster::GetValues(double* contourValues)
{
  this->ContourValues->GetValues(contourValues);
}
void vtkDirectSurfaceRayCaster::SetNumberOfContours(int number)
{
  this->ContourValues->SetNumberOfContours(number);
}
vtkIdType vtkDirectSurfaceRayCaster::GetNumberOfContours()
{
  return this->ContourValues->GetNumberOfContours();
}
void vtkDirectSurfaceRayCaster::GenerateValues(int numContours, double range[2])
{
  this->ContourValues->GenerateValues(numContours, range);
}
void vtkDirectSurfaceRayCaster::GenerateValues(int numContours, double rangeStart, double rangeEnd)
{
  this->ContourValues->GenerateValues(numContours, rangeStart, rangeEnd);
}

//------------------------------------------------------------------------------
vtkIdType vtkDirectSurfaceRayCaster::GetPreprocessedBytes()
{
  return this->Prepared ? static_cast<vtkIdType>(this->Prepared->Mesh.MemoryBytes()) : 0;
}

//------------------------------------------------------------------------------
vtkMTimeType vtkDirectSurfaceRayCaster::GetMTime()
{
  vtkMTimeType time = std::max(this->Superclass::GetMTime(), this->ContourValues->GetMTime());
  if (this->Camera)
  {
    time = std::max(time, this->Camera->GetMTime());
  }
  if (this->LookupTable)
  {
    time = std::max(time, this->LookupTable->GetMTime());
  }
  if (this->ClippingPlanes)
  {
    time = std::max(time, this->ClippingPlanes->GetMTime());
    for (int k = 0; k < this->ClippingPlanes->GetNumberOfItems(); ++k)
    {
      time = std::max(time, this->ClippingPlanes->GetItem(k)->GetMTime());
    }
  }
  return time;
}

//------------------------------------------------------------------------------
int vtkDirectSurfaceRayCaster::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

//------------------------------------------------------------------------------
int vtkDirectSurfaceRayCaster::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  adapter::Messages messages;
  if (!adapter::CheckImageSize(
        this->ImageSize[0], this->ImageSize[1], kBytesPerPixel, "ImageSize", messages))
  {
    REPORT_MESSAGES(messages);
    return 0;
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int extent[6] = { 0, this->ImageSize[0] - 1, 0, this->ImageSize[1] - 1, 0, 0 };
  const double spacing[3] = { 1.0, 1.0, 1.0 };
  const double origin[3] = { 0.0, 0.0, 0.0 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_UNSIGNED_CHAR, 4);
  return 1;
}

//------------------------------------------------------------------------------
vtkDataArray* vtkDirectSurfaceRayCaster::GetPointArray(
  int index, vtkInformationVector** inputVector, int& association)
{
  vtkDataArray* array = this->GetInputArrayToProcess(index, inputVector, association);
  if (array)
  {
    return array;
  }
  vtkInformation* info = this->GetInputArrayInformation(index);
  const char* name =
    info->Has(vtkDataObject::FIELD_NAME()) ? info->Get(vtkDataObject::FIELD_NAME()) : nullptr;
  if (index == 0 && name)
  {
    vtkErrorMacro("No point array named '" << name << "' in the input.");
  }
  else if (index == 0)
  {
    vtkErrorMacro("No point scalars: the input has no active point scalars; choose an array "
                  "with SetInputArrayToProcess(0, 0, 0, FIELD_ASSOCIATION_POINTS, name).");
  }
  else
  {
    vtkErrorMacro("ColorByArray is on but "
      << (name ? "there is no point array named '" + std::string(name) + "'"
               : std::string("no colour array is chosen"))
      << ": choose one with SetInputArrayToProcess(1, 0, 0, FIELD_ASSOCIATION_POINTS, name).");
  }
  return nullptr;
}

//------------------------------------------------------------------------------
int vtkDirectSurfaceRayCaster::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  const int width = this->ImageSize[0]; // RequestInformation checked the size
  const int height = this->ImageSize[1];
  adapter::Messages messages;
  if (!input || input->GetNumberOfCells() == 0 || input->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro("The input mesh is empty: it has no cells or no points.");
    return 0;
  }

  // The field, its iso-values, the colour array and the clipping planes.
  int association = -1;
  vtkDataArray* scalars = this->GetPointArray(0, inputVector, association);
  int component = 0;
  std::vector<double> values;
  if (!scalars ||
    !adapter::CheckPointArray(
      scalars, association, this->ArrayComponent, false, "ArrayComponent", component, messages) ||
    !adapter::ConvertIsoValues(this->ContourValues, values, messages))
  {
    REPORT_MESSAGES(messages);
    return 0;
  }
  vtkDataArray* colorArray = nullptr;
  int colorComponent = -1;
  if (this->ColorByArray)
  {
    int colorAssociation = -1;
    colorArray = this->GetPointArray(1, inputVector, colorAssociation);
    if (!colorArray ||
      !adapter::CheckPointArray(colorArray, colorAssociation, this->ColorArrayComponent, true,
        "ColorArrayComponent", colorComponent, messages))
    {
      REPORT_MESSAGES(messages);
      return 0;
    }
  }
  std::vector<tetdsr::ClipPlane> clipPlanes;
  if (!adapter::ConvertClipPlanes(
        this->ClippingPlanes, MaximumNumberOfClippingPlanes, clipPlanes, messages))
  {
    REPORT_MESSAGES(messages);
    return 0;
  }

  // Preprocess once per mesh, array and transverse test.
  tetdsr::TransverseTest transverse;
  transverse.mode = this->TransverseTest == WIDENED_NODAL_RANGE
    ? tetdsr::TransverseTest::Mode::WidenedNodalRange
    : tetdsr::TransverseTest::Mode::BernsteinBound;
  transverse.widening = this->NodalRangeWidening;
  adapter::PreparedMesh& prepared = this->Prepared->Mesh;
  const bool ready =
    prepared.Prepare(input, scalars, component, transverse, this->NumberOfThreads, messages);
  const tetdsr::PreprocessSummary& summary = prepared.GetSummary();
  this->NumberOfRenderedCells = ready ? summary.validCells : 0;
  this->NumberOfInvertedCells = summary.invertedCells;
  this->NumberOfCurvedCells = summary.curvedCells;
  this->NumberOfDegenerateCells = summary.degenerateCells;
  this->NumberOfOutOfScaleCells = summary.outOfScaleCells;
  this->NumberOfNonFiniteCells = summary.nonFiniteCells;
  this->NumberOfInvalidIdCells = summary.invalidIdCells;
  this->NumberOfUnsupportedCells = prepared.GetUnsupportedCells();
  this->NumberOfMalformedCells = prepared.GetMalformedCells();
  const double* colorValues = colorArray && ready
    ? prepared.PointArrayValues(colorArray, "colour array", messages)
    : nullptr;
  if (!messages.ok() || !ready)
  {
    REPORT_MESSAGES(messages);
    return 0;
  }
  REPORT_MESSAGES(messages); // the warnings
  tetdsr::Scene& scene = *prepared.GetScene();

  // Camera: the user's, or one that sees every rendered cell (points no cell uses do not count).
  tetdsr::Camera camera;
  if (this->Camera)
  {
    double v[3];
    this->Camera->GetPosition(v);
    camera.position = glm::dvec3(v[0], v[1], v[2]);
    this->Camera->GetFocalPoint(v);
    camera.focalPoint = glm::dvec3(v[0], v[1], v[2]);
    this->Camera->GetViewUp(v);
    camera.viewUp = glm::dvec3(v[0], v[1], v[2]);
    camera.viewAngleDegrees = this->Camera->GetViewAngle();
    camera.parallelProjection = this->Camera->GetParallelProjection() != 0;
    camera.parallelScale = this->Camera->GetParallelScale();
  }
  else
  {
    double bounds[6];
    scene.bounds(bounds);
    camera = tetdsr::resetCamera(bounds, static_cast<double>(width) / height);
  }
  if (!adapter::CheckCamera(camera, scene, messages))
  {
    REPORT_MESSAGES(messages);
    return 0;
  }

  // Output arrays, written in place by the core.
  output->SetExtent(0, width - 1, 0, height - 1, 0, 0);
  const vtkIdType pixels = static_cast<vtkIdType>(width) * height;
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(4);
  vtkNew<vtkDoubleArray> depth;
  depth->SetName("Depth");
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  vtkNew<vtkIdTypeArray> cellIds;
  cellIds->SetName("CellId");
  vtkNew<vtkDoubleArray> colorValueImage;
  colorValueImage->SetName("ColorValues");
  const bool colorMapped = colorArray || (this->Capping != NO_CAP && !clipPlanes.empty());
  auto allocate = [pixels](vtkDataArray* array) {
    if (!array->Allocate(pixels * array->GetNumberOfComponents()))
    {
      return false;
    }
    array->SetNumberOfTuples(pixels);
    return true;
  };
  const bool allocated = allocate(colors) && allocate(depth) && allocate(normals) &&
    allocate(cellIds) && (!colorMapped || allocate(colorValueImage));
  if (!allocated)
  {
    vtkErrorMacro("Cannot allocate the " << width << " x " << height << " output image.");
    return 0;
  }
  vtkPointData* pointData = output->GetPointData();
  pointData->Initialize();
  pointData->SetScalars(colors);
  pointData->AddArray(depth);
  pointData->SetNormals(normals);
  pointData->AddArray(cellIds);
  if (colorMapped)
  {
    pointData->AddArray(colorValueImage);
  }

  tetdsr::ImageView image;
  image.width = width;
  image.height = height;
  image.colors = colors->GetPointer(0);
  image.depth = depth->GetPointer(0);
  image.normals = normals->GetPointer(0);
  image.cellIds = cellIds->GetPointer(0);
  image.colorValues = colorMapped ? colorValueImage->GetPointer(0) : nullptr;

  tetdsr::RenderSettings settings;
  tetdsr::Material& material = settings.material;
  material.color = glm::dvec3(this->SurfaceColor[0], this->SurfaceColor[1], this->SurfaceColor[2]);
  material.ambient = this->Ambient;
  material.diffuse = this->Diffuse;
  material.specular = this->Specular;
  material.specularPower = this->SpecularPower;
  tetdsr::Light light; // one white point light
  light.positional = true;
  light.position = this->LightAtCamera
    ? camera.position
    : glm::dvec3(this->LightPosition[0], this->LightPosition[1], this->LightPosition[2]);
  settings.lighting.lights.push_back(light);
  settings.normals.mode = static_cast<tetdsr::NormalMode>(this->NormalMode);
  settings.normals.relativeStep = this->CentralDifferenceStep;
  if (settings.normals.mode == tetdsr::NormalMode::NodalInterpolation)
  {
    scene.computeNodalGradients(); // once per mesh and array: kept with the scene
  }
  settings.isoStyles = this->Prepared->Styles.Styles(values.size(), this->SurfaceColor, 1.0);
  settings.clipPlanes = clipPlanes;
  settings.cap = this->Capping == CAP_BELOW_ISO_VALUE ? tetdsr::CapRegion::BelowIsoValue
    : this->Capping == CAP_ABOVE_ISO_VALUE           ? tetdsr::CapRegion::AboveIsoValue
                                                     : tetdsr::CapRegion::None;
  if (colorMapped)
  {
    double range[2] = { this->ColorRange[0], this->ColorRange[1] };
    if (!(range[0] <= range[1]) || !std::isfinite(range[0]) || !std::isfinite(range[1]))
    {
      // The colour array's finite range (-1: the magnitude's), else the field's.
      adapter::FiniteRange(colorArray ? colorArray : scalars,
        colorArray ? colorComponent : component, range);
    }
    if (colorArray)
    {
      settings.colorBy.values = colorValues;
      settings.colorBy.components = colorArray->GetNumberOfComponents();
      settings.colorBy.component = colorComponent;
    }
    vtkSmartPointer<vtkScalarsToColors> lookupTable = this->LookupTable;
    if (!lookupTable)
    {
      lookupTable = BuiltInColorMap(this->ColorMap);
    }
    settings.colorTable = adapter::SampleColorTable(lookupTable, range[0], range[1]);
  }
  const tetdsr::IsoValues isoValues(values);
  const tetdsr::Renderer renderer(scene, camera, isoValues, settings, image);
  const vtkIdType tiles = renderer.numberOfTiles();
  const vtkIdType tilesDone = adapter::Cast(renderer,
    settings.normals.mode == tetdsr::NormalMode::DepthBuffer, this->NumberOfThreads,
    [this]() { return this->CheckAbort(); },
    [this](double fraction) { this->UpdateProgress(fraction); });
  if (tilesDone < tiles)
  {
    // CheckAbort set AbortOutput: the executive empties the output and marks it aborted.
    vtkWarningMacro("Aborted after " << tilesDone << " of " << tiles << " image tiles.");
    return 1;
  }

  // Map scene cell indices back to input cell ids where cells were re-indexed.
  vtkIdType* ids = cellIds->GetPointer(0);
  for (vtkIdType p = 0; p < pixels; ++p)
  {
    if (ids[p] >= 0)
    {
      ids[p] = prepared.InputCellId(ids[p]);
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRayCaster::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  this->ContourValues->PrintSelf(os, indent.GetNextIndent());
  os << indent << "Camera: " << this->Camera << "\n";
  os << indent << "ImageSize: " << this->ImageSize[0] << " x " << this->ImageSize[1] << "\n";
  os << indent << "ArrayComponent: " << this->ArrayComponent << "\n";
  os << indent << "SurfaceColor: (" << this->SurfaceColor[0] << ", " << this->SurfaceColor[1]
     << ", " << this->SurfaceColor[2] << ")\n";
  os << indent << "Ambient: " << this->Ambient << "\n";
  os << indent << "Diffuse: " << this->Diffuse << "\n";
  os << indent << "Specular: " << this->Specular << "\n";
  os << indent << "SpecularPower: " << this->SpecularPower << "\n";
  os << indent << "LightAtCamera: " << this->LightAtCamera << "\n";
  os << indent << "LightPosition: (" << this->LightPosition[0] << ", " << this->LightPosition[1]
     << ", " << this->LightPosition[2] << ")\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "NormalMode: " << this->NormalMode << "\n";
  os << indent << "CentralDifferenceStep: " << this->CentralDifferenceStep << "\n";
  os << indent << "TransverseTest: "
     << (this->TransverseTest == BERNSTEIN_BOUND ? "BERNSTEIN_BOUND" : "WIDENED_NODAL_RANGE") << "\n";
  os << indent << "NodalRangeWidening: " << this->NodalRangeWidening << "\n";
  os << indent << "Iso-value " << this->Prepared->Styles.Describe() << "\n";
  os << indent << "ColorByArray: " << this->ColorByArray << "\n";
  os << indent << "ColorArrayComponent: " << this->ColorArrayComponent << "\n";
  os << indent << "ColorRange: (" << this->ColorRange[0] << ", " << this->ColorRange[1] << ")\n";
  os << indent << "LookupTable: " << this->LookupTable << "\n";
  os << indent << "ColorMap: " << this->ColorMap << "\n";
  os << indent << "ClippingPlanes: " << this->ClippingPlanes << "\n";
  os << indent << "Capping: " << this->Capping << "\n";
  os << indent << "NumberOfRenderedCells: " << this->NumberOfRenderedCells << "\n";
  os << indent << "NumberOfInvertedCells: " << this->NumberOfInvertedCells << "\n";
  os << indent << "NumberOfCurvedCells: " << this->NumberOfCurvedCells << "\n";
  os << indent << "NumberOfDegenerateCells: " << this->NumberOfDegenerateCells << "\n";
  os << indent << "NumberOfNonFiniteCells: " << this->NumberOfNonFiniteCells << "\n";
  os << indent << "NumberOfInvalidIdCells: " << this->NumberOfInvalidIdCells << "\n";
  os << indent << "NumberOfUnsupportedCells: " << this->NumberOfUnsupportedCells << "\n";
  os << indent << "NumberOfMalformedCells: " << this->NumberOfMalformedCells << "\n";
  os << indent << "NumberOfOutOfScaleCells: " << this->NumberOfOutOfScaleCells << "\n";
  os << indent << "PreprocessedBytes: " << this->GetPreprocessedBytes() << "\n";
}
