// The exact surface (ExactSurface.h): the conforming bisection of the cells that can hold an
// iso-value, each piece certified or bisected, then the pieces' triangles. The integrals are in
// ExactSurfaceIntegrals.cpp.
//
// Why a certified piece's triangles are within its bound of the surface (slabBound). In a
// tetrahedron T of a cell's reference space, let l be the affine function equal to the field f at
// T's corners and E a bound of |f - l| over T (from the bound G of f's gradient over T's box: along
// any of T's edge directions e, f and l have derivatives within e.G, and f - l is 0 at a corner).
// The surface f = c and the triangles (whose corners are roots on T's edges, so within E of l = c)
// both lie in the slab |l - c| <= E, of width w = 2E / |grad l|. With f monotone along n = grad l /
// |grad l| over T (n.G > 0), along an in-face direction in each face the slab meets, and along
// every edge the slab meets, the surface in T is a graph over the plane l = c, one disc bounded by
// the loop through the edges' roots that the marching-tetrahedra case joins; in each face its curve
// and the case's chord are graphs over the same segment within the face's strip of width w_F =
// 2E / |grad_F l|. Hence every point of either lies within w + 2 max w_F of the other (reference
// units), and in the scene within L (w + 2 max w_F) + X, L bounding |dx/dr| over T and X the
// distance between the map of a reference triangle and the flat one through its corners' images.
#include "tetdsr/surface/ExactSurface.h"

#include "tetdsr/cells/Cells.h"
#include "tetdsr/surface/ExactSurfaceCells.h"
#include "tetdsr/surface/ExactSurfaceIntegrals.h"
#include "tetdsr/input/Settings.h"

#include <algorithm>
#include <array>
#include <initializer_list>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <unordered_map>

namespace tetdsr
{
namespace exact
{
namespace
{

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

std::uint64_t edgeKey(std::uint32_t a, std::uint32_t b)
{
  return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}

struct KeyHash
{
  std::size_t operator()(std::uint64_t k) const { return std::hash<std::uint64_t>()(k * 0x9E3779B97F4A7C15ull); }
};

struct FaceKey
{
  std::array<std::uint32_t, 4> v;
  bool operator==(const FaceKey& o) const { return v == o.v; }
};
struct FaceKeyHash
{
  std::size_t operator()(const FaceKey& k) const
  {
    std::uint64_t h = 1469598103934665603ull;
    for (auto x : k.v)
      h = (h ^ x) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

/// A point of the bisection: named by its index, shared by every cell that reaches it.
struct Vertex
{
  glm::dvec3 x;
  double f;
};

enum class State : std::uint8_t
{
  New,
  Empty,      ///< holds no iso-value
  Resolved,   ///< certified for every iso-value it holds
  Split,      ///< to be bisected
  Unresolved  ///< at the level limit, not certified
};

struct Piece
{
  std::uint32_t form; ///< the cell's position in the candidates
  std::uint32_t v[4];
  glm::dvec3 r[4];    ///< the corners' reference points in that cell
  std::uint8_t level;
  State state;
  double bound;
  bool sizeOnly; ///< certified by its size alone (its topology not)
};

constexpr int kEdges[6][2] = { { 0, 1 }, { 0, 2 }, { 0, 3 }, { 1, 2 }, { 1, 3 }, { 2, 3 } };
constexpr int kFaces[4][3] = { { 1, 2, 3 }, { 0, 2, 3 }, { 0, 1, 3 }, { 0, 1, 2 } };

double largestAbs(const Interval& i)
{
  return std::max(std::abs(i.lo), std::abs(i.hi));
}

/// The bounds of d . G.
Interval dot(const glm::dvec3& d, const Interval G[3])
{
  Interval s{ 0.0, 0.0 };
  for (int i = 0; i < 3; ++i)
  {
    if (d[i] == 0.0)
      continue;
    const double a = d[i] * G[i].lo, b = d[i] * G[i].hi;
    s.lo += std::min(a, b);
    s.hi += std::max(a, b);
  }
  return s;
}

bool signDefinite(const Interval& i)
{
  return i.lo > 0.0 || i.hi < 0.0;
}

/// The matrix taking a polynomial's values at k / D (k = 0..D) to its Bernstein coefficients of
/// degree D (the inverse of B_j^D(k / D)), for D up to 12; made once per degree.
const std::vector<double>& bernsteinFromSamples(int D)
{
  static std::mutex mutex;
  static std::vector<double> made[13];
  const std::lock_guard<std::mutex> lock(mutex);
  std::vector<double>& m = made[D];
  if (m.empty())
  {
    const int n = D + 1;
    std::vector<long double> a(static_cast<std::size_t>(n * n)), inv(static_cast<std::size_t>(n * n), 0.0L);
    for (int k = 0; k < n; ++k)
    {
      const long double t = static_cast<long double>(k) / D;
      for (int j = 0; j < n; ++j)
      {
        long double binomial = 1.0L;
        for (int i = 0; i < j; ++i)
          binomial = binomial * (D - i) / (i + 1);
        a[static_cast<std::size_t>(k * n + j)] = binomial * std::pow(t, j) * std::pow(1.0L - t, D - j);
      }
      inv[static_cast<std::size_t>(k * n + k)] = 1.0L;
    }
    // Gauss-Jordan with partial pivoting.
    for (int col = 0; col < n; ++col)
    {
      int pivot = col;
      for (int r = col + 1; r < n; ++r)
        if (std::abs(a[static_cast<std::size_t>(r * n + col)]) > std::abs(a[static_cast<std::size_t>(pivot * n + col)]))
          pivot = r;
      for (int c2 = 0; c2 < n; ++c2)
      {
        std::swap(a[static_cast<std::size_t>(col * n + c2)], a[static_cast<std::size_t>(pivot * n + c2)]);
        std::swap(inv[static_cast<std::size_t>(col * n + c2)], inv[static_cast<std::size_t>(pivot * n + c2)]);
      }
      const long double d = a[static_cast<std::size_t>(col * n + col)];
      for (int c2 = 0; c2 < n; ++c2)
      {
        a[static_cast<std::size_t>(col * n + c2)] /= d;
        inv[static_cast<std::size_t>(col * n + c2)] /= d;
      }
      for (int r = 0; r < n; ++r)
      {
        if (r == col)
          continue;
        const long double f = a[static_cast<std::size_t>(r * n + col)];
        for (int c2 = 0; c2 < n; ++c2)
        {
          a[static_cast<std::size_t>(r * n + c2)] -= f * a[static_cast<std::size_t>(col * n + c2)];
          inv[static_cast<std::size_t>(r * n + c2)] -= f * inv[static_cast<std::size_t>(col * n + c2)];
        }
      }
    }
    m.assign(inv.begin(), inv.end());
  }
  return m;
}

/// What the Bernstein coefficients of f - c along the reference segment r0 -> r1 allow
/// (Descartes' rule for Bernstein forms: no more roots inside than sign changes). An end whose
/// coefficient (its value) is within rounding of 0 is a root there; the other coefficients'
/// sign changes bound the roots inside. A pyramid's field is rational along lines of its own
/// space: with s = 1 - z (linear along the segment, positive off the apex), the collapse's
/// u = 1/2 + (x - 1/2) / s makes each of the form's degree-P factors in u and v a polynomial
/// over s^P, so s^2P (f - c), of degree 3P (lineDegree), has the same roots off the apex.
struct SegmentRoots
{
  int inside = -1;         ///< the sign changes inside; -1: a coefficient within rounding of 0
  bool atStart = false;    ///< f = c at r0 (to rounding)
  bool atEnd = false;      ///< f = c at r1 (to rounding)
  bool everywhere = false; ///< every coefficient within rounding of 0: f = c along the segment

  /// Whether the segment holds the marching case's roots: one where its ends' sides differ
  /// (f >= c counts as above; a root at an end is that end), none where they agree, or the
  /// whole segment in the surface.
  bool asCase(bool crossed) const
  {
    if (everywhere)
      return true;
    if (inside == 0)
      return !(atStart && atEnd) && (!crossed || atStart || atEnd);
    return inside == 1 && crossed && !atStart && !atEnd;
  }
};

SegmentRoots segmentRoots(const CellForms& forms, const glm::dvec3& r0, const glm::dvec3& r1, double c, int degree, double margin)
{
  SegmentRoots out;
  if (degree > 12)
    return out;
  const std::vector<double>& m = bernsteinFromSamples(degree);
  const int n = degree + 1;
  const bool pyramid = forms.type().space == Space::Pyramid;
  const int power = 2 * forms.type().degree;
  double samples[13], coefficients[13];
  for (int k = 0; k < n; ++k)
  {
    const glm::dvec3 r = r0 + (double(k) / degree) * (r1 - r0);
    samples[k] = forms.fieldAtReference(r) - c;
    if (pyramid)
      samples[k] *= std::pow(std::max(0.0, 1.0 - r.z), power);
  }
  // The conversion grows the samples' rounding by its row sums (at most about 1e4 for degree
  // 12): a coefficient within 1e-10 of the samples' magnitude (plus the forms' rounding) has
  // no sign of its own.
  double largest = 0.0;
  for (int k = 0; k < n; ++k)
    largest = std::max(largest, std::abs(samples[k]));
  const double zero = 1e-10 * largest + margin;
  bool allZero = true;
  for (int j = 0; j < n; ++j)
  {
    double sum = 0.0;
    for (int k = 0; k < n; ++k)
      sum += m[static_cast<std::size_t>(j * n + k)] * samples[k];
    coefficients[j] = sum;
    allZero = allZero && std::abs(sum) <= zero;
  }
  if (allZero)
  {
    out.everywhere = true;
    return out;
  }
  out.atStart = std::abs(coefficients[0]) <= zero;
  out.atEnd = std::abs(coefficients[n - 1]) <= zero;
  // A root at an end: f - c = t g (or (1 - t) g), whose coefficients have the others' signs.
  const int first = out.atStart ? 1 : 0, last = out.atEnd ? n - 2 : n - 1;
  int changes = 0;
  for (int j = first; j <= last; ++j)
  {
    if (std::abs(coefficients[j]) <= zero)
      return out; // inside stays -1
    if (j > first && (coefficients[j] > 0.0) != (coefficients[j - 1] > 0.0))
      ++changes;
  }
  out.inside = changes;
  return out;
}

/// The degree of a cell's field along a line of its reference space: P for a tetrahedron (total
/// degree P), 2P for a wedge (P on the triangle, P along the axis), 3P for a cube.
int lineDegree(const FormMatrix& type)
{
  return type.space == Space::Tetrahedron ? type.degree : type.space == Space::Wedge ? 2 * type.degree : 3 * type.degree;
}

/// The root of f = c on the reference segment r0 -> r1, where f - c changes sign (rising: from
/// below): Newton's method inside a shrinking bracket, bisection when a step leaves it.
double edgeRoot(const CellForms& forms, const glm::dvec3& r0, const glm::dvec3& r1, double c, bool rising)
{
  double lo = 0.0, hi = 1.0, t = 0.5;
  for (int iteration = 0; iteration < 200; ++iteration)
  {
    glm::dvec3 x, grad;
    glm::dmat3 J;
    double f = 0.0;
    forms.atReference(r0 + t * (r1 - r0), x, J, f, grad);
    const double g = f - c;
    if (g == 0.0 || !std::isfinite(g))
      break;
    if ((g < 0.0) == rising)
      lo = t;
    else
      hi = t;
    if (hi - lo <= 4.0 * std::numeric_limits<double>::epsilon())
      break;
    const double slope = glm::dot(grad, r1 - r0);
    double next = slope != 0.0 ? t - g / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi))
      next = 0.5 * (lo + hi);
    if (next == t)
      break;
    t = next;
  }
  return t;
}

class Extraction
{
public:
  Extraction(const Scene& scene, const ExactSurfaceSettings& settings, double tolerance)
    : Scene_(scene)
    , Iso(settings.isoValues)
    , Tolerance(tolerance)
  {
  }

  void run(const ParallelFor& parallelFor, ExactSurfaceMesh& surface, SurfaceParts& parts);

private:
  std::uint32_t meshVertex(NodeId point);
  std::uint32_t newVertex(const CellForms& forms, const glm::dvec3& r);
  std::uint32_t midpoint(const Piece& piece, int a, int b);
  void startCell(std::uint32_t form);
  void bisect(std::size_t index);
  bool hanging(const Piece& piece) const;
  void classify(Piece& piece);
  bool certify(const Piece& piece, const CellForms::Bounds& b, std::size_t iso, double margin, double& bound,
    bool& topology) const;
  std::uint32_t root(const Piece& piece, int a, int b, std::size_t iso);
  void caseTriangles(const Piece& piece, std::size_t iso, std::vector<std::array<int, 6>>& out) const;
  glm::dvec3 ellGradient(const Piece& piece) const;
  void emit(ExactSurfaceMesh& surface, SurfaceParts& parts);

  const Scene& Scene_;
  std::vector<double> Iso;
  double Tolerance;
  std::vector<CellForms> Forms;
  std::vector<Vertex> Vertices;
  std::vector<std::uint32_t> PointVertex; ///< per mesh point (merged by position): its vertex
  std::unordered_map<std::uint64_t, std::uint32_t, KeyHash> Midpoints;
  std::unordered_map<FaceKey, std::uint32_t, FaceKeyHash> FaceCentres;
  std::vector<Piece> Pieces;
  /// The pieces (by index; a stale entry is checked on use) having each edge, and the pieces to
  /// look at for a bisected edge (the conforming closure's work list).
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>, KeyHash> EdgePieces;
  std::vector<std::uint32_t> Closure;
  void registerEdges(std::uint32_t index);
  /// Per iso-value: a root's output vertex by edge (its ends' vertices; a vertex at the
  /// iso-value by itself twice).
  std::vector<std::unordered_map<std::uint64_t, std::uint32_t, KeyHash>> Roots;
  std::vector<SurfaceVertex> Out;

public:
  bool BudgetReached = false;
};

std::uint32_t Extraction::meshVertex(NodeId point)
{
  std::uint32_t& slot = PointVertex[static_cast<std::size_t>(point)];
  if (slot == kNone)
  {
    const double* p = Scene_.mesh().points + 3 * point;
    slot = static_cast<std::uint32_t>(Vertices.size());
    Vertices.push_back({ glm::dvec3(p[0], p[1], p[2]), Scene_.mesh().values[point] });
  }
  return slot;
}

std::uint32_t Extraction::newVertex(const CellForms& forms, const glm::dvec3& r)
{
  glm::dvec3 x, grad;
  glm::dmat3 J;
  double f = 0.0;
  forms.atReference(r, x, J, f, grad);
  Vertices.push_back({ x, f });
  return static_cast<std::uint32_t>(Vertices.size() - 1);
}

std::uint32_t Extraction::midpoint(const Piece& piece, int a, int b)
{
  const std::uint64_t key = edgeKey(piece.v[a], piece.v[b]);
  const auto found = Midpoints.find(key);
  if (found != Midpoints.end())
    return found->second;
  const std::uint32_t v = newVertex(Forms[piece.form], 0.5 * (piece.r[a] + piece.r[b]));
  Midpoints.emplace(key, v);
  return v;
}

void Extraction::startCell(std::uint32_t form)
{
  const CellForms& forms = Forms[form];
  const FormMatrix& type = forms.type();
  std::vector<std::uint32_t> corner(type.corners.size());
  for (std::size_t c = 0; c < corner.size(); ++c)
    corner[c] = meshVertex(forms.ids()[c]);
  auto add = [&](std::array<std::uint32_t, 4> v, std::array<glm::dvec3, 4> r) {
    Piece piece{};
    piece.form = form;
    for (int k = 0; k < 4; ++k)
    {
      piece.v[k] = v[static_cast<std::size_t>(k)];
      piece.r[k] = r[static_cast<std::size_t>(k)];
    }
    piece.level = 0;
    piece.state = State::New;
    Pieces.push_back(piece);
    registerEdges(static_cast<std::uint32_t>(Pieces.size() - 1));
  };
  if (type.space == Space::Tetrahedron)
  {
    add({ corner[0], corner[1], corner[2], corner[3] },
      { type.corners[0], type.corners[1], type.corners[2], type.corners[3] });
    return;
  }
  // A centre, and a centre on each quadrilateral face (named by its corners: a neighbour's is
  // the same vertex); a tetrahedron from the centre to each face triangle.
  glm::dvec3 centre(0.0);
  for (const auto& p : type.corners)
    centre += p;
  centre /= static_cast<double>(type.corners.size());
  const std::uint32_t middle = newVertex(forms, centre);
  for (const auto& face : type.faces)
  {
    if (face.size() == 3)
    {
      add({ middle, corner[face[0]], corner[face[1]], corner[face[2]] },
        { centre, type.corners[face[0]], type.corners[face[1]], type.corners[face[2]] });
      continue;
    }
    FaceKey key{ { corner[face[0]], corner[face[1]], corner[face[2]], corner[face[3]] } };
    std::sort(key.v.begin(), key.v.end());
    glm::dvec3 faceCentre(0.0);
    for (int c : face)
      faceCentre += type.corners[static_cast<std::size_t>(c)];
    faceCentre *= 0.25;
    auto found = FaceCentres.find(key);
    std::uint32_t fc;
    if (found == FaceCentres.end())
    {
      fc = newVertex(forms, faceCentre);
      FaceCentres.emplace(key, fc);
    }
    else
      fc = found->second;
    for (int e = 0; e < 4; ++e)
    {
      const int a = face[static_cast<std::size_t>(e)], b = face[static_cast<std::size_t>((e + 1) % 4)];
      add({ middle, fc, corner[static_cast<std::size_t>(a)], corner[static_cast<std::size_t>(b)] },
        { centre, faceCentre, type.corners[static_cast<std::size_t>(a)], type.corners[static_cast<std::size_t>(b)] });
    }
  }
}

/// Bisects a piece at its longest edge in the scene (ties by the ends' names): the rule both
/// cells sharing an edge apply alike.
void Extraction::bisect(std::size_t index)
{
  Piece piece = Pieces[index];
  int best = 0;
  double longest = -1.0;
  std::uint64_t bestKey = 0;
  for (int e = 0; e < 6; ++e)
  {
    const int a = kEdges[e][0], b = kEdges[e][1];
    const glm::dvec3 d = Vertices[piece.v[a]].x - Vertices[piece.v[b]].x;
    const double length = glm::dot(d, d);
    const std::uint64_t key = edgeKey(piece.v[a], piece.v[b]);
    if (length > longest || (length == longest && key < bestKey))
    {
      longest = length;
      best = e;
      bestKey = key;
    }
  }
  const int a = kEdges[best][0], b = kEdges[best][1];
  const std::uint32_t m = midpoint(piece, a, b);
  const glm::dvec3 rm = 0.5 * (piece.r[a] + piece.r[b]);
  Piece first = piece, second = piece;
  first.v[b] = m;
  first.r[b] = rm;
  second.v[a] = m;
  second.r[a] = rm;
  first.level = second.level = static_cast<std::uint8_t>(piece.level + 1);
  first.state = second.state = State::New;
  Pieces[index] = first;
  Pieces.push_back(second);
  const auto second_ = static_cast<std::uint32_t>(Pieces.size() - 1);
  registerEdges(static_cast<std::uint32_t>(index));
  registerEdges(second_);
  // Every piece with the bisected edge now has a point in its middle: it must be bisected too.
  for (std::uint32_t other : EdgePieces[bestKey])
    Closure.push_back(other);
  Closure.push_back(static_cast<std::uint32_t>(index));
  Closure.push_back(second_);
}

void Extraction::registerEdges(std::uint32_t index)
{
  const Piece& piece = Pieces[index];
  for (const auto& e : kEdges)
  {
    auto& list = EdgePieces[edgeKey(piece.v[e[0]], piece.v[e[1]])];
    if (list.empty() || list.back() != index)
      list.push_back(index);
  }
}

/// The gradient of the affine function equal to the field at the piece's corners (reference).
glm::dvec3 Extraction::ellGradient(const Piece& piece) const
{
  glm::dmat3 A;
  for (int j = 0; j < 3; ++j)
    A[j] = piece.r[j + 1] - piece.r[0];
  const double f0 = Vertices[piece.v[0]].f;
  const glm::dvec3 df(Vertices[piece.v[1]].f - f0, Vertices[piece.v[2]].f - f0, Vertices[piece.v[3]].f - f0);
  return glm::inverse(glm::transpose(A)) * df;
}

bool Extraction::hanging(const Piece& piece) const
{
  for (const auto& e : kEdges)
  {
    if (Midpoints.count(edgeKey(piece.v[e[0]], piece.v[e[1]])))
      return true;
  }
  return false;
}

/// Whether the piece is certified for iso-value c, its distance bound, and whether its topology
/// is certified too (the file's comment); else, when small, by its size alone.
bool Extraction::certify(const Piece& piece, const CellForms::Bounds& b, std::size_t iso, double margin,
  double& bound, bool& topology) const
{
  const double c = Iso[iso];
  const CellForms& forms = Forms[piece.form];
  double fv[4];
  bool cut = false;
  for (int k = 0; k < 4; ++k)
  {
    fv[k] = Vertices[piece.v[k]].f - c;
    cut = cut || ((fv[k] >= 0.0) != (fv[0] >= 0.0));
  }
  // Where the gradient has no bound (a pyramid's piece at its apex, where the collapse's
  // derivative is unbounded): by size alone, the box around the piece's image.
  if (!b.finite)
  {
    topology = false;
    bound = glm::length(glm::dvec3(b.x[0].width(), b.x[1].width(), b.x[2].width()));
    return std::isfinite(bound) && bound <= (cut ? Tolerance : 0.5 * Tolerance);
  }
  // E: |f - l| over the piece, from the corner whose edges give the least.
  double E = std::numeric_limits<double>::infinity();
  double diameter = 0.0;
  for (int base = 0; base < 4; ++base)
  {
    double worst = 0.0;
    for (int j = 0; j < 4; ++j)
    {
      if (j == base)
        continue;
      const glm::dvec3 e = piece.r[j] - piece.r[base];
      diameter = std::max(diameter, glm::length(e));
      double s = 0.0;
      for (int i = 0; i < 3; ++i)
        s += std::abs(e[i]) * b.grad[i].width();
      worst = std::max(worst, s);
    }
    E = std::min(E, worst);
  }
  // Second order where the second derivatives are bounded: |f - l| <= K/2 sum l_i |r_i - r|^2,
  // and that sum is at most the enclosing ball's radius squared, 3/8 of the diameter squared.
  if (b.hasHessian)
    E = std::min(E, 3.0 / 16.0 * b.fieldHessian * diameter * diameter);
  // Or directly: |f - l| over the piece's box, from the Bernstein coefficients of f - l there (a
  // pyramid's field, whose derivatives' bounds through the collapse are loose, gets it too).
  glm::dmat3 A;
  for (int j = 0; j < 3; ++j)
    A[j] = piece.r[j + 1] - piece.r[0];
  const glm::dmat3 AinvT = glm::inverse(glm::transpose(A));
  glm::dvec3 boxLo = piece.r[0], boxHi = piece.r[0];
  for (int k = 1; k < 4; ++k)
  {
    boxLo = glm::min(boxLo, piece.r[k]);
    boxHi = glm::max(boxHi, piece.r[k]);
  }
  const glm::dvec3 g = AinvT * glm::dvec3(fv[1] - fv[0], fv[2] - fv[0], fv[3] - fv[0]);
  E = std::min(E, forms.deviation(boxLo, boxHi, 3, fv[0] + c - glm::dot(g, piece.r[0]), g));
  // An affine cell (the map's derivative constant to rounding): the same in the scene, where the
  // second derivatives and the diameter are those of the shape itself (J^-T H J^-1; Gershgorin's
  // row sums bound its norm), and the slab's and strips' widths are scene distances.
  glm::dmat3 Jm(0.0);
  double jScale = 0.0, jWidth = 0.0;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i)
    {
      Jm[i][k] = 0.5 * (b.J[k][i].lo + b.J[k][i].hi);
      jScale = std::max(jScale, largestAbs(b.J[k][i]));
      jWidth = std::max(jWidth, b.J[k][i].width());
    }
  const bool constantJ = b.hasHessian && jWidth <= 1e-12 * jScale && std::abs(glm::determinant(Jm)) > 0.0;
  // Else the map's distance from its own affine interpolant of the corners (per axis): the piece
  // is straight when it is 0 to rounding (a straight pyramid's, whose Jacobian's bounds through
  // the collapse are not constant), and otherwise it bounds how far the flat triangles are from
  // the image of the piece's (twice it).
  double mapDeviation = 0.0;
  bool straight = false;
  glm::dmat3 Jcorners(0.0);
  if (!constantJ)
  {
    double mapScale = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double x0 = Vertices[piece.v[0]].x[a];
      const glm::dvec3 Ga = AinvT * glm::dvec3(Vertices[piece.v[1]].x[a] - x0, Vertices[piece.v[2]].x[a] - x0,
                                      Vertices[piece.v[3]].x[a] - x0);
      for (int i = 0; i < 3; ++i)
        Jcorners[i][a] = Ga[i];
      const double d = forms.deviation(boxLo, boxHi, a, x0 - glm::dot(Ga, piece.r[0]), Ga);
      mapDeviation += d * d;
      mapScale = std::max(mapScale, std::abs(x0) + glm::length(Ga));
    }
    mapDeviation = std::sqrt(mapDeviation);
    straight = mapDeviation <= 1e-12 * mapScale && std::abs(glm::determinant(Jcorners)) > 0.0;
    if (straight)
      Jm = Jcorners;
  }
  const bool affine = constantJ || straight;
  glm::dmat3 Jinv(1.0);
  if (affine)
    Jinv = glm::inverse(Jm);
  if (affine && b.hasHessian)
  {
    // J^-T H J^-1 with H = its middle + a part within the radius: the middle's product exactly
    // (its cancellations kept), the rest bounded in magnitude.
    glm::dmat3 middle, radius;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
      {
        middle[j][i] = 0.5 * (b.fieldSecond[i][j].lo + b.fieldSecond[i][j].hi);
        radius[j][i] = 0.5 * b.fieldSecond[i][j].width();
      }
    const glm::dmat3 product = glm::transpose(Jinv) * middle * Jinv;
    double K = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      double row = 0.0;
      for (int c2 = 0; c2 < 3; ++c2)
      {
        row += std::abs(product[c2][a]);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            row += std::abs(Jinv[a][i] * Jinv[c2][j]) * radius[j][i];
      }
      K = std::max(K, row);
    }
    double diameterX = 0.0;
    for (const auto& e : kEdges)
      diameterX = std::max(diameterX, glm::length(Jm * (piece.r[e[1]] - piece.r[e[0]])));
    E = std::min(E, 3.0 / 16.0 * K * diameterX * diameterX);
  }
  E += margin;
  // No sign change, and every corner beyond the slab: f - c keeps l - c's sign (|f - l| <= E).
  if (!cut && std::min({ std::abs(fv[0]), std::abs(fv[1]), std::abs(fv[2]), std::abs(fv[3]) }) > E)
  {
    bound = 0.0;
    topology = true;
    return true;
  }
  // grad l from the corners' values (g above: A^T g = df, A's columns the edges from corner 0).
  const double gl = glm::length(g);
  if (!(gl > 0.0) || !std::isfinite(gl))
  {
    topology = false;
    bound = glm::length(glm::dvec3(b.x[0].width(), b.x[1].width(), b.x[2].width()));
    return std::isfinite(bound) && bound <= (cut ? Tolerance : 0.5 * Tolerance);
  }
  const glm::dvec3 n = g / gl;
  // Where the surface can be: the slab |l - c| <= width within a simplex of the piece's corners
  // (the piece, a face, an edge), a convex polytope whose corners are the simplex's corners within
  // it and its edges' crossings of l = c +- width. Its box; false when it is empty.
  auto slabBox = [&](std::initializer_list<int> corners, double width, glm::dvec3& lo, glm::dvec3& hi) {
    lo = glm::dvec3(std::numeric_limits<double>::infinity());
    hi = -lo;
    bool any = false;
    auto take = [&](const glm::dvec3& p) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
      any = true;
    };
    for (auto i = corners.begin(); i != corners.end(); ++i)
    {
      if (std::abs(fv[*i]) <= width)
        take(piece.r[*i]);
      for (auto j = i + 1; j != corners.end(); ++j)
      {
        const double p = fv[*i], q = fv[*j];
        for (double level : { -width, width })
        {
          if ((p - level) * (q - level) < 0.0)
            take(piece.r[*i] + (level - p) / (q - p) * (piece.r[*j] - piece.r[*i]));
        }
      }
    }
    return any;
  };
  glm::dvec3 lo, hi;
  // Monotone along n where the surface can be: no closed sheet, no handle, a graph over l = c
  // (along every line along n, f - c has l - c's sign outside the slab).
  if (!slabBox({ 0, 1, 2, 3 }, E, lo, hi))
  {
    bound = 0.0;
    topology = true;
    return true;
  }
  Interval slope[2];
  forms.slopes(lo, hi, &n, 1, slope);
  if (!(slope[0].lo > 0.0))
  {
    // Not even monotone inside: by size alone (the box around the piece's image).
    topology = false;
    bound = glm::length(glm::dvec3(b.x[0].width(), b.x[1].width(), b.x[2].width()));
    return std::isfinite(bound) && bound <= (cut ? Tolerance : 0.5 * Tolerance);
  }
  topology = true;
  // Each face the slab meets: monotone along its in-face direction within the slab.
  double widest = 0.0;
  for (const auto& face : kFaces)
  {
    // |f - l| on the face alone (its box's Bernstein coefficients): the face's own slab.
    glm::dvec3 faceLo = glm::min(glm::min(piece.r[face[0]], piece.r[face[1]]), piece.r[face[2]]);
    glm::dvec3 faceHi = glm::max(glm::max(piece.r[face[0]], piece.r[face[1]]), piece.r[face[2]]);
    const double EF = std::min(E, forms.deviation(faceLo, faceHi, 3, fv[0] + c - glm::dot(g, piece.r[0]), g) + margin);
    if (!slabBox({ face[0], face[1], face[2] }, EF, lo, hi))
      continue;
    const glm::dvec3 normal = glm::normalize(glm::cross(piece.r[face[1]] - piece.r[face[0]], piece.r[face[2]] - piece.r[face[0]]));
    const glm::dvec3 inFace = g - glm::dot(g, normal) * normal;
    const double gf = glm::length(inFace);
    // Monotone along the in-face part of grad l, or of the gradient at the middle of the box.
    glm::dvec3 xm, middle;
    glm::dmat3 Jmiddle;
    double fm = 0.0;
    forms.atReference(0.5 * (lo + hi), xm, Jmiddle, fm, middle);
    middle -= glm::dot(middle, normal) * normal;
    const glm::dvec3 directions[2] = { gf > 0.0 ? inFace / gf : glm::dvec3(0.0),
      glm::length(middle) > 0.0 ? glm::normalize(middle) : glm::dvec3(0.0) };
    forms.slopes(lo, hi, directions, 2, slope);
    const bool alongL = gf > 0.0 && slope[0].lo > 0.0;
    const bool alongMiddle = glm::length(middle) > 0.0 && slope[1].lo > 0.0;
    if (!alongL && !alongMiddle)
    {
      topology = false;
      break;
    }
    // The loop of the surface's boundary runs on the faces with a sign change only (a monotone
    // face without one holds no curve): their strips bound it.
    const bool chord = (fv[face[0]] >= 0.0) != (fv[face[1]] >= 0.0) || (fv[face[0]] >= 0.0) != (fv[face[2]] >= 0.0);
    // The curve and the chord are graphs along the monotone direction d within the strip, so
    // at most the strip's width over the cosine of d's angle to the strip's normal apart.
    if (chord && affine)
    {
      // The strip's width in the scene: the in-face part of the scene gradient J^-T g.
      const glm::dvec3 gx = glm::transpose(Jinv) * g;
      const glm::dvec3 nx = glm::normalize(glm::transpose(Jinv) * normal);
      const glm::dvec3 gFx = gx - glm::dot(gx, nx) * nx;
      double cosine = 1.0;
      if (!alongL)
        cosine = std::abs(glm::dot(glm::normalize(Jm * glm::normalize(middle)), glm::normalize(gFx)));
      widest = std::max(widest, 2.0 * EF / glm::length(gFx) / cosine);
    }
    else if (chord)
    {
      const double cosine = alongL ? 1.0 : std::abs(glm::dot(glm::normalize(middle), inFace / gf));
      widest = std::max(widest, 2.0 * EF / gf / cosine);
    }
  }
  // Each edge: one root or none. Along an edge e, |f - l| <= e^T H e / 8 (its own second
  // derivative's bound); f is monotone where the edge is within that of c.
  for (const auto& e : kEdges)
  {
    if (!topology)
      break;
    const glm::dvec3 d = piece.r[e[1]] - piece.r[e[0]];
    double Ee = E;
    if (b.hasHessian)
    {
      double second = 0.0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          second += largestAbs(b.fieldSecond[i][j]) * std::abs(d[i] * d[j]);
      Ee = std::min(E, second / 8.0 + margin);
    }
    if (!slabBox({ e[0], e[1] }, Ee, lo, hi))
      continue;
    forms.slopes(lo, hi, &d, 1, slope);
    if (signDefinite(slope[0]))
      continue;
    // Not monotone there: the count Descartes' rule allows, for the polynomial along the edge.
    const bool crossed = (fv[e[0]] >= 0.0) != (fv[e[1]] >= 0.0);
    const SegmentRoots roots = segmentRoots(forms, piece.r[e[0]], piece.r[e[1]], c, lineDegree(forms.type()), margin);
    if (!roots.asCase(crossed))
      topology = false;
  }
  double L2 = 0.0, X2 = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    double widthSum = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      L2 += largestAbs(b.J[k][i]) * largestAbs(b.J[k][i]);
      widthSum += b.J[k][i].width();
    }
    X2 += widthSum * widthSum;
  }
  // A piece with no sign change at its corners must be shown empty; or, when a grazing face or
  // edge leaves that open, be smaller than the bound (a piece of surface in it, which its
  // neighbours' triangles need not show, is then within the bound of the piece itself).
  // By size alone: the surface in the piece and its triangles (whose corners are in the piece's
  // image) lie in the box around the image, and within L times its diameter of each other.
  const double image = glm::length(glm::dvec3(b.x[0].width(), b.x[1].width(), b.x[2].width()));
  if (!cut && !topology)
  {
    bound = std::min(std::sqrt(L2) * diameter, image);
    return std::isfinite(bound) && bound <= 0.5 * Tolerance;
  }
  const double flat = std::min(constantJ ? 0.0 : 2.0 * mapDeviation,
    b.hasHessian ? std::min(diameter * std::sqrt(X2), 3.0 / 16.0 * b.mapHessian * diameter * diameter)
                 : diameter * std::sqrt(X2));
  if (topology && cut)
  {
    // The case's triangles are a graph over the plane l = c too (their normals on n's side).
    std::vector<std::array<int, 6>> triangles;
    caseTriangles(piece, iso, triangles);
    auto rootPoint = [&](int a, int b2) {
      if (fv[a] == 0.0)
        return piece.r[a];
      if (fv[b2] == 0.0)
        return piece.r[b2];
      return piece.r[a] + edgeRoot(forms, piece.r[a], piece.r[b2], c, fv[a] < 0.0) * (piece.r[b2] - piece.r[a]);
    };
    int side = 0;
    for (const auto& t : triangles)
    {
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k)
        p[k] = rootPoint(t[static_cast<std::size_t>(2 * k)], t[static_cast<std::size_t>(2 * k + 1)]);
      const double along = glm::dot(glm::cross(p[1] - p[0], p[2] - p[0]), n);
      const int s = along > 0.0 ? 1 : along < 0.0 ? -1 : 0;
      if (s == 0 && glm::length(glm::cross(p[1] - p[0], p[2] - p[0])) == 0.0)
        continue; // a triangle of no area (a corner at the iso-value)
      if (s == 0 || (side != 0 && s != side))
      {
        topology = false;
      }
      side = s;
    }
  }
  if (topology)
  {
    bound = affine ? 2.0 * E / glm::length(glm::transpose(Jinv) * g) + 2.0 * widest
                   : std::sqrt(L2) * (2.0 * E / gl + 2.0 * widest) + flat;
  }
  else
  {
    // By size alone: the surface in the piece and its triangles lie in the image of the piece,
    // within L times its diameter of each other (and the flat triangles within X of that image).
    bound = std::min(std::sqrt(L2) * diameter + flat, image);
  }
  if (topology && !(bound <= Tolerance) && image <= Tolerance)
  {
    topology = false; // the certificate's bound is looser than the piece's size
    bound = image;
  }
  return std::isfinite(bound) && bound <= Tolerance;
}

void Extraction::classify(Piece& piece)
{
  glm::dvec3 lo = piece.r[0], hi = piece.r[0];
  for (int k = 1; k < 4; ++k)
  {
    lo = glm::min(lo, piece.r[k]);
    hi = glm::max(hi, piece.r[k]);
  }
  const CellForms& forms = Forms[piece.form];
  CellForms::Bounds b;
  forms.bounds(lo, hi, b);
  // The forms' rounding: their making grows the nodes' by the matrix's row sums.
  const double margin = 64.0 * std::numeric_limits<double>::epsilon() * forms.type().growth * forms.fieldMagnitude();
  bool any = false, certified = true, sizeOnly = false;
  double worst = 0.0;
  for (std::size_t k = 0; k < Iso.size(); ++k)
  {
    const double c = Iso[k];
    if (c < b.f.lo - margin || c > b.f.hi + margin)
      continue;
    any = true;
    double bound = 0.0;
    bool topology = false;
    if (!certify(piece, b, k, margin, bound, topology))
    {
      certified = false;
      break;
    }
    worst = std::max(worst, bound);
    sizeOnly = sizeOnly || !topology;
  }
  piece.sizeOnly = sizeOnly;
  piece.bound = worst;
  piece.state = !any ? State::Empty
    : certified      ? State::Resolved
    : piece.level >= kMaxSurfaceLevels ? State::Unresolved
                                       : State::Split;
}

/// The output vertex of the root of iso-value `iso` on the piece's edge (a, b), whose ends'
/// values are on either side of it (f >= c counts as above).
std::uint32_t Extraction::root(const Piece& piece, int a, int b, std::size_t iso)
{
  const double c = Iso[iso];
  const std::uint32_t va = piece.v[a], vb = piece.v[b];
  // A vertex at the iso-value is its own root.
  const double fa = Vertices[va].f - c, fb = Vertices[vb].f - c;
  const bool atA = fa == 0.0, atB = fb == 0.0;
  const std::uint64_t key = atA ? edgeKey(va, va) : atB ? edgeKey(vb, vb) : edgeKey(va, vb);
  auto& roots = Roots[iso];
  const auto found = roots.find(key);
  if (found != roots.end())
    return found->second;
  const CellForms& forms = Forms[piece.form];
  // Along the edge from its lower-named end (the same from every cell).
  const bool forward = va < vb;
  const glm::dvec3 r0 = forward ? piece.r[a] : piece.r[b];
  const glm::dvec3 r1 = forward ? piece.r[b] : piece.r[a];
  const double g0 = forward ? fa : fb;
  const double t = atA || atB ? ((atA == forward) ? 0.0 : 1.0) : edgeRoot(forms, r0, r1, c, g0 < 0.0);
  SurfaceVertex out;
  out.form = piece.form;
  out.iso = static_cast<int>(iso);
  out.reference = r0 + t * (r1 - r0);
  out.key = key;
  out.t = t;
  Out.push_back(out);
  const auto index = static_cast<std::uint32_t>(Out.size() - 1);
  roots.emplace(key, index);
  return index;
}

/// The marching-tetrahedra case of iso-value `iso` in a piece: its triangles, each as three
/// (a, b) corner pairs whose edges hold the roots (a == b: a corner at the iso-value).
void Extraction::caseTriangles(const Piece& piece, std::size_t iso, std::vector<std::array<int, 6>>& out) const
{
  out.clear();
  const double c = Iso[iso];
  int above[4], below[4], na = 0, nb = 0;
  for (int k = 0; k < 4; ++k)
  {
    if (Vertices[piece.v[k]].f >= c)
      above[na++] = k;
    else
      below[nb++] = k;
  }
  if (na == 0 || nb == 0)
    return;
  if (na == 1 || nb == 1)
  {
    const int lone = na == 1 ? above[0] : below[0];
    const int* others = na == 1 ? below : above;
    out.push_back({ lone, others[0], lone, others[1], lone, others[2] });
    return;
  }
  // Two and two: the quadrilateral (a0 b0, a0 b1, a1 b1, a1 b0), cut along a0 b1 - a1 b0.
  const int a0 = above[0], a1 = above[1], b0 = below[0], b1 = below[1];
  out.push_back({ a0, b0, a0, b1, a1, b0 });
  out.push_back({ a0, b1, a1, b1, a1, b0 });
}

void Extraction::emit(ExactSurfaceMesh& surface, SurfaceParts& parts)
{
  std::vector<std::array<int, 6>> triangles;
  for (std::size_t index = 0; index < Pieces.size(); ++index)
  {
    const Piece& piece = Pieces[index];
    if (piece.state == State::Unresolved)
      ++surface.unresolvedSubcells;
    if (piece.state == State::Resolved)
    {
      surface.largestBound = std::max(surface.largestBound, piece.bound);
      surface.sizeCertifiedSubcells += piece.sizeOnly ? 1 : 0;
    }
    for (std::size_t iso = 0; iso < Iso.size(); ++iso)
    {
      const double c = Iso[iso];
      int above = 0;
      for (int k = 0; k < 4; ++k)
        above += Vertices[piece.v[k]].f >= c ? 1 : 0;
      if (above == 4)
      {
        parts.volumeTets.push_back({ piece.form, static_cast<int>(iso), 1.0,
          { piece.r[0], piece.r[1], piece.r[2], piece.r[3] } });
      }
      if (above == 0 || above == 4)
        continue;
      // The roots in this piece's cell (their edge parameter is the same from every cell).
      auto rootPoint = [&](int a, int b, std::uint32_t& vertex) {
        vertex = root(piece, a, b, iso);
        const double fa = Vertices[piece.v[a]].f - c, fb = Vertices[piece.v[b]].f - c;
        if (fa == 0.0)
          return piece.r[a];
        if (fb == 0.0)
          return piece.r[b];
        const bool forward = piece.v[a] < piece.v[b];
        const glm::dvec3 r0 = forward ? piece.r[a] : piece.r[b];
        const glm::dvec3 r1 = forward ? piece.r[b] : piece.r[a];
        return r0 + Out[vertex].t * (r1 - r0);
      };
      caseTriangles(piece, iso, triangles);
      Layer layer;
      layer.form = piece.form;
      layer.iso = static_cast<int>(iso);
      layer.direction = ellGradient(piece);
      for (const auto& t : triangles)
      {
        SurfaceTriangle tri;
        for (int k = 0; k < 3; ++k)
          tri.reference[k] = rootPoint(t[static_cast<std::size_t>(2 * k)], t[static_cast<std::size_t>(2 * k + 1)], tri.v[k]);
        layer.triangles.push_back({ tri.reference[0], tri.reference[1], tri.reference[2] });
        if (tri.v[0] == tri.v[1] || tri.v[1] == tri.v[2] || tri.v[0] == tri.v[2])
          continue; // a corner at the iso-value: the triangle is an edge or a point
        tri.form = piece.form;
        tri.iso = static_cast<int>(iso);
        tri.piece = static_cast<std::uint32_t>(index);
        tri.sizeOnly = piece.sizeOnly || piece.state == State::Unresolved;
        parts.triangles.push_back(tri);
      }
      // The polytope above c that the case's flat triangles cut from the piece.
      int up[4], down[4], nu = 0, nd = 0;
      for (int k = 0; k < 4; ++k)
      {
        if (Vertices[piece.v[k]].f >= c)
          up[nu++] = k;
        else
          down[nd++] = k;
      }
      std::uint32_t unused;
      auto add = [&](double sign, const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r, const glm::dvec3& s) {
        parts.volumeTets.push_back({ piece.form, static_cast<int>(iso), sign, { p, q, r, s } });
      };
      if (nu == 1)
      {
        const int A = up[0];
        add(1.0, piece.r[A], rootPoint(A, down[0], unused), rootPoint(A, down[1], unused), rootPoint(A, down[2], unused));
      }
      else if (nd == 1)
      {
        const int D = down[0];
        add(1.0, piece.r[0], piece.r[1], piece.r[2], piece.r[3]);
        add(-1.0, piece.r[D], rootPoint(up[0], D, unused), rootPoint(up[1], D, unused), rootPoint(up[2], D, unused));
      }
      else
      {
        const int a0 = up[0], a1 = up[1], b0 = down[0], b1 = down[1];
        const glm::dvec3 x0 = piece.r[a0], x1 = rootPoint(a0, b0, unused), x2 = rootPoint(a0, b1, unused);
        const glm::dvec3 y0 = piece.r[a1], y1 = rootPoint(a1, b0, unused), y2 = rootPoint(a1, b1, unused);
        add(1.0, x0, x1, x2, y0);
        add(1.0, x1, x2, y0, y1);
        add(1.0, x2, y0, y1, y2);
      }
      for (const auto& tri : layer.triangles)
        for (int k = 0; k < 3; ++k)
          layer.perimeter += glm::length(tri[static_cast<std::size_t>((k + 1) % 3)] - tri[static_cast<std::size_t>(k)]);
      parts.layers.push_back(std::move(layer));
    }
  }
}

void Extraction::run(const ParallelFor& parallelFor, ExactSurfaceMesh& surface, SurfaceParts& parts)
{
  const MeshView& mesh = Scene_.mesh();
  IsoValues sorted(Iso);
  // The cells that can hold an iso-value: their forms.
  std::vector<NodeId> candidates;
  for (const auto& cell : Scene_.validCells())
  {
    if (!sorted.anyWithin(cell.valueLo, cell.valueHi))
      continue;
    candidates.push_back(cell.id);
  }
  Forms.resize(candidates.size());
  parallelFor(static_cast<NodeId>(candidates.size()), [&](NodeId begin, NodeId end) {
    for (NodeId k = begin; k < end; ++k)
      Forms[static_cast<std::size_t>(k)] = CellForms(Scene_, candidates[static_cast<std::size_t>(k)]);
  });
  // Mesh points merged by position, so a mesh written with each cell's own copies of its points
  // still joins up.
  PointVertex.assign(static_cast<std::size_t>(mesh.numberOfPoints), kNone);
  {
    struct PointHash
    {
      std::size_t operator()(const glm::dvec3& p) const
      {
        std::uint64_t h = 1469598103934665603ull;
        for (int a = 0; a < 3; ++a)
        {
          std::uint64_t bits;
          const double v = p[a] == 0.0 ? 0.0 : p[a];
          std::memcpy(&bits, &v, sizeof bits);
          h = (h ^ bits) * 1099511628211ull;
        }
        return static_cast<std::size_t>(h);
      }
    };
    std::unordered_map<glm::dvec3, std::uint32_t, PointHash> byPosition;
    for (const CellForms& forms : Forms)
    {
      for (std::size_t c = 0; c < forms.type().corners.size(); ++c)
      {
        const NodeId id = forms.ids()[c];
        if (PointVertex[static_cast<std::size_t>(id)] != kNone)
          continue;
        const double* p = mesh.points + 3 * id;
        const glm::dvec3 at(p[0], p[1], p[2]);
        const auto found = byPosition.find(at);
        if (found != byPosition.end() && Vertices[found->second].f == mesh.values[id])
        {
          PointVertex[static_cast<std::size_t>(id)] = found->second;
          continue;
        }
        const std::uint32_t v = meshVertex(id);
        byPosition.emplace(at, v);
      }
    }
  }
  for (std::uint32_t form = 0; form < Forms.size(); ++form)
    startCell(form);
  Roots.resize(Iso.size());
  NodeId examined = 0;
  for (;;)
  {
    // Classify the new pieces (in parallel: each reads the forms and the vertices only).
    std::vector<std::size_t> fresh;
    for (std::size_t i = 0; i < Pieces.size(); ++i)
    {
      if (Pieces[i].state == State::New)
        fresh.push_back(i);
    }
    examined += static_cast<NodeId>(fresh.size());
    parallelFor(static_cast<NodeId>(fresh.size()), [&](NodeId begin, NodeId end) {
      for (NodeId k = begin; k < end; ++k)
        classify(Pieces[fresh[static_cast<std::size_t>(k)]]);
    });
    bool split = false;
    const std::size_t count = Pieces.size();
    std::size_t splits = 0;
    for (const Piece& piece : Pieces)
      splits += piece.state == State::Split ? 1 : 0;
    // The budget: a tolerance far below what the mesh's pieces can reach would take them all
    // down to the level limit; past it, what is left uncertified stays so (and is counted).
    if (count + 4 * splits > static_cast<std::size_t>(kMaxSurfacePieces))
    {
      BudgetReached = true;
      for (Piece& piece : Pieces)
        if (piece.state == State::Split)
          piece.state = State::Unresolved;
    }
    for (std::size_t i = 0; i < count; ++i)
    {
      if (Pieces[i].state == State::Split)
      {
        bisect(i);
        split = true;
      }
    }
    // Conforming closure: a piece with a bisected edge is bisected (at its longest edge) until
    // none has one, so neighbours' faces are cut alike.
    while (!Closure.empty())
    {
      const std::uint32_t i = Closure.back();
      Closure.pop_back();
      if (hanging(Pieces[i]))
        bisect(i);
    }
    bool fresher = false;
    for (const Piece& piece : Pieces)
      fresher = fresher || piece.state == State::New;
    if (!split && !fresher)
      break;
  }
  surface.subcells = examined;
  emit(surface, parts);
  parts.forms = &Forms;
  parts.vertices = std::move(Out);
  parts.candidates = std::move(candidates);
}

} // namespace
} // namespace exact

bool checkExactSurfaceSettings(const ExactSurfaceSettings& settings, Messages& messages)
{
  if (!checkIsoValues(settings.isoValues, messages))
    return false;
  if (!std::isfinite(settings.tolerance) || settings.tolerance < 0.0)
  {
    messages.errors.push_back(text("The absolute tolerance (", settings.tolerance,
      ") must be a finite number >= 0 (0: use the relative tolerance)."));
    return false;
  }
  if (settings.tolerance == 0.0 && !(settings.relativeTolerance > 0.0 && std::isfinite(settings.relativeTolerance)))
  {
    messages.errors.push_back(text("The tolerance (", settings.relativeTolerance,
      ", relative to the diagonal of the mesh's box) must be a finite number > 0."));
    return false;
  }
  return true;
}

bool extractExactSurface(const Scene& scene, const ExactSurfaceSettings& settings,
  const std::vector<ArrayView>& arrays, ExactSurfaceMesh& surface, Messages& messages,
  const ParallelFor& parallelFor)
{
  surface = ExactSurfaceMesh();
  if (!checkExactSurfaceSettings(settings, messages))
    return false;
  const MeshView& mesh = scene.mesh();
  // The arrays: checked against the point count, converted once.
  std::vector<std::vector<double>> copies(arrays.size());
  std::vector<const double*> values(arrays.size());
  for (std::size_t a = 0; a < arrays.size(); ++a)
  {
    const ArrayView& array = arrays[a];
    if (!array.data || array.tuples < mesh.numberOfPoints || array.components < 1)
    {
      messages.errors.push_back(text("The point array \"", array.name, "\" has ", array.tuples,
        " tuples of ", array.components, " components; the mesh has ", mesh.numberOfPoints,
        " points: it cannot be interpolated on the surface."));
      return false;
    }
    values[a] = asDoubles(array, mesh.numberOfPoints, 0, array.components, copies[a]);
  }
  const double diagonal = scene.diagonal();
  const double tolerance = settings.tolerance > 0.0 ? settings.tolerance : settings.relativeTolerance * diagonal;
  surface.tolerance = tolerance;
  if (!(tolerance > 0.0))
  {
    messages.errors.push_back("The mesh has no valid cell to make a surface in.");
    return false;
  }
  exact::SurfaceParts parts;
  exact::Extraction extraction(scene, settings, tolerance);
  extraction.run(parallelFor, surface, parts);
  exact::finishSurface(scene, settings, arrays, values, parts, surface, parallelFor);
  if (extraction.BudgetReached)
  {
    messages.warnings.push_back(text("The tolerance (", tolerance, ", ", tolerance / diagonal,
      " of the mesh's diagonal) needed more than ", kMaxSurfacePieces,
      " pieces of cells: the refinement stopped there. Raise the tolerance."));
  }
  if (surface.unresolvedSubcells > 0)
  {
    messages.warnings.push_back(text(surface.unresolvedSubcells,
      " pieces of cells were not certified after ", kMaxSurfaceLevels,
      " bisections or when the refinement stopped (a surface tangent to itself or to a cell's edge,"
      " through a pyramid's apex, or a tolerance too small for the pieces' budget):"
      " their triangles are the marching-tetrahedra case of their corners, within no stated"
      " distance, and a piece of surface inside one without a sign change at its corners is"
      " missed."));
  }
  return true;
}

} // namespace tetdsr
