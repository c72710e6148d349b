#include "haptics/laparoscopic_gripper.h"

#include <algorithm>
#include <cmath>

namespace lap::haptics {

LaparoscopicGripper::LaparoscopicGripper(const GripperGeometry& geometry,
                                         const SegmentProxySettings& settings)
    : geometry_(geometry),
      proxies_{SegmentProxy(settings), SegmentProxy(settings), SegmentProxy(settings)} {}

void LaparoscopicGripper::segments(const GripperPose& pose, std::array<Eigen::Vector3d, 3>* a,
                                   std::array<Eigen::Vector3d, 3>* b) const {
  const double half = 0.5 * pose.opening_rad;
  (*a)[0] = pose.hinge_W;
  (*b)[0] = pose.hinge_W + geometry_.shaft_length_m * pose.shaft_dir_W;
  for (int j = 0; j < 2; ++j) {
    const double side = j == 0 ? 1.0 : -1.0;
    const Eigen::Vector3d dir =
        -std::cos(half) * pose.shaft_dir_W + side * std::sin(half) * pose.open_dir_W;
    (*a)[1 + j] = pose.hinge_W + geometry_.jaw_length_m * dir;
    (*b)[1 + j] = pose.hinge_W;
  }
}

void LaparoscopicGripper::reset(const GripperPose& pose) {
  std::array<Eigen::Vector3d, 3> a;
  std::array<Eigen::Vector3d, 3> b;
  segments(pose, &a, &b);
  for (int i = 0; i < 3; ++i) proxies_[i].reset(a[i], b[i]);
}

GripperOutput LaparoscopicGripper::step(std::span<const HapticObject> objects,
                                        const GripperPose& pose, double dt) noexcept {
  GripperOutput out;
  std::array<Eigen::Vector3d, 3> a;
  std::array<Eigen::Vector3d, 3> b;
  segments(pose, &a, &b);
  double squeeze = 0.0;
  for (int i = 0; i < 3; ++i) {
    out.segments[i] = proxies_[i].step(objects, a[i], b[i], dt);
    out.fault = out.fault || out.segments[i].fault;
    out.force_W += out.segments[i].force_W;
    out.torque_W += proxies_[i].torque_about(pose.hinge_W);
    if (i > 0) {
      // The closing direction of jaw i: perpendicular to it, in the jaws' plane, towards the
      // other jaw. A contact force against it resists the squeeze.
      const Eigen::Vector3d jaw = (a[i] - b[i]).normalized();
      const double side = i == 1 ? 1.0 : -1.0;
      Eigen::Vector3d closing = -side * pose.open_dir_W;
      closing -= closing.dot(jaw) * jaw;
      if (closing.norm() > 0.0) closing.normalize();
      squeeze += std::max(0.0, -out.segments[i].force_W.dot(closing));
    }
  }
  out.squeeze_n = 0.5 * squeeze;
  if (out.fault || !out.force_W.allFinite() || !out.torque_W.allFinite()) {
    GripperOutput bad;
    bad.fault = true;
    return bad;
  }
  return out;
}

}  // namespace lap::haptics
