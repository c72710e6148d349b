#include "app/live_session.h"

#include <algorithm>
#include <filesystem>

#include "sim/report/session_replay.h"
#include "sim/report/session_report.h"
#include "sim/setup/device_factory.h"

namespace lap::app {
namespace fs = std::filesystem;

namespace {

bool live(const hardware::DeviceSpec& spec) {
  return spec.kind == hardware::DeviceKind::kSimulated ||
         spec.kind == hardware::DeviceKind::kPhantom || spec.usb_gripper;
}

}  // namespace

Status LiveSession::start(const sim::Scene& scene,
                          const std::array<hardware::DeviceSpec, 2>& specs) {
  stop();
  if (options_.fast && (live(specs[0]) || live(specs[1]))) {
    return diagnostic(
        "a session played as fast as the computer can takes scripted or replayed devices only");
  }
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices;
  for (int side = 0; side < 2; ++side) {
    const auto i = static_cast<size_t>(side);
    if (specs[i].kind != hardware::DeviceKind::kSimulated) {
      auto device = sim::make_device(specs[i], scene, side);
      if (!device.ok()) {
        devices_ = {};
        return diagnostic(std::string(side == 0 ? "left" : "right") + ": " + device.message());
      }
      devices[i] = std::move(device).value();
      devices_[i] = nullptr;  // not driven from the keyboard
      continue;
    }
    // Home: sim::home_handle_position (in view, pointing at the task's target), the jaws half
    // open (as sim::make_device starts a simulated device).
    hardware::SimulatedInput home;
    home.position_W = sim::home_handle_position(scene, side);
    home.gripper_angle_rad = 0.6;
    homes_[i] = home;
    inputs_[i] = home;
    auto dev = std::make_unique<hardware::SimulatedDevice>(home, side == 0 ? "left" : "right");
    devices_[i] = dev.get();
    devices[i] = std::move(dev);
  }
  sim::RuntimeSettings rs;
  // The renderer (software OpenGL on machines without a GPU) is kept off the haptic thread's
  // processor: measured better while rendering runs (docs/benchmarks.md).
  rs.isolate_haptic_processor = true;
  rs.fast = options_.fast;
  rs.dominant_tool = options_.dominant_tool;
  rs.end_with_task = options_.end_with_task;
  if (options_.end_with_task && scene.scenario.task) {
    // The task ends by its time limit at the latest; a minute more for the end to be seen.
    rs.duration_s = scene.scenario.task->time_limit_s + 60.0;
    rs.record_s = rs.duration_s;
  } else {
    rs.duration_s = 24.0 * 3600.0;  // until the window closes
    rs.record_s = 600.0;            // the first ten minutes of inputs are kept
  }
  auto created = sim::Session::create(scene, std::move(devices), rs);
  if (!created.ok()) {
    devices_ = {};
    return created.diagnostics();
  }
  std::unique_ptr<sim::Session> session = std::move(created).value();
  scenario_ = scene.scenario.file.string();
  if (!options_.record_dir.empty()) {
    // Streamed as it runs, with what it was run with: a crash loses at most the last 100 ms.
    const fs::path dir = options_.record_dir;
    std::error_code ec;
    if (fs::exists(dir / "session.lrec", ec) || fs::exists(dir / "session.json", ec)) {
      devices_ = {};
      return Diagnostic{dir.string(), 0, "",
                        "already holds a recorded session; choose a new folder"};
    }
    fs::create_directories(dir, ec);
    fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace, ec);
    // session.json now, once, with the digest of the scenario's bytes as loaded (a scenario
    // changed while the session runs replays with a note).
    const std::string header = sim::session_record_json(scenario_, scene.scenario.digest, rs);
    Status ready = sim::write_session_record(dir, header);
    if (ready.ok()) ready = session->record_to(dir / "session.lrec", header);
    if (!ready.ok()) {
      devices_ = {};
      return ready;
    }
  }
  session_ = std::move(session);
  user_paused_ = false;
  finished_.store(false, std::memory_order_release);
  runner_ = std::thread([this] {
    metrics_ = session_->run();
    finished_.store(true, std::memory_order_release);
  });
  return {};
}

void LiveSession::stop() {
  if (!session_) return;
  // Stop, then release: a held loop wakes to the stop and runs no tick (released first, it could
  // run one at its ramp's gain before it saw the stop).
  session_->request_stop();
  session_->release();
  if (runner_.joinable()) runner_.join();
  session_.reset();
  devices_ = {};
  user_paused_ = false;
}

Status LiveSession::stop_and_save(const std::string& dir) {
  if (!session_) return diagnostic("no session is running");
  session_->request_stop();  // then release (stop() says why)
  session_->release();
  runner_.join();  // metrics_ is complete from here
  Status saved = sim::save_session(*session_, metrics_, scenario_, options_.fast, dir);
  stop();
  return saved;
}

void LiveSession::nudge(int tool, const hardware::ToolNudge& n) {
  if (!session_ || user_paused_ || tool < 0 || tool > 1 ||
      devices_[static_cast<size_t>(tool)] == nullptr) {
    return;
  }
  hardware::SimulatedInput& in = inputs_[static_cast<size_t>(tool)];
  hardware::SimulatedDevice* device = devices_[static_cast<size_t>(tool)];
  in = hardware::nudged(in, n, device->limits().workspace_W,
                        session_->model().tool(static_cast<size_t>(tool)).trocar.port_W);
  device->set_input(in);
}

void LiveSession::go_home(int tool) {
  if (!session_ || user_paused_ || tool < 0 || tool > 1 ||
      devices_[static_cast<size_t>(tool)] == nullptr) {
    return;
  }
  inputs_[static_cast<size_t>(tool)] = homes_[static_cast<size_t>(tool)];
  devices_[static_cast<size_t>(tool)]->set_input(homes_[static_cast<size_t>(tool)]);
}

void LiveSession::pause() {
  if (!session_ || options_.fast || finished()) return;
  session_->hold();
  user_paused_ = true;
}

void LiveSession::resume() {
  if (!session_) return;
  session_->release();
  session_->resume();
  user_paused_ = false;
}

}  // namespace lap::app
