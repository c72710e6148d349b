#pragma once
/// \file
/// What the 3D view draws, kept by a recording session at a low rate (issue 24: "model
/// snapshots at a low rate for fast seeking"): every kFramePeriodS of session time the
/// modelling thread copies the tools it read and the models it stepped into a slot of this ring,
/// and the recorder's thread writes the slots to the file as frames chunks. A review then
/// seeks anywhere in a recording by reading one chunk (sim/report/recorded_frames.h) instead of
/// replaying the session up to there.
///
/// One writer (the modelling thread), one reader (the recorder's thread). The slots are sized at
/// set-up from the session's catheter and organs, so that writing one never allocates; when the
/// reader falls kSlots frames behind, a frame is dropped and counted (frames serve seeking only:
/// the ticks, which a replay needs, are kept apart).

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "haptics/laparoscopic_gripper.h"
#include "sim/runtime/deformed_surface.h"

namespace lap::sim {

/// One frame: the tools as the modelling step read them, the catheter and the organs as it left
/// them.
struct RecordedFrame {
  int64_t tick = 0;         ///< the haptic tick the modelling step is labelled with
  int64_t model_steps = 0;  ///< modelling steps so far, this one included
  std::array<haptics::GripperPose, 2> tools{};  ///< left, right
  /// Each tool's three segment proxies (shaft, jaw 0, jaw 1) and their contact normals, so that a
  /// replay draws the instruments resting on the tissue as the live view did.
  std::array<std::array<Eigen::Vector3d, 3>, 2> proxy_a_W{};
  std::array<std::array<Eigen::Vector3d, 3>, 2> proxy_b_W{};
  std::array<std::array<Eigen::Vector3d, 3>, 2> proxy_normal_W{};
  std::vector<Eigen::Vector3d> catheter;   ///< particle positions [m]
  std::vector<SurfaceDeformation> organs;  ///< each organ's displaced vertices: `count` entries
};

class FrameRing {
 public:
  static constexpr double kFramePeriodS = 0.1;
  static constexpr int64_t kSlots = 16;  ///< 1.6 s of frames: the recorder drains every 40 ms

  /// Sizes every slot for `catheter_points` particles and organs sized as `organs`
  /// (TissueWorld::make_deformations).
  void reserve(size_t catheter_points, const std::vector<SurfaceDeformation>& organs);
  [[nodiscard]] bool reserved() const { return !slots_.empty(); }

  /// Writer: the slot to fill next, or null when the reader has not freed one (the frame is
  /// dropped and counted). Never allocates. With `wait_for_room` (a --fast session, which runs
  /// many times faster than the recorder's flushes and is not real time) it waits for the
  /// reader instead of dropping.
  [[nodiscard]] RecordedFrame* begin_write(bool wait_for_room = false) noexcept;
  /// Writer: the slot begin_write() gave is complete.
  void publish() noexcept;
  [[nodiscard]] int64_t dropped() const noexcept {
    return dropped_.load(std::memory_order_relaxed);
  }

  /// Reader: frames published so far (acquire), and frame `n`'s slot while n lies between
  /// released() and published().
  [[nodiscard]] int64_t published() const noexcept {
    return published_.load(std::memory_order_acquire);
  }
  [[nodiscard]] const RecordedFrame& frame(int64_t n) const noexcept {
    return slots_[static_cast<size_t>(n % kSlots)];
  }
  /// Reader: frames before `n` are written out; their slots may be filled again.
  void release(int64_t n) noexcept { released_.store(n, std::memory_order_release); }
  [[nodiscard]] int64_t released() const noexcept {
    return released_.load(std::memory_order_relaxed);
  }
  /// Reader: half the slots or more wait to be written (flush now rather than at the period).
  [[nodiscard]] bool filling() const noexcept { return published() - released() >= kSlots / 2; }
  /// Reader: it will release no more (the recording stopped); a waiting writer drops instead.
  void close() noexcept { closed_.store(true, std::memory_order_release); }

 private:
  std::vector<RecordedFrame> slots_;
  std::atomic<int64_t> published_{0};
  std::atomic<int64_t> released_{0};
  std::atomic<int64_t> dropped_{0};
  std::atomic<bool> closed_{false};
};

}  // namespace lap::sim
