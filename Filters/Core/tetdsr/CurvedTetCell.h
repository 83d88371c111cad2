// The curved (isoparametric) quadratic tetrahedron: VTK_QUADRATIC_TETRA with a mid-edge node off
// its edge. Its map from barycentric coordinates is quadratic, so a ray's crossing is the common
// root of three quadratic equations on the reference simplex, solved with Bernstein bounds and
// certified by Krawczyk's test (CurvedTet.h). The cell seam's steps (Cells.h); the cell's nodes
// and values are read from the mesh for each step (its record holds only its value range).
#pragma once

#include "tetdsr/Cells.h"
#include "tetdsr/QuadraticTetCell.h"

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
  /// iso-values sorted()[first, last). `certified` is false for a hit accepted at the
  /// subdivision limit without a Krawczyk certificate (a tangent or near-tangent root).
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

  /// The nodes its record is made from: none (the ray test reads them from the mesh).
  static constexpr int kRecordNodes = 0;
  static constexpr int kRecordCoefficients = 0;

  /// record: only the kind (the cell is solved from the mesh: its nodes and values are read
  /// for each ray test); `cell` keeps its id and value range.
  static void record(const glm::dvec3[kCellNodes], const double[kCellNodes], CellRecord& cell, double* = nullptr)
  {
    cell.kind = CellRecord::Kind::Curved;
  }
};

} // namespace tetdsr
