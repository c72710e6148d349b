#pragma once
/// \file
/// A probe tool as the haptic loop renders it (scenarios/README.md, tools[].kind): `probe`, its
/// tip alone by the point proxy (Neighborhood Watch, chapter 4), or `ray-probe`, its shaft as
/// one line segment from the tip by the ray-based proxy (chapter 5). Either renders every
/// surface property the proxy implements (force shading, friction, textures: chapter 6) and
/// moving objects (§6.4). The shaft of a point probe passes through the organs: it is the
/// thesis' point-based interaction, the condition the §5.5 experiment compares with the ray.
///
/// The step allocates nothing, takes no lock and never throws.

#include <Eigen/Core>
#include <span>

#include "haptics/haptic_object.h"
#include "haptics/laparoscopic_gripper.h"
#include "haptics/point_proxy.h"
#include "haptics/segment_proxy.h"
#include "sim/runtime/tissue_world.h"
#include "sim/runtime/trocar_tool.h"
#include "sim/setup/tool_model.h"

namespace lap::sim {

struct ProbeOutput {
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();   ///< on the tool [N]
  Eigen::Vector3d torque_W = Eigen::Vector3d::Zero();  ///< about its tip (the hinge) [N m]
  /// Where the proxy holds the tip: the IHIP (point probe), the ideal probe's tip (ray probe).
  Eigen::Vector3d proxy_tip_W = Eigen::Vector3d::Zero();
  int32_t contact_count = 0;
  bool fault = false;
};

class ProbeTool {
 public:
  /// kind: kPointProbe or kRayProbe; the ray is shaft_length_m long from the tip.
  ProbeTool(ToolKind kind, double shaft_length_m);

  /// One haptic tick against the objects, with the tool where `pose` puts it.
  ProbeOutput step(std::span<const haptics::HapticObject> objects, const haptics::GripperPose& pose,
                   double dt) noexcept;

  /// The last step's contacts as the tissue models take them (organ, primitive, point, force on
  /// the organ), at most out.size(); returns how many. A point probe touching several objects
  /// at once splits its force among them by how hard it presses along each one's normal.
  int32_t contacts(std::span<ToolContact> out) const noexcept;
  /// Adds every contact's spring to the tool's stiffness budget at the handle.
  void add_to_budget(std::span<const haptics::HapticObject> objects,
                     StiffnessBudget* budget) const noexcept;

  [[nodiscard]] ToolKind kind() const { return kind_; }
  [[nodiscard]] const haptics::PointProxy& point_proxy() const { return point_; }
  [[nodiscard]] const haptics::SegmentProxy& ray_proxy() const { return ray_; }

 private:
  ToolKind kind_;
  double shaft_length_m_;
  bool started_ = false;
  haptics::PointProxy point_;
  haptics::SegmentProxy ray_;
  Eigen::Vector3d last_force_W_ = Eigen::Vector3d::Zero();  ///< the point probe's, on the tool
};

}  // namespace lap::sim
