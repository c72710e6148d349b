#include "sim/runtime/trocar_tool.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>

namespace lap::sim {
namespace {

TrocarToolSettings settings() {
  TrocarToolSettings s;
  s.port_W = {0.0, 0.2, 0.1};
  s.shaft_length_m = 0.36;
  return s;
}

hardware::DeviceSample at(const Eigen::Vector3d& p) {
  hardware::DeviceSample s;
  s.position_W = p;
  return s;
}

TEST(TrocarTool, TheShaftAlwaysPassesThroughThePort) {
  const TrocarToolSettings st = settings();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  Eigen::Vector3d axis = -Eigen::Vector3d::UnitY();
  double worst = 0.0;
  for (int i = 0; i < 100000; ++i) {
    hardware::DeviceSample s = at(st.port_W + Eigen::Vector3d(u(rng), u(rng), u(rng)));
    s.orientation_W = Eigen::Quaterniond::UnitRandom();
    const ToolKinematics k = tool_kinematics(st, s, axis);
    axis = k.axis_W;
    // The port lies on the segment from the handle to the hinge, at the clamped distances.
    const Eigen::Vector3d d = k.pose.hinge_W - k.handle_W;
    const double along = (st.port_W - k.handle_W).dot(d.normalized());
    worst = std::max(worst, (k.handle_W + along * d.normalized() - st.port_W).norm());
    ASSERT_NEAR(d.norm(), st.shaft_length_m, 1e-12);
    ASSERT_GE(k.inside_m, st.min_inside_m - 1e-12);
    ASSERT_GE(k.outside_m, st.min_outside_m - 1e-12);
    ASSERT_NEAR(k.pose.shaft_dir_W.dot(k.axis_W), -1.0, 1e-12);
    ASSERT_NEAR(k.pose.open_dir_W.dot(k.axis_W), 0.0, 1e-9);
    ASSERT_NEAR(k.pose.open_dir_W.norm(), 1.0, 1e-12);
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(TrocarTool, TheTipMovesOppositeToTheHandScaledByTheLengths) {
  const TrocarToolSettings st = settings();
  // Handle 0.2 m straight above the port: tip 0.16 m below it.
  const ToolKinematics k =
      tool_kinematics(st, at(st.port_W + Eigen::Vector3d(0, 0.2, 0)), -Eigen::Vector3d::UnitY());
  EXPECT_NEAR(k.outside_m, 0.2, 1e-15);
  EXPECT_NEAR(k.inside_m, 0.16, 1e-15);
  EXPECT_TRUE(k.pose.hinge_W.isApprox(st.port_W + Eigen::Vector3d(0, -0.16, 0), 1e-14));
  // Move the hand 1 mm along +x: the tip moves about 0.8 mm along -x.
  const ToolKinematics m = tool_kinematics(st, at(st.port_W + Eigen::Vector3d(0.001, 0.2, 0)),
                                           -Eigen::Vector3d::UnitY());
  EXPECT_NEAR((m.pose.hinge_W - k.pose.hinge_W).x(), -0.0008, 1e-7);
}

TEST(TrocarTool, ForcesGoBackThroughTheFulcrumAsHandComputed) {
  const TrocarToolSettings st = settings();
  const ToolKinematics k =
      tool_kinematics(st, at(st.port_W + Eigen::Vector3d(0, 0.2, 0)), -Eigen::Vector3d::UnitY());
  // u = -y (port to tip), a = 0.2 m outside, b = 0.16 m inside.
  // 1. A sideways 1 N at the tip: the hand feels 0.16/0.2 = 0.8 N the other way.
  hardware::DeviceCommand c = handle_command(k, {1.0, 0, 0}, Eigen::Vector3d::Zero(), 0.0);
  EXPECT_TRUE(c.force_W.isApprox(Eigen::Vector3d(-0.8, 0, 0), 1e-14)) << c.force_W.transpose();
  // 2. Along the shaft: transmitted whole (the port takes no axial load).
  c = handle_command(k, {0, 2.0, 0}, Eigen::Vector3d::Zero(), 0.0);
  EXPECT_TRUE(c.force_W.isApprox(Eigen::Vector3d(0, 2.0, 0), 1e-14));
  // 3. A couple of 0.01 N m about z at the tip: balanced by the hand at a = 0.2 m, the hand
  //    force F satisfies (-a u) x F = -tau, i.e. (0.2 y) x F = (0, 0, -0.01): F = (-0.05, 0, 0).
  c = handle_command(k, Eigen::Vector3d::Zero(), {0, 0, 0.01}, 0.0);
  EXPECT_TRUE(c.force_W.isApprox(Eigen::Vector3d(-0.05, 0, 0), 1e-14)) << c.force_W.transpose();
  // 4. Roll torque about the shaft reaches the device as torque; squeeze passes through.
  c = handle_command(k, Eigen::Vector3d::Zero(), {0, 0.003, 0}, 1.5);
  EXPECT_TRUE(c.force_W.isZero(1e-15));
  EXPECT_TRUE(c.torque_W.isApprox(Eigen::Vector3d(0, 0.003, 0), 1e-15));
  EXPECT_EQ(c.squeeze_n, 1.5);
}

TEST(TrocarTool, TheLeverBalancesMomentsAboutThePortForAnyPose) {
  const TrocarToolSettings st = settings();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), 1.0 + u(rng), u(rng)).normalized();
    const ToolKinematics k = tool_kinematics(st, at(st.port_W + (0.1 + 0.1 * (u(rng) + 1)) * dir),
                                             -Eigen::Vector3d::UnitY());
    const Eigen::Vector3d f(u(rng), u(rng), u(rng));
    const Eigen::Vector3d tau(0.01 * u(rng), 0.01 * u(rng), 0.01 * u(rng));
    const hardware::DeviceCommand c = handle_command(k, f, tau, 0.0);
    // The tool is balanced by the tissue (f, tau at the tip), the hand (-c at the handle), the
    // port (perpendicular to the shaft, no moment about it): moments about the port and the
    // axial force must vanish.
    const Eigen::Vector3d moment = (k.pose.hinge_W - st.port_W).cross(f) + tau +
                                   (k.handle_W - st.port_W).cross(-c.force_W) - c.torque_W;
    EXPECT_LT(moment.norm(), 1e-14) << i;
    EXPECT_NEAR((f - c.force_W).dot(k.axis_W), 0.0, 1e-14) << i;
  }
}

// The map from a force at p to the handle's force, column by column through handle_command().
Eigen::Matrix3d lever_map(const ToolKinematics& k, const Eigen::Vector3d& p) {
  Eigen::Matrix3d t;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d f = Eigen::Vector3d::Unit(i);
    t.col(i) = handle_command(k, f, (p - k.pose.hinge_W).cross(f), 0.0).force_W;
  }
  return t;
}

TEST(TrocarTool, TheLeverGainIsTheLargestSingularValueOfTheMapToTheHandle) {
  const TrocarToolSettings st = settings();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), 1.0 + u(rng), u(rng)).normalized();
    const ToolKinematics k = tool_kinematics(st, at(st.port_W + (0.04 + 0.15 * (u(rng) + 1)) * dir),
                                             -Eigen::Vector3d::UnitY());
    // Points along the shaft and the jaws, on the axis and up to 2 cm off it.
    const Eigen::Vector3d p =
        k.pose.hinge_W + 0.1 * u(rng) * k.axis_W + 0.02 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const double sigma = Eigen::JacobiSVD<Eigen::Matrix3d>(lever_map(k, p)).singularValues()(0);
    EXPECT_NEAR(lever_gain_squared(k, p), sigma * sigma, 1e-9 * sigma * sigma) << i;
  }
  // On the axis: max(1, (b/a)²), b from the port to the point.
  const ToolKinematics k =
      tool_kinematics(st, at(st.port_W + Eigen::Vector3d(0, 0.1, 0)), -Eigen::Vector3d::UnitY());
  EXPECT_NEAR(lever_gain_squared(k, k.pose.hinge_W), 2.6 * 2.6, 1e-12);  // b = 0.26, a = 0.1
  EXPECT_NEAR(lever_gain_squared(k, st.port_W + 0.05 * k.axis_W), 1.0, 1e-12);
}

TEST(TrocarTool, ASpringOnTheToolFeelsAtTheHandleAsTheBudgetSays) {
  // A spring k holding the material point p of the tool (on its axis, b_p from the port) where
  // it was: move the handle by δ in every direction and measure the force the hand feels. The
  // stiffest direction (across the shaft) gives k (b_p/a)², the budget's value.
  const TrocarToolSettings st = settings();
  const Eigen::Vector3d h0 = st.port_W + Eigen::Vector3d(0.03, 0.12, -0.02);
  const ToolKinematics k0 = tool_kinematics(st, at(h0), -Eigen::Vector3d::UnitY());
  const double k_spring = 400.0;
  const double along = 0.9 * k0.inside_m;  // a point of the shaft, 90 % of the way to the hinge
  const Eigen::Vector3d p0 = k0.pose.hinge_W - (k0.inside_m - along) * k0.axis_W;
  StiffnessBudget budget(k0);
  budget.add(k_spring, p0);
  const double b_over_a = along / k0.outside_m;
  EXPECT_NEAR(budget.at_handle_n_per_m(), k_spring * std::max(1.0, b_over_a * b_over_a), 1e-9);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double stiffest = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d delta = 1e-6 * Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const ToolKinematics k1 = tool_kinematics(st, at(h0 + delta), k0.axis_W);
    const Eigen::Vector3d p1 = k1.pose.hinge_W - (k1.inside_m - along) * k1.axis_W;
    const Eigen::Vector3d f = -k_spring * (p1 - p0);
    const Eigen::Vector3d f_hand =
        handle_command(k1, f, (p1 - k1.pose.hinge_W).cross(f), 0.0).force_W;
    // What the device pushes back with, per unit of hand motion.
    stiffest = std::max(stiffest, f_hand.norm() / delta.norm());
  }
  EXPECT_LE(stiffest, budget.at_handle_n_per_m() * (1.0 + 1e-4));
  EXPECT_GE(stiffest, budget.at_handle_n_per_m() * 0.99);
  // Springs in parallel add up: the same spring again doubles the budget.
  budget.add(k_spring, p0);
  EXPECT_NEAR(budget.at_handle_n_per_m(), 2.0 * k_spring * b_over_a * b_over_a, 1e-9);
  budget.add(0.0, p0);  // nothing, and no NaN from a zero or negative stiffness
  budget.add(-5.0, p0);
  EXPECT_NEAR(budget.at_handle_n_per_m(), 2.0 * k_spring * b_over_a * b_over_a, 1e-9);
}

}  // namespace
}  // namespace lap::sim
