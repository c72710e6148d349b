#include "sim/report/session_replay.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "hardware/device_spec.h"
#include "hardware/replay_device.h"
#include "sim/report/recording_reader.h"
#include "sim/setup/device_factory.h"
#include "sim/setup/scene.h"

namespace lap::sim {

namespace {

constexpr const char* kFormat = "laptrainer-session";
constexpr int kVersion = 1;
/// A session.json is a few hundred bytes: anything far larger is not one.
constexpr std::uintmax_t kMaxRecordBytes = std::uintmax_t{64} * 1024;

std::string hex64(uint64_t v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%016" PRIx64, v);
  return text;
}

/// What a session's record may say: a day at most, a haptic loop of 10 kHz at most.
constexpr double kMaxDurationS = 86400.0;
constexpr double kMaxRateHz = 10000.0;

/// A number field, finite, positive and at most `most`.
Result<double> positive_field(const nlohmann::json& j, const std::string& file, const char* field,
                              double most) {
  const auto it = j.find(field);
  if (it == j.end() || !it->is_number()) {
    return file_diagnostic(file, 0, field, "expected a number");
  }
  const double v = it->get<double>();
  if (!std::isfinite(v) || v <= 0.0 || v > most) {
    char range[64];
    std::snprintf(range, sizeof(range), "%g", most);
    return file_diagnostic(file, 0, field,
                           std::string("expected a number above 0 and at most ") + range);
  }
  return v;
}

Result<std::string> string_field(const nlohmann::json& j, const std::string& file,
                                 const char* field) {
  const auto it = j.find(field);
  if (it == j.end() || !it->is_string()) {
    return file_diagnostic(file, 0, field, "expected a string");
  }
  return it->get<std::string>();
}

}  // namespace

Result<uint64_t> file_digest(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    return file_diagnostic(file.string(), 0, "", "expected a regular file");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) return file_diagnostic(file.string(), 0, "", "cannot read the file");
  uint64_t h = 1469598103934665603ULL;
  char buf[65536];
  while (in.read(buf, sizeof(buf)) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      h = (h ^ static_cast<unsigned char>(buf[i])) * 1099511628211ULL;
    }
  }
  return h;
}

Result<std::string> session_record_json(const std::filesystem::path& scenario,
                                        const RuntimeSettings& settings) {
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(scenario, ec);
  const Result<uint64_t> digest = file_digest(scenario);
  if (!digest.ok()) return digest.diagnostics();
  nlohmann::ordered_json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["scenario"] = (ec ? scenario : absolute).lexically_normal().string();
  j["scenario_digest"] = hex64(digest.value());
  j["mode"] = settings.fast ? "fast" : "realtime";
  j["duration_s"] = settings.duration_s;
  j["haptic_rate_hz"] = settings.haptic_rate_hz;
  j["model_rate_hz"] = settings.model_rate_hz;
  j["dominant_hand"] = settings.dominant_tool == 0 ? "left" : "right";
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

Status write_session_record(const std::filesystem::path& dir, const std::filesystem::path& scenario,
                            const RuntimeSettings& settings) {
  const Result<std::string> text = session_record_json(scenario, settings);
  if (!text.ok()) return text.diagnostics();
  const std::filesystem::path file = dir / "session.json";
  std::ofstream f(file);
  f << text.value();
  f.flush();
  if (!f) return file_diagnostic(file.string(), 0, "", "cannot write the session's record");
  return {};
}

Result<SessionRecord> read_session_record(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / "session.json";
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return file_diagnostic(file, 0, "", "missing or not a regular file (a session's record)");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec)
    return file_diagnostic(file, 0, "", "cannot read the session's record (" + ec.message() + ")");
  if (size > kMaxRecordBytes) {
    return file_diagnostic(file, 0, "",
                           "is " + std::to_string(size) + " bytes; a session's record is at most " +
                               std::to_string(kMaxRecordBytes));
  }
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    return file_diagnostic(file, 0, "", "expected a JSON object (a session's record)");
  }
  if (j.value("format", std::string()) != kFormat) {
    return file_diagnostic(file, 0, "format", std::string("expected \"") + kFormat + "\"");
  }
  if (!j.contains("version") || !j["version"].is_number_integer() || j["version"] != kVersion) {
    return file_diagnostic(file, 0, "version", "expected " + std::to_string(kVersion));
  }
  SessionRecord r;
  std::vector<Diagnostic> problems;
  auto take = [&](auto result, auto* out) {
    if (result.ok()) {
      *out = result.value();
    } else {
      for (const Diagnostic& d : result.diagnostics()) problems.push_back(d);
    }
  };
  std::string scenario, digest, mode, hand;
  take(string_field(j, file, "scenario"), &scenario);
  take(string_field(j, file, "scenario_digest"), &digest);
  take(string_field(j, file, "mode"), &mode);
  take(string_field(j, file, "dominant_hand"), &hand);
  take(positive_field(j, file, "duration_s", kMaxDurationS), &r.settings.duration_s);
  take(positive_field(j, file, "haptic_rate_hz", kMaxRateHz), &r.settings.haptic_rate_hz);
  take(positive_field(j, file, "model_rate_hz", kMaxRateHz), &r.settings.model_rate_hz);
  if (!problems.empty()) return problems;
  if (r.settings.model_rate_hz > r.settings.haptic_rate_hz) {
    return file_diagnostic(file, 0, "model_rate_hz", "expected at most haptic_rate_hz");
  }
  if (mode != "fast" && mode != "realtime") {
    return file_diagnostic(file, 0, "mode",
                           "expected \"fast\" or \"realtime\", got \"" + mode + "\"");
  }
  if (hand != "left" && hand != "right") {
    return file_diagnostic(file, 0, "dominant_hand",
                           "expected \"left\" or \"right\", got \"" + hand + "\"");
  }
  char* end = nullptr;
  r.scenario_digest = std::strtoull(digest.c_str(), &end, 16);
  if (digest.size() != 16 || end != digest.c_str() + digest.size()) {
    return file_diagnostic(file, 0, "scenario_digest", "expected 16 hexadecimal digits");
  }
  r.scenario = scenario;
  r.settings.fast = mode == "fast";
  r.settings.dominant_tool = hand == "left" ? 0 : 1;
  return r;
}

Result<ReplayedSession> replay_session(const std::filesystem::path& dir) {
  return replay_session(dir, {});
}

Result<ReplayedSession> replay_session(
    const std::filesystem::path& dir,
    const std::function<void(Session& session, const Scene& scene)>& prepare) {
  Result<SessionRecord> record = read_session_record(dir);
  if (!record.ok()) return record.diagnostics();
  ReplayedSession out;
  out.record = std::move(record).value();
  const Result<uint64_t> digest = file_digest(out.record.scenario);
  if (!digest.ok()) {
    return file_diagnostic((dir / "session.json").string(), 0, "scenario",
                           "the scenario it names cannot be read: " + digest.message());
  }
  if (digest.value() != out.record.scenario_digest) {
    out.notes.push_back(out.record.scenario.string() +
                        " has changed since the session was recorded: the replay runs the "
                        "scenario as it is now, and its figures may differ from the session's");
  }
  if (!out.record.settings.fast) {
    out.notes.push_back(
        "recorded in real time: the replay steps the loops in lockstep, so the watchdog's "
        "late-tick pauses of the live session are not in it and its figures may differ");
  }
  const SceneLoadResult scene = load_scene_file(out.record.scenario);
  if (!scene.ok()) return scene.diagnostics();
  out.scenario_name = scene.value().scenario.name;
  out.task = scene.value().scenario.task;
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices;
  std::error_code ec;
  const std::filesystem::path lrec = dir / "session.lrec";
  const bool lapdevs = std::filesystem::is_regular_file(dir / "left.lapdev", ec) &&
                       std::filesystem::is_regular_file(dir / "right.lapdev", ec);
  int64_t recorded = -1;  // ticks to replay, when known before the replay devices read them
  if (std::filesystem::exists(std::filesystem::symlink_status(lrec, ec))) {
    // The streamed recording: what a crash left, too.
    Result<RecordedSession> rec = read_session_recording(lrec);
    if (!rec.ok()) return rec.diagnostics();
    out.streamed = true;
    out.interrupted = rec.value().interrupted;
    out.recorded_ticks = static_cast<int64_t>(rec.value().ticks.size());
    out.recording_problems = rec.value().problems;
    if (out.recorded_ticks == 0 && !lapdevs) {
      std::string why = "no whole tick could be read";
      for (const std::string& p : out.recording_problems) why += "; " + p;
      return file_diagnostic(lrec.string(), 0, "", why);
    }
    if (out.recorded_ticks == 0) {
      out.notes.push_back(lrec.string() + " holds no whole tick: the session's left.lapdev and " +
                          "right.lapdev (written at its end) are replayed instead");
      out.streamed = false;
    } else {
      recorded = out.recorded_ticks;
      for (size_t side = 0; side < 2; ++side) {
        hardware::DeviceRecording r = std::move(rec.value().devices[side]);
        r.period_s = 1.0 / out.record.settings.haptic_rate_hz;
        devices[side] = std::make_unique<hardware::ReplayDevice>(
            std::move(r), side == 0 ? "left replay" : "right replay");
      }
    }
  }
  if (!devices[0]) {
    for (int side = 0; side < 2; ++side) {
      hardware::DeviceSpec spec;
      spec.kind = hardware::DeviceKind::kReplay;
      spec.argument = (dir / (side == 0 ? "left.lapdev" : "right.lapdev")).string();
      auto device = make_device(spec, scene.value(), side);
      if (!device.ok()) return device.diagnostics();
      devices[static_cast<size_t>(side)] = std::move(device).value();
    }
  }
  RuntimeSettings rs = out.record.settings;
  rs.fast = true;
  // As long as what was recorded (a window's session is given a day, and stops much sooner):
  // the replay reserves its recording space for its duration.
  if (recorded > 0) {
    rs.duration_s = std::min(rs.duration_s, static_cast<double>(recorded + 2) / rs.haptic_rate_hz);
  }
  auto session = Session::create(scene.value(), std::move(devices), rs);
  if (!session.ok()) return session.diagnostics();
  if (prepare) prepare(*session.value(), scene.value());
  out.metrics = session.value()->run();
  return out;
}

}  // namespace lap::sim
