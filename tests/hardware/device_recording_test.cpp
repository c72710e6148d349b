#include "hardware/device_recording.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "hardware/replay_device.h"
#include "tests/support/small_disk.h"
#include "tests/test_support.h"

namespace lap::hardware {
namespace {

namespace fs = std::filesystem;

DeviceRecording make_recording(int n) {
  DeviceRecording r;
  r.period_s = 0.001;
  for (int i = 0; i < n; ++i) {
    RecordedSample s;
    s.tick = i;
    s.sample.time_s = 0.001 * i;
    // Values with full mantissas, so a lossy format would show.
    s.sample.position_W = {std::sin(i * 0.1), 1.0 / 3.0 + i, std::exp(-0.01 * i)};
    s.sample.orientation_W =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d(1, 2, 3).normalized()));
    s.sample.velocity_W = {0.1 * i, -0.2, M_PI};
    s.sample.gripper_angle_rad = 0.5 + 1e-17 * i;
    s.sample.buttons = static_cast<uint32_t>(i % 3);
    s.status = i == n - 1 ? DeviceStatus::kFinished : DeviceStatus::kOk;
    r.samples.push_back(s);
  }
  return r;
}

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("laptrainer_" + std::to_string(::getpid()) + "_" + name);
}

TEST(DeviceRecording, RoundTripsBitForBitAndReplaysIt) {
  const DeviceRecording r = make_recording(100);
  const fs::path f = temp_file("roundtrip.lapdev");
  const Status written = write_device_recording(f, r);
  ASSERT_TRUE(written.ok()) << written.message();
  EXPECT_EQ(fs::file_size(f), kDeviceRecordingHeaderBytes + 100 * kDeviceRecordingRecordBytes);
  const Result<DeviceRecording> back = read_device_recording(f);
  ASSERT_TRUE(back.ok()) << back.message();
  ASSERT_EQ(back->samples.size(), 100U);
  EXPECT_EQ(back->period_s, 0.001);
  ReplayDevice replay(back.value(), "left");
  ASSERT_TRUE(replay.start().ok());
  for (int i = 0; i < 100; ++i) {
    DeviceSample s;
    const DeviceStatus st = replay.read(i, 0.001, &s);
    const RecordedSample& want = r.samples[static_cast<size_t>(i)];
    EXPECT_EQ(st, want.status);
    EXPECT_EQ(std::memcmp(s.position_W.data(), want.sample.position_W.data(), 24), 0) << i;
    EXPECT_EQ(
        std::memcmp(s.orientation_W.coeffs().data(), want.sample.orientation_W.coeffs().data(), 32),
        0);
    EXPECT_EQ(s.velocity_W, want.sample.velocity_W);
    EXPECT_EQ(s.gripper_angle_rad, want.sample.gripper_angle_rad);
    EXPECT_EQ(s.buttons, want.sample.buttons);
  }
  DeviceSample past;
  EXPECT_EQ(replay.read(100, 0.001, &past), DeviceStatus::kFinished);
  fs::remove(f);
}

// On a disk with no space left (the kernel's ENOSPC, on a small tmpfs of the test's own:
// tests/support/small_disk.h), a recording is written whole or not at all: the error names the
// file and the reason, no cut-off recording or temporary file is left, and an older recording of
// that name stays as it was. Skipped, saying why, where no such disk can be mounted.
TEST(DeviceRecording, ADiskWithNoSpaceLeftGetsNoCutOffRecording) {
  const test::TempDir dir;
  const fs::path disk = dir.path() / "disk";
  fs::create_directory(disk);
  const test::SmallDiskRun run = test::run_on_a_small_disk(disk, 64U * 1024U, [&] {
    if (!write_device_recording(disk / "old.lapdev", make_recording(10)).ok()) return 3;
    test::fill_the_disk(disk / "filler", 64U * 1024U);
    const Status written = write_device_recording(disk / "old.lapdev", make_recording(2000));
    std::ofstream out(dir.path() / "report.txt");
    out << (written.ok() ? "written" : written.message()) << "\n";
    for (const auto& e : fs::directory_iterator(disk)) out << e.path().filename().string() << "\n";
    std::error_code e;
    fs::copy_file(disk / "old.lapdev", dir.path() / "old.lapdev", e);
    return e ? 4 : 0;
  });
  if (!run.ran) GTEST_SKIP() << "no small disk could be mounted here: " << run.why_not;
  ASSERT_EQ(run.exit_code, 0) << "3: the first recording was not written, 4: not copied out";
  std::vector<std::string> report = test::lines_of(test::read_file(dir.path() / "report.txt"));
  ASSERT_FALSE(report.empty());
  EXPECT_EQ(report[0], (disk / "old.lapdev").string() + ": cannot write the device recording: " +
                           std::strerror(ENOSPC) + " (nothing of it was written)");
  std::sort(report.begin() + 1, report.end());
  EXPECT_EQ(report, (std::vector<std::string>{report[0], "filler", "old.lapdev"}));
  const Result<DeviceRecording> old = read_device_recording(dir.path() / "old.lapdev");
  ASSERT_TRUE(old.ok()) << old.message();
  EXPECT_EQ(old->samples.size(), 10U);
}

TEST(DeviceRecording, TruncatedAndForeignFilesAreClearErrors) {
  const fs::path f = temp_file("bad.lapdev");
  ASSERT_TRUE(write_device_recording(f, make_recording(10)).ok());
  fs::resize_file(f, kDeviceRecordingHeaderBytes + 3 * kDeviceRecordingRecordBytes + 5);
  Result<DeviceRecording> loaded = read_device_recording(f);
  EXPECT_FALSE(loaded.ok());
  EXPECT_EQ(loaded.message(),
            f.string() +
                ": ends inside record 3 (at byte 368, 5 stray bytes): the file is "
                "truncated");

  { std::ofstream(f, std::ios::binary | std::ios::trunc) << "hello, not a recording at all....."; }
  loaded = read_device_recording(f);
  EXPECT_FALSE(loaded.ok());
  EXPECT_EQ(loaded.message(),
            f.string() +
                ": at byte 0: not a laptrainer device recording (expected the header 'LAPDEV01')");

  // Records out of order.
  DeviceRecording r = make_recording(4);
  r.samples[2].tick = 7;
  ASSERT_TRUE(write_device_recording(f, r).ok());
  loaded = read_device_recording(f);
  EXPECT_FALSE(loaded.ok());
  EXPECT_EQ(
      loaded.message(),
      f.string() +
          ": record 2 (at byte 256): tick 7: expected tick 2 (records are one per tick, in order)");

  // A non-finite value.
  r = make_recording(4);
  r.samples[1].sample.position_W.y() = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(write_device_recording(f, r).ok());
  loaded = read_device_recording(f);
  EXPECT_FALSE(loaded.ok());
  EXPECT_NE(loaded.message().find("record 1 (at byte 144): expected finite values"),
            std::string::npos)
      << loaded.message();

  loaded = read_device_recording(temp_file("missing.lapdev"));
  EXPECT_FALSE(loaded.ok());
  EXPECT_NE(loaded.message().find("missing.lapdev: not found (expected a device recording"),
            std::string::npos)
      << loaded.message();
  fs::remove(f);
}

}  // namespace
}  // namespace lap::hardware
