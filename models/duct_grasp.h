#pragma once
/// \file
/// Grasping tissue — the cystic duct — with the laparoscopic gripper (§7.6.2, Figure 7-18; the
/// duct's modes, §7.7(2)). When the device's jaws close past a grasp angle, the duct's nodes
/// lying between them (or within `reach_m` outside their wedge: the proxies keep the drawn jaws
/// on the surface while the device's jaws close further) are attached, each by a spring and
/// damper, to a point fixed in the frame of the jaw on its side. The springs are anchors of the
/// duct's modal step (modal_shell.h: NodeAnchor), inside its implicit solve, so a stiff grasp is
/// stable at the modelling rate. Closing further carries the anchors inwards and flattens the
/// duct: the springs' push against each jaw is the squeeze for the actuated gripper (§7.5),
/// growing with closure through the shell's own stiffness. Opening past the release angle
/// lets go. The tool feels the springs through a virtual coupling evaluated at the haptic rate
/// (duct_coupling()): the model's springs against the duct's latest node positions plus a damper
/// on the jaws' motion, which makes it passive against a model one period behind.
///
/// Frames: the duct's modes live in its own frame D (pose_WD); jaw frame J as in catheter_grasp.h
/// (origin at the hinge, x the opening direction, jaw 0 on +x, jaws along −y). Jaw j's own frame
/// is J turned about z by ±half the opening (+ for jaw 0).
///
/// No allocation, no exceptions.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <span>

#include "models/catheter_grasp.h"
#include "models/modal_shell.h"

namespace lap::models {

struct DuctGraspSettings {
  double jaw_length_m = 0.02;
  double jaw_half_width_m = 0.0025;  ///< across the jaws (J's z): a 5 mm instrument
  double grasp_below_rad = 0.30;     ///< closing past this grasps
  double release_above_rad = 0.45;   ///< opening past this releases
  double reach_m = 0.003;            ///< how far outside the device's wedge a node is still taken
  /// Per node: with up to kMaxNodes nodes the tool feels about count × this when it pulls.
  double attach_stiffness_n_per_m = 20.0;
  double attach_damping_n_s_per_m = 0.01;
  double max_force_n = 0.5;  ///< per node, in the haptic-rate coupling
  /// Per node, in the haptic-rate coupling, on the anchor's velocity (the jaws' motion): the
  /// springs act against node positions held for a modelling period T, a sampled spring, which
  /// Colgate & Schenkel (1997) show passive for b > k T / 2 = 0.05 N s/m at k = 20 N/m,
  /// T = 5 ms; 0.08 leaves a margin of 1.6 (the catheter's coupling keeps 1.33). 32 nodes:
  /// 2.6 N s/m at the jaws.
  double coupling_damping_n_s_per_m = 0.08;
};

struct DuctGraspState {
  static constexpr int32_t kMaxNodes = 32;
  int32_t count = 0;
  std::array<int32_t, kMaxNodes> node{};
  std::array<int8_t, kMaxNodes> jaw{};                  ///< 0 or 1
  std::array<Eigen::Vector3d, kMaxNodes> anchor_jaw{};  ///< in the frame of its jaw
  [[nodiscard]] bool grasping() const { return count > 0; }
};

struct DuctGraspOutput {
  Eigen::Vector3d force_on_tool_W = Eigen::Vector3d::Zero();
  double squeeze_n = 0.0;  ///< the duct's push against the jaws, mean of the two [N]
  bool grasped_now = false;
  bool released_now = false;
};

/// One modelling step, before step_modal_shell and after clear_node_anchors (each grasp adds its
/// anchors every step): grasp or release by the opening angle, add the grasped nodes' anchors
/// at the jaws' present pose, and return the springs' reaction on the tool and the squeeze at
/// the duct's present state. `rest_nodes_D`: the shell mesh's nodes (duct frame).
DuctGraspOutput update_duct_grasp(const DuctGraspSettings& settings, const JawFrame& jaws_W,
                                  const Eigen::Isometry3d& pose_WD,
                                  std::span<const Eigen::Vector3d> rest_nodes_D,
                                  const ModalShellModel& model, ModalShellState* duct,
                                  DuctGraspState* grasp) noexcept;

struct DuctCoupling {
  Eigen::Vector3d force_on_tool_W = Eigen::Vector3d::Zero();
  double squeeze_n = 0.0;
};

/// The virtual coupling at the haptic rate (§7.7: the duct steps at 200 Hz, the hand at 1 kHz),
/// per grasped node: the model's own anchor spring at its last step, k (a(J_step) − n), plus a
/// local spring and damper on the jaws' motion since, k (a(J_now) − a(J_step)) + b ȧ — together
/// k (a(J_now) − n) + b ȧ, with `n` where the modelling loop last put the node (`nodes_D`:
/// deformed node positions, duct frame), a(J) the anchor in jaws J and ȧ its velocity from the
/// jaws one tick ago (`jaws.jaws_before`, `jaws.tick_s`). b = coupling_damping_n_s_per_m > k T/2
/// for the model's period T (Colgate): passive against positions up to T old. Each node's force
/// is clamped to max_force_n; the squeeze is the springs' part; a non-finite result is zero.
[[nodiscard]] DuctCoupling duct_coupling(const DuctGraspSettings& settings, const HapticJaws& jaws,
                                         const Eigen::Isometry3d& pose_WD,
                                         std::span<const Eigen::Vector3d> nodes_D,
                                         const DuctGraspState& grasp) noexcept;

}  // namespace lap::models
