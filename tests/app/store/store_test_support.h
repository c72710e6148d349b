#pragma once
// What the store's tests share: the two back-ends (a station's SQLite file; a programme's
// PostgreSQL server with the station's SQLite file as its outbox), the test PostgreSQL server
// that the ctest fixture starts (postgres_fixture.sh), sessions to store, and raw SQL for
// planting bad rows.

#include <QDateTime>
#include <QString>
#include <QTemporaryDir>
#include <memory>
#include <optional>
#include <ostream>
#include <string>

#include "app/store/session_store.h"
#include "app/store/sql_database.h"
#include "app/store/store_connection.h"

namespace lap::app::testing {

/// The test server the fixture started: read from the file LAP_PG_FIXTURE names.
struct PostgresServer {
  QString socket_dir;  ///< its unix socket's folder (superuser, trust)
  int port = 0;        ///< also on 127.0.0.1 (password: scram-sha-256)
  QString superuser;
  QString user;  ///< the stations' role
  QString password;
  QString state_file;
  QString script;

  /// The server, or why there is none (the reason a test skips with).
  [[nodiscard]] static const PostgresServer* get(std::string* why_not);
  /// A fresh database owned by `user` (its name), or "" and `error`.
  [[nodiscard]] QString create_database(std::string* error) const;
  void drop_database(const QString& name) const;
  /// `pg_ctl stop -m immediate` (every server process quits at once, as in a crash: no
  /// checkpoint, recovery on the next start), and the start after it.
  [[nodiscard]] bool crash() const;
  [[nodiscard]] bool restart() const;
  /// A StoreConnection to database `name` over TCP as the stations' role.
  [[nodiscard]] StoreConnection connection(const QString& name) const;
};

enum class Backend { kSqlite, kPostgresql };
/// The backend in the tests' listing (gtest would print the enum's bytes).
inline void PrintTo(Backend backend, std::ostream* os) {
  *os << (backend == Backend::kSqlite ? "sqlite" : "postgresql");
}

/// One test's store set-up: a temporary folder, and for kPostgresql a fresh database on the test
/// server (dropped at the end). `available()` false: skip with `why_not()`.
class BackendFixture {
 public:
  explicit BackendFixture(Backend backend);
  ~BackendFixture();
  [[nodiscard]] bool available() const { return why_not_.empty(); }
  [[nodiscard]] const std::string& why_not() const { return why_not_; }
  /// A station named `station`: its own SQLite file in the folder (the store, or its outbox).
  [[nodiscard]] StoreConnection station(const QString& station) const;
  [[nodiscard]] QString folder() const { return dir_.path(); }
  [[nodiscard]] Backend backend() const { return backend_; }
  [[nodiscard]] const QString& database() const { return database_; }

 private:
  Backend backend_;
  QTemporaryDir dir_;
  const PostgresServer* server_ = nullptr;
  QString database_;
  std::string why_not_;
};

/// A plausible finished session: the given trainee, scenario and start, a report JSON with task
/// and metrics objects (path_length_left_m = `path_m`, completion_time_s, max_force_duct_n, and
/// one undefined metric).
[[nodiscard]] SessionRow sample_session(
    const QString& trainee, const QDateTime& started_utc, double path_m = 0.5,
    const QString& scenario_file = "scenarios/introductory.yaml");

/// Runs `sql` on the database `connection` names (its SQLite file, or its server when
/// `on_server`), outside the store: for planting rows the store would refuse.
[[nodiscard]] bool raw_sql(const StoreConnection& connection, bool on_server, const QString& sql,
                           std::string* error = nullptr);

/// Counts rows of `sql` (a SELECT COUNT(*) ...) the same way; -1 on failure.
[[nodiscard]] long long raw_count(const StoreConnection& connection, bool on_server,
                                  const QString& sql);

}  // namespace lap::app::testing
