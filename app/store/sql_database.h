#pragma once
/// \file
/// One open connection to a store's database through Qt SQL — the station's SQLite file or the
/// programme's PostgreSQL server — with the checks that belong to opening it (the driver is
/// installed, the file is a database and private to its owner, the server answers) and every
/// statement's failure turned into a Diagnostic naming the database and what was being done.
///
/// A connection belongs to the thread that opened it (Qt SQL's rule); the store is used from
/// the GUI thread.

#include <QSqlDatabase>
#include <QSqlQuery>
#include <QString>
#include <QVariantList>
#include <memory>
#include <string>

#include "app/store/store_connection.h"
#include "core/result.h"

namespace lap::app {

enum class SqlDialect { kSqlite, kPostgresql };

class Database {
 public:
  /// Opens (creating if missing) the SQLite file at `path`: its folder made 0700 when created
  /// here, the file 0600 (and its -wal and -shm files), WAL journal, foreign keys on, full sync,
  /// a 5 s busy timeout. A file that is not an SQLite database is left untouched and named in
  /// the diagnostic.
  [[nodiscard]] static Result<std::unique_ptr<Database>> open_sqlite(const QString& path);
  /// Connects to the PostgreSQL server `connection` names (Qt's QPSQL driver, libpq) with
  /// `password` (empty: libpq's own ~/.pgpass or PGPASSWORD); diagnostics give the server's
  /// reason (unreachable, wrong credentials, no such database).
  [[nodiscard]] static Result<std::unique_ptr<Database>> open_postgresql(
      const StoreConnection& connection, const QString& password);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  [[nodiscard]] SqlDialect dialect() const { return dialect_; }
  /// How messages name it: the SQLite file's path or postgresql://user@host:port/database.
  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] QSqlDatabase handle() const;

  /// Prepares and runs `sql` with `binds` (positional `?`); on failure a Diagnostic naming this
  /// database, `field` (a table or table.field) and `what` was being done, with the driver's text.
  [[nodiscard]] Result<QSqlQuery> run(const QString& sql, const QVariantList& binds,
                                      const std::string& field, const std::string& what) const;
  /// A write transaction (SQLite: BEGIN IMMEDIATE, so that a second writer waits for the lock
  /// rather than failing half-way).
  [[nodiscard]] Status begin_write() const;
  [[nodiscard]] Status commit() const;
  void rollback() const;
  /// Whether the connection still answers (a server may have gone away since it was opened).
  [[nodiscard]] bool alive() const;

  /// The Diagnostic for a failed operation on this database.
  [[nodiscard]] Diagnostic problem(const std::string& field, const std::string& what) const;

 private:
  Database(QString connection_name, SqlDialect dialect, std::string name);
  QString connection_name_;
  SqlDialect dialect_;
  std::string name_;
};

/// Makes `folder` (and its parents) if missing, the folder itself owner-only (0700); an existing
/// folder is tightened to 0700 only when `tighten_existing`. Diagnostics name the folder.
[[nodiscard]] Status make_private_folder(const QString& folder, bool tighten_existing);

}  // namespace lap::app
