// Wedges, as tetrahedra of their polynomials' degree. (Hexahedra are solved as themselves, in
// their reference cube: HexahedronCell.h; their shapes below serve as node tables.)
//
// A wedge's map and field are polynomials in its parametric coordinates (r, s, t): P_p(r, s) x
// P_q(t) and its relatives. Split its parametric domain (the unit triangle times [0, 1]) into 3
// tetrahedra: on each, the cell's polynomials restricted to that tetrahedron are polynomials of
// total degree D in its barycentric coordinates (2p for wedges of order p), so a tetrahedron of
// order D whose nodes (D <= 4: Lagrange) or control points (above: Bezier) come from the cell's
// map and field represents them exactly. The pieces are then ordinary cells of the core
// (straight when the cell's map is affine, then placed by that map; isoparametric otherwise):
// every step (validation, Bernstein bounds, certified roots, tangled cells, colour arrays) is
// theirs, and the hit's cell id is mapped back to the input cell. A curved piece's ray test is a
// subdivision solve whose cost grows steeply with D (docs/performance.md gives the figures per
// kind).
//
// Neighbours stay watertight: two cells sharing a face have the same polynomial map on it (the
// same nodes), and each cell's pieces cover its whole face, however each splits it.
//
// The cell's shape functions come from its nodes (VTK order, checked against VTK's own cells by
// Testing/Cxx/TestSplitCellsNodeOrder) and its polynomial space: the nodal basis (the inverse of
// the space's Vandermonde matrix at the nodes), or for a Bezier cell its Bernstein basis.
// Hexahedra's shapes (their nodes and basis, no pieces) serve HexahedronCell.h's node tables.
#pragma once

#include "tetdsr/Scene.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tetdsr
{


/// How one kind of hexahedron or wedge (a VTK type and node count) is split into tetrahedra.
struct SplitShape
{
  /// How the cell's shape functions are given.
  enum class Basis : std::uint8_t
  {
    Monomials,     ///< the nodal basis of a space of monomials (the inverse Vandermonde matrix)
    LagrangeHex,   ///< products of 1D Lagrange polynomials on equispaced nodes (order p)
    LagrangeWedge, ///< the triangle's Lagrange polynomials on its equispaced lattice times 1D ones
    BezierHex,     ///< products of Bernstein polynomials (control points)
    BezierWedge    ///< the triangle's Bernstein polynomials times 1D ones
  };
  /// The largest absolute row sum of the weights making a piece's Bernstein coefficients
  /// (orders above 4) from the cell's nodes; kPieceConstantRoundings (Cells.h) assumes it.
  static constexpr double kMaxCoefficientWeight = 64.0;

  const char* name = "";  ///< as messages and tests name it ("VTK_HEXAHEDRON", ...)
  bool wedge = false;     ///< the unit triangle times [0, 1]; else the unit cube
  Basis basisKind = Basis::Monomials;
  int order = 1;          ///< p of the Lagrange and Bezier bases
  int nodes = 0;          ///< the cell's node count
  int degree = 0;         ///< D: the total degree of its polynomials, the pieces' order
  int pieces = 0;         ///< tetrahedra per cell: 3 (wedges); 0 (hexahedra: not split)
  int pieceNodes = 0;     ///< latticeCount(degree)
  /// Pieces of order 2 to 4 are Lagrange tetrahedra (nodes: the cell's map and field at their
  /// lattice points, shared between pieces); above, Bezier tetrahedra (their Bernstein
  /// coefficients, from the cell's nodes by exact weights: a Lagrange conversion of such orders
  /// would amplify rounding).
  bool bezierPieces = false;
  /// The parametric coordinates (r, s, t) of the cell's nodes, VTK's order.
  std::vector<std::array<double, 3>> nodePoints;
  /// Per piece, per node of a tetrahedron of order `degree` (VTK's order; HigherOrderTet.h): the
  /// cell's node there (>= 0), or -1 - k for the cell's new point k (pieces x pieceNodes).
  std::vector<int> pieceNode;
  /// The weights giving each new point (coordinates and values) from the cell's nodes
  /// (newPointCount x nodes).
  std::vector<double> newWeights;
  int newPointCount = 0;
  /// Each new point's parametric point (where an affine cell's map puts it exactly).
  std::vector<std::array<double, 3>> newPoints;
  /// The nodes at parametric (0, 0, 0), (1, 0, 0), (0, 1, 0) and (0, 0, 1): a cell whose nodes
  /// all lie where the affine map through these puts them is straight, and its new points are
  /// placed by that map (so its pieces are straight to rounding: the weights of high orders
  /// would move them by up to 4e-12 of the cell, enough to make them curved).
  int frame[4] = { 0, 0, 0, 0 };

  /// The cell's shape functions at a parametric point (nodes values).
  void basis(const double parametric[3], double* weights) const;

  /// A Monomials cell's space (r^a s^b t^c), and its inverse Vandermonde matrix (nodes x nodes):
  /// weights = this * monomials(x).
  std::vector<std::array<int, 3>> monomials;
  std::vector<double> inverseVandermonde;
};

/// Whether a VTK type is one the split reads (kCellTypes' CellSolver::SplitOrTensorForm: the
/// wedges; every other cell is kept as it is, for the scene to read or refuse).
bool isSplitType(int vtkType);

/// The parametric points (r, s, t) of the nodes of VTK's Lagrange and Bezier hexahedron of order
/// p, in VTK's order (vtkHigherOrderHexahedron; order 1 is VTK_HEXAHEDRON's, order 2
/// VTK_TRIQUADRATIC_HEXAHEDRON's).
std::vector<std::array<double, 3>> hexahedronNodePoints(int order);

/// The shape of a cell of a hexahedron or wedge type with `ids` node ids; 0 if it is read, else
/// the status saying why not (kMalformed: an id count that fits no order of the type (kCellTypes'
/// rule); kOrderTooHigh: above the table's highest order; kUnsupported: other types).
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
