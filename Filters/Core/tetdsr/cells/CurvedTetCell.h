// The curved (isoparametric) quadratic tetrahedron: VTK_QUADRATIC_TETRA with a mid-edge node off
// its edge. Its map from barycentric coordinates is quadratic, so a ray's crossing is the common
// root of three quadratic equations on the reference cell. Its record holds the map and field as
// the tensor form of the cube collapsed onto it (collapsedTetrahedron, HexahedronCell.h), where
// the box solve (Bezier clipping, Krawczyk's test) finds and certifies it; validation, point
// location and the gradient work on the simplex (CurvedTet.h). The cell seam's steps (Cells.h).
#pragma once

#include "tetdsr/cells/Cells.h"
#include "tetdsr/cells/HexahedronCell.h"
#include "tetdsr/cells/QuadraticTetCell.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>

namespace tetdsr
{

struct CurvedTetCell
{
  /// validate, after QuadraticTetCell's found the cell curved: the sign of its Jacobian
  /// determinant over the whole cell. kTangled when it changes sign or vanishes (folded);
  /// else `flags` with kInverted set for a negative one.
  static std::uint16_t validate(const glm::dvec3 nodes[kCellNodes], std::uint16_t flags);

  /// extent: the box around the cell's Bernstein control points (the cell lies in their convex
  /// hull); false if not finite.
  static bool extent(const glm::dvec3 nodes[kCellNodes], glm::dvec3& lo, glm::dvec3& hi);

  /// intersect: the first crossing along the ray, with tMin <= t <= tLimit, of one of the
  /// iso-values sorted()[first, last): the cell recorded, then its record's ray test (the
  /// scene keeps records; this is the same test for a cell taken as it is). `certified` is false
  /// for a hit accepted at the subdivision limit without a Krawczyk certificate.
  static bool intersect(const glm::dvec3 nodes[kCellNodes], const double values[kCellNodes],
    const IsoValues& isoValues, std::size_t first, std::size_t last, const Ray& ray, double tMin,
    double tLimit, SurfaceHit& hit, bool& certified);

  /// contains: whether `point` lies in the cell (within kBarycentricTolerance), and the
  /// barycentric coordinates of its preimage there.
  static bool contains(const glm::dvec3 nodes[kCellNodes], const glm::dvec3& point, double L[4]);

  /// coordinates: the barycentric coordinates of the preimage of `point`: inside the cell as
  /// contains finds them; outside, those of the shape functions' extension as far as Newton
  /// finds it from the straight tet's guess.
  static void coordinates(const glm::dvec3 nodes[kCellNodes], const glm::dvec3& point, double L[4]);

  /// gradient: the exact gradient (world coordinates) of the field with these nodal values at
  /// barycentric L.
  static glm::dvec3 gradient(
    const glm::dvec3 nodes[kCellNodes], const double values[kCellNodes], const double L[4]);

  /// valueBound and interpolate: QuadraticTetCell's (the field is the same quadratic in L).
  static void valueBound(
    const double values[kCellNodes], const TransverseTest& transverse, double& lo, double& hi)
  {
    QuadraticTetCell::valueBound(values, transverse, lo, hi);
  }
  static double interpolate(const double values[kCellNodes], const double L[4])
  {
    return QuadraticTetCell::interpolate(values, L);
  }

  /// The nodes its record is made from: all ten; the numbers it keeps beside it: the collapsed
  /// cube's forms (HexahedronCell<2, true>'s).
  static constexpr int kRecordNodes = kCellNodes;
  static constexpr int kRecordCoefficients = HexahedronCell<2, true>::kRecordCoefficients;

  /// record: the map and field as the collapsed cube's tensor forms of degree 2, recorded as a
  /// curved hexahedron's (the ray test is HexahedronCell<2, true>'s).
  static void record(const glm::dvec3 nodes[kCellNodes], const double values[kCellNodes], CellRecord& cell,
    double* coefficients)
  {
    glm::dvec3 tensorNodes[tensor::count(2)];
    double tensorValues[tensor::count(2)];
    const double fieldScale = collapsedTetrahedron<2>(
      [](const double* items, const double L[4]) { return QuadraticTetCell::interpolate(items, L); }, nodes,
      values, kCellNodes, tensorNodes, tensorValues);
    HexahedronCell<2, true>::record(tensorNodes, tensorValues, cell, coefficients);
    cell.scale *= fieldScale;
  }
};

} // namespace tetdsr
