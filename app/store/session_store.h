#pragma once
/// \file
/// The training-record database (issue 24, "Where sessions live"): every finished (or
/// interrupted) session with its trainee, scenario and version, devices, station, result,
/// reasons, metrics and report, and the instructors' accounts.
///
/// Two set-ups, chosen by the connection setting (store_connection.h):
/// - one station: an SQLite file in the user's data folder (WAL journal, owner-only);
/// - a residency programme: a PostgreSQL server shared by its stations, each station keeping
///   its own SQLite file as an outbox. A session is always written to the station's file first
///   (so nothing is lost when the server is down), queued in its outbox, and uploaded when the
///   server answers; an upload is idempotent by the session's UUID, so one repeated after a
///   crash or a dropped connection doubles nothing. While the server is down the station reads
///   its own sessions; when it is back, the server's (with any still queued here).
///
/// Access: trainees sign in by name or ID and see their own sessions; instructors sign in with
/// a password (PBKDF2-HMAC-SHA256, password_hash.h) and see everyone's. The `Viewer` overloads
/// check this; the plain ones are the station's own (the trainee window shows the signed-in
/// trainee's sessions).
///
/// Not thread-safe: use a store from the thread that opened it (Qt SQL's connections are
/// per thread).

#include <QDateTime>
#include <QString>
#include <QStringList>
#include <functional>
#include <memory>
#include <vector>

#include "app/store/session_row.h"
#include "app/store/session_table.h"
#include "app/store/store_connection.h"
#include "core/result.h"

namespace lap::app {

class Database;

/// Who is looking: a trainee (their own sessions) or a signed-in instructor (everyone's). An
/// instructor's Viewer comes only from SessionStore::sign_in_instructor.
class Viewer {
 public:
  /// A trainee, signed in by name or ID (no password: the station is in the skills lab).
  [[nodiscard]] static Viewer trainee(const QString& name) { return Viewer(name, false); }
  [[nodiscard]] const QString& name() const { return name_; }
  [[nodiscard]] bool is_instructor() const { return instructor_; }

 private:
  friend class SessionStore;
  Viewer(QString name, bool instructor) : name_(std::move(name)), instructor_(instructor) {}
  QString name_;
  bool instructor_ = false;
};

/// How the outbox stands (the status bar's "3 sessions waiting for the server").
struct SyncStatus {
  bool server_configured = false;  ///< the postgresql set-up
  bool server_reachable = false;   ///< at the last attempt
  int pending = 0;                 ///< sessions in the outbox
  QString last_error;              ///< why the last attempt failed ("" when it did not)
};

class SessionStore {
 public:
  /// SQLite in the user's data folder (QStandardPaths::AppDataLocation, WAL), or the server the
  /// connection setting names (QSettings), with this station's local SQLite as its outbox.
  static Result<std::unique_ptr<SessionStore>> open_default();
  /// Opens the station's SQLite file (migrating it), and in the postgresql set-up tries the
  /// server once: a server that does not answer (or refuses the credentials) does not fail the
  /// open — the station keeps working — and is told in sync_status().
  static Result<std::unique_ptr<SessionStore>> open(const StoreConnection& connection);
  ~SessionStore();
  SessionStore(const SessionStore&) = delete;
  SessionStore& operator=(const SessionStore&) = delete;

  /// Records a session: checked (each bad field named), written to the station's file with its
  /// metrics (the report's "metrics" object), then, with a server, queued and uploaded.
  /// Idempotent by uuid: adding a session again changes nothing. Fails only when the session
  /// could not be kept on the station; an upload that fails leaves it queued (sync_status()).
  Status add_session(const SessionRow& row);
  /// A trainee's sessions, optionally on one scenario file only; newest first.
  Result<std::vector<SessionRow>> sessions(const QString& trainee,
                                           const QString& scenario_file = {}) const;
  /// Everyone's sessions, newest first (instructors).
  Result<std::vector<SessionRow>> all_sessions() const;
  /// Every trainee's name, sorted.
  Result<std::vector<QString>> trainees() const;

  /// Registers a trainee (the sign-in screen), idempotent; names as check_session_row takes.
  Status add_trainee(const QString& name);
  /// One session by uuid.
  Result<SessionRow> session(const QString& uuid) const;
  /// One session's metrics, by name.
  Result<std::vector<MetricValue>> metrics(const QString& uuid) const;
  /// Metric `name` over the sessions of `trainee` (empty: everyone) on `scenario_file` (empty:
  /// any), oldest first: learning curves and the cohort.
  Result<std::vector<MetricPoint>> metric_history(const QString& name, const QString& trainee,
                                                  const QString& scenario_file = {}) const;

  // --- Accounts and access-checked reading ---------------------------------------------------
  /// Adds an instructor or sets a new password. `by` must be a signed-in instructor, except for
  /// the first instructor of an empty store (set up at the station). With a server, accounts
  /// live on the server (it must answer). `iterations` below the default only for tests.
  Status set_instructor_password(const Viewer* by, const QString& name, const QString& password,
                                 int iterations = 0);
  /// Signs an instructor in: the same answer, after the same work, for an unknown name and a
  /// wrong password ("wrong name or password"). Offline, the station's copy of the accounts
  /// (refreshed whenever the server answers) is used.
  Result<Viewer> sign_in_instructor(const QString& name, const QString& password) const;
  /// Whether any instructor exists (the first one is set up at the station).
  Result<bool> has_instructors() const;
  /// `trainee`'s sessions as `viewer` may see them: an instructor any trainee's, a trainee only
  /// their own (anyone else's is refused, naming both).
  Result<std::vector<SessionRow>> sessions(const Viewer& viewer, const QString& trainee,
                                           const QString& scenario_file = {}) const;
  /// An instructor: everyone's; a trainee: their own.
  Result<std::vector<SessionRow>> all_sessions(const Viewer& viewer) const;
  /// An instructor: every trainee; a trainee: themselves.
  Result<std::vector<QString>> trainees(const Viewer& viewer) const;
  Result<SessionRow> session(const Viewer& viewer, const QString& uuid) const;
  Result<std::vector<MetricValue>> metrics(const Viewer& viewer, const QString& uuid) const;
  /// A trainee may ask for their own history only; the cohort (empty trainee) is instructors'.
  Result<std::vector<MetricPoint>> metric_history(const Viewer& viewer, const QString& name,
                                                  const QString& trainee,
                                                  const QString& scenario_file = {}) const;

  // --- The outbox (postgresql set-up) --------------------------------------------------------
  /// Uploads every queued session, oldest first, each in its own server transaction, removing
  /// it from the outbox only after the server committed it. `progress(done, total)` after each;
  /// returning false stops there (the rest stay queued). Nothing to do without a server.
  Status upload_pending(const std::function<bool(int, int)>& progress = {});
  [[nodiscard]] SyncStatus sync_status() const;

  [[nodiscard]] const StoreConnection& connection() const { return connection_; }
  /// The station's SQLite file (the store, or the outbox).
  [[nodiscard]] QString local_path() const { return connection_.sqlite_path; }

 private:
  explicit SessionStore(StoreConnection connection);
  /// The server's connection when it answers (connecting when `retry_now` or the retry
  /// interval passed); null when there is no server or it does not answer.
  const Database* server(bool retry_now) const;
  void server_failed(const std::vector<Diagnostic>& why) const;
  Status refresh_account_copy() const;
  Result<std::vector<SessionRow>> read_sessions(const SessionFilter& filter) const;
  Result<std::vector<MetricPoint>> read_metric(const QString& name,
                                               const SessionFilter& filter) const;
  Result<std::vector<QString>> read_trainees() const;
  Status check_access(const Viewer& viewer, const QString& trainee) const;

  StoreConnection connection_;
  std::unique_ptr<Database> local_;
  mutable std::unique_ptr<Database> server_;
  mutable QDateTime next_server_attempt_utc_;
  mutable QString server_error_;
};

}  // namespace lap::app
