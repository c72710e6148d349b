#pragma once
/// \file
/// The fixed part of the task engine (thesis §7.4: the catheter guided through the ductotomy into
/// the cystic duct and held there), built once from the scenario's `task` and the tissue's
/// model: which organ is the duct and where its lumen is (the modal shell's rest frame, length
/// and mid-surface radius), where the incision is on its wall, which organs must not be
/// touched, the laparoscope's view cone, and the thresholds. The engine's state and its step
/// are in sim/runtime/task_engine.h; the modelling loop reads this `const`.
///
/// "In the lumen" is measured on the duct at rest: inside the mid-surface's cylinder and between
/// its ends. The duct's wall moves by fractions of a millimetre under the tools (its modes), so
/// the rest geometry is the lumen to within that.

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"
#include "sim/setup/scenario.h"
#include "sim/setup/tissue_model.h"

namespace lap::sim {

enum class TaskKind : uint8_t {
  kNone,               ///< the scenario has no task: nothing is watched
  kCatheterInsertion,  ///< goals and every error
  kFreeExploration,    ///< no goal, no time limit: injuries, out of view, forbidden touches
};

struct TaskModel {
  TaskKind kind = TaskKind::kNone;
  TaskSpec spec;  ///< the thresholds as the scenario gives them
  int32_t organ_count = 0;

  // The duct (the task's target, else the scene's modal-shell organ; -1: none).
  int32_t duct_organ = -1;
  Eigen::Isometry3d pose_DW = Eigen::Isometry3d::Identity();  ///< world to duct frame (z: axis)
  double duct_length_m = 0.0;                                 ///< along z from 0
  double lumen_radius_m = 0.0;  ///< the wall's mid-surface radius about the axis at rest

  // The incision on the duct's wall (duct frame), an ellipse as duct_incision.h cuts it; its
  // half axes include a margin of one face of the wall's mesh and the catheter's radius, since
  // the hole the catheter passes is the union of the faces whose centres lie in the ellipse.
  bool has_incision = false;
  Eigen::Vector3d incision_center_W = Eigen::Vector3d::Zero();
  double incision_z_m = 0.0;
  double incision_angle_rad = 0.0;      ///< about the axis
  double incision_half_length_m = 0.0;  ///< along the axis, with the margin
  double incision_half_width_m = 0.0;   ///< around it (arc length at lumen_radius_m), with margin
  /// The tip within this of the incision's centre is "at the incision": half the incision's
  /// larger size and 2 mm (estimate: within reach of entering it).
  double at_incision_m = 0.0;

  std::vector<uint8_t> forbidden;  ///< per organ: 1 where the tools must not touch it
  /// The common bile duct (the scenario's task.common_bile_duct; -1: none): the catheter's tip
  /// inside it (a closed mesh, at rest) is an error.
  int32_t cbd_organ = -1;

  // The laparoscope's picture at the scenario's camera: the frustum of its vertical view angle
  // and the operative field's 16:9 aspect (HD laparoscopy monitors; the window's field is drawn
  // at that aspect), so that a tip seen anywhere in the picture is in view. Before, a cone of
  // half the vertical angle called tips at the picture's sides out of view (the hardest
  // patient's keyboard tools, 10 cm into their ports, failed at 3 s).
  static constexpr double kPictureAspect = 16.0 / 9.0;
  Eigen::Vector3d camera_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d view_dir_W = -Eigen::Vector3d::UnitZ();
  Eigen::Vector3d view_up_W = Eigen::Vector3d::UnitY();     ///< unit, ⊥ view_dir_W
  Eigen::Vector3d view_right_W = Eigen::Vector3d::UnitX();  ///< unit, view_dir_W × view_up_W
  double cos_half_view = 0.0;  ///< half the vertical angle (the cone, when tan_half_* are 0)
  double tan_half_vertical = 0.0;
  double tan_half_horizontal = 0.0;
  /// `tip_W` within the laparoscope's picture.
  [[nodiscard]] bool in_view(const Eigen::Vector3d& tip_W) const {
    const Eigen::Vector3d v = tip_W - camera_W;
    const double depth = v.dot(view_dir_W);
    if (tan_half_vertical <= 0.0) return depth >= cos_half_view * v.norm();
    return depth > 0.0 && std::abs(v.dot(view_up_W)) <= depth * tan_half_vertical &&
           std::abs(v.dot(view_right_W)) <= depth * tan_half_horizontal;
  }

  /// From the scenario and the tissue's model (the duct's shell and incision faces).
  /// Diagnostics name the scenario's file and line (task) and the field.
  static Result<TaskModel> build(const Scenario& scenario, const TissueModel& tissue);
};

}  // namespace lap::sim
