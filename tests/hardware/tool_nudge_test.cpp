// What a key press and a nudge do to a simulated tool (hardware/tool_nudge.h).

#include "hardware/tool_nudge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>

namespace lap::hardware {
namespace {

constexpr ToolKey kAllKeys[] = {
    ToolKey::kXMinus, ToolKey::kXPlus, ToolKey::kYPlus, ToolKey::kYMinus,    ToolKey::kZMinus,
    ToolKey::kZPlus,  ToolKey::kClose, ToolKey::kOpen,  ToolKey::kRollMinus, ToolKey::kRollPlus};

// Each key moves one thing by one step, and keys come in opposite pairs.
TEST(ToolNudge, EachKeyMovesOneThingByItsStep) {
  for (const ToolKey k : kAllKeys) {
    const ToolNudge n = key_nudge(k);
    int moved = 0;
    for (int a = 0; a < 3; ++a) {
      if (n.delta_W[a] != 0.0) {
        ++moved;
        EXPECT_EQ(std::abs(n.delta_W[a]), kKeyStepM);
      }
    }
    if (n.opening_rad != 0.0) {
      ++moved;
      EXPECT_EQ(std::abs(n.opening_rad), kKeyOpeningRad);
    }
    if (n.roll_rad != 0.0) {
      ++moved;
      EXPECT_EQ(std::abs(n.roll_rad), kKeyRollRad);
    }
    EXPECT_EQ(moved, 1) << static_cast<int>(k);
  }
  EXPECT_EQ(key_nudge(ToolKey::kXPlus).delta_W, Eigen::Vector3d(kKeyStepM, 0, 0));
  EXPECT_EQ(key_nudge(ToolKey::kXMinus).delta_W, -key_nudge(ToolKey::kXPlus).delta_W);
  EXPECT_EQ(key_nudge(ToolKey::kYPlus).delta_W, Eigen::Vector3d(0, kKeyStepM, 0));
  EXPECT_EQ(key_nudge(ToolKey::kYMinus).delta_W, -key_nudge(ToolKey::kYPlus).delta_W);
  EXPECT_EQ(key_nudge(ToolKey::kZPlus).delta_W, Eigen::Vector3d(0, 0, kKeyStepM));
  EXPECT_EQ(key_nudge(ToolKey::kZMinus).delta_W, -key_nudge(ToolKey::kZPlus).delta_W);
  EXPECT_LT(key_nudge(ToolKey::kClose).opening_rad, 0.0);
  EXPECT_EQ(key_nudge(ToolKey::kOpen).opening_rad, -key_nudge(ToolKey::kClose).opening_rad);
  EXPECT_GT(key_nudge(ToolKey::kRollPlus).roll_rad, 0.0);
  EXPECT_EQ(key_nudge(ToolKey::kRollMinus).roll_rad, -key_nudge(ToolKey::kRollPlus).roll_rad);
  EXPECT_NEAR(kKeyRollRad, M_PI / 36.0, 1e-10);  // 5 degrees
}

// The handle stays in the workspace (each coordinate clamped, as the device clamps its sample)
// and the jaws' opening within [0, 1] rad.
TEST(ToolNudge, TheHandleStaysInTheWorkspaceAndTheJawsInTheirRange) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.1, -0.2, -0.3), Eigen::Vector3d(0.1, 0.2, 0.3));
  SimulatedInput in;
  in.position_W = Eigen::Vector3d(0.09, 0.0, -0.29);
  in.gripper_angle_rad = 0.98;
  ToolNudge n;
  n.delta_W = Eigen::Vector3d(0.05, 0.01, -0.05);
  n.opening_rad = 0.05;
  const SimulatedInput out = nudged(in, n, box, std::nullopt);
  EXPECT_EQ(out.position_W, Eigen::Vector3d(0.1, 0.01, -0.3));
  EXPECT_EQ(out.gripper_angle_rad, 1.0);
  n.delta_W = Eigen::Vector3d(-0.02, 0.0, 0.0);
  n.opening_rad = -2.0;
  const SimulatedInput back = nudged(out, n, box, std::nullopt);
  EXPECT_NEAR(back.position_W.x(), 0.08, 1e-15);  // the first press back moves it
  EXPECT_EQ(back.gripper_angle_rad, 0.0);
  // Non-finite motion is ignored, never stored.
  n.delta_W.x() = std::numeric_limits<double>::quiet_NaN();
  n.opening_rad = std::numeric_limits<double>::infinity();
  n.roll_rad = std::numeric_limits<double>::quiet_NaN();
  const SimulatedInput same = nudged(back, n, box, Eigen::Vector3d(0.0, 0.0, 0.5));
  EXPECT_EQ(same.position_W, back.position_W);
  EXPECT_EQ(same.gripper_angle_rad, back.gripper_angle_rad);
  EXPECT_TRUE(same.orientation_W.coeffs() == back.orientation_W.coeffs());
}

// The roll turns the device's x axis (the jaws' opening direction, made perpendicular to the
// shaft) about the line from the handle to the port by the angle asked, right-handed, whatever
// the handle's orientation; the part of the x axis along the shaft and the handle's position do
// not change. Checked against Rodrigues' formula on the x axis.
TEST(ToolNudge, TheRollTurnsTheJawsAboutTheShaft) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d::Constant(-1.0), Eigen::Vector3d::Constant(1.0));
  SimulatedInput in;
  in.position_W = Eigen::Vector3d(0.1, -0.05, 0.4);
  in.orientation_W =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d port(0.06, 0.03, 0.18);
  const Eigen::Vector3d k = (port - in.position_W).normalized();
  for (const double roll : {kKeyRollRad, -kKeyRollRad, 1.0, -2.5}) {
    ToolNudge n;
    n.roll_rad = roll;
    const SimulatedInput out = nudged(in, n, box, port);
    const Eigen::Vector3d x0 = in.orientation_W * Eigen::Vector3d::UnitX();
    const Eigen::Vector3d x1 = out.orientation_W * Eigen::Vector3d::UnitX();
    const Eigen::Vector3d expected =
        x0 * std::cos(roll) + k.cross(x0) * std::sin(roll) + k * k.dot(x0) * (1.0 - std::cos(roll));
    EXPECT_LT((x1 - expected).norm(), 1e-12) << roll;
    EXPECT_NEAR(x1.dot(k), x0.dot(k), 1e-12);
    const Eigen::Vector3d j0 = (x0 - x0.dot(k) * k).normalized();
    const Eigen::Vector3d j1 = (x1 - x1.dot(k) * k).normalized();
    EXPECT_NEAR(std::atan2(j0.cross(j1).dot(k), j0.dot(j1)), roll, 1e-12);
    EXPECT_EQ(out.position_W, in.position_W);
    EXPECT_NEAR(out.orientation_W.norm(), 1.0, 1e-15);
  }
  // Without a port: about the handle's own z axis, which stays where it was.
  ToolNudge n;
  n.roll_rad = 0.4;
  const SimulatedInput own = nudged(in, n, box, std::nullopt);
  const Eigen::Vector3d z = in.orientation_W * Eigen::Vector3d::UnitZ();
  EXPECT_LT((own.orientation_W * Eigen::Vector3d::UnitZ() - z).norm(), 1e-12);
  const Eigen::Vector3d x0 = in.orientation_W * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x1 = own.orientation_W * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(x0.cross(x1).dot(z), x0.dot(x1)), 0.4, 1e-12);
  // The handle at the port: no shaft, no roll.
  const SimulatedInput at_port = nudged(in, n, box, in.position_W);
  EXPECT_TRUE(at_port.orientation_W.coeffs() == in.orientation_W.coeffs());
}

}  // namespace
}  // namespace lap::hardware
