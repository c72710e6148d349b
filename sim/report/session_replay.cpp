#include "sim/report/session_replay.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>

#include "core/bounded_file.h"
#include "core/whole_file.h"
#include "hardware/device_spec.h"
#include "hardware/replay_device.h"
#include "sim/report/recorded_tunings.h"
#include "sim/report/recording_reader.h"
#include "sim/report/touch_departure.h"
#include "sim/setup/device_factory.h"
#include "sim/setup/gltf_references.h"
#include "sim/setup/json_lines.h"
#include "sim/setup/scenario_loader.h"
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

/// session.json's text, for naming a field's line: where the field's key is, or where the
/// object starts for a field that is missing.
struct RecordText {
  std::string file;
  JsonLines lines;
  int object_line = 1;
  [[nodiscard]] Diagnostic problem(const std::string& field, const std::string& what) const {
    return file_diagnostic(file, lines.line(field, object_line), field, what);
  }
};

/// A number field, finite, positive and at most `most`.
Result<double> positive_field(const nlohmann::json& j, const RecordText& at, const char* field,
                              double most) {
  const auto it = j.find(field);
  if (it == j.end() || !it->is_number()) return at.problem(field, "expected a number");
  const double v = it->get<double>();
  if (!std::isfinite(v) || v <= 0.0 || v > most) {
    char range[64];
    std::snprintf(range, sizeof(range), "%g", most);
    return at.problem(field, std::string("expected a number above 0 and at most ") + range);
  }
  return v;
}

Result<std::string> string_field(const nlohmann::json& j, const RecordText& at, const char* field) {
  const auto it = j.find(field);
  if (it == j.end() || !it->is_string()) return at.problem(field, "expected a string");
  return it->get<std::string>();
}

}  // namespace

std::string session_record_json(const std::filesystem::path& scenario, uint64_t digest,
                                const RuntimeSettings& settings) {
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(scenario, ec);
  nlohmann::ordered_json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["scenario"] = (ec ? scenario : absolute).lexically_normal().string();
  j["scenario_digest"] = hex64(digest);
  j["mode"] = settings.fast ? "fast" : "realtime";
  j["duration_s"] = settings.duration_s;
  j["haptic_rate_hz"] = settings.haptic_rate_hz;
  j["model_rate_hz"] = settings.model_rate_hz;
  j["dominant_hand"] = settings.dominant_tool == 0 ? "left" : "right";
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

Result<std::string> session_record_json(const std::filesystem::path& scenario,
                                        const RuntimeSettings& settings) {
  const Result<uint64_t> digest = file_digest(scenario, kMaxScenarioFileBytes);
  if (!digest.ok()) return digest.diagnostics();
  return session_record_json(scenario, digest.value(), settings);
}

Status write_session_record(const std::filesystem::path& dir, const std::string& text) {
  // Whole or not at all, and never over a record already there.
  return write_file_whole(dir / "session.json", text, "a session's record", IfTaken::kRefuse);
}

std::optional<std::string> scenario_change_warning(const std::filesystem::path& scenario,
                                                   uint64_t digest) {
  const Result<uint64_t> now = file_digest(scenario, kMaxScenarioFileBytes);
  if (now.ok() && now.value() == digest) return std::nullopt;
  return "the scenario " + scenario.string() + " changed on disk while the session ran (" +
         (now.ok() ? "digest " + hex64(digest) + " when loaded, " + hex64(now.value()) + " now"
                   : now.message()) +
         "): the session ran the scenario as it was loaded, and a replay uses the file as it is "
         "then";
}

Result<SessionRecord> read_session_record(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / "session.json";
  const std::string file = path.string();
  const Result<std::string> read =
      read_bounded_file(path, kMaxRecordBytes, "a session's record (session.json)");
  if (!read.ok()) return read.diagnostics();
  const std::string& text = read.value();
  RecordText at{file, JsonLines::scan(text, 1), 1};
  const size_t first = text.find_first_not_of(" \t\r\n");
  at.object_line += static_cast<int>(std::count(
      text.begin(),
      text.begin() + static_cast<ptrdiff_t>(first == std::string::npos ? text.size() : first),
      '\n'));
  if (!at.lines.parsed()) {
    return file_diagnostic(file, at.lines.error_line(), "",
                           "expected a JSON object (a session's record): " + at.lines.error());
  }
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    return file_diagnostic(
        file, at.object_line, "",
        "expected a JSON object (a session's record), got " +
            (j.is_discarded() ? std::string("something else") : std::string(j.type_name())));
  }
  if (!j.contains("format") || j["format"] != kFormat) {
    return at.problem("format", std::string("expected \"") + kFormat + "\"");
  }
  if (!j.contains("version") || !j["version"].is_number_integer() || j["version"] != kVersion) {
    return at.problem("version", "expected " + std::to_string(kVersion));
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
  take(string_field(j, at, "scenario"), &scenario);
  take(string_field(j, at, "scenario_digest"), &digest);
  take(string_field(j, at, "mode"), &mode);
  take(string_field(j, at, "dominant_hand"), &hand);
  take(positive_field(j, at, "duration_s", kMaxDurationS), &r.settings.duration_s);
  take(positive_field(j, at, "haptic_rate_hz", kMaxRateHz), &r.settings.haptic_rate_hz);
  take(positive_field(j, at, "model_rate_hz", kMaxRateHz), &r.settings.model_rate_hz);
  if (!problems.empty()) return problems;
  if (r.settings.model_rate_hz > r.settings.haptic_rate_hz) {
    return at.problem("model_rate_hz", "expected at most haptic_rate_hz");
  }
  if (mode != "fast" && mode != "realtime") {
    return at.problem("mode", "expected \"fast\" or \"realtime\", got " + quote_excerpt(mode));
  }
  if (hand != "left" && hand != "right") {
    return at.problem("dominant_hand",
                      "expected \"left\" or \"right\", got " + quote_excerpt(hand));
  }
  char* end = nullptr;
  r.scenario_digest = std::strtoull(digest.c_str(), &end, 16);
  if (digest.size() != 16 || end != digest.c_str() + digest.size() ||
      digest.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) {
    return at.problem("scenario_digest", "expected 16 hexadecimal digits");
  }
  if (scenario.find('\0') != std::string::npos) {
    return at.problem("scenario", "expected a path, got a string holding a NUL byte");
  }
  r.scenario_line = at.lines.line("scenario", at.object_line);
  // A relative path is the recording folder's: a folder that carries its scenario can move.
  r.scenario = std::filesystem::path(scenario).is_absolute() ? std::filesystem::path(scenario)
                                                             : (dir / scenario).lexically_normal();
  r.settings.fast = mode == "fast";
  r.settings.dominant_tool = hand == "left" ? 0 : 1;
  return r;
}

std::vector<std::filesystem::path> replay_scenario_folders(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> folders = {dir};
  for (const std::filesystem::path& f : shipped_scenario_folders()) folders.push_back(f);
  return folders;
}

Result<ReplayedSession> replay_session(const std::filesystem::path& dir,
                                       const ReplaySettings& settings) {
  return replay_session(dir, settings, {});
}

Result<ReplayScenario> load_replay_scenario(const std::filesystem::path& dir,
                                            const ReplaySettings& settings) {
  Result<SessionRecord> record = read_session_record(dir);
  if (!record.ok()) return record.diagnostics();
  ReplayScenario loaded;
  ReplayedSession& out = loaded.session;
  out.record = std::move(record).value();
  ScenarioLoadSettings load;
  load.allowed_paths = settings.allowed_paths;
  if (settings.scenario) {
    // The reviewer named the scenario: the recorded path is not followed.
    if (std::filesystem::absolute(*settings.scenario).lexically_normal() !=
        out.record.scenario.lexically_normal()) {
      out.notes.push_back("replayed with " + settings.scenario->string() +
                          " (--scenario) instead of the scenario the session names, " +
                          out.record.scenario.string());
    }
    out.record.scenario = *settings.scenario;
  } else {
    // The recording is untrusted: the scenario it names must be where recordings' scenarios are,
    // or where the reviewer allows (issue 25: "scenario": "/etc/passwd" had the report read
    // that file and print it whole in its error).
    const auto inside_any = [&](const std::vector<std::filesystem::path>& folders) {
      return std::any_of(folders.begin(), folders.end(), [&](const std::filesystem::path& f) {
        return inside_folder(f, out.record.scenario);
      });
    };
    const bool trusted =
        inside_any(shipped_scenario_folders()) || inside_any(settings.allowed_paths);
    if (!trusted && inside_folder(dir, out.record.scenario)) {
      // A scenario that came with the recording: its own allowed_paths may not reach beyond its
      // folder and the reviewer's.
      load.confine_allowed_paths = settings.allowed_paths;
    } else if (!trusted) {
      // (The folders are replay_scenario_folders(dir); README.md names them.)
      return file_diagnostic((dir / "session.json").string(), out.record.scenario_line, "scenario",
                             quote_excerpt(out.record.scenario.string(), 200) +
                                 " is outside the recording's folder and the shipped scenarios' "
                                 "folders; to replay it from there, give --scenario FILE or "
                                 "--allow-path DIR");
    }
  }
  SceneLoadResult scene = load_scene_file(out.record.scenario, load);
  if (!scene.ok()) return scene.diagnostics();
  // Compared on the very bytes loaded.
  if (scene.value().scenario.digest != out.record.scenario_digest) {
    out.notes.insert(out.notes.begin(),
                     out.record.scenario.string() +
                         " has changed since the session was recorded: the replay runs the "
                         "scenario as it is now, and its figures may differ from the session's");
  }
  out.scenario_name = scene.value().scenario.name;
  out.task = scene.value().scenario.task;
  loaded.scene = std::move(scene).value();
  return loaded;
}

Result<ReplayedSession> replay_session(
    const std::filesystem::path& dir, const ReplaySettings& settings,
    const std::function<void(Session& session, const Scene& scene)>& prepare) {
  Result<ReplayScenario> loaded = load_replay_scenario(dir, settings);
  if (!loaded.ok()) return loaded.diagnostics();
  ReplayedSession out = std::move(loaded.value().session);
  const Scene& scene_loaded = loaded.value().scene;
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices;
  std::error_code ec;
  const std::filesystem::path lrec = dir / "session.lrec";
  const bool lapdevs = std::filesystem::is_regular_file(dir / "left.lapdev", ec) &&
                       std::filesystem::is_regular_file(dir / "right.lapdev", ec);
  int64_t recorded = -1;  // ticks to replay, when known before the replay devices read them
  // Which snapshot each loop read from the other, as the session ran (LAPREC02): the replay
  // takes the same ones (lockstep_order.h).
  std::optional<std::pair<std::vector<TickLog>, std::vector<StepLog>>> reads;
  // What each tool touched and held live (LAPREC03), to check the replay against.
  std::vector<std::array<ToolTouch, 2>> touches;
  // An author's live tunings (LAPREC04), set again at the ticks that took them.
  std::vector<TuningLog> tunings;
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
      if (rec.value().version >= 2) {
        const std::vector<TickLog>& ticks = rec.value().ticks;
        for (std::string& note :
             recorded_tuning_notes(ticks, rec.value().tunings, rec.value().version,
                                   static_cast<int32_t>(scene_loaded.organs.size()),
                                   out.record.settings.haptic_rate_hz)) {
          out.notes.push_back(std::move(note));
        }
        if (rec.value().version >= 3) {
          touches.reserve(ticks.size());
          for (const TickLog& t : ticks) touches.push_back(t.touch);
        }
        tunings = std::move(rec.value().tunings);
        reads.emplace(std::move(rec.value().ticks), std::move(rec.value().steps));
      }
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
      auto device = make_device(spec, scene_loaded, side);
      if (!device.ok()) return device.diagnostics();
      devices[static_cast<size_t>(side)] = std::move(device).value();
    }
  }
  if (!out.record.settings.fast && !reads) {
    out.notes.push_back(
        "recorded in real time without the loops' reads (a LAPREC01 recording, or the .lapdev "
        "files): the replay steps the loops in plain lockstep, so its figures may differ from "
        "the session's");
  }
  RuntimeSettings rs = out.record.settings;
  rs.fast = true;
  // As long as what was recorded (a window's session is given a day, and stops much sooner):
  // the replay reserves its recording space for its duration.
  if (recorded > 0) {
    rs.duration_s = std::min(rs.duration_s, static_cast<double>(recorded + 2) / rs.haptic_rate_hz);
  }
  auto session = Session::create(scene_loaded, std::move(devices), rs);
  if (!session.ok()) return session.diagnostics();
  if (reads) {
    session.value()->replay_in_lockstep(std::move(reads->first), std::move(reads->second),
                                        std::move(tunings));
  }
  if (prepare) prepare(*session.value(), scene_loaded);
  out.metrics = session.value()->run();
  const std::optional<std::string> departure = touch_departure(
      touches, session.value()->tick_log(), out.metrics.organ_names, rs.haptic_rate_hz);
  if (departure) out.notes.push_back(*departure);
  if (!session.value()->lockstep_problem().empty()) {
    out.notes.push_back(session.value()->lockstep_problem());
  } else if (session.value()->lockstep_steps_not_run() > 0 && !out.interrupted) {
    out.notes.push_back(std::to_string(session.value()->lockstep_steps_not_run()) +
                        " recorded modelling steps read a tick after the recording's last: "
                        "they were not replayed (the recording is damaged)");
  }
  return out;
}

}  // namespace lap::sim
