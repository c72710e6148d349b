#pragma once
/// \file
/// A tool as a session's model holds it (thesis §7.2, §7.5): the port its shaft passes through,
/// its gripper's geometry, and its device's name and limits. Fixed after set-up; the tool's
/// kinematics through the port run in the haptic loop (sim/runtime/trocar_tool.h).

#include <Eigen/Geometry>
#include <cstdint>
#include <string>

#include "haptics/laparoscopic_gripper.h"
#include "hardware/haptic_device.h"

namespace lap::sim {

/// The port and the shaft: where the tool pivots and how far it may go in and out.
struct TrocarToolSettings {
  Eigen::Vector3d port_W = Eigen::Vector3d::Zero();
  double shaft_length_m = 0.36;  ///< handle to tip (hinge)
  double min_inside_m = 0.01;    ///< the tip stays at least this far in (it cannot leave the port)
  double min_outside_m = 0.03;   ///< the handle stays at least this far out
};

/// What the session's model needs of a tool's device.
struct DeviceDescription {
  std::string name;
  hardware::DeviceLimits limits;
};
[[nodiscard]] inline DeviceDescription describe(const hardware::HapticDevice& device) {
  return {std::string(device.name()), device.limits()};
}

/// What the haptic loop renders of a tool (scenarios/README.md, tools[].kind).
enum class ToolKind : uint8_t {
  kGripper,     ///< shaft and two jaws, three segment proxies (§7.6.2)
  kPointProbe,  ///< the tip alone, the point proxy (Neighborhood Watch, chapter 4)
  kRayProbe,    ///< the shaft as one line segment, the ray-based proxy (chapter 5)
};
/// The kind a scenario's tools[].kind names: probe, ray-probe, or a gripper.
[[nodiscard]] inline ToolKind tool_kind(const std::string& scenario_kind) {
  if (scenario_kind == "probe") return ToolKind::kPointProbe;
  if (scenario_kind == "ray-probe") return ToolKind::kRayProbe;
  return ToolKind::kGripper;
}

/// One tool, fixed for the session.
struct ToolModel {
  ToolKind kind = ToolKind::kGripper;
  TrocarToolSettings trocar;
  haptics::GripperGeometry gripper;
  DeviceDescription device;
  Eigen::Vector3d initial_axis_W = Eigen::Vector3d::UnitY();  ///< port to scene centre, unit
};

}  // namespace lap::sim
