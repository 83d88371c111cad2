#include "tetdsr/index/SurfaceIndex.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

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
  built->faces.resize(built->records.size());
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
      built->faces[at] = facesOf(scene, built->records[at]);
    }
  });
  built->selection = std::move(selection);
  Cells_ = std::move(built);
}

SurfaceIndex::CellFaces SurfaceIndex::facesOf(const Scene& scene, const CellRecord& record)
{
  CellFaces faces;
  for (int a = 0; a < 3; ++a)
  {
    faces.n[a] = Float4{ 0.0f, 0.0f, 0.0f, 0.0f };
  }
  faces.d = Float4{ 0.0f, 0.0f, 0.0f, 0.0f };
  if (record.kind == CellRecord::Kind::Empty)
  {
    faces.d = Float4{ -1.0f, -1.0f, -1.0f, -1.0f };
    return faces;
  }
  if (record.kind == CellRecord::Kind::Hexahedron ||
    record.kind == CellRecord::Kind::CurvedHexahedron || record.kind == CellRecord::Kind::Wedge)
  {
    // (No four planes bound them: a curved cell, a hexahedron's six faces, a wedge's five.) No
    // culling.
    faces.d = Float4{ 1.0f, 1.0f, 1.0f, 1.0f };
    return faces;
  }
  // L_k = grad L_k . (x - v), v a vertex on face k (vertex 1 for k = 0, vertex 0 for the
  // others); in box units x = origin + x_b / scale, so along the unit normal n = grad L_k /
  // |grad L_k| the signed distance is n . x_b - n . v_b.
  const glm::dvec3 g1 = record.gradient[0], g2 = record.gradient[1], g3 = record.gradient[2];
  const glm::dvec3 gradients[4] = { -(g1 + g2 + g3), g1, g2, g3 };
  CellFaces built = faces;
  for (int k = 0; k < 4; ++k)
  {
    const double length = glm::length(gradients[k]);
    if (!(length > 0.0) || !std::isfinite(length))
    {
      faces.d = Float4{ 1.0f, 1.0f, 1.0f, 1.0f }; // (not for a valid cell) no culling
      return faces;
    }
    const glm::dvec3 n = gradients[k] / length;
    const glm::dvec3 onFace = scene.toBoxUnits(k == 0 ? record.vertex1 : record.vertex0);
    for (int a = 0; a < 3; ++a)
    {
      built.n[a][k] = static_cast<float>(n[a]);
    }
    built.d[k] = static_cast<float>(-glm::dot(n, onFace));
  }
  return built;
}

bool SurfaceIndex::blockMayHit(const Ray corners[4]) const
{
  const Hierarchy& hierarchy = Cells_->hierarchy;
  if (hierarchy.empty())
  {
    return false;
  }
  // In box units, each corner ray's point nearest the root box's centre: the planes through
  // neighbouring corner rays are formed from points of the box's size, whatever the camera's
  // distance. Beyond 2^20 box units from the box (a camera extremely far away, where rounding
  // of these points nears the pad) the block is not culled.
  glm::dvec3 centre;
  for (int a = 0; a < 3; ++a)
  {
    centre[a] = 0.5 * (static_cast<double>(hierarchy.lo()[a]) + hierarchy.hi()[a]);
  }
  glm::dvec3 near[4];
  for (int k = 0; k < 4; ++k)
  {
    const glm::dvec3 origin = Scene_.toBoxUnits(corners[k].origin);
    const double t = glm::dot(centre - origin, corners[k].direction);
    if (!(std::abs(t) < 0x1p20) || !(glm::length(origin - centre) < 0x1p20))
    {
      return true;
    }
    near[k] = origin + t * corners[k].direction;
  }
  glm::dvec3 middle = 0.25 * (near[0] + near[1] + near[2] + near[3]);
  Hierarchy::Frustum frustum;
  for (int k = 0; k < 4; ++k)
  {
    const Ray& a = corners[k];
    const Ray& b = corners[(k + 1) % 4];
    glm::dvec3 n = glm::cross(a.direction, near[(k + 1) % 4] - near[k]);
    const double length = glm::length(n);
    if (!(length > 0.0) || !std::isfinite(length))
    {
      return true; // corners that coincide (a block one pixel wide): not culled
    }
    n /= length;
    double d = -glm::dot(n, near[k]);
    // The plane must hold the second corner ray too (projective rays), and the block's middle
    // must lie inside; else no culling.
    if (!(std::abs(glm::dot(n, b.direction)) < 1e-9))
    {
      return true;
    }
    if (glm::dot(n, middle) + d < 0.0)
    {
      n = -n;
      d = -d;
    }
    if (!(glm::dot(n, middle) + d > 0.0))
    {
      return true;
    }
    for (int c = 0; c < 3; ++c)
    {
      frustum.n[k][c] = static_cast<float>(n[c]);
    }
    frustum.d[k] = static_cast<float>(d);
  }
  return hierarchy.meetsFrustum(frustum);
}

// Flattened: the traversal, its leaf function and the cell test compiled as one (measured 18%
// faster per ray than with the compiler's own inlining choices).
__attribute__((flatten)) bool SurfaceIndex::firstHit(
  const Ray& ray, SurfaceHit& hit, double tMin, double tMax, std::uint32_t hint) const
{
  bool found = false;
  double best = tMax;
  // Boxes are in box units; cells are tested in world coordinates.
  const Hierarchy::BoxRay boxRay{ Scene_.toBoxUnits(ray.origin), ray.direction, Scene_.boxScale() };
  const FillLaterVector<CellRecord>& records = Cells_->records;
  const FillLaterVector<CellFaces>& faces = Cells_->faces;
  const std::vector<std::uint32_t>& ids = Cells_->hierarchy.ids();
  // The faces' test in float, on the ray re-origined at its point nearest the root box's centre
  // (so its coordinates are of the box's size) with parameter u = t * scale - uBase. The pad (far
  // above the rounding of the planes, of this origin and of the products, all within the root
  // box) widens each face outward, so every cell the exact ray meets passes, as for the boxes.
  const Hierarchy& hierarchy = Cells_->hierarchy;
  Float4 origin[3], direction[3];
  double uBase = 0.0;
  {
    glm::dvec3 centre;
    for (int a = 0; a < 3; ++a)
    {
      centre[a] = 0.5 * (static_cast<double>(hierarchy.lo()[a]) + hierarchy.hi()[a]);
    }
    uBase = glm::dot(centre - boxRay.origin, ray.direction);
    const glm::dvec3 local = boxRay.origin + uBase * ray.direction;
    for (int a = 0; a < 3; ++a)
    {
      const float o = static_cast<float>(local[a]), v = static_cast<float>(ray.direction[a]);
      origin[a] = Float4{ o, o, o, o };
      direction[a] = Float4{ v, v, v, v };
    }
  }
  const float pad = hierarchy.pad();
  const Float4 pad4 = Float4{ pad, pad, pad, pad };
  auto meetsFaces = [&](const CellFaces& cell, double limit) {
    const Float4 distance = cell.n[0] * origin[0] + cell.n[1] * origin[1] + cell.n[2] * origin[2] + cell.d + pad4;
    const Float4 slope = cell.n[0] * direction[0] + cell.n[1] * direction[1] + cell.n[2] * direction[2];
    const Float4 zero = Float4{ 0.0f, 0.0f, 0.0f, 0.0f };
    const Float4 one = Float4{ 1.0f, 1.0f, 1.0f, 1.0f };
    // distance + u slope >= 0: u >= -distance / slope where slope > 0, <= where it is < 0.
    const Float4 at = -distance / (slope != zero ? slope : one);
    const Int4 parallelOutside = (slope == zero) & (distance < zero);
    float lo = static_cast<float>(tMin * boxRay.scale - uBase) - pad;
    float hi = static_cast<float>(limit * boxRay.scale - uBase) + pad;
    for (int k = 0; k < 4; ++k)
    {
      if (parallelOutside[k])
      {
        return false;
      }
      if (slope[k] > 0.0f)
      {
        lo = std::max(lo, at[k]);
      }
      else if (slope[k] < 0.0f)
      {
        hi = std::min(hi, at[k]);
      }
    }
    return lo <= hi;
  };
  if (hint < records.size() && meetsFaces(faces[hint], best) &&
    Scene_.intersectCell(records[hint], ray, IsoValues_, tMin, best, hit))
  {
    hit.entry = hint;
    best = hit.t;
    found = true;
  }
  hierarchy.traverse(boxRay, tMin, best, [&](std::uint32_t first, std::uint32_t count, double& limit) {
    bool nearer = false;
    for (std::uint32_t k = first; k < first + count; ++k)
    {
      if (!faces.empty() && !meetsFaces(faces[k], limit))
      {
        continue;
      }
      CellRecord made;
      double madeCoefficients[kMaxRecordCoefficients];
      if (records.empty())
      {
        Scene_.prepareCell(ids[k], made, madeCoefficients); // beyond the record limit: made as needed
      }
      if (Scene_.intersectCell(records.empty() ? made : records[k], ray, IsoValues_, tMin, limit, hit))
      {
        hit.entry = records.empty() ? kNoEntry : k;
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
