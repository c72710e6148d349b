#pragma once
/// \file
/// Shared pieces of the benchmarks: per-step timing with the timer's own cost removed, and the
/// thesis' Table 4-1 objects generated at the requested triangle count.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/segment_database.h"
#include "haptics/triangle_mesh.h"

namespace lap::bench {

/// Collects one duration per step; reports median and p99 (ns) as benchmark counters.
class StepTimer {
 public:
  explicit StepTimer(size_t capacity = 1U << 20U);
  void start() { t0_ = std::chrono::steady_clock::now(); }
  void stop() {
    const auto t1 = std::chrono::steady_clock::now();
    if (count_ < samples_.size()) {
      samples_[count_++] = std::chrono::duration<double, std::nano>(t1 - t0_).count();
    }
  }
  /// Sets median_ns, p99_ns and p999_ns counters (timer overhead subtracted), their names
  /// prefixed by `prefix` (for a second timer in the same benchmark).
  void report(benchmark::State& state, const std::string& prefix = "");

 private:
  std::vector<double> samples_;
  size_t count_ = 0;
  std::chrono::steady_clock::time_point t0_;
};

/// Cost of one start/stop pair of steady_clock, median over many [ns].
double timer_overhead_ns();

/// The object with `triangles` triangles: 12 = the thesis' cube; otherwise a latitude/longitude
/// sphere of radius 5 cm (Table 4-1's object 4 has 32402 vertices and 64800 polygons: exactly a
/// 180 x 181 sphere). Supported: 12, 456, 1800, 64800, 1000000.
haptics::TriangleMesh table_4_1_object(int64_t triangles);
/// A Table 4-1 object with its databases, built once per size for the whole benchmark run
/// (the 10^6-triangle one takes seconds); the segment database only when first asked for.
struct TableObject {
  explicit TableObject(int64_t triangles);
  haptics::MeshDatabase db;
  [[nodiscard]] const haptics::SegmentDatabase& segments();

 private:
  std::unique_ptr<haptics::SegmentDatabase> segments_;
};
TableObject& table_4_1_scene(int64_t triangles);

/// Three organs for the benchmarks that want real anatomy: the OpenHELP liver, stomach and
/// duodenum from ../shared/meshes (or $LAP_SHARED_DIR/meshes), in metres, in that order. A clone
/// without that folder gets the project's generated stand-ins instead (liver, gallbladder and a
/// sphere for the stomach), so every benchmark still runs; `label` says which set was used and
/// the benchmarks put it in their output.
struct OrganSet {
  std::vector<haptics::TriangleMesh> meshes;
  bool openhelp = false;
  std::string label;  ///< "OpenHELP meshes" or "generated stand-ins (...)"
  int64_t triangles = 0;
};
const OrganSet& organ_set();

/// Radius of the spheres [m]; the cube is 10 cm.
constexpr double kSphereRadius = 0.05;

}  // namespace lap::bench
