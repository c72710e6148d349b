#include "sim/report/session_report.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

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

nlohmann::ordered_json metrics_to_json(const SessionMetrics& m, const std::string& scenario,
                                       bool fast) {
  char hash[32];
  std::snprintf(hash, sizeof(hash), "%016llx", static_cast<unsigned long long>(m.state_hash));
  nlohmann::ordered_json j;
  j["scenario"] = scenario;
  j["mode"] = fast ? "fast" : "realtime";
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
  // The inputs (for replay) and the metrics, side by side.
  if (Status written = session.write_recording(dir); !written.ok()) return written;
  const std::filesystem::path metrics = std::filesystem::path(dir) / "metrics.json";
  std::ofstream f(metrics);
  f << metrics_json(m, scenario, fast);
  f.flush();
  if (!f) return Diagnostic{metrics.string(), 0, "", "cannot write the metrics"};
  return {};
}

}  // namespace lap::sim
