#include "sim/setup/session_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "haptics/friction.h"

namespace lap::sim {
namespace {

std::string number(double v, const char* format = "%.0f") {
  char buf[32];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

// The duct's wall stiffness across it at the middle of its top (the side away from the
// membrane, local +y: duct_fit.h), from its modes: a unit force there moves it by the static
// compliance Σ (φ_m · n)² / ω_m² (mass-normalised modes), n the outward normal.
double duct_wall_stiffness(const DuctTissue& duct) {
  if (duct.model == nullptr || duct.rest_D.empty()) return 0.0;
  double z_min = std::numeric_limits<double>::infinity();
  double z_max = -z_min;
  for (const Eigen::Vector3d& p : duct.rest_D) {
    z_min = std::min(z_min, p.z());
    z_max = std::max(z_max, p.z());
  }
  const double z_mid = 0.5 * (z_min + z_max);
  size_t top = 0;
  for (size_t v = 1; v < duct.rest_D.size(); ++v) {
    const Eigen::Vector3d& p = duct.rest_D[v];
    const Eigen::Vector3d& q = duct.rest_D[top];
    const double dz = std::abs(p.z() - z_mid) - std::abs(q.z() - z_mid);
    if (dz < -1e-9 || (dz <= 1e-9 && p.y() > q.y())) top = v;
  }
  const Eigen::Vector3d n =
      Eigen::Vector3d(duct.rest_D[top].x(), duct.rest_D[top].y(), 0.0).normalized();
  const Eigen::MatrixXd& phi = duct.model->translation_modes();
  const Eigen::VectorXd& omega = duct.model->omega();
  double compliance = 0.0;
  for (Eigen::Index m = 0; m < phi.cols(); ++m) {
    const double along_n = phi.block<3, 1>(3 * static_cast<Eigen::Index>(top), m).dot(n);
    compliance += along_n * along_n / (omega(m) * omega(m));
  }
  return compliance > 0.0 ? 1.0 / compliance : 0.0;
}

}  // namespace

Result<std::shared_ptr<const SessionModel>> SessionModel::build(
    const Scene& scene, const RuntimeSettings& settings,
    const std::array<DeviceDescription, 2>& devices) {
  std::shared_ptr<SessionModel> m(new SessionModel());
  m->settings_ = settings;
  m->scenario_file_ = scene.scenario.file.string();
  m->scenario_digest_ = scene.scenario.digest;
  m->proficiency_ = scene.scenario.proficiency;
  for (const Organ& organ : scene.organs) m->organ_names_.push_back(organ.name);
  if (Status timing = m->build_timing(); !timing.ok()) return timing.diagnostics();
  if (Status tools = m->build_tools(scene, devices); !tools.ok()) return tools.diagnostics();
  if (Status tissue = m->build_tissue(scene); !tissue.ok()) return tissue.diagnostics();
  Result<TaskModel> task = TaskModel::build(scene.scenario, *m->tissue_);
  if (!task.ok()) return task.diagnostics();
  m->task_ = std::move(task).value();
  Result<std::vector<RigidBodyOfOrgan>> bodies = build_rigid_bodies(scene);
  if (!bodies.ok()) return bodies.diagnostics();
  m->bodies_ = std::move(bodies).value();
  m->build_surfaces(scene);
  m->duct_wall_stiffness_n_per_m_ = duct_wall_stiffness(m->tissue_->duct());
  m->note_stiffness_budget(scene);
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
    tool.kind = tool_kind(it->kind);
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

namespace {
// The fastest a locally deformed organ's surface moves along its normal, giving way under a
// tool or springing back [m/s]. An estimate, chosen from the soak (docs/benchmarks.md, "Soak",
// stop 66), not measured on tissue: 2 mm a step at 200 Hz, below what the proxies' push-out undoes
// in a tick (10 mm, haptics/segment_proxy_surface_motion.cpp), and above how fast a deliberate
// press moves tissue. Without a bound a soft organ's dent came and went whole in one modelling
// step (the liver's 72 N/m reads 5 N as 69 mm, its share held at max_displacement_m's 20 mm),
// the probes following it into the organ.
constexpr double kTissueSurfaceMPerS = 0.4;
}  // namespace

Status SessionModel::build_tissue(const Scene& scene) {
  // The tissue (§6.5, §7.7): the catheter (§7.7(3)), its proximal end held where it enters;
  // the organs' and the duct's models.
  const Scenario& sc = scene.scenario;
  TissueWorldSettings ws;
  ws.local.max_move_per_step_m = kTissueSurfaceMPerS * timing_.model_dt_s;
  if (sc.catheter) {
    ws.catheter.length_m = sc.catheter->length_m;
    ws.catheter.outer_diameter_m = sc.catheter->diameter_m;
    ws.catheter.particles = sc.catheter->particles;
    ws.catheter.bending_stiffness_n_m2 = sc.catheter->bending_stiffness_n_m2;
    ws.catheter.linear_density_kg_per_m = sc.catheter->mass_kg / sc.catheter->length_m;
  }
  // Where it lies: from its own port towards its aim (the scenario's), or, for a scenario that
  // names neither, from between the tools' ports towards the target, ending 2 cm short of it.
  const Eigen::Vector3d target = scene.task_target_point();
  const TrocarSpec* port =
      sc.catheter && !sc.catheter->port.empty() ? sc.trocar(sc.catheter->port) : nullptr;
  const Eigen::Vector3d entry = port != nullptr
                                    ? port->position_m
                                    : 0.5 * (tools_[0].trocar.port_W + tools_[1].trocar.port_W);
  const Eigen::Vector3d aim = sc.catheter && sc.catheter->aim_m ? *sc.catheter->aim_m : target;
  Eigen::Vector3d dir = aim - entry;
  dir = dir.norm() > 1e-9 ? Eigen::Vector3d(dir.normalized())
                          : Eigen::Vector3d(-Eigen::Vector3d::UnitY());
  ws.catheter_direction_W = dir;
  ws.catheter_start_W =
      port != nullptr ? entry : Eigen::Vector3d(target - (ws.catheter.length_m + 0.02) * dir);
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

double SessionModel::contact_stiffness_n_per_m(int32_t organ) const {
  const haptics::HapticObject& o = objects_[static_cast<size_t>(organ)];
  double k = o.law.stiffness_n_per_m;
  if (o.friction != nullptr && o.friction->enabled()) {
    k = std::max(k, o.friction->stick_stiffness_n_per_m);
  }
  return k;
}

double SessionModel::felt_stiffness_n_per_m(int32_t organ) const {
  const double k = objects_[static_cast<size_t>(organ)].law.stiffness_n_per_m;
  switch (tissue_->organ(organ).kind) {
    case TissueKind::kLocal:
      return (1.0 - tissue_->settings().local.surface_share) * k;
    case TissueKind::kDuct:
      return duct_wall_stiffness_n_per_m_ > 0.0
                 ? 1.0 / (1.0 / k + 1.0 / duct_wall_stiffness_n_per_m_)
                 : k;
    case TissueKind::kFixed:
      break;
  }
  return k;
}

void SessionModel::note_stiffness_budget(const Scene& scene) {
  // The haptic loop keeps each tool's stiffness at the handle within its device's, tick by tick
  // (sim/runtime/trocar_tool.h, hardware/command_limiter.h): worth telling beforehand where the
  // budget will bind. Per tool: its three segments pressing each organ from the first touch on
  // (the organ's point nearest the port: the shortest lever, so the least the hand feels there),
  // holding the duct (every grasped node's spring: the held duct's own contacts are muted for
  // that tool, Session::touched_objects) and holding the catheter at
  // the task's target (its haptic-rate coupling). On the axis a spring's lever² is
  // max(1, (b/a)²).
  const TissueWorldSettings& ws = tissue_->settings();
  for (size_t side = 0; side < 2; ++side) {
    const ToolModel& tool = tools_[side];
    const TrocarToolSettings& t = tool.trocar;
    const double k_max = tool.device.limits.max_stiffness_n_per_m;
    if (!(k_max > 0.0)) continue;
    auto lever2 = [&](const Eigen::Vector3d& p) {
      const double b =
          std::clamp((p - t.port_W).norm(), t.min_inside_m, t.shaft_length_m - t.min_outside_m);
      const double ratio = b / (t.shaft_length_m - b);
      return std::max(1.0, ratio * ratio);
    };
    std::string over;
    auto item = [&](const std::string& what, const std::string& sum, double lever, double k) {
      if (k * lever <= k_max) return;
      if (!over.empty()) over += "; ";
      over += what;
      over += ": (" + sum + ") × lever² ";
      over += number(lever, "%.2f");
      over += " = " + number(k * lever);
      over += " N/m, rendered at " + number(100.0 * k_max / (k * lever));
      over += " %";
    };
    for (size_t i = 0; i < scene.organs.size(); ++i) {
      const auto organ = static_cast<int32_t>(i);
      double nearest = std::numeric_limits<double>::infinity();
      Eigen::Vector3d p = t.port_W;
      for (const Eigen::Vector3d& v : tissue_->surface(organ).positions) {
        if ((v - t.port_W).norm() < nearest) {
          nearest = (v - t.port_W).norm();
          p = v;
        }
      }
      const double k = contact_stiffness_n_per_m(organ);
      item(scene.organs[i].name + " from its first touch", "3 segments × " + number(k) + " N/m",
           lever2(p), 3.0 * k);
      if (organ == tissue_->duct_organ()) {
        const double k_grasp =
            models::DuctGraspState::kMaxNodes * ws.duct_grasp.attach_stiffness_n_per_m;
        item("holding " + scene.organs[i].name,
             std::to_string(models::DuctGraspState::kMaxNodes) + " nodes × " +
                 number(ws.duct_grasp.attach_stiffness_n_per_m) + " N/m",
             lever2(p), k_grasp);
      }
    }
    if (scene.scenario.catheter) {
      const double k = ws.catheter_grasp.coupling_stiffness_n_per_m;
      item("holding the catheter at the target", "the coupling's " + number(k) + " N/m",
           lever2(scene.task_target_point()), k);
    }
    if (!over.empty()) {
      notes_.push_back(std::string(side == 0 ? "left" : "right") + " tool: the stiffness at the " +
                       "handle is above what " + tool.device.name + " renders stably (" +
                       number(k_max) + " N/m) and is scaled down there: " + over);
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
