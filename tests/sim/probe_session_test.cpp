// Probe tools in sessions (tools[].kind probe and ray-probe; sim/runtime/probe_tool.h): pressing
// a plane or a sphere gives k · depth at the tip (and, through a vertical shaft, at the handle);
// friction sticks up to μs Fn and slides at μd Fn, and a sinusoidal texture gives
// k (h(x) + depth) along the perturbed normal, as in the point proxy's own tests
// (tests/haptics/friction_test.cpp, texture_test.cpp). The haptic tick with probes allocates
// nothing: tests/sim/moving_body_test.cpp.

#include <gtest/gtest.h>

#include <cmath>

#include "haptics/setup/mesh_generators.h"
#include "sim/setup/mesh_loader.h"
#include "tests/sim/demo_test_support.h"

namespace lap::sim {
namespace {

using demo_test::observed_session;
using demo_test::tip_force;
using V = Eigen::Vector3d;

constexpr double kK = 400.0;

// A slab (top at y = 0) or a sphere (radius 3 cm, centre at the origin), anchored, with
// `material` appended; the right tool of `kind` through a port straight above the origin.
Scene probe_scene(const test::TempDir& dir, bool sphere, const std::string& kind,
                  const std::string& material = "") {
  const haptics::TriangleMesh mesh =
      sphere ? haptics::make_uv_sphere(0.03, 48, 96) : haptics::make_box({0.06, 0.01, 0.06}, 6);
  EXPECT_TRUE(save_obj(mesh, dir.path() / "shape.obj").ok());
  const std::string yaml = std::string(R"(version: 1
name: probe
organs:
  - name: shape
    mesh: shape.obj
)") + (sphere ? "" : "    transform: {translation_m: [0, -0.005, 0]}\n") +
                           "    material:\n      stiffness_n_per_m: 400\n" + material + R"(
trocars:
  - {name: pl, position_m: [-0.15, 0.12, 0.0]}
  - {name: pr, position_m: [0.0, 0.15, 0.0]}
tools:
  - {name: l, side: left, trocar: pl, kind: probe}
  - {name: r, side: right, trocar: pr, kind: )" +
                           kind + "}\n";
  const SceneLoadResult r = load_scene_file(dir.write("probe.yaml", yaml));
  EXPECT_TRUE(r.ok()) << r.message();
  return r.value();
}

std::vector<TipWaypoint> parked() {
  return {{0.0, V(-0.15, 0.07, 0.0)}, {3.0, V(-0.15, 0.07, 0.0)}};
}

// Lowered from 3 cm above `surface_y` to `depth` below it, then held.
std::vector<TipWaypoint> press(double surface_y, double depth) {
  return {{0.0, V(0.0, surface_y + 0.03, 0.0)},
          {1.0, V(0.0, surface_y - depth, 0.0)},
          {1.5, V(0.0, surface_y - depth, 0.0)}};
}

// Pressed 2 mm (0.8 N: below the default device's 0.88 N sustained force, so the handle gets it
// unscaled). `tilt_rad`: how far the force may lean off the true normal (a tessellated sphere's
// facet beside its pole vertex leans less than the first ring's polar angle, π/48).
void expect_k_depth(const Scene& scene, double surface_y, ToolKind kind, double tilt_rad = 1e-9,
                    double tolerance_n = 1e-6) {
  const double depth = 0.002;
  V felt = V::Zero();
  V proxy_tip = V::Zero();
  ToolKind seen = ToolKind::kGripper;
  auto run = observed_session(scene, {parked(), press(surface_y, depth)}, 1.5,
                              [&](int64_t, const HapticSnapshot& h, const ModelSnapshot&) {
                                felt = tip_force(h.tools[1]);
                                proxy_tip = h.tools[1].proxy_tip_W;
                                seen = h.tools[1].kind;
                              });
  ASSERT_NE(run.session, nullptr);
  run.session->run();
  EXPECT_EQ(seen, kind);
  EXPECT_NEAR(felt.norm(), kK * depth, tolerance_n);
  EXPECT_LT(test::angle_between(felt, V::UnitY()), tilt_rad);
  EXPECT_NEAR(proxy_tip.y(), surface_y, 1e-4) << "the proxy stays on the surface";
  // The shaft is vertical: the lever passes the axial force to the handle 1:1.
  // (The last command is the zero sent when the session ends.)
  ASSERT_GE(run.right->commands.size(), 2U);
  const V sent = run.right->commands[run.right->commands.size() - 2].force_W;
  EXPECT_NEAR(sent.y(), felt.y(), 1e-6);
}

TEST(ProbeSession, APointProbePressingAPlaneFeelsKTimesDepth) {
  const test::TempDir dir;
  expect_k_depth(probe_scene(dir, false, "probe"), 0.0, ToolKind::kPointProbe);
}

TEST(ProbeSession, APointProbePressingASphereFeelsKTimesDepth) {
  const test::TempDir dir;
  // The facets under the pole lie within r (1 − cos(π/48)) = 0.06 mm of the sphere: 2 %.
  expect_k_depth(probe_scene(dir, true, "probe"), 0.03, ToolKind::kPointProbe, M_PI / 48.0,
                 0.02 * kK * 0.002);
}

TEST(ProbeSession, ARayProbePressingAPlaneEndOnFeelsKTimesDepth) {
  const test::TempDir dir;
  expect_k_depth(probe_scene(dir, false, "ray-probe"), 0.0, ToolKind::kRayProbe);
}

// Position-driven across the slab 3 mm deep, slowly: the friction spring k_s dx holds up to
// μs Fn, then the contact slips and the resistance drops to μd Fn (friction_test.cpp's
// PositionDrivenStickThenSlipAtMuSFn, through the trocar).
TEST(ProbeSession, FrictionSticksToMuSFnThenSlidesAtMuDFn) {
  const test::TempDir dir;
  const Scene scene =
      probe_scene(dir, false, "probe", "      friction_static: 0.6\n      friction_dynamic: 0.4\n");
  const double fn = kK * 0.003;
  double peak = 0.0;
  double last = 0.0;
  auto run =
      observed_session(scene,
                       {parked(),
                        {{0.0, V(0.0, 0.03, 0.0)},
                         {1.0, V(0.0, -0.003, 0.0)},
                         {1.2, V(0.0, -0.003, 0.0)},
                         {3.0, V(0.006, -0.003, 0.0)}}},
                       3.0, [&](int64_t tick, const HapticSnapshot& h, const ModelSnapshot&) {
                         if (tick < 1200) return;
                         const double resist = -tip_force(h.tools[1]).x();
                         peak = std::max(peak, resist);
                         last = resist;
                       });
  run.session->run();
  std::printf("friction: peak %.4f N (μs Fn = %.4f), sliding %.4f N (μd Fn = %.4f)\n", peak,
              0.6 * fn, last, 0.4 * fn);
  EXPECT_NEAR(peak, 0.6 * fn, 0.02 * fn);
  EXPECT_NEAR(last, 0.4 * fn, 0.01 * fn);
}

// A sinusoidal texture h = A sin(2π x / λ), K h_max = 1 mm above the 0.2 mm depth (bump
// mapping, eq. 6-4b): wherever h(x) + depth > 0 the force is k (h(x) + depth) along the
// perturbed normal (−h'(x), 1, 0), elsewhere zero (texture_test.cpp's
// SinusoidForceFollowsTheAnalyticHeightAndGradient, through the trocar).
TEST(ProbeSession, ATextureGivesKTimesTheTexturedDepth) {
  const test::TempDir dir;
  const double a = 0.0005;
  const double lambda = 0.005;
  const double depth = 0.0002;
  const Scene scene = probe_scene(dir, false, "probe",
                                  "      texture: {kind: procedural, function: fourier, "
                                  "amplitude_m: 0.0005, wavelength_m: 0.005, k_mix: 2.0, "
                                  "direction: [1, 0, 0]}\n");
  int64_t touching = 0;
  int64_t free_ticks = 0;
  double worst = 0.0;
  double worst_angle = 0.0;
  // Down at x = −1 cm, then across at 1 cm/s, a waypoint every 0.5 mm so that the tip keeps to
  // the line.
  std::vector<TipWaypoint> stroke = {{0.0, V(-0.01, 0.01, 0.0)}, {0.5, V(-0.01, 0.01, 0.0)}};
  for (int i = 0; i <= 40; ++i) {
    stroke.push_back({1.0 + 0.05 * i, V(-0.01 + 0.0005 * i, -depth, 0.0)});
  }
  auto run = observed_session(
      scene, {parked(), stroke}, 3.0,
      [&](int64_t tick, const HapticSnapshot& h, const ModelSnapshot&) {
        if (tick < 1100) return;
        const ToolSnapshot& t = h.tools[1];
        // Where the tip is (its keyframes keep it within microns of the script's 0.2 mm).
        const double x = t.pose.hinge_W.x();
        const double d = a * std::sin(2.0 * M_PI * x / lambda) - t.pose.hinge_W.y();
        const V f = tip_force(t);
        if (d <= 0.0) {
          worst = std::max(worst, f.norm());
          ++free_ticks;
          return;
        }
        ++touching;
        worst = std::max(worst, std::abs(f.norm() - kK * d));
        const double slope = a * 2.0 * M_PI / lambda * std::cos(2.0 * M_PI * x / lambda);
        worst_angle = std::max(worst_angle, test::angle_between(f, V(-slope, 1.0, 0.0)));
      });
  run.session->run();
  EXPECT_GT(touching, 1000);
  EXPECT_GT(free_ticks, 300);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worst_angle, 1e-6);
}

}  // namespace
}  // namespace lap::sim
