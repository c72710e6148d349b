#include "sim/runtime/session.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <limits>
#include <thread>

#include "haptics/laparoscopic_gripper.h"
#include "haptics/segment_database.h"
#include "hardware/device_recording.h"
#include "hardware/gripper_emulator.h"
#include "hardware/phantom_device.h"
#include "hardware/replay_device.h"
#include "hardware/scripted_device.h"
#include "hardware/usb_gripper.h"
#include "sim/report/session_report.h"
#include "sim/runtime/trocar_tool.h"
#include "sim/setup/device_factory.h"
#include "tests/support/brute_force_reference.h"
#include "tests/support/counting_allocator.h"
#include "tests/support/fake_hd_control.h"
#include "tests/test_support.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;
using hardware::DeviceStatus;

const Scene& default_scene() {
  static const SceneLoadResult r = load_scene_file(test::source_dir() / "scenarios/default.yaml");
  EXPECT_TRUE(r.ok());
  return r.scene;
}

// The tool pushed from 5 cm to 20 cm inside its trocar over 1 s, then swept sideways while the
// jaws close: it meets the organs, so forces are not zero.
// A tick at which push_in's left tool presses on the organs (tests of faults there assert it).
constexpr int64_t kPressingTick = 1300;

hardware::ScriptedTrajectory push_in(const Scene& scene, int side) {
  hardware::ScriptedTrajectory t;
  const Eigen::Vector3d a = default_handle_position(scene, side, 0.05);
  const Eigen::Vector3d b = default_handle_position(scene, side, 0.20);
  t.keyframes.push_back({0.0, a, Eigen::Quaterniond::Identity(), 0.8, 0});
  t.keyframes.push_back({1.0, b, Eigen::Quaterniond::Identity(), 0.8, 0});
  t.keyframes.push_back({2.0, b + Eigen::Vector3d(0.03, 0, 0.02),
                         Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY())), 0.1,
                         1});
  return t;
}

// The tool pushed in as by push_in() and then held there, pressing, to the end (2.5 s).
hardware::ScriptedTrajectory push_and_hold(const Scene& scene, int side) {
  hardware::ScriptedTrajectory t;
  t.keyframes.push_back(
      {0.0, default_handle_position(scene, side, 0.05), Eigen::Quaterniond::Identity(), 0.8, 0});
  t.keyframes.push_back(
      {1.0, default_handle_position(scene, side, 0.20), Eigen::Quaterniond::Identity(), 0.8, 0});
  t.keyframes.push_back(
      {2.5, default_handle_position(scene, side, 0.20), Eigen::Quaterniond::Identity(), 0.8, 0});
  return t;
}

// The left tool of push_in() driven through its trocar against the default scene's organs, with
// no session around it. Regression: a jaw re-linearising its edge contacts too often could get
// stuck on a nearly flat edge and keep pushing (7–10 N) after the whole tool had left the organs.
// Whenever every sampled tick of the last 10 found all three segments of the tool (as the device
// puts them) at least 1 mm clear of every organ, by exhaustive search, the force must be zero.
TEST(ToolOnOrgans, NoForceOnceTheToolIsClearOfEveryOrgan) {
  const Scene& scene = default_scene();
  std::vector<std::unique_ptr<haptics::MeshDatabase>> dbs;
  std::vector<std::unique_ptr<haptics::SegmentDatabase>> sds;
  std::vector<haptics::HapticObject> objects;
  for (const Organ& organ : scene.organs) {
    dbs.push_back(
        std::make_unique<haptics::MeshDatabase>(haptics::MeshDatabase::build(organ.mesh)));
    sds.push_back(
        std::make_unique<haptics::SegmentDatabase>(haptics::SegmentDatabase::build(*dbs.back())));
    haptics::HapticObject o;
    o.mesh = dbs.back().get();
    o.segments = sds.back().get();
    objects.push_back(o);
  }
  const ToolSpec* spec = scene.scenario.tool(ToolSpec::Side::kLeft);
  ASSERT_NE(spec, nullptr);
  const TrocarSpec* port = scene.scenario.trocar(spec->trocar);
  ASSERT_NE(port, nullptr);
  TrocarToolSettings trocar;
  trocar.port_W = port->position_m;
  trocar.shaft_length_m = spec->shaft_length_m;
  haptics::GripperGeometry g;
  g.jaw_length_m = spec->jaw_length_m;
  g.shaft_length_m = spec->shaft_length_m;
  haptics::LaparoscopicGripper gripper(g);
  hardware::ScriptedDevice device(push_in(scene, 0), "left");
  const Status started = device.start();
  ASSERT_TRUE(started.ok()) << started.message();
  Eigen::Vector3d axis = (scene.bounds().center() - trocar.port_W).normalized();
  const double dt = 0.001;
  const int64_t kStride = 5 * test::kSanitizerDivisor;
  int64_t clear_since = -1;  // first of the current run of clear samples
  int64_t checked = 0;
  int64_t pressing = 0;
  double most_clear = 0.0;
  for (int64_t tick = 0; tick < 2000; ++tick) {
    hardware::DeviceSample sample;
    ASSERT_EQ(device.read(tick, dt, &sample), DeviceStatus::kOk);
    const ToolKinematics k = tool_kinematics(trocar, sample, axis);
    axis = k.axis_W;
    const haptics::GripperOutput out = gripper.step(objects, k.pose, dt);
    ASSERT_FALSE(out.fault);
    if (out.force_W.norm() > 0.0) ++pressing;
    // Exhaustive clearance on every 5th tick (every 100th in sanitizer builds, 20× slower).
    if (tick < 1000 || tick % kStride != 0) continue;  // (it is pushing in before)
    std::array<Eigen::Vector3d, 3> a;
    std::array<Eigen::Vector3d, 3> b;
    gripper.segments(k.pose, &a, &b);
    double clearance = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < 3; ++i) {
      for (const haptics::HapticObject& o : objects) {
        const double d = haptics::reference_segment_distance(*o.mesh, a[i], b[i]).distance;
        const bool inside = haptics::reference_inside(*o.mesh, a[i]);
        clearance = std::min(clearance, inside ? 0.0 : d);
      }
    }
    if (clearance < 1e-3) {
      clear_since = -1;
      continue;
    }
    if (clear_since < 0) clear_since = tick;
    most_clear = std::max(most_clear, clearance);
    if (tick - clear_since >= std::max<int64_t>(10, kStride)) {
      ++checked;
      EXPECT_EQ(out.force_W.norm(), 0.0)
          << "tick " << tick << ": the tool is " << clearance << " m clear of every organ";
    }
  }
  EXPECT_GT(pressing, 500) << "the tool must meet the organs on its way";
  EXPECT_GT(checked, 250 / kStride) << "the tool must leave them again";
  std::printf("%lld ticks pressing, %lld clear ticks checked (up to %.4f m clear)\n",
              static_cast<long long>(pressing), static_cast<long long>(checked), most_clear);
}

// A device that misbehaves at one tick: a NaN position, an error, a disconnect, or a stall.
class FaultyDevice final : public hardware::HapticDevice {
 public:
  enum class Fault { kNone, kNaN, kError, kDisconnect, kStall };
  FaultyDevice(hardware::ScriptedTrajectory t, Fault fault, int64_t at)
      : inner_(std::move(t), "faulty"), fault_(fault), at_(at) {}
  Status start() override { return inner_.start(); }
  void stop() override {}
  DeviceStatus read(int64_t tick, double dt, hardware::DeviceSample* out) noexcept override {
    const DeviceStatus st = inner_.read(tick, dt, out);
    if (tick != at_) return st;
    switch (fault_) {
      case Fault::kNaN:
        out->position_W.x() = std::numeric_limits<double>::quiet_NaN();
        return st;
      case Fault::kError:
        return DeviceStatus::kError;
      case Fault::kDisconnect:
        return DeviceStatus::kDisconnected;
      case Fault::kStall:
        std::this_thread::sleep_for(std::chrono::milliseconds(6));
        return st;
      case Fault::kNone:
        break;
    }
    return st;
  }
  DeviceStatus write(const hardware::DeviceCommand& c) noexcept override {
    commands.push_back(c);
    return DeviceStatus::kOk;
  }
  [[nodiscard]] const hardware::DeviceLimits& limits() const override { return inner_.limits(); }
  [[nodiscard]] std::string_view name() const override { return "faulty"; }
  [[nodiscard]] std::string last_error() const override { return {}; }
  std::vector<hardware::DeviceCommand> commands;  // reserved by the test

 private:
  hardware::ScriptedDevice inner_;
  Fault fault_;
  int64_t at_;
};

using Devices = std::array<std::unique_ptr<hardware::HapticDevice>, 2>;

// `left` on the left tool, the right tool scripted.
Devices with_left(const Scene& scene, std::unique_ptr<hardware::HapticDevice> left) {
  return {std::move(left), std::make_unique<hardware::ScriptedDevice>(push_in(scene, 1), "right")};
}

// A left FaultyDevice with room for every tick's command.
std::unique_ptr<FaultyDevice> logged(const Scene& scene, FaultyDevice::Fault fault, int64_t at) {
  auto d = std::make_unique<FaultyDevice>(push_in(scene, 0), fault, at);
  d->commands.reserve(4000);
  return d;
}

RuntimeSettings fast(double duration) {
  RuntimeSettings s;
  s.fast = true;
  s.duration_s = duration;
  return s;
}

// Real time, for device faults: a busy test machine's late ticks must not pause first.
RuntimeSettings device_fault_run(double duration) {
  RuntimeSettings s;
  s.duration_s = duration;
  s.realtime_priority = false;
  s.overrun_periods = 1e6;
  return s;
}

std::unique_ptr<Session> scripted_session(const RuntimeSettings& rs) {
  const Scene& scene = default_scene();
  Devices d =
      with_left(scene, std::make_unique<hardware::ScriptedDevice>(push_in(scene, 0), "left"));
  auto s_created = Session::create(scene, std::move(d), rs);
  EXPECT_TRUE(s_created.ok()) << s_created.message();
  auto s = std::move(s_created).value();
  return s;
}

TEST(Session, FastRunsAreDeterministicAndTouchTheOrgans) {
  auto a = scripted_session(fast(2.5));
  auto b = scripted_session(fast(2.5));
  const SessionMetrics ma = a->run();
  const SessionMetrics mb = b->run();
  // The scripts end at 2 s: the session stops when both devices have finished.
  EXPECT_EQ(ma.haptic.ticks(), 2002);
  EXPECT_EQ(ma.model.ticks(), 401);
  EXPECT_EQ(ma.state_hash, mb.state_hash);
  EXPECT_FALSE(ma.paused);
  EXPECT_GT(ma.max_force_sent_n, 0.05);  // the tools pressed on tissue
  EXPECT_LE(ma.max_force_sent_n, hardware::DeviceLimits{}.max_force_n + 1e-12);
  EXPECT_EQ(ma.recorded_ticks, 2002);
}

TEST(Session, AReplayReproducesTheRecordedSessionBitForBit) {
  auto original = scripted_session(fast(2.5));
  const SessionMetrics m = original->run();
  const fs::path dir =
      fs::temp_directory_path() / ("laptrainer_replay_" + std::to_string(::getpid()));
  const Status written = original->write_recording(dir.string());
  ASSERT_TRUE(written.ok()) << written.message();
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> d;
  for (int side = 0; side < 2; ++side) {
    auto rec = hardware::read_device_recording(dir / (side == 0 ? "left.lapdev" : "right.lapdev"));
    ASSERT_TRUE(rec.ok()) << rec.message();
    d[static_cast<size_t>(side)] =
        std::make_unique<hardware::ReplayDevice>(std::move(rec).value(), "replay");
  }
  auto replay_created = Session::create(default_scene(), std::move(d), fast(2.5));
  ASSERT_TRUE(replay_created.ok()) << replay_created.message();
  auto replay = std::move(replay_created).value();
  const SessionMetrics r = replay->run();
  EXPECT_EQ(r.haptic.ticks(), m.haptic.ticks());
  EXPECT_EQ(r.state_hash, m.state_hash);
  fs::remove_all(dir);
}

// The session's fixed model is shared, never changed: two sessions built from one model and
// run side by side, each on its own thread, end in the same state as one built alone.
TEST(Session, TwoSessionsFromOneModelRunSideBySideToTheSameState) {
  const Scene& scene = default_scene();
  auto devices = [&] {
    return with_left(scene, std::make_unique<hardware::ScriptedDevice>(push_in(scene, 0), "left"));
  };
  Devices first = devices();
  const auto model =
      SessionModel::build(scene, fast(2.5), {describe(*first[0]), describe(*first[1])});
  ASSERT_TRUE(model.ok()) << model.message();
  auto a = Session::create(model.value(), std::move(first));
  auto b = Session::create(model.value(), devices());
  ASSERT_TRUE(a.ok()) << a.message();
  ASSERT_TRUE(b.ok()) << b.message();
  EXPECT_EQ(&a.value()->model(), &b.value()->model());
  SessionMetrics ma;
  SessionMetrics mb;
  std::thread ta([&] { ma = a.value()->run(); });
  std::thread tb([&] { mb = b.value()->run(); });
  ta.join();
  tb.join();
  const SessionMetrics alone = scripted_session(fast(2.5))->run();
  EXPECT_EQ(ma.haptic.ticks(), 2002);
  EXPECT_GT(ma.max_force_sent_n, 0.05);  // the tools pressed on tissue
  EXPECT_EQ(ma.state_hash, mb.state_hash);
  EXPECT_EQ(ma.state_hash, alone.state_hash);
}

// A session model is built for its devices' limits: a device with others is refused.
TEST(Session, ADeviceWithOtherLimitsThanTheModelsIsRefused) {
  const Scene& scene = default_scene();
  Devices d =
      with_left(scene, std::make_unique<hardware::ScriptedDevice>(push_in(scene, 0), "left"));
  DeviceDescription left = describe(*d[0]);
  left.limits.max_force_n *= 2.0;
  const auto model = SessionModel::build(scene, fast(1.0), {left, describe(*d[1])});
  ASSERT_TRUE(model.ok()) << model.message();
  const auto s = Session::create(model.value(), std::move(d));
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("other limits than the session model was built for"),
            std::string::npos)
      << s.message();
}

// A model that meets a non-finite value is a fault like a haptic one: zero force from the next
// haptic tick on (the modelling step runs after the haptic tick it belongs to), the session
// paused, the model named; nothing recorded is lost.
class SessionModelFault : public ::testing::TestWithParam<ModelFaultKind> {};

TEST_P(SessionModelFault, ZeroForceWithinOneTickPausedAndTheModelNamed) {
  const Scene& scene = default_scene();
  const int64_t at = kPressingTick - kPressingTick % 5;  // a modelling step's tick (200 Hz)
  auto left = logged(scene, FaultyDevice::Fault::kNone, -1);
  FaultyDevice* dev = left.get();
  auto created = Session::create(scene, with_left(scene, std::move(left)), fast(2.5));
  ASSERT_TRUE(created.ok()) << created.message();
  auto s = std::move(created).value();
  s->inject_model_fault(at, GetParam());
  const SessionMetrics m = s->run();
  ASSERT_GT(dev->commands[at].force_W.norm(), 0.0) << "the fault must hit a pressing tool";
  for (size_t t = at + 1; t < dev->commands.size(); ++t) {
    ASSERT_EQ(dev->commands[t].force_W, Eigen::Vector3d::Zero()) << t;
  }
  EXPECT_TRUE(m.paused);
  ASSERT_FALSE(m.events.empty());
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
  const std::string json = metrics_json(m, "default.yaml", true);
  EXPECT_NE(json.find("\"model\": \"" + std::string(to_string(GetParam())) + "\""),
            std::string::npos)
      << json;
}

INSTANTIATE_TEST_SUITE_P(EachModel, SessionModelFault,
                         ::testing::Values(ModelFaultKind::kCatheter,
                                           ModelFaultKind::kLocalDeformation,
                                           ModelFaultKind::kModalShell));

struct FaultCase {
  FaultyDevice::Fault fault;
  WatchdogReason reason;
};

class SessionWatchdog : public ::testing::TestWithParam<FaultCase> {};

TEST_P(SessionWatchdog, ZeroForceOnTheTickPausedAndNothingLost) {
  const Scene& scene = default_scene();
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

TEST(Session, AnInjectedStallPausesWithZeroForceOnThatTick) {
  const Scene& scene = default_scene();
  auto left = logged(scene, FaultyDevice::Fault::kNone, -1);
  FaultyDevice* dev = left.get();
  Devices d = with_left(scene, std::move(left));
  auto s_created = Session::create(scene, std::move(d), fast(2.5));
  ASSERT_TRUE(s_created.ok()) << s_created.message();
  auto s = std::move(s_created).value();
  s->inject_lateness(kPressingTick, 0.0025);  // 2.5 periods late
  const SessionMetrics m = s->run();
  ASSERT_FALSE(m.events.empty());
  EXPECT_EQ(m.events[0].reason, WatchdogReason::kOverrun);
  EXPECT_EQ(m.events[0].tool, -1);
  EXPECT_EQ(dev->commands[kPressingTick].force_W, Eigen::Vector3d::Zero());
  EXPECT_GT(dev->commands[kPressingTick - 1].force_W.norm(), 0.0);
}

TEST(Session, ResumeRampsForcesBackInAfterAPause) {
  const Scene& scene = default_scene();
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
  s->inject_lateness(1200, 0.01);
  s->resume();  // a resume before the pause does nothing
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

TEST(Session, TheFastLoopAllocatesNothingPerTick) {
  // The same session run for 200 and for 2000 ticks allocates the same number of times: set-up
  // and the metrics allocate, the ticks do not.
  auto count_for = [&](double duration) {
    auto s = scripted_session(fast(duration));
    test::AllocationCounter counter;
    const SessionMetrics m = s->run();
    return counter.count();
  };
  const int64_t short_run = count_for(0.2);
  const int64_t long_run = count_for(2.0);
  EXPECT_EQ(short_run, long_run);
  // The counter is live in this binary (else both counts would be 0 whatever the loop did).
  static std::unique_ptr<int> kept;
  test::AllocationCounter probe;
  kept = std::make_unique<int>(1);
  EXPECT_EQ(probe.count(), 1);
}

TEST(Session, RealTimeLoopsKeepTheirRatesAndAStallTripsTheWatchdog) {
  const Scene& scene = default_scene();
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
  // Tick 300 slept 6 ms: tick 301 started more than 2 periods late, sent zero, paused. A busy
  // machine (a sanitizer build, parallel tests) may add overruns of its own; if one ran right
  // up to tick 301 it is the same lasting event, so: an overrun at 301, or a run of them
  // reaching it, and zero force from 301 on.
  const auto it = std::find_if(m.events.begin(), m.events.end(), [](const WatchdogEvent& e) {
    return e.reason == WatchdogReason::kOverrun && e.tick <= 301;
  });
  ASSERT_NE(it, m.events.end());
  EXPECT_TRUE(m.paused);
  for (size_t t = 301; t < dev->commands.size(); ++t) {
    ASSERT_EQ(dev->commands[t].force_W, Eigen::Vector3d::Zero()) << t;
  }
  EXPECT_EQ(m.recorded_ticks, 500);
}

// The watchdog with a PHANToM (through the fake libHD.so): a servo error zeroes the force the
// device outputs and pauses the session; an unplugged arm is reported as disconnected.
TEST(Session, APhantomServoErrorOrUnplugPausesWithZeroForce) {
  test::FakeHd fake;
  ASSERT_NE(fake.handle, nullptr);
  for (const bool unplug : {false, true}) {
    fake.reset();
    const Scene& scene = default_scene();
    hardware::PhantomSettings ps;
    ps.library = LAP_FAKE_HD;
    // The device's origin 10 cm in, at the left tool's home: the arm starts there.
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
  const Scene& scene = default_scene();
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

TEST(Session, WarnsOfTissueStifferThanADeviceRendersStably) {
  const Scene& scene = default_scene();
  hardware::DeviceLimits soft;
  soft.max_stiffness_n_per_m = 250.0;  // the liver is 300 N/m, the gallbladder 200
  Devices d =
      with_left(scene, std::make_unique<hardware::ScriptedDevice>(push_in(scene, 0), "left", soft));
  auto s_created = Session::create(scene, std::move(d), fast(0.01));
  ASSERT_TRUE(s_created.ok()) << s_created.message();
  auto s = std::move(s_created).value();
  const SessionMetrics m = s->run();
  ASSERT_EQ(m.warnings.size(), 1U);
  EXPECT_NE(m.warnings[0].find("liver: stiffness 300"), std::string::npos) << m.warnings[0];
  EXPECT_NE(m.warnings[0].find("left renders stably (250"), std::string::npos) << m.warnings[0];
}

TEST(Session, BadSettingsAndScenesAreClearErrors) {
  const Scene& scene = default_scene();
  RuntimeSettings rs;
  rs.model_rate_hz = 5000.0;
  Devices d =
      with_left(scene, std::make_unique<hardware::ScriptedDevice>(push_in(scene, 0), "left"));
  auto bad_rates = Session::create(scene, std::move(d), rs);
  EXPECT_FALSE(bad_rates.ok());
  EXPECT_EQ(bad_rates.message(), "rates: expected 0 < model rate <= haptic rate");
  Scene no_tools = scene;
  no_tools.scenario.tools.clear();
  d = with_left(scene, std::make_unique<hardware::ScriptedDevice>(push_in(scene, 0), "left"));
  auto toolless = Session::create(no_tools, std::move(d), RuntimeSettings{});
  EXPECT_FALSE(toolless.ok());
  std::string error = toolless.message();
  EXPECT_NE(error.find("tools: expected a left tool"), std::string::npos) << error;
  // No OpenHaptics on the library path (the fake is loaded by its full path only).
  hardware::DeviceSpec phantom{hardware::DeviceKind::kPhantom, ""};
  auto no_phantom = make_device(phantom, scene, 0);
  EXPECT_FALSE(no_phantom.ok());
  error = no_phantom.message();
  EXPECT_NE(error.find("phantom: OpenHaptics' HD library (libHD.so) could not be loaded"),
            std::string::npos)
      << error;
}

}  // namespace
}  // namespace lap::sim
