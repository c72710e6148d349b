#include "haptics/bounding_volume_tree.h"

#include <algorithm>
#include <array>
#include <limits>

namespace lap::haptics {

void BoundingVolumeTree::set_box(BvhNode& node, const Eigen::AlignedBox3d& box) {
  for (int a = 0; a < 3; ++a) {
    // Round outward: the float box must contain the double box.
    float lo = static_cast<float>(box.min()[a]);
    float hi = static_cast<float>(box.max()[a]);
    if (static_cast<double>(lo) > box.min()[a]) lo = std::nextafter(lo, -std::numeric_limits<float>::infinity());
    if (static_cast<double>(hi) < box.max()[a]) hi = std::nextafter(hi, std::numeric_limits<float>::infinity());
    node.lo[a] = lo;
    node.hi[a] = hi;
  }
}

Eigen::AlignedBox3d BoundingVolumeTree::to_box(const BvhNode& node) {
  return {Eigen::Vector3d(node.lo[0], node.lo[1], node.lo[2]),
          Eigen::Vector3d(node.hi[0], node.hi[1], node.hi[2])};
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

// LSD radix sort of (key, value) pairs by their 63-bit keys, 11 bits per pass (the counts stay
// in the first-level cache).
void radix_sort(std::vector<uint64_t>& keys, std::vector<int32_t>& values) {
  constexpr unsigned kBits = 11;
  constexpr size_t kBuckets = size_t{1} << kBits;
  const size_t n = keys.size();
  std::vector<uint64_t> k2(n);
  std::vector<int32_t> v2(n);
  std::array<size_t, kBuckets> count{};
  for (unsigned shift = 0; shift < 63; shift += kBits) {
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

void BoundingVolumeTree::build(const std::vector<Eigen::Vector3d>& centres, int32_t max_leaf_size,
                               std::vector<int32_t>* order) {
  const auto n = static_cast<int32_t>(centres.size());
  nodes_.clear();
  depth_ = 0;
  order->resize(n);
  for (int32_t i = 0; i < n; ++i) (*order)[i] = i;
  if (n == 0) return;

  // Morton codes of the centres, 21 bits per axis over their bounds.
  Eigen::AlignedBox3d cbox;
  for (const auto& c : centres) cbox.extend(c);
  const Eigen::Vector3d lo = cbox.min();
  Eigen::Vector3d scale;
  for (int a = 0; a < 3; ++a) scale[a] = cbox.sizes()[a] > 0.0 ? 2097151.0 / cbox.sizes()[a] : 0.0;
  std::vector<uint64_t> codes(n);
  for (int32_t i = 0; i < n; ++i) {
    uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double q = std::clamp((centres[i][a] - lo[a]) * scale[a], 0.0, 2097151.0);
      code |= spread_bits(static_cast<uint64_t>(q)) << static_cast<unsigned>(2 - a);
    }
    codes[i] = code;
  }
  radix_sort(codes, *order);

  // Top-down over the sorted codes, splitting each range where its highest differing bit
  // changes. Children are allocated after their parent, so a reverse sweep over the nodes
  // visits children first (refit relies on it).
  struct Task {
    int32_t node;
    int32_t begin;
    int32_t end;
    int32_t depth;
  };
  nodes_.reserve(static_cast<size_t>(2 * (n / std::max(1, max_leaf_size / 2)) + 2));
  std::vector<Task> tasks;
  nodes_.push_back({});
  tasks.push_back({0, 0, n, 0});
  while (!tasks.empty()) {
    const Task t = tasks.back();
    tasks.pop_back();
    depth_ = std::max(depth_, t.depth);
    const int32_t count = t.end - t.begin;
    if (count <= max_leaf_size || t.depth >= kMaxDepth - 1) {
      nodes_[t.node].first = t.begin;
      nodes_[t.node].count = count;
      continue;
    }
    int32_t mid = t.begin + count / 2;  // equal codes: halve the range
    const uint64_t a = codes[t.begin];
    const uint64_t b = codes[t.end - 1];
    if (a != b) {
      // The first code with the highest differing bit set: b's prefix down to that bit.
      const int bit = 63 - __builtin_clzll(a ^ b);
      const uint64_t prefix = b & ~((uint64_t{1} << static_cast<unsigned>(bit)) - 1U);
      mid = static_cast<int32_t>(
          std::lower_bound(codes.begin() + t.begin, codes.begin() + t.end, prefix) - codes.begin());
    }
    const auto left = static_cast<int32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    nodes_[t.node].first = left;
    nodes_[t.node].count = 0;
    tasks.push_back({left + 1, mid, t.end, t.depth + 1});
    tasks.push_back({left, t.begin, mid, t.depth + 1});
  }
  nodes_.shrink_to_fit();
}

}  // namespace lap::haptics
