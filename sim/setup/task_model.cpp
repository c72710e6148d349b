#include "sim/setup/task_model.h"

#include <algorithm>
#include <cmath>

namespace lap::sim {
namespace {

// The incision in the duct's frame, its half axes widened by the largest edge of an open face
// and the catheter's radius (the hole the catheter's contacts pass, duct_incision.h).
void place_incision(const OrganTissue& wall, const IncisionSpec& incision, double catheter_radius_m,
                    TaskModel* m) {
  const Eigen::Vector3d c = m->pose_DW * incision.center_m;
  m->has_incision = true;
  m->incision_center_W = incision.center_m;
  m->incision_z_m = c.z();
  m->incision_angle_rad = std::atan2(c.y(), c.x());
  double edge = 0.0;
  for (size_t f = 0; f < wall.open_faces.size() && f < wall.surface.triangles.size(); ++f) {
    if (wall.open_faces[f] == 0) continue;
    const auto& t = wall.surface.triangles[f];
    for (size_t k = 0; k < 3; ++k) {
      const Eigen::Vector3d& a = wall.surface.positions[static_cast<size_t>(t[k])];
      const Eigen::Vector3d& b = wall.surface.positions[static_cast<size_t>(t[(k + 1) % 3])];
      edge = std::max(edge, (a - b).norm());
    }
  }
  const double margin = edge + catheter_radius_m;
  m->incision_half_length_m = 0.5 * incision.length_m + margin;
  m->incision_half_width_m = 0.5 * incision.width_m + margin;
  m->at_incision_m = 0.5 * std::max(incision.length_m, incision.width_m) + 0.002;
}

// The duct's lumen from its shell at rest: its frame, length and mid-surface radius.
void place_duct(const DuctTissue& duct, TaskModel* m) {
  m->pose_DW = duct.pose_WD.inverse();
  double length = 0.0;
  double radius = 0.0;
  for (const Eigen::Vector3d& p : duct.rest_D) {
    length = std::max(length, p.z());
    radius += p.head<2>().norm();
  }
  m->duct_length_m = length;
  m->lumen_radius_m = duct.rest_D.empty() ? 0.0 : radius / static_cast<double>(duct.rest_D.size());
}

}  // namespace

Result<TaskModel> TaskModel::build(const Scenario& scenario, const TissueModel& tissue) {
  TaskModel m;
  m.organ_count = tissue.organ_count();
  m.forbidden.assign(static_cast<size_t>(m.organ_count), 0);
  const CameraSpec& cam = scenario.camera;
  m.camera_W = cam.position_m;
  m.view_dir_W = (cam.focal_point_m - cam.position_m).normalized();
  m.cos_half_view = std::cos(0.5 * cam.view_angle_deg * M_PI / 180.0);
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
  place_duct(tissue.duct(), &m);
  const IncisionSpec& incision = scenario.organs[static_cast<size_t>(duct)].incision;
  if (incision.present) {
    place_incision(tissue.organ(duct), incision, tissue.catheter_model().radius_m(), &m);
  } else if (m.kind == TaskKind::kCatheterInsertion) {
    return problem("task.target", "the duct '" + spec.target +
                                      "' has no incision to insert the catheter by: expected "
                                      "an incision on it (organs[].incision)");
  }
  return m;
}

}  // namespace lap::sim
