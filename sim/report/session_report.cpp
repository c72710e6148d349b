#include "sim/report/session_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/whole_file.h"
#include "sim/report/proficiency.h"
#include "sim/report/session_replay.h"

namespace lap::sim {

nlohmann::ordered_json loop_json(const LoopStats& s) {
  nlohmann::ordered_json j;
  j["ticks"] = s.ticks();
  j["period_s"] = s.period_s();
  j["achieved_rate_hz"] = s.achieved_rate_hz();
  j["jitter_p50_us"] = s.jitter_quantile_s(0.5) * 1e6;
  j["jitter_p99_us"] = s.jitter_quantile_s(0.99) * 1e6;
  j["jitter_p999_us"] = s.jitter_quantile_s(0.999) * 1e6;
  j["worst_lateness_us"] = s.worst_lateness_s() * 1e6;
  j["missed_deadlines"] = s.missed_deadlines();
  j["overruns"] = s.overruns();
  j["mean_step_us"] = s.mean_step_s() * 1e6;
  j["worst_step_us"] = s.worst_step_s() * 1e6;
  return j;
}

nlohmann::ordered_json watchdog_event_json(const WatchdogEvent& e,
                                           const std::vector<std::string>& organ_names) {
  nlohmann::ordered_json j;
  j["tick"] = e.tick;
  j["tool"] = e.tool == 0 ? "left" : e.tool == 1 ? "right" : "haptic loop";
  j["reason"] = std::string(to_string(e.reason));
  if (e.reason == WatchdogReason::kModelFault) {
    j["model"] = std::string(to_string(e.model_fault.kind));
    const auto organ = static_cast<size_t>(e.model_fault.organ);
    j["organ"] = e.model_fault.organ >= 0 && organ < organ_names.size() ? organ_names[organ] : "";
  }
  return j;
}

namespace {

std::string_view task_kind_name(TaskKind kind) {
  switch (kind) {
    case TaskKind::kNone:
      return "none";
    case TaskKind::kCatheterInsertion:
      return "catheter-insertion";
    case TaskKind::kFreeExploration:
      return "free-exploration";
  }
  return "unknown";
}

nlohmann::ordered_json task_event_json(const TaskEvent& e,
                                       const std::vector<std::string>& organ_names) {
  nlohmann::ordered_json j;
  j["t_s"] = e.t_s;
  j["kind"] = std::string(to_string(e.kind));
  if (e.tool >= 0) j["tool"] = e.tool == 0 ? "left" : "right";
  if (e.organ >= 0) {
    const auto organ = static_cast<size_t>(e.organ);
    j["organ"] = organ < organ_names.size() ? organ_names[organ] : std::to_string(e.organ);
  }
  switch (e.kind) {
    case TaskEventKind::kTargetDepthReached:
    case TaskEventKind::kTargetDepthLost:
      j["depth_m"] = e.value;
      break;
    case TaskEventKind::kDuctInjury:
    case TaskEventKind::kOrganInjury:
      j[e.squeeze ? "squeeze_n" : "force_n"] = e.value;
      j["duration_s"] = e.duration_s;
      break;
    case TaskEventKind::kOutOfView:
    case TaskEventKind::kCatheterDropped:
      j["duration_s"] = e.duration_s;
      break;
    default:
      break;
  }
  return j;
}

}  // namespace

nlohmann::ordered_json task_to_json(TaskKind kind, const TaskState& t,
                                    const std::vector<std::string>& organ_names) {
  nlohmann::ordered_json j;
  j["kind"] = std::string(task_kind_name(kind));
  j["result"] = std::string(to_string(t.result));
  j["reasons"] = nlohmann::ordered_json::array();
  for (size_t i = 0; i < t.reason_count; ++i) {
    j["reasons"].push_back(std::string(to_string(t.reasons[i])));
  }
  j["events"] = nlohmann::ordered_json::array();
  for (const TaskEvent& e : t.events) j["events"].push_back(task_event_json(e, organ_names));
  j["completion_time_s"] =
      t.end_s >= 0.0 ? nlohmann::ordered_json(t.end_s) : nlohmann::ordered_json(nullptr);
  nlohmann::ordered_json phases;
  const char* const names[] = {"catheter_grasped", "tip_at_incision", "tip_in_lumen",
                               "target_depth_reached", "held"};
  for (size_t p = 0; p < t.phase_s.size(); ++p) {
    phases[names[p]] = t.phase_s[p] >= 0.0 ? nlohmann::ordered_json(t.phase_s[p])
                                           : nlohmann::ordered_json(nullptr);
  }
  j["phase_times_s"] = phases;
  j["events_dropped"] = t.events_dropped;
  return j;
}

nlohmann::ordered_json training_to_json(const std::vector<Metric>& metrics) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const Metric& x : metrics) {
    j[x.name] = std::isfinite(x.value) ? nlohmann::ordered_json(x.value) : nullptr;
  }
  return j;
}

nlohmann::ordered_json series_to_json(const MetricsSeries& s) {
  nlohmann::ordered_json j;
  j["t_s"] = s.t_s;
  j["insertion_depth_m"] = s.depth_m;
  j["force_duct_n"] = s.duct_force_n;
  j["squeeze_duct_n"] = s.squeeze_n;
  j["speed_left_m_per_s"] = s.speed_m_per_s[0];
  j["speed_right_m_per_s"] = s.speed_m_per_s[1];
  j["dropped"] = s.dropped;
  return j;
}

nlohmann::ordered_json metrics_to_json(const SessionMetrics& m, const std::string& scenario,
                                       bool fast) {
  char hash[32];
  std::snprintf(hash, sizeof(hash), "%016llx", static_cast<unsigned long long>(m.state_hash));
  nlohmann::ordered_json j;
  j["scenario"] = scenario;
  j["mode"] = fast ? "fast" : "realtime";
  j["task"] = task_to_json(m.task_kind, m.task, m.organ_names);
  j["metrics"] = training_to_json(m.training);
  if (m.proficiency) j["proficiency"] = proficiency_to_json(*m.proficiency, m.training);
  j["haptic"] = loop_json(m.haptic);
  // Ticks the watchdog zeroed for starting late, the forces ramping back (no pause, no event).
  j["haptic"]["late_ticks"] = m.late_ticks;
  j["model"] = loop_json(m.model);
  j["paused"] = m.paused;
  j["watchdog_events"] = nlohmann::ordered_json::array();
  for (const WatchdogEvent& e : m.events) {
    j["watchdog_events"].push_back(watchdog_event_json(e, m.organ_names));
  }
  j["devices"] = {{"left", std::string(hardware::to_string(m.device_status[0]))},
                  {"right", std::string(hardware::to_string(m.device_status[1]))}};
  j["recorded_ticks"] = m.recorded_ticks;
  j["dropped_samples"] = m.dropped_samples;
  j["max_force_sent_n"] = m.max_force_sent_n;
  j["warnings"] = m.warnings;
  j["state_hash"] = hash;
  return j;
}

std::string metrics_json(const SessionMetrics& m, const std::string& scenario, bool fast) {
  // Names and paths come from the user (arguments, scenario files) and need not be UTF-8: such
  // bytes are replaced rather than failing the report at the end of a session.
  return metrics_to_json(m, scenario, fast)
             .dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) +
         "\n";
}

Status save_session(const Session& session, const SessionMetrics& m, const std::string& scenario,
                    bool fast, const std::string& dir) {
  // The inputs (for replay) and the metrics, side by side, each whole or not at all and each
  // tried whatever became of the others (a full disk, issue 25): every failure is said.
  std::vector<Diagnostic> failed;
  auto keep = [&](Status s) {
    for (Diagnostic& d : std::move(s).diagnostics()) failed.push_back(std::move(d));
  };
  keep(session.write_recording(dir));
  // No folder: nothing else can be written there either, and that is said once.
  std::error_code missing;
  if (!std::filesystem::is_directory(dir, missing)) return failed;
  const std::filesystem::path metrics = std::filesystem::path(dir) / "metrics.json";
  nlohmann::ordered_json j = metrics_to_json(m, scenario, fast);
  // A scenario changed on disk while the session ran is said in the metrics it leaves (`run`
  // says it in m.warnings already).
  if (const std::optional<std::string> changed = scenario_change_warning(
          session.model().scenario_file(), session.model().scenario_digest());
      changed && std::find(m.warnings.begin(), m.warnings.end(), *changed) == m.warnings.end()) {
    j["warnings"].push_back(*changed);
  }
  j["series"] = series_to_json(m.series);
  keep(write_file_whole(
      metrics, j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n",
      "the metrics"));
  // What it was run with, for `report` to replay it (session_replay.h): written when the session
  // started (`run --record`), and then never again; else now (the window's saved sessions), with
  // the digest of the scenario as it was loaded.
  std::error_code ec;
  if (!std::filesystem::exists(
          std::filesystem::symlink_status(std::filesystem::path(dir) / "session.json", ec))) {
    keep(write_session_record(
        dir, session_record_json(session.model().scenario_file(), session.model().scenario_digest(),
                                 session.model().settings())));
  }
  return failed;
}

}  // namespace lap::sim
