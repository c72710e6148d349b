#include "models/modal_shell.h"

#include <Spectra/MatOp/SparseSymShiftSolve.h>
#include <Spectra/SymEigsShiftSolver.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>

#include "haptics/closest_point.h"

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
  m.split_translations();
  return m;
}

uint64_t ModalShellModel::key(const ShellMesh& mesh, const std::vector<uint8_t>& held_dof,
                              const ModalShellSettings& settings) {
  uint64_t h = 1469598103934665603ULL;  // FNV-1a over everything the modes depend on
  auto mix = [&](const void* data, size_t n) {
    const auto* b = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < n; ++i) {
      h ^= b[i];
      h *= 1099511628211ULL;
    }
  };
  const uint32_t version = 1;  // bump when the element or the solver changes
  mix(&version, sizeof version);
  for (const auto& p : mesh.nodes) mix(p.data(), 3 * sizeof(double));
  for (const auto& q : mesh.quads) mix(q.data(), 4 * sizeof(int32_t));
  mix(held_dof.data(), held_dof.size());
  const ShellMaterial& m = settings.material;
  for (const double v : {m.young_pa, m.poisson, m.density_kg_per_m3, m.thickness_m}) {
    mix(&v, sizeof v);
  }
  mix(&settings.modes, sizeof settings.modes);
  return h;
}

std::vector<uint8_t> ModalShellModel::to_bytes(uint64_t key) const {
  const auto rows = static_cast<uint64_t>(phi_.rows());
  const auto cols = static_cast<uint64_t>(phi_.cols());
  const uint64_t header[4] = {0x4C4150534D4F4445ULL /* "LAPSMODE" */, key, rows, cols};
  std::vector<uint8_t> out(sizeof header + sizeof(int32_t) + (cols + rows * cols) * sizeof(double));
  uint8_t* w = out.data();
  std::memcpy(w, header, sizeof header);
  w += sizeof header;
  std::memcpy(w, &node_count_, sizeof(int32_t));
  w += sizeof(int32_t);
  std::memcpy(w, omega_.data(), cols * sizeof(double));
  w += cols * sizeof(double);
  std::memcpy(w, phi_.data(), rows * cols * sizeof(double));
  return out;
}

ModalShellModel ModalShellModel::from_bytes(const std::vector<uint8_t>& bytes, uint64_t key,
                                            const ModalShellSettings& settings) {
  uint64_t header[4];
  if (bytes.size() < sizeof header + sizeof(int32_t)) {
    throw std::invalid_argument("modal cache: file too short for its header");
  }
  std::memcpy(header, bytes.data(), sizeof header);
  if (header[0] != 0x4C4150534D4F4445ULL)
    throw std::invalid_argument("modal cache: not a mode file");
  if (header[1] != key)
    throw std::invalid_argument("modal cache: made for another mesh or material");
  const uint64_t rows = header[2];
  const uint64_t cols = header[3];
  if (cols != static_cast<uint64_t>(settings.modes) || rows > (1ULL << 32) ||
      bytes.size() != sizeof header + sizeof(int32_t) + (cols + rows * cols) * sizeof(double)) {
    throw std::invalid_argument("modal cache: size does not match its header");
  }
  ModalShellModel m;
  m.settings_ = settings;
  const uint8_t* r = bytes.data() + sizeof header;
  std::memcpy(&m.node_count_, r, sizeof(int32_t));
  r += sizeof(int32_t);
  if (static_cast<uint64_t>(m.node_count_) * kShellDofsPerNode != rows) {
    throw std::invalid_argument("modal cache: node count does not match the mode rows");
  }
  m.omega_.resize(static_cast<Eigen::Index>(cols));
  std::memcpy(m.omega_.data(), r, cols * sizeof(double));
  r += cols * sizeof(double);
  m.phi_.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  std::memcpy(m.phi_.data(), r, rows * cols * sizeof(double));
  if (!m.omega_.allFinite() || !m.phi_.allFinite() || !(m.omega_.minCoeff() > 0.0)) {
    throw std::invalid_argument("modal cache: non-finite or non-positive values");
  }
  m.split_translations();
  return m;
}

void ModalShellModel::split_translations() {
  phi_translation_.resize(3 * static_cast<Eigen::Index>(node_count_), phi_.cols());
  for (Eigen::Index i = 0; i < node_count_; ++i) {
    phi_translation_.middleRows(3 * i, 3) = phi_.middleRows(kShellDofsPerNode * i, 3);
  }
}

DuctShell make_duct_shell(const DuctSettings& duct) {
  if (!(duct.wall_thickness_m > 0.0) || !(duct.outer_diameter_m > 2.0 * duct.wall_thickness_m)) {
    throw std::invalid_argument("duct: wall_thickness_m must be positive and below the radius");
  }
  DuctShell d;
  d.mesh = make_tube_shell(0.5 * (duct.outer_diameter_m - duct.wall_thickness_m), duct.length_m,
                           duct.around, duct.along);
  d.held_dof.assign(d.mesh.nodes.size() * kShellDofsPerNode, 0);
  // The membrane line: the ring node nearest the membrane angle, all along.
  const double step = 2.0 * M_PI / duct.around;
  const int32_t line =
      static_cast<int32_t>(std::lround(std::remainder(duct.membrane_angle_rad, 2.0 * M_PI) / step) +
                           duct.around) %
      duct.around;
  for (int32_t j = 0; j <= duct.along; ++j) {
    for (int32_t i = 0; i < duct.around; ++i) {
      const size_t node = static_cast<size_t>(j) * duct.around + i;
      const bool end = j == 0 || j == duct.along;
      for (int c = 0; c < kShellDofsPerNode; ++c) {
        if (end || (i == line && c < 3)) d.held_dof[node * kShellDofsPerNode + c] = 1;
      }
    }
  }
  return d;
}

ModalShellSettings default_duct_modal_settings(const DuctSettings& duct) {
  ModalShellSettings s;
  // Bile duct wall: G = 166 kPa, 1060 kg/m³ (PMC6925591, Table 1); ν = 0.45 (estimate);
  // E = 2 (1 + ν) G (DuctSettings' note).
  constexpr double kShearModulusPa = 166e3;
  s.material.poisson = 0.45;
  s.material.young_pa = 2.0 * (1.0 + s.material.poisson) * kShearModulusPa;
  s.material.density_kg_per_m3 = 1060.0;
  s.material.thickness_m = duct.wall_thickness_m;
  s.modes = 24;
  s.damping_ratio = 0.3;  // soft tissue in fluid: heavily damped (project estimate)
  return s;
}

ModalShellState::ModalShellState(const ModalShellModel& model)
    : q(Eigen::VectorXd::Zero(model.mode_count())),
      q_dot(Eigen::VectorXd::Zero(model.mode_count())),
      force(static_cast<size_t>(model.node_count()), Eigen::Vector3d::Zero()),
      modal_force(Eigen::VectorXd::Zero(model.mode_count())),
      displacement(static_cast<size_t>(model.node_count()), Eigen::Vector3d::Zero()),
      is_forced(static_cast<size_t>(model.node_count()), 0) {
  forced_nodes.reserve(static_cast<size_t>(model.node_count()));
  anchors.reserve(kMaxAnchors);
  const Eigen::Index m = model.mode_count();
  anchored_system = Eigen::MatrixXd::Zero(m, m);
  anchored_rhs = Eigen::VectorXd::Zero(m);
}

bool add_node_anchor(ModalShellState* state, const NodeAnchor& anchor) noexcept {
  if (state->anchors.size() >= static_cast<size_t>(ModalShellState::kMaxAnchors) ||
      anchor.node < 0 || static_cast<size_t>(anchor.node) >= state->displacement.size()) {
    return false;
  }
  state->anchors.push_back(anchor);  // reserved: never reallocates
  return true;
}

void clear_node_anchors(ModalShellState* state) noexcept { state->anchors.clear(); }

Eigen::Vector3d anchor_force(const ModalShellModel& model, const ModalShellState& state,
                             const NodeAnchor& anchor) noexcept {
  const Eigen::MatrixXd& phi = model.translation_modes();
  const auto rows =
      phi.block<3, Eigen::Dynamic>(3 * static_cast<Eigen::Index>(anchor.node), 0, 3, phi.cols());
  Eigen::Vector3d u_dot;
  u_dot.noalias() = rows * state.q_dot;
  return anchor.stiffness_n_per_m * (anchor.target_u - state.displacement[anchor.node]) -
         anchor.damping_n_s_per_m * u_dot;
}

void apply_node_force(ModalShellState* state, int32_t node, const Eigen::Vector3d& force_W) {
  state->force[node] += force_W;
  if (state->is_forced[node] == 0) {
    state->is_forced[node] = 1;
    state->forced_nodes.push_back(node);  // reserved for every node: never reallocates
  }
}

void apply_surface_force(const haptics::MeshDatabase& surface, haptics::PrimitiveRef primitive,
                         const Eigen::Vector3d& point_O, const Eigen::Vector3d& force_W,
                         ModalShellState* state) {
  switch (primitive.kind) {
    case haptics::PrimitiveKind::kVertex:
      apply_node_force(state, primitive.index, force_W);
      return;
    case haptics::PrimitiveKind::kEdge: {
      const auto& ev = surface.edge_vertices(primitive.index);
      const Eigen::Vector3d& a = surface.position(ev[0]);
      const Eigen::Vector3d& b = surface.position(ev[1]);
      const double len2 = (b - a).squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((point_O - a).dot(b - a) / len2, 0.0, 1.0) : 0.5;
      apply_node_force(state, ev[0], (1.0 - t) * force_W);
      apply_node_force(state, ev[1], t * force_W);
      return;
    }
    case haptics::PrimitiveKind::kFace: {
      const auto& fv = surface.face_vertices(primitive.index);
      const Eigen::Vector3d bary = haptics::barycentric(
          point_O, surface.position(fv[0]), surface.position(fv[1]), surface.position(fv[2]));
      double v = bary.y();
      double w = bary.z();
      v = std::clamp(v, 0.0, 1.0);
      w = std::clamp(w, 0.0, 1.0 - v);
      apply_node_force(state, fv[0], (1.0 - v - w) * force_W);
      apply_node_force(state, fv[1], v * force_W);
      apply_node_force(state, fv[2], w * force_W);
      return;
    }
    case haptics::PrimitiveKind::kNone:
      return;
  }
}

bool step_modal_shell(const ModalShellModel& model, ModalShellState* state, double dt) noexcept {
  // Φᵀ f over the forced nodes only (contacts touch a few nodes of hundreds), clearing them.
  const Eigen::MatrixXd& phi = model.translation_modes();
  bool finite = true;
  state->modal_force.setZero();
  for (const int32_t node : state->forced_nodes) {
    finite = finite && state->force[node].allFinite();
    state->modal_force.noalias() +=
        phi.middleRows(3 * static_cast<Eigen::Index>(node), 3).transpose() * state->force[node];
    state->force[node].setZero();
    state->is_forced[node] = 0;
  }
  state->forced_nodes.clear();
  if (!(dt > 0.0) || !std::isfinite(dt) || !finite) {
    state->q.setZero();
    state->q_dot.setZero();
    for (auto& u : state->displacement) u.setZero();
    return false;
  }
  const double zeta = model.settings().damping_ratio;
  if (!state->anchors.empty()) {
    // Backward Euler on the coupled modes: (I + dt D + dt² K) q̇' = q̇ + dt (f − K q), q' = q + dt
    // q̇', with K = Ω² + Σ k Φ_aᵀ Φ_a, D = 2ζΩ + Σ c Φ_aᵀ Φ_a and f = Φᵀ f_ext + Σ k Φ_aᵀ u_target.
    Eigen::MatrixXd& a = state->anchored_system;
    Eigen::VectorXd& b = state->anchored_rhs;
    a.setZero();
    b = state->modal_force;
    for (const NodeAnchor& an : state->anchors) {
      finite = finite && an.target_u.allFinite() && std::isfinite(an.stiffness_n_per_m) &&
               std::isfinite(an.damping_n_s_per_m);
      const auto rows =
          phi.block<3, Eigen::Dynamic>(3 * static_cast<Eigen::Index>(an.node), 0, 3, phi.cols());
      a.noalias() +=
          (dt * an.damping_n_s_per_m + dt * dt * an.stiffness_n_per_m) * (rows.transpose() * rows);
      // u = Φ q is up to date from the last step, so Φ_aᵀ k (u_target − u_a) needs no product.
      const Eigen::Vector3d pull =
          an.stiffness_n_per_m * (an.target_u - state->displacement[an.node]);
      b.noalias() += rows.transpose() * pull;
    }
    const Eigen::VectorXd& w = model.omega();
    for (Eigen::Index k = 0; k < w.size(); ++k) {
      a(k, k) += 1.0 + dt * 2.0 * zeta * w(k) + dt * dt * w(k) * w(k);
      b(k) -= w(k) * w(k) * state->q(k);  // the anchors' K q is in `pull` already
    }
    b = state->q_dot + dt * b;
    // Factored in place, in the pre-sized matrix: no allocation.
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> solver(a);
    if (!finite || solver.info() != Eigen::Success) {
      state->q.setZero();
      state->q_dot.setZero();
      for (auto& u : state->displacement) u.setZero();
      return false;
    }
    solver.solveInPlace(b);
    state->q_dot = b;
    state->q += dt * state->q_dot;
    Eigen::Map<Eigen::VectorXd> u(state->displacement.data()->data(),
                                  3 * static_cast<Eigen::Index>(model.node_count()));
    u.noalias() = model.translation_modes() * state->q;
    return true;
  }
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
  // u = Φ q over the translation rows, in one product into the displacement array.
  Eigen::Map<Eigen::VectorXd> u(state->displacement.data()->data(),
                                3 * static_cast<Eigen::Index>(model.node_count()));
  u.noalias() = model.translation_modes() * state->q;
  return true;
}

}  // namespace lap::models
