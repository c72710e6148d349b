// Free rigid bodies in the haptic loop (thesis §6.4, sim/runtime/moving_bodies.h) against
// analytic answers: a known force accelerates a body at F / m, a torque about a principal axis
// gives α = τ / I; in a session the tool's contact impulses are exactly the body's momentum; a
// body bouncing off a probe held still gains no energy (the coupling is passive); an anchored
// rigid organ never moves; the haptic tick with probes and bodies allocates nothing.

#include <gtest/gtest.h>

#include <cstdio>

#include "haptics/mesh_database.h"
#include "haptics/point_proxy.h"
#include "haptics/setup/mesh_generators.h"
#include "models/mass_properties.h"
#include "sim/runtime/moving_bodies.h"
#include "sim/setup/mesh_loader.h"
#include "tests/sim/demo_test_support.h"
#include "tests/support/counting_allocator.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;
using demo_test::observed_session;
using demo_test::tip_force;

const Eigen::Vector3d kBlockSides(0.04, 0.02, 0.02);

MovingBodies one_block(double mass_kg, const Eigen::Vector3d& centre) {
  haptics::TriangleMesh box = haptics::make_box(kBlockSides, 2);
  for (Eigen::Vector3d& p : box.positions) p += centre;
  RigidBodyOfOrgan b;
  b.organ = 0;
  b.model = models::rigid_body_of_mesh(box, mass_kg);
  MovingBodies bodies;
  bodies.init(std::span<const RigidBodyOfOrgan>(&b, 1), 1);
  return bodies;
}

TEST(MovingBodies, AKnownForceAcceleratesTheBodyAtFOverM) {
  const Eigen::Vector3d centre(0.01, 0.02, -0.03);
  MovingBodies bodies = one_block(0.5, centre);
  const Eigen::Vector3d force(0.2, -0.1, 0.05);
  const double dt = 0.001;
  const int ticks = 1000;
  for (int k = 0; k < ticks; ++k) {
    bodies.push(0, force, centre);  // through the centre of mass: no torque
    ASSERT_TRUE(bodies.step(BodyPushes{}, dt));
  }
  const double t = ticks * dt;
  const Eigen::Vector3d a = force / 0.5;
  BodySnapshots snap;
  bodies.write(&snap);
  EXPECT_LT((snap.bodies[0].velocity_W - a * t).norm(), 1e-12);
  // Momenta first, then the position (semi-implicit): x = a t² / 2 + a t dt / 2 exactly.
  EXPECT_LT((snap.bodies[0].pose_W.translation() - (0.5 * a * t * t + 0.5 * a * t * dt)).norm(),
            1e-12);
  // (The mesh's centroid is the centre to rounding: a torque of that size.)
  EXPECT_LT(snap.bodies[0].angular_velocity_W.norm(), 1e-9);
}

TEST(MovingBodies, ATorqueAboutAPrincipalAxisGivesAlphaTauOverI) {
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  MovingBodies bodies = one_block(0.2, centre);
  const double i_zz = bodies.model(0).inertia_B(2, 2);
  EXPECT_NEAR(i_zz, 0.2 * (0.04 * 0.04 + 0.02 * 0.02) / 12.0, 1e-15);
  // A couple about z: ±0.3 mN along y at x = ±0.02 m, τ = 2 × 0.02 × 0.3 mN m.
  const double tau = 2.0 * 0.02 * 3e-4;
  const double dt = 0.001;
  for (int k = 0; k < 500; ++k) {
    bodies.push(0, Eigen::Vector3d(0, 3e-4, 0), Eigen::Vector3d(0.02, 0, 0));
    bodies.push(0, Eigen::Vector3d(0, -3e-4, 0), Eigen::Vector3d(-0.02, 0, 0));
    ASSERT_TRUE(bodies.step(BodyPushes{}, dt));
  }
  BodySnapshots snap;
  bodies.write(&snap);
  const Eigen::Vector3d omega = snap.bodies[0].angular_velocity_W;
  EXPECT_NEAR(omega.z(), tau / i_zz * 0.5, 1e-9 * tau / i_zz);  // ω = α t, α = τ / I
  EXPECT_LT(omega.head<2>().norm(), 1e-12);
  EXPECT_LT(snap.bodies[0].velocity_W.norm(), 1e-12);  // a couple: no net force
  // The angle turned: α t² / 2 + α t dt / 2, as for the translation.
  const double alpha = tau / i_zz;
  const Eigen::AngleAxisd turned(snap.bodies[0].pose_W.linear());
  EXPECT_NEAR(turned.angle(), 0.5 * alpha * 0.25 + 0.5 * alpha * 0.5 * dt, 1e-9);
}

// A body launched at a point proxy held still: the proxy's spring turns it back. The hand does
// no work (it does not move), so any kinetic energy the body comes back with beyond what it
// brought would be energy the coupling created. Stepped at the haptic rate right after the proxy
// (as the session does), the exchange is a symplectic Euler step of body and spring: it comes
// back with what it brought, to the error of the contact starting and ending inside a tick
// (O(ω dt): 0.04 % here), and with the materials' damping, with less. For contrast, the same
// stepped at 200 Hz on the mean force of the period before (a modelling loop's coupling) is
// printed: it gains more (1.6 % undamped).
double bounce(int ticks_per_body_step, double law_damping) {
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  haptics::TriangleMesh box = haptics::make_box(kBlockSides, 2);
  const haptics::MeshDatabase db = haptics::MeshDatabase::build(box);
  std::vector<haptics::HapticObject> objects(1);
  objects[0].mesh = &db;
  objects[0].law.stiffness_n_per_m = 500.0;
  objects[0].law.kind = haptics::ForceLaw::Kind::kHookeDamped;
  objects[0].law.damping_n_s_per_m = law_damping;
  MovingBodies bodies = one_block(0.2, centre);
  models::RigidBodyState launched;
  launched.linear_momentum_W = Eigen::Vector3d(0.2 * 0.05, 0, 0);  // 5 cm/s towards +x
  bodies.set_state(0, launched);
  const double ke0 = models::kinetic_energy(bodies.model(0), bodies.state(0));
  haptics::PointProxy proxy;
  const Eigen::Vector3d hip(0.025, 0.0, 0.0);  // 5 mm off the block's +x face
  proxy.reset(hip);
  const double dt = 0.001;
  Eigen::Vector3d held = Eigen::Vector3d::Zero();
  for (int k = 0; k < 1000; ++k) {
    bodies.pose_objects(objects);
    const haptics::PointProxyOutput out = proxy.step(objects, hip, dt);
    held += -out.force_W;  // the force on the body, summed over the body's period
    if ((k + 1) % ticks_per_body_step == 0) {
      const Eigen::Vector3d f = held / ticks_per_body_step;
      bodies.push(0, f, proxy.ihip());
      EXPECT_TRUE(bodies.step(BodyPushes{}, dt * ticks_per_body_step));
      held.setZero();
    }
  }
  EXPECT_LT(bodies.state(0).linear_momentum_W.x(), 0.0) << "the block must have bounced back";
  return models::kinetic_energy(bodies.model(0), bodies.state(0)) / ke0;
}

TEST(MovingBodies, ABodyBouncingOffAProbeHeldStillGainsNoEnergy) {
  const double undamped = bounce(1, 0.0);
  const double damped = bounce(1, 0.5);
  const double model_rate = bounce(5, 0.0);
  const double model_rate_damped = bounce(5, 0.5);
  std::printf(
      "kinetic energy after / before the bounce: %.6f undamped, %.6f with 0.5 N s/m; "
      "stepped at 200 Hz instead: %.6f, %.6f\n",
      undamped, damped, model_rate, model_rate_damped);
  EXPECT_LT(damped, 1.0) << "with the material's damping the bounce must lose energy";
  EXPECT_NEAR(undamped, 1.0, 1e-3) << "an undamped spring gives the energy back, no more";
}

// An inline scene: a 40 x 20 x 20 mm block at the origin (its top at y = 0.01), a point probe
// coming down on it from above, the left probe parked.
Scene block_scene(const test::TempDir& dir, const std::string& dynamics) {
  EXPECT_TRUE(save_obj(haptics::make_box(kBlockSides, 4), dir.path() / "block.obj").ok());
  const std::string yaml = R"(version: 1
name: block under a probe
organs:
  - name: block
    mesh: block.obj
    model: rigid
)" + dynamics + R"(
    material: {stiffness_n_per_m: 400}
trocars:
  - {name: pl, position_m: [-0.15, 0.12, 0.0]}
  - {name: pr, position_m: [0.0, 0.15, 0.0]}
tools:
  - {name: l, side: left, trocar: pl, kind: probe}
  - {name: r, side: right, trocar: pr, kind: probe}
)";
  const SceneLoadResult r = load_scene_file(dir.write("block.yaml", yaml));
  EXPECT_TRUE(r.ok()) << r.message();
  return r.value();
}

std::array<std::vector<TipWaypoint>, 2> press_down(double depth_m, double hold_until_s) {
  return {{{{0.0, Eigen::Vector3d(-0.15, 0.07, 0.0)},
            {hold_until_s, Eigen::Vector3d(-0.15, 0.07, 0.0)}},
           {{0.0, Eigen::Vector3d(0.0, 0.03, 0.0)},
            {0.5, Eigen::Vector3d(0.0, 0.03, 0.0)},
            {1.0, Eigen::Vector3d(0.0, 0.01 - depth_m, 0.0)},
            {hold_until_s, Eigen::Vector3d(0.0, 0.01 - depth_m, 0.0)}}}};
}

TEST(MovingBodiesInASession, AnAnchoredRigidOrganNeverMoves) {
  const test::TempDir dir;
  const Scene scene = block_scene(dir, "");
  Eigen::Vector3d last = Eigen::Vector3d::Zero();
  int32_t bodies_seen = -1;
  auto run = observed_session(scene, press_down(0.003, 1.5), 1.5,
                              [&](int64_t, const HapticSnapshot& h, const ModelSnapshot&) {
                                last = tip_force(h.tools[1]);
                                bodies_seen = h.bodies.count;
                              });
  run.session->run();
  EXPECT_EQ(run.session->bodies().count(), 0);
  EXPECT_EQ(bodies_seen, 0);
  // Held 3 mm into the fixed block's top: k · depth straight up, tick after tick.
  EXPECT_NEAR(last.y(), 400.0 * 0.003, 0.01);
  EXPECT_NEAR(last.head<1>().norm() + std::abs(last.z()), 0.0, 1e-6);
}

TEST(MovingBodiesInASession, TheToolsContactImpulsesAreTheBodysMomentum) {
  const test::TempDir dir;
  const Scene scene = block_scene(dir, "    dynamics: {mass_kg: 1.0}");
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
  const double dt = 0.001;
  int64_t pressing = 0;
  auto run = observed_session(scene, press_down(0.003, 1.5), 1.5,
                              [&](int64_t, const HapticSnapshot& h, const ModelSnapshot&) {
                                const Eigen::Vector3d f = -tip_force(h.tools[1]);
                                impulse += f * dt;
                                if (f.norm() > 0.0) ++pressing;
                              });
  run.session->run();
  impulse += -tip_force(run.session->graphics_haptic().tools[1]) * dt;  // the last tick's
  ASSERT_EQ(run.session->bodies().count(), 1);
  const models::RigidBodyState& s = run.session->bodies().state(0);
  EXPECT_GT(pressing, 100);
  EXPECT_GT(impulse.norm(), 1e-3);
  EXPECT_LT((s.linear_momentum_W - impulse).norm(), 1e-12 + 1e-9 * impulse.norm());
  // Pushed down, it went down.
  EXPECT_LT(s.pose_WB.translation().y(), -0.001);
}

TEST(MovingBodiesInASession, TheHapticTickWithProbesAndBodiesAllocatesNothing) {
  const test::TempDir dir;
  const Scene scene = block_scene(dir, "    dynamics: {mass_kg: 0.1}");
  auto count_for = [&](double duration) {
    auto run = observed_session(scene, press_down(0.003, 1.5), duration, nullptr);
    test::AllocationCounter counter;
    const SessionMetrics m = run.session->run();
    return counter.count();
  };
  EXPECT_EQ(count_for(0.2), count_for(1.5));
}

// The model kinds as the loader takes them: an organ given the catheter's mass-spring model, and
// dynamics on an organ that is not rigid or without its mass, are refused naming file and line.
TEST(ModelKinds, WhatAnOrganCannotBeIsRefusedWithFileAndLine) {
  const test::TempDir dir;
  ASSERT_TRUE(save_obj(haptics::make_box(kBlockSides, 1), dir.path() / "block.obj").ok());
  auto problems = [&](const std::string& organ) {
    const fs::path f = dir.write("s.yaml",
                                 "version: 1\nname: s\norgans:\n  - name: block\n"
                                 "    mesh: block.obj\n" +
                                     organ + "    material: {stiffness_n_per_m: 400}\n");
    const SceneLoadResult r = load_scene_file(f);
    EXPECT_FALSE(r.ok());
    return r.ok() ? std::string() : r.message();
  };
  EXPECT_NE(problems("    model: mass-spring\n")
                .find("s.yaml:6: organs[0].model: mass-spring is the catheter's model"),
            std::string::npos);
  EXPECT_NE(problems("    model: local\n    dynamics: {mass_kg: 1}\n")
                .find("s.yaml:7: organs[0].dynamics: only a rigid organ moves as a body"),
            std::string::npos);
  EXPECT_NE(
      problems("    dynamics: {linear_damping_per_s: 1}\n").find("s.yaml:6: organs[0].dynamics"),
      std::string::npos);
  EXPECT_NE(problems("    dynamics: {mass_kg: -1}\n").find("mass_kg"), std::string::npos);
}

}  // namespace
}  // namespace lap::sim
