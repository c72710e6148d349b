// BM_RuntimeLoop: the whole runtime headless, in real time — the introductory scene, two scripted
// tools sweeping over the organs, the haptic loop at 1 kHz, the modelling loop at 200 Hz, and a
// graphics reader taking the newest snapshots at 60 Hz — for 60 s (LAP_RUNTIME_BENCH_S to
// change). BM_RuntimeLoopRendered (built with the app): the same with the graphics loop drawing
// each frame with VTK. Reports the haptic loop's achieved rate, start jitter p50/p99/p99.9,
// deadlines missed (a tick more than 2 ms late) and overruns, and the modelling loop's rate.
// Targets (issue 7): ≥ 999 Hz, p99.9 ≤ 200 µs, no tick later than 2 ms.

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <thread>

#include "hardware/scripted_device.h"
#include "sim/runtime/loop_stats.h"
#include "sim/runtime/realtime_thread.h"
#include "sim/runtime/session.h"
#include "sim/setup/device_factory.h"
#include "sim/setup/scenario_loader.h"

#ifdef LAP_BENCH_RENDERING
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include "app/session_actors.h"
#endif

namespace lap::bench {
namespace {

// A slow figure-of-eight of the handle 10–18 cm in, with the jaws opening and closing: the
// tool keeps touching the liver and gallbladder.
hardware::ScriptedTrajectory sweep(const sim::Scene& scene, int side, double duration_s) {
  hardware::ScriptedTrajectory t;
  const Eigen::Vector3d shallow = sim::default_handle_position(scene, side, 0.10);
  const Eigen::Vector3d deep = sim::default_handle_position(scene, side, 0.18);
  for (double time = 0.0; time <= duration_s + 1.0; time += 0.05) {
    const double depth = 0.5 + 0.5 * std::sin(0.9 * time);
    Eigen::Vector3d p = shallow + depth * (deep - shallow);
    p += 0.02 * Eigen::Vector3d(std::sin(0.7 * time), 0.0, std::sin(1.4 * time));
    const double grip = 0.15 + 0.6 * (0.5 + 0.5 * std::sin(2.1 * time + side));
    t.keyframes.push_back({time, p,
                           Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * std::sin(0.5 * time),
                                                                Eigen::Vector3d::UnitY())),
                           grip, 0});
  }
  return t;
}

// The CPU time the hypervisor took from this machine so far (steal, /proc/stat) [s]; 0 where
// there is none to read. A stall that an idle loop also sees, with steal rising over it, is
// the machine's.
double steal_s() {
  std::ifstream in("/proc/stat");
  std::string cpu;
  std::array<double, 8> t{};
  if (!(in >> cpu) || cpu != "cpu") return 0.0;
  for (double& v : t) {
    if (!(in >> v)) return 0.0;
  }
  const long hz = sysconf(_SC_CLK_TCK);
  return hz > 0 ? t[7] / static_cast<double>(hz) : 0.0;
}

// What the graphics loop does with the session while it runs, until `done`; counts its frames.
using GraphicsLoop =
    std::function<void(sim::Session& session, const std::atomic<bool>& done, int64_t* frames)>;

// The whole runtime for LAP_RUNTIME_BENCH_S seconds (default 60) with `graphics` as its graphics
// loop, and the haptic loop's figures as counters.
void run_runtime(benchmark::State& state, bool isolate_by_default, const GraphicsLoop& graphics) {
  const char* env = std::getenv("LAP_RUNTIME_BENCH_S");
  const double duration = env != nullptr ? std::atof(env) : 60.0;
  const sim::SceneLoadResult r =
      sim::load_scene_file(std::string(LAP_SOURCE_DIR) + "/scenarios/introductory.yaml");
  if (!r.ok()) {
    state.SkipWithError("the introductory scenario did not load");
    return;
  }
  for (auto _ : state) {
    std::array<std::unique_ptr<hardware::HapticDevice>, 2> d = {
        std::make_unique<hardware::ScriptedDevice>(sweep(r.value(), 0, duration), "left"),
        std::make_unique<hardware::ScriptedDevice>(sweep(r.value(), 1, duration), "right")};
    sim::RuntimeSettings rs;
    rs.duration_s = duration;
    rs.end_with_task = false;  // the loops' timing over the whole sweep, not the task
    // The haptic thread's processor kept to itself as the app does when it renders, not
    // headless (as laptrainer-cli); LAP_RUNTIME_ISOLATE=0 or 1 overrides.
    const char* isolate = std::getenv("LAP_RUNTIME_ISOLATE");
    rs.isolate_haptic_processor =
        isolate != nullptr ? std::string(isolate) == "1" : isolate_by_default;
    state.counters["isolated"] = rs.isolate_haptic_processor ? 1.0 : 0.0;
    auto created = sim::Session::create(r.value(), std::move(d), rs);
    if (!created.ok()) {
      state.SkipWithError(created.message().c_str());
      return;
    }
    const std::unique_ptr<sim::Session> session = std::move(created).value();
    std::atomic<bool> done{false};
    int64_t frames = 0;
    std::thread graphics_thread([&] { graphics(*session, done, &frames); });
    const double steal0 = steal_s();
    const sim::SessionMetrics m = session->run();
    state.counters["steal_ms"] = 1e3 * (steal_s() - steal0);
    done.store(true);
    graphics_thread.join();
    state.counters["seconds"] = duration;
    state.counters["achieved_rate_hz"] = m.haptic.achieved_rate_hz();
    state.counters["jitter_p50_us"] = m.haptic.jitter_quantile_s(0.5) * 1e6;
    state.counters["jitter_p99_us"] = m.haptic.jitter_quantile_s(0.99) * 1e6;
    state.counters["jitter_p999_us"] = m.haptic.jitter_quantile_s(0.999) * 1e6;
    state.counters["worst_late_us"] = m.haptic.worst_lateness_s() * 1e6;
    state.counters["missed_deadlines"] = static_cast<double>(m.haptic.missed_deadlines());
    state.counters["overruns"] = static_cast<double>(m.haptic.overruns());
    state.counters["mean_step_us"] = m.haptic.mean_step_s() * 1e6;
    state.counters["worst_step_us"] = m.haptic.worst_step_s() * 1e6;
    state.counters["model_rate_hz"] = m.model.achieved_rate_hz();
    state.counters["model_missed_deadlines"] = static_cast<double>(m.model.missed_deadlines());
    state.counters["graphics_frames"] = static_cast<double>(frames);
    state.counters["graphics_rate_hz"] = static_cast<double>(frames) / duration;
    state.counters["watchdog_events"] = static_cast<double>(m.events.size());
    state.counters["late_ticks"] = static_cast<double>(m.late_ticks);
  }
}

// The graphics loop as a reader only: the newest snapshots taken at 60 Hz.
void BM_RuntimeLoop(benchmark::State& state) {
  run_runtime(state, false,
              [](sim::Session& session, const std::atomic<bool>& done, int64_t* frames) {
                double contacts = 0.0;
                while (!done.load()) {
                  const sim::HapticSnapshot& h = session.graphics_haptic();
                  const sim::ModelSnapshot& m = session.graphics_model();
                  contacts += h.tools[0].contacts + h.tools[1].contacts;
                  benchmark::DoNotOptimize(m.catheter.data());
                  ++*frames;
                  std::this_thread::sleep_for(std::chrono::microseconds(16667));
                }
                benchmark::DoNotOptimize(contacts);
              });
}
BENCHMARK(BM_RuntimeLoop)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

#ifdef LAP_BENCH_RENDERING
// BM_RuntimeLoopRendered: the same with the graphics loop drawing every frame with VTK as the
// app does — the session's snapshots into the app's actors (organs deformed and re-lit, tools,
// catheter) and a 1024 x 720 render window, at 60 Hz — off screen. Needs an X display (run
// under xvfb-run -a; software OpenGL there, which is what loads these machines most).
void BM_RuntimeLoopRendered(benchmark::State& state) {
  if (std::getenv("DISPLAY") == nullptr) {
    state.SkipWithError("needs an X display: run under xvfb-run -a");
    return;
  }
  double update_s = 0.0;  // taking up the snapshots into the actors
  double render_s = 0.0;  // drawing
  int64_t drawn = 0;
  run_runtime(
      state, true, [&](sim::Session& session, const std::atomic<bool>& done, int64_t* frames) {
        vtkNew<vtkRenderWindow> window;
        window->SetOffScreenRendering(1);
        window->SetMultiSamples(0);  // as the app's view (app/vtk_view.cpp)
        window->SetSize(1024, 720);
        vtkNew<vtkRenderer> renderer;
        window->AddRenderer(renderer);
        vtkNew<vtkLight> light;
        light->SetLightTypeToHeadlight();
        renderer->AddLight(light);
        // What the app draws (app/session_actors.h), untextured.
        app::SessionDrawing drawing;
        for (int32_t i = 0; i < session.organ_count(); ++i) {
          drawing.surfaces.push_back(&session.organ_surface(i));
          drawing.looks.push_back({Eigen::Vector3d(0.8, 0.4, 0.35), nullptr});
        }
        for (size_t i = 0; i < 2; ++i) {
          drawing.instruments[i].gripper = session.model().tool(i).gripper;
          drawing.instruments[i].port_W = session.model().tool(i).trocar.port_W;
        }
        drawing.catheter_points = session.model().tissue().catheter_model().particle_count();
        drawing.catheter_radius_m = session.model().tissue().catheter_model().radius_m();
        app::SessionActors actors;
        actors.add(renderer, drawing);
        renderer->ResetCamera();
        auto next = std::chrono::steady_clock::now();
        while (!done.load()) {
          const auto t0 = std::chrono::steady_clock::now();
          actors.update(session.graphics_haptic(), session.graphics_model());
          const auto t1 = std::chrono::steady_clock::now();
          window->Render();
          const auto t2 = std::chrono::steady_clock::now();
          update_s += std::chrono::duration<double>(t1 - t0).count();
          render_s += std::chrono::duration<double>(t2 - t1).count();
          ++*frames;
          next += std::chrono::microseconds(16667);
          std::this_thread::sleep_until(next);
        }
        drawn = *frames;
      });
  if (drawn > 0) {
    state.counters["mean_actor_update_ms"] = 1e3 * update_s / static_cast<double>(drawn);
    state.counters["mean_render_ms"] = 1e3 * render_s / static_cast<double>(drawn);
  }
}
BENCHMARK(BM_RuntimeLoopRendered)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
#endif

// BM_SleepLoopBaseline: the haptic loop's timing with no work in it — the same absolute-time
// sleep and spin, the same priority request — for LAP_RUNTIME_BENCH_S seconds (default 30). What
// this machine's scheduler does to an idle 1 kHz loop, against which BM_RuntimeLoop's lateness
// is read.
void BM_SleepLoopBaseline(benchmark::State& state) {
  const char* env = std::getenv("LAP_RUNTIME_BENCH_S");
  const double duration = env != nullptr ? std::atof(env) : 30.0;
  for (auto _ : state) {
    double worst = 0.0;
    sim::LoopStats stats(0.001);
    const double steal0 = steal_s();
    std::thread loop([&] {
      const std::string refused = sim::request_realtime_priority(80);
      state.counters["sched_fifo"] = refused.empty() ? 1.0 : 0.0;
      const auto ticks = static_cast<int64_t>(duration * 1000.0);
      const int64_t period_ns = 1000000;
      const int64_t start = sim::monotonic_ns() + period_ns;
      for (int64_t k = 0; k < ticks; ++k) {
        const int64_t deadline = start + k * period_ns;
        sim::sleep_until_ns(deadline, sim::RuntimeSettings{}.spin_ns);
        const double late = static_cast<double>(sim::monotonic_ns() - deadline) * 1e-9;
        stats.add(late, 0.0);
        worst = std::max(worst, late);
      }
      stats.set_elapsed(static_cast<double>(sim::monotonic_ns() - start) * 1e-9);
    });
    loop.join();
    state.counters["steal_ms"] = 1e3 * (steal_s() - steal0);
    state.counters["seconds"] = duration;
    state.counters["achieved_rate_hz"] = stats.achieved_rate_hz();
    state.counters["jitter_p50_us"] = stats.jitter_quantile_s(0.5) * 1e6;
    state.counters["jitter_p99_us"] = stats.jitter_quantile_s(0.99) * 1e6;
    state.counters["jitter_p999_us"] = stats.jitter_quantile_s(0.999) * 1e6;
    state.counters["worst_late_us"] = worst * 1e6;
    state.counters["missed_deadlines"] = static_cast<double>(stats.missed_deadlines());
  }
}
BENCHMARK(BM_SleepLoopBaseline)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
}  // namespace lap::bench
