#include "hardware/command_limiter.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace lap::hardware {
namespace {

DeviceLimits limits() {
  DeviceLimits l;
  l.max_force_n = 3.0;
  l.max_torque_nm = 0.0;
  l.max_squeeze_n = 5.0;
  l.max_force_rate_n_per_s = 1000.0;  // 1 N per 1 ms tick
  return l;
}

TEST(CommandLimiter, NonFiniteInputSendsZeroAtOnce) {
  CommandLimiter lim(limits());
  DeviceCommand c;
  c.force_W = {0.5, 0, 0};
  lim.apply(c, 0.001, 1.0);
  c.force_W.y() = std::numeric_limits<double>::quiet_NaN();
  const LimitedCommand out = lim.apply(c, 0.001, 1.0);
  EXPECT_TRUE(out.non_finite);
  EXPECT_EQ(out.command.force_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(out.command.squeeze_n, 0.0);
  c.force_W = {0, 0, 0};
  c.squeeze_n = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(lim.apply(c, 0.001, 1.0).non_finite);
}

TEST(CommandLimiter, ClampsMagnitudesToTheDevice) {
  CommandLimiter lim(limits());
  DeviceCommand c;
  c.force_W = {0.0, 0.0, 0.9};
  c.torque_W = {0.1, 0, 0};  // this arm renders no torque
  c.squeeze_n = 9.0;
  const LimitedCommand out = lim.apply(c, 0.001, 1.0);
  EXPECT_TRUE(out.clamped);
  EXPECT_EQ(out.command.torque_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(out.command.squeeze_n, 5.0);
  // A big force is cut to 3 N along its own direction, reached within the rate limit.
  c.force_W = {30.0, 40.0, 0.0};
  LimitedCommand last;
  for (int i = 0; i < 10; ++i) last = lim.apply(c, 0.001, 1.0);
  EXPECT_NEAR(last.command.force_W.norm(), 3.0, 1e-12);
  EXPECT_NEAR(last.command.force_W.normalized().dot(Eigen::Vector3d(0.6, 0.8, 0)), 1.0, 1e-12);
}

TEST(CommandLimiter, LimitsTheRateOfChangeButZeroIsImmediate) {
  CommandLimiter lim(limits());
  DeviceCommand c;
  c.force_W = {2.5, 0, 0};
  // 1 N per tick: 1, 2, 2.5.
  EXPECT_NEAR(lim.apply(c, 0.001, 1.0).command.force_W.x(), 1.0, 1e-12);
  const LimitedCommand second = lim.apply(c, 0.001, 1.0);
  EXPECT_TRUE(second.rate_limited);
  EXPECT_NEAR(second.command.force_W.x(), 2.0, 1e-12);
  EXPECT_NEAR(lim.apply(c, 0.001, 1.0).command.force_W.x(), 2.5, 1e-12);
  EXPECT_EQ(lim.zero().force_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(lim.last().force_W, Eigen::Vector3d::Zero());
  // The gain scales what the device can render: half gain on a 30 N push is 1.5 N, not 3 N.
  CommandLimiter fresh(limits());
  c.force_W = {30.0, 0, 0};
  LimitedCommand half;
  for (int i = 0; i < 5; ++i) half = fresh.apply(c, 0.001, 0.5);
  EXPECT_NEAR(half.command.force_W.x(), 1.5, 1e-12);
}

// The PHANToM Omni's figures (haptic_device.h): 3.3 N peak, 0.88 N continuous; τ = 10 s.
DeviceLimits omni() {
  DeviceLimits l;
  l.max_force_n = 3.3;
  l.max_continuous_force_n = 0.88;
  l.thermal_time_constant_s = 10.0;
  l.max_force_rate_n_per_s = 1000.0;
  return l;
}

TEST(CommandLimiter, ASustainedRequestAboveTheContinuousForceSettlesAtIt) {
  // 3.3 N asked for 20 s: the peak is sent until the thermal state reaches its knee (0.36 s,
  // command_limiter.h), then the bound falls to 0.88 N, within 1 % of it from τ / 2 on, and
  // the output never exceeds the peak nor, once settled, the continuous force.
  const DeviceLimits l = omni();
  CommandLimiter lim(l);
  DeviceCommand c;
  c.force_W = {0.0, 3.3, 0.0};
  const double dt = 0.001;
  double at_300_ms = 0.0;
  for (int tick = 1; tick <= 20000; ++tick) {
    const LimitedCommand out = lim.apply(c, dt, 1.0);
    const double f = out.command.force_W.norm();
    ASSERT_LE(f, l.max_force_n + 1e-12) << "tick " << tick;
    ASSERT_NEAR(out.command.force_W.normalized().y(), 1.0, 1e-12);
    if (tick == 300) at_300_ms = f;
    if (tick * dt >= 0.5 * l.thermal_time_constant_s) {
      ASSERT_NEAR(f, l.max_continuous_force_n, 0.01 * l.max_continuous_force_n) << "tick " << tick;
    }
  }
  EXPECT_NEAR(at_300_ms, 3.3, 1e-12);
  EXPECT_NEAR(lim.last().force_W.norm(), 0.88, 1e-6);
  EXPECT_LE(lim.thermal_state_n2(), 0.88 * 0.88 * (1.0 + 1e-6));
}

TEST(CommandLimiter, AShortPeakPassesUpToTheMaximumAndNeverAbove) {
  CommandLimiter lim(omni());
  DeviceCommand c;
  c.force_W = {5.0, 0.0, 0.0};  // above the peak: cut to 3.3 N
  double top = 0.0;
  for (int tick = 0; tick < 100; ++tick) {  // 100 ms
    const LimitedCommand out = lim.apply(c, 0.001, 1.0);
    EXPECT_FALSE(out.sustained_limited);
    top = std::max(top, out.command.force_W.norm());
  }
  EXPECT_NEAR(top, 3.3, 1e-12);
  // Rest, then the same peak again: a peak at a time, with rests, keeps passing whole.
  c.force_W.setZero();
  for (int tick = 0; tick < 2000; ++tick) lim.apply(c, 0.001, 1.0);
  c.force_W = {5.0, 0.0, 0.0};
  for (int tick = 0; tick < 100; ++tick) top = lim.apply(c, 0.001, 1.0).command.force_W.norm();
  EXPECT_NEAR(top, 3.3, 1e-12);
}

TEST(CommandLimiter, AWarmDeviceStillZeroesAtOnceAndStaysWarm) {
  CommandLimiter lim(omni());
  DeviceCommand c;
  c.force_W = {0.0, 0.0, 3.3};
  for (int tick = 0; tick < 5000; ++tick) lim.apply(c, 0.001, 1.0);
  const double warm = lim.thermal_state_n2();
  ASSERT_GT(warm, 0.5 * 0.88 * 0.88);
  EXPECT_EQ(lim.zero().force_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(lim.thermal_state_n2(), warm);  // zeroing does not pretend the motors cooled
  c.force_W.x() = std::numeric_limits<double>::quiet_NaN();
  const LimitedCommand nan = lim.apply(c, 0.001, 1.0);
  EXPECT_TRUE(nan.non_finite);
  EXPECT_EQ(nan.command.force_W, Eigen::Vector3d::Zero());
  // Below the continuous force nothing is cut, however warm.
  c.force_W = {0.0, 0.5, 0.0};
  const LimitedCommand small = lim.apply(c, 0.001, 1.0);
  EXPECT_FALSE(small.sustained_limited);
  EXPECT_NEAR(small.command.force_W.y(), 0.5, 1e-12);
}

TEST(CommandLimiter, TheStatedStiffnessIsScaledToTheDevicesAtOnceAndRecoversSlowly) {
  DeviceLimits l = limits();
  l.max_stiffness_n_per_m = 1000.0;
  CommandLimiter lim(l);
  DeviceCommand c;
  c.force_W = {0.2, 0.0, 0.0};
  c.torque_W = {0.0, 0.0, 0.0};
  c.stiffness_n_per_m = 4000.0;  // four times what the device renders stably
  LimitedCommand out = lim.apply(c, 0.001, 1.0);
  EXPECT_TRUE(out.stiffness_scaled);
  EXPECT_NEAR(lim.stiffness_scale(), 0.25, 1e-15);
  EXPECT_NEAR(out.command.force_W.x(), 0.05, 1e-15);
  EXPECT_NEAR(out.command.stiffness_n_per_m, 1000.0, 1e-9);
  // The budget falls: the scale comes back at 1 per kStiffnessRecoveryS, never past the target.
  c.stiffness_n_per_m = 500.0;
  double previous = lim.stiffness_scale();
  int ticks = 0;
  while (lim.stiffness_scale() < 1.0 && ticks < 1000) {
    out = lim.apply(c, 0.001, 1.0);
    EXPECT_LE(lim.stiffness_scale() - previous,
              0.001 / CommandLimiter::kStiffnessRecoveryS + 1e-15);
    previous = lim.stiffness_scale();
    ++ticks;
  }
  EXPECT_GE(ticks, 75);  // from 0.25 to 1 at 0.01 per tick
  EXPECT_LE(ticks, 76);
  EXPECT_NEAR(out.command.force_W.x(), 0.2, 1e-12);
}

TEST(CommandLimiter, TheRenderedStiffnessNeverExceedsTheDevicesOnAnyTick) {
  DeviceLimits l = limits();
  l.max_stiffness_n_per_m = 1200.0;
  CommandLimiter lim(l);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> k(0.0, 6000.0);
  DeviceCommand c;
  c.force_W = {0.0, 0.1, 0.0};
  for (int tick = 0; tick < 20000; ++tick) {
    c.stiffness_n_per_m = tick % 50 < 25 ? k(rng) : 0.0;  // bursts of contact and free motion
    const LimitedCommand out = lim.apply(c, 0.001, 1.0);
    ASSERT_LE(lim.stiffness_scale() * c.stiffness_n_per_m, l.max_stiffness_n_per_m * (1 + 1e-12));
    ASSERT_LE(out.command.stiffness_n_per_m, l.max_stiffness_n_per_m * (1 + 1e-12));
  }
}

}  // namespace
}  // namespace lap::hardware
