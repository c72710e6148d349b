#pragma once
/// \file
/// The session the trainee window runs (docs/architecture.md, "The three loops"): the haptic and
/// modelling loops on their own threads (sim::Session in real time), two simulated devices the
/// keyboard drives, and the window as the graphics loop, reading the newest snapshots each frame.
///
/// How it runs is set before start() (LiveSessionOptions): a training attempt ends with its task
/// (success or failure: finished() then says so, and the window shows the result), is streamed
/// to its folder while it runs (session.lrec: a crash leaves a reviewable, interrupted session)
/// and can be paused by the trainee (pause(): zero force, the task's clock stopped).

#include <algorithm>
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "hardware/device_spec.h"
#include "hardware/simulated_device.h"
#include "hardware/tool_nudge.h"
#include "sim/runtime/session.h"

namespace lap::app {

/// How the next session runs (LiveSession::set_options, before start()).
struct LiveSessionOptions {
  /// The session ends when its task ends (success or failure) or when every scripted or replayed
  /// device has run out; it then runs for the task's time limit and a minute more at most.
  /// Otherwise it goes on until stopped (24 hours at most; the first ten minutes recorded).
  bool end_with_task = false;
  /// Lockstep, as fast as the computer can (RuntimeSettings::fast): the result a function of the
  /// inputs only. Scripted and replayed devices only (start() refuses it with a live one).
  bool fast = false;
  /// Stream the session into this folder as it runs (session.json, session.lrec); empty: not.
  std::string record_dir;
  /// The trainee's dominant hand (0 left, 1 right), for the handedness metrics.
  int dominant_tool = 1;
};

class LiveSession {
 public:
  LiveSession() = default;
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;
  LiveSession(LiveSession&&) = delete;
  LiveSession& operator=(LiveSession&&) = delete;
  ~LiveSession() { stop(); }

  /// How the sessions started from now on run.
  void set_options(const LiveSessionOptions& options) { options_ = options; }
  [[nodiscard]] const LiveSessionOptions& options() const { return options_; }

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
  /// The session has ended by itself (its task ended, its devices ran out, its time was up):
  /// the loops have stopped; stop() or stop_and_save() collects it.
  [[nodiscard]] bool finished() const { return finished_.load(std::memory_order_acquire); }
  /// The last session's metrics, once it has stopped (its loops' statistics among them).
  [[nodiscard]] const sim::SessionMetrics& last_metrics() const { return metrics_; }
  /// The scenario file the running (or last) session is on.
  [[nodiscard]] const std::string& scenario_file() const { return scenario_; }
  /// Scheduling problems the loops met (SCHED_FIFO, mlockall refused); empty when all is well.
  [[nodiscard]] std::vector<std::string> scheduling_warnings() const {
    return session_ ? session_->scheduling_warnings() : std::vector<std::string>{};
  }

  /// UI thread: move a simulated tool by `n` (hardware::nudged: the handle kept in the device's
  /// workspace, the roll about the shaft from the handle through the tool's port, so the jaws'
  /// opening direction turns by as much) (ignored while paused: the tools stay where they were).
  void nudge(int tool, const hardware::ToolNudge& n);
  /// Where the keys, mouse and 3D mouse have asked a keyboard-driven tool's handle to be (its
  /// device follows at the hand's speeds: hardware::SimulatedHandSpeeds).
  [[nodiscard]] const hardware::SimulatedInput& input(int tool) const {
    return inputs_[static_cast<size_t>(std::clamp(tool, 0, 1))];
  }
  /// Takes a simulated tool back to where it started (sim::home_handle_position: in view,
  /// pointing at the task's target, the jaws half open).
  void go_home(int tool);
  /// Whether tool `tool` (0 left, 1 right) is driven from the keyboard, mouse and 3D mouse.
  [[nodiscard]] bool keyboard_driven(int tool) const {
    return session_ && tool >= 0 && tool < 2 && devices_[static_cast<size_t>(tool)] != nullptr;
  }

  /// The trainee's pause (sim::Session::hold): both devices sent zero force at once, the loops
  /// stopped, the task's clock with them; a --fast session cannot be paused.
  void pause();
  /// Ends the trainee's pause and a watchdog's pause alike; the forces ramp back in.
  void resume();
  /// The trainee has paused the session (see pause()).
  [[nodiscard]] bool user_paused() const { return user_paused_; }

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
  /// Everything fixed about the running session (its organs' surfaces, tools, catheter, task).
  [[nodiscard]] const sim::SessionModel& session_model() const { return session_->model(); }
  /// The tools' shaft and jaw lengths, as the session renders them.
  [[nodiscard]] const haptics::GripperGeometry& tool_geometry(int tool) const {
    return session_->tool_geometry(tool);
  }
  /// The running session itself (null when none), for what the accessors above do not cover
  /// (the authoring panel's live tuning among them).
  [[nodiscard]] sim::Session* session() { return session_.get(); }

 private:
  LiveSessionOptions options_;
  std::unique_ptr<sim::Session> session_;
  std::array<hardware::SimulatedDevice*, 2> devices_{};
  std::array<hardware::SimulatedInput, 2> inputs_{};
  std::array<hardware::SimulatedInput, 2> homes_{};
  std::thread runner_;
  std::atomic<bool> finished_{false};
  bool user_paused_ = false;
  sim::SessionMetrics metrics_;  // written by the runner, read after it is joined
  std::string scenario_;
};

}  // namespace lap::app
