#include "vtkDirectSurfaceAdapter.h"

#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
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
} // namespace

struct PreparedMesh::Internals
{
  Stamp BuiltFrom;
  int Component = 0;
  TransverseTest Transverse;
  bool Valid = false;

  // The viewed VTK arrays, kept alive as long as the scene views them.
  vtkSmartPointer<vtkDataArray> PointArray;
  vtkSmartPointer<vtkDataArray> ConnectivityArray;
  vtkSmartPointer<vtkDataArray> ScalarArray;
  std::vector<double> PointsCopy;
  std::vector<vtkIdType> CellNodesCopy;
  std::vector<double> ValuesCopy;
  std::vector<vtkIdType> InputCellIds; ///< scene cell -> input cell; empty when the identity
  NodeId NumberOfPoints = 0;

  std::unique_ptr<Scene> TheScene;
  /// The surface index of the last iso-values asked for (GetSurface), and those values as given.
  std::unique_ptr<SurfaceIndex> Surface;
  std::vector<double> SurfaceValues;
  PreprocessSummary EmptySummary;
  vtkIdType UnsupportedCells = 0;
  vtkIdType MalformedCells = 0;

  // A point array (colour), as doubles, kept until it changes.
  vtkDataArray* ColorArray = nullptr;
  vtkMTimeType ColorArrayTime = 0;
  vtkSmartPointer<vtkDataArray> ColorArrayView;
  std::vector<double> ColorValuesCopy;
  const double* ColorValues = nullptr;

  bool Convert(vtkUnstructuredGrid* input, vtkDataArray* scalars, int component,
    MeshView& mesh, Messages& messages);
  template <typename OffsetsType, typename IdsType>
  void CopyCells(vtkUnstructuredGrid* input, OffsetsType* offsets, IdsType* connectivity);
};

PreparedMesh::PreparedMesh()
  : Internal(new Internals)
{
}

PreparedMesh::~PreparedMesh() = default;

Scene* PreparedMesh::GetScene() const
{
  return this->Internal->Valid ? this->Internal->TheScene.get() : nullptr;
}

const PreprocessSummary& PreparedMesh::GetSummary() const
{
  return this->Internal->TheScene ? this->Internal->TheScene->summary()
                                  : this->Internal->EmptySummary;
}

vtkIdType PreparedMesh::GetUnsupportedCells() const
{
  return this->Internal->UnsupportedCells;
}

vtkIdType PreparedMesh::GetMalformedCells() const
{
  return this->Internal->MalformedCells;
}

vtkIdType PreparedMesh::InputCellId(NodeId sceneCell) const
{
  const auto& ids = this->Internal->InputCellIds;
  return ids.empty() ? sceneCell : ids[static_cast<std::size_t>(sceneCell)];
}

const SurfaceIndex& PreparedMesh::GetSurface(const std::vector<double>& isoValues, int numberOfThreads)
{
  Internals& in = *this->Internal;
  if (!in.Surface || isoValues != in.SurfaceValues)
  {
    WithThreads(numberOfThreads, [&]() {
      in.Surface.reset(new SurfaceIndex(
        *in.TheScene, IsoValues(isoValues), SMPParallelFor, in.Surface.get()));
    });
    in.SurfaceValues = isoValues;
  }
  return *in.Surface;
}

std::size_t PreparedMesh::MemoryBytes() const
{
  const Internals& in = *this->Internal;
  return (in.TheScene ? in.TheScene->memoryBytes() : 0) + (in.Surface ? in.Surface->memoryBytes() : 0) +
    sizeof(double) * (in.PointsCopy.capacity() + in.ValuesCopy.capacity()) +
    sizeof(vtkIdType) * (in.CellNodesCopy.capacity() + in.InputCellIds.capacity());
}

bool PreparedMesh::Prepare(vtkUnstructuredGrid* input, vtkDataArray* scalars, int component,
  const TransverseTest& transverse, int numberOfThreads, Messages& messages)
{
  Internals& in = *this->Internal;
  const Stamp stamp = Stamp::Of(input, scalars);
  const bool same = in.TheScene && stamp == in.BuiltFrom && component == in.Component &&
    transverse.mode == in.Transverse.mode && transverse.widening == in.Transverse.widening;
  if (!same)
  {
    // Rebuild from scratch: nothing of the previous conversion is trusted.
    this->Internal.reset(new Internals);
    Internals& fresh = *this->Internal;
    fresh.BuiltFrom = stamp;
    fresh.Component = component;
    fresh.Transverse = transverse;
    MeshView mesh;
    if (!fresh.Convert(input, scalars, component, mesh, messages))
    {
      return false;
    }
    WithThreads(numberOfThreads,
      [&]() { fresh.TheScene.reset(new Scene(mesh, SMPParallelFor, transverse)); });
  }
  Internals& current = *this->Internal;
  current.Valid = false;
  const std::size_t warningsBefore = messages.warnings.size();

  const PreprocessSummary& summary = current.TheScene->summary();
  if (current.UnsupportedCells > 0)
  {
    messages.warnings.push_back(text("Skipped ", current.UnsupportedCells,
      " cells whose type is neither VTK_QUADRATIC_TETRA nor VTK_TETRA."));
  }
  if (current.MalformedCells > 0)
  {
    messages.warnings.push_back(text("Skipped ", current.MalformedCells,
      " malformed cells: a number of node ids that does not match the type (10 for "
      "VTK_QUADRATIC_TETRA, 4 for VTK_TETRA), or offsets out of order or past the end of the "
      "connectivity array."));
  }
  if (summary.tangledCells > 0)
  {
    messages.warnings.push_back(text("Skipped ", summary.tangledCells,
      " tangled curved cells (mid-edge nodes so far off their edges that the cell folds: the "
      "Jacobian determinant of its quadratic map changes sign or vanishes inside it)."));
  }
  if (summary.degenerateCells > 0)
  {
    messages.warnings.push_back(text("Skipped ", summary.degenerateCells,
      " degenerate cells (flat or needle-like: 6 x volume below 1e-13 of the longest edge cubed; "
      "or a node id repeated within the cell)."));
  }
  if (summary.outOfScaleCells > 0)
  {
    messages.warnings.push_back(text("Skipped ", summary.outOfScaleCells,
      " cells whose longest edge is outside [", Scene::kMinCellSize, ", ", Scene::kMaxCellSize,
      "]: their volumes would underflow or overflow double precision."));
  }
  if (summary.nonFiniteCells > 0)
  {
    messages.warnings.push_back(text("Skipped ", summary.nonFiniteCells,
      " cells with NaN or Inf values of '", scalars->GetName() ? scalars->GetName() : "(unnamed)",
      "' or coordinates at their nodes."));
  }
  if (summary.invalidIdCells > 0)
  {
    messages.warnings.push_back(text("Skipped ", summary.invalidIdCells,
      " cells with node ids outside [0, ", current.NumberOfPoints, ")."));
  }
  if (same)
  {
    messages.warnings.resize(warningsBefore); // told when the scene was built: not every render
  }
  if (summary.validCells == 0)
  {
    messages.errors.push_back(text("No cell can be rendered: all ", input->GetNumberOfCells(),
      " input cells were skipped."));
    return false;
  }
  current.Valid = true;
  return true;
}

bool PreparedMesh::Internals::Convert(vtkUnstructuredGrid* input, vtkDataArray* scalars,
  int component, MeshView& mesh, Messages& messages)
{
  vtkPoints* points = input->GetPoints();
  vtkCellArray* cells = input->GetCells();
  const vtkIdType numberOfPoints = points ? points->GetNumberOfPoints() : 0;
  const vtkIdType numberOfCells = cells ? cells->GetNumberOfCells() : 0;
  if (numberOfPoints == 0 || numberOfCells == 0)
  {
    messages.errors.push_back("The input mesh is empty: it has no cells or no points.");
    return false;
  }
  if (numberOfCells > Scene::kMaxCells)
  {
    messages.errors.push_back(text("The input has ", numberOfCells, " cells; at most ",
      Scene::kMaxCells, " can be rendered."));
    return false;
  }
  vtkUnsignedCharArray* types = input->GetCellTypesArray();
  if (!types || types->GetNumberOfTuples() < numberOfCells || types->GetNumberOfComponents() != 1)
  {
    messages.errors.push_back(text("The input's cell types array has ",
      types ? types->GetNumberOfValues() : 0, " values for ", numberOfCells, " cells."));
    return false;
  }
  const char* name = scalars->GetName() ? scalars->GetName() : "(unnamed)";
  if (scalars->GetNumberOfTuples() < numberOfPoints)
  {
    messages.errors.push_back(text("Point array '", name, "' has ", scalars->GetNumberOfTuples(),
      " tuples for ", numberOfPoints, " points."));
    return false;
  }
  NumberOfPoints = numberOfPoints;
  mesh.numberOfPoints = numberOfPoints;

  vtkDataArray* pointData = points->GetData();
  if (auto* doublePoints = vtkDoubleArray::FastDownCast(pointData))
  {
    PointArray = doublePoints;
    mesh.points = doublePoints->GetPointer(0);
  }
  else
  {
    PointsCopy.resize(3 * static_cast<std::size_t>(numberOfPoints));
    for (vtkIdType p = 0; p < numberOfPoints; ++p)
    {
      pointData->GetTuple(p, PointsCopy.data() + 3 * p);
    }
    mesh.points = PointsCopy.data();
  }
  // Mid-edge nodes within rounding of their edges' midpoints are straight; float coordinates
  // round at 2^-24 relative.
  mesh.pointRounding = pointData->GetDataType() == VTK_FLOAT ? 0x1p-23 : 0x1p-52;

  if (scalars->GetNumberOfComponents() == 1 && vtkDoubleArray::FastDownCast(scalars))
  {
    ScalarArray = scalars;
    mesh.values = vtkDoubleArray::FastDownCast(scalars)->GetPointer(0);
  }
  else
  {
    ValuesCopy.resize(static_cast<std::size_t>(numberOfPoints));
    for (vtkIdType p = 0; p < numberOfPoints; ++p)
    {
      ValuesCopy[p] = scalars->GetComponent(p, component);
    }
    mesh.values = ValuesCopy.data();
  }

  // Connectivity: viewed directly when every cell is a quadratic tet whose offsets are exactly
  // 0, 10, 20, ... (a .vtu may claim the type and give another count); else copied cell by cell,
  // each checked against the arrays.
  bool allQuadratic = true;
  for (vtkIdType c = 0; c < numberOfCells && allQuadratic; ++c)
  {
    allQuadratic = types->GetValue(c) == VTK_QUADRATIC_TETRA;
  }
  if (allQuadratic && cells->IsStorage64Bit())
  {
    auto* offsets = cells->GetOffsetsArray64();
    auto* connectivity = cells->GetConnectivityArray64();
    bool regular = connectivity->GetNumberOfValues() == 10 * numberOfCells;
    const vtkIdType* offset = offsets->GetPointer(0);
    for (vtkIdType c = 0; c <= numberOfCells && regular; ++c)
    {
      regular = offset[c] == 10 * c;
    }
    if (regular)
    {
      ConnectivityArray = connectivity;
      mesh.cellNodes = connectivity->GetPointer(0);
      mesh.numberOfCells = numberOfCells;
      return true;
    }
  }
  if (cells->IsStorage64Bit())
  {
    CopyCells(input, cells->GetOffsetsArray64(), cells->GetConnectivityArray64());
  }
  else
  {
    CopyCells(input, cells->GetOffsetsArray32(), cells->GetConnectivityArray32());
  }
  mesh.cellNodes = CellNodesCopy.data();
  mesh.numberOfCells = static_cast<vtkIdType>(InputCellIds.size());
  mesh.straightEdgeMarkers = true; // linear tets' mid-edge ids are kStraightEdge
  if (mesh.numberOfCells == 0)
  {
    messages.errors.push_back(text("No cell can be rendered: none of the ", numberOfCells,
      " input cells is a well-formed VTK_QUADRATIC_TETRA or VTK_TETRA (", UnsupportedCells,
      " of another type, ", MalformedCells, " malformed)."));
    return false;
  }
  return true;
}

template <typename OffsetsType, typename IdsType>
void PreparedMesh::Internals::CopyCells(
  vtkUnstructuredGrid* input, OffsetsType* offsets, IdsType* connectivity)
{
  vtkUnsignedCharArray* types = input->GetCellTypesArray();
  const vtkIdType numberOfCells = offsets->GetNumberOfValues() - 1;
  const vtkIdType size = connectivity->GetNumberOfValues();
  for (vtkIdType c = 0; c < numberOfCells; ++c)
  {
    const int type = types->GetValue(c);
    if (type != VTK_QUADRATIC_TETRA && type != VTK_TETRA)
    {
      ++UnsupportedCells;
      continue;
    }
    const vtkIdType begin = offsets->GetValue(c);
    const vtkIdType end = offsets->GetValue(c + 1);
    const vtkIdType expected = type == VTK_QUADRATIC_TETRA ? 10 : 4;
    if (begin < 0 || end > size || end - begin != expected)
    {
      ++MalformedCells;
      continue;
    }
    for (vtkIdType n = 0; n < 10; ++n)
    {
      vtkIdType id = kStraightEdge; // a linear tet's straight edges
      if (n < expected)
      {
        id = static_cast<vtkIdType>(connectivity->GetValue(begin + n));
        // A quadratic cell's negative id is invalid, not a straight edge: keep it out of range.
        id = id < 0 ? std::numeric_limits<vtkIdType>::min() : id;
      }
      CellNodesCopy.push_back(id);
    }
    InputCellIds.push_back(c);
  }
}

const double* PreparedMesh::PointArrayValues(vtkDataArray* array, const char* role, Messages& messages)
{
  Internals& in = *this->Internal;
  if (array->GetNumberOfTuples() < in.NumberOfPoints)
  {
    messages.errors.push_back(text("The ", role, " '", array->GetName() ? array->GetName() : "",
      "' has ", array->GetNumberOfTuples(), " tuples for ", in.NumberOfPoints, " points."));
    return nullptr;
  }
  if (array == in.ColorArray && array->GetMTime() == in.ColorArrayTime)
  {
    return in.ColorValues;
  }
  in.ColorArray = array;
  in.ColorArrayTime = array->GetMTime();
  in.ColorValuesCopy.clear();
  if (auto* doubles = vtkDoubleArray::FastDownCast(array))
  {
    in.ColorArrayView = doubles;
    in.ColorValues = doubles->GetPointer(0);
    return in.ColorValues;
  }
  in.ColorArrayView = nullptr;
  const int components = array->GetNumberOfComponents();
  in.ColorValuesCopy.resize(static_cast<std::size_t>(in.NumberOfPoints) * components);
  for (vtkIdType p = 0; p < in.NumberOfPoints; ++p)
  {
    array->GetTuple(p, in.ColorValuesCopy.data() + static_cast<std::size_t>(p) * components);
  }
  in.ColorValues = in.ColorValuesCopy.data();
  return in.ColorValues;
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

} // namespace vtkadapter
} // namespace tetdsr
