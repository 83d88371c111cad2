// The curved (isoparametric) tetrahedra of order P = 3 and 4: VTK_LAGRANGE_TETRAHEDRON and
// VTK_BEZIER_TETRAHEDRON whose map is not affine. Map and field are polynomials of degree P in
// the barycentric coordinates L (HigherOrderTet.h), so a ray's crossing is the common root of
// three degree-P equations on the reference simplex, solved with Bernstein bounds and certified
// by Krawczyk's test like the quadratic curved cell's (CurvedTet.h, IsoparametricRay.h). The cell
// seam's steps (Cells.h); valueBound and interpolate are HigherOrderTetCell.h's (inherited: the
// field is the same polynomial in L); the nodes and values are read from the mesh for each step.
//
// `nodes` and `values` are in "Bezier layout" (HigherOrderTet.h): the Bernstein control points and
// field coefficients in VTK node order, latticeCount(P) of each, nodes[0..3] the vertices.
// L is barycentric in the reference tetrahedron, vertex k at L_k = 1.
#pragma once

#include "tetdsr/common/Camera.h"
#include "tetdsr/cells/Cells.h"
#include "tetdsr/cells/HexahedronCell.h"
#include "tetdsr/cells/HigherOrderTetCell.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>

namespace tetdsr
{

template <int P>
struct CurvedHigherOrderTetCell : HigherOrderTetCell<P>
{
  /// validate: the sign of the Jacobian determinant (degree 3 (P - 1)) over the whole cell.
  /// kTangled when it changes sign or vanishes (folded); else `flags` with kInverted set for a
  /// negative one, cleared for a positive one.
  static std::uint16_t validate(const glm::dvec3* nodes, std::uint16_t flags);

  /// extent: the box around the cell's control points (the cell lies in their convex hull);
  /// false if not finite.
  static bool extent(const glm::dvec3* nodes, glm::dvec3& lo, glm::dvec3& hi);

  /// intersect: the first crossing along the ray, with tMin <= t <= tLimit, of one of the
  /// iso-values sorted()[first, last). `certified` is false for a hit accepted at the
  /// subdivision limit without a Krawczyk certificate (a tangent or near-tangent root).
  static bool intersect(const glm::dvec3* nodes, const double* values, const IsoValues& isoValues,
    std::size_t first, std::size_t last, const Ray& ray, double tMin, double tLimit,
    SurfaceHit& hit, bool& certified);

  /// contains: whether `point` lies in the cell (within kBarycentricTolerance), and the
  /// barycentric coordinates of its preimage there.
  static bool contains(const glm::dvec3* nodes, const glm::dvec3& point, double L[4]);

  /// coordinates: the barycentric coordinates of the preimage of `point`: inside the cell as
  /// contains finds them; outside, those of the map's polynomial extension as far as Newton finds
  /// it from the straight tet's guess.
  static void coordinates(const glm::dvec3* nodes, const glm::dvec3& point, double L[4]);

  /// gradient: the exact gradient (world coordinates) of the field with these coefficients at
  /// barycentric L.
  static glm::dvec3 gradient(const glm::dvec3* nodes, const double* values, const double L[4]);

  /// The nodes its record is made from: all; the numbers it keeps beside it: the collapsed
  /// cube's forms (HexahedronCell<P, true>'s).
  static constexpr int kRecordNodes = latticeCount(P);
  static constexpr int kRecordCoefficients = HexahedronCell<P, true>::kRecordCoefficients;

  /// record: the map and field as the collapsed cube's tensor forms of degree P, recorded as a
  /// curved hexahedron's (the ray test is HexahedronCell<P, true>'s).
  static void record(const glm::dvec3* nodes, const double* values, CellRecord& cell, double* coefficients)
  {
    glm::dvec3 tensorNodes[tensor::count(P)];
    double tensorValues[tensor::count(P)];
    const double fieldScale = collapsedTetrahedron<P>(
      [](const double* items, const double L[4]) { return HigherOrderTetCell<P>::interpolate(items, L); },
      nodes, values, latticeCount(P), tensorNodes, tensorValues);
    HexahedronCell<P, true>::record(tensorNodes, tensorValues, cell, coefficients);
    cell.scale *= fieldScale;
  }
};

extern template struct CurvedHigherOrderTetCell<3>;
extern template struct CurvedHigherOrderTetCell<4>;

} // namespace tetdsr
