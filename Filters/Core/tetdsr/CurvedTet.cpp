#include "tetdsr/CurvedTet.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// A sub-simplex: its n + 1 vertices in barycentric coordinates of the reference simplex.
struct Piece
{
  double V[4][4];
  int depth;
  int levelLo = 0, levelHi = 1; ///< candidate levels [levelLo, levelHi) (Levels)
};

template <int n>
double magnitude(const BernsteinForm& form)
{
  double m = 0.0;
  for (int i = 0; i <= n; ++i)
  {
    for (int j = 0; j <= n; ++j)
    {
      m = std::max(m, std::abs(form.b[i][j]));
    }
  }
  return m;
}

/// Min and max of the form's Bernstein coefficients on the piece (its blossom at vertex pairs).
template <int n>
void coefficientRange(const BernsteinForm& form, const Piece& piece, double& lo, double& hi)
{
  // B V_j for each vertex j once; then each coefficient is one dot product.
  double bv[4][4];
  for (int j = 0; j <= n; ++j)
  {
    for (int a = 0; a <= n; ++a)
    {
      double sum = 0.0;
      for (int b = 0; b <= n; ++b)
      {
        sum += form.b[a][b] * piece.V[j][b];
      }
      bv[j][a] = sum;
    }
  }
  lo = kInfinity;
  hi = -kInfinity;
  for (int i = 0; i <= n; ++i)
  {
    for (int j = i; j <= n; ++j)
    {
      double c = 0.0;
      for (int a = 0; a <= n; ++a)
      {
        c += piece.V[i][a] * bv[j][a];
      }
      lo = std::min(lo, c);
      hi = std::max(hi, c);
    }
  }
}

/// (B L)_j - (B L)_0 for j = 1..n, times 2: the derivative along y_j = L_j (L_0 = 1 - sum y).
template <int n>
void formGradient(const BernsteinForm& form, const double L[4], double g[3])
{
  double bl[4];
  for (int i = 0; i <= n; ++i)
  {
    bl[i] = 0.0;
    for (int j = 0; j <= n; ++j)
    {
      bl[i] += form.b[i][j] * L[j];
    }
  }
  for (int j = 1; j <= n; ++j)
  {
    g[j - 1] = 2.0 * (bl[j] - bl[0]);
  }
}

/// Inverse of an n x n matrix (n <= 3); false if singular to rounding.
template <int n>
bool invert(const double a[3][3], double inverse[3][3])
{
  // [a | I], reduced to [I | a^-1].
  double m[3][6];
  for (int r = 0; r < n; ++r)
  {
    for (int c = 0; c < n; ++c)
    {
      m[r][c] = a[r][c];
      m[r][n + c] = r == c ? 1.0 : 0.0;
    }
  }
  // Pivots at rounding level (solveLinearSystem: k^2 2^(k-1) eps = 36 eps = 8.0e-15 for 3 x 3,
  // so 1e-14): no inverse. The callers need no accuracy from it (a Krawczyk test is sound for any
  // preconditioner, Newton's result is checked), only no rounding noise; a refusal costs a bisection.
  constexpr double kJacobianPivotTolerance = 1e-14;
  if (!solveLinearSystem(m, n, n, kJacobianPivotTolerance))
  {
    return false;
  }
  for (int r = 0; r < n; ++r)
  {
    for (int c = 0; c < n; ++c)
    {
      inverse[r][c] = m[r][n + c];
    }
  }
  return true;
}

template <int n>
void evaluate(const BernsteinForm* equations, const double L[4], double F[3], double J[3][3])
{
  for (int k = 0; k < n; ++k)
  {
    F[k] = equations[k].bilinear(L, L, n);
    formGradient<n>(equations[k], L, J[k]);
  }
}

/// Newton's method on the equations from L (in place). Converged when a step moves no coordinate
/// by more than a few ulps; false if it does not converge (or leaves double range).
template <int n>
bool newton(const BernsteinForm* equations, double L[4])
{
  for (int iteration = 0; iteration < 40; ++iteration)
  {
    double F[3], J[3][3], Jinv[3][3];
    evaluate<n>(equations, L, F, J);
    if (!invert<n>(J, Jinv))
    {
      return false;
    }
    double largest = 0.0;
    double sum = 0.0;
    for (int j = 1; j <= n; ++j)
    {
      double step = 0.0;
      for (int k = 0; k < n; ++k)
      {
        step += Jinv[j - 1][k] * F[k];
      }
      L[j] -= step;
      sum += L[j];
      largest = std::max(largest, std::abs(step));
    }
    L[0] = 1.0 - sum;
    if (!std::isfinite(largest) || largest > 1e6)
    {
      return false;
    }
    if (largest <= 4.0 * kEpsilon)
    {
      return true;
    }
  }
  return false; // oscillating at rounding level: the last iterate is as good as any, but unproven
}

enum class Krawczyk
{
  Unique,  ///< exactly one root in the box
  None,    ///< no root in the box
  Unknown
};

/// The Krawczyk operator K(X) = m - Y F(m) + (I - Y J(X)) (X - m) on the box X = m +- r
/// (coordinates y_1..y_n), Y = J(m)^-1: every root in X lies in K(X); K(X) inside X proves
/// exactly one root in X, K(X) disjoint from X proves none. Evaluated in double; the margins
/// (1e-9 relative) absorb rounding.
template <int n>
Krawczyk krawczyk(const BernsteinForm* equations, const double m[4], const double r[3],
  double image[3][2], const double (*known)[3][3] = nullptr)
{
  // F(m), J(m) and J(m)^-1: computed here, or given (known[0], known[1], known[2]; F in row 0).
  double F[3], J[3][3], Y[3][3];
  if (known)
  {
    for (int i = 0; i < n; ++i)
    {
      F[i] = known[0][0][i];
      for (int j = 0; j < n; ++j)
      {
        J[i][j] = known[1][i][j];
        Y[i][j] = known[2][i][j];
      }
    }
  }
  else
  {
    evaluate<n>(equations, m, F, J);
    if (!invert<n>(J, Y))
    {
      return Krawczyk::Unknown;
    }
  }
  // R[k][j] bounds |J_kj(y) - J_kj(m)| over the box: J_kj is affine in y with slope a_kji.
  double R[3][3];
  for (int k = 0; k < n; ++k)
  {
    const auto& b = equations[k].b;
    for (int j = 1; j <= n; ++j)
    {
      double sum = 0.0;
      for (int i = 1; i <= n; ++i)
      {
        const double slope = 2.0 * ((b[j][i] - b[0][i]) - (b[j][0] - b[0][0]));
        sum += std::abs(slope) * r[i - 1];
      }
      R[k][j - 1] = sum;
    }
  }
  bool inside = true;
  for (int i = 0; i < n; ++i)
  {
    double yf = 0.0;
    for (int k = 0; k < n; ++k)
    {
      yf += Y[i][k] * F[k];
    }
    double spread = 0.0;
    for (int j = 0; j < n; ++j)
    {
      double identityMinusYJ = i == j ? 1.0 : 0.0;
      double absYR = 0.0;
      for (int k = 0; k < n; ++k)
      {
        identityMinusYJ -= Y[i][k] * J[k][j];
        absYR += std::abs(Y[i][k]) * R[k][j];
      }
      spread += (std::abs(identityMinusYJ) + absYR) * r[j];
    }
    image[i][0] = m[i + 1] - yf - spread * (1.0 + 1e-9);
    image[i][1] = m[i + 1] - yf + spread * (1.0 + 1e-9);
    if (std::abs(yf) > (spread + r[i]) * (1.0 + 1e-9))
    {
      return Krawczyk::None; // K(X) misses X along y_i
    }
    inside = inside && (std::abs(yf) + spread) * (1.0 + 1e-9) < r[i];
  }
  return inside ? Krawczyk::Unique : Krawczyk::Unknown;
}

template <int n>
bool insideSimplex(const double L[4], double tolerance)
{
  for (int i = 0; i <= n; ++i)
  {
    if (!(L[i] >= -tolerance))
    {
      return false;
    }
  }
  return true;
}

/// The two halves of a piece, split at the midpoint of its longest edge (in barycentric
/// coordinates); they inherit its depth + 1 and its candidate levels.
template <int n>
void bisect(const Piece& piece, Piece children[2])
{
  int ea = 0, eb = 1;
  double longest = -1.0;
  for (int a = 0; a <= n; ++a)
  {
    for (int b = a + 1; b <= n; ++b)
    {
      double length = 0.0;
      for (int i = 0; i <= n; ++i)
      {
        const double d = piece.V[a][i] - piece.V[b][i];
        length += d * d;
      }
      if (length > longest)
      {
        longest = length;
        ea = a;
        eb = b;
      }
    }
  }
  children[0] = children[1] = piece;
  for (int i = 0; i <= n; ++i)
  {
    const double mid = 0.5 * (piece.V[ea][i] + piece.V[eb][i]);
    children[0].V[eb][i] = mid;
    children[1].V[ea][i] = mid;
  }
  children[0].depth = children[1].depth = piece.depth + 1;
}

/// A piece's centre m (barycentric) and, if wanted, the half-widths r of the box around it in
/// y = (L_1..L_n).
template <int n>
void centreOf(const Piece& piece, double m[4], double* r = nullptr)
{
  for (int i = 0; i < 4; ++i)
  {
    m[i] = 0.0;
  }
  for (int v = 0; v <= n; ++v)
  {
    for (int i = 0; i <= n; ++i)
    {
      m[i] += piece.V[v][i] / (n + 1);
    }
  }
  if (r)
  {
    for (int i = 0; i < n; ++i)
    {
      r[i] = 0.0;
      for (int v = 0; v <= n; ++v)
      {
        r[i] = std::max(r[i], std::abs(piece.V[v][i + 1] - m[i + 1]));
      }
    }
  }
}

/// Pushes the two halves, the one whose centre has the smaller objective last (popped first).
template <int n>
void pushNearerLast(Piece* stack, int& top, const Piece children[2], const BernsteinForm* objective)
{
  int nearer = 0;
  if (objective)
  {
    double centre[2][4];
    centreOf<n>(children[0], centre[0]);
    centreOf<n>(children[1], centre[1]);
    nearer = objective->bilinear(centre[1], centre[1], n) < objective->bilinear(centre[0], centre[0], n);
  }
  stack[top++] = children[1 - nearer];
  stack[top++] = children[nearer];
}

template <int n>
bool solve(const BernsteinForm* given, const BernsteinForm* objective, double lo, double hi,
  double tolerance, SimplexRoot& root, const SolveLimits& limits, int* pieces,
  const Levels& levels)
{
  // The equations being solved; with levels, the last is the given form minus the current level.
  BernsteinForm equations[3];
  for (int k = 0; k < n; ++k)
  {
    equations[k] = given[k];
  }
  // Rounding of a blossom of coefficients up to M with weights in [0, 1] summing to 1 stays below
  // a few ulps of M: coefficients within this pad of 0 do not prove a sign.
  double pad[3];
  for (int k = 0; k < n; ++k)
  {
    pad[k] = 64.0 * kEpsilon * magnitude<n>(equations[k]);
  }
  const bool multiLevel = levels.count > 0;
  const double levelPad = pad[n - 1];
  int currentLevel = -1;
  bool found = false;
  double best = hi;
  // Keeps L (a root of the current level inside the simplex) if it is the nearest so far.
  auto keep = [&](const double L[4], bool certified) {
    const double value = objective ? objective->bilinear(L, L, n) : 0.0;
    if (objective && !(value >= lo && value <= best))
    {
      return false;
    }
    found = true;
    best = value;
    for (int i = 0; i < 4; ++i)
    {
      root.L[i] = i <= n ? L[i] : 0.0;
    }
    root.value = value;
    root.certified = certified;
    root.level = currentLevel;
    return true;
  };
  auto setLevel = [&](int level) {
    if (level != currentLevel)
    {
      equations[n - 1] = given[n - 1].minus(levels.values[level] * levels.scale);
      pad[n - 1] = 64.0 * kEpsilon * magnitude<n>(equations[n - 1]);
      currentLevel = level;
    }
  };
  if (!multiLevel)
  {
    currentLevel = 0;
  }
  const double objectivePad = objective ? 64.0 * kEpsilon * magnitude<n>(*objective) : 0.0;

  // Depth-first, nearer child first; at most one pending sibling per level.
  Piece stack[64 + 2];
  int top = 0;
  Piece& first = stack[top++];
  for (int i = 0; i <= n; ++i)
  {
    for (int j = 0; j <= n; ++j)
    {
      first.V[i][j] = i == j ? 1.0 : 0.0;
    }
  }
  first.depth = 0;
  first.levelLo = 0;
  first.levelHi = multiLevel ? levels.count : 1;
  const int maxDepth = std::min(limits.maxDepth, 64);
  // Separating many levels takes pieces along the ray: the budget grows with them (to 64 x).
  const int maxPieces = limits.maxPieces * (multiLevel ? std::min(levels.count, 64) : 1);

  int visited = 0;
  // Whether one of equations [0, count) has Bernstein coefficients of one sign on the piece.
  auto signFixed = [&](const Piece& piece, int count) {
    for (int k = 0; k < count; ++k)
    {
      double cLo, cHi;
      coefficientRange<n>(equations[k], piece, cLo, cHi);
      if (cLo > pad[k] || cHi < -pad[k])
      {
        return true;
      }
    }
    return false;
  };
  // Whether the piece's depth bound lies beyond the nearest root found, or before the window.
  auto outsideWindow = [&](const Piece& piece) {
    if (!objective)
    {
      return false;
    }
    double oLo, oHi;
    coefficientRange<n>(*objective, piece, oLo, oHi);
    return oLo > best + objectivePad || oHi < lo - objectivePad;
  };
  // Boxes proven to hold exactly one root, each already found: a piece inside one holds no other
  // root, so it is dropped (without them, the pieces next to a root, which cannot be certified
  // because the root is not theirs and cannot be excluded because they touch it, are bisected
  // level after level).
  struct KnownBox
  {
    double lo[3], hi[3];
    int level;
  };
  KnownBox known[8];
  int knownCount = 0;
  while (top > 0)
  {
    Piece piece = stack[--top];
    ++visited;
    const bool last = piece.depth >= maxDepth || visited >= maxPieces;
    if (multiLevel)
    {
      // The equations other than the field's first (they do not depend on the level).
      if (signFixed(piece, n - 1))
      {
        continue;
      }
      // The levels within the field's Bernstein range on this piece.
      double fLo, fHi;
      coefficientRange<n>(given[n - 1], piece, fLo, fHi);
      const double* begin = levels.values + piece.levelLo;
      const double* end = levels.values + piece.levelHi;
      piece.levelLo = static_cast<int>(
        std::lower_bound(begin, end, (fLo - levelPad) / levels.scale) - levels.values);
      piece.levelHi = static_cast<int>(
        std::upper_bound(begin, end, (fHi + levelPad) / levels.scale) - levels.values);
      if (piece.levelLo >= piece.levelHi)
      {
        continue;
      }
      if (piece.levelHi - piece.levelLo > 1)
      {
        if (outsideWindow(piece))
        {
          continue;
        }
        if (!last)
        {
          // Several levels still possible: bisect until each piece keeps one (or none).
          Piece children[2];
          bisect<n>(piece, children);
          pushNearerLast<n>(stack, top, children, objective);
          continue;
        }
        // At the limit with several levels: Newton for each, uncertified.
        double m[4], r[3];
        centreOf<n>(piece, m, r);
        for (int level = piece.levelLo; level < piece.levelHi; ++level)
        {
          setLevel(level);
          double L[4] = { m[0], m[1], m[2], m[3] };
          bool near = newton<n>(equations, L);
          for (int i = 1; i <= n; ++i)
          {
            near = near && std::abs(L[i] - m[i]) <= 2.0 * r[i - 1] + tolerance; // this piece's root
          }
          if (near && insideSimplex<n>(L, tolerance))
          {
            keep(L, false);
          }
        }
        continue;
      }
      setLevel(piece.levelLo);
    }
    bool covered = false;
    for (int b = 0; b < knownCount && !covered; ++b)
    {
      covered = known[b].level == currentLevel;
      for (int v = 0; v <= n && covered; ++v)
      {
        for (int i = 1; i <= n; ++i)
        {
          covered = covered && piece.V[v][i] >= known[b].lo[i - 1] && piece.V[v][i] <= known[b].hi[i - 1];
        }
      }
    }
    if (covered)
    {
      continue;
    }
    // Beyond the nearest root found, or before the window: nothing to find.
    if (signFixed(piece, n) || outsideWindow(piece))
    {
      continue;
    }
    bool empty = false;
    // The same test on the equations preconditioned by the inverse Jacobian at the piece's
    // centre (Y F, a combination of forms is a form): near a simple root each is about one
    // coordinate's distance to it, so their convex hulls shut out far more than the raw ones.
    // The piece's centre and the half-widths of the box around it, in y = (L_1..L_n).
    double m[4], r[3];
    centreOf<n>(piece, m, r);
    // Whether a Krawczyk test is worth its cost: when each preconditioned equation varies over
    // the piece by little more than the piece's own width (it is then close to linear there).
    bool promising = false;
    double centreValues[3][3][3]; // F (row 0), J, J^-1 at m, for the first Krawczyk test
    bool haveCentre = false;
    {
      double F[3], J[3][3], Y[3][3];
      evaluate<n>(equations, m, F, J);
      if (invert<n>(J, Y))
      {
        promising = true;
        haveCentre = true;
        for (int i = 0; i < n; ++i)
        {
          centreValues[0][0][i] = F[i];
          for (int j = 0; j < n; ++j)
          {
            centreValues[1][i][j] = J[i][j];
            centreValues[2][i][j] = Y[i][j];
          }
        }
        for (int i = 0; i < n && !empty; ++i)
        {
          BernsteinForm combined{};
          double combinedPad = 0.0;
          for (int k = 0; k < n; ++k)
          {
            for (int a = 0; a <= n; ++a)
            {
              for (int b = 0; b <= n; ++b)
              {
                combined.b[a][b] += Y[i][k] * equations[k].b[a][b];
              }
            }
            combinedPad += std::abs(Y[i][k]) * pad[k];
          }
          double cLo, cHi;
          coefficientRange<n>(combined, piece, cLo, cHi);
          // Rounding of the combination itself: a few ulps of its terms.
          combinedPad = 2.0 * combinedPad + 64.0 * kEpsilon * magnitude<n>(combined);
          empty = cLo > combinedPad || cHi < -combinedPad;
          promising = promising && cHi - cLo <= 6.0 * r[i];
        }
      }
    }
    if (empty)
    {
      continue;
    }
    // Interval Newton: the roots in the box lie in its Krawczyk image too, so the box shrinks
    // to their intersection while that helps (quadratically, near a simple root).
    Krawczyk test = Krawczyk::Unknown;
    for (int contraction = 0; contraction < ((promising || last) ? 8 : 0); ++contraction)
    {
      double image[3][2];
      test = krawczyk<n>(equations, m, r, image, contraction == 0 && haveCentre ? centreValues : nullptr);
      if (test != Krawczyk::Unknown)
      {
        break;
      }
      double shrink = 0.0, sum = 0.0;
      for (int i = 0; i < n; ++i)
      {
        const double lo = std::max(m[i + 1] - r[i], image[i][0]);
        const double hi = std::min(m[i + 1] + r[i], image[i][1]);
        shrink = std::max(shrink, (hi - lo) / (2.0 * r[i]));
        m[i + 1] = 0.5 * (lo + hi);
        // Not below 1e-9 of the cell: an equation linear in y_i contracts its width to zero,
        // and a box of zero width could never be proven to hold its root.
        r[i] = std::max(0.5 * (hi - lo), 1e-9);
        sum += m[i + 1];
      }
      m[0] = 1.0 - sum;
      if (shrink > 0.7)
      {
        break;
      }
    }
    if (test == Krawczyk::None)
    {
      continue;
    }
    const bool certified = test == Krawczyk::Unique;
    if (certified || last)
    {
      double L[4] = { m[0], m[1], m[2], m[3] };
      bool converged = newton<n>(equations, L);
      if (converged && !certified)
      {
        // Uncertified: accept only a root near this piece.
        for (int i = 1; i <= n; ++i)
        {
          converged = converged && std::abs(L[i] - m[i]) <= 2.0 * r[i - 1] + tolerance;
        }
      }
      if (converged && certified)
      {
        // The largest box around the root (doubling) where it is still proven the only one.
        KnownBox box;
        box.level = currentLevel;
        for (int i = 0; i < n; ++i)
        {
          box.lo[i] = m[i + 1] - r[i];
          box.hi[i] = m[i + 1] + r[i];
        }
        double radius = 0.0;
        for (int i = 0; i < n; ++i)
        {
          radius = std::max(radius, r[i]);
        }
        for (int grow = 0; grow < 12; ++grow)
        {
          radius *= 1.5;
          double c[4] = { L[0], L[1], L[2], L[3] }, rr[3] = { radius, radius, radius }, image[3][2];
          if (krawczyk<n>(equations, c, rr, image) != Krawczyk::Unique)
          {
            break;
          }
          for (int i = 0; i < n; ++i)
          {
            box.lo[i] = L[i + 1] - radius;
            box.hi[i] = L[i + 1] + radius;
          }
        }
        known[knownCount < 8 ? knownCount++ : (visited % 8)] = box;
      }
      if (converged && insideSimplex<n>(L, tolerance) && keep(L, certified) && !objective)
      {
        break; // any root will do
      }
      continue;
    }
    Piece children[2];
    bisect<n>(piece, children);
    pushNearerLast<n>(stack, top, children, objective);
  }
  if (pieces)
  {
    *pieces = visited;
  }
  return found;
}
} // namespace

bool solveOnSimplex(int n, const BernsteinForm* equations, const BernsteinForm* objective,
  double lo, double hi, double tolerance, SimplexRoot& root, const SolveLimits& limits, int* pieces,
  const Levels& levels)
{
  return n == 2 ? solve<2>(equations, objective, lo, hi, tolerance, root, limits, pieces, levels)
                : solve<3>(equations, objective, lo, hi, tolerance, root, limits, pieces, levels);
}

CurvedGeometry CurvedGeometry::fromNodes(const glm::dvec3 nodes[10], double scale)
{
  CurvedGeometry g;
  g.origin = nodes[0];
  g.scale = scale;
  glm::dvec3 local[10];
  for (int k = 0; k < 10; ++k)
  {
    local[k] = (nodes[k] - nodes[0]) * scale;
  }
  for (int i = 0; i < 4; ++i)
  {
    g.control[i][i] = local[i];
  }
  for (int e = 0; e < 6; ++e)
  {
    const int a = kEdgeVertices[e][0], b = kEdgeVertices[e][1];
    g.control[a][b] = g.control[b][a] = 2.0 * local[4 + e] - 0.5 * (local[a] + local[b]);
  }
  return g;
}

glm::dvec3 CurvedGeometry::position(const double L[4]) const
{
  glm::dvec3 x(0.0);
  for (int i = 0; i < 4; ++i)
  {
    glm::dvec3 row(0.0);
    for (int j = 0; j < 4; ++j)
    {
      row += L[j] * control[i][j];
    }
    x += L[i] * row;
  }
  return x;
}

glm::dmat3 CurvedGeometry::jacobian(const double L[4]) const
{
  glm::dvec3 pl[4];
  for (int i = 0; i < 4; ++i)
  {
    pl[i] = glm::dvec3(0.0);
    for (int j = 0; j < 4; ++j)
    {
      pl[i] += L[j] * control[i][j];
    }
  }
  return glm::dmat3(2.0 * (pl[1] - pl[0]), 2.0 * (pl[2] - pl[0]), 2.0 * (pl[3] - pl[0]));
}

BernsteinForm CurvedGeometry::component(const glm::dvec3& axis, double offset) const
{
  BernsteinForm form{};
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      form.b[i][j] = glm::dot(axis, control[i][j]) - offset;
    }
  }
  return form;
}

void CurvedGeometry::pointEquations(const glm::dvec3& target, BernsteinForm equations[3]) const
{
  for (int k = 0; k < 3; ++k)
  {
    glm::dvec3 axis(0.0);
    axis[k] = 1.0;
    equations[k] = component(axis, target[k]);
  }
}

void CurvedGeometry::box(glm::dvec3& lo, glm::dvec3& hi) const
{
  lo = glm::dvec3(kInfinity);
  hi = glm::dvec3(-kInfinity);
  for (int i = 0; i < 4; ++i)
  {
    for (int j = i; j < 4; ++j)
    {
      lo = glm::min(lo, control[i][j]);
      hi = glm::max(hi, control[i][j]);
    }
  }
  lo = origin + lo / scale;
  hi = origin + hi / scale;
}

glm::dvec3 curvedGradient(const CurvedGeometry& geometry, const BernsteinForm& field,
  const double L[4])
{
  double g[3];
  formGradient<3>(field, L, g);
  const glm::dmat3 J = geometry.jacobian(L);
  const double det = glm::determinant(J);
  if (!(det != 0.0) || !std::isfinite(det))
  {
    return glm::dvec3(0.0);
  }
  // grad_y f = J^T grad_X f.
  return glm::inverse(glm::transpose(J)) * glm::dvec3(g[0], g[1], g[2]);
}

namespace
{
/// Column j (1..3) of the Jacobian evaluated at U (linear in U).
glm::dvec3 jacobianColumn(const CurvedGeometry& g, int j, const double U[4])
{
  glm::dvec3 c(0.0);
  for (int a = 0; a < 4; ++a)
  {
    c += (2.0 * U[a]) * (g.control[j][a] - g.control[0][a]);
  }
  return c;
}

/// The blossom of det J (a cubic) at U, V, W: the mean over the 6 ways of giving them to the
/// three columns.
double determinantBlossom(const CurvedGeometry& g, const double* U, const double* V, const double* W)
{
  const double* args[3] = { U, V, W };
  static constexpr int kPermutations[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 },
    { 2, 0, 1 }, { 2, 1, 0 } };
  double sum = 0.0;
  for (const auto& p : kPermutations)
  {
    sum += glm::determinant(glm::dmat3(jacobianColumn(g, 1, args[p[0]]),
      jacobianColumn(g, 2, args[p[1]]), jacobianColumn(g, 3, args[p[2]])));
  }
  return sum / 6.0;
}
} // namespace

JacobianSign jacobianSign(const CurvedGeometry& geometry)
{
  constexpr int kMaxDepth = 15;
  Piece stack[kMaxDepth + 2];
  int top = 0;
  Piece& first = stack[top++];
  for (int i = 0; i < 4; ++i)
  {
    for (int j = 0; j < 4; ++j)
    {
      first.V[i][j] = i == j ? 1.0 : 0.0;
    }
  }
  first.depth = 0;
  double tolerance = -1.0; // relative to the whole cell's coefficients
  int sign = 0;
  while (top > 0)
  {
    const Piece piece = stack[--top];
    double lo = kInfinity, hi = -kInfinity, largest = 0.0;
    for (int a = 0; a < 4; ++a)
    {
      for (int b = a; b < 4; ++b)
      {
        for (int c = b; c < 4; ++c)
        {
          const double coefficient =
            determinantBlossom(geometry, piece.V[a], piece.V[b], piece.V[c]);
          lo = std::min(lo, coefficient);
          hi = std::max(hi, coefficient);
          largest = std::max(largest, std::abs(coefficient));
        }
      }
    }
    if (!std::isfinite(lo) || !std::isfinite(hi))
    {
      return JacobianSign::Changes;
    }
    if (tolerance < 0.0)
    {
      tolerance = 1e-12 * largest;
    }
    int pieceSign = lo > tolerance ? 1 : hi < -tolerance ? -1 : 0;
    if (pieceSign != 0)
    {
      if (sign != 0 && pieceSign != sign)
      {
        return JacobianSign::Changes;
      }
      sign = pieceSign;
      continue;
    }
    // Values at the corners are values of det J: opposite signs (or a zero) prove a change.
    double cornerLo = kInfinity, cornerHi = -kInfinity;
    for (int a = 0; a < 4; ++a)
    {
      const double value = determinantBlossom(geometry, piece.V[a], piece.V[a], piece.V[a]);
      cornerLo = std::min(cornerLo, value);
      cornerHi = std::max(cornerHi, value);
    }
    if (cornerLo <= tolerance && cornerHi >= -tolerance)
    {
      return JacobianSign::Changes;
    }
    if ((sign > 0 && cornerHi < 0.0) || (sign < 0 && cornerLo > 0.0) || piece.depth >= kMaxDepth)
    {
      return JacobianSign::Changes;
    }
    Piece children[2];
    bisect<3>(piece, children);
    stack[top++] = children[0];
    stack[top++] = children[1];
  }
  return sign > 0 ? JacobianSign::Positive : JacobianSign::Negative;
}

bool inverseNewton(const CurvedGeometry& geometry, const glm::dvec3& target, double L[4])
{
  BernsteinForm equations[3];
  geometry.pointEquations(target, equations);
  return newton<3>(equations, L);
}

} // namespace tetdsr
