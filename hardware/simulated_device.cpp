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
  if (has_last_) {
    // Towards the input, at most at the hand's speeds over dt (none when time did not advance).
    const double step = std::max(0.0, dt);
    const Eigen::Vector3d d = s.position_W - last_.position_W;
    const double reach_m = speeds_.speed_m_per_s * step;
    if (d.norm() > reach_m) s.position_W = last_.position_W + d * (reach_m / d.norm());
    const double turn = last_.orientation_W.angularDistance(s.orientation_W);
    const double reach_rad = speeds_.turn_rad_per_s * step;
    if (turn > reach_rad) {
      s.orientation_W = last_.orientation_W.slerp(reach_rad / turn, s.orientation_W).normalized();
    }
    const double jaws_rad = speeds_.jaws_rad_per_s * step;
    s.gripper_angle_rad = std::clamp(s.gripper_angle_rad, last_.gripper_angle_rad - jaws_rad,
                                     last_.gripper_angle_rad + jaws_rad);
  }
  s.velocity_W = has_last_ && dt > 0.0 ? Eigen::Vector3d((s.position_W - last_.position_W) / dt)
                                       : Eigen::Vector3d::Zero();
  last_ = s;
  has_last_ = true;
  *out = s;
  return DeviceStatus::kOk;
}

}  // namespace lap::hardware
