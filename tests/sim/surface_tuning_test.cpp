// Live tuning of an organ's haptic surface in a running session (sim/runtime/surface_tuning.h):
// a probe pressing a slab feels k · depth, the stiffness is doubled through the mailbox, and
// from the next tick on it feels 2k · depth; the other parameters reach the objects the proxies
// read; the haptic tick allocates nothing while tunings keep arriving.

#include "sim/runtime/surface_tuning.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>

#include "haptics/setup/mesh_generators.h"
#include "sim/setup/mesh_loader.h"
#include "sim/setup/scenario_loader.h"
#include "tests/sim/demo_test_support.h"
#include "tests/support/counting_allocator.h"

namespace lap::sim {
namespace {

using demo_test::observed_session;
using demo_test::tip_force;
using V = Eigen::Vector3d;

constexpr double kK = 200.0;      // the slab's contact spring [N/m]
constexpr double kDepth = 0.001;  // pressed 1 mm: k d = 0.2 N, 2k d = 0.4 N (under the
                                  // default device's 0.88 N sustained force: sent unscaled)

// A slab (top at y = 0), the right tool a point probe straight above it: rigid with friction,
// or deforming locally (`model: local`, a finer mesh) without.
Scene slab_scene(const test::TempDir& dir, bool local = false) {
  EXPECT_TRUE(
      save_obj(haptics::make_box({0.06, 0.01, 0.06}, local ? 24 : 6), dir.path() / "slab.obj")
          .ok());
  const std::string material = local ? "    model: local\n"
                                       "    material:\n"
                                       "      stiffness_n_per_m: 200\n"
                                     : "    material:\n"
                                       "      stiffness_n_per_m: 200\n"
                                       "      friction_static: 0.4\n"
                                       "      friction_dynamic: 0.2\n";
  const SceneLoadResult r = load_scene_file(dir.write("slab.yaml", R"(version: 1
name: slab
organs:
  - name: slab
    mesh: slab.obj
    transform: {translation_m: [0, -0.005, 0]}
)" + material + R"(trocars:
  - {name: pl, position_m: [-0.15, 0.12, 0.0]}
  - {name: pr, position_m: [0.0, 0.15, 0.0]}
tools:
  - {name: l, side: left, trocar: pl, kind: probe}
  - {name: r, side: right, trocar: pr, kind: probe}
)"));
  EXPECT_TRUE(r.ok()) << r.message();
  return r.value();
}

// The author doubles the slab's stiffness (from the observer, between ticks).
void double_the_stiffness(Session* session) {
  SurfaceParameters p = session->surface_parameters(0);
  p.stiffness_n_per_m = 2.0 * kK;
  EXPECT_TRUE(session->tune_surface(0, p));
}

std::vector<TipWaypoint> parked() {
  return {{0.0, V(-0.15, 0.07, 0.0)}, {3.0, V(-0.15, 0.07, 0.0)}};
}
std::vector<TipWaypoint> press() {
  return {{0.0, V(0.0, 0.03, 0.0)}, {1.0, V(0.0, -kDepth, 0.0)}, {1.6, V(0.0, -kDepth, 0.0)}};
}

TEST(SurfaceTuning, DoublingTheStiffnessIsFeltAtTheNextTick) {
  const test::TempDir dir;
  const Scene scene = slab_scene(dir);
  constexpr int64_t kChangeTick = 1300;  // held 1 mm deep since tick 1000
  std::map<int64_t, double> felt;        // by tick: the tip's normal force [N]
  Session* session = nullptr;
  auto run = observed_session(scene, {parked(), press()}, 1.5,
                              [&](int64_t tick, const HapticSnapshot& h, const ModelSnapshot&) {
                                felt[h.tick] = tip_force(h.tools[1]).y();
                                // Which organ the tools touch, for the authoring panel.
                                if (tick == 100) {
                                  EXPECT_EQ(session->touched_organ(), -1);
                                }
                                if (tick == 1200) {
                                  EXPECT_EQ(session->touched_organ(), 0);
                                }
                                if (tick == kChangeTick) double_the_stiffness(session);
                              });
  ASSERT_NE(run.session, nullptr);
  session = run.session.get();
  EXPECT_EQ(session->surface_parameters(0).stiffness_n_per_m, kK);
  run.session->run();
  // Posted during tick kChangeTick (its device read): that tick still renders k, the next 2k.
  EXPECT_NEAR(felt.at(kChangeTick - 1), kK * kDepth, 1e-6);
  EXPECT_NEAR(felt.at(kChangeTick), kK * kDepth, 1e-6);
  EXPECT_NEAR(felt.at(kChangeTick + 1), 2.0 * kK * kDepth, 1e-6);
  EXPECT_NEAR(felt.at(kChangeTick + 100), 2.0 * kK * kDepth, 1e-6);
  EXPECT_EQ(session->surface_tunings_taken(), session->surface_tunings_posted());
  EXPECT_EQ(session->surface_parameters(0).stiffness_n_per_m, 2.0 * kK);
  // What reached the device: the vertical shaft passes the axial force 1:1 (the last command is
  // the zero sent at the end).
  ASSERT_GE(run.right->commands.size(), 2U);
  EXPECT_NEAR(run.right->commands[run.right->commands.size() - 2].force_W.y(), 2.0 * kK * kDepth,
              1e-6);
}

TEST(SurfaceTuning, EveryParameterReachesTheObjectsTheProxiesRead) {
  // Straight on TunedSurfaces: a friction-less, unshaded object with a texture.
  haptics::HapticObject object;
  object.law.stiffness_n_per_m = 300.0;
  struct Ramp final : haptics::HeightField {
    [[nodiscard]] haptics::HeightSample sample(const Eigen::Vector3d& p) const noexcept override {
      return {0.001 * p.x(), V(0.001, 0.0, 0.0)};
    }
    [[nodiscard]] double max_height_m() const noexcept override { return 0.002; }
  } ramp;
  object.texture = &ramp;
  std::vector<haptics::HapticObject> objects = {object};
  TunedSurfaces tuned;
  tuned.init(objects);
  EXPECT_FALSE(tuned.can_shade(0));
  EXPECT_TRUE(tuned.has_texture(0));
  EXPECT_EQ(tuned.parameters(0).friction_static, 0.0);

  SurfaceTuningMailbox mailbox;
  SurfaceParameters p = tuned.parameters(0);
  p.stiffness_n_per_m = 500.0;
  p.damping_n_s_per_m = 0.7;
  p.friction_static = 0.5;
  p.friction_dynamic = 0.8;  // above μs: capped to it
  p.shading = true;          // no normals: stays off
  p.texture_scale = 0.25;
  ASSERT_TRUE(mailbox.post(0, p));
  ASSERT_TRUE(mailbox.post(7, p));  // no such organ: ignored
  EXPECT_TRUE(tuned.take(&mailbox));
  tuned.apply(objects);
  const haptics::HapticObject& o = objects[0];
  EXPECT_EQ(o.law.stiffness_n_per_m, 500.0);
  EXPECT_EQ(o.law.damping_n_s_per_m, 0.7);
  EXPECT_EQ(o.law.kind, haptics::ForceLaw::Kind::kHookeDamped);
  ASSERT_NE(o.friction, nullptr);
  EXPECT_EQ(o.friction->mu_static, 0.5);
  EXPECT_EQ(o.friction->mu_dynamic, 0.5);
  // §6.2: no friction before, so the sticking spring follows k, the sliding one k μd / μs.
  EXPECT_EQ(o.friction->stick_stiffness_n_per_m, 500.0);
  EXPECT_EQ(o.friction->slide_stiffness_n_per_m, 500.0);
  EXPECT_EQ(o.shading, nullptr);
  ASSERT_NE(o.texture, nullptr);
  EXPECT_DOUBLE_EQ(o.texture->sample(V(2.0, 0, 0)).height_m, 0.25 * 0.002);
  EXPECT_DOUBLE_EQ(o.texture->sample(V(2.0, 0, 0)).gradient.x(), 0.25 * 0.001);
  EXPECT_DOUBLE_EQ(o.texture->max_height_m(), 0.25 * 0.002);

  // A non-finite value is not taken; friction off again removes it.
  SurfaceParameters bad = p;
  bad.stiffness_n_per_m = std::nan("");
  ASSERT_TRUE(mailbox.post(0, bad));
  p.friction_static = 0.0;
  p.friction_dynamic = 0.0;
  ASSERT_TRUE(mailbox.post(0, p));
  EXPECT_TRUE(tuned.take(&mailbox));
  tuned.apply(objects);
  EXPECT_EQ(objects[0].law.stiffness_n_per_m, 500.0);
  EXPECT_EQ(objects[0].friction, nullptr);
  EXPECT_EQ(mailbox.taken(), 4U);
}

// A replay sets the values the recording kept: each organ's parameters() after the live tick's
// tunings (sim/runtime/session_recorder.h). Setting them again changes nothing, even where the
// author's own values were capped (μd above μs, shading without normals); an organ without a
// tuning this tick is not marked as changed, so the recording holds one record per organ tuned.
TEST(SurfaceTuning, SettingTheRenderedParametersAgainChangesNothing) {
  haptics::HapticObject object;
  object.law.stiffness_n_per_m = 300.0;
  std::vector<haptics::HapticObject> objects = {object, object};
  TunedSurfaces live;
  live.init(objects);
  SurfaceParameters author = live.parameters(0);
  author.stiffness_n_per_m = 450.0;
  author.friction_static = 0.3;
  author.friction_dynamic = 0.9;  // capped to 0.3
  author.shading = true;          // no normals: off
  EXPECT_TRUE(live.set(0, author));
  EXPECT_TRUE(live.changed(0));
  EXPECT_FALSE(live.changed(1));
  live.apply(objects);
  const SurfaceParameters rendered = live.parameters(0);
  EXPECT_EQ(rendered.friction_dynamic, 0.3);
  EXPECT_FALSE(rendered.shading);

  std::vector<haptics::HapticObject> replayed_objects = {object, object};
  TunedSurfaces replay;
  replay.init(replayed_objects);
  EXPECT_TRUE(replay.set(0, rendered));
  replay.apply(replayed_objects);
  const haptics::HapticObject& a = objects[0];
  const haptics::HapticObject& b = replayed_objects[0];
  EXPECT_EQ(std::memcmp(&replay.parameters(0), &rendered, sizeof(SurfaceParameters)), 0);
  EXPECT_EQ(a.law.stiffness_n_per_m, b.law.stiffness_n_per_m);
  EXPECT_EQ(a.law.kind, b.law.kind);
  ASSERT_NE(b.friction, nullptr);
  EXPECT_EQ(a.friction->mu_dynamic, b.friction->mu_dynamic);
  EXPECT_EQ(a.friction->slide_stiffness_n_per_m, b.friction->slide_stiffness_n_per_m);
  EXPECT_EQ(a.friction->stick_stiffness_n_per_m, b.friction->stick_stiffness_n_per_m);

  live.clear_changed();
  EXPECT_FALSE(live.changed(0));
  SurfaceParameters bad = author;
  bad.damping_n_s_per_m = -1.0;
  EXPECT_FALSE(live.set(0, bad));  // refused: nothing changed, nothing to record
  EXPECT_FALSE(live.set(2, author));
  EXPECT_FALSE(live.changed(0));
}

// The haptic loop forwards a tuned stiffness to the modelling loop with the tick that posted it;
// the step that read tick t's snapshot takes those of ticks up to t only, and the rest wait, in
// order, for a later step (which a replay then runs at the same point).
TEST(SurfaceTuning, TheModellingStepTakesOnlyWhatTheTicksItReadPosted) {
  SurfaceTuningMailbox mailbox;
  SurfaceParameters p;
  for (int64_t tick : {10, 10, 12, 15}) {
    p.stiffness_n_per_m = static_cast<double>(tick);
    ASSERT_TRUE(mailbox.post(static_cast<int32_t>(tick), p, tick));
  }
  std::vector<int32_t> taken;
  const auto take = [&](int32_t organ, const SurfaceParameters&) { taken.push_back(organ); };
  EXPECT_EQ(mailbox.take_until(9, take), 0);
  EXPECT_EQ(mailbox.take_until(11, take), 2);
  EXPECT_EQ(taken, (std::vector<int32_t>{10, 10}));
  EXPECT_EQ(mailbox.take_until(14, take), 1);
  EXPECT_EQ(mailbox.take_until(15, take), 1);
  EXPECT_EQ(taken, (std::vector<int32_t>{10, 10, 12, 15}));
  EXPECT_EQ(mailbox.taken(), 4U);
}

TEST(SurfaceTuning, AFullMailboxRefusesAndKeepsOrder) {
  SurfaceTuningMailbox mailbox;
  SurfaceParameters p;
  for (uint64_t i = 0; i < SurfaceTuningMailbox::kCapacity; ++i) {
    p.stiffness_n_per_m = static_cast<double>(i);
    ASSERT_TRUE(mailbox.post(0, p));
  }
  EXPECT_FALSE(mailbox.post(0, p));
  double expected = 0.0;
  const int32_t n = mailbox.take([&](int32_t, const SurfaceParameters& q) {
    EXPECT_EQ(q.stiffness_n_per_m, expected);
    expected += 1.0;
  });
  EXPECT_EQ(n, static_cast<int32_t>(SurfaceTuningMailbox::kCapacity));
  EXPECT_TRUE(mailbox.post(0, p));
}

// A slab that deforms locally (thesis §6.3's local model), pressed kDepth deep by the probe: the
// dent takes its share s of the probe's displacement, s·d, and the probe feels (1 − s)·k·d
// (models/local_deformation.h). The model infers that displacement from the haptic loop's
// force, as force / k + the dent's depth, so it must divide by the k the haptic loop renders:
// the stiffness doubled live, the probe feels (1 − s)·2k·d and the dent stays s·d. Dividing by
// the scenario's k instead, the dent would settle at 2·s·d / (1 + s), 4/3 of it at s = 0.5.
TEST(SurfaceTuning, ATunedStiffnessReachesTheTissueModelSoTheDentKeepsItsShare) {
  const test::TempDir dir;
  const Scene scene = slab_scene(dir, true);
  constexpr int64_t kChangeTick = 1300;  // held 1 mm deep since tick 1000
  std::map<int64_t, double> felt, dent;  // by tick: the probe's normal force [N], the dent [m]
  Session* session = nullptr;
  const std::vector<TipWaypoint> hold = {
      {0.0, V(0.0, 0.03, 0.0)}, {1.0, V(0.0, -kDepth, 0.0)}, {2.0, V(0.0, -kDepth, 0.0)}};
  auto run = observed_session(scene, {parked(), hold}, 1.95,
                              [&](int64_t tick, const HapticSnapshot& h, const ModelSnapshot& m) {
                                felt[h.tick] = tip_force(h.tools[1]).y();
                                dent[tick] = m.deepest_dent_m;
                                if (tick == kChangeTick) double_the_stiffness(session);
                              });
  ASSERT_NE(run.session, nullptr);
  session = run.session.get();
  run.session->run();
  const double before = dent.at(kChangeTick - 10);
  const double after = dent.at(1900);
  ASSERT_GT(before, 0.25 * kDepth);  // pressed: about s·d, less between vertices
  EXPECT_NEAR(after, before, 0.01 * before);
  // What the probe feels: twice the force for the same dent.
  EXPECT_NEAR(felt.at(1900), 2.0 * felt.at(kChangeTick - 10), 0.02 * felt.at(kChangeTick - 10));
}

// The catheter meets a tuned organ with the tuned stiffness (TissueWorld's contact settings,
// which its contacts with the organ use): the haptic tick that takes the tuning forwards it, and
// the first modelling step that reads that tick's snapshot takes it up — a step later at most
// (200 Hz against 1 kHz: five ticks), never before the tick that took it.
TEST(SurfaceTuning, TheCatheterMeetsATunedOrganWithItsTunedStiffnessFromTheNextModellingStep) {
  const test::TempDir dir;
  const Scene scene = slab_scene(dir);
  constexpr int64_t kChangeTick = 1300;
  std::map<int64_t, double> catheter_k;  // by tick, at its start
  Session* session = nullptr;
  auto run = observed_session(scene, {parked(), press()}, 1.5,
                              [&](int64_t tick, const HapticSnapshot&, const ModelSnapshot&) {
                                catheter_k[tick] = session->catheter_contact_stiffness(0);
                                if (tick == kChangeTick) double_the_stiffness(session);
                              });
  ASSERT_NE(run.session, nullptr);
  session = run.session.get();
  EXPECT_EQ(session->catheter_contact_stiffness(0), kK);
  run.session->run();
  const int64_t ticks_per_step = session->model().timing().ticks_per_model;
  // Taken by tick kChangeTick + 1; the step that reads it runs after it.
  EXPECT_EQ(catheter_k.at(kChangeTick + 1), kK);
  int64_t first = -1;
  for (const auto& [tick, k] : catheter_k) {
    if (k != kK && first < 0) first = tick;
  }
  ASSERT_GT(first, kChangeTick + 1);
  EXPECT_LE(first, kChangeTick + 2 + ticks_per_step);
  EXPECT_EQ(catheter_k.rbegin()->second, 2.0 * kK);
  EXPECT_EQ(session->catheter_contact_stiffness(0), 2.0 * kK);
}

// Friction tuned live (§6.2), before the probe reaches the slab: pressed 3 mm (Fn = k·3 mm) and
// then slid across slowly, it sticks up to the tuned μs·Fn and slides at the tuned μd·Fn, not at
// the scenario's 0.4 and 0.2 (probe_session_test.cpp's FrictionSticksToMuSFnThenSlidesAtMuDFn
// with the values from the file).
TEST(SurfaceTuning, FrictionTunedLiveSticksAndSlidesAtTheTunedCoefficients) {
  const test::TempDir dir;
  const Scene scene = slab_scene(dir);
  const double fn = kK * 0.003;
  double peak = 0.0, last = 0.0;
  Session* session = nullptr;
  auto run =
      observed_session(scene,
                       {parked(),
                        {{0.0, V(0.0, 0.03, 0.0)},
                         {1.0, V(0.0, -0.003, 0.0)},
                         {1.2, V(0.0, -0.003, 0.0)},
                         {3.0, V(0.006, -0.003, 0.0)}}},
                       3.0, [&](int64_t tick, const HapticSnapshot& h, const ModelSnapshot&) {
                         if (tick == 100) {
                           SurfaceParameters p = session->surface_parameters(0);
                           p.friction_static = 0.6;
                           p.friction_dynamic = 0.4;
                           EXPECT_TRUE(session->tune_surface(0, p));
                         }
                         if (tick < 1200) return;
                         const double resist = -tip_force(h.tools[1]).x();
                         peak = std::max(peak, resist);
                         last = resist;
                       });
  ASSERT_NE(run.session, nullptr);
  session = run.session.get();
  run.session->run();
  EXPECT_NEAR(peak, 0.6 * fn, 0.02 * fn);
  EXPECT_NEAR(last, 0.4 * fn, 0.01 * fn);
}

// Damping tuned live on an undamped slab: the probe pressed in at a steady 10 mm/s feels
// k·depth + b·v (the damper on its speed into the surface, force_law.h), and once held still
// k·depth alone.
TEST(SurfaceTuning, DampingTunedLiveAddsBTimesTheSpeedIntoTheSurface) {
  const test::TempDir dir;
  const Scene scene = slab_scene(dir);
  constexpr double kB = 5.0;       // [N s/m]
  constexpr double kSpeed = 0.01;  // [m/s]: from 1 mm above at 1.0 s to 2 mm deep at 1.3 s
  std::map<int64_t, double> felt;
  Session* session = nullptr;
  auto run =
      observed_session(scene,
                       {parked(),
                        {{0.0, V(0.0, 0.03, 0.0)},
                         {1.0, V(0.0, 0.001, 0.0)},
                         {1.3, V(0.0, -0.002, 0.0)},
                         {1.6, V(0.0, -0.002, 0.0)}}},
                       1.6, [&](int64_t tick, const HapticSnapshot& h, const ModelSnapshot&) {
                         felt[h.tick] = tip_force(h.tools[1]).y();
                         if (tick == 100) {
                           SurfaceParameters p = session->surface_parameters(0);
                           p.damping_n_s_per_m = kB;
                           EXPECT_TRUE(session->tune_surface(0, p));
                         }
                       });
  ASSERT_NE(run.session, nullptr);
  session = run.session.get();
  run.session->run();
  // At 1.2 s: 1 mm deep, still moving in.
  EXPECT_NEAR(felt.at(1200), kK * 0.001 + kB * kSpeed, 0.03 * (kK * 0.001 + kB * kSpeed));
  EXPECT_NEAR(felt.at(1550), kK * 0.002, 0.01 * kK * 0.002);
}

// Force shading (§6.1) switched off live on a faceted sphere whose scenario shades it: pressed
// and held, the probe's force is along an interpolated normal — no face's — while shaded, and
// exactly along the face's normal once shading is off; switched on again, as before.
TEST(SurfaceTuning, ShadingSwitchedLiveTurnsTheForceBetweenTheSmoothAndTheFacesNormal) {
  const test::TempDir dir;
  const haptics::TriangleMesh sphere = haptics::make_uv_sphere(0.02, 4, 8);
  ASSERT_TRUE(save_obj(sphere, dir.path() / "sphere.obj").ok());
  const SceneLoadResult loaded = load_scene_file(dir.write("sphere.yaml", R"(version: 1
name: faceted sphere
organs:
  - name: sphere
    mesh: sphere.obj
    material:
      stiffness_n_per_m: 200
      shading: {enabled: true, crease_angle_deg: 80}
trocars:
  - {name: pl, position_m: [-0.15, 0.12, 0.0]}
  - {name: pr, position_m: [0.0, 0.15, 0.0]}
tools:
  - {name: l, side: left, trocar: pl, kind: probe}
  - {name: r, side: right, trocar: pr, kind: probe}
)"));
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  // Down beside the pole, into a face of the first band (polar angle about 13°, azimuth 27°),
  // about 1 mm below the faceted surface there.
  std::map<int64_t, V> force;
  Session* session = nullptr;
  const std::vector<TipWaypoint> press = {
      {0.0, V(0.004, 0.03, 0.002)}, {1.0, V(0.004, 0.017, 0.002)}, {2.0, V(0.004, 0.017, 0.002)}};
  auto run = observed_session(loaded.value(), {parked(), press}, 1.9,
                              [&](int64_t tick, const HapticSnapshot& h, const ModelSnapshot&) {
                                force[h.tick] = tip_force(h.tools[1]);
                                if (tick == 1300 || tick == 1600) {
                                  SurfaceParameters p = session->surface_parameters(0);
                                  p.shading = tick == 1600;
                                  EXPECT_TRUE(session->tune_surface(0, p));
                                }
                              });
  ASSERT_NE(run.session, nullptr);
  session = run.session.get();
  EXPECT_TRUE(session->surface_can_shade(0));
  run.session->run();
  // The smallest angle between a force and any face's normal.
  const auto off_faces = [&](const V& f) {
    double best = M_PI;
    for (size_t t = 0; t < sphere.triangles.size(); ++t) {
      const auto& tri = sphere.triangles[t];
      const V n = (sphere.positions[static_cast<size_t>(tri[1])] -
                   sphere.positions[static_cast<size_t>(tri[0])])
                      .cross(sphere.positions[static_cast<size_t>(tri[2])] -
                             sphere.positions[static_cast<size_t>(tri[0])]);
      if (n.norm() > 0.0) best = std::min(best, test::angle_between(f, n));
    }
    return best;
  };
  const V shaded = force.at(1250), flat = force.at(1500), again = force.at(1850);
  ASSERT_GT(shaded.norm(), 0.05);
  ASSERT_GT(flat.norm(), 0.05);
  EXPECT_GT(off_faces(shaded), 0.02);  // rad: no face's normal
  EXPECT_LT(off_faces(flat), 1e-6);
  EXPECT_LT(test::angle_between(shaded, again), 1e-3);
}

// The author keeps moving a slider: a tuning every 5 ticks, and the haptic tick still allocates
// nothing (the count does not grow with the session's length).
TEST(SurfaceTuning, TheHapticTickAllocatesNothingWhileTuningsArrive) {
  const test::TempDir dir;
  const Scene scene = slab_scene(dir);
  auto count_for = [&](double duration) {
    Session* session = nullptr;
    SurfaceParameters p;
    auto run = observed_session(scene, {parked(), press()}, duration,
                                [&](int64_t tick, const HapticSnapshot&, const ModelSnapshot&) {
                                  if (tick % 5 != 0) return;
                                  p.stiffness_n_per_m = kK * (1.0 + 0.5 * std::sin(0.01 * tick));
                                  p.friction_static = 0.4;
                                  p.friction_dynamic = 0.2;
                                  EXPECT_TRUE(session->tune_surface(0, p));
                                });
    session = run.session.get();
    test::AllocationCounter counter;
    const SessionMetrics m = run.session->run();
    return counter.count();
  };
  EXPECT_EQ(count_for(0.2), count_for(1.5));
}

}  // namespace
}  // namespace lap::sim
