#include "tests/app/store/store_test_support.h"

#include <gtest/gtest.h>

#include <QFile>
#include <QSqlDatabase>
#include <QSqlError>
#include <QSqlQuery>
#include <QUuid>
#include <cstdlib>
#include <map>

namespace lap::app::testing {
namespace {

std::string str(const QString& s) { return s.toStdString(); }

QString shell_quoted(const QString& s) {
  QString q = s;
  q.replace(QLatin1Char('\''), QStringLiteral("'\\''"));
  return QLatin1Char('\'') + q + QLatin1Char('\'');
}

bool run_script(const PostgresServer& server, const char* command) {
  const QString line = QStringLiteral("bash %1 %2 %3 >/dev/null 2>&1")
                           .arg(shell_quoted(server.script), QLatin1String(command),
                                shell_quoted(server.state_file));
  return std::system(line.toLocal8Bit().constData()) == 0;
}

// A raw connection (outside the store) to the SQLite file or the server of `connection`.
struct RawConnection {
  QString name = QStringLiteral("raw-") + QUuid::createUuid().toString(QUuid::WithoutBraces);
  bool opened = false;
  RawConnection(const StoreConnection& c, bool on_server, std::string* error) {
    QSqlDatabase db = QSqlDatabase::addDatabase(
        on_server ? QStringLiteral("QPSQL") : QStringLiteral("QSQLITE"), name);
    if (on_server) {
      db.setHostName(c.host);
      db.setPort(c.port);
      db.setDatabaseName(c.database);
      db.setUserName(c.user);
      db.setPassword(c.password);
    } else {
      db.setDatabaseName(c.sqlite_path);
    }
    opened = db.open();
    if (!opened && error != nullptr) *error = str(db.lastError().text());
  }
  ~RawConnection() {
    {
      QSqlDatabase db = QSqlDatabase::database(name, false);
      db.close();
    }
    QSqlDatabase::removeDatabase(name);
  }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;
};

}  // namespace

const PostgresServer* PostgresServer::get(std::string* why_not) {
  static std::optional<PostgresServer> server;
  static std::string reason;
  static bool read = false;
  if (!read) {
    read = true;
    const QString state =
        qEnvironmentVariable("LAP_PG_FIXTURE", QStringLiteral(LAP_PG_FIXTURE_DEFAULT));
    QFile f(state);
    if (!f.open(QIODevice::ReadOnly)) {
      reason = "no test PostgreSQL server: " + str(state) +
               " is missing (ctest starts one with the store.postgres.start fixture; by hand: "
               "bash tests/app/store/postgres_fixture.sh start " +
               str(state) + ")";
    } else {
      std::map<QString, QString> values;
      while (!f.atEnd()) {
        const QString line = QString::fromUtf8(f.readLine()).trimmed();
        const qsizetype eq = line.indexOf(QLatin1Char('='));
        if (eq > 0) values[line.left(eq)] = line.mid(eq + 1);
      }
      if (values.count(QStringLiteral("SKIP")) != 0) {
        reason = "PostgreSQL half skipped: " + str(values[QStringLiteral("SKIP")]);
      } else {
        PostgresServer s;
        s.socket_dir = values[QStringLiteral("PG_SOCKET")];
        s.port = values[QStringLiteral("PG_PORT")].toInt();
        s.superuser = values[QStringLiteral("PG_SUPERUSER")];
        s.user = values[QStringLiteral("PG_USER")];
        s.password = values[QStringLiteral("PG_PASSWORD")];
        s.script = values[QStringLiteral("PG_SCRIPT")];
        s.state_file = state;
        if (s.port <= 0 || s.socket_dir.isEmpty() || s.user.isEmpty()) {
          reason = "the PostgreSQL fixture's file " + str(state) + " is incomplete";
        } else {
          server = s;
        }
      }
    }
  }
  if (!server && why_not != nullptr) *why_not = reason;
  return server ? &*server : nullptr;
}

QString PostgresServer::create_database(std::string* error) const {
  StoreConnection admin;
  admin.driver = StoreDriver::kPostgresql;
  admin.host = socket_dir;
  admin.port = port;
  admin.user = superuser;
  admin.database = QStringLiteral("postgres");
  RawConnection raw(admin, true, error);
  if (!raw.opened) return {};
  const QString name = QStringLiteral("lap_") + QUuid::createUuid().toString(QUuid::Id128).left(16);
  QSqlQuery q(QSqlDatabase::database(raw.name, false));
  if (!q.exec(QStringLiteral("CREATE DATABASE %1 OWNER %2").arg(name, user))) {
    if (error != nullptr) *error = str(q.lastError().text());
    return {};
  }
  return name;
}

void PostgresServer::drop_database(const QString& name) const {
  StoreConnection admin;
  admin.driver = StoreDriver::kPostgresql;
  admin.host = socket_dir;
  admin.port = port;
  admin.user = superuser;
  admin.database = QStringLiteral("postgres");
  RawConnection raw(admin, true, nullptr);
  if (!raw.opened) return;
  QSqlQuery q(QSqlDatabase::database(raw.name, false));
  (void)q.exec(QStringLiteral("DROP DATABASE IF EXISTS %1 WITH (FORCE)").arg(name));
}

bool PostgresServer::crash() const { return run_script(*this, "crash"); }
bool PostgresServer::restart() const { return run_script(*this, "restart"); }

StoreConnection PostgresServer::connection(const QString& name) const {
  StoreConnection c;
  c.driver = StoreDriver::kPostgresql;
  c.host = QStringLiteral("127.0.0.1");
  c.port = port;
  c.database = name;
  c.user = user;
  c.password = password;
  c.connect_timeout_s = 2;
  return c;
}

BackendFixture::BackendFixture(Backend backend) : backend_(backend) {
  if (!dir_.isValid()) {
    why_not_ = "cannot make a temporary folder";
    ADD_FAILURE() << why_not_;
    return;
  }
  if (backend_ == Backend::kPostgresql) {
    server_ = PostgresServer::get(&why_not_);
    if (server_ == nullptr) return;
    std::string error;
    database_ = server_->create_database(&error);
    if (database_.isEmpty()) {
      // The fixture says the server runs: not reaching it is a failure, not a reason to skip.
      why_not_ = "cannot create a database on the test server: " + error;
      ADD_FAILURE() << why_not_;
    }
  }
}

BackendFixture::~BackendFixture() {
  if (server_ != nullptr && !database_.isEmpty()) server_->drop_database(database_);
}

StoreConnection BackendFixture::station(const QString& station) const {
  StoreConnection c;
  if (backend_ == Backend::kPostgresql && server_ != nullptr) c = server_->connection(database_);
  c.sqlite_path = dir_.path() + QLatin1Char('/') + station + QStringLiteral(".sqlite");
  c.station = station;
  return c;
}

SessionRow sample_session(const QString& trainee, const QDateTime& started_utc, double path_m,
                          const QString& scenario_file) {
  SessionRow row;
  row.uuid = QUuid::createUuid().toString(QUuid::WithoutBraces);
  row.trainee = trainee;
  row.scenario_file = scenario_file;
  row.scenario_name = QStringLiteral("Catheter into the cystic duct");
  row.scenario_version = QString(64, QLatin1Char('a'));
  row.devices = QStringLiteral("left=simulated; right=phantom:Left Omni+gripper:AB12");
  row.station = QStringLiteral("skills-lab-1");
  row.started_utc = started_utc;
  row.duration_s = 42.25;
  row.result = QStringLiteral("failure");
  row.reasons = {QStringLiteral("duct_injury"), QStringLiteral("time_limit")};
  row.completion_time_s = 40.125;
  // The shape `laptrainer-cli run` prints (sim/report/session_report.h), abridged.
  row.report_json = QStringLiteral(
                        R"({"scenario": "%1", "mode": "realtime",
 "task": {"kind": "catheter_insertion", "result": "failure",
          "reasons": ["duct_injury", "time_limit"], "events": [], "completion_time_s": 40.125},
 "metrics": {"completion_time_s": 40.125, "path_length_left_m": %2,
             "path_length_right_m": 0.75, "max_force_duct_n": 2.5, "catheter_drops": 1,
             "mean_jerk_left_m_per_s3": null},
 "state_hash": "0123456789abcdef"})")
                        .arg(scenario_file)
                        .arg(path_m, 0, 'g', 17);
  row.recording_dir = QStringLiteral("/var/lib/laptrainer/recordings/") + row.uuid;
  row.interrupted = false;
  return row;
}

bool raw_sql(const StoreConnection& connection, bool on_server, const QString& sql,
             std::string* error) {
  RawConnection raw(connection, on_server, error);
  if (!raw.opened) return false;
  QSqlQuery q(QSqlDatabase::database(raw.name, false));
  if (!q.exec(sql)) {
    if (error != nullptr) *error = str(q.lastError().text());
    return false;
  }
  return true;
}

long long raw_count(const StoreConnection& connection, bool on_server, const QString& sql) {
  RawConnection raw(connection, on_server, nullptr);
  if (!raw.opened) return -1;
  QSqlQuery q(QSqlDatabase::database(raw.name, false));
  if (!q.exec(sql) || !q.next()) return -1;
  return q.value(0).toLongLong();
}

}  // namespace lap::app::testing
