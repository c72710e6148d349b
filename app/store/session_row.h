#pragma once
/// \file
/// One training session as the store keeps it: who, which scenario (and which version of its
/// file), on which devices and station, when, how it ended, its whole report, and where its
/// recording is. Checked on the way in (add_session) and on the way out (a row read back), so a
/// bad value is named with its field rather than stored or shown.

#include <QDateTime>
#include <QString>
#include <QStringList>
#include <limits>
#include <utility>
#include <vector>

#include "core/result.h"

namespace lap::app {

struct SessionRow {
  QString uuid;           ///< the session's id (QUuid without braces), unique across stations
  QString trainee;        ///< trainee's name or ID as signed in
  QString scenario_file;  ///< the scenario's path as opened
  QString scenario_name;
  QString scenario_version;  ///< SHA-256 (hex) of the scenario file's bytes
  QString devices;           ///< e.g. "left=simulated; right=phantom:Left Omni+gripper:AB12"
  QString station;           ///< the station's name (host name by default)
  QDateTime started_utc;
  double duration_s = 0.0;
  QString result;       ///< success | failure | incomplete
  QStringList reasons;  ///< the task's reasons (documented vocabulary)
  double completion_time_s = std::numeric_limits<double>::quiet_NaN();  ///< NaN: none
  /// The whole run JSON (the "task" and "metrics" objects, …) as sim::session_report writes it.
  QString report_json;
  /// Where the session's files (session.lrec, *.lapdev, metrics.json) are.
  QString recording_dir;
  bool interrupted = false;  ///< its recording has no end (a crash): listed and reviewable
};

/// One training metric of a session (the run JSON's "metrics" object; docs/metrics.md).
struct MetricValue {
  QString name;  ///< snake_case with its unit as suffix (completion_time_s, max_force_duct_n)
  double value;  ///< NaN: undefined in that session (null in the JSON)
};

/// The task's results (sim/README.md, "The task engine").
[[nodiscard]] bool is_session_result(const QString& result);

/// Problems with `row` as the store would keep it, each naming its field (`sessions.result`) and
/// what was expected; `where` names the database (the diagnostics' file). Empty: fine.
[[nodiscard]] std::vector<Diagnostic> check_session_row(const SessionRow& row,
                                                        const std::string& where);

/// The run JSON's "metrics" object as rows, in the JSON's order; an empty report has none.
/// Diagnostics name `report_json.metrics.NAME` when a value is not a number or null, or the
/// report is not a JSON object.
[[nodiscard]] Result<std::vector<MetricValue>> report_metrics(const QString& report_json,
                                                              const std::string& where);

/// A SHA-256 (hex) of a file's bytes: SessionRow::scenario_version. Diagnostics name the file.
[[nodiscard]] Result<QString> file_sha256(const QString& file);

/// The timestamps the store writes: ISO 8601 in UTC with milliseconds
/// (2025-03-01T09:30:00.000Z), which sort as text in time order on every database.
[[nodiscard]] QString utc_text(const QDateTime& t);
/// The inverse; an invalid QDateTime when `text` is not such a time.
[[nodiscard]] QDateTime parse_utc_text(const QString& text);

}  // namespace lap::app
