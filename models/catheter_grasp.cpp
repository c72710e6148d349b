#include "models/catheter_grasp.h"

#include <algorithm>
#include <cmath>

namespace lap::models {
namespace {

Eigen::Vector3d to_jaw(const JawFrame& j, const Eigen::Vector3d& p_W) {
  return j.rotation_WJ.transpose() * (p_W - j.hinge_W);
}
Eigen::Vector3d to_world(const JawFrame& j, const Eigen::Vector3d& p_J) {
  return j.hinge_W + j.rotation_WJ * p_J;
}
Eigen::Vector3d clamp_norm(const Eigen::Vector3d& f, double max) {
  const double n = f.norm();
  return n > max ? Eigen::Vector3d(f * (max / n)) : f;
}

}  // namespace

GraspOutput update_grasp(const GraspSettings& s, const JawFrame& jaws, const CatheterModel& model,
                         CatheterState* cath, GraspState* grasp) noexcept {
  GraspOutput out;
  const double r = model.radius_m();
  const double half = 0.5 * jaws.opening_rad;
  if (grasp->grasping() && jaws.opening_rad > s.release_above_rad) {
    for (int32_t k = 0; k < grasp->count; ++k) {
      cath->anchor_stiffness[grasp->particle[k]] = 0.0;
      cath->anchor_damping[grasp->particle[k]] = 0.0;
    }
    grasp->count = 0;
    out.released_now = true;
  }
  if (!grasp->grasping() && jaws.opening_rad < s.grasp_below_rad) {
    // The particles inside the jaws' wedge (within the catheter's radius of it).
    for (int32_t i = 0; i < model.particle_count() && grasp->count < GraspState::kMaxGrasped; ++i) {
      const Eigen::Vector3d p = to_jaw(jaws, cath->positions[i]);
      const double depth = -p.y();  // along the jaws from the hinge
      if (depth < 0.0 || depth > s.jaw_length_m || std::abs(p.z()) > r) continue;
      if (std::abs(p.x()) > depth * std::tan(half) + r) continue;
      grasp->particle[grasp->count] = i;
      grasp->anchor_J[grasp->count] = Eigen::Vector3d(0.0, p.y(), 0.0);  // centred between jaws
      ++grasp->count;
    }
    out.grasped_now = grasp->grasping();
  }
  for (int32_t k = 0; k < grasp->count; ++k) {
    const int32_t i = grasp->particle[k];
    // The attachment spring is one of the catheter's anchors, so the implicit step keeps it
    // stable however stiff (as an explicit force it would need dt < 2 sqrt(m / k) ≈ 0.5 ms).
    const Eigen::Vector3d target = to_world(jaws, grasp->anchor_J[k]);
    cath->anchor_target[i] = target;
    cath->anchor_stiffness[i] = s.attach_stiffness_n_per_m;
    cath->anchor_damping[i] = s.attach_damping_n_s_per_m;
    out.force_on_tool_W -= clamp_norm(s.attach_stiffness_n_per_m * (target - cath->positions[i]) -
                                          s.attach_damping_n_s_per_m * cath->velocities[i],
                                      s.max_force_n);
  }
  out.squeeze_n = grasp_squeeze(s, jaws, model, *grasp);
  return out;
}

double grasp_squeeze(const GraspSettings& s, const JawFrame& jaws, const CatheterModel& model,
                     const GraspState& grasp) noexcept {
  const double r = model.radius_m();
  const double half = 0.5 * jaws.opening_rad;
  double squeeze = 0.0;
  for (int32_t k = 0; k < grasp.count; ++k) {
    // The jaws' gap at this depth against the catheter's diameter.
    const double depth = -grasp.anchor_J[k].y();
    const double gap = 2.0 * depth * std::sin(half);
    squeeze += s.squeeze_stiffness_n_per_m * std::max(0.0, 2.0 * r - gap);
  }
  return squeeze;
}

Eigen::Vector3d coupling_force(const GraspSettings& s, const JawFrame& jaws,
                               std::span<const Eigen::Vector3d> positions,
                               const GraspState& grasp) noexcept {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (int32_t k = 0; k < grasp.count; ++k) {
    const auto p = static_cast<size_t>(grasp.particle[k]);
    if (p >= positions.size()) continue;
    const Eigen::Vector3d target = to_world(jaws, grasp.anchor_J[k]);
    f -= clamp_norm(s.attach_stiffness_n_per_m * (target - positions[p]), s.max_force_n);
  }
  return f.allFinite() ? f : Eigen::Vector3d::Zero();
}

Eigen::Vector3d coupling_force(const GraspSettings& s, const JawFrame& jaws,
                               const CatheterState& cath, const GraspState& grasp) noexcept {
  return coupling_force(s, jaws, std::span<const Eigen::Vector3d>(cath.positions), grasp);
}

}  // namespace lap::models
