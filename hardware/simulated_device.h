#pragma once
/// \file
/// A device without hardware, so residents can practise with mouse and keyboard: the UI thread
/// sets where the tool should go (set_input), the haptic thread reads it through a triple buffer
/// (wait-free both ways). The sample follows the input as a hand would, at most at the hand's
/// speeds (SimulatedHandSpeeds), limited to the workspace, and reports its velocity. There is
/// nothing to push back against the hand.

#include "hardware/input_device.h"
#include "hardware/triple_buffer.h"

namespace lap::hardware {

struct SimulatedInput {
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_W = Eigen::Quaterniond::Identity();
  double gripper_angle_rad = 0.0;
  uint32_t buttons = 0;
};

/// How fast the simulated hand follows its input: a key press (2 mm, 5 degrees, 0.05 rad of the
/// jaws: hardware/tool_nudge.h) is a motion over a few tens of milliseconds, never a jump in one
/// tick. Estimates, not measured hands, each at or above a held key's pace (the desktop's
/// autorepeat, about 25 presses a second: 50 mm/s, 2.2 rad/s of roll, 1.25 rad/s of the jaws),
/// so that a held key does not run ahead of the hand. Measured on the keyboard's runs
/// (docs/benchmarks.md, "The keyboard's hand"): the keys' 2 mm steps made as jumps, or at twice
/// this speed, whip the catheter's tip through the cystic duct's wall on the stand-in scene (then
/// the default, now scenarios/introductory.yaml); at this speed it goes in.
struct SimulatedHandSpeeds {
  double speed_m_per_s = 0.05;  ///< the handle's speed
  double turn_rad_per_s = 2.5;  ///< the handle's angular speed (a 5 degree roll in 35 ms)
  double jaws_rad_per_s = 1.5;  ///< the jaws' opening and closing rate
};

class SimulatedDevice final : public InputDevice {
 public:
  SimulatedDevice(const SimulatedInput& home, std::string name, const DeviceLimits& limits = {},
                  const SimulatedHandSpeeds& speeds = {});

  Status start() override;
  /// The first read after start() is at the input; each later one moves towards it by at most
  /// the hand's speeds over the time since the previous read.
  DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept override;

  /// UI thread (one writer): where the tool should be now.
  void set_input(const SimulatedInput& input) { input_.publish(input); }
  [[nodiscard]] const SimulatedHandSpeeds& speeds() const { return speeds_; }

 private:
  TripleBuffer<SimulatedInput> input_;
  SimulatedHandSpeeds speeds_;
  DeviceSample last_{};
  bool has_last_ = false;
};

}  // namespace lap::hardware
