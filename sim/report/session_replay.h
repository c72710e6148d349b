#pragma once
/// \file
/// A recorded session read back for review (`laptrainer-cli report`): the folder that
/// `run --record` writes (left.lapdev, right.lapdev, metrics.json, session.json) replayed through
/// a fresh session in lockstep, so that the task and the training metrics are recomputed from
/// the recorded inputs rather than trusted from the file. A --fast session replays to the same
/// state hash and the same metrics, exactly.
///
/// session.json: {"format": "laptrainer-session", "version": 1, "scenario": absolute path,
/// "scenario_digest": FNV-1a 64 of the scenario file's bytes as loaded (hex), "mode":
/// "fast"|"realtime", "duration_s", "haptic_rate_hz", "model_rate_hz", "dominant_hand":
/// "left"|"right"}. Written once, when the session starts (`run --record`) or is saved (the
/// window's), atomically and never over another; never rewritten.
///
/// The recording is untrusted input (a folder handed over for review): the scenario it names is
/// read only from the recording's own folder, the shipped scenarios' folders
/// (shipped_scenario_folders()) or a folder the reviewer allows (ReplaySettings), so that a
/// session.json naming /etc/passwd or ~/.ssh/id_rsa makes the report refuse it unread.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "core/result.h"
#include "sim/runtime/session.h"
#include "sim/setup/content_digest.h"
#include "sim/setup/runtime_settings.h"
#include "sim/setup/scene.h"

namespace lap::sim {

/// What a recorded session was run with.
struct SessionRecord {
  std::filesystem::path scenario;  ///< absolute (a relative one is the record's folder's)
  int scenario_line = 0;           ///< where session.json names it
  uint64_t scenario_digest = 0;
  RuntimeSettings settings;  ///< fast, duration, rates, dominant hand
};

/// session.json's text for a session on `scenario`, whose bytes as loaded had `digest`
/// (Scenario::digest), run with `settings` (it also heads the streamed recording, session.lrec).
[[nodiscard]] std::string session_record_json(const std::filesystem::path& scenario,
                                              uint64_t digest, const RuntimeSettings& settings);
/// The same with the digest of the scenario file as it is now.
[[nodiscard]] Result<std::string> session_record_json(const std::filesystem::path& scenario,
                                                      const RuntimeSettings& settings);

/// Writes `text` as DIR/session.json once: into a temporary file beside it, synced, then renamed
/// into place, never over an existing session.json (a full disk leaves no half-written record,
/// and never spoils one already there). Diagnostics name the file.
[[nodiscard]] Status write_session_record(const std::filesystem::path& dir,
                                          const std::string& text);

/// When the scenario file no longer holds the bytes the session loaded (`digest`): a warning for
/// the session's metrics that it changed while the session ran; nothing when it is unchanged.
[[nodiscard]] std::optional<std::string> scenario_change_warning(
    const std::filesystem::path& scenario, uint64_t digest);

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

/// What the reviewer says on the command line (`report --scenario FILE --allow-path DIR`).
struct ReplaySettings {
  /// Replay with this scenario instead of the one the recording names (its path is not
  /// followed; a digest that differs is noted).
  std::optional<std::filesystem::path> scenario;
  /// More folders the recorded scenario may be in; the scenario's own references may be in them
  /// too (ScenarioLoadSettings::allowed_paths).
  std::vector<std::filesystem::path> allowed_paths;
};

/// The folders a recording's scenario may be in without being allowed on the command line: the
/// recording's own folder `dir` and shipped_scenario_folders().
[[nodiscard]] std::vector<std::filesystem::path> replay_scenario_folders(
    const std::filesystem::path& dir);

/// A recorded session's scenario, loaded as its replay loads it (confined as above), and what the
/// replay's report says from it alone: the record, the scenario's name and task, the notes (a
/// scenario changed since, or named on the command line).
struct ReplayScenario {
  ReplayedSession session;  ///< no metrics yet
  Scene scene;
};
[[nodiscard]] Result<ReplayScenario> load_replay_scenario(const std::filesystem::path& dir,
                                                          const ReplaySettings& settings = {});

/// Replays DIR's recorded inputs (session.lrec, else left.lapdev and right.lapdev) through the
/// recorded scenario (confined as above), in lockstep (RuntimeSettings::fast), with the recorded
/// rates, duration and dominant hand.
[[nodiscard]] Result<ReplayedSession> replay_session(const std::filesystem::path& dir,
                                                     const ReplaySettings& settings = {});
/// The same, with `prepare` given the session (and the scene it was built from) before it runs:
/// the review keeps its frames through Session::observe_fast.
[[nodiscard]] Result<ReplayedSession> replay_session(
    const std::filesystem::path& dir, const ReplaySettings& settings,
    const std::function<void(Session& session, const Scene& scene)>& prepare);

}  // namespace lap::sim
