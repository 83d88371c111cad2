// The certificate of a piece of the exact surface's bisection (ExactSurfaceCertificate.h).
//
// Why a certified piece's triangles are within its bound of the surface. In a tetrahedron T of a
// cell's reference space, let l be the affine function equal to the field f at T's corners and E a
// bound of |f - l| over T (from the bound G of f's gradient over T's box: along any of T's edge
// directions e, f and l have derivatives within e.G, and f - l is 0 at a corner). The surface f = c
// and the triangles (whose corners are roots on T's edges, so within E of l = c) both lie in the
// slab |l - c| <= E, of width w = 2E / |grad l|. With f monotone along n = grad l / |grad l| over T
// (n.G > 0), along an in-face direction in each face the slab meets, and along every edge the slab
// meets, the surface in T is a graph over the plane l = c, one disc bounded by the loop through the
// edges' roots that the marching-tetrahedra case joins; in each face its curve and the case's chord
// are graphs over the same segment within the face's strip of width w_F = 2E / |grad_F l|. Hence
// every point of either lies within w + 2 max w_F of the other (reference units), and in the scene
// within L (w + 2 max w_F) + X, L bounding |dx/dr| over T and X the distance between the map of a
// reference triangle and the flat one through its corners' images.
//
// The steps (PieceCertificate, in certify's order): the slab's half-width E (slabHalfWidth, with
// the map's shape: mapShape, sceneSecondOrder); monotonicity along n inside the slab; the faces'
// strips (faceStrips); one root or none along each edge (edgesHoldCase, with Descartes' rule:
// segmentRoots); the case's triangles a graph over l = c too (caseIsGraph); the bound
// (finalBound). Where the topology is not shown, or the gradient not bounded (a pyramid's apex),
// the piece is certified by its size alone (byImage, finalBound) when its image is within the
// bound.
#include "tetdsr/surface/ExactSurfaceCertificate.h"

#include "tetdsr/cells/Cells.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <mutex>

namespace tetdsr
{
namespace exact
{
namespace
{

double largestAbs(const Interval& i)
{
  return std::max(std::abs(i.lo), std::abs(i.hi));
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

/// certifyPiece's steps over the state they share (the file's comment).
class PieceCertificate
{
public:
  PieceCertificate(const PieceCorners& piece, const CellForms::Bounds& b, double c, double margin, double tolerance)
    : Piece(piece)
    , B(b)
    , C(c)
    , Margin(margin)
    , Tolerance(tolerance)
    , Forms(*piece.forms)
  {
    for (int k = 0; k < 4; ++k)
    {
      Fv[k] = Piece.f[k] - C;
      Cut = Cut || ((Fv[k] >= 0.0) != (Fv[0] >= 0.0));
    }
  }

  bool certify(double& bound, bool& topology);

private:
  bool byImage(double& bound, bool& topology) const;
  void slabHalfWidth();
  void mapShape();
  void sceneSecondOrder();
  bool slabBox(std::initializer_list<int> corners, double width, glm::dvec3& lo, glm::dvec3& hi) const;
  bool faceStrips(double& widest) const;
  bool edgesHoldCase() const;
  bool caseIsGraph() const;
  bool finalBound(double widest, double& bound, bool& topology) const;

  const PieceCorners& Piece;
  const CellForms::Bounds& B;
  const double C;
  const double Margin;
  const double Tolerance;
  const CellForms& Forms;
  double Fv[4];        ///< f - c at the corners
  bool Cut = false;    ///< a sign change at the corners
  double E = 0.0;      ///< the slab's half-width: |f - l| over the piece, with the margin
  double Diameter = 0.0; ///< the piece's longest edge (reference units)
  glm::dvec3 BoxLo{ 0.0 }, BoxHi{ 0.0 }; ///< the piece's box
  glm::dmat3 AinvT{ 1.0 }; ///< A^-T, A's columns the edges from corner 0
  glm::dvec3 G{ 0.0 };     ///< grad l (reference), from A^T G = the corners' differences of f
  double Gl = 0.0;         ///< |G|
  glm::dvec3 N{ 0.0 };     ///< G / |G|
  bool ConstantJ = false;  ///< the map's derivative is constant to rounding
  bool Affine = false;     ///< constant J, or a straight piece (the map its corners' affine map)
  double MapDeviation = 0.0; ///< the map's distance from its corners' affine map (not ConstantJ)
  glm::dmat3 Jm{ 0.0 };    ///< the affine map's matrix
  glm::dmat3 Jinv{ 1.0 };  ///< its inverse (Affine)
};

/// By size alone: the box around the piece's image within the bound (half of it without a sign
/// change at the corners).
bool PieceCertificate::byImage(double& bound, bool& topology) const
{
  topology = false;
  bound = glm::length(glm::dvec3(B.x[0].width(), B.x[1].width(), B.x[2].width()));
  return std::isfinite(bound) && bound <= (Cut ? Tolerance : 0.5 * Tolerance);
}

/// E, |f - l| over the piece: the least of the corners' edges' gradient bounds, the second-order
/// bound, the Bernstein coefficients of f - l on the piece's box and, for an affine piece, the
/// second-order bound in the scene; plus the margin.
void PieceCertificate::slabHalfWidth()
{
  // From the corner whose edges give the least.
  E = std::numeric_limits<double>::infinity();
  for (int base = 0; base < 4; ++base)
  {
    double worst = 0.0;
    for (int j = 0; j < 4; ++j)
    {
      if (j == base)
        continue;
      const glm::dvec3 e = Piece.r[j] - Piece.r[base];
      Diameter = std::max(Diameter, glm::length(e));
      double s = 0.0;
      for (int i = 0; i < 3; ++i)
        s += std::abs(e[i]) * B.grad[i].width();
      worst = std::max(worst, s);
    }
    E = std::min(E, worst);
  }
  // Second order where the second derivatives are bounded: |f - l| <= K/2 sum l_i |r_i - r|^2,
  // and that sum is at most the enclosing ball's radius squared, 3/8 of the diameter squared.
  if (B.hasHessian)
    E = std::min(E, 3.0 / 16.0 * B.fieldHessian * Diameter * Diameter);
  // Or directly: |f - l| over the piece's box, from the Bernstein coefficients of f - l there (a
  // pyramid's field, whose derivatives' bounds through the collapse are loose, gets it too).
  glm::dmat3 A;
  for (int j = 0; j < 3; ++j)
    A[j] = Piece.r[j + 1] - Piece.r[0];
  AinvT = glm::inverse(glm::transpose(A));
  BoxLo = Piece.r[0];
  BoxHi = Piece.r[0];
  for (int k = 1; k < 4; ++k)
  {
    BoxLo = glm::min(BoxLo, Piece.r[k]);
    BoxHi = glm::max(BoxHi, Piece.r[k]);
  }
  G = AinvT * glm::dvec3(Fv[1] - Fv[0], Fv[2] - Fv[0], Fv[3] - Fv[0]);
  E = std::min(E, Forms.deviation(BoxLo, BoxHi, 3, Fv[0] + C - glm::dot(G, Piece.r[0]), G));
  mapShape();
  sceneSecondOrder();
  E += Margin;
}

/// Whether the piece's map is affine: its derivative constant to rounding, or the map its corners'
/// affine map (a straight pyramid's, whose Jacobian's bounds through the collapse are not
/// constant); else how far the map is from that (which bounds how far the flat triangles are from
/// the image of the piece's: twice it).
void PieceCertificate::mapShape()
{
  double jScale = 0.0, jWidth = 0.0;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i)
    {
      Jm[i][k] = 0.5 * (B.J[k][i].lo + B.J[k][i].hi);
      jScale = std::max(jScale, largestAbs(B.J[k][i]));
      jWidth = std::max(jWidth, B.J[k][i].width());
    }
  ConstantJ = B.hasHessian && jWidth <= 1e-12 * jScale && std::abs(glm::determinant(Jm)) > 0.0;
  // Else the map's distance from its own affine interpolant of the corners (per axis).
  bool straight = false;
  glm::dmat3 Jcorners(0.0);
  if (!ConstantJ)
  {
    double mapScale = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double x0 = Piece.x[0][a];
      const glm::dvec3 Ga = AinvT * glm::dvec3(Piece.x[1][a] - x0, Piece.x[2][a] - x0, Piece.x[3][a] - x0);
      for (int i = 0; i < 3; ++i)
        Jcorners[i][a] = Ga[i];
      const double d = Forms.deviation(BoxLo, BoxHi, a, x0 - glm::dot(Ga, Piece.r[0]), Ga);
      MapDeviation += d * d;
      mapScale = std::max(mapScale, std::abs(x0) + glm::length(Ga));
    }
    MapDeviation = std::sqrt(MapDeviation);
    straight = MapDeviation <= 1e-12 * mapScale && std::abs(glm::determinant(Jcorners)) > 0.0;
    if (straight)
      Jm = Jcorners;
  }
  Affine = ConstantJ || straight;
  if (Affine)
    Jinv = glm::inverse(Jm);
}

/// An affine piece: E in the scene, where the second derivatives and the diameter are those of
/// the shape itself (J^-T H J^-1; Gershgorin's row sums bound its norm), and the slab's and
/// strips' widths are scene distances.
void PieceCertificate::sceneSecondOrder()
{
  if (!(Affine && B.hasHessian))
    return;
  // J^-T H J^-1 with H = its middle + a part within the radius: the middle's product exactly
  // (its cancellations kept), the rest bounded in magnitude.
  glm::dmat3 middle, radius;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
    {
      middle[j][i] = 0.5 * (B.fieldSecond[i][j].lo + B.fieldSecond[i][j].hi);
      radius[j][i] = 0.5 * B.fieldSecond[i][j].width();
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
    diameterX = std::max(diameterX, glm::length(Jm * (Piece.r[e[1]] - Piece.r[e[0]])));
  E = std::min(E, 3.0 / 16.0 * K * diameterX * diameterX);
}

/// Where the surface can be: the slab |l - c| <= width within a simplex of the piece's corners
/// (the piece, a face, an edge), a convex polytope whose corners are the simplex's corners within
/// it and its edges' crossings of l = c +- width. Its box; false when it is empty.
bool PieceCertificate::slabBox(std::initializer_list<int> corners, double width, glm::dvec3& lo, glm::dvec3& hi) const
{
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
    if (std::abs(Fv[*i]) <= width)
      take(Piece.r[*i]);
    for (auto j = i + 1; j != corners.end(); ++j)
    {
      const double p = Fv[*i], q = Fv[*j];
      for (double level : { -width, width })
      {
        if ((p - level) * (q - level) < 0.0)
          take(Piece.r[*i] + (level - p) / (q - p) * (Piece.r[*j] - Piece.r[*i]));
      }
    }
  }
  return any;
}

/// Each face the slab meets: monotone along its in-face direction within the slab (false when a
/// face is not), and `widest` the largest strip around the faces' chords.
bool PieceCertificate::faceStrips(double& widest) const
{
  glm::dvec3 lo, hi;
  Interval slope[2];
  for (const auto& face : kFaces)
  {
    // |f - l| on the face alone (its box's Bernstein coefficients): the face's own slab.
    glm::dvec3 faceLo = glm::min(glm::min(Piece.r[face[0]], Piece.r[face[1]]), Piece.r[face[2]]);
    glm::dvec3 faceHi = glm::max(glm::max(Piece.r[face[0]], Piece.r[face[1]]), Piece.r[face[2]]);
    const double EF = std::min(E, Forms.deviation(faceLo, faceHi, 3, Fv[0] + C - glm::dot(G, Piece.r[0]), G) + Margin);
    if (!slabBox({ face[0], face[1], face[2] }, EF, lo, hi))
      continue;
    const glm::dvec3 normal = glm::normalize(glm::cross(Piece.r[face[1]] - Piece.r[face[0]], Piece.r[face[2]] - Piece.r[face[0]]));
    const glm::dvec3 inFace = G - glm::dot(G, normal) * normal;
    const double gf = glm::length(inFace);
    // Monotone along the in-face part of grad l, or of the gradient at the middle of the box.
    glm::dvec3 xm, middle;
    glm::dmat3 Jmiddle;
    double fm = 0.0;
    Forms.atReference(0.5 * (lo + hi), xm, Jmiddle, fm, middle);
    middle -= glm::dot(middle, normal) * normal;
    const glm::dvec3 directions[2] = { gf > 0.0 ? inFace / gf : glm::dvec3(0.0),
      glm::length(middle) > 0.0 ? glm::normalize(middle) : glm::dvec3(0.0) };
    Forms.slopes(lo, hi, directions, 2, slope);
    const bool alongL = gf > 0.0 && slope[0].lo > 0.0;
    const bool alongMiddle = glm::length(middle) > 0.0 && slope[1].lo > 0.0;
    if (!alongL && !alongMiddle)
      return false;
    // The loop of the surface's boundary runs on the faces with a sign change only (a monotone
    // face without one holds no curve): their strips bound it.
    const bool chord = (Fv[face[0]] >= 0.0) != (Fv[face[1]] >= 0.0) || (Fv[face[0]] >= 0.0) != (Fv[face[2]] >= 0.0);
    // The curve and the chord are graphs along the monotone direction d within the strip, so
    // at most the strip's width over the cosine of d's angle to the strip's normal apart.
    if (chord && Affine)
    {
      // The strip's width in the scene: the in-face part of the scene gradient J^-T g.
      const glm::dvec3 gx = glm::transpose(Jinv) * G;
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
  return true;
}

/// Each edge: one root or none. Along an edge e, |f - l| <= e^T H e / 8 (its own second
/// derivative's bound); f is monotone where the edge is within that of c; where it is not, the
/// count Descartes' rule allows for the polynomial along the edge.
bool PieceCertificate::edgesHoldCase() const
{
  glm::dvec3 lo, hi;
  Interval slope[1];
  for (const auto& e : kEdges)
  {
    const glm::dvec3 d = Piece.r[e[1]] - Piece.r[e[0]];
    double Ee = E;
    if (B.hasHessian)
    {
      double second = 0.0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          second += largestAbs(B.fieldSecond[i][j]) * std::abs(d[i] * d[j]);
      Ee = std::min(E, second / 8.0 + Margin);
    }
    if (!slabBox({ e[0], e[1] }, Ee, lo, hi))
      continue;
    Forms.slopes(lo, hi, &d, 1, slope);
    if (signDefinite(slope[0]))
      continue;
    const bool crossed = (Fv[e[0]] >= 0.0) != (Fv[e[1]] >= 0.0);
    const SegmentRoots roots = segmentRoots(Forms, Piece.r[e[0]], Piece.r[e[1]], C, lineDegree(Forms.type()), Margin);
    if (!roots.asCase(crossed))
      return false;
  }
  return true;
}

/// The case's triangles are a graph over the plane l = c too (their normals on n's side).
bool PieceCertificate::caseIsGraph() const
{
  std::vector<std::array<int, 6>> triangles;
  caseTriangles(Piece.f, C, triangles);
  auto rootPoint = [&](int a, int b2) {
    if (Fv[a] == 0.0)
      return Piece.r[a];
    if (Fv[b2] == 0.0)
      return Piece.r[b2];
    return Piece.r[a] + edgeRoot(Forms, Piece.r[a], Piece.r[b2], C, Fv[a] < 0.0) * (Piece.r[b2] - Piece.r[a]);
  };
  bool graph = true;
  int side = 0;
  for (const auto& t : triangles)
  {
    glm::dvec3 p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = rootPoint(t[static_cast<std::size_t>(2 * k)], t[static_cast<std::size_t>(2 * k + 1)]);
    const double along = glm::dot(glm::cross(p[1] - p[0], p[2] - p[0]), N);
    const int s = along > 0.0 ? 1 : along < 0.0 ? -1 : 0;
    if (s == 0 && glm::length(glm::cross(p[1] - p[0], p[2] - p[0])) == 0.0)
      continue; // a triangle of no area (a corner at the iso-value)
    if (s == 0 || (side != 0 && s != side))
    {
      graph = false;
    }
    side = s;
  }
  return graph;
}

/// The bound: the slab's and strips' widths through the map where the topology is certified, else
/// by size alone (as when the certificate's bound is looser than the piece's size).
bool PieceCertificate::finalBound(double widest, double& bound, bool& topology) const
{
  double L2 = 0.0, X2 = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    double widthSum = 0.0;
    for (int i = 0; i < 3; ++i)
    {
      L2 += largestAbs(B.J[k][i]) * largestAbs(B.J[k][i]);
      widthSum += B.J[k][i].width();
    }
    X2 += widthSum * widthSum;
  }
  // A piece with no sign change at its corners must be shown empty; or, when a grazing face or
  // edge leaves that open, be smaller than the bound (a piece of surface in it, which its
  // neighbours' triangles need not show, is then within the bound of the piece itself).
  // By size alone: the surface in the piece and its triangles (whose corners are in the piece's
  // image) lie in the box around the image, and within L times its diameter of each other.
  const double image = glm::length(glm::dvec3(B.x[0].width(), B.x[1].width(), B.x[2].width()));
  if (!Cut && !topology)
  {
    bound = std::min(std::sqrt(L2) * Diameter, image);
    return std::isfinite(bound) && bound <= 0.5 * Tolerance;
  }
  const double flat = std::min(ConstantJ ? 0.0 : 2.0 * MapDeviation,
    B.hasHessian ? std::min(Diameter * std::sqrt(X2), 3.0 / 16.0 * B.mapHessian * Diameter * Diameter)
                 : Diameter * std::sqrt(X2));
  if (topology && Cut)
    topology = caseIsGraph();
  if (topology)
  {
    bound = Affine ? 2.0 * E / glm::length(glm::transpose(Jinv) * G) + 2.0 * widest
                   : std::sqrt(L2) * (2.0 * E / Gl + 2.0 * widest) + flat;
  }
  else
  {
    // By size alone: the surface in the piece and its triangles lie in the image of the piece,
    // within L times its diameter of each other (and the flat triangles within X of that image).
    bound = std::min(std::sqrt(L2) * Diameter + flat, image);
  }
  if (topology && !(bound <= Tolerance) && image <= Tolerance)
  {
    topology = false; // the certificate's bound is looser than the piece's size
    bound = image;
  }
  return std::isfinite(bound) && bound <= Tolerance;
}

bool PieceCertificate::certify(double& bound, bool& topology)
{
  // Where the gradient has no bound (a pyramid's piece at its apex, where the collapse's
  // derivative is unbounded): by size alone.
  if (!B.finite)
    return byImage(bound, topology);
  slabHalfWidth();
  // No sign change, and every corner beyond the slab: f - c keeps l - c's sign (|f - l| <= E).
  if (!Cut && std::min({ std::abs(Fv[0]), std::abs(Fv[1]), std::abs(Fv[2]), std::abs(Fv[3]) }) > E)
  {
    bound = 0.0;
    topology = true;
    return true;
  }
  Gl = glm::length(G);
  if (!(Gl > 0.0) || !std::isfinite(Gl))
    return byImage(bound, topology);
  N = G / Gl;
  // Monotone along n where the surface can be: no closed sheet, no handle, a graph over l = c
  // (along every line along n, f - c has l - c's sign outside the slab).
  glm::dvec3 lo, hi;
  if (!slabBox({ 0, 1, 2, 3 }, E, lo, hi))
  {
    bound = 0.0;
    topology = true;
    return true;
  }
  Interval slope[1];
  Forms.slopes(lo, hi, &N, 1, slope);
  if (!(slope[0].lo > 0.0))
    return byImage(bound, topology); // not even monotone inside
  double widest = 0.0;
  topology = faceStrips(widest) && edgesHoldCase();
  return finalBound(widest, bound, topology);
}

} // namespace

void caseTriangles(const double values[4], double c, std::vector<std::array<int, 6>>& out)
{
  out.clear();
  int above[4], below[4], na = 0, nb = 0;
  for (int k = 0; k < 4; ++k)
  {
    if (values[k] >= c)
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

/// Newton's method inside a shrinking bracket, bisection when a step leaves it.
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


bool certifyPiece(const PieceCorners& piece, const CellForms::Bounds& b, double c, double margin, double tolerance,
  double& bound, bool& topology)
{
  return PieceCertificate(piece, b, c, margin, tolerance).certify(bound, topology);
}

} // namespace exact
} // namespace tetdsr
