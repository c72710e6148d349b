#pragma once
/// \file
/// Dynamic resolution for the fast picture (render_quality.h): once a second the 3D picture's
/// size is adjusted from the frame rate of the second before, so that the trainee's view holds
/// 30 frames/s with what the machine has, whatever the patient, the window's size and the
/// other load. A second without frames (a hidden window) changes nothing.

namespace lap::app {

/// The fast picture's 3D side is never smaller than this fraction of the window's.
inline constexpr double kMinSceneScale = 0.5;

/// The scale for the next second from the frame rate of the last: 7 % smaller below 30.9
/// frames/s (down to kMinSceneScale), 5 % larger above 40.5 (up to 1), else unchanged (the
/// gap keeps it from hunting).
[[nodiscard]] double next_scene_scale(double scale, double frames_per_s);

}  // namespace lap::app
