// The core's contract with every face: a mesh as VTK's vtkUnstructuredGrid and numpy hold it
// (points, VTK cell type codes, offsets, connectivity, point fields), checked against every size
// it claims, viewed without copies where its layout is the core's, converted once where not, and
// validated cell by cell into a Scene; every problem comes back as a sentence (Messages.h). The
// C++ adapter, the mapper and the Python binding only fill MeshArrays and pass the messages on.
#pragma once

#include "tetdsr/common/Messages.h"
#include "tetdsr/index/Scene.h"
#include "tetdsr/index/SurfaceIndex.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tetdsr
{

/// How an array's numbers are stored (VTK's data types; numpy's dtypes).
enum class NumberType : std::uint8_t
{
  Float32,
  Float64,
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Int64,
  UInt64
};

/// Bytes per number of a type.
std::size_t bytesOf(NumberType type);

/// A non-owning view of `tuples` tuples of `components` numbers each, stored one tuple after
/// another (VTK's AOS arrays, C-contiguous numpy arrays). The data must outlive what is built
/// from it: a Scene views it.
struct ArrayView
{
  const void* data = nullptr;
  NumberType type = NumberType::Float64;
  NodeId tuples = 0;
  int components = 1;
  std::string name; ///< as messages name it ("" for unnamed)
};

/// Components [first, first + count) of an array's first `tuples` tuples, as doubles, one tuple
/// after another: a view when the array holds exactly that as Float64, else converted into
/// `copy`. The caller has checked that the array holds `tuples` tuples of `first + count`
/// components.
const double* asDoubles(const ArrayView& array, NodeId tuples, int first, int count,
  std::vector<double>& copy);

/// A mesh as VTK holds it.
struct MeshArrays
{
  ArrayView points;       ///< 3 components, Float32 or Float64
  ArrayView cellTypes;    ///< UInt8: one VTK cell type code per cell
  ArrayView offsets;      ///< Int32 or Int64: number of cells + 1 entries
  ArrayView connectivity; ///< Int32 or Int64: the cells' point ids, one after another
  ArrayView field;        ///< the scalar field: one tuple per point, any NumberType
  int fieldComponent = 0; ///< the component of `field` that is contoured
  /// VTK's rational weights of Bezier cells (vtkPointData::GetRationalWeights): one value per
  /// point, any NumberType; read when `hasRationalWeights` (an empty array is an array: too short).
  ArrayView rationalWeights;
  bool hasRationalWeights = false;
  /// VTK's cell ghost flags ("vtkGhostType", vtkDataSet::GetCellGhostArray): UInt8, one value
  /// per cell; read when `hasCellGhosts`. Cells flagged duplicate or hidden are left out
  /// (MeshView::cellGhosts), so that a piece draws, composites and names only its own cells.
  ArrayView cellGhosts;
  bool hasCellGhosts = false;
};

/// "The input mesh is empty ..." unless there are points and cells.
bool checkMeshNotEmpty(NodeId numberOfPoints, NodeId numberOfCells, Messages& messages);

/// "No cell can be rendered: ..." unless some point has finite coordinates (a mesh whose
/// bounds are not finite; a renderer culls it before any cell is looked at).
bool checkMeshHasFinitePoints(bool anyFinitePoint, NodeId numberOfCells, Messages& messages);

/// An input of a kind that cannot be drawn (`kind`: its class): an error naming it, unless
/// `drawable` (a vtkUnstructuredGrid or a composite dataset).
bool checkInputKind(bool drawable, const std::string& kind, Messages& messages);

/// The blocks of an input: an error when none is a vtkUnstructuredGrid (`grids`), and a warning
/// counting the `others`, which are not drawn.
bool checkBlocks(std::size_t grids, std::size_t others, Messages& messages);

/// A mesh prepared for rendering: its scene (validation, every decision on every cell), the
/// arrays converted for it, the surface index of the last iso-values, and a colour array's
/// values. Build one, keep it while the input does not change (the face decides that: VTK's
/// modification times, Python's stamps) and ask it for surfaces.
class PreparedMesh
{
public:
  PreparedMesh();
  ~PreparedMesh();
  PreparedMesh(const PreparedMesh&) = delete;
  PreparedMesh& operator=(const PreparedMesh&) = delete;

  /// Checks every size `arrays` claim, then views or converts them and validates every cell (in
  /// parallel through `parallelFor`). False, with errors, when nothing can be rendered; the
  /// warnings count every kind of skipped cell.
  bool prepare(const MeshArrays& arrays, const TransverseTest& transverse,
    const ParallelFor& parallelFor, Messages& messages);

  /// For an input the face found unchanged since the last prepare: that prepare's errors again
  /// (its warnings were told when it was built); false if it failed.
  bool reuse(Messages& messages) const;

  /// The scene of the last successful prepare (null before, or after a failed one).
  Scene* scene() const;
  /// The counts of the last prepare (all zero before).
  const PreprocessSummary& summary() const;

  /// The surface index of the scene for these iso-values (as given: their order matters for
  /// styles, not for the index), rebuilt only when they or the scene changed. Only after a
  /// successful prepare.
  const SurfaceIndex& surface(const std::vector<double>& isoValues, const ParallelFor& parallelFor);

  /// A point array's values as doubles, every component (a colour array): viewed when stored as
  /// Float64, else converted and kept until asked for another array or `stamp` changes. Null,
  /// with an error naming `role`, when it has fewer tuples than the mesh has points.
  const double* pointValues(
    const ArrayView& array, std::uint64_t stamp, const char* role, Messages& messages);

  /// Bytes kept besides the input: the scene, its surface index and converted copies.
  std::size_t memoryBytes() const;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace tetdsr
