// The duct's shell FEM (§7.7(2)) against theory and against full solves of the same model:
// a clamped-free tube's first bending frequency (Euler–Bernoulli, hollow circular section), a
// pinched ring (the classical ring formula), Spectra's modes against a dense eigen-solve, the
// modal static answer converging to the full static solve, and mesh refinement.

#include "models/modal_shell.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "models/shell_mesh.h"

namespace lap::models {
namespace {

constexpr double kPi = 3.14159265358979323846;

ShellMaterial duct_wall(double poisson = 0.3) {
  ShellMaterial m;
  m.young_pa = 2e6;
  m.poisson = poisson;
  m.density_kg_per_m3 = 1060.0;
  m.thickness_m = 0.0008;
  return m;
}

// Every dof of the ring at z = 0 held (clamped end).
std::vector<uint8_t> clamp_first_ring(const ShellMesh& mesh, int32_t around) {
  std::vector<uint8_t> held(mesh.nodes.size() * kShellDofsPerNode, 0);
  for (int32_t i = 0; i < around; ++i) {
    for (int c = 0; c < kShellDofsPerNode; ++c) held[i * kShellDofsPerNode + c] = 1;
  }
  return held;
}

double euler_bernoulli_first_cantilever_omega(double radius, double t, double length,
                                              const ShellMaterial& m) {
  const double ro = radius + 0.5 * t;
  const double ri = radius - 0.5 * t;
  const double i = kPi / 4.0 * (std::pow(ro, 4) - std::pow(ri, 4));
  const double a = kPi * (ro * ro - ri * ri);
  const double beta = 1.8751040687;
  return beta * beta * std::sqrt(m.young_pa * i / (m.density_kg_per_m3 * a * std::pow(length, 4)));
}

double first_tube_omega(int32_t around, int32_t along, double radius, double length,
                        const ShellMaterial& m) {
  const ShellMesh mesh = make_tube_shell(radius, length, around, along);
  const AssembledShell shell = assemble_shell(mesh, m, clamp_first_ring(mesh, around));
  Eigen::VectorXd omega;
  Eigen::MatrixXd phi;
  lowest_modes(shell, 4, &omega, &phi);
  return omega(0);
}

TEST(ModalShell, ClampedTubeFirstBendingFrequencyMatchesEulerBernoulli) {
  const ShellMaterial m = duct_wall();
  const double radius = 0.0036;  // 8 mm outer diameter, 0.8 mm wall
  const double length = 0.1;     // L / D = 12.5: a beam
  const double w_fe = first_tube_omega(24, 100, radius, length, m);
  const double w_eb = euler_bernoulli_first_cantilever_omega(radius, m.thickness_m, length, m);
  const double error = std::abs(w_fe - w_eb) / w_eb;
  EXPECT_LT(error, 0.03);
  std::printf(
      "[ modal shell ] clamped tube 8 mm x 100 mm: first bending %.4f Hz, Euler-Bernoulli "
      "%.4f Hz (%.2f %%)\n",
      w_fe / (2 * kPi), w_eb / (2 * kPi), 100.0 * error);
}

// A thin ring (a short tube) pinched by two opposite loads P across a diameter: the diameter
// between them shortens by (π/4 − 2/π) P R³ / EI (Roark; Timoshenko), EI = E b t³ / 12 with
// ν = 0 so plane stress and plane strain agree.
TEST(ModalShell, PinchedRingMatchesTheRingFormula) {
  ShellMaterial m = duct_wall(0.0);
  m.thickness_m = 0.0002;
  const double radius = 0.004;
  const double width = 0.002;
  const int32_t around = 96;
  const int32_t along = 2;
  const ShellMesh mesh = make_tube_shell(radius, width, around, along);
  std::vector<uint8_t> held(mesh.nodes.size() * kShellDofsPerNode, 0);
  // Symmetry holds: no axial motion, no sideways motion of the loaded lines, no x motion at
  // ±90° (all zero in the symmetric answer, so they only remove the rigid motions).
  for (size_t node = 0; node < mesh.nodes.size(); ++node) {
    const int32_t i = static_cast<int32_t>(node) % around;
    held[node * kShellDofsPerNode + 2] = 1;
    if (i == 0 || i == around / 2) held[node * kShellDofsPerNode + 1] = 1;
    if (i == around / 4 || i == 3 * around / 4) held[node * kShellDofsPerNode + 0] = 1;
  }
  const AssembledShell shell = assemble_shell(mesh, m, held);
  const double p = 1e-5;  // N, in total on each side (a light pinch: 36 µm)
  Eigen::VectorXd f = Eigen::VectorXd::Zero(shell.stiffness.rows());
  for (int32_t j = 0; j <= along; ++j) {
    const double share = (j == 0 || j == along) ? 0.5 / along : 1.0 / along;
    for (const int32_t i : {0, around / 2}) {
      const int32_t node = j * around + i;
      const double inward = i == 0 ? -1.0 : 1.0;
      f(shell.free_of_dof[node * kShellDofsPerNode + 0]) += inward * p * share;
    }
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(shell.stiffness);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::VectorXd u = ldlt.solve(f);
  double shortening = 0.0;
  for (int32_t j = 0; j <= along; ++j) {
    const double u0 = u(shell.free_of_dof[(j * around) * kShellDofsPerNode]);
    const double u1 = u(shell.free_of_dof[(j * around + around / 2) * kShellDofsPerNode]);
    shortening += (u1 - u0) / (along + 1);
  }
  const double ei = m.young_pa * width * std::pow(m.thickness_m, 3) / 12.0;
  const double expected = (kPi / 4.0 - 2.0 / kPi) * p * std::pow(radius, 3) / ei;
  const double error = std::abs(shortening - expected) / expected;
  EXPECT_LT(error, 0.02);
  std::printf(
      "[ modal shell ] pinched ring R = 4 mm, t = 0.2 mm: %.5g um, ring formula %.5g um "
      "(%.3f %%)\n",
      1e6 * shortening, 1e6 * expected, 100.0 * error);
}

TEST(ModalShell, SpectraModesMatchADenseEigenSolve) {
  const ShellMaterial m = duct_wall();
  const int32_t around = 10;
  const ShellMesh mesh = make_tube_shell(0.0036, 0.03, around, 10);
  const AssembledShell shell = assemble_shell(mesh, m, clamp_first_ring(mesh, around));
  Eigen::VectorXd omega;
  Eigen::MatrixXd phi;
  lowest_modes(shell, 10, &omega, &phi);
  const Eigen::MatrixXd k = Eigen::MatrixXd(shell.stiffness);
  const Eigen::MatrixXd mm = shell.mass.asDiagonal();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(k, mm);
  ASSERT_EQ(dense.info(), Eigen::Success);
  double worst = 0.0;
  for (int i = 0; i < 10; ++i) {
    const double w_dense = std::sqrt(dense.eigenvalues()(i));
    worst = std::max(worst, std::abs(omega(i) - w_dense) / w_dense);
  }
  EXPECT_LT(worst, 0.01);
  // Mass-normalised.
  const Eigen::MatrixXd orth = phi.transpose() * shell.mass.asDiagonal() * phi;
  EXPECT_LT((orth - Eigen::MatrixXd::Identity(10, 10)).norm(), 1e-8);
  std::printf(
      "[ modal shell ] %lld free dofs: lowest 10 frequencies, Spectra vs dense, worst "
      "relative difference %.3g\n",
      static_cast<long long>(shell.stiffness.rows()), worst);
}

// Static deflection under a point load at the free end: Σ_{i ≤ m} φ_i φ_iᵀ f / ω_i² against
// the full solve K⁻¹ f.
TEST(ModalShell, ModalStaticDeflectionConvergesToTheFullSolve) {
  const ShellMaterial m = duct_wall();
  const int32_t around = 12;
  const int32_t along = 20;
  const ShellMesh mesh = make_tube_shell(0.0036, 0.04, around, along);
  const AssembledShell shell = assemble_shell(mesh, m, clamp_first_ring(mesh, around));
  Eigen::VectorXd f = Eigen::VectorXd::Zero(shell.stiffness.rows());
  const int32_t tip = along * around;  // a node of the free end, at angle 0
  const int32_t dof = shell.free_of_dof[tip * kShellDofsPerNode + 0];
  f(dof) = -0.001;  // 1 mN radially inwards: a poke
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(shell.stiffness);
  const Eigen::VectorXd full = ldlt.solve(f);
  Eigen::VectorXd omega;
  Eigen::MatrixXd phi;
  lowest_modes(shell, 160, &omega, &phi);
  double last_error = 1e9;
  std::printf(
      "[ modal shell ] static poke, free-end node: modes -> error of the deflection "
      "there\n");
  for (const int modes : {5, 10, 20, 40, 80, 160}) {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(f.size());
    for (int i = 0; i < modes; ++i) {
      u += phi.col(i) * (phi.col(i).dot(f) / (omega(i) * omega(i)));
    }
    const double error = std::abs(u(dof) - full(dof)) / std::abs(full(dof));
    std::printf("[ modal shell ]   m = %3d: %.4f %%\n", modes, 100.0 * error);
    EXPECT_LE(error, last_error + 1e-12) << modes;
    last_error = error;
  }
  EXPECT_LT(last_error, 0.25);
}

TEST(ModalShell, FirstFrequencyConvergesUnderMeshRefinement) {
  const ShellMaterial m = duct_wall();
  std::vector<double> w;
  for (const int32_t around : {8, 12, 16, 24}) {
    w.push_back(first_tube_omega(around, around * 4, 0.0036, 0.1, m));
  }
  const double w_eb = euler_bernoulli_first_cantilever_omega(0.0036, m.thickness_m, 0.1, m);
  for (size_t i = 0; i < w.size(); ++i) {
    std::printf("[ modal shell ] refinement %zu: first bending %.4f Hz (EB %.4f Hz)\n", i,
                w[i] / (2 * kPi), w_eb / (2 * kPi));
  }
  // Successive differences shrink.
  for (size_t i = 2; i < w.size(); ++i) {
    EXPECT_LT(std::abs(w[i] - w[i - 1]), std::abs(w[i - 1] - w[i - 2]) + 1e-12);
  }
}

TEST(ModalShell, ModalStepReachesTheStaticAnswerAndStaysBounded) {
  const ShellMaterial m = duct_wall();
  const int32_t around = 12;
  const ShellMesh mesh = make_tube_shell(0.0036, 0.03, around, 15);
  ModalShellSettings settings;
  settings.material = m;
  settings.modes = 20;
  settings.damping_ratio = 0.2;
  const ModalShellModel model =
      ModalShellModel::build(mesh, clamp_first_ring(mesh, around), settings);
  ModalShellState state(model);
  const int32_t tip = 15 * around;
  // Held load: converges to Σ φ φᵀ f / ω², at any dt (exact per mode).
  for (const double dt : {0.005, 0.5}) {
    state = ModalShellState(model);
    for (int k = 0; k < 4000; ++k) {
      apply_node_force(&state, tip, Eigen::Vector3d(-0.001, 0.0, 0.0));
      ASSERT_TRUE(step_modal_shell(model, &state, dt));
    }
    Eigen::VectorXd f = Eigen::VectorXd::Zero(model.modes().rows());
    f(tip * kShellDofsPerNode) = -0.001;
    const Eigen::VectorXd q_static =
        (model.modes().transpose() * f).cwiseQuotient(model.omega().cwiseAbs2());
    EXPECT_LT((state.q - q_static).norm(), 1e-9 * q_static.norm()) << dt;
    EXPECT_LT(state.displacement[tip].x(), 0.0);
  }
  // Released: free damped vibration decays.
  for (int k = 0; k < 4000; ++k) ASSERT_TRUE(step_modal_shell(model, &state, 0.005));
  EXPECT_LT(state.q.norm(), 1e-6 * (model.modes().transpose().col(0)).norm() + 1e-12);
  // Bad input.
  apply_node_force(&state, tip, Eigen::Vector3d(std::nan(""), 0.0, 0.0));
  EXPECT_FALSE(step_modal_shell(model, &state, 0.005));
  EXPECT_EQ(state.q.norm(), 0.0);
}

TEST(ModalShell, BadMeshesAreRefused) {
  ShellMesh mesh = make_tube_shell(0.004, 0.01, 8, 2);
  mesh.nodes[3].z() += 0.001;  // no longer a rectangle
  EXPECT_THROW(
      (void)assemble_shell(mesh, duct_wall(), std::vector<uint8_t>(mesh.nodes.size() * 6, 0)),
      std::invalid_argument);
  mesh = make_tube_shell(0.004, 0.01, 8, 2);
  mesh.quads[1][2] = 999;
  try {
    (void)assemble_shell(mesh, duct_wall(), std::vector<uint8_t>(mesh.nodes.size() * 6, 0));
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("element 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lap::models
