#pragma once
/// \file
/// What the scripted, replay and simulated devices share: they only give inputs. Commands are
/// taken and render nothing, there is nothing to release, and nothing can fail on its own.

#include <string>
#include <utility>

#include "hardware/haptic_device.h"

namespace lap::hardware {

class InputDevice : public HapticDevice {
 public:
  InputDevice(std::string name, const DeviceLimits& limits)
      : name_(std::move(name)), limits_(limits) {}

  void stop() override {}
  DeviceStatus write(const DeviceCommand& /*command*/) noexcept override {
    return DeviceStatus::kOk;
  }
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] std::string_view name() const override { return name_; }
  [[nodiscard]] std::string last_error() const override { return {}; }

 private:
  std::string name_;
  DeviceLimits limits_;
};

}  // namespace lap::hardware
