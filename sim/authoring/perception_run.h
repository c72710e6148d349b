#pragma once
/// \file
/// Runs the §5.5 shape-perception experiment (sim/runtime/perception_experiment.h) with a
/// participant at the devices: each trial's scene (perception_trials.h) as a real-time session of
/// its own, nothing drawn; the participant explores with the trial's probe and names the shape on
/// a line of `answers` (`laptrainer-cli perception` gives it standard input). The trial's time
/// runs from its session's start to the line's arrival; the session is then stopped (forces
/// zeroed) and the next trial's begins. What the participant is told goes to `prompts`: the trial,
/// its probe, and what a line may hold — never the shape, and no feedback on the answer (§5.5).

#include <array>
#include <functional>
#include <istream>
#include <optional>
#include <ostream>
#include <string_view>

#include "core/result.h"
#include "hardware/device_spec.h"
#include "sim/runtime/perception_experiment.h"
#include "sim/setup/runtime_settings.h"

namespace lap::sim {

struct PerceptionRunSettings {
  std::array<hardware::DeviceSpec, 2> devices;  ///< left (parked), right (the probe)
  double shape_size_m = 0.04;                   ///< across (perception_scene)
  /// Each trial's session; its duration is how long a trial may last (then it waits for the
  /// answer with the forces off, and says so). Nothing is recorded.
  RuntimeSettings runtime;
  /// Called as each trial begins, before its prompt (the command line discards what was typed
  /// ahead on a terminal there), and after each answer (it writes the results so far).
  std::function<void()> before_trial;
  std::function<void(const PerceptionExperiment&)> after_trial;
};

/// What a participant's line names: "sphere", "cone", "cylinder", "cube" (any case, blanks
/// around it ignored) or 1 to 4 in that order; none for anything else.
[[nodiscard]] std::optional<PerceivedShape> parse_participant_answer(std::string_view line);

/// Runs the experiment's remaining trials. Stops with a diagnostic when a trial's devices or
/// session cannot be made, or when `answers` ends before the last trial, or its read is
/// interrupted by a signal (the answers given so far stay in `experiment`). A line that names no
/// shape is asked again, not counted. The sessions' threads block SIGINT and SIGTERM, so that a
/// stop signal interrupts the wait for an answer.
[[nodiscard]] Status run_perception_trials(PerceptionExperiment* experiment,
                                           const PerceptionRunSettings& settings,
                                           std::istream& answers, std::ostream& prompts);

}  // namespace lap::sim
