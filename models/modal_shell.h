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

 private:
  ModalShellSettings settings_;
  int32_t node_count_ = 0;
  Eigen::VectorXd omega_;
  Eigen::MatrixXd phi_;  // 6 n x m
};

/// The lowest `count` eigenpairs of an assembled shell (ascending ω, mass-normalised, free
/// numbering). Throws std::runtime_error if Spectra does not converge.
void lowest_modes(const AssembledShell& shell, int32_t count, Eigen::VectorXd* omega,
                  Eigen::MatrixXd* phi_free);

struct ModalShellState {
  Eigen::VectorXd q;  ///< modal coordinates
  Eigen::VectorXd q_dot;
  Eigen::VectorXd force;        ///< 6 n generalised forces [N, N m], cleared by each step
  Eigen::VectorXd modal_force;  ///< m (workspace)
  std::vector<Eigen::Vector3d> displacement;  ///< n node translations u = Φ q [m]
  explicit ModalShellState(const ModalShellModel& model);
};

/// Adds a force at a node (translation dofs).
void apply_node_force(ModalShellState* state, int32_t node, const Eigen::Vector3d& force_W);

/// Advances the modes by dt (exact for a force held over the step) and updates `displacement`.
/// Returns false (state at rest) on a non-finite force or dt.
bool step_modal_shell(const ModalShellModel& model, ModalShellState* state, double dt) noexcept;

}  // namespace lap::models
