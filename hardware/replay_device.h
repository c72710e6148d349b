#pragma once
/// \file
/// A device that feeds a recorded session's inputs back in (device_recording.h): the sample
/// for tick k is record k, bit for bit, with the status it had. Past the end it holds the last
/// sample and reports kFinished. Replays must run at the recording's period.

#include "hardware/device_recording.h"
#include "hardware/input_device.h"

namespace lap::hardware {

class ReplayDevice final : public InputDevice {
 public:
  ReplayDevice(DeviceRecording recording, std::string name, const DeviceLimits& limits = {});

  Status start() override;
  DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept override;
  /// How long the recording lasts [s] (its samples times its period).
  [[nodiscard]] double length_s() const {
    return static_cast<double>(recording_.samples.size()) * recording_.period_s;
  }

 private:
  DeviceRecording recording_;
};

}  // namespace lap::hardware
