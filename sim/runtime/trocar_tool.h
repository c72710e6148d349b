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
///
/// The stiffness budget at the handle. Through the same lever a spring of stiffness k acting at
/// a point p inside is felt at the handle as T k Tᵀ, T the map above from a force at p to the
/// handle: along the shaft the force passes 1:1, across it scaled by d = (u·r)/a, r = p − port,
/// plus ρ/a times the axial force for a point ρ off the axis (a jaw's). So the hand feels at most
/// k g², g² = the largest singular value of T squared (lever_gain_squared(): max(1, (b/a)²)
/// for a point on the axis). The springs acting on one tool at once — each contact of its three
/// segment proxies (the force law's k, or the sticking friction spring where stiffer) and each
/// grasp coupling — act in parallel, so the stiffness at the handle is at most Σ k_i g_i²
/// (StiffnessBudget). The haptic tick states it with the device command and CommandLimiter keeps
/// it within the device's max_stiffness_n_per_m (hardware/command_limiter.h).

#include <Eigen/Geometry>
#include <span>

#include "haptics/haptic_object.h"
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

/// g²: how much stiffer a spring acting at `point_W` feels at the handle than at the point (the
/// largest singular value, squared, of the lever from a force there to the handle's force).
[[nodiscard]] double lever_gain_squared(const ToolKinematics& kinematics,
                                        const Eigen::Vector3d& point_W) noexcept;

/// The stiffness a contact with `object` renders: its force law's k across the surface, the
/// sticking friction spring k_s along it (scaled by the friction map at `point_W`), whichever is
/// stiffer [N/m].
[[nodiscard]] double contact_stiffness_n_per_m(const haptics::HapticObject& object,
                                               const Eigen::Vector3d& point_W) noexcept;

/// The springs acting on one tool this tick, summed at the handle through their levers (the
/// header's note). Real time: no allocation.
class StiffnessBudget {
 public:
  explicit StiffnessBudget(const ToolKinematics& kinematics) noexcept : kinematics_(kinematics) {}

  /// A spring of stiffness k [N/m] acting at point_W: a contact, or a grasp coupling (the hook
  /// for the couplings: each adds its stiffness here where it is rendered).
  void add(double stiffness_n_per_m, const Eigen::Vector3d& point_W) noexcept;
  /// Every contact the gripper's three segment proxies hold after their step.
  void add_contacts(const haptics::LaparoscopicGripper& gripper,
                    std::span<const haptics::HapticObject> objects) noexcept;
  /// Σ k_i g_i² [N/m].
  [[nodiscard]] double at_handle_n_per_m() const { return total_n_per_m_; }

 private:
  ToolKinematics kinematics_;
  double total_n_per_m_ = 0.0;
};

}  // namespace lap::sim
