// A 4-wide bounding volume hierarchy over boxes, for rays (nearest first, stopping at the first
// hit) and for points. Boxes are floats in "box units" (a scene's coordinates relative to an
// origin, times a power of two that brings its extent near 1), rounded outward by the caller;
// each node tests its four children's boxes at once in 4-lane vectors.
#pragma once

#include "tetdsr/index/Scene.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace tetdsr
{

/// A box and what it bounds (an index the caller chooses).
struct BoxItem
{
  float lo[3];
  float hi[3];
  std::uint32_t id;

  float centroid(int axis) const { return 0.5f * (lo[axis] + hi[axis]); }
};

/// Four floats in one vector register (GCC / Clang vector extension: SSE on x86-64, NEON on
/// ARM); lane-wise arithmetic, comparisons and selects.
typedef float Float4 __attribute__((vector_size(16)));
typedef int Int4 __attribute__((vector_size(16)));

class Hierarchy
{
public:
  /// Items per leaf at most.
  static constexpr int kLeafSize = 4;

  /// Builds over `items` (reordered: afterwards a leaf holds consecutive items, and ids() lists
  /// them in that order), concurrently through `parallelFor`. The result does not depend on how
  /// parallelFor partitions the work.
  void build(std::vector<BoxItem> items, const ParallelFor& parallelFor);

  bool empty() const { return Nodes_.empty(); }
  /// The items' ids in leaf order.
  const std::vector<std::uint32_t>& ids() const { return Ids_; }
  /// The box around all items (box units).
  const float* lo() const { return Lo_; }
  const float* hi() const { return Hi_; }
  /// How much the stored boxes are padded (box units): far above the float rounding of a point
  /// or plane within the root box (see setRootBox).
  float pad() const { return Pad_; }
  std::size_t memoryBytes() const;

  /// A ray in box units: origin, unit direction, and the box units per unit of the caller's
  /// ray parameter t (so the traversal's parameters, t * scale, stay of the boxes' size, in
  /// float range, whatever the scene's scale).
  struct BoxRay
  {
    glm::dvec3 origin;
    glm::dvec3 direction;
    double scale;
  };

  /// Visits the leaves whose boxes the ray meets within [tMin, tMax], nearest box first, and
  /// stops visiting boxes entered beyond tMax, which `leaf(first, count, tMax)` lowers when it
  /// finds a hit in items [first, first + count) of ids(). Conservative: every box that the
  /// exact ray meets within [tMin, tMax] is visited.
  template <typename Leaf>
  void traverse(const BoxRay& ray, double tMin, double& tMax, Leaf&& leaf) const;

  /// A convex region of space bounded by four planes in box units, n . x + d >= 0 inside (n
  /// unit): the rays of a block of pixels (Renderer).
  struct Frustum
  {
    float n[4][3];
    float d[4];
  };
  /// Whether any leaf's box may meet the frustum: false only if every leaf box lies wholly
  /// outside one of its planes (by more than the pad); a box test, so conservative.
  bool meetsFrustum(const Frustum& frustum) const;

  /// Visits the leaves whose boxes contain `point` (box units) until `leaf(first, count)`
  /// returns true; returns whether one did.
  template <typename Leaf>
  bool containing(const glm::dvec3& point, Leaf&& leaf) const;

private:
  /// Up to four children (the first `size` lanes): an interior node (count 0: `child` is its
  /// index) or a leaf (items [child, child + count)).
  struct alignas(64) Node
  {
    Float4 lo[3];
    Float4 hi[3];
    std::uint32_t child[4];
    std::uint8_t count[4];
    std::uint8_t size;
  };
  struct Binary;
  // The build's steps.
  /// The binary SAH tree over `items` (reordered into its leaves), in preorder: the top levels
  /// split serially, the subtrees below them built concurrently.
  static std::vector<Binary> buildBinary(std::vector<BoxItem>& items, const ParallelFor& parallelFor);
  /// The root box and the padding of the float slab test, from the binary tree's root.
  void setRootBox(const std::vector<Binary>& binary);
  /// The binary tree collapsed into 4-wide nodes.
  void collapse(const std::vector<Binary>& binary);
  /// The binary tree the build makes is under 48 + 32 levels deep (SAH splits to depth 48, then
  /// median splits of at most 2^32 items), and the 4-wide tree no deeper; traversal keeps at
  /// most three pending siblings per level (four at the last).
  static constexpr int kStackSize = 3 * 128;

  std::vector<Node> Nodes_;
  std::vector<std::uint32_t> Ids_;
  float Lo_[3] = { 0.0f, 0.0f, 0.0f };
  float Hi_[3] = { 0.0f, 0.0f, 0.0f };
  /// Nodes store their children's boxes padded by this much (box units): the float slab test of
  /// a ray re-origined near the root box then errs by far less, so it never drops a box the
  /// exact ray meets.
  float Pad_ = 0.0f;
};

template <typename Leaf>
void Hierarchy::traverse(const BoxRay& ray, double tMin, double& tMax, Leaf&& leaf) const
{
  if (Nodes_.empty())
  {
    return;
  }
  // Clip the ray to the root box in double (the root box padded twice over) and re-origin it
  // there: the float tests below then work with coordinates and parameters of the box's own
  // size, whatever the camera's distance.
  double tEnter = tMin * ray.scale, tExit = tMax * ray.scale;
  glm::dvec3 inverse;
  for (int a = 0; a < 3; ++a)
  {
    inverse[a] = ray.direction[a] != 0.0 ? 1.0 / ray.direction[a]
                                         : std::copysign(1e300, ray.direction[a]);
    const double t0 = (Lo_[a] - 2.0 * Pad_ - ray.origin[a]) * inverse[a];
    const double t1 = (Hi_[a] + 2.0 * Pad_ - ray.origin[a]) * inverse[a];
    tEnter = std::max(tEnter, std::min(t0, t1));
    tExit = std::min(tExit, std::max(t0, t1));
  }
  if (!(tEnter <= tExit))
  {
    return;
  }
  const double tBase = tEnter;
  Float4 origin[3], inverse4[3];
  for (int a = 0; a < 3; ++a)
  {
    const float o = static_cast<float>(ray.origin[a] + tBase * ray.direction[a]);
    // 1/direction in float; a zero or tiny component becomes a huge finite factor, so a ray
    // parallel to a slab gets +-huge (or 0 at its very boundary), never 0 * inf = NaN.
    const double inv = std::clamp(inverse[a], -1e30, 1e30);
    origin[a] = Float4{ o, o, o, o };
    const float f = static_cast<float>(inv);
    inverse4[a] = Float4{ f, f, f, f };
  }
  // Pending children: an interior node (count 0) or a leaf, with where the ray enters its box.
  struct Entry
  {
    std::uint32_t child;
    std::uint32_t count;
    float tEnter;
  } stack[kStackSize];
  int top = 0;
  float farLimit = static_cast<float>(tExit - tBase);
  const float nearLimit = static_cast<float>(tMin * ray.scale - tBase);
  // The nearest child met goes on at once; the others wait on the stack.
  Entry current{ 0, 0, 0.0f };
  for (;;)
  {
    if (current.count != 0)
    {
      if (leaf(current.child, current.count, tMax))
      {
        farLimit = static_cast<float>(tMax * ray.scale - tBase);
      }
      // Next: the nearest pending box not beyond a hit found meanwhile.
      while (top > 0 && stack[top - 1].tEnter > farLimit)
      {
        --top;
      }
      if (top == 0)
      {
        return;
      }
      current = stack[--top];
      continue;
    }
    const Node& node = Nodes_[current.child];
    Float4 lower = Float4{ nearLimit, nearLimit, nearLimit, nearLimit };
    Float4 upper = Float4{ farLimit, farLimit, farLimit, farLimit };
    for (int a = 0; a < 3; ++a)
    {
      // (boxes are stored padded)
      const Float4 t0 = (node.lo[a] - origin[a]) * inverse4[a];
      const Float4 t1 = (node.hi[a] - origin[a]) * inverse4[a];
      const Float4 tNear = t0 < t1 ? t0 : t1;
      const Float4 tFar = t0 < t1 ? t1 : t0;
      lower = lower > tNear ? lower : tNear;
      upper = upper < tFar ? upper : tFar;
    }
    const Int4 hit = lower <= upper;
    // The children met, farthest first, pushed in that order: the nearest is visited next.
    int order[4], hits = 0;
    for (int c = 0; c < node.size; ++c)
    {
      if (hit[c])
      {
        int k = hits++;
        for (; k > 0 && lower[order[k - 1]] < lower[c]; --k)
        {
          order[k] = order[k - 1];
        }
        order[k] = c;
      }
    }
    for (int k = 0; k + 1 < hits; ++k)
    {
      const int c = order[k];
      stack[top++] = { node.child[c], node.count[c], lower[c] };
    }
    if (hits > 0)
    {
      const int c = order[hits - 1];
      current = { node.child[c], node.count[c], lower[c] };
      continue;
    }
    while (top > 0 && stack[top - 1].tEnter > farLimit)
    {
      --top;
    }
    if (top == 0)
    {
      return;
    }
    current = stack[--top];
  }
}

template <typename Leaf>
bool Hierarchy::containing(const glm::dvec3& point, Leaf&& leaf) const
{
  if (Nodes_.empty())
  {
    return false;
  }
  Float4 p[3];
  for (int a = 0; a < 3; ++a)
  {
    // The point rounded to float errs by at most half a float step of its coordinate; the pad
    // (far above that within the root box) covers it. Outside the root box: in no leaf.
    if (!(point[a] >= Lo_[a] - Pad_ && point[a] <= Hi_[a] + Pad_))
    {
      return false;
    }
    const float f = static_cast<float>(point[a]);
    p[a] = Float4{ f, f, f, f };
  }
  std::uint32_t stack[kStackSize];
  int top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = Nodes_[stack[--top]];
    Int4 inside = Int4{ -1, -1, -1, -1 };
    for (int a = 0; a < 3; ++a)
    {
      inside &= (node.lo[a] <= p[a]) & (p[a] <= node.hi[a]); // (boxes are stored padded)
    }
    for (int c = 0; c < node.size; ++c)
    {
      if (!inside[c])
      {
        continue;
      }
      if (node.count[c] == 0)
      {
        stack[top++] = node.child[c];
      }
      else if (leaf(node.child[c], node.count[c]))
      {
        return true;
      }
    }
  }
  return false;
}

} // namespace tetdsr
