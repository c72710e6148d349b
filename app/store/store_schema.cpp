#include "app/store/store_schema.h"

#include <QDateTime>
#include <QStringList>

#include "app/store/session_row.h"

namespace lap::app {
namespace {

// Serialises migrations between stations on one PostgreSQL server (any fixed number: the
// store's own).
constexpr qint64 kMigrationLockKey = 7'240'024;

// Tables the store makes: a database holding one of them but no schema_version is not one
// this code made (or was damaged), and is not migrated over.
const char* const kStoreTables[] = {"trainees", "instructors", "sessions", "session_metrics",
                                    "outbox"};

}  // namespace

const std::vector<Migration>& store_migrations() {
  // Types both databases accept with the same meaning: TEXT, INTEGER, DOUBLE PRECISION (SQLite
  // gives it REAL affinity). Booleans are INTEGER 0/1 on both.
  static const std::vector<Migration> steps = {
      {1,
       "trainees, instructors, sessions and their metrics",
       {
           "CREATE TABLE schema_version (version INTEGER PRIMARY KEY, applied_utc TEXT NOT NULL, "
           "description TEXT NOT NULL)",
           "CREATE TABLE trainees (name TEXT PRIMARY KEY, added_utc TEXT NOT NULL)",
           "CREATE TABLE instructors (name TEXT PRIMARY KEY, salt_hex TEXT NOT NULL, "
           "hash_hex TEXT NOT NULL, iterations INTEGER NOT NULL CHECK (iterations > 0), "
           "added_utc TEXT NOT NULL)",
           "CREATE TABLE sessions ("
           "uuid TEXT PRIMARY KEY, "
           "trainee TEXT NOT NULL REFERENCES trainees (name), "
           "scenario_file TEXT NOT NULL, scenario_name TEXT NOT NULL, "
           "scenario_version TEXT NOT NULL, devices TEXT NOT NULL, station TEXT NOT NULL, "
           "started_utc TEXT NOT NULL, "
           "duration_s DOUBLE PRECISION NOT NULL CHECK (duration_s >= 0), "
           "result TEXT NOT NULL CHECK (result IN ('success', 'failure', 'incomplete')), "
           "reasons TEXT NOT NULL, "
           "completion_time_s DOUBLE PRECISION, "
           "report_json TEXT NOT NULL, recording_dir TEXT NOT NULL, "
           "interrupted INTEGER NOT NULL CHECK (interrupted IN (0, 1)), "
           "added_utc TEXT NOT NULL)",
           "CREATE INDEX sessions_by_trainee ON sessions (trainee, started_utc)",
           "CREATE INDEX sessions_by_time ON sessions (started_utc)",
           "CREATE TABLE session_metrics ("
           "session_uuid TEXT NOT NULL REFERENCES sessions (uuid) ON DELETE CASCADE, "
           "name TEXT NOT NULL, value DOUBLE PRECISION, PRIMARY KEY (session_uuid, name))",
           "CREATE INDEX session_metrics_by_name ON session_metrics (name)",
       }},
      {2,
       "the station's outbox: sessions waiting for the programme's server",
       {
           "CREATE TABLE outbox ("
           "session_uuid TEXT PRIMARY KEY REFERENCES sessions (uuid) ON DELETE CASCADE, "
           "queued_utc TEXT NOT NULL, attempts INTEGER NOT NULL DEFAULT 0, "
           "last_error TEXT NOT NULL DEFAULT '')",
       }},
  };
  return steps;
}

Result<int> schema_version(const Database& db) {
  const QStringList tables = db.handle().tables(QSql::Tables);
  if (!tables.contains(QStringLiteral("schema_version"))) {
    for (const char* t : kStoreTables) {
      if (tables.contains(QLatin1String(t))) {
        return db.problem("schema_version",
                          std::string("missing, yet the database has a '") + t +
                              "' table: not a laptrainer store, or a damaged one; expected an "
                              "empty database or one laptrainer made");
      }
    }
    return 0;
  }
  Result<QSqlQuery> q = db.run(QStringLiteral("SELECT version FROM schema_version"), {},
                               "schema_version", "read the schema version");
  if (!q.ok()) return std::move(q).diagnostics();
  int newest = 0;
  while (q->next()) {
    bool ok = false;
    const int v = q->value(0).toString().toInt(&ok);
    if (!ok || v < 1) {
      return db.problem("schema_version.version", "expected step numbers 1, 2, ..., found '" +
                                                      q->value(0).toString().toStdString() + "'");
    }
    newest = std::max(newest, v);
  }
  return newest;
}

Status migrate(const Database& db, int target) {
  Result<int> version = schema_version(db);
  if (!version.ok()) return std::move(version).diagnostics();
  if (version.value() > kSchemaVersion) {
    return db.problem("schema_version",
                      "the database is at schema version " + std::to_string(version.value()) +
                          ", newer than this laptrainer knows (" + std::to_string(kSchemaVersion) +
                          "): a newer laptrainer wrote it; update this station's laptrainer");
  }
  for (const Migration& step : store_migrations()) {
    if (step.version <= version.value() || step.version > target) continue;
    if (Status begun = db.begin_write(); !begun.ok()) return begun;
    if (db.dialect() == SqlDialect::kPostgresql) {
      Result<QSqlQuery> lock =
          db.run(QStringLiteral("SELECT pg_advisory_xact_lock(?)"), {kMigrationLockKey},
                 "schema_version", "take the migration lock");
      if (!lock.ok()) {
        db.rollback();
        return std::move(lock).diagnostics();
      }
    }
    // Another station may have applied this step while this one waited for the lock.
    Result<int> now = schema_version(db);
    if (!now.ok()) {
      db.rollback();
      return std::move(now).diagnostics();
    }
    if (now.value() >= step.version) {
      db.rollback();
      continue;
    }
    for (const char* sql : step.statements) {
      Result<QSqlQuery> done = db.run(QLatin1String(sql), {}, "schema_version",
                                      "apply schema step " + std::to_string(step.version));
      if (!done.ok()) {
        db.rollback();
        return std::move(done).diagnostics();
      }
    }
    Result<QSqlQuery> recorded = db.run(
        QStringLiteral(
            "INSERT INTO schema_version (version, applied_utc, description) VALUES (?, ?, ?)"),
        {step.version, utc_text(QDateTime::currentDateTimeUtc()),
         QString::fromUtf8(step.description)},
        "schema_version", "record schema step " + std::to_string(step.version));
    if (!recorded.ok()) {
      db.rollback();
      return std::move(recorded).diagnostics();
    }
    if (Status committed = db.commit(); !committed.ok()) return committed;
  }
  return {};
}

}  // namespace lap::app
