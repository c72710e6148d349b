#pragma once
/// \file
/// Where the trainee's attempts are kept: each in its own folder under the station's folder of
/// recordings, ~/.local/share/laptrainer/recordings/<uuid>/ (app/store's
/// StoreConnection::default_recordings_folder), readable by its owner only. The folder holds what
/// `laptrainer-cli report --session DIR` reviews:
///   attempt.json   who, which patient, which devices, when (written when the attempt starts)
///   session.json   what the session was run with (sim/report/session_replay.h)
///   session.lrec   the recording, streamed while it runs: a crash leaves it, interrupted
///   left.lapdev, right.lapdev, metrics.json   written when the attempt ends
/// An attempt is summed up as a SessionRow (the session database's row, app/store/).
/// Folders found with a recording but not filed (the application was killed mid-attempt, or
/// stopped between saving and filing) are found again by unfiled_attempts().

#include <QString>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

#include "app/store/session_row.h"
#include "core/result.h"

namespace lap::app {

/// The station's folder of recordings, ~/.local/share/laptrainer/recordings (the store's:
/// StoreConnection::default_recordings_folder), created with the owner's permissions only.
[[nodiscard]] Result<std::filesystem::path> recordings_root();

/// A new attempt: a fresh uuid, its folder under `root` (created, 0700), started now on
/// `station`, and attempt.json written. The record's result is "incomplete" until
/// finish_attempt().
[[nodiscard]] Result<SessionRow> begin_attempt(const std::filesystem::path& root,
                                               const QString& trainee,
                                               const std::filesystem::path& scenario_file,
                                               const QString& scenario_name, const QString& devices,
                                               const QString& station);

/// Fills the record's outcome from the metrics JSON (sim::metrics_to_json's: "task",
/// "metrics", "haptic"): result, reasons, completion time, duration, the report.
void finish_attempt(const nlohmann::ordered_json& metrics, SessionRow* record);

/// The record of the attempt in `dir`, from attempt.json and (when the attempt finished)
/// metrics.json; an attempt without metrics.json is interrupted, its duration read from the
/// streamed recording. Diagnostics name the file and what was wrong.
[[nodiscard]] Result<SessionRow> read_attempt(const std::filesystem::path& dir);

/// The attempt in `dir` as attempt.json describes it, without its outcome (cheap: for checking
/// whether it was filed).
[[nodiscard]] Result<SessionRow> read_attempt_header(const std::filesystem::path& dir);

/// The attempts under `root` that have a recording (session.lrec) and that `is_filed` (called
/// with each one's header) says were not filed, each read back with read_attempt; the folders
/// that could not be read are listed with why, not fatal.
struct UnfiledAttempts {
  std::vector<SessionRow> records;
  std::vector<std::string> problems;
};
template <typename IsFiled>
[[nodiscard]] UnfiledAttempts unfiled_attempts(const std::filesystem::path& root, IsFiled is_filed);

/// The attempt folders under `root` that hold a recording (session.lrec), oldest first.
[[nodiscard]] std::vector<std::filesystem::path> recorded_attempt_dirs(
    const std::filesystem::path& root);

template <typename IsFiled>
UnfiledAttempts unfiled_attempts(const std::filesystem::path& root, IsFiled is_filed) {
  UnfiledAttempts out;
  for (const std::filesystem::path& dir : recorded_attempt_dirs(root)) {
    const Result<SessionRow> header = read_attempt_header(dir);
    if (!header.ok()) {
      out.problems.push_back(header.message());
      continue;
    }
    if (is_filed(header.value())) continue;
    Result<SessionRow> r = read_attempt(dir);
    if (r.ok()) {
      out.records.push_back(std::move(r).value());
    } else {
      out.problems.push_back(r.message());
    }
  }
  return out;
}

}  // namespace lap::app
