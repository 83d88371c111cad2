// The cell seam's intersect, contains and coordinates for an isoparametric cell, whatever its
// order: the ray's (or the point's) equations in the cell's reference coordinates, their solve
// (solveOnSimplex) and the hit made of the root. Templates over the cell's geometry
// (CurvedGeometry for VTK_QUADRATIC_TETRA, IsoparametricGeometry<P> for the Lagrange and Bezier
// tetrahedra of order P, CurvedTet.h), used by CurvedTetCell and CurvedHigherOrderTetCell.
//
// In local coordinates X (the geometry's frame) a ray o + T d (T the local depth) meets the
// isosurface f = c where
//   u . (X(L) - o) = 0,  v . (X(L) - o) = 0,  f(L) - c = 0     (u, v orthonormal, both _|_ d),
// and T = d . (X(L) - o): forms of the map's degree in L with coefficients u . P_a - u . o for the
// control points P_a (the B_a sum to 1).
#pragma once

#include "tetdsr/Camera.h"
#include "tetdsr/Cells.h"
#include "tetdsr/CurvedTet.h"

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

/// For a field constant over the cell (to rounding) and equal to an iso-value: the crossing is
/// the stretch of the ray inside the cell, from where it enters (a root on a face, or the start
/// if that is inside the cell: `startInside`) to where it next leaves. `equations` are the ray's
/// two transverse equations, `depth` its depth form, [lo, hi] the local depth interval;
/// t_world = (tCentre + T) / s.
template <class Form>
bool constantCrossing(const IsoValues& isoValues, double boundLo, double boundHi, double scale,
  const Form equations[2], const Form& depth, bool startInside, double lo, double hi,
  double tCentre, double s, SurfaceHit& hit)
{
  std::size_t index;
  if (!constantIsoIndex(isoValues, boundLo, boundHi, scale, index))
  {
    return false;
  }
  // The nearest crossing of the cell's boundary with local depth in [from, to] (+inf if none).
  auto firstFaceCrossing = [&](double from, double to) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int face = 0; face < 4; ++face)
    {
      const Form faceEquations[2] = { equations[0].face(face), equations[1].face(face) };
      const Form faceDepth = depth.face(face);
      SimplexRoot faceRoot;
      if (solveOnSimplex(2, faceEquations, &faceDepth, from, std::min(nearest, to),
            kBarycentricTolerance, faceRoot))
      {
        nearest = std::min(nearest, faceRoot.value);
      }
    }
    return nearest;
  };
  const double enter = std::isfinite(lo) && startInside ? lo : firstFaceCrossing(lo, hi);
  if (!std::isfinite(enter))
  {
    return false;
  }
  const double leave = firstFaceCrossing(enter + kExitSearchStep, hi);
  hit.isoIndex = index;
  hit.t = (tCentre + enter) / s;
  hit.regionEnd = std::isfinite(leave) ? (tCentre + leave) / s : hit.t;
  hit.gradient = glm::dvec3(0.0);
  return true;
}

/// The cell seam's intersect for an isoparametric cell: `field` its field's form scaled by the
/// power of two `scale` to a largest coefficient near 1, [boundLo, boundHi] that form's
/// Bernstein bound; `contains(point)` whether the cell contains a world point (asked only of a
/// constant field's start). `pieces`, if given, receives the sub-simplices the solve visited.
template <class Geometry, class Contains>
bool intersect(const Geometry& geometry, const typename Geometry::Form& field, double scale,
  double boundLo, double boundHi, Contains&& contains, const IsoValues& isoValues,
  std::size_t first, std::size_t last, const Ray& ray, double tMin, double tLimit, SurfaceHit& hit,
  bool& certified, int* pieces = nullptr)
{
  using Form = typename Geometry::Form;
  certified = true;
  const std::vector<double>& sorted = isoValues.sorted();
  const double s = geometry.scale;
  // The ray in local units, re-origined at its point nearest the cell's control points' mean:
  // t_world = (tCentre + T) / s, with T the local depth form below.
  const glm::dvec3 origin = (ray.origin - geometry.origin) * s;
  const glm::dvec3 centroid = geometry.centroid();
  const glm::dvec3& d = ray.direction;
  const double tCentre = glm::dot(centroid - origin, d);
  const glm::dvec3 o = origin + tCentre * d;
  glm::dvec3 u, v;
  orthonormalPair(d, u, v);
  Form equations[3];
  equations[0] = geometry.component(u, glm::dot(u, o));
  equations[1] = geometry.component(v, glm::dot(v, o));
  const Form depth = geometry.component(d, glm::dot(d, o));
  const double lo = tMin * s - tCentre;
  const double hi = tLimit * s - tCentre;
  if (pieces)
  {
    *pieces = 0;
  }
  if (constantToRounding(boundLo, boundHi, Form::kDegree))
  {
    return constantCrossing(isoValues, boundLo, boundHi, scale, equations, depth,
      std::isfinite(lo) && contains(ray.origin + tMin * ray.direction), lo, hi, tCentre, s, hit);
  }
  // Every iso-value the cell's bound admits, in one subdivision (Levels); one, directly.
  Levels levels;
  if (last - first == 1)
  {
    equations[2] = field.minus(sorted[first] * scale);
  }
  else
  {
    equations[2] = field;
    levels.values = sorted.data() + first;
    levels.count = static_cast<int>(std::min<std::size_t>(last - first, 1u << 30));
    levels.scale = scale;
  }
  SimplexRoot root;
  if (!solveOnSimplex(3, equations, &depth, lo, hi, kBarycentricTolerance, root, SolveLimits(),
        pieces, levels))
  {
    return false;
  }
  hit.isoIndex = first + static_cast<std::size_t>(root.level);
  certified = root.certified;
  hit.t = (tCentre + root.value) / s;
  hit.regionEnd = hit.t;
  // grad_x f = s grad_X f; unscaled exactly (a power of two) unless that overflows or underflows.
  const glm::dvec3 gradient = curvedGradient(geometry, field, root.L) * s;
  hit.gradient = unscaledGradient(gradient, scale);
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
