#include "hardware/tool_nudge.h"

#include <algorithm>
#include <cmath>

namespace lap::hardware {

ToolNudge key_nudge(ToolKey key, bool fine) {
  ToolNudge n;
  switch (key) {
    case ToolKey::kXMinus:
      n.delta_W.x() = -kKeyStepM;
      break;
    case ToolKey::kXPlus:
      n.delta_W.x() = kKeyStepM;
      break;
    case ToolKey::kYPlus:
      n.delta_W.y() = kKeyStepM;
      break;
    case ToolKey::kYMinus:
      n.delta_W.y() = -kKeyStepM;
      break;
    case ToolKey::kZMinus:
      n.delta_W.z() = -kKeyStepM;
      break;
    case ToolKey::kZPlus:
      n.delta_W.z() = kKeyStepM;
      break;
    case ToolKey::kClose:
      n.opening_rad = -kKeyOpeningRad;
      break;
    case ToolKey::kOpen:
      n.opening_rad = kKeyOpeningRad;
      break;
    case ToolKey::kRollMinus:
      n.roll_rad = -kKeyRollRad;
      break;
    case ToolKey::kRollPlus:
      n.roll_rad = kKeyRollRad;
      break;
  }
  if (fine) {
    n.delta_W *= kKeyFineFraction;
    n.opening_rad *= kKeyFineFraction;
    n.roll_rad *= kKeyFineFraction;
  }
  return n;
}

SimulatedInput nudged(const SimulatedInput& in, const ToolNudge& n,
                      const Eigen::AlignedBox3d& workspace_W,
                      const std::optional<Eigen::Vector3d>& port_W) {
  SimulatedInput out = in;
  if (n.delta_W.allFinite()) {
    out.position_W =
        (in.position_W + n.delta_W).cwiseMax(workspace_W.min()).cwiseMin(workspace_W.max());
  }
  if (std::isfinite(n.opening_rad)) {
    out.gripper_angle_rad = std::clamp(in.gripper_angle_rad + n.opening_rad, 0.0, 1.0);
  }
  if (n.roll_rad == 0.0 || !std::isfinite(n.roll_rad)) return out;
  Eigen::Vector3d axis = out.orientation_W * Eigen::Vector3d::UnitZ();
  if (port_W) {
    const Eigen::Vector3d to_port = *port_W - out.position_W;
    if (to_port.norm() < 1e-9) return out;  // the handle at the port: no shaft to turn about
    axis = to_port;
  }
  out.orientation_W =
      (Eigen::AngleAxisd(n.roll_rad, axis.normalized()) * out.orientation_W).normalized();
  return out;
}

}  // namespace lap::hardware
