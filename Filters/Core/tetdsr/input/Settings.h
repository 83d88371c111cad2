// The settings every face of TetDSR lets a user choose (iso-values, clipping planes, image size,
// camera, the field and colour arrays, per-iso-value styles, shading numbers, colour maps), each
// checked here once, with the sentence a user reads when it is refused. The faces (the VTK filter
// and mapper through Filters/vtkDirectSurfaceAdapter.h, the Python binding tetdsr._core) only
// translate their objects into these calls and pass the messages on.
#pragma once

#include "tetdsr/common/Camera.h"
#include "tetdsr/common/Messages.h"
#include "tetdsr/render/Renderer.h"
#include "tetdsr/index/Scene.h"

#include <glm/glm.hpp>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

namespace tetdsr
{

/// Bytes per output pixel of the filters: Colors (4), Depth (8), Normals (24), CellId (8),
/// ColorValues (8), and the depth-buffer normals' per-pixel record (64).
constexpr double kBytesPerPixel = 4 + 8 + 24 + 8 + 8 + 64;
/// Entries of a colour table sampled from a lookup table: 1024 keeps the linear interpolation
/// between entries within 1/255 of the lookup table's colour for any map with a few control
/// points.
constexpr int kColorTableSize = 1024;
/// Progress reports / abort checks per cast.
constexpr NodeId kProgressSteps = 32;
/// A camera farther from the scene than this many scene diagonals is refused: hits would carry
/// a rounding error above 1e-7 of the scene.
constexpr double kMaxCameraDistance = 1e9;
/// Clipping planes at most.
constexpr int kMaxClipPlanes = 6;

//------------------------------------------------------------------------------
// Iso-values, clipping planes, image size, camera

/// False, with an error, when there is no iso-value or one is not finite.
bool checkIsoValues(const std::vector<double>& values, Messages& messages);

/// A warning when the field `name`, whose finite nodal values span [lo, hi], is constant and
/// equal to an iso-value: it has no surface to draw (false then). A range that misses every
/// iso-value says nothing: a quadratic field may cross an iso-value between its nodes.
bool checkFieldNotConstantAtIsoValue(
  const std::vector<double>& values, double lo, double hi, const std::string& name, Messages& messages);

/// False, with an error, for more than kMaxClipPlanes planes, or a plane with a NaN or Inf in its
/// normal or origin, or a zero normal.
bool checkClipPlanes(const std::vector<ClipPlane>& planes, Messages& messages);

/// False, with an error naming the size and the bytes (kBytesPerPixel each), when an output image
/// of width x height pixels ("ImageSize") cannot be allocated: a side not positive, more than the
/// machine's physical memory, or 2^31 pixels or more (VTK's image extents and indices are ints).
bool checkImageSize(int width, int height, Messages& messages);

/// The error for an output image whose arrays could not be allocated.
void reportUnallocatedImage(int width, int height, Messages& messages);

/// False, with an error naming the reason, when the camera defines no rays.
bool checkCamera(const Camera& camera, Messages& messages);
/// The same, and false when the camera is farther than kMaxCameraDistance diagonals from the
/// scene's valid cells.
bool checkCamera(const Camera& camera, const Scene& scene, Messages& messages);

/// False, with an error, when a projection (normalised device coordinates to the rays' space, the
/// inverse of a view's composite projection) has a NaN or Inf: its matrix was singular.
bool checkProjection(const glm::dmat4& ndcToWorld, Messages& messages);

/// What a VTK camera may hold beyond a Camera's position, focal point, view up and view angle
/// (or parallel scale): each changes which ray a pixel has, so a filter whose rays come from a
/// Camera must refuse it rather than draw a different picture.
struct CameraExtras
{
  bool explicitProjection = false; ///< an explicit projection matrix
  bool offAxisProjection = false;  ///< an off-axis projection (screen corners and an eye)
  bool windowCenter = false;       ///< a window centre other than (0, 0)
  bool viewShear = false;          ///< a view shear
  bool transforms = false;         ///< a user (view) transform or a model transform matrix
};

/// False, with an error naming each extra the camera uses, when it uses any.
bool checkCameraExtras(const CameraExtras& extras, Messages& messages);

//------------------------------------------------------------------------------
// The field and the colour array

/// The point arrays a filter takes: input array 0 (the field) and 1 (the colour array).
enum class InputArray
{
  Field,
  Color
};

/// The error for an input array that was not found: `name` is the array asked for by name, or
/// null when it was asked for as the active point scalars (the field) or not chosen (colours).
void reportMissingArray(InputArray which, const char* name, Messages& messages);

/// Checks an array chosen as a field or colour array (`name`: "" when unnamed): a point array
/// whose component `requestedComponent` exists (-1: the only one, or with allowMagnitude the
/// vector's magnitude). `componentSetting` names the setting the component is chosen with, for
/// the messages; null for a face that has none (a many-component array is then refused with
/// advice to choose another array). The component to use (-1: the magnitude) comes back through `component`.
bool choosePointArrayComponent(const std::string& name, bool isPointArray, int components,
  int requestedComponent, bool allowMagnitude, const char* componentSetting, int& component,
  Messages& messages);

/// The range of one component (-1: the magnitude) over finite values only, so that one Inf does
/// not stretch a colour map to nothing; values may be added in blocks.
class FiniteRange
{
public:
  /// Adds `tuples` tuples of `components` doubles each.
  void add(const double* values, NodeId tuples, int components, int component);
  /// The range of what was added; [0, 1] when no value was finite.
  void get(double range[2]) const;

private:
  double Lo = std::numeric_limits<double>::infinity(); // Lo > Hi: empty
  double Hi = -std::numeric_limits<double>::infinity();
};

//------------------------------------------------------------------------------
// Per-iso-value colours and opacities

/// Colours and opacities as the filter and the mapper let users set them: index i is the i-th
/// iso-value as given; unset entries fall back to the surface colour and opacity 1.
class IsoValueStyles
{
public:
  /// Indices are refused at and beyond this (no scene needs a million surfaces).
  static constexpr int kMaxIndex = 1 << 20;
  /// Components are clamped to [0, 1] (NaN leaves the entry unset). True when the stored value
  /// changed; false, with an error, for an index outside [0, kMaxIndex).
  bool setColor(int i, const glm::dvec3& color, Messages& messages);
  bool setOpacity(int i, double opacity, Messages& messages);
  glm::dvec3 color(int i, const glm::dvec3& fallback) const;
  double opacity(int i) const;
  /// True when something was removed.
  bool removeAllColors();
  bool removeAllOpacities();
  /// The styles of `count` iso-values; every opacity is multiplied by `opacityFactor`.
  std::vector<SurfaceStyle> styles(
    std::size_t count, const glm::dvec3& fallback, double opacityFactor) const;
  /// "colours (...): r g b ...; opacities (...): a ..." of what is set, NaN where not.
  std::string describe() const;

private:
  std::vector<double> Colors;    ///< 3 per iso-value; NaN: not set
  std::vector<double> Opacities; ///< NaN: not set
};

//------------------------------------------------------------------------------
// Shading numbers

/// A number setting clamped into [lo, hi]; NaN is refused (a clamp would let it through).
struct NumberSetting
{
  const char* name;
  double lo;
  double hi;
};

/// The mapper's level of detail: pixels a ray along each axis while interacting.
constexpr NumberSetting kMaximumImageSampleDistance{ "MaximumImageSampleDistance", 1.0, 64.0 };
constexpr NumberSetting kInteractiveImageSampleDistance{ "InteractiveImageSampleDistance", 1.0,
  64.0 };

/// False, with the error "<name> must be finite numbers, got (a, b, ...); it is left
/// unchanged.", when a number of a vector setting (a range, a colour, a position) is NaN or
/// infinite.
bool checkFiniteNumbers(const char* name, std::initializer_list<double> values, Messages& messages);
bool checkFiniteNumbers(const char* name, const double* values, int count, Messages& messages);

/// `value` clamped into the setting's range, stored in `member`; true when `member` changed.
/// False, with the error "<name> must be a number, got NaN.", for NaN (member unchanged).
bool setClamped(const NumberSetting& setting, double value, double& member, Messages& messages);

/// Opacities and colour components, for faces whose own setters clamp without a word (VTK's
/// vtkProperty, ParaView's properties).
constexpr NumberSetting kOpacity{ "Opacity", 0.0, 1.0 };

/// `value` clamped into the setting's range, into `used`, with a warning naming the setting, the
/// value and the range when it was outside. False, with the error of setClamped, for NaN.
bool checkNumber(const NumberSetting& setting, double value, double& used, Messages& messages);

/// False, with an error, when a flat list of `count` numbers (the setting `name`) is not made of
/// whole groups of `perGroup` numbers, each one `group` (e.g. "plane: a point and a normal").
bool checkGroupedCount(
  const char* name, std::size_t count, int perGroup, const char* group, Messages& messages);

//------------------------------------------------------------------------------
// The settings table: the filters' settings, written once

/// A setting's value type (per component).
enum class SettingType : std::uint8_t
{
  Bool,
  Int,
  Double
};

/// What a setter does with a value (checkSetting).
enum class SettingCheck : std::uint8_t
{
  /// Clamped into [lo, hi]: a number silently, NaN refused with an error (setClamped); an
  /// integer with a warning naming the value, the range and the value used.
  Clamp,
  /// Refused, with an error, unless every component is finite (checkFiniteNumbers); [lo, hi]
  /// is only the range a panel offers.
  Finite,
  /// Stored as given (integers within C's int); the execution checks it (checkImageSize,
  /// choosePointArrayComponent, checkExactSurfaceSettings). [lo, hi]: the range a panel offers.
  AtExecution
};

/// Which filters have a setting.
enum SettingFilters : unsigned
{
  kRayCasterSetting = 1u, ///< vtkDirectSurfaceRayCaster (C++ and Python)
  kContourSetting = 2u    ///< vtkDirectSurfaceContour (C++ and Python)
};

/// One row of the settings table: what every face (the C++ filters' setters, the Python filters'
/// generated Set/Get methods, the ParaView Python plugin's properties, and the test of the
/// ParaView XML) takes of a setting. A bound of +-DBL_MAX (doubles) or INT_MIN / INT_MAX
/// (integers) is no bound.
struct Setting
{
  const char* name;
  SettingType type;
  SettingCheck check;
  int components; ///< 1, 2 or 3
  double lo;      ///< each component's
  double hi;
  double defaults[3];
  unsigned filters; ///< SettingFilters
  /// An enumeration's choices, lo to hi, as the panels name them ("A|B|C"); else nullptr.
  const char* choices = nullptr;
  /// What the older number helpers take (setClamped, checkNumber).
  constexpr operator NumberSetting() const { return { name, lo, hi }; }
};

constexpr double kNoIntBelow = static_cast<double>(std::numeric_limits<int>::min());
constexpr double kNoIntAbove = static_cast<double>(std::numeric_limits<int>::max());
constexpr unsigned kBothFilters = kRayCasterSetting | kContourSetting;

// clang-format off
// (defaults of Material, NormalSettings, TransverseTest and ExactSurfaceSettings: TestSettings
// checks that these equal them)
inline constexpr Setting kImageSize{ "ImageSize", SettingType::Int, SettingCheck::AtExecution, 2, 1, kNoIntAbove, { 512, 512 }, kRayCasterSetting };
inline constexpr Setting kArrayComponent{ "ArrayComponent", SettingType::Int, SettingCheck::AtExecution, 1, -1, kNoIntAbove, { -1 }, kBothFilters };
inline constexpr Setting kSurfaceColor{ "SurfaceColor", SettingType::Double, SettingCheck::Finite, 3, 0.0, 1.0, { 1.0, 1.0, 1.0 }, kRayCasterSetting };
inline constexpr Setting kAmbient{ "Ambient", SettingType::Double, SettingCheck::Clamp, 1, 0.0, 1.0, { 0.1 }, kRayCasterSetting };
inline constexpr Setting kDiffuse{ "Diffuse", SettingType::Double, SettingCheck::Clamp, 1, 0.0, 1.0, { 0.7 }, kRayCasterSetting };
inline constexpr Setting kSpecular{ "Specular", SettingType::Double, SettingCheck::Clamp, 1, 0.0, 1.0, { 0.2 }, kRayCasterSetting };
inline constexpr Setting kSpecularPower{ "SpecularPower", SettingType::Double, SettingCheck::Clamp, 1, 0.0, 128.0, { 30.0 }, kRayCasterSetting };
inline constexpr Setting kLightAtCamera{ "LightAtCamera", SettingType::Bool, SettingCheck::Clamp, 1, 0, 1, { 1 }, kRayCasterSetting };
inline constexpr Setting kLightPosition{ "LightPosition", SettingType::Double, SettingCheck::Finite, 3, -DBL_MAX, DBL_MAX, { 0.0, 0.0, 1.0 }, kRayCasterSetting };
inline constexpr Setting kNormalMode{ "NormalMode", SettingType::Int, SettingCheck::Clamp, 1, 0, 3, { 0 }, kRayCasterSetting, "Exact gradient|Central differences|Nodal interpolation|Depth buffer" };
inline constexpr Setting kCentralDifferenceStep{ "CentralDifferenceStep", SettingType::Double, SettingCheck::Clamp, 1, 1e-12, 1.0, { 1e-3 }, kRayCasterSetting };
inline constexpr Setting kColorByArray{ "ColorByArray", SettingType::Bool, SettingCheck::Clamp, 1, 0, 1, { 0 }, kRayCasterSetting };
inline constexpr Setting kColorArrayComponent{ "ColorArrayComponent", SettingType::Int, SettingCheck::Clamp, 1, -1, kNoIntAbove, { -1 }, kRayCasterSetting };
inline constexpr Setting kColorRange{ "ColorRange", SettingType::Double, SettingCheck::Finite, 2, -DBL_MAX, DBL_MAX, { 0.0, -1.0 }, kRayCasterSetting };
inline constexpr Setting kColorMap{ "ColorMap", SettingType::Int, SettingCheck::Clamp, 1, 0, 3, { 0 }, kRayCasterSetting, "Cool to Warm|Rainbow|Grayscale|Black-Body" };
inline constexpr Setting kCapping{ "Capping", SettingType::Int, SettingCheck::Clamp, 1, 0, 2, { 0 }, kRayCasterSetting, "None|Below the iso-value|Above the iso-value" };
inline constexpr Setting kTransverseTest{ "TransverseTest", SettingType::Int, SettingCheck::Clamp, 1, 0, 1, { 0 }, kRayCasterSetting, "Bernstein bound (guaranteed)|Widened nodal range (paper's heuristic)" };
inline constexpr Setting kNodalRangeWidening{ "NodalRangeWidening", SettingType::Double, SettingCheck::Clamp, 1, 0.0, DBL_MAX, { 0.25 }, kRayCasterSetting };
inline constexpr Setting kNumberOfThreads{ "NumberOfThreads", SettingType::Int, SettingCheck::Clamp, 1, 0, kNoIntAbove, { 0 }, kBothFilters };
inline constexpr Setting kTolerance{ "Tolerance", SettingType::Double, SettingCheck::AtExecution, 1, 0.0, DBL_MAX, { 1e-3 }, kContourSetting };
inline constexpr Setting kAbsoluteTolerance{ "AbsoluteTolerance", SettingType::Double, SettingCheck::AtExecution, 1, 0.0, DBL_MAX, { 0.0 }, kContourSetting };
inline constexpr Setting kComputeIntegrals{ "ComputeIntegrals", SettingType::Bool, SettingCheck::Clamp, 1, 0, 1, { 1 }, kContourSetting };
// clang-format on

/// The table: every row above, in the order the faces list them.
inline constexpr const Setting* kSettings[] = { &kImageSize, &kArrayComponent, &kSurfaceColor,
  &kAmbient, &kDiffuse, &kSpecular, &kSpecularPower, &kLightAtCamera, &kLightPosition,
  &kNormalMode, &kCentralDifferenceStep, &kColorByArray, &kColorArrayComponent, &kColorRange,
  &kColorMap, &kCapping, &kTransverseTest, &kNodalRangeWidening, &kNumberOfThreads, &kTolerance,
  &kAbsoluteTolerance, &kComputeIntegrals };

/// The row named `name`, or nullptr.
const Setting* settingNamed(const std::string& name);

/// A setter's step for one row: `given` (row.components values; integers for Bool and Int rows)
/// checked as row.check says, into `used`. False, with the row's error, when it is refused (then
/// `used` is untouched and the setting keeps its value); a clamped integer adds a warning.
bool checkSetting(const Setting& row, const double* given, double* used, Messages& messages);

//------------------------------------------------------------------------------
// Colour maps and tables

/// How a colour map interpolates between its control points (vtkColorTransferFunction's
/// colour spaces).
enum class ColorSpace
{
  RGB,
  HSV,
  Diverging
};

struct ColorMapPoint
{
  double x;
  glm::dvec3 color;
};

/// A colour map as data: control points over [0, 1], their colour space and the NaN colour.
/// The faces build their own lookup table from it (vtkColorTransferFunction), so that the
/// colours are VTK's to the last bit.
struct ColorMap
{
  ColorSpace space;
  std::vector<ColorMapPoint> points;
  glm::dvec3 nanColor;
};

/// The built-in colour maps, in the filters' numbering.
enum class BuiltInColorMap
{
  CoolToWarm, ///< Moreland's diverging map, blue (0.230, 0.299, 0.754) to red (0.706, 0.016, 0.150)
  Rainbow,    ///< blue to red through HSV
  Grayscale,  ///< black to white
  BlackBody   ///< black, red, yellow, white
};

/// One of the built-in maps; any other number gives CoolToWarm.
const ColorMap& builtInColorMap(int which);

/// Whether an image is colour-mapped (it has colour values): colouring by an array, or caps of
/// the field on clipping planes.
inline bool isColorMapped(bool colorByArray, bool capping, std::size_t clipPlanes)
{
  return colorByArray || (capping && clipPlanes > 0);
}

/// Whether a colour range the user set is used as it is; else (lo > hi, or not finite: VTK's
/// "unset") the data's finite range is.
inline bool isUsableColorRange(double lo, double hi)
{
  return lo <= hi && std::isfinite(lo) && std::isfinite(hi);
}

/// A colour table for `lo`..`hi` sampled from a lookup table (colorOf(value), which spans
/// tableLo..tableHi) at kColorTableSize evenly spaced values; NaN's colour is colorOf(NaN).
ColorTable sampleColorTable(const std::function<glm::dvec3(double)>& colorOf, double tableLo,
  double tableHi, double lo, double hi);

//------------------------------------------------------------------------------
// Casting

/// Renders every tile of `renderer` in kProgressSteps steps, each through `tilesFor` (a
/// ParallelFor over tile indices of the step), asking `abort` before each step (true: stop) and
/// telling `progress` the fraction done after it; then, when `depthBufferNormals` and nothing
/// was aborted, the depth-buffer normals' second pass. Returns the number of tiles rendered.
NodeId castInSteps(const Renderer& renderer, bool depthBufferNormals, const ParallelFor& tilesFor,
  const std::function<bool()>& abort, const std::function<void(double)>& progress);

/// The warning for a cast stopped after `done` of `tiles` tiles.
void reportAbortedCast(NodeId done, NodeId tiles, Messages& messages);

} // namespace tetdsr
