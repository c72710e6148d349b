#include "app/live_session.h"

#include <algorithm>

#include "sim/report/session_report.h"
#include "sim/setup/device_factory.h"

namespace lap::app {

Status LiveSession::start(const sim::Scene& scene,
                          const std::array<hardware::DeviceSpec, 2>& specs) {
  stop();
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
    hardware::SimulatedInput home;
    home.position_W = sim::default_handle_position(scene, side, 0.10);
    home.gripper_angle_rad = 0.6;
    inputs_[i] = home;
    auto dev = std::make_unique<hardware::SimulatedDevice>(home, side == 0 ? "left" : "right");
    devices_[i] = dev.get();
    devices[i] = std::move(dev);
  }
  sim::RuntimeSettings rs;
  // The renderer (software OpenGL on machines without a GPU) is kept off the haptic thread's
  // processor: measured better while rendering runs (docs/benchmarks.md).
  rs.isolate_haptic_processor = true;
  rs.duration_s = 24.0 * 3600.0;  // until the window closes
  rs.record_s = 600.0;            // the first ten minutes of inputs are kept
  rs.end_with_task = false;       // the window's session goes on; the task's outcome is kept
  auto created = sim::Session::create(scene, std::move(devices), rs);
  if (!created.ok()) return created.diagnostics();
  session_ = std::move(created).value();
  scenario_ = scene.scenario.file.string();
  runner_ = std::thread([this] { metrics_ = session_->run(); });
  return {};
}

void LiveSession::stop() {
  if (!session_) return;
  session_->request_stop();
  if (runner_.joinable()) runner_.join();
  session_.reset();
  devices_ = {};
}

Status LiveSession::stop_and_save(const std::string& dir) {
  if (!session_) return diagnostic("no session is running");
  session_->request_stop();
  runner_.join();  // metrics_ is complete from here
  Status saved = sim::save_session(*session_, metrics_, scenario_, false, dir);
  stop();
  return saved;
}

void LiveSession::nudge(int tool, const Eigen::Vector3d& delta, double opening_rad) {
  if (!session_ || tool < 0 || tool > 1 || devices_[static_cast<size_t>(tool)] == nullptr) return;
  hardware::SimulatedInput& in = inputs_[static_cast<size_t>(tool)];
  in.position_W += delta;
  in.gripper_angle_rad = std::clamp(in.gripper_angle_rad + opening_rad, 0.0, 1.0);
  devices_[static_cast<size_t>(tool)]->set_input(in);
}

}  // namespace lap::app
