#include "hardware/command_limiter.h"

#include <gtest/gtest.h>

#include <limits>

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

}  // namespace
}  // namespace lap::hardware
