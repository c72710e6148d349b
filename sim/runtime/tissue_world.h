#pragma once
/// \file
/// The modelling loop's world (docs/architecture.md, "One modelling step": the catheter, the duct
/// and the organs' deformation take the tools' contact forces and publish the surfaces' positions;
/// thesis §6.5, §7.6.3, §7.7).
/// Built once from a scene; one step() per modelling tick:
///
/// 1. each tool's jaws grasp or release the catheter (catheter_grasp.h) and the duct
///    (duct_grasp.h);
/// 2. the catheter's particles meet every organ's rest surface and the duct's present wall
///    (catheter_contacts.h; each particle kept on its side of the open duct, crossing it only at
///    its open ends and through the scenario's incision), with Coulomb friction along them
///    (the material's catheter_friction; in the duct, on the slip relative to its wall);
/// 3. the catheter steps (its contacts and grasps inside its implicit step);
/// 4. organs under local deformation (`model: local`) are dented by the tools' contacts (the
///    proxies' reactions mapped back to the rest shape, surface_share of the tool's displacement
///    into the rest surface: the tool feels (1 − share) k, local_deformation.h) and by
///    the catheter (conforming: the groove meets it); their surface moving out stops short of
///    the grippers' segments that have no contact on them (models::DeformationObstacle);
/// 5. the duct (`model: modal-shell`; its shell fitted to the organ's mesh, duct_fit.h) takes the
///    tools' and the catheter's reactions and its grasp anchors, and its modes step.
///
/// The world is the state only: its fixed part (the organs' rest surfaces and models, the
/// catheter's and the duct's models, the settings) is a TissueModel (sim/setup/tissue_model.h)
/// it reads `const` and shares with the haptic thread and with other worlds built from it.
///
/// A model that meets a non-finite value (step_catheter, deform, step_modal_shell return false,
/// each leaving its state sane) is reported by step() as a ModelFault: the session zeroes the
/// forces and pauses, naming the model (sim/runtime/session.h).
///
/// The step allocates nothing and never throws; set-up may do both.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "haptics/mesh_database.h"
#include "haptics/triangle_mesh.h"
#include "models/catheter_contacts.h"
#include "models/catheter_grasp.h"
#include "models/catheter_model.h"
#include "models/duct_grasp.h"
#include "models/local_deformation.h"
#include "models/modal_shell.h"
#include "sim/runtime/deformed_surface.h"
#include "sim/setup/scene.h"
#include "sim/setup/tissue_model.h"

namespace lap::sim {

/// One of a tool's contacts with an organ, as the haptic loop saw it (on the deformed surface).
struct ToolContact {
  int32_t organ = -1;
  haptics::PrimitiveRef primitive;
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_on_organ_W = Eigen::Vector3d::Zero();  ///< [N]
  /// The contact spring k the haptic loop rendered it with (the organ's, as an author may have
  /// tuned it live that tick): the tissue model infers the tool's displacement from the force
  /// with it (§4: force / k). 0: not known, the organ's (TissueWorld::stiffness_n_per_m).
  double stiffness_n_per_m = 0.0;
  /// The contact's spring in units of its organ's k (haptics::SegmentContact::stiffness_factor:
  /// 1 under the thesis' rule and for a point; under the passive rule, the default, a segment is
  /// held by k at each end, so 2 at its middle or lying on a face).
  double stiffness_factor = 1.0;
  int32_t segment = -1;  ///< the tool's segment that touches (0 shaft, 1 and 2 the jaws)
};

/// What the modelling loop needs of one tool.
struct ToolModelInput {
  static constexpr int32_t kMaxContacts = 12;
  bool valid = false;  ///< false before the haptic loop's first tick
  models::JawFrame jaws;
  int32_t contact_count = 0;
  std::array<ToolContact, kMaxContacts> contacts{};
  /// Where its three segment proxies are (shaft, jaw 0, jaw 1; ToolSnapshot::proxy_a_W): an
  /// organ's dent does not pass the ones without a contact on it (models::DeformationObstacle).
  /// False: not known, or a probe's (none is an obstacle).
  bool has_proxies = false;
  std::array<Eigen::Vector3d, 3> proxy_a_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                           Eigen::Vector3d::Zero()};
  std::array<Eigen::Vector3d, 3> proxy_b_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                           Eigen::Vector3d::Zero()};
};

/// Which model met a non-finite value in a step.
enum class ModelFaultKind : uint8_t { kNone, kCatheter, kLocalDeformation, kModalShell };
/// "catheter", "local deformation", "modal shell" ("" for kNone).
[[nodiscard]] std::string_view to_string(ModelFaultKind kind);

/// The first model that faulted in a step, and on which organ (-1 for the catheter).
struct ModelFault {
  ModelFaultKind kind = ModelFaultKind::kNone;
  int32_t organ = -1;
  explicit operator bool() const { return kind != ModelFaultKind::kNone; }
};

class TissueWorld {
 public:
  /// The state for a model: the catheter where the model's settings lay it, organs at rest.
  static std::unique_ptr<TissueWorld> create(std::shared_ptr<const TissueModel> model);
  /// Model and state in one (tests, benchmarks): TissueModel::build, then create().
  static Result<std::unique_ptr<TissueWorld>> build(const Scene& scene,
                                                    const TissueWorldSettings& settings,
                                                    std::vector<std::string>* notes);

  [[nodiscard]] const TissueModel& model() const { return *model_; }
  [[nodiscard]] int32_t organ_count() const { return model_->organ_count(); }
  /// The surface the proxies feel and the graphics draw, at rest, world frame: the organ's mesh,
  /// or for the duct its triangulated shell (open at both ends).
  [[nodiscard]] const haptics::TriangleMesh& surface(int32_t organ) const {
    return model_->surface(organ);
  }
  /// Open surfaces (the duct) are touched from either side.
  [[nodiscard]] bool two_sided(int32_t organ) const { return model_->two_sided(organ); }
  [[nodiscard]] int32_t duct_organ() const { return model_->duct_organ(); }

  /// One modelling step; the first model that met a non-finite value, if any.
  ModelFault step(const std::array<ToolModelInput, 2>& tools, double dt) noexcept;

  /// Deformations sized for every organ (set-up: allocates), for a snapshot's slots.
  [[nodiscard]] std::vector<SurfaceDeformation> make_deformations() const;
  /// Writes each organ's present deformation (no allocation into make_deformations()' arrays).
  void write_deformations(std::vector<SurfaceDeformation>* out) const noexcept;

  [[nodiscard]] const models::CatheterModel& catheter_model() const {
    return model_->catheter_model();
  }
  [[nodiscard]] const models::CatheterState& catheter() const { return *catheter_; }
  [[nodiscard]] const std::array<models::GraspState, 2>& catheter_grasps() const {
    return catheter_grasps_;
  }
  [[nodiscard]] const std::array<models::DuctGraspState, 2>& duct_grasps() const {
    return duct_grasps_;
  }
  [[nodiscard]] const TissueWorldSettings& settings() const { return model_->settings(); }
  /// The jaws' squeeze on what they hold, per tool, at the last step [N].
  [[nodiscard]] const std::array<double, 2>& squeeze() const { return squeeze_; }
  /// The pull of each tool's grasp on the duct (its springs' force on the jaws), at the last
  /// step [N]; 0 where it does not hold the duct.
  [[nodiscard]] const std::array<double, 2>& duct_grasp_force_n() const {
    return duct_grasp_force_n_;
  }
  /// Each tool's jaws' squeeze on the duct alone, at the last step [N].
  [[nodiscard]] const std::array<double, 2>& duct_squeeze_n() const { return duct_squeeze_n_; }
  /// The catheter's push on organ i, the norm of its contacts' summed reactions, at the last
  /// step [N].
  [[nodiscard]] double catheter_push_n(int32_t organ) const {
    return organs_[static_cast<size_t>(organ)].catheter_push_n;
  }
  /// Catheter particles in contact with an organ or the duct, at the last step.
  [[nodiscard]] int32_t catheter_contacts() const { return catheter_contacts_; }
  /// Largest displacement of any surface vertex from rest, at the last step [m].
  [[nodiscard]] double deepest_dent_m() const { return deepest_dent_; }

  /// Organ `organ`'s contact stiffness k from the next step on, as an author tuned its haptic
  /// surface live (surface_tuning.h): the catheter meets the organ with it, and a tool's contact
  /// that does not carry the k it was rendered with (ToolContact::stiffness_n_per_m) dents by
  /// force / k. False, and nothing changed, for an organ that is not one or a k that is not
  /// finite and positive.
  bool set_stiffness(int32_t organ, double stiffness_n_per_m) noexcept;
  [[nodiscard]] double stiffness_n_per_m(int32_t organ) const {
    return organs_[static_cast<size_t>(organ)].contact.stiffness_n_per_m;
  }

  /// Where a free rigid organ is now (its body's pose, sim/runtime/moving_bodies.h): the
  /// catheter meets its rest surface there from the next step on. Fixed organs stay at the
  /// identity.
  void set_organ_pose(int32_t organ, const Eigen::Isometry3d& pose_W) noexcept {
    if (organ >= 0 && static_cast<size_t>(organ) < organ_pose_W_.size()) {
      organ_pose_W_[static_cast<size_t>(organ)] = pose_W;
    }
  }
  /// The catheter's push on organ i at the last step: its contacts' reactions summed, and their
  /// torque about com_W [N], [N m].
  void catheter_wrench(int32_t organ, const Eigen::Vector3d& com_W, Eigen::Vector3d* force_W,
                       Eigen::Vector3d* torque_W) const noexcept;

  /// Tests: the next step puts a non-finite value into this model's input (the catheter's
  /// velocity, a dent on the first locally deformed organ, a force on the duct), as a numerical
  /// blow-up would.
  void inject_non_finite(ModelFaultKind kind) noexcept { injected_ = kind; }

 private:
  /// One organ's state.
  struct OrganState {
    // The catheter against the organ, with the contact stiffness the haptic loop renders it
    // with (an author's live tuning, else the scenario's): a tool contact that does not carry
    // its own k dents by it too.
    models::SurfaceContactSettings contact;
    std::unique_ptr<models::LocalDeformationState> local;  // kLocal
    std::vector<models::DeformationContact> dents;         // tools' + catheter's, capacity reserved
    std::unique_ptr<models::SurfaceTracking> tracking;
    std::vector<models::SurfaceReaction> reactions;  // one per particle
    int32_t reaction_count = 0;
    double catheter_push_n = 0.0;  // the norm of the settled reactions' sum [N]
  };
  TissueWorld() = default;
  void grasp(const std::array<ToolModelInput, 2>& tools, double dt) noexcept;
  void find_catheter_contacts() noexcept;
  void set_duct_wall_velocities(const OrganState& s) noexcept;
  bool dent_local_organ(int32_t organ, const std::array<ToolModelInput, 2>& tools,
                        std::span<const models::SurfaceReaction> reactions) noexcept;
  bool step_duct(int32_t organ, const std::array<ToolModelInput, 2>& tools,
                 std::span<const models::SurfaceReaction> reactions, double dt) noexcept;
  [[nodiscard]] const haptics::MeshDatabase& contact_surface(int32_t organ) const;

  std::shared_ptr<const TissueModel> model_;
  std::vector<OrganState> organs_;
  std::vector<Eigen::Isometry3d> organ_pose_W_;  // per organ: a free body's pose, else identity
  std::unique_ptr<models::CatheterState> catheter_;
  std::array<models::GraspState, 2> catheter_grasps_{};
  std::array<models::DuctGraspState, 2> duct_grasps_{};
  std::array<double, 2> squeeze_{};
  std::array<double, 2> duct_grasp_force_n_{};
  std::array<double, 2> duct_squeeze_n_{};
  int32_t catheter_contacts_ = 0;
  double deepest_dent_ = 0.0;
  ModelFaultKind injected_ = ModelFaultKind::kNone;

  // The duct's state (model_->duct_organ() >= 0).
  std::unique_ptr<models::ModalShellState> duct_state_;
  std::unique_ptr<haptics::MeshDatabase> duct_wall_;  // world frame, deformed each step
  std::unique_ptr<haptics::MeshUpdateScratch> duct_scratch_;
  std::vector<Eigen::Vector3d> duct_positions_W_;
  std::vector<Eigen::Vector3d> duct_velocities_W_;  // over the last step [m/s]
  std::vector<int32_t> duct_all_nodes_;
};

}  // namespace lap::sim
