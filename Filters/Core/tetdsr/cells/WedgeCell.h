// The straight wedge kinds (WedgeCell<P>, orders 1 to 4 per axis): a wedge whose map is affine,
// intersected as itself, triangle x segment.
//
// Its field is a polynomial of P_P(r, s) x P_P(t) (VTK's wedges of every kind lie in it), kept as
// Bernstein coefficients on the triangle times the segment: T(r, s, t) = sum_k T_k(r, s) B_k^P(t).
// Along a ray the map's inverse makes (r, s, t) linear in the ray's parameter, so after clipping
// to the wedge (five planes) each T_k restricted to the chord is a polynomial of degree P, whose
// Bernstein coefficients are its blossom at the chord's ends (de Casteljau on the triangle with
// one end's barycentric coordinates, then the other's), and B_k^P(t) one of degree P
// (tensor::segmentMatrix): the field along the chord is their sum of products, of degree 2P, and
// its first root is certified as for every other straight cell (firstBernsteinRoot).
//
// Every other step is the hexahedron's (HexahedronCell<P, false> on the wedge's collapsed tensor
// form: validation, including the straightness check for a wedge's lattice, point location,
// interpolation, gradients). A curved wedge is a curved hexahedron kind (the collapsed cube's box
// solve).
#pragma once

#include "tetdsr/cells/HexahedronCell.h"

namespace tetdsr
{

template <int P>
struct WedgeCell : HexahedronCell<P, false>
{
  using Base = HexahedronCell<P, false>;
  /// Coefficients of a triangle's Bernstein form of degree P.
  static constexpr int kTriangle = (P + 1) * (P + 2) / 2;
  /// The record keeps the hexahedron's header (origin, scale, the affine frame of (r, s, t) and
  /// its inverse) and the scaled field's triangle x segment coefficients (triangle index
  /// triangleIndex(a, b) + kTriangle k).
  static constexpr int kRecordCoefficients = Base::kHeader + kTriangle * (P + 1);

  /// The index of the triangle coefficient of r^a s^b (1 - r - s)^(P - a - b).
  static constexpr int triangleIndex(int a, int b) { return b * (P + 1) - b * (b - 1) / 2 + a; }

  static void record(const glm::dvec3* nodes, const double* values, CellRecord& cell, double* coefficients);

  static bool intersect(const CellRecord& cell, const Ray& ray, const IsoValues& isoValues,
    std::size_t first, std::size_t last, double tMin, double tLimit, SurfaceHit& hit, bool& certified);
};

extern template struct WedgeCell<1>;
extern template struct WedgeCell<2>;
extern template struct WedgeCell<3>;
extern template struct WedgeCell<4>;

} // namespace tetdsr
