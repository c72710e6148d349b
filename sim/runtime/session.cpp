#include "sim/runtime/session.h"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "haptics/point_proxy.h"
#include "sim/runtime/lockstep_order.h"
#include "sim/runtime/realtime_thread.h"

namespace lap::sim {
namespace {

constexpr uint64_t kFnvPrime = 1099511628211ULL;
/// The couplings' passivity reservoir leaks with this time constant (estimate: a few cycles of
/// the hand's own 5–25 Hz modes on a grasp; long against a tick, short against a pull).
constexpr double kCouplingLeakS = 0.2;
/// A probe's "jaws" for the grasp models: open past every release angle (models/catheter_grasp.h,
/// models/duct_grasp.h release above 0.45 rad), so a probe never grasps.
constexpr double kProbeOpeningRad = 1.0;

// Whether p is inside a closed surface: the nearest point's primitive's (angle-weighted
// pseudo-)normal points away from p (Baerentzen and Aanaes, IEEE TVCG 2005). Real time.
bool inside_closed_surface(const haptics::MeshDatabase& surface, const Eigen::Vector3d& p) {
  Eigen::Vector3d q;
  const int32_t f = surface.nearest_face(p, &q, nullptr);
  if (f < 0) return false;
  int32_t rounds = 0;
  const haptics::PrimitiveRef prim = haptics::PointProxy::local_search(
      surface, {haptics::PrimitiveKind::kFace, f}, p, &q, &rounds);
  return surface.normal(prim).dot(p - q) < 0.0;
}

void hash_bytes(uint64_t* h, const void* data, size_t n) noexcept {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) {
    *h ^= p[i];
    *h *= kFnvPrime;
  }
}

void hash_vector(uint64_t* h, const Eigen::Vector3d& v) noexcept {
  hash_bytes(h, v.data(), 3 * sizeof(double));
}

models::JawFrame jaw_frame(const haptics::GripperPose& pose) {
  models::JawFrame j;
  j.hinge_W = pose.hinge_W;
  j.rotation_WJ.col(0) = pose.open_dir_W;
  j.rotation_WJ.col(1) = pose.shaft_dir_W;
  j.rotation_WJ.col(2) = pose.open_dir_W.cross(pose.shaft_dir_W);
  j.opening_rad = pose.opening_rad;
  return j;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::string_view to_string(WatchdogReason reason) {
  switch (reason) {
    case WatchdogReason::kStall:
      return "haptic loop stalled";
    case WatchdogReason::kNonFinite:
      return "non-finite force";
    case WatchdogReason::kDeviceDisconnected:
      return "device disconnected";
    case WatchdogReason::kDeviceError:
      return "device error";
    case WatchdogReason::kModelFault:
      return "model fault";
  }
  return "unknown";
}

std::string describe(WatchdogReason reason, const ModelFault& fault,
                     const std::vector<std::string>& organ_names) {
  std::string text(to_string(reason));
  if (reason != WatchdogReason::kModelFault || !fault) return text;
  text += ": ";
  text += to_string(fault.kind);
  if (fault.organ >= 0 && static_cast<size_t>(fault.organ) < organ_names.size()) {
    text += " on " + organ_names[static_cast<size_t>(fault.organ)];
  }
  return text;
}

Result<std::unique_ptr<Session>> Session::create(
    const Scene& scene, std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices,
    const RuntimeSettings& settings) {
  std::array<DeviceDescription, 2> described;
  for (size_t side = 0; side < 2; ++side) {
    if (devices[side] == nullptr) {
      return diagnostic("no device for the " + std::string(side == 0 ? "left" : "right") + " tool");
    }
    described[side] = describe(*devices[side]);
  }
  Result<std::shared_ptr<const SessionModel>> model =
      SessionModel::build(scene, settings, described);
  if (!model.ok()) return model.diagnostics();
  return create(std::move(model).value(), std::move(devices));
}

Result<std::unique_ptr<Session>> Session::create(
    std::shared_ptr<const SessionModel> model,
    std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices) {
  if (model == nullptr) return diagnostic("no session model");
  const RuntimeSettings& rs = model->settings();
  if (!(rs.late_tick_ramp_s >= 0.0 && rs.late_tick_ramp_s <= 0.1)) {
    return diagnostic("watchdog: expected a late tick ramp of 0 to 0.1 s");
  }
  if (!(rs.stall_s > 0.0) || !(rs.overrun_periods > 0.0)) {
    return diagnostic("watchdog: expected a positive stall time and overrun periods");
  }
  std::unique_ptr<Session> s(new Session());
  s->model_ = std::move(model);
  for (auto& per_reason : s->last_trip_tick_) per_reason.fill(-2);
  const SessionModel& m = *s->model_;
  const SessionTiming& timing = m.timing();
  s->haptic_stats_ = LoopStats(timing.dt_s);
  s->model_stats_ = LoopStats(timing.model_dt_s);
  s->warnings_ = m.notes();

  // The tools: their devices (with the limits the model was built for), at their ports.
  for (size_t side = 0; side < 2; ++side) {
    const char* name = side == 0 ? "left" : "right";
    Tool& tool = s->tools_[side];
    tool.device = std::move(devices[side]);
    if (tool.device == nullptr)
      return diagnostic("no device for the " + std::string(name) + " tool");
    const hardware::DeviceLimits& want = m.tool(side).device.limits;
    const hardware::DeviceLimits& have = tool.device->limits();
    if (have.max_force_n != want.max_force_n ||
        have.max_continuous_force_n != want.max_continuous_force_n ||
        have.thermal_time_constant_s != want.thermal_time_constant_s ||
        have.max_torque_nm != want.max_torque_nm || have.max_squeeze_n != want.max_squeeze_n ||
        have.max_stiffness_n_per_m != want.max_stiffness_n_per_m ||
        have.max_force_rate_n_per_s != want.max_force_rate_n_per_s ||
        !have.workspace_W.isApprox(want.workspace_W)) {
      return diagnostic(std::string(tool.device->name()) + ": the " + name +
                        " tool's device has other limits than the session model was built for");
    }
    tool.gripper = haptics::LaparoscopicGripper(m.tool(side).gripper);
    if (m.tool(side).kind != ToolKind::kGripper) {
      tool.probe =
          std::make_unique<ProbeTool>(m.tool(side).kind, m.tool(side).gripper.shaft_length_m);
    }
    tool.limiter = hardware::CommandLimiter(have);
    tool.passivity = hardware::PassivityController(hardware::PassivityController::kMaxDampingNsPerM,
                                                   rs.passivity_control);
    tool.coupling_passivity = hardware::PassivityController(
        hardware::PassivityController::kMaxDampingNsPerM, rs.passivity_control, kCouplingLeakS);
    tool.axis_W = m.tool(side).initial_axis_W;
  }

  // The tissue's state, and the proxies' surfaces: three copies of the model's rest databases
  // for the modelling thread to keep up to date and hand to the haptic thread
  // (haptic_surfaces.h).
  s->world_ = TissueWorld::create(m.tissue_ptr());
  {
    const std::vector<const haptics::MeshDatabase*> dbs = m.rest_databases();
    if (m.task().cbd_organ >= 0) s->cbd_rest_ = dbs[static_cast<size_t>(m.task().cbd_organ)];
    const std::vector<const haptics::SegmentDatabase*> sds = m.rest_segment_databases();
    const std::vector<const haptics::ShadingNormals*> shading = m.rest_shading();
    std::array<std::unique_ptr<HapticSurfaces>, 3> copies;
    for (auto& c : copies) c = std::make_unique<HapticSurfaces>(dbs, sds, shading);
    s->surfaces_to_haptic_.reset(std::move(copies));
  }
  s->objects_ = m.objects();
  s->surfaces_to_haptic_.read()->point(s->objects_);
  s->tuned_surfaces_.init(s->objects_);
  for (int32_t o = 0; o < s->tuned_surfaces_.organ_count(); ++o) {
    s->stiffness_for_model_.push_back(s->tuned_surfaces_.parameters(o).stiffness_n_per_m);
  }
  s->stiffness_waiting_.assign(s->stiffness_for_model_.size(), 0);
  s->bodies_.init(m.bodies(), m.organ_count());
  for (Tool& tool : s->tools_) tool.objects_holding_duct = s->objects_;

  // The task engine: its state, and room for what each modelling step hands it.
  s->task_ = TaskState::create(m.task());
  const auto organs = static_cast<size_t>(m.organ_count());
  s->organ_force_n_.assign(organs, 0.0);
  s->organ_touched_.assign(organs, 0);
  s->tool_push_W_.assign(organs, Eigen::Vector3d::Zero());
  // The training metrics beside it (training_metrics.h), on the same input.
  const models::GraspSettings& grasp = m.tissue().settings().catheter_grasp;
  s->metrics_model_ = MetricsModel::build(m.task(), grasp.grasp_below_rad, grasp.release_above_rad,
                                          m.timing().model_dt_s, rs.duration_s, rs.dominant_tool);
  s->metrics_ = MetricsState::create(s->metrics_model_);
  write_task_progress(m.task(), s->task_, 0.0, {}, 0.0, &s->task_progress_);

  ModelSnapshot m0;
  m0.catheter = s->world_->catheter().positions;
  m0.catheter_velocities = s->world_->catheter().velocities;
  m0.organs = s->world_->make_deformations();
  m0.task = s->task_progress_;
  s->model_to_haptic_.reset(m0);
  s->model_to_graphics_.reset(m0);

  // Recording and event space for the whole duration (the haptic loop never allocates), each
  // written once here so that its pages are the process's from the start: the loops take no
  // page fault on them (as a permitted mlockall does it live; the default memlock limit refuses
  // it) and the resident memory is what it will be (the soak's growth, issue 25).
  const auto touched = [](auto* v, size_t n) {
    v->resize(n);
    v->clear();
  };
  for (hardware::DeviceRecording& r : s->recordings_) {
    r.period_s = timing.dt_s;
    touched(&r.samples, static_cast<size_t>(timing.recorded_ticks) + 1);
  }
  touched(&s->tick_log_, static_cast<size_t>(timing.recorded_ticks) + 1);
  // Live, the modelling loop steps on its own clock: more steps than ticks / 5 when the haptic
  // loop runs behind it (a loaded machine, a sanitizer's build); one per tick is room for a
  // haptic loop five times slower than its rate.
  touched(&s->step_log_, static_cast<size_t>(timing.recorded_ticks) + kStepsBeyondTicks);
  touched(&s->events_, size_t{1024});

  for (Tool& tool : s->tools_) {
    if (Status started = tool.device->start(); !started.ok()) {
      return diagnostic(std::string(tool.device->name()) + ": " + started.message());
    }
    tool.started = true;
  }
  return s;
}

Session::~Session() {
  for (Tool& tool : tools_) {
    if (tool.started && tool.device) tool.device->stop();
  }
}

void Session::trip(int64_t tick, int32_t tool, WatchdogReason reason, ModelFault fault) noexcept {
  // A fault that lasts (a device still unplugged, a model failing step after step: the same
  // fault tick after tick) is one event, not one per tick, whatever else trips meanwhile; a
  // fault that comes back later, or after a resume, is a new one.
  const size_t who = tool < 0 ? 0 : static_cast<size_t>(tool) + 1;  // the loop, left, right
  int64_t& last = last_trip_tick_[who][static_cast<size_t>(reason)];
  const bool repeat = paused_.load(std::memory_order_relaxed) && tick <= last + 1;
  last = tick;
  if (repeat) {
    gain_ = 0.0;
    return;
  }
  if (events_.size() < events_.capacity()) {
    events_.push_back({tick, tool, reason, fault});
  } else {
    ++events_dropped_;
  }
  paused_.store(true, std::memory_order_relaxed);
  gain_ = 0.0;
}

// One haptic tick (§7.6), in its stages: the watchdog's checks and the newest model, each tool
// read and put through its trocar with its proxies' wrench, the commands limited and sent, the
// snapshots published.
void Session::haptic_tick(int64_t tick, double lateness_s) noexcept {
  const ModelSnapshot& model = take_up_model(tick, lateness_s);
  HapticSnapshot& snap = to_model_.write_slot();
  snap.tick = tick;
  bodies_.pose_objects(objects_);  // where the free bodies are this tick (§6.4)
  std::array<hardware::DeviceCommand, 2> wanted{};
  int32_t touched = -1;
  for (size_t i = 0; i < 2; ++i) {
    // What it holds in the model it read; what it touches once its proxies have moved (a tool
    // not read touches nothing).
    const bool catheter_held = model.grasps[i].held;
    const bool duct_held = model.duct_grasps[i].grasping();
    tick_reads_.touch[i] = tool_touch(nullptr, 0, catheter_held, duct_held);
    ToolKinematics k;
    if (!read_tool(i, tick, &k)) continue;  // keep the tool where it was
    wanted[i] = tools_[i].probe ? probe_command(i, k, &snap.tools[i], tick)
                                : tool_command(i, k, model, &snap.tools[i], tick);
    // The tool's contacts push the free bodies (moving_bodies.h: this tick, right after the
    // proxies, so the coupling creates no energy).
    // Each contact also carries the stiffness it was rendered with (its organ's k times its
    // stiffness_factor), for the tissue model's dent (an author's live tuning reaches the model
    // with the very tick that felt it).
    ToolSnapshot& ts = snap.tools[i];
    for (int32_t c = 0; c < ts.organ_contact_count; ++c) {
      ToolContact& tc = ts.organ_contacts[static_cast<size_t>(c)];
      bodies_.push(tc.organ, tc.force_on_organ_W, tc.point_W);
      if (tc.organ >= 0 && static_cast<size_t>(tc.organ) < objects_.size()) {
        tc.stiffness_n_per_m =
            tc.stiffness_factor * objects_[static_cast<size_t>(tc.organ)].law.stiffness_n_per_m;
      }
    }
    if (ts.organ_contact_count > 0) touched = ts.organ_contacts[0].organ;
    tick_reads_.touch[i] =
        tool_touch(ts.organ_contacts.data(), ts.organ_contact_count, catheter_held, duct_held);
  }
  touched_organ_.store(touched, std::memory_order_relaxed);
  if (bodies_.count() > 0) {
    if (!bodies_.step(model.catheter_on_bodies, model_->timing().dt_s)) {
      trip(tick, -1, WatchdogReason::kNonFinite);
    }
    bodies_.write(&snap.bodies);
    for (int32_t b = 0; b < snap.bodies.count; ++b) {
      const Eigen::Isometry3d& pose = snap.bodies.bodies[static_cast<size_t>(b)].pose_W;
      hash_bytes(&hash_, pose.matrix().data(), 16 * sizeof(double));
    }
  }
  send_commands(tick, wanted, snap);
  publish_haptic(snap, lateness_s);
}

// Resume, the tick's timing, a model's fault, and the surfaces as the modelling loop last
// deformed them (already refitted there): the proxies feel them from this tick on.
const ModelSnapshot& Session::take_up_model(int64_t tick, double lateness_s) noexcept {
  // A lockstep replay resumes where the session did (resume() live is another thread's).
  const bool resume =
      scheduled_ ? scheduled_resume_ : resume_requested_.exchange(false, std::memory_order_relaxed);
  tick_reads_.resumed = resume && paused_.load(std::memory_order_relaxed);
  if (tick_reads_.resumed) {
    paused_.store(false, std::memory_order_relaxed);
    gain_ = 0.0;
    ramp_s_ = model_->settings().resume_ramp_s;
  }
  check_timing(tick, lateness_s);
  const ModelSnapshot& model =
      scheduled_model_ != nullptr ? *scheduled_model_ : model_to_haptic_.latest();
  if (model.fault) trip(tick, -1, WatchdogReason::kModelFault, model.fault);
  if (surfaces_to_haptic_.update()) surfaces_to_haptic_.read()->point(objects_);
  // What thread timing decided, for the recording: a replay takes the same (lockstep_order.h).
  tick_reads_.lateness_s = lateness_s;
  tick_reads_.model_steps_read = model.steps;
  tick_reads_.surface_steps_read = surfaces_to_haptic_.read()->model_steps();
  // An author's tuning, felt from this tick on; re-applied after every switch of the surfaces'
  // copy, which resets the shading pointers (surface_tuning.h).
  tick_reads_.tuned = take_tunings(tick);
  tuned_surfaces_.apply(objects_);
  if (tick_reads_.tuned || stiffness_waiting_count_ > 0) forward_stiffness_to_model(tick);
  return model;
}

// The author's tunings waiting in the mailbox (a lockstep replay: those the session took at this
// tick), and for the recording each organ's surface after them.
bool Session::take_tunings(int64_t tick) noexcept {
  tuned_surfaces_.clear_changed();
  bool any = false;
  if (scheduled_) {
    for (; next_scheduled_tuning_ < schedule_tunings_.size() &&
           schedule_tunings_[next_scheduled_tuning_].tick <= tick;
         ++next_scheduled_tuning_) {
      const TuningLog& t = schedule_tunings_[next_scheduled_tuning_];
      any = tuned_surfaces_.set(t.organ, t.parameters) || any;
    }
  } else {
    any = tuned_surfaces_.take(&tuning_mailbox_);
  }
  if (!any) return false;
  for (int32_t o = 0; o < tuned_surfaces_.organ_count(); ++o) {
    if (!tuned_surfaces_.changed(o)) continue;
    if (tuning_log_.size() < tuning_log_.capacity()) {
      tuning_log_.push_back({tick, o, tuned_surfaces_.parameters(o)});
    } else {
      ++tunings_unrecorded_;
    }
  }
  published_tunings_.store(static_cast<int64_t>(tuning_log_.size()), std::memory_order_release);
  return true;
}

// A tuned stiffness reaches the catheter's contacts too (TissueWorld::set_stiffness; the tools'
// contacts carry theirs): each organ's newest, posted once; one the mailbox had no room for
// waits for a later tick. A stiffness of 0 (no force) is not one the catheter can meet: it
// keeps the last positive one.
void Session::forward_stiffness_to_model(int64_t tick) noexcept {
  stiffness_waiting_count_ = 0;
  for (size_t o = 0; o < stiffness_for_model_.size(); ++o) {
    const double k = tuned_surfaces_.parameters(static_cast<int32_t>(o)).stiffness_n_per_m;
    if (k > 0.0 && k != stiffness_for_model_[o]) {
      stiffness_for_model_[o] = k;
      stiffness_waiting_[o] = 1;
    }
    if (stiffness_waiting_[o] == 0) continue;
    SurfaceParameters p;
    p.stiffness_n_per_m = k;
    stiffness_waiting_[o] = stiffness_to_model_.post(static_cast<int32_t>(o), p, tick) ? 0 : 1;
    stiffness_waiting_count_ += stiffness_waiting_[o];
  }
}

// A stall pauses; a late tick only zeroes this tick's commands and restarts the ramp back.
// In real time a stall's missed ticks then run back to back (absolute deadlines), each less
// late than the one before: those still a stall's lateness trip again as the same lasting event
// (trip()); the rest are late while paused, where zero is sent anyway, so they are not counted
// as late ticks. The catch-up of a shorter hold-up is a run of late ticks: zero until the loop
// is back on time, then one ramp.
void Session::check_timing(int64_t tick, double lateness_s) noexcept {
  const RuntimeSettings& settings = model_->settings();
  if (lateness_s >= settings.stall_s) {
    trip(tick, -1, WatchdogReason::kStall);
    return;
  }
  if (lateness_s <= settings.overrun_periods * model_->timing().dt_s ||
      paused_.load(std::memory_order_relaxed)) {
    return;
  }
  ++late_ticks_;
  late_tick_ = true;
  // The ramp starts again from zero; a slower one under way (a resume's) keeps its pace.
  if (!(gain_ < 1.0 && ramp_s_ > settings.late_tick_ramp_s)) ramp_s_ = settings.late_tick_ramp_s;
  gain_ = 0.0;
}

// Reads tool i's device, records the sample, and puts the tool through its trocar. False (and
// the watchdog told) when the sample is not finite.
bool Session::read_tool(size_t i, int64_t tick, ToolKinematics* k) noexcept {
  Tool& tool = tools_[i];
  hardware::DeviceSample sample;
  const hardware::DeviceStatus st = tool.device->read(tick, model_->timing().dt_s, &sample);
  tool.status = st;
  if (st == hardware::DeviceStatus::kFinished) tool.finished = true;
  if (st == hardware::DeviceStatus::kDisconnected) {
    trip(tick, static_cast<int32_t>(i), WatchdogReason::kDeviceDisconnected);
  } else if (st == hardware::DeviceStatus::kError) {
    trip(tick, static_cast<int32_t>(i), WatchdogReason::kDeviceError);
  }
  tool.handle_read = false;
  hardware::DeviceRecording& rec = recordings_[i];
  if (rec.samples.size() < rec.samples.capacity()) {
    rec.samples.push_back({tick, sample, st});
  } else {
    ++dropped_samples_;
  }
  const bool sample_ok = sample.position_W.allFinite() &&
                         sample.orientation_W.coeffs().allFinite() &&
                         std::isfinite(sample.gripper_angle_rad);
  if (!sample_ok) {
    trip(tick, static_cast<int32_t>(i), WatchdogReason::kNonFinite);
    return false;
  }
  tool.handle_W = sample.position_W;
  tool.handle_read = true;
  *k = tool_kinematics(model_->tool(i).trocar, sample, tool.axis_W);
  tool.axis_W = k->axis_W;
  // A probe has no jaws: held open, it never grasps the catheter or the duct.
  if (tool.probe) k->pose.opening_rad = kProbeOpeningRad;
  return true;
}

// A probe (tools[].kind probe or ray-probe): its one proxy against the organs, the command at
// the handle through the fulcrum; its contacts for the tissue models and the free bodies.
hardware::DeviceCommand Session::probe_command(size_t i, const ToolKinematics& k, ToolSnapshot* ts,
                                               int64_t tick) noexcept {
  Tool& tool = tools_[i];
  const ProbeOutput out = tool.probe->step(objects_, k.pose, model_->timing().dt_s);
  Eigen::Vector3d force = out.force_W;
  Eigen::Vector3d torque = out.torque_W;
  if (out.fault || !force.allFinite() || !torque.allFinite()) {
    trip(tick, static_cast<int32_t>(i), WatchdogReason::kNonFinite);
    force.setZero();
    torque.setZero();
  }
  ts->pose = k.pose;
  ts->kind = tool.probe->kind();
  ts->proxy_tip_W = out.proxy_tip_W;
  ts->contacts = out.contact_count;
  ts->organ_contact_count = tool.probe->contacts(ts->organ_contacts);
  StiffnessBudget budget(k);
  tool.probe->add_to_budget(objects_, &budget);
  tool.coupling_wanted_W.setZero();  // a probe holds nothing: no coupling
  hardware::DeviceCommand command = handle_command(k, force, torque, 0.0);
  command.stiffness_n_per_m = budget.at_handle_n_per_m();
  return command;
}

// The tool's proxies against the organs, the virtual couplings to what its jaws hold, and the
// command at the handle through the fulcrum; its contacts for the tissue models.
hardware::DeviceCommand Session::tool_command(size_t i, const ToolKinematics& k,
                                              const ModelSnapshot& model, ToolSnapshot* ts,
                                              int64_t tick) noexcept {
  Tool& tool = tools_[i];
  const TissueModel& tissue = model_->tissue();
  const models::DuctGraspState& duct_grasp = model.duct_grasps[i];
  const std::span<const haptics::HapticObject> objects = touched_objects(i, duct_grasp);
  const haptics::GripperOutput out = tool.gripper.step(objects, k.pose, model_->timing().dt_s);
  Eigen::Vector3d force = out.force_W;
  Eigen::Vector3d torque = out.torque_W;
  double squeeze = out.squeeze_n;
  Eigen::Vector3d coupling_force = Eigen::Vector3d::Zero();  // the grasps' share, at the tip
  Eigen::Vector3d coupling_torque = Eigen::Vector3d::Zero();
  const models::GraspState& grasp = model.grasps[i];
  const models::JawFrame jaws = jaw_frame(k.pose);
  if (!tool.jaws_seen) tool.last_jaws = jaws;
  tool.jaws_seen = true;
  // The jaws now and a tick ago, for the couplings' dampers.
  models::HapticJaws now;
  now.jaws = jaws;
  now.jaws_before = tool.last_jaws;
  now.tick_s = model_->timing().dt_s;
  now.since_step_s = static_cast<double>(std::max<int64_t>(tick - model.tick, 0)) * now.tick_s;
  if (grasp.grasping()) {
    // The virtual coupling to the grasped catheter at the haptic rate: the coupling's spring
    // and damper between the jaws now and the held section as the model last left it, the
    // force the model's next step integrates (catheter_grasp.h); the squeeze from the jaws'
    // closure on it.
    const models::GraspWrench w =
        models::coupling_wrench(tissue.settings().catheter_grasp, now, tissue.catheter_model(),
                                {model.catheter, model.catheter_velocities}, grasp);
    coupling_force += w.force_W;
    coupling_torque += w.torque_W;
    squeeze = std::max(squeeze, grasp_squeeze(tissue.settings().catheter_grasp, jaws,
                                              tissue.catheter_model(), grasp));
  }
  tool.last_jaws = jaws;
  if (duct_grasp.grasping() && tissue.duct_organ() >= 0) {
    // The same for grasped tissue, against the duct's wall as this loop's database has it: the
    // model's springs and a damper on the jaws' motion (duct_grasp.h).
    const models::DuctCoupling c = models::duct_coupling(
        tissue.settings().duct_grasp, now, Eigen::Isometry3d::Identity(),
        surfaces_to_haptic_.read()->positions(tissue.duct_organ()), duct_grasp);
    coupling_force += c.force_on_tool_W;
    squeeze = std::max(squeeze, c.squeeze_n);
  }
  force += coupling_force;
  torque += coupling_torque;
  if (out.fault || !force.allFinite() || !torque.allFinite()) {
    trip(tick, static_cast<int32_t>(i), WatchdogReason::kNonFinite);
    force.setZero();
    torque.setZero();
  }
  ts->pose = k.pose;
  ts->contacts =
      out.segments[0].contact_count + out.segments[1].contact_count + out.segments[2].contact_count;
  // Where the proxies are, for drawing the tool on the tissue rather than in it (§5).
  for (size_t seg = 0; seg < 3; ++seg) {
    const haptics::SegmentProxyOutput& so = out.segments[seg];
    const bool fine = !out.fault && so.ideal_a_W.allFinite() && so.ideal_b_W.allFinite();
    ts->proxy_a_W[seg] = fine ? so.ideal_a_W : Eigen::Vector3d::Zero();
    ts->proxy_b_W[seg] = fine ? so.ideal_b_W : Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (const haptics::SegmentContact& c : tool.gripper.proxy(static_cast<int>(seg)).contacts()) {
      normal += c.normal_W;
    }
    ts->proxy_normal_W[seg] =
        normal.norm() > 1e-9 && normal.allFinite() ? normal.normalized() : Eigen::Vector3d::Zero();
  }
  if (out.fault) {
    // A faulted proxy was reset: the device's pose is the best there is.
    std::array<Eigen::Vector3d, 3> a;
    std::array<Eigen::Vector3d, 3> b;
    tool.gripper.segments(k.pose, &a, &b);
    ts->proxy_a_W = a;
    ts->proxy_b_W = b;
  }
  // The tools' contacts for the tissue models: where each segment presses on which organ.
  ts->organ_contact_count = 0;
  for (int seg = 0; seg < 3; ++seg) {
    for (const haptics::SegmentContact& c : tool.gripper.proxy(seg).contacts()) {
      if (ts->organ_contact_count >= ToolModelInput::kMaxContacts) break;
      // The duct this tool holds is held by the grasp's anchors at the jaws (duct_grasp.h):
      // its contacts would push the same wall again, a step late, and that exchange alternates
      // step by step against the anchors (a 100 Hz force at the handle).
      if (duct_grasp.grasping() && c.object == tissue.duct_organ()) continue;
      ToolContact& tc = ts->organ_contacts[static_cast<size_t>(ts->organ_contact_count++)];
      tc.organ = c.object;
      tc.primitive = c.primitive;
      tc.point_W = c.point_W;
      tc.force_on_organ_W = -c.force_W;
      tc.stiffness_factor = c.stiffness_factor;
      tc.segment = seg;
    }
  }
  // The stiffness budget at the handle (trocar_tool.h): the three segments' contacts and the
  // grasp couplings in parallel, each through its lever; the limiter keeps it within the
  // device's (command_limiter.h). The couplings are taken at the jaws' tip, the longest lever.
  StiffnessBudget budget(k);
  budget.add_contacts(tool.gripper, objects);
  const Eigen::Vector3d jaw_tip_W =
      k.pose.hinge_W - tool.gripper.geometry().jaw_length_m * k.pose.shaft_dir_W;
  if (grasp.grasping()) {  // the coupling to the held section (catheter_grasp.h)
    budget.add(tissue.settings().catheter_grasp.coupling_stiffness_n_per_m, jaw_tip_W);
    // and its moment on the jaws' turn, felt at the handle as K / a² (trocar_tool.h)
    budget.add(
        models::coupling_rotational_stiffness(tissue.settings().catheter_grasp,
                                              tissue.catheter_model(), model.catheter, grasp) /
            (k.outside_m * k.outside_m),
        k.handle_W);
  }
  if (duct_grasp.grasping()) {  // a spring per grasped node (duct_grasp.h)
    budget.add(duct_grasp.count * tissue.settings().duct_grasp.attach_stiffness_n_per_m, jaw_tip_W);
  }
  hardware::DeviceCommand command = handle_command(k, force, torque, squeeze);
  command.stiffness_n_per_m = budget.at_handle_n_per_m();
  if (command.force_W.allFinite())
    command.force_W += coupling_damper(i, k, force, coupling_force, coupling_torque);
  return command;
}

// The organs as tool i's proxies see them this tick. While the tool holds the duct, the grasp's
// springs are the contact between its jaws and the held wall (duct_grasp.h): the wall's own force
// law would render that contact a second time, against a wall the grasp itself moves at the
// modelling rate, and the two exchange force from tick to tick (a buzz of about 2 N at the tip in
// the simulated hand's holds). The duct stays a geometric obstacle for the proxies — they do not
// pass through it, so letting go finds them where they were — but with its force clamped to zero.
std::span<const haptics::HapticObject> Session::touched_objects(
    size_t i, const models::DuctGraspState& duct_grasp) noexcept {
  const int32_t duct = model_->tissue().duct_organ();
  if (!duct_grasp.grasping() || duct < 0) return objects_;
  std::vector<haptics::HapticObject>& held = tools_[i].objects_holding_duct;
  std::copy(objects_.begin(), objects_.end(), held.begin());  // same size: no allocation
  haptics::ForceLaw& law = held[static_cast<size_t>(duct)].law;
  law.max_force_n = 0.0;        // no force, whatever the law
  law.stiffness_n_per_m = 0.0;  // and none in the stiffness budget at the handle
  return held;
}

// The grasp couplings' own passivity controller: their share of the force at the handle, observed
// on its own (the organs' contacts dissipate plenty, which must not pay for a coupling's
// activity), with a reservoir that leaks (hardware/passivity_controller.h): a coupling that feeds
// the hand a little energy every cycle — two tools holding the catheter taut between them, the
// model's stiff tension sampled at 200 Hz — meets a damper within a few cycles. Returns the damper
// at the handle; zero while the tool's force is not finite (the watchdog's case).
Eigen::Vector3d Session::coupling_damper(size_t i, const ToolKinematics& k,
                                         const Eigen::Vector3d& force_tip_W,
                                         const Eigen::Vector3d& coupling_force_W,
                                         const Eigen::Vector3d& coupling_torque_W) noexcept {
  Tool& tool = tools_[i];
  tool.coupling_wanted_W.setZero();
  if (!force_tip_W.allFinite()) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d share = handle_command(k, coupling_force_W, coupling_torque_W, 0.0).force_W;
  tool.coupling_wanted_W = tool.coupling_passivity.apply(
      tool.handle_W, share, model_->timing().dt_s, tool.limiter.limits().max_force_n);
  return tool.coupling_wanted_W - share;
}

// Limits, the watchdog's zero, and the ramp back (after a resume or a late tick); then write,
// and hash what was sent.
void Session::send_commands(int64_t tick, const std::array<hardware::DeviceCommand, 2>& wanted,
                            const HapticSnapshot& snap) noexcept {
  const double dt = model_->timing().dt_s;
  const bool paused = paused_.load(std::memory_order_relaxed);
  const bool late = late_tick_;
  late_tick_ = false;
  if (!paused && !late && gain_ < 1.0) {
    gain_ = ramp_s_ > 0.0 ? std::min(1.0, gain_ + dt / ramp_s_) : 1.0;
  }
  std::array<hardware::DeviceCommand, 2> sent{};
  if (!paused) {
    // On a late tick too, so that a non-finite command still trips on the tick it appears.
    for (size_t i = 0; i < 2; ++i) {
      const hardware::LimitedCommand l = tools_[i].limiter.apply(wanted[i], dt, gain_);
      if (l.non_finite) trip(tick, static_cast<int32_t>(i), WatchdogReason::kNonFinite);
      sent[i] = l.command;
    }
  }
  // The couplings' share as sent: the limiter scales the whole force (stiffness, peak, sustained;
  // the rate limit apart), so by the same factor.
  for (size_t i = 0; i < 2; ++i) {
    Tool& tool = tools_[i];
    if (!tool.handle_read) {
      tool.coupling_passivity.skip();
      continue;
    }
    const double w2 = wanted[i].force_W.squaredNorm();
    const double scale =
        w2 > 0.0 ? std::clamp(sent[i].force_W.dot(wanted[i].force_W) / w2, 0.0, 1.0) : 0.0;
    tool.coupling_passivity.sent(scale * tool.coupling_wanted_W);
  }
  // The passivity controller at each handle, last: a damper where the simulation would give the
  // hand more energy than it took, within the limiter's force bound.
  for (size_t i = 0; i < 2; ++i) {
    Tool& tool = tools_[i];
    if (!tool.handle_read) {
      tool.passivity.skip();
    } else {
      sent[i].force_W =
          tool.passivity.apply(tool.handle_W, sent[i].force_W, dt, tool.limiter.force_bound_n());
    }
  }
  // Paused before this tick or by it, or a late tick: zero, past the rate limit.
  if (late || paused_.load(std::memory_order_relaxed)) {
    for (size_t i = 0; i < 2; ++i) sent[i] = tools_[i].limiter.zero();
  }
  for (size_t i = 0; i < 2; ++i) {
    tools_[i].passivity.sent(sent[i].force_W);
    hardware::DeviceStatus st = tools_[i].device->write(sent[i]);
    // A lockstep replay's device takes any command; the live one's answer is in the record.
    if (scheduled_) st = schedule_ticks_[static_cast<size_t>(tick)].write_status[i];
    tick_reads_.write_status[i] = st;
    if (st == hardware::DeviceStatus::kDisconnected || st == hardware::DeviceStatus::kError) {
      trip(tick, static_cast<int32_t>(i),
           st == hardware::DeviceStatus::kError ? WatchdogReason::kDeviceError
                                                : WatchdogReason::kDeviceDisconnected);
    }
    max_force_sent_n_ = std::max(max_force_sent_n_, sent[i].force_W.norm());
    hash_vector(&hash_, sent[i].force_W);
    hash_vector(&hash_, sent[i].torque_W);
    hash_bytes(&hash_, &sent[i].squeeze_n, sizeof(double));
    hash_vector(&hash_, snap.tools[i].pose.hinge_W);
  }
  log_tick(tick, sent, late, paused);
}

// What was sent, beside the devices' samples, for the recording (capacity reserved at set-up);
// the ticks complete in all three are published to the recorder's thread.
void Session::log_tick(int64_t tick, const std::array<hardware::DeviceCommand, 2>& sent, bool late,
                       bool paused) noexcept {
  if (tick_log_.size() < tick_log_.capacity()) {
    TickLog log;
    log.tick = tick;
    timespec now{};
    clock_gettime(CLOCK_REALTIME, &now);  // vDSO: no system call
    log.wall_ns = static_cast<int64_t>(now.tv_sec) * 1000000000 + now.tv_nsec;
    for (size_t i = 0; i < 2; ++i) {
      log.force_W[i] = sent[i].force_W;
      log.squeeze_n[i] = sent[i].squeeze_n;
    }
    log.gain = gain_;
    log.late = late;
    log.paused = paused;
    log.resumed = tick_reads_.resumed;
    log.after_hold = after_hold_;
    log.tuned = tick_reads_.tuned;
    log.write_status = tick_reads_.write_status;
    log.lateness_s = tick_reads_.lateness_s;
    log.model_steps_read = tick_reads_.model_steps_read;
    log.surface_steps_read = tick_reads_.surface_steps_read;
    log.touch = tick_reads_.touch;
    tick_log_.push_back(log);
  }
  after_hold_ = false;
  const size_t complete =
      std::min({recordings_[0].samples.size(), recordings_[1].samples.size(), tick_log_.size()});
  published_ticks_.store(static_cast<int64_t>(complete), std::memory_order_release);
}

void Session::publish_haptic(HapticSnapshot& snap, double lateness_s) noexcept {
  snap.paused = paused_.load(std::memory_order_relaxed);
  worst_lateness_s_ = std::max(worst_lateness_s_, lateness_s);
  if (lateness_s > LoopStats::kMissedLateS) ++missed_deadlines_;
  snap.worst_lateness_s = worst_lateness_s_;
  snap.missed_deadlines = missed_deadlines_;
  snap.late_ticks = late_ticks_;
  if (!events_.empty()) {
    snap.last_reason = events_.back().reason;
    snap.last_model_fault = events_.back().model_fault;
  }
  to_graphics_.publish(snap);
  to_model_.publish();
}

void Session::model_tick(int64_t tick) noexcept {
  const HapticSnapshot& h = scheduled_haptic_ != nullptr ? *scheduled_haptic_ : to_model_.latest();
  if (step_log_.size() < step_log_.capacity()) step_log_.push_back({tick, h.tick});
  // A tuned stiffness is part of the models' state: hashed where it is taken up.
  stiffness_to_model_.take_until(h.tick, [this](int32_t organ, const SurfaceParameters& p) {
    world_->set_stiffness(organ, p.stiffness_n_per_m);
    hash_bytes(&model_hash_, &organ, sizeof(organ));
    hash_bytes(&model_hash_, &p.stiffness_n_per_m, sizeof(double));
  });
  for (size_t i = 0; i < 2; ++i) {
    ToolModelInput& in = model_input_[i];
    in.valid = h.tick >= 0;
    if (!in.valid) continue;
    const ToolSnapshot& t = h.tools[i];
    in.jaws = jaw_frame(t.pose);
    in.contact_count = t.organ_contact_count;
    in.contacts = t.organ_contacts;
    in.has_proxies = t.kind == ToolKind::kGripper;  // a probe's proxy is not kept there
    in.proxy_a_W = t.proxy_a_W;
    in.proxy_b_W = t.proxy_b_W;
  }
  if (injected_fault_steps_ > 0 && tick >= injected_fault_tick_) {
    world_->inject_non_finite(injected_fault_);
    --injected_fault_steps_;
  }
  // The free bodies where the haptic loop has them: the catheter meets them there.
  for (int32_t b = 0; b < h.bodies.count; ++b) {
    const BodySnapshot& body = h.bodies.bodies[static_cast<size_t>(b)];
    world_->set_organ_pose(body.organ, body.pose_W);
  }
  const ModelFault fault = world_->step(model_input_, model_->timing().model_dt_s);
  ++model_steps_;
  step_task_engine(tick, h);
  for (const Eigen::Vector3d& p : world_->catheter().positions) hash_vector(&model_hash_, p);
  // Before the snapshots: a tick that reads them is published after this step's read is.
  published_steps_.store(static_cast<int64_t>(step_log_.size()), std::memory_order_release);
  for (hardware::TripleBuffer<ModelSnapshot>* buf : {&model_to_haptic_, &model_to_graphics_}) {
    ModelSnapshot& m = buf->write_slot();
    m.tick = tick;
    m.steps = model_steps_;
    m.catheter = world_->catheter().positions;  // same size: no allocation
    m.catheter_velocities = world_->catheter().velocities;
    m.grasps = world_->catheter_grasps();
    m.duct_grasps = world_->duct_grasps();
    m.squeeze = world_->squeeze();
    m.catheter_contacts = world_->catheter_contacts();
    m.deepest_dent_m = world_->deepest_dent_m();
    world_->write_deformations(&m.organs);  // sized at set-up: no allocation
    m.fault = fault;
    m.catheter_on_bodies.clear();
    for (int32_t b = 0; b < h.bodies.count; ++b) {
      const BodySnapshot& body = h.bodies.bodies[static_cast<size_t>(b)];
      // The snapshot lists the bodies in the model's order (MovingBodies::write).
      const models::RigidBodyModel& bm = model_->bodies()[static_cast<size_t>(b)].model;
      world_->catheter_wrench(body.organ, body.pose_W * bm.com_B,
                              &m.catheter_on_bodies.force_W[static_cast<size_t>(b)],
                              &m.catheter_on_bodies.torque_W[static_cast<size_t>(b)]);
    }
    m.task = task_progress_;
    if (buf == &model_to_haptic_ && !scheduled_) {
      // The proxies' next copy of the surfaces takes up the same deformations here, on this
      // thread, so the haptic step only switches to it. (A lockstep replay takes up the copy
      // each tick felt live: scheduled_tick.)
      surfaces_to_haptic_.write_slot()->take_up(m.organs, model_steps_);
      surfaces_to_haptic_.publish();
    }
    buf->publish();
  }
  record_frame(tick, h);
}

// Every FrameRing::kFramePeriodS of session time, what the 3D view draws, for seeking in the
// recording (frame_ring.h): the tools this step read, the catheter and the organs it left.
void Session::record_frame(int64_t tick, const HapticSnapshot& h) noexcept {
  if (!frames_.reserved() || tick < next_frame_tick_) return;
  next_frame_tick_ = (tick / frame_every_ticks_ + 1) * frame_every_ticks_;
  // Real time: never wait on the recorder (a frame it is too far behind for is dropped and
  // counted; the ticks are kept regardless). --fast: wait for it, so that every frame is kept.
  RecordedFrame* f = frames_.begin_write(model_->settings().fast);
  if (f == nullptr) return;
  f->tick = tick;
  f->model_steps = model_steps_;
  for (size_t i = 0; i < 2; ++i) {
    const ToolSnapshot& t = h.tools[i];
    f->tools[i] = t.pose;
    f->proxy_a_W[i] = t.proxy_a_W;
    f->proxy_b_W[i] = t.proxy_b_W;
    f->proxy_normal_W[i] = t.proxy_normal_W;
  }
  f->catheter = world_->catheter().positions;  // same size: no allocation
  world_->write_deformations(&f->organs);      // sized at set-up: no allocation
  frames_.publish();
}

// The task engine on what this step has: the catheter and its grasps, each tool's tip and
// contacts, the forces on every organ (a tool's contacts summed, its grasp's pull on the duct;
// the catheter's push), the squeeze on the duct. Ends the session with the task when asked.
void Session::step_task_engine(int64_t tick, const HapticSnapshot& h) noexcept {
  const TaskModel& tm = model_->task();
  if (metrics_.done) return;
  std::fill(organ_force_n_.begin(), organ_force_n_.end(), 0.0);
  std::fill(organ_touched_.begin(), organ_touched_.end(), uint8_t{0});
  TaskInput in;
  in.t_s = static_cast<double>(tick) * model_->timing().dt_s;
  in.catheter = world_->catheter().positions;
  std::array<ToolForces, 2> forces{};  // each tool's, for the heads-up display
  for (size_t i = 0; i < 2; ++i) {
    in.catheter_held[i] = world_->catheter_grasps()[i].grasping();
    const ToolModelInput& tool = model_input_[i];
    in.tool_valid[i] = tool.valid;
    if (!tool.valid) continue;
    in.tool_tip_W[i] = h.tools[i].pose.hinge_W;
    std::fill(tool_push_W_.begin(), tool_push_W_.end(), Eigen::Vector3d::Zero());
    for (int32_t c = 0; c < tool.contact_count; ++c) {
      const ToolContact& tc = tool.contacts[static_cast<size_t>(c)];
      if (tc.organ < 0 || static_cast<size_t>(tc.organ) >= tool_push_W_.size()) continue;
      tool_push_W_[static_cast<size_t>(tc.organ)] += tc.force_on_organ_W;
      organ_touched_[static_cast<size_t>(tc.organ)] = 1;
    }
    for (size_t o = 0; o < organ_force_n_.size(); ++o) {
      double f = tool_push_W_[o].norm();
      if (static_cast<int32_t>(o) == tm.duct_organ) {
        f += world_->duct_grasp_force_n()[i];
        forces[i].on_duct_n = f;
      } else if (f > forces[i].on_organ_n) {
        forces[i].on_organ_n = f;
        forces[i].organ = static_cast<int32_t>(o);
      }
      organ_force_n_[o] = std::max(organ_force_n_[o], f);
    }
    forces[i].duct_squeeze_n = world_->duct_squeeze_n()[i];
    in.duct_squeeze_n = std::max(in.duct_squeeze_n, world_->duct_squeeze_n()[i]);
  }
  if (cbd_rest_ != nullptr && !in.catheter.empty()) {
    in.tip_in_common_bile_duct = inside_closed_surface(*cbd_rest_, in.catheter.back());
  }
  for (size_t o = 0; o < organ_force_n_.size(); ++o) {
    organ_force_n_[o] =
        std::max(organ_force_n_[o], world_->catheter_push_n(static_cast<int32_t>(o)));
  }
  in.organ_force_n = organ_force_n_;
  in.organ_touched = organ_touched_;
  step_task(tm, in, &task_);
  write_task_progress(tm, task_, in.t_s, forces,
                      tm.duct_organ >= 0 ? world_->catheter_push_n(tm.duct_organ) : 0.0,
                      &task_progress_);
  const std::array<double, 2> opening = {h.tools[0].pose.opening_rad, h.tools[1].pose.opening_rad};
  step_metrics(metrics_model_, tm, in, opening, task_, &metrics_);
  if (task_.done() && model_->settings().end_with_task) {
    stop_by_task_.store(true, std::memory_order_relaxed);
    request_stop();
  }
}

void Session::run_fast() {
  const SessionTiming& timing = model_->timing();
  const auto t0 = std::chrono::steady_clock::now();
  for (int64_t tick = 0; tick < timing.max_ticks; ++tick) {
    if (stop_.load(std::memory_order_relaxed)) {
      zero_forces();
      break;
    }
    const double late = injected_lateness(tick);
    const auto a = std::chrono::steady_clock::now();
    haptic_tick(tick, late);
    haptic_stats_.add(late, seconds_since(a));
    if (tick % timing.ticks_per_model == 0) {
      const auto b = std::chrono::steady_clock::now();
      model_tick(tick);
      model_stats_.add(0.0, seconds_since(b));
    }
    if (fast_observer_ && tick % fast_observe_every_ == 0) {
      fast_observer_(tick, to_graphics_.latest(), model_to_graphics_.latest());
    }
    if (tools_[0].finished && tools_[1].finished) break;
  }
  const double elapsed = seconds_since(t0);
  haptic_stats_.set_elapsed(elapsed);
  model_stats_.set_elapsed(elapsed);
}

namespace {

// Where a lockstep replay keeps snapshot i of a loop's last Session::kLockstepHistory.
size_t history_slot(int64_t i) {
  constexpr int64_t n = Session::kLockstepHistory;
  return static_cast<size_t>(((i % n) + n) % n);
}

}  // namespace

// A lockstep replay (replay_in_lockstep): ticks and steps in LockstepOrder's order, each tick
// given the model snapshot, surfaces, lateness and resume of its record, each step the haptic
// snapshot of its; both loops' last kLockstepHistory snapshots kept, and the next tick's older
// read apart (allocated here, before the first tick: a replay is not real-time, but it runs
// the same tick code).
void Session::run_scheduled() {
  const size_t ticks =
      std::min(schedule_ticks_.size(), static_cast<size_t>(model_->timing().max_ticks));
  std::vector<int64_t> oldest(ticks), newest(ticks), reads(schedule_steps_.size());
  for (size_t t = 0; t < ticks; ++t) {
    const TickLog& r = schedule_ticks_[t];
    oldest[t] = std::min(r.model_steps_read, r.surface_steps_read);
    newest[t] = std::max(r.model_steps_read, r.surface_steps_read);
  }
  for (size_t k = 0; k < reads.size(); ++k) reads[k] = schedule_steps_[k].haptic_tick_read;
  haptic_history_.assign(static_cast<size_t>(kLockstepHistory), to_model_.latest());
  model_history_.assign(static_cast<size_t>(kLockstepHistory), model_to_haptic_.latest());
  model_kept_ = model_to_haptic_.latest();
  model_kept_.steps = -1;  // nothing kept apart yet
  LockstepOrder order(oldest, newest, reads);
  // A review's frame of tick t once the steps run after it have run too (as run_fast's).
  int64_t frame = -1;
  const auto show = [&] {
    if (frame >= 0) fast_observer_(frame, to_graphics_.latest(), model_to_graphics_.latest());
    frame = -1;
  };
  const auto t0 = std::chrono::steady_clock::now();
  for (LockstepOrder::Next next = order.next(); next != LockstepOrder::Next::kDone;
       next = order.next()) {
    const int64_t t = order.ticks_done();
    // Asked from outside (the review's Cancel: ReplayTimeline::replay's progress): end here.
    if (stop_.load(std::memory_order_relaxed) && !stop_by_task_.load(std::memory_order_relaxed)) {
      break;
    }
    if (next == LockstepOrder::Next::kStuck) {
      lockstep_problem_ = "tick " + std::to_string(t) + " read the snapshot of modelling step " +
                          std::to_string(newest[static_cast<size_t>(t)]) + ", which the " +
                          "recording does not have whole (it is missing, or a step before it " +
                          "reads a tick after the recording's last): the replay stops there";
      break;
    }
    if (next == LockstepOrder::Next::kTick) show();
    const bool ran = next == LockstepOrder::Next::kTick
                         ? scheduled_tick(t)
                         : scheduled_step(order.steps_done(), order.next_tick_oldest_read());
    if (!ran) {
      lockstep_problem_ = "at tick " + std::to_string(t) + " the loops were further apart live " +
                          "than the replay keeps (" + std::to_string(kLockstepHistory) +
                          " snapshots of each): the replay stops there";
      break;
    }
    if (next == LockstepOrder::Next::kTick && fast_observer_ && t % fast_observe_every_ == 0) {
      frame = t;
    }
    order.ran(next);
  }
  lockstep_steps_not_run_ = static_cast<int64_t>(reads.size()) - order.steps_done();
  show();
  scheduled_haptic_ = nullptr;
  scheduled_model_ = nullptr;
  const double elapsed = seconds_since(t0);
  haptic_stats_.set_elapsed(elapsed);
  model_stats_.set_elapsed(elapsed);
}

// The model snapshot after `steps` steps if the replay still has it (in its history, or kept
// apart for the next tick), else null.
const ModelSnapshot* Session::kept_model(int64_t steps) const {
  const ModelSnapshot& m = model_history_[history_slot(steps)];
  if (m.steps == steps) return &m;
  return model_kept_.steps == steps ? &model_kept_ : nullptr;
}

// Tick t of a lockstep replay, on the surfaces, model snapshot, lateness and resume it had live;
// its snapshot kept for the steps that read it. False, and nothing run, when a snapshot it read
// is no longer kept.
bool Session::scheduled_tick(int64_t t) {
  const TickLog& r = schedule_ticks_[static_cast<size_t>(t)];
  const ModelSnapshot* model = kept_model(r.model_steps_read);
  const bool new_surfaces = r.surface_steps_read != scheduled_surface_steps_;
  const ModelSnapshot* surfaces = new_surfaces ? kept_model(r.surface_steps_read) : model;
  if (model == nullptr || surfaces == nullptr) return false;
  if (new_surfaces) {
    // The copy of the surfaces it felt, taken up here as the modelling thread does live.
    surfaces_to_haptic_.write_slot()->take_up(surfaces->organs, r.surface_steps_read);
    surfaces_to_haptic_.publish();
    scheduled_surface_steps_ = r.surface_steps_read;
  }
  scheduled_model_ = model;
  scheduled_resume_ = r.resumed;
  if (r.after_hold) {
    zero_forces();
    ramp_after_hold();
    after_hold_ = true;
  }
  const auto a = std::chrono::steady_clock::now();
  haptic_tick(t, r.lateness_s);
  haptic_stats_.add(r.lateness_s, seconds_since(a));
  haptic_history_[history_slot(t + 1)] = to_model_.latest();
  return true;
}

// Step k of a lockstep replay, on the haptic snapshot it had live; its snapshot kept for the
// ticks that read it, and the one it replaces in the history kept apart when it is the next
// tick's (`next_tick_read`). False, and nothing run, when its haptic snapshot is no longer kept.
bool Session::scheduled_step(int64_t k, int64_t next_tick_read) {
  const StepLog& r = schedule_steps_[static_cast<size_t>(k)];
  const HapticSnapshot& h = haptic_history_[history_slot(r.haptic_tick_read + 1)];
  if (h.tick != r.haptic_tick_read) return false;
  scheduled_haptic_ = &h;
  const auto b = std::chrono::steady_clock::now();
  model_tick(r.tick);
  model_stats_.add(0.0, seconds_since(b));
  ModelSnapshot& slot = model_history_[history_slot(k + 1)];
  if (slot.steps == next_tick_read && model_kept_.steps != next_tick_read) model_kept_ = slot;
  slot = model_to_haptic_.latest();
  return true;
}

double Session::injected_lateness(int64_t tick) const noexcept {
  double late = 0.0;
  for (size_t i = 0; i < injected_late_count_; ++i) {
    if (injected_late_[i].tick == tick) late = injected_late_[i].late_s;
  }
  return late;
}

void Session::run_realtime() {
  const RuntimeSettings& settings = model_->settings();
  const SessionTiming& timing = model_->timing();
  if (settings.realtime_priority) {
    const std::string mem = lock_memory();
    if (!mem.empty()) {
      warnings_.push_back(mem);
      memory_warning_ = mem;
      scheduling_flags_.fetch_or(2U, std::memory_order_release);
    }
  }
  std::string haptic_warning;
  std::string model_warning;
  const int64_t period_ns = std::llround(timing.dt_s * 1e9);
  const int64_t model_period_ns = period_ns * timing.ticks_per_model;
  // The schedule starts once the haptic thread runs at its priority: starting a thread (its
  // stack populated under mlockall) can take tens of milliseconds, which would otherwise make
  // the first ticks late and trip the watchdog before the session has begun.
  std::atomic<int64_t> start{0};
  haptic_done_.store(false);
  int isolated_cpu = -1;
  std::thread haptic([&] {
    if (settings.realtime_priority) haptic_warning = request_realtime_priority(80);
    int64_t spin_ns = settings.spin_ns;
    if (settings.isolate_haptic_processor) {
      const bool fifo = settings.realtime_priority && haptic_warning.empty();
      const bool keep_others_off = keep_others_off_haptic_processor(allowed_processors(), fifo);
      const Result<int> cpu = isolate_calling_thread(keep_others_off);
      isolated_cpu = cpu.ok() ? cpu.value() : -1;
      spin_ns = haptic_spin_ns(settings, /*shares_processor=*/!keep_others_off);
    }
    if (!haptic_warning.empty()) {  // before the first tick: the string may allocate
      priority_warning_ = haptic_warning;
      scheduling_flags_.fetch_or(1U, std::memory_order_release);
    }
    const int64_t start_ns = monotonic_ns() + 5 * period_ns;
    start.store(start_ns, std::memory_order_release);
    for (int64_t tick = 0; tick < timing.max_ticks; ++tick) {
      if (stop_.load(std::memory_order_relaxed)) {
        zero_forces();  // first, before the modelling loop is joined (a step may be running)
        break;
      }
      int64_t deadline =
          start_ns + hold_offset_ns_.load(std::memory_order_relaxed) + tick * period_ns;
      if (hold_requested_.load(std::memory_order_relaxed)) {
        deadline = wait_while_held(deadline);
        after_hold_ = true;
        if (stop_.load(std::memory_order_relaxed)) break;  // the hold's zero was the last command
      }
      // A test's late tick (inject_lateness): the thread wakes that much after its deadline.
      sleep_until_ns(deadline + std::llround(injected_lateness(tick) * 1e9), spin_ns);
      const int64_t begin = monotonic_ns();
      const double late = static_cast<double>(begin - deadline) * 1e-9;
      haptic_tick(tick, late);
      haptic_stats_.add(late, static_cast<double>(monotonic_ns() - begin) * 1e-9);
      if (tools_[0].finished && tools_[1].finished) break;
    }
    // The loops' time, not the trainee's pauses (hold()): their rates are of the time they ran.
    haptic_stats_.set_elapsed(
        static_cast<double>(monotonic_ns() - start_ns - hold_offset_ns_.load()) * 1e-9);
    haptic_done_.store(true);
  });
  std::thread model([&] {
    // Below the haptic thread, above rendering: a software-rendered frame can hold both cores
    // for tens of milliseconds, which would starve a best-effort modelling loop.
    if (settings.realtime_priority) model_warning = request_realtime_priority(60);
    int64_t start_ns = 0;
    while ((start_ns = start.load(std::memory_order_acquire)) == 0) {
      sleep_until_ns(monotonic_ns() + period_ns, 0);
    }
    for (int64_t k = 0; !haptic_done_.load(); ++k) {
      // While the haptic loop is held no step is taken and no period counts: the schedule
      // resumes where it was, moved on by the time held.
      if (holding_.load(std::memory_order_acquire)) {
        sleep_until_ns(monotonic_ns() + period_ns, 0);
        --k;
        continue;
      }
      const int64_t base_ns = start_ns + hold_offset_ns_.load(std::memory_order_acquire);
      const int64_t deadline = base_ns + k * model_period_ns;
      sleep_until_ns(deadline, 0);
      if (holding_.load(std::memory_order_acquire)) {
        --k;
        continue;
      }
      const int64_t begin = monotonic_ns();
      model_tick(k * timing.ticks_per_model);
      if (injected_delay_tick_ >= 0 && k * timing.ticks_per_model >= injected_delay_tick_) {
        injected_delay_tick_ = -1;  // once
        sleep_until_ns(monotonic_ns() + std::llround(injected_delay_s_ * 1e9), 0);
      }
      const int64_t end = monotonic_ns();
      model_stats_.add(static_cast<double>(begin - deadline) * 1e-9,
                       static_cast<double>(end - begin) * 1e-9);
      // Periods already past are skipped, not caught up: a model step is worth taking only on
      // fresh inputs, and a real-time thread that never sleeps would starve the rest.
      // (From the schedule as it is now: a hold taken meanwhile moved it on.)
      k = std::max(
          k, (end - start_ns - hold_offset_ns_.load(std::memory_order_acquire)) / model_period_ns);
    }
    model_stats_.set_elapsed(
        static_cast<double>(monotonic_ns() - start_ns - hold_offset_ns_.load()) * 1e-9);
  });
  haptic.join();
  model.join();
  release_isolated_processor(isolated_cpu);
  if (!haptic_warning.empty()) warnings_.push_back(haptic_warning);
  if (!model_warning.empty()) warnings_.push_back("modelling loop: " + model_warning);
}

int64_t Session::wait_while_held(int64_t deadline_ns) noexcept {
  zero_forces();
  holding_.store(true, std::memory_order_release);
  const int64_t period_ns = std::llround(model_->timing().dt_s * 1e9);
  // Acquire: what the releasing thread did before release() happens before the ticks after it
  // (ThreadSanitizer found the test's reads of the device log racing the next tick's write).
  while (hold_requested_.load(std::memory_order_acquire) &&
         !stop_.load(std::memory_order_relaxed)) {
    sleep_until_ns(monotonic_ns() + period_ns, 0);
  }
  // The tick that was due runs now; every later one keeps its distance from it.
  const int64_t now_ns = monotonic_ns();
  if (now_ns > deadline_ns) {
    hold_offset_ns_.fetch_add(now_ns - deadline_ns, std::memory_order_release);
    deadline_ns = now_ns;
  }
  ramp_after_hold();
  holding_.store(false, std::memory_order_release);
  return deadline_ns;
}

// Zero first, past the rate limit: the hand feels nothing from the moment the hold is taken,
// or the stop seen.
void Session::zero_forces() noexcept {
  for (Tool& tool : tools_) (void)tool.device->write(tool.limiter.zero());
}

// The forces come back as after a resume: from zero, over resume_ramp_s.
void Session::ramp_after_hold() noexcept {
  gain_ = 0.0;
  ramp_s_ = model_->settings().resume_ramp_s;
}

std::vector<std::string> Session::scheduling_warnings() const {
  const uint8_t flags = scheduling_flags_.load(std::memory_order_acquire);
  std::vector<std::string> w;
  if ((flags & 1U) != 0) w.push_back(priority_warning_);
  if ((flags & 2U) != 0) w.push_back(memory_warning_);
  return w;
}

Status Session::record_to(const std::filesystem::path& file, const std::string& header_json) {
  auto opened = SessionRecorder::open(file, header_json);
  if (!opened.ok()) return opened.diagnostics();
  recorder_ = std::move(opened).value();
  // An author's tunings have room only in a session that records them (4 MB).
  tuning_log_.reserve(kMaxRecordedTunings);
  frames_.reserve(world_->catheter().positions.size(), world_->make_deformations());
  frame_every_ticks_ =
      std::max<int64_t>(1, std::llround(FrameRing::kFramePeriodS / model_->timing().dt_s));
  return {};
}

SessionMetrics Session::run() {
  if (recorder_) {
    RecordingSources from;
    from.left = recordings_[0].samples.data();
    from.right = recordings_[1].samples.data();
    from.ticks = tick_log_.data();
    from.published_ticks = &published_ticks_;
    from.steps = step_log_.data();
    from.published_steps = &published_steps_;
    from.tunings = tuning_log_.data();
    from.published_tunings = &published_tunings_;
    from.frames = &frames_;
    recorder_->start(from);
  }
  if (scheduled_) {
    run_scheduled();
  } else if (model_->settings().fast) {
    run_fast();
  } else {
    run_realtime();
  }
  // The devices feel nothing once the session is over.
  for (Tool& tool : tools_) {
    tool.limiter.zero();
    (void)tool.device->write(hardware::DeviceCommand{});
  }
  SessionMetrics m;
  m.haptic = haptic_stats_;
  m.model = model_stats_;
  m.paused = paused_.load();
  m.events = events_;
  m.late_ticks = late_ticks_;
  m.recorded_ticks = static_cast<int64_t>(recordings_[0].samples.size());
  m.dropped_samples = dropped_samples_;
  // Each loop hashes its own state (no sharing between threads); the two are combined here.
  m.state_hash = hash_;
  hash_bytes(&m.state_hash, &model_hash_, sizeof(model_hash_));
  m.device_status = {tools_[0].status, tools_[1].status};
  m.warnings = warnings_;
  if (events_dropped_ > 0) {
    m.warnings.push_back(std::to_string(events_dropped_) + " watchdog events beyond the first " +
                         std::to_string(events_.size()) + " were counted but not listed");
  }
  m.max_force_sent_n = max_force_sent_n_;
  m.passivity = {tools_[0].passivity.figures(), tools_[1].passivity.figures()};
  m.coupling_passivity = {tools_[0].coupling_passivity.figures(),
                          tools_[1].coupling_passivity.figures()};
  m.organ_names = model_->organ_names();
  m.task_kind = model_->task().kind;
  m.task = task_;
  m.training = training_metrics(metrics_model_, metrics_, task_, m.organ_names);
  m.series = metrics_.series;
  m.proficiency = model_->proficiency();
  if (recorder_) finish_recording(&m);
  return m;
}

// The streamed recording's end: the rest of the ticks, the events, the end chunk (a file
// without it was interrupted). A recording stopped early (a full disk) is a warning: the session
// itself went on.
void Session::finish_recording(SessionMetrics* m) {
  nlohmann::ordered_json events = nlohmann::ordered_json::array();
  for (const TaskEvent& e : m->task.events) {
    events.push_back({{"t_s", e.t_s}, {"kind", std::string(to_string(e.kind))}});
  }
  const nlohmann::ordered_json body = {{"task_events", events},
                                       {"watchdog_events", m->events.size()}};
  char hash[32];
  std::snprintf(hash, sizeof(hash), "%016llx", static_cast<unsigned long long>(m->state_hash));
  // Fewer ticks recorded than run: the space reserved (RuntimeSettings::record_s) ran out; the
  // same for an author's tunings (kMaxRecordedTunings).
  const nlohmann::ordered_json end = {{"ticks", published_ticks_.load()},
                                      {"session_ticks", m->haptic.ticks()},
                                      {"tunings", published_tunings_.load()},
                                      {"tunings_unrecorded", tunings_unrecorded_},
                                      {"frames", frames_.published()},
                                      {"frames_dropped", frames_.dropped()},
                                      {"result", std::string(to_string(m->task.result))},
                                      {"state_hash", hash}};
  const Status done = recorder_->finish(body.dump(), end.dump());
  if (!done.ok()) m->warnings.push_back(done.message());
  recorder_.reset();
}

Status Session::write_recording(const std::string& dir) const {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Diagnostic{dir, 0, "", "cannot create the recording folder: " + ec.message()};
  // A trainee's session: readable by its owner only.
  std::filesystem::permissions(dir, std::filesystem::perms::owner_all,
                               std::filesystem::perm_options::replace, ec);
  // Each hand's inputs whole or not at all, the one tried whatever became of the other (a full
  // disk may take the first and leave room for neither): every failure is said.
  const std::filesystem::path d(dir);
  std::vector<Diagnostic> failed;
  for (size_t i = 0; i < 2; ++i) {
    Status written = hardware::write_device_recording(d / (i == 0 ? "left.lapdev" : "right.lapdev"),
                                                      recordings_[i]);
    for (Diagnostic& problem : std::move(written).diagnostics())
      failed.push_back(std::move(problem));
  }
  return failed;
}

}  // namespace lap::sim
