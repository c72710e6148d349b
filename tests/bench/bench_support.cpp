#include "tests/bench/bench_support.h"

#include <cstdlib>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "haptics/setup/mesh_generators.h"
#include "sim/setup/mesh_loader.h"

namespace lap::bench {

namespace {

OrganSet load_organ_set() {
  // As tests/test_support.cpp: an empty LAP_SHARED_DIR counts as unset.
  const char* env = std::getenv("LAP_SHARED_DIR");
  const std::filesystem::path dir =
      std::filesystem::path(env != nullptr && *env != '\0' ? env : LAP_SHARED_DIR) / "meshes";
  OrganSet set;
  set.openhelp = true;
  set.label = "OpenHELP meshes";
  std::string why = "no OpenHELP meshes in " + dir.string();
  for (const char* f : {"liver_openhelp.stl", "stomach_openhelp.stl", "duodenum_openhelp.stl"}) {
    std::error_code ec;
    if (!std::filesystem::exists(dir / f, ec)) {
      set.openhelp = false;
      break;
    }
    // The scans are in millimetres. One that does not load is said, and the stand-ins used.
    Result<haptics::TriangleMesh> mesh = sim::load_mesh(dir / f, {0.001, 0.0});
    if (!mesh.ok()) {
      set.openhelp = false;
      why = mesh.message();
      break;
    }
    set.meshes.push_back(std::move(mesh).value());
  }
  if (!set.openhelp) {
    set.label = "generated stand-ins (" + why + ")";
    set.meshes = {haptics::make_stand_in_liver(), haptics::make_stand_in_gallbladder(),
                  haptics::make_uv_sphere(0.05, 80, 120)};
    set.meshes[2].transform(Eigen::Affine3d(Eigen::Translation3d(0.15, 0.0, 0.0)));
  }
  for (const haptics::TriangleMesh& m : set.meshes) set.triangles += m.triangle_count();
  return set;
}

}  // namespace

const OrganSet& organ_set() {
  static const OrganSet set = load_organ_set();
  return set;
}

StepTimer::StepTimer(size_t capacity) : samples_(capacity, 0.0) {}

double timer_overhead_ns() {
  static const double overhead = [] {
    std::vector<double> v(20000);
    for (double& x : v) {
      const auto a = std::chrono::steady_clock::now();
      const auto b = std::chrono::steady_clock::now();
      x = std::chrono::duration<double, std::nano>(b - a).count();
    }
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  }();
  return overhead;
}

void StepTimer::report(benchmark::State& state, const std::string& prefix) {
  if (count_ == 0) return;
  std::vector<double> s(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(count_));
  const double overhead = timer_overhead_ns();
  auto quantile = [&s, overhead](double q) {
    const auto k = static_cast<size_t>(q * static_cast<double>(s.size() - 1));
    std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(k), s.end());
    return std::max(0.0, s[k] - overhead);
  };
  state.counters[prefix + "median_ns"] = quantile(0.5);
  state.counters[prefix + "p99_ns"] = quantile(0.99);
  state.counters[prefix + "p999_ns"] = quantile(0.999);
  state.counters["timer_overhead_ns"] = overhead;
}

haptics::TriangleMesh table_4_1_object(int64_t triangles) {
  switch (triangles) {
    case 12:
      return haptics::make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 1);
    case 456:
      return haptics::make_uv_sphere(kSphereRadius, 13, 19);  // 2*19*12
    case 1800:
      return haptics::make_uv_sphere(kSphereRadius, 31, 30);  // 2*30*30
    case 64800:
      return haptics::make_uv_sphere(kSphereRadius, 181, 180);  // 2*180*180
    case 1000000:
      return haptics::make_uv_sphere(kSphereRadius, 501, 1000);  // 2*1000*500
    default:
      break;
  }
  throw std::invalid_argument("no Table 4-1 object with " + std::to_string(triangles) +
                              " triangles");
}

TableObject::TableObject(int64_t triangles)
    : db(haptics::MeshDatabase::build(table_4_1_object(triangles))) {}

const haptics::SegmentDatabase& TableObject::segments() {
  if (!segments_) {
    segments_ = std::make_unique<haptics::SegmentDatabase>(haptics::SegmentDatabase::build(db));
  }
  return *segments_;
}

TableObject& table_4_1_scene(int64_t triangles) {
  static std::map<int64_t, std::unique_ptr<TableObject>> cache;
  auto& s = cache[triangles];
  if (!s) s = std::make_unique<TableObject>(triangles);
  return *s;
}

}  // namespace lap::bench
