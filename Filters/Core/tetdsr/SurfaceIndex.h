// What rays are cast into: the cells of a Scene that can hold one of a set of iso-values (the
// transverse cells: value range within the scene's transverse test), and a 4-wide hierarchy over
// them. Built per set of iso-values: a scan of the scene's ranges and a build over the cells it
// selects, which are usually a small part of the mesh ("model only what the scene needs").
#pragma once

#include "tetdsr/Hierarchy.h"
#include "tetdsr/Scene.h"

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
  /// is none.
  bool firstHit(const Ray& ray, SurfaceHit& hit, double tMin = 0.0,
    double tMax = std::numeric_limits<double>::infinity()) const;

  /// How many cells can hold one of the iso-values.
  NodeId transverseCells() const { return static_cast<NodeId>(Cells_->selection.size()); }

  /// Whether records are kept (see the constructor).
  bool keepsRecords() const { return !Cells_->records.empty() || Cells_->selection.empty(); }

  /// Bytes this index keeps: per transverse cell a 256-byte record (within the limit; for cells
  /// of order 3 and 4 also 160 and 280 bytes of coefficients), 8 bytes of selection and
  /// hierarchy order, and about 40 bytes of hierarchy nodes (128 bytes per node of up to 4
  /// leaves).
  std::size_t memoryBytes() const
  {
    return Cells_->hierarchy.memoryBytes() + Cells_->records.capacity() * sizeof(CellRecord) +
      Cells_->coefficients.capacity() * sizeof(double) +
      Cells_->selection.capacity() * sizeof(std::uint32_t);
  }

private:
  /// What depends only on which cells are selected.
  struct Cells
  {
    std::vector<std::uint32_t> selection; ///< cell ids, ascending
    Hierarchy hierarchy;
    FillLaterVector<CellRecord> records; ///< in the hierarchy's leaf order; or none
    /// The numbers records keep beside them (cells of order 3 and 4: their field's coefficients)
    FillLaterVector<double> coefficients;
  };
  const Scene& Scene_;
  IsoValues IsoValues_;
  std::shared_ptr<const Cells> Cells_;
};

} // namespace tetdsr
