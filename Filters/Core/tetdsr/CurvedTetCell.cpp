#include "tetdsr/CurvedTetCell.h"

#include "tetdsr/CurvedTet.h"
#include "tetdsr/QuadraticTet.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
/// The curved cell's geometry in its local frame (origin its vertex 0, unit near its size).
CurvedGeometry localGeometry(const glm::dvec3 nodes[kCellNodes])
{
  double size = 0.0;
  for (const auto& edge : kEdgeVertices)
  {
    size = std::max(size, glm::length(nodes[edge[0]] - nodes[edge[1]]));
  }
  return CurvedGeometry::fromNodes(nodes, scaleFor(size));
}

/// For a constant field with Bernstein bound [lo, hi] (field scaled by `scale`): the sorted()
/// position of an iso-value it equals; false if it equals none.
bool constantIsoIndex(const IsoValues& isoValues, double lo, double hi, double scale, std::size_t& index)
{
  const std::vector<double>& sorted = isoValues.sorted();
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), lo / scale);
  index = static_cast<std::size_t>(it - sorted.begin());
  return it != sorted.end() && *it <= hi / scale;
}

/// The field's form scaled by a power of two (returned in `scale`) to a largest magnitude near 1,
/// and its Bernstein bound [lo, hi] (scaled).
QuadraticForm scaledFieldForm(const double nodeValues[kCellNodes], double& scale, double& lo, double& hi)
{
  scale = unitScale(nodeValues);
  double values[kCellNodes];
  for (int n = 0; n < kCellNodes; ++n)
  {
    values[n] = nodeValues[n] * scale;
  }
  const BernsteinForm bernstein = BernsteinForm::fromNodeValues(values);
  bernstein.range(lo, hi);
  QuadraticForm form;
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      form.b[i][j] = bernstein.b[i][j];
    }
  }
  return form;
}

/// Two unit vectors orthogonal to the unit vector d and to each other.
void orthonormalPair(const glm::dvec3& d, glm::dvec3& u, glm::dvec3& v)
{
  const glm::dvec3 helper = std::abs(d.x) < 0.6 ? glm::dvec3(1.0, 0.0, 0.0)
    : std::abs(d.y) < 0.6                       ? glm::dvec3(0.0, 1.0, 0.0)
                                                : glm::dvec3(0.0, 0.0, 1.0);
  u = glm::normalize(glm::cross(d, helper));
  v = glm::cross(d, u);
}

/// For a field constant over the cell (to rounding) and equal to an iso-value: the crossing is
/// the stretch of the ray inside the cell, from where it enters (a root on a face, or the start
/// if that is inside the cell) to where it next leaves. `equations` are the ray's two transverse
/// equations, `depth` its depth form, [lo, hi] the local depth interval; t_world = (tCentre + T) / s.
bool constantCrossing(const glm::dvec3 nodes[kCellNodes], const IsoValues& isoValues,
  double boundLo, double boundHi, double scale, const QuadraticForm equations[2],
  const QuadraticForm& depth, const Ray& ray, double tMin, double lo, double hi, double tCentre,
  double s, SurfaceHit& hit)
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
      const QuadraticForm faceEquations[2] = { equations[0].face(face), equations[1].face(face) };
      const QuadraticForm faceDepth = depth.face(face);
      SimplexRoot faceRoot;
      if (solveOnSimplex(2, faceEquations, &faceDepth, from, std::min(nearest, to),
            kBarycentricTolerance, faceRoot))
      {
        nearest = std::min(nearest, faceRoot.value);
      }
    }
    return nearest;
  };
  // The start is inside when it is finite and the cell contains it; 1e-9 (local units, the
  // cell's size near 1) steps past the entry root so that the exit search does not find it.
  double startL[4];
  const double enter = std::isfinite(lo) && CurvedTetCell::contains(nodes, ray.origin + tMin * ray.direction, startL)
    ? lo
    : firstFaceCrossing(lo, hi);
  if (!std::isfinite(enter))
  {
    return false;
  }
  const double leave = firstFaceCrossing(enter + 1e-9, hi);
  hit.isoIndex = index;
  hit.t = (tCentre + enter) / s;
  hit.regionEnd = std::isfinite(leave) ? (tCentre + leave) / s : hit.t;
  hit.gradient = glm::dvec3(0.0);
  return true;
}
} // namespace

std::uint16_t CurvedTetCell::validate(const glm::dvec3 nodes[kCellNodes], std::uint16_t flags)
{
  const JacobianSign sign =
    jacobianSign(CurvedGeometry::fromNodes(nodes, scaleFor(longestEdge(nodes))));
  if (sign == JacobianSign::Changes)
  {
    return kTangled;
  }
  return static_cast<std::uint16_t>(
    (flags & ~kInverted) | (sign == JacobianSign::Negative ? kInverted : 0));
}

bool CurvedTetCell::extent(const glm::dvec3 nodes[kCellNodes], glm::dvec3& lo, glm::dvec3& hi)
{
  CurvedGeometry::fromNodes(nodes, scaleFor(longestEdge(nodes))).box(lo, hi);
  return isFinite(lo) && isFinite(hi);
}

bool CurvedTetCell::contains(const glm::dvec3 nodes[kCellNodes], const glm::dvec3& point, double L[4])
{
  const CurvedGeometry geometry = localGeometry(nodes);
  QuadraticForm equations[3];
  geometry.pointEquations((point - geometry.origin) * geometry.scale, equations);
  SimplexRoot root;
  if (!solveOnSimplex(3, equations, nullptr, 0.0, 0.0, kBarycentricTolerance, root))
  {
    return false;
  }
  std::copy(root.L, root.L + 4, L);
  return true;
}

void CurvedTetCell::coordinates(const glm::dvec3 nodes[kCellNodes], const glm::dvec3& point, double L[4])
{
  if (contains(nodes, point, L))
  {
    return;
  }
  // Outside: the extension of the map, from the straight tet's guess.
  TetFrame frame;
  TetFrame::fromVertices(nodes, frame);
  frame.barycentricOfOffsets(point - nodes[0], point - nodes[1], L);
  const CurvedGeometry geometry = localGeometry(nodes);
  double guess[4] = { L[0], L[1], L[2], L[3] };
  if (inverseNewton(geometry, (point - geometry.origin) * geometry.scale, guess))
  {
    std::copy(guess, guess + 4, L);
  }
}

glm::dvec3 CurvedTetCell::gradient(
  const glm::dvec3 nodes[kCellNodes], const double values[kCellNodes], const double L[4])
{
  const CurvedGeometry geometry = localGeometry(nodes);
  const BernsteinForm bernstein = BernsteinForm::fromNodeValues(values);
  QuadraticForm field{};
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      field.b[i][j] = bernstein.b[i][j];
    }
  }
  // grad_x f = s grad_X f (X the local coordinates).
  return curvedGradient(geometry, field, L) * geometry.scale;
}

bool CurvedTetCell::intersect(const glm::dvec3 nodes[kCellNodes], const double values[kCellNodes],
  const IsoValues& isoValues, std::size_t first, std::size_t last, const Ray& ray, double tMin,
  double tLimit, SurfaceHit& hit, bool& certified)
{
  certified = true;
  const std::vector<double>& sorted = isoValues.sorted();
  const CurvedGeometry geometry = localGeometry(nodes);
  const double s = geometry.scale;
  // The ray in local units, re-origined at its point nearest the cell's control points' mean:
  // t_world = (tCentre + T) / s, with T the local depth form below.
  const glm::dvec3 origin = (ray.origin - geometry.origin) * s;
  glm::dvec3 centroid(0.0);
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      centroid += geometry.control[i][j] / 16.0;
    }
  }
  const glm::dvec3& d = ray.direction;
  const double tCentre = glm::dot(centroid - origin, d);
  const glm::dvec3 o = origin + tCentre * d;
  glm::dvec3 u, v;
  orthonormalPair(d, u, v);
  QuadraticForm equations[3];
  equations[0] = geometry.component(u, glm::dot(u, o));
  equations[1] = geometry.component(v, glm::dot(v, o));
  const QuadraticForm depth = geometry.component(d, glm::dot(d, o));
  const double lo = tMin * s - tCentre;
  const double hi = tLimit * s - tCentre;

  double scale, boundLo, boundHi;
  const QuadraticForm field = scaledFieldForm(values, scale, boundLo, boundHi);
  SimplexRoot root;
  if (constantToRounding(boundLo, boundHi))
  {
    return constantCrossing(nodes, isoValues, boundLo, boundHi, scale, equations, depth, ray,
      tMin, lo, hi, tCentre, s, hit);
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
  if (!solveOnSimplex(3, equations, &depth, lo, hi, kBarycentricTolerance, root, SolveLimits(),
        nullptr, levels))
  {
    return false;
  }
  hit.isoIndex = first + static_cast<std::size_t>(root.level);
  certified = root.certified;
  hit.t = (tCentre + root.value) / s;
  hit.regionEnd = hit.t;
  // grad_x f = s grad_X f; unscaled exactly (a power of two) unless that overflows.
  const glm::dvec3 gradient = curvedGradient(geometry, field, root.L) * s;
  hit.gradient = isFinite(gradient / scale) ? gradient / scale : gradient;
  return true;
}

} // namespace tetdsr
