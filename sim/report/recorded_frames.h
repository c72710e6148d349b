#pragma once
/// \file
/// Seeking in a session's recording (session.lrec, LAPREC05) by its frames (frame_ring.h):
/// what the 3D view draws, kept every 0.1 s of session time while the session ran. Opening reads
/// the file's header and its chunks' heads only, to index the frames chunks; a seek then reads
/// and checks the one chunk that holds the frame at or before the time asked for (issue 24:
/// seeking anywhere in a 10-minute recording within 200 ms, without replaying up to there).
///
/// Untrusted input, as recording_reader.h: every length and count is checked against the file's
/// before storage is taken; a frames chunk whose checksum fails is left out of the index (its
/// head is not trusted), one whose frames are impossible is reported when a seek reads it (its
/// byte offset) and the frame before it taken; a file cut off mid-chunk keeps every whole chunk.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "sim/report/replay_timeline.h"

namespace lap::sim {

class RecordedFrames {
 public:
  /// Indexes `file`'s frames, reading each frames chunk once to check it (9 MB for a 10-minute
  /// session). Diagnostics (the file named) for a file that cannot be read or is not a
  /// recording with frames (one written before LAPREC05 has none: it must be replayed).
  [[nodiscard]] static Result<RecordedFrames> open(const std::filesystem::path& file);

  /// The frame at or before `t_s` (the first one for a time before it, the last after the end),
  /// into `out` (its storage reused). Diagnostics only when no frame before `t_s` can be read.
  [[nodiscard]] Status seek(double t_s, ReplayFrame* out);

  /// Every frame that reads, in time order (a damaged chunk's left out and reported).
  [[nodiscard]] std::vector<ReplayFrame> all();

  /// Frames in whole chunks, the haptic period [s], the last frame's time [s].
  [[nodiscard]] int64_t frame_count() const { return frames_; }
  [[nodiscard]] size_t chunk_count() const { return chunks_.size(); }
  [[nodiscard]] double dt_s() const { return dt_s_; }
  [[nodiscard]] double duration_s() const { return static_cast<double>(last_tick_) * dt_s_; }
  /// Damage met so far (indexing, and the chunks seeks have read), each with its byte offset.
  [[nodiscard]] const std::vector<std::string>& problems() const { return problems_; }

  /// Every frame of a frames chunk's payload, in order; what makes it impossible, or empty.
  [[nodiscard]] static std::string decode(const std::string& payload, uint32_t count, double dt_s,
                                          std::vector<ReplayFrame>* frames);

 private:
  struct Chunk {
    uint64_t offset = 0;  ///< of its mark
    uint32_t bytes = 0;   ///< payload
    uint32_t count = 0;   ///< frames
    int64_t first_tick = 0;
    bool bad = false;  ///< a seek found it damaged: skipped from then on
  };
  [[nodiscard]] bool index(uint64_t at, std::string* why);
  [[nodiscard]] bool read_chunk(size_t k, std::vector<ReplayFrame>* frames);
  void problem(uint64_t at, const std::string& what);

  std::filesystem::path file_;
  std::shared_ptr<int> fd_;  ///< closed with the last copy
  uint64_t size_ = 0;
  double dt_s_ = 0.0;
  std::vector<Chunk> chunks_;
  int64_t frames_ = 0;
  int64_t last_tick_ = 0;
  std::vector<std::string> problems_;
  std::vector<ReplayFrame> decoded_;  ///< the chunk read last (reused)
  size_t decoded_chunk_ = SIZE_MAX;
  std::string buffer_;
};

}  // namespace lap::sim
