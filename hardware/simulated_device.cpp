#include "hardware/simulated_device.h"

#include <utility>

namespace lap::hardware {

SimulatedDevice::SimulatedDevice(const SimulatedInput& home, std::string name,
                                 const DeviceLimits& limits)
    : InputDevice(std::move(name), limits), input_(home) {}

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
  const double dt = s.time_s - last_.time_s;
  s.velocity_W = has_last_ && dt > 0.0 ? Eigen::Vector3d((s.position_W - last_.position_W) / dt)
                                       : Eigen::Vector3d::Zero();
  last_ = s;
  has_last_ = true;
  *out = s;
  return DeviceStatus::kOk;
}

}  // namespace lap::hardware
