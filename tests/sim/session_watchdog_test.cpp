// The watchdog of a running session: every fault, from a device, a stalled loop or a tissue
// model, sends zero force on the tick that sees it, pauses the session and loses nothing; a
// single late tick sends zero on that tick only, and the forces ramp back by themselves.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>
#include <thread>
#include <utility>
#include <vector>

#include "hardware/gripper_emulator.h"
#include "hardware/phantom_device.h"
#include "hardware/usb_gripper.h"
#include "sim/report/session_report.h"
#include "sim/runtime/session.h"
#include "sim/setup/device_factory.h"
#include "tests/sim/session_test_support.h"
#include "tests/support/fake_hd_control.h"
#include "tests/test_support.h"

namespace lap::sim {

// The model in the tests' listing (gtest would print the enum's byte). Here, in the enum's own
// namespace, where gtest's printer finds it.
inline void PrintTo(ModelFaultKind kind, std::ostream* os) { *os << to_string(kind); }

namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

// A model that meets a non-finite value is a fault like a haptic one: zero force from the next
// haptic tick on (the modelling step runs after the haptic tick it belongs to), the session
// paused, the model named; nothing recorded is lost.
class SessionModelFault : public ::testing::TestWithParam<ModelFaultKind> {};

TEST_P(SessionModelFault, ZeroForceWithinOneTickPausedAndTheModelNamed) {
  const Scene& scene = introductory_scene();
  const int64_t at = kPressingTick - kPressingTick % 5;  // a modelling step's tick (200 Hz)
  auto left = logged(scene, FaultyDevice::Fault::kNone, -1);
  FaultyDevice* dev = left.get();
  auto created = Session::create(scene, with_left(scene, std::move(left)), fast(2.5));
  ASSERT_TRUE(created.ok()) << created.message();
  auto s = std::move(created).value();
  s->inject_model_fault(at, GetParam(), 10);  // a fault that lasts ten modelling steps
  const SessionMetrics m = s->run();
  ASSERT_GT(dev->commands[at].force_W.norm(), 0.0) << "the fault must hit a pressing tool";
  for (size_t t = at + 1; t < dev->commands.size(); ++t) {
    ASSERT_EQ(dev->commands[t].force_W, Eigen::Vector3d::Zero()) << t;
  }
  EXPECT_TRUE(m.paused);
  // One event for the lasting fault, and nothing else: no non-finite value reached the proxies.
  ASSERT_EQ(m.events.size(), 1U);
  EXPECT_EQ(m.events[0].tick, at + 1);
  EXPECT_EQ(m.events[0].reason, WatchdogReason::kModelFault);
  EXPECT_EQ(m.events[0].model_fault.kind, GetParam());
  const int32_t organ = m.events[0].model_fault.organ;
  if (GetParam() == ModelFaultKind::kCatheter) {
    EXPECT_EQ(organ, -1);
  } else {
    ASSERT_GE(organ, 0);
    const std::string name = scene.organs[static_cast<size_t>(organ)].name;
    EXPECT_EQ(scene.organs[static_cast<size_t>(organ)].model,
              GetParam() == ModelFaultKind::kModalShell ? models::ModelKind::kModalShell
                                                        : models::ModelKind::kLocal)
        << name;
  }
  EXPECT_EQ(m.recorded_ticks, m.haptic.ticks());
  const nlohmann::ordered_json event =
      metrics_to_json(m, "default.yaml", true)["watchdog_events"][0];
  EXPECT_EQ(event["reason"], "model fault");
  EXPECT_EQ(event["model"], std::string(to_string(GetParam())));
  EXPECT_EQ(event["organ"], organ < 0 ? "" : scene.organs[static_cast<size_t>(organ)].name);
}

INSTANTIATE_TEST_SUITE_P(EachModel, SessionModelFault,
                         ::testing::Values(ModelFaultKind::kCatheter,
                                           ModelFaultKind::kLocalDeformation,
                                           ModelFaultKind::kModalShell),
                         [](const ::testing::TestParamInfo<ModelFaultKind>& info) {
                           std::string name(to_string(info.param));
                           std::replace(name.begin(), name.end(), ' ', '_');
                           return name;
                         });

struct FaultCase {
  FaultyDevice::Fault fault;
  WatchdogReason reason;
};

// The parameter in the tests' listing (gtest would print the struct's bytes).
void PrintTo(const FaultCase& c, std::ostream* os) { *os << to_string(c.reason); }

class SessionWatchdog : public ::testing::TestWithParam<FaultCase> {};

TEST_P(SessionWatchdog, ZeroForceOnTheTickPausedAndNothingLost) {
  const Scene& scene = introductory_scene();
  const int64_t at = kPressingTick;
  auto left = logged(scene, GetParam().fault, at);
  FaultyDevice* dev = left.get();
  Devices d = with_left(scene, std::move(left));
  auto s_created = Session::create(scene, std::move(d), fast(2.5));
  ASSERT_TRUE(s_created.ok()) << s_created.message();
  auto s = std::move(s_created).value();
  const SessionMetrics m = s->run();
  ASSERT_GT(dev->commands[at - 1].force_W.norm(), 0.0) << "the fault must hit a pressing tool";
  EXPECT_EQ(dev->commands[at].force_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(dev->commands[at].squeeze_n, 0.0);
  for (size_t t = at; t < dev->commands.size(); ++t) {
    ASSERT_EQ(dev->commands[t].force_W, Eigen::Vector3d::Zero()) << t;
  }
  EXPECT_TRUE(m.paused);
  ASSERT_FALSE(m.events.empty());
  EXPECT_EQ(m.events[0].tick, at);
  EXPECT_EQ(m.events[0].reason, GetParam().reason);
  // Every tick's input was recorded, before and after the fault.
  EXPECT_EQ(m.recorded_ticks, m.haptic.ticks());
  EXPECT_EQ(s->recording(0).samples.size(), static_cast<size_t>(m.haptic.ticks()));
}

INSTANTIATE_TEST_SUITE_P(
    Faults, SessionWatchdog,
    ::testing::Values(FaultCase{FaultyDevice::Fault::kNaN, WatchdogReason::kNonFinite},
                      FaultCase{FaultyDevice::Fault::kError, WatchdogReason::kDeviceError},
                      FaultCase{FaultyDevice::Fault::kDisconnect,
                                WatchdogReason::kDeviceDisconnected}),
    // Named by the fault (the default name would print the struct's bytes, padding included).
    [](const ::testing::TestParamInfo<FaultCase>& info) {
      switch (info.param.fault) {
        case FaultyDevice::Fault::kNaN:
          return std::string("NaN");
        case FaultyDevice::Fault::kError:
          return std::string("DeviceError");
        case FaultyDevice::Fault::kDisconnect:
          return std::string("Disconnect");
        default:
          return std::string("Other");
      }
    });

// A session of the left tool pushed in and held there, pressing on the organs (push_and_hold),
// with lateness injected at some ticks: what it sent, and its metrics. The device has no
// sustained-force bound and a stiffness limit the tool's budget never reaches: the runs compare
// the ramps after a late tick or a pause with a run without them, and both limits keep a state
// (the motors' heat, the stiffness scale recovering) that would make each command depend on what
// was sent before, or on whether the session was paused (they have their own tests,
// tests/hardware/command_limiter_test.cpp).
struct HeldRun {
  std::vector<hardware::DeviceCommand> commands;
  SessionMetrics metrics;
  int64_t snapshot_late_ticks = -1;  ///< as the graphics' last snapshot counts them
};

HeldRun held_run(const std::vector<std::pair<int64_t, double>>& lateness,
                 const RuntimeSettings& rs = fast(2.5),
                 const std::function<void(Session*, int64_t)>& on_read = {}) {
  HeldRun r;
  const Scene& scene = introductory_scene();
  hardware::DeviceLimits stateless;
  stateless.max_continuous_force_n = 0.0;
  stateless.max_stiffness_n_per_m = 1e9;
  auto left = std::make_unique<FaultyDevice>(push_and_hold(scene, 0), FaultyDevice::Fault::kNone,
                                             -1, stateless);
  left->commands.reserve(4000);
  FaultyDevice* dev = left.get();
  auto created = Session::create(scene, with_left(scene, std::move(left)), rs);
  EXPECT_TRUE(created.ok()) << created.message();
  if (!created.ok()) return r;
  auto s = std::move(created).value();
  for (const auto& [tick, late_s] : lateness) EXPECT_TRUE(s->inject_lateness(tick, late_s));
  if (on_read) dev->on_read = [&](int64_t tick) { on_read(s.get(), tick); };
  r.metrics = s->run();
  r.commands = dev->commands;
  r.snapshot_late_ticks = s->graphics_haptic().late_ticks;
  return r;
}

bool is_zero(const hardware::DeviceCommand& c) {
  return c.force_W == Eigen::Vector3d::Zero() && c.torque_W == Eigen::Vector3d::Zero() &&
         c.squeeze_n == 0.0;
}

// A desktop kernel starts a tick a few milliseconds late now and then: each such tick sends
// zero force and the forces ramp back by themselves within 100 ms; the session never pauses
// and the events list stays empty (the late ticks are counted instead).
TEST(Session, SingleLateTicksNeverPauseAndTheForcesRampBackWithin100Ms) {
  const HeldRun reference = held_run({});
  ASSERT_FALSE(reference.metrics.paused);
  std::vector<std::pair<int64_t, double>> late;
  for (int k = 0; k < 10; ++k) {  // 2.5 ms .. 15 ms late, 110 ms apart, while pressing
    late.emplace_back(kPressingTick + 110 * k, 0.0025 + k * (0.015 - 0.0025) / 9.0);
  }
  const HeldRun r = held_run(late);
  const SessionMetrics& m = r.metrics;
  EXPECT_FALSE(m.paused);
  EXPECT_TRUE(m.events.empty());
  EXPECT_EQ(m.late_ticks, 10);
  EXPECT_EQ(r.snapshot_late_ticks, 10);
  const nlohmann::ordered_json haptic = metrics_to_json(m, "default.yaml", true)["haptic"];
  EXPECT_EQ(haptic["late_ticks"], 10);
  EXPECT_EQ(haptic["missed_deadlines"], 10);  // still there, as before
  ASSERT_EQ(r.commands.size(), reference.commands.size());
  const double ramp_ticks = RuntimeSettings{}.late_tick_ramp_s / 0.001;
  for (const auto& [tick, late_s] : late) {
    const auto t = static_cast<size_t>(tick);
    SCOPED_TRACE(::testing::Message() << "late tick " << t << ", " << late_s * 1e3 << " ms");
    const double before = r.commands[t - 1].force_W.norm();
    ASSERT_GT(before, 0.1) << "the late tick must hit a pressing tool";
    EXPECT_TRUE(is_zero(r.commands[t]));
    // Back by itself: from 2 % on the next tick, growing, never above what it would have been.
    EXPECT_NEAR(r.commands[t + 1].force_W.norm(),
                reference.commands[t + 1].force_W.norm() / ramp_ticks, 1e-9);
    for (size_t u = t + 1; u <= t + 100; ++u) {
      ASSERT_LE(r.commands[u].force_W.norm(), reference.commands[u].force_W.norm() + 1e-12) << u;
    }
    // ... and full again within 100 ms: as without the late tick, and at the level before it.
    const size_t back = t + 100;
    EXPECT_LT((r.commands[back].force_W - reference.commands[back].force_W).norm(), 1e-9);
    EXPECT_NEAR(r.commands[back].force_W.norm(), before, 0.05 * before);
  }
}

// Late ticks in a row (a loop catching up after a hold-up shorter than a stall) keep the force
// off until the loop is back on time, then ramp it back once.
TEST(Session, LateTicksInARowKeepTheForceOffThenRampBackOnce) {
  const HeldRun reference = held_run({});
  const int64_t at = kPressingTick;
  const HeldRun r = held_run({{at, 0.012}, {at + 1, 0.008}, {at + 2, 0.004}});
  EXPECT_FALSE(r.metrics.paused);
  EXPECT_TRUE(r.metrics.events.empty());
  EXPECT_EQ(r.metrics.late_ticks, 3);
  const auto t = static_cast<size_t>(at);
  ASSERT_GT(r.commands[t - 1].force_W.norm(), 0.1);
  for (size_t u = t; u < t + 3; ++u) EXPECT_TRUE(is_zero(r.commands[u])) << u;
  const double ramp_ticks = RuntimeSettings{}.late_tick_ramp_s / 0.001;
  EXPECT_NEAR(r.commands[t + 3].force_W.norm(),
              reference.commands[t + 3].force_W.norm() / ramp_ticks, 1e-9);
  EXPECT_LT((r.commands[t + 100].force_W - reference.commands[t + 100].force_W).norm(), 1e-9);
}

// A loop held up for 20 ms or more is a stall: zero force from that tick on, the session
// paused, one event; a tick 19 ms late before it was only a late tick.
TEST(Session, A30MsStallPausesWithZeroForceFromThatTickOn) {
  const int64_t at = kPressingTick;
  const HeldRun r = held_run({{at - 200, 0.019}, {at, 0.030}});
  const SessionMetrics& m = r.metrics;
  EXPECT_TRUE(m.paused);
  ASSERT_EQ(m.events.size(), 1U);
  EXPECT_EQ(m.events[0].tick, at);
  EXPECT_EQ(m.events[0].tool, -1);
  EXPECT_EQ(m.events[0].reason, WatchdogReason::kStall);
  EXPECT_EQ(m.late_ticks, 1);
  const auto t = static_cast<size_t>(at);
  ASSERT_GT(r.commands[t - 1].force_W.norm(), 0.1) << "the stall must hit a pressing tool";
  for (size_t u = t; u < r.commands.size(); ++u) ASSERT_TRUE(is_zero(r.commands[u])) << u;
  const nlohmann::ordered_json event =
      metrics_to_json(m, "default.yaml", true)["watchdog_events"][0];
  EXPECT_EQ(event["reason"], "haptic loop stalled");
  EXPECT_EQ(event["tool"], "haptic loop");
}

// In real time, the ticks a stall held up run back to back afterwards (absolute deadlines),
// each less late than the one before: one event for them all, and no late ticks counted (the
// session is paused, the force already off). Here in fast mode, as a catch-up two ticks per
// period would look.
TEST(Session, AStallsCatchUpIsOneEventAndNoLateTicks) {
  const int64_t at = kPressingTick;
  std::vector<std::pair<int64_t, double>> catch_up;
  for (int k = 0; k < 16; ++k) catch_up.emplace_back(at + k, 0.030 - 0.002 * k);  // 30 .. 0 ms
  const HeldRun r = held_run(catch_up);
  ASSERT_EQ(r.metrics.events.size(), 1U);
  EXPECT_EQ(r.metrics.events[0].tick, at);
  EXPECT_EQ(r.metrics.events[0].reason, WatchdogReason::kStall);
  EXPECT_EQ(r.metrics.late_ticks, 0);
  EXPECT_TRUE(r.metrics.paused);
}

// A late tick during a resume's slower ramp sends zero and starts the ramp again, at the
// resume's pace: a late tick never hurries the forces back.
TEST(Session, ALateTickDuringAResumeRampRestartsItAtTheResumesPace) {
  const HeldRun reference = held_run({});
  const int64_t stall = 1200;
  const int64_t late = 1350;
  RuntimeSettings rs = fast(2.5);
  rs.resume_ramp_s = 0.2;  // 0.5 % per tick; a late tick's ramp is 2 %
  // Resumed from the device's read at tick 1300: the tick after takes the resume up.
  const HeldRun r = held_run({{stall, 0.030}, {late, 0.005}}, rs, [](Session* s, int64_t tick) {
    if (tick == 1300) s->resume();
  });
  EXPECT_FALSE(r.metrics.paused);
  ASSERT_EQ(r.metrics.events.size(), 1U);
  EXPECT_EQ(r.metrics.late_ticks, 1);
  const auto ratio = [&](int64_t tick) {
    const auto t = static_cast<size_t>(tick);
    return r.commands[t].force_W.norm() / reference.commands[t].force_W.norm();
  };
  EXPECT_TRUE(is_zero(r.commands[1300]));
  EXPECT_NEAR(ratio(1301), 0.005, 1e-9);  // the resume's ramp
  EXPECT_NEAR(ratio(late - 1), 0.005 * static_cast<double>(late - 1 - 1300), 1e-9);
  EXPECT_TRUE(is_zero(r.commands[static_cast<size_t>(late)]));
  EXPECT_NEAR(ratio(late + 1), 0.005, 1e-9);  // from zero again, at the same pace
  EXPECT_NEAR(ratio(late + 100), 0.5, 1e-9);
}

TEST(Session, ResumeRampsForcesBackInAfterAPause) {
  const Scene& scene = introductory_scene();
  // The tool keeps pressing after the pause, however late the resume comes in fast mode.
  auto left =
      std::make_unique<FaultyDevice>(push_and_hold(scene, 0), FaultyDevice::Fault::kNone, -1);
  left->commands.reserve(4000);
  FaultyDevice* dev = left.get();
  Devices d = with_left(scene, std::move(left));
  RuntimeSettings rs = fast(2.5);
  rs.resume_ramp_s = 0.1;
  auto s_created = Session::create(scene, std::move(d), rs);
  ASSERT_TRUE(s_created.ok()) << s_created.message();
  auto s = std::move(s_created).value();
  s->inject_lateness(1200, 0.030);  // a stall: a late tick would not pause
  s->resume();                      // a resume before the pause does nothing
  // Resume on the next tick after the pause, from "another thread" (the flag is atomic).
  std::thread resumer([&] {
    while (!s->paused()) std::this_thread::yield();
    s->resume();
  });
  const SessionMetrics m = s->run();
  resumer.join();
  EXPECT_FALSE(m.paused);
  EXPECT_EQ(dev->commands[1200].force_W, Eigen::Vector3d::Zero());
  // The forces come back through the ramp: the gain grows by dt / ramp = 1 % per tick, so the
  // first force after the resume is at most 1 % of the device's 3 N, and later ones grow.
  size_t first = 0;
  for (size_t t = 1201; t < dev->commands.size() && first == 0; ++t) {
    if (dev->commands[t].force_W.norm() > 0.0) first = t;
  }
  ASSERT_GT(first, 0U) << "forces never came back";
  EXPECT_LE(dev->commands[first].force_W.norm(), 0.01 * 3.0 + 1e-12);
  double later = 0.0;
  for (size_t t = first; t < dev->commands.size(); ++t) {
    later = std::max(later, dev->commands[t].force_W.norm());
  }
  EXPECT_GT(later, 10.0 * dev->commands[first].force_W.norm());
}

TEST(Session, RealTimeLoopsKeepTheirRatesAndAStallTripsTheWatchdog) {
  const Scene& scene = introductory_scene();
  auto left = logged(scene, FaultyDevice::Fault::kStall, 300);
  FaultyDevice* dev = left.get();
  Devices d = with_left(scene, std::move(left));
  RuntimeSettings rs;
  rs.duration_s = 0.5;
  rs.realtime_priority = false;
  auto s_created = Session::create(scene, std::move(d), rs);
  ASSERT_TRUE(s_created.ok()) << s_created.message();
  auto s = std::move(s_created).value();
  const SessionMetrics m = s->run();
  EXPECT_EQ(m.haptic.ticks(), 500);
  EXPECT_GT(m.model.ticks(), 10);
  // Tick 300's read held the loop 30 ms: tick 301 started at least 29 ms late, a stall (its
  // catch-up ticks after it, the same lasting event), sent zero, paused. A busy machine (a
  // sanitizer build, parallel tests) may add stalls of its own; if one ran right up to tick 301
  // it is the same lasting event, so: a stall at 301, or a run of them reaching it, and zero
  // force from 301 on. Its late ticks only cut the force for a tick: no pause.
  const auto it = std::find_if(m.events.begin(), m.events.end(), [](const WatchdogEvent& e) {
    return e.reason == WatchdogReason::kStall && e.tick <= 301;
  });
  ASSERT_NE(it, m.events.end());
  EXPECT_TRUE(m.paused);
  for (size_t t = 301; t < dev->commands.size(); ++t) {
    ASSERT_EQ(dev->commands[t].force_W, Eigen::Vector3d::Zero()) << t;
  }
  EXPECT_EQ(m.recorded_ticks, 500);
}

// Issue 25's fault injection: a modelling step that takes 100 ms. The loops share only
// lock-free buffers, so the haptic loop goes on at 1 kHz on the last model state: the tool
// still feels the organ it presses, within the device's limits; nothing pauses (a slow model is
// not a fault: the tissue only stands still for that long). The modelling loop then skips the
// periods it missed rather than running them back to back, and its statistics show the step.
TEST(Session, AModellingStepOf100MsNeitherPausesNorHoldsUpTheHapticLoop) {
  const Scene& scene = introductory_scene();
  auto left = logged(scene, FaultyDevice::Fault::kNone, -1);
  FaultyDevice* dev = left.get();
  // The task is not what this test watches: on a loaded machine the model's skipped periods
  // may end it early, and the run must go on past the slow step whatever the task does.
  RuntimeSettings rs = device_fault_run(1.8);
  rs.end_with_task = false;
  auto created = Session::create(scene, with_left(scene, std::move(left)), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  auto s = std::move(created).value();
  // push_in's left tool presses with 2.1–2.7 N from tick 1000 to 1230 (it leaves the organs
  // near tick 1380 as it sweeps sideways): the slow step and the 100 ticks after it fall there.
  constexpr int64_t kAt = 1100;
  s->inject_model_delay(kAt, 0.100);
  const SessionMetrics m = s->run();
  EXPECT_EQ(m.haptic.ticks(), 1800);
  EXPECT_TRUE(m.events.empty());
  EXPECT_FALSE(m.paused);
  EXPECT_GE(m.model.worst_step_s(), 0.100);
  EXPECT_GE(m.model.overruns(), 1);  // the step overran its period (the next is on time)
  // The periods of the time the loop ran (360 at 200 Hz for 1.8 s; more where a busy machine
  // made the haptic loop's 1800 ticks take longer), of which the ~20 the step overran are
  // skipped, not caught up.
  const auto periods = static_cast<int64_t>(m.model.elapsed_s() / m.model.period_s()) + 1;
  EXPECT_GE(periods, 360);
  EXPECT_LE(m.model.ticks(), periods - 15);
  const double limit = hardware::DeviceLimits{}.max_force_n;
  // Every tick's command, then the zero force sent as the session stops.
  ASSERT_GE(static_cast<int64_t>(dev->commands.size()), 1800);
  EXPECT_EQ(dev->commands.back().force_W.norm(), 0.0);
  // device_fault_run() lets late ticks through (a busy test machine makes some), so every tick
  // of the slow step's 100 ms still presses on the organ as it stood before the step.
  int64_t zeroed = 0;
  for (int64_t t = kAt; t < kAt + 100; ++t) {
    const Eigen::Vector3d f = dev->commands[static_cast<size_t>(t)].force_W;
    ASSERT_TRUE(f.allFinite()) << t;
    ASSERT_LE(f.norm(), limit + 1e-12) << t;
    if (f.norm() == 0.0) ++zeroed;
  }
  EXPECT_EQ(zeroed, 0) << "the pressing tool lost the organ while the model was held up";
  if (test::kSanitizerDivisor == 1) {  // a sanitizer on a loaded machine has its own hold-ups
    EXPECT_LT(m.haptic.worst_lateness_s(), 0.050);
  }
}

// The watchdog with a PHANToM (through the fake libHD.so): a servo error zeroes the force the
// device outputs and pauses the session; an unplugged arm is reported as disconnected.
TEST(Session, APhantomServoErrorOrUnplugPausesWithZeroForce) {
  test::FakeHd fake;
  ASSERT_NE(fake.handle, nullptr);
  for (const bool unplug : {false, true}) {
    fake.reset();
    const Scene& scene = introductory_scene();
    hardware::PhantomSettings ps;
    ps.library = LAP_FAKE_HD;
    // The device's origin 10 cm in (the left tool's home on the introductory scenario): the arm
    // starts there.
    ps.device_to_world = Eigen::Translation3d(default_handle_position(scene, 0, 0.10)) *
                         Eigen::Isometry3d::Identity();
    Devices d = with_left(scene, std::make_unique<hardware::PhantomDevice>(ps));
    const RuntimeSettings rs = device_fault_run(0.6);
    auto s_created = Session::create(scene, std::move(d), rs);
    ASSERT_TRUE(s_created.ok()) << s_created.message();
    auto s = std::move(s_created).value();
    // Swing the handle so the tip goes 4 cm into the liver (the axis through the liver's
    // middle, 16 cm in), then fail while the arm is pushing.
    const Eigen::Vector3d port = scene.scenario.trocars[0].position_m;
    const Eigen::Vector3d liver_mid(0.0, 0.071, 0.0);
    const Eigen::Vector3d u = (liver_mid - port).normalized();
    const Eigen::Vector3d target_handle = port - (0.36 - 0.16) * u;
    const Eigen::Vector3d move_mm = 1000.0 * (target_handle - ps.device_to_world.translation());
    Eigen::Vector3d before = Eigen::Vector3d::Zero();
    Eigen::Vector3d after = Eigen::Vector3d::Constant(1.0);
    std::thread fault([&] {
      for (int i = 1; i <= 60; ++i) {
        fake.set_state(0, (i / 60.0) * move_mm, Eigen::Vector3d::Zero(), 0);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(150));
      before = fake.force(0);
      if (unplug) {
        fake.unplug(0, true);
      } else {
        fake.set_servo_error(0x0204);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      after = fake.force(0);
    });
    const SessionMetrics m = s->run();
    fault.join();
    EXPECT_GT(before.norm(), 0.05) << "the arm must be pushing on tissue when it fails"
                                   << (unplug ? " (unplug)" : " (servo error)");
    EXPECT_TRUE(m.paused);
    const auto want = unplug ? WatchdogReason::kDeviceDisconnected : WatchdogReason::kDeviceError;
    const auto it = std::find_if(m.events.begin(), m.events.end(),
                                 [&](const WatchdogEvent& e) { return e.reason == want; });
    EXPECT_NE(it, m.events.end()) << (unplug ? "unplug" : "servo error");
    // The fault lasts to the end of the session: one event for it, not one per tick.
    EXPECT_EQ(std::count_if(m.events.begin(), m.events.end(),
                            [&](const WatchdogEvent& e) { return e.reason == want; }),
              1);
    // A servo error: the arm is still there and is sent zero within the session (checked while
    // the session still ran, not by the zero every session sends when it ends).
    if (!unplug) {
      EXPECT_EQ(after, Eigen::Vector3d::Zero());
    }
    EXPECT_EQ(m.recorded_ticks, m.haptic.ticks());
    s.reset();
  }
  fake.reset();
}

// The watchdog with the actuated gripper (emulated behind the USB seam): a motor fault reaches
// the watchdog, which pauses the session and sends zero force and squeeze from that tick on; the
// recording is kept. (That the zero replaces a real push is shown by the fast-mode watchdog
// tests above, which are deterministic; here the contacts depend on thread timing.)
TEST(Session, AGripperFaultPausesWithZeroForceAndSqueeze) {
  const Scene& scene = introductory_scene();
  auto emulator = std::make_unique<hardware::GripperEmulator>();
  hardware::GripperEmulator* emu = emulator.get();
  hardware::GripperEmulator::Controls c;
  c.encoder_counts = 6500;  // jaws open 0.79 rad, as the script starts
  emu->set(c);
  auto arm = logged(scene, FaultyDevice::Fault::kNone, -1);
  FaultyDevice* arm_log = arm.get();
  auto left = std::make_unique<hardware::ArmWithGripper>(
      std::move(arm), std::make_unique<hardware::UsbGripper>(std::move(emulator)));
  Devices d = with_left(scene, std::move(left));
  const RuntimeSettings rs = device_fault_run(1.8);
  auto s_created = Session::create(scene, std::move(d), rs);
  ASSERT_TRUE(s_created.ok()) << s_created.message();
  auto s = std::move(s_created).value();
  std::thread fault([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    hardware::GripperEmulator::Controls f = emu->controls();
    f.motor_fault = true;
    emu->set(f);
  });
  const SessionMetrics m = s->run();
  fault.join();
  EXPECT_TRUE(m.paused);
  const auto it = std::find_if(m.events.begin(), m.events.end(), [](const WatchdogEvent& e) {
    return e.reason == WatchdogReason::kDeviceError && e.tool == 0;
  });
  ASSERT_NE(it, m.events.end());
  const auto t = static_cast<size_t>(it->tick);
  ASSERT_LT(t, arm_log->commands.size());
  for (size_t k = t; k < arm_log->commands.size(); ++k) {
    ASSERT_EQ(arm_log->commands[k].force_W, Eigen::Vector3d::Zero()) << k;
    ASSERT_EQ(arm_log->commands[k].squeeze_n, 0.0) << k;
  }
  EXPECT_EQ(m.recorded_ticks, m.haptic.ticks());
}

// Issue 25's fault injection: a device unplugged mid-session and plugged back (as the USB
// gripper's driver and the PHANToM report it: kDisconnected while away, kOk once back). The tick
// it goes: zero force and a pause, one event however long it stays away. A resume while it is
// still away changes nothing but the log (it trips again on the tick it is taken up: zero sent,
// and a second event, as trip() counts a fault after a resume as a new one). Once it is back, the
// session stays paused until resume(), which brings the forces back through the ramp, never at
// once. Every tick's input is recorded, the device's state with it.
class ReconnectingDevice final : public hardware::HapticDevice {
 public:
  ReconnectingDevice(hardware::ScriptedTrajectory t, int64_t gone, int64_t back)
      : inner_(std::move(t), "reconnecting"), gone_(gone), back_(back) {}
  Status start() override { return inner_.start(); }
  void stop() override {}
  DeviceStatus read(int64_t tick, double dt, hardware::DeviceSample* out) noexcept override {
    if (on_read) on_read(tick);
    const DeviceStatus st = inner_.read(tick, dt, out);
    return tick >= gone_ && tick < back_ ? DeviceStatus::kDisconnected : st;
  }
  DeviceStatus write(const hardware::DeviceCommand& c) noexcept override {
    commands.push_back(c);
    writers.push_back(std::this_thread::get_id());
    return DeviceStatus::kOk;
  }
  [[nodiscard]] const hardware::DeviceLimits& limits() const override { return inner_.limits(); }
  [[nodiscard]] std::string_view name() const override { return "reconnecting"; }
  [[nodiscard]] std::string last_error() const override { return {}; }
  void reserve(size_t n) {
    commands.reserve(n);
    writers.reserve(n);
  }
  std::vector<hardware::DeviceCommand> commands;  // reserved by the test
  std::vector<std::thread::id> writers;           // the thread of each write, reserved too
  std::function<void(int64_t tick)> on_read;      // on the haptic thread (fast mode: the test's)

 private:
  hardware::ScriptedDevice inner_;
  int64_t gone_, back_;
};

TEST(Session, ADeviceUnpluggedAndPluggedBackPausesUntilResumedThenRampsBack) {
  const Scene& scene = introductory_scene();
  constexpr int64_t kGone = kPressingTick;       // pressing on the organs, as push_in's test
  constexpr int64_t kEarlyResume = kGone + 100;  // a resume while it is still away
  constexpr int64_t kBack = kGone + 300;
  constexpr int64_t kResume = kBack + 200;  // the trainee resumes once it is back
  auto left = std::make_unique<ReconnectingDevice>(push_and_hold(scene, 0), kGone, kBack);
  left->reserve(4000);
  ReconnectingDevice* dev = left.get();
  Session* session = nullptr;
  // resume() from the read of a tick is taken up at the start of the next.
  dev->on_read = [&session](int64_t tick) {
    if (tick == kEarlyResume || tick == kResume) session->resume();
  };
  RuntimeSettings rs = fast(2.5);
  rs.resume_ramp_s = 0.1;
  auto created = Session::create(scene, with_left(scene, std::move(left)), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  session = created.value().get();
  const SessionMetrics m = created.value()->run();

  ASSERT_GT(dev->commands[kGone - 1].force_W.norm(), 0.0) << "it must be pressing when it goes";
  // Zero from the tick it went to the tick the resume was asked on (taken up at the next).
  for (int64_t t = kGone; t <= kResume; ++t) {
    ASSERT_EQ(dev->commands[static_cast<size_t>(t)].force_W, Eigen::Vector3d::Zero()) << t;
  }
  // One event at the tick it went, one more at the tick the early resume was taken up (the
  // next): the device still away trips at once. None while it stays away otherwise.
  ASSERT_EQ(m.events.size(), 2U);
  EXPECT_EQ(m.events[0].tick, kGone);
  EXPECT_EQ(m.events[1].tick, kEarlyResume + 1);
  for (const WatchdogEvent& e : m.events) {
    EXPECT_EQ(e.tool, 0);
    EXPECT_EQ(e.reason, WatchdogReason::kDeviceDisconnected);
  }
  EXPECT_FALSE(m.paused);  // resumed, and still running at the end
  // Back through the ramp: 1 % of the gain per tick (dt / resume_ramp_s), so the first force is
  // at most 1 % of the device's 3 N, and the forces grow from there.
  size_t first = 0;
  for (size_t t = kResume + 1; t < dev->commands.size() && first == 0; ++t) {
    if (dev->commands[t].force_W.norm() > 0.0) first = t;
  }
  ASSERT_GT(first, 0U) << "forces never came back";
  EXPECT_LE(dev->commands[first].force_W.norm(), 0.01 * 3.0 + 1e-12);
  double later = 0.0;
  for (size_t t = first; t < dev->commands.size(); ++t) {
    later = std::max(later, dev->commands[t].force_W.norm());
  }
  EXPECT_GT(later, 10.0 * dev->commands[first].force_W.norm());
  // Recorded throughout, with the device's state.
  EXPECT_EQ(m.recorded_ticks, m.haptic.ticks());
  const hardware::DeviceRecording& rec = session->recording(0);
  ASSERT_GT(rec.samples.size(), static_cast<size_t>(kResume));
  EXPECT_EQ(rec.samples[kGone - 1].status, DeviceStatus::kOk);
  EXPECT_EQ(rec.samples[kGone].status, DeviceStatus::kDisconnected);
  EXPECT_EQ(rec.samples[kBack - 1].status, DeviceStatus::kDisconnected);
  EXPECT_EQ(rec.samples[kBack].status, DeviceStatus::kOk);
}

// A stop (SIGINT or SIGTERM to laptrainer-cli run, End Session in the window, the task's end)
// zeroes the forces first: the tick after the one that asked is not run; its first act is zero
// force to both devices, written on the haptic thread (in real time, before the modelling loop
// is joined), and run() writes zero again at the end, on its caller's thread. Fast and real time
// (issue 25: "forces zeroed first").
TEST(Session, AStopZeroesTheForcesAtTheNextTickBeforeAnythingElse) {
  const Scene& scene = introductory_scene();
  constexpr int64_t kStop = kPressingTick + 50;  // pressing on the organs
  constexpr int64_t kNever = std::numeric_limits<int64_t>::max();
  for (const bool realtime : {false, true}) {
    SCOPED_TRACE(realtime ? "real time" : "fast");
    Devices devices;
    std::array<ReconnectingDevice*, 2> dev{};
    for (int side = 0; side < 2; ++side) {
      auto d = std::make_unique<ReconnectingDevice>(push_and_hold(scene, side), kNever, kNever);
      d->reserve(4000);
      dev[static_cast<size_t>(side)] = d.get();
      devices[static_cast<size_t>(side)] = std::move(d);
    }
    Session* session = nullptr;
    dev[0]->on_read = [&session](int64_t tick) {
      if (tick == kStop) session->request_stop();  // on the haptic thread, in tick kStop
    };
    auto created =
        Session::create(scene, std::move(devices), realtime ? device_fault_run(2.5) : fast(2.5));
    ASSERT_TRUE(created.ok()) << created.message();
    session = created.value().get();
    const SessionMetrics m = created.value()->run();
    EXPECT_EQ(m.haptic.ticks(), kStop + 1);  // the tick that asked ran whole, no later one
    EXPECT_TRUE(m.events.empty());           // a stop, not a fault
    const std::thread::id caller = std::this_thread::get_id();
    for (size_t side = 0; side < 2; ++side) {
      SCOPED_TRACE(side == 0 ? "left" : "right");
      const ReconnectingDevice& d = *dev[side];
      // One command per tick up to the one that asked, then the stop's zero, then run()'s.
      ASSERT_EQ(static_cast<int64_t>(d.commands.size()), kStop + 3);
      EXPECT_EQ(d.commands[kStop + 1].force_W, Eigen::Vector3d::Zero());
      EXPECT_EQ(d.commands[kStop + 2].force_W, Eigen::Vector3d::Zero());
      // The stop's zero from the thread that ran the ticks: the haptic thread in real time.
      EXPECT_EQ(d.writers[kStop + 1], d.writers[kStop]);
      EXPECT_EQ(d.writers[kStop + 2], caller);
      if (realtime) {
        EXPECT_NE(d.writers[kStop + 1], caller);
      }
    }
    EXPECT_GT(dev[0]->commands[kStop].force_W.norm(), 0.05) << "pressing when it stops";
  }
}

}  // namespace
}  // namespace lap::sim
