#include "vtkDirectSurfaceAdapter.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSetAttributes.h"
#include "vtkDirectSurfacePick.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSMPTools.h"
#include "vtkScalarsToColors.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <type_traits>

static_assert(std::is_same<vtkIdType, tetdsr::NodeId>::value,
  "TetDSR needs VTK built with 64-bit ids (VTK_USE_64BIT_IDS)");

namespace tetdsr
{
namespace vtkadapter
{

namespace
{
/// What a scene was built from: each object and its modification time. vtkUnstructuredGrid's
/// own MTime does not follow edits of its cell arrays, so every array is stamped on its own.
/// The input's cell ghost flags (any array named vtkGhostType: the core checks its type and size).
vtkDataArray* CellGhosts(vtkUnstructuredGrid* input)
{
  return input->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
}
static_assert(vtkDataSetAttributes::DUPLICATECELL == tetdsr::kGhostDuplicateCell &&
    vtkDataSetAttributes::HIDDENCELL == tetdsr::kGhostHiddenCell,
  "the core leaves out the cells VTK flags duplicate or hidden");

struct Stamp
{
  std::vector<std::pair<const void*, vtkMTimeType>> parts;

  static Stamp Of(vtkUnstructuredGrid* input, vtkDataArray* scalars)
  {
    Stamp stamp;
    auto add = [&stamp](vtkObject* object) {
      stamp.parts.emplace_back(object, object ? object->GetMTime() : 0);
    };
    add(input);
    add(input->GetPoints());
    add(input->GetPoints() ? input->GetPoints()->GetData() : nullptr);
    vtkCellArray* cells = input->GetCells();
    add(cells);
    add(cells ? cells->GetOffsetsArray() : nullptr);
    add(cells ? cells->GetConnectivityArray() : nullptr);
    add(input->GetCellTypesArray());
    add(scalars);
    add(input->GetPointData()->GetRationalWeights());
    add(CellGhosts(input));
    return stamp;
  }
  bool operator==(const Stamp& other) const { return parts == other.parts; }
};
} // namespace

vtkMTimeType MeshModifiedTime(vtkUnstructuredGrid* grid)
{
  vtkMTimeType time = 0;
  for (const auto& part : Stamp::Of(grid, nullptr).parts)
  {
    time = std::max(time, part.second);
  }
  return time;
}

namespace
{
/// The core's ParallelFor on vtkSMPTools' threads.
void SMPParallelFor(NodeId count, const std::function<void(NodeId, NodeId)>& body)
{
  vtkSMPTools::For(0, count, [&](vtkIdType begin, vtkIdType end) { body(begin, end); });
}

/// The core's number type of a VTK data type; false for one the core does not read (bits,
/// strings).
bool NumberTypeOf(int vtkType, NumberType& type)
{
  switch (vtkType)
  {
    case VTK_FLOAT:
      type = NumberType::Float32;
      return true;
    case VTK_DOUBLE:
      type = NumberType::Float64;
      return true;
    case VTK_CHAR:
    case VTK_SIGNED_CHAR:
      type = NumberType::Int8;
      return true;
    case VTK_UNSIGNED_CHAR:
      type = NumberType::UInt8;
      return true;
    case VTK_SHORT:
      type = NumberType::Int16;
      return true;
    case VTK_UNSIGNED_SHORT:
      type = NumberType::UInt16;
      return true;
    case VTK_INT:
      type = NumberType::Int32;
      return true;
    case VTK_UNSIGNED_INT:
      type = NumberType::UInt32;
      return true;
    case VTK_LONG:
    case VTK_LONG_LONG:
    case VTK_ID_TYPE:
      type = sizeof(long) == 8 || vtkType != VTK_LONG ? NumberType::Int64 : NumberType::Int32;
      return true;
    case VTK_UNSIGNED_LONG:
    case VTK_UNSIGNED_LONG_LONG:
      type = sizeof(unsigned long) == 8 || vtkType != VTK_UNSIGNED_LONG ? NumberType::UInt64
                                                                        : NumberType::UInt32;
      return true;
    default:
      return false;
  }
}

/// A VTK array as the core's view of it: its own memory where VTK stores it one tuple after
/// another (AOS), else (SOA or implicit arrays, bits) one copy as doubles; `keep` holds what
/// the view points into. A null array gives an empty view.
ArrayView ViewOf(vtkDataArray* array, std::vector<vtkSmartPointer<vtkDataArray>>& keep)
{
  ArrayView view;
  if (!array)
  {
    return view;
  }
  vtkSmartPointer<vtkDataArray> viewed = array;
  if (!array->HasStandardMemoryLayout() || !NumberTypeOf(array->GetDataType(), view.type))
  {
    vtkNew<vtkDoubleArray> copy;
    copy->DeepCopy(array);
    viewed = copy;
    view.type = NumberType::Float64;
  }
  keep.push_back(viewed);
  view.data = viewed->GetVoidPointer(0);
  view.tuples = viewed->GetNumberOfTuples();
  view.components = viewed->GetNumberOfComponents();
  view.name = array->GetName() ? array->GetName() : "";
  return view;
}
} // namespace

struct PreparedMesh::Internals
{
  Stamp BuiltFrom;
  int Component = 0;
  TransverseTest Transverse;
  bool Built = false;
  /// The VTK arrays the core views (or their copies), kept alive as long as it does.
  std::vector<vtkSmartPointer<vtkDataArray>> Viewed;
  std::vector<vtkSmartPointer<vtkDataArray>> ColorViewed;
  tetdsr::PreparedMesh Core;
};

PreparedMesh::PreparedMesh()
  : Internal(new Internals)
{
}

PreparedMesh::~PreparedMesh() = default;

Scene* PreparedMesh::GetScene() const
{
  return this->Internal->Core.scene();
}

const PreprocessSummary& PreparedMesh::GetSummary() const
{
  return this->Internal->Core.summary();
}

const SurfaceIndex& PreparedMesh::GetSurface(const std::vector<double>& isoValues, int numberOfThreads)
{
  const SurfaceIndex* surface = nullptr;
  WithThreads(numberOfThreads,
    [&]() { surface = &this->Internal->Core.surface(isoValues, SMPParallelFor); });
  return *surface;
}

std::size_t PreparedMesh::MemoryBytes() const
{
  const Internals& in = *this->Internal;
  std::size_t copies = 0; // arrays copied here because VTK did not store them one tuple after another
  for (const auto* viewed : { &in.Viewed, &in.ColorViewed })
  {
    for (const auto& array : *viewed)
    {
      copies += array->HasStandardMemoryLayout() ? 0 : array->GetActualMemorySize() * 1024;
    }
  }
  return in.Core.memoryBytes() + copies;
}

bool PreparedMesh::Prepare(vtkUnstructuredGrid* input, vtkDataArray* scalars, int component,
  const TransverseTest& transverse, int numberOfThreads, Messages& messages)
{
  Internals& in = *this->Internal;
  const Stamp stamp = Stamp::Of(input, scalars);
  if (in.Built && stamp == in.BuiltFrom && component == in.Component &&
    transverse.mode == in.Transverse.mode && transverse.widening == in.Transverse.widening)
  {
    return in.Core.reuse(messages);
  }
  // Rebuild from scratch: nothing of the previous conversion is trusted.
  this->Internal.reset(new Internals);
  Internals& fresh = *this->Internal;
  fresh.BuiltFrom = stamp;
  fresh.Component = component;
  fresh.Transverse = transverse;
  fresh.Built = true;
  MeshArrays arrays;
  vtkPoints* points = input->GetPoints();
  arrays.points = ViewOf(points ? points->GetData() : nullptr, fresh.Viewed);
  vtkCellArray* cells = input->GetCells();
  arrays.offsets = ViewOf(cells ? cells->GetOffsetsArray() : nullptr, fresh.Viewed);
  arrays.connectivity = ViewOf(cells ? cells->GetConnectivityArray() : nullptr, fresh.Viewed);
  arrays.cellTypes = ViewOf(input->GetCellTypesArray(), fresh.Viewed);
  arrays.field = ViewOf(scalars, fresh.Viewed);
  arrays.fieldComponent = component;
  if (vtkDataArray* weights = input->GetPointData()->GetRationalWeights())
  {
    arrays.rationalWeights = ViewOf(weights, fresh.Viewed);
    arrays.hasRationalWeights = true;
  }
  if (vtkDataArray* ghosts = CellGhosts(input))
  {
    arrays.cellGhosts = ViewOf(ghosts, fresh.Viewed);
    arrays.hasCellGhosts = true;
  }
  bool prepared = false;
  WithThreads(numberOfThreads,
    [&]() { prepared = fresh.Core.prepare(arrays, transverse, SMPParallelFor, messages); });
  return prepared;
}

const double* PreparedMesh::PointArrayValues(vtkDataArray* array, const char* role, Messages& messages)
{
  Internals& in = *this->Internal;
  in.ColorViewed.clear();
  return in.Core.pointValues(ViewOf(array, in.ColorViewed), array->GetMTime(), role, messages);
}

//------------------------------------------------------------------------------
void IsoValueStyles::GetColor(int i, const double fallback[3], double color[3]) const
{
  const glm::dvec3 c = this->Core.color(i, glm::dvec3(fallback[0], fallback[1], fallback[2]));
  for (int k = 0; k < 3; ++k)
  {
    color[k] = c[k];
  }
}

bool ConvertIsoValues(vtkContourValues* contourValues, std::vector<double>& values, Messages& messages)
{
  const int count = std::max(contourValues->GetNumberOfContours(), 0);
  values.assign(contourValues->GetValues(), contourValues->GetValues() + count);
  return checkIsoValues(values, messages);
}

bool ConvertClipPlanes(vtkPlaneCollection* planes, std::vector<ClipPlane>& clipPlanes, Messages& messages)
{
  clipPlanes.clear();
  const int count = planes ? planes->GetNumberOfItems() : 0;
  for (int k = 0; k < count; ++k)
  {
    vtkPlane* plane = planes->GetItem(k);
    ClipPlane clip;
    double v[3];
    plane->GetOrigin(v);
    clip.origin = glm::dvec3(v[0], v[1], v[2]);
    plane->GetNormal(v);
    clip.normal = glm::dvec3(v[0], v[1], v[2]);
    clipPlanes.push_back(clip);
  }
  return checkClipPlanes(clipPlanes, messages);
}

bool CheckPointArray(vtkDataArray* array, int association, int requestedComponent,
  bool allowMagnitude, const char* componentSetting, int& component, Messages& messages)
{
  return choosePointArrayComponent(array->GetName() ? array->GetName() : "",
    association == vtkDataObject::FIELD_ASSOCIATION_POINTS, array->GetNumberOfComponents(),
    requestedComponent, allowMagnitude, componentSetting, component, messages);
}

void FiniteRange(vtkDataArray* array, int component, double range[2])
{
  tetdsr::FiniteRange finite;
  const int components = array->GetNumberOfComponents();
  const vtkIdType tuples = array->GetNumberOfTuples();
  if (auto* doubles = vtkDoubleArray::FastDownCast(array))
  {
    finite.add(doubles->GetPointer(0), tuples, components, component);
  }
  else
  {
    // Other types as doubles, a block of tuples at a time.
    constexpr vtkIdType kBlock = 4096;
    std::vector<double> block(static_cast<std::size_t>(kBlock) * components);
    for (vtkIdType first = 0; first < tuples; first += kBlock)
    {
      const vtkIdType count = std::min(kBlock, tuples - first);
      for (vtkIdType p = 0; p < count; ++p)
      {
        array->GetTuple(first + p, block.data() + static_cast<std::size_t>(p) * components);
      }
      finite.add(block.data(), count, components, component);
    }
  }
  finite.get(range);
}

ColorTable SampleColorTable(vtkScalarsToColors* lookupTable, double lo, double hi)
{
  const double* range = lookupTable->GetRange();
  return sampleColorTable(
    [lookupTable](double value) {
      double rgb[3];
      lookupTable->GetColor(value, rgb);
      return glm::dvec3(rgb[0], rgb[1], rgb[2]);
    },
    range[0], range[1], lo, hi);
}

void WithThreads(int numberOfThreads, const std::function<void()>& work)
{
  std::string backend = vtkSMPTools::GetBackend();
  if (backend == "Sequential" && !std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    backend = "STDThread";
  }
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ numberOfThreads, backend, false }, work);
}

NodeId Cast(const Renderer& renderer, bool depthBufferNormals, int numberOfThreads,
  const std::function<bool()>& abort, const std::function<void(double)>& progress)
{
  NodeId done = 0;
  WithThreads(numberOfThreads, [&]() {
    // One tile at a time: tiles differ in cost.
    const ParallelFor tilesFor = [](NodeId count, const std::function<void(NodeId, NodeId)>& body) {
      vtkSMPTools::For(0, count, 1, [&](vtkIdType begin, vtkIdType end) { body(begin, end); });
    };
    done = castInSteps(renderer, depthBufferNormals, tilesFor, abort, progress);
  });
  return done;
}

bool ExtractExactSurface(const PreparedMesh& prepared, const ExactSurfaceSettings& settings,
  const std::vector<vtkDataArray*>& arrays, int numberOfThreads, ExactSurfaceMesh& surface,
  Messages& messages)
{
  // The views point into these (the arrays themselves, or copies of those VTK stores in another
  // layout) until the core has read them.
  std::vector<vtkSmartPointer<vtkDataArray>> keep;
  std::vector<ArrayView> views;
  views.reserve(arrays.size());
  for (vtkDataArray* array : arrays)
  {
    views.push_back(ViewOf(array, keep));
  }
  bool extracted = false;
  WithThreads(numberOfThreads, [&]() {
    extracted = extractExactSurface(
      *prepared.GetScene(), settings, views, surface, messages, SMPParallelFor);
  });
  return extracted;
}

bool PickPrepared(PreparedMesh& prepared, const std::vector<double>& isoValues,
  const RenderSettings& settings, const Ray& ray, double tLimit, int numberOfThreads, Pick& pick)
{
  // A caster on an image of one pixel: only its pick is asked for.
  const RayGenerator rays(glm::dmat4(1.0), 1, 1);
  std::uint8_t color[4];
  double depth, normal[3];
  NodeId cellId;
  ImageView image;
  image.width = image.height = 1;
  image.colors = color;
  image.depth = &depth;
  image.normals = normal;
  image.cellIds = &cellId;
  const Renderer caster(prepared.GetSurface(isoValues, numberOfThreads), rays, settings, image);
  return caster.pick(ray, pick, tLimit);
}

void FillPick(const Pick& pick, vtkUnstructuredGrid* grid, PreparedMesh& prepared,
  vtkIdType flatIndex, const glm::dmat4& modelToWorld, double scale, vtkDirectSurfacePick* result,
  Messages& messages)
{
  const glm::dvec3 world = glm::dvec3(modelToWorld * glm::dvec4(pick.point, 1.0));
  const glm::dvec3 worldNormal =
    unitVector(glm::transpose(glm::inverse(glm::dmat3(modelToWorld))) * pick.normal);
  result->SetHit(true);
  result->SetMapperPosition(pick.point.x, pick.point.y, pick.point.z);
  result->SetPosition(world.x, world.y, world.z);
  result->SetMapperNormal(pick.normal.x, pick.normal.y, pick.normal.z);
  result->SetNormal(worldNormal.x, worldNormal.y, worldNormal.z);
  result->SetCellId(static_cast<vtkIdType>(pick.cellId));
  result->SetFlatBlockIndex(flatIndex);
  result->SetDataSet(grid);
  result->SetHasParametricCoordinates(pick.hasParametric);
  result->SetParametricCoordinates(const_cast<double*>(pick.parametric));
  result->SetIsoValueIndex(pick.isoValue);
  result->SetClippingPlaneId(pick.clipPlane);
  result->SetValue(pick.value);
  result->SetRayParameter(pick.t * scale);
  // Every point array of the grid at the hit, with the hit cell's shape functions.
  const Scene* scene = prepared.GetScene();
  vtkPointData* points = grid->GetPointData();
  for (int a = 0; scene && a < points->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = points->GetArray(a);
    const double* values = array
      ? prepared.PointArrayValues(array, array->GetName() ? array->GetName() : "point array", messages)
      : nullptr;
    if (!values)
    {
      continue;
    }
    const int components = array->GetNumberOfComponents();
    vtkNew<vtkDoubleArray> interpolated;
    interpolated->SetName(array->GetName());
    interpolated->SetNumberOfComponents(components);
    interpolated->SetNumberOfTuples(1);
    for (int c = 0; c < components; ++c)
    {
      interpolated->SetValue(c, scene->interpolate(pick.cellId, pick.point, values, components, c));
    }
    result->GetPointData()->AddArray(interpolated);
  }
}

} // namespace vtkadapter
} // namespace tetdsr
