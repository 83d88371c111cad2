// The exact surface's last step (ExactSurfaceIntegrals.h): the bisection's parts made into the
// output (vertices with their exact normals and arrays, triangles oriented toward higher values,
// edge counts) and, when asked, the integrals: area and arrays over the triangles carried onto the
// curved surface, their boundary edges' strips, and the volume where f >= c (the pieces' tetrahedra,
// the layers between their flat triangles and the surface, and the cells wholly above c).
#include "tetdsr/surface/ExactSurfaceIntegrals.h"

#include "tetdsr/cells/Cells.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace tetdsr
{
namespace exact
{
namespace
{

constexpr double kPi = 3.14159265358979323846;

/// Gauss-Legendre nodes and weights on [0, 1] (Newton's method on the Legendre polynomial).
struct GaussRule
{
  std::vector<double> x, w;
  explicit GaussRule(int m)
  {
    x.resize(static_cast<std::size_t>(m));
    w.resize(static_cast<std::size_t>(m));
    for (int i = 0; i < m; ++i)
    {
      double z = std::cos(kPi * (i + 0.75) / (m + 0.5));
      double derivative = 1.0;
      for (int iteration = 0; iteration < 100; ++iteration)
      {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= m; ++k)
        {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        if (m == 1)
        {
          p1 = z;
          p0 = 1.0;
        }
        derivative = m * (z * p1 - p0) / (z * z - 1.0);
        const double step = p1 / derivative;
        z -= step;
        if (std::abs(step) < 1e-16)
          break;
      }
      x[static_cast<std::size_t>(i)] = 0.5 * (1.0 - z);
      w[static_cast<std::size_t>(i)] = 1.0 / ((1.0 - z * z) * derivative * derivative);
    }
  }
};

const GaussRule& gauss(int m)
{
  static const GaussRule rules[] = { GaussRule(1), GaussRule(2), GaussRule(3), GaussRule(4), GaussRule(5),
    GaussRule(6), GaussRule(7), GaussRule(8), GaussRule(9), GaussRule(10) };
  return rules[m - 1];
}

/// A collapsed Gauss rule on the unit triangle (x, y >= 0, x + y <= 1): weights sum to 1/2.
struct TrianglePoint
{
  double x, y, w;
};
std::vector<TrianglePoint> triangleRule(int m)
{
  const GaussRule& g = gauss(m);
  std::vector<TrianglePoint> points;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
    {
      const double u = g.x[static_cast<std::size_t>(i)], v = g.x[static_cast<std::size_t>(j)];
      points.push_back({ u * (1.0 - v), v, g.w[static_cast<std::size_t>(i)] * g.w[static_cast<std::size_t>(j)] * (1.0 - v) });
    }
  return points;
}

/// The same on the unit tetrahedron: weights sum to 1/6.
struct TetPoint
{
  glm::dvec3 x;
  double w;
};
std::vector<TetPoint> tetRule(int m)
{
  const GaussRule& g = gauss(m);
  std::vector<TetPoint> points;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k)
      {
        const double u = g.x[static_cast<std::size_t>(i)], v = g.x[static_cast<std::size_t>(j)], w = g.x[static_cast<std::size_t>(k)];
        points.push_back({ glm::dvec3(u * (1.0 - v) * (1.0 - w), v * (1.0 - w), w),
          g.w[static_cast<std::size_t>(i)] * g.w[static_cast<std::size_t>(j)] * g.w[static_cast<std::size_t>(k)] * (1.0 - v) * (1.0 - w) * (1.0 - w) });
      }
  return points;
}

/// The physical gradient from the form-space one: J^-T grad.
glm::dvec3 physicalGradient(const glm::dmat3& J, const glm::dvec3& grad)
{
  return glm::inverse(glm::transpose(J)) * grad;
}

/// Carries the triangle's point p (direction d) onto f = c: the form point e and the distance s
/// along d. False when Newton's method does not converge.
bool carry(const CellForms& forms, double c, const glm::dvec3& p, const glm::dvec3& d, glm::dvec3& e, double& s,
  glm::dmat3& J, glm::dvec3& grad)
{
  s = 0.0;
  const double scale = std::max(1.0, glm::length(p));
  for (int iteration = 0; iteration < 40; ++iteration)
  {
    glm::dvec3 x;
    double f = 0.0;
    forms.at(e, x, J, f, grad);
    const glm::dvec3 r = x - p - s * d;
    const double g = f - c;
    glm::dmat4 M(0.0);
    for (int i = 0; i < 3; ++i)
      M[i] = glm::dvec4(J[i], grad[i]);
    M[3] = glm::dvec4(-d, 0.0);
    const glm::dvec4 step = glm::inverse(M) * glm::dvec4(-r, -g);
    if (!std::isfinite(step.x + step.y + step.z + step.w))
      return false;
    e += glm::dvec3(step);
    s += step.w;
    const double moved = glm::length(glm::dvec3(step));
    if (moved < 1e-14 && std::abs(step.w) < 1e-14 * scale)
    {
      forms.at(e, x, J, f, grad);
      return true;
    }
  }
  return false;
}

/// One triangle's carried integrals under the fine rule [0] and the coarse one [1].
struct TriangleResult
{
  double area[2] = { 0.0, 0.0 };
  std::vector<double> arrays[2];
  bool ok = true;
};

/// finishSurface's steps, in order, over the state they share.
class SurfaceFinisher
{
public:
  SurfaceFinisher(const Scene& scene, const ExactSurfaceSettings& settings, const std::vector<ArrayView>& arrays,
    const std::vector<const double*>& values, SurfaceParts& parts, ExactSurfaceMesh& surface,
    const ParallelFor& parallelFor)
    : Scene_(scene)
    , Settings(settings)
    , Arrays(arrays)
    , Values(values)
    , Parts(parts)
    , Surface(surface)
    , Parallel(parallelFor)
    , Forms(*parts.forms)
  {
  }

  void renumberVertices();
  void startArrays();
  void vertexAttributes();
  void orientTriangles();
  void countEdges();
  void startIntegrals();
  void triangleIntegrals();
  void boundaryEdgeErrors();
  void pieceVolumes();
  void layerVolumes();
  void wholeCellVolumes();

private:
  glm::dvec3 point(std::uint32_t v) const
  {
    return glm::dvec3(Surface.points[3 * v], Surface.points[3 * v + 1], Surface.points[3 * v + 2]);
  }
  glm::dvec3 normal(std::uint32_t v) const
  {
    return glm::dvec3(Surface.normals[3 * v], Surface.normals[3 * v + 1], Surface.normals[3 * v + 2]);
  }
  void arrayForms(const CellForms& cell, std::vector<std::vector<double>>& out) const;

  const Scene& Scene_;
  const ExactSurfaceSettings& Settings;
  const std::vector<ArrayView>& Arrays;
  const std::vector<const double*>& Values;
  SurfaceParts& Parts;
  ExactSurfaceMesh& Surface;
  const ParallelFor& Parallel;
  const std::vector<CellForms>& Forms;
  std::vector<std::uint32_t> Used; ///< per output vertex: its index in the parts' vertices
  std::vector<int> Components;     ///< per array
  int TotalComponents = 0;
  /// Per edge (its ends' output vertices): the triangles using it, and the last of them.
  std::unordered_map<std::uint64_t, std::pair<int, std::uint32_t>> Edges;
};

/// The vertices the triangles use, renumbered in order of first use.
void SurfaceFinisher::renumberVertices()
{
  std::vector<std::uint32_t> renumber(Parts.vertices.size(), 0xFFFFFFFFu);
  for (auto& tri : Parts.triangles)
  {
    for (auto& v : tri.v)
    {
      if (renumber[v] == 0xFFFFFFFFu)
      {
        renumber[v] = static_cast<std::uint32_t>(Used.size());
        Used.push_back(v);
      }
      v = renumber[v];
    }
  }
  Surface.points.resize(3 * Used.size());
  Surface.normals.resize(3 * Used.size());
}

/// Arrays' components, one after another.
void SurfaceFinisher::startArrays()
{
  for (const ArrayView& a : Arrays)
  {
    Components.push_back(a.components);
    TotalComponents += a.components;
  }
  Surface.arrays.assign(Arrays.size(), {});
  for (std::size_t a = 0; a < Arrays.size(); ++a)
    Surface.arrays[a].resize(Used.size() * static_cast<std::size_t>(Components[a]));
}

/// Array forms per cell, made when a cell's first vertex or patch needs them.
void SurfaceFinisher::arrayForms(const CellForms& cell, std::vector<std::vector<double>>& out) const
{
  out.resize(static_cast<std::size_t>(TotalComponents));
  int k = 0;
  for (std::size_t a = 0; a < Arrays.size(); ++a)
    for (int comp = 0; comp < Components[a]; ++comp)
      cell.arrayForm(Values[a], Components[a], comp, out[static_cast<std::size_t>(k++)]);
}

/// Each vertex's position, exact unit normal and arrays, from its cell (vertices grouped by cell).
void SurfaceFinisher::vertexAttributes()
{
  const std::size_t nv = Used.size();
  std::vector<std::uint32_t> byCell(nv);
  for (std::uint32_t i = 0; i < nv; ++i)
    byCell[i] = i;
  std::sort(byCell.begin(), byCell.end(), [&](std::uint32_t a, std::uint32_t b) {
    return Parts.vertices[Used[a]].form < Parts.vertices[Used[b]].form;
  });
  std::vector<std::pair<std::size_t, std::size_t>> groups;
  for (std::size_t i = 0; i < nv;)
  {
    std::size_t j = i;
    while (j < nv && Parts.vertices[Used[byCell[j]]].form == Parts.vertices[Used[byCell[i]]].form)
      ++j;
    groups.emplace_back(i, j);
    i = j;
  }
  Parallel(static_cast<NodeId>(groups.size()), [&](NodeId begin, NodeId end) {
    std::vector<std::vector<double>> forms2;
    for (NodeId g = begin; g < end; ++g)
    {
      const auto [first, last] = groups[static_cast<std::size_t>(g)];
      const CellForms& cell = Forms[Parts.vertices[Used[byCell[first]]].form];
      if (TotalComponents > 0)
        arrayForms(cell, forms2);
      for (std::size_t i = first; i < last; ++i)
      {
        const std::uint32_t out = byCell[i];
        const SurfaceVertex& v = Parts.vertices[Used[out]];
        const glm::dvec3 e = cell.toForm(v.reference);
        glm::dvec3 x, grad;
        glm::dmat3 J;
        double f = 0.0;
        cell.at(e, x, J, f, grad);
        glm::dvec3 n = physicalGradient(J, grad);
        const double length = glm::length(n);
        n = length > 0.0 && std::isfinite(length) ? n / length : glm::dvec3(0.0);
        for (int a = 0; a < 3; ++a)
        {
          Surface.points[3 * out + static_cast<std::size_t>(a)] = x[a];
          Surface.normals[3 * out + static_cast<std::size_t>(a)] = n[a];
        }
        int k = 0;
        for (std::size_t a = 0; a < Arrays.size(); ++a)
          for (int comp = 0; comp < Components[a]; ++comp)
            Surface.arrays[a][out * static_cast<std::size_t>(Components[a]) + static_cast<std::size_t>(comp)] =
              cell.evaluateForm(forms2[static_cast<std::size_t>(k++)].data(), e);
      }
    }
  });
}

/// Triangles, their normals toward higher values (the corners' exact normals' side).
void SurfaceFinisher::orientTriangles()
{
  for (auto& tri : Parts.triangles)
  {
    const glm::dvec3 N = glm::cross(point(tri.v[1]) - point(tri.v[0]), point(tri.v[2]) - point(tri.v[0]));
    if (glm::dot(N, normal(tri.v[0]) + normal(tri.v[1]) + normal(tri.v[2])) < 0.0)
    {
      std::swap(tri.v[1], tri.v[2]);
      std::swap(tri.reference[1], tri.reference[2]);
    }
    for (auto v : tri.v)
      Surface.triangles.push_back(v);
    Surface.cellIds.push_back(Forms[tri.form].cellId());
    Surface.isoIndices.push_back(tri.iso);
  }
}

/// Edges: used once (the mesh's boundary), more than twice (none on a certified surface).
void SurfaceFinisher::countEdges()
{
  for (std::uint32_t t = 0; t < Parts.triangles.size(); ++t)
  {
    const auto& tri = Parts.triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      const std::uint32_t a = tri.v[k], b = tri.v[(k + 1) % 3];
      const std::uint64_t key = a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
      auto& slot = Edges[key];
      slot.first += 1;
      slot.second = t;
    }
  }
  for (const auto& [key, slot] : Edges)
  {
    if (slot.first == 1)
      ++Surface.boundaryEdges;
    else if (slot.first > 2)
      ++Surface.nonManifoldEdges;
  }
}

/// Per iso-value: its integrals zeroed, its triangles counted and their flat area (always made).
void SurfaceFinisher::startIntegrals()
{
  const std::size_t isoCount = Settings.isoValues.size();
  Surface.integrals.assign(isoCount, {});
  for (std::size_t k = 0; k < isoCount; ++k)
  {
    Surface.integrals[k].isoValue = Settings.isoValues[k];
    Surface.integrals[k].arrayIntegrals.assign(static_cast<std::size_t>(TotalComponents), 0.0);
    Surface.integrals[k].arrayErrors.assign(static_cast<std::size_t>(TotalComponents), 0.0);
  }
  for (const auto& tri : Parts.triangles)
  {
    auto& I = Surface.integrals[static_cast<std::size_t>(tri.iso)];
    I.flatArea += 0.5 * glm::length(glm::cross(point(tri.v[1]) - point(tri.v[0]), point(tri.v[2]) - point(tri.v[0])));
    I.triangles += 1;
  }
}

/// Area and arrays: each triangle carried onto the surface (the header's comment).
void SurfaceFinisher::triangleIntegrals()
{
  const auto fine = triangleRule(6), coarse = triangleRule(4);
  std::vector<TriangleResult> results(Parts.triangles.size());
  Parallel(static_cast<NodeId>(Parts.triangles.size()), [&](NodeId begin, NodeId end) {
    std::vector<std::vector<double>> af;
    std::uint32_t formsOf = 0xFFFFFFFFu;
    for (NodeId t = begin; t < end; ++t)
    {
      const SurfaceTriangle& tri = Parts.triangles[static_cast<std::size_t>(t)];
      const CellForms& cell = Forms[tri.form];
      if (TotalComponents > 0 && formsOf != tri.form)
      {
        arrayForms(cell, af);
        formsOf = tri.form;
      }
      const double c = Settings.isoValues[static_cast<std::size_t>(tri.iso)];
      const glm::dvec3 P[3] = { point(tri.v[0]), point(tri.v[1]), point(tri.v[2]) };
      const glm::dvec3 N[3] = { normal(tri.v[0]), normal(tri.v[1]), normal(tri.v[2]) };
      TriangleResult& result = results[static_cast<std::size_t>(t)];
      for (int rule = 0; rule < 2; ++rule)
      {
        result.arrays[rule].assign(static_cast<std::size_t>(TotalComponents), 0.0);
        for (const TrianglePoint& q : rule == 0 ? fine : coarse)
        {
          const double l1 = q.x, l2 = q.y, l0 = 1.0 - l1 - l2;
          const glm::dvec3 p = l0 * P[0] + l1 * P[1] + l2 * P[2];
          const glm::dvec3 d = l0 * N[0] + l1 * N[1] + l2 * N[2];
          glm::dvec3 e = cell.toForm(l0 * tri.reference[0] + l1 * tri.reference[1] + l2 * tri.reference[2]);
          double s = 0.0;
          glm::dmat3 J;
          glm::dvec3 grad;
          if (!carry(cell, c, p, d, e, s, J, grad))
          {
            result.ok = false;
            continue;
          }
          const glm::dvec3 gx = physicalGradient(J, grad);
          const double gd = glm::dot(gx, d);
          glm::dvec3 X[2];
          for (int k = 0; k < 2; ++k)
          {
            const glm::dvec3 pk = P[k + 1] - P[0], dk = N[k + 1] - N[0];
            const double sk = -glm::dot(gx, pk + s * dk) / gd;
            X[k] = pk + sk * d + s * dk;
          }
          const double dA = glm::length(glm::cross(X[0], X[1]));
          result.area[rule] += q.w * dA;
          for (int a = 0; a < TotalComponents; ++a)
            result.arrays[rule][static_cast<std::size_t>(a)] += q.w * dA * cell.evaluateForm(af[static_cast<std::size_t>(a)].data(), e);
        }
      }
    }
  });
  for (std::size_t t = 0; t < Parts.triangles.size(); ++t)
  {
    const SurfaceTriangle& tri = Parts.triangles[t];
    auto& I = Surface.integrals[static_cast<std::size_t>(tri.iso)];
    const TriangleResult& r = results[t];
    if (!r.ok)
    {
      // Newton's method failed somewhere on it: the flat triangle's area, its whole as the error.
      const double flat = 0.5 * glm::length(glm::cross(point(tri.v[1]) - point(tri.v[0]), point(tri.v[2]) - point(tri.v[0])));
      I.area += flat;
      I.areaError += flat;
      continue;
    }
    I.area += r.area[0];
    // The rules' difference, and the rounding of the carried points (relative to the
    // coordinates' magnitude) over the triangle's perimeter.
    const glm::dvec3 P0 = point(tri.v[0]), P1 = point(tri.v[1]), P2 = point(tri.v[2]);
    const double magnitude = std::max({ glm::length(P0), glm::length(P1), glm::length(P2) });
    const double perimeter = glm::length(P1 - P0) + glm::length(P2 - P1) + glm::length(P0 - P2);
    I.areaError += std::abs(r.area[0] - r.area[1]) + 256.0 * std::numeric_limits<double>::epsilon() * magnitude * perimeter;
    // A triangle of a piece certified by its size alone may fold over its neighbours: all of it
    // counts in the error.
    if (tri.sizeOnly)
      I.areaError += std::abs(r.area[0]);
    for (int a = 0; a < TotalComponents; ++a)
    {
      I.arrayIntegrals[static_cast<std::size_t>(a)] += r.arrays[0][static_cast<std::size_t>(a)];
      I.arrayErrors[static_cast<std::size_t>(a)] += std::abs(r.arrays[0][static_cast<std::size_t>(a)] - r.arrays[1][static_cast<std::size_t>(a)]) +
        (tri.sizeOnly ? std::abs(r.arrays[0][static_cast<std::size_t>(a)]) : 0.0);
    }
  }
}

/// Edges on the mesh's boundary: the carried edge is on the surface, not necessarily on the
/// boundary; its length times the carrying distance at its middle.
void SurfaceFinisher::boundaryEdgeErrors()
{
  std::vector<std::vector<double>> af;
  for (const auto& [key, slot] : Edges)
  {
    if (slot.first != 1)
      continue;
    const SurfaceTriangle& tri = Parts.triangles[slot.second];
    const std::uint32_t a = static_cast<std::uint32_t>(key >> 32), b = static_cast<std::uint32_t>(key & 0xFFFFFFFFu);
    int ka = 0, kb = 0;
    for (int k = 0; k < 3; ++k)
    {
      if (tri.v[k] == a)
        ka = k;
      if (tri.v[k] == b)
        kb = k;
    }
    const CellForms& cell = Forms[tri.form];
    const glm::dvec3 p = 0.5 * (point(a) + point(b)), d = 0.5 * (normal(a) + normal(b));
    glm::dvec3 e = cell.toForm(0.5 * (tri.reference[ka] + tri.reference[kb]));
    double s = 0.0;
    glm::dmat3 J;
    glm::dvec3 grad;
    const double length = glm::length(point(a) - point(b));
    auto& I = Surface.integrals[static_cast<std::size_t>(tri.iso)];
    const double c = Settings.isoValues[static_cast<std::size_t>(tri.iso)];
    const bool ok = carry(cell, c, p, d, e, s, J, grad);
    const double strip = length * (ok ? std::abs(s) * glm::length(d) : length);
    I.areaError += strip;
    if (TotalComponents > 0)
    {
      arrayForms(cell, af);
      for (int k = 0; k < TotalComponents; ++k)
        I.arrayErrors[static_cast<std::size_t>(k)] += strip * std::abs(cell.evaluateForm(af[static_cast<std::size_t>(k)].data(), e));
    }
  }
}

/// |det J| at a reference point of a cell.
double detAt(const CellForms& cell, const glm::dvec3& r)
{
  glm::dvec3 x, grad;
  glm::dmat3 J;
  double f = 0.0;
  cell.atReference(r, x, J, f, grad);
  return glm::determinant(J);
}

/// The volume of a reference tetrahedron's image, by a rule on the unit tetrahedron.
double tetIntegral(const CellForms& cell, const glm::dvec3 r[4], const std::vector<TetPoint>& rule)
{
  const glm::dmat3 A(r[1] - r[0], r[2] - r[0], r[3] - r[0]);
  const double scale = std::abs(glm::determinant(A));
  double sum = 0.0;
  for (const TetPoint& q : rule)
    sum += q.w * std::abs(detAt(cell, r[0] + A * q.x));
  return sum * scale;
}

/// Volume where f >= c: the pieces' tetrahedra (whole pieces above c, and the cut pieces'
/// polytopes).
void SurfaceFinisher::pieceVolumes()
{
  const auto tetFine = tetRule(3), tetCoarse = tetRule(2);
  std::vector<double> volumeFine(Parts.volumeTets.size()), volumeCoarse(Parts.volumeTets.size());
  Parallel(static_cast<NodeId>(Parts.volumeTets.size()), [&](NodeId begin, NodeId end) {
    for (NodeId k = begin; k < end; ++k)
    {
      const VolumeTet& v = Parts.volumeTets[static_cast<std::size_t>(k)];
      volumeFine[static_cast<std::size_t>(k)] = v.sign * tetIntegral(Forms[v.form], v.r, tetFine);
      volumeCoarse[static_cast<std::size_t>(k)] = v.sign * tetIntegral(Forms[v.form], v.r, tetCoarse);
    }
  });
  for (std::size_t k = 0; k < Parts.volumeTets.size(); ++k)
  {
    auto& I = Surface.integrals[static_cast<std::size_t>(Parts.volumeTets[k].iso)];
    I.volume += volumeFine[k];
    I.volumeError += std::abs(volumeFine[k] - volumeCoarse[k]);
  }
}

/// The layers between the flat reference triangles and the surface.
void SurfaceFinisher::layerVolumes()
{
  const auto layerFine = triangleRule(3), layerCoarse = triangleRule(2);
  const GaussRule& inner = gauss(2);
  std::vector<std::array<double, 3>> layerResults(Parts.layers.size());
  Parallel(static_cast<NodeId>(Parts.layers.size()), [&](NodeId begin, NodeId end) {
    for (NodeId k = begin; k < end; ++k)
    {
      const Layer& layer = Parts.layers[static_cast<std::size_t>(k)];
      const CellForms& cell = Forms[layer.form];
      const double c = Settings.isoValues[static_cast<std::size_t>(layer.iso)];
      const double gl = glm::length(layer.direction);
      auto& out = layerResults[static_cast<std::size_t>(k)];
      out = { 0.0, 0.0, 0.0 };
      if (!(gl > 0.0))
        continue;
      const glm::dvec3 n = layer.direction / gl;
      double tauMax = 0.0, detMax = 0.0;
      for (const auto& tri : layer.triangles)
      {
        const double measure = std::abs(glm::determinant(glm::dmat3(tri[1] - tri[0], tri[2] - tri[0], n)));
        if (measure == 0.0)
          continue;
        for (int rule = 0; rule < 2; ++rule)
        {
          double sum = 0.0;
          for (const TrianglePoint& q : rule == 0 ? layerFine : layerCoarse)
          {
            const glm::dvec3 delta = (1.0 - q.x - q.y) * tri[0] + q.x * tri[1] + q.y * tri[2];
            // The surface along n from delta: Newton's method on f(delta + tau n) = c.
            double tau = 0.0;
            for (int iteration = 0; iteration < 30; ++iteration)
            {
              glm::dvec3 x, grad;
              glm::dmat3 J;
              double f = 0.0;
              cell.atReference(delta + tau * n, x, J, f, grad);
              const double slope = glm::dot(grad, n);
              if (!(std::abs(slope) > 0.0))
                break;
              const double step = (f - c) / slope;
              tau -= step;
              if (std::abs(step) < 1e-15)
                break;
            }
            if (!std::isfinite(tau))
              tau = 0.0;
            tauMax = std::max(tauMax, std::abs(tau));
            double column = 0.0;
            for (std::size_t j = 0; j < inner.x.size(); ++j)
            {
              const double det = std::abs(detAt(cell, delta + tau * inner.x[j] * n));
              detMax = std::max(detMax, det);
              column += inner.w[j] * det;
            }
            sum += q.w * column * tau;
          }
          out[static_cast<std::size_t>(rule)] -= sum * measure;
        }
      }
      // Where neighbouring pieces' layers (swept along different directions) meet: a wedge of the
      // cut's length by the layer's thickness squared.
      out[2] = layer.perimeter * tauMax * tauMax * detMax;
    }
  });
  for (std::size_t k = 0; k < Parts.layers.size(); ++k)
  {
    auto& I = Surface.integrals[static_cast<std::size_t>(Parts.layers[k].iso)];
    I.volume += layerResults[k][0];
    I.volumeError += std::abs(layerResults[k][0] - layerResults[k][1]) + layerResults[k][2];
  }
}

/// The valid cells without pieces: wholly above c (counted whole), or wholly below.
void SurfaceFinisher::wholeCellVolumes()
{
  std::vector<NodeId> whole;
  {
    std::vector<char> isCandidate(static_cast<std::size_t>(Scene_.mesh().numberOfCells), 0);
    for (NodeId id : Parts.candidates)
      isCandidate[static_cast<std::size_t>(id)] = 1;
    for (const auto& cell : Scene_.validCells())
    {
      if (!isCandidate[cell.id])
      {
        bool anyAbove = false;
        for (double c : Settings.isoValues)
          anyAbove = anyAbove || cell.valueLo >= c;
        if (anyAbove)
          whole.push_back(cell.id);
      }
    }
  }
  std::vector<double> wholeVolume(whole.size()), wholeCoarse(whole.size());
  Parallel(static_cast<NodeId>(whole.size()), [&](NodeId begin, NodeId end) {
    for (NodeId k = begin; k < end; ++k)
    {
      const CellForms cell(Scene_, whole[static_cast<std::size_t>(k)]);
      // Over the reference space: the cube, a tetrahedron or wedge collapsed from it, or for a
      // pyramid its collapsed cube (the map is the cube's).
      double sums[2] = { 0.0, 0.0 };
      for (int rule = 0; rule < 2; ++rule)
      {
        const GaussRule& g = gauss(rule == 0 ? 8 : 6);
        for (std::size_t i = 0; i < g.x.size(); ++i)
          for (std::size_t j = 0; j < g.x.size(); ++j)
            for (std::size_t l = 0; l < g.x.size(); ++l)
            {
              const double u = g.x[i], v = g.x[j], w = g.x[l];
              double weight = g.w[i] * g.w[j] * g.w[l];
              glm::dvec3 x, grad;
              glm::dmat3 J;
              double f = 0.0;
              switch (cell.type().space)
              {
                case Space::Tetrahedron:
                  cell.atReference(glm::dvec3(u * (1 - v) * (1 - w), v * (1 - w), w), x, J, f, grad);
                  weight *= (1 - v) * (1 - w) * (1 - w);
                  break;
                case Space::Wedge:
                  cell.atReference(glm::dvec3(u * (1 - v), v, w), x, J, f, grad);
                  weight *= 1 - v;
                  break;
                default: // the cube, and a pyramid's form space
                  cell.at(glm::dvec3(u, v, w), x, J, f, grad);
              }
              sums[rule] += weight * std::abs(glm::determinant(J));
            }
      }
      wholeVolume[static_cast<std::size_t>(k)] = sums[0];
      wholeCoarse[static_cast<std::size_t>(k)] = sums[1];
    }
  });
  const auto& valid = Scene_.validCells();
  std::unordered_map<NodeId, std::pair<float, float>> ranges;
  for (const auto& cell : valid)
    ranges.emplace(cell.id, std::make_pair(cell.valueLo, cell.valueHi));
  for (std::size_t k = 0; k < whole.size(); ++k)
  {
    const auto range = ranges[whole[k]];
    for (std::size_t i = 0; i < Settings.isoValues.size(); ++i)
    {
      if (range.first >= Settings.isoValues[i])
      {
        Surface.integrals[i].volume += wholeVolume[k];
        Surface.integrals[i].volumeError += std::abs(wholeVolume[k] - wholeCoarse[k]);
      }
    }
  }
}

} // namespace

void finishSurface(const Scene& scene, const ExactSurfaceSettings& settings,
  const std::vector<ArrayView>& arrays, const std::vector<const double*>& values, SurfaceParts& parts,
  ExactSurfaceMesh& surface, const ParallelFor& parallelFor)
{
  SurfaceFinisher finish(scene, settings, arrays, values, parts, surface, parallelFor);
  finish.renumberVertices();
  finish.startArrays();
  finish.vertexAttributes();
  finish.orientTriangles();
  finish.countEdges();
  finish.startIntegrals();
  if (!settings.integrals)
    return;
  finish.triangleIntegrals();
  finish.boundaryEdgeErrors();
  finish.pieceVolumes();
  finish.layerVolumes();
  finish.wholeCellVolumes();
}

} // namespace exact
} // namespace tetdsr
