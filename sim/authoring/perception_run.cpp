#include "sim/authoring/perception_run.h"

#include <pthread.h>

#include <atomic>
#include <cctype>
#include <chrono>
#include <csignal>
#include <string>
#include <thread>

#include "sim/authoring/perception_trials.h"
#include "sim/runtime/session.h"
#include "sim/setup/device_factory.h"

namespace lap::sim {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string_view probe_name(ProbeMode mode) {
  return mode == ProbeMode::kPoint ? "the point probe" : "the ray probe";
}

// Joins the trial's loops whatever ends the wait for the answer: the session is stopped first
// (forces zeroed at its next tick, and again by run()).
struct LoopsThread {
  Session* session;
  std::thread thread;
  ~LoopsThread() {
    session->request_stop();
    if (thread.joinable()) thread.join();
  }
};

// What the participant names, read line by line; none when the answers end (or a signal
// interrupts the read).
std::optional<PerceivedShape> read_answer(std::istream& answers, std::ostream& prompts,
                                          const Session& session, const std::atomic<bool>& ended) {
  std::string line;
  bool told = false;
  while (std::getline(answers, line)) {
    if (const std::optional<PerceivedShape> named = parse_participant_answer(line)) return named;
    if (!told && (ended.load() || session.paused())) {
      prompts << "the trial's session has stopped (its time is up, or a device fault paused it; "
                 "the forces are off): name the shape you felt\n";
      told = true;
    }
    prompts << "'" << line.substr(0, 40)
            << "' names no shape: type sphere, cone, cylinder or cube (or 1-4)\n"
            << std::flush;
  }
  return std::nullopt;
}

// One trial: its session runs on a thread of its own while this one waits for the answer.
Status run_trial(PerceptionExperiment* experiment, const PerceptionRunSettings& settings,
                 Clock::time_point t0, std::istream& answers, std::ostream& prompts) {
  const PerceptionTrial trial = *experiment->current();
  const Scene scene = perception_scene(trial, settings.shape_size_m);
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices;
  for (int side = 0; side < 2; ++side) {
    auto device = make_device(settings.devices[static_cast<size_t>(side)], scene, side);
    if (!device.ok()) return device.diagnostics();
    devices[static_cast<size_t>(side)] = std::move(device).value();
  }
  RuntimeSettings rs = settings.runtime;
  rs.fast = false;
  rs.record_s = 0.0;  // nothing kept: no room reserved for the trial's whole length
  auto created = Session::create(scene, std::move(devices), rs);
  if (!created.ok()) return created.diagnostics();
  Session& session = *created.value();
  if (settings.before_trial) settings.before_trial();
  const auto total = experiment->trials().size();
  prompts << "trial " << trial.index + 1 << " of " << total << ": explore with "
          << probe_name(trial.mode)
          << ", then type the shape (sphere, cone, cylinder, cube, or 1-4) and Enter\n"
          << std::flush;
  Status status = experiment->start_trial(seconds_since(t0));
  if (!status.ok()) return status;
  std::optional<PerceivedShape> named;
  std::atomic<bool> ended{false};
  {
    LoopsThread loops{&session, std::thread([&session, &ended] {
                        // The stop signals go to the thread waiting for the answer (and the
                        // loops' threads, started from here, inherit this mask).
                        sigset_t stop;
                        sigemptyset(&stop);
                        sigaddset(&stop, SIGINT);
                        sigaddset(&stop, SIGTERM);
                        pthread_sigmask(SIG_BLOCK, &stop, nullptr);
                        (void)session.run();
                        ended.store(true);
                      })};
    named = read_answer(answers, prompts, session, ended);
  }
  if (!named) {
    return diagnostic("the answers ended after " + std::to_string(experiment->answers().size()) +
                      " of " + std::to_string(total) + " trials");
  }
  status = experiment->answer(*named, seconds_since(t0));
  if (status.ok() && settings.after_trial) settings.after_trial(*experiment);
  return status;
}

}  // namespace

std::optional<PerceivedShape> parse_participant_answer(std::string_view line) {
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!line.empty() && blank(line.front())) line.remove_prefix(1);
  while (!line.empty() && blank(line.back())) line.remove_suffix(1);
  std::string word;
  for (const char c : line) word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (word.size() == 1 && word[0] >= '1' && word[0] <= '4') {
    return kPerceivedShapes[static_cast<size_t>(word[0] - '1')];
  }
  return parse_perceived_shape(word);
}

Status run_perception_trials(PerceptionExperiment* experiment,
                             const PerceptionRunSettings& settings, std::istream& answers,
                             std::ostream& prompts) {
  const Clock::time_point t0 = Clock::now();
  while (!experiment->done()) {
    Status s = run_trial(experiment, settings, t0, answers, prompts);
    if (!s.ok()) return s;
  }
  return {};
}

}  // namespace lap::sim
