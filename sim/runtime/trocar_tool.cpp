#include "sim/runtime/trocar_tool.h"

#include <algorithm>
#include <cmath>

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

}  // namespace lap::sim
