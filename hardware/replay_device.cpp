#include "hardware/replay_device.h"

#include <utility>

namespace lap::hardware {

ReplayDevice::ReplayDevice(DeviceRecording recording, std::string name, const DeviceLimits& limits)
    : InputDevice(std::move(name), limits), recording_(std::move(recording)) {}

Status ReplayDevice::start() {
  if (recording_.samples.empty()) {
    return diagnostic(std::string(name()) + ": the recording has no samples");
  }
  return {};
}

DeviceStatus ReplayDevice::read(int64_t tick, double /*period_s*/, DeviceSample* out) noexcept {
  const auto n = static_cast<int64_t>(recording_.samples.size());
  if (tick < 0 || tick >= n) {
    *out = recording_.samples.back().sample;
    out->velocity_W.setZero();
    return DeviceStatus::kFinished;
  }
  const RecordedSample& r = recording_.samples[static_cast<size_t>(tick)];
  *out = r.sample;
  return r.status;
}

}  // namespace lap::hardware
