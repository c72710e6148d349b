#include "models/modal_shell.h"

#include <Spectra/MatOp/SparseSymShiftSolve.h>
#include <Spectra/SymEigsShiftSolver.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace lap::models {

AssembledShell assemble_shell(const ShellMesh& mesh, const ShellMaterial& material,
                              const std::vector<uint8_t>& held_dof) {
  const auto n = static_cast<int32_t>(mesh.nodes.size());
  if (held_dof.size() != static_cast<size_t>(kShellDofsPerNode) * n) {
    throw std::invalid_argument("shell: held_dof must have 6 entries per node");
  }
  if (!(material.young_pa > 0.0) || !(material.thickness_m > 0.0) ||
      !(material.density_kg_per_m3 > 0.0) || !(material.poisson > -1.0 && material.poisson < 0.5)) {
    throw std::invalid_argument(
        "shell: young_pa, thickness_m, density must be positive and poisson in (-1, 0.5)");
  }
  AssembledShell s;
  s.free_of_dof.assign(held_dof.size(), -1);
  for (size_t d = 0; d < held_dof.size(); ++d) {
    if (held_dof[d] == 0) {
      s.free_of_dof[d] = static_cast<int32_t>(s.dof_of_free.size());
      s.dof_of_free.push_back(static_cast<int32_t>(d));
    }
  }
  const auto nf = static_cast<Eigen::Index>(s.dof_of_free.size());
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(mesh.quads.size() * 24 * 24);
  Eigen::VectorXd mass_all = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(held_dof.size()));
  for (size_t e = 0; e < mesh.quads.size(); ++e) {
    const auto& q = mesh.quads[e];
    std::array<Eigen::Vector3d, 4> p;
    for (int i = 0; i < 4; ++i) {
      if (q[i] < 0 || q[i] >= n) {
        throw std::invalid_argument("shell: element " + std::to_string(e) + " names node " +
                                    std::to_string(q[i]) + " of " + std::to_string(n));
      }
      p[i] = mesh.nodes[q[i]];
    }
    ShellElementMatrix k;
    Eigen::Matrix<double, 24, 1> m;
    try {
      shell_element_matrices(p, material, &k, &m);
    } catch (const std::invalid_argument& err) {
      throw std::invalid_argument("shell: element " + std::to_string(e) + ": " + err.what());
    }
    for (int a = 0; a < 24; ++a) {
      const int32_t ga = kShellDofsPerNode * q[a / 6] + a % 6;
      mass_all(ga) += m(a);
      const int32_t fa = s.free_of_dof[ga];
      if (fa < 0) continue;
      for (int b = 0; b < 24; ++b) {
        const int32_t fb = s.free_of_dof[kShellDofsPerNode * q[b / 6] + b % 6];
        if (fb >= 0 && k(a, b) != 0.0) triplets.emplace_back(fa, fb, k(a, b));
      }
    }
  }
  s.stiffness.resize(nf, nf);
  s.stiffness.setFromTriplets(triplets.begin(), triplets.end());
  s.mass.resize(nf);
  for (Eigen::Index f = 0; f < nf; ++f) s.mass(f) = mass_all(s.dof_of_free[f]);
  if (nf > 0 && !(s.mass.minCoeff() > 0.0)) {
    throw std::invalid_argument("shell: a free degree of freedom belongs to no element");
  }
  return s;
}

void lowest_modes(const AssembledShell& shell, int32_t count, Eigen::VectorXd* omega,
                  Eigen::MatrixXd* phi_free) {
  const Eigen::Index n = shell.stiffness.rows();
  if (count < 1 || count >= n) {
    throw std::invalid_argument("shell: modes must be in 1 .. free dofs - 1");
  }
  // Standard symmetric form A = M^-½ K M^-½ (M diagonal), ψ orthonormal, φ = M^-½ ψ.
  const Eigen::VectorXd inv_sqrt = shell.mass.cwiseSqrt().cwiseInverse();
  Eigen::SparseMatrix<double> a = shell.stiffness;
  for (Eigen::Index col = 0; col < a.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, col); it; ++it) {
      it.valueRef() *= inv_sqrt(it.row()) * inv_sqrt(it.col());
    }
  }
  Spectra::SparseSymShiftSolve<double> op(a);
  const Eigen::Index ncv =
      std::min<Eigen::Index>(n, std::max<Eigen::Index>(2 * count + 1, count + 20));
  Spectra::SymEigsShiftSolver<Spectra::SparseSymShiftSolve<double>> eigs(op, count, ncv, 0.0);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 2000, 1e-12);
  if (eigs.info() != Spectra::CompInfo::Successful) {
    throw std::runtime_error("shell: the eigen-solver did not converge");
  }
  const Eigen::VectorXd lambda = eigs.eigenvalues();
  const Eigen::MatrixXd psi = eigs.eigenvectors();
  std::vector<Eigen::Index> order(static_cast<size_t>(lambda.size()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](Eigen::Index i, Eigen::Index j) { return lambda(i) < lambda(j); });
  omega->resize(count);
  phi_free->resize(n, count);
  for (int32_t k = 0; k < count; ++k) {
    (*omega)(k) = std::sqrt(std::max(0.0, lambda(order[k])));
    phi_free->col(k) = inv_sqrt.cwiseProduct(psi.col(order[k]));
  }
}

ModalShellModel ModalShellModel::build(const ShellMesh& mesh, const std::vector<uint8_t>& held_dof,
                                       const ModalShellSettings& settings) {
  if (!(settings.damping_ratio >= 0.0 && settings.damping_ratio < 1.0)) {
    throw std::invalid_argument("modal shell: damping_ratio must be in [0, 1)");
  }
  const AssembledShell shell = assemble_shell(mesh, settings.material, held_dof);
  ModalShellModel m;
  m.settings_ = settings;
  m.node_count_ = static_cast<int32_t>(mesh.nodes.size());
  Eigen::MatrixXd phi_free;
  lowest_modes(shell, settings.modes, &m.omega_, &phi_free);
  m.phi_ = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(held_dof.size()), settings.modes);
  for (Eigen::Index f = 0; f < phi_free.rows(); ++f) {
    m.phi_.row(shell.dof_of_free[f]) = phi_free.row(f);
  }
  return m;
}

ModalShellState::ModalShellState(const ModalShellModel& model)
    : q(Eigen::VectorXd::Zero(model.mode_count())),
      q_dot(Eigen::VectorXd::Zero(model.mode_count())),
      force(
          Eigen::VectorXd::Zero(static_cast<Eigen::Index>(kShellDofsPerNode) * model.node_count())),
      modal_force(Eigen::VectorXd::Zero(model.mode_count())),
      displacement(static_cast<size_t>(model.node_count()), Eigen::Vector3d::Zero()) {}

void apply_node_force(ModalShellState* state, int32_t node, const Eigen::Vector3d& force_W) {
  state->force.segment<3>(static_cast<Eigen::Index>(kShellDofsPerNode) * node) += force_W;
}

bool step_modal_shell(const ModalShellModel& model, ModalShellState* state, double dt) noexcept {
  if (!(dt > 0.0) || !std::isfinite(dt) || !state->force.allFinite()) {
    state->q.setZero();
    state->q_dot.setZero();
    state->force.setZero();
    for (auto& u : state->displacement) u.setZero();
    return false;
  }
  const Eigen::MatrixXd& phi = model.modes();
  state->modal_force.noalias() = phi.transpose() * state->force;
  state->force.setZero();
  const double zeta = model.settings().damping_ratio;
  for (int32_t k = 0; k < model.mode_count(); ++k) {
    // x = q − f/ω² oscillates freely about the static answer: advance it exactly.
    const double w = model.omega()(k);
    const double wd = w * std::sqrt(1.0 - zeta * zeta);
    const double qs = state->modal_force(k) / (w * w);
    const double x0 = state->q(k) - qs;
    const double v0 = state->q_dot(k);
    const double e = std::exp(-zeta * w * dt);
    const double c = std::cos(wd * dt);
    const double s = std::sin(wd * dt);
    state->q(k) = qs + e * (x0 * c + (v0 + zeta * w * x0) / wd * s);
    state->q_dot(k) = e * (v0 * c - (zeta * w * v0 + w * w * x0) / wd * s);
  }
  for (int32_t i = 0; i < model.node_count(); ++i) {
    state->displacement[i].noalias() =
        phi.block(static_cast<Eigen::Index>(kShellDofsPerNode) * i, 0, 3, model.mode_count()) *
        state->q;
  }
  return true;
}

}  // namespace lap::models
