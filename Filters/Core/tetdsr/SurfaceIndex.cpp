#include "tetdsr/SurfaceIndex.h"

namespace tetdsr
{

SurfaceIndex::SurfaceIndex(const Scene& scene, const IsoValues& isoValues,
  const ParallelFor& parallelFor, const SurfaceIndex* previous)
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
  if (previous && &previous->Scene_ == &scene && previous->Cells_->selection == selection)
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
  built->records.resize(order.size());
  parallelFor(static_cast<NodeId>(order.size()), [&](NodeId begin, NodeId end) {
    for (NodeId k = begin; k < end; ++k)
    {
      scene.prepareCell(order[static_cast<std::size_t>(k)], built->records[static_cast<std::size_t>(k)]);
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
  Cells_->hierarchy.traverse(boxRay, tMin, best, [&](std::uint32_t first, std::uint32_t count, double& limit) {
    bool nearer = false;
    for (std::uint32_t k = first; k < first + count; ++k)
    {
      if (Scene_.intersectCell(records[k], ray, IsoValues_, tMin, limit, hit))
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
