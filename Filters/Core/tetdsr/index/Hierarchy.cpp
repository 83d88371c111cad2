#include "tetdsr/index/Hierarchy.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace tetdsr
{

namespace
{
constexpr int kBins = 16;
constexpr int kMaxSahDepth = 48; // below this, split at the median: depth stays < 48 + log2(n)
// Subtrees below this depth, or smaller than this, are built as one task each.
constexpr int kParallelBuildDepth = 4;
constexpr std::size_t kSerialBuildSize = 4096;
constexpr float kFloatInfinity = std::numeric_limits<float>::infinity();

struct Bounds
{
  float lo[3] = { kFloatInfinity, kFloatInfinity, kFloatInfinity };
  float hi[3] = { -kFloatInfinity, -kFloatInfinity, -kFloatInfinity };
  float centroidLo[3] = { kFloatInfinity, kFloatInfinity, kFloatInfinity };
  float centroidHi[3] = { -kFloatInfinity, -kFloatInfinity, -kFloatInfinity };

  void grow(const BoxItem& item)
  {
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::min(lo[a], item.lo[a]);
      hi[a] = std::max(hi[a], item.hi[a]);
      centroidLo[a] = std::min(centroidLo[a], item.centroid(a));
      centroidHi[a] = std::max(centroidHi[a], item.centroid(a));
    }
  }

  void merge(const Bounds& other)
  {
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::min(lo[a], other.lo[a]);
      hi[a] = std::max(hi[a], other.hi[a]);
      centroidLo[a] = std::min(centroidLo[a], other.centroidLo[a]);
      centroidHi[a] = std::max(centroidHi[a], other.centroidHi[a]);
    }
  }

  /// Half the surface area of the box; 0 when empty.
  double area() const
  {
    if (!(lo[0] <= hi[0]))
    {
      return 0.0;
    }
    const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
  }

  static Bounds of(const std::vector<BoxItem>& items, std::size_t begin, std::size_t end)
  {
    Bounds bounds;
    for (std::size_t i = begin; i < end; ++i)
    {
      bounds.grow(items[i]);
    }
    return bounds;
  }
};
} // namespace

/// The binary tree the build makes first (preorder: an interior node's first child follows it).
struct Hierarchy::Binary
{
  float lo[3];
  float hi[3];
  std::uint32_t firstOrSecondChild; ///< leaf: first item; interior: index of the second child
  std::uint32_t count; ///< leaf: number of items (at most kLeafSize); interior: 0

  double area() const
  {
    const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
  }

  /// Makes the node for items [begin, end), whose bounds are given. Returns false for a leaf,
  /// or true with the items partitioned at `middle` and the two sides' bounds.
  static bool split(std::vector<BoxItem>& items, std::size_t begin, std::size_t end, int depth,
    const Bounds& bounds, Binary& node, std::size_t& middle, Bounds& left, Bounds& right)
  {
    node = Binary{};
    for (int a = 0; a < 3; ++a)
    {
      node.lo[a] = bounds.lo[a];
      node.hi[a] = bounds.hi[a];
    }
    const std::size_t count = end - begin;
    if (count <= static_cast<std::size_t>(kLeafSize))
    {
      node.firstOrSecondChild = static_cast<std::uint32_t>(begin);
      node.count = static_cast<std::uint32_t>(count);
      return false;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
    {
      if (bounds.centroidHi[a] - bounds.centroidLo[a] >
        bounds.centroidHi[axis] - bounds.centroidLo[axis])
      {
        axis = a;
      }
    }
    const float extent = bounds.centroidHi[axis] - bounds.centroidLo[axis];

    // Items whose centroids coincide (extent 0) are split at the median too: leaves never hold
    // more than kLeafSize items, however many copies of a cell the mesh has.
    if (depth < kMaxSahDepth && extent > 0.0f)
    {
      // Binned surface area heuristic over centroids: cost of a split = area * count per side.
      // The bins also collect each side's bounds, so children need no pass of their own.
      Bounds bins[kBins];
      std::size_t binCount[kBins] = {};
      const float scale = kBins / extent;
      const float lo = bounds.centroidLo[axis];
      auto binOf = [&](const BoxItem& item) {
        return std::min(kBins - 1, static_cast<int>((item.centroid(axis) - lo) * scale));
      };
      for (std::size_t i = begin; i < end; ++i)
      {
        const int bin = binOf(items[i]);
        ++binCount[bin];
        bins[bin].grow(items[i]);
      }
      Bounds rightOf[kBins];
      std::size_t rightCount[kBins];
      Bounds accumulated;
      std::size_t accumulatedCount = 0;
      for (int b = kBins - 1; b > 0; --b)
      {
        accumulated.merge(bins[b]);
        accumulatedCount += binCount[b];
        rightOf[b] = accumulated;
        rightCount[b] = accumulatedCount;
      }
      Bounds leftOf;
      std::size_t leftCount = 0;
      double bestCost = std::numeric_limits<double>::infinity();
      int bestBin = -1;
      Bounds bestLeft;
      for (int b = 1; b < kBins; ++b)
      {
        leftOf.merge(bins[b - 1]);
        leftCount += binCount[b - 1];
        if (leftCount == 0 || rightCount[b] == 0)
        {
          continue;
        }
        const double cost = leftOf.area() * leftCount + rightOf[b].area() * rightCount[b];
        if (cost < bestCost)
        {
          bestCost = cost;
          bestBin = b;
          bestLeft = leftOf;
        }
      }
      if (bestBin > 0)
      {
        const auto it = std::partition(items.begin() + begin, items.begin() + end,
          [&](const BoxItem& item) { return binOf(item) < bestBin; });
        middle = static_cast<std::size_t>(it - items.begin());
        if (middle > begin && middle < end)
        {
          left = bestLeft;
          right = rightOf[bestBin];
          return true;
        }
      }
    }
    // Median split (deep trees, or no useful SAH split).
    middle = begin + count / 2;
    std::nth_element(items.begin() + begin, items.begin() + middle, items.begin() + end,
      [axis](const BoxItem& x, const BoxItem& y) { return x.centroid(axis) < y.centroid(axis); });
    left = Bounds::of(items, begin, middle);
    right = Bounds::of(items, middle, end);
    return true;
  }

  static std::uint32_t build(std::vector<BoxItem>& items, std::size_t begin, std::size_t end,
    int depth, const Bounds& bounds, std::vector<Binary>& nodes)
  {
    const auto index = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    Binary node;
    std::size_t middle;
    Bounds left, right;
    if (split(items, begin, end, depth, bounds, node, middle, left, right))
    {
      build(items, begin, middle, depth + 1, left, nodes);
      node.firstOrSecondChild = build(items, middle, end, depth + 1, right, nodes);
    }
    nodes[index] = node;
    return index;
  }
};

void Hierarchy::build(std::vector<BoxItem> items, const ParallelFor& parallelFor)
{
  Nodes_.clear();
  Ids_.clear();
  if (items.empty())
  {
    return;
  }
  const std::vector<Binary> binary = buildBinary(items, parallelFor);
  setRootBox(binary);
  collapse(binary);
  Ids_.resize(items.size());
  for (std::size_t i = 0; i < items.size(); ++i)
  {
    Ids_[i] = items[i].id;
  }
}


std::vector<Hierarchy::Binary> Hierarchy::buildBinary(
  std::vector<BoxItem>& items, const ParallelFor& parallelFor)
{
  // The binary tree: the top levels are split serially; the subtrees below them (disjoint
  // ranges of `items`) are built concurrently, each into its own node list, then laid out in
  // preorder.
  struct TopNode
  {
    Binary node;
    int left = -1;  ///< top-level children, or -1
    int right = -1;
    int task = -1;  ///< >= 0: this node is the subtree built by that task
  };
  struct Task
  {
    std::size_t begin, end;
    int depth;
    Bounds bounds;
  };
  std::vector<TopNode> top;
  std::vector<Task> tasks;
  std::function<int(std::size_t, std::size_t, int, const Bounds&)> splitTop =
    [&](std::size_t begin, std::size_t end, int depth, const Bounds& bounds) {
      const int index = static_cast<int>(top.size());
      top.emplace_back();
      if (depth == kParallelBuildDepth || end - begin <= kSerialBuildSize)
      {
        top[index].task = static_cast<int>(tasks.size());
        tasks.push_back({ begin, end, depth, bounds });
        return index;
      }
      Binary node;
      std::size_t middle;
      Bounds leftBounds, rightBounds;
      const bool interior =
        Binary::split(items, begin, end, depth, bounds, node, middle, leftBounds, rightBounds);
      top[index].node = node;
      if (interior)
      {
        const int left = splitTop(begin, middle, depth + 1, leftBounds);
        const int right = splitTop(middle, end, depth + 1, rightBounds);
        top[index].left = left;
        top[index].right = right;
      }
      return index;
    };
  splitTop(0, items.size(), 0, Bounds::of(items, 0, items.size()));

  std::vector<std::vector<Binary>> subtrees(tasks.size());
  parallelFor(static_cast<NodeId>(tasks.size()), [&](NodeId first, NodeId last) {
    for (NodeId t = first; t < last; ++t)
    {
      const Task& task = tasks[static_cast<std::size_t>(t)];
      Binary::build(items, task.begin, task.end, task.depth, task.bounds,
        subtrees[static_cast<std::size_t>(t)]);
    }
  });

  std::size_t total = top.size();
  for (const auto& subtree : subtrees)
  {
    total += subtree.size();
  }
  std::vector<Binary> binary;
  binary.reserve(total);
  std::function<std::uint32_t(int)> emit = [&](int t) {
    const auto index = static_cast<std::uint32_t>(binary.size());
    if (top[t].task >= 0)
    {
      for (Binary node : subtrees[static_cast<std::size_t>(top[t].task)])
      {
        if (node.count == 0)
        {
          node.firstOrSecondChild += index; // interior: child indices were subtree-relative
        }
        binary.push_back(node);
      }
      std::vector<Binary>().swap(subtrees[static_cast<std::size_t>(top[t].task)]);
      return index;
    }
    binary.push_back(top[t].node);
    if (top[t].left >= 0)
    {
      emit(top[t].left);
      binary[index].firstOrSecondChild = emit(top[t].right);
    }
    return index;
  };
  emit(0);
  return binary;
}

void Hierarchy::setRootBox(const std::vector<Binary>& binary)
{
  for (int a = 0; a < 3; ++a)
  {
    Lo_[a] = binary[0].lo[a];
    Hi_[a] = binary[0].hi[a];
  }
  float magnitude = 0.0f;
  for (int a = 0; a < 3; ++a)
  {
    magnitude = std::max({ magnitude, std::abs(Lo_[a]), std::abs(Hi_[a]), Hi_[a] - Lo_[a] });
  }
  // Float rounding of the re-origined ray and of the slab test errs by a few units of 2^-24 of
  // the coordinates' magnitude over the root box; 2^-16 of it is 256 times that.
  Pad_ = std::ldexp(magnitude, -16);
}

void Hierarchy::collapse(const std::vector<Binary>& binary)
{
  // Collapse into 4-wide nodes: each takes its binary node's children and opens the interior
  // one of largest area until it has four (Wald et al.'s BVH4 collapse).
  Nodes_.reserve(binary.size() / 2 + 1);
  std::function<std::uint32_t(const std::uint32_t*, int)> collapseNode =
    [&](const std::uint32_t* roots, int rootCount) {
      std::uint32_t children[4];
      int size = rootCount;
      std::copy(roots, roots + rootCount, children);
      while (size < 4)
      {
        int open = -1;
        for (int c = 0; c < size; ++c)
        {
          if (binary[children[c]].count == 0 &&
            (open < 0 || binary[children[c]].area() > binary[children[open]].area()))
          {
            open = c;
          }
        }
        if (open < 0)
        {
          break;
        }
        const std::uint32_t opened = children[open];
        children[open] = opened + 1;
        children[size++] = binary[opened].firstOrSecondChild;
      }
      const auto index = static_cast<std::uint32_t>(Nodes_.size());
      Nodes_.emplace_back();
      Node node{};
      node.size = static_cast<std::uint8_t>(size);
      for (int c = 0; c < size; ++c)
      {
        const Binary& child = binary[children[c]];
        for (int a = 0; a < 3; ++a)
        {
          node.lo[a][c] = child.lo[a] - Pad_;
          node.hi[a][c] = child.hi[a] + Pad_;
        }
        node.count[c] = static_cast<std::uint8_t>(child.count);
        node.child[c] = child.count > 0 ? child.firstOrSecondChild : 0;
      }
      for (int c = 0; c < size; ++c)
      {
        if (binary[children[c]].count == 0)
        {
          const std::uint32_t pair[2] = { children[c] + 1,
            binary[children[c]].firstOrSecondChild };
          node.child[c] = collapseNode(pair, 2);
        }
      }
      Nodes_[index] = node;
      return index;
    };
  const std::uint32_t root = 0;
  collapseNode(&root, 1);
}

bool Hierarchy::meetsFrustum(const Frustum& frustum) const
{
  if (Nodes_.empty())
  {
    return false;
  }
  // Per plane, the children's box corners farthest along its normal: a box is outside when even
  // that corner is. The stored boxes are padded, and the pad is added once more for the planes'
  // float rounding (their points lie within the root box's size of it).
  std::uint32_t stack[kStackSize];
  int top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = Nodes_[stack[--top]];
    Int4 inside = Int4{ -1, -1, -1, -1 };
    for (int p = 0; p < 4; ++p)
    {
      Float4 reach = Float4{ 0.0f, 0.0f, 0.0f, 0.0f } + (frustum.d[p] + Pad_);
      for (int a = 0; a < 3; ++a)
      {
        const float n = frustum.n[p][a];
        reach += n * (n > 0.0f ? node.hi[a] : node.lo[a]);
      }
      inside &= reach >= Float4{ 0.0f, 0.0f, 0.0f, 0.0f };
    }
    for (int c = 0; c < node.size; ++c)
    {
      if (!inside[c])
      {
        continue;
      }
      if (node.count[c] != 0)
      {
        return true;
      }
      stack[top++] = node.child[c];
    }
  }
  return false;
}

std::size_t Hierarchy::memoryBytes() const
{
  return Nodes_.capacity() * sizeof(Node) + Ids_.capacity() * sizeof(std::uint32_t);
}

} // namespace tetdsr
