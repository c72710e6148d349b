#include "sim/report/recording_reader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "core/bounded_file.h"
#include "sim/runtime/tissue_world.h"

namespace lap::sim {

namespace {

/// Three hours of ticks at 1 kHz (400 bytes each: 4.3 GB), steps at 200 Hz (16 bytes each) and
/// frames at 10 Hz (LAPREC05: up to 1.7 GB with a duct of 1 000 vertices deformed throughout,
/// 16 bytes each): what a session may leave.
constexpr std::uintmax_t kMaxRecordingBytes = std::uintmax_t{7} << 30;

template <typename T>
T get(const std::string& bytes, size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof(T));
  return v;
}

/// One tool's touch at `p` (a LAPREC03 tick record's): what makes it impossible, or empty.
std::string_view decode_touch(const std::string& b, size_t p, ToolTouch* t) {
  const auto flags = static_cast<uint8_t>(b[p]);
  t->catheter_held = (flags & 1U) != 0;
  t->duct_held = (flags & 2U) != 0;
  t->organs = static_cast<uint8_t>(b[p + 1]);
  t->contacts = static_cast<uint8_t>(b[p + 2]);
  if (flags > 3U) return "unknown grasp flags (expected 0 to 3)";
  if (t->contacts > ToolModelInput::kMaxContacts || t->organs > t->contacts) {
    return "more contacts than a tool has (12), or more organs touched than contacts";
  }
  int32_t listed_contacts = 0;
  for (size_t k = 0; k < ToolTouch::kListedOrgans; ++k) {
    const size_t at = p + 4 + 8 * k;
    t->organ[k] = get<uint16_t>(b, at);
    t->organ_contacts[k] = get<uint16_t>(b, at + 2);
    t->force_n[k] = get<float>(b, at + 4);
    if (!std::isfinite(t->force_n[k]) || t->force_n[k] < 0.0F) {
      return "a push on an organ that is not finite, or negative";
    }
    if (k < t->listed() ? t->organ_contacts[k] == 0 : t->organ_contacts[k] != 0) {
      return "a listed organ without contacts, or contacts on an unlisted one";
    }
    listed_contacts += t->organ_contacts[k];
  }
  if (listed_contacts > t->contacts) return "more contacts on its organs than the tool had";
  return {};
}

/// Reads one tick record at `at` (a LAPREC0`version` one): what is wrong with it (a value not
/// finite, a status unknown, a read impossible, a touch that cannot be), or empty.
std::string decode_tick(const std::string& b, size_t at, int version,
                        hardware::RecordedSample* left, hardware::RecordedSample* right,
                        TickLog* log) {
  log->tick = get<int64_t>(b, at);
  log->wall_ns = get<int64_t>(b, at + 8);
  size_t p = at + 16;
  const auto d = [&] {
    const double v = get<double>(b, p);
    p += 8;
    return v;
  };
  static constexpr auto kLastStatus = static_cast<uint32_t>(hardware::DeviceStatus::kError);
  static constexpr const char* kStatuses =
      " (expected 0 ok, 1 finished, 2 disconnected or 3 error)";
  constexpr const char* kNotFinite = "a value that is not finite";
  for (size_t i = 0; i < 2; ++i) {
    const char* tool = i == 0 ? "the left tool's " : "the right tool's ";
    hardware::RecordedSample& r = i == 0 ? *left : *right;
    r.tick = log->tick;
    hardware::DeviceSample& s = r.sample;
    s.time_s = d();
    s.position_W = {d(), d(), d()};
    const double w = d(), x = d(), y = d(), z = d();
    s.orientation_W = Eigen::Quaterniond(w, x, y, z);
    s.velocity_W = {d(), d(), d()};
    s.gripper_angle_rad = d();
    s.buttons = get<uint32_t>(b, p);
    const auto status = get<uint32_t>(b, p + 4);
    p += 8;
    if (status > kLastStatus) {
      return std::string(tool) + "device status " + std::to_string(status) + kStatuses;
    }
    r.status = static_cast<hardware::DeviceStatus>(status);
    log->force_W[i] = {d(), d(), d()};
    log->squeeze_n[i] = d();
    if (!s.position_W.allFinite() || !s.orientation_W.coeffs().allFinite() ||
        !s.velocity_W.allFinite() || !std::isfinite(s.gripper_angle_rad) ||
        !std::isfinite(s.time_s) || !log->force_W[i].allFinite()) {
      return std::string(tool) + "sample or force holds " + kNotFinite;
    }
  }
  log->gain = d();
  if (!std::isfinite(log->gain)) return std::string("the watchdog's gain is ") + kNotFinite;
  log->late = b[p] != 0;
  log->paused = b[p + 1] != 0;
  if (version == 1) return {};
  log->resumed = b[p + 2] != 0;
  log->after_hold = b[p + 3] != 0;
  log->tuned = b[p + 4] != 0;
  for (size_t i = 0; i < 2; ++i) {
    const auto status = static_cast<uint8_t>(b[p + 5 + i]);
    if (status > kLastStatus) {
      return std::string(i == 0 ? "the left" : "the right") + " device's write status " +
             std::to_string(status) + kStatuses;
    }
    log->write_status[i] = static_cast<hardware::DeviceStatus>(status);
  }
  p += 8;
  log->lateness_s = d();
  if (!std::isfinite(log->lateness_s)) return std::string("its lateness is ") + kNotFinite;
  log->model_steps_read = get<int64_t>(b, p);
  log->surface_steps_read = get<int64_t>(b, p + 8);
  p += 16;
  if (log->model_steps_read < 0 || log->surface_steps_read < 0) {
    return "it reads a negative modelling step";
  }
  if (version == 2) return {};
  for (size_t i = 0; i < 2; ++i) {
    const std::string_view why = decode_touch(b, p, &log->touch[i]);
    if (!why.empty())
      return (i == 0 ? "the left tool's touch: " : "the right tool's touch: ") + std::string(why);
    p += kToolTouchBytes;
  }
  return {};
}

class Reader {
 public:
  Reader(const std::filesystem::path& file, std::string bytes)
      : file_(file.string()), b_(std::move(bytes)) {}

  Result<RecordedSession> read() {
    const size_t head = header();
    if (head == 0) return file_diagnostic(file_, 0, "", header_problem_);
    for (size_t at = head; at < b_.size();) at = chunk(at);
    if (!s_.end_json.empty()) truncated();
    // A session reserves room for this many steps and no more (a replay runs each that read a
    // tick it has; those after, what a cut leaves, are never run).
    const auto runnable = static_cast<size_t>(
        std::partition_point(s_.steps.begin(), s_.steps.end(),
                             [&](const StepLog& k) {
                               return k.haptic_tick_read < static_cast<int64_t>(s_.ticks.size());
                             }) -
        s_.steps.begin());
    if (runnable > s_.ticks.size() + kStepsBeyondTicks) {
      problem(b_.size(),
              std::to_string(runnable) + " modelling steps for " + std::to_string(s_.ticks.size()) +
                  " ticks: more than a session " + "records; those after the first " +
                  std::to_string(s_.ticks.size() + kStepsBeyondTicks) + " are not replayed");
      s_.steps.resize(s_.ticks.size() + kStepsBeyondTicks);
    }
    return std::move(s_);
  }

 private:
  size_t header() {
    if (b_.size() >= 16 && b_.compare(0, 8, kRecordingMagicV1) == 0) {
      s_.version = 1;
      record_bytes_ = kTickRecordBytesV1;
    } else if (b_.size() >= 16 && b_.compare(0, 8, kRecordingMagicV2) == 0) {
      s_.version = 2;
      record_bytes_ = kTickRecordBytesV2;
    } else if (b_.size() >= 16 && b_.compare(0, 8, kRecordingMagicV3) == 0) {
      s_.version = 3;
    } else if (b_.size() >= 16 && b_.compare(0, 8, kRecordingMagicV4) == 0) {
      s_.version = 4;
    } else if (b_.size() < 16 || b_.compare(0, 8, kRecordingMagic) != 0) {
      header_problem_ =
          "at byte 0: not a laptrainer session recording (expected it to start with LAPREC05, "
          "LAPREC04, LAPREC03, LAPREC02 or LAPREC01)";
      return 0;
    }
    const auto n = get<uint32_t>(b_, 8);
    if (n > kMaxRecordingHeaderBytes || 12 + static_cast<size_t>(n) + 4 > b_.size()) {
      header_problem_ =
          "at byte 8: its header's length (" + std::to_string(n) + " bytes) runs past the file";
      return 0;
    }
    s_.header_json = b_.substr(12, n);
    if (crc32(s_.header_json.data(), n) != get<uint32_t>(b_, 12 + n)) {
      header_problem_ = "at byte " + std::to_string(12 + static_cast<size_t>(n)) +
                        ": its header's checksum does not match (the file is damaged)";
      return 0;
    }
    return 12 + static_cast<size_t>(n) + 4;
  }

  // One chunk at `at`; returns where the next one starts (the next mark after damage).
  size_t chunk(size_t at) {
    if (b_.size() - at < kChunkHeadBytes + 4) {
      problem(at, "the last " + std::to_string(b_.size() - at) +
                      " bytes are an incomplete chunk (the session was cut off)");
      return b_.size();
    }
    if (get<uint32_t>(b_, at) != kChunkMagic) return skip_to_next_mark(at, "not a chunk's mark");
    const auto kind = get<uint32_t>(b_, at + 4);
    const auto bytes = get<uint32_t>(b_, at + 8);
    const auto count = get<uint32_t>(b_, at + 12);
    const auto first = get<int64_t>(b_, at + 16);
    const size_t end = at + kChunkHeadBytes + static_cast<size_t>(bytes) + 4;
    if (bytes > kMaxChunkPayloadBytes) return skip_to_next_mark(at, "a chunk of impossible length");
    if (end > b_.size()) {
      if (next_mark(at + 4) == std::string::npos) {
        problem(at, "the last chunk is incomplete (the session was cut off)");
        return b_.size();
      }
      return skip_to_next_mark(at, "a chunk whose length runs past the file");
    }
    if (!chunk_intact(b_.data() + at, bytes)) {
      return skip_to_next_mark(at, "a chunk whose checksum does not match (" +
                                       std::to_string(count) +
                                       (kind == kChunkSteps     ? " modelling steps from step "
                                        : kind == kChunkTunings ? " surface tunings from tuning "
                                        : kind == kChunkFrames  ? " frames from tick "
                                                                : " ticks from tick ") +
                                       std::to_string(first) + " if its head is right)");
    }
    const size_t payload = at + kChunkHeadBytes;
    if (!s_.interrupted) problem(at, "a chunk after the end chunk");
    if (kind == kChunkTicks) {
      ticks(at, payload, bytes, count);
    } else if (kind == kChunkEvents) {
      s_.events_json = b_.substr(payload, bytes);
    } else if (kind == kChunkSteps && s_.version >= 2) {
      steps(at, payload, bytes, count, first);
    } else if (kind == kChunkTunings && s_.version >= 4) {
      tunings(at, payload, bytes, count, first);
    } else if (kind == kChunkFrames && s_.version >= 5) {
      s_.frames_read += count;  // for seeking only (recorded_frames.h): the replay needs none
    } else if (kind == kChunkEnd) {
      s_.end_json = b_.substr(payload, bytes);
      s_.interrupted = false;
    } else {
      problem(at, "a chunk of unknown kind " + std::to_string(kind) + ", skipped");
    }
    return end;
  }

  void ticks(size_t at, size_t payload, uint32_t bytes, uint32_t count) {
    if (static_cast<size_t>(count) * record_bytes_ != bytes) {
      problem(at, "a ticks chunk whose length is not its count's, skipped");
      return;
    }
    for (uint32_t k = 0; k < count; ++k) {
      hardware::RecordedSample left, right;
      TickLog log;
      const std::string why =
          decode_tick(b_, payload + k * record_bytes_, s_.version, &left, &right, &log);
      if (!why.empty()) {
        problem(at, "tick record " + std::to_string(k) + ": " + why +
                        "; the ticks from there on are not replayed");
        gap_ = true;
        return;
      }
      ++s_.ticks_read;
      if (!gap_ && log.tick < static_cast<int64_t>(s_.ticks.size())) {
        problem(at, "tick " + std::to_string(log.tick) +
                        " again (a repeated or out-of-order chunk): skipped");
        return;
      }
      const bool next = log.tick == static_cast<int64_t>(s_.ticks.size());
      // Each tick reads the newest snapshots there are: never older ones than the tick before.
      if (next && !gap_ && !s_.ticks.empty() &&
          (log.model_steps_read < s_.ticks.back().model_steps_read ||
           log.surface_steps_read < s_.ticks.back().surface_steps_read)) {
        problem(at, "tick " + std::to_string(log.tick) +
                        " reads an older modelling step than the tick before; the ticks from "
                        "there on are not replayed");
        gap_ = true;
        return;
      }
      if (!next && !gap_) {
        problem(at, "ticks " + std::to_string(s_.ticks.size()) + " to " +
                        std::to_string(log.tick - 1) +
                        " are missing; the replay stops before them");
      }
      gap_ = gap_ || !next;
      if (gap_) continue;
      s_.devices[0].samples.push_back(left);
      s_.devices[1].samples.push_back(right);
      s_.ticks.push_back(log);
    }
  }

  // What a numbered record kind is called in the problems, and what a gap in it means.
  struct RecordNames {
    const char* short_name;
    const char* long_name;
    const char* gap_means;
  };

  // Whether a chunk whose records are numbered from `first` continues the `have` kept so far. A
  // repeated chunk is skipped, a gap ends what is kept (`*gap`); each reported once.
  bool continues(size_t at, int64_t first, int64_t have, bool* gap, const RecordNames& names) {
    if (first == have) return !*gap;
    if (!*gap) {
      problem(at, first < have
                      ? std::string(names.short_name) + " " + std::to_string(first) +
                            " on again (a repeated or out-of-order chunk): skipped"
                      : std::string(names.long_name) + " " + std::to_string(have) + " to " +
                            std::to_string(first - 1) + " are missing; " + names.gap_means);
    }
    *gap = *gap || first > have;
    return false;
  }

  // The modelling steps' reads from step 0 on; a step after a gap (a damaged chunk) is not kept,
  // so a replay stops at the first tick that needs it.
  void steps(size_t at, size_t payload, uint32_t bytes, uint32_t count, int64_t first) {
    if (static_cast<size_t>(count) * kStepRecordBytes != bytes) {
      problem(at, "a steps chunk whose length is not its count's, skipped");
      return;
    }
    if (!continues(
            at, first, static_cast<int64_t>(s_.steps.size()), &steps_gap_,
            {"steps", "modelling steps", "the replay stops at the first tick that read one"})) {
      return;
    }
    for (uint32_t k = 0; k < count; ++k) {
      const size_t p = payload + static_cast<size_t>(k) * kStepRecordBytes;
      StepLog step{get<int64_t>(b_, p), get<int64_t>(b_, p + 8)};
      // Each step reads a tick already published, in order, and is labelled with a later tick
      // than the step before: anything else is damage.
      const int64_t last = s_.steps.empty() ? -1 : s_.steps.back().haptic_tick_read;
      const int64_t label = s_.steps.empty() ? -1 : s_.steps.back().tick;
      if (step.haptic_tick_read < last || step.tick <= label) {
        problem(at, "step record " + std::to_string(k) +
                        " reads a haptic tick out of order, or is labelled with no later tick "
                        "than the step before; the steps from there on are not replayed");
        steps_gap_ = true;
        return;
      }
      s_.steps.push_back(step);
    }
  }

  // An author's tunings from the first on; one after a gap (a damaged chunk) is not kept, so a
  // replay departs at the first tick that took a missing one (recorded_tunings.h says where).
  void tunings(size_t at, size_t payload, uint32_t bytes, uint32_t count, int64_t first) {
    if (static_cast<size_t>(count) * kTuningRecordBytes != bytes) {
      problem(at, "a tunings chunk whose length is not its count's, skipped");
      return;
    }
    if (!continues(at, first, static_cast<int64_t>(s_.tunings.size()), &tunings_gap_,
                   {"tunings", "surface tunings", "the replay renders without them"})) {
      return;
    }
    for (uint32_t k = 0; k < count; ++k) {
      TuningLog t;
      const std::string why =
          decode_tuning(payload + static_cast<size_t>(k) * kTuningRecordBytes, &t);
      if (!why.empty()) {
        problem(at, "tuning record " + std::to_string(k) + ": " + why +
                        "; the tunings from there on are not replayed");
        tunings_gap_ = true;
        return;
      }
      s_.tunings.push_back(t);
    }
  }

  // One tuning record at `p`: what makes it impossible, or empty.
  std::string decode_tuning(size_t p, TuningLog* t) const {
    t->tick = get<int64_t>(b_, p);
    t->organ = get<int32_t>(b_, p + 8);
    const auto shading = static_cast<uint8_t>(b_[p + 12]);
    SurfaceParameters& s = t->parameters;
    s.shading = shading == 1U;
    s.stiffness_n_per_m = get<double>(b_, p + 16);
    s.damping_n_s_per_m = get<double>(b_, p + 24);
    s.friction_static = get<double>(b_, p + 32);
    s.friction_dynamic = get<double>(b_, p + 40);
    s.texture_scale = get<double>(b_, p + 48);
    const int64_t last = s_.tunings.empty() ? 0 : s_.tunings.back().tick;
    if (t->tick < last) return "taken at an earlier tick than the tuning before";
    if (t->organ < 0) return "a negative organ index";
    if (shading > 1U) return "force shading neither 0 nor 1";
    for (const double v : {s.stiffness_n_per_m, s.damping_n_s_per_m, s.friction_static,
                           s.friction_dynamic, s.texture_scale}) {
      if (!std::isfinite(v) || v < 0.0) return "a parameter that is not finite, or negative";
    }
    if (s.friction_dynamic > s.friction_static) return "dynamic friction above static friction";
    return {};
  }

  [[nodiscard]] size_t next_mark(size_t from) const {
    char mark[4];
    std::memcpy(mark, &kChunkMagic, 4);
    return b_.find(std::string(mark, 4), from);
  }

  // The end chunk says how many ticks the session ran and how many it recorded: fewer recorded
  // means the space reserved for the recording ran out (RuntimeSettings::record_s).
  void truncated() {
    const nlohmann::json end = nlohmann::json::parse(s_.end_json, nullptr, false);
    if (!end.is_object()) return;
    // Untrusted: a field that is not a whole number is as if absent.
    const auto count = [&](const char* key, int64_t absent) {
      const auto it = end.find(key);
      return it != end.end() && it->is_number_integer() ? it->get<int64_t>() : absent;
    };
    const int64_t ran = count("session_ticks", -1);
    const int64_t kept = count("ticks", -1);
    if (ran > 0 && kept >= 0 && ran > kept) {
      problem(b_.size(), "the session ran " + std::to_string(ran) +
                             " ticks and its recording kept " + std::to_string(kept) +
                             " (the space reserved for it ran out)");
    }
    const int64_t unrecorded = count("tunings_unrecorded", 0);
    if (unrecorded > 0) {
      problem(b_.size(), "an author's last " + std::to_string(unrecorded) +
                             " surface tunings were not recorded (the room reserved for " +
                             std::to_string(kMaxRecordedTunings) + " ran out)");
    }
  }

  size_t skip_to_next_mark(size_t at, const std::string& what) {
    const size_t next = next_mark(at + 1);
    const size_t to = next == std::string::npos ? b_.size() : next;
    problem(at,
            what + ": bytes " + std::to_string(at) + " to " + std::to_string(to - 1) + " skipped");
    return to;
  }

  void problem(size_t at, const std::string& what) {
    s_.problems.push_back(file_ + ": at byte " + std::to_string(at) + ": " + what);
  }

  std::string file_;
  std::string b_;
  RecordedSession s_;
  std::string header_problem_;
  bool gap_ = false;
  bool steps_gap_ = false;
  bool tunings_gap_ = false;
  size_t record_bytes_ = kTickRecordBytes;
};

}  // namespace

Result<RecordedSession> read_session_recording(const std::filesystem::path& file) {
  // Three hours at most; a regular file only (a FIFO would block, /dev/zero never end).
  Result<std::string> bytes = read_bounded_file(
      file, kMaxRecordingBytes, "a session's recording (session.lrec: 3 hours at most)");
  if (!bytes.ok()) return bytes.diagnostics();
  return Reader(file, std::move(bytes).value()).read();
}

}  // namespace lap::sim
