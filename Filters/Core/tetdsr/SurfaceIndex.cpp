#include "tetdsr/SurfaceIndex.h"

#include <unistd.h>

namespace tetdsr
{

std::size_t SurfaceIndex::defaultRecordBytesLimit()
{
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long pageSize = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || pageSize <= 0)
  {
    return std::size_t(2) << 30;
  }
  return static_cast<std::size_t>(pages) / 4 * static_cast<std::size_t>(pageSize);
}

SurfaceIndex::SurfaceIndex(const Scene& scene, const IsoValues& isoValues,
  const ParallelFor& parallelFor, const SurfaceIndex* previous, std::size_t recordBytesLimit)
  : Scene_(scene)
  , IsoValues_(isoValues)
{
  // Mark the transverse cells in parallel, then gather them in cell order (so the hierarchy,
  // and every image, is the same for any number of threads).
  const FillLaterVector<Scene::ValidCell>& cells = scene.validCells();
  FillLaterVector<std::uint8_t> transverse(cells.size());
  parallelFor(static_cast<NodeId>(cells.size()), [&](NodeId begin, NodeId end) {
    for (NodeId k = begin; k < end; ++k)
    {
      const auto c = static_cast<std::size_t>(k);
      transverse[c] = isoValues.anyWithin(cells[c].valueLo, cells[c].valueHi);
    }
  });
  std::vector<std::uint32_t> selection;
  for (std::size_t c = 0; c < cells.size(); ++c)
  {
    if (transverse[c])
    {
      selection.push_back(cells[c].id);
    }
  }
  FillLaterVector<std::uint8_t>().swap(transverse);
  const bool keepRecords = selection.size() <= recordBytesLimit / sizeof(CellRecord);
  if (previous && &previous->Scene_ == &scene && previous->Cells_->selection == selection &&
    previous->keepsRecords() == keepRecords)
  {
    Cells_ = previous->Cells_;
    return;
  }
  // Their boxes, the hierarchy over them, then their records in its leaf order (a leaf's cells
  // consecutive in memory).
  auto built = std::make_shared<Cells>();
  std::vector<BoxItem> boxes(selection.size());
  parallelFor(static_cast<NodeId>(selection.size()), [&](NodeId begin, NodeId end) {
    for (NodeId k = begin; k < end; ++k)
    {
      boxes[static_cast<std::size_t>(k)] = scene.cellBox(selection[static_cast<std::size_t>(k)]);
    }
  });
  built->hierarchy.build(std::move(boxes), parallelFor);
  const std::vector<std::uint32_t>& order = built->hierarchy.ids();
  built->records.resize(keepRecords ? order.size() : 0);
  // Where each record's coefficients go (most kinds keep none).
  std::vector<std::size_t> coefficientsAt(built->records.size() + 1, 0);
  for (std::size_t k = 0; k < built->records.size(); ++k)
  {
    coefficientsAt[k + 1] = coefficientsAt[k] + static_cast<std::size_t>(scene.recordCoefficients(order[k]));
  }
  built->coefficients.resize(coefficientsAt.back());
  parallelFor(static_cast<NodeId>(built->records.size()), [&](NodeId begin, NodeId end) {
    for (NodeId k = begin; k < end; ++k)
    {
      const auto at = static_cast<std::size_t>(k);
      scene.prepareCell(order[at], built->records[at], built->coefficients.data() + coefficientsAt[at]);
    }
  });
  built->selection = std::move(selection);
  Cells_ = std::move(built);
}

// Flattened: the traversal, its leaf function and the cell test compiled as one (measured 18%
// faster per ray than with the compiler's own inlining choices).
__attribute__((flatten)) bool SurfaceIndex::firstHit(
  const Ray& ray, SurfaceHit& hit, double tMin, double tMax) const
{
  bool found = false;
  double best = tMax;
  // Boxes are in box units; cells are tested in world coordinates.
  const Hierarchy::BoxRay boxRay{ Scene_.toBoxUnits(ray.origin), ray.direction, Scene_.boxScale() };
  const FillLaterVector<CellRecord>& records = Cells_->records;
  const std::vector<std::uint32_t>& ids = Cells_->hierarchy.ids();
  Cells_->hierarchy.traverse(boxRay, tMin, best, [&](std::uint32_t first, std::uint32_t count, double& limit) {
    bool nearer = false;
    for (std::uint32_t k = first; k < first + count; ++k)
    {
      CellRecord made;
      double madeCoefficients[kMaxCellNodes];
      if (records.empty())
      {
        Scene_.prepareCell(ids[k], made, madeCoefficients); // beyond the record limit: made as needed
      }
      if (Scene_.intersectCell(records.empty() ? made : records[k], ray, IsoValues_, tMin, limit, hit))
      {
        limit = hit.t;
        nearer = true;
      }
    }
    found = found || nearer;
    return nearer;
  });
  return found;
}

} // namespace tetdsr
