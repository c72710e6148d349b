#include "hardware/scripted_device.h"

#include <utility>

namespace lap::hardware {

ScriptedDevice::ScriptedDevice(ScriptedTrajectory trajectory, std::string name,
                               const DeviceLimits& limits)
    : InputDevice(std::move(name), limits), trajectory_(std::move(trajectory)) {}

Status ScriptedDevice::start() {
  if (trajectory_.keyframes.empty()) {
    return diagnostic(std::string(name()) + ": the trajectory has no keyframes");
  }
  cursor_ = 0;
  return {};
}

DeviceStatus ScriptedDevice::read(int64_t tick, double period_s, DeviceSample* out) noexcept {
  const double t = static_cast<double>(tick) * period_s;
  trajectory_.sample(t, &cursor_, out);
  return t > trajectory_.duration_s() ? DeviceStatus::kFinished : DeviceStatus::kOk;
}

}  // namespace lap::hardware
