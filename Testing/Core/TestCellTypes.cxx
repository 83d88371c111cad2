// The cell type table (CellTypes.h) against the core's reading and the project's documents:
// - every VTK code and id count reads as the table says (unsupported, malformed, order too high,
//   or read with exactly that many nodes), the split's and the tensor forms' readers agree, and
//   each cell read gets a kind of its own order (no dispatch falls back to another);
// - the messages name every type read and none refused;
// - the plugin's XML, the filters' and Python package's docstrings, the package's metadata and
//   the README name every type read (or, where a line is short, every shape and the orders), and
//   the nine places that state what the product reads name no type it does not read and no
//   other orders.
#include "tetdsr/cells/CellKinds.h"
#include "tetdsr/common/CellTypes.h"
#include "tetdsr/cells/HexahedronCell.h"
#include "tetdsr/cells/SplitCells.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace
{

/// The order of a kind's cells (hexahedra: per axis), from the kind alone.
int kindOrder(tetdsr::CellKind kind)
{
  using tetdsr::CellKind;
  switch (kind)
  {
    case CellKind::LinearTet:
      return 1;
    case CellKind::QuadraticTet:
    case CellKind::CurvedTet:
      return 2;
    case CellKind::CubicTet:
    case CellKind::CurvedCubicTet:
      return 3;
    case CellKind::QuarticTet:
    case CellKind::CurvedQuarticTet:
      return 4;
    default:
    {
      // Hexahedron1..4, CurvedHexahedron1..4, Wedge1..4.
      const CellKind first = kind >= CellKind::Wedge1 ? CellKind::Wedge1
        : kind >= CellKind::CurvedHexahedron1        ? CellKind::CurvedHexahedron1
                                                     : CellKind::Hexahedron1;
      return 1 + static_cast<int>(kind) - static_cast<int>(first);
    }
  }
}

std::string fileText(const std::string& relative)
{
  std::ifstream in(std::string(TETDSR_SOURCE_DIR) + "/" + relative);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

} // namespace

TEST(CellTypes, TheTableIsWellFormed)
{
  std::set<int> codes;
  std::set<std::string> names;
  for (const tetdsr::CellType& type : tetdsr::kCellTypes)
  {
    EXPECT_TRUE(codes.insert(type.vtkType).second) << type.name;
    EXPECT_TRUE(names.insert(type.name).second) << type.name;
    EXPECT_EQ(tetdsr::cellTypeOf(type.vtkType), &type) << type.name;
    EXPECT_EQ(tetdsr::isRead(&type), type.refusal == nullptr) << type.name << ": a refused type says why";
    if (tetdsr::isRead(&type) && type.rule == tetdsr::NodeRule::Fixed)
    {
      EXPECT_GT(type.nodes, 0) << type.name;
      EXPECT_EQ(type.maxOrder, type.order) << type.name;
    }
    if (type.rule != tetdsr::NodeRule::Fixed)
    {
      EXPECT_EQ(type.maxOrder, tetdsr::kMaxReadOrder) << type.name;
    }
  }
  for (int code = 0; code < 256; ++code)
  {
    if (!codes.count(code))
    {
      EXPECT_EQ(tetdsr::cellTypeOf(code), nullptr) << code;
    }
  }
  EXPECT_EQ(tetdsr::cellTypeOf(-1), nullptr);
  EXPECT_EQ(tetdsr::cellTypeOf(1 << 20), nullptr);
}

TEST(CellTypes, EveryCodeAndIdCountReadsAsTheTableSays)
{
  int read = 0;
  double largestGrowth = 0.0;
  for (int code = 0; code < 256; ++code)
  {
    const tetdsr::CellType* type = tetdsr::cellTypeOf(code);
    for (long long ids : { -1LL, 0LL, 1LL, 2LL, 3LL, 1LL << 40, 1LL << 62 })
    {
      tetdsr::CellLayout layout;
      const std::uint16_t status = tetdsr::cellLayout(code, ids, layout);
      EXPECT_EQ(status, tetdsr::isRead(type) ? tetdsr::kMalformed : tetdsr::kUnsupported) << code << ", " << ids;
    }
    for (long long ids = 4; ids <= 400; ++ids)
    {
      tetdsr::CellLayout layout;
      const std::uint16_t status = tetdsr::cellLayout(code, ids, layout);
      if (!tetdsr::isRead(type))
      {
        EXPECT_EQ(status, tetdsr::kUnsupported) << code << ", " << ids;
        continue;
      }
      const int order = tetdsr::orderOf(*type, ids);
      const std::uint16_t expected =
        order == 0 ? tetdsr::kMalformed : order > type->maxOrder ? tetdsr::kOrderTooHigh : 0;
      ASSERT_EQ(status, expected) << type->name << ", " << ids << " ids";
      // The split's and the tensor forms' readers say the same for their shapes.
      const tetdsr::SplitShape* shape = nullptr;
      if (type->shape == tetdsr::CellShape::Hexahedron || type->shape == tetdsr::CellShape::Wedge)
      {
        EXPECT_EQ(tetdsr::splitShapeOf(code, ids, shape), expected) << type->name << ", " << ids;
      }
      const tetdsr::HexahedronNodes* table = nullptr;
      if (type->shape != tetdsr::CellShape::Tetrahedron)
      {
        EXPECT_EQ(tetdsr::hexahedronNodesOf(code, ids, table), expected) << type->name << ", " << ids;
      }
      if (status != 0)
      {
        continue;
      }
      ++read;
      // Read with exactly its nodes, by a kind of its own order, straight or curved.
      EXPECT_EQ(layout.nodes, ids) << type->name;
      EXPECT_EQ(nodeCount(*type, order), ids) << type->name;
      EXPECT_EQ(layout.bezier, type->bezier) << type->name;
      for (bool curved : { false, true })
      {
        const tetdsr::CellKind kind = tetdsr::kindOf(layout, curved);
        EXPECT_EQ(kindOrder(kind), layout.order) << type->name << ", " << ids << " ids";
        EXPECT_EQ(tetdsr::isHexahedronKind(kind), type->shape != tetdsr::CellShape::Tetrahedron) << type->name;
      }
      if (table)
      {
        EXPECT_EQ(table->name, std::string(type->name));
        EXPECT_EQ(table->mirrored, type->mirrored) << type->name;
        // Its tensor form's degree per axis: the type's order, but for the 19-node pyramid's
        // (of degree 3 along its axis in the cube collapsed onto it).
        EXPECT_EQ(table->order, code == tetdsr::kVtkTriquadraticPyramid ? 3 : order) << type->name;
        // Its making grows rounding within what the tensor forms' constant test allows.
        EXPECT_GE(table->roundingGrowth, 1.0) << type->name;
        EXPECT_LE(table->roundingGrowth, tetdsr::kMaxRoundingGrowth) << type->name << ", " << ids << " ids";
        largestGrowth = std::max(largestGrowth, table->roundingGrowth);
      }
    }
  }
  // 2 + 2 x 4 tetrahedra, 5 + 2 x 4 hexahedra, 4 + 2 x 4 wedges, 3 pyramids.
  EXPECT_EQ(read, 10 + 13 + 12 + 3);
  std::printf("largest node table rounding growth: %.3g (allowed %.3g)\n", largestGrowth, tetdsr::kMaxRoundingGrowth);
}

TEST(CellTypes, MessagesNameEveryTypeReadAndNoneRefused)
{
  const std::string reads = tetdsr::readTypesText(), counts = tetdsr::nodeCountsText();
  const std::string refused = tetdsr::refusedTypesText();
  for (const tetdsr::CellType& type : tetdsr::kCellTypes)
  {
    const std::string name = type.name;
    // (Whole names: VTK_PYRAMID is inside VTK_QUADRATIC_PYRAMID's.)
    auto names = [&](const std::string& text) {
      for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1))
      {
        const bool before = at == 0 || (text[at - 1] != '_' && !std::isalnum(static_cast<unsigned char>(text[at - 1])));
        const std::size_t end = at + name.size();
        const bool after = end == text.size() || (text[end] != '_' && !std::isalnum(static_cast<unsigned char>(text[end])));
        if (before && after)
        {
          return true;
        }
      }
      return false;
    };
    EXPECT_EQ(names(reads), tetdsr::isRead(&type)) << name << " in: " << reads;
    EXPECT_EQ(names(counts), tetdsr::isRead(&type)) << name << " in: " << counts;
    // The malformed cells' message gives each type's node counts, the table's.
    if (tetdsr::isRead(&type) && type.rule == tetdsr::NodeRule::Fixed)
    {
      const std::string count = std::to_string(type.nodes) + " for " + name;
      EXPECT_NE(counts.find(count), std::string::npos) << "expected \"" << count << "\" in: " << counts;
    }
    else if (tetdsr::isRead(&type))
    {
      std::string sequence = "(";
      for (int order = 1; order <= tetdsr::kMaxReadOrder; ++order)
      {
        sequence += std::to_string(tetdsr::nodeCount(type, order)) + ", ";
      }
      sequence += "...) for ";
      const std::size_t at = counts.find(sequence);
      EXPECT_TRUE(at != std::string::npos && counts.find(name, at) != std::string::npos &&
        counts.find(name, at) < counts.find(" for ", at + sequence.size()))
        << "expected \"" << sequence << "... " << name << "\" in: " << counts;
    }
    EXPECT_EQ(names(refused), !tetdsr::isRead(&type)) << name << " in: " << refused;
  }
  EXPECT_EQ(tetdsr::orderLimitsText(),
    "Lagrange or Bezier tetrahedra of order above 4 (more than 35 nodes), hexahedra of order above 4 "
    "(more than 125 nodes) and wedges of order above 4 (more than 75 nodes)");
}

namespace
{
/// The nine places that state what the product reads (and the binding's own docstring): each
/// names only types the table reads, and every "orders 1 to K" in it says the table's highest.
const char* const kCapabilityTexts[] = { "Plugin/DirectSurfaceRayCaster.xml",
  "Plugin/DirectSurfaceRepresentation.xml", "Plugin/paraview.plugin", "pyproject.toml",
  "Wrapping/Python/tetdsr/__init__.py", "Wrapping/Python/tetdsr/paraview_plugin.py",
  "Wrapping/Python/tetdsr/pyvista.py", "Rendering/vtkDirectSurfaceMapper.h",
  "Filters/vtkDirectSurfaceRayCaster.h", "Wrapping/Python/module.cpp" };

/// Failures for each claim of `text` the table contradicts: a cell type named that the core does
/// not read (refused, or not a VTK type at all), an order range other than 1 to kMaxReadOrder.
void expectClaimsOfTheTable(const std::string& document, const std::string& text)
{
  const std::regex typeName("VTK_[A-Z_]*(TETRA|TETRAHEDRON|HEXAHEDRON|VOXEL|WEDGE|PYRAMID)\\b");
  for (std::sregex_iterator it(text.begin(), text.end(), typeName), end; it != end; ++it)
  {
    const std::string name = it->str();
    const auto row = std::find_if(std::begin(tetdsr::kCellTypes), std::end(tetdsr::kCellTypes),
      [&](const tetdsr::CellType& type) { return name == type.name; });
    EXPECT_TRUE(row != std::end(tetdsr::kCellTypes) && tetdsr::isRead(&*row))
      << document << " names " << name << ", which the core's cell type table does not read";
  }
  const std::regex orders("orders? 1 to (\\d+)");
  int claims = 0;
  for (std::sregex_iterator it(text.begin(), text.end(), orders), end; it != end; ++it, ++claims)
  {
    EXPECT_EQ(std::stoi((*it)[1].str()), tetdsr::kMaxReadOrder)
      << document << " says \"" << it->str() << "\"";
  }
  EXPECT_GT(claims, 0) << document << " does not give the orders read";
}
} // namespace

TEST(CellTypes, CapabilityTextsClaimWhatTheTableReads)
{
  for (const char* document : kCapabilityTexts)
  {
    const std::string text = fileText(document);
    ASSERT_FALSE(text.empty()) << document;
    expectClaimsOfTheTable(document, text);
  }
}

TEST(CellTypes, DocumentsNameEveryTypeRead)
{
  // Where users read what is read: every type's name.
  for (const char* document : { "Plugin/DirectSurfaceRayCaster.xml", "Plugin/DirectSurfaceRepresentation.xml",
         "Filters/vtkDirectSurfaceRayCaster.h", "Rendering/vtkDirectSurfaceMapper.h", "README.md",
         "Wrapping/Python/module.cpp", "Wrapping/Python/tetdsr/__init__.py", "docs/reliability-and-limits.md" })
  {
    const std::string text = fileText(document);
    ASSERT_FALSE(text.empty()) << document;
    for (const tetdsr::CellType& type : tetdsr::kCellTypes)
    {
      if (tetdsr::isRead(&type))
      {
        EXPECT_NE(text.find(type.name), std::string::npos) << document << " does not name " << type.name;
      }
    }
  }
  // Where a line is short (the package's one-line description, the classes' docstrings): every
  // shape and the orders.
  for (const char* document : { "pyproject.toml", "Wrapping/Python/tetdsr/filter.py",
         "Wrapping/Python/tetdsr/contour.py", "Wrapping/Python/tetdsr/pyvista.py",
         "Wrapping/Python/tetdsr/paraview_plugin.py", "Plugin/paraview.plugin" })
  {
    const std::string text = fileText(document);
    ASSERT_FALSE(text.empty()) << document;
    for (const char* shape : { "tetrahedra", "hexahedra", "wedges", "pyramids" })
    {
      EXPECT_NE(text.find(shape), std::string::npos) << document << " does not name " << shape;
    }
    EXPECT_NE(text.find("orders 1 to " + std::to_string(tetdsr::kMaxReadOrder)), std::string::npos)
      << document << " does not give the orders read";
  }
}
