#include "hardware/mouse_nudge.h"

namespace lap::hardware {

ToolNudge mouse_drag_nudge(double dx_px, double dy_px, const Eigen::Vector3d& right_W,
                           const Eigen::Vector3d& up_W) {
  ToolNudge n;
  n.delta_W = kMouseMetresPerPixel * (dx_px * right_W - dy_px * up_W);
  return n;
}

ToolNudge mouse_wheel_nudge(double notches, const Eigen::Vector3d& view_dir_W, bool fine) {
  ToolNudge n;
  n.delta_W = (fine ? kKeyFineFraction : 1.0) * kMouseWheelMetresPerNotch * notches * view_dir_W;
  return n;
}

ToolNudge mouse_roll_nudge(double dx_px) {
  ToolNudge n;
  n.roll_rad = kMouseRollRadPerPixel * dx_px;
  return n;
}

ToolNudge mouse_jaws_nudge(double dy_px) {
  ToolNudge n;
  n.opening_rad = -kMouseJawsRadPerPixel * dy_px;
  return n;
}

}  // namespace lap::hardware
