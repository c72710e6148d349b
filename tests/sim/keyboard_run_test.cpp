// The procedure completed with the keyboard alone (issue 23: "with no hardware, mouse, keyboard
// and 3D mouse drive the tools, and the procedure can be completed with them"), --fast: the
// operator of tests/support/keyboard_operator.h copies the expert's run with the keys; each
// press reaches the tool's simulated device (the window's, hardware::SimulatedDevice) at the
// first tick at or after its time, and none while the heads-up display says hold, so the run is
// a function of the presses alone. In the window, with real key events in real time, to the
// ductotomy (the whole run on request): tests/app/session_flow_test.cpp.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hardware/scripted_trajectory.h"
#include "hardware/simulated_device.h"
#include "hardware/tool_nudge.h"
#include "sim/runtime/session.h"
#include "sim/runtime/task_progress.h"
#include "sim/runtime/trocar_tool.h"
#include "sim/setup/device_factory.h"
#include "tests/sim/session_test_support.h"
#include "tests/support/keyboard_operator.h"

namespace lap::sim {
namespace {

using hardware::SimulatedInput;
using test::KeyboardOperator;
using test::Press;
using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

// A simulated device (the window's, for a keyboard-driven tool) that takes the operator's
// presses for its tool at their times: at the first tick at or after each, the input is nudged
// and published, as LiveSession::nudge does on the UI thread.
class PressedDevice final : public hardware::HapticDevice {
 public:
  PressedDevice(const SimulatedInput& home, std::vector<test::TimedNudge> presses,
                Eigen::Vector3d port_W)
      : inner_(home, "keyboard"), in_(home), presses_(std::move(presses)), port_W_(port_W) {}
  Status start() override { return inner_.start(); }
  void stop() override {}
  hardware::DeviceStatus read(int64_t tick, double dt,
                              hardware::DeviceSample* out) noexcept override {
    const double t = static_cast<double>(tick) * dt;
    bool moved = false;
    while (next_ < presses_.size() && presses_[next_].t_s <= t + 1e-9) {
      const test::TimedNudge& p = presses_[next_++];
      if (holding && holding()) {
        ++skipped;  // the display says "hold": the resident's hands keep still
        continue;
      }
      in_ = hardware::nudged(in_, p.nudge, inner_.limits().workspace_W, port_W_);
      moved = true;
    }
    if (moved) inner_.set_input(in_);
    return inner_.read(tick, dt, out);
  }
  hardware::DeviceStatus write(const hardware::DeviceCommand& c) noexcept override {
    return inner_.write(c);
  }
  [[nodiscard]] const hardware::DeviceLimits& limits() const override { return inner_.limits(); }
  [[nodiscard]] std::string_view name() const override { return "keyboard"; }
  [[nodiscard]] std::string last_error() const override { return {}; }
  /// Whether the heads-up display tells the resident to hold (the target depth reached): no
  /// key is pressed meanwhile. Read on the haptic thread (in fast mode: the test's own).
  std::function<bool()> holding;
  int skipped = 0;  ///< presses not made while holding

 private:
  hardware::SimulatedDevice inner_;
  SimulatedInput in_;
  std::vector<test::TimedNudge> presses_;
  size_t next_ = 0;
  Eigen::Vector3d port_W_;
};

struct KeyboardRun {
  size_t motions = 0;          ///< key presses, mouse gestures or 3D mouse frames planned
  int switches = 0;            ///< T pressed
  double script_done_s = 0.0;  ///< when the operator had followed the expert's run to its end
  SessionMetrics metrics;
  int skipped = 0;  ///< motions the resident did not make while told to hold
};

// `nudges` played on the scene from the window's home pose of each tool (`op.start`), --fast,
// with nothing pressed while the display says hold.
KeyboardRun play(const Scene& scene, const KeyboardOperator& op,
                 const std::vector<test::TimedNudge>& nudges) {
  RuntimeSettings rs;
  rs.fast = true;
  rs.duration_s = 200.0;  // the slowest operator here succeeds at about 125 s
  KeyboardRun run;
  run.motions = nudges.size();
  Devices devices;
  for (int side = 0; side < 2; ++side) {
    const auto i = static_cast<size_t>(side);
    std::vector<test::TimedNudge> mine;
    for (const test::TimedNudge& n : nudges) {
      if (n.tool == side) mine.push_back(n);
    }
    devices[i] = std::make_unique<PressedDevice>(op.start[i], std::move(mine), op.ports_W[i]);
  }
  std::array<PressedDevice*, 2> pressed{static_cast<PressedDevice*>(devices[0].get()),
                                        static_cast<PressedDevice*>(devices[1].get())};
  auto created = Session::create(scene, std::move(devices), rs);
  EXPECT_TRUE(created.ok()) << created.message();
  Session& session = *created.value();
  for (PressedDevice* d : pressed) {
    d->holding = [&session] { return session.graphics_model().task.stage == TaskStage::kHold; };
  }
  run.metrics = session.run();
  run.skipped = pressed[0]->skipped + pressed[1]->skipped;
  return run;
}

const Scene& scene_of(const std::string& stem) {
  static std::map<std::string, SceneLoadResult> loaded;
  auto it = loaded.find(stem);
  if (it == loaded.end()) {
    it = loaded.emplace(stem, load_scene_file(test::source_dir() / "scenarios" / (stem + ".yaml")))
             .first;
  }
  EXPECT_TRUE(it->second.ok()) << it->second.message();
  return it->second.value();
}

// The keyboard operator's presses for `stem`'s expert run.
KeyboardRun run_with_keys(const std::string& stem, double presses_per_s) {
  const Scene& scene = scene_of(stem);
  const KeyboardOperator op = test::keyboard_operator(scene, stem, presses_per_s);
  const KeyboardOperator::Plan plan = op.plan();
  std::vector<test::TimedNudge> nudges;
  for (const Press& p : plan.presses) nudges.push_back(test::as_nudge(p));
  KeyboardRun run = play(scene, op, nudges);
  run.switches = plan.switches;
  run.script_done_s = plan.script_done_s;
  return run;
}

// The same operator with a continuous input, a motion a 60 Hz frame: the 3D mouse
// (test::PuckOperator, the default mapping) or the mouse alone (test::MouseOperator, Ctrl held).
template <typename Operator>
KeyboardRun run_with(const std::string& stem) {
  const Scene& scene = scene_of(stem);
  const KeyboardOperator op = test::keyboard_operator(scene, stem, 25.0);
  Operator input;
  input.op = &op;
  const test::FollowPlan plan = input.plan();
  KeyboardRun run = play(scene, op, test::timed_nudges(plan));
  run.switches = plan.switches;
  run.script_done_s = plan.script_done_s;
  return run;
}

// The shipped scenarios with a task, easiest first: the stand-in scene, the default patient and
// the graded ones.
constexpr std::array<const char*, 5> kScenarios = {"introductory", "default", "patient_easy",
                                                   "patient_moderate", "patient_hard"};

// Both keyboard tools start in the laparoscope's picture (the task counts an instrument out of
// view from the first tick), at least 10 cm into their ports, pointing at the task's target:
// 10 cm exactly where the tip is in view from 8 cm on (the introductory scenario).
TEST(KeyboardRun, BothToolsStartInThePicture) {
  for (const char* stem : kScenarios) {
    const SceneLoadResult loaded =
        load_scene_file(test::source_dir() / "scenarios" / (std::string(stem) + ".yaml"));
    ASSERT_TRUE(loaded.ok()) << loaded.message();
    const Scene& scene = loaded.value();
    RuntimeSettings rs;
    rs.fast = true;
    const auto model =
        SessionModel::build(scene, rs, {DeviceDescription{"left", {}}, {"right", {}}});
    ASSERT_TRUE(model.ok()) << model.message();
    const SessionModel& m = *model.value();
    for (int side = 0; side < 2; ++side) {
      const auto i = static_cast<size_t>(side);
      hardware::DeviceSample home;
      home.position_W = home_handle_position(scene, side);
      const ToolKinematics k = tool_kinematics(m.tool(i).trocar, home, m.tool(i).initial_axis_W);
      EXPECT_TRUE(m.task().in_view(k.pose.hinge_W)) << stem << " " << side;
      EXPECT_GE(k.inside_m, 0.10 - 1e-9) << stem << " " << side;
      const Eigen::Vector3d to_target = scene.task_target_point() - m.tool(i).trocar.port_W;
      EXPECT_LT((k.axis_W - to_target.normalized()).norm(), 1e-9) << stem << " " << side;
      // 10 cm exactly where the tip is in the picture 2 cm shallower already (the margin).
      hardware::DeviceSample eight;
      eight.position_W = default_handle_position(scene, side, 0.08);
      const bool eight_in_view = m.task().in_view(
          tool_kinematics(m.tool(i).trocar, eight, m.tool(i).initial_axis_W).pose.hinge_W);
      if (std::string(stem) == "introductory") {
        EXPECT_TRUE(eight_in_view) << side;  // so the check below is made there
      }
      if (eight_in_view) {
        EXPECT_LT((home.position_W - default_handle_position(scene, side, 0.10)).norm(), 1e-12)
            << stem << " " << side;
      }
      std::printf("[ home ] %s %s tool: %.3f m into its port\n", stem, side == 0 ? "left" : "right",
                  k.inside_m);
    }
  }
}

// The events of a successful keyboard run: the catheter taken, its tip at the incision and in
// the lumen (where it may slip out and back through the incision while it sits on its edge),
// the target depth, success; no error.
void expect_success(const KeyboardRun& run, const char* what) {
  const TaskState& task = run.metrics.task;
  std::printf(
      "[ keys ] %s: %zu motions planned (key presses, mouse gestures or 3D mouse frames; %d not "
      "made while "
      "holding), %d switches of tool, the "
      "expert's path followed by %.1f s; %s at %.2f s after %zu events\n",
      what, run.motions, run.skipped, run.switches, run.script_done_s,
      std::string(to_string(task.result)).c_str(), task.end_s, task.events.size());
  EXPECT_EQ(task.result, TaskResult::kSuccess) << what << ": " << event_kinds(task);
  EXPECT_EQ(task.reason_count, 0U);
  ASSERT_GE(task.events.size(), 5U) << event_kinds(task);
  EXPECT_EQ(task.events[0].kind, TaskEventKind::kCatheterGrasped);
  EXPECT_EQ(task.events[1].kind, TaskEventKind::kTipAtIncision);
  EXPECT_EQ(task.events[2].kind, TaskEventKind::kTipInLumen);
  for (size_t i = 3; i + 2 < task.events.size(); ++i) {
    const TaskEventKind k = task.events[i].kind;
    EXPECT_TRUE(k == TaskEventKind::kTipInLumen || k == TaskEventKind::kTipLeftLumen)
        << what << ": " << event_kinds(task);
  }
  EXPECT_EQ(task.events[task.events.size() - 2].kind, TaskEventKind::kTargetDepthReached);
  EXPECT_EQ(task.events.back().kind, TaskEventKind::kSuccess);
}

// A held key (the desktop's autorepeat: about 25 presses a second) and a resident who taps a
// key five times a second, on the default patient.
// The sanitizer builds, 5-20 times slower, play one run, the default patient's held keys (27 s
// under ASan; the hardest patient's 3D mouse run took 142 s there): the others run the same
// session and nudges on other paths, and space_mouse_nudge has its own tests.
constexpr bool kEveryRun = test::kSanitizerDivisor == 1;

TEST(KeyboardRun, TheDefaultPatientsProcedureCanBeCompletedWithTheKeys) {
  expect_success(run_with_keys("default", 25.0), "default, 25 presses/s");
  if (kEveryRun) expect_success(run_with_keys("default", 5.0), "default, 5 presses/s");
}

// The stand-in scene too (the window's keyboard test plays these presses in real time:
// SessionFlow.TheIntroductorySceneWithTheKeysInTheWindow).
TEST(KeyboardRun, TheIntroductorySceneCanBeCompletedWithTheKeys) {
  if (!kEveryRun) GTEST_SKIP() << "the optimised build's";
  expect_success(run_with_keys("introductory", 25.0), "introductory, 25 presses/s");
  expect_success(run_with_keys("introductory", 5.0), "introductory, 5 presses/s");
}

// The other patients, with held keys, the hardest also tapped. (On the hardest patient the keys'
// tip slid off the duct's wall beside the incision while the expert came in at the planner's 39
// degrees, and goes in at the 42 its scenario now names: docs/benchmarks.md, "Why the keys miss
// the hardest patient's incision".)
TEST(KeyboardRun, TheOtherPatientsCanBeCompletedWithTheKeys) {
  if (!kEveryRun) GTEST_SKIP() << "the optimised build's";
  expect_success(run_with_keys("patient_easy", 25.0), "patient_easy, 25 presses/s");
  expect_success(run_with_keys("patient_moderate", 25.0), "patient_moderate, 25 presses/s");
  expect_success(run_with_keys("patient_hard", 25.0), "patient_hard, 25 presses/s");
  expect_success(run_with_keys("patient_hard", 10.0), "patient_hard, 10 presses/s");
  expect_success(run_with_keys("patient_hard", 5.0), "patient_hard, 5 presses/s");
}

// The mouse alone, on every patient: drags in the picture's plane, the wheel along the line of
// sight, drags for the roll and the jaws, one gesture a frame.
TEST(KeyboardRun, ThePatientsCanBeCompletedWithTheMouse) {
  if (!kEveryRun) GTEST_SKIP() << "the optimised build's";
  for (const char* stem : kScenarios) {
    expect_success(run_with<test::MouseOperator>(stem), (std::string(stem) + ", mouse").c_str());
  }
}

// The 3D mouse, on every patient, the hardest too: its hand moves along all three axes at once,
// smoothly, where the keys' move along one at a time.
TEST(KeyboardRun, ThePatientsCanBeCompletedWithThe3DMouse) {
  if (!kEveryRun) GTEST_SKIP() << "the optimised build's";
  for (const char* stem : kScenarios) {
    expect_success(run_with<test::PuckOperator>(stem), (std::string(stem) + ", 3D mouse").c_str());
  }
}

}  // namespace
}  // namespace lap::sim
