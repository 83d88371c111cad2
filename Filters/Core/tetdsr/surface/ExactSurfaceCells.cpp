// The exact surface's view of a cell (ExactSurfaceCells.h): its map and field as tensor forms in
// its reference space, evaluated at points and bounded over boxes (Bernstein coefficients).
#include "tetdsr/surface/ExactSurfaceCells.h"

#include "tetdsr/cells/Cells.h"
#include "tetdsr/cells/HexahedronCell.h"
#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/cells/SplitCells.h"
#include "tetdsr/math/TensorBernstein.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>

namespace tetdsr
{
namespace exact
{
namespace
{

template <typename Step>
decltype(auto) forDegree(int P, Step&& step)
{
  return forHexahedronOrder(P, std::forward<Step>(step));
}

/// The tetrahedron's shape function of node multi-index alpha (sum p) at barycentric L: the
/// Lagrange polynomial of the equispaced lattice, or the Bernstein polynomial.
double tetBasis(int p, const int alpha[4], const double L[4], bool bezier)
{
  double value = 1.0;
  if (bezier)
  {
    int rest = p;
    for (int k = 0; k < 4; ++k)
    {
      value *= tensor::binomial(rest, alpha[k]) * std::pow(L[k], alpha[k]);
      rest -= alpha[k];
    }
    return value;
  }
  for (int k = 0; k < 4; ++k)
  {
    for (int m = 0; m < alpha[k]; ++m)
    {
      value *= (p * L[k] - m) / (m + 1);
    }
  }
  return value;
}

/// The faces of a space, from its corners' reference points: the corners on each bounding
/// plane, in cyclic order about their centre.
std::vector<std::vector<int>> facesOf(Space space, const std::vector<glm::dvec3>& corners)
{
  std::vector<std::vector<int>> faces;
  auto plane = [&](auto on) {
    std::vector<int> face;
    for (int c = 0; c < static_cast<int>(corners.size()); ++c)
    {
      if (on(corners[static_cast<std::size_t>(c)]))
        face.push_back(c);
    }
    // Cyclic order: by angle about the centre in the face's plane.
    glm::dvec3 centre(0.0);
    for (int c : face)
      centre += corners[static_cast<std::size_t>(c)];
    centre /= static_cast<double>(face.size());
    const glm::dvec3 u = corners[static_cast<std::size_t>(face[0])] - centre;
    const glm::dvec3 normal = glm::cross(u, corners[static_cast<std::size_t>(face[1])] - centre);
    glm::dvec3 n = glm::length(normal) > 0.0 ? normal : glm::cross(u, corners[static_cast<std::size_t>(face[2])] - centre);
    const glm::dvec3 v = glm::cross(n, u);
    std::sort(face.begin(), face.end(), [&](int a, int b) {
      const glm::dvec3 da = corners[static_cast<std::size_t>(a)] - centre;
      const glm::dvec3 db = corners[static_cast<std::size_t>(b)] - centre;
      return std::atan2(glm::dot(da, v), glm::dot(da, u)) < std::atan2(glm::dot(db, v), glm::dot(db, u));
    });
    faces.push_back(face);
  };
  auto near = [](double a, double b) { return std::abs(a - b) < 1e-9; };
  switch (space)
  {
    case Space::Tetrahedron:
      faces = { { 1, 2, 3 }, { 0, 2, 3 }, { 0, 1, 3 }, { 0, 1, 2 } };
      break;
    case Space::Cube:
      for (int axis = 0; axis < 3; ++axis)
        for (double side : { 0.0, 1.0 })
          plane([&](const glm::dvec3& p) { return near(p[axis], side); });
      break;
    case Space::Wedge:
      plane([&](const glm::dvec3& p) { return near(p.x, 0.0); });
      plane([&](const glm::dvec3& p) { return near(p.y, 0.0); });
      plane([&](const glm::dvec3& p) { return near(p.x + p.y, 1.0); });
      plane([&](const glm::dvec3& p) { return near(p.z, 0.0); });
      plane([&](const glm::dvec3& p) { return near(p.z, 1.0); });
      break;
    case Space::Pyramid:
      plane([&](const glm::dvec3& p) { return near(p.z, 0.0); });
      for (int axis = 0; axis < 2; ++axis)
        for (double side : { 0.0, 1.0 })
          plane([&](const glm::dvec3& p) { return near(p[axis], side) || near(p.z, 1.0); });
      break;
  }
  return faces;
}

/// A form matrix from shape functions sampled at the lattice of degree P in [0, 1]^3.
template <typename Basis>
void sampleMatrix(FormMatrix& type, Basis&& basis)
{
  forDegree(type.degree, [&](auto degree) {
    constexpr int P = decltype(degree)::value;
    constexpr int N = tensor::count(P);
    const int nodes = type.nodes;
    type.matrix.assign(static_cast<std::size_t>(N * nodes), 0.0);
    std::vector<double> weights(static_cast<std::size_t>(nodes));
    std::vector<double> columns(static_cast<std::size_t>(N * nodes));
    for (int k = 0; k <= P; ++k)
      for (int j = 0; j <= P; ++j)
        for (int i = 0; i <= P; ++i)
        {
          const double point[3] = { double(i) / P, double(j) / P, double(k) / P };
          basis(point, weights.data());
          const int at = tensor::index(P, i, j, k);
          for (int n = 0; n < nodes; ++n)
            columns[static_cast<std::size_t>(n * N + at)] = weights[static_cast<std::size_t>(n)];
        }
    for (int n = 0; n < nodes; ++n)
    {
      double* column = columns.data() + static_cast<std::size_t>(n * N);
      tensor::lagrangeToBernstein<P>(column);
      for (int k = 0; k < N; ++k)
        type.matrix[static_cast<std::size_t>(k * nodes + n)] = column[k];
    }
  });
}

void finish(FormMatrix& type)
{
  const int N = tensor::count(type.degree);
  type.growth = 0.0;
  for (int k = 0; k < N; ++k)
  {
    double sum = 0.0;
    for (int n = 0; n < type.nodes; ++n)
      sum += std::abs(type.matrix[static_cast<std::size_t>(k * type.nodes + n)]);
    type.growth = std::max(type.growth, sum);
  }
  type.faces = facesOf(type.space, type.corners);
}

std::unique_ptr<FormMatrix> makeFormMatrix(int vtkType, long long ids)
{
  const CellType* cellType = cellTypeOf(vtkType);
  int order = 0;
  if (!cellType || readOrder(cellType, ids, order) != 0)
    return nullptr;
  auto type = std::make_unique<FormMatrix>();
  type->nodes = static_cast<int>(ids);
  switch (cellType->shape)
  {
    case CellShape::Tetrahedron:
    {
      type->space = Space::Tetrahedron;
      type->degree = order;
      std::vector<std::array<int, 4>> alpha(static_cast<std::size_t>(ids));
      for (int n = 0; n < ids; ++n)
      {
        double L[4];
        tetNodePoint(order, n, L);
        for (int k = 0; k < 4; ++k)
          alpha[static_cast<std::size_t>(n)][static_cast<std::size_t>(k)] = static_cast<int>(std::lround(L[k] * order));
      }
      const bool bezier = cellType->bezier;
      sampleMatrix(*type, [&](const double r[3], double* weights) {
        const double L[4] = { 1.0 - r[0] - r[1] - r[2], r[0], r[1], r[2] };
        for (int n = 0; n < ids; ++n)
          weights[n] = tetBasis(order, alpha[static_cast<std::size_t>(n)].data(), L, bezier);
      });
      type->corners = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
      break;
    }
    case CellShape::Hexahedron:
    case CellShape::Wedge:
    {
      const SplitShape* shape = nullptr;
      if (splitShapeOf(vtkType, ids, shape) != 0)
        return nullptr;
      type->space = cellType->shape == CellShape::Wedge ? Space::Wedge : Space::Cube;
      type->degree = order;
      sampleMatrix(*type, [&](const double r[3], double* weights) { shape->basis(r, weights); });
      const int cornerCount = type->space == Space::Wedge ? 6 : 8;
      for (int c = 0; c < cornerCount; ++c)
      {
        const auto& p = shape->nodePoints[static_cast<std::size_t>(c)];
        type->corners.emplace_back(p[0], p[1], p[2]);
      }
      break;
    }
    case CellShape::Pyramid:
    {
      const HexahedronNodes* table = nullptr;
      if (hexahedronNodesOf(vtkType, ids, table) != 0)
        return nullptr;
      type->space = Space::Pyramid;
      type->degree = table->order;
      const int N = tensor::count(table->order);
      type->matrix.assign(static_cast<std::size_t>(N * type->nodes), 0.0);
      std::vector<double> items(static_cast<std::size_t>(std::max(kMaxCellNodes, type->nodes)));
      for (int n = 0; n < type->nodes; ++n)
      {
        std::fill(items.begin(), items.end(), 0.0);
        items[static_cast<std::size_t>(n)] = 1.0;
        toTensorForm(*table, items.data());
        for (int k = 0; k < N; ++k)
          type->matrix[static_cast<std::size_t>(k * type->nodes + n)] = items[static_cast<std::size_t>(k)];
      }
      for (int c = 0; c < 5; ++c)
      {
        const auto& p = table->nodePoints[static_cast<std::size_t>(c)];
        type->corners.emplace_back(0.5 + (p[0] - 0.5) * (1.0 - p[2]), 0.5 + (p[1] - 0.5) * (1.0 - p[2]), p[2]);
      }
      break;
    }
  }
  finish(*type);
  return type;
}

/// The bounds of a product and a sum of intervals.
Interval operator*(const Interval& a, const Interval& b)
{
  const double p[4] = { a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi };
  return { *std::min_element(p, p + 4), *std::max_element(p, p + 4) };
}
Interval operator+(const Interval& a, const Interval& b)
{
  return { a.lo + b.lo, a.hi + b.hi };
}

/// A form's coefficients on the form-space box [a, b] (its segment matrices, made once per box).
template <int P>
struct BoxRestriction
{
  double matrix[3][P + 1][P + 1];

  BoxRestriction(const glm::dvec3& a, const glm::dvec3& b)
  {
    for (int axis = 0; axis < 3; ++axis)
      tensor::segmentMatrix<P>(a[axis], b[axis], matrix[axis]);
  }

  /// `out` (count(P) values) = the form's coefficients on the box.
  void operator()(const double* form, double* out) const
  {
    double work[tensor::count(P)];
    tensor::transformAxis<P>(form, 0, matrix[0], out);
    tensor::transformAxis<P>(out, 1, matrix[1], work);
    tensor::transformAxis<P>(work, 2, matrix[2], out);
  }
};

} // namespace

const FormMatrix* formMatrixOf(int vtkType, long long ids)
{
  static std::mutex mutex;
  static std::map<std::pair<int, long long>, std::unique_ptr<FormMatrix>> built;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& slot = built[{ vtkType, ids }];
  if (!slot)
    slot = makeFormMatrix(vtkType, ids);
  return slot.get();
}

CellForms::CellForms(const Scene& scene, NodeId cellId)
  : CellId(cellId)
{
  const MeshView& mesh = scene.mesh();
  const NodeId begin = mesh.offsets[cellId];
  const long long count = mesh.offsets[cellId + 1] - begin;
  Type = formMatrixOf(mesh.cellTypes[cellId], count);
  Ids = mesh.connectivity + begin;
  const int N = tensor::count(Type->degree);
  const int nodes = Type->nodes;
  Coefficients.assign(static_cast<std::size_t>(4 * N), 0.0);
  for (int k = 0; k < N; ++k)
  {
    const double* row = Type->matrix.data() + static_cast<std::size_t>(k * nodes);
    double sums[4] = { 0.0, 0.0, 0.0, 0.0 };
    for (int n = 0; n < nodes; ++n)
    {
      const NodeId id = Ids[n];
      for (int a = 0; a < 3; ++a)
        sums[a] += row[n] * mesh.points[3 * id + a];
      sums[3] += row[n] * mesh.values[id];
    }
    for (int a = 0; a < 4; ++a)
      Coefficients[static_cast<std::size_t>(a * N + k)] = sums[a];
  }
  for (int n = 0; n < nodes; ++n)
    FieldMagnitude = std::max(FieldMagnitude, std::abs(mesh.values[Ids[n]]));
}

glm::dvec3 CellForms::toForm(const glm::dvec3& r) const
{
  if (Type->space != Space::Pyramid)
    return r;
  const double rest = 1.0 - r.z;
  if (!(rest > 0.0))
    return { 0.5, 0.5, 1.0 };
  return { std::clamp(0.5 + (r.x - 0.5) / rest, 0.0, 1.0), std::clamp(0.5 + (r.y - 0.5) / rest, 0.0, 1.0), r.z };
}

double CellForms::evaluateForm(const double* form, const glm::dvec3& at) const
{
  const double x[3] = { at.x, at.y, at.z };
  return forDegree(Type->degree, [&](auto degree) {
    constexpr int P = decltype(degree)::value;
    return tensor::evaluate<P>(form, x);
  });
}

void CellForms::at(const glm::dvec3& e, glm::dvec3& x, glm::dmat3& J, double& f, glm::dvec3& grad) const
{
  const double point[3] = { e.x, e.y, e.z };
  forDegree(Type->degree, [&](auto degree) {
    constexpr int P = decltype(degree)::value;
    constexpr int N = tensor::count(P);
    double g[3];
    for (int a = 0; a < 3; ++a)
    {
      x[a] = tensor::evaluate<P>(Coefficients.data() + a * N, point, g);
      for (int i = 0; i < 3; ++i)
        J[i][a] = g[i]; // column i (d/d axis i), row a
    }
    f = tensor::evaluate<P>(Coefficients.data() + 3 * N, point, g);
    grad = glm::dvec3(g[0], g[1], g[2]);
  });
}

void CellForms::atReference(const glm::dvec3& r, glm::dvec3& x, glm::dmat3& J, double& f, glm::dvec3& grad) const
{
  const glm::dvec3 e = toForm(r);
  at(e, x, J, f, grad);
  if (Type->space != Space::Pyramid)
    return;
  // The collapse's derivative D = d form / d reference: u = 1/2 + (a - 1/2) k, k = 1/(1 - c).
  const double k = 1.0 / std::max(1.0 - r.z, std::numeric_limits<double>::min());
  glm::dmat3 D(0.0);
  D[0][0] = k;                 // column a: du/da
  D[1][1] = k;                 // column b: dv/db
  D[2] = glm::dvec3((e.x - 0.5) * k, (e.y - 0.5) * k, 1.0); // column c
  J = J * D;
  grad = glm::transpose(D) * grad;
}

double CellForms::fieldAtReference(const glm::dvec3& r) const
{
  const int N = tensor::count(Type->degree);
  return evaluateForm(Coefficients.data() + 3 * N, toForm(r));
}

void CellForms::arrayForm(const double* values, int components, int component, std::vector<double>& out) const
{
  const int N = tensor::count(Type->degree);
  const int nodes = Type->nodes;
  out.assign(static_cast<std::size_t>(N), 0.0);
  for (int k = 0; k < N; ++k)
  {
    const double* row = Type->matrix.data() + static_cast<std::size_t>(k * nodes);
    double sum = 0.0;
    for (int n = 0; n < nodes; ++n)
      sum += row[n] * values[Ids[n] * components + component];
    out[static_cast<std::size_t>(k)] = sum;
  }
}

void CellForms::bounds(const glm::dvec3& lo, const glm::dvec3& hi, Bounds& out) const
{
  boundsOf(lo, hi, out, false);
}

void CellForms::fieldBounds(const glm::dvec3& lo, const glm::dvec3& hi, Bounds& out) const
{
  boundsOf(lo, hi, out, true);
}

bool CellForms::formBox(const glm::dvec3& boxLo, const glm::dvec3& boxHi, glm::dvec3& a, glm::dvec3& b, Interval& k,
  Interval& uc, Interval& vc) const
{
  // A box flat along an axis (a face or an edge along the space's axes) is widened a little
  // there: a larger box's bounds hold too, and its differences give the derivative across it.
  glm::dvec3 lo = boxLo, hi = boxHi;
  for (int axis = 0; axis < 3; ++axis)
  {
    if (hi[axis] - lo[axis] < 1e-6)
    {
      lo[axis] = std::max(0.0, lo[axis] - 1e-6);
      hi[axis] = std::min(1.0, hi[axis] + 1e-6);
    }
  }
  a = lo;
  b = hi;
  k = { 1.0, 1.0 };
  uc = vc = { 0.0, 0.0 };
  if (Type->space != Space::Pyramid)
    return true;
  // The box's image in the collapsed cube: u - 1/2 = (a - 1/2) k, k = 1 / (1 - c).
  if (hi.z >= 1.0)
  {
    a = glm::dvec3(0.0, 0.0, lo.z);
    b = glm::dvec3(1.0, 1.0, 1.0);
    return false;
  }
  k = { 1.0 / (1.0 - lo.z), 1.0 / (1.0 - hi.z) };
  uc = Interval{ lo.x - 0.5, hi.x - 0.5 } * k;
  vc = Interval{ lo.y - 0.5, hi.y - 0.5 } * k;
  a = glm::dvec3(std::max(0.0, 0.5 + uc.lo), std::max(0.0, 0.5 + vc.lo), lo.z);
  b = glm::dvec3(std::min(1.0, 0.5 + uc.hi), std::min(1.0, 0.5 + vc.hi), hi.z);
  return true;
}

double CellForms::deviation(const glm::dvec3& lo, const glm::dvec3& hi, int quantity, double value,
  const glm::dvec3& gradient) const
{
  glm::dvec3 a, b;
  Interval k, uc, vc;
  if (!formBox(lo, hi, a, b, k, uc, vc))
    return std::numeric_limits<double>::infinity();
  const bool pyramid = Type->space == Space::Pyramid;
  return forDegree(Type->degree, [&](auto degree) {
    constexpr int P = decltype(degree)::value;
    constexpr int N = tensor::count(P);
    double one[N];
    BoxRestriction<P>(a, b)(Coefficients.data() + quantity * N, one);
    double largest = 0.0;
    for (int kk = 0; kk <= P; ++kk)
      for (int jj = 0; jj <= P; ++jj)
        for (int ii = 0; ii <= P; ++ii)
        {
          // The Greville point's form-space point, and its reference point.
          const glm::dvec3 t(double(ii) / P, double(jj) / P, double(kk) / P);
          const glm::dvec3 u = a + t * (b - a);
          const glm::dvec3 r = pyramid ? glm::dvec3(0.5 + (u.x - 0.5) * (1.0 - u.z), 0.5 + (u.y - 0.5) * (1.0 - u.z), u.z) : u;
          const double affine = value + glm::dot(gradient, r);
          largest = std::max(largest, std::abs(one[tensor::index(P, ii, jj, kk)] - affine));
        }
    return largest;
  });
}

void CellForms::slopes(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3* directions, int count,
  Interval* out) const
{
  if (Type->space == Space::Pyramid)
  {
    Bounds b;
    fieldBounds(lo, hi, b);
    for (int d = 0; d < count; ++d)
    {
      out[d] = Interval{ 0.0, 0.0 };
      for (int i = 0; i < 3; ++i)
      {
        const Interval term = b.grad[i] * Interval{ directions[d][i], directions[d][i] };
        out[d].lo += term.lo;
        out[d].hi += term.hi;
      }
      if (!b.finite || !(out[d].lo <= out[d].hi))
        out[d] = { -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity() };
    }
    return;
  }
  glm::dvec3 a, b;
  Interval k, uc, vc;
  formBox(lo, hi, a, b, k, uc, vc);
  forDegree(Type->degree, [&](auto degree) {
    constexpr int P = decltype(degree)::value;
    constexpr int N = tensor::count(P);
    double one[N];
    BoxRestriction<P>(a, b)(Coefficients.data() + 3 * N, one);
    for (int d = 0; d < count; ++d)
    {
      double scale[3];
      for (int axis = 0; axis < 3; ++axis)
        scale[axis] = directions[d][axis] / (b[axis] - a[axis]);
      tensor::directionalRange<P>(one, scale, out[d].lo, out[d].hi);
    }
  });
}

void CellForms::boundsOf(const glm::dvec3& boxLo, const glm::dvec3& boxHi, Bounds& out, bool fieldOnly) const
{
  glm::dvec3 a, b;
  Interval k, uc, vc;
  out.finite = formBox(boxLo, boxHi, a, b, k, uc, vc);
  out.fieldHessian = out.mapHessian = 0.0;
  out.hasHessian = false;
  forDegree(Type->degree, [&](auto degree) {
    constexpr int P = decltype(degree)::value;
    constexpr int N = tensor::count(P);
    const BoxRestriction<P> onBox(a, b);
    Interval partial[4][3]; // per quantity, d/d form axis
    for (int q = fieldOnly ? 3 : 0; q < 4; ++q)
    {
      double one[N];
      onBox(Coefficients.data() + q * N, one);
      if (q == 3)
        out.f = { *std::min_element(one, one + N), *std::max_element(one, one + N) };
      else
        out.x[q] = { *std::min_element(one, one + N), *std::max_element(one, one + N) };
      if (Type->space != Space::Pyramid && !fieldOnly)
      {
        // Second differences of the box's coefficients: the second derivatives' ranges.
        double frobenius = 0.0;
        for (int i = 0; i < 3; ++i)
          for (int j = i; j < 3; ++j)
          {
            const int si = tensor::stride(P, i), sj = tensor::stride(P, j);
            const double factor = (i == j ? P * (P - 1.0) : double(P) * P) / ((b[i] - a[i]) * (b[j] - a[j]));
            double largest = 0.0;
            Interval range{ std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity() };
            for (int kk = 0; kk <= P; ++kk)
              for (int jj = 0; jj <= P; ++jj)
                for (int ii = 0; ii <= P; ++ii)
                {
                  const int n[3] = { ii, jj, kk };
                  if (i == j ? n[i] + 2 > P : (n[i] + 1 > P || n[j] + 1 > P))
                    continue;
                  const int at = tensor::index(P, ii, jj, kk);
                  const double d = i == j ? one[at + 2 * si] - 2.0 * one[at + si] + one[at]
                                          : one[at + si + sj] - one[at + si] - one[at + sj] + one[at];
                  largest = std::max(largest, std::abs(d * factor));
                  range.lo = std::min(range.lo, d * factor);
                  range.hi = std::max(range.hi, d * factor);
                }
            if (P == 1 && i == j)
              range = { 0.0, 0.0 };
            if (q == 3)
              out.fieldSecond[i][j] = out.fieldSecond[j][i] = range;
            frobenius += (i == j ? 1.0 : 2.0) * largest * largest;
          }
        if (q == 3)
          out.fieldHessian = std::sqrt(frobenius);
        else
          out.mapHessian = std::sqrt(out.mapHessian * out.mapHessian + frobenius);
        out.hasHessian = true;
      }
      for (int axis = 0; axis < 3; ++axis)
      {
        const double width = b[axis] - a[axis];
        double dlo = 0.0, dhi = 0.0;
        tensor::derivativeRange<P>(one, axis, dlo, dhi);
        if (width > 0.0)
          partial[q][axis] = { dlo / width, dhi / width };
        else
          partial[q][axis] = { -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity() };
      }
    }
    for (int q = fieldOnly ? 3 : 0; q < 4; ++q)
    {
      Interval ref[3];
      if (Type->space == Space::Pyramid)
      {
        ref[0] = partial[q][0] * k;
        ref[1] = partial[q][1] * k;
        ref[2] = partial[q][2] + partial[q][0] * (uc * k) + partial[q][1] * (vc * k);
      }
      else
      {
        ref[0] = partial[q][0];
        ref[1] = partial[q][1];
        ref[2] = partial[q][2];
      }
      for (int i = 0; i < 3; ++i)
      {
        if (q == 3)
          out.grad[i] = ref[i];
        else
          out.J[q][i] = ref[i];
      }
    }
  });
  if (!out.finite)
  {
    for (int i = 0; i < 3; ++i)
    {
      out.grad[i] = { -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity() };
    }
  }
}

} // namespace exact
} // namespace tetdsr
