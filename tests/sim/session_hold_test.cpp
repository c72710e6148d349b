// The trainee's pause (Session::hold): zero force at once, no tick while held (the task's clock,
// the models and the recording stand still), no watchdog event, and the forces ramped back in
// from zero after release(), as after a resume.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "tests/sim/session_test_support.h"

namespace lap::sim::session_test {
namespace {

TEST(SessionHold, NoTickRunsWhileHeldAndTheForcesComeBackAsAfterAResume) {
  const Scene& scene = introductory_scene();
  // The left tool pushed in and kept pressing on the organs: its force is not zero at the hold.
  auto left =
      std::make_unique<FaultyDevice>(push_and_hold(scene, 0), FaultyDevice::Fault::kNone, -1);
  left->commands.reserve(4000);
  FaultyDevice* device = left.get();
  RuntimeSettings rs = device_fault_run(2.0);
  rs.resume_ramp_s = 0.5;
  auto created = Session::create(scene, with_left(scene, std::move(left)), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  Session* s = created.value().get();
  constexpr int64_t kHoldAfterTick = kPressingTick;
  device->on_read = [s](int64_t tick) {
    if (tick == kHoldAfterTick) s->hold();
  };

  SessionMetrics m;
  const auto t0 = std::chrono::steady_clock::now();
  std::thread runner([&] { m = s->run(); });
  // Wait for the haptic loop to take the hold up (a loaded machine starts slowly).
  const auto give_up = t0 + std::chrono::seconds(30);
  while (!s->held() && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_TRUE(s->held()) << "the hold was never taken up";
  // held() (acquire) orders the haptic thread's writes before it: the commands so far are
  // readable here, and nothing writes while held.
  const size_t at_hold = device->commands.size();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const size_t after_wait = device->commands.size();
  s->release();
  runner.join();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Ticks 0..kHoldAfterTick each wrote one command, then the hold wrote one zero; nothing more
  // while held.
  ASSERT_EQ(at_hold, static_cast<size_t>(kHoldAfterTick + 2));
  EXPECT_EQ(after_wait, at_hold);
  const hardware::DeviceCommand& before = device->commands[static_cast<size_t>(kHoldAfterTick)];
  const hardware::DeviceCommand& zero = device->commands[at_hold - 1];
  EXPECT_GT(before.force_W.norm(), 0.05) << "the tool was not pressing when held";
  EXPECT_EQ(zero.force_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(zero.squeeze_n, 0.0);

  // Every tick of the session ran, after the wait too: the clock stood still while held.
  EXPECT_EQ(m.haptic.ticks(), 2000);
  // Its 2000 commands, the hold's zero, and the zero the session sends as it stops.
  EXPECT_EQ(device->commands.size(), 2002U);
  EXPECT_EQ(device->commands.back().force_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(m.recorded_ticks, 2000);
  EXPECT_GE(wall_s, 2.0 + 0.3);
  EXPECT_TRUE(m.events.empty()) << "a hold is not a watchdog event";
  EXPECT_FALSE(m.paused);

  // The first tick after the hold sends at most dt / resume_ramp_s of the force, growing back.
  const double first_after = device->commands[at_hold].force_W.norm();
  EXPECT_LE(first_after, 0.002 * 3.0 + 1e-12);  // the gain's first step times the device's peak
  ASSERT_GT(device->commands.size(), at_hold + 600);
  const double later = device->commands[at_hold + 600].force_W.norm();  // ramp done (0.5 s)
  EXPECT_GT(later, 0.05);
}

// A hold asked for in a --fast session is ignored: lockstep runs have no wall clock to stop.
TEST(SessionHold, AFastSessionIgnoresIt) {
  auto s = scripted_session(fast(0.5));
  s->hold();
  const SessionMetrics m = s->run();
  EXPECT_EQ(m.haptic.ticks(), 500);
  EXPECT_FALSE(s->held());
}

}  // namespace
}  // namespace lap::sim::session_test
