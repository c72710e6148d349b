#pragma once
/// \file
/// What a finished session leaves for review (instructors, `run --record`, the app's saved
/// sessions): its metrics as JSON (loop statistics, watchdog events, device states, warnings,
/// the state hash), and the folder that holds them beside the recorded inputs.

#include <string>

#include "sim/session.h"

namespace lap::sim {

/// A JSON string literal of s (quotes and control characters escaped).
[[nodiscard]] std::string json_quote(const std::string& s);

/// The session's metrics as a JSON object (what `laptrainer-cli run` prints).
[[nodiscard]] std::string metrics_json(const SessionMetrics& m, const std::string& scenario,
                                       bool fast);

/// Writes the session's recorded inputs (left.lapdev, right.lapdev) and `metrics_json` as
/// metrics.json into `dir` (created if missing). False and *error (naming the file) on failure.
bool save_session(const Session& session, const SessionMetrics& m, const std::string& scenario,
                  bool fast, const std::string& dir, std::string* error);

}  // namespace lap::sim
