#include "sim/report/recorded_frames.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "sim/runtime/session_recorder.h"

namespace lap::sim {

namespace {

// A frame's bounds: more particles or organs than any scenario loads is damage.
constexpr uint32_t kMaxCatheterPoints = 1U << 16;
constexpr uint32_t kMaxOrgans = 1U << 12;
constexpr size_t kToolBytes = size_t{8} * (10 + 27);
constexpr size_t kDeformedVertexBytes = size_t{4} + size_t{3} * 4;
// The least a frame takes: ticks, tools, the catheter's and organs' counts.
constexpr size_t kMinFrameBytes = 16 + 2 * kToolBytes + 8;

template <typename T>
T get(const std::string& bytes, size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof(T));
  return v;
}

Eigen::Vector3d get_vec(const std::string& b, size_t at) {
  return {get<double>(b, at), get<double>(b, at + 8), get<double>(b, at + 16)};
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// Reads `n` bytes at `at` (pread: the file's offset is not shared state).
bool read_at(int fd, uint64_t at, size_t n, std::string* out) {
  out->resize(n);
  size_t got = 0;
  while (got < n) {
    const ssize_t r = ::pread(fd, out->data() + got, n - got, static_cast<off_t>(at + got));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    got += static_cast<size_t>(r);
  }
  return true;
}

// One tool of a frame record at `p`.
void decode_tool(const std::string& b, size_t p, size_t i, ReplayFrame* f) {
  haptics::GripperPose& pose = f->tools[i];
  pose.hinge_W = get_vec(b, p);
  pose.shaft_dir_W = get_vec(b, p + 24);
  pose.open_dir_W = get_vec(b, p + 48);
  pose.opening_rad = get<double>(b, p + 72);
  p += 80;
  for (auto* segment : {&f->proxy_a_W[i], &f->proxy_b_W[i], &f->proxy_normal_W[i]}) {
    for (Eigen::Vector3d& v : *segment) {
      v = get_vec(b, p);
      p += 24;
    }
  }
}

bool tool_finite(const ReplayFrame& f, size_t i) {
  const haptics::GripperPose& pose = f.tools[i];
  bool ok = finite(pose.hinge_W) && finite(pose.shaft_dir_W) && finite(pose.open_dir_W) &&
            std::isfinite(pose.opening_rad);
  for (const auto* segment : {&f.proxy_a_W[i], &f.proxy_b_W[i], &f.proxy_normal_W[i]}) {
    for (const Eigen::Vector3d& v : *segment) ok = ok && finite(v);
  }
  return ok;
}

}  // namespace

std::string RecordedFrames::decode(const std::string& b, uint32_t count, double dt_s,
                                   std::vector<ReplayFrame>* frames) {
  // An untrusted count: no more frames than the payload's bytes can hold, before any storage.
  if (count > b.size() / kMinFrameBytes) {
    return std::to_string(count) + " frames in " + std::to_string(b.size()) +
           " bytes (a frame takes at least " + std::to_string(kMinFrameBytes) + ")";
  }
  frames->resize(count);
  size_t p = 0;
  for (uint32_t k = 0; k < count; ++k) {
    const std::string which = "frame " + std::to_string(k) + ": ";
    if (b.size() - p < 16 + 2 * kToolBytes + 8) return which + "cut short";
    ReplayFrame& f = (*frames)[k];
    f.tick = get<int64_t>(b, p);
    f.model_steps = get<int64_t>(b, p + 8);
    if (f.tick < 0 || f.model_steps < 0) return which + "a negative tick or step count";
    if (k > 0 && f.tick <= (*frames)[k - 1].tick) return which + "not after the frame before";
    f.t_s = static_cast<double>(f.tick) * dt_s;
    p += 16;
    for (size_t i = 0; i < 2; ++i) {
      decode_tool(b, p, i, &f);
      if (!tool_finite(f, i)) return which + "a tool's pose that is not finite";
      p += kToolBytes;
    }
    const auto particles = get<uint32_t>(b, p);
    const auto organs = get<uint32_t>(b, p + 4);
    p += 8;
    if (particles > kMaxCatheterPoints || organs > kMaxOrgans) {
      return which + "more catheter particles (" + std::to_string(particles) + ") or organs (" +
             std::to_string(organs) + ") than a scenario has";
    }
    if ((b.size() - p) / 24 < particles) return which + "its catheter runs past the chunk";
    f.catheter.resize(particles);
    for (Eigen::Vector3d& x : f.catheter) {
      x = get_vec(b, p);
      p += 24;
      if (!finite(x)) return which + "a catheter particle that is not finite";
    }
    f.organs.resize(organs);
    for (SurfaceDeformation& d : f.organs) {
      if (b.size() - p < 4) return which + "cut short in its organs";
      const auto n = get<uint32_t>(b, p);
      p += 4;
      if ((b.size() - p) / kDeformedVertexBytes < n) return which + "an organ runs past the chunk";
      d.count = static_cast<int32_t>(n);
      d.vertex.resize(n);
      d.position.resize(n);
      for (uint32_t v = 0; v < n; ++v, p += kDeformedVertexBytes) {
        d.vertex[v] = get<int32_t>(b, p);
        d.position[v] = {get<float>(b, p + 4), get<float>(b, p + 8), get<float>(b, p + 12)};
        if (d.vertex[v] < 0 || !finite(d.position[v])) {
          return which + "a deformed vertex with a negative index or a position not finite";
        }
      }
    }
  }
  if (p != b.size()) return std::to_string(b.size() - p) + " bytes after the last frame";
  return {};
}

Result<RecordedFrames> RecordedFrames::open(const std::filesystem::path& file) {
  RecordedFrames r;
  r.file_ = file;
  const std::string name = file.string();
  // Non-blocking: a FIFO named in place of a recording must not hang the review.
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0)
    return file_diagnostic(name, 0, "", std::string("cannot open: ") + std::strerror(errno));
  r.fd_ = std::shared_ptr<int>(new int(fd), [](int* f) {
    ::close(*f);
    delete f;
  });
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    return file_diagnostic(name, 0, "", "expected a session's recording, a regular file");
  }
  r.size_ = static_cast<uint64_t>(st.st_size);
  std::string head;
  if (!read_at(fd, 0, 12, &head) ||
      (head.compare(0, 8, kRecordingMagic) != 0 && head.compare(0, 6, "LAPREC") != 0)) {
    return file_diagnostic(name, 0, "",
                           "not a laptrainer session recording (expected it to start with "
                           "LAPREC05)");
  }
  if (head.compare(0, 8, kRecordingMagic) != 0) {
    return file_diagnostic(name, 0, "",
                           "recorded as " + head.substr(0, 8) +
                               ", before frames were kept (LAPREC05): replay it to seek");
  }
  const auto n = get<uint32_t>(head, 8);
  std::string header;
  if (n > kMaxRecordingHeaderBytes || !read_at(fd, 12, static_cast<size_t>(n) + 4, &header) ||
      crc32(header.data(), n) != get<uint32_t>(header, n)) {
    return file_diagnostic(name, 0, "", "its header is damaged or runs past the file");
  }
  header.resize(n);
  const nlohmann::json j = nlohmann::json::parse(header, nullptr, false);
  const auto rate = j.is_object() ? j.find("haptic_rate_hz") : j.end();
  if (!j.is_object() || rate == j.end() || !rate->is_number() || !(rate->get<double>() > 0.0) ||
      !std::isfinite(rate->get<double>())) {
    return file_diagnostic(name, 0, "haptic_rate_hz",
                           "its header has no haptic rate (expected a positive number)");
  }
  r.dt_s_ = 1.0 / rate->get<double>();
  std::string why;
  if (!r.index(12 + static_cast<uint64_t>(n) + 4, &why)) return file_diagnostic(name, 0, "", why);
  return r;
}

// The frames chunks' heads from the first chunk at `at`, in file order; damage reported and skipped
// to the next mark.
bool RecordedFrames::index(uint64_t at, std::string* why) {
  const int fd = *fd_;
  std::string head;
  // The next chunk mark at or after `from`, or the file's size.
  const auto next_mark = [&](uint64_t from) {
    std::string block;
    constexpr size_t kBlock = size_t{1} << 16;
    while (from < size_) {
      const size_t n = static_cast<size_t>(std::min<uint64_t>(kBlock + 3, size_ - from));
      if (!read_at(fd, from, n, &block)) return size_;
      char mark[4];
      std::memcpy(mark, &kChunkMagic, 4);
      const size_t found = block.find(std::string(mark, 4));
      if (found != std::string::npos) return from + found;
      from += kBlock;
    }
    return size_;
  };
  while (at < size_) {
    if (size_ - at < kChunkHeadBytes + 4 || !read_at(fd, at, kChunkHeadBytes, &head)) {
      problem(at, "the last " + std::to_string(size_ - at) +
                      " bytes are an incomplete chunk (the session was cut off)");
      break;
    }
    const auto bytes = get<uint32_t>(head, 8);
    const uint64_t end = at + kChunkHeadBytes + bytes + 4;
    if (get<uint32_t>(head, 0) != kChunkMagic || bytes > kMaxChunkPayloadBytes || end > size_) {
      const uint64_t next = next_mark(at + 1);
      if (next < size_ || get<uint32_t>(head, 0) != kChunkMagic) {
        problem(at, "not a whole chunk: bytes " + std::to_string(at) + " to " +
                        std::to_string(next - 1) + " skipped");
      } else {
        problem(at, "the last chunk is incomplete (the session was cut off)");
      }
      at = next;
      continue;
    }
    const auto kind = get<uint32_t>(head, 4);
    const auto count = get<uint32_t>(head, 12);
    const auto first = get<int64_t>(head, 16);
    if (kind == kChunkFrames && count > 0) {
      // Its head is trusted only with its checksum (a damaged first tick would misplace every
      // chunk after it, a damaged count inflate the frames): the whole chunk is read here.
      const size_t n = kChunkHeadBytes + bytes + 4;
      if (!read_at(fd, at, n, &buffer_) || !chunk_intact(buffer_.data(), bytes)) {
        problem(at, "a frames chunk whose checksum does not match (" + std::to_string(count) +
                        " frames from tick " + std::to_string(first) +
                        " if its head is right): skipped");
      } else if (count > bytes / kMinFrameBytes) {
        problem(at, "a frames chunk of " + std::to_string(count) + " frames in " +
                        std::to_string(bytes) + " bytes: skipped");
      } else if (!chunks_.empty() && first <= chunks_.back().first_tick) {
        problem(at, "a frames chunk from tick " + std::to_string(first) +
                        " not after the one before: skipped");
      } else {
        chunks_.push_back({at, bytes, count, first, false});
      }
    }
    at = end;
  }
  // The last frame's time: from the last chunk that reads.
  for (size_t k = chunks_.size(); k-- > 0;) {
    if (read_chunk(k, &decoded_)) {
      last_tick_ = decoded_.back().tick;
      break;
    }
  }
  for (const Chunk& c : chunks_) frames_ += c.bad ? 0 : c.count;
  if (frames_ == 0) {
    *why = "has no frames that read (a recording's frames come every 0.1 s of the session)";
    return false;
  }
  return true;
}

// Chunk k read, checked and decoded into `frames` (kept: the next seek often lands in it).
bool RecordedFrames::read_chunk(size_t k, std::vector<ReplayFrame>* frames) {
  if (frames == &decoded_ && decoded_chunk_ == k) return true;
  Chunk& c = chunks_[k];
  if (c.bad) return false;
  const size_t n = kChunkHeadBytes + c.bytes + 4;
  std::string what;
  if (!read_at(*fd_, c.offset, n, &buffer_)) {
    what = "cannot be read";
  } else if (!chunk_intact(buffer_.data(), c.bytes)) {
    what = "its checksum does not match";
  } else {
    what = decode(buffer_.substr(kChunkHeadBytes, c.bytes), c.count, dt_s_, frames);
    if (what.empty() && frames->front().tick != c.first_tick) {
      what = "its first frame is not the tick its head names";
    }
  }
  if (!what.empty()) {
    problem(c.offset, "a frames chunk (" + std::to_string(c.count) + " frames from tick " +
                          std::to_string(c.first_tick) + "): " + what + "; skipped");
    c.bad = true;
    if (frames == &decoded_) decoded_chunk_ = SIZE_MAX;
    return false;
  }
  if (frames == &decoded_) decoded_chunk_ = k;
  return true;
}

Status RecordedFrames::seek(double t_s, ReplayFrame* out) {
  // A nanosecond's tolerance: the scrub bar's rounded milliseconds land on their frame.
  const double ticks = std::isfinite(t_s) ? std::max(0.0, t_s / dt_s_ + 1e-6) : 0.0;
  const auto target = static_cast<int64_t>(std::min(ticks, 9.0e18));
  const auto after = std::upper_bound(chunks_.begin(), chunks_.end(), target,
                                      [](int64_t t, const Chunk& c) { return t < c.first_tick; });
  const size_t k = after == chunks_.begin() ? 0 : static_cast<size_t>(after - chunks_.begin()) - 1;
  // The chunk that holds it, else the last whole one before, else the first whole one after.
  for (size_t i = k + 1; i-- > 0;) {
    if (!read_chunk(i, &decoded_)) continue;
    const auto frame = std::upper_bound(decoded_.begin(), decoded_.end(), target,
                                        [](int64_t t, const ReplayFrame& f) { return t < f.tick; });
    *out = frame == decoded_.begin() ? decoded_.front() : *(frame - 1);
    return {};
  }
  for (size_t i = k + 1; i < chunks_.size(); ++i) {
    if (!read_chunk(i, &decoded_)) continue;
    *out = decoded_.front();
    return {};
  }
  return file_diagnostic(file_.string(), 0, "",
                         "no frame at or near " + std::to_string(t_s) +
                             " s reads: " + (problems_.empty() ? "" : problems_.back()));
}

std::vector<ReplayFrame> RecordedFrames::all() {
  std::vector<ReplayFrame> out;
  std::vector<ReplayFrame> chunk;
  for (size_t k = 0; k < chunks_.size(); ++k) {
    if (!read_chunk(k, &chunk)) continue;
    for (ReplayFrame& f : chunk) out.push_back(std::move(f));
  }
  return out;
}

void RecordedFrames::problem(uint64_t at, const std::string& what) {
  problems_.push_back(file_.string() + ": at byte " + std::to_string(at) + ": " + what);
}

}  // namespace lap::sim
