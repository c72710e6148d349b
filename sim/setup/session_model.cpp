#include "sim/setup/session_model.h"

#include <algorithm>
#include <cmath>

namespace lap::sim {

Result<std::shared_ptr<const SessionModel>> SessionModel::build(
    const Scene& scene, const RuntimeSettings& settings,
    const std::array<DeviceDescription, 2>& devices) {
  std::shared_ptr<SessionModel> m(new SessionModel());
  m->settings_ = settings;
  m->scenario_file_ = scene.scenario.file.string();
  for (const Organ& organ : scene.organs) m->organ_names_.push_back(organ.name);
  if (Status timing = m->build_timing(); !timing.ok()) return timing.diagnostics();
  if (Status tools = m->build_tools(scene, devices); !tools.ok()) return tools.diagnostics();
  if (Status tissue = m->build_tissue(scene); !tissue.ok()) return tissue.diagnostics();
  m->build_surfaces(scene);
  m->note_stiff_tissue(scene);
  return std::shared_ptr<const SessionModel>(std::move(m));
}

Status SessionModel::build_timing() {
  const RuntimeSettings& s = settings_;
  if (!(s.haptic_rate_hz > 0.0) || !(s.model_rate_hz > 0.0) || s.model_rate_hz > s.haptic_rate_hz) {
    return diagnostic("rates: expected 0 < model rate <= haptic rate");
  }
  if (!(s.duration_s > 0.0) || !std::isfinite(s.duration_s)) {
    return diagnostic("duration: expected a positive number of seconds");
  }
  timing_.dt_s = 1.0 / s.haptic_rate_hz;
  timing_.ticks_per_model = std::max<int64_t>(1, std::llround(s.haptic_rate_hz / s.model_rate_hz));
  timing_.model_dt_s = timing_.dt_s * static_cast<double>(timing_.ticks_per_model);
  timing_.max_ticks = std::llround(s.duration_s * s.haptic_rate_hz);
  timing_.recorded_ticks =
      s.record_s < 0.0
          ? timing_.max_ticks
          : std::min<int64_t>(timing_.max_ticks, std::llround(s.record_s * s.haptic_rate_hz));
  return {};
}

Status SessionModel::build_tools(const Scene& scene,
                                 const std::array<DeviceDescription, 2>& devices) {
  // The tools: left and right, each at its trocar, pointing from the port at the scene's centre.
  const Scenario& sc = scene.scenario;
  for (int side = 0; side < 2; ++side) {
    const ToolSpec* it = sc.tool(side == 0 ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight);
    if (it == nullptr) {
      return diagnostic(sc.file.string() + ": tools: expected a " + (side == 0 ? "left" : "right") +
                        " tool");
    }
    const TrocarSpec* port = sc.trocar(it->trocar);
    if (port == nullptr) {
      return diagnostic(sc.file.string() + ": tools: " + it->name + ": trocar '" + it->trocar +
                        "' is not among the trocars");
    }
    ToolModel& tool = tools_[static_cast<size_t>(side)];
    tool.trocar.port_W = port->position_m;
    tool.trocar.shaft_length_m = it->shaft_length_m;
    tool.gripper.jaw_length_m = it->jaw_length_m;
    tool.gripper.shaft_length_m = it->shaft_length_m;
    tool.device = devices[static_cast<size_t>(side)];
    const Eigen::Vector3d centre = scene.bounds().center();
    if ((centre - tool.trocar.port_W).norm() > 1e-9) {
      tool.initial_axis_W = (centre - tool.trocar.port_W).normalized();
    }
  }
  return {};
}

Status SessionModel::build_tissue(const Scene& scene) {
  // The tissue (§6.5, §7.7): the catheter (§7.7(3)), its proximal end held where it enters,
  // between the two ports, pointing at the task's target and ending 2 cm short of its centre;
  // the organs' and the duct's models.
  const Scenario& sc = scene.scenario;
  TissueWorldSettings ws;
  if (sc.catheter) {
    ws.catheter.length_m = sc.catheter->length_m;
    ws.catheter.outer_diameter_m = sc.catheter->diameter_m;
    ws.catheter.particles = sc.catheter->particles;
    ws.catheter.bending_stiffness_n_m2 = sc.catheter->bending_stiffness_n_m2;
    ws.catheter.linear_density_kg_per_m = sc.catheter->mass_kg / sc.catheter->length_m;
  }
  const Eigen::Vector3d target = scene.task_target_point();
  const Eigen::Vector3d entry = 0.5 * (tools_[0].trocar.port_W + tools_[1].trocar.port_W);
  Eigen::Vector3d dir = target - entry;
  dir = dir.norm() > 1e-9 ? Eigen::Vector3d(dir.normalized())
                          : Eigen::Vector3d(-Eigen::Vector3d::UnitY());
  ws.catheter_direction_W = dir;
  ws.catheter_start_W = target - (ws.catheter.length_m + 0.02) * dir;
  Result<std::shared_ptr<const TissueModel>> tissue = TissueModel::build(scene, ws, &notes_);
  if (!tissue.ok()) {
    // The same words as before the model existed: `file: organ: problem`.
    std::vector<Diagnostic> d = tissue.diagnostics();
    for (Diagnostic& x : d) {
      if (x.file.empty()) x.file = sc.file.string();
    }
    return d;
  }
  tissue_ = std::move(tissue).value();
  return {};
}

void SessionModel::build_surfaces(const Scene& scene) {
  // The proxies' databases at rest: the surfaces the tissue deforms (the duct: its shell); each
  // session's surfaces start as copies of them (sim/runtime/haptic_surfaces.h).
  for (size_t i = 0; i < scene.organs.size(); ++i) {
    auto db = std::make_unique<haptics::MeshDatabase>(
        haptics::MeshDatabase::build(tissue_->surface(static_cast<int32_t>(i))));
    // The duct's open shell is touched from inside its lumen and from outside.
    haptics::SegmentDatabaseSettings segment_settings;
    segment_settings.two_sided = tissue_->two_sided(static_cast<int32_t>(i));
    segment_databases_.push_back(std::make_unique<haptics::SegmentDatabase>(
        haptics::SegmentDatabase::build(*db, segment_settings)));
    surfaces_.push_back(build_organ_surface(scene.organs[i], *db));
    databases_.push_back(std::move(db));
    haptics::HapticObject o;
    o.two_sided = tissue_->two_sided(static_cast<int32_t>(i));
    surfaces_.back().apply(scene.organs[i].material, &o);
    objects_.push_back(o);
  }
}

void SessionModel::note_stiff_tissue(const Scene& scene) {
  // A tissue stiffer than a device renders stably is worth saying before the session starts.
  for (size_t i = 0; i < scene.organs.size(); ++i) {
    for (const ToolModel& tool : tools_) {
      const double k = objects_[i].law.stiffness_n_per_m;
      const double k_max = tool.device.limits.max_stiffness_n_per_m;
      if (k > k_max) {
        notes_.push_back(scene.organs[i].name + ": stiffness " + std::to_string(k) +
                         " N/m is above what " + tool.device.name + " renders stably (" +
                         std::to_string(k_max) + " N/m); expect buzzing");
      }
    }
  }
}

std::vector<const haptics::MeshDatabase*> SessionModel::rest_databases() const {
  std::vector<const haptics::MeshDatabase*> v;
  for (const auto& d : databases_) v.push_back(d.get());
  return v;
}

std::vector<const haptics::SegmentDatabase*> SessionModel::rest_segment_databases() const {
  std::vector<const haptics::SegmentDatabase*> v;
  for (const auto& d : segment_databases_) v.push_back(d.get());
  return v;
}

std::vector<const haptics::ShadingNormals*> SessionModel::rest_shading() const {
  std::vector<const haptics::ShadingNormals*> v;
  for (const OrganSurface& s : surfaces_) v.push_back(s.shading.get());
  return v;
}

}  // namespace lap::sim
