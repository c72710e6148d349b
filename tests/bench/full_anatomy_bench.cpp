// The whole anatomy of the hardest patient (issue 22; the easiest beside it), measured on the
// session's own loops: scenarios/patient_hard.yaml with the expert's insertion
// (scenarios/scripts/patient_hard/) run in --fast mode, each haptic tick and modelling step
// timed by the loops' step histograms (sim/runtime/loop_stats.h: 0.25 µs bins).
// - BM_HapticTickFullAnatomy: one haptic tick — both tools' three segment proxies against every
//   organ, their surface properties, the couplings, the limiter. Target: median <= 20 µs,
//   p99.9 <= 100 µs.
// - BM_ModelStepFullAnatomy: one modelling step — grasps, the catheter and its contacts, the
//   duct's modes, the dents, the task engine, the surfaces' take-up. Target: median <= 1 ms.
// - BM_ScenarioLoadToFirstTick/warm|cold: from reading the scenario to the first haptic tick
//   done, the duct's modes from the cache (warm) or computed (cold: an empty cache folder).
//   Target: warm <= 2 s.

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "hardware/scripted_device.h"
#include "hardware/scripted_trajectory.h"
#include "sim/runtime/session.h"
#include "sim/setup/scene.h"

namespace lap::bench {
namespace {

namespace fs = std::filesystem;

// A session of the patient `stem` (scenarios/<stem>.yaml) with its expert's scripts,
// `duration_s` long (--fast).
std::unique_ptr<sim::Session> expert_session(benchmark::State& state, const std::string& stem,
                                             double duration_s) {
  const fs::path scenario = fs::path(LAP_SOURCE_DIR) / "scenarios" / (stem + ".yaml");
  const fs::path scripts = fs::path(LAP_SOURCE_DIR) / "scenarios/scripts" / stem;
  const sim::SceneLoadResult r = sim::load_scene_file(scenario);
  if (!r.ok()) {
    state.SkipWithError((stem + " did not load: " + r.message()).c_str());
    return nullptr;
  }
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> d;
  for (int side = 0; side < 2; ++side) {
    auto t = hardware::load_scripted_trajectory(
        scripts / (side == 0 ? "expert_left.csv" : "expert_right.csv"));
    if (!t.ok()) {
      state.SkipWithError(t.message().c_str());
      return nullptr;
    }
    d[static_cast<size_t>(side)] =
        std::make_unique<hardware::ScriptedDevice>(std::move(t).value(), side == 0 ? "l" : "r");
  }
  sim::RuntimeSettings rs;
  rs.fast = true;
  rs.duration_s = duration_s;
  rs.end_with_task = false;  // the whole insertion and hold
  auto created = sim::Session::create(r.value(), std::move(d), rs);
  if (!created.ok()) {
    state.SkipWithError(created.message().c_str());
    return nullptr;
  }
  state.counters["organs"] = static_cast<double>(r.value().organs.size());
  state.counters["triangles"] = static_cast<double>(r.value().triangle_count());
  return std::move(created).value();
}

void report_steps(benchmark::State& state, const sim::LoopStats& s) {
  state.counters["steps"] = static_cast<double>(s.ticks());
  state.counters["median_ns"] = s.step_quantile_s(0.5) * 1e9;
  state.counters["p99_ns"] = s.step_quantile_s(0.99) * 1e9;
  state.counters["p999_ns"] = s.step_quantile_s(0.999) * 1e9;
  state.counters["mean_ns"] = s.mean_step_s() * 1e9;
  state.counters["worst_ns"] = s.worst_step_s() * 1e9;
}

void BM_HapticTickFullAnatomy(benchmark::State& state, const std::string& stem) {
  for (auto _ : state) {
    const std::unique_ptr<sim::Session> session = expert_session(state, stem, 20.0);
    if (!session) return;
    const sim::SessionMetrics m = session->run();
    report_steps(state, m.haptic);
    state.counters["task_success"] = m.task.result == sim::TaskResult::kSuccess ? 1.0 : 0.0;
  }
}
BENCHMARK_CAPTURE(BM_HapticTickFullAnatomy, hard, std::string("patient_hard"))
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_HapticTickFullAnatomy, easy, std::string("patient_easy"))
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

void BM_ModelStepFullAnatomy(benchmark::State& state, const std::string& stem) {
  for (auto _ : state) {
    const std::unique_ptr<sim::Session> session = expert_session(state, stem, 20.0);
    if (!session) return;
    const sim::SessionMetrics m = session->run();
    report_steps(state, m.model);
  }
}
BENCHMARK_CAPTURE(BM_ModelStepFullAnatomy, hard, std::string("patient_hard"))
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_ModelStepFullAnatomy, easy, std::string("patient_easy"))
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

// From reading the scenario to the first haptic tick done; cold: the modes computed afresh;
// warm: after one untimed load has filled the cache.
void BM_ScenarioLoadToFirstTick(benchmark::State& state, bool cold) {
  const fs::path cache = fs::temp_directory_path() / "laptrainer-bench-cold-modes";
  if (!cold) (void)expert_session(state, "patient_hard", 0.001);
  for (auto _ : state) {
    if (cold) {
      fs::remove_all(cache);
      setenv("LAPTRAINER_CACHE_DIR", cache.c_str(), 1);
    }
    const auto t0 = std::chrono::steady_clock::now();
    const std::unique_ptr<sim::Session> session = expert_session(state, "patient_hard", 0.001);
    if (!session) return;
    const sim::SessionMetrics m = session->run();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.SetIterationTime(s);
    state.counters["seconds"] = s;
    state.counters["haptic_ticks"] = static_cast<double>(m.haptic.ticks());
    if (cold) unsetenv("LAPTRAINER_CACHE_DIR");
  }
  if (cold) fs::remove_all(cache);
}
BENCHMARK_CAPTURE(BM_ScenarioLoadToFirstTick, warm, false)
    ->Iterations(3)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_ScenarioLoadToFirstTick, cold, true)
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

}  // namespace
}  // namespace lap::bench
