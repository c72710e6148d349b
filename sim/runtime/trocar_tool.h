#pragma once
/// \file
/// A laparoscopic tool through its trocar (thesis §7.2, §7.5, Figure 7-10): the device holds the
/// instrument's handle, the shaft passes through the port — a fixed fulcrum on the abdominal
/// wall — and the tip (the jaws' hinge) is inside, `shaft_length` from the handle along the
/// shaft. So the device drives the tip through the fulcrum: 4 DOF (pivot about the port in two
/// angles, insertion, roll) plus the grip, and the tip moves opposite to the hand, scaled by the
/// ratio of the lengths inside and outside (the mirrored hand–eye mapping of §7.2).
///
/// The wrench the proxies put on the tool at its tip goes back to the device through the same
/// lever: with the tool in quasi-static balance between the tissue's force F and torque τ at the
/// tip, the port's reaction (perpendicular to the shaft, no moment about the port) and the hand
/// at the handle, the device renders
///     F_axial = (F·u) u,
///     F_lateral = −(b/a) F_⊥ − (τ_⊥ × u)/a,
///     torque = (τ·u) u  (the roll, for devices that render torque),
/// with u the unit shaft direction from port to tip, b the length inside and a outside.

#include <Eigen/Geometry>

#include "haptics/laparoscopic_gripper.h"
#include "hardware/haptic_device.h"
#include "sim/setup/tool_model.h"

namespace lap::sim {

struct ToolKinematics {
  haptics::GripperPose pose;                           ///< the three segments' pose for the proxies
  Eigen::Vector3d handle_W = Eigen::Vector3d::Zero();  ///< where the device is (as clamped)
  Eigen::Vector3d axis_W = Eigen::Vector3d::UnitY();   ///< u: unit, port to tip
  double inside_m = 0.0;                               ///< b: port to tip
  double outside_m = 0.0;                              ///< a: handle to port
};

/// Where the tool is for a device sample (the sample's position is the handle).
/// `previous_axis` is used when the handle sits exactly on the port line's degenerate point.
[[nodiscard]] ToolKinematics tool_kinematics(const TrocarToolSettings& settings,
                                             const hardware::DeviceSample& sample,
                                             const Eigen::Vector3d& previous_axis_W) noexcept;

/// The device command (at the handle) for the tissue's force and torque at the tip (torque
/// about the hinge), through the fulcrum; squeeze passed through.
[[nodiscard]] hardware::DeviceCommand handle_command(const ToolKinematics& kinematics,
                                                     const Eigen::Vector3d& force_tip_W,
                                                     const Eigen::Vector3d& torque_tip_W,
                                                     double squeeze_n) noexcept;

}  // namespace lap::sim
