#pragma once
/// \file
/// A device that feeds a recorded session's inputs back in (device_recording.h): the sample
/// for tick k is record k, bit for bit, with the status it had. Past the end it holds the last
/// sample and reports kFinished. Replays must run at the recording's period.

#include "hardware/device_recording.h"
#include "hardware/haptic_device.h"

namespace lap::hardware {

class ReplayDevice final : public HapticDevice {
 public:
  ReplayDevice(DeviceRecording recording, std::string name, const DeviceLimits& limits = {});

  bool start(std::string* error) override;
  void stop() override {}
  DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept override;
  DeviceStatus write(const DeviceCommand& command) noexcept override;
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] std::string_view name() const override { return name_; }
  [[nodiscard]] std::string last_error() const override { return {}; }

  [[nodiscard]] const DeviceRecording& recording() const { return recording_; }

 private:
  DeviceRecording recording_;
  std::string name_;
  DeviceLimits limits_;
};

}  // namespace lap::hardware
