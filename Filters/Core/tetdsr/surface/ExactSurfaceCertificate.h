// The certificate of one piece of the exact surface's bisection (ExactSurface.cpp): whether the
// surface f = c in a tetrahedron of a cell's reference space is one disc within a stated distance
// of the marching-tetrahedra case's triangles, or small enough to be within it by the piece's size
// alone; and the two steps the bisection shares with it, the case's triangles and the root on an
// edge. Why the bound holds: ExactSurfaceCertificate.cpp's top comment.
#pragma once

#include "tetdsr/surface/ExactSurfaceCells.h"

#include <array>
#include <vector>

namespace tetdsr
{
namespace exact
{

/// A tetrahedron's edges, and its faces (face k lacks corner k), by corner.
constexpr int kEdges[6][2] = { { 0, 1 }, { 0, 2 }, { 0, 3 }, { 1, 2 }, { 1, 3 }, { 2, 3 } };
constexpr int kFaces[4][3] = { { 1, 2, 3 }, { 0, 2, 3 }, { 0, 1, 3 }, { 0, 1, 2 } };

/// A piece as the certificate reads it: its cell's forms and, per corner, the reference point, the
/// scene position and the field value (those of the bisection's vertices).
struct PieceCorners
{
  const CellForms* forms = nullptr;
  glm::dvec3 r[4];
  glm::dvec3 x[4];
  double f[4];
};

/// The marching-tetrahedra case of iso-value c for corners with field values `values`: its
/// triangles, each as three (a, b) corner pairs whose edges hold the roots (a == b: a corner at
/// the iso-value; f >= c counts as above).
void caseTriangles(const double values[4], double c, std::vector<std::array<int, 6>>& out);

/// The root of f = c on the reference segment r0 -> r1, where f - c changes sign (rising: from
/// below), as the segment's parameter.
double edgeRoot(const CellForms& forms, const glm::dvec3& r0, const glm::dvec3& r1, double c, bool rising);

/// Whether the piece is certified for iso-value c within `tolerance` (scene units): `bound` its
/// distance bound, `topology` whether the surface in it is certified one disc joined as the case
/// joins it (else it is certified by its size alone). `b` bounds the cell over the piece's box;
/// `margin` is the forms' rounding.
bool certifyPiece(const PieceCorners& piece, const CellForms::Bounds& b, double c, double margin, double tolerance,
  double& bound, bool& topology);

} // namespace exact
} // namespace tetdsr
