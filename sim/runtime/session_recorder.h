#pragma once
/// \file
/// A session's recording written while it runs, so that a crash loses at most the last 100 ms
/// (issue 24): a writer thread of its own (never the loops) appends what the haptic loop has
/// published every kFlushPeriodS, each time as a chunk with its own checksum, and hands it to
/// the operating system at once (a killed process loses nothing the kernel has). At the end it
/// writes the events and an end chunk; a file without one is an interrupted session.
///
/// File (session.lrec), little-endian:
///   "LAPREC05" | uint32 header bytes | header JSON (session.json's fields) | uint32 CRC-32
///   chunks:    uint32 magic "LRCK" | uint32 kind | uint32 payload bytes | uint32 count |
///              int64 first tick (or step) | payload | uint32 CRC-32 of kind … payload
///   kinds:     1 ticks (count records of kTickRecordBytes), 2 events (JSON), 3 end (JSON),
///              4 modelling steps (count records of kStepRecordBytes), 5 an author's surface
///              tunings (count records of kTuningRecordBytes; first: the first record's index),
///              6 frames for seeking (count frame records, first: the first one's tick)
/// A tick record: int64 tick, int64 wall clock [ns since the epoch], per tool (left, right) the
/// device's sample (double time_s, position[3], orientation w x y z, velocity[3], gripper angle;
/// uint32 buttons, uint32 status) and what was sent (double force[3], squeeze), then double
/// gain, uint8 late, uint8 paused, uint8 resumed, uint8 after a hold, uint8 tuned, uint8 per
/// tool the status its write returned, 1 byte zero, double lateness [s], int64 the
/// modelling steps of the model snapshot it read, int64 those of the proxies' surfaces it felt;
/// then per tool what it touched and held (tool_touch.h): uint8 flags (1: the catheter held, 2:
/// the duct), uint8 organs touched, uint8 contacts, 1 byte zero, and ToolTouch::kListedOrgans
/// times uint16 organ, uint16 contacts on it, float32 force on it [N] (unlisted ones zero).
/// A step record: int64 the haptic tick the step is labelled with, int64 the haptic tick whose
/// snapshot it read (-1: none yet).
/// A tuning record: int64 the haptic tick that took it, int32 the organ, uint8 force shading,
/// 3 bytes zero, double stiffness [N/m], damping [N s/m], μs, μd, texture scale: the organ's
/// surface as the haptic loop rendered it from that tick on (surface_tuning.h).
/// A frame record (frame_ring.h), every FrameRing::kFramePeriodS of session time: int64 tick,
/// int64 modelling steps; per tool (left, right) double hinge[3], shaft direction[3], opening
/// direction[3], opening [rad], then proxy a[3][3], proxy b[3][3], normal[3][3]; uint32
/// catheter particles, uint32 organs; the particles as double[3]; per organ uint32 count, then
/// count times int32 vertex and float32 position[3] (world frame [m]: drawing needs no more than
/// float's 0.03 µm at 0.3 m, and halves what a deformed duct costs on disk).
/// The reads make a real-time session replayable in lockstep to the same state (issue 24): they
/// say which snapshot each loop took from the other, which thread timing decided live.
/// Older files are still read: "LAPREC04" (no frames: a review replays to seek),
/// "LAPREC03" (no tunings: a tuned tick is only marked), "LAPREC02"
/// (tick records of 328 bytes, without the touches) and "LAPREC01" (304 bytes, ending after
/// `paused` and 6 bytes zero; no steps, so they replay in plain lockstep).

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "core/result.h"
#include "hardware/device_recording.h"
#include "sim/runtime/frame_ring.h"
#include "sim/runtime/surface_tuning.h"
#include "sim/runtime/tool_touch.h"

namespace lap::sim {

/// What the haptic loop sent on one tick, beside the devices' samples.
struct TickLog {
  int64_t tick = 0;
  int64_t wall_ns = 0;  ///< CLOCK_REALTIME when the tick began
  std::array<Eigen::Vector3d, 2> force_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::array<double, 2> squeeze_n{};
  double gain = 1.0;  ///< the watchdog's factor on every command
  bool late = false;  ///< a late tick: zero sent
  bool paused = false;
  bool resumed = false;     ///< a resume() taken up on this tick (while paused)
  bool after_hold = false;  ///< the first tick after the trainee's pause (Session::hold)
  bool tuned = false;       ///< an author's surface tuning taken up (Session::tune_surface)
  /// What each device's write returned (a fault reported there trips the watchdog).
  std::array<hardware::DeviceStatus, 2> write_status{hardware::DeviceStatus::kOk,
                                                     hardware::DeviceStatus::kOk};
  double lateness_s = 0.0;  ///< how late the tick started
  /// Which snapshots this tick read (their ModelSnapshot::steps, HapticSurfaces::model_steps).
  int64_t model_steps_read = 0;
  int64_t surface_steps_read = 0;
  std::array<ToolTouch, 2> touch{};  ///< what each tool touched and held (tool_touch.h)
};

/// What one modelling step read from the haptic loop (written by the modelling thread).
struct StepLog {
  int64_t tick = 0;               ///< the haptic tick the step is labelled with
  int64_t haptic_tick_read = -1;  ///< whose HapticSnapshot it read; -1: the initial one
};

/// An organ's surface as an author's tuning left it, from haptic tick `tick` on (written by the
/// haptic thread, one per organ the tick's tunings changed).
struct TuningLog {
  int64_t tick = 0;
  int32_t organ = -1;
  SurfaceParameters parameters;
};

/// What the loops fill for the recorder: arrays reserved at set-up (they never move), of which
/// the first `*published_…` entries are complete (release-stored by the thread that fills them).
struct RecordingSources {
  const hardware::RecordedSample* left = nullptr;  ///< haptic thread: the devices' samples
  const hardware::RecordedSample* right = nullptr;
  const TickLog* ticks = nullptr;  ///< haptic thread: beside them, per tick
  const std::atomic<int64_t>* published_ticks = nullptr;
  const StepLog* steps = nullptr;  ///< modelling thread
  const std::atomic<int64_t>* published_steps = nullptr;
  const TuningLog* tunings = nullptr;  ///< haptic thread
  const std::atomic<int64_t>* published_tunings = nullptr;
  FrameRing* frames = nullptr;  ///< modelling thread: what the 3D view draws (may be null)
};

inline constexpr char kRecordingMagic[9] = "LAPREC05";
inline constexpr char kRecordingMagicV4[9] = "LAPREC04";
inline constexpr char kRecordingMagicV3[9] = "LAPREC03";
inline constexpr char kRecordingMagicV2[9] = "LAPREC02";
inline constexpr char kRecordingMagicV1[9] = "LAPREC01";
inline constexpr uint32_t kChunkMagic = 0x4B43524CU;  // "LRCK"
inline constexpr uint32_t kChunkTicks = 1;
inline constexpr uint32_t kChunkEvents = 2;
inline constexpr uint32_t kChunkEnd = 3;
inline constexpr uint32_t kChunkSteps = 4;
inline constexpr uint32_t kChunkTunings = 5;
inline constexpr uint32_t kChunkFrames = 6;
inline constexpr size_t kChunkHeadBytes = 24;
inline constexpr size_t kToolTouchBytes = 4 + ToolTouch::kListedOrgans * 8;  // 36
inline constexpr size_t kTickRecordBytes =
    16 + 2 * (104 + 32) + 16 + 24 + 2 * kToolTouchBytes;                     // 400
inline constexpr size_t kTickRecordBytesV2 = 16 + 2 * (104 + 32) + 16 + 24;  // 328
inline constexpr size_t kTickRecordBytesV1 = 16 + 2 * (104 + 32) + 16;       // 304
inline constexpr size_t kStepRecordBytes = 16;
inline constexpr size_t kTuningRecordBytes = 16 + 5 * 8;  // 56
/// The tunings a recording session keeps (4 MB reserved in memory, 56 bytes each on disk): a
/// slider dragged for an hour posts tens of thousands; those beyond are counted in the end chunk
/// and a replay says where it departs.
inline constexpr size_t kMaxRecordedTunings = size_t{1} << 16;
/// Modelling steps a session records beyond one per tick (a haptic loop five times slower than
/// its rate, live): the room the session reserves, and what a reader accepts.
inline constexpr size_t kStepsBeyondTicks = 64;

/// What a reader accepts: a header JSON is a few hundred bytes, a chunk 40 ms of ticks (or a
/// --fast session's burst of frames).
inline constexpr uint32_t kMaxRecordingHeaderBytes = 1U << 20;
inline constexpr uint32_t kMaxChunkPayloadBytes = 64U << 20;

/// CRC-32 (IEEE 802.3, reflected, as zlib's crc32) of `n` bytes, continuing from `crc`.
[[nodiscard]] uint32_t crc32(const void* data, size_t n, uint32_t crc = 0);
/// Whether the whole chunk at `chunk` (its mark, head, `payload_bytes` of payload and CRC) has
/// the checksum it carries.
[[nodiscard]] bool chunk_intact(const char* chunk, uint32_t payload_bytes);

/// One tick as its record's bytes (appended to `out`).
void append_tick_record(const hardware::RecordedSample& left, const hardware::RecordedSample& right,
                        const TickLog& log, std::string* out);
/// One modelling step as its record's bytes (appended to `out`).
void append_step_record(const StepLog& step, std::string* out);
/// One tuning as its record's bytes (appended to `out`).
void append_tuning_record(const TuningLog& tuning, std::string* out);
/// One frame as its record's bytes (appended to `out`).
void append_frame_record(const RecordedFrame& frame, std::string* out);

class SessionRecorder {
 public:
  static constexpr double kFlushPeriodS = 0.04;

  /// Creates the file and writes its header (`header_json`: what session.json holds).
  static Result<std::unique_ptr<SessionRecorder>> open(const std::filesystem::path& file,
                                                       const std::string& header_json);
  ~SessionRecorder();
  SessionRecorder(const SessionRecorder&) = delete;
  SessionRecorder& operator=(const SessionRecorder&) = delete;

  /// Starts the writer over what the loops fill (`from`: the steps' and tunings' may be null).
  void start(const RecordingSources& from);
  /// Stops the writer, writes what is left, the events chunk and the end chunk, and closes.
  /// The problem that stopped the recording early (a full disk), if any, is returned; what was
  /// written before it stays.
  [[nodiscard]] Status finish(const std::string& events_json, const std::string& end_json);

  [[nodiscard]] int64_t written_ticks() const { return written_.load(); }
  [[nodiscard]] const std::filesystem::path& file() const { return file_; }

 private:
  SessionRecorder() = default;
  void run();
  void write_published();
  void write_ticks_up_to(int64_t published);
  void write_steps_up_to(int64_t published);
  void write_tunings_up_to(int64_t published);
  void write_frames();
  bool write_chunk(uint32_t kind, uint32_t count, int64_t first_tick, const std::string& payload);

  std::filesystem::path file_;
  std::FILE* f_ = nullptr;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> written_{0};
  RecordingSources from_;
  int64_t written_steps_ = 0;    ///< writer thread's until finish() joins it
  int64_t written_tunings_ = 0;  ///< writer thread's until finish() joins it
  std::string problem_;          ///< writer thread's until finish() joins it
  std::string payload_;
};

}  // namespace lap::sim
