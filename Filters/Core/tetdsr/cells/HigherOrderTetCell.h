// The straight tetrahedron of order P = 3 or 4 (VTK_LAGRANGE_TETRAHEDRON or VTK_BEZIER_TETRAHEDRON
// of 20 or 35 nodes whose nodes sit where the affine map of its vertices puts them): along a ray
// the barycentric coordinates are affine, so the field is exactly a polynomial of degree P in t,
// whose Bernstein coefficients on the ray's stretch inside the cell are blossoms of the cell's
// (TetBernstein.h). Its first root there is certified by firstBernsteinRoot. The cell seam's
// steps (Cells.h); the cell's nodes and values arrive in Bezier layout (HigherOrderTet.h), the
// field's coefficients are read from the mesh for each ray test (the record holds the frame).
#pragma once

#include "tetdsr/cells/Cells.h"
#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/cells/QuadraticTetCell.h"
#include "tetdsr/math/TetBernstein.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tetdsr
{

template <int P>
struct HigherOrderTetCell
{
  static constexpr int kNodes = latticeCount(P);
  /// The nodes its record is made from: the vertices (the map is affine).
  static constexpr int kRecordNodes = 4;
  /// The coefficients its record keeps beside it (record).
  static constexpr int kRecordCoefficients = kNodes;

  /// validate, on the cell's nodes as given (VTK order; Lagrange nodes or Bezier control points:
  /// both sit at alpha_n / P under an affine map): QuadraticTetCell's vertex checks, then kCurved
  /// if a node is off its place by more than the coordinates' rounding allows.
  static std::uint16_t validate(const glm::dvec3 nodes[], double pointRounding)
  {
    double curvedTolerance = 0.0;
    const std::uint16_t flags = QuadraticTetCell::validateVertices(nodes, pointRounding, curvedTolerance);
    if (!(flags & kValid))
    {
      return flags;
    }
    for (int n = 4; n < kNodes; ++n)
    {
      double L[4];
      HigherOrderTet<P>::nodePoint(n, L);
      const glm::dvec3 expected = L[0] * nodes[0] + L[1] * nodes[1] + L[2] * nodes[2] + L[3] * nodes[3];
      if (QuadraticTetCell::offItsPlace(nodes[n], expected, curvedTolerance))
      {
        return flags | kCurved;
      }
    }
    return flags;
  }

  /// valueBound: the least and largest Bernstein coefficient, a guaranteed bound, whatever the
  /// transverse test (its widened nodal range is the paper's heuristic for quadratic cells).
  static void valueBound(const double values[], const TransverseTest&, double& lo, double& hi)
  {
    bernstein::range(values, kNodes, lo, hi);
  }

  /// extent: the vertices' box (a straight cell is their convex hull).
  static bool extent(const glm::dvec3 nodes[], glm::dvec3& lo, glm::dvec3& hi)
  {
    return QuadraticTetCell::extent(nodes, lo, hi);
  }

  /// record: the barycentric frame (as QuadraticTetCell's) and the field's coefficients, scaled
  /// by a power of two and in canonical order, into `coefficients` (kNodes of them, kept beside
  /// the record: CellRecord::coefficients); a field constant to rounding is recorded as
  /// QuadraticTetCell's constant record.
  static void record(const glm::dvec3 vertices[], const double values[], CellRecord& cell,
    double* coefficients)
  {
    QuadraticTetCell::recordFrame(vertices, cell);
    cell.scale = unitScale(values, kNodes);
    cell.order = P;
    double lo, hi;
    bernstein::range(values, kNodes, lo, hi);
    if (constantToRounding(lo, hi, P))
    {
      // QuadraticTetCell's constant record: a form whose coefficients span [lo, hi] (scaled).
      std::fill(cell.form, cell.form + kCellNodes, lo * cell.scale);
      cell.form[1] = hi * cell.scale;
      cell.kind = CellRecord::Kind::Constant;
      return;
    }
    HigherOrderTet<P>::toLattice(values, coefficients);
    for (int k = 0; k < kNodes; ++k)
    {
      coefficients[k] *= cell.scale;
    }
    cell.coefficients = coefficients;
    cell.kind = CellRecord::Kind::HigherOrder;
  }

  /// intersect: the first crossing along the ray, with tMin <= t <= tLimit, of one of the
  /// iso-values sorted()[first, last). `certified` is false for a tangent root accepted without
  /// a sign change.
  static bool intersect(const CellRecord& cell, const Ray& ray, const IsoValues& isoValues,
    std::size_t first, std::size_t last, double tMin, double tLimit, SurfaceHit& hit,
    bool& certified)
  {
    // The ray in the cell's barycentric coordinates, re-origined near its centroid, clipped.
    TetFrame frame;
    double L[4], dL[4], tCentre, sEntry, sExit;
    if (!quadratic_tet_detail::rayInCell(cell, ray, tMin, tLimit, frame, L, dL, tCentre, sEntry, sExit))
    {
      return false;
    }
    // The field (scaled by a power of two) along the stretch [sEntry, sExit]: Bernstein
    // coefficients on [0, 1] of u = (s - sEntry) / (sExit - sEntry).
    const double* c = cell.coefficients;
    double entry[4], exit[4];
    for (int k = 0; k < 4; ++k)
    {
      entry[k] = L[k] + sEntry * dL[k];
      exit[k] = L[k] + sExit * dL[k];
    }
    double along[P + 1];
    bernstein::onSegment<P>(c, entry, exit, along);
    double nearest;
    if (!nearestBernsteinRoot<P>(along, isoValues.sorted(), first, last, cell.scale, nearest, hit.isoIndex, certified))
    {
      return false;
    }
    const double s = sEntry + nearest * (sExit - sEntry);
    double LHit[4];
    for (int k = 0; k < 4; ++k)
    {
      LHit[k] = L[k] + s * dL[k];
    }
    hit.t = tCentre + s;
    hit.regionEnd = hit.t;
    hit.cellId = cell.cellId;
    // Unscaled exactly (a power of two), unless that overflows or underflows.
    const glm::dvec3 gradient = latticeGradient(c, frame, LHit);
    hit.gradient = unscaledGradient(gradient, cell.scale);
    return true;
  }

  /// contains / coordinates: QuadraticTetCell's (the vertices' affine map).
  static bool contains(const glm::dvec3 nodes[], const glm::dvec3& point, double L[4])
  {
    return QuadraticTetCell::contains(nodes, point, L);
  }
  static void coordinates(const glm::dvec3 nodes[], const glm::dvec3& point, double L[4])
  {
    QuadraticTetCell::coordinates(nodes, point, L);
  }

  /// interpolate: the Bernstein polynomial at L (de Casteljau), scaled by a power of two so that
  /// the steps cannot overflow for values near the largest double.
  static double interpolate(const double values[], const double L[4])
  {
    const double scale = unitScale(values, kNodes);
    double c[kNodes];
    HigherOrderTet<P>::toLattice(values, c);
    for (double& coefficient : c)
    {
      coefficient *= scale;
    }
    return bernstein::evaluate<P>(c, L) / scale;
  }

  /// gradient: the exact gradient of the field with these coefficients at barycentric L.
  static glm::dvec3 gradient(const glm::dvec3 nodes[], const double values[], const double L[4])
  {
    TetFrame frame;
    TetFrame::fromVertices(nodes, frame);
    double c[kNodes];
    HigherOrderTet<P>::toLattice(values, c);
    return latticeGradient(c, frame, L);
  }

private:
  /// grad f = sum_k (df/dL_k) grad L_k, with f taken as homogeneous of degree P in L (any
  /// multiple of (1, 1, 1, 1) in its partials cancels: the grad L_k sum to zero).
  static glm::dvec3 latticeGradient(const double c[], const TetFrame& frame, const double L[4])
  {
    double d[4];
    bernstein::partials<P>(c, L, d);
    return d[0] * frame.gradient[0] + d[1] * frame.gradient[1] + d[2] * frame.gradient[2] +
      d[3] * frame.gradient[3];
  }
};

} // namespace tetdsr
