#include "tetdsr/input/MeshInput.h"

#include "tetdsr/cells/QuadraticTetCell.h"
#include "tetdsr/cells/SplitCells.h"

#include <algorithm>
#include <cstring>

namespace tetdsr
{

std::size_t bytesOf(NumberType type)
{
  switch (type)
  {
    case NumberType::Int8:
    case NumberType::UInt8:
      return 1;
    case NumberType::Int16:
    case NumberType::UInt16:
      return 2;
    case NumberType::Float32:
    case NumberType::Int32:
    case NumberType::UInt32:
      return 4;
    case NumberType::Float64:
    case NumberType::Int64:
    case NumberType::UInt64:
      break;
  }
  return 8;
}

namespace
{
/// Calls `use` with the array's data as a pointer to its own number type.
template <typename Use>
void withTypedData(const ArrayView& array, Use&& use)
{
  switch (array.type)
  {
    case NumberType::Float32:
      return use(static_cast<const float*>(array.data));
    case NumberType::Float64:
      return use(static_cast<const double*>(array.data));
    case NumberType::Int8:
      return use(static_cast<const std::int8_t*>(array.data));
    case NumberType::UInt8:
      return use(static_cast<const std::uint8_t*>(array.data));
    case NumberType::Int16:
      return use(static_cast<const std::int16_t*>(array.data));
    case NumberType::UInt16:
      return use(static_cast<const std::uint16_t*>(array.data));
    case NumberType::Int32:
      return use(static_cast<const std::int32_t*>(array.data));
    case NumberType::UInt32:
      return use(static_cast<const std::uint32_t*>(array.data));
    case NumberType::Int64:
      return use(static_cast<const std::int64_t*>(array.data));
    case NumberType::UInt64:
      return use(static_cast<const std::uint64_t*>(array.data));
  }
}

} // namespace

/// Components [first, first + count) of the first `tuples` tuples, as doubles, one tuple after
/// another: a view when the array holds exactly that as Float64, else converted into `copy`.
const double* asDoubles(const ArrayView& array, NodeId tuples, int first, int count,
  std::vector<double>& copy)
{
  if (array.type == NumberType::Float64 && first == 0 && count == array.components)
  {
    return static_cast<const double*>(array.data);
  }
  copy.resize(static_cast<std::size_t>(tuples) * static_cast<std::size_t>(count));
  withTypedData(array, [&](auto* data) {
    for (NodeId t = 0; t < tuples; ++t)
    {
      for (int c = 0; c < count; ++c)
      {
        copy[static_cast<std::size_t>(t * count + c)] =
          static_cast<double>(data[t * array.components + first + c]);
      }
    }
  });
  return copy.data();
}

namespace
{

/// An id array (offsets, connectivity) as 64-bit ids: viewed when Int64, else converted.
const NodeId* asIds(const ArrayView& array, std::vector<NodeId>& copy)
{
  if (array.type == NumberType::Int64)
  {
    return static_cast<const NodeId*>(array.data);
  }
  copy.resize(static_cast<std::size_t>(array.tuples));
  withTypedData(array, [&](auto* data) {
    for (NodeId k = 0; k < array.tuples; ++k)
    {
      copy[static_cast<std::size_t>(k)] = static_cast<NodeId>(data[k]);
    }
  });
  return copy.data();
}

std::string nameOf(const ArrayView& array)
{
  return array.name.empty() ? std::string("(unnamed)") : array.name;
}

bool isIdType(NumberType type)
{
  return type == NumberType::Int32 || type == NumberType::Int64;
}

/// Checks the sizes and types the arrays claim, before anything is read.
bool checkArrays(const MeshArrays& arrays, NodeId numberOfCells, Messages& messages)
{
  const NodeId numberOfPoints = arrays.points.tuples;
  if (numberOfCells > Scene::kMaxCells)
  {
    messages.errors.push_back(text("The input has ", numberOfCells, " cells; at most ",
      Scene::kMaxCells, " can be rendered."));
    return false;
  }
  const ArrayView& types = arrays.cellTypes;
  if (!types.data || types.type != NumberType::UInt8 || types.tuples < numberOfCells ||
    types.components != 1)
  {
    messages.errors.push_back(text("The input's cell types array has ",
      types.data ? types.tuples * types.components : 0, " values for ", numberOfCells, " cells."));
    return false;
  }
  if (!isIdType(arrays.offsets.type) || arrays.offsets.components != 1 ||
    !isIdType(arrays.connectivity.type) || arrays.connectivity.components != 1 ||
    (arrays.connectivity.tuples > 0 && !arrays.connectivity.data))
  {
    messages.errors.push_back("The input's cell offsets and connectivity must be arrays of 32- or "
                              "64-bit integers with one component.");
    return false;
  }
  if (arrays.points.components != 3 || !arrays.points.data)
  {
    messages.errors.push_back(text("The input's points have ", arrays.points.components,
      " components: points need 3 (x, y, z)."));
    return false;
  }
  const ArrayView& field = arrays.field;
  if (field.tuples < numberOfPoints || !field.data)
  {
    messages.errors.push_back(text("Point array '", nameOf(field), "' has ", field.tuples,
      " tuples for ", numberOfPoints, " points."));
    return false;
  }
  if (arrays.fieldComponent < 0 || arrays.fieldComponent >= field.components)
  {
    messages.errors.push_back(text("Component ", arrays.fieldComponent, " of point array '",
      nameOf(field), "' is out of range: it has ", field.components, " components."));
    return false;
  }
  const ArrayView& weights = arrays.rationalWeights;
  if (arrays.hasRationalWeights &&
    (weights.tuples < numberOfPoints || weights.components != 1 || !weights.data))
  {
    messages.errors.push_back(text("The rational weights array '", nameOf(weights), "' has ",
      weights.tuples, " tuples of ", weights.components, " components for ", numberOfPoints,
      " points: it needs one value per point."));
    return false;
  }
  const ArrayView& ghosts = arrays.cellGhosts;
  if (arrays.hasCellGhosts &&
    (ghosts.tuples < numberOfCells || ghosts.components != 1 || !ghosts.data ||
      ghosts.type != NumberType::UInt8))
  {
    messages.errors.push_back(text("The cell ghost array '", nameOf(ghosts), "' has ",
      ghosts.tuples, " tuples of ", ghosts.components, " components",
      ghosts.type != NumberType::UInt8 ? " of a type other than unsigned 8-bit" : "", " for ",
      numberOfCells, " cells: it needs one unsigned 8-bit value per cell."));
    return false;
  }
  return true;
}

/// The warnings for every kind of cell the scene skipped, then whether any cell is left.
bool describeSkipped(const PreprocessSummary& summary, NodeId numberOfCells, NodeId numberOfPoints,
  const std::string& fieldName, Messages& messages)
{
  if (summary.unsupportedCells + summary.malformedCells + summary.orderTooHighCells == numberOfCells)
  {
    messages.errors.push_back(text("No cell can be rendered: none of the ", numberOfCells,
      " input cells is a well-formed cell of a type TetDSR reads (", readTypesText(), "): ",
      summary.unsupportedCells, " of another type, ", summary.orderTooHighCells,
      " of an order it does not read, ", summary.malformedCells, " malformed."));
    return false;
  }
  std::vector<std::string>& warnings = messages.warnings;
  if (summary.unsupportedCells > 0)
  {
    warnings.push_back(text("Skipped ", summary.unsupportedCells,
      " cells of a type TetDSR does not read (it reads ", readTypesText(), "; not ", refusedTypesText(),
      ")."));
  }
  if (summary.orderTooHighCells > 0)
  {
    warnings.push_back(text("Skipped ", summary.orderTooHighCells,
      " cells of an order TetDSR does not read: ", orderLimitsText(), "."));
  }
  if (summary.malformedCells > 0)
  {
    warnings.push_back(text("Skipped ", summary.malformedCells,
      " malformed cells: a number of node ids that does not fit the type (", nodeCountsText(),
      "; VTK's 15-node Lagrange tetrahedron and 21-node Lagrange wedge, with extra face and body "
      "nodes, are not read), or offsets out of order or past the end of the connectivity array."));
  }
  if (summary.rationalCells > 0)
  {
    warnings.push_back(text("Skipped ", summary.rationalCells,
      " rational Bezier cells (rational weights that differ within the cell, or "
      "are not positive and finite): TetDSR renders polynomial Bezier cells only."));
  }
  if (summary.tangledCells > 0)
  {
    warnings.push_back(text("Skipped ", summary.tangledCells,
      " tangled curved cells (nodes so far off their straight places that the cell folds: the "
      "Jacobian determinant of its map changes sign or vanishes inside it)."));
  }
  if (summary.degenerateCells > 0)
  {
    warnings.push_back(text("Skipped ", summary.degenerateCells,
      " degenerate cells (flat or needle-like: 6 x volume below 1e-13 of the longest edge cubed; "
      "or a node id repeated within the cell)."));
  }
  if (summary.outOfScaleCells > 0)
  {
    warnings.push_back(text("Skipped ", summary.outOfScaleCells, " cells whose longest edge or box is outside [",
      QuadraticTetCell::kMinCellSize, ", ", QuadraticTetCell::kMaxCellSize,
      "], or whose Bernstein coefficients (made from Lagrange nodes) leave double range: their "
      "volumes or coefficients would underflow or overflow double precision."));
  }
  if (summary.nonFiniteCells > 0)
  {
    warnings.push_back(text("Skipped ", summary.nonFiniteCells, " cells with NaN or Inf values of '",
      fieldName, "' or coordinates at their nodes."));
  }
  if (summary.invalidIdCells > 0)
  {
    warnings.push_back(text("Skipped ", summary.invalidIdCells,
      " cells with node ids outside [0, ", numberOfPoints, ")."));
  }
  if (summary.validCells == 0)
  {
    messages.errors.push_back(text("No cell can be rendered: all ", numberOfCells,
      " input cells were skipped",
      summary.ghostCells > 0 ? text(" (", summary.ghostCells,
                                 " of them ghost cells, which the pieces that own them draw)")
                             : std::string(),
      "."));
    return false;
  }
  return true;
}
} // namespace

bool checkMeshNotEmpty(NodeId numberOfPoints, NodeId numberOfCells, Messages& messages)
{
  if (numberOfPoints <= 0 || numberOfCells <= 0)
  {
    messages.errors.push_back("The input mesh is empty: it has no cells or no points.");
    return false;
  }
  return true;
}

bool checkMeshHasFinitePoints(bool anyFinitePoint, NodeId numberOfCells, Messages& messages)
{
  if (!anyFinitePoint)
  {
    messages.errors.push_back(text("No cell can be rendered: no point of the input's ",
      numberOfCells, " cells has finite coordinates (all are NaN or Inf)."));
    return false;
  }
  return true;
}

bool checkInputKind(bool drawable, const std::string& kind, Messages& messages)
{
  if (!drawable)
  {
    messages.errors.push_back(text("A ", kind, " cannot be drawn: give a vtkUnstructuredGrid of "
      "the cells TetDSR reads, or a composite dataset of them."));
  }
  return drawable;
}

bool checkBlocks(std::size_t grids, std::size_t others, Messages& messages)
{
  if (grids == 0)
  {
    messages.errors.push_back(
      "The input is neither a vtkUnstructuredGrid nor a composite dataset of them.");
    return false;
  }
  if (others > 0)
  {
    messages.warnings.push_back(text(others, " of ", others + grids,
      " blocks of the composite input are not vtkUnstructuredGrid: not drawn."));
  }
  return true;
}

struct PreparedMesh::Internals
{
  // Copies of what could not be viewed (another number type or layout).
  std::vector<double> Points;
  std::vector<double> Values;
  std::vector<double> Weights;
  std::vector<NodeId> Offsets;
  std::vector<NodeId> Connectivity;
  NodeId NumberOfPoints = 0;

  std::unique_ptr<Scene> TheScene;
  bool Ready = false;
  std::vector<std::string> Errors; ///< the last prepare's, told again on reuse
  PreprocessSummary EmptySummary;

  /// The surface index of the last iso-values asked for, and those values as given.
  std::unique_ptr<SurfaceIndex> Surface;
  std::vector<double> SurfaceValues;

  /// The last colour array asked for (what identifies it) and its values as doubles.
  const void* ColorData = nullptr;
  NumberType ColorType = NumberType::Float64;
  NodeId ColorTuples = 0;
  int ColorComponents = 0;
  std::uint64_t ColorStamp = 0;
  std::vector<double> ColorCopy;
  const double* ColorValues = nullptr;
};

PreparedMesh::PreparedMesh()
  : Internal(new Internals)
{
}

PreparedMesh::~PreparedMesh() = default;

bool PreparedMesh::prepare(const MeshArrays& arrays, const TransverseTest& transverse,
  const ParallelFor& parallelFor, Messages& messages)
{
  // From scratch: nothing of a previous conversion is trusted.
  this->Internal.reset(new Internals);
  Internals& in = *this->Internal;
  const std::size_t errorsBefore = messages.errors.size();
  auto fail = [&]() {
    in.Errors.assign(messages.errors.begin() + static_cast<std::ptrdiff_t>(errorsBefore),
      messages.errors.end());
    return false;
  };
  const NodeId numberOfPoints = arrays.points.tuples;
  const NodeId numberOfCells = std::max<NodeId>(arrays.offsets.tuples - 1, 0);
  if (!checkMeshNotEmpty(numberOfPoints, numberOfCells, messages) ||
    !checkArrays(arrays, numberOfCells, messages))
  {
    return fail();
  }
  in.NumberOfPoints = numberOfPoints;
  MeshView mesh;
  mesh.numberOfPoints = numberOfPoints;
  mesh.points = asDoubles(arrays.points, numberOfPoints, 0, 3, in.Points);
  // Mid-edge nodes within rounding of their edges' midpoints are straight; float coordinates
  // round at 2^-24 relative.
  mesh.pointRounding = arrays.points.type == NumberType::Float32 ? 0x1p-23 : 0x1p-52;
  mesh.values = asDoubles(arrays.field, numberOfPoints, arrays.fieldComponent, 1, in.Values);
  mesh.numberOfCells = numberOfCells;
  mesh.cellTypes = static_cast<const std::uint8_t*>(arrays.cellTypes.data);
  mesh.offsets = asIds(arrays.offsets, in.Offsets);
  mesh.connectivity = asIds(arrays.connectivity, in.Connectivity);
  mesh.connectivitySize = arrays.connectivity.tuples;
  if (arrays.hasRationalWeights)
  {
    mesh.rationalWeights = asDoubles(arrays.rationalWeights, numberOfPoints, 0, 1, in.Weights);
  }
  if (arrays.hasCellGhosts)
  {
    mesh.cellGhosts = static_cast<const std::uint8_t*>(arrays.cellGhosts.data);
  }
  in.TheScene.reset(new Scene(mesh, parallelFor, transverse));
  if (!describeSkipped(
        in.TheScene->summary(), numberOfCells, numberOfPoints, nameOf(arrays.field), messages))
  {
    return fail();
  }
  in.Ready = true;
  return true;
}

bool PreparedMesh::reuse(Messages& messages) const
{
  const Internals& in = *this->Internal;
  messages.errors.insert(messages.errors.end(), in.Errors.begin(), in.Errors.end());
  return in.Ready;
}

Scene* PreparedMesh::scene() const
{
  return this->Internal->Ready ? this->Internal->TheScene.get() : nullptr;
}

const PreprocessSummary& PreparedMesh::summary() const
{
  return this->Internal->TheScene ? this->Internal->TheScene->summary() : this->Internal->EmptySummary;
}

const SurfaceIndex& PreparedMesh::surface(
  const std::vector<double>& isoValues, const ParallelFor& parallelFor)
{
  Internals& in = *this->Internal;
  if (!in.Surface || isoValues != in.SurfaceValues)
  {
    in.Surface.reset(
      new SurfaceIndex(*in.TheScene, IsoValues(isoValues), parallelFor, in.Surface.get()));
    in.SurfaceValues = isoValues;
  }
  return *in.Surface;
}

const double* PreparedMesh::pointValues(
  const ArrayView& array, std::uint64_t stamp, const char* role, Messages& messages)
{
  Internals& in = *this->Internal;
  if (array.tuples < in.NumberOfPoints || !array.data)
  {
    messages.errors.push_back(text("The ", role, " '", array.name, "' has ", array.tuples,
      " tuples for ", in.NumberOfPoints, " points."));
    return nullptr;
  }
  if (in.ColorValues && array.data == in.ColorData && array.type == in.ColorType &&
    array.tuples == in.ColorTuples && array.components == in.ColorComponents &&
    stamp == in.ColorStamp)
  {
    return in.ColorValues;
  }
  in.ColorData = array.data;
  in.ColorType = array.type;
  in.ColorTuples = array.tuples;
  in.ColorComponents = array.components;
  in.ColorStamp = stamp;
  in.ColorCopy.clear();
  in.ColorValues = asDoubles(array, in.NumberOfPoints, 0, array.components, in.ColorCopy);
  return in.ColorValues;
}

std::size_t PreparedMesh::memoryBytes() const
{
  const Internals& in = *this->Internal;
  return (in.TheScene ? in.TheScene->memoryBytes() : 0) +
    (in.Surface ? in.Surface->memoryBytes() : 0) +
    sizeof(double) * (in.Points.capacity() + in.Values.capacity() + in.ColorCopy.capacity()) +
    sizeof(NodeId) * (in.Offsets.capacity() + in.Connectivity.capacity());
}

} // namespace tetdsr
