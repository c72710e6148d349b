#include "sim/setup/tissue_model.h"

#include <algorithm>
#include <cmath>
#include <exception>

#include "sim/setup/duct_fit.h"
#include "sim/setup/duct_incision.h"
#include "sim/setup/modal_shell_cache.h"

namespace lap::sim {
namespace {

// Texture coordinates for drawing the duct's shell with its organ's colour texture (the shell
// replaces the file's mesh, and its uvs with it): in the duct's frame (z its axis), u the angle
// round the axis mirrored about the x axis (0 to 1 over half a turn, so no seam where u would
// jump from 1 back to 0), v along the axis in the same arc length per unit.
void add_duct_texture_coordinates(haptics::TriangleMesh* surface) {
  double radius = 0.0;
  for (const Eigen::Vector3d& p : surface->positions) radius += p.head<2>().norm();
  radius /= std::max<double>(1.0, static_cast<double>(surface->positions.size()));
  const double v_per_m = 1.0 / std::max(M_PI * radius, 1e-6);
  surface->uvs.clear();
  surface->uvs.reserve(surface->positions.size());
  for (const Eigen::Vector3d& p : surface->positions) {
    surface->uvs.emplace_back(std::abs(std::atan2(p.y(), p.x())) / M_PI, p.z() * v_per_m);
  }
}

// The duct's lumen from its shell at rest (its length, the mid-surface's mean radius) and the
// incision in its frame, half axes widened by the largest edge of an open face and the
// catheter's radius: the hole the catheter's contacts let it through (duct_incision.h).
void measure_lumen(const OrganTissue& wall, const IncisionSpec& incision, double catheter_radius_m,
                   DuctTissue* duct) {
  models::IncisionRim& rim = duct->rim;
  rim.pose_DW = duct->pose_WD.inverse();
  double radius = 0.0;
  for (const Eigen::Vector3d& p : duct->rest_D) {
    rim.length_m = std::max(rim.length_m, p.z());
    radius += p.head<2>().norm();
  }
  rim.mid_radius_m = duct->rest_D.empty() ? 0.0 : radius / static_cast<double>(duct->rest_D.size());
  if (!incision.present) return;
  const Eigen::Vector3d c = rim.pose_DW * incision.center_m;
  duct->has_incision = true;
  duct->incision_center_W = incision.center_m;
  rim.z_m = c.z();
  rim.angle_rad = std::atan2(c.y(), c.x());
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
  rim.half_length_m = 0.5 * incision.length_m + margin;
  rim.half_width_m = 0.5 * incision.width_m + margin;
}

}  // namespace

Result<std::shared_ptr<const TissueModel>> TissueModel::build(const Scene& scene,
                                                              const TissueWorldSettings& settings,
                                                              std::vector<std::string>* notes) {
  std::shared_ptr<TissueModel> m(new TissueModel());
  m->settings_ = settings;
  try {
    m->catheter_model_ =
        std::make_unique<models::CatheterModel>(models::CatheterModel::build(settings.catheter));
  } catch (const std::exception& e) {
    return Diagnostic{scene.scenario.file.string(), 0, "catheter", e.what()};
  }
  for (size_t i = 0; i < scene.organs.size(); ++i) {
    Status added = m->add_organ(scene.organs[i], static_cast<int32_t>(i), notes);
    if (!added.ok()) {
      std::vector<Diagnostic> d = std::move(added).diagnostics();
      for (Diagnostic& one : d) {
        if (one.file.empty() && one.line > 0) one.file = scene.scenario.file.string();
      }
      return d;
    }
  }
  return std::shared_ptr<const TissueModel>(std::move(m));
}

Status TissueModel::add_organ(const Organ& organ, int32_t index, std::vector<std::string>* notes) {
  OrganTissue t;
  t.stiffness_n_per_m = organ.material.stiffness_n_per_m;
  t.contact.clearance_m = catheter_model_->radius_m();
  t.contact.stiffness_n_per_m = organ.material.stiffness_n_per_m;
  t.contact.damping_n_s_per_m = organ.material.damping_n_s_per_m;
  t.contact.friction_coefficient = organ.material.catheter_friction;
  auto problem = [&](const std::string& what) { return Diagnostic{"", 0, organ.name, what}; };
  try {
    if (organ.model == models::ModelKind::kModalShell) {
      if (duct_.organ >= 0) return problem("only one modal-shell organ is supported");
      const Result<DuctFit> fitted = fit_duct(organ.mesh, settings_.duct_wall_thickness_m);
      if (!fitted.ok()) return problem(fitted.message());
      const DuctFit& fit = fitted.value();
      const models::DuctShell shell = models::make_duct_shell(fit.duct);
      const std::filesystem::path dir =
          settings_.mode_cache_dir.empty() ? default_mode_cache_dir() : settings_.mode_cache_dir;
      Result<ModalShellLoad> loaded = load_or_build_modal_shell(
          shell.mesh, shell.held_dof, models::default_duct_modal_settings(fit.duct), dir);
      if (!loaded.ok()) return problem(loaded.message());
      ModalShellLoad& load = loaded.value();
      if (!load.note.empty() && notes != nullptr) notes->push_back(organ.name + ": " + load.note);
      duct_.model = std::make_unique<models::ModalShellModel>(std::move(load.model));
      duct_.pose_WD = fit.pose_WD;
      duct_.rest_D = shell.mesh.nodes;
      duct_.organ = index;
      t.kind = TissueKind::kDuct;
      t.surface = models::triangulate(shell.mesh);
      add_duct_texture_coordinates(&t.surface);
      t.surface.transform(Eigen::Affine3d(fit.pose_WD.matrix()));
      t.contact.clearance_m += 0.5 * settings_.duct_wall_thickness_m;  // its mid-surface
      t.contact.keep_side = true;  // the catheter may be inside or outside
      if (organ.incision.present) {
        Result<std::vector<uint8_t>> open =
            incision_faces(t.surface, fit.duct, fit.pose_WD, organ.incision);
        if (!open.ok()) {
          Diagnostic d = open.diagnostics().front();
          d.field = "organs[" + std::to_string(index) + "]." + d.field;
          return d;
        }
        t.open_faces = std::move(open).value();
      }
      measure_lumen(t, organ.incision, 0.5 * settings_.catheter.outer_diameter_m, &duct_);
    } else {
      t.surface = organ.mesh;
      auto rest = std::make_unique<haptics::MeshDatabase>(haptics::MeshDatabase::build(t.surface));
      if (organ.model == models::ModelKind::kLocal) {
        t.kind = TissueKind::kLocal;
        t.local = std::make_unique<models::LocalDeformationModel>(
            models::LocalDeformationModel::build(*rest, settings_.local));
      }
      t.rest = std::move(rest);
    }
  } catch (const std::exception& e) {
    return problem(e.what());
  }
  organs_.push_back(std::move(t));
  return {};
}

}  // namespace lap::sim
