#include "sim/setup/camera_picture.h"

#include <cmath>

namespace lap::sim {

CameraPicture CameraPicture::of(const CameraSpec& cam) {
  CameraPicture p;
  p.camera_W = cam.position_m;
  p.view_dir_W = (cam.focal_point_m - cam.position_m).normalized();
  p.cos_half_view = std::cos(0.5 * cam.view_angle_deg * M_PI / 180.0);
  // The picture's up: the scenario's view_up made square to the line of sight.
  const Eigen::Vector3d up = cam.view_up - cam.view_up.dot(p.view_dir_W) * p.view_dir_W;
  if (up.norm() > 1e-9 && p.view_dir_W.allFinite()) {
    p.view_up_W = up.normalized();
    p.view_right_W = p.view_dir_W.cross(p.view_up_W);
    p.tan_half_vertical = std::tan(0.5 * cam.view_angle_deg * M_PI / 180.0);
    p.tan_half_horizontal = kAspect * p.tan_half_vertical;
  }
  return p;
}

}  // namespace lap::sim
