#include "sim/runtime/deformed_surface.h"

#include <algorithm>
#include <utility>

namespace lap::sim {

DeformedSurface::DeformedSurface(std::vector<Eigen::Vector3d> rest)
    : rest_(std::move(rest)), positions_(rest_), flags_(rest_.size(), 0) {
  displaced_.reserve(rest_.size());
  displacing_.reserve(rest_.size());
  changed_.reserve(rest_.size());
}

std::span<const int32_t> DeformedSurface::apply(const SurfaceDeformation& d) noexcept {
  // Every flagged vertex is in changed_ (the displaced ones too): clearing them clears all.
  for (const int32_t v : changed_) flags_[static_cast<size_t>(v)] = 0;
  changed_.clear();
  // The new deformation first, each listed vertex once (bit 1): a vertex displaced before and
  // now is not put back to rest in between.
  displacing_.clear();
  const auto n = std::min(static_cast<size_t>(std::max(d.count, 0)),
                          std::min(d.vertex.size(), d.position.size()));
  for (size_t k = 0; k < n; ++k) {
    const int32_t v = d.vertex[k];
    if (v < 0 || static_cast<size_t>(v) >= rest_.size() || !d.position[k].allFinite()) continue;
    uint8_t& f = flags_[static_cast<size_t>(v)];
    if ((f & 2U) != 0) continue;  // listed twice: once is enough (and the lists stay in capacity)
    f = 2U;
    positions_[static_cast<size_t>(v)] = d.position[k];
    displacing_.push_back(v);
  }
  // Changed: what the last deformation displaced (back to rest unless displaced again), then
  // what this one displaces and the last did not (bit 0: listed in changed_). The same
  // deformation again gives the same list in the same order (the database's region is reused).
  for (const int32_t v : displaced_) {
    uint8_t& f = flags_[static_cast<size_t>(v)];
    if ((f & 2U) == 0) positions_[static_cast<size_t>(v)] = rest_[static_cast<size_t>(v)];
    f |= 1U;
    changed_.push_back(v);
  }
  for (const int32_t v : displacing_) {
    if ((flags_[static_cast<size_t>(v)] & 1U) != 0) continue;
    flags_[static_cast<size_t>(v)] |= 1U;
    changed_.push_back(v);
  }
  displaced_.swap(displacing_);  // both keep their reserved capacity
  return changed_;
}

bool DeformedSurface::apply_to(const SurfaceDeformation& d, const Targets& t) noexcept {
  const std::span<const int32_t> changed = apply(d);
  if (changed.empty()) return false;
  t.db->set_positions(positions_, changed, t.scratch);
  if (t.segments != nullptr) t.segments->refit_moved_edges(t.scratch->moved, t.segment_scratch);
  if (t.shading != nullptr) t.shading->update(*t.db, *t.scratch);
  return true;
}

}  // namespace lap::sim
