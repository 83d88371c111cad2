#include "vtkDirectSurfaceAdapter.h"

#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
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
#include <sstream>
#include <type_traits>
#include <unistd.h>

static_assert(std::is_same<vtkIdType, tetdsr::NodeId>::value,
  "TetDSR needs VTK built with 64-bit ids (VTK_USE_64BIT_IDS)");

namespace tetdsr
{
namespace vtkadapter
{

namespace
{
// Entries of the colour table sampled from a lookup table: 1024 keeps the linear interpolation
// between entries within 1/255 of the lookup table's colour for any map with a few control points.
constexpr int kColorTableSize = 1024;

// Progress reports / abort checks per cast.
constexpr NodeId kProgressSteps = 32;


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
bool IsoValueStyles::SetColor(int i, double red, double green, double blue, Messages& messages)
{
  if (i < 0 || i >= kMaxIndex)
  {
    messages.errors.push_back(text("SetIsoValueColor: index ", i, " is outside [0, ", kMaxIndex, ")."));
    return false;
  }
  const std::size_t first = 3 * static_cast<std::size_t>(i);
  if (this->Colors.size() < first + 3)
  {
    this->Colors.resize(first + 3, vtkMath::Nan());
  }
  const double color[3] = { red, green, blue };
  for (int c = 0; c < 3; ++c)
  {
    this->Colors[first + c] = vtkMath::ClampValue(color[c], 0.0, 1.0);
  }
  return true;
}

bool IsoValueStyles::SetOpacity(int i, double opacity, Messages& messages)
{
  if (i < 0 || i >= kMaxIndex)
  {
    messages.errors.push_back(text("SetIsoValueOpacity: index ", i, " is outside [0, ", kMaxIndex, ")."));
    return false;
  }
  if (this->Opacities.size() < static_cast<std::size_t>(i) + 1)
  {
    this->Opacities.resize(static_cast<std::size_t>(i) + 1, vtkMath::Nan());
  }
  this->Opacities[static_cast<std::size_t>(i)] = vtkMath::ClampValue(opacity, 0.0, 1.0);
  return true;
}

void IsoValueStyles::GetColor(int i, const double fallback[3], double color[3]) const
{
  const std::size_t first = 3 * static_cast<std::size_t>(std::max(i, 0));
  const bool set = i >= 0 && first < this->Colors.size() && !std::isnan(this->Colors[first]);
  for (int c = 0; c < 3; ++c)
  {
    color[c] = set ? this->Colors[first + c] : fallback[c];
  }
}

double IsoValueStyles::GetOpacity(int i) const
{
  return i >= 0 && static_cast<std::size_t>(i) < this->Opacities.size() &&
      !std::isnan(this->Opacities[static_cast<std::size_t>(i)])
    ? this->Opacities[static_cast<std::size_t>(i)]
    : 1.0;
}

bool IsoValueStyles::RemoveAllColors()
{
  const bool any = !this->Colors.empty();
  this->Colors.clear();
  return any;
}

bool IsoValueStyles::RemoveAllOpacities()
{
  const bool any = !this->Opacities.empty();
  this->Opacities.clear();
  return any;
}

std::vector<SurfaceStyle> IsoValueStyles::Styles(
  std::size_t count, const double fallback[3], double opacityFactor) const
{
  std::vector<SurfaceStyle> styles;
  for (std::size_t i = 0; i < count; ++i)
  {
    double color[3];
    this->GetColor(static_cast<int>(i), fallback, color);
    styles.push_back({ glm::dvec3(color[0], color[1], color[2]),
      opacityFactor * this->GetOpacity(static_cast<int>(i)) });
  }
  return styles;
}

std::string IsoValueStyles::Describe() const
{
  std::ostringstream text;
  text << "colours (r g b per value, nan: not set):";
  for (double c : this->Colors)
  {
    text << " " << c;
  }
  text << "; opacities (nan: 1):";
  for (double o : this->Opacities)
  {
    text << " " << o;
  }
  return text.str();
}

//------------------------------------------------------------------------------
bool ConvertIsoValues(vtkContourValues* contourValues, std::vector<double>& values, Messages& messages)
{
  const int count = contourValues->GetNumberOfContours();
  if (count <= 0)
  {
    messages.errors.push_back("No iso-value: set one with SetValue(0, value).");
    return false;
  }
  values.assign(contourValues->GetValues(), contourValues->GetValues() + count);
  for (double value : values)
  {
    if (!std::isfinite(value))
    {
      messages.errors.push_back(text("Iso-value ", value, " is not finite."));
      return false;
    }
  }
  return true;
}

bool ConvertClipPlanes(vtkPlaneCollection* planes, int maximum, std::vector<ClipPlane>& clipPlanes,
  Messages& messages)
{
  clipPlanes.clear();
  const int count = planes ? planes->GetNumberOfItems() : 0;
  if (count > maximum)
  {
    messages.errors.push_back(text(count, " clipping planes: at most ", maximum, " are supported."));
    return false;
  }
  for (int k = 0; k < count; ++k)
  {
    vtkPlane* plane = planes->GetItem(k);
    ClipPlane clip;
    double v[3];
    plane->GetOrigin(v);
    clip.origin = glm::dvec3(v[0], v[1], v[2]);
    plane->GetNormal(v);
    clip.normal = glm::dvec3(v[0], v[1], v[2]);
    if (!isFinite(clip.normal) || !isFinite(clip.origin))
    {
      messages.errors.push_back(text("Clipping plane ", k, " has a NaN or Inf in its normal or origin."));
      return false;
    }
    if (unitVector(clip.normal) == glm::dvec3(0.0))
    {
      messages.errors.push_back(text("Clipping plane ", k, " has a zero normal: it keeps no side."));
      return false;
    }
    clipPlanes.push_back(clip);
  }
  return true;
}

bool CheckPointArray(vtkDataArray* array, int association, int requestedComponent,
  bool allowMagnitude, const char* componentSetting, int& component, Messages& messages)
{
  const char* name = array->GetName() ? array->GetName() : "(unnamed)";
  if (association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
  {
    messages.errors.push_back(text("Array '", name,
      "' is not a point array: the quadratic field needs values at the nodes."));
    return false;
  }
  const int components = array->GetNumberOfComponents();
  if (requestedComponent >= components)
  {
    messages.errors.push_back(text(componentSetting, " ", requestedComponent,
      " is out of range: array '", name, "' has ", components, " components."));
    return false;
  }
  if (requestedComponent >= 0 || components == 1)
  {
    component = std::max(requestedComponent, 0);
    return true;
  }
  if (!allowMagnitude)
  {
    messages.errors.push_back(text("Array '", name, "' has ", components,
      " components: choose one with ", componentSetting, "."));
    return false;
  }
  component = -1;
  return true;
}

void FiniteRange(vtkDataArray* array, int component, double range[2])
{
  range[0] = std::numeric_limits<double>::infinity();
  range[1] = -std::numeric_limits<double>::infinity();
  const int components = array->GetNumberOfComponents();
  std::vector<double> tuple(static_cast<std::size_t>(components));
  for (vtkIdType p = 0; p < array->GetNumberOfTuples(); ++p)
  {
    array->GetTuple(p, tuple.data());
    double value = 0.0;
    if (component >= 0)
    {
      value = tuple[static_cast<std::size_t>(component)];
    }
    else
    {
      for (double x : tuple)
      {
        value += x * x;
      }
      value = std::sqrt(value);
    }
    if (std::isfinite(value))
    {
      range[0] = std::min(range[0], value);
      range[1] = std::max(range[1], value);
    }
  }
  if (range[0] > range[1])
  {
    range[0] = 0.0;
    range[1] = 1.0;
  }
}

ColorTable SampleColorTable(vtkScalarsToColors* lookupTable, double lo, double hi)
{
  ColorTable table;
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

bool CheckImageSize(int width, int height, double bytesPerPixel, const char* what, Messages& messages)
{
  const double pixels = static_cast<double>(width) * static_cast<double>(height);
  const double bytes = pixels * bytesPerPixel;
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long pageSize = sysconf(_SC_PAGESIZE);
  const double memory = pages > 0 && pageSize > 0 ? static_cast<double>(pages) * pageSize : 0.0;
  // Extents and pixel indices are ints in VTK's image data: each side below 2^31, and the
  // product too (so that no index wraps).
  const bool fitsIndices = pixels < 2147483647.0;
  if (width <= 0 || height <= 0 || !fitsIndices || (memory > 0.0 && bytes > memory))
  {
    std::ostringstream text;
    text << what << " " << width << " x " << height << " pixels";
    if (width > 0 && height > 0)
    {
      text.precision(3);
      text << " needs " << bytes / (1024.0 * 1024.0 * 1024.0) << " GiB";
      if (memory > 0.0)
      {
        text << "; this machine has " << memory / (1024.0 * 1024.0 * 1024.0) << " GiB";
      }
      if (!fitsIndices)
      {
        text << "; VTK images hold fewer than 2^31 pixels";
      }
    }
    text << ": choose a smaller size.";
    messages.errors.push_back(text.str());
    return false;
  }
  return true;
}

bool CheckCamera(const Camera& camera, const Scene& scene, Messages& messages)
{
  const CameraProblem problem = RayGenerator::check(camera);
  if (problem != CameraProblem::None)
  {
    messages.errors.push_back(text("Cannot render: ", describe(problem), "."));
    return false;
  }
  double box[6];
  if (scene.bounds(box))
  {
    const glm::dvec3 centre(
      0.5 * (box[0] + box[1]), 0.5 * (box[2] + box[3]), 0.5 * (box[4] + box[5]));
    const glm::dvec3 offset = (camera.position - centre) / std::max(scene.diagonal(), 1e-300);
    // Compared in units of the diagonal, each component first, so nothing overflows.
    const double largest = std::max({ std::abs(offset.x), std::abs(offset.y), std::abs(offset.z) });
    if (!(largest <= kMaxCameraDistance))
    {
      messages.errors.push_back(text("Cannot render: the camera is ", largest,
        " scene diagonals from the scene; beyond ", kMaxCameraDistance,
        " double-precision rays cannot place hits within 1e-7 of the scene."));
      return false;
    }
  }
  return true;
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
  const NodeId tiles = renderer.numberOfTiles();
  NodeId done = 0;
  WithThreads(numberOfThreads, [&]() {
    const NodeId step = std::max<NodeId>(1, tiles / kProgressSteps);
    while (done < tiles && !abort())
    {
      const NodeId end = std::min(tiles, done + step);
      vtkSMPTools::For(
        done, end, 1, [&](vtkIdType begin, vtkIdType last) { renderer.renderTiles(begin, last); });
      done = end;
      progress(static_cast<double>(done) / tiles);
    }
    if (done == tiles && depthBufferNormals)
    {
      vtkSMPTools::For(
        0, tiles, 1, [&](vtkIdType begin, vtkIdType last) { renderer.shadeFromDepth(begin, last); });
    }
  });
  return done;
}

} // namespace vtkadapter
} // namespace tetdsr
