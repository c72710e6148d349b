#include "sim/setup/task_model.h"

#include <algorithm>
#include <cmath>

namespace lap::sim {
namespace {

// The duct's lumen and its incision, as the tissue model measured them (its rim's hold uses
// the same hole), and the incision's "at" distance: half its larger side and 2 mm.
void place_duct(const DuctTissue& duct, const IncisionSpec& incision, TaskModel* m) {
  const models::IncisionRim& rim = duct.rim;
  m->pose_DW = rim.pose_DW;
  m->duct_length_m = rim.length_m;
  m->lumen_radius_m = rim.mid_radius_m;
  if (!duct.has_incision) return;
  m->has_incision = true;
  m->incision_center_W = duct.incision_center_W;
  m->incision_z_m = rim.z_m;
  m->incision_angle_rad = rim.angle_rad;
  m->incision_half_length_m = rim.half_length_m;
  m->incision_half_width_m = rim.half_width_m;
  m->at_incision_m = 0.5 * std::max(incision.length_m, incision.width_m) + 0.002;
}

}  // namespace

Result<TaskModel> TaskModel::build(const Scenario& scenario, const TissueModel& tissue) {
  TaskModel m;
  m.organ_count = tissue.organ_count();
  m.forbidden.assign(static_cast<size_t>(m.organ_count), 0);
  m.picture = CameraPicture::of(scenario.camera);
  if (!scenario.task) return m;
  const TaskSpec& spec = *scenario.task;
  m.spec = spec;
  m.kind =
      spec.kind == "free-exploration" ? TaskKind::kFreeExploration : TaskKind::kCatheterInsertion;
  auto problem = [&](const std::string& field, const std::string& what) {
    return Diagnostic{scenario.file.string(), spec.line, field, what};
  };
  int32_t target = -1;
  for (size_t i = 0; i < scenario.organs.size(); ++i) {
    const std::string& name = scenario.organs[i].name;
    if (name == spec.target) target = static_cast<int32_t>(i);
    if (!spec.common_bile_duct.empty() && name == spec.common_bile_duct) {
      m.cbd_organ = static_cast<int32_t>(i);
    }
    if (std::find(spec.forbidden_organs.begin(), spec.forbidden_organs.end(), name) !=
            spec.forbidden_organs.end() &&
        i < m.forbidden.size()) {
      m.forbidden[i] = 1;
    }
  }
  const int32_t duct = tissue.duct_organ();
  if (m.kind == TaskKind::kCatheterInsertion && (target < 0 || target != duct)) {
    return problem("task.target", "'" + spec.target +
                                      "' is not a modal-shell duct (the catheter is inserted "
                                      "into its lumen): expected the organ with model: "
                                      "modal-shell");
  }
  if (target >= 0 && target != duct) return m;  // free exploration of a solid organ: no duct
  if (duct < 0) return m;
  m.duct_organ = duct;
  const IncisionSpec& incision = scenario.organs[static_cast<size_t>(duct)].incision;
  place_duct(tissue.duct(), incision, &m);
  if (!incision.present && m.kind == TaskKind::kCatheterInsertion) {
    return problem("task.target", "the duct '" + spec.target +
                                      "' has no incision to insert the catheter by: expected "
                                      "an incision on it (organs[].incision)");
  }
  return m;
}

}  // namespace lap::sim
