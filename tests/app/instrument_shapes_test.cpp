// The instruments' shapes (app/instrument_shapes.h): closed where they should be, wound so that
// each triangle faces the way its vertices' normals say (lit from outside), within the shaft's
// radius, the jaws as long as the scenario says, two closed jaws making up the shaft's round
// section; each kind distinct (a Maryland dissector's jaws curve, both the same way in the world).

#include "app/instrument_shapes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lap::app {
namespace {

// Every triangle's winding agrees with its vertices' normals.
void expect_outward(const haptics::TriangleMesh& m, const std::string& what) {
  ASSERT_EQ(m.normals.size(), m.positions.size()) << what;
  int disagree = 0;
  for (int32_t t = 0; t < m.triangle_count(); ++t) {
    const Eigen::Vector3d n = m.triangle_cross(t);
    if (n.norm() < 1e-14) continue;  // a degenerate one where a section shrinks to the tip
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const int32_t v : m.triangles[static_cast<size_t>(t)]) mean += m.normals[v];
    if (n.dot(mean) <= 0.0) ++disagree;
  }
  EXPECT_EQ(disagree, 0) << what;
}

TEST(InstrumentShapes, ShaftAndClevisAreRoundAndOutward) {
  const double r = 0.0025;
  const haptics::TriangleMesh shaft = make_shaft(r, 0.36);
  expect_outward(shaft, "shaft");
  for (const Eigen::Vector3d& p : shaft.positions) {
    EXPECT_NEAR(std::hypot(p.x(), p.z()), r, 1e-12);
    EXPECT_GE(p.y(), kClevisLengthM - 1e-12);
    EXPECT_LE(p.y(), 0.36 + 1e-12);
  }
  const haptics::TriangleMesh clevis = make_clevis(r);
  expect_outward(clevis, "clevis");
  for (const Eigen::Vector3d& p : clevis.positions) {
    EXPECT_LE(std::hypot(p.x(), p.z()), r + 1e-12);
    EXPECT_LE(p.y(), kClevisLengthM + 1e-12);
  }
}

// A probe (point or ray): a rod from its tip, ending in a ball of its radius that encloses the
// ball's volume (within the tessellation's loss, under 10 % at 20 sides), wound outward.
TEST(InstrumentShapes, AProbeIsARodWithABallTip) {
  EXPECT_EQ(instrument_kind("probe"), InstrumentKind::kProbe);
  EXPECT_EQ(instrument_kind("ray-probe"), InstrumentKind::kProbe);
  EXPECT_EQ(instrument_kind("grasper"), InstrumentKind::kGrasper);
  const double r = 0.002;
  const haptics::TriangleMesh tip = make_probe_tip(r);
  expect_outward(tip, "probe tip");
  for (const Eigen::Vector3d& p : tip.positions) EXPECT_NEAR(p.norm(), r, 1e-12);
  const double ball = 4.0 / 3.0 * M_PI * r * r * r;
  EXPECT_GT(tip.signed_volume(), 0.9 * ball);
  EXPECT_LT(tip.signed_volume(), ball);
  const haptics::TriangleMesh rod = make_shaft(r, 0.3, 0.0);
  double lowest = 1.0;
  for (const Eigen::Vector3d& p : rod.positions) lowest = std::min(lowest, p.y());
  EXPECT_NEAR(lowest, 0.0, 1e-12);  // from the tip, no clevis between
}

TEST(InstrumentShapes, JawsOfEveryKindFitTheShaftAndReachTheirLength) {
  const double r = 0.0025;
  const double length = 0.02;
  for (const char* name : {"grasper", "dissector", "clip-applier", "scissors"}) {
    const InstrumentKind kind = instrument_kind(name);
    for (const int side : {1, -1}) {
      const haptics::TriangleMesh jaw = make_jaw(kind, length, r, side);
      expect_outward(jaw, std::string(name) + " jaw " + std::to_string(side));
      double tip = 0.0;
      for (const Eigen::Vector3d& p : jaw.positions) {
        // From the hinge down −y, never past the face towards the other jaw by more than a
        // loaded clip's 0.3 mm, its back within the radius.
        EXPECT_LE(p.y(), 1e-12) << name;
        EXPECT_GE(p.x(), -0.0003 - 1e-12) << name;
        EXPECT_LE(p.x(), r + 1e-12) << name;
        tip = std::min(tip, p.y());
      }
      EXPECT_NEAR(tip, -length, 1e-12) << name;
    }
  }
  EXPECT_EQ(instrument_kind("something else"), InstrumentKind::kGrasper);
}

// Closed, a grasper's two jaws (jaw 1 mirrored across the face: its frame's x is the other
// way) fill the shaft's section: at their roots every point lies within the radius and the
// section's width is nearly the shaft's diameter.
TEST(InstrumentShapes, ClosedJawsMakeUpTheShaftsSection) {
  const double r = 0.0025;
  const haptics::TriangleMesh jaw = make_jaw(InstrumentKind::kGrasper, 0.02, r, 1);
  double widest = 0.0;
  double deepest = 0.0;
  for (const Eigen::Vector3d& p : jaw.positions) {
    if (p.y() < -1e-9) continue;  // the root section only
    widest = std::max(widest, std::abs(p.z()));
    deepest = std::max(deepest, p.x());
    EXPECT_LE(std::hypot(p.x(), p.z()), r + 1e-12);
  }
  EXPECT_GT(widest, 0.85 * r);
  EXPECT_GT(deepest, 0.6 * r);
}

// The dissector's jaws curve sideways (z), each by the same amount, to opposite sides of its own
// frame: in the world (jaw 1's frame has z the other way) both curve the same way.
TEST(InstrumentShapes, ADissectorsJawsCurveTogether) {
  auto tip_z = [](int side) {
    const haptics::TriangleMesh jaw = make_jaw(InstrumentKind::kDissector, 0.02, 0.0025, side);
    double z = 0.0;
    double y = 0.0;
    for (const Eigen::Vector3d& p : jaw.positions) {
      if (p.y() < y) {
        y = p.y();
        z = p.z();
      }
    }
    return z;
  };
  EXPECT_GT(tip_z(1), 0.003);
  EXPECT_NEAR(tip_z(-1), -tip_z(1), 1e-12);
  const haptics::TriangleMesh grasper = make_jaw(InstrumentKind::kGrasper, 0.02, 0.0025, 1);
  for (const Eigen::Vector3d& p : grasper.positions) EXPECT_LE(std::abs(p.z()), 0.0025);
}

}  // namespace
}  // namespace lap::app
