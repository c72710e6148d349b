#pragma once
/// \file
/// The session the trainee window runs (docs/architecture.md, "The three loops"): the haptic and
/// modelling loops on their own threads (sim::Session in real time), two simulated devices the
/// keyboard drives, and the window as the graphics loop, reading the newest snapshots each frame.

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "hardware/device_spec.h"
#include "hardware/simulated_device.h"
#include "sim/runtime/session.h"

namespace lap::app {

class LiveSession {
 public:
  LiveSession() = default;
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;
  LiveSession(LiveSession&&) = delete;
  LiveSession& operator=(LiveSession&&) = delete;
  ~LiveSession() { stop(); }

  /// Starts the loops on the scene with the given devices (`simulated`: driven by the keyboard
  /// and mouse; `scripted:FILE`, `replay:FILE` — a saved session played back for review —,
  /// `phantom:NAME`: hardware/README.md); the diagnostics say why not.
  [[nodiscard]] Status start(const sim::Scene& scene,
                             const std::array<hardware::DeviceSpec, 2>& devices);
  void stop();
  /// Ends the session (the loops stop) and writes its inputs and metrics into `dir`
  /// (left.lapdev, right.lapdev, metrics.json: sim::save_session); the diagnostics name the
  /// file on failure. The session is over either way.
  [[nodiscard]] Status stop_and_save(const std::string& dir);
  [[nodiscard]] bool running() const { return session_ != nullptr; }
  /// The running session (for the authoring panel's live tuning); null when none runs.
  [[nodiscard]] sim::Session* session() { return session_.get(); }
  /// The last session's metrics, once it has stopped (its loops' statistics among them).
  [[nodiscard]] const sim::SessionMetrics& last_metrics() const { return metrics_; }
  /// Scheduling problems the loops met (SCHED_FIFO, mlockall refused); empty when all is well.
  [[nodiscard]] std::vector<std::string> scheduling_warnings() const {
    return session_ ? session_->scheduling_warnings() : std::vector<std::string>{};
  }

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
  /// Each organ's name (for naming a faulted model in the status bar); empty with no session.
  [[nodiscard]] std::vector<std::string> organ_names() const {
    return session_ ? session_->model().organ_names() : std::vector<std::string>{};
  }
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
  sim::SessionMetrics metrics_;  // written by the runner, read after it is joined
  std::string scenario_;
};

}  // namespace lap::app
