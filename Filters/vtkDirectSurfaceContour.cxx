#include "vtkDirectSurfaceContour.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnstructuredGrid.h"

#include "vtkDirectSurfaceAdapter.h"
#include "vtkDirectSurfaceReporting.h"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

static_assert(std::is_same<vtkIdType, tetdsr::NodeId>::value,
  "TetDSR needs VTK built with 64-bit ids (VTK_USE_64BIT_IDS)");

vtkStandardNewMacro(vtkDirectSurfaceContour);

/// The prepared mesh (see vtkDirectSurfaceAdapter.h), kept across updates, and the last update's
/// integrals.
struct vtkDirectSurfaceContour::Cache
{
  tetdsr::vtkadapter::PreparedMesh Mesh;
  std::vector<tetdsr::SurfaceIntegrals> Integrals; ///< empty unless computed
};

namespace
{
namespace adapter = tetdsr::vtkadapter;

/// A double array `name` of `components` components holding `values` (whole tuples).
vtkSmartPointer<vtkDoubleArray> DoubleArray(
  const std::string& name, int components, const std::vector<double>& values)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name.c_str());
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()) / components);
  std::copy(values.begin(), values.end(), array->GetPointer(0));
  return array;
}

/// A one-tuple id array `name` holding `count`.
vtkSmartPointer<vtkIdTypeArray> CountArray(const char* name, vtkIdType count)
{
  auto array = vtkSmartPointer<vtkIdTypeArray>::New();
  array->SetName(name);
  array->InsertNextValue(count);
  return array;
}

/// `count` ids as a vtkIdTypeArray (tetdsr::NodeId is vtkIdType: see the static_assert).
vtkSmartPointer<vtkIdTypeArray> IdArray(const tetdsr::NodeId* ids, std::size_t count)
{
  auto array = vtkSmartPointer<vtkIdTypeArray>::New();
  array->SetNumberOfTuples(static_cast<vtkIdType>(count));
  std::copy(ids, ids + count, array->GetPointer(0));
  return array;
}

/// The input's point arrays given to the core, and the names their output arrays take.
struct PointArrays
{
  std::vector<vtkDataArray*> arrays;
  std::vector<std::string> names; ///< an unnamed one: "array <its index in the point data>"
};

/// The core's surface as `output`: points, triangles, normals, the interpolated arrays, and per
/// triangle its input cell and iso-value.
void WriteSurface(const tetdsr::ExactSurfaceMesh& surface, const std::vector<double>& isoValues,
  const PointArrays& input, vtkPolyData* output)
{
  const vtkIdType triangles = static_cast<vtkIdType>(surface.cellIds.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetData(DoubleArray("Points", 3, surface.points));
  output->SetPoints(points);

  std::vector<tetdsr::NodeId> offsets(static_cast<std::size_t>(triangles) + 1);
  for (vtkIdType t = 0; t <= triangles; ++t)
  {
    offsets[t] = 3 * t;
  }
  vtkNew<vtkCellArray> polys;
  polys->SetData(IdArray(offsets.data(), offsets.size()),
    IdArray(surface.triangles.data(), surface.triangles.size()));
  output->SetPolys(polys);

  // The input's arrays first: an input array named "Normals" is replaced by the exact normals.
  vtkPointData* pointData = output->GetPointData();
  for (std::size_t a = 0; a < input.arrays.size(); ++a)
  {
    pointData->AddArray(
      DoubleArray(input.names[a], input.arrays[a]->GetNumberOfComponents(), surface.arrays[a]));
  }
  pointData->SetNormals(DoubleArray("Normals", 3, surface.normals));

  vtkSmartPointer<vtkIdTypeArray> cellIds = IdArray(surface.cellIds.data(), surface.cellIds.size());
  cellIds->SetName("vtkOriginalCellIds");
  vtkNew<vtkDoubleArray> isoValue;
  isoValue->SetName("IsoValue");
  isoValue->SetNumberOfTuples(triangles);
  for (vtkIdType t = 0; t < triangles; ++t)
  {
    isoValue->SetValue(t, isoValues[surface.isoIndices[t]]);
  }
  output->GetCellData()->AddArray(cellIds);
  output->GetCellData()->AddArray(isoValue);
}

/// The integrals (one tuple per iso-value) and the surface's counts as `output`'s field data.
void WriteFieldData(const tetdsr::ExactSurfaceMesh& surface, const std::vector<double>& isoValues,
  const PointArrays& input, bool integrals, vtkFieldData* fieldData)
{
  fieldData->AddArray(DoubleArray("IsoValues", 1, isoValues));
  const std::vector<tetdsr::SurfaceIntegrals>& perValue = surface.integrals;
  auto perIsoValue = [&](const char* name, double tetdsr::SurfaceIntegrals::*member) {
    std::vector<double> values;
    for (const tetdsr::SurfaceIntegrals& of : perValue)
    {
      values.push_back(of.*member);
    }
    fieldData->AddArray(DoubleArray(name, 1, values));
  };
  if (integrals && perValue.size() == isoValues.size())
  {
    perIsoValue("Area", &tetdsr::SurfaceIntegrals::area);
    perIsoValue("AreaError", &tetdsr::SurfaceIntegrals::areaError);
    perIsoValue("Volume", &tetdsr::SurfaceIntegrals::volume);
    perIsoValue("VolumeError", &tetdsr::SurfaceIntegrals::volumeError);
    perIsoValue("FlatArea", &tetdsr::SurfaceIntegrals::flatArea);
    // The arrays' integrals: arrays one after another, components within each (ExactSurface.h).
    std::size_t first = 0;
    for (std::size_t a = 0; a < input.arrays.size(); ++a)
    {
      const std::size_t components =
        static_cast<std::size_t>(input.arrays[a]->GetNumberOfComponents());
      std::vector<double> integral, error;
      for (const tetdsr::SurfaceIntegrals& of : perValue)
      {
        integral.insert(integral.end(), of.arrayIntegrals.begin() + first,
          of.arrayIntegrals.begin() + first + components);
        error.insert(
          error.end(), of.arrayErrors.begin() + first, of.arrayErrors.begin() + first + components);
      }
      const int k = static_cast<int>(components);
      fieldData->AddArray(DoubleArray(input.names[a] + " Integral", k, integral));
      fieldData->AddArray(DoubleArray(input.names[a] + " IntegralError", k, error));
      first += components;
    }
  }
  fieldData->AddArray(DoubleArray("DistanceBound", 1, { surface.tolerance }));
  fieldData->AddArray(DoubleArray("LargestCertifiedBound", 1, { surface.largestBound }));
  fieldData->AddArray(CountArray("Subcells", surface.subcells));
  fieldData->AddArray(CountArray("UnresolvedSubcells", surface.unresolvedSubcells));
  fieldData->AddArray(CountArray("SizeCertifiedSubcells", surface.sizeCertifiedSubcells));
  fieldData->AddArray(CountArray("BoundaryEdges", surface.boundaryEdges));
  fieldData->AddArray(CountArray("NonManifoldEdges", surface.nonManifoldEdges));
}
}

//------------------------------------------------------------------------------
vtkDirectSurfaceContour::vtkDirectSurfaceContour()
  : Tolerance(tetdsr::kDefaultRelativeTolerance)
  , Prepared(new Cache)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS,
    vtkDataSetAttributes::SCALARS);
}

//------------------------------------------------------------------------------
vtkDirectSurfaceContour::~vtkDirectSurfaceContour() = default;

//------------------------------------------------------------------------------
void vtkDirectSurfaceContour::SetValue(int i, double value)
{
  this->ContourValues->SetValue(i, value);
}
double vtkDirectSurfaceContour::GetValue(int i)
{
  return this->ContourValues->GetValue(i);
}
void vtkDirectSurfaceContour::SetNumberOfThreads(int threads)
{
  // Clamped as the core's settings table says, with its warning.
  adapter::Messages messages;
  const double given = threads;
  double used = given;
  if (tetdsr::checkSetting(tetdsr::kNumberOfThreads, &given, &used, messages) &&
    static_cast<int>(used) != this->NumberOfThreads)
  {
    this->NumberOfThreads = static_cast<int>(used);
    this->Modified();
  }
  adapter::ReportMessages(this, messages);
}

void vtkDirectSurfaceContour::SetNumberOfContours(int number)
{
  this->ContourValues->SetNumberOfContours(number);
}
vtkIdType vtkDirectSurfaceContour::GetNumberOfContours()
{
  return this->ContourValues->GetNumberOfContours();
}

//------------------------------------------------------------------------------
namespace
{
double IntegralOf(const std::vector<tetdsr::SurfaceIntegrals>& integrals, int i,
  double tetdsr::SurfaceIntegrals::*member)
{
  return i >= 0 && static_cast<std::size_t>(i) < integrals.size()
    ? integrals[i].*member
    : std::numeric_limits<double>::quiet_NaN();
}
}

double vtkDirectSurfaceContour::GetArea(int i)
{
  return IntegralOf(this->Prepared->Integrals, i, &tetdsr::SurfaceIntegrals::area);
}
double vtkDirectSurfaceContour::GetAreaError(int i)
{
  return IntegralOf(this->Prepared->Integrals, i, &tetdsr::SurfaceIntegrals::areaError);
}
double vtkDirectSurfaceContour::GetVolume(int i)
{
  return IntegralOf(this->Prepared->Integrals, i, &tetdsr::SurfaceIntegrals::volume);
}
double vtkDirectSurfaceContour::GetVolumeError(int i)
{
  return IntegralOf(this->Prepared->Integrals, i, &tetdsr::SurfaceIntegrals::volumeError);
}

//------------------------------------------------------------------------------
vtkMTimeType vtkDirectSurfaceContour::GetMTime()
{
  return std::max(this->Superclass::GetMTime(), this->ContourValues->GetMTime());
}

//------------------------------------------------------------------------------
int vtkDirectSurfaceContour::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

//------------------------------------------------------------------------------
int vtkDirectSurfaceContour::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkUnstructuredGrid* input = vtkUnstructuredGrid::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->Initialize(); // an error leaves it empty
  this->Prepared->Integrals.clear();
  this->DistanceBound = 0.0;
  this->UnresolvedSubcells = 0;
  adapter::Messages messages;

  // The settings, checked by the core: iso-values first (as the ray caster's), then the rest.
  tetdsr::ExactSurfaceSettings settings;
  settings.relativeTolerance = this->Tolerance;
  settings.tolerance = this->AbsoluteTolerance;
  settings.integrals = this->ComputeIntegrals;
  if (!adapter::ConvertIsoValues(this->ContourValues, settings.isoValues, messages) ||
    !tetdsr::checkExactSurfaceSettings(settings, messages))
  {
    adapter::ReportMessages(this, messages);
    return 0;
  }

  // An empty piece of a distributed mesh has no surface; anywhere else it is the core's error.
  const vtkIdType numberOfPoints = input ? input->GetNumberOfPoints() : 0;
  const vtkIdType numberOfCells = input ? input->GetNumberOfCells() : 0;
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if ((numberOfPoints == 0 || numberOfCells == 0) && controller &&
    controller->GetNumberOfProcesses() > 1)
  {
    return 1;
  }
  if (!tetdsr::checkMeshNotEmpty(numberOfPoints, numberOfCells, messages))
  {
    adapter::ReportMessages(this, messages);
    return 0;
  }

  // The field.
  int association = -1;
  vtkDataArray* scalars = this->GetInputArrayToProcess(0, inputVector, association);
  if (!scalars)
  {
    vtkInformation* info = this->GetInputArrayInformation(0);
    tetdsr::reportMissingArray(tetdsr::InputArray::Field,
      info->Has(vtkDataObject::FIELD_NAME()) ? info->Get(vtkDataObject::FIELD_NAME()) : nullptr,
      messages);
    adapter::ReportMessages(this, messages);
    return 0;
  }
  int component = 0;
  if (!adapter::CheckPointArray(
        scalars, association, this->ArrayComponent, false, "ArrayComponent", component, messages))
  {
    adapter::ReportMessages(this, messages);
    return 0;
  }

  // The scene (kept while the mesh and the field do not change), then its surface with every
  // numeric point array interpolated and integrated.
  adapter::PreparedMesh& prepared = this->Prepared->Mesh;
  if (!prepared.Prepare(input, scalars, component, tetdsr::TransverseTest(), this->NumberOfThreads,
        messages))
  {
    adapter::ReportMessages(this, messages);
    return 0;
  }
  PointArrays arrays;
  vtkPointData* inputPointData = input->GetPointData();
  for (int a = 0; a < inputPointData->GetNumberOfArrays(); ++a)
  {
    if (vtkDataArray* array = inputPointData->GetArray(a)) // (null: not numeric)
    {
      arrays.arrays.push_back(array);
      arrays.names.push_back(array->GetName() ? array->GetName() : "array " + std::to_string(a));
    }
  }
  tetdsr::ExactSurfaceMesh surface;
  if (!adapter::ExtractExactSurface(
        prepared, settings, arrays.arrays, this->NumberOfThreads, surface, messages))
  {
    adapter::ReportMessages(this, messages);
    return 0;
  }
  adapter::ReportMessages(this, messages); // the warnings: cells skipped, pieces uncertified

  WriteSurface(surface, settings.isoValues, arrays, output);
  WriteFieldData(surface, settings.isoValues, arrays, this->ComputeIntegrals, output->GetFieldData());
  if (this->ComputeIntegrals)
  {
    this->Prepared->Integrals = surface.integrals;
  }
  this->DistanceBound = surface.tolerance;
  this->UnresolvedSubcells = surface.unresolvedSubcells;
  return 1;
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceContour::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  this->ContourValues->PrintSelf(os, indent.GetNextIndent());
  os << indent << "ArrayComponent: " << this->ArrayComponent << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "AbsoluteTolerance: " << this->AbsoluteTolerance << "\n";
  os << indent << "ComputeIntegrals: " << this->ComputeIntegrals << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "DistanceBound: " << this->DistanceBound << "\n";
  os << indent << "UnresolvedSubcells: " << this->UnresolvedSubcells << "\n";
  os << indent << "PreparedBytes: " << this->Prepared->Mesh.MemoryBytes() << "\n";
}
