// The box solve of three tensor forms on the unit cube (HexahedronCell.h's solveOnUnitBox,
// solveOnCube, widen): exclusion by coefficient signs and depth, Bezier clipping, Krawczyk's test,
// Newton (newtonOnBox).
#include "tetdsr/cells/HexahedronCell.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace tetdsr
{

namespace
{
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

bool invert3(const double a[3][3], double inverse[3][3])
{
  const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
  const double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
  const double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
  const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
  if (!(std::abs(det) > 0.0) || !std::isfinite(det))
  {
    return false;
  }
  const double s = 1.0 / det;
  inverse[0][0] = c00 * s;
  inverse[1][0] = c01 * s;
  inverse[2][0] = c02 * s;
  inverse[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * s;
  inverse[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * s;
  inverse[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * s;
  inverse[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * s;
  inverse[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * s;
  inverse[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * s;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(inverse[i][j]))
        return false;
  return true;
}

// ---- The box solve -----------------------------------------------------------------------------

template <int P>
struct Box
{
  static constexpr int N = tensor::count(P);
  double lo[3], hi[3];  ///< in the widened cube's unit coordinates
  double c[4][N];       ///< the three equations' and the objective's coefficients on the box
};

/// What Krawczyk's test says of a box.
enum class Krawczyk
{
  None,    ///< no root in the box
  Unique,  ///< exactly one root, within `inner` (box unit coordinates)
  Unknown
};

/// Krawczyk's test in the box's own unit coordinates w (centre m = 1/2, radius 1/2): with Y the
/// inverse of the Jacobian at m, K = m - Y F(m) + (I - Y J(box)) (w - m); K inside the box's
/// interior proves a unique root (in K), K outside it proves none. J(box) is bounded entry by
/// entry by the coefficients' differences (tensor::derivativeRange).
template <int P>
Krawczyk krawczyk(const Box<P>& box, double inner[3][2], double scoreByAxis[3])
{
  const double m[3] = { 0.5, 0.5, 0.5 };
  double f[3], jm[3][3];
  double jLo[3][3], jHi[3][3];
  for (int e = 0; e < 3; ++e)
  {
    f[e] = tensor::evaluate<P>(box.c[e], m, jm[e]);
    for (int a = 0; a < 3; ++a)
    {
      tensor::derivativeRange<P>(box.c[e], a, jLo[e][a], jHi[e][a]);
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    scoreByAxis[a] = 0.0;
    for (int e = 0; e < 3; ++e)
    {
      scoreByAxis[a] += std::max(std::abs(jLo[e][a]), std::abs(jHi[e][a])) /
        (std::abs(jm[e][0]) + std::abs(jm[e][1]) + std::abs(jm[e][2]) + 1e-300);
    }
  }
  double y[3][3];
  if (!invert3(jm, y))
  {
    return Krawczyk::Unknown;
  }
  for (int i = 0; i < 3; ++i)
  {
    const double yf = y[i][0] * f[0] + y[i][1] * f[1] + y[i][2] * f[2];
    // |(I - Y J(box)) (w - m)|_i <= sum_a |I - Y Jc|_ia r + (|Y| Jr)_ia r, r = 1/2.
    double spread = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      double centre = i == a ? 1.0 : 0.0, radius = 0.0;
      for (int e = 0; e < 3; ++e)
      {
        centre -= y[i][e] * 0.5 * (jLo[e][a] + jHi[e][a]);
        radius += std::abs(y[i][e]) * 0.5 * (jHi[e][a] - jLo[e][a]);
      }
      spread += 0.5 * (std::abs(centre) + radius);
    }
    // Rounding of F, J and Y (numbers near 1 in the box's units): a relative margin.
    spread = spread * (1.0 + 1e-12) + 1e-13 + 64.0 * kEpsilon * std::abs(yf);
    if (!std::isfinite(spread) || !std::isfinite(yf))
    {
      return Krawczyk::Unknown;
    }
    inner[i][0] = 0.5 - yf - spread;
    inner[i][1] = 0.5 - yf + spread;
  }
  for (int i = 0; i < 3; ++i)
  {
    if (inner[i][0] > 1.0 || inner[i][1] < 0.0)
    {
      return Krawczyk::None;
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    if (!(inner[i][0] > 0.0 && inner[i][1] < 1.0))
    {
      return Krawczyk::Unknown;
    }
  }
  return Krawczyk::Unique;
}

/// Bezier clipping (Sederberg and Nishita): along `axis`, the form restricted to any line of
/// that axis is a univariate Bernstein polynomial whose coefficient i lies within [lo_i, hi_i] (the
/// least and largest coefficient of index i along the axis, widened by `pad`), so its roots lie
/// where the convex hull of the points (i / P, lo_i), (i / P, hi_i) meets zero: [from, to] in the
/// box's unit coordinates. False if it does not (no root in the box).
template <int P>
bool clipAxis(const double* c, int axis, double pad, double& from, double& to)
{
  double lo[P + 1], hi[P + 1];
  const int step = tensor::stride(P, axis);
  for (int i = 0; i <= P; ++i)
  {
    lo[i] = std::numeric_limits<double>::infinity();
    hi[i] = -lo[i];
  }
  for (int b = 0; b <= P; ++b)
  {
    for (int a = 0; a <= P; ++a)
    {
      const int base = axis == 0 ? tensor::index(P, 0, a, b) : axis == 1 ? tensor::index(P, a, 0, b) : tensor::index(P, a, b, 0);
      for (int i = 0; i <= P; ++i)
      {
        const double value = c[base + i * step];
        lo[i] = std::min(lo[i], value);
        hi[i] = std::max(hi[i], value);
      }
    }
  }
  // The hull meets zero between the least and largest zero crossing of a segment joining two of
  // its points of opposite signs (or a point that is zero within the pad).
  from = std::numeric_limits<double>::infinity();
  to = -from;
  double x[2 * P + 2], y[2 * P + 2];
  for (int i = 0; i <= P; ++i)
  {
    x[2 * i] = x[2 * i + 1] = static_cast<double>(i) / P;
    y[2 * i] = lo[i] - pad;
    y[2 * i + 1] = hi[i] + pad;
  }
  for (int p = 0; p < 2 * P + 2; ++p)
  {
    if (y[p] == 0.0)
    {
      from = std::min(from, x[p]);
      to = std::max(to, x[p]);
      continue;
    }
    for (int q = p + 1; q < 2 * P + 2; ++q)
    {
      if ((y[p] < 0.0) != (y[q] < 0.0) && y[q] != 0.0)
      {
        const double crossing = x[p] + (x[q] - x[p]) * (y[p] / (y[p] - y[q]));
        from = std::min(from, crossing);
        to = std::max(to, crossing);
      }
    }
  }
  if (!(from <= to))
  {
    return false;
  }
  // (Rounding of the crossings: a relative margin, then the box itself.)
  const double margin = 1e-12;
  from = std::max(0.0, from - margin);
  to = std::min(1.0, to + margin);
  return true;
}

/// A thread's stack of boxes, reused between solves.
template <int P>
std::vector<Box<P>>& boxStack()
{
  thread_local std::vector<Box<P>> stack;
  return stack;
}

} // namespace

/// Newton on the equations (coefficients on the widened cube, unit coordinates) from x; true if
/// it converges (steps below rounding) with x finite.
template <int P>
bool newtonOnBox(const double* const forms[3], double x[3])
{
  for (int iteration = 0; iteration < 16; ++iteration)
  {
    double f[3], j[3][3], inverse[3][3];
    for (int e = 0; e < 3; ++e)
    {
      f[e] = tensor::evaluate<P>(forms[e], x, j[e]);
    }
    if (!invert3(j, inverse))
    {
      return false;
    }
    double largest = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double step = inverse[a][0] * f[0] + inverse[a][1] * f[1] + inverse[a][2] * f[2];
      x[a] -= step;
      largest = std::max(largest, std::abs(step));
    }
    if (!(std::abs(x[0]) + std::abs(x[1]) + std::abs(x[2]) < 1e6))
    {
      return false;
    }
    if (largest <= 4.0 * kEpsilon)
    {
      return true;
    }
  }
  return true; // (the last steps within a few roundings: the caller checks where it landed)
}

template bool newtonOnBox<1>(const double* const[3], double[3]);
template bool newtonOnBox<2>(const double* const[3], double[3]);
template bool newtonOnBox<3>(const double* const[3], double[3]);
template bool newtonOnBox<4>(const double* const[3], double[3]);


template <int P>
void widen(const double* form, double tolerance, double* out)
{
  constexpr int N = tensor::count(P);
  double matrix[P + 1][P + 1];
  tensor::segmentMatrix<P>(-tolerance, 1.0 + tolerance, matrix);
  double work[N];
  tensor::transformAxis<P>(form, 0, matrix, out);
  tensor::transformAxis<P>(out, 1, matrix, work);
  tensor::transformAxis<P>(work, 2, matrix, out);
}

template <int P>
bool solveOnCube(const double* const equations[3], const double* objective, double lo, double hi,
  double tolerance, BoxRoot& root, const BoxSolveLimits& limits, int* pieces)
{
  // The forms on the cube widened by `tolerance` (roots on a face shared with a neighbour are
  // interior to both cells' boxes): x = -tolerance + w (1 + 2 tolerance), w in [0, 1].
  constexpr int N = tensor::count(P);
  double widened[4][N];
  for (int f = 0; f < (objective ? 4 : 3); ++f)
  {
    widen<P>(f < 3 ? equations[f] : objective, tolerance, widened[f]);
  }
  const double* forms[3] = { widened[0], widened[1], widened[2] };
  if (!solveOnUnitBox<P>(forms, objective ? widened[3] : nullptr, lo, hi, root, limits, pieces))
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    root.x[a] = -tolerance + root.x[a] * (1.0 + 2.0 * tolerance);
  }
  return true;
}

template <int P>
bool solveOnUnitBox(const double* const equations[3], const double* objective, double lo, double hi,
  BoxRoot& root, const BoxSolveLimits& limits, int* pieces)
{
  constexpr int N = tensor::count(P);
  const int forms = objective ? 4 : 3;
  const double* whole[3] = { equations[0], equations[1], equations[2] };
  // Coefficients within this of zero prove no sign: subdivision rounds each by about one
  // rounding a level (averages), evaluation by a few per degree.
  double pad[4];
  for (int f = 0; f < forms; ++f)
  {
    pad[f] = (64.0 + 16.0 * P) * kEpsilon * bernstein::magnitude(f < 3 ? equations[f] : objective, N);
  }
  std::vector<Box<P>>& stack = boxStack<P>();
  stack.clear();
  stack.emplace_back();
  Box<P>& first = stack.back();
  for (int a = 0; a < 3; ++a)
  {
    first.lo[a] = 0.0;
    first.hi[a] = 1.0;
  }
  for (int f = 0; f < forms; ++f)
  {
    const double* form = f < 3 ? equations[f] : objective;
    std::copy(form, form + N, first.c[f]);
  }
  bool found = false;
  double best = hi;
  int visited = 0;
  auto accept = [&](const double w[3], bool certified) {
    const double value = objective ? tensor::evaluate<P>(objective, w) : 0.0;
    if (objective && !(value >= lo && value <= best))
    {
      return;
    }
    found = true;
    best = value;
    root.value = value;
    root.certified = certified;
    std::copy(w, w + 3, root.x);
  };
  while (!stack.empty())
  {
    if (++visited > limits.maxPieces)
    {
      break;
    }
    Box<P> box = stack.back();
    stack.pop_back();
    // Exclusion: an equation of one sign on the box; depth beyond the nearest root or the range.
    bool excluded = false;
    for (int e = 0; e < 3 && !excluded; ++e)
    {
      double cLo, cHi;
      bernstein::range(box.c[e], N, cLo, cHi);
      excluded = cLo > pad[e] || cHi < -pad[e];
    }
    if (excluded)
    {
      continue;
    }
    // Bezier clipping while it shrinks the box well (its roots converge quadratically; a box it
    // cannot shrink goes on to Krawczyk's test and bisection).
    for (int round = 0; round < 4 && !excluded; ++round)
    {
      double from[3] = { 0.0, 0.0, 0.0 }, to[3] = { 1.0, 1.0, 1.0 };
      for (int e = 0; e < 3 && !excluded; ++e)
      {
        for (int a = 0; a < 3 && !excluded; ++a)
        {
          double f0, f1;
          excluded = !clipAxis<P>(box.c[e], a, pad[e], f0, f1);
          from[a] = std::max(from[a], f0);
          to[a] = std::min(to[a], f1);
          excluded = excluded || !(from[a] <= to[a]);
        }
      }
      double shrink = 0.0;
      for (int a = 0; a < 3; ++a)
      {
        shrink = std::max(shrink, to[a] - from[a]);
      }
      if (excluded || shrink > 0.7)
      {
        break;
      }
      // The forms on the clipped box (each axis reparametrised) and its place in the cube.
      for (int a = 0; a < 3; ++a)
      {
        if (from[a] == 0.0 && to[a] == 1.0)
        {
          continue;
        }
        double matrix[P + 1][P + 1];
        tensor::segmentMatrix<P>(from[a], to[a], matrix);
        for (int f = 0; f < forms; ++f)
        {
          double work[N];
          tensor::transformAxis<P>(box.c[f], a, matrix, work);
          std::copy(work, work + N, box.c[f]);
        }
        const double span = box.hi[a] - box.lo[a];
        const double lower = box.lo[a] + from[a] * span;
        box.hi[a] = box.lo[a] + to[a] * span;
        box.lo[a] = lower;
      }
    }
    if (excluded)
    {
      continue;
    }
    if (objective)
    {
      double dLo, dHi;
      bernstein::range(box.c[3], N, dLo, dHi);
      if (dLo > best + pad[3] || dHi < lo - pad[3])
      {
        continue;
      }
    }
    double inner[3][2], score[3];
    const Krawczyk test = krawczyk<P>(box, inner, score);
    if (test == Krawczyk::None)
    {
      continue;
    }
    double width = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      width = std::max(width, box.hi[a] - box.lo[a]);
    }
    if (test == Krawczyk::Unique || width <= limits.minWidth)
    {
      // Newton from the box's centre (or the Krawczyk box's) on the whole forms.
      double w[3];
      for (int a = 0; a < 3; ++a)
      {
        const double centre = test == Krawczyk::Unique ? 0.5 * (inner[a][0] + inner[a][1]) : 0.5;
        w[a] = box.lo[a] + centre * (box.hi[a] - box.lo[a]);
      }
      if (newtonOnBox<P>(whole, w))
      {
        // Proven roots lie in K (inside the box); Newton's must land there (to rounding).
        bool inside = true;
        for (int a = 0; a < 3; ++a)
        {
          const double span = box.hi[a] - box.lo[a];
          const double margin = 1e-9 * span + 4.0 * kEpsilon;
          const double from = test == Krawczyk::Unique ? box.lo[a] + inner[a][0] * span : box.lo[a];
          const double to = test == Krawczyk::Unique ? box.lo[a] + inner[a][1] * span : box.hi[a];
          inside = inside && w[a] >= from - margin && w[a] <= to + margin;
        }
        if (inside)
        {
          accept(w, test == Krawczyk::Unique);
          if (!objective && found)
          {
            break;
          }
          continue;
        }
      }
      if (width <= limits.minWidth)
      {
        continue; // no root Newton can reach here
      }
    }
    // Bisect along the axis where the equations vary most over the box (relative to their
    // gradients' sizes), the nearer half (least depth bound) popped first.
    int axis = 0;
    for (int a = 1; a < 3; ++a)
    {
      if (score[a] * (box.hi[a] - box.lo[a]) > score[axis] * (box.hi[axis] - box.lo[axis]))
      {
        axis = a;
      }
    }
    if (!(score[axis] > 0.0))
    {
      axis = 0;
      for (int a = 1; a < 3; ++a)
      {
        if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis])
        {
          axis = a;
        }
      }
    }
    Box<P> halves[2];
    for (int h = 0; h < 2; ++h)
    {
      std::copy(box.lo, box.lo + 3, halves[h].lo);
      std::copy(box.hi, box.hi + 3, halves[h].hi);
    }
    const double middle = 0.5 * (box.lo[axis] + box.hi[axis]);
    halves[0].hi[axis] = middle;
    halves[1].lo[axis] = middle;
    for (int f = 0; f < forms; ++f)
    {
      tensor::halve<P>(box.c[f], axis, halves[0].c[f], halves[1].c[f]);
    }
    int nearer = 0;
    if (objective)
    {
      double lo0, hi0, lo1, hi1;
      bernstein::range(halves[0].c[3], N, lo0, hi0);
      bernstein::range(halves[1].c[3], N, lo1, hi1);
      nearer = lo1 < lo0 ? 1 : 0;
    }
    stack.push_back(halves[1 - nearer]);
    stack.push_back(halves[nearer]);
  }
  if (pieces)
  {
    *pieces = visited;
  }
  if (visited > limits.maxPieces && found)
  {
    root.certified = false; // boxes left unexplored might hold a nearer root
  }
  return found;
}

template void widen<1>(const double*, double, double*);
template void widen<2>(const double*, double, double*);
template void widen<3>(const double*, double, double*);
template void widen<4>(const double*, double, double*);
template bool solveOnUnitBox<1>(const double* const[3], const double*, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnUnitBox<2>(const double* const[3], const double*, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnUnitBox<3>(const double* const[3], const double*, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnUnitBox<4>(const double* const[3], const double*, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnCube<1>(const double* const[3], const double*, double, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnCube<2>(const double* const[3], const double*, double, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnCube<3>(const double* const[3], const double*, double, double, double, BoxRoot&, const BoxSolveLimits&, int*);
template bool solveOnCube<4>(const double* const[3], const double*, double, double, double, BoxRoot&, const BoxSolveLimits&, int*);

} // namespace tetdsr
