// The procedure completed with the keyboard alone (issue 23: "with no hardware, mouse, keyboard
// and 3D mouse drive the tools, and the procedure can be completed with them"). A resident at the
// keyboard is played by an operator who watches the expert's run (the shipped scripts) and
// copies it with the keys the application gives: one key at a time, at a held key's autorepeat
// rate, on the active tool only (T switches tools, and takes a press's time), each press doing
// what it does in the window (hardware::key_nudge and hardware::nudged, as app::LiveSession
// applies them). The operator never looks at the simulation, only at the expert: where the
// keys' 2 mm steps cannot follow the expert's hand, it falls behind and catches up. Each press
// reaches the tool's simulated device at its time, and the session runs --fast, so the run is a
// function of the presses alone.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "hardware/scripted_trajectory.h"
#include "hardware/simulated_device.h"
#include "hardware/tool_nudge.h"
#include "sim/runtime/session.h"
#include "sim/runtime/task_progress.h"
#include "sim/runtime/trocar_tool.h"
#include "sim/setup/device_factory.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using hardware::SimulatedInput;
using hardware::ToolKey;
using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

struct Press {
  double t_s = 0.0;
  int tool = 0;
  ToolKey key = ToolKey::kXPlus;
  bool fine = false;  ///< Shift held: a quarter step
};

struct KeyChoice {
  ToolKey key = ToolKey::kXPlus;
  bool fine = false;
};

// The keys an operator presses to follow `expert` from `start`: every 1/presses_per_s s one
// press, of the key that most reduces the active tool's largest error to the expert's pose at
// the operator's place in the script (position along one axis in steps, the jaws' opening, the
// roll of the jaws' opening direction about the shaft); when the active tool is within half a
// step of the expert on all of them and the other is not, a switch to the other (no key
// pressed on a tool); when both are, the operator reads on in the script by one press's time.
struct KeyboardOperator {
  std::array<hardware::ScriptedTrajectory, 2> expert;
  std::array<SimulatedInput, 2> start;
  std::array<Eigen::Vector3d, 2> ports_W;
  std::array<Eigen::AlignedBox3d, 2> workspaces_W;
  double presses_per_s = 20.0;
  double give_up_s = 300.0;
  /// Where the operator starts reading the expert's run: once the expert has brought both
  /// instruments into the laparoscope's picture (its approach through the ports is not followed:
  /// the keyboard's tools start in view, sim::home_handle_position).
  double script_start_s = 0.0;

  struct Plan {
    std::vector<Press> presses;
    int switches = 0;
    double script_done_s = 0.0;  ///< when the operator reached the expert's last keyframe
  };

  // The jaws' opening direction (the device's x axis made perpendicular to the shaft,
  // sim::tool_kinematics) of orientation q with the handle at p.
  Eigen::Vector3d opening_dir(int tool, const Eigen::Quaterniond& q,
                              const Eigen::Vector3d& p) const {
    const Eigen::Vector3d s = (ports_W[static_cast<size_t>(tool)] - p).normalized();
    const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();
    return (x - x.dot(s) * s).normalized();
  }

  // The press that most reduces tool's largest error, measured in fine presses (Shift: a
  // quarter step); a whole press while that error is at least three quarters of one. None
  // within half a fine press.
  std::optional<KeyChoice> best_key(int tool, const SimulatedInput& at,
                                    const hardware::DeviceSample& want) const {
    constexpr double kFine = hardware::kKeyFineFraction;
    double worst = 0.5 + 1e-6;  // in fine presses
    std::optional<ToolKey> key;
    const Eigen::Vector3d e = want.position_W - at.position_W;
    constexpr std::array<std::array<ToolKey, 2>, 3> kAxis{{{ToolKey::kXMinus, ToolKey::kXPlus},
                                                           {ToolKey::kYMinus, ToolKey::kYPlus},
                                                           {ToolKey::kZMinus, ToolKey::kZPlus}}};
    for (int a = 0; a < 3; ++a) {
      const double presses = std::abs(e[a]) / (kFine * hardware::kKeyStepM);
      if (presses > worst) {
        worst = presses;
        key = kAxis[static_cast<size_t>(a)][e[a] > 0.0 ? 1 : 0];
      }
    }
    const double open = want.gripper_angle_rad - at.gripper_angle_rad;
    if (std::abs(open) / (kFine * hardware::kKeyOpeningRad) > worst) {
      worst = std::abs(open) / (kFine * hardware::kKeyOpeningRad);
      key = open > 0.0 ? ToolKey::kOpen : ToolKey::kClose;
    }
    const Eigen::Vector3d s = (ports_W[static_cast<size_t>(tool)] - at.position_W).normalized();
    const Eigen::Vector3d now = opening_dir(tool, at.orientation_W, at.position_W);
    const Eigen::Vector3d goal = opening_dir(tool, want.orientation_W, at.position_W);
    const double roll = std::atan2(now.cross(goal).dot(s), now.dot(goal));
    if (std::abs(roll) / (kFine * hardware::kKeyRollRad) > worst) {
      worst = std::abs(roll) / (kFine * hardware::kKeyRollRad);
      key = roll > 0.0 ? ToolKey::kRollPlus : ToolKey::kRollMinus;
    }
    if (!key) return std::nullopt;
    return KeyChoice{*key, worst < 0.75 / kFine};
  }

  [[nodiscard]] Plan plan() const {
    Plan out;
    std::array<SimulatedInput, 2> at = start;
    const double period = 1.0 / presses_per_s;
    const double end = std::max(expert[0].duration_s(), expert[1].duration_s());
    double script_s = script_start_s;
    int active = 1;  // the window starts with the right tool active
    std::array<size_t, 2> cursor{};
    for (double t = period; t < give_up_s; t += period) {
      std::array<std::optional<KeyChoice>, 2> key;
      for (int tool = 0; tool < 2; ++tool) {
        const auto i = static_cast<size_t>(tool);
        hardware::DeviceSample want;
        expert[i].sample(script_s, &cursor[i], &want);
        key[i] = best_key(tool, at[i], want);
      }
      if (key[static_cast<size_t>(active)]) {
        const auto i = static_cast<size_t>(active);
        at[i] = hardware::nudged(at[i], hardware::key_nudge(key[i]->key, key[i]->fine),
                                 workspaces_W[i], ports_W[i]);
        out.presses.push_back({t, active, key[i]->key, key[i]->fine});
      } else if (key[static_cast<size_t>(1 - active)]) {
        active = 1 - active;
        ++out.switches;
      } else if (script_s < end) {
        script_s = std::min(end, script_s + period);
        if (script_s == end) out.script_done_s = t;
      } else {
        break;  // done: both tools hold the expert's last pose
      }
    }
    return out;
  }
};

// A simulated device (the window's, for a keyboard-driven tool) that takes the operator's
// presses for its tool at their times: at the first tick at or after each, the input is nudged
// and published, as LiveSession::nudge does on the UI thread.
class PressedDevice final : public hardware::HapticDevice {
 public:
  PressedDevice(const SimulatedInput& home, std::vector<Press> presses, Eigen::Vector3d port_W)
      : inner_(home, "keyboard"), in_(home), presses_(std::move(presses)), port_W_(port_W) {}
  Status start() override { return inner_.start(); }
  void stop() override {}
  hardware::DeviceStatus read(int64_t tick, double dt,
                              hardware::DeviceSample* out) noexcept override {
    const double t = static_cast<double>(tick) * dt;
    bool moved = false;
    while (next_ < presses_.size() && presses_[next_].t_s <= t + 1e-9) {
      const Press& p = presses_[next_++];
      if (holding && holding()) {
        ++skipped;  // the display says "hold": the resident's hands keep still
        continue;
      }
      in_ = hardware::nudged(in_, hardware::key_nudge(p.key, p.fine), inner_.limits().workspace_W,
                             port_W_);
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
  std::vector<Press> presses_;
  size_t next_ = 0;
  Eigen::Vector3d port_W_;
};

struct KeyboardRun {
  KeyboardOperator::Plan plan;
  SessionMetrics metrics;
  int skipped = 0;  ///< presses the resident did not make while told to hold
};

// The operator's presses for `stem`'s expert run, played on the scene from the window's home
// pose of each tool (app::LiveSession: sim::home_handle_position, the jaws half open, the
// orientation the identity).
KeyboardRun run_with_keys(const std::string& stem, double presses_per_s) {
  const SceneLoadResult loaded =
      load_scene_file(test::source_dir() / "scenarios" / (stem + ".yaml"));
  EXPECT_TRUE(loaded.ok()) << loaded.message();
  const Scene& scene = loaded.value();
  KeyboardOperator op;
  op.presses_per_s = presses_per_s;
  const hardware::SimulatedDevice probe({}, "limits");
  for (int side = 0; side < 2; ++side) {
    const auto i = static_cast<size_t>(side);
    const fs::path script = test::source_dir() / "scenarios/scripts" / stem /
                            (side == 0 ? "expert_left.csv" : "expert_right.csv");
    auto t = hardware::load_scripted_trajectory(script);
    EXPECT_TRUE(t.ok()) << t.message();
    op.expert[i] = std::move(t).value();
    op.start[i].position_W = home_handle_position(scene, side);
    op.start[i].gripper_angle_rad = 0.6;
    const ToolSpec* tool =
        scene.scenario.tool(side == 0 ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight);
    EXPECT_NE(tool, nullptr);
    op.ports_W[i] = scene.scenario.trocar(tool->trocar)->position_m;
    op.workspaces_W[i] = probe.limits().workspace_W;
  }
  RuntimeSettings rs;
  rs.fast = true;
  rs.duration_s = 200.0;  // the slowest operator here succeeds at about 125 s
  const auto model = SessionModel::build(scene, rs, {DeviceDescription{"left", {}}, {"right", {}}});
  EXPECT_TRUE(model.ok()) << model.message();
  const SessionModel& m = *model.value();
  for (size_t i = 0; i < 2; ++i) EXPECT_EQ(op.ports_W[i], m.tool(i).trocar.port_W);
  // The first 10 ms at which both of the expert's jaws' hinges are in the picture.
  std::array<size_t, 2> cursor{};
  for (double t = 0.0; t <= op.expert[1].duration_s(); t += 0.01) {
    bool both = true;
    for (size_t i = 0; i < 2; ++i) {
      hardware::DeviceSample at;
      op.expert[i].sample(t, &cursor[i], &at);
      const ToolKinematics k = tool_kinematics(m.tool(i).trocar, at, m.tool(i).initial_axis_W);
      both = both && m.task().in_view(k.pose.hinge_W);
    }
    if (both) {
      op.script_start_s = t;
      break;
    }
  }
  KeyboardRun run;
  run.plan = op.plan();
  Devices devices;
  for (int side = 0; side < 2; ++side) {
    const auto i = static_cast<size_t>(side);
    std::vector<Press> mine;
    for (const Press& p : run.plan.presses) {
      if (p.tool == side) mine.push_back(p);
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

// Both keyboard tools start in the laparoscope's picture (the task counts an instrument out of
// view from the first tick), at least 10 cm into their ports, pointing at the task's target:
// 10 cm exactly where the tip is in view from 8 cm on (the default scenario).
TEST(KeyboardRun, BothToolsStartInThePicture) {
  for (const char* stem : {"default", "patient_easy", "patient_moderate", "patient_hard"}) {
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
      "[ keys ] %s: %zu presses planned (%d not made while holding), %d switches of tool, the "
      "expert's path followed by %.1f s; %s at %.2f s after %zu events\n",
      what, run.plan.presses.size(), run.skipped, run.plan.switches, run.plan.script_done_s,
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
TEST(KeyboardRun, TheDefaultPatientsProcedureCanBeCompletedWithTheKeys) {
  expect_success(run_with_keys("default", 25.0), "default, 25 presses/s");
  expect_success(run_with_keys("default", 5.0), "default, 5 presses/s");
}

// The easy and the moderate patient, with held keys. (The hardest patient is not completed this
// way: the catheter's tip comes to the incision and does not go in before the time limit. The
// operator copies the expert's hands, not the tip: where its grasp took the catheter a little
// off the expert's, the tip misses the ductotomy by as much, and a resident would aim it.)
TEST(KeyboardRun, TheEasyAndModeratePatientsCanBeCompletedWithTheKeys) {
  expect_success(run_with_keys("patient_easy", 25.0), "patient_easy, 25 presses/s");
  expect_success(run_with_keys("patient_moderate", 25.0), "patient_moderate, 25 presses/s");
}

}  // namespace
}  // namespace lap::sim
