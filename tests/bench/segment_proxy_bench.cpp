// Issue 4 speed: the segment proxy's step while its tip slides over objects of 12 ... 10^6
// triangles (the Table 4-1 objects), and the three-segment gripper against the real OpenHELP
// liver, stomach and duodenum together.

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "haptics/friction.h"
#include "haptics/laparoscopic_gripper.h"
#include "haptics/mesh_database.h"
#include "haptics/procedural_textures.h"
#include "haptics/segment_database.h"
#include "haptics/segment_proxy.h"
#include "haptics/shading_normals.h"
#include "tests/bench/bench_support.h"

namespace lap::bench {
namespace {

using haptics::HapticObject;
using haptics::MeshDatabase;
using haptics::SegmentDatabase;

constexpr double kDepth = 0.002;  // tip pressed 2 mm in
constexpr double kSpeed = 0.02;   // sliding at 20 mm/s
constexpr double kDt = 0.001;
constexpr double kLength = 0.1;  // 10 cm of shaft behind the tip

// The tip's path: as BM_PointProxySlide (a circle on the cube's top, a precessing path over the
// sphere); the shaft leans 30° from the outward normal, in free space.
void slide_probe(int64_t triangles, int64_t tick, Eigen::Vector3d* a, Eigen::Vector3d* b) {
  const double s = kSpeed * kDt * static_cast<double>(tick);
  Eigen::Vector3d tip;
  Eigen::Vector3d normal;
  if (triangles == 12) {
    const double r = 0.03;
    tip = {r * std::cos(s / r), 0.05 - kDepth, r * std::sin(s / r)};
    normal = Eigen::Vector3d::UnitY();
  } else {
    const double R = kSphereRadius - kDepth;
    const double phi = s / (R * 0.8);
    const double theta = 1.0 + 0.6 * std::sin(0.37 * phi);
    tip = {R * std::sin(theta) * std::cos(phi), R * std::cos(theta),
           R * std::sin(theta) * std::sin(phi)};
    normal = tip.normalized();
  }
  const Eigen::Vector3d side = normal.cross(Eigen::Vector3d(0.3, 0.1, 0.9)).normalized();
  const double lean = 30.0 * M_PI / 180.0;
  *a = tip;
  *b = tip + kLength * (std::cos(lean) * normal + std::sin(lean) * side);
}

void BM_SegmentProxySlide(benchmark::State& state) {
  const int64_t n = state.range(0);
  TableObject& sc = table_4_1_scene(n);
  HapticObject object;
  object.mesh = &sc.db;
  object.segments = &sc.segments();
  haptics::SegmentProxy proxy;
  Eigen::Vector3d a;
  Eigen::Vector3d b;
  slide_probe(n, 0, &a, &b);
  const Eigen::Vector3d lift = (b - a).normalized() * 0.01;
  proxy.reset(a + lift, b + lift);
  for (int i = 1; i <= 20; ++i) {
    proxy.step({&object, 1}, a + lift * (1.0 - i / 20.0), b + lift * (1.0 - i / 20.0), kDt);
  }
  int64_t tick = 0;
  for (; tick < 2000; ++tick) {
    slide_probe(n, tick, &a, &b);
    proxy.step({&object, 1}, a, b, kDt);
  }
  StepTimer timer;
  int64_t contacts = 0;
  for (auto _ : state) {
    slide_probe(n, tick++, &a, &b);
    timer.start();
    const haptics::SegmentProxyOutput r = proxy.step({&object, 1}, a, b, kDt);
    timer.stop();
    contacts += r.contact_count;
    benchmark::DoNotOptimize(r);
  }
  timer.report(state);
  state.counters["triangles"] = static_cast<double>(sc.db.face_count());
  state.counters["in_contact"] =
      static_cast<double>(contacts) / static_cast<double>(state.iterations());
  state.counters["passes"] =
      static_cast<double>(proxy.stats().placements) / static_cast<double>(proxy.stats().steps);
  state.counters["refills"] =
      static_cast<double>(proxy.stats().cache_rebuilds) / static_cast<double>(proxy.stats().steps);
  state.counters["tree_sweeps"] =
      static_cast<double>(proxy.stats().tree_sweeps) / static_cast<double>(proxy.stats().steps);
  state.counters["cached_tests"] =
      static_cast<double>(proxy.stats().cached_tests) /
      static_cast<double>(std::max<int64_t>(1, proxy.stats().cached_sweeps));
}
BENCHMARK(BM_SegmentProxySlide)
    ->Apply([](benchmark::internal::Benchmark* b) {
      for (int64_t n : {12, 456, 1800, 64800, 1000000}) b->Arg(n);
    })
    ->Iterations(200000);

// The OpenHELP liver, stomach and duodenum (../shared/meshes, millimetres), as one scene; the
// generated stand-ins where those meshes are absent (bench_support.h). Every surface property
// on (chapter 6), as default.yaml has them: stick-slip friction on every organ; the liver shaded
// (§6.1), or textured (§6.3, the gallbladder's fractal texture: a texture wins over shading,
// §6.6).
struct OrganScene {
  std::vector<std::unique_ptr<MeshDatabase>> dbs;
  std::vector<std::unique_ptr<SegmentDatabase>> sds;
  std::vector<std::unique_ptr<haptics::ShadingNormals>> shading;
  haptics::FrictionModel friction;
  haptics::FractalNoise texture{0.0001, 0.004, 5, 2.0, 0.5, 1};
  std::vector<HapticObject> objects;
  int64_t triangles = 0;
  explicit OrganScene(bool textured) {
    friction.mu_static = 0.2;
    friction.mu_dynamic = 0.1;
    friction.stick_stiffness_n_per_m = 400.0;
    friction.slide_stiffness_n_per_m = 200.0;
    for (const haptics::TriangleMesh& mesh : organ_set().meshes) {
      dbs.push_back(std::make_unique<MeshDatabase>(MeshDatabase::build(mesh)));
      sds.push_back(std::make_unique<SegmentDatabase>(SegmentDatabase::build(*dbs.back())));
      shading.push_back(std::make_unique<haptics::ShadingNormals>(
          haptics::ShadingNormals::build(*dbs.back(), 40.0 * M_PI / 180.0)));
      HapticObject o;
      o.mesh = dbs.back().get();
      o.segments = sds.back().get();
      o.law.stiffness_n_per_m = 800.0;
      o.friction = &friction;
      if (textured) {
        o.texture = &texture;
      } else {
        o.shading = shading.back().get();
      }
      objects.push_back(o);
      triangles += o.mesh->face_count();
    }
  }
};

// The gripper's hinge slides 2 mm deep over the liver near a vertex, jaws half open, the shaft
// leaning 30° off the outward normal; the jaws open and close at 1 Hz.
void BM_GripperStep(benchmark::State& state, bool textured) {
  static OrganScene shaded_scene(false);
  static OrganScene textured_scene(true);
  OrganScene& sc = textured ? textured_scene : shaded_scene;
  state.SetLabel(organ_set().label + (textured ? ", textured + friction" : ", shaded + friction"));
  const MeshDatabase& liver = *sc.dbs[0];
  const int32_t v0 = liver.vertex_count() / 3;
  const Eigen::Vector3d p0 = liver.position(v0);
  const Eigen::Vector3d n0 = liver.vertex_normal(v0);
  const Eigen::Vector3d t1 = n0.cross(Eigen::Vector3d(0.3, 0.1, 0.9)).normalized();
  const Eigen::Vector3d t2 = n0.cross(t1);
  auto pose_at = [&](int64_t tick) {
    const double s = kSpeed * kDt * static_cast<double>(tick);
    const double r = 0.01;
    haptics::GripperPose pose;
    pose.hinge_W = p0 + r * (std::cos(s / r) * t1 + std::sin(s / r) * t2) - kDepth * n0;
    const double lean = 30.0 * M_PI / 180.0;
    pose.shaft_dir_W = std::cos(lean) * n0 + std::sin(lean) * t1;
    pose.open_dir_W = pose.shaft_dir_W.cross(t2).normalized();
    pose.opening_rad = 0.5 + 0.4 * std::sin(2.0 * M_PI * kDt * static_cast<double>(tick));
    return pose;
  };
  haptics::LaparoscopicGripper gripper;
  haptics::GripperPose start = pose_at(0);
  start.hinge_W += 0.01 * n0;
  gripper.reset(start);
  int64_t tick = 0;
  for (; tick < 2000; ++tick) gripper.step(sc.objects, pose_at(tick), kDt);
  StepTimer timer;
  int64_t contacts = 0;
  for (auto _ : state) {
    const haptics::GripperPose pose = pose_at(tick++);
    timer.start();
    const haptics::GripperOutput r = gripper.step(sc.objects, pose, kDt);
    timer.stop();
    contacts +=
        r.segments[0].contact_count + r.segments[1].contact_count + r.segments[2].contact_count;
    benchmark::DoNotOptimize(r);
  }
  timer.report(state);
  state.counters["triangles"] = static_cast<double>(sc.triangles);
  state.counters["contacts"] =
      static_cast<double>(contacts) / static_cast<double>(state.iterations());
  double passes = 0.0;
  double limits = 0.0;
  double refills = 0.0;
  double tree_sweeps = 0.0;
  for (int i = 0; i < 3; ++i) {
    passes += static_cast<double>(gripper.proxy(i).stats().placements) /
              static_cast<double>(gripper.proxy(i).stats().steps);
    limits += static_cast<double>(gripper.proxy(i).stats().placement_limit_hits) /
              static_cast<double>(gripper.proxy(i).stats().steps);
    refills += static_cast<double>(gripper.proxy(i).stats().cache_rebuilds) /
               static_cast<double>(gripper.proxy(i).stats().steps);
    tree_sweeps += static_cast<double>(gripper.proxy(i).stats().tree_sweeps) /
                   static_cast<double>(gripper.proxy(i).stats().steps);
  }
  state.counters["passes"] = passes;
  state.counters["limit_rate"] = limits;
  state.counters["refills"] = refills;
  state.counters["tree_sweeps"] = tree_sweeps;
  int64_t slips = 0;
  for (int i = 0; i < 3; ++i) slips += gripper.proxy(i).stats().stick_to_slide;
  state.counters["slips_per_s"] =
      static_cast<double>(slips) / (kDt * static_cast<double>(gripper.proxy(0).stats().steps));
}
// Registered with the scene's triangle count as its argument (47396 for the OpenHELP meshes).
const bool kGripperStepRegistered = [] {
  benchmark::RegisterBenchmark("BM_GripperStep", BM_GripperStep, false)
      ->Arg(organ_set().triangles)
      ->Iterations(100000);
  benchmark::RegisterBenchmark("BM_GripperStepTextured", BM_GripperStep, true)
      ->Arg(organ_set().triangles)
      ->Iterations(100000);
  return true;
}();

}  // namespace
}  // namespace lap::bench
