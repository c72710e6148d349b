// The passivity observer and controller at a device port (Hannaford & Ryu 2002): against a
// simulated hand (a mass on a spring and damper towards a target, integrated at 1 kHz with the
// device's force held over each tick), a passive rendering is left alone, and an active one — a
// negative damper, a stiff wall sampled 5 ms late — gives the hand no more energy than it took,
// where without the controller it gives ever more.

#include "hardware/passivity_controller.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>

#include "tests/support/simulated_hand.h"

namespace lap::hardware {
namespace {

constexpr double kDt = 0.001;

struct HandRun {
  double delivered_net_max_j = 0.0;  ///< the most the device gave the hand over any prefix
  double peak_speed = 0.0;
  PassivityFigures figures;
};

/// `render(n, x)`: the simulation's force at tick n for the handle at x. The target moves the
/// hand ±5 mm at 2 Hz for `seconds`.
HandRun run(const std::function<Eigen::Vector3d(int, const Eigen::Vector3d&)>& render, bool control,
            double seconds = 2.0) {
  PassivityController pc(PassivityController::kMaxDampingNsPerM, control);
  test::SimulatedHand hand;
  HandRun r;
  double delivered = 0.0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  const int ticks = static_cast<int>(seconds / kDt);
  for (int n = 0; n < ticks; ++n) {
    const Eigen::Vector3d wanted = render(n, hand.x);
    force = pc.apply(hand.x, wanted, kDt, 3.0);
    pc.sent(force);
    const Eigen::Vector3d target(0.005 * std::sin(2.0 * M_PI * 2.0 * n * kDt), 0.0, 0.0);
    delivered += force.dot(hand.step(force, target, kDt).dx);
    if (!std::isfinite(delivered) || hand.v.norm() > 100.0) break;
    r.delivered_net_max_j = std::max(r.delivered_net_max_j, delivered);
    r.peak_speed = std::max(r.peak_speed, hand.v.norm());
  }
  r.figures = pc.figures();
  return r;
}

TEST(PassivityController, LeavesAPassiveRenderingAlone) {
  // A damper on the handle's motion over the last tick: it only ever takes energy.
  const HandRun r = run(
      [last = Eigen::Vector3d(Eigen::Vector3d::Zero())](int, const Eigen::Vector3d& x) mutable {
        const Eigen::Vector3d f = -2.0 * (x - last) / kDt;
        last = x;
        return f;
      },
      true);
  EXPECT_EQ(r.figures.active_ticks, 0);
  EXPECT_EQ(r.figures.dissipated_j, 0.0);
  EXPECT_GT(r.figures.observed_j, 0.0);
  EXPECT_GE(r.figures.lowest_j, 0.0);
}

// A negative damper of 1 N s/m: an energy source. Without the controller it pumps energy into
// the hand; with it the device gives no more than it took, within one tick's prediction.
TEST(PassivityController, BoundsAnActiveRenderingsEnergy) {
  auto negative_damper = [] {
    return
        [last = Eigen::Vector3d(Eigen::Vector3d::Zero())](int, const Eigen::Vector3d& x) mutable {
          const Eigen::Vector3d f = 1.0 * (x - last) / kDt;
          last = x;
          return f;
        };
  };
  const HandRun off = run(negative_damper(), false);
  const HandRun on = run(negative_damper(), true);
  EXPECT_GT(off.delivered_net_max_j, 1e-3);  // it really is active
  EXPECT_LT(on.delivered_net_max_j, 1e-5);
  EXPECT_GT(on.figures.lowest_j, -1e-5);
  EXPECT_GT(on.figures.active_ticks, 0);
  EXPECT_GT(on.figures.dissipated_j, 0.0);
  std::printf(
      "[ passivity ] negative damper 1 N s/m, 2 s: most energy given to the hand beyond what it "
      "took, over any prefix: %.3e J without the controller, %.3e J with it\n",
      off.delivered_net_max_j, on.delivered_net_max_j);
}

// A wall of 3000 N/m at x > 1 mm whose force is computed from the handle as it was 5 ms before:
// a stiff spring against stale positions, which pumps the hand without the controller.
TEST(PassivityController, TamesAStiffWallSampledLate) {
  auto wall = [] {
    return [history = std::array<double, 5>{}](int n, const Eigen::Vector3d& x) mutable {
      double& slot = history[static_cast<size_t>(n) % history.size()];
      const double old = slot;  // 5 ticks ago
      slot = x.x();
      const double depth = old - 0.001;
      return Eigen::Vector3d(depth > 0.0 ? -3000.0 * depth : 0.0, 0.0, 0.0);
    };
  };
  const HandRun off = run(wall(), false, 4.0);
  const HandRun on = run(wall(), true, 4.0);
  EXPECT_GT(off.delivered_net_max_j, 1e-3);
  // Within what the damper's and the force's bounds let it take back on a tick, against a wall
  // that pushes 3 N within a millimetre: a hundredth of the excess without it.
  EXPECT_LT(on.delivered_net_max_j, 2e-3);
  EXPECT_LT(on.delivered_net_max_j, 0.01 * off.delivered_net_max_j);
  EXPECT_LT(on.peak_speed, off.peak_speed);
  std::printf(
      "[ passivity ] wall 3000 N/m sampled 5 ms late, 4 s: most energy given beyond taken over "
      "any prefix %.3e J without, %.3e J with (peak hand speed %.3f / %.3f m/s)\n",
      off.delivered_net_max_j, on.delivered_net_max_j, off.peak_speed, on.peak_speed);
}

TEST(PassivityController, StaysWithinTheForceBoundAndPassesBadInputThrough) {
  PassivityController pc;
  // First tick: nothing observed yet.
  EXPECT_EQ(pc.apply(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 0), kDt, 3.0),
            Eigen::Vector3d(1, 0, 0));
  pc.sent(Eigen::Vector3d(2.9, 0, 0));
  // The handle moved 1 mm along the force: 2.9 mJ given; the damper would want far more than
  // the bound allows.
  const Eigen::Vector3d f =
      pc.apply(Eigen::Vector3d(0.001, 0, 0), Eigen::Vector3d(2.9, 0, 0), kDt, 3.0);
  EXPECT_LE(f.norm(), 3.0 + 1e-12);
  EXPECT_LT(f.x(), 2.9);
  EXPECT_NEAR(pc.figures().observed_j, -2.9e-3, 1e-12);
  const Eigen::Vector3d nan(NAN, 0, 0);
  EXPECT_TRUE(std::isnan(pc.apply(Eigen::Vector3d::Zero(), nan, kDt, 3.0).x()));
  pc.sent(nan);  // stored as zero
  EXPECT_EQ(pc.apply(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 0), kDt, 3.0),
            Eigen::Vector3d(1, 0, 0));  // after a gap: observes afresh
}

}  // namespace
}  // namespace lap::hardware
