#pragma once
/// \file
/// Sessions, their metrics and trainees written to and read from one database (either
/// dialect). Writes are idempotent by the session's UUID (`INSERT ... ON CONFLICT DO NOTHING`,
/// which SQLite ≥ 3.24 and PostgreSQL ≥ 9.5 both accept): the second copy of a session changes
/// nothing, which is what makes the outbox's upload safe to repeat. Every row read back is
/// checked (session_row.h): a bad value is an error naming the row and field, never a default.

#include <QDateTime>
#include <QString>
#include <vector>

#include "app/store/session_row.h"
#include "app/store/sql_database.h"
#include "core/result.h"

namespace lap::app {

/// Inserts `row`, its trainee (if new) and `metrics`; the caller holds a write transaction.
/// True when the session was new, false when a session with its UUID was already there (then
/// nothing is written).
[[nodiscard]] Result<bool> insert_session(const Database& db, const SessionRow& row,
                                          const std::vector<MetricValue>& metrics);

/// Registers a trainee (nothing when already there).
[[nodiscard]] Status insert_trainee(const Database& db, const QString& name);

/// A filter on sessions; empty fields do not filter.
struct SessionFilter {
  QString trainee;
  QString scenario_file;
  QString uuid;
  bool outbox_only = false;  ///< only sessions still waiting in this database's outbox
};

/// The sessions matching `filter`, newest first (then by UUID, so the order is total).
[[nodiscard]] Result<std::vector<SessionRow>> select_sessions(const Database& db,
                                                              const SessionFilter& filter);

/// One session's metrics, by name.
[[nodiscard]] Result<std::vector<MetricValue>> select_metrics(const Database& db,
                                                              const QString& uuid);

/// One metric of one session, as a learning curve or a cohort sees it.
struct MetricPoint {
  QString trainee;
  QString uuid;
  QString scenario_file;
  QDateTime started_utc;
  double value = 0.0;  ///< NaN: undefined in that session
};

/// Metric `name` across the sessions matching `filter` (trainee, scenario), oldest first.
[[nodiscard]] Result<std::vector<MetricPoint>> select_metric(const Database& db,
                                                             const QString& name,
                                                             const SessionFilter& filter);

/// Every trainee's name, sorted.
[[nodiscard]] Result<std::vector<QString>> select_trainees(const Database& db);

}  // namespace lap::app
