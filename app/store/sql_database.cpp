#include "app/store/sql_database.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <QDir>
#include <QFileInfo>
#include <QSqlError>
#include <QUuid>
#include <cerrno>
#include <cstring>

namespace lap::app {
namespace {

std::string str(const QString& s) { return s.toStdString(); }

QString new_connection_name() {
  return QStringLiteral("lap-store-") + QUuid::createUuid().toString(QUuid::WithoutBraces);
}

std::string driver_text(const QSqlError& e) {
  QString text = e.text().trimmed();
  if (text.isEmpty()) text = QStringLiteral("(no reason given)");
  return str(text);
}

Diagnostic missing_driver(const char* driver, const char* package, const std::string& name) {
  return file_diagnostic(name, 0, "",
                         std::string("Qt's ") + driver +
                             " driver is not installed: apt-get "
                             "install " +
                             package);
}

// 0600 for a file the store owns (the database and SQLite's -wal and -shm beside it).
Status make_owner_only_file(const QString& path) {
  const QByteArray p = QFile::encodeName(path);
  struct stat st {};
  if (::stat(p.constData(), &st) != 0) return {};
  if (!S_ISREG(st.st_mode)) {
    return file_diagnostic(str(path), 0, "", "expected a regular file (the SQLite database)");
  }
  if ((st.st_mode & 0777) != 0600 && ::chmod(p.constData(), 0600) != 0) {
    return file_diagnostic(
        str(path), 0, "",
        std::string("cannot make it owner-only (chmod 600): ") + std::strerror(errno));
  }
  return {};
}

}  // namespace

Status make_private_folder(const QString& folder, bool tighten_existing) {
  const QByteArray p = QFile::encodeName(folder);
  struct stat st {};
  if (::stat(p.constData(), &st) == 0) {
    if (!S_ISDIR(st.st_mode)) return file_diagnostic(str(folder), 0, "", "expected a folder");
    if (tighten_existing && (st.st_mode & 0777) != 0700 && ::chmod(p.constData(), 0700) != 0) {
      return file_diagnostic(
          str(folder), 0, "",
          std::string("cannot make it owner-only (chmod 700): ") + std::strerror(errno));
    }
    return {};
  }
  const QString parent = QFileInfo(folder).absolutePath();
  if (!QDir().mkpath(parent)) {
    return file_diagnostic(str(parent), 0, "", "cannot create the folder");
  }
  if (::mkdir(p.constData(), 0700) != 0 && errno != EEXIST) {
    return file_diagnostic(str(folder), 0, "",
                           std::string("cannot create the folder: ") + std::strerror(errno));
  }
  // mkdir's mode is masked by the umask; a permissive umask cannot widen 0700, but say it anyway.
  if (::chmod(p.constData(), 0700) != 0) {
    return file_diagnostic(
        str(folder), 0, "",
        std::string("cannot make it owner-only (chmod 700): ") + std::strerror(errno));
  }
  return {};
}

Database::Database(QString connection_name, SqlDialect dialect, std::string name)
    : connection_name_(std::move(connection_name)), dialect_(dialect), name_(std::move(name)) {}

Database::~Database() {
  {
    QSqlDatabase db = QSqlDatabase::database(connection_name_, false);
    db.close();
  }
  QSqlDatabase::removeDatabase(connection_name_);
}

QSqlDatabase Database::handle() const { return QSqlDatabase::database(connection_name_, false); }

Diagnostic Database::problem(const std::string& field, const std::string& what) const {
  return file_diagnostic(name_, 0, field, what);
}

Result<QSqlQuery> Database::run(const QString& sql, const QVariantList& binds,
                                const std::string& field, const std::string& what) const {
  QSqlQuery q(handle());
  q.setForwardOnly(true);
  if (binds.isEmpty()) {
    // Run as it is: Qt's PostgreSQL driver prepares a statement with the server's PREPARE,
    // which takes no schema statements (CREATE TABLE).
    if (!q.exec(sql)) return problem(field, "cannot " + what + ": " + driver_text(q.lastError()));
    return q;
  }
  if (!q.prepare(sql)) {
    return problem(field, "cannot " + what + ": " + driver_text(q.lastError()));
  }
  for (const QVariant& v : binds) q.addBindValue(v);
  if (!q.exec()) return problem(field, "cannot " + what + ": " + driver_text(q.lastError()));
  return q;
}

Status Database::begin_write() const {
  const QString sql =
      dialect_ == SqlDialect::kSqlite ? QStringLiteral("BEGIN IMMEDIATE") : QStringLiteral("BEGIN");
  QSqlQuery q(handle());
  if (!q.exec(sql)) {
    return problem("", "cannot begin a transaction: " + driver_text(q.lastError()));
  }
  return {};
}

Status Database::commit() const {
  QSqlQuery q(handle());
  if (!q.exec(QStringLiteral("COMMIT"))) {
    const Diagnostic d = problem("", "cannot commit: " + driver_text(q.lastError()));
    rollback();
    return d;
  }
  return {};
}

void Database::rollback() const {
  QSqlQuery q(handle());
  (void)q.exec(QStringLiteral("ROLLBACK"));
}

bool Database::alive() const {
  QSqlQuery q(handle());
  return q.exec(QStringLiteral("SELECT 1")) && q.next();
}

Result<std::unique_ptr<Database>> Database::open_sqlite(const QString& path) {
  const std::string name = str(path);
  if (!QSqlDatabase::isDriverAvailable(QStringLiteral("QSQLITE"))) {
    return missing_driver("SQLite (QSQLITE)", "libqt6sql6-sqlite", name);
  }
  const QFileInfo info(path);
  if (Status folder = make_private_folder(info.absolutePath(), false); !folder.ok())
    return folder.diagnostics();
  // Created owner-only before SQLite opens it, so that no moment exists when others could read
  // it; SQLite gives its -wal and -shm files the database file's permissions.
  const QByteArray p = QFile::encodeName(path);
  const int fd = ::open(p.constData(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd >= 0) {
    ::close(fd);
  } else if (errno != EEXIST) {
    return file_diagnostic(name, 0, "",
                           std::string("cannot create the database: ") + std::strerror(errno));
  }
  if (!QFileInfo(path).isFile()) {
    return file_diagnostic(name, 0, "", "expected a regular file (the SQLite database)");
  }

  std::unique_ptr<Database> database(
      new Database(new_connection_name(), SqlDialect::kSqlite, name));
  {
    QSqlDatabase db =
        QSqlDatabase::addDatabase(QStringLiteral("QSQLITE"), database->connection_name_);
    db.setDatabaseName(path);
    db.setConnectOptions(QStringLiteral("QSQLITE_BUSY_TIMEOUT=5000"));
    if (!db.open()) {
      return file_diagnostic(name, 0, "",
                             "cannot open the database: " + driver_text(db.lastError()));
    }
  }
  // The first statement reads the file's header: a file that is not a database fails here, and
  // nothing has been written to it.
  QSqlQuery q(database->handle());
  if (!q.exec(QStringLiteral("PRAGMA journal_mode=WAL")) || !q.next()) {
    return file_diagnostic(
        name, 0, "",
        "not an SQLite database, or a damaged one (" + driver_text(q.lastError()) +
            "); it was left as it is: move it aside to start a new one, or restore a backup");
  }
  if (q.value(0).toString().toLower() != QLatin1String("wal")) {
    return file_diagnostic(name, 0, "",
                           "cannot switch the database to WAL (write-ahead "
                           "logging): its journal mode stays " +
                               str(q.value(0).toString()));
  }
  q.finish();
  // Foreign keys are off by default in SQLite; FULL makes each commit durable (a session is
  // written once, at its end).
  for (const char* pragma : {"PRAGMA foreign_keys=ON", "PRAGMA synchronous=FULL"}) {
    if (!q.exec(QLatin1String(pragma))) {
      return file_diagnostic(
          name, 0, "", std::string("cannot set ") + pragma + ": " + driver_text(q.lastError()));
    }
  }
  q.finish();
  // An older file with wider permissions (or a copy) is made owner-only too, now that it is
  // known to be a database.
  for (const QString& file : {path, path + QStringLiteral("-wal"), path + QStringLiteral("-shm")}) {
    if (Status owner_only = make_owner_only_file(file); !owner_only.ok())
      return owner_only.diagnostics();
  }
  return database;
}

Result<std::unique_ptr<Database>> Database::open_postgresql(const StoreConnection& c,
                                                            const QString& password) {
  const std::string name = str(c.server_name());
  if (!QSqlDatabase::isDriverAvailable(QStringLiteral("QPSQL"))) {
    return missing_driver("PostgreSQL (QPSQL)", "libqt6sql6-psql", name);
  }
  std::unique_ptr<Database> database(
      new Database(new_connection_name(), SqlDialect::kPostgresql, name));
  QSqlDatabase db = QSqlDatabase::addDatabase(QStringLiteral("QPSQL"), database->connection_name_);
  db.setHostName(c.host);
  db.setPort(c.port);
  db.setDatabaseName(c.database);
  db.setUserName(c.user);
  if (!password.isEmpty()) db.setPassword(password);
  db.setConnectOptions(
      QStringLiteral("connect_timeout=%1;application_name=laptrainer").arg(c.connect_timeout_s));
  if (!db.open()) {
    return file_diagnostic(name, 0, "", "cannot connect: " + driver_text(db.lastError()));
  }
  return database;
}

}  // namespace lap::app
