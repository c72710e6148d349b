#pragma once
/// \file
/// Grasping the catheter with the laparoscopic gripper (§7.6.2–7.6.3, Figure 7-18): when the
/// jaws close on catheter particles lying between them, those particles are attached by springs
/// to points fixed in the jaws' frame (a grasp), and follow the tool; opening past a release
/// angle lets them go (hysteresis between the two angles). The catheter's diameter between the
/// jaws gives the squeeze force for the actuated gripper (§7.5), growing with closure. The tool
/// feels the attachment springs through a virtual coupling evaluated at the haptic rate against
/// the model's latest particle positions, so the force stays smooth and bounded between model
/// steps (coupling_force()).
///
/// The jaw frame J: origin at the hinge, x the opening direction (jaw 0 opens along +x), y along
/// the shaft towards the handle, z = x × y; the jaws lie in the x–y plane pointing along −y.
///
/// Settings are plain values (no allocation); state holds a fixed number of grasped particles.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>

#include "models/catheter_model.h"

namespace lap::models {

struct JawFrame {
  Eigen::Vector3d hinge_W = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation_WJ = Eigen::Matrix3d::Identity();  ///< columns: J's axes in W
  double opening_rad = 0.5;                                   ///< angle between the jaws
};

struct GraspSettings {
  double jaw_length_m = 0.02;
  double grasp_below_rad = 0.30;    ///< closing past this grasps what lies between the jaws
  double release_above_rad = 0.45;  ///< opening past this releases
  double attach_stiffness_n_per_m = 300.0;
  double attach_damping_n_s_per_m = 0.3;
  double squeeze_stiffness_n_per_m = 3000.0;  ///< the catheter's wall, compressed by the jaws
  double max_force_n = 5.0;                   ///< per attachment spring
};

struct GraspState {
  static constexpr int kMaxGrasped = 8;
  int32_t count = 0;
  std::array<int32_t, kMaxGrasped> particle{};
  std::array<Eigen::Vector3d, kMaxGrasped> anchor_J{};  ///< attachment points in the jaw frame
  [[nodiscard]] bool grasping() const { return count > 0; }
};

struct GraspOutput {
  Eigen::Vector3d force_on_tool_W = Eigen::Vector3d::Zero();
  double squeeze_n = 0.0;  ///< force the jaws feel resisting closure
  bool grasped_now = false;
  bool released_now = false;
};

/// One modelling step, before step_catheter: grasp or release by the opening angle, set the
/// grasped particles' anchors to the jaws (cleared on release), return the reaction on the tool
/// and the squeeze.
GraspOutput update_grasp(const GraspSettings& settings, const JawFrame& jaws,
                         const CatheterModel& model, CatheterState* catheter,
                         GraspState* grasp) noexcept;

/// The squeeze the grasped particles put on the jaws at their present opening [N] (haptic
/// rate: it needs only the jaws and the grasp).
[[nodiscard]] double grasp_squeeze(const GraspSettings& settings, const JawFrame& jaws,
                                   const CatheterModel& model, const GraspState& grasp) noexcept;

/// The virtual coupling at the haptic rate: the attachment springs between the jaws now and the
/// particles where the model last put them. Clamped to max_force_n per spring.
[[nodiscard]] Eigen::Vector3d coupling_force(const GraspSettings& settings, const JawFrame& jaws,
                                             const CatheterState& catheter,
                                             const GraspState& grasp) noexcept;
/// The same against particle positions published by the modelling loop (another thread's
/// copy of CatheterState::positions).
[[nodiscard]] Eigen::Vector3d coupling_force(const GraspSettings& settings, const JawFrame& jaws,
                                             std::span<const Eigen::Vector3d> positions,
                                             const GraspState& grasp) noexcept;

}  // namespace lap::models
