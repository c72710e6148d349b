#pragma once
/// \file
/// A device that plays a keyframed trajectory (scripted_trajectory.h) in session time: the
/// sample for tick k is the trajectory at k * period. After the last keyframe it holds still and
/// reports kFinished.

#include "hardware/input_device.h"
#include "hardware/scripted_trajectory.h"

namespace lap::hardware {

class ScriptedDevice final : public InputDevice {
 public:
  ScriptedDevice(ScriptedTrajectory trajectory, std::string name, const DeviceLimits& limits = {});

  Status start() override;
  DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept override;

  [[nodiscard]] const ScriptedTrajectory& trajectory() const { return trajectory_; }

 private:
  ScriptedTrajectory trajectory_;
  size_t cursor_ = 0;
};

}  // namespace lap::hardware
