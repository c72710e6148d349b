#include "models/duct_grasp.h"

#include <algorithm>
#include <cmath>

namespace lap::models {
namespace {

/// The jaws seen from the duct's frame.
struct JawsInDuct {
  Eigen::Vector3d hinge_D;
  Eigen::Matrix3d rotation_DJ;
  double half = 0.0;  ///< half the opening
};

JawsInDuct in_duct(const JawFrame& jaws_W, const Eigen::Isometry3d& pose_WD) {
  return {pose_WD.inverse() * jaws_W.hinge_W, pose_WD.linear().transpose() * jaws_W.rotation_WJ,
          0.5 * jaws_W.opening_rad};
}

/// Jaw j's frame in J: J turned about z by +half (jaw 0, on +x) or −half (jaw 1).
Eigen::Matrix3d jaw_rotation(int jaw, double half) {
  return Eigen::AngleAxisd(jaw == 0 ? half : -half, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

Eigen::Vector3d anchor_in_duct(const JawsInDuct& j, int jaw, const Eigen::Vector3d& anchor_jaw) {
  return j.hinge_D + j.rotation_DJ * (jaw_rotation(jaw, j.half) * anchor_jaw);
}

/// The jaw's face normal pointing at the other jaw (the way it pushes tissue when closing).
Eigen::Vector3d inward_in_duct(const JawsInDuct& j, int jaw) {
  return j.rotation_DJ * (jaw_rotation(jaw, j.half) * Eigen::Vector3d(jaw == 0 ? -1.0 : 1.0, 0, 0));
}

Eigen::Vector3d clamp_norm(const Eigen::Vector3d& f, double max) {
  const double n = f.norm();
  return n > max ? Eigen::Vector3d(f * (max / n)) : f;
}

/// Takes the nodes nearest the jaws' faces among those between the jaws (or within reach).
void take_nodes(const DuctGraspSettings& s, const JawsInDuct& j,
                std::span<const Eigen::Vector3d> rest_nodes_D, const ModalShellState& duct,
                DuctGraspState* grasp) {
  std::array<double, DuctGraspState::kMaxNodes> score{};
  int32_t n = 0;
  const double tan_half = std::tan(j.half);
  const auto count = std::min(rest_nodes_D.size(), duct.displacement.size());
  for (size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d p_J =
        j.rotation_DJ.transpose() * (rest_nodes_D[i] + duct.displacement[i] - j.hinge_D);
    const double depth = -p_J.y();
    if (depth < 0.0 || depth > s.jaw_length_m || std::abs(p_J.z()) > s.jaw_half_width_m) continue;
    const double off = std::abs(p_J.x()) - depth * tan_half;  // < 0: inside the wedge
    if (off > s.reach_m) continue;
    const double d = std::abs(off);  // from the jaw's face
    // Insertion into the kept list, nearest first; the farthest falls off a full list.
    int32_t k = n < DuctGraspState::kMaxNodes ? n : DuctGraspState::kMaxNodes - 1;
    if (n == DuctGraspState::kMaxNodes && d >= score[k]) continue;
    while (k > 0 && score[k - 1] > d) {
      score[k] = score[k - 1];
      grasp->node[k] = grasp->node[k - 1];
      grasp->jaw[k] = grasp->jaw[k - 1];
      grasp->anchor_jaw[k] = grasp->anchor_jaw[k - 1];
      --k;
    }
    const int jaw = p_J.x() >= 0.0 ? 0 : 1;
    score[k] = d;
    grasp->node[k] = static_cast<int32_t>(i);
    grasp->jaw[k] = static_cast<int8_t>(jaw);
    // Held where the jaw took it: no force at the grasp, the squeeze grows from there.
    grasp->anchor_jaw[k] = jaw_rotation(jaw, j.half).transpose() * p_J;
    n = std::min(n + 1, DuctGraspState::kMaxNodes);
  }
  grasp->count = n;
}

}  // namespace

DuctGraspOutput update_duct_grasp(const DuctGraspSettings& s, const JawFrame& jaws_W,
                                  const Eigen::Isometry3d& pose_WD,
                                  std::span<const Eigen::Vector3d> rest_nodes_D,
                                  const ModalShellModel& model, ModalShellState* duct,
                                  DuctGraspState* grasp) noexcept {
  DuctGraspOutput out;
  const JawsInDuct j = in_duct(jaws_W, pose_WD);
  if (grasp->grasping() && jaws_W.opening_rad > s.release_above_rad) {
    grasp->count = 0;
    out.released_now = true;
  }
  if (!grasp->grasping() && jaws_W.opening_rad < s.grasp_below_rad && j.hinge_D.allFinite() &&
      j.rotation_DJ.allFinite()) {
    take_nodes(s, j, rest_nodes_D, *duct, grasp);
    out.grasped_now = grasp->grasping();
  }
  Eigen::Vector3d force_D = Eigen::Vector3d::Zero();
  for (int32_t k = 0; k < grasp->count; ++k) {
    const int32_t node = grasp->node[k];
    NodeAnchor a;
    a.node = node;
    a.target_u = anchor_in_duct(j, grasp->jaw[k], grasp->anchor_jaw[k]) -
                 rest_nodes_D[static_cast<size_t>(node)];
    a.stiffness_n_per_m = s.attach_stiffness_n_per_m;
    a.damping_n_s_per_m = s.attach_damping_n_s_per_m;
    if (!add_node_anchor(duct, a)) continue;
    const Eigen::Vector3d f = anchor_force(model, *duct, a);
    force_D -= f;
    out.squeeze_n += std::max(0.0, f.dot(inward_in_duct(j, grasp->jaw[k])));
  }
  out.squeeze_n *= 0.5;
  out.force_on_tool_W = pose_WD.linear() * force_D;
  if (!out.force_on_tool_W.allFinite() || !std::isfinite(out.squeeze_n)) {
    out.force_on_tool_W.setZero();
    out.squeeze_n = 0.0;
  }
  return out;
}

DuctCoupling duct_coupling(const DuctGraspSettings& s, const HapticJaws& jaws,
                           const Eigen::Isometry3d& pose_WD,
                           std::span<const Eigen::Vector3d> nodes_D,
                           const DuctGraspState& grasp) noexcept {
  DuctCoupling out;
  if (!(jaws.tick_s > 0.0)) return out;
  const JawsInDuct j = in_duct(jaws.jaws, pose_WD);
  const JawsInDuct before = in_duct(jaws.jaws_before, pose_WD);
  Eigen::Vector3d force_D = Eigen::Vector3d::Zero();
  for (int32_t k = 0; k < grasp.count; ++k) {
    const auto node = static_cast<size_t>(grasp.node[k]);
    if (node >= nodes_D.size()) continue;
    const Eigen::Vector3d anchor = anchor_in_duct(j, grasp.jaw[k], grasp.anchor_jaw[k]);
    const Eigen::Vector3d velocity =
        (anchor - anchor_in_duct(before, grasp.jaw[k], grasp.anchor_jaw[k])) / jaws.tick_s;
    const Eigen::Vector3d spring = s.attach_stiffness_n_per_m * (anchor - nodes_D[node]);
    const Eigen::Vector3d f =
        clamp_norm(spring + s.coupling_damping_n_s_per_m * velocity, s.max_force_n);
    force_D -= f;
    out.squeeze_n +=
        std::max(0.0, clamp_norm(spring, s.max_force_n).dot(inward_in_duct(j, grasp.jaw[k])));
  }
  out.squeeze_n *= 0.5;
  out.force_on_tool_W = pose_WD.linear() * force_D;
  if (!out.force_on_tool_W.allFinite() || !std::isfinite(out.squeeze_n)) return {};
  return out;
}

}  // namespace lap::models
