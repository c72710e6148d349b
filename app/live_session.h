#pragma once
/// \file
/// The session the trainee window runs (ARCHITECTURE.md "Three loops"): the haptic and
/// modelling loops on their own threads (sim::Session in real time), two simulated devices the
/// keyboard drives, and the window as the graphics loop, reading the newest snapshots each frame.

#include <memory>
#include <string>
#include <thread>

#include "hardware/simulated_device.h"
#include "sim/session.h"

namespace lap::app {

class LiveSession {
 public:
  LiveSession() = default;
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;
  LiveSession(LiveSession&&) = delete;
  LiveSession& operator=(LiveSession&&) = delete;
  ~LiveSession() { stop(); }

  /// Starts the loops on the scene with two simulated tools; false and *error on failure.
  bool start(const sim::Scene& scene, std::string* error);
  void stop();
  [[nodiscard]] bool running() const { return session_ != nullptr; }

  /// UI thread: move a simulated tool's handle by `delta` [m] and open its jaws by `opening`.
  void nudge(int tool, const Eigen::Vector3d& delta, double opening_rad);
  void resume() {
    if (session_) session_->resume();
  }

  /// UI thread (the graphics loop is the snapshots' one reader).
  const sim::HapticSnapshot& haptic() { return session_->graphics_haptic(); }
  const sim::ModelSnapshot& model() { return session_->graphics_model(); }
  /// The organs' surfaces at rest as the session has them (ModelSnapshot::organs deforms them).
  [[nodiscard]] int32_t organ_count() const { return session_->organ_count(); }
  [[nodiscard]] const haptics::TriangleMesh& organ_surface(int32_t organ) const {
    return session_->organ_surface(organ);
  }
  /// The tools' shaft and jaw lengths, as the session renders them.
  [[nodiscard]] const haptics::GripperGeometry& tool_geometry(int tool) const {
    return session_->tool_geometry(tool);
  }

 private:
  std::unique_ptr<sim::Session> session_;
  std::array<hardware::SimulatedDevice*, 2> devices_{};
  std::array<hardware::SimulatedInput, 2> inputs_{};
  std::thread runner_;
};

}  // namespace lap::app
