// Surface properties at the segment proxy's contacts (thesis chapter 6 at the ray-based probe),
// against analytic answers: Coulomb stick-slip on a plane (the tip, and the shaft lying flat),
// a force continuous when sliding stops, the shaded force's turn on a tessellated cylinder within
// the tessellation bound, and a texture's force along its height gradient (eq. 6-2/6-4).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ostream>
#include <vector>

#include "haptics/friction.h"
#include "haptics/mesh_database.h"
#include "haptics/procedural_textures.h"
#include "haptics/segment_database.h"
#include "haptics/segment_proxy.h"
#include "haptics/setup/mesh_generators.h"
#include "haptics/shading_normals.h"
#include "tests/test_support.h"

namespace lap::haptics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 0.001;
constexpr double kK = 1000.0;     // contact stiffness [N/m]
constexpr double kTop = 0.05;     // the box's top face, y [m]
constexpr double kDepth = 0.002;  // pressed 2 mm in: Fn = 2 N at the tip, 4 N lying
constexpr double kMuS = 0.5;
constexpr double kMuD = 0.3;
constexpr double kKs = 2000.0;
constexpr double kKd = kKs * kMuD / kMuS;  // proportional to the coefficients (§6.2)

using test::angle_between;

struct Body {
  MeshDatabase mesh;
  SegmentDatabase segments;
  explicit Body(const TriangleMesh& m)
      : mesh(MeshDatabase::build(m)), segments(SegmentDatabase::build(mesh)) {}
  [[nodiscard]] HapticObject object() const {
    HapticObject o;
    o.mesh = &mesh;
    o.segments = &segments;
    o.law.stiffness_n_per_m = kK;
    o.law.max_force_n = 1e9;  // the analytic answers are for the unclamped law
    return o;
  }
};

// A probe of two poses on the box's top: its tip pressing (a point–polygon contact at end a),
// or lying flat along z (a segment–face contact at its middle). at(x, depth) gives its ends
// with the contact point at (x, kTop - depth, 0).
enum class Pose { kTip, kLying };
// The normal stiffness the pose feels under the passive response (haptics/segment_proxy.h,
// "Response"): the spring of k at each end between the ideal and the virtual probe, so k for the
// tip alone and 2 k lying flat (both ends pressed by the depth).
double normal_stiffness(Pose pose, double k) { return pose == Pose::kTip ? k : 2.0 * k; }
// The parameter's name in the tests' listing (gtest would print the enum's bytes).
void PrintTo(Pose pose, std::ostream* os) { *os << (pose == Pose::kTip ? "tip" : "lying"); }
void probe_at(Pose pose, double x, double depth, Eigen::Vector3d* a, Eigen::Vector3d* b) {
  const Eigen::Vector3d p(x, kTop - depth, 0.0);
  if (pose == Pose::kTip) {
    *a = p;
    *b = p + Eigen::Vector3d(0.03, 0.08, 0.02);  // the shaft leans away, in free space
  } else {
    *a = p - Eigen::Vector3d(0.0, 0.0, 0.02);
    *b = p + Eigen::Vector3d(0.0, 0.0, 0.02);
  }
}

// Brings the probe down from 2 mm above to `depth` under the top at x.
SegmentProxyOutput press(SegmentProxy& proxy, const HapticObject& o, Pose pose, double x,
                         double depth) {
  Eigen::Vector3d a;
  Eigen::Vector3d b;
  probe_at(pose, x, -0.002, &a, &b);
  proxy.reset(a, b);
  SegmentProxyOutput out;
  for (int i = 1; i <= 40; ++i) {
    probe_at(pose, x, -0.002 + (0.002 + depth) * i / 40.0, &a, &b);
    out = proxy.step({&o, 1}, a, b, kDt);
  }
  return out;
}

struct FrictionBlock : Body {
  FrictionModel friction;
  FrictionBlock() : Body(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 4)) {
    friction.mu_static = kMuS;
    friction.mu_dynamic = kMuD;
    friction.stick_stiffness_n_per_m = kKs;
    friction.slide_stiffness_n_per_m = kKd;
  }
  [[nodiscard]] HapticObject object() const {
    HapticObject o = Body::object();
    o.friction = &friction;
    return o;
  }
};

class SegmentFriction : public ::testing::TestWithParam<Pose> {};

// Position-driven: the probe pressed with Fn, then moved sideways. The friction is the sticking
// spring k_s dx up to mu_s Fn, then drops to mu_d Fn and stays there while the probe slides.
TEST_P(SegmentFriction, StickThenSlipAtMuSFnThenSlideAtMuDFn) {
  const FrictionBlock block;
  const HapticObject o = block.object();
  SegmentProxy proxy;
  const SegmentProxyOutput pressed = press(proxy, o, GetParam(), 0.0, kDepth);
  ASSERT_EQ(pressed.contact_count, 1);
  EXPECT_EQ(proxy.contacts()[0].kind, GetParam() == Pose::kTip ? SegmentContactKind::kPointPolygon
                                                               : SegmentContactKind::kSegmentFace);
  const double fn = normal_stiffness(GetParam(), kK) * kDepth;
  EXPECT_NEAR(pressed.force_W.y(), fn, 1e-9);
  EXPECT_NEAR(pressed.force_W.x(), 0.0, 1e-9);
  const double slip_at = kMuS * fn / kKs;  // 0.5 mm at the tip, 1 mm lying
  const double step = slip_at / 100.0;
  int slipped_tick = -1;
  for (int i = 1; i <= 2000; ++i) {
    const double dx = step * i;
    Eigen::Vector3d a;
    Eigen::Vector3d b;
    probe_at(GetParam(), dx, kDepth, &a, &b);
    const SegmentProxyOutput out = proxy.step({&o, 1}, a, b, kDt);
    ASSERT_EQ(out.contact_count, 1) << i;
    EXPECT_NEAR(out.force_W.y(), fn, 1e-9) << "friction is tangential, tick " << i;
    const FrictionState::Phase phase = proxy.contacts()[0].friction_phase;
    if (phase == FrictionState::Phase::kSticking) {
      ASSERT_LT(slipped_tick, 0) << "sticks again while still moving, tick " << i;
      EXPECT_NEAR(out.friction_W.x(), -kKs * dx, 1e-9) << i;
      EXPECT_LE(out.friction_W.norm(), kMuS * fn + 1e-9);
    } else {
      ASSERT_EQ(phase, FrictionState::Phase::kSliding) << i;
      if (slipped_tick < 0) slipped_tick = i;
      // Sliding: the sticking point follows at mu_d Fn / k_d: the resistance is mu_d Fn.
      EXPECT_NEAR(out.friction_W.x(), -kMuD * fn, 1e-9) << i;
    }
    EXPECT_NEAR(out.friction_W.z(), 0.0, 1e-9);
  }
  // Tick 100 is exactly at the limit: it slips there or at the next, as rounding falls (lying,
  // the normal force comes out 4e-12 N under 2 k d).
  EXPECT_GE(slipped_tick, 100);
  EXPECT_LE(slipped_tick, 101);
  EXPECT_EQ(proxy.stats().stick_to_slide, 1);
  EXPECT_EQ(proxy.stats().slide_to_stick, 0);
}

// When the hand stops, friction goes from the sliding spring to the sticking spring without a
// step in force (a step would hand the user ½(k_s − k_d)x² of energy from nothing), then holds;
// moving on, it builds up from there and slips again at mu_s Fn.
TEST_P(SegmentFriction, TheForceIsContinuousWhenSlidingStopsAndStarts) {
  const FrictionBlock block;
  const HapticObject o = block.object();
  SegmentProxy proxy;
  press(proxy, o, GetParam(), 0.0, kDepth);
  const double fn = normal_stiffness(GetParam(), kK) * kDepth;
  const double speed = 0.02;  // m/s
  double x = 0.0;
  std::vector<double> force;  // tangential, per tick
  std::vector<FrictionState::Phase> phase;
  std::vector<double> xs;
  for (int i = 1; i <= 900; ++i) {
    const bool moving = i <= 300 || i > 600;  // slide, stop for 0.3 s, slide on
    if (moving) x += speed * kDt;
    Eigen::Vector3d a;
    Eigen::Vector3d b;
    probe_at(GetParam(), x, kDepth, &a, &b);
    const SegmentProxyOutput out = proxy.step({&o, 1}, a, b, kDt);
    ASSERT_EQ(out.contact_count, 1) << i;
    force.push_back(-out.friction_W.x());
    phase.push_back(proxy.contacts()[0].friction_phase);
    xs.push_back(x);
  }
  EXPECT_NEAR(force[299], kMuD * fn, 1e-9);  // sliding just before the stop
  EXPECT_EQ(phase[299], FrictionState::Phase::kSliding);
  // Stopped: sticks (on the first still tick, or the next where rounding left the sliding
  // spring a hair over mu_d Fn).
  EXPECT_EQ(phase[301], FrictionState::Phase::kSticking);
  for (int i = 300; i < 600; ++i) {
    // Held still: the force stays exactly where sliding left it (no step up to k_s / k_d of it).
    EXPECT_NEAR(force[i], kMuD * fn, 1e-9) << "tick " << i + 1;
  }
  // Moving on: it grows by k_s per metre from mu_d Fn until it slips at mu_s Fn.
  int slipped = -1;
  for (int i = 600; i < 900 && slipped < 0; ++i) {
    if (phase[i] == FrictionState::Phase::kSliding) {
      slipped = i;
      break;
    }
    EXPECT_NEAR(force[i], kMuD * fn + kKs * (xs[i] - xs[599]), 1e-9) << i + 1;
  }
  ASSERT_GT(slipped, 600);
  EXPECT_GE(force[slipped - 1] + kKs * speed * kDt, kMuS * fn - 1e-9);
  EXPECT_EQ(proxy.stats().slide_to_stick, 1);
  EXPECT_EQ(proxy.stats().stick_to_slide, 2);
}

INSTANTIATE_TEST_SUITE_P(TipAndLying, SegmentFriction, ::testing::Values(Pose::kTip, Pose::kLying),
                         [](const auto& info) {
                           return std::string(info.param == Pose::kTip ? "Tip" : "Lying");
                         });

// An object without friction adds none: the probe moved sideways feels no tangential force.
TEST(SegmentFrictionScope, AFrictionlessObjectAddsNoFriction) {
  const FrictionBlock block;
  HapticObject o = block.object();
  o.friction = nullptr;
  SegmentProxy proxy;
  press(proxy, o, Pose::kTip, 0.0, kDepth);
  Eigen::Vector3d a;
  Eigen::Vector3d b;
  probe_at(Pose::kTip, 0.0003, kDepth, &a, &b);
  const SegmentProxyOutput out = proxy.step({&o, 1}, a, b, kDt);
  EXPECT_EQ(out.friction_W, Eigen::Vector3d::Zero());
  EXPECT_NEAR(out.force_W.x(), 0.0, 1e-12);
}

// An object whose force law is clamped to zero (a session mutes the duct this way for a tool that
// holds it: the grasp's springs are that contact) is still an obstacle — the probe stays on its
// surface — but pushes nothing, and its friction (on a zero normal force) holds nothing either.
TEST(SegmentFrictionScope, AMutedObjectStopsTheProbeAndPushesNothing) {
  const FrictionBlock block;
  HapticObject o = block.object();
  o.law.max_force_n = 0.0;
  for (const Pose pose : {Pose::kTip, Pose::kLying}) {
    SegmentProxy proxy;
    SegmentProxyOutput out = press(proxy, o, pose, 0.0, kDepth);
    EXPECT_EQ(out.contact_count, 1);
    EXPECT_EQ(out.force_W, Eigen::Vector3d::Zero());
    EXPECT_GE(proxy.ideal_a().y(), kTop - 1e-6) << "the probe passed into the object";
    for (int i = 1; i <= 100; ++i) {  // dragged 3 mm sideways, pressed in
      Eigen::Vector3d a;
      Eigen::Vector3d b;
      probe_at(pose, 3e-5 * i, kDepth, &a, &b);
      out = proxy.step({&o, 1}, a, b, kDt);
      ASSERT_EQ(out.force_W, Eigen::Vector3d::Zero()) << "tick " << i;
      ASSERT_EQ(out.friction_W, Eigen::Vector3d::Zero()) << "tick " << i;
      ASSERT_GE(std::min(proxy.ideal_a().y(), proxy.ideal_b().y()), kTop - 1e-6) << "tick " << i;
    }
  }
}

// Force shading (§6.1) on a 24-sided cylinder: the tip pressing radially 1 mm deep, carried around
// it. (A shaft lying parallel to the facets' edges is not yet followed around a convex crease: see
// haptics/README.md.)
constexpr double kR = 0.02;
constexpr int kSlices = 24;

struct Cylinder : Body {
  ShadingNormals shading = ShadingNormals::build(mesh, 30.0 * kPi / 180.0);
  Cylinder() : Body(make_cylinder(kR, 0.06, kSlices, 4)) {}
  [[nodiscard]] HapticObject object(bool shaded) const {
    HapticObject o = Body::object();
    o.shading = shaded ? &shading : nullptr;
    return o;
  }
};

// The largest angle between consecutive forces over one turn at radius r.
double stroke(const HapticObject& o, Pose pose, double r, double dphi,
              std::vector<Eigen::Vector3d>* forces) {
  auto at = [](double radius, double phi, double y) {
    return Eigen::Vector3d(radius * std::cos(phi), y, -radius * std::sin(phi));
  };
  auto ends = [&](double radius, double phi, Eigen::Vector3d* a, Eigen::Vector3d* b) {
    if (pose == Pose::kTip) {
      *a = at(radius, phi, 0.0225);
      *b = at(radius + 0.08, phi, 0.0225);
    } else {
      *a = at(radius, phi, 0.017);
      *b = at(radius, phi, 0.043);
    }
  };
  SegmentProxy proxy;
  Eigen::Vector3d a;
  Eigen::Vector3d b;
  ends(kR + 0.005, 0.0, &a, &b);
  proxy.reset(a, b);
  for (int i = 1; i <= 60; ++i) {
    ends(kR + 0.005 - i * (kR + 0.005 - r) / 60, 0.0, &a, &b);
    proxy.step({&o, 1}, a, b, kDt);
  }
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  double worst = 0.0;
  const int ticks = static_cast<int>(std::lround(2.0 * kPi / dphi));
  for (int i = 1; i <= ticks; ++i) {
    ends(r, i * dphi, &a, &b);
    const SegmentProxyOutput out = proxy.step({&o, 1}, a, b, kDt);
    EXPECT_EQ(out.contact_count, 1) << "tick " << i;
    forces->push_back(out.force_W);
    if (i > 1) worst = std::max(worst, angle_between(previous, out.force_W));
    previous = out.force_W;
  }
  return worst;
}

TEST(SegmentShading, TheForceAtTheTipTurnsWithinTheTessellationBoundOnACylinder) {
  const Cylinder c;
  const double facet = 2.0 * kPi / kSlices;
  const double dphi = facet / 20.0;
  const double r = kR - 0.001;
  // The bound of ForceShading.StrokingACylinder... (force_shading_test.cpp): the tip's contact
  // point moves over the facets as the point proxy's IHIP does, so the same bound holds: the
  // shaded normal's turn within a facet plus one jump per facet.
  const double half = facet / 2.0;
  const double per_tick = dphi * r / (kR * std::cos(half));
  const double jump = (kR - r) * std::sin(facet) / (2.0 * kR * std::sin(half)) * std::sin(facet) /
                      (std::cos(half) * std::cos(half));
  const double bound = per_tick + jump;
  std::vector<Eigen::Vector3d> shaded_forces;
  std::vector<Eigen::Vector3d> flat_forces;
  const double shaded = stroke(c.object(true), Pose::kTip, r, dphi, &shaded_forces);
  const double flat = stroke(c.object(false), Pose::kTip, r, dphi, &flat_forces);
  std::printf("segment tip: shaded max turn %.5f rad (bound %.5f), flat %.5f rad\n", shaded, bound,
              flat);
  EXPECT_LE(shaded, bound + 1e-9);
  EXPECT_GE(flat, 0.9 * facet);  // without shading the force jumps by a facet at each edge
  EXPECT_LE(5.0 * shaded, flat);
  // Horizontal, outward, k times the distance to the facet plane along the shaded normal; on the
  // tick after the tip passes a crease the ideal tip is still held on the crease (one contact of
  // two planes, its penetration measured to the crease line), a tick's motion past it.
  const double past_crease = std::hypot(kR - r * std::cos(dphi), r * std::sin(dphi));
  for (const Eigen::Vector3d& f : shaded_forces) {
    EXPECT_NEAR(f.y(), 0.0, 1e-9);
    EXPECT_GT(f.norm(), kK * (kR * std::cos(half) - r) * 0.999);
    EXPECT_LT(f.norm(), kK * past_crease / std::cos(half) * 1.001);
  }
}

// A sinusoidal texture h(x) = A sin(2 pi x / lambda) on the box's top (§6.3, Fourier texture):
// the force is K d along the perturbed normal M (K the pose's normal stiffness: k at the tip, 2k
// lying) = normalize(-h'(x), 1, 0) (eq. 6-2) with
// d = h(x) + depth the depth under the textured surface (eq. 6-4 with K h > d: pure bump
// mapping), and zero in a trough deeper than the probe.
constexpr double kA = 0.0005;
constexpr double kLambda = 0.005;

class SegmentTexture : public ::testing::TestWithParam<Pose> {};

TEST_P(SegmentTexture, TheForceFollowsTheHeightAndItsGradient) {
  const Body block(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 4));
  const FourierSeries texture = FourierSeries::sinusoid(kA, kLambda, Eigen::Vector3d::UnitX());
  HapticObject o = block.object();
  o.texture = &texture;
  o.texture_k = 2.0;
  SegmentProxy proxy;
  const double depth = 0.0002;
  press(proxy, o, GetParam(), -0.01, depth);
  int touching = 0;
  int trough = 0;
  for (int i = 0; i <= 2000; ++i) {
    const double x = -0.01 + 1e-5 * i;
    Eigen::Vector3d a;
    Eigen::Vector3d b;
    probe_at(GetParam(), x, depth, &a, &b);
    const SegmentProxyOutput out = proxy.step({&o, 1}, a, b, kDt);
    ASSERT_EQ(out.contact_count, 1) << "the face itself is still touched, tick " << i;
    const double h = kA * std::sin(2.0 * kPi * x / kLambda);
    const double slope = kA * 2.0 * kPi / kLambda * std::cos(2.0 * kPi * x / kLambda);
    const double d = h + depth;
    if (d <= 0.0) {
      EXPECT_EQ(out.force_W.norm(), 0.0) << "in a trough deeper than the probe, tick " << i;
      ++trough;
      continue;
    }
    ++touching;
    EXPECT_NEAR(out.force_W.norm(), normal_stiffness(GetParam(), kK) * d, 1e-9) << i;
    const Eigen::Vector3d m = Eigen::Vector3d(-slope, 1.0, 0.0).normalized();
    EXPECT_LT(angle_between(out.force_W, m), 1e-9) << i;
  }
  EXPECT_GT(touching, 1000);
  EXPECT_GT(trough, 300);
}

INSTANTIATE_TEST_SUITE_P(TipAndLying, SegmentTexture, ::testing::Values(Pose::kTip, Pose::kLying),
                         [](const auto& info) {
                           return std::string(info.param == Pose::kTip ? "Tip" : "Lying");
                         });

}  // namespace
}  // namespace lap::haptics
