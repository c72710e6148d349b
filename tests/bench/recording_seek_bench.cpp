// Seeking anywhere in a 10-minute recording by its frames (issue 24: ≤ 200 ms;
// sim/report/recorded_frames.h): a real 600 s session recorded — the introductory scenario's clumsy
// run that holds the catheter at the incision until the time limit (`laptrainer-cli run --fast
// --record`) — its file indexed once (RecordedFrames::open, timed), then 200 seeks to random
// times, each reading the chunk that holds the frame from the file, checking it and decoding it.
// No replay up to the time asked for. /0: the page cache holds the file (it was just written);
// /1: the file's pages are dropped from the cache before every seek (posix_fadvise DONTNEED), so
// that each seek reads its chunk from the disk.
//
//   build/release/bin/laptrainer-bench --benchmark_filter='BM_SeekInRecording|BM_ReviewOpen'
//   (LAP_SEEK_BENCH_S=20: a 20-second session instead, for the smoke test)

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "sim/report/recorded_frames.h"
#include "tests/bench/bench_support.h"

namespace lap::bench {
namespace {

// The recording, made once per run of the benchmark binary.
struct Recorded {
  std::filesystem::path dir;
  std::string error;
  double record_wall_s = 0.0;
  ~Recorded() {
    std::error_code ec;
    if (!dir.empty()) std::filesystem::remove_all(dir, ec);
  }
};

const Recorded& recorded() {
  static Recorded r = [] {
    Recorded out;
    std::error_code ec;
    const std::filesystem::path bin =
        std::filesystem::read_symlink("/proc/self/exe", ec).parent_path();
    out.dir = std::filesystem::temp_directory_path() /
              ("lap-seek-recording-" + std::to_string(::getpid()));
    std::filesystem::remove_all(out.dir, ec);
    const std::string source = LAP_SOURCE_DIR;
    const std::string scripts = source + "/scenarios/scripts/introductory/clumsy_time_limit_";
    const char* shorter = std::getenv("LAP_SEEK_BENCH_S");
    const std::string duration =
        shorter != nullptr ? " --duration " + std::string(shorter) : std::string();
    const std::string command = (bin / "laptrainer-cli").string() + " run --scenario " + source +
                                "/scenarios/introductory.yaml --left scripted:" + scripts +
                                "left.csv --right scripted:" + scripts + "right.csv --fast" +
                                duration + " --record " + out.dir.string() +
                                " > /dev/null 2> /dev/null";
    const auto t0 = std::chrono::steady_clock::now();
    if (std::system(command.c_str()) != 0) out.error = "cannot record the session: " + command;
    out.record_wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }();
  return r;
}

void BM_SeekInRecording(benchmark::State& state) {
  const Recorded& r = recorded();
  if (!r.error.empty()) {
    state.SkipWithError(r.error.c_str());
    return;
  }
  const std::filesystem::path file = r.dir / "session.lrec";
  const auto open_start = std::chrono::steady_clock::now();
  Result<sim::RecordedFrames> opened = sim::RecordedFrames::open(file);
  const double open_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - open_start)
          .count();
  if (!opened.ok()) {
    state.SkipWithError(opened.message().c_str());
    return;
  }
  sim::RecordedFrames& frames = opened.value();
  const bool cold = state.range(0) == 1;
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  std::mt19937_64 random(24);
  std::uniform_real_distribution<double> anywhere(0.0, frames.duration_s());
  sim::ReplayFrame frame;
  StepTimer timer;
  double worst_ms = 0.0;
  for (auto _ : state) {
    const double t = anywhere(random);
    if (cold) {
      state.PauseTiming();
      (void)::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
      state.ResumeTiming();
    }
    const auto t0 = std::chrono::steady_clock::now();
    timer.start();
    const Status sought = frames.seek(t, &frame);
    timer.stop();
    worst_ms = std::max(
        worst_ms,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (!sought.ok() || frame.t_s > t + 1e-6 || frame.t_s < t - 0.2) {
      state.SkipWithError("a seek gave no frame, or one not at or just before the time asked");
      break;
    }
  }
  if (fd >= 0) ::close(fd);
  timer.report(state);
  std::error_code ec;
  state.counters["worst_ms"] = worst_ms;
  state.counters["open_ms"] = open_ms;
  state.counters["session_s"] = frames.duration_s();
  state.counters["frames"] = static_cast<double>(frames.frame_count());
  state.counters["chunks"] = static_cast<double>(frames.chunk_count());
  state.counters["file_mb"] = static_cast<double>(std::filesystem::file_size(file, ec)) / 1e6;
  state.counters["record_wall_s"] = r.record_wall_s;
  state.counters["problems"] = static_cast<double>(frames.problems().size());
}
BENCHMARK(BM_SeekInRecording)->Arg(0)->Arg(1)->Iterations(200)->Unit(benchmark::kMillisecond);

// What the instructor waits for when selecting the session in the review: its recorded frames
// over its scene (ReplayTimeline::from_recorded_frames: the 3D replay can be scrubbed), then the
// replay that recomputes the metrics and plots (ReplayTimeline::replay), each timed once.
void BM_ReviewOpen(benchmark::State& state) {
  const Recorded& r = recorded();
  if (!r.error.empty()) {
    state.SkipWithError(r.error.c_str());
    return;
  }
  double frames_s = 0.0, replay_s = 0.0, frames = 0.0, replay_frames = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    Result<sim::ReplayTimeline> shown = sim::ReplayTimeline::from_recorded_frames(r.dir);
    const auto t1 = std::chrono::steady_clock::now();
    Result<sim::ReplayTimeline> replayed = sim::ReplayTimeline::replay(r.dir);
    const auto t2 = std::chrono::steady_clock::now();
    if (!shown.ok() || !replayed.ok()) {
      state.SkipWithError(shown.ok() ? replayed.message().c_str() : shown.message().c_str());
      return;
    }
    frames_s = std::chrono::duration<double>(t1 - t0).count();
    replay_s = std::chrono::duration<double>(t2 - t1).count();
    frames = static_cast<double>(shown.value().size());
    replay_frames = static_cast<double>(replayed.value().size());
  }
  state.counters["recorded_frames_s"] = frames_s;
  state.counters["replay_s"] = replay_s;
  state.counters["recorded_frames"] = frames;
  state.counters["replay_frames"] = replay_frames;
}
BENCHMARK(BM_ReviewOpen)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
}  // namespace lap::bench
