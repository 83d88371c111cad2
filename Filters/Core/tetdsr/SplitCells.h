// Hexahedra and wedges, as tetrahedra of their polynomials' degree.
//
// A hexahedron's or wedge's map and field are polynomials in its parametric coordinates (r, s, t):
// trilinear for VTK_HEXAHEDRON, the serendipity space for the 20-node hexahedron, P_p(r, s) x
// P_q(t) and its relatives for wedges. Split its parametric domain (the unit cube, or the unit
// triangle times [0, 1]) into tetrahedra (6 along the cube's diagonal, Kuhn's split; 3 for the
// wedge): on each, the cell's polynomials restricted to that tetrahedron are polynomials of total
// degree D in its barycentric coordinates (D = 3 for a trilinear hexahedron, 4 for the serendipity
// one, 2 to 4 for wedges), so a Lagrange tetrahedron of order D whose nodes are the cell's map
// and field evaluated at the tetrahedron's lattice points represents them exactly. The pieces
// are then ordinary cells of the core (straight when the cell's map is affine, isoparametric
// otherwise): every step (validation, Bernstein bounds, certified roots, tangled cells, colour
// arrays) is theirs, and the hit's cell id is mapped back to the input cell.
//
// Neighbours stay watertight: two cells sharing a face have the same polynomial map on it (the
// same nodes), and each cell's pieces cover its whole face, however each splits it.
//
// The cell's shape functions come from its nodes (VTK order, checked against VTK's own cells by
// Testing/Cxx/TestSplitCellsNodeOrder) and its polynomial space: the nodal basis (the inverse of
// the space's Vandermonde matrix at the nodes), or for a Bezier cell its Bernstein basis.
#pragma once

#include "tetdsr/Scene.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tetdsr
{

/// VTK's codes (vtkCellType.h) of hexahedra, wedges and pyramids.
enum VtkSplitCellType : int
{
  kVtkVoxel = 11,
  kVtkHexahedron = 12,
  kVtkWedge = 13,
  kVtkPyramid = 14,
  kVtkQuadraticHexahedron = 25,
  kVtkQuadraticWedge = 26,
  kVtkQuadraticPyramid = 27,
  kVtkTriquadraticHexahedron = 29,
  kVtkQuadraticLinearWedge = 31,
  kVtkBiquadraticQuadraticWedge = 32,
  kVtkBiquadraticQuadraticHexahedron = 33,
  kVtkTriquadraticPyramid = 37,
  kVtkLagrangeHexahedron = 72,
  kVtkLagrangeWedge = 73,
  kVtkLagrangePyramid = 74,
  kVtkBezierHexahedron = 79,
  kVtkBezierWedge = 80,
  kVtkBezierPyramid = 81
};

/// How one kind of hexahedron or wedge (a VTK type and node count) is split into tetrahedra.
struct SplitShape
{
  const char* name = "";  ///< as messages and tests name it ("VTK_HEXAHEDRON", ...)
  bool wedge = false;     ///< the unit triangle times [0, 1]; else the unit cube
  bool bezier = false;    ///< nodes are Bernstein control points (else nodal values)
  int nodes = 0;          ///< the cell's node count
  int degree = 0;         ///< D: the total degree of its polynomials, the pieces' order (2..4)
  int pieces = 0;         ///< tetrahedra per cell: 6 (hexahedra), 3 (wedges)
  int pieceNodes = 0;     ///< latticeCount(degree)
  /// The parametric coordinates (r, s, t) of the cell's nodes, VTK's order.
  std::vector<std::array<double, 3>> nodePoints;
  /// Per piece, per node of a Lagrange tetrahedron of order `degree` (VTK's order): the cell's
  /// lattice point there (pieces x pieceNodes).
  std::vector<int> pieceLattice;
  /// Per lattice point used by a piece: the cell's node there, or -1 (then a new point).
  std::vector<int> latticeNode;
  /// Per lattice point: its place among the cell's new points, or -1.
  std::vector<int> latticeNew;
  /// The parametric point of each new point, and the cell's shape functions there
  /// (newPoints() x nodes).
  std::vector<std::array<double, 3>> newPoints;
  std::vector<double> newWeights;

  int newPointCount() const { return static_cast<int>(newPoints.size()); }
  /// The cell's shape functions at a parametric point (nodes values), as the split uses them.
  void basis(const double parametric[3], double* weights) const;

  // The polynomial space of a nodal cell: monomials r^a s^b t^c (empty for a Bezier cell).
  std::vector<std::array<int, 3>> monomials;
  /// The inverse transposed Vandermonde matrix (nodes x nodes): weights = this * monomials(x).
  std::vector<double> inverseVandermonde;
  int bezierTriangle = 0; ///< a Bezier wedge's degree in (r, s)
  int bezierAxis = 0;     ///< and in t
};

/// Whether a VTK type is a hexahedron, wedge or pyramid (read or refused by the split).
bool isSplitType(int vtkType);

/// The shape of a cell of a hexahedron or wedge type with `ids` node ids; 0 if it is read, else
/// the status saying why not (kMalformed: an id count that does not fit the type; kOrderTooHigh:
/// polynomials of total degree above kMaxTetOrder; kUnsupported: pyramids).
std::uint16_t splitShapeOf(int vtkType, long long ids, const SplitShape*& shape);

/// A mesh whose hexahedra and wedges are split into tetrahedra (the other cells kept as they
/// are), with the map back to the input's cells: a MeshView the Scene reads, owning its arrays.
class SplitMesh
{
public:
  SplitMesh();
  ~SplitMesh();
  SplitMesh(const SplitMesh&) = delete;
  SplitMesh& operator=(const SplitMesh&) = delete;

  /// Whether `input` has a cell of a split type at all (else it is read as it is).
  static bool needed(const MeshView& input);

  /// Splits `input` (whose counts MeshInput checked). False, with `error` set, when the pieces
  /// would be more than a scene can index.
  bool split(const MeshView& input, const ParallelFor& parallelFor, std::string& error);

  /// The split mesh (its sourceCells, sourceOffsets and sourceStatus map back to the input).
  const MeshView& view() const { return View_; }

  /// A point array of the input (`components` values per point, the input's point count)
  /// extended to the split mesh's points: the new points' values are the cells' shape functions
  /// applied to their nodes' values.
  void extend(const double* input, int components, std::vector<double>& out) const;

  std::size_t memoryBytes() const;

private:
  struct Arrays;
  std::unique_ptr<Arrays> Data_;
  MeshView View_;
};

} // namespace tetdsr
