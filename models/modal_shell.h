#pragma once
/// \file
/// The cystic duct as a modal-reduced shell FEM (thesis §7.7(2), after Basdogan 1999): the wall
/// is meshed into shell elements (shell_element.h), the global sparse stiffness K and lumped mass
/// M are assembled once, the degrees of freedom held by the supporting membrane are removed, and
/// the lowest m modes of K φ = ω² M φ are found (Spectra, shift-invert at 0 on the symmetric
/// form M^-½ K M^-½). In real time only the m modal coordinates move: contact forces are
/// projected on the modes, each mode is advanced exactly over the step (a damped oscillator
/// under a force held over the step: unconditionally stable at any dt) with its own damping, and
/// the displacement is u = Φ q.
///
/// Model (immutable: matrices, modes) apart from state (modal coordinates). The step allocates
/// nothing and never throws.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <span>
#include <vector>

#include "haptics/mesh_database.h"
#include "models/shell_element.h"
#include "models/shell_mesh.h"

namespace lap::models {

constexpr int kShellDofsPerNode = 6;  ///< u, v, w (translations), θx, θy, θz

/// The assembled model with the held degrees of freedom removed ("free" numbering).
struct AssembledShell {
  Eigen::SparseMatrix<double> stiffness;  ///< free x free [N/m, N, N m]
  Eigen::VectorXd mass;                   ///< free, diagonal [kg, kg m²]
  std::vector<int32_t> free_of_dof;       ///< 6 n: free index, or -1 if held
  std::vector<int32_t> dof_of_free;       ///< free -> global dof (6 node + component)
};

/// Assembles K and M; `held_dof` (6 n, 1 = held) are the boundary conditions. Throws
/// std::invalid_argument on a non-rectangular element or bad sizes.
[[nodiscard]] AssembledShell assemble_shell(const ShellMesh& mesh, const ShellMaterial& material,
                                            const std::vector<uint8_t>& held_dof);

struct ModalShellSettings {
  ShellMaterial material;
  int32_t modes = 24;
  double damping_ratio = 0.1;  ///< ζ of every mode (< 1)
};

class ModalShellModel {
 public:
  /// Assembles and finds the lowest modes. Throws std::invalid_argument (bad input) or
  /// std::runtime_error (the eigen-solver did not converge).
  static ModalShellModel build(const ShellMesh& mesh, const std::vector<uint8_t>& held_dof,
                               const ModalShellSettings& settings);

  [[nodiscard]] int32_t mode_count() const { return static_cast<int32_t>(omega_.size()); }
  [[nodiscard]] int32_t node_count() const { return node_count_; }
  /// Angular frequencies ω_i, ascending [rad/s].
  [[nodiscard]] const Eigen::VectorXd& omega() const { return omega_; }
  /// Mass-normalised mode shapes over all 6 n dofs (held rows zero): Φᵀ M Φ = I.
  [[nodiscard]] const Eigen::MatrixXd& modes() const { return phi_; }
  [[nodiscard]] const ModalShellSettings& settings() const { return settings_; }

  /// What the modes depend on (mesh, held dofs, material, mode count), hashed: the cache key.
  [[nodiscard]] static uint64_t key(const ShellMesh& mesh, const std::vector<uint8_t>& held_dof,
                                    const ModalShellSettings& settings);
  /// The model as bytes, for the on-disk cache (sim/setup/modal_shell_cache), tagged with `key`.
  [[nodiscard]] std::vector<uint8_t> to_bytes(uint64_t key) const;
  /// Reads to_bytes() output; throws std::invalid_argument when the bytes are short, corrupt or
  /// made for another key.
  static ModalShellModel from_bytes(const std::vector<uint8_t>& bytes, uint64_t key,
                                    const ModalShellSettings& settings);

 private:
  ModalShellSettings settings_;
  int32_t node_count_ = 0;
  Eigen::VectorXd omega_;
  Eigen::MatrixXd phi_;              // 6 n x m
  Eigen::MatrixXd phi_translation_;  // 3 n x m: the translation rows, contiguous for u = Φ q
  void split_translations();

 public:
  /// The translation rows of the modes (node i's at 3 i), for u = Φ q in one product.
  [[nodiscard]] const Eigen::MatrixXd& translation_modes() const { return phi_translation_; }
};

/// The lowest `count` eigenpairs of an assembled shell (ascending ω, mass-normalised, free
/// numbering). Throws std::runtime_error if Spectra does not converge.
void lowest_modes(const AssembledShell& shell, int32_t count, Eigen::VectorXd* omega,
                  Eigen::MatrixXd* phi_free);

/// The default cystic duct: a straight tube, its two end rings held where it joins the
/// gallbladder neck and the common bile duct, and the translations of one line along its
/// underside held by the supporting membrane (it "can be deformed but not translated", §7.7).
/// Anatomy, not the thesis' 8–10 mm (§7.4): 2–4 cm long, 2–3 mm across inside (Gray's
/// Anatomy); here 3 mm inside with a 1 mm wall (the wall's thickness an estimate), 5 mm outside.
/// The wall's material (default_duct_modal_settings()): bile duct shear modulus G = 166 kPa and
/// 1060 kg/m³ (PMC6925591, Table 1, after Duch et al. 2004), ν = 0.45 (nearly incompressible
/// soft tissue; estimate), E = 2 (1 + ν) G = 481 kPa. docs/tissue-parameters.md derives the
/// stiffness it gives.
struct DuctSettings {
  double outer_diameter_m = 0.005;
  double wall_thickness_m = 0.001;
  double length_m = 0.03;
  int32_t around = 24;
  int32_t along = 30;
  double membrane_angle_rad = -M_PI / 2;  ///< where the membrane line runs (about the axis)
};
struct DuctShell {
  ShellMesh mesh;
  std::vector<uint8_t> held_dof;
};
[[nodiscard]] DuctShell make_duct_shell(const DuctSettings& duct);
[[nodiscard]] ModalShellSettings default_duct_modal_settings(const DuctSettings& duct);

/// A spring and damper holding one node's translation to a target displacement (the jaws
/// grasping the duct, duct_grasp.h). Inside the step, so it is stable however stiff.
struct NodeAnchor {
  int32_t node = -1;
  Eigen::Vector3d target_u = Eigen::Vector3d::Zero();  ///< wanted displacement u of the node [m]
  double stiffness_n_per_m = 0.0;
  double damping_n_s_per_m = 0.0;
};

struct ModalShellState {
  static constexpr int32_t kMaxAnchors = 64;
  Eigen::VectorXd q;  ///< modal coordinates
  Eigen::VectorXd q_dot;
  std::vector<Eigen::Vector3d> force;         ///< n node forces [N], cleared by each step
  Eigen::VectorXd modal_force;                ///< m (workspace)
  std::vector<Eigen::Vector3d> displacement;  ///< n node translations u = Φ q [m]
  std::vector<int32_t> forced_nodes;          ///< nodes with a force this step (workspace)
  std::vector<uint8_t> is_forced;             ///< n flags for forced_nodes
  std::vector<NodeAnchor> anchors;            ///< this step's anchors (capacity kMaxAnchors)
  // Workspace of the anchored step (m x m system, factored in place): sized once.
  Eigen::MatrixXd anchored_system;
  Eigen::VectorXd anchored_rhs;
  explicit ModalShellState(const ModalShellModel& model);
};

/// Adds a force at a node (translation dofs).
void apply_node_force(ModalShellState* state, int32_t node, const Eigen::Vector3d& force_W);
/// Adds a force at a point of the shell's triangulated surface (shell_mesh.h triangulate()),
/// shared among the nodes of the primitive it lies on by barycentric weights.
void apply_surface_force(const haptics::MeshDatabase& surface, haptics::PrimitiveRef primitive,
                         const Eigen::Vector3d& point_O, const Eigen::Vector3d& force_W,
                         ModalShellState* state);

/// Adds an anchor for the next steps; false (nothing added) when kMaxAnchors are held or the
/// node is out of range.
bool add_node_anchor(ModalShellState* state, const NodeAnchor& anchor) noexcept;
/// Removes every anchor.
void clear_node_anchors(ModalShellState* state) noexcept;
/// The force an anchor puts on its node now [N] (spring and damper at the state's u and u̇).
[[nodiscard]] Eigen::Vector3d anchor_force(const ModalShellModel& model,
                                           const ModalShellState& state,
                                           const NodeAnchor& anchor) noexcept;

/// Advances the modes by dt (exact for a force held over the step) and updates `displacement`.
/// With anchors, the modes couple (Φ_aᵀ k Φ_a is not diagonal): the step is then backward Euler
/// on all m modes (an m x m SPD solve), unconditionally stable and damping the modes above the
/// step's frequency, which for the default duct (modes from 142 Hz up against the 200 Hz step,
/// ω dt ≥ 4.5, ζ = 0.3: three quarters of a mode's motion gone per step) the exact step nearly
/// does too. Returns false (state at rest) on a non-finite force, anchor or dt.
bool step_modal_shell(const ModalShellModel& model, ModalShellState* state, double dt) noexcept;

}  // namespace lap::models
