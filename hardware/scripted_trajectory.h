#pragma once
/// \file
/// A keyframed tool trajectory for the scripted device: a CSV file, one keyframe per line,
///
///     time_s,x_m,y_m,z_m,qw,qx,qy,qz,gripper_rad[,buttons]
///
/// in the world frame (metres, seconds, radians). Blank lines and lines starting with '#' are
/// skipped; a first line that does not start with a number is a header. Times must increase
/// strictly; quaternions need not be unit (they are normalised) but must not be zero.
/// Between keyframes the position and the gripper angle are interpolated linearly and the
/// orientation by slerp, so a keyframe is reproduced exactly at its own time.

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"
#include "hardware/haptic_device.h"

namespace lap::hardware {

/// Limits on a script, which may come from anywhere: most keyframes (a million is 1000 s at
/// 1 kHz, beyond any hand-written or exported motion; longer runs are recordings), and the
/// largest file [bytes] (a million keyframes of about 100 characters, twice over).
inline constexpr size_t kMaxKeyframes = 1'000'000;
inline constexpr uint64_t kMaxScriptFileBytes = 256ULL * 1024 * 1024;

struct Keyframe {
  double time_s = 0.0;
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_W = Eigen::Quaterniond::Identity();
  double gripper_angle_rad = 0.0;
  uint32_t buttons = 0;
};

struct ScriptedTrajectory {
  std::vector<Keyframe> keyframes;  ///< at least one, strictly increasing times

  [[nodiscard]] double duration_s() const {
    return keyframes.empty() ? 0.0 : keyframes.back().time_s;
  }
  /// The sample at time t (held at the ends); `cursor` is the keyframe search's start and is
  /// updated, so a forward sweep costs O(1) per call.
  void sample(double t, size_t* cursor, DeviceSample* out) const;
};

/// Parses the CSV text; on failure a diagnostic at `source:line` naming the field.
[[nodiscard]] Result<ScriptedTrajectory> parse_scripted_trajectory(const std::string& text,
                                                                   const std::string& source);

/// Reads and parses a trajectory file.
[[nodiscard]] Result<ScriptedTrajectory> load_scripted_trajectory(
    const std::filesystem::path& file);

}  // namespace lap::hardware
