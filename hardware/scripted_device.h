#pragma once
/// \file
/// A device that plays a keyframed trajectory (scripted_trajectory.h) in session time: the
/// sample for tick k is the trajectory at k * period. Commands are taken and ignored (kept as
/// the last command for tests). After the last keyframe it holds still and reports kFinished.

#include "hardware/haptic_device.h"
#include "hardware/scripted_trajectory.h"

namespace lap::hardware {

class ScriptedDevice final : public HapticDevice {
 public:
  ScriptedDevice(ScriptedTrajectory trajectory, std::string name, const DeviceLimits& limits = {});

  bool start(std::string* error) override;
  void stop() override {}
  DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept override;
  DeviceStatus write(const DeviceCommand& command) noexcept override;
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] std::string_view name() const override { return name_; }
  [[nodiscard]] std::string last_error() const override { return {}; }

  [[nodiscard]] const ScriptedTrajectory& trajectory() const { return trajectory_; }
  [[nodiscard]] const DeviceCommand& last_command() const { return last_command_; }

 private:
  ScriptedTrajectory trajectory_;
  std::string name_;
  DeviceLimits limits_;
  size_t cursor_ = 0;
  DeviceCommand last_command_;
};

}  // namespace lap::hardware
