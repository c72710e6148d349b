#pragma once
/// \file
/// What the instructor's review exports, as text and files (no widgets, so tests check them
/// directly): a session's metrics (CSV, with the proficiency limit and verdict where the
/// scenario benchmarks the metric), its raw series (CSV), the whole session (JSON: the stored
/// record, the replay's task, metrics, proficiency and series), a trainee's metrics over their
/// sessions (CSV), and the PDF reports per session (sim/report/session_pdf.h) and per trainee
/// (sim/report/trainee_pdf.h). Numbers are written as the shortest text that reads back to the
/// same double; an undefined metric is an empty CSV field and null in JSON.

#include <QString>
#include <optional>
#include <string>
#include <vector>

#include "app/store/session_row.h"
#include "core/result.h"
#include "sim/report/session_replay.h"
#include "sim/report/trainee_pdf.h"
#include "sim/setup/scenario.h"

namespace lap::app {

/// The shortest decimal text that reads back to `v`; "" for a non-finite value.
[[nodiscard]] std::string number_text(double v);

/// `metric,value,limit,better,met` per metric; the last three empty where not benchmarked.
[[nodiscard]] std::string metrics_csv(const std::vector<sim::Metric>& metrics,
                                      const std::optional<sim::ProficiencySpec>& proficiency);

/// `t_s,insertion_depth_m,force_duct_n,squeeze_duct_n,speed_left_m_per_s,speed_right_m_per_s`.
[[nodiscard]] std::string series_csv(const sim::MetricsSeries& series);

/// The session as JSON: "session" (the stored row's fields), "report" (its stored run JSON),
/// and, when replayed, "replay" (metrics_to_json of the replay with its "series", notes and
/// whether the recording was interrupted).
[[nodiscard]] std::string session_json(const SessionRow& row, const sim::ReplayedSession* replayed);

/// One row per session (oldest first): uuid, started_utc, scenario_file, result, then each
/// metric named in `metric_names` (empty where a session lacks it).
[[nodiscard]] std::string trainee_metrics_csv(
    const std::vector<SessionRow>& sessions,
    const std::vector<std::vector<MetricValue>>& metrics_per_session,
    const std::vector<QString>& metric_names);

/// The per-trainee report's content from the store's rows (oldest first), their metrics and the
/// scenario's benchmarks.
[[nodiscard]] sim::TraineePdfContext trainee_report(
    const QString& trainee, const QString& scenario_name, const QString& scenario_file,
    const std::vector<SessionRow>& sessions,
    const std::vector<std::vector<MetricValue>>& metrics_per_session,
    const std::optional<sim::ProficiencySpec>& proficiency);

/// The session's PDF report (sim::session_pdf) from its replay.
[[nodiscard]] std::string session_pdf_bytes(const SessionRow& row,
                                            const sim::ReplayedSession& replayed);

/// Writes `bytes` to `file` (replacing it); the diagnostic names the file.
[[nodiscard]] Status write_export(const QString& file, const std::string& bytes);

/// The scenario's proficiency benchmarks, read from its file (none: the file has none or cannot
/// be read, which `why` then says).
[[nodiscard]] std::optional<sim::ProficiencySpec> scenario_proficiency(const QString& scenario_file,
                                                                       std::string* why = nullptr);

/// A stored session's metrics as the sim's Metric list (order kept; NaN for undefined).
[[nodiscard]] std::vector<sim::Metric> to_metrics(const std::vector<MetricValue>& values);

}  // namespace lap::app
