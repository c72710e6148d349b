#pragma once
/// \file
/// The modelling loop's world (ARCHITECTURE.md "Three loops": catheter, duct, organ deformation;
/// consumes contact forces, publishes surface positions; thesis §6.5, §7.6.3, §7.7). Built once
/// from a scene; one step() per modelling tick:
///
/// 1. each tool's jaws grasp or release the catheter (catheter_grasp.h) and the duct
///    (duct_grasp.h);
/// 2. the catheter's particles meet every organ's rest surface and the duct's present wall
///    (catheter_contacts.h; each particle kept on its side of the open duct);
/// 3. the catheter steps (its contacts and grasps inside its implicit step);
/// 4. organs under local deformation (`model: local`) are dented by the tools' contacts (the
///    proxies' reactions mapped back to the rest shape, share of the penetration as set) and by
///    the catheter (conforming: the groove meets it);
/// 5. the duct (`model: modal-shell`; its shell fitted to the organ's mesh, duct_fit.h) takes the
///    tools' and the catheter's reactions and its grasp anchors, and its modes step.
///
/// `rigid` organs stay put (they are obstacles; the rigid-body dynamics of models/rigid_body.h
/// are for loose objects, none in the scenarios yet); `mass-spring` organs are treated as rigid
/// here (the catheter is the one mass-spring model).
///
/// The step allocates nothing and never throws; set-up may do both.

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/triangle_mesh.h"
#include "models/catheter_contacts.h"
#include "models/catheter_grasp.h"
#include "models/catheter_model.h"
#include "models/duct_grasp.h"
#include "models/local_deformation.h"
#include "models/modal_shell.h"
#include "sim/deformed_surface.h"
#include "sim/scene.h"

namespace lap::sim {

/// One of a tool's contacts with an organ, as the haptic loop saw it (on the deformed surface).
struct ToolContact {
  int32_t organ = -1;
  haptics::PrimitiveRef primitive;
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_on_organ_W = Eigen::Vector3d::Zero();  ///< [N]
};

/// What the modelling loop needs of one tool.
struct ToolModelInput {
  static constexpr int32_t kMaxContacts = 12;
  bool valid = false;  ///< false before the haptic loop's first tick
  models::JawFrame jaws;
  int32_t contact_count = 0;
  std::array<ToolContact, kMaxContacts> contacts{};
};

struct TissueWorldSettings {
  models::CatheterSettings catheter;
  Eigen::Vector3d catheter_start_W = Eigen::Vector3d::Zero();  ///< particle 0, held there
  Eigen::Vector3d catheter_direction_W = Eigen::Vector3d::UnitX();
  models::LocalDeformationSettings local;
  double duct_wall_thickness_m = 0.0008;
  models::GraspSettings catheter_grasp;
  models::DuctGraspSettings duct_grasp;
  std::filesystem::path mode_cache_dir;  ///< empty: default_mode_cache_dir()
};

class TissueWorld {
 public:
  /// Builds every organ's model. Throws std::runtime_error naming the organ and the problem.
  /// `notes` gets what is worth telling (the duct's modes rebuilt and why).
  static std::unique_ptr<TissueWorld> build(const Scene& scene, const TissueWorldSettings& settings,
                                            std::vector<std::string>* notes);

  [[nodiscard]] int32_t organ_count() const { return static_cast<int32_t>(organs_.size()); }
  /// The surface the proxies feel and the graphics draw, at rest, world frame: the organ's mesh,
  /// or for the duct its triangulated shell (open at both ends).
  [[nodiscard]] const haptics::TriangleMesh& surface(int32_t organ) const {
    return organs_[static_cast<size_t>(organ)].surface;
  }
  /// Open surfaces (the duct) are touched from either side.
  [[nodiscard]] bool two_sided(int32_t organ) const {
    return organs_[static_cast<size_t>(organ)].kind == Kind::kDuct;
  }
  [[nodiscard]] int32_t duct_organ() const { return duct_organ_; }

  void step(const std::array<ToolModelInput, 2>& tools, double dt) noexcept;

  /// Deformations sized for every organ (set-up: allocates), for a snapshot's slots.
  [[nodiscard]] std::vector<SurfaceDeformation> make_deformations() const;
  /// Writes each organ's present deformation (no allocation into make_deformations()' arrays).
  void write_deformations(std::vector<SurfaceDeformation>* out) const noexcept;

  [[nodiscard]] const models::CatheterModel& catheter_model() const { return *catheter_model_; }
  [[nodiscard]] const models::CatheterState& catheter() const { return *catheter_; }
  [[nodiscard]] const std::array<models::GraspState, 2>& catheter_grasps() const {
    return catheter_grasps_;
  }
  [[nodiscard]] const std::array<models::DuctGraspState, 2>& duct_grasps() const {
    return duct_grasps_;
  }
  [[nodiscard]] const TissueWorldSettings& settings() const { return settings_; }
  /// The jaws' squeeze on what they hold, per tool, at the last step [N].
  [[nodiscard]] const std::array<double, 2>& squeeze() const { return squeeze_; }
  /// Catheter particles in contact with an organ or the duct, at the last step.
  [[nodiscard]] int32_t catheter_contacts() const { return catheter_contacts_; }
  /// Largest displacement of any surface vertex from rest, at the last step [m].
  [[nodiscard]] double deepest_dent_m() const { return deepest_dent_; }

 private:
  enum class Kind : uint8_t { kFixed, kLocal, kDuct };
  struct OrganModel {
    Kind kind = Kind::kFixed;
    haptics::TriangleMesh surface;                // rest, world frame
    std::unique_ptr<haptics::MeshDatabase> rest;  // never deformed: the catheter's contacts
    std::unique_ptr<models::LocalDeformationModel> local;
    std::unique_ptr<models::LocalDeformationState> local_state;
    std::vector<models::DeformationContact> dents;  // tools' + catheter's, capacity reserved
    models::SurfaceContactSettings contact;
    std::unique_ptr<models::SurfaceTracking> tracking;
    std::vector<models::SurfaceReaction> reactions;  // one per particle
    int32_t reaction_count = 0;
    double stiffness_n_per_m = 0.0;
  };
  TissueWorld() = default;

  TissueWorldSettings settings_;
  std::vector<OrganModel> organs_;
  std::unique_ptr<models::CatheterModel> catheter_model_;
  std::unique_ptr<models::CatheterState> catheter_;
  std::array<models::GraspState, 2> catheter_grasps_{};
  std::array<models::DuctGraspState, 2> duct_grasps_{};
  std::array<double, 2> squeeze_{};
  int32_t catheter_contacts_ = 0;
  double deepest_dent_ = 0.0;

  // The duct (duct_organ_ >= 0).
  int32_t duct_organ_ = -1;
  Eigen::Isometry3d duct_pose_WD_ = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> duct_rest_D_;  // shell nodes, duct frame
  std::unique_ptr<models::ModalShellModel> duct_model_;
  std::unique_ptr<models::ModalShellState> duct_state_;
  std::unique_ptr<haptics::MeshDatabase> duct_wall_;  // world frame, deformed each step
  std::unique_ptr<haptics::MeshUpdateScratch> duct_scratch_;
  std::vector<Eigen::Vector3d> duct_positions_W_;
  std::vector<int32_t> duct_all_nodes_;
};

}  // namespace lap::sim
