#include "tetdsr/cells/CurvedHigherOrderTetCell.h"

#include "tetdsr/math/CurvedTet.h"
#include "tetdsr/math/HigherOrderTet.h"
#include "tetdsr/cells/IsoparametricRay.h"
#include "tetdsr/math/QuadraticTet.h"

#include <algorithm>
#include <cmath>

namespace tetdsr
{

namespace
{
/// The cell's geometry in its local frame (origin its vertex 0, unit near its longest edge).
template <int P>
IsoparametricGeometry<P> localGeometry(const glm::dvec3* nodes)
{
  return IsoparametricGeometry<P>::fromNodes(nodes, scaleFor(longestEdge(nodes)));
}

/// The field's form (canonical order) from its coefficients (VTK order), times `scale`.
template <int P>
PolynomialForm<P> fieldForm(const double* values, double scale)
{
  PolynomialForm<P> form;
  for (int node = 0; node < latticeCount(P); ++node)
  {
    form.c[HigherOrderTet<P>::kLatticeOfNode[node]] = values[node] * scale;
  }
  return form;
}
} // namespace

template <int P>
std::uint16_t CurvedHigherOrderTetCell<P>::validate(const glm::dvec3* nodes, std::uint16_t flags)
{
  const JacobianSign sign = jacobianSign(localGeometry<P>(nodes));
  if (sign == JacobianSign::Changes)
  {
    return kTangled;
  }
  return static_cast<std::uint16_t>(
    (flags & ~kInverted) | (sign == JacobianSign::Negative ? kInverted : 0));
}

template <int P>
bool CurvedHigherOrderTetCell<P>::extent(const glm::dvec3* nodes, glm::dvec3& lo, glm::dvec3& hi)
{
  // The control points are the nodes (world coordinates): their box, exactly.
  lo = hi = nodes[0];
  for (int node = 1; node < latticeCount(P); ++node)
  {
    lo = glm::min(lo, nodes[node]);
    hi = glm::max(hi, nodes[node]);
  }
  return isFinite(lo) && isFinite(hi);
}

template <int P>
bool CurvedHigherOrderTetCell<P>::contains(const glm::dvec3* nodes, const glm::dvec3& point, double L[4])
{
  return isoparametric::contains(localGeometry<P>(nodes), point, L);
}

template <int P>
void CurvedHigherOrderTetCell<P>::coordinates(const glm::dvec3* nodes, const glm::dvec3& point, double L[4])
{
  isoparametric::coordinates(localGeometry<P>(nodes), nodes, point, L);
}

template <int P>
glm::dvec3 CurvedHigherOrderTetCell<P>::gradient(
  const glm::dvec3* nodes, const double* values, const double L[4])
{
  const IsoparametricGeometry<P> geometry = localGeometry<P>(nodes);
  // grad_x f = s grad_X f (X the local coordinates).
  return curvedGradient(geometry, fieldForm<P>(values, 1.0), L) * geometry.scale;
}

template <int P>
bool CurvedHigherOrderTetCell<P>::intersect(const glm::dvec3* nodes, const double* values,
  const IsoValues& isoValues, std::size_t first, std::size_t last, const Ray& ray, double tMin,
  double tLimit, SurfaceHit& hit, bool& certified)
{
  // Recorded, then the record's ray test (the collapsed cube's box solve).
  CellRecord cell{};
  double coefficients[kRecordCoefficients];
  record(nodes, values, cell, coefficients);
  return HexahedronCell<P, true>::intersect(cell, ray, isoValues, first, last, tMin, tLimit, hit, certified);
}

template struct CurvedHigherOrderTetCell<3>;
template struct CurvedHigherOrderTetCell<4>;

} // namespace tetdsr
