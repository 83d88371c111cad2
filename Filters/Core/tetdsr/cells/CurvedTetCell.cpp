#include "tetdsr/cells/CurvedTetCell.h"

#include "tetdsr/math/CurvedTet.h"
#include "tetdsr/cells/IsoparametricRay.h"
#include "tetdsr/math/QuadraticTet.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetdsr
{

namespace
{
/// The curved cell's geometry in its local frame (origin its vertex 0, unit near its size).
CurvedGeometry localGeometry(const glm::dvec3 nodes[kCellNodes])
{
  double size = 0.0;
  for (const auto& edge : kEdgeVertices)
  {
    size = std::max(size, glm::length(nodes[edge[0]] - nodes[edge[1]]));
  }
  return CurvedGeometry::fromNodes(nodes, scaleFor(size));
}

/// The field's form scaled by a power of two (returned in `scale`) to a largest magnitude near 1,
/// and its Bernstein bound [lo, hi] (scaled).
BernsteinForm scaledFieldForm(const double nodeValues[kCellNodes], double& scale, double& lo, double& hi)
{
  scale = unitScale(nodeValues);
  double values[kCellNodes];
  for (int n = 0; n < kCellNodes; ++n)
  {
    values[n] = nodeValues[n] * scale;
  }
  const BernsteinForm form = BernsteinForm::fromNodeValues(values);
  form.range(lo, hi);
  return form;
}
} // namespace

std::uint16_t CurvedTetCell::validate(const glm::dvec3 nodes[kCellNodes], std::uint16_t flags)
{
  const JacobianSign sign =
    jacobianSign(CurvedGeometry::fromNodes(nodes, scaleFor(longestEdge(nodes))));
  if (sign == JacobianSign::Changes)
  {
    return kTangled;
  }
  return static_cast<std::uint16_t>(
    (flags & ~kInverted) | (sign == JacobianSign::Negative ? kInverted : 0));
}

bool CurvedTetCell::extent(const glm::dvec3 nodes[kCellNodes], glm::dvec3& lo, glm::dvec3& hi)
{
  CurvedGeometry::fromNodes(nodes, scaleFor(longestEdge(nodes))).box(lo, hi);
  return isFinite(lo) && isFinite(hi);
}

bool CurvedTetCell::contains(const glm::dvec3 nodes[kCellNodes], const glm::dvec3& point, double L[4])
{
  return isoparametric::contains(localGeometry(nodes), point, L);
}

void CurvedTetCell::coordinates(const glm::dvec3 nodes[kCellNodes], const glm::dvec3& point, double L[4])
{
  isoparametric::coordinates(localGeometry(nodes), nodes, point, L);
}

glm::dvec3 CurvedTetCell::gradient(
  const glm::dvec3 nodes[kCellNodes], const double values[kCellNodes], const double L[4])
{
  const CurvedGeometry geometry = localGeometry(nodes);
  const BernsteinForm field = BernsteinForm::fromNodeValues(values);
  // grad_x f = s grad_X f (X the local coordinates).
  return curvedGradient(geometry, field, L) * geometry.scale;
}

bool CurvedTetCell::intersect(const glm::dvec3 nodes[kCellNodes], const double values[kCellNodes],
  const IsoValues& isoValues, std::size_t first, std::size_t last, const Ray& ray, double tMin,
  double tLimit, SurfaceHit& hit, bool& certified)
{
  CellRecord cell{};
  double coefficients[kRecordCoefficients];
  record(nodes, values, cell, coefficients);
  return HexahedronCell<2, true>::intersect(cell, ray, isoValues, first, last, tMin, tLimit, hit, certified);
}

} // namespace tetdsr
