#include "sim/runtime/session_recorder.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>

namespace lap::sim {

namespace {

std::array<uint32_t, 256> crc_table() {
  std::array<uint32_t, 256> t{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    t[i] = c;
  }
  return t;
}

template <typename T>
void put(std::string* out, T v) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));  // little-endian hosts (x86-64, arm64 Linux)
  out->append(bytes, sizeof(T));
}

void put_vec(std::string* out, const Eigen::Vector3d& v) {
  for (int k = 0; k < 3; ++k) put(out, v[k]);
}

}  // namespace

uint32_t crc32(const void* data, size_t n, uint32_t crc) {
  static const std::array<uint32_t, 256> table = crc_table();
  const auto* p = static_cast<const unsigned char*>(data);
  crc = ~crc;
  for (size_t i = 0; i < n; ++i) crc = table[(crc ^ p[i]) & 0xFFU] ^ (crc >> 8);
  return ~crc;
}

bool chunk_intact(const char* chunk, uint32_t payload_bytes) {
  const size_t covered = kChunkHeadBytes - 4 + payload_bytes;  // kind … payload
  uint32_t stored = 0;
  std::memcpy(&stored, chunk + 4 + covered, 4);
  return crc32(chunk + 4, covered) == stored;
}

void append_tick_record(const hardware::RecordedSample& left, const hardware::RecordedSample& right,
                        const TickLog& log, std::string* out) {
  put(out, log.tick);
  put(out, log.wall_ns);
  for (size_t i = 0; i < 2; ++i) {
    const hardware::RecordedSample& r = i == 0 ? left : right;
    const hardware::DeviceSample& s = r.sample;
    put(out, s.time_s);
    put_vec(out, s.position_W);
    put(out, s.orientation_W.w());
    put(out, s.orientation_W.x());
    put(out, s.orientation_W.y());
    put(out, s.orientation_W.z());
    put_vec(out, s.velocity_W);
    put(out, s.gripper_angle_rad);
    put(out, s.buttons);
    put(out, static_cast<uint32_t>(r.status));
    put_vec(out, log.force_W[i]);
    put(out, log.squeeze_n[i]);
  }
  put(out, log.gain);
  put(out, static_cast<uint8_t>(log.late ? 1 : 0));
  put(out, static_cast<uint8_t>(log.paused ? 1 : 0));
  put(out, static_cast<uint8_t>(log.resumed ? 1 : 0));
  put(out, static_cast<uint8_t>(log.after_hold ? 1 : 0));
  put(out, static_cast<uint8_t>(log.tuned ? 1 : 0));
  put(out, static_cast<uint8_t>(log.write_status[0]));
  put(out, static_cast<uint8_t>(log.write_status[1]));
  out->append(1, '\0');
  put(out, log.lateness_s);
  put(out, log.model_steps_read);
  put(out, log.surface_steps_read);
  for (const ToolTouch& t : log.touch) {
    put(out, static_cast<uint8_t>((t.catheter_held ? 1U : 0U) | (t.duct_held ? 2U : 0U)));
    put(out, t.organs);
    put(out, t.contacts);
    out->append(1, '\0');
    for (size_t k = 0; k < ToolTouch::kListedOrgans; ++k) {
      put(out, t.organ[k]);
      put(out, t.organ_contacts[k]);
      put(out, t.force_n[k]);
    }
  }
}
static_assert(kTuningRecordBytes == 8 + 4 + 1 + 3 + 5 * 8);
static_assert(kTickRecordBytes ==
              8 + 8 + 2 * (8 * 12 + 4 + 4 + 8 * 4) + 8 + 8 * 1 + 24 + 2 * (4 + 4 * (2 + 2 + 4)));

void append_step_record(const StepLog& step, std::string* out) {
  put(out, step.tick);
  put(out, step.haptic_tick_read);
}

void append_tuning_record(const TuningLog& tuning, std::string* out) {
  const SurfaceParameters& p = tuning.parameters;
  put(out, tuning.tick);
  put(out, tuning.organ);
  put(out, static_cast<uint8_t>(p.shading ? 1 : 0));
  out->append(3, '\0');
  put(out, p.stiffness_n_per_m);
  put(out, p.damping_n_s_per_m);
  put(out, p.friction_static);
  put(out, p.friction_dynamic);
  put(out, p.texture_scale);
}

void append_frame_record(const RecordedFrame& frame, std::string* out) {
  put(out, frame.tick);
  put(out, frame.model_steps);
  for (size_t i = 0; i < 2; ++i) {
    const haptics::GripperPose& pose = frame.tools[i];
    put_vec(out, pose.hinge_W);
    put_vec(out, pose.shaft_dir_W);
    put_vec(out, pose.open_dir_W);
    put(out, pose.opening_rad);
    for (const auto* segment :
         {&frame.proxy_a_W[i], &frame.proxy_b_W[i], &frame.proxy_normal_W[i]}) {
      for (const Eigen::Vector3d& v : *segment) put_vec(out, v);
    }
  }
  put(out, static_cast<uint32_t>(frame.catheter.size()));
  put(out, static_cast<uint32_t>(frame.organs.size()));
  for (const Eigen::Vector3d& p : frame.catheter) put_vec(out, p);
  for (const SurfaceDeformation& d : frame.organs) {
    const auto n = static_cast<uint32_t>(std::max<int32_t>(0, d.count));
    put(out, n);
    for (uint32_t k = 0; k < n; ++k) {
      put(out, d.vertex[k]);
      for (int c = 0; c < 3; ++c) put(out, static_cast<float>(d.position[k][c]));
    }
  }
}

Result<std::unique_ptr<SessionRecorder>> SessionRecorder::open(const std::filesystem::path& file,
                                                               const std::string& header_json) {
  std::unique_ptr<SessionRecorder> r(new SessionRecorder());
  r->file_ = file;
  // A new file, for its owner only (a trainee's session): an existing one is never overwritten.
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  r->f_ = fd >= 0 ? ::fdopen(fd, "wb") : nullptr;
  if (r->f_ == nullptr) {
    if (fd >= 0) ::close(fd);
    return file_diagnostic(file.string(), 0, "",
                           std::string("cannot create the recording: ") + std::strerror(errno));
  }
  std::string head(kRecordingMagic, 8);
  put(&head, static_cast<uint32_t>(header_json.size()));
  head += header_json;
  put(&head, crc32(header_json.data(), header_json.size()));
  if (std::fwrite(head.data(), 1, head.size(), r->f_) != head.size() || std::fflush(r->f_) != 0) {
    return file_diagnostic(file.string(), 0, "",
                           std::string("cannot write the recording: ") + std::strerror(errno));
  }
  return r;
}

SessionRecorder::~SessionRecorder() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  if (f_ != nullptr) std::fclose(f_);
}

void SessionRecorder::start(const RecordingSources& from) {
  from_ = from;
  thread_ = std::thread([this] { run(); });
}

// Every kFlushPeriodS, and sooner when the frames' ring fills (a --fast session's modelling
// step waits for room there).
void SessionRecorder::run() {
  using Clock = std::chrono::steady_clock;
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kFlushPeriodS));
  auto next = Clock::now() + period;
  while (!stop_.load(std::memory_order_relaxed)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (Clock::now() < next && (from_.frames == nullptr || !from_.frames->filling())) continue;
    write_published();
    next = Clock::now() + period;
  }
}

// The ticks' count is loaded first: every step a tick read, and every tuning a tick took, was
// published before the tick, so the steps and tunings loaded after include them all. Those are
// written first: a session killed between the chunks leaves steps or tunings without their
// ticks (unused), never ticks without theirs.
void SessionRecorder::write_published() {
  const int64_t ticks = from_.published_ticks->load(std::memory_order_acquire);
  const auto published = [](const std::atomic<int64_t>* n) {
    return n != nullptr ? n->load(std::memory_order_acquire) : 0;
  };
  write_steps_up_to(published(from_.published_steps));
  write_tunings_up_to(published(from_.published_tunings));
  write_ticks_up_to(ticks);
  write_frames();
}

void SessionRecorder::write_steps_up_to(int64_t published) {
  const int64_t from = written_steps_;
  if (!problem_.empty() || published <= from) return;
  payload_.clear();
  for (int64_t i = from; i < published; ++i) {
    append_step_record(from_.steps[static_cast<size_t>(i)], &payload_);
  }
  if (write_chunk(kChunkSteps, static_cast<uint32_t>(published - from), from, payload_)) {
    written_steps_ = published;
  }
}

void SessionRecorder::write_tunings_up_to(int64_t published) {
  const int64_t from = written_tunings_;
  if (!problem_.empty() || published <= from) return;
  payload_.clear();
  for (int64_t i = from; i < published; ++i) {
    append_tuning_record(from_.tunings[static_cast<size_t>(i)], &payload_);
  }
  if (write_chunk(kChunkTunings, static_cast<uint32_t>(published - from), from, payload_)) {
    written_tunings_ = published;
  }
}

// Every frame the modelling thread has published, in one chunk; their slots are then free.
void SessionRecorder::write_frames() {
  FrameRing* ring = from_.frames;
  if (ring == nullptr) return;
  if (!problem_.empty()) {
    ring->close();  // nothing more is written: a --fast step must not wait for room
    return;
  }
  const int64_t from = ring->released();
  const int64_t published = ring->published();
  if (published <= from) return;
  payload_.clear();
  for (int64_t n = from; n < published; ++n) append_frame_record(ring->frame(n), &payload_);
  if (write_chunk(kChunkFrames, static_cast<uint32_t>(published - from), ring->frame(from).tick,
                  payload_)) {
    ring->release(published);
  }
}

void SessionRecorder::write_ticks_up_to(int64_t published) {
  const int64_t from = written_.load(std::memory_order_relaxed);
  if (!problem_.empty() || published <= from) return;
  payload_.clear();
  for (int64_t i = from; i < published; ++i) {
    const auto k = static_cast<size_t>(i);
    append_tick_record(from_.left[k], from_.right[k], from_.ticks[k], &payload_);
  }
  if (write_chunk(kChunkTicks, static_cast<uint32_t>(published - from), from_.ticks[from].tick,
                  payload_)) {
    written_.store(published, std::memory_order_relaxed);
  }
}

bool SessionRecorder::write_chunk(uint32_t kind, uint32_t count, int64_t first_tick,
                                  const std::string& payload) {
  if (!problem_.empty()) return false;
  std::string chunk;
  put(&chunk, kChunkMagic);
  put(&chunk, kind);
  put(&chunk, static_cast<uint32_t>(payload.size()));
  put(&chunk, count);
  put(&chunk, first_tick);
  chunk += payload;
  put(&chunk, crc32(chunk.data() + 4, chunk.size() - 4));
  // Handed to the kernel now: a process killed after this loses none of it.
  if (std::fwrite(chunk.data(), 1, chunk.size(), f_) != chunk.size() || std::fflush(f_) != 0) {
    problem_ = "the recording " + file_.string() + " stopped after " +
               std::to_string(written_.load()) + " ticks: " + std::strerror(errno) +
               " (what was written before is kept)";
    return false;
  }
  return true;
}

Status SessionRecorder::finish(const std::string& events_json, const std::string& end_json) {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  if (from_.published_ticks != nullptr) write_published();
  if (from_.frames != nullptr) from_.frames->close();
  write_chunk(kChunkEvents, 0, 0, events_json);
  write_chunk(kChunkEnd, 0, 0, end_json);
  // On the disk, not only in the kernel's cache, before it is called done.
  if (f_ != nullptr && ::fdatasync(::fileno(f_)) != 0 && problem_.empty()) {
    problem_ = "the recording " + file_.string() + " could not be synced: " + std::strerror(errno);
  }
  if (f_ != nullptr && std::fclose(f_) != 0 && problem_.empty()) {
    problem_ = "the recording " + file_.string() + " did not close: " + std::strerror(errno);
  }
  f_ = nullptr;
  if (!problem_.empty()) return diagnostic(problem_);
  return {};
}

}  // namespace lap::sim
