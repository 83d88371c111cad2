// The exact surface (ExactSurface.h): the conforming bisection of the cells that can hold an
// iso-value, each piece certified (ExactSurfaceCertificate.cpp: why a certified piece's triangles
// are within its bound of the surface) or bisected, then the pieces' triangles, their roots and
// the parts the integrals need (ExactSurfaceIntegrals.cpp), and the settings' check.
#include "tetdsr/surface/ExactSurface.h"

#include "tetdsr/cells/Cells.h"
#include "tetdsr/surface/ExactSurfaceCertificate.h"
#include "tetdsr/surface/ExactSurfaceCells.h"
#include "tetdsr/surface/ExactSurfaceIntegrals.h"
#include "tetdsr/input/Settings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
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
  std::uint32_t root(const Piece& piece, int a, int b, std::size_t iso);
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
  PieceCorners corners;
  corners.forms = &forms;
  for (int k = 0; k < 4; ++k)
  {
    corners.r[k] = piece.r[k];
    corners.x[k] = Vertices[piece.v[k]].x;
    corners.f[k] = Vertices[piece.v[k]].f;
  }
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
    if (!certifyPiece(corners, b, c, margin, Tolerance, bound, topology))
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

void Extraction::emit(ExactSurfaceMesh& surface, SurfaceParts& parts)
{
  std::vector<std::array<int, 6>> triangles;
  for (std::size_t index = 0; index < Pieces.size(); ++index)
  {
    const Piece& piece = Pieces[index];
    double values[4];
    for (int k = 0; k < 4; ++k)
      values[k] = Vertices[piece.v[k]].f;
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
        above += values[k] >= c ? 1 : 0;
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
      caseTriangles(values, c, triangles);
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
        if (values[k] >= c)
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
