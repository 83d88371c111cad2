// The cell seam's contains and coordinates for a curved tetrahedron, whatever its order: the
// point's equations in the cell's barycentric coordinates and their solve (solveOnSimplex).
// Templates over the cell's geometry (CurvedGeometry for VTK_QUADRATIC_TETRA,
// IsoparametricGeometry<P> for the Lagrange and Bezier tetrahedra of order P, CurvedTet.h), used
// by CurvedTetCell and CurvedHigherOrderTetCell (whose rays are solved in the collapsed cube:
// HexahedronCell.h). And what every curved cell's ray test shares: the ray's two transverse
// directions, a constant field's iso-value, the step past a constant region's entry.
#pragma once

#include "tetdsr/common/Camera.h"
#include "tetdsr/cells/Cells.h"
#include "tetdsr/math/CurvedTet.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace tetdsr
{
namespace isoparametric
{

/// How far past a constant region's entry (local units: the cell's size is near 1) the search for
/// its exit starts, so that it does not find the entry root again: 1e-9 of the cell, far above
/// the face roots' rounding (~1e-15) and far below a pixel.
constexpr double kExitSearchStep = 1e-9;

/// Two unit vectors orthogonal to the unit vector d and to each other.
inline void orthonormalPair(const glm::dvec3& d, glm::dvec3& u, glm::dvec3& v)
{
  const glm::dvec3 helper = std::abs(d.x) < 0.6 ? glm::dvec3(1.0, 0.0, 0.0)
    : std::abs(d.y) < 0.6                       ? glm::dvec3(0.0, 1.0, 0.0)
                                                : glm::dvec3(0.0, 0.0, 1.0);
  u = glm::normalize(glm::cross(d, helper));
  v = glm::cross(d, u);
}

/// For a constant field with Bernstein bound [lo, hi] (field scaled by `scale`): the sorted()
/// position of an iso-value it equals; false if it equals none.
inline bool constantIsoIndex(
  const IsoValues& isoValues, double lo, double hi, double scale, std::size_t& index)
{
  const std::vector<double>& sorted = isoValues.sorted();
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), lo / scale);
  index = static_cast<std::size_t>(it - sorted.begin());
  return it != sorted.end() && *it <= hi / scale;
}

/// A straight cell's hit for a field constant to rounding (Bernstein bound [lo, hi], scaled by
/// `scale`) that equals an iso-value: the ray's stretch inside the cell, local depths [enter,
/// leave] (t_world = (tCentre + T) / s), with no gradient. False if it equals none.
inline bool constantStretch(const IsoValues& isoValues, double lo, double hi, double scale, double tCentre,
  double enter, double leave, double s, std::uint32_t cellId, SurfaceHit& hit)
{
  std::size_t index;
  if (!constantIsoIndex(isoValues, lo, hi, scale, index))
  {
    return false;
  }
  hit.isoIndex = index;
  hit.t = (tCentre + enter) / s;
  hit.regionEnd = (tCentre + leave) / s;
  hit.cellId = cellId;
  hit.gradient = glm::dvec3(0.0);
  return true;
}

/// The cell seam's contains: whether the world `point` lies in the cell (within
/// kBarycentricTolerance), and the barycentric coordinates of its preimage there.
template <class Geometry>
bool contains(const Geometry& geometry, const glm::dvec3& point, double L[4])
{
  typename Geometry::Form equations[3];
  geometry.pointEquations((point - geometry.origin) * geometry.scale, equations);
  SimplexRoot root;
  if (!solveOnSimplex(3, equations, nullptr, 0.0, 0.0, kBarycentricTolerance, root))
  {
    return false;
  }
  std::copy(root.L, root.L + 4, L);
  return true;
}

/// The cell seam's coordinates: inside the cell as contains finds them; outside, those of the
/// map's polynomial extension as far as Newton finds it from the guess of the straight tet on
/// the cell's `vertices` (its centre if they are coplanar).
template <class Geometry>
void coordinates(const Geometry& geometry, const glm::dvec3 vertices[4], const glm::dvec3& point,
  double L[4])
{
  if (contains(geometry, point, L))
  {
    return;
  }
  TetFrame frame;
  double guess[4] = { 0.25, 0.25, 0.25, 0.25 };
  if (TetFrame::fromVertices(vertices, frame))
  {
    frame.barycentricOfOffsets(point - vertices[0], point - vertices[1], guess);
  }
  std::copy(guess, guess + 4, L);
  if (inverseNewton(geometry, (point - geometry.origin) * geometry.scale, guess))
  {
    std::copy(guess, guess + 4, L);
  }
}

} // namespace isoparametric
} // namespace tetdsr
