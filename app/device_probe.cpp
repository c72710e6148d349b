#include "app/device_probe.h"

#include <algorithm>
#include <cmath>

#include "sim/setup/device_factory.h"

namespace lap::app {

void DeviceProbe::start(const sim::Scene& scene, const std::array<hardware::DeviceSpec, 2>& specs) {
  stop();
  for (int side = 0; side < 2; ++side) {
    const auto i = static_cast<size_t>(side);
    homes_[i] = sim::home_handle_position(scene, side);
    problems_[i].clear();
    simulated_[i] = nullptr;
    if (specs[i].kind == hardware::DeviceKind::kSimulated) {  // as LiveSession builds it
      hardware::SimulatedInput home;
      home.position_W = homes_[i];
      home.gripper_angle_rad = 0.6;  // as LiveSession starts it
      home_inputs_[i] = home;
      inputs_[i] = home;
      auto dev = std::make_unique<hardware::SimulatedDevice>(home, side == 0 ? "left" : "right");
      simulated_[i] = dev.get();
      devices_[i] = std::move(dev);
    } else {
      auto made = sim::make_device(specs[i], scene, side);
      if (!made.ok()) {
        problems_[i] = made.message();
        continue;
      }
      devices_[i] = std::move(made).value();
    }
    if (const Status started = devices_[i]->start(); !started.ok()) {
      problems_[i] = started.message();
      devices_[i].reset();
      simulated_[i] = nullptr;
      continue;
    }
    // Nothing but zero: the test only reads.
    (void)devices_[i]->write(hardware::DeviceCommand{});
  }
  last_tick_ = -1;
  running_ = true;
}

void DeviceProbe::stop() {
  for (auto& d : devices_) {
    if (!d) continue;
    (void)d->write(hardware::DeviceCommand{});
    d->stop();
    d.reset();
  }
  simulated_ = {};
  running_ = false;
}

std::array<ProbeReading, 2> DeviceProbe::read(double elapsed_s) {
  std::array<ProbeReading, 2> out;
  // Ticks of 1 ms since start(), as a session's would be; never twice the same one.
  const int64_t tick = std::max(last_tick_ + 1, static_cast<int64_t>(std::floor(elapsed_s * 1e3)));
  last_tick_ = tick;
  for (size_t i = 0; i < 2; ++i) {
    ProbeReading& r = out[i];
    r.problem = problems_[i];
    if (!devices_[i]) continue;
    r.open = true;
    r.status = devices_[i]->read(tick, 1e-3, &r.sample);
    if (r.status == hardware::DeviceStatus::kDisconnected ||
        r.status == hardware::DeviceStatus::kError) {
      r.problem = devices_[i]->last_error();
    }
    r.from_home_m = r.sample.position_W - homes_[i];
  }
  return out;
}

void DeviceProbe::nudge(int side, const hardware::ToolNudge& n) {
  if (side < 0 || side > 1 || simulated_[static_cast<size_t>(side)] == nullptr) return;
  hardware::SimulatedInput& in = inputs_[static_cast<size_t>(side)];
  hardware::SimulatedDevice* device = simulated_[static_cast<size_t>(side)];
  // No port on this page: a roll turns the handle about its own axis.
  in = hardware::nudged(in, n, device->limits().workspace_W, std::nullopt);
  device->set_input(in);
}

void DeviceProbe::go_home(int side) {
  if (side < 0 || side > 1 || simulated_[static_cast<size_t>(side)] == nullptr) return;
  inputs_[static_cast<size_t>(side)] = home_inputs_[static_cast<size_t>(side)];
  simulated_[static_cast<size_t>(side)]->set_input(home_inputs_[static_cast<size_t>(side)]);
}

}  // namespace lap::app
