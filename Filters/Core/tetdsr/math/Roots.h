// Roots of the ray quadratic a s^2 + b s + c = 0, solved stably.
#pragma once

#include <cmath>
#include <utility>

namespace tetdsr
{

/// b^2 - 4ac with the product a*c split exactly by fma (Kahan's discriminant), so a
/// discriminant that is small next to b^2 keeps its relative accuracy: the result is within a
/// few ulps of the exact value instead of an absolute error of eps * b^2.
inline double discriminant(double a, double b, double c)
{
  const double product = a * c;
  const double productError = std::fma(a, c, -product); // a*c = product + productError exactly
  return std::fma(b, b, -4.0 * product) - 4.0 * productError;
}

/// A discriminant negative by less than this fraction of its terms' size (b^2 + |4ac|) is taken
/// as 0, a double root (the surface touched, e.g. f = x^2 at iso-value 0); one more negative, as
/// a ray that passes. a, b and c are bilinear forms of the field (sums of up to 16 rounded
/// products), so the discriminant is uncertain by a few tens of eps of its terms, more where those
/// sums cancel: 1e-12 (about 4500 eps) leaves two orders of magnitude for that.
inline constexpr double kDoubleRootBand = 1e-12;

/// Smallest root of a s^2 + b s + c in [lo, hi]; returns false if there is none.
/// A segment on which the quadratic is identically zero (a = b = c = 0: the field equals the
/// iso-value along the whole segment) reports its start.
inline bool firstRootInInterval(double a, double b, double c, double lo, double hi, double& root)
{
  auto accept = [&](double s) {
    if (s >= lo && s <= hi)
    {
      root = s;
      return true;
    }
    return false;
  };
  if (a == 0.0)
  {
    if (b == 0.0)
    {
      return c == 0.0 && accept(lo);
    }
    return accept(-c / b); // linear: one root
  }
  // Most rays that pass through a cell miss its surface with a clearly negative discriminant:
  // the plain b^2 - 4ac (error below 4 eps of its terms, far inside twice the band) says so
  // without the exact one's fma calls, with the same outcome.
  const double terms = b * b + std::abs(4.0 * a * c);
  if (b * b - 4.0 * a * c < -2.0 * kDoubleRootBand * terms)
  {
    return false;
  }
  double disc = discriminant(a, b, c);
  if (disc < 0.0)
  {
    // Within the band: a double root; beyond it the ray passes.
    if (disc < -kDoubleRootBand * terms)
    {
      return false;
    }
    disc = 0.0;
  }
  // Stable formula: q has no cancellation; the roots are q/a and c/q (Vieta: product c/a).
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  if (q == 0.0)
  {
    return accept(0.0); // b = 0 and disc = 0 force c = 0: double root at 0
  }
  double s0 = q / a;
  double s1 = c / q;
  if (s0 > s1)
  {
    std::swap(s0, s1);
  }
  return accept(s0) || accept(s1);
}

} // namespace tetdsr
