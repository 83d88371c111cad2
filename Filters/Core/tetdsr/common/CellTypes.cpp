// The cell type table's lookup, VTK's node-count rules, and the texts messages take from it.
#include "tetdsr/common/CellTypes.h"

#include <array>
#include <sstream>
#include <vector>

namespace tetdsr
{

namespace
{

/// Each VTK code's row in kCellTypes (VTK's codes are below 256), or -1.
constexpr std::array<int, 256> rowIndex()
{
  std::array<int, 256> index{};
  for (int& row : index)
  {
    row = -1;
  }
  for (int row = 0; row < static_cast<int>(std::size(kCellTypes)); ++row)
  {
    index[static_cast<std::size_t>(kCellTypes[row].vtkType)] = row;
  }
  return index;
}
constexpr std::array<int, 256> kRowIndex = rowIndex();

const char* shapePlural(CellShape shape)
{
  switch (shape)
  {
    case CellShape::Tetrahedron:
      return "tetrahedra";
    case CellShape::Hexahedron:
      return "hexahedra";
    case CellShape::Wedge:
      return "wedges";
    case CellShape::Pyramid:
      break;
  }
  return "pyramids";
}

/// The rows read, grouped by shape in the table's order.
std::vector<std::vector<const CellType*>> readByShape()
{
  std::vector<std::vector<const CellType*>> groups;
  for (const CellType& type : kCellTypes)
  {
    if (!isRead(&type))
    {
      continue;
    }
    if (groups.empty() || groups.back().front()->shape != type.shape)
    {
      groups.emplace_back();
    }
    groups.back().push_back(&type);
  }
  return groups;
}

/// "A", "A or B", "A, B or C" (`word`: "or", "and").
std::string joined(const std::vector<std::string>& items, const char* word)
{
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k)
  {
    out += k == 0 ? "" : k + 1 == items.size() ? std::string(" ") + word + " " : ", ";
    out += items[k];
  }
  return out;
}

} // namespace

const CellType* cellTypeOf(int vtkType)
{
  if (vtkType < 0 || vtkType >= 256 || kRowIndex[static_cast<std::size_t>(vtkType)] < 0)
  {
    return nullptr;
  }
  return &kCellTypes[kRowIndex[static_cast<std::size_t>(vtkType)]];
}

long long nodeCount(const CellType& type, int order)
{
  const long long p = order;
  switch (type.rule)
  {
    case NodeRule::Fixed:
      return order == type.order ? type.nodes : 0;
    case NodeRule::Tetrahedral:
      return (p + 1) * (p + 2) * (p + 3) / 6;
    case NodeRule::Cubic:
      return (p + 1) * (p + 1) * (p + 1);
    case NodeRule::Prismatic:
      break;
  }
  return (p + 1) * (p + 1) * (p + 2) / 2;
}

int orderOf(const CellType& type, long long ids)
{
  if (type.rule == NodeRule::Fixed)
  {
    return type.nodes > 0 && ids == type.nodes ? type.order : 0;
  }
  // The counts grow as p^3: the p with count(p) >= ids is within the cube root of 6 ids + 1
  // (beyond 2^50 ids, 8 PiB of connectivity, none is taken, so the products stay in range).
  if (ids < 4 || ids > (1LL << 50))
  {
    return 0;
  }
  for (int p = 1; p <= (1 << 17); ++p)
  {
    const long long n = nodeCount(type, p);
    if (n >= ids)
    {
      return n == ids ? p : 0;
    }
  }
  return 0;
}

std::string readTypesText()
{
  std::vector<std::string> groups;
  for (const auto& group : readByShape())
  {
    std::vector<std::string> fixed, ruled;
    int maxOrder = 0;
    for (const CellType* type : group)
    {
      (type->rule == NodeRule::Fixed ? fixed : ruled).push_back(type->name);
      if (type->rule != NodeRule::Fixed)
      {
        maxOrder = type->maxOrder;
      }
    }
    if (!ruled.empty())
    {
      fixed.push_back(joined(ruled, "or") + " of order 1 to " + std::to_string(maxOrder));
    }
    std::string text;
    for (std::size_t k = 0; k < fixed.size(); ++k)
    {
      text += (k ? ", " : "") + fixed[k];
    }
    groups.push_back(text);
  }
  std::string out;
  for (std::size_t k = 0; k < groups.size(); ++k)
  {
    out += (k ? "; " : "") + groups[k];
  }
  return out;
}

std::string nodeCountsText()
{
  std::vector<std::string> items;
  for (const auto& group : readByShape())
  {
    for (std::size_t k = 0; k < group.size(); ++k)
    {
      const CellType& type = *group[k];
      if (type.rule == NodeRule::Fixed)
      {
        items.push_back(std::to_string(type.nodes) + " for " + type.name);
        continue;
      }
      // Rows of one rule side by side share it: "a cube number (8, 27, 64, ...) for A and B".
      std::vector<std::string> names{ type.name };
      while (k + 1 < group.size() && group[k + 1]->rule == type.rule)
      {
        names.push_back(group[++k]->name);
      }
      std::ostringstream counts;
      for (int p = 1; p <= 4; ++p)
      {
        counts << nodeCount(type, p) << ", ";
      }
      const char* rule = type.rule == NodeRule::Tetrahedral ? "a tetrahedral number"
        : type.rule == NodeRule::Cubic                      ? "a cube number"
                                                            : "(p + 1)^2 (p + 2) / 2";
      items.push_back(std::string(rule) + " (" + counts.str() + "...) for " + joined(names, "and"));
    }
  }
  return joined(items, "and");
}

std::string orderLimitsText()
{
  std::vector<std::string> items;
  for (const auto& group : readByShape())
  {
    for (const CellType* type : group)
    {
      if (type->rule != NodeRule::Fixed)
      {
        items.push_back(std::string(items.empty() ? "Lagrange or Bezier " : "") + shapePlural(type->shape) +
          " of order above " + std::to_string(type->maxOrder) + " (more than " +
          std::to_string(nodeCount(*type, type->maxOrder)) + " nodes)");
        break;
      }
    }
  }
  return joined(items, "and");
}

std::string refusedTypesText()
{
  // Per reason, in the table's order: "A or B: why; C: another".
  std::vector<std::string> reasons;
  for (const CellType& type : kCellTypes)
  {
    if (isRead(&type) || !type.refusal)
    {
      continue;
    }
    bool told = false;
    for (const std::string& reason : reasons)
    {
      told = told || reason == type.refusal;
    }
    if (told)
    {
      continue;
    }
    reasons.emplace_back(type.refusal);
  }
  std::string out;
  for (const std::string& reason : reasons)
  {
    std::vector<std::string> names;
    for (const CellType& type : kCellTypes)
    {
      if (!isRead(&type) && type.refusal && reason == type.refusal)
      {
        names.push_back(type.name);
      }
    }
    out += (out.empty() ? "" : "; ") + joined(names, "or") + ": " + reason;
  }
  return out;
}

} // namespace tetdsr
