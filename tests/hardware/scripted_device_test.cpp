#include "hardware/scripted_device.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "hardware/scripted_trajectory.h"

namespace lap::hardware {
namespace {

const char* const kScript =
    "time_s,x_m,y_m,z_m,qw,qx,qy,qz,gripper_rad\n"
    "# start at rest, closed\n"
    "0.000, 0.0, 0.1, 0.0, 1, 0, 0, 0, 0.0\n"
    "0.010, 0.01, 0.1, 0.0, 1, 0, 0, 0, 0.5\n"
    "0.030, 0.01, 0.1, 0.02, 0, 0, 0, 1, 0.5, 3\n";

ScriptedTrajectory parse_ok(const std::string& text) {
  Result<ScriptedTrajectory> t = parse_scripted_trajectory(text, "test.csv");
  EXPECT_TRUE(t.ok()) << t.message();
  return t.ok() ? std::move(t).value() : ScriptedTrajectory{};
}

std::string parse_error(const std::string& text) {
  const Result<ScriptedTrajectory> t = parse_scripted_trajectory(text, "bad.csv");
  EXPECT_FALSE(t.ok());
  return t.message();
}

TEST(ScriptedTrajectory, ReproducesEveryKeyframeExactlyAtItsTick) {
  ScriptedDevice dev(parse_ok(kScript), "left");
  const Status started = dev.start();
  ASSERT_TRUE(started.ok()) << started.message();
  const double dt = 0.001;
  DeviceSample s;
  // Ticks 0, 10 and 30 fall on the keyframes: the very values of the file.
  for (const auto& [tick, index] : {std::pair<int64_t, size_t>{0, 0}, {10, 1}, {30, 2}}) {
    const Keyframe& k = dev.trajectory().keyframes[index];
    ASSERT_EQ(dev.read(tick, dt, &s), DeviceStatus::kOk);
    EXPECT_EQ(s.position_W, k.position_W) << "tick " << tick;
    EXPECT_EQ(s.gripper_angle_rad, k.gripper_angle_rad);
    EXPECT_EQ(s.orientation_W.coeffs(), k.orientation_W.coeffs());
    EXPECT_EQ(s.buttons, k.buttons);
  }
}

TEST(ScriptedTrajectory, InterpolatesLinearlyAndBySlerpBetweenKeyframes) {
  ScriptedDevice dev(parse_ok(kScript), "left");
  ASSERT_TRUE(dev.start().ok());
  const double dt = 0.001;
  DeviceSample s;
  for (int64_t tick = 0; tick <= 30; ++tick) {
    ASSERT_EQ(dev.read(tick, dt, &s), DeviceStatus::kOk);
    const double t = static_cast<double>(tick) * dt;
    // Analytic: x ramps 0 → 10 mm over the first 10 ms, then z 0 → 20 mm over 20 ms.
    const double x = t <= 0.010 ? t : 0.01;
    const double z = t <= 0.010 ? 0.0 : (t - 0.010);
    EXPECT_NEAR(s.position_W.x(), x, 1e-15) << tick;
    EXPECT_NEAR(s.position_W.z(), z, 1e-15) << tick;
    EXPECT_NEAR(s.gripper_angle_rad, t <= 0.010 ? 50.0 * t : 0.5, 1e-14) << tick;
    // The second leg turns 180° about z at a constant rate: the angle is linear in time.
    if (t > 0.010) {
      const double angle = 2.0 * std::acos(std::min(1.0, std::abs(s.orientation_W.w())));
      EXPECT_NEAR(angle, M_PI * (t - 0.010) / 0.020, 1e-9) << tick;
    }
  }
  ASSERT_EQ(dev.read(20, dt, &s), DeviceStatus::kOk);
  EXPECT_NEAR(s.velocity_W.z(), 1.0, 1e-12);  // 20 mm in 20 ms
}

TEST(ScriptedTrajectory, HoldsTheLastKeyframeAndSaysItFinished) {
  ScriptedDevice dev(parse_ok(kScript), "left");
  ASSERT_TRUE(dev.start().ok());
  DeviceSample s;
  EXPECT_EQ(dev.read(31, 0.001, &s), DeviceStatus::kFinished);
  EXPECT_EQ(s.position_W, Eigen::Vector3d(0.01, 0.1, 0.02));
  EXPECT_EQ(s.velocity_W, Eigen::Vector3d::Zero());
  // Reading backwards (a new session) starts over.
  EXPECT_EQ(dev.read(0, 0.001, &s), DeviceStatus::kOk);
  EXPECT_EQ(s.position_W, Eigen::Vector3d(0.0, 0.1, 0.0));
}

// A leading '+' is a number's sign, as a spreadsheet writes it.
TEST(ScriptedTrajectory, ReadsAPlusSignAsASpreadsheetWritesIt) {
  const ScriptedTrajectory t = parse_ok("+0,+0.01,-0.02,+1e-1,+1,0,0,0,+0.5,+3\n");
  ASSERT_EQ(t.keyframes.size(), 1U);
  EXPECT_EQ(t.keyframes[0].position_W, Eigen::Vector3d(0.01, -0.02, 0.1));
  EXPECT_EQ(t.keyframes[0].gripper_angle_rad, 0.5);
  EXPECT_EQ(t.keyframes[0].buttons, 3U);
}

TEST(ScriptedTrajectory, BadFilesNameTheLineAndTheField) {
  EXPECT_EQ(parse_error("0,0,0,0,1,0,0,0,0\n0.01,0,0,0,1,0,0,0\n"),
            "bad.csv:2: expected 9 or 10 comma-separated fields "
            "(time_s,x_m,y_m,z_m,qw,qx,qy,qz,gripper_rad[,buttons]), got 8");
  EXPECT_EQ(parse_error("t,x\n0,0,0,abc,1,0,0,0,0\n"),
            "bad.csv:2: z_m: expected a finite number, got 'abc'");
  EXPECT_EQ(parse_error("0,0,0,0,1,0,0,0,0\n0,0,0,0,1,0,0,0,0\n"),
            "bad.csv:2: time_s: expected times to increase, 0 does not follow the previous "
            "keyframe");
  EXPECT_EQ(parse_error("0,0,0,0,0,0,0,0,0\n"),
            "bad.csv:1: qw,qx,qy,qz: expected a non-zero quaternion");
  EXPECT_EQ(parse_error("0,0,0,0,1,0,0,0,0,1.5\n"),
            "bad.csv:1: buttons: expected a whole number from 0 to 4294967295");
  EXPECT_EQ(parse_error("0,0,0,nan,1,0,0,0,0\n"),
            "bad.csv:1: z_m: expected a finite number, got 'nan'");
  EXPECT_EQ(parse_error("# nothing\n"), "bad.csv:1: expected at least one keyframe");
  EXPECT_EQ(parse_error("0,0,0,+-1,1,0,0,0,0\n"),
            "bad.csv:1: z_m: expected a finite number, got '+-1'");
  EXPECT_EQ(parse_error("0,0,0,+,1,0,0,0,0\n"),
            "bad.csv:1: z_m: expected a finite number, got '+'");
  const Result<ScriptedTrajectory> missing = load_scripted_trajectory("/nonexistent/path.csv");
  EXPECT_FALSE(missing.ok());
  EXPECT_EQ(missing.message(),
            "/nonexistent/path.csv: not found (expected a keyframe script (CSV))");
}

// Issue 25: limits on an untrusted script (hardware/scripted_trajectory.h).
TEST(ScriptedTrajectory, MoreKeyframesThanTheLimitAreRefusedAtTheLineThatPassesIt) {
  std::string text;
  text.reserve((kMaxKeyframes + 1) * 24);
  for (size_t i = 0; i <= kMaxKeyframes; ++i) text += std::to_string(i) + ",0,0,0,1,0,0,0,0\n";
  EXPECT_EQ(parse_error(text), "bad.csv:" + std::to_string(kMaxKeyframes + 1) +
                                   ": expected at most 1000000 keyframes (the limit, "
                                   "hardware/scripted_trajectory.h)");
}

TEST(ScriptedTrajectory, AFileLargerThanTheLimitIsRefusedUnread) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("lap-big-script-" + std::to_string(getpid()) + ".csv");
  { std::ofstream(file) << "0,0,0,0,1,0,0,0,0\n"; }
  std::filesystem::resize_file(file, kMaxScriptFileBytes + 1);  // sparse
  const Result<ScriptedTrajectory> t = load_scripted_trajectory(file);
  std::filesystem::remove(file);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.message(), file.string() +
                             ": file of 268435457 bytes is larger than the limit of "
                             "268435456 for a keyframe script (CSV) "
                             "(hardware/scripted_trajectory.h)");
}

}  // namespace
}  // namespace lap::hardware
