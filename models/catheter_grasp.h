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
/// Hold: the held section (its extent in the jaws' mid-plane, at least the jaw's width) is held
/// at its two ends and at the particles between them on a straight line fixed in the jaws'
/// frame. Its shape and orientation are held stiffly, by links between consecutive held points
/// (CenterlineLink: each keeps its pair's difference at the line's, hold_stiffness), which carry
/// no net force, only a moment, so the section follows the jaws' turn. Its position is held by
/// the virtual coupling to the hand: a spring and damper (coupling_stiffness, coupling_damping)
/// shared by the held points' centre-line anchors (CenterlineAnchor, catheter_model.h), their
/// targets on the line in the jaws as they were read for this step, their damper on the velocity
/// relative to the jaws'. Both are inside the catheter's implicit step. As the jaws close they
/// flatten the section into the gap between them, turning it towards their mid-plane at its
/// length, by at most flatten_step_m per step (the jaws sweep it in; a jump would be a force
/// step).
///
/// Squeeze and slip: the catheter's wall, compressed by the jaws' gap at the held depth, pushes
/// each jaw apart with the squeeze N (it resists closure: the actuated gripper renders it, §7.5).
/// Along the held section the two jaw faces hold by Coulomb friction up to 2·μ·N, solved inside
/// the catheter's step on the anchors' axial force (AnchorFriction, catheter_model.h): pulled
/// harder, the catheter slides through the jaws against 2·μ·N, and the held material is re-read
/// where it then lies; sliding off either end drops it.
///
/// The hand (coupling_wrench(), at the haptic rate) feels the same spring and damper, evaluated
/// with the jaws as they are now against the held section as the model last left it, and the
/// links' moment: a virtual coupling in Colgate, Stanley & Brown's sense (IROS 1995; Adams &
/// Hannaford, IEEE T-RA 15(3), 1999) between the tool and the 200 Hz model. The hand never feels
/// more than the coupling's stiffness through a grasp, however stiff the taut catheter beyond
/// it, and no energy is made where the rates meet, given its damper (GraspSettings):
///
///  - The coupling's energy U(J, x) = ½ k |J − x|² (J where the jaws hold a point, x the point).
///    The modelling step reads the jaws at J_a and moves the section from x0 to x1 by backward
///    Euler with J_a fixed, which gives the catheter at most U(J_a, x0) − U(J_a, x1) (it
///    dissipates ½ k |x1 − x0|² besides). The haptic loop takes x1 up a little later, when the
///    jaws are at J_b: the coupling's energy changes by U(J_b, x1) − U(J_b, x0). What that
///    switch makes beyond what the model took is −k (J_b − J_a)·(x1 − x0) − ½ k |x1 − x0|²,
///    at most ½ k |J_b − J_a|².
///  - J_b − J_a is the jaws' travel in the lag τ ≤ T between the model's read and the haptic
///    take-up (T the modelling period: a step that ran longer is skipped, not waited for).
///    Moving at v, that is at most ½ k v² τ² per step, while the damper on the jaws' motion
///    relative to the section takes b v² T over the step: b ≥ k τ² / (2 T) suffices, and with
///    τ ≤ T, b ≥ k T / 2 — Colgate & Schenkel's b > K T / 2 for a spring sampled at T (J. Robotic
///    Systems 14(1), 1997), here for the model's period. (With the section moving too, the worst
///    case over both motions needs only b ≥ k T / 6 on the relative velocity.)
///  - The links' moment is a rotational spring Σ k_l |r_l|² on the jaws' turn, sampled alike:
///    hold_damping ≥ hold_stiffness · T / 2 for the same reason.
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
  /// Each link between consecutive held points (project estimate: stiff enough that the held
  /// section turns with the jaws within 2° against the catheter's own bending — as two end
  /// anchors of 20 kN/m did, its rotational stiffness 2 k h²; inside the catheter's implicit
  /// step, so stable at the modelling rate). The hand feels its moment through the trocar as
  /// Σ k |r|² / a² (a the handle's distance from the port): 8 N/m for a section held across
  /// the jaws (4 mm), 25 N/m for one along them (20 mm) at a = 0.2 m (in the stiffness budget).
  double hold_stiffness_n_per_m = 20000.0;
  /// k T / 2 = 50 N s/m at T = 5 ms (the header's bound), with margin 1.2.
  double hold_damping_n_s_per_m = 60.0;
  /// The jaws' squeeze on the catheter per metre of the wall's compression, k_s: an estimate, a
  /// rendering choice rather than the tube's own stiffness. The tube pinched across a diameter
  /// is a ring under diametral load, δ = 0.149 F R³ / (E I) per unit length (Roark), I = t³/12:
  /// for the 5 Fr tube (mid-wall R = 0.67 mm, wall t = 0.33 mm, E = 152 MPa, Pellethane
  /// 2363-55D) over the jaw's 4 mm, k = w E t³ / (12 × 0.149 R³) ≈ 43 kN/m. The actuated
  /// gripper renders at most 5 N at the jaws (hardware/haptic_device.h, max_squeeze_n), which
  /// that stiffness would reach in the first 0.12 mm of closure: a step to the motor's limit.
  /// 3000 N/m spreads it over the whole closure onto the 1.67 mm catheter (5.0 N with the jaws
  /// shut), so the trainee feels the squeeze grow as the jaws close.
  double squeeze_stiffness_n_per_m = 3000.0;
  /// Jaw faces on the catheter: estimate for serrated steel on polyurethane (no measured value
  /// found; steel on polyurethane is quoted at 0.3–0.5 dry).
  double friction = 0.4;
  /// The coupling's force on the tool at the haptic rate is clamped to this [N] (a guard: the
  /// limiter bounds what reaches the device).
  double max_force_n = 5.0;
  /// The virtual coupling between the jaws and the held section (the header): the stiffness the
  /// hand feels through a grasp, within the device's budget (1000 N/m at the handle, through the
  /// lever (b/a)² ≈ 0.3–1 in the scenarios, beside the organs' contacts), and its damper for the
  /// 200 Hz model: b ≥ k T / 2 = 1.0 N s/m at k = 400 N/m, T = 5 ms; 1.6 N s/m, margin 1.6.
  /// The held section lags the jaws by F / k under a load F (0.5 mm at 0.2 N).
  double coupling_stiffness_n_per_m = 400.0;
  double coupling_damping_n_s_per_m = 1.6;
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
  /// The jaws at the last modelling step (where the model's anchors were).
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

/// One modelling step of dt, before step_catheter (after clear_anchors): grasp or release by the
/// opening angle, slide the held section if pulled beyond friction, and add its anchors and
/// links to the catheter; returns the anchors' reaction on the tool and the squeeze.
GraspOutput update_grasp(const GraspSettings& settings, const JawFrame& jaws,
                         const CatheterModel& model, CatheterState* catheter, GraspState* grasp,
                         double dt) noexcept;

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
/// 1 kHz; the header): the anchors' spring and damper with the jaws now against the held points
/// as the model last left them, and the links' moment likewise — the same force the model's
/// next step integrates. While the section slid in the last step, the friction it met stands
/// for the anchors' part along it. The force is clamped to max_force_n; zero when not finite.
[[nodiscard]] GraspWrench coupling_wrench(const GraspSettings& settings, const HapticJaws& now,
                                          const CatheterModel& model,
                                          const CatheterMotion& catheter,
                                          const GraspState& grasp) noexcept;

/// The coupling's stiffness against a turn of the jaws, Σ k_l |r_l|² over the held section's
/// links [N m/rad] (for the stiffness budget at the handle: through the trocar, divided by the
/// handle's distance from the port squared).
[[nodiscard]] double coupling_rotational_stiffness(const GraspSettings& settings,
                                                   const CatheterModel& model,
                                                   std::span<const Eigen::Vector3d> positions,
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
