#include "app/review/review_export.h"

#include <QFile>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>

#include "sim/report/proficiency.h"
#include "sim/report/session_pdf.h"
#include "sim/report/session_report.h"
#include "sim/setup/scenario_loader.h"

namespace lap::app {

namespace {

std::string str(const QString& s) { return s.toStdString(); }

// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

nlohmann::ordered_json number_json(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

}  // namespace

std::string number_text(double v) {
  if (!std::isfinite(v)) return {};
  char text[64];
  const auto end = std::to_chars(text, text + sizeof(text), v).ptr;
  return std::string(text, end);
}

std::string metrics_csv(const std::vector<sim::Metric>& metrics,
                        const std::optional<sim::ProficiencySpec>& proficiency) {
  std::vector<sim::BenchmarkResult> verdicts;
  if (proficiency) verdicts = sim::assess_proficiency(*proficiency, metrics);
  std::string out = "metric,value,limit,better,met\n";
  for (const sim::Metric& m : metrics) {
    out += csv_field(m.name) + "," + number_text(m.value);
    const sim::BenchmarkResult* verdict = nullptr;
    for (const sim::BenchmarkResult& r : verdicts) {
      if (r.benchmark.metric == m.name) verdict = &r;
    }
    if (verdict != nullptr) {
      out += "," + number_text(verdict->limit) + "," +
             (verdict->benchmark.higher_is_better ? "higher" : "lower") + "," +
             (verdict->met ? "yes" : "no");
    } else {
      out += ",,,";
    }
    out += "\n";
  }
  return out;
}

std::string series_csv(const sim::MetricsSeries& s) {
  std::string out =
      "t_s,insertion_depth_m,force_duct_n,squeeze_duct_n,speed_left_m_per_s,speed_right_m_per_s\n";
  const auto at = [](const std::vector<double>& v, size_t i) {
    return i < v.size() ? number_text(v[i]) : std::string();
  };
  for (size_t i = 0; i < s.t_s.size(); ++i) {
    out += number_text(s.t_s[i]) + "," + at(s.depth_m, i) + "," + at(s.duct_force_n, i) + "," +
           at(s.squeeze_n, i) + "," + at(s.speed_m_per_s[0], i) + "," + at(s.speed_m_per_s[1], i) +
           "\n";
  }
  return out;
}

std::string session_json(const SessionRow& row, const sim::ReplayedSession* replayed) {
  nlohmann::ordered_json j;
  nlohmann::ordered_json s;
  s["uuid"] = str(row.uuid);
  s["trainee"] = str(row.trainee);
  s["scenario_file"] = str(row.scenario_file);
  s["scenario_name"] = str(row.scenario_name);
  s["scenario_version"] = str(row.scenario_version);
  s["devices"] = str(row.devices);
  s["station"] = str(row.station);
  s["started_utc"] = str(utc_text(row.started_utc));
  s["duration_s"] = number_json(row.duration_s);
  s["result"] = str(row.result);
  s["reasons"] = nlohmann::ordered_json::array();
  for (const QString& r : row.reasons) s["reasons"].push_back(str(r));
  s["completion_time_s"] = number_json(row.completion_time_s);
  s["recording_dir"] = str(row.recording_dir);
  s["interrupted"] = row.interrupted;
  j["session"] = s;
  const QByteArray report = row.report_json.toUtf8();
  const nlohmann::ordered_json stored =
      nlohmann::ordered_json::parse(report.begin(), report.end(), nullptr, false);
  j["report"] = stored.is_discarded() ? nlohmann::ordered_json(nullptr) : stored;
  if (replayed != nullptr) {
    nlohmann::ordered_json r = sim::metrics_to_json(
        replayed->metrics, replayed->record.scenario.string(), replayed->record.settings.fast);
    r["interrupted"] = replayed->interrupted;
    r["notes"] = replayed->notes;
    r["recording_problems"] = replayed->recording_problems;
    r["series"] = sim::series_to_json(replayed->metrics.series);
    j["replay"] = r;
  }
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

std::string trainee_metrics_csv(const std::vector<SessionRow>& sessions,
                                const std::vector<std::vector<MetricValue>>& metrics_per_session,
                                const std::vector<QString>& metric_names) {
  std::string out = "uuid,started_utc,scenario_file,result";
  for (const QString& name : metric_names) out += "," + csv_field(str(name));
  out += "\n";
  for (size_t i = 0; i < sessions.size(); ++i) {
    const SessionRow& r = sessions[i];
    out += str(r.uuid) + "," + str(utc_text(r.started_utc)) + "," +
           csv_field(str(r.scenario_file)) + "," + str(r.result);
    for (const QString& name : metric_names) {
      double value = std::nan("");
      if (i < metrics_per_session.size()) {
        for (const MetricValue& m : metrics_per_session[i]) {
          if (m.name == name) value = m.value;
        }
      }
      out += "," + number_text(value);
    }
    out += "\n";
  }
  return out;
}

std::vector<sim::Metric> to_metrics(const std::vector<MetricValue>& values) {
  std::vector<sim::Metric> out;
  out.reserve(values.size());
  for (const MetricValue& v : values) out.push_back({str(v.name), v.value});
  return out;
}

sim::TraineePdfContext trainee_report(
    const QString& trainee, const QString& scenario_name, const QString& scenario_file,
    const std::vector<SessionRow>& sessions,
    const std::vector<std::vector<MetricValue>>& metrics_per_session,
    const std::optional<sim::ProficiencySpec>& proficiency) {
  sim::TraineePdfContext c;
  c.trainee = str(trainee);
  c.scenario_name = str(scenario_name);
  c.scenario_file = str(scenario_file);
  std::vector<std::vector<sim::Metric>> per_session;
  for (size_t i = 0; i < sessions.size(); ++i) {
    const SessionRow& r = sessions[i];
    sim::TraineeSessionLine line;
    line.started = str(r.started_utc.toLocalTime().toString(QStringLiteral("yyyy-MM-dd HH:mm")));
    line.result = str(r.result);
    for (const QString& reason : r.reasons) line.reasons.push_back(str(reason));
    line.completion_time_s = r.completion_time_s;
    line.interrupted = r.interrupted;
    c.sessions.push_back(line);
    per_session.push_back(i < metrics_per_session.size() ? to_metrics(metrics_per_session[i])
                                                         : std::vector<sim::Metric>{});
  }
  std::vector<sim::ProficiencyProgress> progress;
  if (proficiency) {
    c.proficiency_source = proficiency->source;
    progress = sim::proficiency_progress(*proficiency, per_session);
  }
  // Every metric any session has, in the first session's order then any new ones.
  std::vector<std::string> names;
  for (const std::vector<sim::Metric>& metrics : per_session) {
    for (const sim::Metric& m : metrics) {
      if (std::find(names.begin(), names.end(), m.name) == names.end()) names.push_back(m.name);
    }
  }
  for (const std::string& name : names) {
    sim::LearningCurve curve;
    curve.metric = name;
    for (const std::vector<sim::Metric>& metrics : per_session) {
      double v = std::nan("");
      for (const sim::Metric& m : metrics) {
        if (m.name == name) v = m.value;
      }
      curve.values.push_back(v);
    }
    for (const sim::ProficiencyProgress& p : progress) {
      if (p.benchmark.metric == name) curve.progress = p;
    }
    c.curves.push_back(std::move(curve));
  }
  return c;
}

std::string session_pdf_bytes(const SessionRow& row, const sim::ReplayedSession& r) {
  sim::SessionPdfContext c;
  c.scenario_name = r.scenario_name;
  c.scenario_file = r.record.scenario.string();
  c.session = str(row.recording_dir) + "  (" + str(row.trainee) + ", " +
              str(row.started_utc.toLocalTime().toString(QStringLiteral("yyyy-MM-dd HH:mm"))) + ")";
  c.mode = r.record.settings.fast ? "fast" : "realtime";
  if (r.task) {
    c.duct_injury_force_n = r.task->duct_injury_force_n;
    c.insertion_depth_m = r.task->insertion_depth_m;
  }
  c.notes = r.notes;
  if (r.interrupted) c.notes.push_back("interrupted: the recording has no end (a crash)");
  return sim::session_pdf(r.metrics, c).bytes();
}

Status write_export(const QString& file, const std::string& bytes) {
  QFile f(file);
  if (!f.open(QIODevice::WriteOnly | QIODevice::Truncate)) {
    return file_diagnostic(str(file), 0, "", "cannot write the export: " + str(f.errorString()));
  }
  if (f.write(bytes.data(), static_cast<qint64>(bytes.size())) !=
          static_cast<qint64>(bytes.size()) ||
      !f.flush()) {
    return file_diagnostic(str(file), 0, "", "cannot write the export: " + str(f.errorString()));
  }
  return {};
}

std::optional<sim::ProficiencySpec> scenario_proficiency(const QString& scenario_file,
                                                         std::string* why) {
  const sim::ScenarioLoadResult scenario = sim::load_scenario(str(scenario_file));
  if (!scenario.ok()) {
    if (why != nullptr) *why = scenario.message();
    return std::nullopt;
  }
  if (!scenario.value().proficiency && why != nullptr) {
    *why = str(scenario_file) + ": the scenario has no proficiency benchmarks";
  }
  return scenario.value().proficiency;
}

}  // namespace lap::app
