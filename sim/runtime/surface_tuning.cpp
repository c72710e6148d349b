#include "sim/runtime/surface_tuning.h"

#include <algorithm>
#include <cmath>

namespace lap::sim {

void TunedSurfaces::init(std::span<const haptics::HapticObject> objects) {
  organs_.clear();
  organs_.resize(objects.size());
  for (size_t o = 0; o < objects.size(); ++o) {
    const haptics::HapticObject& object = objects[o];
    Organ& organ = organs_[o];
    organ.now.stiffness_n_per_m = object.law.stiffness_n_per_m;
    organ.now.damping_n_s_per_m = object.law.damping_n_s_per_m;
    organ.base_stiffness_n_per_m = object.law.stiffness_n_per_m;
    if (object.friction != nullptr) {
      organ.base_friction = *object.friction;
      organ.had_friction = object.friction->enabled();
      organ.now.friction_static = object.friction->mu_static;
      organ.now.friction_dynamic = object.friction->mu_dynamic;
    }
    organ.friction = organ.base_friction;
    organ.normals = object.shading;
    organ.now.shading = object.shading != nullptr;
    if (object.texture != nullptr)
      organ.texture = std::make_unique<ScaledHeightField>(object.texture);
  }
}

bool TunedSurfaces::take(SurfaceTuningMailbox* mailbox) noexcept {
  bool any = false;
  mailbox->take([&](int32_t o, const SurfaceParameters& p) { any = set(o, p) || any; });
  return any;
}

bool TunedSurfaces::set(int32_t o, const SurfaceParameters& p) noexcept {
  if (o < 0 || o >= organ_count()) return false;
  const bool valid = std::isfinite(p.stiffness_n_per_m) && p.stiffness_n_per_m >= 0.0 &&
                     std::isfinite(p.damping_n_s_per_m) && p.damping_n_s_per_m >= 0.0 &&
                     std::isfinite(p.friction_static) && p.friction_static >= 0.0 &&
                     std::isfinite(p.friction_dynamic) && p.friction_dynamic >= 0.0 &&
                     std::isfinite(p.texture_scale) && p.texture_scale >= 0.0;
  if (!valid) return false;
  Organ& organ = organs_[static_cast<size_t>(o)];
  organ.now = p;
  organ.now.friction_dynamic = std::min(p.friction_dynamic, p.friction_static);
  organ.now.shading = p.shading && organ.normals != nullptr;
  organ.tuned = true;
  if (!organ.changed) ++changed_count_;
  organ.changed = true;
  // §6.2: the sticking spring as the scenario gave it, or the contact stiffness where it
  // followed it (the loader's default) or the organ had no friction; the sliding spring in
  // proportion, k_d = k_s μd / μs (the loader's default).
  haptics::FrictionModel& f = organ.friction;
  f = organ.base_friction;
  f.mu_static = organ.now.friction_static;
  f.mu_dynamic = organ.now.friction_dynamic;
  const bool follows_k = !organ.had_friction || organ.base_friction.stick_stiffness_n_per_m ==
                                                    organ.base_stiffness_n_per_m;
  if (follows_k) f.stick_stiffness_n_per_m = organ.now.stiffness_n_per_m;
  f.slide_stiffness_n_per_m =
      f.mu_static > 0.0 ? f.stick_stiffness_n_per_m * f.mu_dynamic / f.mu_static : 0.0;
  if (organ.texture) organ.texture->set_scale(organ.now.texture_scale);
  return true;
}

void TunedSurfaces::clear_changed() noexcept {
  if (changed_count_ == 0) return;
  for (Organ& organ : organs_) organ.changed = false;
  changed_count_ = 0;
}

void TunedSurfaces::apply(std::span<haptics::HapticObject> objects) noexcept {
  const size_t n = std::min(objects.size(), organs_.size());
  for (size_t o = 0; o < n; ++o) {
    Organ& organ = organs_[o];
    haptics::HapticObject& object = objects[o];
    // The surfaces' copy just switched points the object at its own normals: remember them.
    if (object.shading != nullptr) organ.normals = object.shading;
    if (!organ.tuned) continue;
    object.law.kind = organ.now.damping_n_s_per_m > 0.0 ? haptics::ForceLaw::Kind::kHookeDamped
                                                        : haptics::ForceLaw::Kind::kHooke;
    object.law.stiffness_n_per_m = organ.now.stiffness_n_per_m;
    object.law.damping_n_s_per_m = organ.now.damping_n_s_per_m;
    object.friction = organ.friction.enabled() ? &organ.friction : nullptr;
    object.shading = organ.now.shading ? organ.normals : nullptr;
    if (organ.texture) object.texture = organ.texture.get();
  }
}

}  // namespace lap::sim
