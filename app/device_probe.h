#pragma once
/// \file
/// The device set-up's live test: each hand's device opened on its own, before any session, and
/// read from the UI thread a few dozen times a second, so that the trainee sees each one move —
/// its position against the home position (where the hand starts: sim::home_handle_position,
/// the tool in view, pointing at the task's target), its grip and its buttons. Nothing is sent to a
/// device but zero force. Closed (stop()) before a session opens the same devices.

#include <array>
#include <memory>
#include <string>

#include "core/result.h"
#include "hardware/device_spec.h"
#include "hardware/haptic_device.h"
#include "hardware/simulated_device.h"
#include "hardware/tool_nudge.h"
#include "sim/setup/scene.h"

namespace lap::app {

/// One hand's device as the test screen shows it.
struct ProbeReading {
  bool open = false;
  std::string problem;  ///< why it did not open, or what went wrong since
  hardware::DeviceStatus status = hardware::DeviceStatus::kOk;
  hardware::DeviceSample sample;
  Eigen::Vector3d from_home_m = Eigen::Vector3d::Zero();  ///< sample position - home
};

class DeviceProbe {
 public:
  DeviceProbe() = default;
  ~DeviceProbe() { stop(); }
  DeviceProbe(const DeviceProbe&) = delete;
  DeviceProbe& operator=(const DeviceProbe&) = delete;
  DeviceProbe(DeviceProbe&&) = delete;
  DeviceProbe& operator=(DeviceProbe&&) = delete;

  /// Opens both hands' devices on `scene` (for their home positions). A hand whose device does
  /// not open says why in its reading; the other is opened all the same.
  void start(const sim::Scene& scene, const std::array<hardware::DeviceSpec, 2>& specs);
  /// Zero force, then each device released. Safe to call twice.
  void stop();
  [[nodiscard]] bool running() const { return running_; }

  /// Reads both devices as at `elapsed_s` since start() (scripted and replayed devices play
  /// their inputs in real time from start()).
  [[nodiscard]] std::array<ProbeReading, 2> read(double elapsed_s);
  /// Where each hand starts [m, world].
  [[nodiscard]] const Eigen::Vector3d& home(int side) const {
    return homes_[static_cast<size_t>(side)];
  }
  /// Moves a simulated device's handle (the keyboard, in the test screen), as in a session.
  void nudge(int side, const hardware::ToolNudge& n);
  /// Takes a simulated device back home.
  void go_home(int side);

 private:
  bool running_ = false;
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices_;
  std::array<hardware::SimulatedDevice*, 2> simulated_{};
  std::array<hardware::SimulatedInput, 2> inputs_{};
  std::array<hardware::SimulatedInput, 2> home_inputs_{};
  std::array<Eigen::Vector3d, 2> homes_{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::array<std::string, 2> problems_;
  int64_t last_tick_ = -1;
};

}  // namespace lap::app
