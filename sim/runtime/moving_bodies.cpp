#include "sim/runtime/moving_bodies.h"

#include <algorithm>

namespace lap::sim {

void MovingBodies::init(std::span<const RigidBodyOfOrgan> bodies, int32_t organ_count) {
  models_.assign(bodies.begin(), bodies.end());
  states_.assign(models_.size(), models::RigidBodyState{});
  body_of_organ_.assign(static_cast<size_t>(std::max(organ_count, 0)), -1);
  for (size_t b = 0; b < models_.size(); ++b) {
    const int32_t o = models_[b].organ;
    if (o >= 0 && o < organ_count) body_of_organ_[static_cast<size_t>(o)] = static_cast<int32_t>(b);
  }
}

void MovingBodies::pose_objects(std::span<haptics::HapticObject> objects) const noexcept {
  for (size_t b = 0; b < models_.size(); ++b) {
    const auto o = static_cast<size_t>(models_[b].organ);
    if (o >= objects.size()) continue;
    objects[o].prev_pose_WO = objects[o].pose_WO;
    objects[o].pose_WO = states_[b].pose_WB;
  }
}

void MovingBodies::push(int32_t organ, const Eigen::Vector3d& force_on_organ_W,
                        const Eigen::Vector3d& p_W) noexcept {
  const int32_t b = body_of(organ);
  if (b < 0) return;
  models::apply_force_at(models_[static_cast<size_t>(b)].model, &states_[static_cast<size_t>(b)],
                         force_on_organ_W, p_W);
}

bool MovingBodies::step(const BodyPushes& held, double dt) noexcept {
  bool ok = true;
  for (size_t b = 0; b < models_.size(); ++b) {
    models::RigidBodyState& s = states_[b];
    s.force_W += held.force_W[b];
    s.torque_W += held.torque_W[b];
    ok = models::step_rigid_body(models_[b].model, &s, dt) && ok;
  }
  return ok;
}

void MovingBodies::write(BodySnapshots* out) const noexcept {
  out->count = static_cast<int32_t>(models_.size());
  for (size_t b = 0; b < models_.size(); ++b) {
    BodySnapshot& s = out->bodies[b];
    s.organ = models_[b].organ;
    s.pose_W = states_[b].pose_WB;
    s.velocity_W = models::linear_velocity_W(models_[b].model, states_[b]);
    s.angular_velocity_W = models::angular_velocity_W(models_[b].model, states_[b]);
  }
}

}  // namespace lap::sim
