// What the exact surface's bisection (ExactSurface.cpp) hands on, and the step that makes the
// output of it: vertices' positions, exact normals and arrays, triangles oriented toward higher
// values, the edge count, and the integrals.
//
// The integrals (ExactSurfaceIntegrals.cpp):
//  - Area and arrays over the surface: each flat triangle is carried onto the curved surface
//    along the directions interpolated from its corners' exact normals (a point p(l) of the
//    triangle goes to p + s d(l) with f = c there, solved with the cell's map and field by
//    Newton's method). Neighbouring triangles share their corners' normals, so the curved patches
//    meet along the same curves: they tile the surface, with no gap or overlap inside the mesh.
//    Each patch's area element is exact (implicit differentiation) and integrated by a collapsed
//    Gauss rule of 6 x 6 points; the estimate is the difference from 4 x 4 points, plus, on edges
//    where the surface meets the mesh's boundary, the edge's length times the carrying distance
//    (the patch's edge is on the surface but need not be on the boundary).
//  - Volume where the field >= c: per piece of the bisection (a tetrahedron of a cell's reference
//    space), |det J| integrated over it (whole pieces above c), or over the polytope the case's
//    triangles cut from it, corrected by the layer between those flat reference triangles and the
//    surface (swept along the piece's direction n). Collapsed Gauss rules of 3^3 and 2^3 points;
//    the estimate is their difference, plus the layers' second-order mismatch at the pieces' faces.
#pragma once

#include "tetdsr/surface/ExactSurface.h"
#include "tetdsr/surface/ExactSurfaceCells.h"

#include <array>
#include <cstdint>
#include <vector>

namespace tetdsr
{
namespace exact
{

/// A root on a piece's edge: an output vertex.
struct SurfaceVertex
{
  std::uint32_t form = 0; ///< the cell (candidate position) that found it
  int iso = 0;
  glm::dvec3 reference{ 0.0 }; ///< in that cell's reference space
  std::uint64_t key = 0;
  double t = 0.0; ///< along its edge from the lower-named end
};

struct SurfaceTriangle
{
  std::uint32_t v[3] = { 0, 0, 0 };
  std::uint32_t form = 0;
  int iso = 0;
  glm::dvec3 reference[3]; ///< its corners in its cell's reference space
  std::uint32_t piece = 0;
  /// Its piece was certified by its size alone: its triangles are within the bound, but they may
  /// fold or overlap, so their area is not the surface's (it counts in the area's error).
  bool sizeOnly = false;
};

/// A tetrahedron of a cell's reference space counted in a volume (sign -1: taken away).
struct VolumeTet
{
  std::uint32_t form = 0;
  int iso = 0;
  double sign = 1.0;
  glm::dvec3 r[4];
};

/// A piece's layer correction for one iso-value: its flat reference triangles and direction.
struct Layer
{
  std::uint32_t form = 0;
  int iso = 0;
  glm::dvec3 direction{ 0.0 };
  std::vector<std::array<glm::dvec3, 3>> triangles;
  double perimeter = 0.0; ///< of the cut in the piece (reference units)
};

struct SurfaceParts
{
  const std::vector<CellForms>* forms = nullptr;
  std::vector<SurfaceVertex> vertices;
  std::vector<SurfaceTriangle> triangles;
  std::vector<VolumeTet> volumeTets; ///< whole pieces above c, and the cut pieces' polytopes
  std::vector<Layer> layers;
  std::vector<NodeId> candidates;    ///< the cells with pieces (the forms' cells)
};

/// The output from the parts: ExactSurfaceMesh's vertices, normals, arrays, triangles, edge
/// counts and (when asked) integrals.
void finishSurface(const Scene& scene, const ExactSurfaceSettings& settings,
  const std::vector<ArrayView>& arrays, const std::vector<const double*>& values, SurfaceParts& parts,
  ExactSurfaceMesh& surface, const ParallelFor& parallelFor);

} // namespace exact
} // namespace tetdsr
