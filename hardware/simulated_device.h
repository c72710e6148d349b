#pragma once
/// \file
/// A device without hardware, so residents can practise with mouse and keyboard: the UI thread
/// sets where the tool should go (set_input), the haptic thread reads it through a triple buffer
/// (wait-free both ways). The sample follows the input, limited to the workspace, and reports
/// the velocity of the last change. Forces are taken and kept for display (there is nothing to
/// push back against the hand).

#include "hardware/haptic_device.h"
#include "hardware/triple_buffer.h"

namespace lap::hardware {

struct SimulatedInput {
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_W = Eigen::Quaterniond::Identity();
  double gripper_angle_rad = 0.0;
  uint32_t buttons = 0;
};

class SimulatedDevice final : public HapticDevice {
 public:
  SimulatedDevice(const SimulatedInput& home, std::string name, const DeviceLimits& limits = {});

  bool start(std::string* error) override;
  void stop() override {}
  DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept override;
  DeviceStatus write(const DeviceCommand& command) noexcept override;
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] std::string_view name() const override { return name_; }
  [[nodiscard]] std::string last_error() const override { return {}; }

  /// UI thread (one writer): where the tool should be now.
  void set_input(const SimulatedInput& input) { input_.publish(input); }
  /// UI thread (one reader): the newest command the haptic loop sent.
  const DeviceCommand& latest_command() { return commands_.latest(); }

 private:
  std::string name_;
  DeviceLimits limits_;
  TripleBuffer<SimulatedInput> input_;
  TripleBuffer<DeviceCommand> commands_;
  DeviceSample last_{};
  bool has_last_ = false;
};

}  // namespace lap::hardware
