#pragma once
/// \file
/// The store's schema and its migrations: the same tables on SQLite and PostgreSQL, built by
/// numbered steps. `schema_version` holds one row per step applied; opening a database applies
/// the steps it lacks, each in its own transaction (on PostgreSQL under an advisory lock, so
/// that two stations starting at once do not both build the tables). A database newer than this
/// code knows is refused with a clear error rather than written to.
///
/// Tables (docs in app/store/README.md):
///   trainees(name PK, added_utc)
///   instructors(name PK, salt_hex, hash_hex, iterations, added_utc)    accounts
///   sessions(uuid PK, trainee → trainees, scenario_file, scenario_name, scenario_version,
///            devices, station, started_utc, duration_s, result, reasons (JSON array),
///            completion_time_s (NULL: none), report_json, recording_dir, interrupted (0|1),
///            added_utc)
///   session_metrics(session_uuid → sessions, name, value (NULL: undefined); PK both)
///   outbox(session_uuid PK → sessions, queued_utc, attempts, last_error)    step 2
/// Times are ISO 8601 text in UTC with milliseconds (session_row.h utc_text): they sort as text.

#include <vector>

#include "app/store/sql_database.h"
#include "core/result.h"

namespace lap::app {

/// The newest schema this code knows.
inline constexpr int kSchemaVersion = 2;

struct Migration {
  int version;                          ///< 1, 2, ...: applied in order
  const char* description;              ///< kept in schema_version
  std::vector<const char*> statements;  ///< SQL both SQLite and PostgreSQL accept
};

/// Every step, oldest first.
[[nodiscard]] const std::vector<Migration>& store_migrations();

/// The database's schema version: 0 for an empty database. Diagnostics for a database that
/// holds the store's tables without a schema_version, or a schema_version that is not numbers.
[[nodiscard]] Result<int> schema_version(const Database& db);

/// Applies the steps after the database's version up to `target` (tests migrate to older
/// versions to make an old database). Refuses a database newer than kSchemaVersion.
[[nodiscard]] Status migrate(const Database& db, int target = kSchemaVersion);

}  // namespace lap::app
