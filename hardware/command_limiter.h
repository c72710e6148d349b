#pragma once
/// \file
/// The last step before a command reaches a device: whatever the rendering produced, what is
/// sent is finite, within the device's limits, scaled by a gain the runtime ramps from 0 to 1
/// when a paused session resumes, and changes no faster than the device's force-rate limit. A
/// zero command (the watchdog's) bypasses the rate limit: forces drop to zero within the tick.
///
/// The limits, in the order they act:
///  1. Stiffness. The command states the stiffness behind its force at the handle
///     (DeviceCommand::stiffness_n_per_m, the tool's stiffness budget). Above the device's
///     max_stiffness_n_per_m the force and torque are scaled by s = max / stated, which renders
///     every spring behind them s times as stiff. s falls at once (a lower stiffness takes energy
///     out, never puts it in) and rises back by at most 1/stiffness_recovery_s per second: a
///     spring still compressed while s rises gains ½ Δs k x², so the rise is kept slow; s times
///     the stated stiffness never exceeds the maximum on any tick.
///  2. Peak: |F| ≤ max_force_n, |τ| ≤ max_torque_nm, squeeze in [0, max_squeeze_n].
///  3. Sustained force (an I²t model, as servo drives protect their motors: heat goes with the
///     current squared, and current with force): θ, the exponential mean of |F_sent|² with the
///     device's thermal_time_constant_s τ, is the motors' temperature rise in units of force².
///     While θ ≤ ½ F_c² (F_c = max_continuous_force_n) a command may reach the peak; from there
///     the bound falls linearly in θ to F_c at θ = F_c². A request held above F_c therefore
///     settles at F_c exactly (θ → F_c² from below, without chatter: the bound is continuous in
///     θ). From cold such a request is sent whole until θ reaches the knee, for
///     t = −τ ln(1 − F_c² / (2 F²)) (0.36 s for 3.3 N against 0.88 N at τ = 10 s): a short peak
///     passes untouched. The torque is scaled with the force.
///  4. The gain, then the rate limit.
///
/// Real time: no allocation, no lock, no exception.

#include "hardware/haptic_device.h"

namespace lap::hardware {

struct LimitedCommand {
  DeviceCommand command;
  bool non_finite = false;  ///< the input had a NaN or an infinity (the command is zero)
  bool clamped = false;     ///< a magnitude limit cut it
  bool rate_limited = false;
  bool stiffness_scaled = false;   ///< the stiffness limit scaled it (stiffness_scale() < 1)
  bool sustained_limited = false;  ///< the continuous-force bound cut it
};

class CommandLimiter {
 public:
  /// How fast the stiffness scale may rise again, from 0 to 1 [s].
  static constexpr double kStiffnessRecoveryS = 0.1;
  /// The fraction of F_c² the thermal state may reach before the peak bound starts to fall.
  static constexpr double kThermalKnee = 0.5;

  CommandLimiter() = default;
  explicit CommandLimiter(const DeviceLimits& limits) : limits_(limits) {}

  /// The command to send for `wanted` this tick of length dt, scaled by gain in [0, 1].
  LimitedCommand apply(const DeviceCommand& wanted, double dt, double gain) noexcept;
  /// Zero at once (the watchdog): returns the zero command and remembers it as sent. The
  /// thermal state is left as it is (it does not cool while zeroed: the safe side).
  DeviceCommand zero() noexcept;

  [[nodiscard]] const DeviceCommand& last() const { return last_; }
  [[nodiscard]] const DeviceLimits& limits() const { return limits_; }
  /// The scale the stiffness limit applied on the last tick, in (0, 1].
  [[nodiscard]] double stiffness_scale() const { return stiffness_scale_; }
  /// The thermal state θ: the exponential mean of |F_sent|² [N²].
  [[nodiscard]] double thermal_state_n2() const { return thermal_n2_; }
  /// The largest |F| allowed now by the peak and the sustained bound [N].
  [[nodiscard]] double force_bound_n() const noexcept;

 private:
  DeviceLimits limits_;
  DeviceCommand last_;
  double stiffness_scale_ = 1.0;
  double thermal_n2_ = 0.0;
};

}  // namespace lap::hardware
