// The keyboard's device follows its input as a hand would (hardware/simulated_device.h): at most
// at the hand's speeds, in a straight line, and there at once when it is near.

#include "hardware/simulated_device.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace lap::hardware {
namespace {

constexpr double kPeriodS = 1e-3;

// A 2 cm move at 50 mm/s: 400 ticks along the straight line, 0.05 mm a tick, the velocity the
// speed along it; then still. The jaws and a quarter turn at their own rates meanwhile.
TEST(SimulatedDevice, TheHandFollowsAStepAtItsSpeedsInAStraightLine) {
  SimulatedInput home;
  home.position_W = Eigen::Vector3d(0.1, 0.2, 0.3);
  home.gripper_angle_rad = 0.2;
  SimulatedDevice d(home, "keys");
  const SimulatedHandSpeeds& v = d.speeds();
  ASSERT_TRUE(d.start().ok());
  DeviceSample s;
  ASSERT_EQ(d.read(0, kPeriodS, &s), DeviceStatus::kOk);
  EXPECT_EQ(s.position_W, home.position_W);  // the first read is at the input
  SimulatedInput to = home;
  const Eigen::Vector3d step(0.012, -0.016, 0.0);  // 2 cm
  to.position_W += step;
  to.gripper_angle_rad = 0.5;
  to.orientation_W = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  d.set_input(to);
  const int64_t ticks = static_cast<int64_t>(std::llround(0.02 / v.speed_m_per_s / kPeriodS));
  ASSERT_EQ(ticks, 400);
  for (int64_t k = 1; k <= ticks + 400; ++k) {  // the quarter turn ends at 785
    ASSERT_EQ(d.read(k, kPeriodS, &s), DeviceStatus::kOk);
    const double t = static_cast<double>(k) * kPeriodS;
    const double along = std::min(0.02, v.speed_m_per_s * t);
    EXPECT_LT((s.position_W - (home.position_W + step.normalized() * along)).norm(), 1e-12) << k;
    EXPECT_NEAR(s.gripper_angle_rad, std::min(0.5, 0.2 + v.jaws_rad_per_s * t), 1e-12) << k;
    EXPECT_NEAR(s.orientation_W.angularDistance(Eigen::Quaterniond::Identity()),
                std::min(M_PI / 2, v.turn_rad_per_s * t), 1e-9)
        << k;
    const double speed = k <= ticks ? v.speed_m_per_s : 0.0;
    EXPECT_NEAR(s.velocity_W.norm(), speed, 1e-9) << k;
  }
  EXPECT_LT((s.position_W - to.position_W).norm(), 1e-15);
  EXPECT_LT(s.orientation_W.angularDistance(to.orientation_W), 1e-12);
}

// The workspace still bounds it, and a tick that does not advance time does not move it.
TEST(SimulatedDevice, TheWorkspaceBoundsItAndTimeMustPassForItToMove) {
  DeviceLimits limits;
  limits.workspace_W =
      Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.1), Eigen::Vector3d::Constant(0.1));
  SimulatedDevice d(SimulatedInput{}, "keys", limits);
  ASSERT_TRUE(d.start().ok());
  DeviceSample s;
  d.read(0, kPeriodS, &s);
  SimulatedInput far;
  far.position_W = Eigen::Vector3d(0.5, 0.0, 0.0);
  d.set_input(far);
  d.read(0, kPeriodS, &s);  // the same tick again
  EXPECT_EQ(s.position_W, Eigen::Vector3d::Zero());
  for (int64_t k = 1; k <= 3000; ++k) d.read(k, kPeriodS, &s);
  EXPECT_EQ(s.position_W, Eigen::Vector3d(0.1, 0.0, 0.0));
}

// A non-finite input leaves the hand where it was (and the next finite one is still followed at
// the hand's speed, not jumped to); the same orientation given as -q is no turn, and the
// sample's coefficients keep their sign; a read at an earlier tick does not move the hand.
TEST(SimulatedDevice, NonFiniteInputsTheDoubleCoverAndTimeGoingBackAreHeld) {
  SimulatedInput home;
  home.orientation_W = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  SimulatedDevice d(home, "keys");
  ASSERT_TRUE(d.start().ok());
  DeviceSample s;
  d.read(0, kPeriodS, &s);
  const Eigen::Vector4d q0 = s.orientation_W.coeffs();
  SimulatedInput bad = home;
  bad.position_W.x() = std::numeric_limits<double>::quiet_NaN();
  d.set_input(bad);
  d.read(1, kPeriodS, &s);
  EXPECT_EQ(s.position_W, Eigen::Vector3d::Zero());
  SimulatedInput far = home;
  far.position_W = Eigen::Vector3d(0.1, 0.0, 0.0);
  d.set_input(far);
  d.read(2, kPeriodS, &s);
  EXPECT_NEAR(s.position_W.x(), d.speeds().speed_m_per_s * kPeriodS, 1e-15);  // one tick's reach
  SimulatedInput flipped = home;
  flipped.position_W = s.position_W;
  flipped.orientation_W.coeffs() = -home.orientation_W.coeffs();
  d.set_input(flipped);
  d.read(3, kPeriodS, &s);
  EXPECT_LT((s.orientation_W.coeffs() - q0).norm(), 1e-12) << "the coefficients flipped";
  const Eigen::Vector3d at = s.position_W;
  d.set_input(far);
  d.read(1, kPeriodS, &s);  // back in time
  EXPECT_EQ(s.position_W, at);
}

}  // namespace
}  // namespace lap::hardware
