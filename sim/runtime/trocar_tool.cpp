#include "sim/runtime/trocar_tool.h"

#include <algorithm>
#include <cmath>

#include "haptics/friction.h"

namespace lap::sim {

ToolKinematics tool_kinematics(const TrocarToolSettings& settings,
                               const hardware::DeviceSample& sample,
                               const Eigen::Vector3d& previous_axis_W) noexcept {
  ToolKinematics k;
  const Eigen::Vector3d to_port = settings.port_W - sample.position_W;
  const double dist = to_port.norm();
  k.axis_W = dist > 1e-9 ? Eigen::Vector3d(to_port / dist) : previous_axis_W.normalized();
  // The handle stays outside and the tip inside: clamp the distance from the port.
  const double L = settings.shaft_length_m;
  k.outside_m = std::clamp(dist, settings.min_outside_m, L - settings.min_inside_m);
  k.inside_m = L - k.outside_m;
  k.handle_W = settings.port_W - k.outside_m * k.axis_W;
  k.pose.hinge_W = settings.port_W + k.inside_m * k.axis_W;
  k.pose.shaft_dir_W = -k.axis_W;
  // Roll: the device's x axis, made perpendicular to the shaft, is the opening direction.
  const Eigen::Vector3d x = sample.orientation_W.normalized() * Eigen::Vector3d::UnitX();
  Eigen::Vector3d open = x - x.dot(k.axis_W) * k.axis_W;
  if (open.norm() < 1e-6) {
    open = k.axis_W.unitOrthogonal();
  }
  k.pose.open_dir_W = open.normalized();
  k.pose.opening_rad = std::max(0.0, sample.gripper_angle_rad);
  return k;
}

hardware::DeviceCommand handle_command(const ToolKinematics& kinematics,
                                       const Eigen::Vector3d& force_tip_W,
                                       const Eigen::Vector3d& torque_tip_W,
                                       double squeeze_n) noexcept {
  const Eigen::Vector3d& u = kinematics.axis_W;
  const double a = kinematics.outside_m;
  const double b = kinematics.inside_m;
  const Eigen::Vector3d f_axial = force_tip_W.dot(u) * u;
  const Eigen::Vector3d f_perp = force_tip_W - f_axial;
  const Eigen::Vector3d t_axial = torque_tip_W.dot(u) * u;
  const Eigen::Vector3d t_perp = torque_tip_W - t_axial;
  hardware::DeviceCommand c;
  c.force_W = f_axial - (b / a) * f_perp - t_perp.cross(u) / a;
  c.torque_W = t_axial;
  c.squeeze_n = squeeze_n;
  return c;
}

double lever_gain_squared(const ToolKinematics& kinematics,
                          const Eigen::Vector3d& point_W) noexcept {
  // In the basis (u, e, w), e the point's direction off the axis, the handle force for a force
  // F at the point is F_u (u + c e) − d (F_e e + F_w w), c = ρ/a, d = (u·r)/a (handle_command()
  // with the torque r × F about the port): the block [[1, 0], [c, −d]] and −d. The largest
  // eigenvalue of the block's AᵀA = [[1 + c², −c d], [−c d, d²]] is at least d², so it is g².
  const Eigen::Vector3d& u = kinematics.axis_W;
  const double a = kinematics.outside_m;
  const Eigen::Vector3d port_W = kinematics.pose.hinge_W - kinematics.inside_m * u;
  const Eigen::Vector3d r = point_W - port_W;
  const double along = r.dot(u);
  const double d = along / a;
  const double c = (r - along * u).norm() / a;
  const double trace = 1.0 + c * c + d * d;
  return 0.5 * (trace + std::sqrt(std::max(0.0, trace * trace - 4.0 * d * d)));
}

double contact_stiffness_n_per_m(const haptics::HapticObject& object,
                                 const Eigen::Vector3d& point_W) noexcept {
  double k = object.law.stiffness_n_per_m;
  if (object.friction != nullptr && object.friction->enabled()) {
    const double factor = object.friction->map.factor(object.pose_WO.inverse() * point_W);
    k = std::max(k, factor * object.friction->stick_stiffness_n_per_m);
  }
  return k;
}

void StiffnessBudget::add(double stiffness_n_per_m, const Eigen::Vector3d& point_W) noexcept {
  if (!(stiffness_n_per_m > 0.0)) return;
  total_n_per_m_ += stiffness_n_per_m * lever_gain_squared(kinematics_, point_W);
}

void StiffnessBudget::add_contacts(const haptics::LaparoscopicGripper& gripper,
                                   std::span<const haptics::HapticObject> objects) noexcept {
  for (int seg = 0; seg < 3; ++seg) {
    for (const haptics::SegmentContact& c : gripper.proxy(seg).contacts()) {
      if (c.object < 0 || static_cast<size_t>(c.object) >= objects.size()) continue;
      add(c.stiffness_factor *
              contact_stiffness_n_per_m(objects[static_cast<size_t>(c.object)], c.point_W),
          c.point_W);
    }
  }
}

}  // namespace lap::sim
