#include "hardware/device_recording.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string_view>

#include "core/bounded_file.h"
#include "core/whole_file.h"

namespace lap::hardware {
namespace {

constexpr char kMagic[8] = {'L', 'A', 'P', 'D', 'E', 'V', '0', '1'};
constexpr uint32_t kVersion = 1;

template <typename T>
void put(std::vector<char>* out, const T& v) {
  const size_t at = out->size();
  out->resize(at + sizeof(T));
  std::memcpy(out->data() + at, &v, sizeof(T));
}

template <typename T>
T get(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

// `file: field: message`. Without a file name the text is kept as it always printed (": ...").

}  // namespace

Status write_device_recording(const std::filesystem::path& file, const DeviceRecording& recording) {
  std::vector<char> bytes;
  bytes.reserve(kDeviceRecordingHeaderBytes +
                recording.samples.size() * kDeviceRecordingRecordBytes);
  bytes.insert(bytes.end(), std::begin(kMagic), std::end(kMagic));
  put(&bytes, kVersion);
  put(&bytes, static_cast<uint32_t>(kDeviceRecordingRecordBytes));
  put(&bytes, recording.period_s);
  put(&bytes, uint64_t{0});
  for (const RecordedSample& r : recording.samples) {
    const DeviceSample& s = r.sample;
    put(&bytes, r.tick);
    put(&bytes, s.time_s);
    for (int k = 0; k < 3; ++k) put(&bytes, s.position_W[k]);
    put(&bytes, s.orientation_W.w());
    put(&bytes, s.orientation_W.x());
    put(&bytes, s.orientation_W.y());
    put(&bytes, s.orientation_W.z());
    for (int k = 0; k < 3; ++k) put(&bytes, s.velocity_W[k]);
    put(&bytes, s.gripper_angle_rad);
    put(&bytes, s.buttons);
    put(&bytes, static_cast<uint32_t>(r.status));
  }
  // Whole or not at all: on a full disk no cut-off recording is left to be replayed.
  return write_file_whole(file, std::string_view(bytes.data(), bytes.size()),
                          "the device recording");
}

Result<DeviceRecording> read_device_recording(const std::filesystem::path& file) {
  auto fail = [&](const std::string& what,
                  const std::string& field = "") -> Result<DeviceRecording> {
    return file_diagnostic(file.string(), 0, field, what);
  };
  const Result<std::string> read =
      read_bounded_file(file, kMaxDeviceRecordingBytes, "a device recording (.lapdev)",
                        "hardware/device_recording.h");
  if (!read.ok()) return read.diagnostics();
  const std::string& bytes = read.value();
  if (bytes.size() < kDeviceRecordingHeaderBytes ||
      std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    return fail("at byte 0: not a laptrainer device recording (expected the header 'LAPDEV01')");
  }
  const auto version = get<uint32_t>(bytes.data() + 8);
  const auto record = get<uint32_t>(bytes.data() + 12);
  if (version != kVersion) {
    return fail("at byte 8: version " + std::to_string(version) + ": expected version 1");
  }
  if (record != kDeviceRecordingRecordBytes) {
    return fail("at byte 12: record size " + std::to_string(record) + ": expected 112 bytes");
  }
  DeviceRecording rec;
  rec.period_s = get<double>(bytes.data() + 16);
  if (!std::isfinite(rec.period_s) || !(rec.period_s > 0.0)) {
    char got[32];
    std::snprintf(got, sizeof(got), "%g", rec.period_s);
    return fail(std::string("at byte 16: expected a positive period, got ") + got, "period_s");
  }
  const size_t body = bytes.size() - kDeviceRecordingHeaderBytes;
  if (body % kDeviceRecordingRecordBytes != 0) {
    const size_t last = body / kDeviceRecordingRecordBytes;
    return fail("ends inside record " + std::to_string(last) + " (at byte " +
                std::to_string(kDeviceRecordingHeaderBytes + last * kDeviceRecordingRecordBytes) +
                ", " + std::to_string(body % kDeviceRecordingRecordBytes) +
                " stray bytes): the file is truncated");
  }
  const size_t n = body / kDeviceRecordingRecordBytes;
  rec.samples.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const char* p = bytes.data() + kDeviceRecordingHeaderBytes + i * kDeviceRecordingRecordBytes;
    RecordedSample& r = rec.samples[i];
    r.tick = get<int64_t>(p);
    double d[12];
    std::memcpy(d, p + 8, sizeof(d));
    DeviceSample& s = r.sample;
    s.time_s = d[0];
    s.position_W = {d[1], d[2], d[3]};
    s.orientation_W = Eigen::Quaterniond(d[4], d[5], d[6], d[7]);
    s.velocity_W = {d[8], d[9], d[10]};
    s.gripper_angle_rad = d[11];
    s.buttons = get<uint32_t>(p + 104);
    const auto status = get<uint32_t>(p + 108);
    const std::string where =
        "record " + std::to_string(i) + " (at byte " +
        std::to_string(kDeviceRecordingHeaderBytes + i * kDeviceRecordingRecordBytes) + "): ";
    if (r.tick != static_cast<int64_t>(i)) {
      return fail(where + "tick " + std::to_string(r.tick) + ": expected tick " +
                  std::to_string(i) + " (records are one per tick, in order)");
    }
    for (const double x : d) {
      if (!std::isfinite(x))
        return fail(where + "expected finite values, found " + std::to_string(x));
    }
    if (status > static_cast<uint32_t>(DeviceStatus::kError)) {
      return fail(where + "status " + std::to_string(status) + ": expected 0 to 3");
    }
    r.status = static_cast<DeviceStatus>(status);
  }
  return rec;
}

}  // namespace lap::hardware
