// The station's SQLite file: where it lives by default (the user's data folder), owner-only
// (0600 files, 0700 folders, whatever the umask), in WAL mode, and what happens to a file that is
// not a database or is damaged (a clear error naming it; the file left as it was). The connection
// settings (QSettings keys) and their errors.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <QDir>
#include <QFile>
#include <QSettings>
#include <QTemporaryDir>
#include <QTimeZone>

#include "app/store/session_store.h"
#include "app/store/sql_database.h"
#include "tests/app/store/store_test_support.h"

namespace lap::app {
namespace {

using testing::sample_session;

bool mentions(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

int mode_of(const QString& path) {
  struct stat st {};
  if (::stat(QFile::encodeName(path).constData(), &st) != 0) return -1;
  return static_cast<int>(st.st_mode & 0777);
}

QDateTime start_time() { return QDateTime(QDate(2025, 3, 1), QTime(9, 0), QTimeZone::utc()); }

StoreConnection sqlite_at(const QString& path) {
  StoreConnection c;
  c.sqlite_path = path;
  c.station = QStringLiteral("station-a");
  return c;
}

// Sets the process's umask for a scope.
class Umask {
 public:
  explicit Umask(mode_t mask) : old_(::umask(mask)) {}
  ~Umask() { ::umask(old_); }
  Umask(const Umask&) = delete;
  Umask& operator=(const Umask&) = delete;

 private:
  mode_t old_;
};

TEST(SqliteStore, TheDatabaseIsReadableByItsOwnerOnly) {
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  const Umask permissive(0);  // a careless umask must not widen anything
  const QString folder = dir.path() + QStringLiteral("/programme/station");
  const QString path = folder + QStringLiteral("/sessions.sqlite");
  {
    Result<std::unique_ptr<SessionStore>> store = SessionStore::open(sqlite_at(path));
    ASSERT_TRUE(store.ok()) << store.message();
    ASSERT_TRUE(store.value()->add_session(sample_session("r1", start_time())).ok());
    EXPECT_EQ(mode_of(folder), 0700);
    EXPECT_EQ(mode_of(path), 0600);
    // WAL's files exist while it is open, with the database's permissions.
    EXPECT_EQ(mode_of(path + QStringLiteral("-wal")), 0600);
    EXPECT_EQ(mode_of(path + QStringLiteral("-shm")), 0600);
  }
  // A database copied in with wider permissions is made owner-only when opened.
  ASSERT_EQ(::chmod(QFile::encodeName(path).constData(), 0644), 0);
  Result<std::unique_ptr<SessionStore>> again = SessionStore::open(sqlite_at(path));
  ASSERT_TRUE(again.ok()) << again.message();
  EXPECT_EQ(mode_of(path), 0600);
  EXPECT_EQ(again.value()->all_sessions().value().size(), 1U);
}

TEST(SqliteStore, ItsJournalIsWriteAheadLogging) {
  QTemporaryDir dir;
  const QString path = dir.path() + QStringLiteral("/s.sqlite");
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open(sqlite_at(path));
  ASSERT_TRUE(store.ok()) << store.message();
  Result<std::unique_ptr<Database>> db = Database::open_sqlite(path);
  ASSERT_TRUE(db.ok());
  Result<QSqlQuery> q = db.value()->run(QStringLiteral("PRAGMA journal_mode"), {}, "", "ask");
  ASSERT_TRUE(q.ok() && q->next());
  EXPECT_EQ(q->value(0).toString(), QStringLiteral("wal"));
}

TEST(SqliteStore, TheDefaultIsTheUsersDataFolderWithAPrivateRecordingsFolder) {
  QTemporaryDir home;
  ASSERT_TRUE(home.isValid());
  const QByteArray old_data = qgetenv("XDG_DATA_HOME");
  const QByteArray old_config = qgetenv("XDG_CONFIG_HOME");
  qputenv("XDG_DATA_HOME", QFile::encodeName(home.path() + QStringLiteral("/data")));
  qputenv("XDG_CONFIG_HOME", QFile::encodeName(home.path() + QStringLiteral("/config")));
  {
    Result<std::unique_ptr<SessionStore>> store = SessionStore::open_default();
    ASSERT_TRUE(store.ok()) << store.message();
    const QString data = home.path() + QStringLiteral("/data/laptrainer");
    EXPECT_EQ(store.value()->local_path(), data + QStringLiteral("/sessions.sqlite"));
    EXPECT_EQ(StoreConnection::default_recordings_folder(), data + QStringLiteral("/recordings"));
    EXPECT_EQ(store.value()->connection().driver, StoreDriver::kSqlite);
    EXPECT_EQ(mode_of(data), 0700);
    EXPECT_EQ(mode_of(data + QStringLiteral("/recordings")), 0700);
    EXPECT_EQ(mode_of(data + QStringLiteral("/sessions.sqlite")), 0600);
    EXPECT_FALSE(store.value()->connection().station.isEmpty());  // the host name
    EXPECT_FALSE(store.value()->sync_status().server_configured);
  }
  for (const auto& [name, old] :
       {std::pair{"XDG_DATA_HOME", old_data}, std::pair{"XDG_CONFIG_HOME", old_config}}) {
    if (old.isNull()) {
      qunsetenv(name);
    } else {
      qputenv(name, old);
    }
  }
}

TEST(SqliteStore, AFileThatIsNotADatabaseIsNamedAndLeftAlone) {
  QTemporaryDir dir;
  const QString path = dir.path() + QStringLiteral("/sessions.sqlite");
  QByteArray garbage;
  for (int i = 0; i < 8192; ++i) garbage.append(static_cast<char>((i * 37 + 11) & 0xff));
  {
    QFile f(path);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    f.write(garbage);
  }
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open(sqlite_at(path));
  ASSERT_FALSE(store.ok());
  EXPECT_TRUE(mentions(store.message(), path.toStdString())) << store.message();
  EXPECT_TRUE(mentions(store.message(), "not an SQLite database")) << store.message();
  QFile f(path);
  ASSERT_TRUE(f.open(QIODevice::ReadOnly));
  EXPECT_EQ(f.readAll(), garbage);  // untouched
}

TEST(SqliteStore, ADamagedDatabaseIsAnErrorNotACrash) {
  QTemporaryDir dir;
  const QString path = dir.path() + QStringLiteral("/sessions.sqlite");
  {
    Result<std::unique_ptr<SessionStore>> store = SessionStore::open(sqlite_at(path));
    ASSERT_TRUE(store.ok());
    for (int i = 0; i < 40; ++i) {
      ASSERT_TRUE(store.value()->add_session(sample_session("r1", start_time().addSecs(i))).ok());
    }
  }  // closed: the WAL checkpointed into the file
  // Every page after the first (which holds the schema) overwritten.
  QFile f(path);
  ASSERT_TRUE(f.open(QIODevice::ReadWrite));
  const qint64 size = f.size();
  ASSERT_GT(size, 8192);
  f.seek(4096);
  f.write(QByteArray(static_cast<int>(size - 4096), '\xa5'));
  f.close();
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open(sqlite_at(path));
  std::string message;
  if (!store.ok()) {
    message = store.message();
  } else {
    Result<std::vector<SessionRow>> rows = store.value()->all_sessions();
    ASSERT_FALSE(rows.ok()) << "read " << rows->size() << " sessions from a damaged file";
    message = rows.message();
  }
  EXPECT_TRUE(mentions(message, path.toStdString())) << message;
  EXPECT_TRUE(mentions(message, "malformed") || mentions(message, "not an SQLite database"))
      << message;
}

TEST(SqliteStore, AFolderInTheWayIsNamed) {
  QTemporaryDir dir;
  const QString path = dir.path() + QStringLiteral("/sessions.sqlite");
  ASSERT_TRUE(QDir().mkpath(path));
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open(sqlite_at(path));
  ASSERT_FALSE(store.ok());
  EXPECT_TRUE(mentions(store.message(), path.toStdString())) << store.message();
}

// --- The connection setting --------------------------------------------------------------------

TEST(StoreSettings, ThePostgresqlSetUpIsReadFromItsKeys) {
  QTemporaryDir dir;
  const QString file = dir.path() + QStringLiteral("/laptrainer.conf");
  {
    QSettings s(file, QSettings::IniFormat);
    s.setValue("store/driver", "postgresql");
    s.setValue("store/host", "db.residency.example");
    s.setValue("store/port", "5433");
    s.setValue("store/database", "skills");
    s.setValue("store/user", "station");
    s.setValue("store/password_file", "/etc/laptrainer/db-password");
    s.setValue("store/station", "skills-lab-2");
    s.setValue("store/sqlite_path", "/var/lib/laptrainer/outbox.sqlite");
  }
  const QSettings s(file, QSettings::IniFormat);
  Result<StoreConnection> c = StoreConnection::from_settings(s);
  ASSERT_TRUE(c.ok()) << c.message();
  EXPECT_EQ(c->driver, StoreDriver::kPostgresql);
  EXPECT_EQ(c->host, QStringLiteral("db.residency.example"));
  EXPECT_EQ(c->port, 5433);
  EXPECT_EQ(c->database, QStringLiteral("skills"));
  EXPECT_EQ(c->user, QStringLiteral("station"));
  EXPECT_EQ(c->password_file, QStringLiteral("/etc/laptrainer/db-password"));
  EXPECT_EQ(c->station, QStringLiteral("skills-lab-2"));
  EXPECT_EQ(c->sqlite_path, QStringLiteral("/var/lib/laptrainer/outbox.sqlite"));
  EXPECT_EQ(c->server_name(),
            QStringLiteral("postgresql://station@db.residency.example:5433/skills"));
}

TEST(StoreSettings, NothingSetIsTheStationsOwnSqlite) {
  QTemporaryDir dir;
  const QSettings s(dir.path() + QStringLiteral("/empty.conf"), QSettings::IniFormat);
  Result<StoreConnection> c = StoreConnection::from_settings(s);
  ASSERT_TRUE(c.ok()) << c.message();
  EXPECT_EQ(c->driver, StoreDriver::kSqlite);
  EXPECT_EQ(c->sqlite_path, StoreConnection::default_sqlite_path());
}

TEST(StoreSettings, BadValuesNameTheirKey) {
  QTemporaryDir dir;
  const QString file = dir.path() + QStringLiteral("/bad.conf");
  {
    QSettings s(file, QSettings::IniFormat);
    s.setValue("store/driver", "mysql");
    s.setValue("store/port", "99999");
    s.setValue("store/connect_timeout_s", "soon");
  }
  const QSettings s(file, QSettings::IniFormat);
  Result<StoreConnection> c = StoreConnection::from_settings(s);
  ASSERT_FALSE(c.ok());
  const std::string m = c.message();
  EXPECT_TRUE(mentions(m, file.toStdString())) << m;
  EXPECT_TRUE(mentions(m, "store/driver: expected sqlite or postgresql, found 'mysql'")) << m;
  EXPECT_TRUE(mentions(m, "store/port: expected a whole number from 1 to 65535, found '99999'"))
      << m;
  EXPECT_TRUE(mentions(m, "store/connect_timeout_s")) << m;
  {
    QSettings p(file, QSettings::IniFormat);
    p.clear();
    p.setValue("store/driver", "postgresql");
  }
  Result<StoreConnection> no_host =
      StoreConnection::from_settings(QSettings(file, QSettings::IniFormat));
  ASSERT_FALSE(no_host.ok());
  EXPECT_TRUE(mentions(no_host.message(), "store/host")) << no_host.message();
}

TEST(StoreSettings, APasswordFileMustBeTheOwnersOnly) {
  QTemporaryDir dir;
  const QString file = dir.path() + QStringLiteral("/db-password");
  {
    QFile f(file);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    f.write("s3cret-pass\nignored second line\n");
  }
  StoreConnection c;
  c.driver = StoreDriver::kPostgresql;
  c.password_file = file;
  ASSERT_EQ(::chmod(QFile::encodeName(file).constData(), 0644), 0);
  Result<QString> open_to_all = connection_password(c);
  ASSERT_FALSE(open_to_all.ok());
  EXPECT_TRUE(mentions(open_to_all.message(), "readable by others")) << open_to_all.message();
  ASSERT_EQ(::chmod(QFile::encodeName(file).constData(), 0600), 0);
  Result<QString> password = connection_password(c);
  ASSERT_TRUE(password.ok()) << password.message();
  EXPECT_EQ(password.value(), QStringLiteral("s3cret-pass"));
  c.password_file = dir.path() + QStringLiteral("/missing");
  EXPECT_FALSE(connection_password(c).ok());
}

}  // namespace
}  // namespace lap::app
