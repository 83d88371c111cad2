#include "vtkDirectSurfaceRayCaster.h"

#include "vtkCamera.h"
#include "vtkMatrix4x4.h"
#include "vtkCellArray.h"
#include "vtkCellType.h"
#include "vtkColorTransferFunction.h"
#include "vtkCommunicator.h"
#include "vtkContourValues.h"
#include "vtkDataArray.h"
#include "vtkDirectSurfacePick.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
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
#include "vtkWeakPointer.h"

#include "vtkDirectSurfaceAdapter.h"
#include "vtkDirectSurfaceReporting.h"
#include "tetdsr/render/LayerExchange.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <vector>

static_assert(std::is_same<vtkIdType, tetdsr::NodeId>::value,
  "TetDSR needs VTK built with 64-bit ids (VTK_USE_64BIT_IDS)");

vtkStandardNewMacro(vtkDirectSurfaceRayCaster);
vtkCxxSetObjectMacro(vtkDirectSurfaceRayCaster, Camera, vtkCamera);
vtkCxxSetObjectMacro(vtkDirectSurfaceRayCaster, LookupTable, vtkScalarsToColors);
vtkCxxSetObjectMacro(vtkDirectSurfaceRayCaster, ClippingPlanes, vtkPlaneCollection);
vtkCxxSetObjectMacro(vtkDirectSurfaceRayCaster, Controller, vtkMultiProcessController);

/// The prepared mesh (see vtkDirectSurfaceAdapter.h), kept across updates.
struct vtkDirectSurfaceRayCaster::Cache
{
  tetdsr::vtkadapter::PreparedMesh Mesh;
  tetdsr::vtkadapter::IsoValueStyles Styles;
  // What the last image was cast with (Pick).
  vtkWeakPointer<vtkUnstructuredGrid> Input;
  vtkMTimeType InputTime = 0;
  tetdsr::Camera Camera;
  int Width = 0;
  int Height = 0;
  std::vector<double> Values;
  tetdsr::RenderSettings Settings;
};

namespace
{
namespace adapter = tetdsr::vtkadapter;

static_assert(vtkDirectSurfaceRayCaster::MaximumNumberOfClippingPlanes == tetdsr::kMaxClipPlanes,
  "the filter's plane limit is the core's");
static_assert(vtkDirectSurfaceRayCaster::COOL_TO_WARM ==
      static_cast<int>(tetdsr::BuiltInColorMap::CoolToWarm) &&
    vtkDirectSurfaceRayCaster::RAINBOW == static_cast<int>(tetdsr::BuiltInColorMap::Rainbow) &&
    vtkDirectSurfaceRayCaster::GRAYSCALE == static_cast<int>(tetdsr::BuiltInColorMap::Grayscale) &&
    vtkDirectSurfaceRayCaster::BLACK_BODY == static_cast<int>(tetdsr::BuiltInColorMap::BlackBody),
  "the filter's colour maps are numbered as the core's");

/// One of the core's built-in colour maps (over [0, 1]) as a VTK lookup table.
vtkSmartPointer<vtkScalarsToColors> BuiltInColorMap(int which)
{
  const tetdsr::ColorMap& data = tetdsr::builtInColorMap(which);
  auto map = vtkSmartPointer<vtkColorTransferFunction>::New();
  switch (data.space)
  {
    case tetdsr::ColorSpace::HSV:
      map->SetColorSpaceToHSV();
      break;
    case tetdsr::ColorSpace::Diverging:
      map->SetColorSpaceToDiverging();
      break;
    case tetdsr::ColorSpace::RGB:
      map->SetColorSpaceToRGB();
      break;
  }
  for (const tetdsr::ColorMapPoint& point : data.points)
  {
    map->AddRGBPoint(point.x, point.color.r, point.color.g, point.color.b);
  }
  map->SetNanColor(data.nanColor.r, data.nanColor.g, data.nanColor.b);
  return map;
}

/// The arrays of an output image: Colors (the scalars), Depth, Normals, CellId and, when
/// colour-mapping, ColorValues.
struct ImageArrays
{
  vtkNew<vtkUnsignedCharArray> Colors;
  vtkNew<vtkDoubleArray> Depth;
  vtkNew<vtkDoubleArray> Normals;
  vtkNew<vtkIdTypeArray> CellIds;
  vtkSmartPointer<vtkDoubleArray> ColorValues; ///< null unless colour-mapping

  explicit ImageArrays(bool colorMapped)
  {
    this->Colors->SetName("Colors");
    this->Colors->SetNumberOfComponents(4);
    this->Depth->SetName("Depth");
    this->Normals->SetName("Normals");
    this->Normals->SetNumberOfComponents(3);
    this->CellIds->SetName("CellId");
    if (colorMapped)
    {
      this->ColorValues = vtkSmartPointer<vtkDoubleArray>::New();
      this->ColorValues->SetName("ColorValues");
    }
  }

  /// Sizes every array to `pixels` tuples; false when memory is short.
  bool Allocate(vtkIdType pixels)
  {
    for (vtkDataArray* array : this->Arrays())
    {
      if (!array->Allocate(pixels * array->GetNumberOfComponents()))
      {
        return false;
      }
      array->SetNumberOfTuples(pixels);
    }
    return true;
  }

  /// The background (what the core writes on a miss) everywhere.
  void FillMisses()
  {
    this->Colors->FillValue(0);
    this->Depth->FillValue(std::numeric_limits<double>::infinity());
    this->Normals->FillValue(0.0);
    this->CellIds->FillValue(-1);
    if (this->ColorValues)
    {
      this->ColorValues->FillValue(std::numeric_limits<double>::quiet_NaN());
    }
  }

  /// The arrays as the core's image of `width` x `height` pixels, which it writes in place.
  tetdsr::ImageView View(int width, int height) const
  {
    tetdsr::ImageView view;
    view.width = width;
    view.height = height;
    view.colors = this->Colors->GetPointer(0);
    view.depth = this->Depth->GetPointer(0);
    view.normals = this->Normals->GetPointer(0);
    view.cellIds = this->CellIds->GetPointer(0);
    view.colorValues = this->ColorValues ? this->ColorValues->GetPointer(0) : nullptr;
    return view;
  }

  void AddTo(vtkPointData* pointData) const
  {
    pointData->SetScalars(this->Colors);
    pointData->AddArray(this->Depth);
    pointData->SetNormals(this->Normals);
    pointData->AddArray(this->CellIds);
    if (this->ColorValues)
    {
      pointData->AddArray(this->ColorValues);
    }
  }

  std::vector<vtkDataArray*> Arrays() const
  {
    std::vector<vtkDataArray*> arrays{ this->Colors, this->Depth, this->Normals, this->CellIds };
    if (this->ColorValues)
    {
      arrays.push_back(this->ColorValues);
    }
    return arrays;
  }
};

/// The processes the input is distributed over. With one process (or no controller) every step
/// is local; with several, each is a collective operation every process must call.
class ProcessGroup
{
public:
  explicit ProcessGroup(vtkMultiProcessController* controller)
    : Controller(controller && controller->GetNumberOfProcesses() > 1 ? controller : nullptr)
  {
  }

  bool Distributed() const { return this->Controller != nullptr; }

  /// Whether `value` holds on every process / on some process.
  bool All(bool value) const { return this->Reduce(value ? 1 : 0, vtkCommunicator::MIN_OP) != 0; }
  bool Any(bool value) const { return this->Reduce(value ? 1 : 0, vtkCommunicator::MAX_OP) != 0; }

  /// A box (xmin, xmax, ...) or a range that any other one contains after UniteBoxes/Ranges.
  static void EmptyBox(double box[6])
  {
    for (int a = 0; a < 3; ++a)
    {
      box[2 * a] = VTK_DOUBLE_MAX;
      box[2 * a + 1] = -VTK_DOUBLE_MAX;
    }
  }
  static void EmptyRange(double range[2])
  {
    range[0] = VTK_DOUBLE_MAX;
    range[1] = -VTK_DOUBLE_MAX;
  }

  /// The union of every process's box, on every process.
  void UniteBoxes(double box[6]) const
  {
    for (int a = 0; a < 3; ++a)
    {
      this->UniteRanges(box + 2 * a);
    }
  }
  void UniteRanges(double range[2]) const
  {
    if (this->Controller)
    {
      const double local[2] = { range[0], -range[1] };
      double united[2];
      this->Controller->AllReduce(local, united, 2, vtkCommunicator::MIN_OP);
      range[0] = united[0];
      range[1] = -united[1];
    }
  }

  /// The number of cells of the processes before this one.
  vtkIdType CellsBefore(vtkIdType localCells) const
  {
    if (!this->Controller)
    {
      return 0;
    }
    std::vector<vtkIdType> counts(this->Controller->GetNumberOfProcesses());
    this->Controller->AllGather(&localCells, counts.data(), 1);
    const int self = this->Controller->GetLocalProcessId();
    return std::accumulate(counts.begin(), counts.begin() + self, vtkIdType(0));
  }

  /// Composites every process's whole image (width pixels a row) into this process's `extent`
  /// of it (within the image): per pixel, the nearest process's depth, normal, cell and colour
  /// value, and the colours of every process's crossings (`layers`, per tile as the core wrote
  /// them), sorted along the ray and composited by the core as one process holding every cell
  /// would (crossings within `gap` of each other are one surface). False, on every process, when
  /// one could not allocate its part.
  bool CompositeByDepth(const ImageArrays& image, int width, const int extent[6],
    const std::vector<std::vector<tetdsr::PixelLayer>>& layers, double gap,
    ImageArrays& composited) const
  {
    const double* depth = image.Depth->GetPointer(0);
    const double* normals = image.Normals->GetPointer(0);
    const vtkIdType* cellIds = image.CellIds->GetPointer(0);
    const double* colorValues = image.ColorValues ? image.ColorValues->GetPointer(0) : nullptr;
    // The hits: the pixel's index in the receiver's extent, depth, normal (3), cell id, colour
    // value.
    const std::vector<double> hits =
      this->SendToOwners(extent, [&](const Block& block, std::vector<double>& records) {
        for (int j = block.jBegin; j < block.jEnd; ++j)
        {
          for (int i = block.iBegin; i < block.iEnd; ++i)
          {
            const vtkIdType p = i + static_cast<vtkIdType>(j) * width;
            if (std::isfinite(depth[p])) // (a miss: nothing to composite)
            {
              records.insert(records.end(),
                { static_cast<double>(block.Index(i, j)), depth[p], normals[3 * p],
                  normals[3 * p + 1], normals[3 * p + 2], static_cast<double>(cellIds[p]),
                  colorValues ? colorValues[p] : std::numeric_limits<double>::quiet_NaN() });
            }
          }
        }
      });
    // The crossings, packed by the core's LayerExchange at the pixel's index in the receiver's
    // extent.
    const std::vector<double> crossings =
      this->SendToOwners(extent, [&](const Block& block, std::vector<double>& records) {
        for (const auto& tile : layers)
        {
          for (const tetdsr::PixelLayer& layer : tile)
          {
            const int i = static_cast<int>(layer.pixel % static_cast<std::uint32_t>(width));
            const int j = static_cast<int>(layer.pixel / static_cast<std::uint32_t>(width));
            if (block.Contains(i, j))
            {
              tetdsr::packLayer(layer, static_cast<std::uint32_t>(block.Index(i, j)), records);
            }
          }
        }
      });
    const Block own(extent);
    if (!this->All(composited.Allocate(own.Pixels())))
    {
      return false;
    }
    composited.FillMisses();
    // Per pixel, the nearest hit (a stable sort: equal depths stay in process order).
    std::vector<const double*> records(hits.size() / kHitRecord);
    for (std::size_t r = 0; r < records.size(); ++r)
    {
      records[r] = &hits[kHitRecord * r];
    }
    std::stable_sort(records.begin(), records.end(), [](const double* first, const double* second) {
      return first[0] < second[0] || (first[0] == second[0] && first[1] < second[1]);
    });
    for (std::size_t r = 0; r < records.size(); ++r)
    {
      if (r == 0 || records[r][0] != records[r - 1][0])
      {
        WriteNearest(records[r], composited);
      }
    }
    std::vector<tetdsr::PixelLayer> pixelLayers;
    tetdsr::unpackLayers(crossings.data(), crossings.size(), pixelLayers);
    tetdsr::compositeLayers(pixelLayers, static_cast<std::size_t>(own.Pixels()), gap, nullptr,
      composited.Colors->GetPointer(0));
    return true;
  }

private:
  static constexpr int kHitRecord = 7;

  struct Block;

  /// Sends each process the records `fill` makes for that process's extent (of the image all
  /// processes share); returns the records of `extent` (this process's) from every process, in
  /// process order.
  template <typename Fill>
  std::vector<double> SendToOwners(const int extent[6], Fill&& fill) const
  {
    const int processes = this->Controller->GetNumberOfProcesses();
    std::vector<int> extents(6 * static_cast<std::size_t>(processes));
    this->Controller->AllGather(extent, extents.data(), 6);
    std::vector<double> received;
    for (int destination = 0; destination < processes; ++destination)
    {
      const Block block(&extents[6 * static_cast<std::size_t>(destination)]);
      std::vector<double> records;
      fill(block, records);
      const vtkIdType length = static_cast<vtkIdType>(records.size());
      std::vector<vtkIdType> lengths(processes), offsets(processes);
      this->Controller->Gather(&length, lengths.data(), 1, destination);
      std::partial_sum(lengths.begin(), lengths.end() - 1, offsets.begin() + 1);
      if (destination == this->Controller->GetLocalProcessId())
      {
        received.resize(static_cast<std::size_t>(offsets.back() + lengths.back()));
      }
      this->Controller->GatherV(
        records.data(), received.data(), length, lengths.data(), offsets.data(), destination);
    }
    return received;
  }

  /// Writes the depth, normal, cell and colour value of a pixel's nearest hit.
  static void WriteNearest(const double* nearest, ImageArrays& composited)
  {
    const vtkIdType p = static_cast<vtkIdType>(nearest[0]);
    composited.Depth->SetValue(p, nearest[1]);
    composited.Normals->SetTypedTuple(p, nearest + 2);
    composited.CellIds->SetValue(p, static_cast<vtkIdType>(nearest[5]));
    if (composited.ColorValues)
    {
      composited.ColorValues->SetValue(p, nearest[6]);
    }
  }

  /// The pixels of an extent of the image (within it), and their indices in the extent.
  struct Block
  {
    int iBegin, iEnd, jBegin, jEnd; ///< empty when there is no pixel
    explicit Block(const int extent[6])
      : iBegin(extent[0])
      , iEnd(extent[1] + 1)
      , jBegin(extent[2])
      , jEnd(extent[3] + 1)
    {
      if (iEnd <= iBegin || jEnd <= jBegin || extent[5] < extent[4])
      {
        iEnd = iBegin;
        jEnd = jBegin;
      }
    }
    bool Contains(int i, int j) const
    {
      return i >= this->iBegin && i < this->iEnd && j >= this->jBegin && j < this->jEnd;
    }
    vtkIdType Index(int i, int j) const
    {
      const vtkIdType rowLength = this->iEnd - this->iBegin;
      return (i - this->iBegin) + (j - this->jBegin) * rowLength;
    }
    vtkIdType Pixels() const
    {
      return static_cast<vtkIdType>(this->iEnd - this->iBegin) * (this->jEnd - this->jBegin);
    }
  };

  int Reduce(int value, int operation) const
  {
    int result = value;
    if (this->Controller)
    {
      this->Controller->AllReduce(&value, &result, 1, operation);
    }
    return result;
  }

  vtkMultiProcessController* Controller; ///< null unless there are several processes
};
}

//------------------------------------------------------------------------------
vtkDirectSurfaceRayCaster::vtkDirectSurfaceRayCaster()
  : Prepared(new Cache)
{
  // The defaults of the core's settings table.
  auto defaults = [](const tetdsr::Setting& row, auto* member) {
    for (int c = 0; c < row.components; ++c)
    {
      member[c] = static_cast<std::remove_pointer_t<decltype(member)>>(row.defaults[c]);
    }
  };
  defaults(tetdsr::kImageSize, this->ImageSize);
  defaults(tetdsr::kArrayComponent, &this->ArrayComponent);
  defaults(tetdsr::kSurfaceColor, this->SurfaceColor);
  defaults(tetdsr::kAmbient, &this->Ambient);
  defaults(tetdsr::kDiffuse, &this->Diffuse);
  defaults(tetdsr::kSpecular, &this->Specular);
  defaults(tetdsr::kSpecularPower, &this->SpecularPower);
  defaults(tetdsr::kLightAtCamera, &this->LightAtCamera);
  defaults(tetdsr::kLightPosition, this->LightPosition);
  defaults(tetdsr::kNormalMode, &this->NormalMode);
  defaults(tetdsr::kCentralDifferenceStep, &this->CentralDifferenceStep);
  defaults(tetdsr::kColorByArray, &this->ColorByArray);
  defaults(tetdsr::kColorArrayComponent, &this->ColorArrayComponent);
  defaults(tetdsr::kColorRange, this->ColorRange);
  defaults(tetdsr::kColorMap, &this->ColorMap);
  defaults(tetdsr::kCapping, &this->Capping);
  defaults(tetdsr::kTransverseTest, &this->TransverseTest);
  defaults(tetdsr::kNodalRangeWidening, &this->NodalRangeWidening);
  defaults(tetdsr::kNumberOfThreads, &this->NumberOfThreads);
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS,
    vtkDataSetAttributes::SCALARS);
  this->SetController(vtkMultiProcessController::GetGlobalController());
}

//------------------------------------------------------------------------------
vtkDirectSurfaceRayCaster::~vtkDirectSurfaceRayCaster()
{
  this->SetCamera(nullptr);
  this->SetLookupTable(nullptr);
  this->SetClippingPlanes(nullptr);
  this->SetController(nullptr);
}

//------------------------------------------------------------------------------
void vtkDirectSurfaceRayCaster::SetIsoValueColor(int i, double red, double green, double blue)
{
  adapter::Messages messages;
  if (this->Prepared->Styles.SetColor(i, red, green, blue, messages))
  {
    this->Modified();
  }
  adapter::ReportMessages(this, messages);
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
  adapter::ReportMessages(this, messages);
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
// The settings of the core's table (tetdsr::kSettings), each checked by the core as its row
// says: numbers clamped (NaN refused), integers clamped with a warning, vectors refused unless
// finite, each with the core's message.
namespace
{
/// `given` checked as `row` says into `member` (row.components values); true when it changed.
template <typename T>
bool SetFromTable(vtkObject* object, const tetdsr::Setting& row, const double* given, T* member)
{
  adapter::Messages messages;
  double used[3] = { 0.0, 0.0, 0.0 };
  bool changed = false;
  if (tetdsr::checkSetting(row, given, used, messages))
  {
    for (int c = 0; c < row.components; ++c)
    {
      changed = changed || member[c] != static_cast<T>(used[c]);
      member[c] = static_cast<T>(used[c]);
    }
  }
  adapter::ReportMessages(object, messages);
  return changed;
}
}

#define TETDSR_TABLE_SETTER(Name, Type)                                                            \
  void vtkDirectSurfaceRayCaster::Set##Name(Type value)                                            \
  {                                                                                                \
    const double given = static_cast<double>(value);                                               \
    if (SetFromTable(this, tetdsr::k##Name, &given, &this->Name))                                  \
    {                                                                                              \
      this->Modified();                                                                            \
    }                                                                                              \
  }
TETDSR_TABLE_SETTER(Ambient, double)
TETDSR_TABLE_SETTER(Diffuse, double)
TETDSR_TABLE_SETTER(Specular, double)
TETDSR_TABLE_SETTER(SpecularPower, double)
TETDSR_TABLE_SETTER(CentralDifferenceStep, double)
TETDSR_TABLE_SETTER(NodalRangeWidening, double)
TETDSR_TABLE_SETTER(NormalMode, int)
TETDSR_TABLE_SETTER(ColorArrayComponent, int)
TETDSR_TABLE_SETTER(ColorMap, int)
TETDSR_TABLE_SETTER(Capping, int)
TETDSR_TABLE_SETTER(TransverseTest, int)
TETDSR_TABLE_SETTER(NumberOfThreads, int)
#undef TETDSR_TABLE_SETTER

#define TETDSR_TABLE_VECTOR3_SETTER(Name)                                                          \
  void vtkDirectSurfaceRayCaster::Set##Name(double x, double y, double z)                          \
  {                                                                                                \
    const double given[3] = { x, y, z };                                                           \
    if (SetFromTable(this, tetdsr::k##Name, given, this->Name))                                    \
    {                                                                                              \
      this->Modified();                                                                            \
    }                                                                                              \
  }
TETDSR_TABLE_VECTOR3_SETTER(SurfaceColor)
TETDSR_TABLE_VECTOR3_SETTER(LightPosition)
#undef TETDSR_TABLE_VECTOR3_SETTER

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
namespace
{
/// vtkCamera's frame and projection as the core's camera.
tetdsr::Camera CoreCamera(vtkCamera* vtkcamera)
{
  tetdsr::Camera camera;
  double v[3];
  vtkcamera->GetPosition(v);
  camera.position = glm::dvec3(v[0], v[1], v[2]);
  vtkcamera->GetFocalPoint(v);
  camera.focalPoint = glm::dvec3(v[0], v[1], v[2]);
  vtkcamera->GetViewUp(v);
  camera.viewUp = glm::dvec3(v[0], v[1], v[2]);
  camera.viewAngleDegrees = vtkcamera->GetViewAngle();
  camera.parallelProjection = vtkcamera->GetParallelProjection() != 0;
  camera.parallelScale = vtkcamera->GetParallelScale();
  return camera;
}

/// What `vtkcamera` holds beyond the core's camera (the filter refuses it: CameraExtras).
tetdsr::CameraExtras CameraExtrasOf(vtkCamera* vtkcamera)
{
  tetdsr::CameraExtras extras;
  extras.explicitProjection = vtkcamera->GetUseExplicitProjectionTransformMatrix();
  extras.offAxisProjection = vtkcamera->GetUseOffAxisProjection() != 0;
  const double* centre = vtkcamera->GetWindowCenter();
  extras.windowCenter = centre[0] != 0.0 || centre[1] != 0.0;
  const double* shear = vtkcamera->GetViewShear();
  extras.viewShear = shear[0] != 0.0 || shear[1] != 0.0;
  vtkMatrix4x4* model = vtkcamera->GetModelTransformMatrix();
  extras.transforms = vtkcamera->GetUserTransform() || vtkcamera->GetUserViewTransform() ||
    (model && !model->IsIdentity());
  return extras;
}

/// The filter's shading settings (material, its one point light, normals, iso-value styles, cap)
/// for the core.
tetdsr::RenderSettings ShadingSettings(vtkDirectSurfaceRayCaster* self,
  const adapter::IsoValueStyles& styles, const tetdsr::Camera& camera, std::size_t numberOfValues)
{
  tetdsr::RenderSettings settings;
  tetdsr::Material& material = settings.material;
  const double* color = self->GetSurfaceColor();
  material.color = glm::dvec3(color[0], color[1], color[2]);
  material.ambient = self->GetAmbient();
  material.diffuse = self->GetDiffuse();
  material.specular = self->GetSpecular();
  material.specularPower = self->GetSpecularPower();
  tetdsr::Light light; // one white point light
  light.positional = true;
  const double* position = self->GetLightPosition();
  light.position = self->GetLightAtCamera() ? camera.position
                                            : glm::dvec3(position[0], position[1], position[2]);
  settings.lighting.lights.push_back(light);
  settings.normals.mode = static_cast<tetdsr::NormalMode>(self->GetNormalMode());
  settings.normals.relativeStep = self->GetCentralDifferenceStep();
  settings.isoStyles = styles.Styles(numberOfValues, color, 1.0);
  const int capping = self->GetCapping();
  settings.cap = capping == vtkDirectSurfaceRayCaster::CAP_BELOW_ISO_VALUE
    ? tetdsr::CapRegion::BelowIsoValue
    : capping == vtkDirectSurfaceRayCaster::CAP_ABOVE_ISO_VALUE ? tetdsr::CapRegion::AboveIsoValue
                                                                : tetdsr::CapRegion::None;
  return settings;
}

/// Puts `image` (this process's) into `output` over the requested extent: the whole image, a
/// part of it, or, distributed, this process's block of the depth-composited image. False when
/// compositing fails.
bool WriteOutput(const ProcessGroup& processes, ImageArrays& image, int width, int height,
  bool colorMapped, const std::vector<std::vector<tetdsr::PixelLayer>>& layers, double gap,
  vtkInformation* outInfo, vtkImageData* output)
{
  int wholeExtent[6] = { 0, width - 1, 0, height - 1, 0, 0 };
  int extent[6] = { 0, width - 1, 0, height - 1, 0, 0 };
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent);
    for (int a = 0; a < 6; a += 2) // the pipeline asks for no more than the image; make sure
    {
      extent[a] = std::max(extent[a], wholeExtent[a]);
      extent[a + 1] = std::min(extent[a + 1], wholeExtent[a + 1]);
    }
  }
  vtkPointData* pointData = output->GetPointData();
  pointData->Initialize();
  if (processes.Distributed())
  {
    ImageArrays composited(colorMapped);
    if (!processes.CompositeByDepth(image, width, extent, layers, gap, composited))
    {
      return false;
    }
    output->SetExtent(extent);
    composited.AddTo(pointData);
  }
  else
  {
    output->SetExtent(wholeExtent);
    image.AddTo(pointData);
    if (!std::equal(extent, extent + 6, wholeExtent))
    {
      output->Crop(extent);
    }
  }
  return true;
}
}

//------------------------------------------------------------------------------
int vtkDirectSurfaceRayCaster::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  adapter::Messages messages;
  if (!tetdsr::checkImageSize(this->ImageSize[0], this->ImageSize[1], messages))
  {
    adapter::ReportMessages(this, messages);
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
  // Any block of the image can be asked for: distributed, each process outputs its own.
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
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
  adapter::Messages messages;
  tetdsr::reportMissingArray(
    index == 0 ? tetdsr::InputArray::Field : tetdsr::InputArray::Color, name, messages);
  adapter::ReportMessages(this, messages);
  return nullptr;
}

//------------------------------------------------------------------------------
/// What one execution works with, from step to step of RequestData.
struct vtkDirectSurfaceRayCaster::Execution
{
  Execution(vtkMultiProcessController* controller, vtkUnstructuredGrid* input, const int size[2])
    : Processes(controller)
    , Input(input)
    , HasPiece(input && input->GetNumberOfCells() > 0 && input->GetNumberOfPoints() > 0)
    , Width(size[0])
    , Height(size[1])
  {
  }

  const ProcessGroup Processes;
  vtkUnstructuredGrid* const Input;
  const bool HasPiece; ///< else this process only checks the settings and casts nothing
  const int Width;     ///< of the image (RequestInformation checked the size)
  const int Height;
  adapter::Messages Messages;

  // The field and its component, the iso-values, the colour array and its component, and the
  // clipping planes.
  vtkDataArray* Scalars = nullptr;
  int Component = 0;
  std::vector<double> Values;
  vtkDataArray* ColorArray = nullptr;
  int ColorComponent = -1;
  std::vector<tetdsr::ClipPlane> ClipPlanes;
  bool ColorMapped = false; ///< the output has ColorValues: colouring by an array, or capping

  tetdsr::Scene* Scene = nullptr;      ///< the piece's (null when it has nothing to render)
  const double* ColorValues = nullptr; ///< the colour array, in the scene's point order
  tetdsr::Camera Camera;
  tetdsr::RenderSettings Settings;
  tetdsr::ImageView View; ///< the output arrays of this process's image

  vtkIdType Pixels() const { return static_cast<vtkIdType>(this->Width) * this->Height; }
};

//------------------------------------------------------------------------------
int vtkDirectSurfaceRayCaster::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // Distributed, every process takes part in each collective step below (ProcessGroup::All and
  // the rest), so that none returns while another waits for it.
  Execution run(this->Controller, vtkUnstructuredGrid::GetData(inputVector[0]), this->ImageSize);
  if (!run.Processes.Any(run.HasPiece))
  {
    tetdsr::checkMeshNotEmpty(run.Input ? run.Input->GetNumberOfPoints() : 0,
      run.Input ? run.Input->GetNumberOfCells() : 0, run.Messages); // (no process has a piece)
    adapter::ReportMessages(this, run.Messages);
    return 0;
  }
  if (!this->ChooseArraysAndSettings(inputVector, run) || !this->PrepareScene(run) ||
    !this->ChooseCamera(run))
  {
    return 0;
  }

  // The image of this process's piece, written in place by the core.
  ImageArrays image(run.ColorMapped);
  if (!run.Processes.All(image.Allocate(run.Pixels())))
  {
    tetdsr::reportUnallocatedImage(run.Width, run.Height, run.Messages);
    adapter::ReportMessages(this, run.Messages);
    return 0;
  }
  run.View = image.View(run.Width, run.Height);
  // Distributed, every crossing is kept, to be sorted along the rays with the other processes'.
  std::vector<std::vector<tetdsr::PixelLayer>> layers;
  if (run.Processes.Distributed())
  {
    run.View.layers = &layers;
  }
  this->ChooseShading(run);
  bool completed = true;
  if (run.Scene)
  {
    completed = this->CastPiece(run);
  }
  else
  {
    image.FillMisses();
  }
  if (!run.Processes.All(completed))
  {
    // The executive empties the output and marks it aborted (CheckAbort set AbortOutput here, or
    // another process aborted).
    this->SetAbortOutput(true);
    return 1;
  }
  this->MapCellIds(run);
  // For Pick: what this image was cast with.
  Cache& cache = *this->Prepared;
  cache.Input = run.Scene ? run.Input : nullptr;
  cache.InputTime = run.Scene ? adapter::MeshModifiedTime(run.Input) : 0;
  cache.Camera = run.Camera;
  cache.Width = run.Width;
  cache.Height = run.Height;
  cache.Values = run.Values;
  cache.Settings = run.Settings;

  // The requested extent: the whole image, a part of it, or (distributed) this process's block
  // of the image all pieces give together.
  // Crossings nearer than the layer gap of the whole scene are one surface.
  double box[6];
  ProcessGroup::EmptyBox(box);
  if (run.Scene)
  {
    run.Scene->bounds(box);
  }
  run.Processes.UniteBoxes(box);
  const double diagonal = box[0] <= box[1]
    ? std::sqrt((box[1] - box[0]) * (box[1] - box[0]) + (box[3] - box[2]) * (box[3] - box[2]) +
        (box[5] - box[4]) * (box[5] - box[4]))
    : 0.0;
  if (!WriteOutput(run.Processes, image, run.Width, run.Height, run.ColorMapped, layers,
        tetdsr::Renderer::kLayerGap * diagonal, outputVector->GetInformationObject(0),
        vtkImageData::GetData(outputVector)))
  {
    adapter::Messages messages;
    tetdsr::describeCompositingFailure(messages);
    adapter::ReportMessages(this, messages);
    return 0;
  }
  return 1;
}

bool vtkDirectSurfaceRayCaster::ChooseArraysAndSettings(
  vtkInformationVector** inputVector, Execution& run)
{
  int association = -1;
  run.Scalars = run.HasPiece ? this->GetPointArray(0, inputVector, association) : nullptr;
  bool ok = (!run.HasPiece ||
              (run.Scalars &&
                adapter::CheckPointArray(run.Scalars, association, this->ArrayComponent, false,
                  "ArrayComponent", run.Component, run.Messages))) &&
    adapter::ConvertIsoValues(this->ContourValues, run.Values, run.Messages);
  if (ok && this->ColorByArray && run.HasPiece)
  {
    int colorAssociation = -1;
    run.ColorArray = this->GetPointArray(1, inputVector, colorAssociation);
    ok = run.ColorArray &&
      adapter::CheckPointArray(run.ColorArray, colorAssociation, this->ColorArrayComponent, true,
        "ColorArrayComponent", run.ColorComponent, run.Messages);
  }
  ok = ok &&
    adapter::ConvertClipPlanes(this->ClippingPlanes, run.ClipPlanes, run.Messages);
  run.ColorMapped =
    tetdsr::isColorMapped(this->ColorByArray, this->Capping != NO_CAP, run.ClipPlanes.size());
  ok = run.Processes.All(ok);
  adapter::ReportMessages(this, run.Messages);
  return ok;
}

bool vtkDirectSurfaceRayCaster::PrepareScene(Execution& run)
{
  tetdsr::TransverseTest transverse;
  transverse.mode = this->TransverseTest == WIDENED_NODAL_RANGE
    ? tetdsr::TransverseTest::Mode::WidenedNodalRange
    : tetdsr::TransverseTest::Mode::BernsteinBound;
  transverse.widening = this->NodalRangeWidening;
  adapter::PreparedMesh& prepared = this->Prepared->Mesh;
  const bool ready = run.HasPiece &&
    prepared.Prepare(
      run.Input, run.Scalars, run.Component, transverse, this->NumberOfThreads, run.Messages);
  const tetdsr::PreprocessSummary summary =
    run.HasPiece ? prepared.GetSummary() : tetdsr::PreprocessSummary();
  this->NumberOfRenderedCells = ready ? summary.validCells : 0;
  this->NumberOfInvertedCells = summary.invertedCells;
  this->NumberOfCurvedCells = summary.curvedCells;
  this->NumberOfDegenerateCells = summary.degenerateCells;
  this->NumberOfTangledCells = summary.tangledCells;
  this->NumberOfOutOfScaleCells = summary.outOfScaleCells;
  this->NumberOfNonFiniteCells = summary.nonFiniteCells;
  this->NumberOfInvalidIdCells = summary.invalidIdCells;
  this->NumberOfUnsupportedCells = summary.unsupportedCells;
  this->NumberOfMalformedCells = summary.malformedCells;
  this->NumberOfOrderTooHighCells = summary.orderTooHighCells;
  this->NumberOfRationalCells = summary.rationalCells;
  this->NumberOfHigherOrderCells = summary.higherOrderCells;
  this->NumberOfGhostCells = summary.ghostCells;
  run.ColorValues = run.ColorArray && ready
    ? prepared.PointArrayValues(run.ColorArray, "colour array", run.Messages)
    : nullptr;
  const bool ok = run.Processes.All(run.Messages.ok() && (ready || !run.HasPiece));
  adapter::ReportMessages(this, run.Messages); // the errors, or the warnings of cells skipped
  run.Scene = ready ? prepared.GetScene() : nullptr;
  return ok;
}

bool vtkDirectSurfaceRayCaster::ChooseCamera(Execution& run)
{
  bool readable = true; // (every process has the camera: they all refuse it, or none)
  if (this->Camera)
  {
    run.Camera = CoreCamera(this->Camera);
    readable = tetdsr::checkCameraExtras(CameraExtrasOf(this->Camera), run.Messages);
  }
  else
  {
    double bounds[6];
    if (!run.Scene || !run.Scene->bounds(bounds))
    {
      ProcessGroup::EmptyBox(bounds);
    }
    run.Processes.UniteBoxes(bounds);
    run.Camera = tetdsr::resetCamera(bounds, static_cast<double>(run.Width) / run.Height);
  }
  const bool ok = run.Processes.All(
    readable && (!run.Scene || tetdsr::checkCamera(run.Camera, *run.Scene, run.Messages)));
  adapter::ReportMessages(this, run.Messages);
  return ok;
}

void vtkDirectSurfaceRayCaster::ChooseShading(Execution& run)
{
  tetdsr::RenderSettings& settings = run.Settings;
  settings = ShadingSettings(this, this->Prepared->Styles, run.Camera, run.Values.size());
  if (run.Scene && settings.normals.mode == tetdsr::NormalMode::NodalInterpolation)
  {
    run.Scene->computeNodalGradients(); // once per mesh and array: kept with the scene
  }
  settings.clipPlanes = run.ClipPlanes;
  if (!run.ColorMapped)
  {
    return;
  }
  double range[2] = { this->ColorRange[0], this->ColorRange[1] };
  if (!tetdsr::isUsableColorRange(range[0], range[1]))
  {
    // The colour array's finite range (-1: the magnitude's), else the field's, over every piece.
    ProcessGroup::EmptyRange(range);
    if (run.HasPiece)
    {
      adapter::FiniteRange(run.ColorArray ? run.ColorArray : run.Scalars,
        run.ColorArray ? run.ColorComponent : run.Component, range);
    }
    run.Processes.UniteRanges(range);
  }
  if (run.ColorArray)
  {
    settings.colorBy.values = run.ColorValues;
    settings.colorBy.components = run.ColorArray->GetNumberOfComponents();
    settings.colorBy.component = run.ColorComponent;
  }
  vtkSmartPointer<vtkScalarsToColors> lookupTable = this->LookupTable;
  if (!lookupTable)
  {
    lookupTable = BuiltInColorMap(this->ColorMap);
  }
  settings.colorTable = adapter::SampleColorTable(lookupTable, range[0], range[1]);
}

bool vtkDirectSurfaceRayCaster::CastPiece(Execution& run)
{
  const tetdsr::Renderer renderer(
    this->Prepared->Mesh.GetSurface(run.Values, this->NumberOfThreads), run.Camera, run.Settings,
    run.View);
  const vtkIdType tiles = renderer.numberOfTiles();
  const tetdsr::NodeId uncertifiedBefore = run.Scene->uncertifiedHits();
  const vtkIdType tilesDone = adapter::Cast(
    renderer, run.Settings.normals.mode == tetdsr::NormalMode::DepthBuffer, this->NumberOfThreads,
    [this]() { return this->CheckAbort(); },
    [this](double fraction) { this->UpdateProgress(fraction); });
  this->NumberOfUncertifiedHits =
    static_cast<vtkIdType>(run.Scene->uncertifiedHits() - uncertifiedBefore);
  if (tilesDone < tiles)
  {
    tetdsr::reportAbortedCast(tilesDone, tiles, run.Messages);
    adapter::ReportMessages(this, run.Messages);
    return false;
  }
  return true;
}

bool vtkDirectSurfaceRayCaster::Pick(double x, double y, vtkDirectSurfacePick* result)
{
  if (!result)
  {
    return false;
  }
  result->Initialize();
  Cache& cache = *this->Prepared;
  vtkUnstructuredGrid* input = cache.Input;
  if (!input || adapter::MeshModifiedTime(input) != cache.InputTime || !std::isfinite(x) ||
    !std::isfinite(y))
  {
    return false;
  }
  const tetdsr::RayGenerator rays(cache.Camera, cache.Width, cache.Height);
  tetdsr::Pick pick;
  adapter::Messages messages;
  const bool found = adapter::PickPrepared(cache.Mesh, cache.Values, cache.Settings,
    rays.displayRay(x, y), std::numeric_limits<double>::infinity(), this->NumberOfThreads, pick);
  if (found)
  {
    adapter::FillPick(pick, input, cache.Mesh, -1, glm::dmat4(1.0), 1.0, result, messages);
  }
  adapter::ReportMessages(this, messages);
  return found;
}

void vtkDirectSurfaceRayCaster::MapCellIds(const Execution& run)
{
  const vtkIdType cellOffset =
    run.Processes.CellsBefore(run.HasPiece ? run.Input->GetNumberOfCells() : 0);
  vtkIdType* ids = run.View.cellIds;
  const vtkIdType pixels = run.Pixels();
  for (vtkIdType p = 0; p < pixels; ++p)
  {
    if (ids[p] >= 0)
    {
      ids[p] += cellOffset;
    }
  }
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
  os << indent << "Controller: " << this->Controller << "\n";
  os << indent << "NumberOfRenderedCells: " << this->NumberOfRenderedCells << "\n";
  os << indent << "NumberOfInvertedCells: " << this->NumberOfInvertedCells << "\n";
  os << indent << "NumberOfCurvedCells: " << this->NumberOfCurvedCells << "\n";
  os << indent << "NumberOfDegenerateCells: " << this->NumberOfDegenerateCells << "\n";
  os << indent << "NumberOfTangledCells: " << this->NumberOfTangledCells << "\n";
  os << indent << "NumberOfUncertifiedHits: " << this->NumberOfUncertifiedHits << "\n";
  os << indent << "NumberOfNonFiniteCells: " << this->NumberOfNonFiniteCells << "\n";
  os << indent << "NumberOfInvalidIdCells: " << this->NumberOfInvalidIdCells << "\n";
  os << indent << "NumberOfUnsupportedCells: " << this->NumberOfUnsupportedCells << "\n";
  os << indent << "NumberOfMalformedCells: " << this->NumberOfMalformedCells << "\n";
  os << indent << "NumberOfOrderTooHighCells: " << this->NumberOfOrderTooHighCells << "\n";
  os << indent << "NumberOfRationalCells: " << this->NumberOfRationalCells << "\n";
  os << indent << "NumberOfHigherOrderCells: " << this->NumberOfHigherOrderCells << "\n";
  os << indent << "NumberOfOutOfScaleCells: " << this->NumberOfOutOfScaleCells << "\n";
  os << indent << "NumberOfGhostCells: " << this->NumberOfGhostCells << "\n";
  os << indent << "PreprocessedBytes: " << this->GetPreprocessedBytes() << "\n";
}
