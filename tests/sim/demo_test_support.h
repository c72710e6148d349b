#pragma once
/// \file
/// What the tests of moving objects, probes and the demonstrations share: a scripted device that
/// lets a test look at the session on every tick and keeps every command sent to it, a tool tip
/// led along waypoints through its trocar, and a --fast session over both.

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hardware/scripted_device.h"
#include "sim/authoring/demo_assets.h"
#include "sim/runtime/session.h"
#include "sim/setup/scene.h"
#include "tests/test_support.h"

namespace lap::sim::demo_test {

/// A scripted device that calls `on_read` at the start of every tick (in a --fast session, on
/// the test's thread, when the snapshot of the tick before is the newest) and keeps the
/// commands it is sent.
class ObservedDevice final : public hardware::HapticDevice {
 public:
  ObservedDevice(hardware::ScriptedTrajectory t, const std::string& name)
      : inner_(std::move(t), name) {
    commands.reserve(20000);
  }
  Status start() override { return inner_.start(); }
  void stop() override {}
  hardware::DeviceStatus read(int64_t tick, double dt,
                              hardware::DeviceSample* out) noexcept override {
    if (on_read) on_read(tick);
    return inner_.read(tick, dt, out);
  }
  hardware::DeviceStatus write(const hardware::DeviceCommand& c) noexcept override {
    if (commands.size() < commands.capacity()) commands.push_back(c);
    return hardware::DeviceStatus::kOk;
  }
  [[nodiscard]] const hardware::DeviceLimits& limits() const override { return inner_.limits(); }
  [[nodiscard]] std::string_view name() const override { return "observed"; }
  [[nodiscard]] std::string last_error() const override { return {}; }
  std::function<void(int64_t tick)> on_read;
  std::vector<hardware::DeviceCommand> commands;

 private:
  hardware::ScriptedDevice inner_;
};

/// A --fast session of `scene` with each tool's tip led along its waypoints; `observe` is
/// called on every tick from the second on with the tick and the snapshot of the tick before.
struct ObservedRun {
  std::unique_ptr<Session> session;
  ObservedDevice* left = nullptr;
  ObservedDevice* right = nullptr;
};

using Observer = std::function<void(int64_t, const HapticSnapshot&, const ModelSnapshot&)>;

inline ObservedRun observed_session(const Scene& scene,
                                    std::array<hardware::ScriptedTrajectory, 2> scripts,
                                    double duration_s, const Observer& observe) {
  ObservedRun run;
  auto left = std::make_unique<ObservedDevice>(std::move(scripts[0]), "left");
  auto right = std::make_unique<ObservedDevice>(std::move(scripts[1]), "right");
  run.left = left.get();
  run.right = right.get();
  RuntimeSettings rs;
  rs.fast = true;
  rs.duration_s = duration_s;
  auto s = Session::create(scene, {std::move(left), std::move(right)}, rs);
  EXPECT_TRUE(s.ok()) << s.message();
  if (!s.ok()) return run;
  run.session = std::move(s).value();
  Session* session = run.session.get();
  if (observe) {
    run.left->on_read = [session, observe](int64_t tick) {
      if (tick == 0) return;
      observe(tick, session->graphics_haptic(), session->graphics_model());
    };
  }
  return run;
}

inline ObservedRun observed_session(const Scene& scene,
                                    const std::array<std::vector<TipWaypoint>, 2>& paths,
                                    double duration_s, const Observer& observe) {
  return observed_session(
      scene, {tip_path_script(scene, 0, paths[0]), tip_path_script(scene, 1, paths[1])}, duration_s,
      observe);
}

/// The force the tool's contacts put on the tool at its tip (the negated sum of their forces on
/// the organs) [N].
inline Eigen::Vector3d tip_force(const ToolSnapshot& t) {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (int32_t c = 0; c < t.organ_contact_count; ++c) {
    f -= t.organ_contacts[static_cast<size_t>(c)].force_on_organ_W;
  }
  return f;
}

}  // namespace lap::sim::demo_test
