// The 10-node (quadratic) tetrahedron: barycentric frame, Bernstein form of the field,
// and the field along a ray as an exact quadratic.
//
// Node order is VTK_QUADRATIC_TETRA's: vertices 0..3, then the mid-edge nodes of the edges
// (0,1) (1,2) (0,2) (0,3) (1,3) (2,3). The paper's shape functions (its eq. 2),
//   f = sum_i f_i L_i (2 L_i - 1) + sum_{edges ab} 4 f_ab L_a L_b,
// rewritten with sum_j L_j = 1 become the homogeneous quadratic form
//   f = L^T B L,  B_ii = f_i,  B_ab = B_ba = 2 f_ab - (f_a + f_b) / 2,
// whose entries are the Bernstein-Bezier coefficients of f on the simplex. Two consequences:
// f lies between the min and max of the 10 entries of B (convex hull property), and along a
// ray L is affine in t, so f(t) is exactly the quadratic (dL^T B dL) t^2 + 2 (L^T B dL) t + L^T B L.
#pragma once

#include "tetdsr/math/LinearSystem.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <array>

namespace tetdsr
{

/// Vertex pairs of the six edges, in the order of the mid-edge nodes 4..9.
inline constexpr std::array<std::array<int, 2>, 6> kEdgeVertices = {
  { { 0, 1 }, { 1, 2 }, { 0, 2 }, { 0, 3 }, { 1, 3 }, { 2, 3 } }
};

/// A symmetric quadratic form q(L) = L^T B L in the barycentric coordinates L_0..L_n of a simplex
/// (n = 3, a tetrahedron, or n = 2, a triangle; entries beyond n are unused), B holding its
/// Bernstein-Bezier coefficients: the field of a cell, and in a curved cell each coordinate of its
/// map and the equations of a ray (CurvedTet.h).
struct BernsteinForm
{
  static constexpr int kDegree = 2;
  double b[4][4];

  /// @param nodeValues the field at the 10 nodes, VTK order.
  static BernsteinForm fromNodeValues(const double nodeValues[10])
  {
    BernsteinForm form{};
    for (int i = 0; i < 4; ++i)
    {
      form.b[i][i] = nodeValues[i];
    }
    for (int e = 0; e < 6; ++e)
    {
      const int a = kEdgeVertices[e][0];
      const int c = kEdgeVertices[e][1];
      const double coefficient = 2.0 * nodeValues[4 + e] - 0.5 * (nodeValues[a] + nodeValues[c]);
      form.b[a][c] = coefficient;
      form.b[c][a] = coefficient;
    }
    return form;
  }

  /// Rigorous bounds of f over the cell: the min and max Bernstein coefficient.
  void range(double& lo, double& hi) const
  {
    lo = hi = b[0][0];
    for (int i = 0; i < 4; ++i)
    {
      for (int j = i; j < 4; ++j)
      {
        lo = std::min(lo, b[i][j]);
        hi = std::max(hi, b[i][j]);
      }
    }
  }

  /// The exact range of f over the cell. A quadratic's extrema on the simplex lie at critical
  /// points of its restriction to the relative interior of one of the 15 faces (vertices, edges,
  /// triangles, the tet). On face S, stationarity of L_S^T B_SS L_S under sum(L_S) = 1 is the
  /// Lagrange system [2 B_SS, -1; 1^T, 0] [L_S; lambda] = [0; 1]; a singular system means a line
  /// of critical points, whose extremes lie on the face's boundary (a smaller face).
  /// Used to measure what range bounds miss; ~15 small solves, not for every frame.
  void exactRange(double& lo, double& hi) const
  {
    lo = hi = b[0][0];
    for (int subset = 1; subset < 16; ++subset)
    {
      int index[4], n = 0;
      for (int k = 0; k < 4; ++k)
        if (subset & (1 << k))
          index[n++] = k;
      double system[5][6] = {}; // augmented (n + 1) x (n + 2)
      for (int r = 0; r < n; ++r)
      {
        for (int c = 0; c < n; ++c)
          system[r][c] = 2.0 * b[index[r]][index[c]];
        system[r][n] = -1.0;
        system[n][r] = 1.0;
      }
      system[n][n + 1] = 1.0;
      // Pivots at rounding level (solveLinearSystem: k^2 2^(k-1) eps = 400 eps = 8.9e-14 for
      // the tet's 5 x 5 system, so 1e-13) mean a singular system: a line of critical points,
      // whose extremes its face's boundary gives.
      constexpr double kLagrangePivotTolerance = 1e-13;
      if (!solveLinearSystem(system, n + 1, 1, kLagrangePivotTolerance))
        continue;
      double L[4];
      for (int r = 0; r < n; ++r)
        L[r] = system[r][n + 1];
      bool inside = true;
      double full[4] = { 0.0, 0.0, 0.0, 0.0 };
      for (int r = 0; r < n; ++r)
      {
        inside = inside && L[r] >= 0.0;
        full[index[r]] = L[r];
      }
      if (inside)
      {
        const double value = bilinear(full, full);
        lo = std::min(lo, value);
        hi = std::max(hi, value);
      }
    }
  }

  /// u^T B v over indices 0..n: the blossom (polar form) of q, which is q(L) at u = v = L.
  /// A template on n, so the innermost ray test's loops (n = 3) unroll.
  template <int n = 3>
  double bilinear(const double u[4], const double v[4]) const
  {
    double sum = 0.0;
    for (int i = 0; i <= n; ++i)
    {
      double bv = b[i][0] * v[0];
      for (int j = 1; j <= n; ++j)
      {
        bv += b[i][j] * v[j];
      }
      sum += u[i] * bv;
    }
    return sum;
  }

  /// The form minus a constant (sum L = 1, so a constant is c in every coefficient).
  BernsteinForm minus(double c) const
  {
    BernsteinForm form = *this;
    for (auto& row : form.b)
    {
      for (double& entry : row)
      {
        entry -= c;
      }
    }
    return form;
  }

  /// Its restriction to the face opposite vertex `omit` of a tetrahedron (n = 3 -> 2): the face's
  /// barycentric coordinates are the other three, in order.
  BernsteinForm face(int omit) const
  {
    BernsteinForm form{};
    int index[3], count = 0;
    for (int k = 0; k < 4; ++k)
    {
      if (k != omit)
      {
        index[count++] = k;
      }
    }
    for (int i = 0; i < 3; ++i)
    {
      for (int j = 0; j < 3; ++j)
      {
        form.b[i][j] = b[index[i]][index[j]];
      }
    }
    return form;
  }
};

/// Affine map from world coordinates to barycentric coordinates of a straight-sided tet.
struct TetFrame
{
  glm::dvec3 vertex[4];
  /// gradient[k] = grad L_k (constant over the cell).
  glm::dvec3 gradient[4];
  /// det[x1-x0, x2-x0, x3-x0] = 6 * signed volume (the paper's T_vol, eq. 1).
  double orientedVolume6 = 0.0;

  /// Returns false for a zero-volume cell (no barycentric frame exists).
  static bool fromVertices(const glm::dvec3 vertices[4], TetFrame& frame)
  {
    for (int k = 0; k < 4; ++k)
    {
      frame.vertex[k] = vertices[k];
    }
    const glm::dvec3 e1 = vertices[1] - vertices[0];
    const glm::dvec3 e2 = vertices[2] - vertices[0];
    const glm::dvec3 e3 = vertices[3] - vertices[0];
    const glm::dvec3 n1 = glm::cross(e2, e3);
    frame.orientedVolume6 = glm::dot(e1, n1);
    if (frame.orientedVolume6 == 0.0 || !std::isfinite(frame.orientedVolume6))
    {
      return false;
    }
    // Cramer's rule: grad L_k is the face normal opposite vertex k scaled by 1/det, so
    // grad L_k . (x_j - x_0) = delta_kj. The sign of det cancels, so inverted cells get the
    // same barycentric coordinates (and the same field gradient) as well-oriented ones.
    const double inverse = 1.0 / frame.orientedVolume6;
    frame.gradient[1] = n1 * inverse;
    frame.gradient[2] = glm::cross(e3, e1) * inverse;
    frame.gradient[3] = glm::cross(e1, e2) * inverse;
    frame.gradient[0] = -(frame.gradient[1] + frame.gradient[2] + frame.gradient[3]);
    return true;
  }

  /// Barycentric coordinates of p. Each L_k is measured from a vertex on the face where L_k = 0,
  /// so points on a face get L_k close to 0 with an error relative to the cell, not to |p|.
  void barycentric(const glm::dvec3& p, double L[4]) const
  {
    barycentricOfOffsets(p - vertex[0], p - vertex[1], L);
  }

  /// The same from p - vertex[0] and p - vertex[1], for callers that can form these offsets
  /// without ever rounding p itself (p far from the origin, e.g. coordinates offset by 1e6).
  void barycentricOfOffsets(const glm::dvec3& fromVertex0, const glm::dvec3& fromVertex1,
    double L[4]) const
  {
    L[0] = glm::dot(gradient[0], fromVertex1);
    L[1] = glm::dot(gradient[1], fromVertex0);
    L[2] = glm::dot(gradient[2], fromVertex0);
    L[3] = glm::dot(gradient[3], fromVertex0);
  }

  /// Barycentric rate of change along direction d (sums to 0).
  void barycentricDirection(const glm::dvec3& d, double dL[4]) const
  {
    for (int k = 0; k < 4; ++k)
    {
      dL[k] = glm::dot(gradient[k], d);
    }
  }
};

/// Field gradient in world coordinates at barycentric point L: grad f = sum_k 2 (B L)_k grad L_k.
inline glm::dvec3 fieldGradient(const BernsteinForm& form, const TetFrame& frame, const double L[4])
{
  glm::dvec3 g(0.0);
  for (int k = 0; k < 4; ++k)
  {
    const double bl =
      form.b[k][0] * L[0] + form.b[k][1] * L[1] + form.b[k][2] * L[2] + form.b[k][3] * L[3];
    g += (2.0 * bl) * frame.gradient[k];
  }
  return g;
}

} // namespace tetdsr
