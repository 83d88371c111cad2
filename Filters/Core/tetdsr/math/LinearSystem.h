// Small dense linear systems (at most 5 unknowns): the curved solver's Jacobian inverses and the
// Lagrange systems of a quadratic's critical points on a simplex's faces.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

namespace tetdsr
{

/// Solves A X = B in place on the augmented matrix m = [A | B] (`size` rows, `size` + `columns`
/// <= 6 columns) by Gauss-Jordan elimination with partial pivoting: on success the last
/// `columns` columns of m hold X. Returns false when A is zero or not finite, or when a pivot is
/// not above `pivotTolerance` times A's largest entry.
///
/// The pivots computed for a k x k matrix A are exact for a matrix within about
/// k^2 2^(k-1) eps max|A| of A (backward error gamma_k |L||U|, k terms of at most the largest
/// entry of U, which partial pivoting lets grow to 2^(k-1) max|A|: Higham, Accuracy and
/// Stability of Numerical Algorithms, Thm 9.3): a pivot below that cannot be told from 0, and the
/// solution would be rounding noise. Callers pass that bound for their largest system, rounded
/// up to a power of ten.
inline bool solveLinearSystem(double m[][6], int size, int columns, double pivotTolerance)
{
  // The pivots are measured against A's largest entry (the solve is invariant under scaling A).
  double scale = 0.0;
  for (int r = 0; r < size; ++r)
  {
    for (int c = 0; c < size; ++c)
    {
      scale = std::max(scale, std::abs(m[r][c]));
    }
  }
  if (!(scale > 0.0) || !std::isfinite(scale))
  {
    return false;
  }
  const int width = size + columns;
  for (int col = 0; col < size; ++col)
  {
    // The largest entry left in the column, so that no multiplier exceeds 1 in magnitude.
    int pivot = col;
    for (int r = col + 1; r < size; ++r)
    {
      if (std::abs(m[r][col]) > std::abs(m[pivot][col]))
      {
        pivot = r;
      }
    }
    if (!(std::abs(m[pivot][col]) > pivotTolerance * scale))
    {
      return false;
    }
    for (int c = 0; c < width; ++c)
    {
      std::swap(m[col][c], m[pivot][c]);
    }
    // Normalise the pivot row, then clear the pivot's column in every other row.
    const double p = m[col][col];
    for (int c = 0; c < width; ++c)
    {
      m[col][c] /= p;
    }
    for (int r = 0; r < size; ++r)
    {
      if (r != col)
      {
        const double factor = m[r][col];
        for (int c = 0; c < width; ++c)
        {
          m[r][c] -= factor * m[col][c];
        }
      }
    }
  }
  return true;
}

} // namespace tetdsr
