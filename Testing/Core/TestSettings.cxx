// The settings' checks every face shares (tetdsr/input/Settings.h): what each refuses, and the exact
// sentence a user reads (the faces' tests compare these texts too); the settings table's rows, their
// defaults against the core's structs, and the ParaView XML's properties against the rows.
#include "tetdsr/input/Settings.h"
#include "tetdsr/surface/ExactSurface.h"

#include "LatticeMesh.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace
{
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

/// The only error of `messages` ("" when there is none, "several" when there are more).
std::string onlyError(const tetdsr::Messages& messages)
{
  if (messages.errors.size() > 1)
  {
    return "several";
  }
  return messages.errors.empty() ? "" : messages.errors.front();
}
}

TEST(Settings, IsoValues)
{
  tetdsr::Messages messages;
  EXPECT_TRUE(tetdsr::checkIsoValues({ 0.0, -1e300 }, messages));
  EXPECT_FALSE(tetdsr::checkIsoValues({}, messages));
  EXPECT_EQ(onlyError(messages), "No iso-value: set one with SetValue(0, value).");
  messages = tetdsr::Messages();
  EXPECT_FALSE(tetdsr::checkIsoValues({ 1.0, -kInf, kNaN }, messages));
  EXPECT_EQ(onlyError(messages), "Iso-value -inf is not finite.");
}

TEST(Settings, ClipPlanes)
{
  tetdsr::Messages messages;
  tetdsr::ClipPlane plane;
  std::vector<tetdsr::ClipPlane> planes(tetdsr::kMaxClipPlanes, plane);
  EXPECT_TRUE(tetdsr::checkClipPlanes(planes, messages));
  planes.push_back(plane);
  EXPECT_FALSE(tetdsr::checkClipPlanes(planes, messages));
  EXPECT_EQ(onlyError(messages), "7 clipping planes: at most 6 are supported.");
  planes.assign(2, plane);
  planes[1].origin.y = kNaN;
  messages = tetdsr::Messages();
  EXPECT_FALSE(tetdsr::checkClipPlanes(planes, messages));
  EXPECT_EQ(onlyError(messages), "Clipping plane 1 has a NaN or Inf in its normal or origin.");
  planes[1].origin.y = 0.0;
  planes[1].normal = glm::dvec3(0.0);
  messages = tetdsr::Messages();
  EXPECT_FALSE(tetdsr::checkClipPlanes(planes, messages));
  EXPECT_EQ(onlyError(messages), "Clipping plane 1 has a zero normal: it keeps no side.");
  planes[1].normal = glm::dvec3(1e300, 1e300, 0.0); // huge but finite: fine
  messages = tetdsr::Messages();
  EXPECT_TRUE(tetdsr::checkClipPlanes(planes, messages)) << onlyError(messages);
}

TEST(Settings, ImageSize)
{
  tetdsr::Messages messages;
  EXPECT_TRUE(tetdsr::checkImageSize(512, 512, messages));
  EXPECT_FALSE(tetdsr::checkImageSize(0, 30, messages));
  EXPECT_EQ(onlyError(messages), "ImageSize 0 x 30 pixels: choose a smaller size.");
  messages = tetdsr::Messages();
  EXPECT_FALSE(tetdsr::checkImageSize(100000, 100000, messages));
  const std::string error = onlyError(messages);
  EXPECT_EQ(error.rfind("ImageSize 100000 x 100000 pixels needs 1.08e+03 GiB", 0), 0u) << error;
  EXPECT_NE(error.find("; VTK images hold fewer than 2^31 pixels: choose a smaller size."),
    std::string::npos)
    << error;
  messages = tetdsr::Messages();
  tetdsr::reportUnallocatedImage(640, 480, messages);
  EXPECT_EQ(onlyError(messages), "Cannot allocate the 640 x 480 output image.");
}

TEST(Settings, Camera)
{
  tetdsr::Messages messages;
  tetdsr::Camera camera;
  EXPECT_TRUE(tetdsr::checkCamera(camera, messages));
  camera.viewUp = glm::dvec3(0.0, 0.0, 1.0); // along the direction of view
  EXPECT_FALSE(tetdsr::checkCamera(camera, messages));
  EXPECT_EQ(onlyError(messages),
    "Cannot render: the camera's view up is zero or parallel to its direction of view.");

  // Distance, in diagonals of the scene (a unit cube of 6 cells: diagonal sqrt(3)).
  tetdsr_test::LatticeMesh lattice = tetdsr_test::makeLattice(1, glm::dvec3(0.0), 1.0);
  lattice.sample([](const glm::dvec3& x) { return x.x; });
  const tetdsr::Scene scene(lattice.view());
  camera = tetdsr::Camera();
  camera.focalPoint = glm::dvec3(0.5);
  camera.position = glm::dvec3(0.5, 0.5, 0.5 + 1e8 * std::sqrt(3.0));
  messages = tetdsr::Messages();
  EXPECT_TRUE(tetdsr::checkCamera(camera, scene, messages)) << onlyError(messages);
  camera.position.z = 0.5 + 1e10 * std::sqrt(3.0);
  EXPECT_FALSE(tetdsr::checkCamera(camera, scene, messages));
  EXPECT_EQ(onlyError(messages),
    "Cannot render: the camera is 1e+10 scene diagonals from the scene; beyond 1e+09 "
    "double-precision rays cannot place hits within 1e-7 of the scene.");
}

TEST(Settings, MissingArrays)
{
  tetdsr::Messages messages;
  tetdsr::reportMissingArray(tetdsr::InputArray::Field, "pressure", messages);
  tetdsr::reportMissingArray(tetdsr::InputArray::Field, nullptr, messages);
  tetdsr::reportMissingArray(tetdsr::InputArray::Color, "speed", messages);
  tetdsr::reportMissingArray(tetdsr::InputArray::Color, nullptr, messages);
  ASSERT_EQ(messages.errors.size(), 4u);
  EXPECT_EQ(messages.errors[0], "No point array named 'pressure' in the input.");
  EXPECT_EQ(messages.errors[1],
    "No point scalars: the input has no active point scalars; choose an array with "
    "SetInputArrayToProcess(0, 0, 0, FIELD_ASSOCIATION_POINTS, name).");
  EXPECT_EQ(messages.errors[2],
    "ColorByArray is on but there is no point array named 'speed': choose one with "
    "SetInputArrayToProcess(1, 0, 0, FIELD_ASSOCIATION_POINTS, name).");
  EXPECT_EQ(messages.errors[3],
    "ColorByArray is on but no colour array is chosen: choose one with "
    "SetInputArrayToProcess(1, 0, 0, FIELD_ASSOCIATION_POINTS, name).");
}

TEST(Settings, PointArrayComponent)
{
  tetdsr::Messages messages;
  int component = 7;
  EXPECT_TRUE(tetdsr::choosePointArrayComponent("f", true, 1, -1, false, "ArrayComponent", component, messages));
  EXPECT_EQ(component, 0) << "the only component";
  EXPECT_TRUE(tetdsr::choosePointArrayComponent("v", true, 3, 2, false, "ArrayComponent", component, messages));
  EXPECT_EQ(component, 2);
  EXPECT_TRUE(tetdsr::choosePointArrayComponent("v", true, 3, -1, true, "ColorArrayComponent", component, messages));
  EXPECT_EQ(component, -1) << "the magnitude";
  EXPECT_TRUE(messages.ok());
  EXPECT_FALSE(tetdsr::choosePointArrayComponent("", false, 1, -1, false, "ArrayComponent", component, messages));
  EXPECT_EQ(onlyError(messages),
    "Array '(unnamed)' is not a point array: the quadratic field needs values at the nodes.");
  messages = tetdsr::Messages();
  EXPECT_FALSE(tetdsr::choosePointArrayComponent("v", true, 3, 3, true, "ColorArrayComponent", component, messages));
  EXPECT_EQ(onlyError(messages), "ColorArrayComponent 3 is out of range: array 'v' has 3 components.");
  messages = tetdsr::Messages();
  EXPECT_FALSE(tetdsr::choosePointArrayComponent("v", true, 3, -1, false, "ArrayComponent", component, messages));
  EXPECT_EQ(onlyError(messages), "Array 'v' has 3 components: choose one with ArrayComponent.");
}

TEST(Settings, FiniteRangeSkipsNonFiniteValues)
{
  const double values[] = { 3.0, 4.0, kInf, 0.0, -1.0, kNaN, 1e200, 1e200 };
  double range[2];
  tetdsr::FiniteRange component0;
  component0.add(values, 4, 2, 0);
  component0.get(range);
  EXPECT_EQ(range[0], -1.0);
  EXPECT_EQ(range[1], 1e200);
  tetdsr::FiniteRange magnitude; // 5, inf, NaN, and an overflowing square: only 5 is finite
  magnitude.add(values, 2, 2, -1);
  magnitude.add(values + 4, 2, 2, -1);
  magnitude.get(range);
  EXPECT_EQ(range[0], 5.0);
  EXPECT_EQ(range[1], 5.0);
  tetdsr::FiniteRange none;
  none.add(values + 2, 1, 1, 0);
  none.get(range);
  EXPECT_EQ(range[0], 0.0) << "no finite value: [0, 1]";
  EXPECT_EQ(range[1], 1.0);
}

TEST(Settings, IsoValueStyles)
{
  tetdsr::IsoValueStyles styles;
  tetdsr::Messages messages;
  const glm::dvec3 white(1.0);
  EXPECT_TRUE(styles.setColor(2, glm::dvec3(-1.0, 0.5, 7.0), messages));
  EXPECT_FALSE(styles.setColor(2, glm::dvec3(0.0, 0.5, 1.0), messages)) << "unchanged after clamping";
  EXPECT_EQ(styles.color(2, white), glm::dvec3(0.0, 0.5, 1.0));
  EXPECT_EQ(styles.color(1, white), white) << "unset";
  EXPECT_EQ(styles.color(-3, white), white);
  EXPECT_TRUE(styles.setOpacity(1, 2.0, messages));
  EXPECT_EQ(styles.opacity(1), 1.0);
  EXPECT_TRUE(styles.setOpacity(1, 0.25, messages));
  EXPECT_EQ(styles.opacity(0), 1.0);
  EXPECT_TRUE(messages.ok());
  const std::vector<tetdsr::SurfaceStyle> three = styles.styles(3, white, 0.5);
  ASSERT_EQ(three.size(), 3u);
  EXPECT_EQ(three[1].opacity, 0.125);
  EXPECT_EQ(three[2].color, glm::dvec3(0.0, 0.5, 1.0));
  EXPECT_EQ(styles.describe(),
    "colours (r g b per value, nan: not set): nan nan nan nan nan nan 0 0.5 1; opacities (nan: "
    "1): nan 0.25");
  EXPECT_FALSE(styles.setColor(tetdsr::IsoValueStyles::kMaxIndex, white, messages));
  EXPECT_FALSE(styles.setOpacity(-1, 1.0, messages));
  ASSERT_EQ(messages.errors.size(), 2u);
  EXPECT_EQ(messages.errors[0], "SetIsoValueColor: index 1048576 is outside [0, 1048576).");
  EXPECT_EQ(messages.errors[1], "SetIsoValueOpacity: index -1 is outside [0, 1048576).");
  EXPECT_TRUE(styles.removeAllColors());
  EXPECT_FALSE(styles.removeAllColors());
  EXPECT_TRUE(styles.removeAllOpacities());
}

TEST(Settings, ClampedNumbers)
{
  tetdsr::Messages messages;
  double member = 0.5;
  EXPECT_TRUE(tetdsr::setClamped(tetdsr::kSpecularPower, 1e9, member, messages));
  EXPECT_EQ(member, 128.0);
  EXPECT_FALSE(tetdsr::setClamped(tetdsr::kSpecularPower, 200.0, member, messages)) << "unchanged";
  EXPECT_TRUE(tetdsr::setClamped(tetdsr::kCentralDifferenceStep, 0.0, member, messages));
  EXPECT_EQ(member, 1e-12);
  EXPECT_TRUE(messages.ok());
  EXPECT_FALSE(tetdsr::setClamped(tetdsr::kNodalRangeWidening, kNaN, member, messages));
  EXPECT_EQ(member, 1e-12) << "NaN leaves the setting as it was";
  EXPECT_EQ(onlyError(messages), "NodalRangeWidening must be a number, got NaN.");
}

TEST(Settings, ColorMapsAndTables)
{
  EXPECT_EQ(tetdsr::builtInColorMap(1).space, tetdsr::ColorSpace::HSV);
  EXPECT_EQ(tetdsr::builtInColorMap(3).points.size(), 4u);
  EXPECT_EQ(&tetdsr::builtInColorMap(99), &tetdsr::builtInColorMap(0)) << "unknown: cool to warm";
  EXPECT_EQ(tetdsr::builtInColorMap(0).points.front().color, glm::dvec3(0.230, 0.299, 0.754));
  // A lookup table over [10, 20] whose red is its value's position in it.
  const tetdsr::ColorTable table = tetdsr::sampleColorTable(
    [](double v) { return std::isnan(v) ? glm::dvec3(0.5) : glm::dvec3((v - 10.0) / 10.0, 0.0, 0.0); },
    10.0, 20.0, -1.0, 1.0);
  ASSERT_EQ(table.colors.size(), static_cast<std::size_t>(tetdsr::kColorTableSize));
  EXPECT_EQ(table.lo, -1.0);
  EXPECT_EQ(table.hi, 1.0);
  EXPECT_EQ(table.colors.front().r, 0.0);
  EXPECT_EQ(table.colors.back().r, 1.0);
  EXPECT_EQ(table.nanColor, glm::dvec3(0.5));
  EXPECT_NEAR(table.map(0.0).r, 0.5, 1e-12);
}

TEST(Settings, CastInStepsReportsProgressAndStops)
{
  tetdsr_test::LatticeMesh lattice = tetdsr_test::makeLattice(2, glm::dvec3(0.0), 1.0);
  lattice.sample([](const glm::dvec3& x) { return glm::dot(x - 0.5, x - 0.5); });
  const tetdsr::Scene scene(lattice.view());
  const tetdsr::SurfaceIndex surface(scene, tetdsr::IsoValues({ 0.5 }));
  const int width = 200, height = 120; // 13 x 8 tiles
  std::vector<std::uint8_t> colors(4 * width * height);
  std::vector<double> depth(width * height), normals(3 * width * height);
  std::vector<tetdsr::NodeId> cellIds(width * height);
  tetdsr::ImageView image{ width, height, colors.data(), depth.data(), normals.data(), cellIds.data() };
  tetdsr::Camera camera;
  camera.position = glm::dvec3(0.5, 0.5, 4.0);
  camera.focalPoint = glm::dvec3(0.5);
  const tetdsr::Renderer renderer(surface, camera, tetdsr::RenderSettings(), image);
  const tetdsr::NodeId tiles = renderer.numberOfTiles();
  ASSERT_EQ(tiles, 13 * 8);
  std::vector<double> fractions;
  const tetdsr::NodeId done = tetdsr::castInSteps(
    renderer, false, tetdsr::serialFor, [] { return false; },
    [&](double f) { fractions.push_back(f); });
  EXPECT_EQ(done, tiles);
  EXPECT_EQ(fractions.size(), static_cast<std::size_t>((tiles + 2) / 3)) << "steps of 104 / 32 = 3 tiles";
  EXPECT_EQ(fractions.back(), 1.0);
  fractions.clear();
  const tetdsr::NodeId stopped = tetdsr::castInSteps(
    renderer, true, tetdsr::serialFor, [&] { return fractions.size() == 4; },
    [&](double f) { fractions.push_back(f); });
  EXPECT_EQ(stopped, 12) << "4 steps of 3 tiles";
  tetdsr::Messages messages;
  tetdsr::reportAbortedCast(stopped, tiles, messages);
  ASSERT_EQ(messages.warnings.size(), 1u);
  EXPECT_EQ(messages.warnings[0], "Aborted after 12 of 104 image tiles.");
}

TEST(Settings, TheTableIsWellFormedAndItsDefaultsAreTheCores)
{
  std::set<std::string> names;
  for (const tetdsr::Setting* row : tetdsr::kSettings)
  {
    EXPECT_TRUE(names.insert(row->name).second) << row->name << " twice";
    EXPECT_EQ(tetdsr::settingNamed(row->name), row) << row->name;
    EXPECT_TRUE(row->components >= 1 && row->components <= 3) << row->name;
    EXPECT_LE(row->lo, row->hi) << row->name;
    EXPECT_NE(row->filters & tetdsr::kBothFilters, 0u) << row->name;
    for (int c = 0; c < row->components; ++c)
    {
      // A default is a value its own setter keeps as it is, without a word.
      tetdsr::Messages messages;
      double used[3];
      ASSERT_TRUE(tetdsr::checkSetting(*row, row->defaults, used, messages)) << row->name;
      EXPECT_EQ(used[c], row->defaults[c]) << row->name << " component " << c;
      EXPECT_TRUE(messages.errors.empty() && messages.warnings.empty()) << row->name;
    }
  }
  EXPECT_EQ(tetdsr::settingNamed("NoSuchSetting"), nullptr);
  // The defaults the core shades, tests and extracts with, when no face says otherwise.
  const tetdsr::Material material;
  const tetdsr::NormalSettings normals;
  const tetdsr::TransverseTest transverse;
  for (int c = 0; c < 3; ++c)
  {
    EXPECT_EQ(tetdsr::kSurfaceColor.defaults[c], material.color[c]);
  }
  EXPECT_EQ(tetdsr::kAmbient.defaults[0], material.ambient);
  EXPECT_EQ(tetdsr::kDiffuse.defaults[0], material.diffuse);
  EXPECT_EQ(tetdsr::kSpecular.defaults[0], material.specular);
  EXPECT_EQ(tetdsr::kSpecularPower.defaults[0], material.specularPower);
  EXPECT_EQ(tetdsr::kNormalMode.defaults[0], static_cast<double>(normals.mode));
  EXPECT_EQ(tetdsr::kNormalMode.hi, static_cast<double>(tetdsr::NormalMode::DepthBuffer));
  EXPECT_EQ(tetdsr::kCentralDifferenceStep.defaults[0], normals.relativeStep);
  EXPECT_EQ(tetdsr::kTransverseTest.defaults[0], static_cast<double>(transverse.mode));
  EXPECT_EQ(tetdsr::kTransverseTest.hi, static_cast<double>(tetdsr::TransverseTest::Mode::WidenedNodalRange));
  EXPECT_EQ(tetdsr::kNodalRangeWidening.defaults[0], transverse.widening);
  EXPECT_EQ(tetdsr::kCapping.hi, static_cast<double>(tetdsr::CapRegion::AboveIsoValue));
  EXPECT_EQ(tetdsr::kColorMap.hi, static_cast<double>(tetdsr::BuiltInColorMap::BlackBody));
  const tetdsr::ExactSurfaceSettings surface;
  EXPECT_EQ(tetdsr::kTolerance.defaults[0], surface.relativeTolerance);
  EXPECT_EQ(tetdsr::kAbsoluteTolerance.defaults[0], surface.tolerance);
  EXPECT_EQ(tetdsr::kComputeIntegrals.defaults[0], surface.integrals ? 1.0 : 0.0);
}

TEST(Settings, EachRowIsCheckedAsItSays)
{
  tetdsr::Messages messages;
  double used[3] = { -7.0, -7.0, -7.0 };
  // A clamped number: silently; NaN refused.
  double given[3] = { 2.0, 0.0, 0.0 };
  EXPECT_TRUE(tetdsr::checkSetting(tetdsr::kAmbient, given, used, messages));
  EXPECT_EQ(used[0], 1.0);
  EXPECT_TRUE(messages.warnings.empty() && messages.errors.empty());
  given[0] = kNaN;
  used[0] = -7.0;
  EXPECT_FALSE(tetdsr::checkSetting(tetdsr::kSpecularPower, given, used, messages));
  EXPECT_EQ(used[0], -7.0) << "untouched";
  EXPECT_EQ(onlyError(messages), "SpecularPower must be a number, got NaN.");
  messages = tetdsr::Messages();
  // A clamped integer: with a warning in whole numbers.
  given[0] = 7.0;
  EXPECT_TRUE(tetdsr::checkSetting(tetdsr::kNormalMode, given, used, messages));
  EXPECT_EQ(used[0], 3.0);
  given[0] = -2.0;
  EXPECT_TRUE(tetdsr::checkSetting(tetdsr::kNumberOfThreads, given, used, messages));
  EXPECT_EQ(used[0], 0.0);
  ASSERT_EQ(messages.warnings.size(), 2u);
  EXPECT_EQ(messages.warnings[0], "NormalMode 7 is outside [0, 3]: 3 is used.");
  EXPECT_EQ(messages.warnings[1], "NumberOfThreads -2 is outside [0, 2147483647]: 0 is used.");
  messages = tetdsr::Messages();
  // A vector: refused unless finite, not clamped.
  const double colour[3] = { 2.0, kNaN, 0.0 };
  EXPECT_FALSE(tetdsr::checkSetting(tetdsr::kSurfaceColor, colour, used, messages));
  EXPECT_EQ(onlyError(messages), "SurfaceColor must be finite numbers, got (2, nan, 0); it is left unchanged.");
  messages = tetdsr::Messages();
  const double range[2] = { 5.0, -1e300 };
  EXPECT_TRUE(tetdsr::checkSetting(tetdsr::kColorRange, range, used, messages));
  EXPECT_EQ(used[0], 5.0);
  EXPECT_EQ(used[1], -1e300);
  // Checked at execution: stored as given (integers within C's int), a Bool as 0 or 1.
  const double size[2] = { -5.0, 1e12 };
  EXPECT_TRUE(tetdsr::checkSetting(tetdsr::kImageSize, size, used, messages));
  EXPECT_EQ(used[0], -5.0);
  EXPECT_EQ(used[1], 2147483647.0);
  given[0] = -1.0;
  EXPECT_TRUE(tetdsr::checkSetting(tetdsr::kTolerance, given, used, messages));
  EXPECT_EQ(used[0], -1.0) << "refused by checkExactSurfaceSettings at execution, not here";
  given[0] = 5.0;
  EXPECT_TRUE(tetdsr::checkSetting(tetdsr::kLightAtCamera, given, used, messages));
  EXPECT_EQ(used[0], 1.0);
  EXPECT_TRUE(messages.warnings.empty() && messages.errors.empty());
}

namespace
{
std::string sourceText(const std::string& relative)
{
  std::ifstream in(std::string(TETDSR_SOURCE_DIR) + "/" + relative);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The value of attribute `name` in `attributes` (an XML start tag's text), or nullopt.
std::optional<std::string> attribute(const std::string& attributes, const std::string& name)
{
  std::smatch found;
  if (std::regex_search(attributes, found, std::regex("\\b" + name + "=\"([^\"]*)\"")))
  {
    return found[1].str();
  }
  return std::nullopt;
}

std::vector<double> numbersOf(const std::string& text)
{
  std::istringstream in(text);
  std::vector<double> numbers;
  for (double v; in >> v;)
  {
    numbers.push_back(v);
  }
  return numbers;
}

/// A row's bound as a panel's domain gives it: the number repeated per component, or "" when the
/// row has none (+-DBL_MAX, INT_MIN / INT_MAX).
std::vector<double> boundOf(const tetdsr::Setting& row, double bound)
{
  const bool none = row.type == tetdsr::SettingType::Double
    ? std::abs(bound) == DBL_MAX
    : bound <= tetdsr::kNoIntBelow || bound >= tetdsr::kNoIntAbove;
  return none ? std::vector<double>() : std::vector<double>(row.components, bound);
}

/// Compares every property of a ParaView XML whose command sets a row of the settings table
/// (`filter`: the rows it must hold, or 0 for a representation, whose defaults are its own) with
/// the row: elements, defaults, the domain's range or choices. Returns the rows compared.
std::set<std::string> compareXmlWithTable(const std::string& file, unsigned filter)
{
  const std::string xml = sourceText(file);
  EXPECT_FALSE(xml.empty()) << file;
  std::set<std::string> compared;
  const std::regex property("<(Int|Double)VectorProperty\\b([^>]*)>([\\s\\S]*?)</\\1VectorProperty>");
  for (std::sregex_iterator it(xml.begin(), xml.end(), property), end; it != end; ++it)
  {
    const std::string attributes = (*it)[2].str(), body = (*it)[3].str();
    const std::string command = attribute(attributes, "command").value_or("");
    const tetdsr::Setting* row = command.rfind("Set", 0) == 0 ? tetdsr::settingNamed(command.substr(3)) : nullptr;
    if (!row || (filter && !(row->filters & filter)))
    {
      continue;
    }
    const std::string where = file + ", " + row->name + ": ";
    compared.insert(row->name);
    EXPECT_EQ((*it)[1].str() == "Double", row->type == tetdsr::SettingType::Double) << where << "type";
    EXPECT_EQ(attribute(attributes, "number_of_elements").value_or(""), std::to_string(row->components))
      << where << "elements";
    if (filter)
    {
      const std::vector<double> defaults(row->defaults, row->defaults + row->components);
      EXPECT_EQ(numbersOf(attribute(attributes, "default_values").value_or("")), defaults)
        << where << "default_values";
    }
    if (row->type == tetdsr::SettingType::Bool)
    {
      EXPECT_NE(body.find("<BooleanDomain"), std::string::npos) << where << "a switch";
      continue;
    }
    if (row->choices)
    {
      std::string texts;
      int value = static_cast<int>(row->lo);
      const std::regex entry("<Entry\\s+value=\"(-?\\d+)\"\\s+text=\"([^\"]*)\"");
      for (std::sregex_iterator e(body.begin(), body.end(), entry), last; e != last; ++e, ++value)
      {
        EXPECT_EQ(std::stoi((*e)[1].str()), value) << where << "entries lo to hi";
        texts += (texts.empty() ? "" : "|") + (*e)[2].str();
      }
      EXPECT_EQ(value - 1, static_cast<int>(row->hi)) << where << "the last entry";
      EXPECT_EQ(texts, row->choices) << where << "the choices' texts";
      continue;
    }
    std::smatch domain;
    const std::string tag = row->type == tetdsr::SettingType::Double ? "Double" : "Int";
    const bool has = std::regex_search(body, domain, std::regex("<" + tag + "RangeDomain\\b([^>]*)>"));
    const std::string range = has ? domain[1].str() : "";
    EXPECT_EQ(numbersOf(attribute(range, "min").value_or("")), boundOf(*row, row->lo)) << where << "min";
    EXPECT_EQ(numbersOf(attribute(range, "max").value_or("")), boundOf(*row, row->hi)) << where << "max";
  }
  return compared;
}
} // namespace

TEST(Settings, TheParaViewXmlAgreesWithTheTable)
{
  // Each filter's XML holds every row of the filter but ArrayComponent (its panels list
  // one-component arrays only), with the row's elements, defaults and range or choices.
  const std::pair<const char*, unsigned> filters[] = { { "Plugin/DirectSurfaceRayCaster.xml",
                                                         tetdsr::kRayCasterSetting },
    { "Plugin/DirectSurfaceContour.xml", tetdsr::kContourSetting } };
  for (const auto& [file, filter] : filters)
  {
    const std::set<std::string> compared = compareXmlWithTable(file, filter);
    for (const tetdsr::Setting* row : tetdsr::kSettings)
    {
      if ((row->filters & filter) && row != &tetdsr::kArrayComponent)
      {
        EXPECT_EQ(compared.count(row->name), 1u) << file << " has no property setting " << row->name;
      }
    }
  }
  // The representation's properties of the same settings: their ranges (its defaults are
  // ParaView's, as its other representations').
  const std::set<std::string> shading = compareXmlWithTable("Plugin/DirectSurfaceRepresentation.xml", 0);
  EXPECT_EQ(shading, (std::set<std::string>{ "Ambient", "Diffuse", "Specular", "SpecularPower" }));
}
