// BM_SurfaceEffects: the cost each surface property (thesis chapter 6) adds to one point-proxy
// step. Each iteration steps two proxies along the same sliding path over the 1800-triangle
// Table 4-1 sphere, one on the plain object and one with the effect, and times both: the
// reported added_ns is the median of the effect's step minus the median of the plain step, from
// the same run and the same ticks.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "haptics/friction.h"
#include "haptics/image_height_field.h"
#include "haptics/point_proxy.h"
#include "haptics/procedural_textures.h"
#include "haptics/shading_normals.h"
#include "tests/bench/bench_support.h"

namespace lap::bench {
namespace {

using haptics::HapticObject;
using haptics::PointProxy;

constexpr int64_t kTriangles = 1800;
constexpr double kDepth = 0.002;
constexpr double kDt = 0.001;

enum class Effect {
  kShading,
  kFriction,
  kFrictionRandomMap,
  kPerlin,
  kFbm,
  kWorley,
  kFourier,
  kImage,
  kAllWithTexture,  // friction + image texture + a moving object
  kAllWithWorley,   // friction + the costliest texture + a moving object
  kAllWithShading,  // friction + shading + a moving object
};

// Sliding 2 mm under the sphere's surface at 20 mm/s over many faces.
Eigen::Vector3d path(int64_t tick) {
  const double s = 0.02 * kDt * static_cast<double>(tick);
  const double r = kSphereRadius - kDepth;
  const double phi = s / (r * 0.8);
  const double theta = 1.0 + 0.6 * std::sin(0.37 * phi);
  return {r * std::sin(theta) * std::cos(phi), r * std::cos(theta),
          r * std::sin(theta) * std::sin(phi)};
}

struct Surfaces {
  haptics::ShadingNormals shading;
  haptics::FrictionModel friction;
  haptics::FrictionModel sandpaper;
  haptics::PerlinNoise perlin{0.0002, 0.003};
  haptics::FractalNoise fbm{0.0002, 0.004, 4};
  haptics::WorleyCells worley{0.0002, 0.003};
  haptics::FourierSeries fourier;
  std::unique_ptr<haptics::ImageHeightField> image;
  explicit Surfaces(const haptics::MeshDatabase& db)
      : shading(haptics::ShadingNormals::build(db, 0.6)) {
    friction.mu_static = 0.3;
    friction.mu_dynamic = 0.2;
    friction.stick_stiffness_n_per_m = 500.0;
    friction.slide_stiffness_n_per_m = 333.0;
    sandpaper = friction;
    sandpaper.map.kind = haptics::FrictionCoefficientMap::Kind::kRandom;
    fourier.add({0.0001, Eigen::Vector3d(300.0, 0.0, 0.0), 0.0});
    fourier.add({0.00005, Eigen::Vector3d(0.0, 500.0, 200.0), 1.0});
    fourier.add({0.00005, Eigen::Vector3d(100.0, 0.0, 700.0), 2.0});
    haptics::HeightImage img;
    img.width = 256;
    img.height = 256;
    for (int y = 0; y < 256; ++y) {
      for (int x = 0; x < 256; ++x) {
        img.values.push_back(
            static_cast<float>(0.5 + 0.25 * std::sin(0.2 * x) * std::cos(0.3 * y)));
      }
    }
    haptics::IntermediateSurface sphere;
    sphere.kind = haptics::IntermediateSurface::Kind::kSphere;
    sphere.repeat_u = 4;
    sphere.repeat_v = 2;
    image = std::make_unique<haptics::ImageHeightField>(std::move(img), sphere, 0.0002, 0.0001);
  }
};

void BM_SurfaceEffects(benchmark::State& state, Effect effect) {
  TableObject& sc = table_4_1_scene(kTriangles);
  static Surfaces surfaces(sc.db);
  HapticObject plain;
  plain.mesh = &sc.db;
  plain.law.stiffness_n_per_m = 500.0;
  HapticObject with = plain;
  bool moving = false;
  switch (effect) {
    case Effect::kShading:
      with.shading = &surfaces.shading;
      break;
    case Effect::kFriction:
      with.friction = &surfaces.friction;
      break;
    case Effect::kFrictionRandomMap:
      with.friction = &surfaces.sandpaper;
      break;
    case Effect::kPerlin:
      with.texture = &surfaces.perlin;
      break;
    case Effect::kFbm:
      with.texture = &surfaces.fbm;
      break;
    case Effect::kWorley:
      with.texture = &surfaces.worley;
      break;
    case Effect::kFourier:
      with.texture = &surfaces.fourier;
      break;
    case Effect::kImage:
      with.texture = surfaces.image.get();
      break;
    case Effect::kAllWithTexture:
      with.texture = surfaces.image.get();
      with.friction = &surfaces.friction;
      moving = true;
      break;
    case Effect::kAllWithWorley:
      with.texture = &surfaces.worley;
      with.friction = &surfaces.friction;
      moving = true;
      break;
    case Effect::kAllWithShading:
      with.shading = &surfaces.shading;
      with.friction = &surfaces.friction;
      moving = true;
      break;
  }
  PointProxy a;
  PointProxy b;
  const Eigen::Vector3d start = path(0) * 1.2;
  a.reset(start);
  b.reset(start);
  for (int i = 1; i <= 20; ++i) {
    const Eigen::Vector3d hip = start + (path(0) - start) * (i / 20.0);
    a.step({&plain, 1}, hip, kDt);
    b.step({&with, 1}, hip, kDt);
  }
  auto place = [&](int64_t tick) {
    if (!moving) return;
    // The organ breathes: a slow 1 mm shift (§6.4: the proxy works in the object's frame).
    const Eigen::Isometry3d pose(
        Eigen::Translation3d(0.0, 0.001 * std::sin(1e-3 * static_cast<double>(tick)), 0.0));
    plain.prev_pose_WO = plain.pose_WO;
    plain.pose_WO = pose;
    with.prev_pose_WO = with.pose_WO;
    with.pose_WO = pose;
  };
  int64_t tick = 1;
  for (; tick < 2000; ++tick) {
    place(tick);
    a.step({&plain, 1}, path(tick), kDt);
    b.step({&with, 1}, path(tick), kDt);
  }
  std::vector<double> base;
  std::vector<double> effect_ns;
  base.reserve(1U << 20U);
  effect_ns.reserve(1U << 20U);
  int64_t contacts = 0;
  for (auto _ : state) {
    place(tick);
    const Eigen::Vector3d hip = path(tick++);
    auto t0 = std::chrono::steady_clock::now();
    const haptics::PointProxyOutput ra = a.step({&plain, 1}, hip, kDt);
    auto t1 = std::chrono::steady_clock::now();
    const haptics::PointProxyOutput rb = b.step({&with, 1}, hip, kDt);
    auto t2 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(ra);
    benchmark::DoNotOptimize(rb);
    contacts += rb.contact_count > 0 || rb.texture_contact ? 1 : 0;
    if (base.size() < base.capacity()) {
      base.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
      effect_ns.push_back(std::chrono::duration<double, std::nano>(t2 - t1).count());
    }
  }
  auto median = [](std::vector<double>& v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const double mb = median(base);
  const double me = median(effect_ns);
  state.counters["plain_median_ns"] = mb;
  state.counters["median_ns"] = me;
  state.counters["added_ns"] = me - mb;
  state.counters["in_contact"] =
      static_cast<double>(contacts) / static_cast<double>(std::max<int64_t>(1, state.iterations()));
  state.counters["friction_slips"] = static_cast<double>(b.friction_state().stick_to_slide);
}

BENCHMARK_CAPTURE(BM_SurfaceEffects, shading, Effect::kShading)->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, friction, Effect::kFriction)->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, friction_random_map, Effect::kFrictionRandomMap)
    ->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, texture_perlin, Effect::kPerlin)->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, texture_fbm, Effect::kFbm)->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, texture_worley, Effect::kWorley)->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, texture_fourier, Effect::kFourier)->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, texture_image, Effect::kImage)->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, all_friction_image_moving, Effect::kAllWithTexture)
    ->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, all_friction_worley_moving, Effect::kAllWithWorley)
    ->Iterations(200000);
BENCHMARK_CAPTURE(BM_SurfaceEffects, all_friction_shading_moving, Effect::kAllWithShading)
    ->Iterations(200000);

}  // namespace
}  // namespace lap::bench
