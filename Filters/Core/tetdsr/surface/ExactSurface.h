// The exact isosurface as data: a watertight triangle surface whose vertices are certified roots
// of the cell's own polynomial field and whose every triangle lies within a stated distance of
// the true surface, with every piece found, and the area, enclosed volume and point-array
// integrals of the curved surface computed to high order.
//
// How (docs/how-it-works.md, "The exact surface as data"):
//  - Each cell whose certified field range holds an iso-value is divided, in its own reference
//    space (the tetrahedron's, the cube's, the wedge's triangle x segment, the pyramid's own
//    shape: spaces whose faces map affinely onto a neighbour's), into tetrahedra: a centre, and
//    a centre on each quadrilateral face.
//  - Those tetrahedra are bisected at their longest edge until each that can hold an iso-value is
//    certified: the Bernstein coefficients of f - l on its box (l the affine function of its
//    corners' values) bound the slab the surface lies in, and those of the field's directional
//    derivatives show it monotone along a direction inside it and along a direction in each face
//    the surface may cross, and along every edge the surface may cross (or Descartes' rule counts
//    the edge's roots); then the surface in it is one disc, bounded by the loop the
//    marching-tetrahedra case draws, and the distance from it to the case's triangles is bounded
//    (ExactSurfaceCertificate.cpp). A piece at a pyramid's apex, or whose topology is not shown,
//    is certified by its size alone (the box around its image within the bound). Vertices are
//    named by the mesh's points and the edges bisected, so neighbouring cells bisect shared faces
//    alike (conforming closure): no cracks.
//  - A tetrahedron still uncertified after kMaxSurfaceLevels bisections is counted, and warned of.
#pragma once

#include "tetdsr/input/MeshInput.h"
#include "tetdsr/common/Messages.h"
#include "tetdsr/index/Scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace tetdsr
{

/// Bisections of a cell's first tetrahedra at most.
constexpr int kMaxSurfaceLevels = 48;
/// Pieces of cells at most (about 150 bytes each): past it refinement stops, with a warning.
constexpr long long kMaxSurfacePieces = 2000000;
/// The default distance bound, relative to the diagonal of the valid cells' box.
constexpr double kDefaultRelativeTolerance = 1e-3;

/// What the exact surface is asked for.
struct ExactSurfaceSettings
{
  std::vector<double> isoValues;
  /// The largest distance from any triangle to the true surface (and back), relative to the
  /// diagonal of the valid cells' box; used when `tolerance` is 0.
  double relativeTolerance = kDefaultRelativeTolerance;
  /// The same, absolute (scene units); 0: relativeTolerance times the diagonal.
  double tolerance = 0.0;
  /// Compute the area, enclosed volume and point-array integrals.
  bool integrals = true;
};

/// False, with an error naming the setting, when a tolerance is negative, not finite, or both
/// are 0, or an iso-value is refused (checkIsoValues).
bool checkExactSurfaceSettings(const ExactSurfaceSettings& settings, Messages& messages);

/// The integrals of one iso-value's surface.
struct SurfaceIntegrals
{
  double isoValue = 0.0;
  double area = 0.0;        ///< of the curved surface
  double areaError = 0.0;   ///< an estimate of |area - exact| (see ExactSurfaceIntegrals.h)
  double volume = 0.0;      ///< of the region of the valid cells where the field >= isoValue
  double volumeError = 0.0; ///< an estimate of |volume - exact|
  /// Per point array given, per component: its integral over the curved surface, and an estimate
  /// of that integral's error. Arrays one after another, components within each.
  std::vector<double> arrayIntegrals;
  std::vector<double> arrayErrors;
  double flatArea = 0.0;    ///< the triangles' area, for comparison
  NodeId triangles = 0;
};

/// The surface.
struct ExactSurfaceMesh
{
  std::vector<double> points;    ///< x, y, z per vertex: certified roots on the surface
  std::vector<double> normals;   ///< the exact unit normal (the field's gradient) per vertex
  std::vector<NodeId> triangles; ///< 3 vertex ids per triangle, its normal toward higher values
  std::vector<NodeId> cellIds;   ///< per triangle: the input cell it lies in
  std::vector<int> isoIndices;   ///< per triangle: the iso-value's position in the settings
  /// Per point array given: its values at each vertex (its components per vertex), interpolated
  /// exactly with the cell's shape functions.
  std::vector<std::vector<double>> arrays;
  std::vector<SurfaceIntegrals> integrals; ///< per iso-value, the settings' order
  double tolerance = 0.0;     ///< the absolute distance bound asked
  double largestBound = 0.0;  ///< the largest certified distance bound of any piece drawn
  NodeId subcells = 0;        ///< tetrahedra examined, all levels
  NodeId unresolvedSubcells = 0; ///< at kMaxSurfaceLevels without a certificate (drawn as cased)
  /// Certified by their size alone: the surface crosses one of their faces or edges at a grazing
  /// angle, so the surface in them is within the bound of their triangles, but its topology there
  /// (at a scale below the bound) is not certified.
  NodeId sizeCertifiedSubcells = 0;
  /// Edges of the output used by one triangle (on the mesh's boundary where the surface meets
  /// it), and by more than two (none on a certified surface).
  NodeId boundaryEdges = 0;
  NodeId nonManifoldEdges = 0;
};

/// The exact surface of the scene's field (every valid cell, every kind and order). `arrays`
/// are point arrays (as MeshArrays holds them: any NumberType, any components, at least one
/// tuple per point) interpolated at the vertices and integrated over the surface; one that has
/// too few tuples is refused with an error naming it. False, with errors, when nothing can be
/// made; warnings count uncertified tetrahedra.
bool extractExactSurface(const Scene& scene, const ExactSurfaceSettings& settings,
  const std::vector<ArrayView>& arrays, ExactSurfaceMesh& surface, Messages& messages,
  const ParallelFor& parallelFor = serialFor);

} // namespace tetdsr
