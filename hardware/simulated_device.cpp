#include "hardware/simulated_device.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace lap::hardware {

SimulatedDevice::SimulatedDevice(const SimulatedInput& home, std::string name,
                                 const DeviceLimits& limits, const SimulatedHandSpeeds& speeds)
    : InputDevice(std::move(name), limits), input_(home), speeds_(speeds) {}

Status SimulatedDevice::start() {
  has_last_ = false;
  return {};
}

namespace {

// `last` moved towards `target` by at most the hand's speeds over step_s (none when the target
// is not finite: the hand keeps still rather than jump to wherever the next finite input is).
DeviceSample follow(const DeviceSample& last, DeviceSample target, const SimulatedHandSpeeds& v,
                    double step_s) {
  if (!target.position_W.allFinite() || !target.orientation_W.coeffs().allFinite() ||
      !std::isfinite(target.gripper_angle_rad)) {
    DeviceSample held = last;
    held.time_s = target.time_s;
    return held;
  }
  // The same turn on last's side of the quaternion double cover: the coefficients never flip.
  if (last.orientation_W.dot(target.orientation_W) < 0.0) {
    target.orientation_W.coeffs() = -target.orientation_W.coeffs();
  }
  const Eigen::Vector3d d = target.position_W - last.position_W;
  const double reach_m = v.speed_m_per_s * step_s;
  if (d.norm() > reach_m) target.position_W = last.position_W + d * (reach_m / d.norm());
  const double turn = last.orientation_W.angularDistance(target.orientation_W);
  const double reach_rad = v.turn_rad_per_s * step_s;
  if (turn > reach_rad) {
    target.orientation_W =
        last.orientation_W.slerp(reach_rad / turn, target.orientation_W).normalized();
  }
  const double jaws_rad = v.jaws_rad_per_s * step_s;
  target.gripper_angle_rad = std::clamp(target.gripper_angle_rad, last.gripper_angle_rad - jaws_rad,
                                        last.gripper_angle_rad + jaws_rad);
  return target;
}

}  // namespace

DeviceStatus SimulatedDevice::read(int64_t tick, double period_s, DeviceSample* out) noexcept {
  const SimulatedInput& in = input_.latest();
  DeviceSample s;
  s.time_s = static_cast<double>(tick) * period_s;
  s.position_W =
      in.position_W.cwiseMax(limits().workspace_W.min()).cwiseMin(limits().workspace_W.max());
  s.orientation_W = in.orientation_W.normalized();
  s.gripper_angle_rad = in.gripper_angle_rad;
  s.buttons = in.buttons;
  const double dt = has_last_ ? s.time_s - last_.time_s : 0.0;
  if (has_last_) s = follow(last_, s, speeds_, std::max(0.0, dt));
  s.velocity_W = has_last_ && dt > 0.0 ? Eigen::Vector3d((s.position_W - last_.position_W) / dt)
                                       : Eigen::Vector3d::Zero();
  last_ = s;
  has_last_ = true;
  *out = s;
  return DeviceStatus::kOk;
}

}  // namespace lap::hardware
