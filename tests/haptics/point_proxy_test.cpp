// Point proxy (thesis chapter 4) against analytic answers.

#include "haptics/point_proxy.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "haptics/setup/mesh_generators.h"
#include "haptics/setup/mesh_validation.h"
#include "tests/support/brute_force_reference.h"

namespace lap::haptics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 0.001;

HapticObject object_of(const MeshDatabase& db, double k = 500.0, bool two_sided = false) {
  HapticObject o;
  o.mesh = &db;
  o.two_sided = two_sided;
  o.law.stiffness_n_per_m = k;
  o.law.max_force_n = 1e9;  // analytic tests look at the unclamped law
  return o;
}

// Moves the HIP in a straight line from a to b in `steps` ticks; returns the last output.
PointProxyOutput move(PointProxy& proxy, std::span<const HapticObject> objects,
                      const Eigen::Vector3d& a, const Eigen::Vector3d& b, int steps) {
  PointProxyOutput out;
  for (int i = 1; i <= steps; ++i) {
    out = proxy.step(objects, a + (b - a) * (static_cast<double>(i) / steps), kDt);
  }
  return out;
}

TEST(PointProxy, PlaneForceIsStiffnessTimesDepth) {
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.2, 0.1, 0.2), 4));
  const HapticObject objects[] = {object_of(db, 700.0)};
  for (double depth : {1e-6, 1e-4, 2e-3, 7.5e-3}) {
    PointProxy proxy;
    proxy.reset(Eigen::Vector3d(0.013, 0.06, -0.021));
    const Eigen::Vector3d target(0.013, 0.05 - depth, -0.021);
    const PointProxyOutput out =
        move(proxy, objects, Eigen::Vector3d(0.013, 0.06, -0.021), target, 10);
    ASSERT_EQ(out.contact_count, 1);
    EXPECT_NEAR(out.force_W.y(), 700.0 * depth, 1e-9 * 700.0 * depth);
    EXPECT_NEAR(out.force_W.x(), 0.0, 1e-12);
    EXPECT_NEAR(out.force_W.z(), 0.0, 1e-12);
    EXPECT_NEAR(out.ihip_W.y(), 0.05, 1e-15);
    EXPECT_EQ(out.primitive.kind, PrimitiveKind::kFace);
  }
}

TEST(PointProxy, SubMicrometreTrianglesAreCollidedWithInMetres) {
  // A sphere of radius 0.5 micrometre (edges of about 0.1 micrometre) placed 0.2 m from the
  // origin, where a float step is 1.5e-8 m: no tolerance or size limit may hide it.
  const double R = 5e-7;
  TriangleMesh m = make_uv_sphere(R, 12, 24);
  const Eigen::Vector3d c(0.2, -0.1, 0.15);
  m.transform(Eigen::Affine3d(Eigen::Translation3d(c)));
  const MeshDatabase db = MeshDatabase::build(m);
  const HapticObject objects[] = {object_of(db, 1e6)};
  PointProxy proxy;
  const Eigen::Vector3d start = c + Eigen::Vector3d(0, 3 * R, 0);
  proxy.reset(start);
  const PointProxyOutput out = move(proxy, objects, start, c + Eigen::Vector3d(0, 0.8 * R, 0), 10);
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_GT(out.force_W.y(), 0.0);
  // Shallow inside a convex shape: the IHIP is at the nearest surface distance (exhaustive
  // reference; on the symmetry axis all 24 pole faces are equally near, so compare distances)
  // and the force is k times that distance.
  const Eigen::Vector3d hip = c + Eigen::Vector3d(0, 0.8 * R, 0);
  const ReferenceClosest r = reference_closest_point(db, hip);
  EXPECT_NEAR((out.ihip_W - hip).norm(), r.distance, 1e-9 * r.distance);
  EXPECT_NEAR(out.force_W.norm(), 1e6 * r.distance, 1e-9 * 1e6 * r.distance);
  EXPECT_GT(r.distance, 0.1 * R);
}

TEST(PointProxy, LeavingThePlaneReleasesAndZeroesTheForce) {
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.2, 0.1, 0.2), 2));
  const HapticObject objects[] = {object_of(db)};
  PointProxy proxy;
  proxy.reset(Eigen::Vector3d(0, 0.06, 0));
  EXPECT_EQ(move(proxy, objects, {0, 0.06, 0}, {0, 0.045, 0}, 10).contact_count, 1);
  const PointProxyOutput out = move(proxy, objects, {0, 0.045, 0}, {0, 0.051, 0}, 10);
  EXPECT_EQ(out.contact_count, 0);
  EXPECT_EQ(out.force_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(out.ihip_W, Eigen::Vector3d(0, 0.051, 0));
  EXPECT_EQ(proxy.stats().releases, 1);
}

TEST(PointProxy, TessellatedSphereWithinTheDerivedTessellationBound) {
  // Latitude/longitude sphere of radius R: every face is a chord triangle whose vertices lie on
  // the sphere, and none spans more than rho = sqrt(dtheta^2 + dphi^2) of arc (its diagonal).
  // So each face plane lies between R cos(rho) and R from the centre: the polyhedral depth of a
  // point differs from the true depth by at most R (1 - cos rho), and the face normal from the
  // radial direction by at most rho.
  const double R = 0.05;
  const int stacks = 90;
  const int slices = 180;
  const double rho = std::hypot(kPi / stacks, 2 * kPi / slices);
  const double depth_bound = R * (1.0 - std::cos(rho));
  const MeshDatabase db = MeshDatabase::build(make_uv_sphere(R, stacks, slices));
  const double k = 400.0;
  const HapticObject objects[] = {object_of(db, k)};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Vector3d dir(u(rng), u(rng), u(rng));
    if (dir.norm() < 0.1) continue;
    dir.normalize();
    const double depth = 0.004 * (0.1 + 0.9 * (u(rng) + 1.0) / 2.0);
    PointProxy proxy;
    const Eigen::Vector3d start = dir * (R + 0.005);
    proxy.reset(start);
    const PointProxyOutput out = move(proxy, objects, start, dir * (R - depth), 20);
    ASSERT_EQ(out.contact_count, 1) << "trial " << trial;
    EXPECT_NEAR(out.force_W.norm(), k * depth, k * depth_bound + 1e-12) << "trial " << trial;
    const double angle = std::acos(std::clamp(out.force_W.normalized().dot(dir), -1.0, 1.0));
    EXPECT_LE(angle, rho) << "trial " << trial;
  }
}

TEST(PointProxy, CubeApproachedFromTheTopKeepsTheForceUp) {
  // Figure 2-11: entering the top face near the right edge, then pressing deeper than the
  // distance to the right face: the nearest surface is the right face, but the force stays up.
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 3));
  const HapticObject objects[] = {object_of(db, 500.0)};
  PointProxy proxy;
  proxy.reset({0.048, 0.06, 0.0});
  PointProxyOutput out = move(proxy, objects, {0.048, 0.06, 0.0}, {0.048, 0.049, 0.0}, 10);
  ASSERT_EQ(out.contact_count, 1);
  out = move(proxy, objects, {0.048, 0.049, 0.0}, {0.048, 0.040, 0.0},
             20);  // 2 mm from the side, 10 mm deep
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_NEAR(out.force_W.normalized().y(), 1.0, 1e-12);
  EXPECT_NEAR(out.force_W.norm(), 500.0 * 0.010, 1e-9);
  // The brute-force nearest-surface reference would push right (what Figure 2-11(c) warns of).
  EXPECT_NEAR(reference_closest_point(db, {0.048, 0.040, 0.0}).point.x(), 0.05, 1e-12);
}

TEST(PointProxy, CubeCornerApproachedFromTheTopKeepsTheForceUp) {
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 1));
  const HapticObject objects[] = {object_of(db, 500.0)};
  PointProxy proxy;
  const Eigen::Vector3d above(0.049, 0.06, 0.049);
  proxy.reset(above);
  const PointProxyOutput out = move(proxy, objects, above, {0.049, 0.045, 0.049}, 15);
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_NEAR(out.force_W.normalized().y(), 1.0, 1e-12);
}

TEST(PointProxy, SlidingOffACubeEdgeReleasesExactlyWhenTheHipLeaves) {
  // Pressed 2 mm into the top face, the HIP slides outward: the force stays straight up while
  // the HIP is inside, and drops to zero the tick it passes the side face's plane.
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 3));
  const HapticObject objects[] = {object_of(db, 500.0)};
  PointProxy proxy;
  proxy.reset({0.0, 0.06, 0.01});
  move(proxy, objects, {0.0, 0.06, 0.01}, {0.0, 0.048, 0.01}, 10);
  PointProxyOutput out = move(proxy, objects, {0.0, 0.048, 0.01}, {0.0499, 0.048, 0.01}, 50);
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_TRUE(out.force_W.isApprox(Eigen::Vector3d(0.0, 500.0 * 0.002, 0.0), 1e-9));
  out = proxy.step(objects, {0.0501, 0.048, 0.01}, kDt);
  EXPECT_EQ(out.contact_count, 0);
  EXPECT_TRUE(out.force_W.isZero());
}

TEST(PointProxy, SlidingOverAnEdgeFromOutsideFollowsTheEdge) {
  // From above the top face the HIP moves down and outward over the edge, staying inside the
  // wedge where the edge is nearest: when it enters the cube there, the force points from the
  // HIP back towards the edge, and the search reports the edge.
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 3));
  const HapticObject objects[] = {object_of(db, 500.0)};
  PointProxy proxy;
  proxy.reset({0.049, 0.051, 0.01});
  PointProxyOutput out = move(proxy, objects, {0.049, 0.051, 0.01}, {0.0495, 0.0495, 0.01}, 10);
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_EQ(out.primitive.kind, PrimitiveKind::kFace);
  // Now the nearest primitive for a HIP pressed below the edge region and leaving the top face's
  // prism is the edge itself; Local search from the face steps down to it.
  Eigen::Vector3d q;
  int32_t rounds = 0;
  const PrimitiveRef edge =
      PointProxy::local_search(db, out.primitive, {0.0502, 0.0502, 0.01}, &q, &rounds);
  EXPECT_EQ(edge.kind, PrimitiveKind::kEdge);
  EXPECT_TRUE(q.isApprox(Eigen::Vector3d(0.05, 0.05, 0.01), 1e-12));
}

TEST(PointProxy, ThinPlateIsFeltFromTheSideFirstTouched) {
  // Figures 2-13 and 4-6: a zero-thickness plate, touched from above or from below; pushing on
  // through it keeps the force towards the side first touched.
  const MeshDatabase db = MeshDatabase::build(make_plate(0.1, 8));
  ASSERT_TRUE(db.has_boundary());
  const HapticObject objects[] = {object_of(db, 300.0, /*two_sided=*/true)};
  for (double side : {1.0, -1.0}) {
    PointProxy proxy;
    const Eigen::Vector3d start(0.011, 0.01 * side, -0.007);
    proxy.reset(start);
    PointProxyOutput out = move(proxy, objects, start, {0.011, -0.003 * side, -0.007}, 13);
    ASSERT_EQ(out.contact_count, 1) << side;
    EXPECT_NEAR(out.force_W.y(), 300.0 * 0.003 * side, 1e-12) << side;
    EXPECT_EQ(proxy.contacts()[0].side, side > 0 ? 1 : -1);
    // Sliding around on the far side still pushes back towards the first side.
    out = move(proxy, objects, {0.011, -0.003 * side, -0.007}, {-0.02, -0.006 * side, 0.013}, 40);
    ASSERT_EQ(out.contact_count, 1);
    EXPECT_NEAR(out.force_W.y(), 300.0 * 0.006 * side, 1e-12);
    EXPECT_NEAR(out.ihip_W.y(), 0.0, 1e-15);
  }
}

TEST(PointProxy, PlatePassedQuicklyIsStillCaught) {
  // Figure 2-13: a path that jumps across the plate within one tick is still a contact.
  const MeshDatabase db = MeshDatabase::build(make_plate(0.1, 2));
  const HapticObject objects[] = {object_of(db, 300.0, true)};
  PointProxy proxy;
  proxy.reset({0.0, 0.0004, 0.0});
  const PointProxyOutput out = proxy.step(objects, {0.0, -0.0006, 0.0}, kDt);
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_GT(out.force_W.y(), 0.0);
}

TEST(PointProxy, LShapedBlockInnerCornerPushesOutOfBothFaces) {
  // An L of 2 x 2 cells minus the upper right one (cell 1 cm): the floor at y = 1 cm for
  // x in [1, 2] cm meets the wall x = 1 cm rising to y = 2 cm. The HIP pressed into the floor
  // slides into the wall: the IHIP stops at the concave edge and the force points up and away.
  const double c = 0.01;
  const MeshDatabase db = MeshDatabase::build(
      make_voxel_solid(2, 2, 1, c, [](int i, int j, int) { return !(i == 1 && j == 1); }));
  const HapticObject objects[] = {object_of(db, 500.0)};
  PointProxy proxy;
  const Eigen::Vector3d start(0.016, 0.012, 0.005);
  proxy.reset(start);
  move(proxy, objects, start, {0.016, 0.009, 0.005}, 10);  // 1 mm into the floor
  const PointProxyOutput out =
      move(proxy, objects, {0.016, 0.009, 0.005}, {0.008, 0.009, 0.005}, 80);
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_EQ(out.primitive.kind, PrimitiveKind::kEdge);
  EXPECT_TRUE(out.ihip_W.isApprox(Eigen::Vector3d(0.01, 0.01, 0.005), 1e-12))
      << out.ihip_W.transpose();
  EXPECT_TRUE(out.force_W.isApprox(Eigen::Vector3d(0.002, 0.001, 0.0) * 500.0, 1e-9))
      << out.force_W.transpose();
}

TEST(PointProxy, BowlPushesTowardsItsCentre) {
  // Inside a hemispherical bowl the surface normal points to the centre: pressing outward at any
  // point of the inner surface is pushed back towards the centre.
  const double R = 0.04;
  const int stacks = 120;
  const int slices = 240;
  const double rho = std::hypot(kPi / stacks, 2 * kPi / slices);
  const MeshDatabase db = MeshDatabase::build(make_bowl(R, stacks, slices));
  const HapticObject objects[] = {object_of(db, 250.0, true)};
  for (double tilt_deg : {0.0, 20.0, 45.0, 70.0}) {
    const double t = tilt_deg * kPi / 180.0;
    const Eigen::Vector3d dir(std::sin(t), -std::cos(t), 0.0);  // from the centre to the wall
    PointProxy proxy;
    proxy.reset(dir * (R - 0.005));
    const PointProxyOutput out = move(proxy, objects, dir * (R - 0.005), dir * (R + 0.002), 20);
    ASSERT_EQ(out.contact_count, 1) << tilt_deg;
    const double angle = std::acos(std::clamp(-out.force_W.normalized().dot(dir), -1.0, 1.0));
    EXPECT_LE(angle, rho) << tilt_deg;
    EXPECT_NEAR(out.force_W.norm(), 250.0 * 0.002, 250.0 * R * (1 - std::cos(rho)) + 1e-12);
  }
}

TEST(PointProxy, MovingObjectIsFeltInItsOwnFrame) {
  // §6.4: a box moving up into a resting HIP makes contact; a rotated box is felt rotated.
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 2));
  HapticObject o = object_of(db, 500.0);
  PointProxy proxy;
  const Eigen::Vector3d hip(0.0, 0.06, 0.0);
  proxy.reset(hip);
  PointProxyOutput out;
  for (int i = 0; i <= 20; ++i) {
    o.prev_pose_WO = o.pose_WO;
    o.pose_WO = Eigen::Translation3d(0.0, 0.0005 * i, 0.0) * Eigen::Isometry3d::Identity();
    out = proxy.step(std::span<const HapticObject>(&o, 1), hip, kDt);
  }
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_NEAR(out.force_W.y(), 500.0 * (0.06 - 0.06), 1e-12 + 500.0 * 0.0);
  // Top face now at y = 0.05 + 0.01 = 0.06 exactly: zero depth. Move 1 mm more.
  o.prev_pose_WO = o.pose_WO;
  o.pose_WO = Eigen::Translation3d(0.0, 0.011, 0.0) * Eigen::Isometry3d::Identity();
  out = proxy.step(std::span<const HapticObject>(&o, 1), hip, kDt);
  EXPECT_NEAR(out.force_W.y(), 500.0 * 0.001, 1e-9);

  // Rotated 30 degrees about z: the top face's normal, and so the force, turns with it.
  PointProxy rotated;
  HapticObject r = object_of(db, 500.0);
  r.pose_WO = Eigen::Isometry3d(Eigen::AngleAxisd(kPi / 6, Eigen::Vector3d::UnitZ()));
  r.prev_pose_WO = r.pose_WO;
  const Eigen::Vector3d n = r.pose_WO.linear() * Eigen::Vector3d::UnitY();
  rotated.reset(n * 0.06);
  out = move(rotated, std::span<const HapticObject>(&r, 1), n * 0.06, n * 0.047, 10);
  EXPECT_TRUE(out.force_W.isApprox(n * 500.0 * 0.003, 1e-9));
}

TEST(PointProxy, SlidingAlongOneObjectNeverEntersItsNeighbour) {
  // Two boxes side by side: a low one (top at y = 1 cm) and a tall one to its right (wall at
  // x = 2 cm). Pressed into the low box's top, the HIP slides right into the tall box: the IHIP
  // stops at the tall box's wall instead of sliding into it.
  const MeshDatabase low =
      MeshDatabase::build(make_voxel_solid(2, 1, 1, 0.01, [](int, int, int) { return true; }));
  TriangleMesh tall_mesh = make_voxel_solid(1, 3, 1, 0.01, [](int, int, int) { return true; });
  tall_mesh.transform(Eigen::Affine3d(Eigen::Translation3d(0.02, 0.0, 0.0)));
  const MeshDatabase tall = MeshDatabase::build(tall_mesh);
  const HapticObject objects[] = {object_of(low, 500.0), object_of(tall, 800.0)};
  PointProxy proxy;
  proxy.reset({0.01, 0.012, 0.005});
  move(proxy, objects, {0.01, 0.012, 0.005}, {0.01, 0.009, 0.005}, 10);
  PointProxyOutput out;
  for (int i = 1; i <= 100; ++i) {
    const Eigen::Vector3d hip(0.01 + 0.015 * i / 100.0, 0.009, 0.005);
    out = proxy.step(objects, hip, kDt);
    EXPECT_LE(out.ihip_W.x(), 0.02 + 1e-12) << "tick " << i;  // never inside the tall box
  }
  EXPECT_EQ(out.contact_count, 2);
  EXPECT_TRUE(out.ihip_W.isApprox(Eigen::Vector3d(0.02, 0.01, 0.005), 1e-12))
      << out.ihip_W.transpose();
  // Both surfaces push: up from the low box, left from the tall one (the stiffer law applies).
  EXPECT_TRUE(out.force_W.isApprox(Eigen::Vector3d(-0.005, 0.001, 0.0) * 800.0, 1e-9))
      << out.force_W.transpose();
}

TEST(ForceLaw, HookeDampedAndNonlinear) {
  ForceLaw law;
  law.stiffness_n_per_m = 200.0;
  const Eigen::Vector3d x(0.0, -0.003, 0.0);  // HIP 3 mm below the IHIP
  EXPECT_TRUE(contact_force(law, x, 0.0).isApprox(Eigen::Vector3d(0, 0.6, 0)));
  law.kind = ForceLaw::Kind::kHookeDamped;
  law.damping_n_s_per_m = 2.0;
  // Approaching at 0.1 m/s adds b v; withdrawing slowly takes b v off; withdrawing fast never
  // pulls the HIP in.
  EXPECT_TRUE(contact_force(law, x, 0.1).isApprox(Eigen::Vector3d(0, 0.8, 0)));
  EXPECT_TRUE(contact_force(law, x, -0.1).isApprox(Eigen::Vector3d(0, 0.4, 0)));
  EXPECT_TRUE(contact_force(law, x, -1.0).isZero());
  law.kind = ForceLaw::Kind::kNonlinear;
  law.k1_n_per_sqrt_m = 3.0;
  law.k2_n_per_m = 100.0;
  law.k3_n_per_m2 = 5000.0;
  const double expected = 3.0 * std::sqrt(0.003) + 100.0 * 0.003 + 5000.0 * 0.003 * 0.003;
  EXPECT_NEAR(contact_force(law, x, 0.0).y(), expected, 1e-15);
  law.max_force_n = 0.2;
  EXPECT_NEAR(contact_force(law, x, 0.0).norm(), 0.2, 1e-15);
  law.k1_n_per_sqrt_m = std::nan("");
  EXPECT_TRUE(contact_force(law, x, 0.0).isZero());
}

// A HIP moving into a plane at a constant speed v feels k d + b v on every tick, the tick it
// crosses the surface too (d: its depth); withdrawing at v, k d - b v, never below zero.
TEST(PointProxy, DampedPlaneForceIsStiffnessTimesDepthPlusDampingTimesSpeed) {
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.2, 0.1, 0.2), 4));
  HapticObject o = object_of(db, 600.0);
  o.law.kind = ForceLaw::Kind::kHookeDamped;
  o.law.damping_n_s_per_m = 3.0;
  const double v = 0.04;  // m/s: 40 micrometres a tick
  PointProxy proxy;
  const Eigen::Vector3d start(0.013, 0.0503, -0.021);  // 0.3 mm above the top face (y = 0.05)
  proxy.reset(start);
  int ticks_in_contact = 0;
  Eigen::Vector3d hip = start;
  for (int i = 1; i <= 100; ++i) {
    hip.y() = start.y() - v * kDt * i;
    const PointProxyOutput out = proxy.step({&o, 1}, hip, kDt);
    const double depth = 0.05 - hip.y();
    if (depth <= 0.0) {
      EXPECT_EQ(out.contact_count, 0) << i;
      continue;
    }
    ++ticks_in_contact;
    ASSERT_EQ(out.contact_count, 1) << i;
    EXPECT_NEAR(out.force_W.y(), 600.0 * depth + 3.0 * v, 1e-9) << i;
    EXPECT_NEAR(out.force_W.x(), 0.0, 1e-12);
    EXPECT_NEAR(out.force_W.z(), 0.0, 1e-12);
  }
  EXPECT_GT(ticks_in_contact, 80);
  // Withdrawing at v from 3.7 mm deep: k d - b v.
  for (int i = 1; i <= 20; ++i) {
    hip.y() += v * kDt;
    const PointProxyOutput out = proxy.step({&o, 1}, hip, kDt);
    ASSERT_EQ(out.contact_count, 1) << i;
    EXPECT_NEAR(out.force_W.y(), 600.0 * (0.05 - hip.y()) - 3.0 * v, 1e-9) << i;
  }
  // Withdrawing fast (1 mm in a tick from 2.9 mm deep): the damper would pull; the force is zero.
  hip.y() += 0.001;
  const PointProxyOutput out = proxy.step({&o, 1}, hip, kDt);
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_EQ(out.force_W, Eigen::Vector3d::Zero());
}

// The damper takes the velocity relative to the surface (§6.4): a box moving up at v into a
// HIP held still is approached at v, as a HIP moving down at v onto a still box.
TEST(PointProxy, DampingOnAMovingObjectIsOnTheRelativeVelocity) {
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 2));
  HapticObject o = object_of(db, 500.0);
  o.law.kind = ForceLaw::Kind::kHookeDamped;
  o.law.damping_n_s_per_m = 2.0;
  const double v = 0.05;
  PointProxy proxy;
  const Eigen::Vector3d hip(0.01, 0.0515, 0.0);  // 1.5 mm above the top face at rest
  proxy.reset(hip);
  int ticks_in_contact = 0;
  for (int i = 1; i <= 60; ++i) {
    o.prev_pose_WO = o.pose_WO;
    o.pose_WO = Eigen::Translation3d(0.0, v * kDt * i, 0.0) * Eigen::Isometry3d::Identity();
    const PointProxyOutput out = proxy.step({&o, 1}, hip, kDt);
    const double depth = 0.05 + v * kDt * i - hip.y();
    // (At zero depth, give or take a rounding, the force's direction is not defined.)
    if (out.contact_count == 0 || depth < 1e-9) {
      EXPECT_LE(depth, 1e-9) << i;
      continue;
    }
    ++ticks_in_contact;
    EXPECT_NEAR(out.force_W.y(), 500.0 * depth + 2.0 * v, 1e-9) << i;
  }
  EXPECT_GT(ticks_in_contact, 20);
}

// The IHIP jumps, the HIP moves smoothly: the damped force never leaves k |x| -+ b |v|, no
// spike and no dropout. Two jumps: (1) the surface under a pressing HIP updated by a modelling
// step (the proxies switch to the next copy of a deformed organ, here 1 mm higher or lower),
// where the damper on the rate of the penetration vector, as before, spikes by b times 1 mm per
// tick (evaluated alongside, so the test does exercise the jump); (2) a coarse sphere, the HIP
// going round 3 mm under it: at each edge the proxy passes onto the next face, whose nearest
// point from inside is nearer than the edge's, and the IHIP moves by over 1 mm in one tick.
TEST(PointProxy, AnIhipJumpGivesNoDampingSpike) {
  const double k = 400.0;
  const double b = 2.0;
  auto damped = [&](const MeshDatabase& db) {
    HapticObject o = object_of(db, k);
    o.law.kind = ForceLaw::Kind::kHookeDamped;
    o.law.damping_n_s_per_m = b;
    return o;
  };
  {
    const TriangleMesh box = make_box(Eigen::Vector3d(0.2, 0.1, 0.2), 4);
    const MeshDatabase rest = MeshDatabase::build(box);
    std::array<MeshDatabase, 2> moved = {rest, rest};  // copies: the same topology
    for (int s = 0; s < 2; ++s) {
      std::vector<Eigen::Vector3d> p = box.positions;
      for (Eigen::Vector3d& x : p) x.y() += s == 0 ? 0.001 : -0.001;
      moved[static_cast<size_t>(s)].set_positions(p);
    }
    HapticObject o = damped(rest);
    const double v = 0.02;
    PointProxy proxy;
    Eigen::Vector3d hip(0.013, 0.0502, -0.021);
    proxy.reset(hip);
    double worst = 0.0;
    double worst_old = 0.0;
    int in_contact = 0;
    Eigen::Vector3d last_x = Eigen::Vector3d::Zero();
    for (int i = 1; i <= 200; ++i) {
      if (i == 80) o.mesh = &moved[0];   // the surface rises 1 mm
      if (i == 140) o.mesh = &moved[1];  // and falls 2 mm
      hip.y() -= v * kDt;
      const PointProxyOutput out = proxy.step({&o, 1}, hip, kDt);
      if (out.contact_count == 0) continue;
      const Eigen::Vector3d x = hip - out.ihip_W;
      if (x.norm() < 1e-9) continue;  // (at zero depth the direction is not defined)
      ++in_contact;
      const double spring = k * x.norm();
      worst = std::max(worst, std::abs(out.force_W.norm() - spring) - b * v);
      if (last_x.norm() > 0.0) {
        const double old_law = std::max(0.0, spring + b * ((x - last_x) / kDt).dot(x.normalized()));
        worst_old = std::max(worst_old, std::abs(old_law - spring) - b * v);
      }
      last_x = x;
    }
    EXPECT_GT(in_contact, 180);  // the contact held through both updates
    EXPECT_LE(worst, 1e-9);
    EXPECT_GT(worst_old, 0.5 * b * 1.0) << "the old law should spike by b x 1 m/s here";
  }
  {
    const double R = 0.04;
    const MeshDatabase db = MeshDatabase::build(make_uv_sphere(R, 8, 12));
    const HapticObject o = damped(db);
    // Round the sphere once in 10 s (2.3 cm/s), 5 mm above its equator, 3 mm into it.
    auto hip_at = [&](double angle, double depth) {
      const double r = std::sqrt(R * R - 0.005 * 0.005) - depth;
      return Eigen::Vector3d(r * std::cos(angle), 0.005, r * std::sin(angle));
    };
    PointProxy proxy;
    proxy.reset(hip_at(0.1, -0.004));
    move(proxy, {&o, 1}, hip_at(0.1, -0.004), hip_at(0.1, 0.003), 20);
    Eigen::Vector3d last_hip = hip_at(0.1, 0.003);
    Eigen::Vector3d last_ihip = proxy.ihip();
    double worst = 0.0;
    double longest_jump = 0.0;
    double step = 0.0;
    for (int i = 1; i <= 10000; ++i) {
      const Eigen::Vector3d hip = hip_at(0.1 + 2.0 * kPi * i / 10000.0, 0.003);
      const PointProxyOutput out = proxy.step({&o, 1}, hip, kDt);
      ASSERT_EQ(out.contact_count, 1) << i;
      step = (hip - last_hip).norm();
      worst = std::max(
          worst, std::abs(out.force_W.norm() - k * (hip - out.ihip_W).norm()) - b * step / kDt);
      longest_jump = std::max(longest_jump, (out.ihip_W - last_ihip).norm());
      last_hip = hip;
      last_ihip = out.ihip_W;
    }
    EXPECT_LE(worst, 1e-9);
    EXPECT_GT(longest_jump, 1e-3);  // the IHIP did jump: over 40 times the HIP's step
    EXPECT_GT(longest_jump, 40.0 * step);
  }
}

TEST(PointProxy, ForceIsClampedToTheMaterialMaximum) {
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 1));
  HapticObject o = object_of(db, 5000.0);
  o.law.max_force_n = 3.0;
  PointProxy proxy;
  proxy.reset({0, 0.06, 0});
  const PointProxyOutput out =
      move(proxy, std::span<const HapticObject>(&o, 1), {0, 0.06, 0}, {0, 0.03, 0}, 40);
  EXPECT_NEAR(out.force_W.norm(), 3.0, 1e-12);
}

TEST(PointProxy, NonFiniteInputZeroesTheForceAndResets) {
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 1));
  const HapticObject objects[] = {object_of(db)};
  PointProxy proxy;
  proxy.reset({0, 0.06, 0});
  ASSERT_EQ(move(proxy, objects, {0, 0.06, 0}, {0, 0.045, 0}, 10).contact_count, 1);
  const PointProxyOutput bad = proxy.step(objects, {std::nan(""), 0.0, 0.0}, kDt);
  EXPECT_TRUE(bad.fault);
  EXPECT_TRUE(bad.force_W.isZero());
  EXPECT_EQ(proxy.stats().faults, 1);
  EXPECT_EQ(proxy.contacts().size(), 0U);
  // Back to finite input inside the box: no contact (it was not entered from outside).
  EXPECT_EQ(proxy.step(objects, {0, 0.045, 0}, kDt).contact_count, 0);
}

TEST(PointProxy, StartingInsideIsNotAContact) {
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 1));
  const HapticObject objects[] = {object_of(db)};
  PointProxy proxy;
  proxy.reset({0, 0, 0});
  EXPECT_EQ(move(proxy, objects, {0, 0, 0}, {0.01, 0.02, 0}, 10).contact_count, 0);
  // Leaving through the top from inside is no contact either.
  EXPECT_EQ(move(proxy, objects, {0.01, 0.02, 0}, {0.01, 0.07, 0}, 10).contact_count, 0);
}

// A closed solid shaped like a C in the x-z plane, extruded along y (millimetres, scaled to
// metres): a 1 mm top plate (x -4..2, z -1..0) joined on the left to a 3 mm lower slab
// (x -4..6, z -6..-3) across a 2 mm gap. Counter-clockwise outline in (x, z); outward faces.
TriangleMesh make_folded_plate(double half_length_mm) {
  const std::array<Eigen::Vector2d, 8> outline = {Eigen::Vector2d(-4, -6), Eigen::Vector2d(6, -6),
                                                  Eigen::Vector2d(6, -3),  Eigen::Vector2d(-3, -3),
                                                  Eigen::Vector2d(-3, -1), Eigen::Vector2d(2, -1),
                                                  Eigen::Vector2d(2, 0),   Eigen::Vector2d(-4, 0)};
  // The outline's triangulation, by hand: two triangles on the slab, one at the plate's tip and
  // three fanned around the top-left corner (vertex 7).
  const std::array<Triangle, 6> cap = {Triangle{0, 1, 2}, Triangle{0, 2, 3}, Triangle{0, 3, 7},
                                       Triangle{3, 4, 7}, Triangle{4, 5, 6}, Triangle{4, 6, 7}};
  TriangleMesh m;
  for (const double y : {-half_length_mm, half_length_mm}) {
    for (const Eigen::Vector2d& p : outline) m.positions.emplace_back(p.x(), y, p.y());
  }
  const int32_t n = static_cast<int32_t>(outline.size());
  for (const Triangle& t : cap) {
    m.triangles.push_back({t[0], t[1], t[2]});              // y = -L: outline x-z CCW faces -y
    m.triangles.push_back({n + t[0], n + t[2], n + t[1]});  // y = +L
  }
  for (int32_t i = 0; i < n; ++i) {
    const int32_t j = (i + 1) % n;
    m.triangles.push_back({i, n + j, j});
    m.triangles.push_back({i, n + i, n + j});
  }
  m.scale(0.001);
  return m;
}

// Regression for a release under a fold (found on a liver mesh by PointProxyRandom): the HIP
// goes through the thin top plate, across the gap and into the lower slab, then slides past the
// plate's edge. The local search from the plate's top face then stops on the plate's lower edge,
// on the outer side of which the HIP is, and wants release; but the HIP is inside the slab. The
// IHIP's path to it enters the slab from outside, so the proxy must keep (or take) a contact and
// push the HIP out: never a HIP inside the solid with no contact and no force.
TEST(PointProxy, AHipThatLeftAThinPartThroughAFoldIsStillHeld) {
  const TriangleMesh mesh = make_folded_plate(10.0);
  const MeshDiagnostics diag = validate_mesh(mesh);
  ASSERT_TRUE(diag.clean()) << ::testing::PrintToString(diag.describe());  // closed, outward
  ASSERT_NEAR(mesh.signed_volume(), 1e-9 * 20.0 * (6.0 * 1.0 + 10.0 * 3.0 + 1.0 * 2.0), 1e-15);
  const MeshDatabase db = MeshDatabase::build(mesh);
  const HapticObject objects[] = {object_of(db, 500.0)};
  const auto mm = [](double x, double z) { return Eigen::Vector3d(0.001 * x, 0.0, 0.001 * z); };
  ASSERT_TRUE(reference_inside(db, mm(1.0, -4.5)));   // the lower slab
  ASSERT_FALSE(reference_inside(db, mm(1.0, -2.0)));  // the gap

  PointProxy proxy;
  proxy.reset(mm(1.0, 2.0));
  // Down through the plate (held on its top face: the proxy does not pop through), the gap and
  // into the slab.
  PointProxyOutput out = move(proxy, objects, mm(1.0, 2.0), mm(1.0, -4.5), 200);
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_NEAR(out.ihip_W.z(), 0.0, 1e-12);
  // Sideways, past the plate's edge at x = 2 mm, to x = 4 mm, inside the slab all the way.
  int32_t inside_ticks = 0;
  int32_t inside_free = 0;
  const int steps = 300;
  for (int i = 1; i <= steps; ++i) {
    const Eigen::Vector3d hip = mm(1.0 + 3.0 * i / steps, -4.5);
    out = proxy.step(objects, hip, kDt);
    if (!reference_inside(db, hip)) continue;
    ++inside_ticks;
    if (out.contact_count == 0 || !(out.force_W.z() > 0.0)) ++inside_free;
  }
  EXPECT_EQ(inside_ticks, steps);
  EXPECT_EQ(inside_free, 0);
  EXPECT_EQ(proxy.stats().reentries, 1);  // once, at the plate's edge; then held on the slab
  // At rest beyond the plate: held on the face the IHIP's path entered, the slab's top, 1.5 mm
  // above the HIP (its bottom is as near; history, not the nearest face, decides, §4.3).
  for (int i = 0; i < 5; ++i) out = proxy.step(objects, mm(4.0, -4.5), kDt);
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_NEAR(out.ihip_W.z(), -0.003, 1e-12);
  EXPECT_NEAR(out.force_W.z(), 500.0 * 0.0015, 1e-9);
  EXPECT_NEAR(out.force_W.x(), 0.0, 1e-9);
}

}  // namespace
}  // namespace lap::haptics
