// What rays are cast into: the cells of a Scene that can hold one of a set of iso-values (the
// transverse cells: value range within the scene's transverse test), and a 4-wide hierarchy over
// them. Built per set of iso-values: a scan of the scene's ranges and a build over the cells it
// selects, which are usually a small part of the mesh ("model only what the scene needs").
#pragma once

#include "tetdsr/Hierarchy.h"
#include "tetdsr/Scene.h"

#include <limits>

namespace tetdsr
{

class SurfaceIndex
{
public:
  /// Selects the transverse cells of `scene` (which must outlive the index) and builds the
  /// hierarchy over them, concurrently through `parallelFor`.
  SurfaceIndex(const Scene& scene, const IsoValues& isoValues,
    const ParallelFor& parallelFor = serialFor);

  const Scene& scene() const { return Scene_; }
  const IsoValues& isoValues() const { return IsoValues_; }

  /// The first crossing of any iso-value along the ray with tMin <= t <= tMax; false if there
  /// is none.
  bool firstHit(const Ray& ray, SurfaceHit& hit, double tMin = 0.0,
    double tMax = std::numeric_limits<double>::infinity()) const;

  /// How many cells can hold one of the iso-values.
  NodeId transverseCells() const { return static_cast<NodeId>(Records_.size()); }

  /// Bytes this index keeps: per transverse cell a 256-byte record, 4 bytes of hierarchy order
  /// and about 40 bytes of hierarchy nodes (128 bytes per node of up to 4 leaves).
  std::size_t memoryBytes() const
  {
    return Hierarchy_.memoryBytes() + Records_.capacity() * sizeof(CellRecord);
  }

private:
  const Scene& Scene_;
  IsoValues IsoValues_;
  Hierarchy Hierarchy_;
  FillLaterVector<CellRecord> Records_; ///< in the hierarchy's leaf order
};

} // namespace tetdsr
