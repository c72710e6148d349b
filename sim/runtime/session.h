#pragma once
/// \file
/// A running session: the three loops of docs/architecture.md over a loaded scene (thesis §6.5,
/// §7.6: haptics fastest, modelling slower, graphics slowest), two tools each driven by a
/// device through its trocar, the watchdog, and the recording of every device input.
///
/// - Haptic loop (default 1 kHz): read both devices, tool kinematics through the trocars, the
///   three-segment gripper proxies (or a probe's one proxy, probe_tool.h) against the organs,
///   the free rigid bodies pushed and stepped (moving_bodies.h), the virtual coupling to a grasped
///   catheter and duct, the wrench back through the fulcrum, limits, the passivity controller at
///   the handle (hardware/passivity_controller.h), write both devices. No allocation,
///   lock or exception after start-up.
/// - Modelling loop (default 200 Hz): the tissue world (tissue_world.h): grasping the catheter
///   and the duct, the mass-spring catheter (§7.7(3)) and its contacts, organs dented by the tools
///   and the catheter (§6.5), the duct's modes (§7.7(2)); it publishes the deformed surfaces for
///   the graphics, and brings the proxies' next copy of the surfaces up to date with them
///   (haptic_surfaces.h), which the haptic loop switches to.
/// - Graphics: whoever shows the session reads snapshots (graphics_snapshot()).
/// The loops exchange whole snapshots through triple buffers: nobody waits for anybody.
///
/// Real time: the haptic and modelling loops are threads woken at absolute times. --fast: the
/// same ticks run in lockstep in the calling thread as fast as possible, so a run is a pure
/// function of its inputs (state_hash) — replays reproduce a recorded session bit for bit.
///
/// Watchdog: a haptic tick starting more than 2 periods late (a late tick) sends zero force on
/// that tick and ramps the forces back by itself within 50 ms; it is counted, nothing else. A
/// stall (a tick starting 20 ms late or more), a non-finite force, a device that reports an
/// error or a disconnect, or a model that met a non-finite value in the modelling step (its
/// fault published with the step's snapshot, which the next haptic tick reads) sends zero force
/// on that tick, pauses the session (forces stay zero; proxies, models and recording go on) and
/// records why; resume() ramps the forces back in.
///
/// Model apart from state: everything fixed once the session is set up is one SessionModel
/// (sim/setup/session_model.h) that both loops read `const`; the session owns only state,
/// buffers and threads.

#include <algorithm>
#include <array>
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "haptics/laparoscopic_gripper.h"
#include "haptics/mesh_database.h"
#include "haptics/segment_database.h"
#include "hardware/command_limiter.h"
#include "hardware/device_recording.h"
#include "hardware/haptic_device.h"
#include "hardware/passivity_controller.h"
#include "hardware/triple_buffer.h"
#include "models/catheter_grasp.h"
#include "models/catheter_model.h"
#include "sim/runtime/deformed_surface.h"
#include "sim/runtime/haptic_surfaces.h"
#include "sim/runtime/loop_stats.h"
#include "sim/runtime/moving_bodies.h"
#include "sim/runtime/probe_tool.h"
#include "sim/runtime/session_recorder.h"
#include "sim/runtime/surface_tuning.h"
#include "sim/runtime/task_engine.h"
#include "sim/runtime/task_progress.h"
#include "sim/runtime/tissue_world.h"
#include "sim/runtime/training_metrics.h"
#include "sim/runtime/trocar_tool.h"
#include "sim/setup/runtime_settings.h"
#include "sim/setup/scene.h"
#include "sim/setup/session_model.h"

namespace lap::sim {

enum class WatchdogReason : uint8_t {
  kStall,  ///< a haptic tick started RuntimeSettings::stall_s late or more
  kNonFinite,
  kDeviceDisconnected,
  kDeviceError,
  kModelFault,  ///< a tissue model met a non-finite value (WatchdogEvent::model_fault says which)
};
inline constexpr size_t kWatchdogReasons = 5;
[[nodiscard]] std::string_view to_string(WatchdogReason reason);

struct WatchdogEvent {
  int64_t tick = 0;
  int32_t tool = -1;  ///< 0 left, 1 right, -1 the loop itself
  WatchdogReason reason = WatchdogReason::kStall;
  ModelFault model_fault;  ///< kModelFault: which model, on which organ
};

struct ToolSnapshot {
  haptics::GripperPose pose;  ///< the tool as the device put it
  int32_t contacts = 0;       ///< over its three segments
  /// Where its three segment proxies are (shaft, jaw 0, jaw 1: ends a and b as
  /// LaparoscopicGripper::segments orders them): the ideal segments, on the organs' surfaces
  /// where the device's pose has gone into them (chapter 5), never inside (the soak checks), so
  /// that a tool drawn there rests on the tissue instead of passing into it.
  std::array<Eigen::Vector3d, 3> proxy_a_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                           Eigen::Vector3d::Zero()};
  std::array<Eigen::Vector3d, 3> proxy_b_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                           Eigen::Vector3d::Zero()};
  /// Per segment: the unit mean of its contacts' normals (out of the organs), zero when it
  /// touches nothing (a drawn segment of some thickness is lifted off the surface along it).
  std::array<Eigen::Vector3d, 3> proxy_normal_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                                Eigen::Vector3d::Zero()};
  /// Its contacts with the organs (the first kMaxContacts), for the tissue models.
  int32_t organ_contact_count = 0;
  std::array<ToolContact, ToolModelInput::kMaxContacts> organ_contacts{};
  /// What the haptic loop renders of it (a gripper, or a probe: tools[].kind), and for a probe
  /// where its proxy holds the tip (the IHIP of a point probe, the ideal ray's tip), for drawing.
  ToolKind kind = ToolKind::kGripper;
  Eigen::Vector3d proxy_tip_W = Eigen::Vector3d::Zero();
};

struct HapticSnapshot {
  int64_t tick = -1;
  bool paused = false;
  std::array<ToolSnapshot, 2> tools{};
  // The loop's own figures, for the app to show while the session runs.
  double worst_lateness_s = 0.0;  ///< so far
  int64_t missed_deadlines = 0;   ///< ticks started more than 2 ms late, so far
  int64_t late_ticks = 0;         ///< ticks the watchdog zeroed for starting late, so far
  WatchdogReason last_reason = WatchdogReason::kStall;  ///< of the latest event, if any
  ModelFault last_model_fault;  ///< the latest event's model, when it was a model fault
  /// The free rigid bodies where this tick left them (§6.4; moving_bodies.h): for drawing, and
  /// for the modelling loop's catheter contacts.
  BodySnapshots bodies;
};

struct ModelSnapshot {
  int64_t tick = -1;                                 ///< the haptic tick this step belongs to
  int64_t steps = 0;                                 ///< modelling steps so far
  std::vector<Eigen::Vector3d> catheter;             ///< particle positions [m]
  std::vector<Eigen::Vector3d> catheter_velocities;  ///< [m/s]
  std::array<models::GraspState, 2> grasps{};
  std::array<models::DuctGraspState, 2> duct_grasps{};
  std::array<double, 2> squeeze{};         ///< of each tool's jaws on what they hold [N]
  int32_t catheter_contacts = 0;           ///< particles touching an organ or the duct
  double deepest_dent_m = 0.0;             ///< largest displacement of a surface vertex
  std::vector<SurfaceDeformation> organs;  ///< each organ's deformed vertices (world frame)
  /// The model that met a non-finite value in this step, if any: the haptic loop trips its
  /// watchdog on every tick that sees it (a fault lasting several steps is one event).
  ModelFault fault;
  /// The catheter's push on each free body at this step, which the haptic loop holds on it
  /// until the next (in the order of HapticSnapshot::bodies).
  BodyPushes catheter_on_bodies;
  /// The task as this step left it, for the heads-up display (task_progress.h).
  TaskProgress task;
};

struct SessionMetrics {
  LoopStats haptic;
  LoopStats model;
  bool paused = false;
  std::vector<WatchdogEvent> events;
  /// Late ticks (RuntimeSettings::overrun_periods): each sent zero and the forces ramped back;
  /// not events. Ticks late while paused (a stall's catch-up among them) are not counted.
  int64_t late_ticks = 0;
  int64_t recorded_ticks = 0;
  int64_t dropped_samples = 0;  ///< inputs not recorded because the recording was full
  uint64_t state_hash = 0;
  std::array<hardware::DeviceStatus, 2> device_status{};
  std::vector<std::string> warnings;
  double max_force_sent_n = 0.0;
  /// Each tool's passivity observer and controller (hardware/passivity_controller.h): the energy
  /// the simulation absorbed from the hand, the lowest it went, what the controller dissipated
  /// and on how many ticks.
  std::array<hardware::PassivityFigures, 2> passivity{};
  std::array<hardware::PassivityFigures, 2> coupling_passivity{};  ///< the couplings' own
  std::vector<std::string> organ_names;  ///< for naming the organ of a model fault
  /// The task engine's outcome: result, reasons, events, phase times (task_engine.h).
  TaskKind task_kind = TaskKind::kNone;
  TaskState task;
  /// The training metrics (training_metrics.h; the JSON's top-level "metrics") and their series.
  std::vector<Metric> training;
  MetricsSeries series;
  std::optional<ProficiencySpec> proficiency;  ///< the scenario's benchmarks for them, if any
};

/// What a watchdog event's reason says to a user: its reason, and for a model fault which model
/// on which organ ("model fault: local deformation on liver").
[[nodiscard]] std::string describe(WatchdogReason reason, const ModelFault& fault,
                                   const std::vector<std::string>& organ_names);

class Session {
 public:
  /// Set-up over a session model: each tool's device (whose limits must be the ones the model
  /// was built for), the proxies' surfaces, the tissue's state, recording space for the whole
  /// duration. Devices are started here.
  static Result<std::unique_ptr<Session>> create(
      std::shared_ptr<const SessionModel> model,
      std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices);
  /// The model built from the scene and the devices' limits, then the session.
  static Result<std::unique_ptr<Session>> create(
      const Scene& scene, std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices,
      const RuntimeSettings& settings);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  Session(Session&&) = delete;
  Session& operator=(Session&&) = delete;

  /// Runs the session to its end (fast or real time) and returns the metrics.
  SessionMetrics run();
  /// Any thread: end the session at the next tick, whose first act is to command zero force to
  /// both devices (the haptic thread; run() writes zero again once the loops are joined). A
  /// lockstep replay ends before its next tick or step.
  void request_stop() { stop_.store(true, std::memory_order_relaxed); }
  /// Scheduling problems the loops met as they started (SCHED_FIFO or mlockall refused: the
  /// loops then run best effort), for showing while the session runs. Any thread.
  [[nodiscard]] std::vector<std::string> scheduling_warnings() const;
  /// Any thread: un-pause; forces ramp back in over resume_ramp_s.
  void resume() { resume_requested_.store(true, std::memory_order_relaxed); }
  [[nodiscard]] bool paused() const { return paused_.load(std::memory_order_relaxed); }
  /// Any thread: the trainee's pause (real time; a --fast session ignores it). The haptic loop
  /// sends zero force to both devices and stops ticking, and the modelling loop stops stepping:
  /// while held no tick runs, so the task's clock (tick time), the models, the metrics and the
  /// recording stand still, and no watchdog event is recorded. release() starts the schedule
  /// again from the moment it is taken up, the forces ramping back over resume_ramp_s as after
  /// resume(). The devices are not read while held: a live arm moved meanwhile takes its tool
  /// to where it now is on the first tick after, the proxies keeping it on the surfaces.
  void hold() { hold_requested_.store(true, std::memory_order_release); }
  void release() { hold_requested_.store(false, std::memory_order_release); }
  /// The haptic loop has taken a hold up: zero sent, no tick running until release().
  [[nodiscard]] bool held() const { return holding_.load(std::memory_order_acquire); }

  /// Tests: make tick `tick` start `late_s` late, as a loop held up would (fast mode: as if; real
  /// time: the haptic thread wakes that much after the tick's deadline); up to
  /// kMaxInjectedLateness ticks, one call each (false once full).
  bool inject_lateness(int64_t tick, double late_s) {
    if (injected_late_count_ >= kMaxInjectedLateness) return false;
    injected_late_[injected_late_count_++] = {tick, late_s};
    return true;
  }
  static constexpr size_t kMaxInjectedLateness = 16;
  /// Tests (fast mode): the modelling steps from haptic tick `tick` on, `steps` of them, put a
  /// non-finite value into model `kind` (TissueWorld::inject_non_finite), as a numerical
  /// blow-up would.
  void inject_model_fault(int64_t tick, ModelFaultKind kind, int64_t steps = 1) {
    injected_fault_tick_ = tick;
    injected_fault_ = kind;
    injected_fault_steps_ = steps;
  }
  /// Replay (before run(), fast mode): run the recorded ticks and modelling steps of a session
  /// in the order lockstep_order.h gives, each tick reading the model snapshot, the surfaces,
  /// the lateness and the resume it read live, each step the haptic tick it read (the streamed
  /// recording's reads, session_recorder.h), so that a session run in real time replays to its
  /// own state_hash. The run ends with the recorded ticks, not with the task. `tunings`: an
  /// author's, set at the ticks that took them live (tick order), in place of the mailbox's.
  void replay_in_lockstep(std::vector<TickLog> ticks, std::vector<StepLog> steps,
                          std::vector<TuningLog> tunings = {}) {
    schedule_ticks_ = std::move(ticks);
    schedule_steps_ = std::move(steps);
    schedule_tunings_ = std::move(tunings);
    scheduled_ = true;
  }
  /// After a replay_in_lockstep run(): why it stopped before the recording's last tick, if it
  /// did (its steps cut or damaged; the loops further apart live than the replay keeps).
  [[nodiscard]] const std::string& lockstep_problem() const { return lockstep_problem_; }
  /// After a replay_in_lockstep run(): recorded steps that read a tick after the last one run
  /// (normal at the end of an interrupted recording; damage in a complete one).
  [[nodiscard]] int64_t lockstep_steps_not_run() const { return lockstep_steps_not_run_; }
  /// How many snapshots of each loop a lockstep replay keeps (the newest and those before).
  static constexpr int64_t kLockstepHistory = 8;
  /// Tests (real time): the modelling step at haptic tick `tick` takes `delay_s` longer, as a
  /// step held up by the machine would (issue 25's fault injection: a 100 ms step).
  void inject_model_delay(int64_t tick, double delay_s) {
    injected_delay_tick_ = tick;
    injected_delay_s_ = delay_s;
  }

  /// Authoring (one thread besides the haptic one): organ `organ`'s haptic surface takes `p`
  /// from the next haptic tick on (surface_tuning.h); false when the mailbox is full (post
  /// again later). Wait-free, no allocation.
  bool tune_surface(int32_t organ, const SurfaceParameters& p) noexcept {
    return tuning_mailbox_.post(organ, p);
  }
  /// Tunings posted so far, and taken up by the haptic loop so far (any thread).
  [[nodiscard]] uint64_t surface_tunings_posted() const { return tuning_mailbox_.posted(); }
  [[nodiscard]] uint64_t surface_tunings_taken() const { return tuning_mailbox_.taken(); }
  /// Organ `organ`'s surface as the haptic loop renders it: the haptic thread's state, so read
  /// it once surface_tunings_taken() has reached surface_tunings_posted() with no post since
  /// (the acquire there orders it), after run(), or in fast mode between ticks.
  [[nodiscard]] const SurfaceParameters& surface_parameters(int32_t organ) const {
    return tuned_surfaces_.parameters(organ);
  }
  /// The contact stiffness the catheter meets organ `organ` with (TissueWorld, the modelling
  /// thread's state: read after run(), or in fast mode between ticks): the scenario's, or the
  /// author's tuning once the modelling step that read the tick which took it has run.
  [[nodiscard]] double catheter_contact_stiffness(int32_t organ) const {
    return world_->stiffness_n_per_m(organ);
  }
  /// The organ a tool touched at the latest haptic tick (the right tool's first contact, else
  /// the left's), or -1: the organ the authoring panel tunes. Any thread.
  [[nodiscard]] int32_t touched_organ() const {
    return touched_organ_.load(std::memory_order_relaxed);
  }
  /// Whether organ `organ` has force-shading normals to switch on, and a texture to scale.
  [[nodiscard]] bool surface_can_shade(int32_t organ) const {
    return tuned_surfaces_.can_shade(organ);
  }
  [[nodiscard]] bool surface_has_texture(int32_t organ) const {
    return tuned_surfaces_.has_texture(organ);
  }

  [[nodiscard]] const SessionModel& model() const { return *model_; }
  /// The free bodies (haptic thread's state: read after run(), or in fast mode between ticks).
  [[nodiscard]] const MovingBodies& bodies() const { return bodies_; }

  /// A fast session's frames for review (the instructor's replay, app/review): before run(),
  /// `observer` is called on the running thread after every `every_ticks`-th haptic tick (and
  /// its modelling step) with the newest haptic and model snapshots. It takes the graphics
  /// loop's place as their reader, and may allocate: never in a live session (real time: not
  /// called).
  using FastObserver =
      std::function<void(int64_t tick, const HapticSnapshot& haptic, const ModelSnapshot& model)>;
  void observe_fast(FastObserver observer, int64_t every_ticks) {
    fast_observer_ = std::move(observer);
    fast_observe_every_ = std::max<int64_t>(1, every_ticks);
  }

  /// The graphics loop (one reader): the newest haptic and model snapshots.
  const HapticSnapshot& graphics_haptic() { return to_graphics_.latest(); }
  const ModelSnapshot& graphics_model() { return model_to_graphics_.latest(); }

  /// Every device's inputs so far (the recording keeps what was recorded when a session
  /// pauses or stops early).
  [[nodiscard]] const hardware::DeviceRecording& recording(int tool) const {
    return recordings_[static_cast<size_t>(tool)];
  }
  /// After run(): what the haptic loop sent, read and touched on each tick recorded, in order
  /// (what session.lrec holds beside the devices' inputs).
  [[nodiscard]] const std::vector<TickLog>& tick_log() const { return tick_log_; }
  /// Writes DIR/left.lapdev, DIR/right.lapdev, each whole or not at all and each tried; a
  /// diagnostic naming the file for each that could not be written.
  [[nodiscard]] Status write_recording(const std::string& dir) const;
  /// Before run(): the session is also recorded as it runs into `file` (session_recorder.h),
  /// so that a crash loses at most the last 100 ms; `header_json` heads it (session.json's
  /// fields). run() closes it, after the devices are sent zero.
  [[nodiscard]] Status record_to(const std::filesystem::path& file, const std::string& header_json);

  [[nodiscard]] const haptics::GripperGeometry& tool_geometry(int tool) const {
    return model_->tool(static_cast<size_t>(tool)).gripper;
  }
  /// The organs' surfaces at rest as the session renders and feels them (the duct: its shell);
  /// ModelSnapshot::organs deforms them.
  [[nodiscard]] int32_t organ_count() const { return world_->organ_count(); }
  [[nodiscard]] const haptics::TriangleMesh& organ_surface(int32_t organ) const {
    return world_->surface(organ);
  }

 private:
  Session() = default;
  void haptic_tick(int64_t tick, double lateness_s) noexcept;
  const ModelSnapshot& take_up_model(int64_t tick, double lateness_s) noexcept;
  bool take_tunings(int64_t tick) noexcept;
  void forward_stiffness_to_model(int64_t tick) noexcept;
  void check_timing(int64_t tick, double lateness_s) noexcept;
  [[nodiscard]] double injected_lateness(int64_t tick) const noexcept;
  bool read_tool(size_t i, int64_t tick, ToolKinematics* k) noexcept;
  hardware::DeviceCommand probe_command(size_t i, const ToolKinematics& k, ToolSnapshot* ts,
                                        int64_t tick) noexcept;
  hardware::DeviceCommand tool_command(size_t i, const ToolKinematics& k,
                                       const ModelSnapshot& model, ToolSnapshot* ts,
                                       int64_t tick) noexcept;
  Eigen::Vector3d coupling_damper(size_t i, const ToolKinematics& k,
                                  const Eigen::Vector3d& force_tip_W,
                                  const Eigen::Vector3d& coupling_force_W,
                                  const Eigen::Vector3d& coupling_torque_W) noexcept;
  [[nodiscard]] std::span<const haptics::HapticObject> touched_objects(
      size_t i, const models::DuctGraspState& duct_grasp) noexcept;
  void send_commands(int64_t tick, const std::array<hardware::DeviceCommand, 2>& wanted,
                     const HapticSnapshot& snap) noexcept;
  void publish_haptic(HapticSnapshot& snap, double lateness_s) noexcept;
  void log_tick(int64_t tick, const std::array<hardware::DeviceCommand, 2>& sent, bool late,
                bool paused) noexcept;
  void finish_recording(SessionMetrics* m);
  void model_tick(int64_t tick) noexcept;
  void record_frame(int64_t tick, const HapticSnapshot& h) noexcept;
  void step_task_engine(int64_t tick, const HapticSnapshot& h) noexcept;
  void trip(int64_t tick, int32_t tool, WatchdogReason reason, ModelFault fault = {}) noexcept;
  void run_fast();
  void run_realtime();
  void run_scheduled();
  bool scheduled_tick(int64_t t);
  bool scheduled_step(int64_t k, int64_t next_tick_read);
  [[nodiscard]] const ModelSnapshot* kept_model(int64_t steps) const;
  /// Haptic thread, real time: zero to both devices, then wait until released (or stopped);
  /// returns when the tick due at `deadline_ns` may run, the schedule moved on by the wait.
  int64_t wait_while_held(int64_t deadline_ns) noexcept;
  /// Zero to both devices past the rate limit, on the haptic thread: as a hold is taken (live,
  /// and in a lockstep replay), and as the loop sees a stop (request_stop: a signal, End
  /// Session, the task's end), before the other loops are joined.
  void zero_forces() noexcept;
  /// After a hold: the forces ramp back from zero over resume_ramp_s.
  void ramp_after_hold() noexcept;

  /// A tool's state: its device, its proxies, its limiter, where its shaft points.
  struct Tool {
    std::unique_ptr<hardware::HapticDevice> device;
    haptics::LaparoscopicGripper gripper;
    std::unique_ptr<ProbeTool> probe;  ///< a probe's proxy instead of the gripper's; null: gripper
    hardware::CommandLimiter limiter;
    /// Keeps the port passive: the energy given to the hand within what it put in.
    hardware::PassivityController passivity;
    /// The same for the grasp couplings' share of the force alone, with a leaky reservoir: the
    /// organs' dissipation cannot pay for a coupling's activity (session.cpp, tool_command).
    hardware::PassivityController coupling_passivity;
    Eigen::Vector3d coupling_wanted_W = Eigen::Vector3d::Zero();  ///< its share at the handle
    Eigen::Vector3d handle_W = Eigen::Vector3d::Zero();           ///< as read this tick
    bool handle_read = false;                                     ///< this tick's sample was finite
    Eigen::Vector3d axis_W = Eigen::Vector3d::UnitY();
    models::JawFrame last_jaws;  ///< at the previous tick (the couplings' jaw velocity)
    /// The organs as this tool's proxies see them while it holds the duct: the duct's force law
    /// muted (session.cpp, tool_command). Sized with objects_ at creation.
    std::vector<haptics::HapticObject> objects_holding_duct;
    bool jaws_seen = false;
    bool started = false;
    bool finished = false;
    hardware::DeviceStatus status = hardware::DeviceStatus::kOk;
  };

  std::shared_ptr<const SessionModel> model_;  ///< both loops read it const

  // The organs as this session's proxies see them (the model's objects, pointed at the
  // surfaces' newest copy) and the tools.
  std::vector<haptics::HapticObject> objects_;
  std::array<Tool, 2> tools_;
  // Authoring's live surface tuning: the mailbox from the author's thread, and the haptic
  // thread's tuned surfaces it feeds (surface_tuning.h).
  SurfaceTuningMailbox tuning_mailbox_;
  TunedSurfaces tuned_surfaces_;
  // A tuned stiffness, forwarded by the haptic thread to the modelling loop's catheter contacts
  // (TissueWorld::set_stiffness): per organ the last one posted and whether it still waits for
  // room in the mailbox (the haptic thread's), the mailbox (haptic thread to modelling thread:
  // each message carries the tick that posted it, taken by the step that read that tick's
  // snapshot, so that a replay takes it at the same step).
  std::vector<double> stiffness_for_model_;
  std::vector<uint8_t> stiffness_waiting_;
  int32_t stiffness_waiting_count_ = 0;
  SurfaceTuningMailbox stiffness_to_model_;
  std::atomic<int32_t> touched_organ_{-1};
  MovingBodies bodies_;  ///< the free rigid bodies, stepped every haptic tick (§6.4)

  // Models' state (the modelling thread's own).
  std::unique_ptr<TissueWorld> world_;
  std::array<ToolModelInput, 2> model_input_{};
  int64_t injected_fault_tick_ = -1;
  ModelFaultKind injected_fault_ = ModelFaultKind::kNone;
  int64_t injected_fault_steps_ = 0;
  int64_t injected_delay_tick_ = -1;  ///< modelling thread reads; set before run()
  double injected_delay_s_ = 0.0;
  // What each modelling step read (modelling thread writes, capacity reserved at set-up), for
  // the recording; the steps complete are published to the recorder's thread.
  std::vector<StepLog> step_log_;
  std::atomic<int64_t> published_steps_{0};
  // The task engine's state and its inputs' storage, sized at set-up (modelling thread).
  TaskState task_;
  MetricsModel metrics_model_;
  MetricsState metrics_;
  std::vector<double> organ_force_n_;         ///< per organ [N]
  std::vector<uint8_t> organ_touched_;        ///< per organ
  std::vector<Eigen::Vector3d> tool_push_W_;  ///< per organ, one tool's contacts' sum [N]
  TaskProgress task_progress_;                ///< after the last task step (modelling thread)
  /// The common bile duct's surface at rest (the model's), for the tip inside it; null: none.
  const haptics::MeshDatabase* cbd_rest_ = nullptr;
  // Scheduling warnings, published once each (bit 0: the haptic thread's priority, bit 1: the
  // memory lock); each string is written before its bit is set and never after.
  std::string priority_warning_;
  std::string memory_warning_;
  std::atomic<uint8_t> scheduling_flags_{0};
  // The proxies' surfaces: three copies, brought up to date by the modelling thread.
  hardware::TripleBuffer<std::unique_ptr<HapticSurfaces>> surfaces_to_haptic_;

  FastObserver fast_observer_;  ///< observe_fast(): review only, fast mode
  int64_t fast_observe_every_ = 1;

  // Exchange (each buffer: one writer, one reader).
  hardware::TripleBuffer<HapticSnapshot> to_model_;
  hardware::TripleBuffer<HapticSnapshot> to_graphics_;
  hardware::TripleBuffer<ModelSnapshot> model_to_haptic_;
  hardware::TripleBuffer<ModelSnapshot> model_to_graphics_;

  // Watchdog and safety (haptic thread).
  std::atomic<bool> paused_{false};
  std::atomic<bool> resume_requested_{false};
  std::atomic<bool> stop_{false};
  /// The stop was the task's end (model_tick), not a request from outside: a lockstep replay
  /// goes on through the ticks the live loops ran after it (they are in its recording).
  std::atomic<bool> stop_by_task_{false};
  std::atomic<bool> haptic_done_{false};
  // The trainee's pause (hold()): asked for by any thread, taken up by the haptic thread, which
  // then moves both loops' schedules on by the time held (hold_offset_ns_, written before
  // holding_ is cleared).
  std::atomic<bool> hold_requested_{false};
  std::atomic<bool> holding_{false};
  std::atomic<int64_t> hold_offset_ns_{0};
  /// The factor on every command, ramping back to 1 at 1 / ramp_s_ per second after a resume
  /// or a late tick.
  double gain_ = 1.0;
  double ramp_s_ = 0.0;
  bool late_tick_ = false;  ///< this tick started late: it sends zero (send_commands)
  int64_t late_ticks_ = 0;
  std::vector<WatchdogEvent> events_;  ///< capacity reserved at set-up
  int64_t events_dropped_ = 0;
  /// The last tick each tool (left, right, the loop itself) tripped for each reason: a fault
  /// tripping again on the next tick is the same lasting fault, not a new event.
  std::array<std::array<int64_t, kWatchdogReasons>, 3> last_trip_tick_{};
  struct InjectedLateness {
    int64_t tick = -1;
    double late_s = 0.0;
  };
  std::array<InjectedLateness, kMaxInjectedLateness> injected_late_{};  ///< no allocation
  size_t injected_late_count_ = 0;
  double max_force_sent_n_ = 0.0;
  double worst_lateness_s_ = 0.0;
  int64_t missed_deadlines_ = 0;
  int64_t model_steps_ = 0;  ///< modelling thread

  // A lockstep replay (replay_in_lockstep): the recorded reads, each loop's last snapshots, and
  // which ones the next tick or step reads (null: the newest, as live).
  bool scheduled_ = false;
  std::vector<TickLog> schedule_ticks_;
  std::vector<StepLog> schedule_steps_;
  std::vector<TuningLog> schedule_tunings_;
  size_t next_scheduled_tuning_ = 0;
  std::vector<HapticSnapshot> haptic_history_;  ///< tick t at (t + 1) % kLockstepHistory
  std::vector<ModelSnapshot> model_history_;    ///< n steps at n % kLockstepHistory
  ModelSnapshot model_kept_;  ///< the next tick's older read, once out of model_history_
  const HapticSnapshot* scheduled_haptic_ = nullptr;
  const ModelSnapshot* scheduled_model_ = nullptr;
  bool scheduled_resume_ = false;
  int64_t scheduled_surface_steps_ = 0;
  std::string lockstep_problem_;
  int64_t lockstep_steps_not_run_ = 0;

  // Recording (haptic thread writes, capacity reserved at set-up).
  std::array<hardware::DeviceRecording, 2> recordings_{};
  std::vector<TickLog> tick_log_;
  std::atomic<int64_t> published_ticks_{0};  ///< complete in recordings_ and tick_log_
  // The organs' surfaces after each tick's tunings (haptic thread writes; kMaxRecordedTunings
  // reserved by record_to(), none otherwise), and those there was no room for.
  std::vector<TuningLog> tuning_log_;
  std::atomic<int64_t> published_tunings_{0};
  int64_t tunings_unrecorded_ = 0;
  // What the 3D view draws, every FrameRing::kFramePeriodS, for the recording's seeking
  // (modelling thread writes; reserved by record_to(), none otherwise).
  FrameRing frames_;
  int64_t frame_every_ticks_ = 100;
  int64_t next_frame_tick_ = 0;  ///< modelling thread
  TickLog tick_reads_;  ///< this tick's lateness, resume and reads, for its log (haptic thread)
  bool after_hold_ = false;  ///< the tick about to run is the first after a hold (its log says)
  std::unique_ptr<SessionRecorder> recorder_;  ///< streams them to disk (record_to)
  int64_t dropped_samples_ = 0;
  uint64_t hash_ = 1469598103934665603ULL;        ///< haptic thread: commands, tool poses
  uint64_t model_hash_ = 1469598103934665603ULL;  ///< modelling thread: catheter

  LoopStats haptic_stats_;
  LoopStats model_stats_;
  std::vector<std::string> warnings_;
};

}  // namespace lap::sim
