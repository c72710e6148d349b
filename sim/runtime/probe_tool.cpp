#include "sim/runtime/probe_tool.h"

#include <algorithm>

namespace lap::sim {

ProbeTool::ProbeTool(ToolKind kind, double shaft_length_m)
    : kind_(kind), shaft_length_m_(shaft_length_m) {}

ProbeOutput ProbeTool::step(std::span<const haptics::HapticObject> objects,
                            const haptics::GripperPose& pose, double dt) noexcept {
  ProbeOutput out;
  const Eigen::Vector3d tip = pose.hinge_W;
  if (kind_ == ToolKind::kPointProbe) {
    if (!started_) point_.reset(tip);
    started_ = true;
    const haptics::PointProxyOutput p = point_.step(objects, tip, dt);
    out.force_W = p.force_W;
    out.proxy_tip_W = p.ihip_W;
    out.contact_count = p.contact_count;
    out.fault = p.fault;
    last_force_W_ = p.force_W;
    return out;
  }
  const Eigen::Vector3d end = tip + shaft_length_m_ * pose.shaft_dir_W;
  if (!started_) ray_.reset(tip, end);
  started_ = true;
  const haptics::SegmentProxyOutput r = ray_.step(objects, tip, end, dt);
  out.force_W = r.force_W;
  out.torque_W = ray_.torque_about(tip);
  out.proxy_tip_W = r.ideal_a_W;
  out.contact_count = r.contact_count;
  out.fault = r.fault || !out.torque_W.allFinite();
  return out;
}

int32_t ProbeTool::contacts(std::span<ToolContact> out) const noexcept {
  int32_t n = 0;
  if (kind_ == ToolKind::kRayProbe) {
    for (const haptics::SegmentContact& c : ray_.contacts()) {
      if (static_cast<size_t>(n) >= out.size()) break;
      ToolContact& tc = out[static_cast<size_t>(n++)];
      tc.organ = c.object;
      tc.primitive = c.primitive;
      tc.point_W = c.point_W;
      tc.force_on_organ_W = -c.force_W;
      tc.stiffness_factor = c.stiffness_factor;
    }
    return n;
  }
  // The point proxy's force is one, on the IHIP; each contact takes the share it presses along
  // its own normal (all of it for one contact).
  const std::span<const haptics::PointContact> cs = point_.contacts();
  double total = 0.0;
  for (const haptics::PointContact& c : cs) total += std::max(0.0, last_force_W_.dot(c.normal_W));
  for (const haptics::PointContact& c : cs) {
    if (static_cast<size_t>(n) >= out.size()) break;
    const double share = cs.size() == 1 ? 1.0
                         : total > 0.0  ? std::max(0.0, last_force_W_.dot(c.normal_W)) / total
                                        : 1.0 / static_cast<double>(cs.size());
    ToolContact& tc = out[static_cast<size_t>(n++)];
    tc.organ = c.object;
    tc.primitive = c.primitive;
    tc.point_W = c.point_W;
    tc.force_on_organ_W = -share * last_force_W_;
    tc.stiffness_factor = 1.0;
  }
  return n;
}

void ProbeTool::add_to_budget(std::span<const haptics::HapticObject> objects,
                              StiffnessBudget* budget) const noexcept {
  auto add = [&](int32_t object, const Eigen::Vector3d& p_W, double factor) {
    if (object < 0 || static_cast<size_t>(object) >= objects.size()) return;
    budget->add(factor * contact_stiffness_n_per_m(objects[static_cast<size_t>(object)], p_W), p_W);
  };
  if (kind_ == ToolKind::kRayProbe) {
    for (const haptics::SegmentContact& c : ray_.contacts()) {
      add(c.object, c.point_W, c.stiffness_factor);
    }
  } else {
    for (const haptics::PointContact& c : point_.contacts()) add(c.object, c.point_W, 1.0);
  }
}

}  // namespace lap::sim
