#pragma once
/// \file
/// A device without hardware, so residents can practise with mouse and keyboard: the UI thread
/// sets where the tool should go (set_input), the haptic thread reads it through a triple buffer
/// (wait-free both ways). The sample follows the input, limited to the workspace, and reports
/// the velocity of the last change. There is nothing to push back against the hand.

#include "hardware/input_device.h"
#include "hardware/triple_buffer.h"

namespace lap::hardware {

struct SimulatedInput {
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_W = Eigen::Quaterniond::Identity();
  double gripper_angle_rad = 0.0;
  uint32_t buttons = 0;
};

class SimulatedDevice final : public InputDevice {
 public:
  SimulatedDevice(const SimulatedInput& home, std::string name, const DeviceLimits& limits = {});

  Status start() override;
  DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept override;

  /// UI thread (one writer): where the tool should be now.
  void set_input(const SimulatedInput& input) { input_.publish(input); }

 private:
  TripleBuffer<SimulatedInput> input_;
  DeviceSample last_{};
  bool has_last_ = false;
};

}  // namespace lap::hardware
