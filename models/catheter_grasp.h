#pragma once
/// \file
/// Grasping the catheter with the laparoscopic gripper (§7.6.2–7.6.3, Figure 7-18).
///
/// Capture: when the jaws close past the grasp angle, the section of the catheter's centre line
/// that lies between them is found by clipping every segment against the jaws' wedge (a convex
/// region: depth 0..jaw length from the hinge, the jaw's width, and the gap between the jaws plus
/// the catheter's radius), so the catheter is caught wherever it crosses, between particles too.
/// The wedge is the one the jaws had when they started closing: closing sweeps what lay between
/// them to the middle (the tools do not push the catheter otherwise).
///
/// Hold: the held section (its extent in the jaws' mid-plane, at least the jaw's width) is tied
/// at its two ends and at the particles between them to a straight line fixed in the jaws'
/// frame, by centre-line anchors (catheter_model.h), so the section follows the jaws in position
/// and orientation (the anchors transmit a moment; none is a hinge inside the jaws). As the jaws
/// close they flatten it into the gap between them, turning it towards their mid-plane at its
/// length, by at most flatten_step_m per step (the jaws sweep it in; a jump would be a force step).
///
/// Squeeze and slip: the catheter's wall, compressed by the jaws' gap at the held depth, pushes
/// each jaw apart with the squeeze N (it resists closure: the actuated gripper renders it, §7.5).
/// Along the held section the two jaw faces hold by Coulomb friction up to 2·μ·N, solved inside
/// the catheter's step (AnchorFriction, catheter_model.h): pulled harder, the catheter slides
/// through the jaws against 2·μ·N, and the held material is re-read where it then lies; sliding
/// off either end drops it.
///
/// The tool feels the grasp through a virtual coupling at the haptic rate (coupling_wrench()).
///
/// The jaw frame J: origin at the hinge, x the opening direction (jaw 0 opens along +x), y along
/// the shaft towards the handle, z = x × y; the jaws lie in the x–y plane pointing along −y.
///
/// Settings are plain values; the state is fixed-size (no allocation).

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
  /// Each jaw's width (along z): a 5 mm instrument's jaws fit its shaft, ≈ 4 mm (estimate).
  double jaw_width_m = 0.004;
  double grasp_below_rad = 0.30;    ///< closing past this grasps what lies between the jaws
  double release_above_rad = 0.45;  ///< opening past this releases
  /// Each of the two anchors at the held section's ends (project estimate: stiff enough that the
  /// held section turns with the jaws within 2° against the catheter's own bending; it is inside
  /// the catheter's implicit step, so it needs no device budget there).
  double attach_stiffness_n_per_m = 20000.0;
  double attach_damping_n_s_per_m = 0.3;
  double squeeze_stiffness_n_per_m = 3000.0;  ///< the catheter's wall, compressed by the jaws
  /// Jaw faces on the catheter: estimate for serrated steel on polyurethane (no measured value
  /// found; steel on polyurethane is quoted at 0.3–0.5 dry).
  double friction = 0.4;
  double max_force_n = 5.0;  ///< per held point, at the haptic rate
  /// The haptic coupling between model steps (coupling_wrench): the stiffness the hand feels
  /// through a grasp before the next model step answers, within the device's budget, and a
  /// damper for passivity with a model 5 ms behind (Colgate: b > k T / 2 = 0.75 N s/m at
  /// T = 5 ms; estimate with margin).
  double coupling_stiffness_n_per_m = 300.0;
  double coupling_damping_n_s_per_m = 1.0;
  double flatten_step_m = 0.0005;  ///< per modelling step: 0.1 m/s at 200 Hz (estimate)
};

struct GraspState {
  bool held = false;
  /// The held section's centre and half length along the catheter, in segments (material
  /// coordinate s: particle i at s = i).
  double center_s = 0.0;
  double half_length_s = 0.0;
  /// Where the section is held, in the jaws' frame: its centre, its unit axis (towards
  /// increasing s) and half its length [m]; its ends are centre ∓ half length · axis.
  Eigen::Vector3d center_J = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_J = Eigen::Vector3d::UnitZ();
  double half_length_m = 0.0;
  /// The opening at which the jaws last started closing: the wedge that closing sweeps.
  double closing_from_rad = 0.0;
  double last_opening_rad = -1.0;
  double slid_m = 0.0;  ///< how far the catheter has slid through the jaws while held, in total
  /// Slipping through the jaws (Coulomb): friction_n against slide_sign (+1: the catheter
  /// moves towards increasing s relative to the jaws).
  bool sliding = false;
  double slide_sign = 1.0;
  double friction_n = 0.0;
  int32_t friction_slot = -1;  ///< the catheter's friction group holding it (catheter_model.h)
  /// The jaws at the last modelling step (where the model's anchors were; the haptic coupling
  /// starts from there).
  JawFrame jaws;
  [[nodiscard]] bool grasping() const { return held; }
};

struct GraspOutput {
  Eigen::Vector3d force_on_tool_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_on_tool_W = Eigen::Vector3d::Zero();  ///< about the hinge
  double squeeze_n = 0.0;  ///< force each jaw feels resisting closure
  bool grasped_now = false;
  bool released_now = false;  ///< by opening the jaws
  bool slipped_out = false;   ///< slid off the catheter's end (dropped)
  bool sliding = false;       ///< slipped through the jaws in the last step
};

/// The section of the centre line between the jaws, swept from `closing_from_rad`: [s0, s1] in
/// segments (the longest connected piece), or s0 > s1 when nothing lies between them.
struct HeldSection {
  double s0 = 1.0;
  double s1 = 0.0;
  [[nodiscard]] bool found() const { return s0 <= s1; }
};
[[nodiscard]] HeldSection section_between_jaws(const GraspSettings& settings, const JawFrame& jaws,
                                               double wedge_rad, const CatheterModel& model,
                                               std::span<const Eigen::Vector3d> positions) noexcept;

/// After step_catheter: whether the held section slipped in that step (and the friction it
/// met), for the haptic coupling and the next update_grasp.
void finish_grasp_step(const CatheterState& catheter, GraspState* grasp) noexcept;

/// One modelling step, before step_catheter (after clear_anchors): grasp or release by the opening
/// angle, slide the held section if pulled beyond friction, and add its two anchors to the
/// catheter; returns the reaction on the tool and the squeeze.
GraspOutput update_grasp(const GraspSettings& settings, const JawFrame& jaws,
                         const CatheterModel& model, CatheterState* catheter,
                         GraspState* grasp) noexcept;

/// The squeeze on each jaw at the jaws' present opening [N] (haptic rate: it needs only the
/// jaws and the grasp).
[[nodiscard]] double grasp_squeeze(const GraspSettings& settings, const JawFrame& jaws,
                                   const CatheterModel& model, const GraspState& grasp) noexcept;

/// The wrench on the tool (force, and torque about the hinge) from the held section.
struct GraspWrench {
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_W = Eigen::Vector3d::Zero();
};

/// The jaws at a haptic tick, for the coupling.
struct HapticJaws {
  JawFrame jaws;         ///< now
  JawFrame jaws_before;  ///< one tick ago
  double tick_s = 0.001;
  double since_step_s = 0.0;  ///< since the modelling step the catheter's motion is from
};
/// The catheter as the modelling loop last published it (another thread's copies).
struct CatheterMotion {
  std::span<const Eigen::Vector3d> positions;
  std::span<const Eigen::Vector3d> velocities;
};

/// The virtual coupling at the haptic rate (§7.7: the models step at 200 Hz, the hand at
/// 1 kHz). Per held point: the model's own anchor force at its last step (exact, however stiff
/// the anchor), plus a spring and damper of the coupling's stiffness (within the device's
/// budget) on how far the jaws have moved since that step relative to where the held point is
/// heading (its velocity then) — a local model of the grasp between model steps (Cavusoglu &
/// Tendick 2000), not a stiff spring against stale positions. Each held point's force is clamped
/// to max_force_n; zero when not finite.
[[nodiscard]] GraspWrench coupling_wrench(const GraspSettings& settings, const HapticJaws& now,
                                          const CatheterModel& model,
                                          const CatheterMotion& catheter,
                                          const GraspState& grasp) noexcept;

/// The held section's end k (0, 1) on the centre line, at material coordinate center ∓ half.
[[nodiscard]] double held_end_s(const GraspState& grasp, int k);
/// Where the jaws hold that end, in their frame.
[[nodiscard]] Eigen::Vector3d held_end_J(const GraspState& grasp, int k);
/// Where the jaws hold the held section's point at material coordinate s, in their frame.
[[nodiscard]] Eigen::Vector3d held_point_J(const GraspState& grasp, double s);
/// A point of the centre line at material coordinate s (segments), clamped to the catheter.
[[nodiscard]] Eigen::Vector3d point_at(std::span<const Eigen::Vector3d> positions, double s);

}  // namespace lap::models
