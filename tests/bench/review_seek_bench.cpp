// The instructor's review: seeking anywhere in a 10-minute session (issue 24: ≤ 200 ms). A seek
// is what the review's scrub bar does (app/review/replay_player.cpp): find the frame at the time
// (sim::ReplayTimeline::seek), take it up as the snapshots the actors read, update the app's
// actors (tools, catheter, the organs' deformation and normals) and, in the rendered variant,
// draw the 3D view. The timeline is a real one — the introductory scenario's expert session
// recorded by `laptrainer-cli run --fast --record` and replayed — laid end to end to ten minutes
// (12 000 frames at 20 a second), so every frame holds what a real frame holds.
//
//   xvfb-run -a build/release/bin/laptrainer-bench --benchmark_filter=BM_ReviewSeek

#ifdef LAP_BENCH_RENDERING
#include <unistd.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>
#include <string>

#include "app/session_actors.h"
#include "sim/report/replay_timeline.h"
#include "tests/bench/bench_support.h"

namespace lap::bench {
namespace {

constexpr double kSessionS = 600.0;
// The one replay that builds the timeline when a session is selected, per second of session
// (the recorded expert's, measured once): a 10-minute session's wait before its first seek.
double replay_s_per_session_s = 0.0;

// The expert's session recorded and replayed, its frames repeated to ten minutes; built once.
const sim::ReplayTimeline* ten_minute_timeline(std::string* error) {
  static std::unique_ptr<sim::ReplayTimeline> timeline;
  static std::string why;
  static bool tried = false;
  if (tried) {
    *error = why;
    return timeline.get();
  }
  tried = true;
  std::error_code ec;
  const std::filesystem::path bin =
      std::filesystem::read_symlink("/proc/self/exe", ec).parent_path();
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("lap-review-seek-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir, ec);
  const std::string source = LAP_SOURCE_DIR;
  const std::string command =
      (bin / "laptrainer-cli").string() + " run --scenario " + source +
      "/scenarios/introductory.yaml --left scripted:" + source +
      "/scenarios/scripts/introductory/expert_left.csv --right scripted:" + source +
      "/scenarios/scripts/introductory/expert_right.csv --fast --record " + dir.string() +
      " > /dev/null";
  if (std::system(command.c_str()) != 0) {
    why = "cannot record the expert's session: " + command;
    *error = why;
    return nullptr;
  }
  const auto replay_start = std::chrono::steady_clock::now();
  Result<sim::ReplayTimeline> replayed = sim::ReplayTimeline::replay(dir);
  const double replay_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - replay_start).count();
  std::filesystem::remove_all(dir, ec);
  if (!replayed.ok()) {
    why = replayed.message();
    *error = why;
    return nullptr;
  }
  const sim::ReplayTimeline& one = replayed.value();
  replay_s_per_session_s = replay_s / std::max(one.duration_s(), 1e-3);
  std::vector<sim::ReplayFrame> frames;
  const double period = one.duration_s() / static_cast<double>(std::max<size_t>(1, one.size() - 1));
  frames.reserve(static_cast<size_t>(kSessionS / period) + 1);
  for (size_t k = 0; frames.size() * period <= kSessionS; ++k) {
    sim::ReplayFrame f = one.frame(k % one.size());
    f.t_s = static_cast<double>(frames.size()) * period;
    f.tick = static_cast<int64_t>(frames.size());
    f.model_steps = static_cast<int64_t>(frames.size()) + 1;  // each a new step for the actors
    frames.push_back(std::move(f));
  }
  timeline = std::make_unique<sim::ReplayTimeline>(
      sim::ReplayTimeline::from_frames(one.scene(), std::move(frames)));
  return timeline.get();
}

// range(0): 0 the seek and the actors' update, 1 with the view drawn (1024 x 720, off screen).
void BM_ReviewSeek(benchmark::State& state) {
  const bool rendered = state.range(0) == 1;
  if (std::getenv("DISPLAY") == nullptr) {
    state.SkipWithError("needs an X display: run under xvfb-run -a");
    return;
  }
  std::string error;
  const sim::ReplayTimeline* timeline = ten_minute_timeline(&error);
  if (timeline == nullptr) {
    state.SkipWithError(error.c_str());
    return;
  }
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);  // as the app's view (app/vtk_view.cpp)
  window->SetSize(1024, 720);
  vtkNew<vtkRenderer> renderer;
  window->AddRenderer(renderer);
  vtkNew<vtkLight> light;
  light->SetLightTypeToHeadlight();
  renderer->AddLight(light);
  const sim::ReplayScene& scene = timeline->scene();
  app::SessionActors actors;
  actors.add(renderer, app::replay_drawing(scene));
  renderer->ResetCamera();
  window->Render();
  sim::HapticSnapshot haptic;
  sim::ModelSnapshot model;
  std::mt19937_64 random(24);
  std::uniform_real_distribution<double> anywhere(0.0, timeline->duration_s());
  StepTimer timer;
  double worst_ms = 0.0;
  for (auto _ : state) {
    const double t = anywhere(random);
    const auto t0 = std::chrono::steady_clock::now();
    timer.start();
    const size_t i = timeline->seek(t);
    timeline->snapshots(i, &haptic, &model);
    actors.update(haptic, model);
    if (rendered) window->Render();
    timer.stop();
    worst_ms = std::max(
        worst_ms,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  timer.report(state);
  state.counters["worst_ms"] = worst_ms;
  state.counters["frames"] = static_cast<double>(timeline->size());
  state.counters["session_s"] = timeline->duration_s();
  state.counters["replay_s_per_session_s"] = replay_s_per_session_s;
}
BENCHMARK(BM_ReviewSeek)->Arg(0)->Arg(1)->Iterations(200)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace lap::bench
#endif  // LAP_BENCH_RENDERING
