// The shapes of VTK's hexahedra and wedges: each type's node points (VTK's parametric
// coordinates and order) and its shape functions, from which HexahedronCell.h's node tables make
// the tensor forms every hexahedron and wedge is solved in. (The file's name is from when straight
// wedges were split into tetrahedra of their polynomials' degree; none is any more: WedgeCell.h.)
//
// The cell's shape functions come from its nodes (VTK order, checked against VTK's own cells by
// Testing/Cxx/TestSplitCellsNodeOrder) and its polynomial space: the nodal basis (the inverse of
// the space's Vandermonde matrix at the nodes), or for a Bezier cell its Bernstein basis.
#pragma once

#include "tetdsr/cells/Cells.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tetdsr
{


/// One kind of hexahedron or wedge (a VTK type and node count): its nodes and shape functions.
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
  const char* name = "";  ///< as messages and tests name it ("VTK_HEXAHEDRON", ...)
  bool wedge = false;     ///< the unit triangle times [0, 1]; else the unit cube
  Basis basisKind = Basis::Monomials;
  int order = 1;          ///< p of the Lagrange and Bezier bases
  int nodes = 0;          ///< the cell's node count
  /// The parametric coordinates (r, s, t) of the cell's nodes, VTK's order.
  std::vector<std::array<double, 3>> nodePoints;

  /// The cell's shape functions at a parametric point (nodes values).
  void basis(const double parametric[3], double* weights) const;

  /// A Monomials cell's space (r^a s^b t^c), and its inverse Vandermonde matrix (nodes x nodes):
  /// weights = this * monomials(x).
  std::vector<std::array<int, 3>> monomials;
  std::vector<double> inverseVandermonde;
};

/// The parametric points (r, s, t) of the nodes of VTK's Lagrange and Bezier hexahedron of order
/// p, in VTK's order (vtkHigherOrderHexahedron; order 1 is VTK_HEXAHEDRON's, order 2
/// VTK_TRIQUADRATIC_HEXAHEDRON's).
std::vector<std::array<double, 3>> hexahedronNodePoints(int order);

/// The shape of a cell of a hexahedron or wedge type with `ids` node ids; 0 if it is read, else
/// the status saying why not (kMalformed: an id count that fits no order of the type (kCellTypes'
/// rule); kOrderTooHigh: above the table's highest order; kUnsupported: other types).
std::uint16_t splitShapeOf(int vtkType, long long ids, const SplitShape*& shape);

} // namespace tetdsr
