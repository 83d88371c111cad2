// The exact surface's view of a cell (ExactSurface.h): its map and field as tensor forms, evaluated
// at points and bounded over boxes of its own reference space.
//
// Every cell is seen in a reference space whose faces a neighbour's face maps onto affinely (so
// a point bisecting a shared edge is the same point seen from either cell): VTK's parametric
// tetrahedron, cube and wedge (triangle x segment), and for pyramids the pyramid itself, apex at
// (1/2, 1/2, 1) (VTK's pyramid parametric space is a collapsed cube, whose side faces are not
// affine images of a tetrahedron's). Tetrahedra, hexahedra and wedges are polynomials of degree
// at most P per axis there, held as tensor Bernstein forms on the unit cube (extended past the
// tetrahedron and the wedge's triangle, which the cube contains); a pyramid is the tensor form of
// its collapsed cube (HexahedronCell.h's tables), composed with the collapse.
#pragma once

#include "tetdsr/index/Scene.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace tetdsr
{
namespace exact
{

/// A cell's reference space.
enum class Space : std::uint8_t
{
  Tetrahedron,
  Cube,
  Wedge,
  Pyramid
};

struct Interval
{
  double lo = 0.0;
  double hi = 0.0;
  double width() const { return hi - lo; }
  bool contains(double v) const { return lo <= v && v <= hi; }
};

/// How a cell type's nodal values become its tensor forms (one per type and node count).
struct FormMatrix
{
  Space space = Space::Cube;
  int degree = 1; ///< P per axis
  int nodes = 0;
  /// count(P) x nodes: coefficient k of a nodal quantity q is sum_n matrix[k * nodes + n] q_n.
  std::vector<double> matrix;
  /// The largest absolute row sum of `matrix`: the growth of the nodes' relative rounding.
  double growth = 1.0;
  /// The reference points of the cell's corners (its first nodes, VTK's order).
  std::vector<glm::dvec3> corners;
  /// The faces, as corner positions in cyclic order (3 or 4).
  std::vector<std::vector<int>> faces;
};

/// The form matrix of a valid cell's type and id count (built on first use, thread-safe); null
/// for a type the scene does not read.
const FormMatrix* formMatrixOf(int vtkType, long long ids);

/// One cell's forms: x, y, z and the field, in the form space (the reference space, or for a
/// pyramid its collapsed cube).
class CellForms
{
public:
  CellForms() = default;
  CellForms(const Scene& scene, NodeId cellId);

  const FormMatrix& type() const { return *Type; }
  NodeId cellId() const { return CellId; }
  const NodeId* ids() const { return Ids; }
  double fieldMagnitude() const { return FieldMagnitude; }

  /// A reference point's form-space point (the same but for pyramids).
  glm::dvec3 toForm(const glm::dvec3& reference) const;

  /// At a form-space point: position, its Jacobian (columns: d/d form axis), field and gradient.
  void at(const glm::dvec3& form, glm::dvec3& x, glm::dmat3& J, double& f, glm::dvec3& grad) const;
  /// The same at a reference point, derivatives along the reference axes.
  void atReference(const glm::dvec3& reference, glm::dvec3& x, glm::dmat3& J, double& f, glm::dvec3& grad) const;
  /// The field alone at a reference point.
  double fieldAtReference(const glm::dvec3& reference) const;

  /// A point array's component as a form (count(P) coefficients), and its value at a form point.
  void arrayForm(const double* values, int components, int component, std::vector<double>& out) const;
  double evaluateForm(const double* form, const glm::dvec3& at) const;

  /// Guaranteed bounds over a box of the reference space: the field, its gradient and the map's
  /// Jacobian (J[k][i] = d x_k / d reference axis i). `finite` false where they are not bounded
  /// (a pyramid's box that reaches its apex).
  struct Bounds
  {
    Interval f;
    Interval grad[3];
    Interval J[3][3];
    Interval x[3]; ///< the map's range: a box around the image of the box
    /// Bounds of the second derivatives' magnitudes along the reference axes, as Frobenius norms
    /// of their largest magnitudes: the field's, and the map's (all components); for spaces
    /// other than pyramids (hasHessian).
    double fieldHessian = 0.0;
    Interval fieldSecond[3][3]; ///< the field's second derivatives (hasHessian)
    double mapHessian = 0.0;
    bool hasHessian = false;
    bool finite = true;
  };
  void bounds(const glm::dvec3& lo, const glm::dvec3& hi, Bounds& out) const;
  /// The field's bounds only (f and grad; the rest left as they are).
  void fieldBounds(const glm::dvec3& lo, const glm::dvec3& hi, Bounds& out) const;

  /// The range of the field's derivative along each of `count` reference directions over a
  /// reference box (the directional derivative's own Bernstein coefficients; a pyramid's from
  /// its gradient's bounds through the collapse); unbounded where they are not bounded.
  void slopes(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3* directions, int count, Interval* out) const;

  /// The largest |Q - A| over a reference box, Q a quantity (0-2: the map's components, 3: the
  /// field) and A(r) = value + gradient . r an affine function of the reference point: from the
  /// Bernstein coefficients of Q - A on the box's form-space box (an affine function of the
  /// reference point is of degree at most 1 per form axis, through a pyramid's collapse too, so
  /// its coefficients are its values at the Greville points). Infinite where a pyramid's box
  /// reaches its apex.
  double deviation(const glm::dvec3& lo, const glm::dvec3& hi, int quantity, double value, const glm::dvec3& gradient) const;

private:
  void boundsOf(const glm::dvec3& lo, const glm::dvec3& hi, Bounds& out, bool fieldOnly) const;
  /// The form-space box of a reference box (flat axes widened by 1e-6), and for pyramids the
  /// collapse's k = 1 / (1 - z) and (u - 1/2), (v - 1/2) ranges; false where it reaches the apex.
  bool formBox(const glm::dvec3& lo, const glm::dvec3& hi, glm::dvec3& a, glm::dvec3& b, Interval& k, Interval& uc,
    Interval& vc) const;

public:

private:
  const FormMatrix* Type = nullptr;
  NodeId CellId = -1;
  const NodeId* Ids = nullptr;
  std::vector<double> Coefficients; ///< 4 forms of count(P): x, y, z, field
  double FieldMagnitude = 0.0;
};

} // namespace exact
} // namespace tetdsr
