#include "app/store/store_connection.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QStandardPaths>
#include <QSysInfo>

namespace lap::app {
namespace {

std::string str(const QString& s) { return s.toStdString(); }

Diagnostic setting_problem(const QSettings& settings, const QString& key, const std::string& what) {
  return file_diagnostic(str(settings.fileName()), 0, "store/" + str(key), what);
}

}  // namespace

QString StoreConnection::server_name() const {
  if (driver == StoreDriver::kSqlite) return sqlite_path;
  QString name = QStringLiteral("postgresql://");
  if (!user.isEmpty()) name += user + QLatin1Char('@');
  name += host.isEmpty() ? QStringLiteral("localhost") : host;
  name += QLatin1Char(':') + QString::number(port) + QLatin1Char('/') + database;
  return name;
}

QString StoreConnection::default_sqlite_path() {
  // The application's own folder under the user's data folder, whatever the running program's
  // name (laptrainer, a test): QStandardPaths' AppDataLocation for the application "laptrainer".
  return QStandardPaths::writableLocation(QStandardPaths::GenericDataLocation) +
         QStringLiteral("/laptrainer/sessions.sqlite");
}

QString StoreConnection::default_recordings_folder() {
  return QStandardPaths::writableLocation(QStandardPaths::GenericDataLocation) +
         QStringLiteral("/laptrainer/recordings");
}

Result<StoreConnection> StoreConnection::from_settings(const QSettings& settings) {
  StoreConnection c;
  std::vector<Diagnostic> problems;
  const auto text = [&](const char* key, const QString& fallback) {
    return settings.value(QStringLiteral("store/") + QLatin1String(key), fallback).toString();
  };
  const QString driver = text("driver", QStringLiteral("sqlite")).trimmed().toLower();
  if (driver == QLatin1String("sqlite")) {
    c.driver = StoreDriver::kSqlite;
  } else if (driver == QLatin1String("postgresql") || driver == QLatin1String("postgres")) {
    c.driver = StoreDriver::kPostgresql;
  } else {
    problems.push_back(
        setting_problem(settings, QStringLiteral("driver"),
                        "expected sqlite or postgresql, found '" + str(driver) + "'"));
  }
  c.sqlite_path = text("sqlite_path", default_sqlite_path());
  c.host = text("host", {});
  c.database = text("database", QStringLiteral("laptrainer"));
  c.user = text("user", {});
  c.password = text("password", {});
  c.password_file = text("password_file", {});
  c.station = text("station", QSysInfo::machineHostName());
  const auto integer = [&](const char* key, int fallback, int low, int high, int* out) {
    const QVariant v = settings.value(QStringLiteral("store/") + QLatin1String(key));
    if (!v.isValid()) {
      *out = fallback;
      return;
    }
    bool ok = false;
    const int n = v.toString().trimmed().toInt(&ok);
    if (!ok || n < low || n > high) {
      problems.push_back(setting_problem(settings, QLatin1String(key),
                                         "expected a whole number from " + std::to_string(low) +
                                             " to " + std::to_string(high) + ", found '" +
                                             str(v.toString()) + "'"));
      return;
    }
    *out = n;
  };
  integer("port", 5432, 1, 65535, &c.port);
  integer("connect_timeout_s", 5, 1, 600, &c.connect_timeout_s);
  if (c.driver == StoreDriver::kPostgresql) {
    if (c.host.isEmpty()) {
      problems.push_back(setting_problem(settings, QStringLiteral("host"),
                                         "the postgresql driver needs the server's host name "
                                         "(or its unix socket's folder)"));
    }
    if (c.database.isEmpty()) {
      problems.push_back(
          setting_problem(settings, QStringLiteral("database"), "expected a database name"));
    }
  }
  if (c.sqlite_path.isEmpty()) {
    problems.push_back(
        setting_problem(settings, QStringLiteral("sqlite_path"), "expected a file name"));
  }
  if (c.station.trimmed().isEmpty()) c.station = QStringLiteral("station");
  if (!problems.empty()) return problems;
  return c;
}

Result<StoreConnection> StoreConnection::from_default_settings() {
  const QSettings settings(QSettings::NativeFormat, QSettings::UserScope,
                           QStringLiteral("laptrainer"), QStringLiteral("laptrainer"));
  return from_settings(settings);
}

Result<QString> connection_password(const StoreConnection& connection) {
  if (!connection.password.isEmpty() || connection.password_file.isEmpty()) {
    return connection.password;
  }
  const std::string file = str(connection.password_file);
  const QFileInfo info(connection.password_file);
  if (!info.exists() || !info.isFile()) {
    return file_diagnostic(file, 0, "store/password_file",
                           "expected a regular file holding "
                           "the database password");
  }
  // As libpq demands of ~/.pgpass: nobody but the owner may read a file holding a password.
  const QFileDevice::Permissions others = QFileDevice::ReadGroup | QFileDevice::WriteGroup |
                                          QFileDevice::ExeGroup | QFileDevice::ReadOther |
                                          QFileDevice::WriteOther | QFileDevice::ExeOther;
  if (info.permissions() & others) {
    return file_diagnostic(file, 0, "store/password_file",
                           "readable by others: expected owner-only permissions (chmod 600)");
  }
  QFile f(connection.password_file);
  if (!f.open(QIODevice::ReadOnly)) {
    return file_diagnostic(file, 0, "store/password_file", "cannot read: " + str(f.errorString()));
  }
  const QString first_line = QString::fromUtf8(f.readLine(4096)).trimmed();
  if (first_line.isEmpty()) {
    return file_diagnostic(file, 1, "store/password_file", "expected the password on line 1");
  }
  return first_line;
}

}  // namespace lap::app
