#pragma once
/// \file
/// The fixed part of the modelling loop's world (thesis §6.5, §7.6.3, §7.7), built once from a
/// scene: the catheter's model (§7.7(3)), each organ's rest surface, rest database, local
/// deformation model and contact settings, and the duct's modal shell (§7.7(2)) with its pose.
/// Nothing here changes after build(): the modelling thread steps a TissueWorld (its state,
/// sim/runtime/tissue_world.h) over it, and the haptic thread reads the grasp settings and the
/// catheter's model from it, both through a `const` reference, as MuJoCo's mjModel is shared by
/// its mjData.
///
/// `rigid` organs are kFixed here: anchored ones never move, free ones (with `dynamics`) are
/// moved by the haptic loop (sim/runtime/moving_bodies.h), the catheter meeting them where they
/// are (TissueWorld::set_organ_pose). `mass-spring` is refused for an organ at load.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "haptics/mesh_database.h"
#include "haptics/triangle_mesh.h"
#include "models/catheter_contacts.h"
#include "models/catheter_grasp.h"
#include "models/catheter_model.h"
#include "models/duct_grasp.h"
#include "models/incision_rim.h"
#include "models/local_deformation.h"
#include "models/modal_shell.h"
#include "sim/setup/scene.h"

namespace lap::sim {

struct TissueWorldSettings {
  models::CatheterSettings catheter;
  Eigen::Vector3d catheter_start_W = Eigen::Vector3d::Zero();  ///< particle 0, held there
  Eigen::Vector3d catheter_direction_W = Eigen::Vector3d::UnitX();
  models::LocalDeformationSettings local;
  /// The duct's wall (DuctSettings): about 1 mm (estimate), 3 mm inside a 5 mm duct.
  double duct_wall_thickness_m = 0.001;
  models::GraspSettings catheter_grasp;
  models::DuctGraspSettings duct_grasp;
  std::filesystem::path mode_cache_dir;  ///< empty: default_mode_cache_dir()
};

/// How an organ responds to the tools and the catheter.
enum class TissueKind : uint8_t {
  kFixed,  ///< rigid obstacle
  kLocal,  ///< local deformation (§6.5)
  kDuct,   ///< the modal shell (§7.7(2)); its surface is the shell, open at both ends
};

/// One organ's fixed tissue model.
struct OrganTissue {
  TissueKind kind = TissueKind::kFixed;
  haptics::TriangleMesh surface;  ///< rest, world frame: the proxies' and the graphics' surface
  /// The rest surface's database (not the duct's: its wall moves, TissueWorld keeps it).
  std::unique_ptr<const haptics::MeshDatabase> rest;
  std::unique_ptr<const models::LocalDeformationModel> local;  ///< kLocal only
  models::SurfaceContactSettings contact;                      ///< the catheter against it
  /// Per face of `surface`, 1 where the scenario's incision opens it to the catheter (the
  /// duct's ductotomy, duct_incision.h); empty: none.
  std::vector<uint8_t> open_faces;
  double stiffness_n_per_m = 0.0;
};

/// The duct's modal shell and where it lies.
struct DuctTissue {
  int32_t organ = -1;  ///< its index among the organs; -1: no duct in the scene
  Eigen::Isometry3d pose_WD = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> rest_D;  ///< shell nodes, duct frame
  std::unique_ptr<const models::ModalShellModel> model;
  /// Its lumen at rest (length, the mid-surface's mean radius) and the incision in the duct's
  /// frame, its half axes widened by the largest edge of an open face and the catheter's radius
  /// (the hole the catheter's contacts pass, duct_incision.h): the rim's hold and the task
  /// engine read it. Without an incision, half axes 0.
  models::IncisionRim rim;
  bool has_incision = false;
  Eigen::Vector3d incision_center_W = Eigen::Vector3d::Zero();  ///< the scenario's point
};

class TissueModel {
 public:
  /// Builds every organ's model. Diagnostics name the organ and the problem. `notes` gets what is
  /// worth telling (the duct's modes rebuilt and why).
  static Result<std::shared_ptr<const TissueModel>> build(const Scene& scene,
                                                          const TissueWorldSettings& settings,
                                                          std::vector<std::string>* notes);

  [[nodiscard]] const TissueWorldSettings& settings() const { return settings_; }
  [[nodiscard]] const models::CatheterModel& catheter_model() const { return *catheter_model_; }
  [[nodiscard]] int32_t organ_count() const { return static_cast<int32_t>(organs_.size()); }
  [[nodiscard]] const OrganTissue& organ(int32_t i) const {
    return organs_[static_cast<size_t>(i)];
  }
  /// The surface the proxies feel and the graphics draw, at rest, world frame: the organ's mesh,
  /// or for the duct its triangulated shell (open at both ends).
  [[nodiscard]] const haptics::TriangleMesh& surface(int32_t i) const { return organ(i).surface; }
  /// Open surfaces (the duct) are touched from either side.
  [[nodiscard]] bool two_sided(int32_t i) const { return organ(i).kind == TissueKind::kDuct; }
  [[nodiscard]] int32_t duct_organ() const { return duct_.organ; }
  [[nodiscard]] const DuctTissue& duct() const { return duct_; }

 private:
  TissueModel() = default;
  Status add_organ(const Organ& organ, int32_t index, std::vector<std::string>* notes);

  TissueWorldSettings settings_;
  std::unique_ptr<const models::CatheterModel> catheter_model_;
  std::vector<OrganTissue> organs_;
  DuctTissue duct_;
};

}  // namespace lap::sim
