#pragma once
/// \file
/// Where a station keeps its training records: an SQLite file in the user's data folder (one
/// station on its own), or a residency programme's PostgreSQL server shared by several stations,
/// with the station's SQLite file as its outbox. Read from QSettings (the README's "Where sessions
/// are stored" lists the keys):
///
///   [store]
///   driver=sqlite|postgresql    (default sqlite)
///   sqlite_path=FILE            (default: <AppDataLocation>/sessions.sqlite)
///   host=HOST|/socket/folder    port=5432    database=laptrainer    user=USER
///   password=...  or  password_file=FILE (owner-only: 0600)
///   connect_timeout_s=5         station=NAME (default: the host name)
///
/// QSettings looks in the user's ~/.config/laptrainer/laptrainer.conf first, then the system's
/// /etc/xdg/laptrainer/laptrainer.conf, so a programme can configure every station in one place.

#include <QSettings>
#include <QString>

#include "core/result.h"

namespace lap::app {

enum class StoreDriver { kSqlite, kPostgresql };

struct StoreConnection {
  StoreDriver driver = StoreDriver::kSqlite;
  /// The station's SQLite file: the whole store (kSqlite), or the outbox (kPostgresql).
  QString sqlite_path;
  QString host;  ///< a host name or address, or a folder holding the server's unix socket
  int port = 5432;
  QString database = QStringLiteral("laptrainer");
  QString user;
  QString password;       ///< empty: password_file, else libpq's own (~/.pgpass, PGPASSWORD)
  QString password_file;  ///< a file holding the password on its first line; owner-only
  int connect_timeout_s = 5;
  QString station;  ///< this station's name in the records (default: the host name)

  /// `postgresql://user@host:port/database` or the SQLite file: how messages name the store.
  [[nodiscard]] QString server_name() const;

  /// Reads the [store] group of `settings`; diagnostics name the settings file and the key, and
  /// what was expected (an unknown driver, a port out of range, an unreadable password file).
  [[nodiscard]] static Result<StoreConnection> from_settings(const QSettings& settings);
  /// The settings every laptrainer program reads: organisation and application "laptrainer".
  [[nodiscard]] static Result<StoreConnection> from_default_settings();
  /// <AppDataLocation>/sessions.sqlite (AppDataLocation: ~/.local/share/laptrainer, or
  /// $XDG_DATA_HOME/laptrainer).
  [[nodiscard]] static QString default_sqlite_path();
  /// <AppDataLocation>/recordings: where the station keeps its sessions' recordings.
  [[nodiscard]] static QString default_recordings_folder();
};

/// The password for `connection`: `password`, else the first line of `password_file` (which must
/// be a regular file readable by its owner only, as libpq demands of ~/.pgpass), else empty.
[[nodiscard]] Result<QString> connection_password(const StoreConnection& connection);

}  // namespace lap::app
