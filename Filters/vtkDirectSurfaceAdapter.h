// The one layer between VTK and the VTK-free core, shared by every VTK face of TetDSR (the
// filters vtkDirectSurfaceRayCaster and vtkDirectSurfaceContour, and the mapper
// vtkDirectSurfaceMapper): it hands VTK's arrays
// to the core's mesh contract (tetdsr/input/MeshInput.h, which checks and converts them), keeps the
// prepared scene while nothing it was built from changes, turns VTK settings (iso-values, lookup
// tables, clipping planes) into the core's (tetdsr/input/Settings.h, which checks them), and casts an
// image on VTK's threads. It decides nothing and writes no sentence: the core's messages are
// reported by vtkDirectSurfaceReporting.h.
//
// Not wrapped for Python: a C++ helper of the TetDSR modules.
#ifndef vtkDirectSurfaceAdapter_h
#define vtkDirectSurfaceAdapter_h

#include "TetDSRFiltersModule.h" // for export macro
#include "vtkType.h"

#include "tetdsr/surface/ExactSurface.h"
#include "tetdsr/input/MeshInput.h"
#include "tetdsr/common/Messages.h"
#include "tetdsr/render/Renderer.h"
#include "tetdsr/index/Scene.h"
#include "tetdsr/input/Settings.h"
#include "tetdsr/index/SurfaceIndex.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

class vtkContourValues;
class vtkDataArray;
class vtkDirectSurfacePick;
class vtkPlaneCollection;
class vtkScalarsToColors;
class vtkUnstructuredGrid;

namespace tetdsr
{
namespace vtkadapter
{

/// The core's messages (errors and counted warnings), passed on by each face.
using Messages = tetdsr::Messages;

/// A mesh and field converted for the core, and the scene (validation + hierarchy) built from
/// them; kept until the mesh, its points, cells or types, or the field array change.
class TETDSRFILTERS_EXPORT PreparedMesh
{
public:
  PreparedMesh();
  ~PreparedMesh();
  PreparedMesh(const PreparedMesh&) = delete;
  PreparedMesh& operator=(const PreparedMesh&) = delete;

  /// Makes the scene current for `input` and its point array `scalars` (one `component`):
  /// re-uses the last one when none of them changed, else checks every size the input claims
  /// and builds it on `numberOfThreads` threads (0: all cores). False, with errors, when
  /// nothing can be rendered; warnings count the cells skipped, once, when the scene is built
  /// (a mapper re-uses it every frame).
  bool Prepare(vtkUnstructuredGrid* input, vtkDataArray* scalars, int component,
    const TransverseTest& transverse, int numberOfThreads, Messages& messages);

  /// The scene of the last successful Prepare (null before).
  Scene* GetScene() const;

  /// The surface index of the scene for these iso-values (as given: order matters for styles,
  /// not for the index), built on `numberOfThreads` threads (0: all cores) when the values or
  /// the scene changed since the last call. Only after a successful Prepare.
  const SurfaceIndex& GetSurface(const std::vector<double>& isoValues, int numberOfThreads);

  /// Counts of the last Prepare (the core's, cells of unread types and malformed ones among them).
  const PreprocessSummary& GetSummary() const;

  /// A point array's values as doubles (all components), viewed or copied once and kept until
  /// the array changes. Null, with an error, when the array has fewer tuples than the mesh has
  /// points.
  const double* PointArrayValues(vtkDataArray* array, const char* role, Messages& messages);

  /// Bytes kept besides the input: the scene and any converted copies.
  std::size_t MemoryBytes() const;

  struct Internals; // (public only so that its helpers in the .cxx may name it)

private:
  std::unique_ptr<Internals> Internal;
};

/// The latest modification time of a mesh: the grid's own, and its points', cell arrays',
/// types' (vtkUnstructuredGrid::GetMTime does not follow edits of its cell arrays).
TETDSRFILTERS_EXPORT vtkMTimeType MeshModifiedTime(vtkUnstructuredGrid* grid);

/// The core's per-iso-value colours and opacities (tetdsr/input/Settings.h) with VTK's double[3]
/// colours, for the filter's and the mapper's SetIsoValueColor / SetIsoValueOpacity.
class TETDSRFILTERS_EXPORT IsoValueStyles
{
public:
  /// True when the stored value changed; false, with an error, for an index out of range.
  bool SetColor(int i, double red, double green, double blue, Messages& messages)
  {
    return this->Core.setColor(i, glm::dvec3(red, green, blue), messages);
  }
  bool SetOpacity(int i, double opacity, Messages& messages)
  {
    return this->Core.setOpacity(i, opacity, messages);
  }
  void GetColor(int i, const double fallback[3], double color[3]) const;
  double GetOpacity(int i) const { return this->Core.opacity(i); }
  /// True when something was removed.
  bool RemoveAllColors() { return this->Core.removeAllColors(); }
  bool RemoveAllOpacities() { return this->Core.removeAllOpacities(); }
  std::vector<SurfaceStyle> Styles(std::size_t count, const double fallback[3], double opacityFactor) const
  {
    return this->Core.styles(
      count, glm::dvec3(fallback[0], fallback[1], fallback[2]), opacityFactor);
  }
  std::string Describe() const { return this->Core.describe(); }

private:
  tetdsr::IsoValueStyles Core;
};

/// Iso-values from VTK's contour values, checked by the core.
TETDSRFILTERS_EXPORT bool ConvertIsoValues(
  vtkContourValues* contourValues, std::vector<double>& values, Messages& messages);

/// Clipping planes from VTK's, checked by the core (at most kMaxClipPlanes, finite, a nonzero
/// normal each).
TETDSRFILTERS_EXPORT bool ConvertClipPlanes(
  vtkPlaneCollection* planes, std::vector<ClipPlane>& clipPlanes, Messages& messages);

/// The core's check of an array chosen as a field or colour array (choosePointArrayComponent)
/// for a VTK array and its association.
TETDSRFILTERS_EXPORT bool CheckPointArray(vtkDataArray* array, int association,
  int requestedComponent, bool allowMagnitude, const char* componentSetting, int& component,
  Messages& messages);

/// The core's finite range of one component (-1: the magnitude) of a VTK array.
TETDSRFILTERS_EXPORT void FiniteRange(vtkDataArray* array, int component, double range[2]);

/// `lookupTable` sampled over its own range into a table spanning [lo, hi] (sampleColorTable).
TETDSRFILTERS_EXPORT ColorTable SampleColorTable(vtkScalarsToColors* lookupTable, double lo, double hi);

/// The core's castInSteps on vtkSMPTools' threads, `numberOfThreads` of them (0: all cores).
/// Returns the number of tiles rendered (all of them unless aborted).
TETDSRFILTERS_EXPORT NodeId Cast(const Renderer& renderer, bool depthBufferNormals,
  int numberOfThreads, const std::function<bool()>& abort,
  const std::function<void(double)>& progress);

/// Runs `work` with vtkSMPTools set to `numberOfThreads` (0: all cores), on STDThread when VTK's
/// default backend is Sequential (ParaView's) and the user did not choose one.
TETDSRFILTERS_EXPORT void WithThreads(int numberOfThreads, const std::function<void()>& work);

/// The core's exact surface (extractExactSurface) of a prepared mesh's scene, with `arrays` (point
/// arrays of the grid it was prepared from) viewed as VTK stores them, interpolated and
/// integrated, on `numberOfThreads` threads (0: all cores). Only after a successful Prepare.
TETDSRFILTERS_EXPORT bool ExtractExactSurface(const PreparedMesh& prepared,
  const ExactSurfaceSettings& settings, const std::vector<vtkDataArray*>& arrays,
  int numberOfThreads, ExactSurfaceMesh& surface, Messages& messages);

/// The core's Renderer::pick along `ray` (the mesh's coordinates, no farther than tLimit) in a
/// prepared mesh, with the iso-values and settings of a render. False when nothing is hit.
TETDSRFILTERS_EXPORT bool PickPrepared(PreparedMesh& prepared, const std::vector<double>& isoValues,
  const RenderSettings& settings, const Ray& ray, double tLimit, int numberOfThreads, Pick& pick);

/// `result` from a core pick in `grid` (block `flatIndex` of a composite input; -1 for none),
/// seen through `modelToWorld` (an actor's matrix): positions, normals, cell, parametric
/// coordinates, and every point array of the grid interpolated at the hit; `scale` turns the
/// ray's parameter into the result's RayParameter.
TETDSRFILTERS_EXPORT void FillPick(const Pick& pick, vtkUnstructuredGrid* grid,
  PreparedMesh& prepared, vtkIdType flatIndex, const glm::dmat4& modelToWorld, double scale,
  vtkDirectSurfacePick* result, Messages& messages);

} // namespace vtkadapter
} // namespace tetdsr

#endif
