// Stick-slip friction (§6.2) through the point proxy on a flat face: the thresholds against
// mu_s Fn and mu_d Fn, a force-driven device that does or does not slip, stick-slip in a slow
// stroke, coefficient maps, and friction on a moving object.

#include "haptics/friction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/point_proxy.h"
#include "haptics/setup/mesh_generators.h"

namespace lap::haptics {
namespace {

constexpr double kDt = 0.001;
constexpr double kK = 1000.0;     // contact stiffness [N/m]
constexpr double kTop = 0.05;     // the box's top face, y [m]
constexpr double kDepth = 0.002;  // HIP under the face: Fn = 2 N
constexpr double kMuS = 0.5;
constexpr double kMuD = 0.3;
constexpr double kKs = 2000.0;
constexpr double kKd = kKs * kMuD / kMuS;  // proportional to the coefficients, as in §6.2

struct Block {
  MeshDatabase mesh = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 4));
  FrictionModel friction;
  Block() {
    friction.mu_static = kMuS;
    friction.mu_dynamic = kMuD;
    friction.stick_stiffness_n_per_m = kKs;
    friction.slide_stiffness_n_per_m = kKd;
  }
  [[nodiscard]] HapticObject object() const {
    HapticObject o;
    o.mesh = &mesh;
    o.friction = &friction;
    o.law.stiffness_n_per_m = kK;
    o.law.max_force_n = 1e9;
    return o;
  }
};

// Brings the HIP down onto the face at (x, z) to depth kDepth.
PointProxyOutput press(PointProxy& proxy, const HapticObject& o, double x, double z) {
  proxy.reset(Eigen::Vector3d(x, kTop + 0.002, z));
  PointProxyOutput out;
  for (int i = 1; i <= 40; ++i) {
    out =
        proxy.step({&o, 1}, Eigen::Vector3d(x, kTop + 0.002 - (0.002 + kDepth) * i / 40.0, z), kDt);
  }
  return out;
}

TEST(Friction, PositionDrivenStickThenSlipAtMuSFn) {
  const Block b;
  const HapticObject o = b.object();
  PointProxy proxy;
  const PointProxyOutput pressed = press(proxy, o, 0.0, 0.0);
  ASSERT_EQ(pressed.contact_count, 1);
  const double fn = kK * kDepth;
  EXPECT_NEAR(pressed.force_W.y(), fn, 1e-9);
  EXPECT_EQ(proxy.friction_state().phase, FrictionState::Phase::kSticking);
  // Tangential displacement dx: the spring k_s dx holds while it is at most mu_s Fn.
  const double slip_at = kMuS * fn / kKs;  // 0.5 mm
  const double step = slip_at / 100.0;
  int slipped_tick = -1;
  for (int i = 1; i <= 150; ++i) {
    const double dx = step * i;
    const PointProxyOutput out = proxy.step({&o, 1}, Eigen::Vector3d(dx, kTop - kDepth, 0.0), kDt);
    if (proxy.friction_state().phase == FrictionState::Phase::kSticking) {
      EXPECT_NEAR(out.friction_W.x(), -kKs * dx, 1e-9) << "tick " << i;
      EXPECT_LE(out.friction_W.norm(), kMuS * fn + 1e-9);
    } else if (slipped_tick < 0) {
      slipped_tick = i;
      // The sticking point moved to mu_d Fn / k_d behind the IHIP: the force drops to mu_d Fn.
      EXPECT_NEAR(out.friction_W.x(), -kMuD * fn, 1e-9);
    }
  }
  // No slip below mu_s Fn, slip as soon as it is exceeded (tick 100 is exactly at the limit).
  EXPECT_EQ(slipped_tick, 101);
  EXPECT_EQ(proxy.friction_state().stick_to_slide, 1);
}

TEST(Friction, SlidingResistanceAtConstantSpeedIsMuDFn) {
  const Block b;
  const HapticObject o = b.object();
  PointProxy proxy;
  press(proxy, o, -0.02, 0.0);
  // 20 mm/s along a direction in the face plane; the normal force varies with a slow ripple in
  // depth so the test does not depend on Fn being constant.
  const Eigen::Vector3d dir = Eigen::Vector3d(1.0, 0.0, 0.5).normalized();
  double sum_ratio = 0.0;
  int n = 0;
  for (int i = 1; i <= 2000; ++i) {
    const double depth = kDepth * (1.0 + 0.3 * std::sin(i * 0.01));
    const Eigen::Vector3d hip = Eigen::Vector3d(-0.02, kTop - depth, 0.0) + 2e-5 * i * dir;
    const PointProxyOutput out = proxy.step({&o, 1}, hip, kDt);
    ASSERT_EQ(out.contact_count, 1);
    if (i < 200) continue;  // past the initial stick
    const double fn = out.force_W.y();
    const Eigen::Vector3d ft(out.force_W.x(), 0.0, out.force_W.z());
    EXPECT_GT(-ft.dot(dir), 0.99 * ft.norm()) << "resists the motion, tick " << i;
    sum_ratio += ft.norm() / fn;
    ++n;
    EXPECT_EQ(proxy.friction_state().phase, FrictionState::Phase::kSliding) << i;
  }
  const double mean = sum_ratio / n;
  std::printf("sliding: mean |Ft|/Fn = %.5f (mu_d = %.2f)\n", mean, kMuD);
  EXPECT_NEAR(mean, kMuD, 0.05 * kMuD);
  EXPECT_EQ(proxy.friction_state().slide_to_stick, 0);  // stays sliding while the user moves
}

// A device of mass m with viscous loss b, pushed tangentially by the hand with force fa(t), the
// haptic force acting back on it. Returns the HIP's final tangential displacement.
struct DeviceRun {
  double final_dx = 0.0;
  int64_t slips = 0;
  int64_t sticks = 0;
  double peak_friction = 0.0;
  std::vector<double> friction;  // per tick, tangential
};

template <typename HandForce>
DeviceRun drive(const HapticObject& o, int ticks, double loss, const HandForce& hand) {
  constexpr double kMass = 0.1;
  PointProxy proxy;
  PointProxyOutput out = press(proxy, o, 0.0, 0.0);
  double x = 0.0;
  double v = 0.0;
  DeviceRun r;
  for (int i = 1; i <= ticks; ++i) {
    const double f = hand(i * kDt, x) + out.force_W.x() - loss * v;
    v += kDt * f / kMass;  // semi-implicit Euler
    x += kDt * v;
    out = proxy.step({&o, 1}, Eigen::Vector3d(x, kTop - kDepth, 0.0), kDt);
    r.friction.push_back(-out.friction_W.x());
    r.peak_friction = std::max(r.peak_friction, -out.friction_W.x());
  }
  r.final_dx = x;
  r.slips = proxy.friction_state().stick_to_slide;
  r.sticks = proxy.friction_state().slide_to_stick;
  return r;
}

TEST(Friction, ForceDrivenDeviceHoldsBelowMuSFnAndSlipsAbove) {
  const Block b;
  const HapticObject o = b.object();
  const double fn = kK * kDepth;
  // The hand's force ramps up over 1 s (quasi-static), then holds.
  const auto ramp_to = [](double target) {
    return [target](double t, double /*x*/) { return target * std::min(1.0, t); };
  };
  // A well-damped hand (20 N s/m) so the ramp does not overshoot.
  const DeviceRun below = drive(o, 3000, 20.0, ramp_to(0.9 * kMuS * fn));
  EXPECT_EQ(below.slips, 0);
  EXPECT_NEAR(below.final_dx, 0.9 * kMuS * fn / kKs, 1e-6);  // held by the sticking spring
  const DeviceRun above = drive(o, 1500, 20.0, ramp_to(1.1 * kMuS * fn));
  EXPECT_GE(above.slips, 1);
  // Slips at t = 1/1.1 s; then fa - mu_d Fn = 0.5 N against 20 N s/m: 25 mm/s for ~0.6 s.
  EXPECT_GT(above.final_dx, 0.005);
  EXPECT_LT(above.final_dx, 0.03);
  std::printf("force-driven: 0.9 mu_s Fn -> %.3f mm, 1.1 mu_s Fn -> %.1f mm\n",
              below.final_dx * 1e3, above.final_dx * 1e3);
}

TEST(Friction, SlowStrokeThroughTheHandSpringSticksAndSlips) {
  const Block b;
  const HapticObject o = b.object();
  const double fn = kK * kDepth;
  // The hand moves at 5 mm/s and drags the device through a soft spring (the fingers).
  const auto hand = [](double t, double x) { return 200.0 * (0.005 * t - x); };
  const DeviceRun r = drive(o, 4000, 1.0, hand);
  std::printf("slow stroke: %lld slips, %lld re-sticks, peak friction %.3f N (mu_s Fn %.3f)\n",
              static_cast<long long>(r.slips), static_cast<long long>(r.sticks), r.peak_friction,
              kMuS * fn);
  EXPECT_GE(r.slips, 3);
  EXPECT_GE(r.sticks, 3);
  // The sawtooth: friction climbs to mu_s Fn while sticking, drops to mu_d Fn on slipping.
  EXPECT_NEAR(r.peak_friction, kMuS * fn, 0.05 * kMuS * fn);
  int drops = 0;
  for (size_t i = 1; i < r.friction.size(); ++i) {
    if (r.friction[i - 1] > 0.95 * kMuS * fn && r.friction[i] < 1.05 * kMuD * fn) ++drops;
  }
  EXPECT_GE(drops, 3);
}

TEST(Friction, PeriodicMapVariesTheResistanceWithThePeriod) {
  Block b;
  b.friction.map.kind = FrictionCoefficientMap::Kind::kPeriodic;
  b.friction.map.period_m = 0.004;
  b.friction.map.amplitude = 0.5;
  const HapticObject o = b.object();
  PointProxy proxy;
  press(proxy, o, -0.01, 0.0);
  double lo = 1e9;
  double hi = 0.0;
  for (int i = 1; i <= 1000; ++i) {
    const Eigen::Vector3d hip(-0.01 + 2e-5 * i, kTop - kDepth, 0.0);
    const PointProxyOutput out = proxy.step({&o, 1}, hip, kDt);
    if (i < 100 || proxy.friction_state().phase != FrictionState::Phase::kSliding) continue;
    const double ratio = out.friction_W.norm() / out.force_W.y();
    const double expected = kMuD * b.friction.map.factor(proxy.ihip());  // object = world
    EXPECT_NEAR(ratio, expected, 1e-6) << "tick " << i;
    lo = std::min(lo, ratio);
    hi = std::max(hi, ratio);
  }
  // sin over x (y, z fixed) swings the factor by +-amplitude/3 around 1 + sin(2 pi y/L)/3.
  EXPECT_GT(hi - lo, 0.9 * kMuD * 2.0 * 0.5 / 3.0);
}

TEST(Friction, RandomMapHasTheRequestedMeanAndSpread) {
  FrictionCoefficientMap map;
  map.kind = FrictionCoefficientMap::Kind::kRandom;
  map.grain_m = 0.0005;
  map.relative_std_dev = 0.2;
  double sum = 0.0;
  double sum2 = 0.0;
  const int n = 40000;
  for (int i = 0; i < n; ++i) {
    // One sample per grain, along a diagonal line so the grains differ in every coordinate.
    const double s = (i + 0.5) * map.grain_m;
    const double f = map.factor(Eigen::Vector3d(s, 0.37 * s, -0.61 * s));
    sum += f;
    sum2 += f * f;
  }
  const double mean = sum / n;
  const double sd = std::sqrt(sum2 / n - mean * mean);
  std::printf("random map: mean %.4f sd %.4f (asked 1, 0.2)\n", mean, sd);
  EXPECT_NEAR(mean, 1.0, 0.01);
  EXPECT_NEAR(sd, 0.2, 0.01);
  // Within one grain the factor is constant; reproducible for a seed, different across seeds.
  EXPECT_EQ(map.factor(Eigen::Vector3d(1e-4, 1e-4, 1e-4)),
            map.factor(Eigen::Vector3d(2e-4, 3e-4, 4e-4)));
  FrictionCoefficientMap other = map;
  other.seed = 2;
  int same = 0;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d p(i * 0.001, 0.0, 0.0);
    same += map.factor(p) == other.factor(p) ? 1 : 0;
  }
  EXPECT_LT(same, 5);
}

TEST(Friction, StickingPointMovesWithAMovingObject) {
  const Block b;
  HapticObject o = b.object();
  PointProxy proxy;
  press(proxy, o, 0.0, 0.0);
  // The block slides 0.2 mm along x under a still HIP: the sticking point goes with it, so the
  // friction force drags the HIP along +x (k_s times the relative displacement).
  for (int i = 1; i <= 20; ++i) {
    o.prev_pose_WO = o.pose_WO;
    o.pose_WO.translation().x() = 1e-5 * i;
    const PointProxyOutput out = proxy.step({&o, 1}, Eigen::Vector3d(0, kTop - kDepth, 0), kDt);
    ASSERT_EQ(out.contact_count, 1);
    EXPECT_NEAR(out.friction_W.x(), kKs * 1e-5 * i, 1e-9);
  }
}

TEST(Friction, ModelProblemsAreReported) {
  FrictionModel m;
  m.mu_static = 0.2;
  m.mu_dynamic = 0.3;
  EXPECT_STRNE(m.problem(), "");
  m.mu_dynamic = 0.1;
  m.stick_stiffness_n_per_m = 100.0;
  m.slide_stiffness_n_per_m = 200.0;
  EXPECT_STRNE(m.problem(), "");
  m.slide_stiffness_n_per_m = 50.0;
  EXPECT_STREQ(m.problem(), "");
  m.map.kind = FrictionCoefficientMap::Kind::kPeriodic;
  m.map.period_m = 0.0;
  EXPECT_STRNE(m.problem(), "");
}

}  // namespace
}  // namespace lap::haptics
