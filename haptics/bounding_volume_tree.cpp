#include "haptics/bounding_volume_tree.h"

#include <algorithm>
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

void BoundingVolumeTree::build(const std::vector<Eigen::AlignedBox3d>& boxes,
                               int32_t max_leaf_size, std::vector<int32_t>* order) {
  const auto n = static_cast<int32_t>(boxes.size());
  order->resize(n);
  for (int32_t i = 0; i < n; ++i) (*order)[i] = i;
  nodes_.clear();
  depth_ = 0;
  if (n == 0) return;
  nodes_.reserve(static_cast<size_t>(2 * (n / std::max(1, max_leaf_size / 2) + 1)));
  std::vector<Eigen::Vector3d> centroid(n);
  for (int32_t i = 0; i < n; ++i) centroid[i] = boxes[i].center();

  struct Task {
    int32_t node;
    int32_t begin;
    int32_t end;
    int32_t depth;
  };
  std::vector<Task> tasks;
  nodes_.push_back({});
  tasks.push_back({0, 0, n, 0});
  constexpr int kBins = 16;
  std::vector<int32_t>& idx = *order;

  while (!tasks.empty()) {
    const Task task = tasks.back();
    tasks.pop_back();
    Eigen::AlignedBox3d box;
    Eigen::AlignedBox3d cbox;
    for (int32_t k = task.begin; k < task.end; ++k) {
      box.extend(boxes[idx[k]]);
      cbox.extend(centroid[idx[k]]);
    }
    set_box(nodes_[task.node], box);
    depth_ = std::max(depth_, task.depth);
    const int32_t count = task.end - task.begin;
    int axis = 0;
    cbox.sizes().maxCoeff(&axis);
    const double extent = cbox.sizes()[axis];
    auto make_leaf = [&] {
      nodes_[task.node].first = task.begin;
      nodes_[task.node].count = count;
    };
    if (count <= max_leaf_size || task.depth >= kMaxDepth - 1 || !(extent > 0.0)) {
      if (count <= max_leaf_size || task.depth >= kMaxDepth - 1) {
        make_leaf();
        continue;
      }
    }
    int32_t mid = task.begin + count / 2;
    if (extent > 0.0) {
      // Binned surface-area heuristic along the widest centroid axis.
      std::array<Eigen::AlignedBox3d, kBins> bin_box;
      std::array<int32_t, kBins> bin_count{};
      const double lo = cbox.min()[axis];
      const double scale = kBins / extent;
      auto bin_of = [&](int32_t prim) {
        const int b = static_cast<int>((centroid[prim][axis] - lo) * scale);
        return std::clamp(b, 0, kBins - 1);
      };
      for (int32_t k = task.begin; k < task.end; ++k) {
        const int b = bin_of(idx[k]);
        bin_box[b].extend(boxes[idx[k]]);
        ++bin_count[b];
      }
      auto area = [](const Eigen::AlignedBox3d& b) {
        if (b.isEmpty()) return 0.0;
        const Eigen::Vector3d s = b.sizes();
        return s.x() * s.y() + s.y() * s.z() + s.z() * s.x();
      };
      std::array<double, kBins> left_cost{};
      Eigen::AlignedBox3d acc;
      int32_t acc_n = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        acc.extend(bin_box[b]);
        acc_n += bin_count[b];
        left_cost[b] = area(acc) * acc_n;
      }
      acc.setEmpty();
      acc_n = 0;
      double best = std::numeric_limits<double>::infinity();
      int best_split = -1;
      for (int b = kBins - 1; b > 0; --b) {
        acc.extend(bin_box[b]);
        acc_n += bin_count[b];
        const double cost = left_cost[b - 1] + area(acc) * acc_n;
        if (cost < best && acc_n > 0 && acc_n < count) {
          best = cost;
          best_split = b;
        }
      }
      if (best_split > 0) {
        const auto it = std::partition(idx.begin() + task.begin, idx.begin() + task.end,
                                       [&](int32_t prim) { return bin_of(prim) < best_split; });
        mid = static_cast<int32_t>(it - idx.begin());
      }
    }
    if (mid <= task.begin || mid >= task.end) {
      // All centroids coincide (or no useful split): split the range in half.
      mid = task.begin + count / 2;
      std::nth_element(idx.begin() + task.begin, idx.begin() + mid, idx.begin() + task.end,
                       [&](int32_t a, int32_t b) { return centroid[a][axis] < centroid[b][axis]; });
    }
    const auto left = static_cast<int32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    nodes_[task.node].first = left;
    nodes_[task.node].count = 0;
    tasks.push_back({left + 1, mid, task.end, task.depth + 1});
    tasks.push_back({left, task.begin, mid, task.depth + 1});
  }
  nodes_.shrink_to_fit();
}

}  // namespace lap::haptics
