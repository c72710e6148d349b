// Soak (issue 25): a --fast session of the default scenario with both tools in random smooth
// motion about the duct — in and out along their ports, sideways, the jaws opening and closing
// at random, so that they take and let go of the catheter and the duct again and again — for
// LAP_SOAK_S simulated seconds (30 by default; a twentieth under the sanitizers; an hour for the
// figures in docs/benchmarks.md). Checked: no watchdog event (no non-finite value anywhere, no
// model fault, no device fault), every tick run, the largest force finite and within the
// devices' limit, the catheter and the duct taken, the resident memory at the end within 1 % of
// what it was once the storage reserved at set-up had been touched.
// Not checked here: that no proxy is ever inside a mesh (the proxies' own tests do that).

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <random>
#include <thread>

#include "hardware/scripted_device.h"
#include "sim/runtime/session.h"
#include "sim/setup/device_factory.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

double soak_s() {
  const char* s = std::getenv("LAP_SOAK_S");
  const double requested = s != nullptr ? std::atof(s) : 30.0;
  return std::max(1.0, requested / static_cast<double>(test::kSanitizerDivisor));
}

/// Keyframes every 0.4 s: the tip within ±20 mm (along the port) and ±25 mm (across it) of the
/// duct, the jaws open or closed at random.
hardware::ScriptedTrajectory wander(const Scene& scene, int side, double duration_s,
                                    uint32_t seed) {
  const ToolSpec* tool =
      scene.scenario.tool(side == 0 ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight);
  const TrocarSpec* port = scene.scenario.trocar(tool->trocar);
  const Eigen::Vector3d target = scene.task_target_point();
  const Eigen::Vector3d axis = (target - port->position_m).normalized();
  const Eigen::Vector3d across = axis.unitOrthogonal();
  const Eigen::Vector3d across2 = axis.cross(across);
  const double reach = (target - port->position_m).norm();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  hardware::ScriptedTrajectory t;
  for (int i = 0; i == 0 || t.keyframes.back().time_s < duration_s; ++i) {
    hardware::Keyframe k;
    k.time_s = std::min(0.4 * i, duration_s);            // the last one at the session's end
    const double inside = reach - 0.01 + 0.02 * u(rng);  // the tip's depth past the port
    const Eigen::Vector3d tip =
        port->position_m + inside * axis + 0.025 * u(rng) * across + 0.025 * u(rng) * across2;
    // The handle: the shaft's length back from the tip through the port.
    k.position_W = tip - tool->shaft_length_m * (tip - port->position_m).normalized();
    k.gripper_angle_rad = u(rng) > 0.0 ? 0.8 : 0.1;
    t.keyframes.push_back(k);
  }
  return t;
}

int64_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  int64_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * sysconf(_SC_PAGESIZE);
}

TEST(Soak, BothToolsWanderingGraspingAndLettingGoForAWhile) {
  const double duration = soak_s();
  const Scene& scene = default_scene();
  Devices d{std::make_unique<hardware::ScriptedDevice>(wander(scene, 0, duration, 11), "left"),
            std::make_unique<hardware::ScriptedDevice>(wander(scene, 1, duration, 12), "right")};
  RuntimeSettings rs = fast(duration);
  rs.end_with_task = false;  // the task fails soon enough; the soak goes on
  // An hour's inputs would be 0.8 GB: the first fifth (10 s at most) are enough here.
  rs.record_s = std::min(10.0, duration / 5.0);
  auto created = Session::create(scene, std::move(d), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  const std::unique_ptr<Session> session = std::move(created).value();

  // The resident memory once the storage reserved at set-up has been touched (the first
  // record_s of inputs; at least a fifth of the way in), and what the tools hold, sampled while
  // it runs by this thread, the graphics snapshots' one reader as the window would be. Nothing
  // here grows as it samples (its own growth would read as the session's).
  const double settled = std::max(0.2, rs.record_s / duration + 0.05);
  const auto settled_tick = static_cast<int64_t>(settled * duration * 1000.0);
  std::atomic<bool> done{false};
  int64_t early = -1;
  int catheter_takes = 0, duct_takes = 0;
  const auto t0 = std::chrono::steady_clock::now();
  std::thread sampler([&] {
    bool catheter_held = false, duct_held = false;
    while (!done.load()) {
      if (early < 0 && session->graphics_haptic().tick >= settled_tick) early = resident_bytes();
      const ModelSnapshot& snap = session->graphics_model();
      const bool c = snap.grasps[0].grasping() || snap.grasps[1].grasping();
      const bool g = snap.duct_grasps[0].grasping() || snap.duct_grasps[1].grasping();
      catheter_takes += c && !catheter_held ? 1 : 0;
      duct_takes += g && !duct_held ? 1 : 0;
      catheter_held = c;
      duct_held = g;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  const SessionMetrics m = session->run();
  done.store(true);
  sampler.join();
  const int64_t late = resident_bytes();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  EXPECT_TRUE(m.events.empty()) << describe(m.events.front().reason, m.events.front().model_fault,
                                            m.organ_names);
  EXPECT_FALSE(m.paused);
  EXPECT_EQ(m.haptic.ticks(), static_cast<int64_t>(std::llround(duration * 1000.0)));
  EXPECT_TRUE(std::isfinite(m.max_force_sent_n));
  EXPECT_GT(m.max_force_sent_n, 0.0);  // they did touch
  for (const auto& s : m.device_status) EXPECT_NE(s, hardware::DeviceStatus::kError);
  // The catheter and the duct were taken and let go of (as sampled).
  EXPECT_GE(catheter_takes + duct_takes, duration >= 10.0 ? 2 : 1);
  ASSERT_GT(early, 0) << "the session ended before it settled";
  const double growth = static_cast<double>(late - early) / static_cast<double>(early);
  std::printf(
      "soak: %.1f s simulated in %.1f s; %lld haptic ticks (mean %.2f us, p99.9 %.2f us), %lld "
      "modelling steps (mean %.1f us); the catheter taken %d times, the duct %d times (as "
      "sampled); largest force %.2f N; resident memory %.1f MB once settled, %.1f MB at the end "
      "(%+.3f %%)\n",
      duration, wall_s, static_cast<long long>(m.haptic.ticks()), m.haptic.mean_step_s() * 1e6,
      m.haptic.step_quantile_s(0.999) * 1e6, static_cast<long long>(m.model.ticks()),
      m.model.mean_step_s() * 1e6, catheter_takes, duct_takes, m.max_force_sent_n,
      static_cast<double>(early) / 1e6, static_cast<double>(late) / 1e6, growth * 100.0);
  // (The sanitizers' allocator keeps freed memory in quarantine: the figure means nothing there.)
  if (test::kSanitizerDivisor == 1) {
    EXPECT_LT(growth, 0.01);
  }
}

}  // namespace
}  // namespace lap::sim
