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

#include "tetdsr/Renderer.h"
#include "tetdsr/Scene.h"

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

/// The converted mesh and its scene, kept until the mesh or the scalar array changes.
/// Arrays VTK already stores in the core's layout are viewed, not copied.
struct vtkDirectSurfaceRayCaster::Cache
{
  // Identity of what the scene was built from.
  vtkUnstructuredGrid* Input = nullptr;
  vtkMTimeType InputTime = 0;
  vtkDataArray* Array = nullptr;
  vtkMTimeType ArrayTime = 0;
  int Component = 0;
  tetdsr::TransverseTest Transverse;

  // Keep the viewed VTK arrays alive as long as the scene views them.
  vtkSmartPointer<vtkDataArray> PointArray;
  vtkSmartPointer<vtkDataArray> ConnectivityArray;
  vtkSmartPointer<vtkDataArray> ScalarArray;
  std::vector<double> PointsCopy;
  std::vector<vtkIdType> CellNodesCopy;
  std::vector<double> ValuesCopy;
  std::vector<vtkIdType> InputCellIds; ///< scene cell -> input cell; empty when the identity

  std::unique_ptr<tetdsr::Scene> Scene;
  vtkIdType UnsupportedCells = 0;

  // The colour array, as doubles (all components), kept until it changes.
  vtkDataArray* ColorArray = nullptr;
  vtkMTimeType ColorArrayTime = 0;
  vtkSmartPointer<vtkDataArray> ColorArrayView;
  std::vector<double> ColorValuesCopy;
  const double* ColorValues = nullptr;

  /// The colour array's values for the core, copied only when VTK stores them otherwise.
  const double* ColorArrayValues(vtkDataArray* array)
  {
    if (array == this->ColorArray && array->GetMTime() == this->ColorArrayTime)
    {
      return this->ColorValues;
    }
    this->ColorArray = array;
    this->ColorArrayTime = array->GetMTime();
    this->ColorValuesCopy.clear();
    if (auto* doubles = vtkDoubleArray::FastDownCast(array))
    {
      this->ColorArrayView = doubles;
      this->ColorValues = doubles->GetPointer(0);
      return this->ColorValues;
    }
    this->ColorArrayView = nullptr;
    const int components = array->GetNumberOfComponents();
    this->ColorValuesCopy.resize(static_cast<std::size_t>(array->GetNumberOfTuples()) * components);
    for (vtkIdType p = 0; p < array->GetNumberOfTuples(); ++p)
    {
      array->GetTuple(p, this->ColorValuesCopy.data() + static_cast<std::size_t>(p) * components);
    }
    this->ColorValues = this->ColorValuesCopy.data();
    return this->ColorValues;
  }

  /// Convert the input to the core's MeshView, copying only what VTK stores differently.
  tetdsr::MeshView View(vtkUnstructuredGrid* input, vtkDataArray* scalars, int component);

  bool Matches(vtkUnstructuredGrid* input, vtkDataArray* array, int component,
    const tetdsr::TransverseTest& transverse) const
  {
    return this->Scene && input == this->Input && input->GetMTime() == this->InputTime &&
      array == this->Array && array->GetMTime() == this->ArrayTime &&
      component == this->Component && transverse.mode == this->Transverse.mode &&
      transverse.widening == this->Transverse.widening;
  }
};

namespace
{
// Progress reports / abort checks per render.
constexpr vtkIdType kProgressSteps = 32;

// Entries of the colour table sampled from the lookup table: 1024 keeps the linear interpolation
// between entries within 1/255 of the lookup table's colour for any map with a few control points.
constexpr int kColorTableSize = 1024;

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

/// Samples `lookupTable`'s own range at kColorTableSize evenly spaced values into a table that
/// spans [lo, hi]: the lookup table is stretched over the colour range.
tetdsr::ColorTable SampleColorTable(vtkScalarsToColors* lookupTable, double lo, double hi)
{
  tetdsr::ColorTable table;
  table.lo = lo;
  table.hi = hi;
  const double* range = lookupTable->GetRange();
  double rgb[3];
  for (int k = 0; k < kColorTableSize; ++k)
  {
    const double x = static_cast<double>(k) / (kColorTableSize - 1);
    lookupTable->GetColor(range[0] + x * (range[1] - range[0]), rgb);
    table.colors.emplace_back(rgb[0], rgb[1], rgb[2]);
  }
  lookupTable->GetColor(vtkMath::Nan(), rgb);
  table.nanColor = glm::dvec3(rgb[0], rgb[1], rgb[2]);
  return table;
}

/// tetdsr::ParallelFor on vtkSMPTools.
void SMPFor(tetdsr::NodeId count, const std::function<void(tetdsr::NodeId, tetdsr::NodeId)>& body)
{
  vtkSMPTools::For(0, count, [&](vtkIdType begin, vtkIdType end) { body(begin, end); });
}

/// Runs `work` with all cores by default: ParaView's VTK defaults to the Sequential backend,
/// so STDThread is used unless the user chose a backend with VTK_SMP_BACKEND_IN_USE.
template <typename Work>
void WithThreads(int numberOfThreads, Work&& work)
{
  std::string backend = vtkSMPTools::GetBackend();
  if (backend == "Sequential" && !std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    backend = "STDThread";
  }
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ numberOfThreads, backend, false }, work);
}
}

//------------------------------------------------------------------------------
vtkDirectSurfaceRayCaster::vtkDirectSurfaceRayCaster()
  : ContourValues(vtkContourValues::New())
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
  if (i < 0)
  {
    vtkErrorMacro("SetIsoValueColor: index " << i << " is negative.");
    return;
  }
  if (this->IsoValueColors.size() < 3 * static_cast<std::size_t>(i + 1))
  {
    this->IsoValueColors.resize(3 * static_cast<std::size_t>(i + 1), vtkMath::Nan());
  }
  const double color[3] = { red, green, blue };
  for (int c = 0; c < 3; ++c)
  {
    this->IsoValueColors[3 * i + c] = vtkMath::ClampValue(color[c], 0.0, 1.0);
  }
  this->Modified();
}

void vtkDirectSurfaceRayCaster::GetIsoValueColor(int i, double color[3])
{
  const bool set = i >= 0 && 3 * static_cast<std::size_t>(i) < this->IsoValueColors.size() &&
    !std::isnan(this->IsoValueColors[3 * i]);
  for (int c = 0; c < 3; ++c)
  {
    color[c] = set ? this->IsoValueColors[3 * i + c] : this->SurfaceColor[c];
  }
}

void vtkDirectSurfaceRayCaster::RemoveAllIsoValueColors()
{
  if (!this->IsoValueColors.empty())
  {
    this->IsoValueColors.clear();
    this->Modified();
  }
}

void vtkDirectSurfaceRayCaster::SetIsoValueOpacity(int i, double opacity)
{
  if (i < 0)
  {
    vtkErrorMacro("SetIsoValueOpacity: index " << i << " is negative.");
    return;
  }
  if (this->IsoValueOpacities.size() < static_cast<std::size_t>(i + 1))
  {
    this->IsoValueOpacities.resize(static_cast<std::size_t>(i + 1), vtkMath::Nan());
  }
  this->IsoValueOpacities[i] = vtkMath::ClampValue(opacity, 0.0, 1.0);
  this->Modified();
}

double vtkDirectSurfaceRayCaster::GetIsoValueOpacity(int i)
{
  return i >= 0 && static_cast<std::size_t>(i) < this->IsoValueOpacities.size() &&
      !std::isnan(this->IsoValueOpacities[i])
    ? this->IsoValueOpacities[i]
    : 1.0;
}

void vtkDirectSurfaceRayCaster::RemoveAllIsoValueOpacities()
{
  if (!this->IsoValueOpacities.empty())
  {
    this->IsoValueOpacities.clear();
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
  if (!this->Prepared || !this->Prepared->Scene)
  {
    return 0;
  }
  const Cache& cache = *this->Prepared;
  return static_cast<vtkIdType>(cache.Scene->memoryBytes() +
    sizeof(double) * (cache.PointsCopy.capacity() + cache.ValuesCopy.capacity()) +
    sizeof(vtkIdType) * (cache.CellNodesCopy.capacity() + cache.InputCellIds.capacity()));
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
  if (this->ImageSize[0] <= 0 || this->ImageSize[1] <= 0)
  {
    vtkErrorMacro("ImageSize must be positive, got " << this->ImageSize[0] << " x "
                                                     << this->ImageSize[1] << ".");
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
int vtkDirectSurfaceRayCaster::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  const int width = this->ImageSize[0]; // positive: RequestInformation checked it
  const int height = this->ImageSize[1];
  if (!input || input->GetNumberOfCells() == 0 || input->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro("The input mesh is empty: it has no cells or no points.");
    return 0;
  }

  // The scalar field.
  int association = -1;
  vtkDataArray* scalars = this->GetInputArrayToProcess(0, inputVector, association);
  if (!scalars)
  {
    vtkInformation* arrayInfo = this->GetInputArrayInformation(0);
    const char* name =
      arrayInfo->Has(vtkDataObject::FIELD_NAME()) ? arrayInfo->Get(vtkDataObject::FIELD_NAME()) : nullptr;
    if (name)
    {
      vtkErrorMacro("No point array named '" << name << "' in the input.");
    }
    else
    {
      vtkErrorMacro("No point scalars: the input has no active point scalars; choose an array "
                    "with SetInputArrayToProcess(0, 0, 0, FIELD_ASSOCIATION_POINTS, name).");
    }
    return 0;
  }
  const char* arrayName = scalars->GetName() ? scalars->GetName() : "(unnamed)";
  if (association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
  {
    vtkErrorMacro("Array '" << arrayName << "' is not a point array: the quadratic field needs "
                            << "values at the nodes.");
    return 0;
  }
  const int components = scalars->GetNumberOfComponents();
  int component = this->ArrayComponent;
  if (component < 0)
  {
    if (components != 1)
    {
      vtkErrorMacro("Array '" << arrayName << "' has " << components
                              << " components: choose one with SetArrayComponent.");
      return 0;
    }
    component = 0;
  }
  else if (component >= components)
  {
    vtkErrorMacro("ArrayComponent " << component << " is out of range: array '" << arrayName
                                    << "' has " << components << " components.");
    return 0;
  }

  const int numberOfValues = this->ContourValues->GetNumberOfContours();
  if (numberOfValues == 0)
  {
    vtkErrorMacro("No iso-value: set one with SetValue(0, value).");
    return 0;
  }
  std::vector<double> values(this->ContourValues->GetValues(),
    this->ContourValues->GetValues() + numberOfValues);
  for (double value : values)
  {
    if (!std::isfinite(value))
    {
      vtkErrorMacro("Iso-value " << value << " is not finite.");
      return 0;
    }
  }

  // The colour array.
  vtkDataArray* colorArray = nullptr;
  int colorComponent = this->ColorArrayComponent;
  if (this->ColorByArray)
  {
    int colorAssociation = -1;
    colorArray = this->GetInputArrayToProcess(1, inputVector, colorAssociation);
    if (!colorArray)
    {
      vtkInformation* arrayInfo = this->GetInputArrayInformation(1);
      const char* name = arrayInfo->Has(vtkDataObject::FIELD_NAME())
        ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
        : nullptr;
      vtkErrorMacro("ColorByArray is on but "
        << (name ? "there is no point array named '" + std::string(name) + "'"
                 : std::string("no colour array is chosen"))
        << ": choose one with SetInputArrayToProcess(1, 0, 0, FIELD_ASSOCIATION_POINTS, name).");
      return 0;
    }
    const char* colorName = colorArray->GetName() ? colorArray->GetName() : "(unnamed)";
    if (colorAssociation != vtkDataObject::FIELD_ASSOCIATION_POINTS)
    {
      vtkErrorMacro("Colour array '" << colorName << "' is not a point array.");
      return 0;
    }
    if (colorComponent >= colorArray->GetNumberOfComponents())
    {
      vtkErrorMacro("ColorArrayComponent " << colorComponent << " is out of range: array '"
                                           << colorName << "' has "
                                           << colorArray->GetNumberOfComponents()
                                           << " components.");
      return 0;
    }
    if (colorArray->GetNumberOfComponents() == 1)
    {
      colorComponent = 0;
    }
  }

  // Clipping planes.
  std::vector<tetdsr::ClipPlane> clipPlanes;
  const int numberOfPlanes = this->ClippingPlanes ? this->ClippingPlanes->GetNumberOfItems() : 0;
  if (numberOfPlanes > MaximumNumberOfClippingPlanes)
  {
    vtkErrorMacro(<< numberOfPlanes << " clipping planes: at most "
                  << MaximumNumberOfClippingPlanes << " are supported.");
    return 0;
  }
  for (int k = 0; k < numberOfPlanes; ++k)
  {
    vtkPlane* plane = this->ClippingPlanes->GetItem(k);
    tetdsr::ClipPlane clip;
    double v[3];
    plane->GetOrigin(v);
    clip.origin = glm::dvec3(v[0], v[1], v[2]);
    plane->GetNormal(v);
    clip.normal = glm::dvec3(v[0], v[1], v[2]);
    const double length = glm::length(clip.normal);
    if (!(length > 0.0) || !std::isfinite(length) ||
      !std::isfinite(glm::dot(clip.origin, clip.origin)))
    {
      vtkErrorMacro("Clipping plane " << k << " has a zero or non-finite normal or origin.");
      return 0;
    }
    clipPlanes.push_back(clip);
  }

  // Preprocess once per mesh, array and transverse test.
  tetdsr::TransverseTest transverse;
  transverse.mode = this->TransverseTest == WIDENED_NODAL_RANGE
    ? tetdsr::TransverseTest::Mode::WidenedNodalRange
    : tetdsr::TransverseTest::Mode::BernsteinBound;
  transverse.widening = this->NodalRangeWidening;
  if (!this->Prepared || !this->Prepared->Matches(input, scalars, component, transverse))
  {
    this->Prepared.reset(new Cache);
    this->Prepared->Transverse = transverse;
    const tetdsr::MeshView mesh = this->Prepared->View(input, scalars, component);
    WithThreads(this->NumberOfThreads,
      [&]() { this->Prepared->Scene.reset(new tetdsr::Scene(mesh, SMPFor, transverse)); });
  }
  Cache& prepared = *this->Prepared;
  const tetdsr::PreprocessSummary& summary = prepared.Scene->summary();
  this->NumberOfRenderedCells = summary.validCells;
  this->NumberOfInvertedCells = summary.invertedCells;
  this->NumberOfCurvedCells = summary.curvedCells;
  this->NumberOfDegenerateCells = summary.degenerateCells;
  this->NumberOfNonFiniteCells = summary.nonFiniteCells;
  this->NumberOfInvalidIdCells = summary.invalidIdCells;
  this->NumberOfUnsupportedCells = prepared.UnsupportedCells;
  if (prepared.UnsupportedCells > 0)
  {
    vtkWarningMacro("Skipped " << prepared.UnsupportedCells
                               << " cells whose type is neither VTK_QUADRATIC_TETRA nor VTK_TETRA.");
  }
  if (summary.curvedCells > 0)
  {
    vtkWarningMacro(<< summary.curvedCells
                    << " cells are curved (a mid-edge node off its edge's midpoint): they are "
                       "rendered as straight-sided tetrahedra, so only approximately.");
  }
  if (summary.degenerateCells > 0)
  {
    vtkWarningMacro("Skipped " << summary.degenerateCells
                               << " degenerate cells (zero volume or a repeated node id).");
  }
  if (summary.nonFiniteCells > 0)
  {
    vtkWarningMacro("Skipped " << summary.nonFiniteCells << " cells with NaN or Inf values of '"
                               << arrayName << "' or coordinates at their nodes.");
  }
  if (summary.invalidIdCells > 0)
  {
    vtkWarningMacro("Skipped " << summary.invalidIdCells << " cells with node ids outside [0, "
                               << input->GetNumberOfPoints() << ").");
  }
  if (summary.validCells == 0)
  {
    vtkErrorMacro("No cell can be rendered: all " << input->GetNumberOfCells()
                                                  << " input cells were skipped.");
    return 0;
  }

  // Camera.
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
    camera = tetdsr::resetCamera(input->GetBounds(), static_cast<double>(width) / height);
  }
  if (!tetdsr::RayGenerator::valid(camera))
  {
    vtkErrorMacro("The camera is degenerate: position and focal point must differ, view up must "
                  "not be parallel to the view direction, and the view angle (or parallel scale) "
                  "must be positive.");
    return 0;
  }

  // Output arrays, written in place by the core.
  output->SetExtent(0, width - 1, 0, height - 1, 0, 0);
  const vtkIdType pixels = static_cast<vtkIdType>(width) * height;
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(4);
  colors->SetNumberOfTuples(pixels);
  vtkNew<vtkDoubleArray> depth;
  depth->SetName("Depth");
  depth->SetNumberOfTuples(pixels);
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(pixels);
  vtkNew<vtkIdTypeArray> cellIds;
  cellIds->SetName("CellId");
  cellIds->SetNumberOfTuples(pixels);
  vtkPointData* pointData = output->GetPointData();
  pointData->Initialize();
  pointData->SetScalars(colors);
  pointData->AddArray(depth);
  pointData->SetNormals(normals);
  pointData->AddArray(cellIds);
  vtkNew<vtkDoubleArray> colorValues;
  const bool colorMapped = this->ColorByArray || (this->Capping != NO_CAP && numberOfPlanes > 0);
  if (colorMapped)
  {
    colorValues->SetName("ColorValues");
    colorValues->SetNumberOfTuples(pixels);
    pointData->AddArray(colorValues);
  }

  tetdsr::ImageView image;
  image.width = width;
  image.height = height;
  image.colors = colors->GetPointer(0);
  image.depth = depth->GetPointer(0);
  image.normals = normals->GetPointer(0);
  image.cellIds = cellIds->GetPointer(0);
  image.colorValues = colorMapped ? colorValues->GetPointer(0) : nullptr;

  tetdsr::RenderSettings settings;
  tetdsr::Material& material = settings.material;
  material.color = glm::dvec3(this->SurfaceColor[0], this->SurfaceColor[1], this->SurfaceColor[2]);
  material.ambient = this->Ambient;
  material.diffuse = this->Diffuse;
  material.specular = this->Specular;
  material.specularPower = this->SpecularPower;
  settings.lightPosition = this->LightAtCamera
    ? camera.position
    : glm::dvec3(this->LightPosition[0], this->LightPosition[1], this->LightPosition[2]);
  settings.normals.mode = static_cast<tetdsr::NormalMode>(this->NormalMode);
  settings.normals.relativeStep = this->CentralDifferenceStep;
  if (settings.normals.mode == tetdsr::NormalMode::NodalInterpolation)
  {
    prepared.Scene->computeNodalGradients(); // once per mesh and array: kept with the scene
  }
  for (int i = 0; i < numberOfValues; ++i)
  {
    double color[3];
    this->GetIsoValueColor(i, color);
    settings.isoStyles.push_back({ glm::dvec3(color[0], color[1], color[2]),
      this->GetIsoValueOpacity(i) });
  }
  settings.clipPlanes = clipPlanes;
  settings.cap = this->Capping == CAP_BELOW_ISO_VALUE ? tetdsr::CapRegion::BelowIsoValue
    : this->Capping == CAP_ABOVE_ISO_VALUE           ? tetdsr::CapRegion::AboveIsoValue
                                                     : tetdsr::CapRegion::None;
  if (colorMapped)
  {
    double range[2] = { this->ColorRange[0], this->ColorRange[1] };
    if (range[0] > range[1])
    {
      // The colour array's range (-1: the magnitude's), else the field's.
      if (colorArray)
      {
        colorArray->GetRange(range, colorComponent);
      }
      else
      {
        scalars->GetRange(range, component);
      }
    }
    if (colorArray)
    {
      settings.colorBy.values = prepared.ColorArrayValues(colorArray);
      settings.colorBy.components = colorArray->GetNumberOfComponents();
      settings.colorBy.component = colorComponent;
    }
    vtkSmartPointer<vtkScalarsToColors> lookupTable = this->LookupTable;
    if (!lookupTable)
    {
      lookupTable = BuiltInColorMap(this->ColorMap);
    }
    settings.colorTable = SampleColorTable(lookupTable, range[0], range[1]);
  }
  const tetdsr::IsoValues isoValues(values);
  const tetdsr::Renderer renderer(*prepared.Scene, camera, isoValues, settings, image);

  const vtkIdType tiles = renderer.numberOfTiles();
  vtkIdType tilesDone = 0;
  WithThreads(this->NumberOfThreads, [&]() {
    const vtkIdType step = std::max<vtkIdType>(1, tiles / kProgressSteps);
    while (tilesDone < tiles && !this->CheckAbort())
    {
      const vtkIdType end = std::min(tiles, tilesDone + step);
      vtkSMPTools::For(tilesDone, end, 1,
        [&](vtkIdType begin, vtkIdType last) { renderer.renderTiles(begin, last); });
      tilesDone = end;
      this->UpdateProgress(static_cast<double>(tilesDone) / tiles);
    }
    if (tilesDone == tiles && settings.normals.mode == tetdsr::NormalMode::DepthBuffer)
    {
      vtkSMPTools::For(0, tiles, 1,
        [&](vtkIdType begin, vtkIdType last) { renderer.shadeFromDepth(begin, last); });
    }
  });
  if (tilesDone < tiles)
  {
    // CheckAbort set AbortOutput: the executive empties the output and marks it aborted.
    vtkWarningMacro("Aborted after " << tilesDone << " of " << tiles << " image tiles.");
    return 1;
  }

  // Map scene cell indices back to input cell ids where cells were re-indexed.
  if (!prepared.InputCellIds.empty())
  {
    vtkIdType* ids = cellIds->GetPointer(0);
    for (vtkIdType p = 0; p < pixels; ++p)
    {
      if (ids[p] >= 0)
      {
        ids[p] = prepared.InputCellIds[static_cast<std::size_t>(ids[p])];
      }
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
tetdsr::MeshView vtkDirectSurfaceRayCaster::Cache::View(
  vtkUnstructuredGrid* input, vtkDataArray* scalars, int component)
{
  Cache& cache = *this;
  cache.Input = input;
  cache.InputTime = input->GetMTime();
  cache.Array = scalars;
  cache.ArrayTime = scalars->GetMTime();
  cache.Component = component;

  tetdsr::MeshView mesh;
  const vtkIdType numberOfPoints = input->GetNumberOfPoints();
  mesh.numberOfPoints = numberOfPoints;

  vtkDataArray* points = input->GetPoints()->GetData();
  if (auto* doublePoints = vtkDoubleArray::FastDownCast(points))
  {
    cache.PointArray = doublePoints;
    mesh.points = doublePoints->GetPointer(0);
  }
  else
  {
    cache.PointsCopy.resize(3 * static_cast<std::size_t>(numberOfPoints));
    for (vtkIdType p = 0; p < numberOfPoints; ++p)
    {
      points->GetTuple(p, cache.PointsCopy.data() + 3 * p);
    }
    mesh.points = cache.PointsCopy.data();
  }

  if (scalars->GetNumberOfComponents() == 1 && vtkDoubleArray::FastDownCast(scalars))
  {
    cache.ScalarArray = scalars;
    mesh.values = vtkDoubleArray::FastDownCast(scalars)->GetPointer(0);
  }
  else
  {
    cache.ValuesCopy.resize(static_cast<std::size_t>(numberOfPoints));
    for (vtkIdType p = 0; p < numberOfPoints; ++p)
    {
      cache.ValuesCopy[p] = scalars->GetComponent(p, component);
    }
    mesh.values = cache.ValuesCopy.data();
  }

  // Connectivity: view it directly when every cell is a quadratic tet (10 ids each).
  vtkCellArray* cells = input->GetCells();
  vtkUnsignedCharArray* types = input->GetCellTypesArray();
  const vtkIdType numberOfCells = input->GetNumberOfCells();
  vtkIdType quadratic = 0;
  for (vtkIdType c = 0; c < numberOfCells; ++c)
  {
    quadratic += types->GetValue(c) == VTK_QUADRATIC_TETRA;
  }
  if (quadratic == numberOfCells && cells->IsStorage64Bit())
  {
    cache.ConnectivityArray = cells->GetConnectivityArray();
    mesh.cellNodes = cells->GetConnectivityArray64()->GetPointer(0);
    mesh.numberOfCells = numberOfCells;
    return mesh;
  }
  const vtkIdType* ids;
  vtkIdType count;
  for (vtkIdType c = 0; c < numberOfCells; ++c)
  {
    const int type = types->GetValue(c);
    if (type != VTK_QUADRATIC_TETRA && type != VTK_TETRA)
    {
      ++cache.UnsupportedCells;
      continue;
    }
    cells->GetCellAtId(c, count, ids);
    const vtkIdType expected = type == VTK_QUADRATIC_TETRA ? 10 : 4;
    if (count != expected)
    {
      ++cache.UnsupportedCells; // malformed: wrong number of nodes for its type
      continue;
    }
    for (vtkIdType n = 0; n < 10; ++n)
    {
      cache.CellNodesCopy.push_back(n < count ? ids[n] : -1);
    }
    cache.InputCellIds.push_back(c);
  }
  mesh.cellNodes = cache.CellNodesCopy.data();
  mesh.numberOfCells = static_cast<vtkIdType>(cache.InputCellIds.size());
  return mesh;
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
  os << indent << "IsoValueColors (r g b per value, nan: SurfaceColor):";
  for (double c : this->IsoValueColors)
  {
    os << " " << c;
  }
  os << "\n" << indent << "IsoValueOpacities (nan: 1):";
  for (double o : this->IsoValueOpacities)
  {
    os << " " << o;
  }
  os << "\n";
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
  os << indent << "PreprocessedBytes: " << this->GetPreprocessedBytes() << "\n";
}
