#pragma once
/// \file
/// The last step before a command reaches a device: whatever the rendering produced, what is
/// sent is finite, within the device's limits (force, torque, squeeze magnitudes), scaled by a
/// gain the runtime ramps from 0 to 1 when a paused session resumes, and changes no faster than
/// the device's force-rate limit. A zero command (the watchdog's) bypasses the rate limit: forces
/// drop to zero within the tick.
///
/// Real time: no allocation, no lock, no exception.

#include "hardware/haptic_device.h"

namespace lap::hardware {

struct LimitedCommand {
  DeviceCommand command;
  bool non_finite = false;  ///< the input had a NaN or an infinity (the command is zero)
  bool clamped = false;     ///< a magnitude limit cut it
  bool rate_limited = false;
};

class CommandLimiter {
 public:
  CommandLimiter() = default;
  explicit CommandLimiter(const DeviceLimits& limits) : limits_(limits) {}

  /// The command to send for `wanted` this tick of length dt, scaled by gain in [0, 1].
  LimitedCommand apply(const DeviceCommand& wanted, double dt, double gain) noexcept;
  /// Zero at once (the watchdog): returns the zero command and remembers it as sent.
  DeviceCommand zero() noexcept;

  [[nodiscard]] const DeviceCommand& last() const { return last_; }
  [[nodiscard]] const DeviceLimits& limits() const { return limits_; }

 private:
  DeviceLimits limits_;
  DeviceCommand last_;
};

}  // namespace lap::hardware
