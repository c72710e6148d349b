#pragma once
/// \file
/// One interface for every device that drives a tool (docs/architecture.md, hardware/): a
/// PHANToM-class arm with an actuated gripper on its end (thesis §7.5, Figures 7-9 and 7-10), the
/// simulated, scripted and replay devices that stand in for it.
///
/// Devices report in the world frame, in metres: a driver converts its own units and frame
/// (OpenHaptics reports millimetres) before the sample leaves it. read() and write() are called
/// by the haptic thread once per tick and must not allocate, lock, throw or block; everything
/// else is set-up.

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/result.h"

namespace lap::hardware {

/// One consistent reading of a device (all fields from the same servo tick).
struct DeviceSample {
  double time_s = 0.0;  ///< device clock, seconds since the device started
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();  ///< the driven point [m]
  Eigen::Quaterniond orientation_W = Eigen::Quaterniond::Identity();
  Eigen::Vector3d velocity_W = Eigen::Vector3d::Zero();  ///< [m/s]
  uint32_t buttons = 0;                                  ///< bit i: button i pressed
  double gripper_angle_rad = 0.0;                        ///< opening of the jaws (0: closed)
};

/// What the haptic loop sends back each tick.
struct DeviceCommand {
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();   ///< at the driven point [N]
  Eigen::Vector3d torque_W = Eigen::Vector3d::Zero();  ///< [N m]; 0 on 3-DOF arms
  double squeeze_n = 0.0;  ///< actuated gripper: force resisting closure [N]
  /// The stiffness behind force_W at the driven point [N/m]: the sum of every spring acting
  /// there in parallel (sim/runtime/trocar_tool.h, StiffnessBudget). CommandLimiter scales the
  /// force and torque so that this times the scale stays within max_stiffness_n_per_m; 0: none
  /// stated (nothing scaled). Devices ignore it.
  double stiffness_n_per_m = 0.0;
};

/// What a device can safely render; the runtime clamps every command to these.
///
/// The defaults are a PHANToM Omni's, rounded down: SensAble's specification sheet gives 3.3 N
/// peak, 0.88 N continuous and 1.02–2.31 N/mm depending on the axis (the continuous figure is
/// also what the device reports for HD_NOMINAL_MAX_CONTINUOUS_FORCE), hence 3.0 N, 0.88 N and
/// 1000 N/m. For comparison, the PHANToM Premium 1.5's sheet gives 8.5 N peak, 1.4 N continuous
/// and 3.5 N/mm. Each driver sets its own device's figures (phantom_device.cpp reads them from
/// the device).
struct DeviceLimits {
  double max_force_n = 3.0;  ///< peak: no single command above it
  /// Sustained output: a thermal (I²t) model of the motors keeps the running mean of |F|² at or
  /// below this squared (command_limiter.h). 0, or at least max_force_n: no sustained bound.
  double max_continuous_force_n = 0.88;
  /// The thermal model's time constant [s]. Estimate: of the order of the winding time constant
  /// of the small coreless DC motors such arms use (tens of seconds); shorter is safer.
  double thermal_time_constant_s = 10.0;
  double max_torque_nm = 0.0;              ///< 0: the arm renders no torque
  double max_squeeze_n = 5.0;              ///< actuated gripper
  double max_stiffness_n_per_m = 1000.0;   ///< highest stiffness at the handle rendered stably
  double max_force_rate_n_per_s = 1000.0;  ///< rate limit on force changes
  Eigen::AlignedBox3d workspace_W{Eigen::Vector3d::Constant(-1.0), Eigen::Vector3d::Constant(1.0)};
};

enum class DeviceStatus : uint8_t {
  kOk,
  kFinished,      ///< a scripted or replayed input ran out (not an error)
  kDisconnected,  ///< the device went away (unplugged, link lost)
  kError,         ///< the device reported a fault or a reply made no sense
};

[[nodiscard]] std::string_view to_string(DeviceStatus status);

class HapticDevice {
 public:
  HapticDevice() = default;
  HapticDevice(const HapticDevice&) = delete;
  HapticDevice& operator=(const HapticDevice&) = delete;
  HapticDevice(HapticDevice&&) = delete;
  HapticDevice& operator=(HapticDevice&&) = delete;
  virtual ~HapticDevice() = default;

  /// Set-up: opens the device; on failure, diagnostics that say why.
  virtual Status start() = 0;
  /// Zero force, then release the device. Safe to call twice.
  virtual void stop() = 0;

  /// Real time. The sample for haptic tick `tick` (tick * period seconds after the session
  /// started; live devices ignore it and return their newest reading).
  virtual DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept = 0;
  /// Real time. Sends the command (already clamped by the runtime).
  virtual DeviceStatus write(const DeviceCommand& command) noexcept = 0;

  [[nodiscard]] virtual const DeviceLimits& limits() const = 0;
  [[nodiscard]] virtual std::string_view name() const = 0;
  /// The last problem in words (empty when none); not for the haptic thread.
  [[nodiscard]] virtual std::string last_error() const = 0;
};

}  // namespace lap::hardware
