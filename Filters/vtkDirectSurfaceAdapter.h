// The one layer between VTK and the VTK-free core, shared by every VTK face of TetDSR (the
// filter vtkDirectSurfaceRayCaster and the mapper vtkDirectSurfaceMapper): it checks VTK data
// against the sizes it claims, converts it to the core's inputs once, keeps the prepared scene
// while nothing it was built from changes, turns VTK settings (iso-values, lookup tables,
// clipping planes) into the core's, and casts an image on VTK's threads. It never prints:
// problems come back as messages, which each face reports through its own vtkErrorMacro /
// vtkWarningMacro.
//
// Not wrapped for Python: a C++ helper of the TetDSR modules.
#ifndef vtkDirectSurfaceAdapter_h
#define vtkDirectSurfaceAdapter_h

#include "TetDSRFiltersModule.h" // for export macro
#include "vtkType.h"

#include "tetdsr/MeshInput.h"
#include "tetdsr/Messages.h"
#include "tetdsr/Renderer.h"
#include "tetdsr/Scene.h"
#include "tetdsr/SurfaceIndex.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

class vtkContourValues;
class vtkDataArray;
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

/// Per-iso-value colours and opacities, as the filter and the mapper let users set them: index i
/// is the i-th iso-value as given; unset entries fall back to the surface colour and opacity 1.
class TETDSRFILTERS_EXPORT IsoValueStyles
{
public:
  /// Indices are refused at and beyond this (no scene needs a million surfaces).
  static constexpr int kMaxIndex = 1 << 20;
  /// False, with an error, for an index outside [0, kMaxIndex). Components are clamped to [0, 1].
  bool SetColor(int i, double red, double green, double blue, Messages& messages);
  bool SetOpacity(int i, double opacity, Messages& messages);
  void GetColor(int i, const double fallback[3], double color[3]) const;
  double GetOpacity(int i) const;
  /// True when something was removed.
  bool RemoveAllColors();
  bool RemoveAllOpacities();
  /// The core's styles of `count` iso-values; every opacity is multiplied by `opacityFactor`.
  std::vector<SurfaceStyle> Styles(std::size_t count, const double fallback[3], double opacityFactor) const;
  /// "r g b ..." and "a ..." of what is set, NaN where not.
  std::string Describe() const;

private:
  std::vector<double> Colors;    ///< 3 per iso-value; NaN: not set
  std::vector<double> Opacities; ///< NaN: not set
};

/// Iso-values from VTK's contour values; false, with an error, when there is none or one is
/// not finite.
TETDSRFILTERS_EXPORT bool ConvertIsoValues(
  vtkContourValues* contourValues, std::vector<double>& values, Messages& messages);

/// Clipping planes (at most `maximum`); false, with an error, for too many planes or a zero or
/// non-finite normal or origin.
TETDSRFILTERS_EXPORT bool ConvertClipPlanes(vtkPlaneCollection* planes, int maximum,
  std::vector<ClipPlane>& clipPlanes, Messages& messages);

/// Checks an array chosen as a field or colour array: a point array whose component
/// `requestedComponent` exists (-1: the only one, or with allowMagnitude the vector's magnitude).
/// `componentSetting` names the setting the user chose the component with, for the messages.
/// Returns the component to use through `component`.
TETDSRFILTERS_EXPORT bool CheckPointArray(vtkDataArray* array, int association,
  int requestedComponent, bool allowMagnitude, const char* componentSetting, int& component,
  Messages& messages);

/// The range of one component (-1: the magnitude) over its finite values only, so one Inf does
/// not stretch a colour map to nothing; [0, 1] when no value is finite.
TETDSRFILTERS_EXPORT void FiniteRange(vtkDataArray* array, int component, double range[2]);

/// `lookupTable` sampled over its own range into a table spanning [lo, hi].
TETDSRFILTERS_EXPORT ColorTable SampleColorTable(vtkScalarsToColors* lookupTable, double lo, double hi);

/// False, with an error naming the size and the bytes, when an image of width x height pixels
/// of `bytesPerPixel` each cannot be allocated: more than the machine's physical memory, or a
/// size beyond VTK's 32-bit extents.
TETDSRFILTERS_EXPORT bool CheckImageSize(
  int width, int height, double bytesPerPixel, const char* what, Messages& messages);

/// False, with an error, when the camera cannot see the scene with double-precision rays: a
/// degenerate camera (the reason named), or one farther from the scene than kMaxCameraDistance
/// times its diagonal (hits would carry a rounding error above 1e-7 of the scene).
constexpr double kMaxCameraDistance = 1e9;
TETDSRFILTERS_EXPORT bool CheckCamera(const Camera& camera, const Scene& scene, Messages& messages);

/// Renders every tile of `renderer` on `numberOfThreads` threads (0: all cores), in steps
/// between which `abort` is asked (true: stop) and `progress` told the fraction done. Returns
/// the number of tiles rendered (all of them unless aborted).
TETDSRFILTERS_EXPORT NodeId Cast(const Renderer& renderer, bool depthBufferNormals,
  int numberOfThreads, const std::function<bool()>& abort,
  const std::function<void(double)>& progress);

/// Runs `work` with vtkSMPTools set to `numberOfThreads` (0: all cores), on STDThread when VTK's
/// default backend is Sequential (ParaView's) and the user did not choose one.
TETDSRFILTERS_EXPORT void WithThreads(int numberOfThreads, const std::function<void()>& work);

} // namespace vtkadapter
} // namespace tetdsr

#endif
