#pragma once
/// \file
/// A recorded session read back for review (`laptrainer-cli report`): the folder that
/// `run --record` writes (left.lapdev, right.lapdev, metrics.json, session.json) replayed through
/// a fresh session in lockstep, so that the task and the training metrics are recomputed from
/// the recorded inputs rather than trusted from the file. A --fast session replays to the same
/// state hash and the same metrics, exactly.
///
/// session.json: {"format": "laptrainer-session", "version": 1, "scenario": absolute path,
/// "scenario_digest": FNV-1a 64 of the scenario file's bytes (hex), "mode": "fast"|"realtime",
/// "duration_s", "haptic_rate_hz", "model_rate_hz", "dominant_hand": "left"|"right"}.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "core/result.h"
#include "sim/runtime/session.h"
#include "sim/setup/runtime_settings.h"
#include "sim/setup/scene.h"

namespace lap::sim {

/// What a recorded session was run with.
struct SessionRecord {
  std::filesystem::path scenario;  ///< absolute
  uint64_t scenario_digest = 0;
  RuntimeSettings settings;  ///< fast, duration, rates, dominant hand
};

/// FNV-1a 64 of a file's bytes; diagnostics name the file when it cannot be read.
[[nodiscard]] Result<uint64_t> file_digest(const std::filesystem::path& file);

/// session.json's text for a session on `scenario` run with `settings` (it also heads the
/// streamed recording, session.lrec).
[[nodiscard]] Result<std::string> session_record_json(const std::filesystem::path& scenario,
                                                      const RuntimeSettings& settings);

/// Writes DIR/session.json for a session on `scenario` run with `settings`.
[[nodiscard]] Status write_session_record(const std::filesystem::path& dir,
                                          const std::filesystem::path& scenario,
                                          const RuntimeSettings& settings);

/// Reads DIR/session.json; diagnostics name the file and the field, and what was expected.
[[nodiscard]] Result<SessionRecord> read_session_record(const std::filesystem::path& dir);

/// What a replay gives: the session's metrics, the record it replayed, and what a reader of
/// the report should know (the scenario changed since, a real-time session's replay).
struct ReplayedSession {
  SessionRecord record;
  std::string scenario_name;     ///< the scenario's `name`
  std::optional<TaskSpec> task;  ///< its task as it is now (thresholds for the plots)
  SessionMetrics metrics;
  std::vector<std::string> notes;
  /// From the streamed recording (session.lrec) when the folder has one, else the .lapdev
  /// files: interrupted when it has no end (the process was killed), with what was damaged.
  bool streamed = false;
  bool interrupted = false;
  int64_t recorded_ticks = 0;
  std::vector<std::string> recording_problems;
};

/// Replays DIR's recorded inputs (session.lrec, else left.lapdev and right.lapdev) through the
/// recorded scenario, in lockstep (RuntimeSettings::fast), with the recorded rates, duration
/// and dominant hand.
[[nodiscard]] Result<ReplayedSession> replay_session(const std::filesystem::path& dir);
/// The same, with `prepare` given the session (and the scene it was built from) before it runs:
/// the review keeps its frames through Session::observe_fast.
[[nodiscard]] Result<ReplayedSession> replay_session(
    const std::filesystem::path& dir,
    const std::function<void(Session& session, const Scene& scene)>& prepare);

}  // namespace lap::sim
