// The one table of the VTK cell types the core knows (kCellTypes): each type's code and name, its
// shape, how its id count gives its order (VTK's rules) and which orders are read, whether its
// nodes are control points or mirror the parametric cell, and how its cells are solved.
//
// Everything that asks "is this type read, of what order, by which solver" asks this table:
// validation (cellLayout, Cells.h), the split of straight wedges (SplitCells.h), the tensor forms
// (HexahedronCell.h), and every message that names the types read, their node counts or their
// highest orders (MeshInput.cpp, from the texts below). Testing/Core/TestCellTypes checks the
// table against the core's own reading of every type and id count, and the plugin's XML, the
// filters' docstrings and the package's metadata against the table.
//
// Adding a type: a row here, and its node table (its own construction in HexahedronTables.cpp
// for a hexahedron, wedge or pyramid; a tetrahedron is read by its order alone).
#pragma once

#include <cstdint>
#include <string>

namespace tetdsr
{

/// VTK's codes (vtkCellType.h) of the volume cell types the table names.
enum VtkCellType : int
{
  kVtkTetra = 10,
  kVtkVoxel = 11,
  kVtkHexahedron = 12,
  kVtkWedge = 13,
  kVtkPyramid = 14,
  kVtkQuadraticTetra = 24,
  kVtkQuadraticHexahedron = 25,
  kVtkQuadraticWedge = 26,
  kVtkQuadraticPyramid = 27,
  kVtkTriquadraticHexahedron = 29,
  kVtkQuadraticLinearWedge = 31,
  kVtkBiquadraticQuadraticWedge = 32,
  kVtkBiquadraticQuadraticHexahedron = 33,
  kVtkTriquadraticPyramid = 37,
  kVtkLagrangeTetrahedron = 71,
  kVtkLagrangeHexahedron = 72,
  kVtkLagrangeWedge = 73,
  kVtkLagrangePyramid = 74,
  kVtkBezierTetrahedron = 78,
  kVtkBezierHexahedron = 79,
  kVtkBezierWedge = 80,
  kVtkBezierPyramid = 81
};

enum class CellShape : std::uint8_t
{
  Tetrahedron,
  Hexahedron,
  Wedge,
  Pyramid
};

/// How a type's id count tells its order p.
enum class NodeRule : std::uint8_t
{
  Fixed,       ///< one count, one order (CellType::nodes, ::order)
  Tetrahedral, ///< (p + 1)(p + 2)(p + 3) / 6 (vtkHigherOrderTetra; its 15-node variant is not read)
  Cubic,       ///< (p + 1)^3 (vtkHigherOrderHexahedron)
  Prismatic    ///< (p + 1)^2 (p + 2) / 2 (vtkHigherOrderWedge; its 21-node variant is not read)
};

/// How the core solves a type's cells.
enum class CellSolver : std::uint8_t
{
  Tetrahedron, ///< a tetrahedron kind of its order, straight or curved (Cells.h)
  TensorForm,  ///< in its own reference cube (HexahedronCell.h; straight wedges: WedgeCell.h)
  None         ///< not read (CellType::refusal says why)
};

struct CellType
{
  int vtkType;
  const char* name;
  CellShape shape;
  NodeRule rule;
  int nodes;    ///< Fixed: its id count
  int order;    ///< Fixed: its order (per axis; a tetrahedron's total)
  int maxOrder; ///< the highest order read
  bool bezier;  ///< its nodes are Bernstein control points
  /// VTK orders its nodes so that a well-formed cell's map reverses the parametric orientation
  /// (the triangle (0, 1, 2)'s right-hand normal points away from (3, 4, 5)): such a cell is
  /// inverted when its map is positive.
  bool mirrored;
  CellSolver solver;
  const char* refusal; ///< why a type not read is not (the warning's words), else nullptr
};

/// The highest order of Lagrange and Bezier cells the core reads, per axis (tetrahedra: total).
constexpr int kMaxReadOrder = 4;

// clang-format off
inline constexpr CellType kCellTypes[] = {
  // code, name, shape, rule, nodes, order, max order, bezier, mirrored, solver, refusal
  { kVtkTetra, "VTK_TETRA", CellShape::Tetrahedron, NodeRule::Fixed, 4, 1, 1, false, false, CellSolver::Tetrahedron, nullptr },
  { kVtkQuadraticTetra, "VTK_QUADRATIC_TETRA", CellShape::Tetrahedron, NodeRule::Fixed, 10, 2, 2, false, false, CellSolver::Tetrahedron, nullptr },
  { kVtkLagrangeTetrahedron, "VTK_LAGRANGE_TETRAHEDRON", CellShape::Tetrahedron, NodeRule::Tetrahedral, 0, 0, kMaxReadOrder, false, false, CellSolver::Tetrahedron, nullptr },
  { kVtkBezierTetrahedron, "VTK_BEZIER_TETRAHEDRON", CellShape::Tetrahedron, NodeRule::Tetrahedral, 0, 0, kMaxReadOrder, true, false, CellSolver::Tetrahedron, nullptr },
  { kVtkHexahedron, "VTK_HEXAHEDRON", CellShape::Hexahedron, NodeRule::Fixed, 8, 1, 1, false, false, CellSolver::TensorForm, nullptr },
  { kVtkVoxel, "VTK_VOXEL", CellShape::Hexahedron, NodeRule::Fixed, 8, 1, 1, false, false, CellSolver::TensorForm, nullptr },
  { kVtkQuadraticHexahedron, "VTK_QUADRATIC_HEXAHEDRON", CellShape::Hexahedron, NodeRule::Fixed, 20, 2, 2, false, false, CellSolver::TensorForm, nullptr },
  { kVtkBiquadraticQuadraticHexahedron, "VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON", CellShape::Hexahedron, NodeRule::Fixed, 24, 2, 2, false, false, CellSolver::TensorForm, nullptr },
  { kVtkTriquadraticHexahedron, "VTK_TRIQUADRATIC_HEXAHEDRON", CellShape::Hexahedron, NodeRule::Fixed, 27, 2, 2, false, false, CellSolver::TensorForm, nullptr },
  { kVtkLagrangeHexahedron, "VTK_LAGRANGE_HEXAHEDRON", CellShape::Hexahedron, NodeRule::Cubic, 0, 0, kMaxReadOrder, false, false, CellSolver::TensorForm, nullptr },
  { kVtkBezierHexahedron, "VTK_BEZIER_HEXAHEDRON", CellShape::Hexahedron, NodeRule::Cubic, 0, 0, kMaxReadOrder, true, false, CellSolver::TensorForm, nullptr },
  { kVtkWedge, "VTK_WEDGE", CellShape::Wedge, NodeRule::Fixed, 6, 1, 1, false, true, CellSolver::TensorForm, nullptr },
  { kVtkQuadraticLinearWedge, "VTK_QUADRATIC_LINEAR_WEDGE", CellShape::Wedge, NodeRule::Fixed, 12, 2, 2, false, true, CellSolver::TensorForm, nullptr },
  { kVtkQuadraticWedge, "VTK_QUADRATIC_WEDGE", CellShape::Wedge, NodeRule::Fixed, 15, 2, 2, false, true, CellSolver::TensorForm, nullptr },
  { kVtkBiquadraticQuadraticWedge, "VTK_BIQUADRATIC_QUADRATIC_WEDGE", CellShape::Wedge, NodeRule::Fixed, 18, 2, 2, false, true, CellSolver::TensorForm, nullptr },
  { kVtkLagrangeWedge, "VTK_LAGRANGE_WEDGE", CellShape::Wedge, NodeRule::Prismatic, 0, 0, kMaxReadOrder, false, false, CellSolver::TensorForm, nullptr },
  { kVtkBezierWedge, "VTK_BEZIER_WEDGE", CellShape::Wedge, NodeRule::Prismatic, 0, 0, kMaxReadOrder, true, false, CellSolver::TensorForm, nullptr },
  { kVtkPyramid, "VTK_PYRAMID", CellShape::Pyramid, NodeRule::Fixed, 5, 1, 1, false, false, CellSolver::TensorForm, nullptr },
  { kVtkQuadraticPyramid, "VTK_QUADRATIC_PYRAMID", CellShape::Pyramid, NodeRule::Fixed, 13, 2, 2, false, false, CellSolver::TensorForm, nullptr },
  { kVtkTriquadraticPyramid, "VTK_TRIQUADRATIC_PYRAMID", CellShape::Pyramid, NodeRule::Fixed, 19, 2, 2, false, false, CellSolver::TensorForm, nullptr },
  { kVtkLagrangePyramid, "VTK_LAGRANGE_PYRAMID", CellShape::Pyramid, NodeRule::Fixed, 0, 0, 0, false, false, CellSolver::None, "VTK 9.2 has no cell class of the type" },
  { kVtkBezierPyramid, "VTK_BEZIER_PYRAMID", CellShape::Pyramid, NodeRule::Fixed, 0, 0, 0, true, false, CellSolver::None, "VTK 9.2 has no cell class of the type" },
};
// clang-format on

/// The table's row of a VTK type, or nullptr (a type the table does not name).
const CellType* cellTypeOf(int vtkType);

/// Whether the core reads the type at all.
inline bool isRead(const CellType* type)
{
  return type && type->solver != CellSolver::None;
}

/// The order a cell of the type with `ids` node ids has by VTK's rule (any order, read or not), or
/// 0 if the count fits no order of the type (a malformed cell).
int orderOf(const CellType& type, long long ids);

/// The node count of an order by the type's rule.
long long nodeCount(const CellType& type, int order);

/// For messages, from the table: the types read ("VTK_TETRA, ... of order 1 to 4; VTK_HEXAHEDRON,
/// ..."), the node counts each takes, and the orders above those read (by shape).
std::string readTypesText();
std::string nodeCountsText();
std::string orderLimitsText();
/// The types the table names but refuses, with why ("VTK_LAGRANGE_PYRAMID or
/// VTK_BEZIER_PYRAMID: VTK 9.2 has no cell class of the type"); empty if none.
std::string refusedTypesText();

} // namespace tetdsr
