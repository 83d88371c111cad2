#include "tetdsr/input/Settings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <unistd.h>

namespace tetdsr
{

//------------------------------------------------------------------------------
bool checkIsoValues(const std::vector<double>& values, Messages& messages)
{
  if (values.empty())
  {
    messages.errors.push_back("No iso-value: set one with SetValue(0, value).");
    return false;
  }
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

bool checkFieldNotConstantAtIsoValue(
  const std::vector<double>& values, double lo, double hi, const std::string& name, Messages& messages)
{
  if (lo != hi || std::find(values.begin(), values.end(), lo) == values.end())
  {
    return true;
  }
  messages.warnings.push_back(text("'", name, "' is ", lo, " everywhere, equal to an iso-value: a "
    "field equal to the iso-value everywhere has no surface to draw."));
  return false;
}

bool checkClipPlanes(const std::vector<ClipPlane>& planes, Messages& messages)
{
  if (planes.size() > static_cast<std::size_t>(kMaxClipPlanes))
  {
    messages.errors.push_back(
      text(planes.size(), " clipping planes: at most ", kMaxClipPlanes, " are supported."));
    return false;
  }
  for (std::size_t k = 0; k < planes.size(); ++k)
  {
    if (!isFinite(planes[k].normal) || !isFinite(planes[k].origin))
    {
      messages.errors.push_back(text("Clipping plane ", k, " has a NaN or Inf in its normal or origin."));
      return false;
    }
    if (unitVector(planes[k].normal) == glm::dvec3(0.0))
    {
      messages.errors.push_back(text("Clipping plane ", k, " has a zero normal: it keeps no side."));
      return false;
    }
  }
  return true;
}

bool checkImageSize(int width, int height, Messages& messages)
{
  const double pixels = static_cast<double>(width) * static_cast<double>(height);
  const double bytes = pixels * kBytesPerPixel;
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long pageSize = sysconf(_SC_PAGESIZE);
  const double memory = pages > 0 && pageSize > 0 ? static_cast<double>(pages) * pageSize : 0.0;
  // Extents and pixel indices are ints in VTK's image data: each side below 2^31, and the
  // product too (so that no index wraps).
  const bool fitsIndices = pixels < 2147483647.0;
  if (width > 0 && height > 0 && fitsIndices && !(memory > 0.0 && bytes > memory))
  {
    return true;
  }
  std::ostringstream sentence;
  sentence << "ImageSize " << width << " x " << height << " pixels";
  if (width > 0 && height > 0)
  {
    sentence.precision(3);
    sentence << " needs " << bytes / (1024.0 * 1024.0 * 1024.0) << " GiB";
    if (memory > 0.0)
    {
      sentence << "; this machine has " << memory / (1024.0 * 1024.0 * 1024.0) << " GiB";
    }
    if (!fitsIndices)
    {
      sentence << "; VTK images hold fewer than 2^31 pixels";
    }
  }
  sentence << ": choose a smaller size.";
  messages.errors.push_back(sentence.str());
  return false;
}

void reportUnallocatedImage(int width, int height, Messages& messages)
{
  messages.errors.push_back(text("Cannot allocate the ", width, " x ", height, " output image."));
}

bool checkCamera(const Camera& camera, Messages& messages)
{
  const CameraProblem problem = RayGenerator::check(camera);
  if (problem != CameraProblem::None)
  {
    messages.errors.push_back(text("Cannot render: ", describe(problem), "."));
    return false;
  }
  return true;
}

bool checkCamera(const Camera& camera, const Scene& scene, Messages& messages)
{
  if (!checkCamera(camera, messages))
  {
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

bool checkProjection(const glm::dmat4& ndcToWorld, Messages& messages)
{
  for (int column = 0; column < 4; ++column)
  {
    for (int row = 0; row < 4; ++row)
    {
      if (!std::isfinite(ndcToWorld[column][row]))
      {
        messages.errors.push_back(
          text("Cannot render: ", describe(CameraProblem::SingularProjection), "."));
        return false;
      }
    }
  }
  return true;
}

bool checkCameraExtras(const CameraExtras& extras, Messages& messages)
{
  const std::pair<bool, const char*> named[] = {
    { extras.explicitProjection, "an explicit projection matrix" },
    { extras.offAxisProjection, "an off-axis projection" },
    { extras.windowCenter, "a window centre other than (0, 0)" },
    { extras.viewShear, "a view shear" },
    { extras.transforms, "a user transform, user view transform or model transform matrix" },
  };
  std::string used;
  for (const auto& extra : named)
  {
    if (extra.first)
    {
      used += (used.empty() ? "" : ", ") + std::string(extra.second);
    }
  }
  if (used.empty())
  {
    return true;
  }
  messages.errors.push_back(text("Cannot render: the camera uses ", used,
    "; this filter's rays follow only the camera's position, focal point, view up and view angle "
    "(or parallel scale). Draw with vtkDirectSurfaceMapper in a render window, which follows "
    "every projection."));
  return false;
}

//------------------------------------------------------------------------------
void reportMissingArray(InputArray which, const char* name, Messages& messages)
{
  if (which == InputArray::Field && name)
  {
    messages.errors.push_back(text("No point array named '", name, "' in the input."));
  }
  else if (which == InputArray::Field)
  {
    messages.errors.push_back("No point scalars: the input has no active point scalars; choose an "
                              "array with SetInputArrayToProcess(0, 0, 0, FIELD_ASSOCIATION_POINTS, "
                              "name).");
  }
  else
  {
    const std::string missing = name ? text("there is no point array named '", name, "'")
                                     : std::string("no colour array is chosen");
    messages.errors.push_back(text("ColorByArray is on but ", missing,
      ": choose one with SetInputArrayToProcess(1, 0, 0, FIELD_ASSOCIATION_POINTS, name)."));
  }
}

bool choosePointArrayComponent(const std::string& name, bool isPointArray, int components,
  int requestedComponent, bool allowMagnitude, const char* componentSetting, int& component,
  Messages& messages)
{
  const std::string shown = name.empty() ? "(unnamed)" : name;
  if (!isPointArray)
  {
    messages.errors.push_back(text("Array '", shown,
      "' is not a point array: the quadratic field needs values at the nodes."));
    return false;
  }
  if (requestedComponent >= components)
  {
    messages.errors.push_back(text(componentSetting, " ", requestedComponent,
      " is out of range: array '", shown, "' has ", components, " components."));
    return false;
  }
  if (requestedComponent >= 0 || components == 1)
  {
    component = std::max(requestedComponent, 0);
    return true;
  }
  if (!allowMagnitude && !componentSetting)
  {
    // A face with no component setting (the mapper): only another array will do.
    messages.errors.push_back(text("Array '", shown, "' has ", components,
      " components but the field must have one: choose a one-component point array with "
      "SetInputArrayToProcess(0, 0, 0, FIELD_ASSOCIATION_POINTS, name)."));
    return false;
  }
  if (!allowMagnitude)
  {
    messages.errors.push_back(text("Array '", shown, "' has ", components,
      " components: choose one with ", componentSetting, "."));
    return false;
  }
  component = -1;
  return true;
}

void FiniteRange::add(const double* values, NodeId tuples, int components, int component)
{
  for (NodeId p = 0; p < tuples; ++p)
  {
    const double* tuple = values + static_cast<std::size_t>(p) * components;
    double value = 0.0;
    if (component >= 0)
    {
      value = tuple[component];
    }
    else
    {
      for (int c = 0; c < components; ++c)
      {
        value += tuple[c] * tuple[c];
      }
      value = std::sqrt(value);
    }
    if (std::isfinite(value))
    {
      Lo = std::min(Lo, value);
      Hi = std::max(Hi, value);
    }
  }
}

void FiniteRange::get(double range[2]) const
{
  const bool empty = Lo > Hi;
  range[0] = empty ? 0.0 : Lo;
  range[1] = empty ? 1.0 : Hi;
}

//------------------------------------------------------------------------------
bool IsoValueStyles::setColor(int i, const glm::dvec3& color, Messages& messages)
{
  if (i < 0 || i >= kMaxIndex)
  {
    messages.errors.push_back(text("SetIsoValueColor: index ", i, " is outside [0, ", kMaxIndex, ")."));
    return false;
  }
  const std::size_t first = 3 * static_cast<std::size_t>(i);
  if (Colors.size() < first + 3)
  {
    Colors.resize(first + 3, std::numeric_limits<double>::quiet_NaN());
  }
  bool changed = false;
  for (int c = 0; c < 3; ++c)
  {
    // (a NaN component stays NaN: the entry reads as unset)
    const double clamped = color[c] < 0.0 ? 0.0 : (color[c] > 1.0 ? 1.0 : color[c]);
    double& stored = Colors[first + static_cast<std::size_t>(c)];
    changed = changed || !(stored == clamped || (std::isnan(stored) && std::isnan(clamped)));
    stored = clamped;
  }
  return changed;
}

bool IsoValueStyles::setOpacity(int i, double opacity, Messages& messages)
{
  if (i < 0 || i >= kMaxIndex)
  {
    messages.errors.push_back(text("SetIsoValueOpacity: index ", i, " is outside [0, ", kMaxIndex, ")."));
    return false;
  }
  if (Opacities.size() < static_cast<std::size_t>(i) + 1)
  {
    Opacities.resize(static_cast<std::size_t>(i) + 1, std::numeric_limits<double>::quiet_NaN());
  }
  const double clamped = opacity < 0.0 ? 0.0 : (opacity > 1.0 ? 1.0 : opacity);
  double& stored = Opacities[static_cast<std::size_t>(i)];
  const bool changed = !(stored == clamped || (std::isnan(stored) && std::isnan(clamped)));
  stored = clamped;
  return changed;
}

glm::dvec3 IsoValueStyles::color(int i, const glm::dvec3& fallback) const
{
  const std::size_t first = 3 * static_cast<std::size_t>(std::max(i, 0));
  const bool set = i >= 0 && first < Colors.size() && !std::isnan(Colors[first]);
  return set ? glm::dvec3(Colors[first], Colors[first + 1], Colors[first + 2]) : fallback;
}

double IsoValueStyles::opacity(int i) const
{
  return i >= 0 && static_cast<std::size_t>(i) < Opacities.size() &&
      !std::isnan(Opacities[static_cast<std::size_t>(i)])
    ? Opacities[static_cast<std::size_t>(i)]
    : 1.0;
}

bool IsoValueStyles::removeAllColors()
{
  const bool any = !Colors.empty();
  Colors.clear();
  return any;
}

bool IsoValueStyles::removeAllOpacities()
{
  const bool any = !Opacities.empty();
  Opacities.clear();
  return any;
}

std::vector<SurfaceStyle> IsoValueStyles::styles(
  std::size_t count, const glm::dvec3& fallback, double opacityFactor) const
{
  std::vector<SurfaceStyle> result;
  result.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
  {
    result.push_back(
      { color(static_cast<int>(i), fallback), opacityFactor * opacity(static_cast<int>(i)) });
  }
  return result;
}

std::string IsoValueStyles::describe() const
{
  std::ostringstream sentence;
  sentence << "colours (r g b per value, nan: not set):";
  for (double c : Colors)
  {
    sentence << " " << c;
  }
  sentence << "; opacities (nan: 1):";
  for (double o : Opacities)
  {
    sentence << " " << o;
  }
  return sentence.str();
}

//------------------------------------------------------------------------------
bool checkFiniteNumbers(const char* name, std::initializer_list<double> values, Messages& messages)
{
  return checkFiniteNumbers(name, values.begin(), static_cast<int>(values.size()), messages);
}

bool checkFiniteNumbers(const char* name, const double* values, int count, Messages& messages)
{
  if (std::all_of(values, values + count, [](double v) { return std::isfinite(v); }))
  {
    return true;
  }
  std::string shown;
  for (int k = 0; k < count; ++k)
  {
    shown += (shown.empty() ? "" : ", ") + text(values[k]);
  }
  messages.errors.push_back(
    text(name, " must be finite numbers, got (", shown, "); it is left unchanged."));
  return false;
}

bool setClamped(const NumberSetting& setting, double value, double& member, Messages& messages)
{
  if (std::isnan(value))
  {
    messages.errors.push_back(text(setting.name, " must be a number, got NaN."));
    return false;
  }
  value = std::min(std::max(value, setting.lo), setting.hi);
  const bool changed = value != member;
  member = value;
  return changed;
}

bool checkNumber(const NumberSetting& setting, double value, double& used, Messages& messages)
{
  if (std::isnan(value))
  {
    messages.errors.push_back(text(setting.name, " must be a number, got NaN."));
    return false;
  }
  used = std::min(std::max(value, setting.lo), setting.hi);
  if (used != value)
  {
    messages.warnings.push_back(text(setting.name, " ", value, " is outside [", setting.lo, ", ",
      setting.hi, "]: ", used, " is used."));
  }
  return true;
}

bool checkGroupedCount(
  const char* name, std::size_t count, int perGroup, const char* group, Messages& messages)
{
  if (count % static_cast<std::size_t>(perGroup) == 0)
  {
    return true;
  }
  messages.errors.push_back(text(name, " has ", count, " numbers, not a multiple of ", perGroup,
    " (", perGroup, " per ", group, "): none of them is used."));
  return false;
}

//------------------------------------------------------------------------------
namespace
{
/// An integer setting's value as its digits (2147483647, not 2.14748e+09).
std::string wholeNumber(double value)
{
  return std::abs(value) < 9e18 ? std::to_string(static_cast<long long>(value)) : text(value);
}
} // namespace

const Setting* settingNamed(const std::string& name)
{
  for (const Setting* row : kSettings)
  {
    if (name == row->name)
    {
      return row;
    }
  }
  return nullptr;
}

bool checkSetting(const Setting& row, const double* given, double* used, Messages& messages)
{
  const int n = row.components;
  if (row.type == SettingType::Bool)
  {
    std::transform(given, given + n, used, [](double v) { return v != 0.0 ? 1.0 : 0.0; });
    return true;
  }
  if (row.type == SettingType::Int)
  {
    // An Int row's own range when clamped, else C's int (what every face stores).
    const bool clamp = row.check == SettingCheck::Clamp;
    const double lo = clamp ? row.lo : kNoIntBelow, hi = clamp ? row.hi : kNoIntAbove;
    for (int c = 0; c < n; ++c)
    {
      used[c] = std::min(std::max(given[c], lo), hi);
      if (clamp && used[c] != given[c])
      {
        messages.warnings.push_back(text(row.name, " ", wholeNumber(given[c]), " is outside [",
          wholeNumber(lo), ", ", wholeNumber(hi), "]: ", wholeNumber(used[c]), " is used."));
      }
    }
    return true;
  }
  if (row.check == SettingCheck::Clamp && std::any_of(given, given + n, [](double v) { return std::isnan(v); }))
  {
    messages.errors.push_back(text(row.name, " must be a number, got NaN."));
    return false;
  }
  if (row.check == SettingCheck::Finite && !checkFiniteNumbers(row.name, given, n, messages))
  {
    return false;
  }
  const bool clamp = row.check == SettingCheck::Clamp;
  std::transform(given, given + n, used,
    [&](double v) { return clamp ? std::min(std::max(v, row.lo), row.hi) : v; });
  return true;
}

//------------------------------------------------------------------------------
const ColorMap& builtInColorMap(int which)
{
  static const glm::dvec3 kGrey(0.5, 0.5, 0.5);
  static const ColorMap kMaps[] = {
    // Moreland's diverging map.
    { ColorSpace::Diverging,
      { { 0.0, { 0.230, 0.299, 0.754 } }, { 1.0, { 0.706, 0.016, 0.150 } } }, kGrey },
    { ColorSpace::HSV, { { 0.0, { 0.0, 0.0, 1.0 } }, { 1.0, { 1.0, 0.0, 0.0 } } }, kGrey },
    { ColorSpace::RGB, { { 0.0, { 0.0, 0.0, 0.0 } }, { 1.0, { 1.0, 1.0, 1.0 } } }, kGrey },
    { ColorSpace::RGB,
      { { 0.0, { 0.0, 0.0, 0.0 } }, { 0.4, { 0.9, 0.0, 0.0 } }, { 0.8, { 0.9, 0.9, 0.0 } },
        { 1.0, { 1.0, 1.0, 1.0 } } },
      kGrey },
  };
  const bool known = which >= static_cast<int>(BuiltInColorMap::CoolToWarm) &&
    which <= static_cast<int>(BuiltInColorMap::BlackBody);
  return kMaps[known ? which : 0];
}

ColorTable sampleColorTable(const std::function<glm::dvec3(double)>& colorOf, double tableLo,
  double tableHi, double lo, double hi)
{
  ColorTable table;
  table.lo = lo;
  table.hi = hi;
  table.colors.reserve(kColorTableSize);
  for (int k = 0; k < kColorTableSize; ++k)
  {
    const double x = static_cast<double>(k) / (kColorTableSize - 1);
    table.colors.push_back(colorOf(tableLo + x * (tableHi - tableLo)));
  }
  table.nanColor = colorOf(std::numeric_limits<double>::quiet_NaN());
  return table;
}

//------------------------------------------------------------------------------
NodeId castInSteps(const Renderer& renderer, bool depthBufferNormals, const ParallelFor& tilesFor,
  const std::function<bool()>& abort, const std::function<void(double)>& progress)
{
  const NodeId tiles = renderer.numberOfTiles();
  const NodeId step = std::max<NodeId>(1, tiles / kProgressSteps);
  NodeId done = 0;
  while (done < tiles && !abort())
  {
    const NodeId end = std::min(tiles, done + step);
    const NodeId first = done;
    tilesFor(end - first,
      [&](NodeId begin, NodeId last) { renderer.renderTiles(first + begin, first + last); });
    done = end;
    progress(static_cast<double>(done) / tiles);
  }
  if (done == tiles && depthBufferNormals)
  {
    tilesFor(tiles, [&](NodeId begin, NodeId last) { renderer.shadeFromDepth(begin, last); });
  }
  return done;
}

void reportAbortedCast(NodeId done, NodeId tiles, Messages& messages)
{
  messages.warnings.push_back(text("Aborted after ", done, " of ", tiles, " image tiles."));
}

} // namespace tetdsr
