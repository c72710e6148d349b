#pragma once
/// \file
/// A recorded session replayed once for the instructor's review, keeping what its 3D view draws
/// at a low rate — each tool's pose, the catheter's particles, the organs' deformation — so that
/// seeking anywhere in it is a lookup (a binary search over the frames) and playing, pausing,
/// scrubbing and changing speed never replays the session again. The replay is
/// replay_session's (the same metrics, series and task: the plots' source); the frames are taken
/// through Session::observe_fast as it runs.
///
/// A frame's organ deformations are kept compact (their `count` entries only): a 10-minute
/// session at 20 frames a second is 12 000 frames.

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "haptics/laparoscopic_gripper.h"
#include "haptics/triangle_mesh.h"
#include "sim/report/session_replay.h"
#include "sim/runtime/session.h"
#include "sim/setup/scenario.h"
#include "sim/setup/scene.h"

namespace lap::sim {

/// One frame: what the 3D view shows at `t_s`.
struct ReplayFrame {
  int64_t tick = 0;
  double t_s = 0.0;                             ///< tick × the haptic period
  std::array<haptics::GripperPose, 2> tools{};  ///< left, right
  /// Each tool's three segment proxies and their contact normals (ToolSnapshot's), so that the
  /// replay draws the instruments resting on the tissue as the live view did.
  std::array<std::array<Eigen::Vector3d, 3>, 2> proxy_a_W{};
  std::array<std::array<Eigen::Vector3d, 3>, 2> proxy_b_W{};
  std::array<std::array<Eigen::Vector3d, 3>, 2> proxy_normal_W{};
  int64_t model_steps = 0;
  std::vector<Eigen::Vector3d> catheter;   ///< particle positions [m]
  std::vector<SurfaceDeformation> organs;  ///< compact: `count` entries each
};

/// What the 3D view needs once: the organs at rest as the session has them (the duct: its
/// shell), their colours, the tools' geometry, the catheter's particle count, the camera.
struct ReplayScene {
  std::vector<haptics::TriangleMesh> organ_surfaces;
  std::vector<Eigen::Vector3d> organ_colours;
  /// Each organ's colour texture (null: drawn in its colour), as the scene loaded it.
  std::vector<std::shared_ptr<const haptics::RgbImage>> organ_albedos;
  std::array<haptics::GripperGeometry, 2> tools{};
  std::array<std::string, 2> tool_kinds{};  ///< the scenario's kind (grasper, dissector, ...)
  std::array<double, 2> tool_shaft_radius_m{0.0025, 0.0025};
  std::array<Eigen::Vector3d, 2> tool_port_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  int catheter_points = 0;  ///< -1: the scenario has no catheter to draw
  double catheter_radius_m = 0.0;
  CameraSpec camera;
};

class ReplayTimeline {
 public:
  static constexpr double kDefaultFramePeriodS = 0.05;

  /// Replays the recorded session in `dir` (replay_session), keeping a frame every
  /// `frame_period_s` of session time. `progress(fraction)` is called as it goes, on the
  /// replaying thread; returning false stops the replay there (what was replayed is kept, and
  /// a note says so).
  [[nodiscard]] static Result<ReplayTimeline> replay(
      const std::filesystem::path& dir, double frame_period_s = kDefaultFramePeriodS,
      const std::function<bool(double fraction)>& progress = {});
  /// The frames the session kept in its recording (DIR/session.lrec, LAPREC05: one every 0.1 s,
  /// recorded_frames.h) over its scenario, without a replay: what the review shows at once,
  /// while the replay that recomputes the figures runs. `session()` holds the record, the
  /// scenario's name and task and the notes, no metrics; damaged frames are in its
  /// recording_problems. Diagnostics for a recording without frames (before LAPREC05).
  [[nodiscard]] static Result<ReplayTimeline> from_recorded_frames(
      const std::filesystem::path& dir);
  /// A timeline from frames already made (tests, benchmarks): `frames` in time order.
  [[nodiscard]] static ReplayTimeline from_frames(ReplayScene scene,
                                                  std::vector<ReplayFrame> frames);

  /// The frame at or before `t_s` (within 1 ns: frame times are tick × period, rounded), the
  /// first for a time before it, the last after the end.
  [[nodiscard]] size_t seek(double t_s) const;
  [[nodiscard]] size_t size() const { return frames_.size(); }
  [[nodiscard]] const ReplayFrame& frame(size_t i) const { return frames_[i]; }
  /// The last frame's time [s]; 0 without frames.
  [[nodiscard]] double duration_s() const;

  /// Frame `i` as the snapshots the 3D view's actors take (app/tool_actors.h), written into
  /// `haptic` and `model` (whose storage is reused from call to call).
  void snapshots(size_t i, HapticSnapshot* haptic, ModelSnapshot* model) const;

  [[nodiscard]] const ReplayScene& scene() const { return scene_; }
  /// The replay's metrics, series, task and notes (the plots' and the report's source).
  [[nodiscard]] const ReplayedSession& session() const { return session_; }

 private:
  ReplayScene scene_;
  std::vector<ReplayFrame> frames_;
  ReplayedSession session_;
};

/// What the 3D view needs once, from a session set up over `scene` (its organs as the session
/// has them: the duct its shell).
[[nodiscard]] ReplayScene replay_scene(const Session& session, const Scene& scene);

/// `d` with its `count` entries only.
[[nodiscard]] SurfaceDeformation compact(const SurfaceDeformation& d);

}  // namespace lap::sim
