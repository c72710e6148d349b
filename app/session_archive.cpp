#include "app/session_archive.h"

#include <QSysInfo>
#include <QUuid>
#include <algorithm>
#include <fstream>

#include "app/store/store_connection.h"
#include "sim/report/recording_reader.h"

namespace lap::app {
namespace fs = std::filesystem;

namespace {

// attempt.json and metrics.json are small; anything larger is not ours.
constexpr std::uintmax_t kMaxJsonBytes = 64U << 20U;

Status make_private_dir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Diagnostic{dir.string(), 0, "", "cannot create the folder: " + ec.message()};
  // A trainee's sessions are theirs: the folder for its owner only.
  fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace, ec);
  if (ec) return Diagnostic{dir.string(), 0, "", "cannot set its permissions: " + ec.message()};
  return {};
}

Result<nlohmann::ordered_json> read_json(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    return Diagnostic{file.string(), 0, "", "missing or not a regular file"};
  }
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec || size > kMaxJsonBytes) {
    return Diagnostic{file.string(), 0, "", "unreadable or larger than 64 MB"};
  }
  std::ifstream f(file);
  auto j = nlohmann::ordered_json::parse(f, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) {
    return Diagnostic{file.string(), 0, "", "is not a JSON object"};
  }
  return j;
}

QString text_field(const nlohmann::ordered_json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_string() ? QString::fromStdString(it->get<std::string>())
                                          : QString();
}

}  // namespace

Result<fs::path> recordings_root() {
  const QString folder = StoreConnection::default_recordings_folder();
  if (folder.startsWith("/laptrainer")) {
    return diagnostic("the desktop gives no folder for the application's data");
  }
  const fs::path root = folder.toStdString();
  if (Status made = make_private_dir(root); !made.ok()) return made.diagnostics();
  return root;
}

Result<SessionRow> begin_attempt(const fs::path& root, const QString& trainee,
                                 const fs::path& scenario_file, const QString& scenario_name,
                                 const QString& devices, const QString& station) {
  SessionRow r;
  r.uuid = QUuid::createUuid().toString(QUuid::WithoutBraces);
  r.trainee = trainee;
  std::error_code ec;
  const fs::path absolute = fs::absolute(scenario_file, ec);
  r.scenario_file = QString::fromStdString((ec ? scenario_file : absolute).string());
  r.scenario_name = scenario_name;
  const Result<QString> version = file_sha256(QString::fromStdString(scenario_file.string()));
  if (!version.ok()) return version.diagnostics();
  r.scenario_version = version.value();
  r.devices = devices;
  r.station = station.trimmed().isEmpty() ? QSysInfo::machineHostName() : station;
  r.started_utc = QDateTime::currentDateTimeUtc();
  r.result = "incomplete";
  const fs::path dir = root / r.uuid.toStdString();
  r.recording_dir = QString::fromStdString(dir.string());
  if (fs::exists(dir, ec)) return Diagnostic{dir.string(), 0, "", "already exists"};
  if (Status made = make_private_dir(dir); !made.ok()) return made.diagnostics();
  const nlohmann::ordered_json j = {
      {"format", "laptrainer-attempt"},
      {"version", 1},
      {"uuid", r.uuid.toStdString()},
      {"trainee", r.trainee.toStdString()},
      {"scenario", r.scenario_file.toStdString()},
      {"scenario_name", r.scenario_name.toStdString()},
      {"scenario_sha256", r.scenario_version.toStdString()},
      {"devices", r.devices.toStdString()},
      {"station", r.station.toStdString()},
      {"started_utc", r.started_utc.toString(Qt::ISODateWithMs).toStdString()}};
  const fs::path file = dir / "attempt.json";
  std::ofstream f(file);
  f << j.dump(2) << "\n";
  f.flush();
  if (!f) return Diagnostic{file.string(), 0, "", "cannot write the attempt's description"};
  return r;
}

void finish_attempt(const nlohmann::ordered_json& metrics, SessionRow* r) {
  r->interrupted = false;
  r->reasons.clear();
  r->result = "incomplete";
  r->completion_time_s = std::nan("");
  const auto task = metrics.find("task");
  if (task != metrics.end() && task->is_object()) {
    if (const QString result = text_field(*task, "result"); !result.isEmpty()) r->result = result;
    if (const auto reasons = task->find("reasons"); reasons != task->end() && reasons->is_array()) {
      for (const auto& reason : *reasons) {
        if (reason.is_string()) r->reasons << QString::fromStdString(reason.get<std::string>());
      }
    }
  }
  const auto m = metrics.find("metrics");
  if (m != metrics.end() && m->is_object()) {
    if (const auto c = m->find("completion_time_s"); c != m->end() && c->is_number()) {
      r->completion_time_s = c->get<double>();
    }
    if (const auto t = m->find("session_time_s"); t != m->end() && t->is_number()) {
      r->duration_s = t->get<double>();
    }
  }
  // The report without its series: the database keeps the figures, the folder the plots' data.
  nlohmann::ordered_json report = metrics;
  report.erase("series");
  r->report_json = QString::fromStdString(report.dump());
}

Result<SessionRow> read_attempt_header(const fs::path& dir) {
  const fs::path file = dir / "attempt.json";
  const Result<nlohmann::ordered_json> read = read_json(file);
  if (!read.ok()) return read.diagnostics();
  const nlohmann::ordered_json& j = read.value();
  SessionRow r;
  r.uuid = text_field(j, "uuid");
  r.trainee = text_field(j, "trainee");
  r.scenario_file = text_field(j, "scenario");
  r.scenario_name = text_field(j, "scenario_name");
  r.scenario_version = text_field(j, "scenario_sha256");
  r.devices = text_field(j, "devices");
  r.station = text_field(j, "station");
  r.started_utc = QDateTime::fromString(text_field(j, "started_utc"), Qt::ISODateWithMs);
  r.recording_dir = QString::fromStdString(dir.string());
  r.result = "incomplete";
  for (const auto& [field, value] :
       {std::pair{"uuid", &r.uuid}, {"trainee", &r.trainee}, {"scenario", &r.scenario_file}}) {
    if (value->isEmpty()) {
      return Diagnostic{file.string(), 0, field, "expected a non-empty string"};
    }
  }
  if (r.uuid.toStdString() != dir.filename().string()) {
    return Diagnostic{file.string(), 0, "uuid",
                      "expected the folder's name, " + dir.filename().string()};
  }
  if (!r.started_utc.isValid()) {
    return Diagnostic{file.string(), 0, "started_utc", "expected an ISO 8601 date and time"};
  }
  r.started_utc.setTimeSpec(Qt::UTC);
  return r;
}

Result<SessionRow> read_attempt(const fs::path& dir) {
  Result<SessionRow> header = read_attempt_header(dir);
  if (!header.ok()) return header;
  SessionRow r = std::move(header).value();
  std::error_code ec;
  if (fs::is_regular_file(dir / "metrics.json", ec)) {
    // It ended and was saved; only the filing was missed.
    const Result<nlohmann::ordered_json> metrics = read_json(dir / "metrics.json");
    if (!metrics.ok()) return metrics.diagnostics();
    finish_attempt(metrics.value(), &r);
    return r;
  }
  // Killed mid-attempt: what the streamed recording kept (`laptrainer-cli report --session DIR`
  // replays it for the metrics).
  r.interrupted = true;
  const Result<sim::RecordedSession> rec = sim::read_session_recording(dir / "session.lrec");
  if (!rec.ok()) return rec.diagnostics();
  double rate_hz = 1000.0;
  const auto head = nlohmann::json::parse(rec.value().header_json, nullptr, false);
  if (head.is_object() && head.contains("haptic_rate_hz") && head["haptic_rate_hz"].is_number() &&
      head["haptic_rate_hz"].get<double>() > 0.0) {
    rate_hz = head["haptic_rate_hz"].get<double>();
  }
  r.duration_s = static_cast<double>(rec.value().ticks_read) / rate_hz;
  nlohmann::ordered_json report = {{"interrupted", true},
                                   {"recorded_ticks", rec.value().ticks_read},
                                   {"task", {{"result", "incomplete"}, {"reasons", {}}}}};
  if (!rec.value().problems.empty()) report["recording_problems"] = rec.value().problems;
  r.report_json = QString::fromStdString(report.dump());
  return r;
}

std::vector<fs::path> recorded_attempt_dirs(const fs::path& root) {
  std::vector<std::pair<fs::file_time_type, fs::path>> found;
  std::error_code ec;
  for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e2;
    if (!it->is_directory(e2)) continue;
    const fs::path lrec = it->path() / "session.lrec";
    if (!fs::is_regular_file(lrec, e2)) continue;
    found.emplace_back(fs::last_write_time(lrec, e2), it->path());
  }
  std::sort(found.begin(), found.end());
  std::vector<fs::path> out;
  out.reserve(found.size());
  for (auto& f : found) out.push_back(std::move(f.second));
  return out;
}

}  // namespace lap::app
