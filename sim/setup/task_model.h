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
#include "sim/setup/camera_picture.h"
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

  /// The laparoscope's picture at the scenario's camera (sim/setup/camera_picture.h).
  CameraPicture picture;
  /// `tip_W` within the laparoscope's picture.
  [[nodiscard]] bool in_view(const Eigen::Vector3d& tip_W) const { return picture.contains(tip_W); }

  /// From the scenario and the tissue's model (the duct's shell and incision faces).
  /// Diagnostics name the scenario's file and line (task) and the field.
  static Result<TaskModel> build(const Scenario& scenario, const TissueModel& tissue);
};

}  // namespace lap::sim
