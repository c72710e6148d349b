#pragma once
/// \file
/// What a finished session leaves for review (instructors, `run --record`, the app's saved
/// sessions): its metrics as JSON (loop statistics, watchdog events, device states, warnings,
/// the state hash), and the folder that holds them beside the recorded inputs.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "core/result.h"
#include "sim/runtime/session.h"

namespace lap::sim {

/// One loop's statistics (LoopStats) as a JSON object: ticks, rate, jitter quantiles [us], missed
/// deadlines, overruns, step times [us].
[[nodiscard]] nlohmann::ordered_json loop_json(const LoopStats& stats);

/// The task's outcome as the JSON's top-level "task" object (docs/architecture.md): kind, result
/// (`success`, `failure`, `incomplete`), reasons, events (`t_s`, `kind`, and per kind `tool`,
/// `organ`, `depth_m`, `force_n` or `squeeze_n`, `duration_s`), completion_time_s (null while
/// incomplete), phase_times_s (null where not reached), events_dropped. A scenario without a
/// task: kind "none", result "incomplete", no reasons, no events.
[[nodiscard]] nlohmann::ordered_json task_to_json(TaskKind kind, const TaskState& task,
                                                  const std::vector<std::string>& organ_names);

/// The training metrics as the JSON's top-level "metrics" object: numbers in the order given,
/// null where undefined (docs/metrics.md).
[[nodiscard]] nlohmann::ordered_json training_to_json(const std::vector<Metric>& metrics);
/// The metrics' series (plots: insertion depth, force and squeeze on the duct, tool speeds), one
/// array per series with the times in "t_s".
[[nodiscard]] nlohmann::ordered_json series_to_json(const MetricsSeries& series);

/// The session's metrics as a JSON object (what `laptrainer-cli run` prints), keys in the order
/// written.
[[nodiscard]] nlohmann::ordered_json metrics_to_json(const SessionMetrics& m,
                                                     const std::string& scenario, bool fast);
/// The same, as indented text.
[[nodiscard]] std::string metrics_json(const SessionMetrics& m, const std::string& scenario,
                                       bool fast);

/// Writes the session's recorded inputs (left.lapdev, right.lapdev) and `metrics_json` as
/// metrics.json into `dir` (created if missing), and session.json if it is not there yet: each
/// file whole or not at all (core/whole_file.h), each tried whatever became of the others, and
/// one diagnostic naming the file for each that could not be written (a full disk).
[[nodiscard]] Status save_session(const Session& session, const SessionMetrics& m,
                                  const std::string& scenario, bool fast, const std::string& dir);

}  // namespace lap::sim
