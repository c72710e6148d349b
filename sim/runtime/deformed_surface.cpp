#include "sim/runtime/deformed_surface.h"

#include <algorithm>
#include <utility>

namespace lap::sim {

DeformedSurface::DeformedSurface(std::vector<Eigen::Vector3d> rest)
    : rest_(std::move(rest)), positions_(rest_), flags_(rest_.size(), 0) {
  displaced_.reserve(rest_.size());
  changed_.reserve(rest_.size());
}

std::span<const int32_t> DeformedSurface::apply(const SurfaceDeformation& d) noexcept {
  // Every flagged vertex is in changed_ (the displaced ones too): clearing them clears all.
  for (const int32_t v : changed_) flags_[static_cast<size_t>(v)] = 0;
  changed_.clear();
  // Back to rest where the last deformation moved; each listed once.
  for (const int32_t v : displaced_) {
    positions_[static_cast<size_t>(v)] = rest_[static_cast<size_t>(v)];
    flags_[static_cast<size_t>(v)] = 1;
    changed_.push_back(v);
  }
  displaced_.clear();
  const auto n = std::min(static_cast<size_t>(std::max(d.count, 0)),
                          std::min(d.vertex.size(), d.position.size()));
  for (size_t k = 0; k < n; ++k) {
    const int32_t v = d.vertex[k];
    if (v < 0 || static_cast<size_t>(v) >= rest_.size() || !d.position[k].allFinite()) continue;
    uint8_t& f = flags_[static_cast<size_t>(v)];
    if ((f & 2U) != 0) continue;  // listed twice: once is enough (and the lists stay in capacity)
    positions_[static_cast<size_t>(v)] = d.position[k];
    displaced_.push_back(v);
    if ((f & 1U) == 0) changed_.push_back(v);
    f = 3U;
  }
  return changed_;
}

bool DeformedSurface::apply_to(const SurfaceDeformation& d, const Targets& t) noexcept {
  const std::span<const int32_t> changed = apply(d);
  if (changed.empty()) return false;
  t.db->set_positions(positions_, changed, t.scratch);
  if (t.segments != nullptr) t.segments->refit_edge_tree(t.scratch->dirty_faces, t.segment_scratch);
  if (t.shading != nullptr) t.shading->update(*t.db, *t.scratch);
  return true;
}

}  // namespace lap::sim
