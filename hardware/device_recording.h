#pragma once
/// \file
/// A device's inputs over a session, one sample per haptic tick, as the replay device reads
/// them back. Binary, so that a replay feeds the very same doubles in (bit-for-bit, as
/// `run --fast` promises): a 32-byte header
///
///     "LAPDEV01" | uint32 version (1) | uint32 record size (112) | double period_s | 8 reserved
///
/// then one 112-byte record per tick: int64 tick, double time_s, double position[3],
/// double orientation[4] (w, x, y, z), double velocity[3], double gripper_angle_rad,
/// uint32 buttons, uint32 status. Little-endian IEEE 754, as written by x86-64 and arm64 Linux.
/// The record count is the file's length: a session cut short keeps every whole record.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"
#include "hardware/haptic_device.h"

namespace lap::hardware {

struct RecordedSample {
  int64_t tick = 0;
  DeviceSample sample;
  DeviceStatus status = DeviceStatus::kOk;
};

struct DeviceRecording {
  double period_s = 0.001;
  std::vector<RecordedSample> samples;
};

inline constexpr size_t kDeviceRecordingHeaderBytes = 32;
inline constexpr size_t kDeviceRecordingRecordBytes = 112;
/// The largest recording read: three hours at 1 kHz is 1.2 GB (a window's session records its
/// first ten minutes, 67 MB); anything larger, and anything but a regular file (/dev/zero, a
/// FIFO), is refused unread.
inline constexpr uint64_t kMaxDeviceRecordingBytes = uint64_t{2} << 30;

/// Writes the recording whole or not at all (core/whole_file.h: a full disk leaves no cut-off
/// recording, and an older file of that name as it was); a diagnostic naming the file and the
/// system's reason on failure.
[[nodiscard]] Status write_device_recording(const std::filesystem::path& file,
                                            const DeviceRecording& recording);

/// Reads a recording and checks it: a regular file of at most kMaxDeviceRecordingBytes, header,
/// whole records, ticks 0, 1, 2, ... in order, finite values, known status codes. Diagnostics
/// name the file and the record.
[[nodiscard]] Result<DeviceRecording> read_device_recording(const std::filesystem::path& file);

}  // namespace lap::hardware
