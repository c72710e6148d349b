#include "app/store/session_store.h"

#include <QFileInfo>
#include <QUuid>
#include <algorithm>
#include <set>

#include "app/store/password_hash.h"
#include "app/store/sql_database.h"
#include "app/store/store_schema.h"

namespace lap::app {
namespace {

std::string str(const QString& s) { return s.toStdString(); }

// After a server did not answer, the station works on without it and tries again this much
// later (or at once when asked to upload): a session's end must not wait for a timeout each time.
constexpr int kServerRetryS = 30;

bool newest_first(const SessionRow& a, const SessionRow& b) {
  if (a.started_utc != b.started_utc) return a.started_utc > b.started_utc;
  return a.uuid > b.uuid;
}

bool oldest_first(const MetricPoint& a, const MetricPoint& b) {
  if (a.started_utc != b.started_utc) return a.started_utc < b.started_utc;
  return a.uuid < b.uuid;
}

Diagnostic store_problem(const SessionStore& store, const std::string& field,
                         const std::string& what) {
  return file_diagnostic(str(store.connection().server_name()), 0, field, what);
}

bool valid_name(const QString& name) {
  SessionRow probe;
  probe.trainee = name;
  for (const Diagnostic& d : check_session_row(probe, "")) {
    if (d.field == "sessions.trainee") return false;
  }
  return true;
}

}  // namespace

SessionStore::SessionStore(StoreConnection connection) : connection_(std::move(connection)) {}

SessionStore::~SessionStore() = default;

Result<std::unique_ptr<SessionStore>> SessionStore::open_default() {
  Result<StoreConnection> connection = StoreConnection::from_default_settings();
  if (!connection.ok()) return std::move(connection).diagnostics();
  return open(connection.value());
}

Result<std::unique_ptr<SessionStore>> SessionStore::open(const StoreConnection& connection) {
  if (connection.sqlite_path.isEmpty()) {
    return diagnostic("store/sqlite_path: expected the station's SQLite file");
  }
  std::unique_ptr<SessionStore> store(new SessionStore(connection));
  if (store->connection_.station.trimmed().isEmpty()) {
    store->connection_.station = QStringLiteral("station");
  }
  Result<std::unique_ptr<Database>> local = Database::open_sqlite(connection.sqlite_path);
  if (!local.ok()) return std::move(local).diagnostics();
  store->local_ = std::move(local).value();
  if (Status migrated = migrate(*store->local_); !migrated.ok()) return migrated.diagnostics();
  // The station's folder of recordings, owner-only beside its database (the default set-up).
  if (connection.sqlite_path == StoreConnection::default_sqlite_path()) {
    if (Status folder = make_private_folder(StoreConnection::default_recordings_folder(), true);
        !folder.ok()) {
      return folder.diagnostics();
    }
    if (Status folder = make_private_folder(QFileInfo(connection.sqlite_path).absolutePath(), true);
        !folder.ok()) {
      return folder.diagnostics();
    }
  }
  (void)store->server(true);  // a server that does not answer is told in sync_status()
  return store;
}

// --- The server ------------------------------------------------------------------------------

void SessionStore::server_failed(const std::vector<Diagnostic>& why) const {
  server_.reset();
  server_error_ = QString::fromStdString(to_string(why));
  next_server_attempt_utc_ = QDateTime::currentDateTimeUtc().addSecs(kServerRetryS);
}

const Database* SessionStore::server(bool retry_now) const {
  if (connection_.driver != StoreDriver::kPostgresql) return nullptr;
  if (server_) {
    if (server_->alive()) return server_.get();
    // It went away (restarted, network): try once at once, it may be back already.
    server_.reset();
    retry_now = true;
  }
  if (!retry_now && next_server_attempt_utc_.isValid() &&
      QDateTime::currentDateTimeUtc() < next_server_attempt_utc_) {
    return nullptr;
  }
  Result<QString> password = connection_password(connection_);
  if (!password.ok()) {
    server_failed(password.diagnostics());
    return nullptr;
  }
  Result<std::unique_ptr<Database>> db = Database::open_postgresql(connection_, password.value());
  if (!db.ok()) {
    server_failed(db.diagnostics());
    return nullptr;
  }
  if (Status migrated = migrate(*db.value()); !migrated.ok()) {
    server_failed(migrated.diagnostics());
    return nullptr;
  }
  server_ = std::move(db).value();
  server_error_.clear();
  next_server_attempt_utc_ = {};
  if (Status copied = refresh_account_copy(); !copied.ok()) {
    server_error_ = QString::fromStdString(copied.message());
  }
  return server_.get();
}

Status SessionStore::refresh_account_copy() const {
  // The station keeps a copy of the instructors' hashes so that they can sign in while the
  // server is down (to review this station's sessions).
  Result<QSqlQuery> q = server_->run(
      QStringLiteral("SELECT name, salt_hex, hash_hex, iterations, added_utc FROM instructors"), {},
      "instructors", "read the accounts");
  if (!q.ok()) return std::move(q).diagnostics();
  std::vector<QVariantList> rows;
  while (q->next()) {
    rows.push_back({q->value(0), q->value(1), q->value(2), q->value(3), q->value(4)});
  }
  if (Status begun = local_->begin_write(); !begun.ok()) return begun;
  Result<QSqlQuery> cleared = local_->run(QStringLiteral("DELETE FROM instructors"), {},
                                          "instructors", "refresh the accounts' copy");
  if (!cleared.ok()) {
    local_->rollback();
    return std::move(cleared).diagnostics();
  }
  for (const QVariantList& row : rows) {
    Result<QSqlQuery> added =
        local_->run(QStringLiteral("INSERT INTO instructors (name, salt_hex, hash_hex, iterations, "
                                   "added_utc) VALUES (?, ?, ?, ?, ?)"),
                    row, "instructors", "refresh the accounts' copy");
    if (!added.ok()) {
      local_->rollback();
      return std::move(added).diagnostics();
    }
  }
  return local_->commit();
}

SyncStatus SessionStore::sync_status() const {
  SyncStatus s;
  s.server_configured = connection_.driver == StoreDriver::kPostgresql;
  s.server_reachable = server_ != nullptr;
  s.last_error = server_error_;
  if (s.server_configured) {
    Result<QSqlQuery> q = local_->run(QStringLiteral("SELECT COUNT(*) FROM outbox"), {}, "outbox",
                                      "count the queued sessions");
    if (q.ok() && q->next()) {
      s.pending = q->value(0).toInt();
    } else if (!q.ok()) {
      s.last_error = QString::fromStdString(q.message());
    }
  }
  return s;
}

// --- Writing ---------------------------------------------------------------------------------

Status SessionStore::add_session(const SessionRow& given) {
  SessionRow row = given;
  // One spelling of a UUID, so that the same session cannot be stored twice under two.
  if (const QUuid uuid(row.uuid); !uuid.isNull()) row.uuid = uuid.toString(QUuid::WithoutBraces);
  std::vector<Diagnostic> problems = check_session_row(row, local_->name());
  Result<std::vector<MetricValue>> metrics = report_metrics(row.report_json, local_->name());
  if (!metrics.ok()) {
    const std::vector<Diagnostic>& d = metrics.diagnostics();
    problems.insert(problems.end(), d.begin(), d.end());
  }
  if (!problems.empty()) return problems;

  const bool with_server = connection_.driver == StoreDriver::kPostgresql;
  if (Status begun = local_->begin_write(); !begun.ok()) return begun;
  Result<bool> added = insert_session(*local_, row, metrics.value());
  if (!added.ok()) {
    local_->rollback();
    return std::move(added).diagnostics();
  }
  if (with_server && added.value()) {
    Result<QSqlQuery> queued =
        local_->run(QStringLiteral("INSERT INTO outbox (session_uuid, queued_utc) VALUES (?, ?) "
                                   "ON CONFLICT (session_uuid) DO NOTHING"),
                    {row.uuid, utc_text(QDateTime::currentDateTimeUtc())}, "outbox",
                    "queue session " + str(row.uuid) + " for the server");
    if (!queued.ok()) {
      local_->rollback();
      return std::move(queued).diagnostics();
    }
  }
  if (Status committed = local_->commit(); !committed.ok()) return committed;
  // Kept on the station: an upload that fails now leaves it queued for the next.
  if (with_server && server(false) != nullptr) (void)upload_pending();
  return {};
}

Status SessionStore::add_trainee(const QString& name) {
  if (!valid_name(name)) {
    return local_->problem("trainees.name",
                           "expected a trainee's name or ID (no leading or trailing space, no "
                           "control characters), found '" +
                               str(name) + "'");
  }
  if (Status added = insert_trainee(*local_, name); !added.ok()) return added;
  if (const Database* srv = server(false)) (void)insert_trainee(*srv, name);
  return {};
}

Status SessionStore::upload_pending(const std::function<bool(int, int)>& progress) {
  if (connection_.driver != StoreDriver::kPostgresql) return {};
  Result<QSqlQuery> q = local_->run(
      QStringLiteral("SELECT session_uuid FROM outbox ORDER BY queued_utc, session_uuid"), {},
      "outbox", "read the queued sessions");
  if (!q.ok()) return std::move(q).diagnostics();
  std::vector<QString> pending;
  while (q->next()) pending.push_back(q->value(0).toString());
  q->finish();
  if (pending.empty()) return {};

  const Database* srv = server(true);
  if (srv == nullptr) {
    return store_problem(*this, "",
                         "the server does not answer; " + std::to_string(pending.size()) +
                             " session(s) stay queued in " + str(connection_.sqlite_path) + ": " +
                             str(server_error_));
  }
  std::vector<Diagnostic> problems;
  const auto note_attempt = [&](const QString& uuid, const std::string& why) {
    (void)local_->run(QStringLiteral("UPDATE outbox SET attempts = attempts + 1, last_error = ? "
                                     "WHERE session_uuid = ?"),
                      {QString::fromStdString(why), uuid}, "outbox", "note the failed upload");
  };
  int done = 0;
  for (const QString& uuid : pending) {
    SessionFilter one;
    one.uuid = uuid;
    Result<std::vector<SessionRow>> rows = select_sessions(*local_, one);
    Result<std::vector<MetricValue>> metrics = select_metrics(*local_, uuid);
    if (!rows.ok() || !metrics.ok() || rows->size() != 1) {
      // A row this station cannot read back is not sent; it stays queued, named.
      std::vector<Diagnostic> why =
          !rows.ok()      ? rows.diagnostics()
          : !metrics.ok() ? metrics.diagnostics()
                          : std::vector<Diagnostic>{local_->problem(
                                "outbox", "session " + str(uuid) + " is queued but missing")};
      note_attempt(uuid, to_string(why));
      problems.insert(problems.end(), why.begin(), why.end());
      continue;
    }
    Status uploaded = srv->begin_write();
    if (uploaded.ok()) {
      Result<bool> inserted = insert_session(*srv, rows->front(), metrics.value());
      if (inserted.ok()) {
        uploaded = srv->commit();
      } else {
        srv->rollback();
        uploaded = std::move(inserted).diagnostics();
      }
    }
    if (!uploaded.ok()) {
      note_attempt(uuid, uploaded.message());
      if (!srv->alive()) {
        // The server went away mid-way: the rest stay queued for the next attempt.
        server_failed(uploaded.diagnostics());
        problems.insert(problems.end(), uploaded.diagnostics().begin(),
                        uploaded.diagnostics().end());
        problems.push_back(store_problem(*this, "outbox",
                                         "the server went away after " + std::to_string(done) +
                                             " of " + std::to_string(pending.size()) +
                                             " session(s); the rest stay queued"));
        return problems;
      }
      problems.insert(problems.end(), uploaded.diagnostics().begin(), uploaded.diagnostics().end());
      continue;
    }
    // Only now, with the server's commit done, does it leave the outbox: a crash in between
    // uploads it again, which the server ignores (same UUID).
    Result<QSqlQuery> dequeued =
        local_->run(QStringLiteral("DELETE FROM outbox WHERE session_uuid = ?"), {uuid}, "outbox",
                    "take session " + str(uuid) + " off the outbox");
    if (!dequeued.ok()) return std::move(dequeued).diagnostics();
    ++done;
    if (progress && !progress(done, static_cast<int>(pending.size()))) break;
  }
  if (!problems.empty()) return problems;
  return {};
}

// --- Reading ---------------------------------------------------------------------------------

Result<std::vector<SessionRow>> SessionStore::read_sessions(const SessionFilter& filter) const {
  const Database* srv = server(false);
  if (srv == nullptr) return select_sessions(*local_, filter);
  Result<std::vector<SessionRow>> remote = select_sessions(*srv, filter);
  if (!remote.ok()) {
    if (srv->alive()) return remote;  // the server's answer: a bad row there, named
    server_failed(remote.diagnostics());
    return select_sessions(*local_, filter);
  }
  // With the sessions still waiting here for the server.
  SessionFilter queued = filter;
  queued.outbox_only = true;
  Result<std::vector<SessionRow>> waiting = select_sessions(*local_, queued);
  if (!waiting.ok()) return waiting;
  std::vector<SessionRow> rows = std::move(remote).value();
  std::set<QString> seen;
  for (const SessionRow& r : rows) seen.insert(r.uuid);
  for (SessionRow& r : waiting.value()) {
    if (seen.insert(r.uuid).second) rows.push_back(std::move(r));
  }
  std::sort(rows.begin(), rows.end(), newest_first);
  return rows;
}

Result<std::vector<MetricPoint>> SessionStore::read_metric(const QString& name,
                                                           const SessionFilter& filter) const {
  const Database* srv = server(false);
  Result<std::vector<MetricPoint>> points =
      srv != nullptr ? select_metric(*srv, name, filter) : select_metric(*local_, name, filter);
  if (srv != nullptr && !points.ok()) {
    if (srv->alive()) return points;
    server_failed(points.diagnostics());
    srv = nullptr;
    points = select_metric(*local_, name, filter);
  }
  if (!points.ok() || srv == nullptr) return points;
  SessionFilter queued = filter;
  queued.outbox_only = true;
  Result<std::vector<MetricPoint>> waiting = select_metric(*local_, name, queued);
  if (!waiting.ok()) return waiting;
  std::vector<MetricPoint> all = std::move(points).value();
  std::set<QString> seen;
  for (const MetricPoint& p : all) seen.insert(p.uuid);
  for (MetricPoint& p : waiting.value()) {
    if (seen.insert(p.uuid).second) all.push_back(std::move(p));
  }
  std::sort(all.begin(), all.end(), oldest_first);
  return all;
}

Result<std::vector<QString>> SessionStore::read_trainees() const {
  Result<std::vector<QString>> local = select_trainees(*local_);
  if (!local.ok()) return local;
  const Database* srv = server(false);
  if (srv == nullptr) return local;
  Result<std::vector<QString>> remote = select_trainees(*srv);
  if (!remote.ok()) {
    if (srv->alive()) return remote;
    server_failed(remote.diagnostics());
    return local;
  }
  std::set<QString> names(remote->begin(), remote->end());
  names.insert(local->begin(), local->end());
  return std::vector<QString>(names.begin(), names.end());
}

Result<std::vector<SessionRow>> SessionStore::sessions(const QString& trainee,
                                                       const QString& scenario_file) const {
  if (trainee.isEmpty()) return store_problem(*this, "sessions.trainee", "expected a trainee");
  SessionFilter filter;
  filter.trainee = trainee;
  filter.scenario_file = scenario_file;
  return read_sessions(filter);
}

Result<std::vector<SessionRow>> SessionStore::all_sessions() const { return read_sessions({}); }

Result<std::vector<QString>> SessionStore::trainees() const { return read_trainees(); }

Result<SessionRow> SessionStore::session(const QString& uuid) const {
  SessionFilter filter;
  filter.uuid = uuid;
  Result<std::vector<SessionRow>> rows = read_sessions(filter);
  if (!rows.ok()) return std::move(rows).diagnostics();
  if (rows->empty()) return store_problem(*this, "sessions.uuid", "no session " + str(uuid));
  return rows->front();
}

Result<std::vector<MetricValue>> SessionStore::metrics(const QString& uuid) const {
  if (const Database* srv = server(false)) {
    Result<std::vector<MetricValue>> remote = select_metrics(*srv, uuid);
    if (remote.ok() && !remote->empty()) return remote;
    if (!remote.ok() && srv->alive()) return remote;
    if (!remote.ok()) server_failed(remote.diagnostics());
  }
  return select_metrics(*local_, uuid);
}

Result<std::vector<MetricPoint>> SessionStore::metric_history(const QString& name,
                                                              const QString& trainee,
                                                              const QString& scenario_file) const {
  SessionFilter filter;
  filter.trainee = trainee;
  filter.scenario_file = scenario_file;
  return read_metric(name, filter);
}

// --- Accounts and access ---------------------------------------------------------------------

Result<bool> SessionStore::has_instructors() const {
  const Database* db = server(false);
  if (db == nullptr) db = local_.get();
  Result<QSqlQuery> q = db->run(QStringLiteral("SELECT COUNT(*) FROM instructors"), {},
                                "instructors", "count the instructors");
  if (!q.ok()) return std::move(q).diagnostics();
  if (!q->next()) return db->problem("instructors", "cannot count the instructors");
  return q->value(0).toLongLong() > 0;
}

Status SessionStore::set_instructor_password(const Viewer* by, const QString& name,
                                             const QString& password, int iterations) {
  if (!valid_name(name)) {
    return store_problem(*this, "instructors.name",
                         "expected an instructor's name (no leading or trailing space, no "
                         "control characters), found '" +
                             str(name) + "'");
  }
  if (by != nullptr && !by->is_instructor()) {
    return store_problem(*this, "instructors",
                         "trainee '" + str(by->name()) + "' may not set instructors' passwords");
  }
  const Database* db = local_.get();
  if (connection_.driver == StoreDriver::kPostgresql) {
    db = server(true);
    if (db == nullptr) {
      return store_problem(*this, "instructors",
                           "accounts are kept on the programme's server, which does not answer: " +
                               str(server_error_));
    }
  }
  Result<PasswordHash> hash =
      hash_password(password, iterations > 0 ? iterations : kPasswordIterations);
  if (!hash.ok()) return std::move(hash).diagnostics();
  if (Status begun = db->begin_write(); !begun.ok()) return begun;
  if (by == nullptr) {
    // Only the first instructor is set up without one signed in; checked inside the
    // transaction, so that two stations cannot both do it.
    Result<QSqlQuery> count = db->run(QStringLiteral("SELECT COUNT(*) FROM instructors"), {},
                                      "instructors", "count the instructors");
    if (!count.ok() || !count->next()) {
      db->rollback();
      return count.ok() ? Status(db->problem("instructors", "cannot count the instructors"))
                        : Status(std::move(count).diagnostics());
    }
    if (count->value(0).toLongLong() > 0) {
      db->rollback();
      return db->problem("instructors",
                         "an instructor must sign in to add instructors or set passwords (only "
                         "the first instructor is set up without one)");
    }
  }
  Result<QSqlQuery> q = db->run(
      QStringLiteral("INSERT INTO instructors (name, salt_hex, hash_hex, iterations, added_utc) "
                     "VALUES (?, ?, ?, ?, ?) ON CONFLICT (name) DO UPDATE SET "
                     "salt_hex = excluded.salt_hex, hash_hex = excluded.hash_hex, "
                     "iterations = excluded.iterations"),
      {name, QString::fromLatin1(hash->salt.toHex()), QString::fromLatin1(hash->hash.toHex()),
       hash->iterations, utc_text(QDateTime::currentDateTimeUtc())},
      "instructors", "set instructor " + str(name) + "'s password");
  if (!q.ok()) {
    db->rollback();
    return std::move(q).diagnostics();
  }
  if (Status committed = db->commit(); !committed.ok()) return committed;
  if (db != local_.get()) return refresh_account_copy();
  return {};
}

Result<Viewer> SessionStore::sign_in_instructor(const QString& name,
                                                const QString& password) const {
  const Database* db = server(false);
  if (db == nullptr) db = local_.get();
  Result<QSqlQuery> q = db->run(
      QStringLiteral("SELECT salt_hex, hash_hex, iterations FROM instructors WHERE name = ?"),
      {name}, "instructors", "read the account");
  if (!q.ok()) return std::move(q).diagnostics();
  PasswordHash stored;
  bool known = false;
  if (q->next()) {
    const QString salt = q->value(0).toString();
    const QString hash = q->value(1).toString();
    bool ok = false;
    stored.iterations = q->value(2).toString().toInt(&ok);
    stored.salt = QByteArray::fromHex(salt.toLatin1());
    stored.hash = QByteArray::fromHex(hash.toLatin1());
    if (!ok || stored.iterations < 1 || stored.salt.isEmpty() ||
        stored.hash.size() != kPasswordHashBytes ||
        QString::fromLatin1(stored.hash.toHex()) != hash.toLower()) {
      return db->problem("instructors.hash_hex",
                         "instructor " + str(name) +
                             ": expected a hex salt, a 32-byte hex hash and iterations >= 1: "
                             "the account is damaged; set its password again");
    }
    known = true;
  }
  if (!known) {
    // The same work for an unknown name as for a known one: the time taken does not tell
    // which names are instructors'.
    stored.salt = QByteArray(kPasswordSaltBytes, '\0');
    stored.hash = QByteArray(kPasswordHashBytes, '\0');
    stored.iterations = kPasswordIterations;
  }
  const bool matches = verify_password(password, stored);
  if (!known || !matches) {
    return db->problem("instructors", "wrong name or password");
  }
  return Viewer(name, true);
}

Status SessionStore::check_access(const Viewer& viewer, const QString& trainee) const {
  if (viewer.is_instructor()) return {};
  if (!viewer.name().isEmpty() && trainee == viewer.name()) return {};
  return store_problem(
      *this, "sessions.trainee",
      "trainee '" + str(viewer.name()) + "' may see only their own sessions" +
          (trainee.isEmpty() ? std::string(", not everyone's") : ", not '" + str(trainee) + "''s") +
          ": an instructor must sign in");
}

Result<std::vector<SessionRow>> SessionStore::sessions(const Viewer& viewer, const QString& trainee,
                                                       const QString& scenario_file) const {
  if (Status allowed = check_access(viewer, trainee); !allowed.ok()) return allowed.diagnostics();
  return sessions(trainee, scenario_file);
}

Result<std::vector<SessionRow>> SessionStore::all_sessions(const Viewer& viewer) const {
  if (viewer.is_instructor()) return all_sessions();
  return sessions(viewer, viewer.name());
}

Result<std::vector<QString>> SessionStore::trainees(const Viewer& viewer) const {
  if (viewer.is_instructor()) return trainees();
  if (Status allowed = check_access(viewer, viewer.name()); !allowed.ok()) {
    return allowed.diagnostics();
  }
  return std::vector<QString>{viewer.name()};
}

Result<SessionRow> SessionStore::session(const Viewer& viewer, const QString& uuid) const {
  Result<SessionRow> row = session(uuid);
  if (!row.ok()) return row;
  if (Status allowed = check_access(viewer, row->trainee); !allowed.ok()) {
    return allowed.diagnostics();
  }
  return row;
}

Result<std::vector<MetricValue>> SessionStore::metrics(const Viewer& viewer,
                                                       const QString& uuid) const {
  Result<SessionRow> row = session(viewer, uuid);
  if (!row.ok()) return std::move(row).diagnostics();
  return metrics(uuid);
}

Result<std::vector<MetricPoint>> SessionStore::metric_history(const Viewer& viewer,
                                                              const QString& name,
                                                              const QString& trainee,
                                                              const QString& scenario_file) const {
  if (Status allowed = check_access(viewer, trainee); !allowed.ok()) return allowed.diagnostics();
  return metric_history(name, trainee, scenario_file);
}

}  // namespace lap::app
