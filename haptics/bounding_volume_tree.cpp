#include "haptics/bounding_volume_tree.h"

#include <algorithm>
#include <array>
#include <limits>

namespace lap::haptics {

BoundingVolumeTree::PartialRefit::PartialRefit(const BoundingVolumeTree& tree)
    : count(tree.nodes_.size(), 0),
      marks((tree.nodes_.size() + 63) / 64, 0),
      leaf_bits(marks.size(), 0),
      parent(tree.nodes_.size(), -1) {
  int32_t primitives = 0;
  for (const BvhNode& n : tree.nodes_) primitives += n.count;
  leaf_of.assign(static_cast<size_t>(primitives), -1);
  for (size_t i = 0; i < tree.nodes_.size(); ++i) {
    const BvhNode& n = tree.nodes_[i];
    if (n.count > 0) {
      leaf_bits[i >> 6U] |= uint64_t{1} << (i & 63U);
      for (int32_t k = n.first; k < n.first + n.count; ++k) {
        leaf_of[static_cast<size_t>(k)] = static_cast<int32_t>(i);
      }
    } else {
      parent[i + 1] = static_cast<int32_t>(i);
      parent[static_cast<size_t>(n.first)] = static_cast<int32_t>(i);
    }
  }
}

void BoundingVolumeTree::PartialRefit::clear() {
  std::fill(count.begin(), count.end(), 0);
  std::fill(marks.begin(), marks.end(), uint64_t{0});
}

void BoundingVolumeTree::set_box(BvhNode& node, const Eigen::AlignedBox3d& box) {
  for (int a = 0; a < 3; ++a) {
    node.lo[a] = float_below(box.min()[a]);
    node.hi[a] = float_above(box.max()[a]);
  }
}

namespace {

// Spreads the low 21 bits of x to every third bit.
uint64_t spread_bits(uint64_t x) {
  x &= 0x1fffffULL;
  x = (x | x << 32U) & 0x1f00000000ffffULL;
  x = (x | x << 16U) & 0x1f0000ff0000ffULL;
  x = (x | x << 8U) & 0x100f00f00f00f00fULL;
  x = (x | x << 4U) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2U) & 0x1249249249249249ULL;
  return x;
}

// LSD radix sort of (key, value) pairs by their low 33 bits, 11 bits per pass (the counts stay
// in the first-level cache).
void radix_sort(std::vector<uint64_t>& keys, std::vector<int32_t>& values) {
  constexpr unsigned kBits = 11;
  constexpr size_t kBuckets = size_t{1} << kBits;
  const size_t n = keys.size();
  std::vector<uint64_t> k2(n);
  std::vector<int32_t> v2(n);
  std::array<size_t, kBuckets> count{};
  for (unsigned shift = 0; shift < 33; shift += kBits) {
    count.fill(0);
    for (uint64_t k : keys) ++count[(k >> shift) & (kBuckets - 1)];
    size_t sum = 0;
    for (size_t& c : count) {
      const size_t c0 = c;
      c = sum;
      sum += c0;
    }
    for (size_t i = 0; i < n; ++i) {
      const size_t d = count[(keys[i] >> shift) & (kBuckets - 1)]++;
      k2[d] = keys[i];
      v2[d] = values[i];
    }
    keys.swap(k2);
    values.swap(v2);
  }
}

}  // namespace

uint64_t BoundingVolumeTree::morton_code(const Eigen::Vector3d& p, const Eigen::Vector3d& origin,
                                         const Eigen::Vector3d& scale) {
  uint64_t code = 0;
  for (int a = 0; a < 3; ++a) {
    const double q = std::clamp((p[a] - origin[a]) * scale[a], 0.0, 2097151.0);
    code |= spread_bits(static_cast<uint64_t>(q)) << static_cast<unsigned>(2 - a);
  }
  return code;
}

void BoundingVolumeTree::build_from_codes(std::vector<uint64_t>& codes, int32_t max_leaf_size,
                                          std::vector<int32_t>* order) {
  const auto n = static_cast<int32_t>(codes.size());
  nodes_.clear();
  depth_ = 0;
  order->resize(n);
  for (int32_t i = 0; i < n; ++i) (*order)[i] = i;
  if (n == 0) return;
  // Only the top 33 bits (11 per axis: cells of 1/2048 of the bounds) order the primitives;
  // finer order would not change the tree, whose small ranges are halved anyway.
  for (uint64_t& c : codes) c >>= 30U;
  radix_sort(codes, *order);

  // Top-down over the sorted codes, splitting each range where its highest differing bit
  // changes, allocating nodes in pre-order (left subtree right after its parent).
  struct Task {
    int32_t parent;  // -1 for the root
    bool right;      // this task is its parent's right child
    int32_t begin;
    int32_t end;
    int32_t depth;
  };
  // Leaves average about 3/4 full: reserving for that avoids both regrowth and a shrinking copy.
  nodes_.reserve(
      2 * static_cast<size_t>(n) * 4 / (3 * static_cast<size_t>(std::max(1, max_leaf_size))) + 64);
  std::vector<Task> tasks;
  tasks.push_back({-1, false, 0, n, 0});
  while (!tasks.empty()) {
    const Task t = tasks.back();
    tasks.pop_back();
    const auto index = static_cast<int32_t>(nodes_.size());
    nodes_.push_back({});
    if (t.right) nodes_[t.parent].first = index;
    depth_ = std::max(depth_, t.depth);
    const int32_t count = t.end - t.begin;
    if (count <= max_leaf_size || t.depth >= kMaxDepth - 1) {
      nodes_[index].first = t.begin;
      nodes_[index].count = count;
      continue;
    }
    int32_t mid = t.begin + count / 2;  // equal codes, or a small range: halve it (full leaves)
    const uint64_t a = codes[t.begin];
    const uint64_t b = codes[t.end - 1];
    if (a != b && count > 2 * max_leaf_size) {
      // The first code with the highest differing bit set: b's prefix down to that bit.
      const int bit = 63 - __builtin_clzll(a ^ b);
      const uint64_t prefix = b & ~((uint64_t{1} << static_cast<unsigned>(bit)) - 1U);
      mid = static_cast<int32_t>(
          std::lower_bound(codes.begin() + t.begin, codes.begin() + t.end, prefix) - codes.begin());
    }
    nodes_[index].count = 0;
    tasks.push_back({index, true, mid, t.end, t.depth + 1});
    tasks.push_back({index, false, t.begin, mid, t.depth + 1});  // popped next: index + 1
  }
  if (nodes_.capacity() > nodes_.size() + nodes_.size() / 4) nodes_.shrink_to_fit();
}

}  // namespace lap::haptics
