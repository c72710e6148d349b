// Grasping the duct (§7.6.2, §7.7(2)): closing the jaws on the default duct grasps nodes on both
// jaws, the squeeze grows with closure through the shell's stiffness, the grasped duct follows
// the jaws and comes back to rest when they open, a stiff grasp stays stable at the modelling
// rate, the haptic-rate coupling equals the model's springs at rest, damps the jaws' motion, and
// absorbs energy against the real duct stepped at 200 Hz.

#include "models/duct_grasp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace lap::models {
namespace {

constexpr double kDt = 0.005;    // the modelling loop's 200 Hz
constexpr double kTick = 0.001;  // the haptic loop's 1 kHz

/// Jaws at a haptic tick that have not moved since the last.
HapticJaws still(const JawFrame& jaws) { return {jaws, jaws, kTick, 0.0}; }

const DuctShell& duct_shell() {
  static const DuctShell shell = make_duct_shell(DuctSettings{});
  return shell;
}
const ModalShellModel& duct_model() {
  static const ModalShellModel model = ModalShellModel::build(
      duct_shell().mesh, duct_shell().held_dof, default_duct_modal_settings(DuctSettings{}));
  return model;
}

/// The default duct (axis z, 0–30 mm, mid-surface radius 3.6 mm) at a tilted, shifted pose, and
/// jaws coming at its middle from the side: shaft along the duct's +x, opening along its y.
struct Bench {
  Eigen::Isometry3d pose_WD = Eigen::Isometry3d::Identity();
  ModalShellState duct{duct_model()};
  DuctGraspSettings settings;
  DuctGraspState grasp;
  JawFrame jaws;
  Bench() {
    pose_WD.translate(Eigen::Vector3d(0.02, -0.01, 0.005));
    pose_WD.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -0.5).normalized()));
    set_jaws(Eigen::Vector3d(0.015, 0.0, 0.015), 0.8);
  }
  /// Jaws with their hinge at `hinge_D` (duct frame) and the given opening.
  void set_jaws(const Eigen::Vector3d& hinge_D, double opening) {
    jaws.hinge_W = pose_WD * hinge_D;
    Eigen::Matrix3d r_DJ;
    r_DJ.col(0) = Eigen::Vector3d::UnitY();
    r_DJ.col(1) = Eigen::Vector3d::UnitX();
    r_DJ.col(2) = r_DJ.col(0).cross(r_DJ.col(1));
    jaws.rotation_WJ = pose_WD.linear() * r_DJ;
    jaws.opening_rad = opening;
  }
  DuctGraspOutput step() {
    clear_node_anchors(&duct);
    const DuctGraspOutput out = update_duct_grasp(settings, jaws, pose_WD, duct_shell().mesh.nodes,
                                                  duct_model(), &duct, &grasp);
    EXPECT_TRUE(step_modal_shell(duct_model(), &duct, kDt));
    return out;
  }
  [[nodiscard]] std::vector<Eigen::Vector3d> nodes_now() const {
    std::vector<Eigen::Vector3d> p(duct_shell().mesh.nodes);
    for (size_t i = 0; i < p.size(); ++i) p[i] += duct.displacement[i];
    return p;
  }
  [[nodiscard]] double max_displacement() const {
    double m = 0.0;
    for (const Eigen::Vector3d& u : duct.displacement) m = std::max(m, u.norm());
    return m;
  }
};

TEST(DuctGrasp, ClosingGraspsBothWallsAndTheSqueezeGrowsWithClosure) {
  Bench b;
  const Eigen::Vector3d hinge(0.015, 0.0, 0.015);
  bool grasped = false;
  for (int k = 0; k <= 60; ++k) {
    b.set_jaws(hinge, 0.8 - 0.01 * k);
    const DuctGraspOutput out = b.step();
    if (b.jaws.opening_rad >= b.settings.grasp_below_rad) {
      EXPECT_FALSE(b.grasp.grasping());
    }
    grasped = grasped || out.grasped_now;
  }
  ASSERT_TRUE(grasped);
  // Both walls: nodes on each jaw, on the duct's upper (y > 0) and lower side respectively.
  int on_jaw[2] = {0, 0};
  for (int32_t k = 0; k < b.grasp.count; ++k) {
    const Eigen::Vector3d& p = duct_shell().mesh.nodes[static_cast<size_t>(b.grasp.node[k])];
    ++on_jaw[b.grasp.jaw[k]];
    EXPECT_GT(b.grasp.jaw[k] == 0 ? p.y() : -p.y(), 0.0) << "node " << b.grasp.node[k];
    EXPECT_NEAR(p.z(), 0.015, b.settings.jaw_half_width_m + 1e-12);
  }
  EXPECT_GE(on_jaw[0], 4);
  EXPECT_GE(on_jaw[1], 4);
  // Quasi-static closure: the squeeze grows at every step down.
  double last = 0.0;
  std::printf("[ duct grasp ] %d nodes (%d + %d); opening [rad] -> squeeze [N], flattening [mm]:",
              b.grasp.count, on_jaw[0], on_jaw[1]);
  for (const double opening : {0.28, 0.22, 0.16, 0.10, 0.04}) {
    b.set_jaws(hinge, opening);
    DuctGraspOutput out;
    for (int k = 0; k < 200; ++k) out = b.step();
    // Top and bottom of the ring at the jaws' middle: how much nearer they are.
    const int32_t ring = 15 * 24;
    const Eigen::Vector3d top = b.nodes_now()[static_cast<size_t>(ring + 6)];
    const Eigen::Vector3d bottom = b.nodes_now()[static_cast<size_t>(ring + 18)];
    const double flattening = 2.0 * 0.0036 - (top - bottom).norm();
    std::printf(" %.2f -> %.4f, %.3f;", opening, out.squeeze_n, 1e3 * flattening);
    EXPECT_GT(out.squeeze_n, last + 1e-4) << "at " << opening << " rad";
    EXPECT_GT(flattening, 0.0);
    last = out.squeeze_n;
  }
  std::printf("\n");
  // The coupled implicit step's rest is the modal equilibrium Ω² q = Σ Φ_aᵀ f_a.
  Eigen::VectorXd balance = Eigen::VectorXd::Zero(duct_model().mode_count());
  for (const NodeAnchor& a : b.duct.anchors) {
    balance += duct_model().translation_modes().middleRows(3 * a.node, 3).transpose() *
               anchor_force(duct_model(), b.duct, a);
  }
  const Eigen::VectorXd elastic =
      duct_model().omega().array().square().matrix().cwiseProduct(b.duct.q);
  EXPECT_LT((elastic - balance).norm(), 1e-6 * elastic.norm());
}

TEST(DuctGrasp, GraspedDuctFollowsTheJawsAndOpeningReleasesIt) {
  Bench b;
  Eigen::Vector3d hinge(0.015, 0.0, 0.015);
  for (int k = 0; k <= 60; ++k) {
    b.set_jaws(hinge, 0.8 - 0.01 * k);
    b.step();
  }
  ASSERT_TRUE(b.grasp.grasping());
  // Pull the tool 1 mm away from the duct (+x, up the shaft) and 1 mm along it (+z).
  DuctGraspOutput out;
  for (int k = 1; k <= 100; ++k) {
    b.set_jaws(hinge + Eigen::Vector3d(0.001, 0.0, 0.001) * std::min(1.0, k / 50.0), 0.2);
    out = b.step();
  }
  Eigen::Vector3d mean_u = Eigen::Vector3d::Zero();
  for (int32_t k = 0; k < b.grasp.count; ++k) {
    mean_u += b.duct.displacement[static_cast<size_t>(b.grasp.node[k])];
  }
  mean_u /= b.grasp.count;
  std::printf(
      "[ duct grasp ] jaws moved (1, 0, 1) mm: grasped nodes moved (%.3f, %.3f, %.3f) mm, "
      "tool feels (%.4f, %.4f, %.4f) N in the duct frame\n",
      1e3 * mean_u.x(), 1e3 * mean_u.y(), 1e3 * mean_u.z(),
      (b.pose_WD.linear().transpose() * out.force_on_tool_W).x(),
      (b.pose_WD.linear().transpose() * out.force_on_tool_W).y(),
      (b.pose_WD.linear().transpose() * out.force_on_tool_W).z());
  // The tissue follows, part of the way: away from the duct freely, along it hardly (its ends and
  // membrane hold its translations), and pulls the tool back.
  EXPECT_GT(mean_u.x(), 0.1e-3);
  EXPECT_GT(mean_u.z(), 0.0);
  const Eigen::Vector3d f_D = b.pose_WD.linear().transpose() * out.force_on_tool_W;
  EXPECT_LT(f_D.x(), 0.0);
  EXPECT_LT(f_D.z(), 0.0);
  // Open: released at once, no force, and the duct comes back to rest.
  b.set_jaws(hinge, 0.6);
  out = b.step();
  EXPECT_TRUE(out.released_now);
  EXPECT_FALSE(b.grasp.grasping());
  EXPECT_EQ(out.force_on_tool_W.norm(), 0.0);
  EXPECT_EQ(
      duct_coupling(b.settings, still(b.jaws), b.pose_WD, b.nodes_now(), b.grasp).force_on_tool_W,
      Eigen::Vector3d::Zero());
  for (int k = 0; k < 200; ++k) b.step();
  EXPECT_LT(b.max_displacement(), 1e-9);
}

TEST(DuctGrasp, AStiffGraspStaysStableAtTheModellingRate) {
  Bench b;
  b.settings.attach_stiffness_n_per_m = 1e5;  // 5000x the default: explicit would explode
  b.settings.attach_damping_n_s_per_m = 0.0;
  const Eigen::Vector3d hinge(0.015, 0.0, 0.015);
  for (int k = 0; k <= 60; ++k) {
    b.set_jaws(hinge, 0.8 - 0.01 * k);
    b.step();
  }
  ASSERT_TRUE(b.grasp.grasping());
  double worst = 0.0;
  for (int k = 0; k < 400; ++k) {  // 2 s of jaws shaking ±1 mm at 5 Hz
    b.set_jaws(hinge + Eigen::Vector3d(0.0, 0.0, 0.001 * std::sin(2 * M_PI * 5.0 * k * kDt)), 0.2);
    b.step();
    ASSERT_TRUE(b.duct.q.allFinite());
    worst = std::max(worst, b.max_displacement());
  }
  // Bounded: 24 modes cannot put 3 x 32 anchored translations exactly where the springs want
  // them, so a very stiff grasp bends the duct more than the jaws move, but never grows.
  EXPECT_LT(worst, 0.015);
  b.set_jaws(hinge, 0.2);
  for (int k = 0; k < 200; ++k) b.step();
  EXPECT_LT(b.duct.q_dot.norm(), 1e-6 * std::max(1.0, b.duct.q.norm() * 1e3));
  std::printf(
      "[ duct grasp ] k = 1e5 N/m per node, jaws shaken 2 s: largest displacement %.3f mm, "
      "modal speed after 1 s still %.2e\n",
      1e3 * worst, b.duct.q_dot.norm());
}

TEST(DuctGrasp, HapticCouplingEqualsTheModelsSprings) {
  Bench b;
  const Eigen::Vector3d hinge(0.015, 0.0, 0.015);
  for (int k = 0; k <= 60; ++k) {
    b.set_jaws(hinge, 0.8 - 0.01 * k);
    b.step();
  }
  b.set_jaws(hinge + Eigen::Vector3d(0.0005, 0.0, 0.0), 0.1);
  for (int k = 0; k < 300; ++k) b.step();
  // At rest (no damping force left), the model's springs and the haptic coupling agree.
  clear_node_anchors(&b.duct);
  const DuctGraspOutput model = update_duct_grasp(
      b.settings, b.jaws, b.pose_WD, duct_shell().mesh.nodes, duct_model(), &b.duct, &b.grasp);
  const DuctCoupling haptic =
      duct_coupling(b.settings, still(b.jaws), b.pose_WD, b.nodes_now(), b.grasp);
  ASSERT_GT(model.force_on_tool_W.norm(), 1e-3);
  EXPECT_LT((haptic.force_on_tool_W - model.force_on_tool_W).norm(),
            1e-6 * model.force_on_tool_W.norm());
  EXPECT_NEAR(haptic.squeeze_n, model.squeeze_n, 1e-6 * model.squeeze_n);
  // Moving the jaws between model steps changes the coupling by at most k per node and metre.
  JawFrame moved = b.jaws;
  moved.hinge_W += b.pose_WD.linear() * Eigen::Vector3d(0.0, 0.0, 1e-4);
  const DuctCoupling after =
      duct_coupling(b.settings, still(moved), b.pose_WD, b.nodes_now(), b.grasp);
  EXPECT_LE((after.force_on_tool_W - haptic.force_on_tool_W).norm(),
            b.grasp.count * b.settings.attach_stiffness_n_per_m * 1e-4 * (1 + 1e-9));
  // A non-finite node position gives no force rather than a NaN.
  std::vector<Eigen::Vector3d> bad = b.nodes_now();
  bad[static_cast<size_t>(b.grasp.node[0])] = Eigen::Vector3d::Constant(NAN);
  EXPECT_EQ(duct_coupling(b.settings, still(b.jaws), b.pose_WD, bad, b.grasp).force_on_tool_W,
            Eigen::Vector3d::Zero());
}

// The damper of the coupling acts on the jaws' motion since the last tick: b times each anchor's
// velocity, exactly, on top of the springs.
TEST(DuctGrasp, HapticCouplingDampsTheJawsMotion) {
  Bench b;
  const Eigen::Vector3d hinge(0.015, 0.0, 0.015);
  for (int k = 0; k <= 60; ++k) {
    b.set_jaws(hinge, 0.8 - 0.01 * k);
    b.step();
  }
  ASSERT_TRUE(b.grasp.grasping());
  const DuctCoupling at_rest =
      duct_coupling(b.settings, still(b.jaws), b.pose_WD, b.nodes_now(), b.grasp);
  // The jaws came from 0.02 mm away along W's x in the last tick (a translation: every anchor
  // moved the same).
  JawFrame before = b.jaws;
  const Eigen::Vector3d step_W(2e-5, 0.0, 0.0);
  before.hinge_W -= step_W;
  const DuctCoupling moving =
      duct_coupling(b.settings, {b.jaws, before, kTick, 0.0}, b.pose_WD, b.nodes_now(), b.grasp);
  const Eigen::Vector3d expected =
      -b.grasp.count * b.settings.coupling_damping_n_s_per_m * step_W / kTick;
  EXPECT_LT((moving.force_on_tool_W - at_rest.force_on_tool_W - expected).norm(),
            1e-9 * expected.norm());
  EXPECT_DOUBLE_EQ(moving.squeeze_n, at_rest.squeeze_n);  // the squeeze is the springs'
  // Colgate's bound for the modelling period, with margin.
  EXPECT_GT(b.settings.coupling_damping_n_s_per_m,
            1.5 * b.settings.attach_stiffness_n_per_m * kDt / 2.0);
  // No tick length: no force.
  EXPECT_EQ(duct_coupling(b.settings, {b.jaws, before, 0.0, 0.0}, b.pose_WD, b.nodes_now(), b.grasp)
                .force_on_tool_W,
            Eigen::Vector3d::Zero());
}

// The jaws shaken along the duct's x at the haptic rate while the real duct steps at 200 Hz on
// the jaws as they were at its step, as the session interleaves them (a haptic tick reads the
// step published before it): the work the jaws do on the coupling, Σ −F·Δx with the force held
// over each tick, over whole cycles from rest. Positive: the coupling absorbs. Returns it [J].
double work_into_coupling(const DuctGraspSettings& settings, double hz, double amplitude_m) {
  Bench b;
  b.settings = settings;
  const Eigen::Vector3d hinge(0.015, 0.0, 0.015);
  for (int k = 0; k <= 60; ++k) {
    b.set_jaws(hinge, 0.8 - 0.01 * k);
    b.step();
  }
  EXPECT_TRUE(b.grasp.grasping());
  for (int k = 0; k < 200; ++k) b.step();  // settled
  const Eigen::Vector3d dir_W = b.pose_WD.linear() * Eigen::Vector3d::UnitX();
  const auto ticks = static_cast<int>(std::lround(1.0 / (hz * kTick)));  // per cycle
  const int cycles = std::max(1, static_cast<int>(1.0 / (ticks * kTick)));
  std::vector<Eigen::Vector3d> nodes = b.nodes_now();
  JawFrame before = b.jaws;
  const Eigen::Vector3d hinge_W = b.jaws.hinge_W;
  double work = 0.0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  for (int n = 0; n <= cycles * ticks; ++n) {
    JawFrame now = b.jaws;
    now.hinge_W = hinge_W + amplitude_m * std::sin(2.0 * M_PI * hz * n * kTick) * dir_W;
    work -= force.dot(now.hinge_W - before.hinge_W);  // the last tick's force over its motion
    force = duct_coupling(b.settings, {now, before, kTick, 0.0}, b.pose_WD, nodes, b.grasp)
                .force_on_tool_W;
    before = now;
    if (n % 5 == 0) {  // the modelling step on this tick's jaws, read from the next tick on
      b.jaws = now;
      b.step();
      nodes = b.nodes_now();
    }
  }
  return work;
}

TEST(DuctGrasp, TheHapticCouplingAbsorbsEnergyAgainstTheDuctSteppedAt200Hz) {
  DuctGraspSettings undamped;
  undamped.coupling_damping_n_s_per_m = 0.0;
  for (const double hz : {1.0, 5.0, 20.0, 50.0, 100.0}) {
    const double damped_j = work_into_coupling({}, hz, 0.0005);
    const double undamped_j = work_into_coupling(undamped, hz, 0.0005);
    EXPECT_GT(damped_j, 0.0) << hz << " Hz";
    EXPECT_GT(damped_j, undamped_j) << hz << " Hz";
    // The coupling without its damper (as it was) gives the jaws energy at 100 Hz: not passive.
    if (hz == 100.0) {
      EXPECT_LT(undamped_j, 0.0);
    }
    std::printf(
        "[ duct coupling ] jaws +-0.5 mm at %5.1f Hz for 1 s: work into the coupling %.3e J "
        "(undamped %.3e J)\n",
        hz, damped_j, undamped_j);
  }
}

}  // namespace
}  // namespace lap::models
