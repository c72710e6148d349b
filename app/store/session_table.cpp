#include "app/store/session_table.h"

#include <QSqlError>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace lap::app {
namespace {

std::string str(const QString& s) { return s.toStdString(); }

const QString kSessionColumns = QStringLiteral(
    "uuid, trainee, scenario_file, scenario_name, scenario_version, devices, station, "
    "started_utc, duration_s, result, reasons, completion_time_s, report_json, recording_dir, "
    "interrupted");

// A double for a statement: NaN and the infinities as NULL (SQLite would store NaN as NULL
// anyway; PostgreSQL would keep it).
QVariant nullable(double v) {
  return std::isfinite(v) ? QVariant(v) : QVariant(QMetaType::fromType<double>());
}

// Text for a statement: Qt binds a null QString as SQL NULL, and the store's text columns are
// NOT NULL (an empty field is "", not unknown).
QVariant text(const QString& s) { return s.isNull() ? QVariant(QStringLiteral("")) : QVariant(s); }

QString reasons_json(const QStringList& reasons) {
  nlohmann::json j = nlohmann::json::array();
  for (const QString& r : reasons) j.push_back(str(r));
  return QString::fromStdString(j.dump());
}

// WHERE clause and binds for a filter.
QString where_clause(const SessionFilter& f, QVariantList* binds, const QString& prefix = {}) {
  QStringList parts;
  if (!f.trainee.isEmpty()) {
    parts << prefix + QStringLiteral("trainee = ?");
    binds->append(f.trainee);
  }
  if (!f.scenario_file.isEmpty()) {
    parts << prefix + QStringLiteral("scenario_file = ?");
    binds->append(f.scenario_file);
  }
  if (!f.uuid.isEmpty()) {
    parts << prefix + QStringLiteral("uuid = ?");
    binds->append(f.uuid);
  }
  if (f.outbox_only) {
    parts << prefix + QStringLiteral("uuid IN (SELECT session_uuid FROM outbox)");
  }
  return parts.isEmpty() ? QString()
                         : QStringLiteral(" WHERE ") + parts.join(QStringLiteral(" AND "));
}

// Reads a number column: NULL gives NaN when `nullable`, anything that is not a number an error.
bool read_number(const QVariant& v, bool allow_null, double* out) {
  if (v.isNull()) {
    *out = std::nan("");
    return allow_null;
  }
  bool ok = false;
  // Text in a number column (SQLite keeps what it is given) is not taken as a number.
  if (v.typeId() == QMetaType::QString || v.typeId() == QMetaType::QByteArray) return false;
  *out = v.toDouble(&ok);
  return ok;
}

// One row of kSessionColumns, checked: every problem named with the session and field.
Result<SessionRow> read_row(const Database& db, const QSqlQuery& q) {
  SessionRow row;
  std::vector<Diagnostic> problems;
  row.uuid = q.value(0).toString();
  const std::string session = "session " + str(row.uuid);
  const auto problem = [&](const char* field, const std::string& what) {
    problems.push_back(db.problem(std::string("sessions.") + field, session + ": " + what));
  };
  const auto found = [](const QVariant& v) {
    return v.isNull() ? std::string("NULL") : "'" + str(v.toString().left(60)) + "'";
  };
  row.trainee = q.value(1).toString();
  row.scenario_file = q.value(2).toString();
  row.scenario_name = q.value(3).toString();
  row.scenario_version = q.value(4).toString();
  row.devices = q.value(5).toString();
  row.station = q.value(6).toString();
  row.started_utc = parse_utc_text(q.value(7).toString());
  if (!row.started_utc.isValid()) {
    problem("started_utc",
            "expected a UTC time as 2025-03-01T09:30:00.000Z, found " + found(q.value(7)));
  }
  if (!read_number(q.value(8), false, &row.duration_s)) {
    problem("duration_s", "expected a number of seconds, found " + found(q.value(8)));
    row.duration_s = 0.0;
  }
  row.result = q.value(9).toString();
  const QByteArray reasons = q.value(10).toString().toUtf8();
  const nlohmann::json r = nlohmann::json::parse(reasons.begin(), reasons.end(), nullptr, false);
  if (r.is_discarded() || !r.is_array()) {
    problem("reasons", "expected a JSON array of reasons, found " + found(q.value(10)));
  } else {
    for (const nlohmann::json& reason : r) {
      if (!reason.is_string()) {
        problem("reasons", "expected each reason as a string, found " + reason.dump());
        continue;
      }
      row.reasons << QString::fromStdString(reason.get<std::string>());
    }
  }
  if (!read_number(q.value(11), true, &row.completion_time_s)) {
    problem("completion_time_s",
            "expected a number of seconds or NULL, found " + found(q.value(11)));
  }
  row.report_json = q.value(12).toString();
  row.recording_dir = q.value(13).toString();
  const QVariant interrupted = q.value(14);
  bool ok = false;
  const int flag = interrupted.toString().toInt(&ok);
  if (!ok || (flag != 0 && flag != 1)) {
    problem("interrupted", "expected 0 or 1, found " + found(interrupted));
  }
  row.interrupted = flag == 1;
  if (problems.empty()) {
    // The same checks as on the way in (uuid, result, times, ...).
    std::vector<Diagnostic> checked = check_session_row(row, db.name());
    problems.insert(problems.end(), checked.begin(), checked.end());
  }
  if (!problems.empty()) return problems;
  return row;
}

}  // namespace

Status insert_trainee(const Database& db, const QString& name) {
  Result<QSqlQuery> q =
      db.run(QStringLiteral("INSERT INTO trainees (name, added_utc) VALUES (?, ?) "
                            "ON CONFLICT (name) DO NOTHING"),
             {name, utc_text(QDateTime::currentDateTimeUtc())}, "trainees", "add the trainee");
  if (!q.ok()) return std::move(q).diagnostics();
  return {};
}

Result<bool> insert_session(const Database& db, const SessionRow& row,
                            const std::vector<MetricValue>& metrics) {
  if (Status trainee = insert_trainee(db, row.trainee); !trainee.ok()) return trainee.diagnostics();
  Result<QSqlQuery> q = db.run(
      QStringLiteral("INSERT INTO sessions (") + kSessionColumns +
          QStringLiteral(", added_utc) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
                         "ON CONFLICT (uuid) DO NOTHING"),
      {text(row.uuid), text(row.trainee), text(row.scenario_file), text(row.scenario_name),
       text(row.scenario_version), text(row.devices), text(row.station), utc_text(row.started_utc),
       row.duration_s, text(row.result), reasons_json(row.reasons), nullable(row.completion_time_s),
       text(row.report_json), text(row.recording_dir), row.interrupted ? 1 : 0,
       utc_text(QDateTime::currentDateTimeUtc())},
      "sessions", "add session " + str(row.uuid));
  if (!q.ok()) return std::move(q).diagnostics();
  if (q->numRowsAffected() == 0) return false;  // already there: its first copy stands
  for (const MetricValue& m : metrics) {
    Result<QSqlQuery> mq = db.run(
        QStringLiteral("INSERT INTO session_metrics (session_uuid, name, value) VALUES (?, ?, ?) "
                       "ON CONFLICT (session_uuid, name) DO NOTHING"),
        {row.uuid, m.name, nullable(m.value)}, "session_metrics." + str(m.name),
        "add session " + str(row.uuid) + "'s metric");
    if (!mq.ok()) return std::move(mq).diagnostics();
  }
  return true;
}

Result<std::vector<SessionRow>> select_sessions(const Database& db, const SessionFilter& filter) {
  QVariantList binds;
  const QString sql = QStringLiteral("SELECT ") + kSessionColumns +
                      QStringLiteral(" FROM sessions") + where_clause(filter, &binds) +
                      QStringLiteral(" ORDER BY started_utc DESC, uuid DESC");
  Result<QSqlQuery> q = db.run(sql, binds, "sessions", "read the sessions");
  if (!q.ok()) return std::move(q).diagnostics();
  std::vector<SessionRow> rows;
  std::vector<Diagnostic> problems;
  while (q->next()) {
    Result<SessionRow> row = read_row(db, q.value());
    if (!row.ok()) {
      const std::vector<Diagnostic>& d = row.diagnostics();
      problems.insert(problems.end(), d.begin(), d.end());
      continue;
    }
    rows.push_back(std::move(row).value());
  }
  if (q->lastError().isValid()) {
    problems.push_back(
        db.problem("sessions", "cannot read the sessions: " + str(q->lastError().text())));
  }
  if (!problems.empty()) return problems;
  return rows;
}

Result<std::vector<MetricValue>> select_metrics(const Database& db, const QString& uuid) {
  Result<QSqlQuery> q =
      db.run(QStringLiteral("SELECT name, value FROM session_metrics WHERE session_uuid = ? "
                            "ORDER BY name"),
             {uuid}, "session_metrics", "read session " + str(uuid) + "'s metrics");
  if (!q.ok()) return std::move(q).diagnostics();
  std::vector<MetricValue> metrics;
  std::vector<Diagnostic> problems;
  while (q->next()) {
    MetricValue m{q->value(0).toString(), 0.0};
    if (!read_number(q->value(1), true, &m.value)) {
      problems.push_back(
          db.problem("session_metrics.value", "session " + str(uuid) + ": metric " + str(m.name) +
                                                  ": expected a number or NULL, found '" +
                                                  str(q->value(1).toString().left(60)) + "'"));
      continue;
    }
    metrics.push_back(m);
  }
  if (!problems.empty()) return problems;
  return metrics;
}

Result<std::vector<MetricPoint>> select_metric(const Database& db, const QString& name,
                                               const SessionFilter& filter) {
  QVariantList binds{name};
  QString where = where_clause(filter, &binds, QStringLiteral("s."));
  where = where.isEmpty() ? QStringLiteral(" WHERE m.name = ?")
                          : where + QStringLiteral(" AND m.name = ?");
  // The name is bound first in `binds` but used last: move it to the end.
  binds.append(binds.takeFirst());
  Result<QSqlQuery> q =
      db.run(QStringLiteral("SELECT s.trainee, s.uuid, s.scenario_file, s.started_utc, m.value "
                            "FROM session_metrics m JOIN sessions s ON s.uuid = m.session_uuid") +
                 where + QStringLiteral(" ORDER BY s.started_utc, s.uuid"),
             binds, "session_metrics." + str(name), "read the metric across sessions");
  if (!q.ok()) return std::move(q).diagnostics();
  std::vector<MetricPoint> points;
  std::vector<Diagnostic> problems;
  while (q->next()) {
    MetricPoint p;
    p.trainee = q->value(0).toString();
    p.uuid = q->value(1).toString();
    p.scenario_file = q->value(2).toString();
    p.started_utc = parse_utc_text(q->value(3).toString());
    if (!p.started_utc.isValid() || !read_number(q->value(4), true, &p.value)) {
      problems.push_back(
          db.problem("session_metrics." + str(name),
                     "session " + str(p.uuid) + ": expected a start time and a number or NULL"));
      continue;
    }
    points.push_back(p);
  }
  if (!problems.empty()) return problems;
  return points;
}

Result<std::vector<QString>> select_trainees(const Database& db) {
  Result<QSqlQuery> q = db.run(QStringLiteral("SELECT name FROM trainees ORDER BY name"), {},
                               "trainees", "read the trainees");
  if (!q.ok()) return std::move(q).diagnostics();
  std::vector<QString> names;
  while (q->next()) names.push_back(q->value(0).toString());
  // In code-point order on both databases (their collations differ).
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace lap::app
