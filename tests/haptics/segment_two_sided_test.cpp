// Two-sided walls for the segment proxy: an open tube (the duct's shell) is touched from inside
// its lumen as well as from outside. A segment inside the tube moved outward through its wall,
// from every direction and in several poses, is held inside with a force back into the lumen.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "haptics/mesh_database.h"
#include "haptics/segment_database.h"
#include "haptics/segment_proxy.h"
#include "haptics/triangle_mesh.h"

namespace lap::haptics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 0.001;
constexpr double kK = 500.0;
constexpr double kR = 0.004;      // a 8 mm tube, as a duct's shell
constexpr double kLength = 0.04;  // along +y from y = 0
constexpr int kSlices = 16;
constexpr int kRings = 8;

// An open tube, outward normals (its front is the outside), no caps.
TriangleMesh open_tube() {
  TriangleMesh m;
  for (int j = 0; j <= kRings; ++j) {
    for (int i = 0; i < kSlices; ++i) {
      const double phi = 2.0 * kPi * i / kSlices;
      m.positions.emplace_back(kR * std::cos(phi), kLength * j / kRings, -kR * std::sin(phi));
    }
  }
  auto v = [](int i, int j) { return j * kSlices + (i % kSlices); };
  for (int j = 0; j < kRings; ++j) {
    for (int i = 0; i < kSlices; ++i) {
      // Counter-clockwise seen from outside.
      m.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  }
  return m;
}

struct Tube {
  MeshDatabase mesh = MeshDatabase::build(open_tube());
  SegmentDatabase segments;
  explicit Tube(bool two_sided)
      : segments(SegmentDatabase::build(mesh, [&] {
          SegmentDatabaseSettings s;
          s.two_sided = two_sided;
          return s;
        }())) {}
  [[nodiscard]] HapticObject object() const {
    HapticObject o;
    o.mesh = &mesh;
    o.segments = &segments;
    o.two_sided = segments.two_sided();
    o.law.stiffness_n_per_m = kK;
    o.law.max_force_n = 1e9;
    return o;
  }
};

double distance_from_axis(const Eigen::Vector3d& p) { return std::hypot(p.x(), p.z()); }

// The probe's poses inside the lumen, each centred on the axis at height y.
enum class Pose { kAlongTheAxis, kOutOfTheOpenEnd, kAcross, kTilted };
const char* name(Pose p) {
  switch (p) {
    case Pose::kAlongTheAxis:
      return "along the axis";
    case Pose::kOutOfTheOpenEnd:
      return "half out of the open end";
    case Pose::kAcross:
      return "across the lumen";
    case Pose::kTilted:
      return "tilted";
  }
  return "?";
}
void pose_ends(Pose pose, double spin, Eigen::Vector3d* a, Eigen::Vector3d* b) {
  const Eigen::Vector3d across(std::cos(spin), 0.0, std::sin(spin));
  switch (pose) {
    case Pose::kAlongTheAxis:
      *a = Eigen::Vector3d(0, 0.01, 0);
      *b = Eigen::Vector3d(0, 0.03, 0);
      break;
    case Pose::kOutOfTheOpenEnd:  // the jaws reaching out of the duct's cut end
      *a = Eigen::Vector3d(0, 0.03, 0);
      *b = Eigen::Vector3d(0, 0.05, 0);
      break;
    case Pose::kAcross:  // a 5 mm chord
      *a = Eigen::Vector3d(0, 0.02, 0) - 0.0025 * across;
      *b = Eigen::Vector3d(0, 0.02, 0) + 0.0025 * across;
      break;
    case Pose::kTilted:
      *a = Eigen::Vector3d(0, 0.012, 0) - 0.002 * across;
      *b = Eigen::Vector3d(0, 0.028, 0) + 0.002 * across;
      break;
  }
}

struct Push {
  double force_out = 0.0;       // force along the push (negative: back into the lumen)
  double force = 0.0;           // |force|
  double worst_escape_m = 0.0;  // how far the ideal probe got past the wall, within its length
  int contacts = 0;
};

// Moves the probe from its pose in the lumen 6 mm along `dir` over 300 ticks, then holds it.
Push push(const HapticObject& o, Pose pose, double spin, const Eigen::Vector3d& dir) {
  Eigen::Vector3d a;
  Eigen::Vector3d b;
  pose_ends(pose, spin, &a, &b);
  SegmentProxy proxy;
  proxy.reset(a, b);
  Push r;
  SegmentProxyOutput out;
  for (int i = 1; i <= 320; ++i) {
    const double s = 0.006 * std::min(1.0, i / 300.0);
    out = proxy.step({&o, 1}, a + s * dir, b + s * dir, kDt);
    for (int k = 0; k <= 100; ++k) {
      const Eigen::Vector3d p = out.ideal_a_W + (out.ideal_b_W - out.ideal_a_W) * (k / 100.0);
      if (p.y() < 0.0 || p.y() > kLength) continue;  // beyond the open ends: nothing to cross
      r.worst_escape_m = std::max(r.worst_escape_m, distance_from_axis(p) - kR);
    }
  }
  r.force_out = out.force_W.dot(dir);
  r.force = out.force_W.norm();
  r.contacts = out.contact_count;
  return r;
}

TEST(SegmentTwoSided, AProbeInsideATubeIsHeldInsideFromEveryDirection) {
  const Tube tube(true);
  const HapticObject o = tube.object();
  int pushes = 0;
  double worst_escape = 0.0;
  for (Pose pose : {Pose::kAlongTheAxis, Pose::kOutOfTheOpenEnd, Pose::kAcross, Pose::kTilted}) {
    for (int i = 0; i < 24; ++i) {
      const double phi = 2.0 * kPi * (i + 0.37) / 24.0;  // not on the vertex columns
      for (double rise : {0.0, 0.5, -0.5}) {             // outward, and outward along the axis
        const Eigen::Vector3d dir =
            Eigen::Vector3d(std::cos(phi), rise, -std::sin(phi)).normalized();
        const Push r = push(o, pose, phi * 0.7 + 0.3, dir);
        const std::string what = std::string(name(pose)) + ", phi " + std::to_string(phi) +
                                 ", rise " + std::to_string(rise);
        // Pushed 6 mm from the axis against a wall at most 4 mm away along the push: at least
        // 2 mm of spring (less the facets' sag and the push's axial part).
        EXPECT_GE(r.contacts, 1) << what;
        EXPECT_LT(r.force_out, -0.5 * kK * 0.002 * std::sqrt(1.0 - rise * rise / (1 + rise * rise)))
            << what;
        EXPECT_LT(r.worst_escape_m, 1e-5) << what;
        worst_escape = std::max(worst_escape, r.worst_escape_m);
        ++pushes;
      }
    }
  }
  std::printf("two-sided tube: %d pushes from inside, ideal probe at most %.2e m past the wall\n",
              pushes, worst_escape);
}

// The same tube marked one-sided: from inside, the probe passes through the wall unopposed (what
// sessions did with the duct before), so the test above can fail.
TEST(SegmentTwoSided, AOneSidedTubeLetsTheProbeOut) {
  const Tube tube(false);
  const HapticObject o = tube.object();
  const Push r = push(o, Pose::kAlongTheAxis, 0.0, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(r.contacts, 0);
  EXPECT_GT(r.worst_escape_m, 0.001);
}

// From outside, the two-sided tube still feels like the outside of a tube: a probe along the
// axis pushed onto the middle of a facet, to 2.5 mm from the axis, is held on the facet with 2 k
// times its depth under it (k at each end), outward.
TEST(SegmentTwoSided, FromOutsideTheWallPushesOutward) {
  const Tube tube(true);
  const HapticObject o = tube.object();
  const double phi = kPi / kSlices;  // the middle of the first facet
  const Eigen::Vector3d radial(std::cos(phi), 0.0, -std::sin(phi));
  const Eigen::Vector3d a = 0.008 * radial + Eigen::Vector3d(0, 0.01, 0);
  const Eigen::Vector3d b = 0.008 * radial + Eigen::Vector3d(0, 0.03, 0);
  SegmentProxy proxy;
  proxy.reset(a, b);
  SegmentProxyOutput out;
  for (int i = 1; i <= 100; ++i) {
    const Eigen::Vector3d d = -0.0055 * (i / 100.0) * radial;
    out = proxy.step({&o, 1}, a + d, b + d, kDt);
  }
  ASSERT_GE(out.contact_count, 1);
  const double depth = kR * std::cos(kPi / kSlices) - 0.0025;
  // Lying along the wall: both ends pushed, a spring of k at each (the passive response), 2 k d.
  EXPECT_NEAR(out.force_W.dot(radial), 2.0 * kK * depth, 1e-6);
  EXPECT_NEAR((out.force_W - out.force_W.dot(radial) * radial).norm(), 0.0, 1e-6);
  EXPECT_NEAR(out.ideal_a_W.dot(radial), kR * std::cos(kPi / kSlices), 2e-6);
}

TEST(SegmentTwoSided, TheDatabaseAndTheObjectMustAgree) {
  const Tube tube(false);
  HapticObject o = tube.object();
  o.two_sided = true;
  EXPECT_NE(std::string(surface_problem(o)), "");
  o.two_sided = false;
  EXPECT_EQ(std::string(surface_problem(o)), "");
}

}  // namespace
}  // namespace lap::haptics
