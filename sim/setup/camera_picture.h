#pragma once
/// \file
/// The laparoscope's picture at the scenario's camera, as the task judges "in view": the frustum
/// of its vertical view angle and the operative field's 16:9 aspect (HD laparoscopy monitors;
/// the window's field is drawn at that aspect), so that a tip seen anywhere in the picture is in
/// view. Before, a cone of half the vertical angle called tips at the picture's sides out of
/// view. The task model (sim/setup/task_model.h) and the simulated tools' home pose
/// (sim/setup/device_factory.h) both use it.

#include <Eigen/Core>
#include <cmath>

#include "sim/setup/scenario.h"

namespace lap::sim {

struct CameraPicture {
  static constexpr double kAspect = 16.0 / 9.0;
  Eigen::Vector3d camera_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d view_dir_W = -Eigen::Vector3d::UnitZ();
  Eigen::Vector3d view_up_W = Eigen::Vector3d::UnitY();     ///< unit, ⊥ view_dir_W
  Eigen::Vector3d view_right_W = Eigen::Vector3d::UnitX();  ///< unit, view_dir_W × view_up_W
  double cos_half_view = 0.0;  ///< half the vertical angle (the cone, when tan_half_* are 0)
  double tan_half_vertical = 0.0;
  double tan_half_horizontal = 0.0;

  /// The picture of the scenario's camera (a view_up along the line of sight leaves the cone).
  [[nodiscard]] static CameraPicture of(const CameraSpec& camera);

  /// `p_W` within the picture.
  [[nodiscard]] bool contains(const Eigen::Vector3d& p_W) const {
    const Eigen::Vector3d v = p_W - camera_W;
    const double depth = v.dot(view_dir_W);
    if (tan_half_vertical <= 0.0) return depth >= cos_half_view * v.norm();
    return depth > 0.0 && std::abs(v.dot(view_up_W)) <= depth * tan_half_vertical &&
           std::abs(v.dot(view_right_W)) <= depth * tan_half_horizontal;
  }
};

}  // namespace lap::sim
