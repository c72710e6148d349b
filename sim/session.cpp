#include "sim/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <thread>

#include "sim/realtime_thread.h"

namespace lap::sim {
namespace {

constexpr uint64_t kFnvPrime = 1099511628211ULL;

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
    case WatchdogReason::kOverrun:
      return "haptic tick overran";
    case WatchdogReason::kNonFinite:
      return "non-finite force";
    case WatchdogReason::kDeviceDisconnected:
      return "device disconnected";
    case WatchdogReason::kDeviceError:
      return "device error";
  }
  return "unknown";
}

std::unique_ptr<Session> Session::create(
    const Scene& scene, std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices,
    const RuntimeSettings& settings, std::string* error) {
  auto fail = [&](const std::string& why) -> std::unique_ptr<Session> {
    if (error != nullptr) *error = why;
    return nullptr;
  };
  if (!(settings.haptic_rate_hz > 0.0) || !(settings.model_rate_hz > 0.0) ||
      settings.model_rate_hz > settings.haptic_rate_hz) {
    return fail("rates: expected 0 < model rate <= haptic rate");
  }
  if (!(settings.duration_s > 0.0) || !std::isfinite(settings.duration_s)) {
    return fail("duration: expected a positive number of seconds");
  }
  std::unique_ptr<Session> s(new Session());
  s->settings_ = settings;
  s->dt_ = 1.0 / settings.haptic_rate_hz;
  s->ticks_per_model_ =
      std::max<int64_t>(1, std::llround(settings.haptic_rate_hz / settings.model_rate_hz));
  s->model_dt_ = s->dt_ * static_cast<double>(s->ticks_per_model_);
  s->max_ticks_ = std::llround(settings.duration_s * settings.haptic_rate_hz);
  s->haptic_stats_ = LoopStats(s->dt_);
  s->model_stats_ = LoopStats(s->model_dt_);

  // The tools: left and right, each at its trocar.
  const Scenario& sc = scene.scenario;
  for (int side = 0; side < 2; ++side) {
    const ToolSpec* it = sc.tool(side == 0 ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight);
    if (it == nullptr) {
      return fail(sc.file.string() + ": tools: expected a " + (side == 0 ? "left" : "right") +
                  " tool");
    }
    const TrocarSpec* port = sc.trocar(it->trocar);
    if (port == nullptr) {
      return fail(sc.file.string() + ": tools: " + it->name + ": trocar '" + it->trocar +
                  "' is not among the trocars");
    }
    Tool& tool = s->tools_[static_cast<size_t>(side)];
    tool.trocar.port_W = port->position_m;
    tool.trocar.shaft_length_m = it->shaft_length_m;
    haptics::GripperGeometry g;
    g.jaw_length_m = it->jaw_length_m;
    g.shaft_length_m = it->shaft_length_m;
    tool.gripper = haptics::LaparoscopicGripper(g);
    tool.device = std::move(devices[static_cast<size_t>(side)]);
    if (tool.device == nullptr)
      return fail("no device for the " + std::string(side == 0 ? "left" : "right") + " tool");
    tool.limiter = hardware::CommandLimiter(tool.device->limits());
    // Start pointing from the port at the scene's centre.
    const Eigen::Vector3d centre = scene.bounds().center();
    if ((centre - tool.trocar.port_W).norm() > 1e-9) {
      tool.axis_W = (centre - tool.trocar.port_W).normalized();
    }
  }

  // The tissue world (§6.5, §7.7): the catheter (§7.7(3)), its proximal end held where it
  // enters, pointing at the task's target and ending 2 cm short of its centre; the organs' and
  // the duct's models.
  TissueWorldSettings ws;
  if (sc.catheter) {
    ws.catheter.length_m = sc.catheter->length_m;
    ws.catheter.outer_diameter_m = sc.catheter->diameter_m;
    ws.catheter.particles = sc.catheter->particles;
    ws.catheter.bending_stiffness_n_m2 = sc.catheter->bending_stiffness_n_m2;
    ws.catheter.linear_density_kg_per_m = sc.catheter->mass_kg / sc.catheter->length_m;
  }
  const Eigen::Vector3d target = scene.task_target_point();
  const Eigen::Vector3d entry = 0.5 * (s->tools_[0].trocar.port_W + s->tools_[1].trocar.port_W);
  Eigen::Vector3d dir = target - entry;
  dir = dir.norm() > 1e-9 ? Eigen::Vector3d(dir.normalized())
                          : Eigen::Vector3d(-Eigen::Vector3d::UnitY());
  ws.catheter_direction_W = dir;
  ws.catheter_start_W = target - (ws.catheter.length_m + 0.02) * dir;
  try {
    s->world_ = TissueWorld::build(scene, ws, &s->warnings_);
  } catch (const std::exception& e) {
    return fail(sc.file.string() + ": " + e.what());
  }

  // The proxies' databases: the surfaces the tissue world deforms (the duct: its shell), built
  // once at rest, then copied three times for the modelling thread to keep up to date and hand
  // to the haptic thread (haptic_surfaces.h).
  std::vector<std::unique_ptr<haptics::MeshDatabase>> dbs;
  std::vector<std::unique_ptr<haptics::SegmentDatabase>> sds;
  for (size_t i = 0; i < scene.organs.size(); ++i) {
    dbs.push_back(std::make_unique<haptics::MeshDatabase>(
        haptics::MeshDatabase::build(s->world_->surface(static_cast<int32_t>(i)))));
    sds.push_back(
        std::make_unique<haptics::SegmentDatabase>(haptics::SegmentDatabase::build(*dbs.back())));
    s->surfaces_.push_back(build_organ_surface(scene.organs[i], *dbs.back()));
  }
  {
    std::vector<const haptics::MeshDatabase*> db_ptrs;
    std::vector<const haptics::SegmentDatabase*> sd_ptrs;
    std::vector<const haptics::ShadingNormals*> shading_ptrs;
    for (size_t i = 0; i < dbs.size(); ++i) {
      db_ptrs.push_back(dbs[i].get());
      sd_ptrs.push_back(sds[i].get());
      shading_ptrs.push_back(s->surfaces_[i].shading.get());
    }
    std::array<std::unique_ptr<HapticSurfaces>, 3> copies;
    for (auto& c : copies) c = std::make_unique<HapticSurfaces>(db_ptrs, sd_ptrs, shading_ptrs);
    s->surfaces_to_haptic_.reset(std::move(copies));
  }
  for (size_t i = 0; i < scene.organs.size(); ++i) {
    haptics::HapticObject o;
    o.two_sided = s->world_->two_sided(static_cast<int32_t>(i));
    s->surfaces_[i].apply(scene.organs[i].material, &o);
    s->objects_.push_back(o);
  }
  s->surfaces_to_haptic_.read()->point(s->objects_);

  // A tissue stiffer than a device renders stably is worth saying before the session starts.
  for (size_t i = 0; i < scene.organs.size(); ++i) {
    for (const Tool& tool : s->tools_) {
      const double k = s->objects_[i].law.stiffness_n_per_m;
      const double k_max = tool.device->limits().max_stiffness_n_per_m;
      if (k > k_max) {
        s->warnings_.push_back(scene.organs[i].name + ": stiffness " + std::to_string(k) +
                               " N/m is above what " + std::string(tool.device->name()) +
                               " renders stably (" + std::to_string(k_max) +
                               " N/m); expect buzzing");
      }
    }
  }

  ModelSnapshot m0;
  m0.catheter = s->world_->catheter().positions;
  m0.organs = s->world_->make_deformations();
  s->model_to_haptic_.reset(m0);
  s->model_to_graphics_.reset(m0);

  // Recording and event space for the whole duration (the haptic loop never allocates).
  for (hardware::DeviceRecording& r : s->recordings_) {
    r.period_s = s->dt_;
    const int64_t keep =
        settings.record_s < 0.0
            ? s->max_ticks_
            : std::min<int64_t>(s->max_ticks_,
                                std::llround(settings.record_s * settings.haptic_rate_hz));
    r.samples.reserve(static_cast<size_t>(keep) + 1);
  }
  s->events_.reserve(1024);

  for (Tool& tool : s->tools_) {
    std::string why;
    if (!tool.device->start(&why)) {
      return fail(std::string(tool.device->name()) + ": " + why);
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

void Session::trip(int64_t tick, int32_t tool, WatchdogReason reason) noexcept {
  // A fault that lasts (a device still unplugged: the same fault tick after tick) is one
  // event, not one per tick; a fault that comes back later is a new one.
  const bool repeat = paused_.load(std::memory_order_relaxed) && !events_.empty() &&
                      events_.back().tool == tool && events_.back().reason == reason &&
                      tick <= last_trip_tick_ + 1;
  last_trip_tick_ = tick;
  if (repeat) {
    gain_ = 0.0;
    return;
  }
  if (events_.size() < events_.capacity()) {
    events_.push_back({tick, tool, reason});
  } else {
    ++events_dropped_;
  }
  paused_.store(true, std::memory_order_relaxed);
  gain_ = 0.0;
}

void Session::haptic_tick(int64_t tick, double lateness_s) noexcept {
  if (resume_requested_.exchange(false, std::memory_order_relaxed) &&
      paused_.load(std::memory_order_relaxed)) {
    paused_.store(false, std::memory_order_relaxed);
    gain_ = 0.0;
  }
  if (lateness_s > settings_.overrun_periods * dt_) trip(tick, -1, WatchdogReason::kOverrun);

  const ModelSnapshot& model = model_to_haptic_.latest();
  // The surfaces as the modelling loop last deformed them, already refitted there: the proxies
  // feel them from this tick on.
  if (surfaces_to_haptic_.update()) surfaces_to_haptic_.read()->point(objects_);
  HapticSnapshot& snap = to_model_.write_slot();
  snap.tick = tick;
  std::array<hardware::DeviceCommand, 2> wanted{};
  for (size_t i = 0; i < 2; ++i) {
    Tool& tool = tools_[i];
    hardware::DeviceSample sample;
    const hardware::DeviceStatus st = tool.device->read(tick, dt_, &sample);
    tool.status = st;
    if (st == hardware::DeviceStatus::kFinished) tool.finished = true;
    if (st == hardware::DeviceStatus::kDisconnected) {
      trip(tick, static_cast<int32_t>(i), WatchdogReason::kDeviceDisconnected);
    } else if (st == hardware::DeviceStatus::kError) {
      trip(tick, static_cast<int32_t>(i), WatchdogReason::kDeviceError);
    }
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
      continue;  // keep the tool where it was
    }
    const ToolKinematics k = tool_kinematics(tool.trocar, sample, tool.axis_W);
    tool.axis_W = k.axis_W;
    const haptics::GripperOutput out = tool.gripper.step(objects_, k.pose, dt_);
    Eigen::Vector3d force = out.force_W;
    double squeeze = out.squeeze_n;
    const TissueWorldSettings& ws = world_->settings();
    const models::GraspState& grasp = model.grasps[i];
    if (grasp.grasping()) {
      // The virtual coupling to the grasped catheter at the haptic rate, against the particles
      // where the modelling loop last put them (catheter_grasp.h); the squeeze from the jaws'
      // closure on it.
      const models::JawFrame jaws = jaw_frame(k.pose);
      force += models::coupling_force(ws.catheter_grasp, jaws, model.catheter, grasp);
      squeeze = std::max(squeeze,
                         grasp_squeeze(ws.catheter_grasp, jaws, world_->catheter_model(), grasp));
    }
    const models::DuctGraspState& duct_grasp = model.duct_grasps[i];
    if (duct_grasp.grasping() && world_->duct_organ() >= 0) {
      // The same for grasped tissue, against the duct's wall as this loop's database has it.
      const models::DuctCoupling c = models::duct_coupling(
          ws.duct_grasp, jaw_frame(k.pose), Eigen::Isometry3d::Identity(),
          surfaces_to_haptic_.read()->positions(world_->duct_organ()), duct_grasp);
      force += c.force_on_tool_W;
      squeeze = std::max(squeeze, c.squeeze_n);
    }
    if (out.fault || !force.allFinite()) {
      trip(tick, static_cast<int32_t>(i), WatchdogReason::kNonFinite);
      force.setZero();
    }
    wanted[i] = handle_command(k, force, out.torque_W, squeeze);
    ToolSnapshot& ts = snap.tools[i];
    ts.pose = k.pose;
    ts.contacts = out.segments[0].contact_count + out.segments[1].contact_count +
                  out.segments[2].contact_count;
    // The tools' contacts for the tissue models: where each segment presses on which organ.
    ts.organ_contact_count = 0;
    for (int seg = 0; seg < 3; ++seg) {
      for (const haptics::SegmentContact& c : tool.gripper.proxy(seg).contacts()) {
        if (ts.organ_contact_count >= ToolModelInput::kMaxContacts) break;
        ToolContact& tc = ts.organ_contacts[static_cast<size_t>(ts.organ_contact_count++)];
        tc.organ = c.object;
        tc.primitive = c.primitive;
        tc.point_W = c.point_W;
        tc.force_on_organ_W = -c.force_W;
      }
    }
  }
  // Limits, the watchdog's zero, and the resume ramp; then write.
  const bool paused = paused_.load(std::memory_order_relaxed);
  if (!paused && gain_ < 1.0) {
    gain_ =
        settings_.resume_ramp_s > 0.0 ? std::min(1.0, gain_ + dt_ / settings_.resume_ramp_s) : 1.0;
  }
  std::array<hardware::DeviceCommand, 2> sent{};
  if (!paused) {
    for (size_t i = 0; i < 2; ++i) {
      const hardware::LimitedCommand l = tools_[i].limiter.apply(wanted[i], dt_, gain_);
      if (l.non_finite) trip(tick, static_cast<int32_t>(i), WatchdogReason::kNonFinite);
      sent[i] = l.command;
    }
  }
  // Paused before this tick or by it: zero, past the rate limit.
  if (paused_.load(std::memory_order_relaxed)) {
    for (size_t i = 0; i < 2; ++i) sent[i] = tools_[i].limiter.zero();
  }
  for (size_t i = 0; i < 2; ++i) {
    const hardware::DeviceStatus st = tools_[i].device->write(sent[i]);
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
  snap.paused = paused_.load(std::memory_order_relaxed);
  worst_lateness_s_ = std::max(worst_lateness_s_, lateness_s);
  if (lateness_s > LoopStats::kMissedLateS) ++missed_deadlines_;
  snap.worst_lateness_s = worst_lateness_s_;
  snap.missed_deadlines = missed_deadlines_;
  if (!events_.empty()) snap.last_reason = events_.back().reason;
  to_graphics_.publish(snap);
  to_model_.publish();
}

void Session::model_tick(int64_t tick) noexcept {
  const HapticSnapshot& h = to_model_.latest();
  for (size_t i = 0; i < 2; ++i) {
    ToolModelInput& in = model_input_[i];
    in.valid = h.tick >= 0;
    if (!in.valid) continue;
    const ToolSnapshot& t = h.tools[i];
    in.jaws = jaw_frame(t.pose);
    in.contact_count = t.organ_contact_count;
    in.contacts = t.organ_contacts;
  }
  world_->step(model_input_, model_dt_);
  ++model_steps_;
  for (const Eigen::Vector3d& p : world_->catheter().positions) hash_vector(&model_hash_, p);
  for (hardware::TripleBuffer<ModelSnapshot>* buf : {&model_to_haptic_, &model_to_graphics_}) {
    ModelSnapshot& m = buf->write_slot();
    m.tick = tick;
    m.steps = model_steps_;
    m.catheter = world_->catheter().positions;  // same size: no allocation
    m.grasps = world_->catheter_grasps();
    m.duct_grasps = world_->duct_grasps();
    m.squeeze = world_->squeeze();
    m.catheter_contacts = world_->catheter_contacts();
    m.deepest_dent_m = world_->deepest_dent_m();
    world_->write_deformations(&m.organs);  // sized at set-up: no allocation
    if (buf == &model_to_haptic_) {
      // The proxies' next copy of the surfaces takes up the same deformations here, on this
      // thread, so the haptic step only switches to it.
      surfaces_to_haptic_.write_slot()->take_up(m.organs, model_steps_);
      surfaces_to_haptic_.publish();
    }
    buf->publish();
  }
}

void Session::run_fast() {
  const auto t0 = std::chrono::steady_clock::now();
  for (int64_t tick = 0; tick < max_ticks_; ++tick) {
    if (stop_.load(std::memory_order_relaxed)) break;
    const double late = tick == injected_late_tick_ ? injected_late_s_ : 0.0;
    const auto a = std::chrono::steady_clock::now();
    haptic_tick(tick, late);
    haptic_stats_.add(late, seconds_since(a));
    if (tick % ticks_per_model_ == 0) {
      const auto b = std::chrono::steady_clock::now();
      model_tick(tick);
      model_stats_.add(0.0, seconds_since(b));
    }
    if (tools_[0].finished && tools_[1].finished) break;
  }
  const double elapsed = seconds_since(t0);
  haptic_stats_.set_elapsed(elapsed);
  model_stats_.set_elapsed(elapsed);
}

void Session::run_realtime() {
  if (settings_.realtime_priority) {
    const std::string mem = lock_memory();
    if (!mem.empty()) {
      warnings_.push_back(mem);
      memory_warning_ = mem;
      scheduling_flags_.fetch_or(2U, std::memory_order_release);
    }
  }
  std::string haptic_warning;
  std::string model_warning;
  const int64_t period_ns = std::llround(dt_ * 1e9);
  const int64_t model_period_ns = period_ns * ticks_per_model_;
  // The schedule starts once the haptic thread runs at its priority: starting a thread (its
  // stack populated under mlockall) can take tens of milliseconds, which would otherwise make
  // the first ticks late and trip the watchdog before the session has begun.
  std::atomic<int64_t> start{0};
  haptic_done_.store(false);
  int isolated_cpu = -1;
  std::thread haptic([&] {
    if (settings_.realtime_priority) haptic_warning = request_realtime_priority(80);
    if (settings_.isolate_haptic_processor) isolated_cpu = isolate_calling_thread(nullptr);
    if (!haptic_warning.empty()) {  // before the first tick: the string may allocate
      priority_warning_ = haptic_warning;
      scheduling_flags_.fetch_or(1U, std::memory_order_release);
    }
    const int64_t start_ns = monotonic_ns() + 5 * period_ns;
    start.store(start_ns, std::memory_order_release);
    for (int64_t tick = 0; tick < max_ticks_; ++tick) {
      if (stop_.load(std::memory_order_relaxed)) break;
      const int64_t deadline = start_ns + tick * period_ns;
      sleep_until_ns(deadline, settings_.spin_ns);
      const int64_t begin = monotonic_ns();
      const double late = static_cast<double>(begin - deadline) * 1e-9;
      haptic_tick(tick, late);
      haptic_stats_.add(late, static_cast<double>(monotonic_ns() - begin) * 1e-9);
      if (tools_[0].finished && tools_[1].finished) break;
    }
    haptic_stats_.set_elapsed(static_cast<double>(monotonic_ns() - start_ns) * 1e-9);
    haptic_done_.store(true);
  });
  std::thread model([&] {
    // Below the haptic thread, above rendering: a software-rendered frame can hold both cores
    // for tens of milliseconds, which would starve a best-effort modelling loop.
    if (settings_.realtime_priority) model_warning = request_realtime_priority(60);
    int64_t start_ns = 0;
    while ((start_ns = start.load(std::memory_order_acquire)) == 0) {
      sleep_until_ns(monotonic_ns() + period_ns, 0);
    }
    for (int64_t k = 0; !haptic_done_.load(); ++k) {
      const int64_t deadline = start_ns + k * model_period_ns;
      sleep_until_ns(deadline, 0);
      const int64_t begin = monotonic_ns();
      model_tick(k * ticks_per_model_);
      const int64_t end = monotonic_ns();
      model_stats_.add(static_cast<double>(begin - deadline) * 1e-9,
                       static_cast<double>(end - begin) * 1e-9);
      // Periods already past are skipped, not caught up: a model step is worth taking only on
      // fresh inputs, and a real-time thread that never sleeps would starve the rest.
      k = std::max(k, (end - start_ns) / model_period_ns);
    }
    model_stats_.set_elapsed(static_cast<double>(monotonic_ns() - start_ns) * 1e-9);
  });
  haptic.join();
  model.join();
  release_isolated_processor(isolated_cpu);
  if (!haptic_warning.empty()) warnings_.push_back(haptic_warning);
  if (!model_warning.empty()) warnings_.push_back("modelling loop: " + model_warning);
}

std::vector<std::string> Session::scheduling_warnings() const {
  const uint8_t flags = scheduling_flags_.load(std::memory_order_acquire);
  std::vector<std::string> w;
  if ((flags & 1U) != 0) w.push_back(priority_warning_);
  if ((flags & 2U) != 0) w.push_back(memory_warning_);
  return w;
}

SessionMetrics Session::run() {
  if (settings_.fast) {
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
  return m;
}

bool Session::write_recording(const std::string& dir, std::string* error) const {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    if (error != nullptr) *error = dir + ": cannot create the recording folder: " + ec.message();
    return false;
  }
  const std::filesystem::path d(dir);
  return hardware::write_device_recording(d / "left.lapdev", recordings_[0], error) &&
         hardware::write_device_recording(d / "right.lapdev", recordings_[1], error);
}

}  // namespace lap::sim
