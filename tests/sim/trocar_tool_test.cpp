#include "sim/runtime/trocar_tool.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace lap::sim
