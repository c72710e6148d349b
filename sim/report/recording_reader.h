#pragma once
/// \file
/// Reads a session's streamed recording (session.lrec, sim/runtime/session_recorder.h) back,
/// tolerating what a crash or a bad disk leaves: a file cut off mid-chunk keeps every whole
/// chunk before it; a chunk whose checksum fails is reported (its byte offset, what it held)
/// and skipped, and reading goes on at the next chunk's mark; a file without its end chunk is
/// an interrupted session. Untrusted input: every length is checked against the file's.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"
#include "hardware/device_recording.h"
#include "sim/runtime/session_recorder.h"

namespace lap::sim {

struct RecordedSession {
  std::string header_json;  ///< what session.json holds
  /// The devices' samples of the ticks from 0 on without a gap (what a replay can use).
  std::array<hardware::DeviceRecording, 2> devices;
  std::vector<TickLog> ticks;  ///< the same ticks' commands
  /// The modelling steps' reads from 0 on without a gap (none in a LAPREC01 file): with the
  /// ticks' own, what a lockstep replay needs (Session::replay_in_lockstep).
  std::vector<StepLog> steps;
  /// An author's surface tunings from the first on without a gap, in tick order (LAPREC04).
  std::vector<TuningLog> tunings;
  /// 1: LAPREC01 (no reads recorded), 2: LAPREC02 (no touches: TickLog::touch empty), 3:
  /// LAPREC03 (no tunings: a tuned tick is only marked), 4: LAPREC04 (no frames), 5.
  int version = 5;
  int64_t frames_read = 0;  ///< frames for seeking in whole chunks (recorded_frames.h)
  int64_t ticks_read = 0;   ///< every tick read, after a gap too
  bool interrupted = true;  ///< no end chunk
  std::string events_json;
  std::string end_json;
  std::vector<std::string> problems;  ///< corrupted or missing parts, each with its offset
};

/// Diagnostics (the file named) only for a file that is not a recording at all (its header);
/// damage after the header is in `problems`.
[[nodiscard]] Result<RecordedSession> read_session_recording(const std::filesystem::path& file);

}  // namespace lap::sim
