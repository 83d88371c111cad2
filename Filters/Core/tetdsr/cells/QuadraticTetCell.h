// The straight quadratic tetrahedron (VTK_QUADRATIC_TETRA whose mid-edge nodes lie on their
// edges' midpoints): an affine map, so along a ray the barycentric coordinates are affine and the
// field is exactly a quadratic in t (QuadraticTet.h). The cell seam's steps (Cells.h).
#pragma once

#include "tetdsr/cells/Cells.h"
#include "tetdsr/math/QuadraticTet.h"
#include "tetdsr/math/Roots.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cstdint>

namespace tetdsr
{

struct QuadraticTetCell
{
  /// The range of cell sizes (longest edge) whose barycentric frames stay within double
  /// precision: the volume (size^3) and its inverse times size^2 stay far from under- and
  /// overflow. Cells outside it are skipped and counted (outOfScaleCells).
  static constexpr double kMinCellSize = 1e-100;
  static constexpr double kMaxCellSize = 1e100;
  /// Below this fraction of max-edge^3, 6*volume is treated as zero: the barycentric frame would
  /// amplify rounding by more than 1e13. Slivers and needles of aspect ratio 1e4 stay far above.
  static constexpr double kDegenerateVolumeRatio = 1e-13;
  /// A mid-edge node farther than this many times the coordinates' rounding (pointRounding),
  /// relative to the cell's longest edge, from its edge's midpoint makes the cell curved
  /// (isoparametric). Treating a cell straight moves its surface by about the offset: below
  /// this, by less than 1e-13 of the cell for double coordinates.
  static constexpr double kCurvedRoundings = 64.0;
  /// The nodes its record is made from: the vertices (the map is affine).
  static constexpr int kRecordNodes = 4;
  /// The coefficients its record keeps beside it: none (they fit in the record).
  static constexpr int kRecordCoefficients = 0;

  /// The checks of a straight cell's 4 vertices: size, volume and orientation (kValid, with
  /// kInverted for a negative volume; or why not valid). Sets `curvedTolerance`: how far a node
  /// may lie from where the affine map puts it before the cell is curved (kCurvedRoundings
  /// roundings of the coordinates).
  static std::uint16_t validateVertices(
    const glm::dvec3 vertices[4], double pointRounding, double& curvedTolerance)
  {
    const double maxEdge = longestEdge(vertices);
    if (!(maxEdge >= kMinCellSize && maxEdge <= kMaxCellSize)) // also an overflowed (Inf) length
    {
      return kOutOfScale;
    }
    // 6 x the signed volume, as TetFrame::fromVertices computes it (its frame is not needed).
    const glm::dvec3 e1 = vertices[1] - vertices[0];
    const double volume6 =
      glm::dot(e1, glm::cross(vertices[2] - vertices[0], vertices[3] - vertices[0]));
    if (!std::isfinite(volume6) ||
      std::abs(volume6) <= kDegenerateVolumeRatio * maxEdge * maxEdge * maxEdge)
    {
      return kDegenerate;
    }
    // Rounding is relative to the coordinates' magnitude (a float coordinate near 2.5e6 rounds
    // by 0.25), so it is measured against the larger of the cell's size and its distance from 0.
    double reach = maxEdge;
    for (int k = 0; k < 4; ++k)
    {
      for (int a = 0; a < 3; ++a)
      {
        reach = std::max(reach, std::abs(vertices[k][a]));
      }
    }
    curvedTolerance = kCurvedRoundings * pointRounding * reach;
    return static_cast<std::uint16_t>(volume6 < 0.0 ? kValid | kInverted : kValid);
  }

  /// Whether `node` lies farther than `tolerance` from `expected` (where the affine map puts it).
  static bool offItsPlace(const glm::dvec3& node, const glm::dvec3& expected, double tolerance)
  {
    const glm::dvec3 offset = node - expected;
    // Components within half the tolerance put the length within it (sqrt(3) / 2 < 1): the
    // length is only needed for the rare others.
    const double largest = std::max({ std::abs(offset.x), std::abs(offset.y), std::abs(offset.z) });
    return largest > 0.5 * tolerance && glm::length(offset) > tolerance;
  }

  /// validate: size, volume and orientation of the cell's 10 finite nodes, and whether a
  /// mid-edge node is off its edge (kCurved: the cell is then CurvedTetCell's). `pointRounding`
  /// is the coordinates' relative rounding (2^-52 for double, 2^-23 for float).
  static std::uint16_t validate(const glm::dvec3 nodes[kCellNodes], double pointRounding)
  {
    double curvedTolerance = 0.0;
    const std::uint16_t flags = validateVertices(nodes, pointRounding, curvedTolerance);
    if (!(flags & kValid))
    {
      return flags;
    }
    for (int e = 0; e < 6; ++e)
    {
      if (offItsPlace(nodes[4 + e], 0.5 * (nodes[kEdgeVertices[e][0]] + nodes[kEdgeVertices[e][1]]),
            curvedTolerance))
      {
        return flags | kCurved;
      }
    }
    return static_cast<std::uint16_t>(flags);
  }

  /// valueBound: the transverse test's range of the field over the cell.
  static void valueBound(
    const double values[kCellNodes], const TransverseTest& transverse, double& lo, double& hi)
  {
    transverse.range(values, lo, hi);
  }

  /// extent: the vertices' box (a straight cell is their convex hull); false if not finite.
  static bool extent(const glm::dvec3 nodes[kCellNodes], glm::dvec3& lo, glm::dvec3& hi)
  {
    lo = glm::min(glm::min(nodes[0], nodes[1]), glm::min(nodes[2], nodes[3]));
    hi = glm::max(glm::max(nodes[0], nodes[1]), glm::max(nodes[2], nodes[3]));
    return isFinite(lo) && isFinite(hi);
  }

  /// A Bezier cell's control points (or coefficients) of order 2 made the nodes (values) of
  /// the quadratic tetrahedron, in place: a mid-edge node is the map's value at its edge's
  /// midpoint, (b_aa + b_bb) / 4 + b_ab / 2.
  template <typename T>
  static void fromBezier(T nodes[kCellNodes])
  {
    for (int e = 0; e < 6; ++e)
    {
      nodes[4 + e] = 0.25 * (nodes[kEdgeVertices[e][0]] + nodes[kEdgeVertices[e][1]]) + 0.5 * nodes[4 + e];
    }
  }

  /// The barycentric map of a valid cell's vertices into its record.
  static void recordFrame(const glm::dvec3 vertices[4], CellRecord& cell)
  {
    TetFrame frame;
    if (!TetFrame::fromVertices(vertices, frame))
    {
      return; // (not for a valid cell)
    }
    cell.vertex0 = vertices[0];
    cell.vertex1 = vertices[1];
    cell.centroidOffset =
      0.25 * ((vertices[1] - vertices[0]) + (vertices[2] - vertices[0]) + (vertices[3] - vertices[0]));
    for (int k = 0; k < 3; ++k)
    {
      cell.gradient[k] = frame.gradient[k + 1];
    }
  }

  /// record: the barycentric map and the Bernstein coefficients of the field (scaled by a power
  /// of two), for a valid cell; `cell` keeps its id and value range. (No coefficients kept
  /// beside it: kRecordCoefficients.)
  static void record(const glm::dvec3 vertices[kCellNodes], const double nodeValues[kCellNodes],
    CellRecord& cell, double* = nullptr)
  {
    recordFrame(vertices, cell);
    // Scale the field by a power of two (exact) so that its largest nodal magnitude is about 1:
    // the products in the quadratic's coefficients and its discriminant (field^2) then neither
    // overflow nor underflow, whatever the field's scale within double range.
    cell.scale = unitScale(nodeValues);
    double values[kCellNodes];
    for (int n = 0; n < kCellNodes; ++n)
    {
      values[n] = nodeValues[n] * cell.scale;
    }
    const BernsteinForm form = BernsteinForm::fromNodeValues(values);
    for (int i = 0; i < 4; ++i)
    {
      cell.form[i] = form.b[i][i];
    }
    for (int e = 0; e < 6; ++e)
    {
      cell.form[4 + e] = form.b[kEdgeVertices[e][0]][kEdgeVertices[e][1]];
    }
    // A field constant over the cell (to rounding): the Bernstein bound (a true bound whatever
    // the transverse test) is within rounding of one value.
    double boundLo, boundHi;
    form.range(boundLo, boundHi);
    cell.kind = constantToRounding(boundLo, boundHi) ? CellRecord::Kind::Constant
                                                     : CellRecord::Kind::Quadratic;
  }

  /// intersect: the first crossing along the ray, with tMin <= t <= tLimit, of one of the
  /// iso-values sorted()[first, last) (those within the cell's range). Inline: the innermost
  /// test of every ray.
  static bool intersect(const CellRecord& cell, const Ray& ray, const IsoValues& isoValues,
    std::size_t first, std::size_t last, double tMin, double tLimit, SurfaceHit& hit);

  /// contains / coordinates: the barycentric coordinates of `point` (exact outside the cell too:
  /// the map is affine); true if the point lies in the cell, within kBarycentricTolerance.
  static bool contains(const glm::dvec3 vertices[kCellNodes], const glm::dvec3& point, double L[4])
  {
    TetFrame frame;
    TetFrame::fromVertices(vertices, frame);
    frame.barycentricOfOffsets(point - vertices[0], point - vertices[1], L);
    return L[0] >= -kBarycentricTolerance && L[1] >= -kBarycentricTolerance &&
      L[2] >= -kBarycentricTolerance && L[3] >= -kBarycentricTolerance;
  }

  static void coordinates(const glm::dvec3 nodes[kCellNodes], const glm::dvec3& point, double L[4])
  {
    contains(nodes, point, L);
  }

  /// interpolate: nodal values at barycentric coordinates with the quadratic shape functions (the
  /// paper's eq. 2, as L^T B L). Scaled (exactly) so that the Bernstein coefficients cannot
  /// overflow for values near the largest double; the result overflows only if the value does.
  static double interpolate(const double nodeValues[kCellNodes], const double L[4])
  {
    const double scale = unitScale(nodeValues);
    double values[kCellNodes];
    for (int n = 0; n < kCellNodes; ++n)
    {
      values[n] = nodeValues[n] * scale;
    }
    return BernsteinForm::fromNodeValues(values).bilinear(L, L) / scale;
  }

  /// gradient: the exact gradient of the field with these nodal values at barycentric L.
  static glm::dvec3 gradient(
    const glm::dvec3 vertices[kCellNodes], const double values[kCellNodes], const double L[4])
  {
    TetFrame frame;
    TetFrame::fromVertices(vertices, frame);
    return fieldGradient(BernsteinForm::fromNodeValues(values), frame, L);
  }
};

namespace quadratic_tet_detail
{
/// The ray re-origined at its point nearest the cell centroid, in the cell's barycentric
/// coordinates: L(s) = L + s dL, t = tCentre + s. Then the barycentric coordinates and the
/// quadratic's coefficients are of the cell's own scale, not of the camera distance. The point is
/// formed as offsets from the cell's vertices (origin - vertex first, both of the scene's
/// magnitude, then the small step): never rounded at the coordinates' own magnitude.
inline double localRay(const CellRecord& cell, const TetFrame& frame, const Ray& ray, double L[4],
  double dL[4])
{
  const glm::dvec3 fromVertex0 = ray.origin - cell.vertex0;
  const double tCentre = glm::dot(cell.centroidOffset - fromVertex0, ray.direction);
  frame.barycentricOfOffsets(fromVertex0 + tCentre * ray.direction,
    (ray.origin - cell.vertex1) + tCentre * ray.direction, L);
  frame.barycentricDirection(ray.direction, dL);
  return tCentre;
}

/// Entry and exit: the tet is {L_k >= 0} widened by kBarycentricTolerance; each L_k(s) is affine
/// in s. Narrows [sEntry, sExit]; false if the ray misses the cell there.
inline bool clipToCell(const double L[4], const double dL[4], double& sEntry, double& sExit)
{
  for (int k = 0; k < 4; ++k)
  {
    const double bound = (-kBarycentricTolerance - L[k]);
    if (dL[k] > 0.0)
    {
      sEntry = std::max(sEntry, bound / dL[k]);
    }
    else if (dL[k] < 0.0)
    {
      sExit = std::min(sExit, bound / dL[k]);
    }
    else if (L[k] < -kBarycentricTolerance)
    {
      return false; // parallel to face k and outside it
    }
  }
  return sEntry <= sExit;
}

/// A straight cell's ray test up to its field: the barycentric frame from the record, the ray
/// there (localRay: L(s) = L + s dL, t = tCentre + s) and its stretch [sEntry, sExit] inside the
/// cell within [tMin, tLimit] (clipToCell); false if the ray misses the cell there.
inline bool rayInCell(const CellRecord& cell, const Ray& ray, double tMin, double tLimit,
  TetFrame& frame, double L[4], double dL[4], double& tCentre, double& sEntry, double& sExit)
{
  for (int k = 0; k < 3; ++k)
  {
    frame.gradient[k + 1] = cell.gradient[k];
  }
  frame.gradient[0] = -(frame.gradient[1] + frame.gradient[2] + frame.gradient[3]);
  tCentre = localRay(cell, frame, ray, L, dL);
  sEntry = tMin - tCentre;
  sExit = tLimit - tCentre;
  return clipToCell(L, dL, sEntry, sExit);
}

/// The record's Bernstein coefficients as the symmetric form.
inline BernsteinForm formOf(const CellRecord& cell)
{
  BernsteinForm form;
  for (int i = 0; i < 4; ++i)
  {
    form.b[i][i] = cell.form[i];
  }
  for (int e = 0; e < 6; ++e)
  {
    const int a = kEdgeVertices[e][0], c = kEdgeVertices[e][1];
    form.b[a][c] = form.b[c][a] = cell.form[4 + e];
  }
  return form;
}
/// Up to this many iso-values within a cell's range are each solved for (firstCrossingOfEach);
/// more are searched (firstCrossingOfMany), so that the cost grows with their logarithm.
constexpr std::size_t kDirectIsoValues = 8;

/// The first root in [sEntry, sHit] of f(s) - v, f(s) = a s^2 + b s + c (the field times
/// `scale`), over the iso-values v = sorted[first, last): each solved for. Narrows sHit; true if
/// any was found, with its sorted() index.
inline bool firstCrossingOfEach(double a, double b, double c, double scale,
  const std::vector<double>& sorted, std::size_t first, std::size_t last, double sEntry,
  double& sHit, std::size_t& index)
{
  bool found = false;
  for (std::size_t k = first; k < last; ++k)
  {
    double s;
    if (firstRootInInterval(a, b, c - sorted[k] * scale, sEntry, sHit, s))
    {
      found = true;
      sHit = s;
      index = k;
    }
  }
  return found;
}

/// The same for many iso-values, by search. On each piece of [sEntry, sHit] where f is monotone
/// (split at its vertex), the values crossed lie between f at the piece's ends, and they are
/// crossed in order from f(start) on: those within a rounding band of f(start) are each solved
/// for, then the others in the direction f moves, until one has a root. The band (1e-10 of the
/// terms' size) covers the rounding of f's evaluation (a few eps) and the quadratic solver's
/// double-root band (1e-12 of the discriminant's terms) with room to spare; it only widens the
/// candidates, every root is still firstRootInInterval's.
inline bool firstCrossingOfMany(double a, double b, double c, double scale,
  const std::vector<double>& sorted, std::size_t first, std::size_t last, double sEntry,
  double& sHit, std::size_t& index)
{
  double ends[3] = { sEntry, sHit, sHit };
  int pieces = 1;
  if (a != 0.0)
  {
    const double vertex = -b / (2.0 * a);
    if (vertex > sEntry && vertex < sHit)
    {
      ends[1] = vertex;
      pieces = 2;
    }
  }
  const auto begin = sorted.begin() + static_cast<std::ptrdiff_t>(first);
  const auto end = sorted.begin() + static_cast<std::ptrdiff_t>(last);
  for (int piece = 0; piece < pieces; ++piece)
  {
    const double s0 = ends[piece], s1 = ends[piece + 1];
    const double f0 = (a * s0 + b) * s0 + c;
    const double f1 = (a * s1 + b) * s1 + c;
    const double reach = std::max(std::abs(s0), std::abs(s1));
    const double band = 1e-10 *
      (std::abs(a) * reach * reach + std::abs(b) * reach + std::abs(c) +
        (a != 0.0 ? b * b / (4.0 * std::abs(a)) : 0.0));
    // The candidates v * scale in [min(f0, f1) - band, max(f0, f1) + band], nearest f0 first.
    const auto lo = std::lower_bound(begin, end, (std::min(f0, f1) - band) / scale);
    const auto hi = std::upper_bound(begin, end, (std::max(f0, f1) + band) / scale);
    const bool rising = f1 >= f0;
    bool found = false;
    for (std::ptrdiff_t step = 0; step < hi - lo; ++step)
    {
      const auto k = rising ? lo + step : hi - 1 - step;
      double s;
      if (firstRootInInterval(a, b, c - *k * scale, s0, sHit, s))
      {
        found = true;
        sHit = s;
        index = static_cast<std::size_t>(k - sorted.begin());
      }
      // Past the band around f(start), the first value with a root is the first crossed.
      if (found && std::abs(*k * scale - f0) > band)
      {
        break;
      }
    }
    if (found)
    {
      return true;
    }
  }
  return false;
}
} // namespace quadratic_tet_detail

inline bool QuadraticTetCell::intersect(const CellRecord& cell, const Ray& ray,
  const IsoValues& isoValues, std::size_t first, std::size_t last, double tMin, double tLimit,
  SurfaceHit& hit)
{
  using namespace quadratic_tet_detail;
  TetFrame frame;
  double L[4], dL[4], tCentre, sEntry, sExit;
  if (!rayInCell(cell, ray, tMin, tLimit, frame, L, dL, tCentre, sEntry, sExit))
  {
    return false;
  }
  const BernsteinForm form = formOf(cell);
  if (cell.kind == CellRecord::Kind::Constant)
  {
    // The field constant over the cell (to rounding) and equal to an iso-value: the whole cell
    // is on the "surface"; the ray meets it where it enters, with no gradient. Rounding would
    // otherwise scatter the roots of a quadratic whose coefficients are all noise.
    double boundLo, boundHi;
    form.range(boundLo, boundHi);
    std::size_t equal, beyond;
    if (!isoValues.within(boundLo / cell.scale, boundHi / cell.scale, equal, beyond))
    {
      return false;
    }
    hit.t = tCentre + sEntry;
    hit.regionEnd = tCentre + sExit;
    hit.cellId = cell.cellId;
    hit.gradient = glm::dvec3(0.0);
    hit.isoIndex = equal;
    return true;
  }
  // The field along the ray, exactly: f(s) = a s^2 + b s + c (see QuadraticTet.h); the nearest
  // root of f - iso in [sEntry, sHit] over the iso-values the cell can hold.
  const double a = form.bilinear(dL, dL);
  const double b = 2.0 * form.bilinear(L, dL);
  const double c = form.bilinear(L, L);
  double sHit = sExit;
  const bool found = last - first <= kDirectIsoValues
    ? firstCrossingOfEach(a, b, c, cell.scale, isoValues.sorted(), first, last, sEntry, sHit, hit.isoIndex)
    : firstCrossingOfMany(a, b, c, cell.scale, isoValues.sorted(), first, last, sEntry, sHit, hit.isoIndex);
  if (!found)
  {
    return false;
  }
  double LHit[4];
  for (int k = 0; k < 4; ++k)
  {
    LHit[k] = L[k] + sHit * dL[k];
  }
  hit.t = tCentre + sHit;
  hit.regionEnd = hit.t;
  hit.cellId = cell.cellId;
  // Unscaled exactly (a power of two), unless that overflows or underflows (a field near the
  // ends of double range): then the scaled gradient, whose direction is the same.
  const glm::dvec3 gradient = fieldGradient(form, frame, LHit);
  hit.gradient = unscaledGradient(gradient, cell.scale);
  return true;
}

} // namespace tetdsr
