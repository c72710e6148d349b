// The incision's rim (models/incision_rim.h): the crossing of the catheter through the duct's
// wall is found where a brute-force march along the catheter finds it, only inside the
// incision; held there, the catheter is pulled to the incision's centre across it and slides
// along it as freely as without the rim.

#include "models/incision_rim.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace lap::models {
namespace {

constexpr double kDt = 0.005;

// A duct along the world's z (duct frame = world), 35 mm long, its wall's mid-surface 2 mm
// from the axis; the incision at mid-length on the +y side, 3 mm along, 2 mm around.
IncisionRim rim() {
  IncisionRim r;
  r.length_m = 0.035;
  r.mid_radius_m = 0.002;
  r.z_m = 0.0175;
  r.angle_rad = 0.5 * std::numbers::pi;
  r.half_length_m = 0.0015;
  r.half_width_m = 0.001;
  return r;
}

// The incision's centre on the mid-surface, shifted along the axis by dz.
Eigen::Vector3d centre(const IncisionRim& r, double dz = 0.0) {
  return {0.0, r.mid_radius_m, r.z_m + dz};
}

// A catheter that runs along `dir` and passes through `through` at particle 20 + 0.4 of a
// segment (its tip, the last particle, inside the lumen when dir points in).
CatheterState threaded(const CatheterModel& m, const Eigen::Vector3d& through,
                       const Eigen::Vector3d& dir) {
  return CatheterState(m, through - 20.4 * m.rest_length_m() * dir, dir);
}

// Where the centre line first crosses the mid-surface, marching in 1e-5 steps of a segment.
double brute_force_crossing_s(const IncisionRim& r, const CatheterState& c) {
  const auto radius = [&](const Eigen::Vector3d& p) { return p.head<2>().norm() - r.mid_radius_m; };
  for (size_t i = 0; i + 1 < c.positions.size(); ++i) {
    const Eigen::Vector3d& a = c.positions[i];
    const Eigen::Vector3d& b = c.positions[i + 1];
    constexpr int kSteps = 100000;
    for (int k = 0; k < kSteps; ++k) {
      const double t0 = static_cast<double>(k) / kSteps;
      const double t1 = static_cast<double>(k + 1) / kSteps;
      if ((radius(a + t0 * (b - a)) < 0.0) != (radius(a + t1 * (b - a)) < 0.0)) {
        return static_cast<double>(i) + 0.5 * (t0 + t1);
      }
    }
  }
  return -1.0;
}

Eigen::Vector3d inward(double slant_deg) {
  // Down through the +y wall at slant_deg to the axis, towards +z.
  const double a = slant_deg * std::numbers::pi / 180.0;
  return Eigen::Vector3d(0.0, -std::sin(a), std::cos(a));
}

TEST(IncisionRim, FindsTheCrossingWhereAMarchAlongTheCatheterFindsIt) {
  const CatheterModel m = CatheterModel::build({});
  const IncisionRim r = rim();
  for (const double slant : {20.0, 35.0, 60.0, 90.0}) {
    for (const double dz : {-0.001, 0.0, 0.0008}) {
      const CatheterState c = threaded(m, centre(r, dz), inward(slant));
      const RimCrossing x = find_rim_crossing(r, c.positions);
      ASSERT_GE(x.segment, 0) << slant << " deg, dz " << dz;
      const double s = brute_force_crossing_s(r, c);
      EXPECT_NEAR(x.segment + x.t, s, 2e-5) << slant << " deg, dz " << dz;
      EXPECT_NEAR(x.point_D.z(), r.z_m + dz, 1e-9);
      EXPECT_NEAR(x.point_D.head<2>().norm(), r.mid_radius_m, 1e-12);
    }
  }
}

TEST(IncisionRim, ACrossingBesideTheIncisionIsNotHeld) {
  const CatheterModel m = CatheterModel::build({});
  const IncisionRim r = rim();
  // 2 mm beyond its end along the axis, and round the duct at 90 degrees from it.
  CatheterState along = threaded(m, centre(r, 0.0035), inward(35.0));
  EXPECT_LT(find_rim_crossing(r, along.positions).segment, 0);
  EXPECT_FALSE(hold_at_incision(r, m, &along));
  EXPECT_EQ(along.anchor_count, 0);
  EXPECT_EQ(along.friction_count, 0);
  const Eigen::Vector3d side(r.mid_radius_m, 0.0, r.z_m);
  CatheterState around = threaded(m, side, Eigen::Vector3d(-0.5, 0.0, 0.866));
  EXPECT_LT(find_rim_crossing(r, around.positions).segment, 0);
  EXPECT_FALSE(hold_at_incision(r, m, &around));
}

// Steps a free catheter (nothing fixed) for `seconds`, its rim hold set afresh each step when
// `with_rim`, every particle pushed by `force_each_n`.
void run(const CatheterModel& m, const IncisionRim& r, bool with_rim,
         const Eigen::Vector3d& force_each_n, double seconds, CatheterState* c) {
  const int steps = static_cast<int>(std::lround(seconds / kDt));
  for (int k = 0; k < steps; ++k) {
    clear_anchors(c);
    if (with_rim) {
      EXPECT_TRUE(hold_at_incision(r, m, c)) << "step " << k;
    }
    for (Eigen::Vector3d& f : c->external_force) f = force_each_n;
    ASSERT_TRUE(step_catheter(m, c, kDt));
  }
}

TEST(IncisionRim, PullsTheCatheterToTheIncisionsCentreAcrossIt) {
  // Threaded 1 mm from the centre along the axis and 0.6 mm round it (inside the hole): held
  // by the rim alone, the crossing comes to the centre.
  const CatheterModel m = CatheterModel::build({});
  IncisionRim r = rim();
  const Eigen::Vector3d off(0.0006, r.mid_radius_m, r.z_m + 0.001);
  CatheterState c = threaded(m, off, inward(35.0));
  run(m, r, true, Eigen::Vector3d::Zero(), 4.0, &c);
  const RimCrossing x = find_rim_crossing(r, c.positions);
  ASSERT_GE(x.segment, 0);
  // Across the catheter the crossing is at the centre; along it the catheter is free, and a
  // crossing off centre along the catheter is still a crossing through the centre's line.
  const Eigen::Vector3d axis = inward(35.0);
  const Eigen::Vector3d miss = x.point_D - centre(r);
  EXPECT_LT((miss - miss.dot(axis) * axis).norm(), 1e-4) << miss.transpose();
  EXPECT_GT((off - centre(r)).norm(), 1e-3);  // it had that far to come
}

TEST(IncisionRim, LetsTheCatheterSlideThroughAsFreelyAsWithoutIt) {
  // Pushed along itself, threaded through the centre: the same travel with and without the rim
  // (it holds across only), and its friction group reports no axial force.
  const CatheterModel m = CatheterModel::build({});
  const IncisionRim r = rim();
  const Eigen::Vector3d axis = inward(35.0);
  const Eigen::Vector3d push = 2e-6 * axis;  // per particle: 0.13 mN in all (about 1 cm in 0.5 s)
  CatheterState held = threaded(m, centre(r), axis);
  CatheterState free = held;
  run(m, r, true, push, 0.5, &held);
  run(m, r, false, push, 0.5, &free);
  const double travel_free = (free.positions[0] - threaded(m, centre(r), axis).positions[0]).norm();
  const double travel_held = (held.positions[0] - threaded(m, centre(r), axis).positions[0]).norm();
  EXPECT_GT(travel_free, 0.002);  // it went some way
  EXPECT_NEAR(travel_held, travel_free, 0.01 * travel_free);
  ASSERT_EQ(held.friction_count, 1);
  EXPECT_TRUE(held.friction_results[0].slipped);
  EXPECT_EQ(held.friction_results[0].axial_force_n, 0.0);
}

}  // namespace
}  // namespace lap::models
