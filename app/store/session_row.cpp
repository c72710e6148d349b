#include "app/store/session_row.h"

#include <QCryptographicHash>
#include <QFile>
#include <QRegularExpression>
#include <QUuid>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace lap::app {
namespace {

std::string str(const QString& s) { return s.toStdString(); }

// A value quoted for a message, cut short: a corrupt field may be megabytes.
std::string quoted(const QString& s) {
  constexpr int kShown = 60;
  return "'" + str(s.left(kShown)) + (s.size() > kShown ? "…'" : "'");
}

bool has_control_characters(const QString& s) {
  return std::any_of(s.begin(), s.end(),
                     [](QChar c) { return c.category() == QChar::Other_Control; });
}

constexpr int kMaxNameLength = 200;

}  // namespace

bool is_session_result(const QString& result) {
  return result == QLatin1String("success") || result == QLatin1String("failure") ||
         result == QLatin1String("incomplete");
}

std::vector<Diagnostic> check_session_row(const SessionRow& row, const std::string& where) {
  std::vector<Diagnostic> problems;
  const std::string session =
      row.uuid.isEmpty() ? std::string("session") : "session " + str(row.uuid);
  const auto problem = [&](const char* field, const std::string& what) {
    problems.push_back(
        file_diagnostic(where, 0, std::string("sessions.") + field, session + ": " + what));
  };
  const QUuid uuid(row.uuid);
  if (uuid.isNull() || uuid.toString(QUuid::WithoutBraces) != row.uuid) {
    problem("uuid", "expected a UUID in lower case without braces (QUuid::WithoutBraces), found " +
                        quoted(row.uuid));
  }
  const QString trainee = row.trainee.trimmed();
  if (trainee.isEmpty() || trainee != row.trainee || trainee.size() > kMaxNameLength ||
      has_control_characters(trainee)) {
    problem("trainee", "expected the trainee's name or ID (1 to " + std::to_string(kMaxNameLength) +
                           " characters, no leading or trailing space, no control characters), "
                           "found " +
                           quoted(row.trainee));
  }
  if (row.scenario_file.isEmpty()) problem("scenario_file", "expected the scenario's path");
  static const QRegularExpression kSha256(QStringLiteral("^[0-9a-f]{64}$"));
  if (!kSha256.match(row.scenario_version).hasMatch()) {
    problem("scenario_version",
            "expected the SHA-256 of the scenario file's bytes (64 lower-case hex digits), found " +
                quoted(row.scenario_version));
  }
  if (row.station.trimmed().isEmpty()) problem("station", "expected the station's name");
  if (!row.started_utc.isValid()) problem("started_utc", "expected the time the session started");
  if (!std::isfinite(row.duration_s) || row.duration_s < 0.0) {
    problem("duration_s",
            "expected a finite number of seconds >= 0, found " + std::to_string(row.duration_s));
  }
  if (!is_session_result(row.result)) {
    problem("result", "expected success, failure or incomplete, found " + quoted(row.result));
  }
  static const QRegularExpression kReason(QStringLiteral("^[a-z][a-z0-9_]*$"));
  for (const QString& reason : row.reasons) {
    if (!kReason.match(reason).hasMatch()) {
      problem("reasons",
              "expected snake_case reasons from the task's vocabulary (duct_injury, "
              "time_limit, ...), found " +
                  quoted(reason));
    }
  }
  if (!std::isnan(row.completion_time_s) &&
      (!std::isfinite(row.completion_time_s) || row.completion_time_s < 0.0)) {
    problem("completion_time_s",
            "expected seconds >= 0 or none (NaN), found " + std::to_string(row.completion_time_s));
  }
  return problems;
}

Result<std::vector<MetricValue>> report_metrics(const QString& report_json,
                                                const std::string& where) {
  std::vector<MetricValue> metrics;
  if (report_json.isEmpty()) return metrics;
  const QByteArray bytes = report_json.toUtf8();
  const nlohmann::json j = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    return file_diagnostic(where, 0, "sessions.report_json",
                           "expected the run's JSON object (as laptrainer-cli run prints it)");
  }
  const auto m = j.find("metrics");
  if (m == j.end()) return metrics;
  if (!m->is_object()) {
    return file_diagnostic(where, 0, "report_json.metrics", "expected an object of numbers");
  }
  std::vector<Diagnostic> problems;
  for (const auto& [name, value] : m->items()) {
    if (value.is_null()) {
      metrics.push_back({QString::fromStdString(name), std::nan("")});
    } else if (value.is_number()) {
      metrics.push_back({QString::fromStdString(name), value.get<double>()});
    } else {
      problems.push_back(file_diagnostic(where, 0, "report_json.metrics." + name,
                                         "expected a number or null, found " + value.dump()));
    }
  }
  if (!problems.empty()) return problems;
  return metrics;
}

Result<QString> file_sha256(const QString& file) {
  QFile f(file);
  if (!f.open(QIODevice::ReadOnly)) {
    return file_diagnostic(str(file), 0, "", "cannot read: " + str(f.errorString()));
  }
  QCryptographicHash hash(QCryptographicHash::Sha256);
  if (!hash.addData(&f)) {
    return file_diagnostic(str(file), 0, "", "cannot read: " + str(f.errorString()));
  }
  return QString::fromLatin1(hash.result().toHex());
}

QString utc_text(const QDateTime& t) { return t.toUTC().toString(Qt::ISODateWithMs); }

QDateTime parse_utc_text(const QString& text) {
  // Parsed as ISO 8601 (never as local time, which a daylight-saving gap would make invalid),
  // and only the exact form utc_text writes.
  const QDateTime t = QDateTime::fromString(text, Qt::ISODateWithMs);
  if (!t.isValid() || utc_text(t) != text) return {};
  return t.toUTC();
}

}  // namespace lap::app
