#include "sim/session_report.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace lap::sim {

std::string json_quote(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string metrics_json(const SessionMetrics& m, const std::string& scenario, bool fast) {
  char hash[32];
  std::snprintf(hash, sizeof(hash), "%016llx", static_cast<unsigned long long>(m.state_hash));
  std::string out = "{\n";
  out += "  \"scenario\": " + json_quote(scenario) + ",\n";
  out += "  \"mode\": " + std::string(fast ? "\"fast\"" : "\"realtime\"") + ",\n";
  out += "  \"haptic\": " + m.haptic.to_json() + ",\n";
  out += "  \"model\": " + m.model.to_json() + ",\n";
  out += "  \"paused\": " + std::string(m.paused ? "true" : "false") + ",\n";
  out += "  \"watchdog_events\": [";
  for (size_t i = 0; i < m.events.size(); ++i) {
    const auto& e = m.events[i];
    out += std::string(i > 0 ? ", " : "") + "{\"tick\": " + std::to_string(e.tick) +
           ", \"tool\": " +
           json_quote(e.tool == 0   ? "left"
                      : e.tool == 1 ? "right"
                                    : "haptic loop") +
           ", \"reason\": " + json_quote(std::string(to_string(e.reason))) + "}";
  }
  out += "],\n";
  out += "  \"devices\": {\"left\": " +
         json_quote(std::string(hardware::to_string(m.device_status[0]))) +
         ", \"right\": " + json_quote(std::string(hardware::to_string(m.device_status[1]))) +
         "},\n";
  out += "  \"recorded_ticks\": " + std::to_string(m.recorded_ticks) + ",\n";
  out += "  \"dropped_samples\": " + std::to_string(m.dropped_samples) + ",\n";
  char force[64];
  std::snprintf(force, sizeof(force), "%.6g", m.max_force_sent_n);
  out += "  \"max_force_sent_n\": " + std::string(force) + ",\n";
  out += "  \"warnings\": [";
  for (size_t i = 0; i < m.warnings.size(); ++i) {
    out += std::string(i > 0 ? ", " : "") + json_quote(m.warnings[i]);
  }
  out += "],\n";
  out += "  \"state_hash\": \"" + std::string(hash) + "\"\n}\n";
  return out;
}

bool save_session(const Session& session, const SessionMetrics& m, const std::string& scenario,
                  bool fast, const std::string& dir, std::string* error) {
  // The inputs (for replay) and the metrics, side by side.
  if (!session.write_recording(dir, error)) return false;
  const std::filesystem::path metrics = std::filesystem::path(dir) / "metrics.json";
  std::ofstream f(metrics);
  f << metrics_json(m, scenario, fast);
  f.flush();
  if (!f) {
    if (error != nullptr) *error = metrics.string() + ": cannot write the metrics";
    return false;
  }
  return true;
}

}  // namespace lap::sim
