// What rays are cast into: the cells of a Scene that can hold one of a set of iso-values (the
// transverse cells: value range within the scene's transverse test), and a 4-wide hierarchy over
// them. Built per set of iso-values: a scan of the scene's ranges and a build over the cells it
// selects, which are usually a small part of the mesh ("model only what the scene needs").
#pragma once

#include "tetdsr/index/Hierarchy.h"
#include "tetdsr/index/Scene.h"

#include <limits>
#include <memory>

namespace tetdsr
{

class SurfaceIndex
{
public:
  /// Selects the transverse cells of `scene` (which must outlive the index) and builds the
  /// hierarchy over them, concurrently through `parallelFor`. When `previous` (an index of the
  /// same scene) selected the very same cells, its hierarchy and records are shared instead of
  /// rebuilt: an iso-value change that keeps the set of transverse cells costs one scan.
  /// Records (256 bytes per transverse cell) are kept only within `recordBytesLimit`; beyond
  /// it (a field with a surface in most of a huge mesh's cells) each candidate cell's record is
  /// made as it is tested: the same hits, about half the rays per second.
  SurfaceIndex(const Scene& scene, const IsoValues& isoValues,
    const ParallelFor& parallelFor = serialFor, const SurfaceIndex* previous = nullptr,
    std::size_t recordBytesLimit = defaultRecordBytesLimit());

  /// A quarter of the machine's physical memory (2 GiB where it cannot be told).
  static std::size_t defaultRecordBytesLimit();

  const Scene& scene() const { return Scene_; }
  const IsoValues& isoValues() const { return IsoValues_; }

  /// The first crossing of any iso-value along the ray with tMin <= t <= tMax; false if there
  /// is none. `hint`, an entry (SurfaceHit::entry) of this index or kNoEntry, is a cell to test
  /// first: where the ray crosses the surface in it, that crossing bounds the search (the
  /// hierarchy prunes every box entered beyond it), and the nearest crossing is still the one
  /// found. Any hint gives the same answer; a good one (e.g. the cell a neighbouring ray hit in
  /// the last frame) gives it sooner.
  bool firstHit(const Ray& ray, SurfaceHit& hit, double tMin = 0.0,
    double tMax = std::numeric_limits<double>::infinity(), std::uint32_t hint = kNoEntry) const;

  /// How many entries the index has (cells that can hold a surface, with records kept).
  std::uint32_t entries() const { return static_cast<std::uint32_t>(Cells_->records.size()); }

  /// Whether any ray within [0, inf) through the pixels of a block, given by the rays of its four
  /// corner pixels in order around it (from a projective camera: the rays between two corners
  /// lie in one plane), may meet a transverse cell's box. False only when none can: the block's
  /// pixels are misses without casting them.
  bool blockMayHit(const Ray corners[4]) const;

  /// How many cells can hold one of the iso-values.
  NodeId transverseCells() const { return static_cast<NodeId>(Cells_->selection.size()); }

  /// Whether records are kept (see the constructor).
  bool keepsRecords() const { return !Cells_->records.empty() || Cells_->selection.empty(); }

  /// Bytes this index keeps: per transverse cell a 256-byte record and its 64-byte faces (within the limit; for cells
  /// of order 3 and 4 also 160 and 280 bytes of coefficients), 8 bytes of selection and
  /// hierarchy order, and about 40 bytes of hierarchy nodes (128 bytes per node of up to 4
  /// leaves).
  std::size_t memoryBytes() const
  {
    return Cells_->hierarchy.memoryBytes() + Cells_->records.capacity() * sizeof(CellRecord) +
      Cells_->faces.capacity() * sizeof(CellFaces) +
      Cells_->coefficients.capacity() * sizeof(double) +
      Cells_->selection.capacity() * sizeof(std::uint32_t);
  }

private:
  /// A straight cell's four face planes in box units, lane k the face where barycentric
  /// coordinate L_k vanishes: n . x + d >= 0 inside (n unit, rounded to float). A ray is tested
  /// against them before the cell's record is read: 1 cache line instead of 4, and a few vector
  /// operations instead of the double-precision test, for the cells whose boxes the ray meets but
  /// which it misses (a tet fills a sixth of its box or less). Curved cells pass (n = 0, d = 1),
  /// records that never hit fail (n = 0, d = -1).
  struct alignas(64) CellFaces
  {
    Float4 n[3];
    Float4 d;
  };
  static CellFaces facesOf(const Scene& scene, const CellRecord& record);
  /// What depends only on which cells are selected.
  struct Cells
  {
    std::vector<std::uint32_t> selection; ///< cell ids, ascending
    Hierarchy hierarchy;
    FillLaterVector<CellRecord> records; ///< in the hierarchy's leaf order; or none
    FillLaterVector<CellFaces> faces;    ///< beside the records (none without records)
    /// The numbers records keep beside them (cells of order 3 and 4: their field's coefficients)
    FillLaterVector<double> coefficients;
  };
  const Scene& Scene_;
  IsoValues IsoValues_;
  std::shared_ptr<const Cells> Cells_;
};

} // namespace tetdsr
