// The expert's and the clumsy runs of the default scenario (sim/authoring/expert_run.h): the
// shipped scripts are what the planner writes from the scenario, the expert's run ends in
// success, and each clumsy run fails for its own reason, with the exact sequence of events
// (sim/runtime/task_engine.h). All in --fast mode: a function of the inputs only.

#include "sim/authoring/expert_run.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "hardware/scripted_device.h"
#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

const fs::path kScripts = test::source_dir() / "scenarios/scripts/default";

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The session's model for the planner, as `laptrainer-cli plan-expert` builds it.
std::shared_ptr<const SessionModel> model_of(const Scene& scene) {
  RuntimeSettings rs;
  rs.fast = true;
  auto m = SessionModel::build(scene, rs, {DeviceDescription{"left", {}}, {"right", {}}});
  EXPECT_TRUE(m.ok()) << m.message();
  return m.value();
}

// The scripts `stem`_left.csv and _right.csv run on the scene until the task ends (60 s at
// most).
SessionMetrics run_scripts(const Scene& scene, const std::string& stem) {
  Devices d;
  for (int side = 0; side < 2; ++side) {
    const fs::path file = kScripts / (stem + (side == 0 ? "_left.csv" : "_right.csv"));
    auto t = hardware::load_scripted_trajectory(file);
    EXPECT_TRUE(t.ok()) << t.message();
    d[static_cast<size_t>(side)] = std::make_unique<hardware::ScriptedDevice>(
        std::move(t).value(), side == 0 ? "left" : "right");
  }
  auto created = Session::create(scene, std::move(d), fast(60.0));
  EXPECT_TRUE(created.ok()) << created.message();
  return created.value()->run();
}

std::string kinds(const TaskState& t) {
  std::string s;
  for (const TaskEvent& e : t.events) {
    if (!s.empty()) s += ", ";
    s += std::string(to_string(e.kind));
  }
  return s;
}

TEST(ExpertRun, TheShippedScriptsAreWhatThePlannerWritesFromTheScenario) {
  const Scene& scene = default_scene();
  const std::shared_ptr<const SessionModel> model = model_of(scene);
  const test::TempDir dir;
  for (const auto& [mistake, stem] : {std::pair{ExpertMistake::kNone, "expert"},
                                      std::pair{ExpertMistake::kDropsCatheter, "clumsy_drop"},
                                      std::pair{ExpertMistake::kOvershoots, "clumsy_overshoot"},
                                      std::pair{ExpertMistake::kTearsDuct, "clumsy_tear"}}) {
    ExpertRunSettings settings;
    settings.mistake = mistake;
    const Result<ExpertRun> plan = plan_expert_run(scene, *model, settings);
    ASSERT_TRUE(plan.ok()) << plan.message();
    for (const auto& [trajectory, side] : {std::pair{&plan.value().left, "_left.csv"},
                                           std::pair{&plan.value().right, "_right.csv"}}) {
      const fs::path written = dir.path() / (std::string(stem) + side);
      ASSERT_TRUE(save_trajectory_csv(*trajectory, written).ok());
      EXPECT_EQ(read(written), read(kScripts / (std::string(stem) + side)))
          << stem << side << " is stale: laptrainer-cli plan-expert --scenario "
          << "scenarios/default.yaml --out scenarios/scripts/default [--mistake ...]";
    }
  }
}

TEST(ExpertRun, TheExpertInsertsTheCatheterAndHoldsIt) {
  const SessionMetrics m = run_scripts(default_scene(), "expert");
  EXPECT_EQ(m.task.result, TaskResult::kSuccess);
  EXPECT_EQ(kinds(m.task),
            "catheter_grasped, tip_at_incision, tip_in_lumen, target_depth_reached, success");
  ASSERT_FALSE(m.task.events.empty());
  EXPECT_EQ(m.task.events[0].tool, 1);  // the right hand holds the catheter
  const TaskEvent& depth = m.task.events[3];
  EXPECT_GE(depth.value, default_scene().scenario.task->insertion_depth_m);
  // Held at depth for the scenario's 3 s, and done well within the time limit.
  EXPECT_NEAR(m.task.end_s - depth.t_s, default_scene().scenario.task->hold_s, 0.006);
  EXPECT_LT(m.task.end_s, 20.0);
  // Gently: nothing near an injury threshold, a fraction of a newton at the hands.
  EXPECT_LT(m.max_force_sent_n, 1.0);
  EXPECT_FALSE(m.paused);
}

TEST(ExpertRun, ACatheterLetGoOnTheWayIsDropped) {
  const SessionMetrics m = run_scripts(default_scene(), "clumsy_drop");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(kinds(m.task), "catheter_grasped, catheter_released, catheter_dropped, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kCatheterDropped);
  // The drop is called the scenario's grace after the release.
  EXPECT_NEAR(m.task.events[2].t_s - m.task.events[1].t_s,
              default_scene().scenario.task->drop_grace_s, 0.006);
}

TEST(ExpertRun, PushingOnPastTheTargetPerforatesTheWall) {
  const SessionMetrics m = run_scripts(default_scene(), "clumsy_overshoot");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(kinds(m.task),
            "catheter_grasped, tip_at_incision, tip_in_lumen, target_depth_reached, "
            "wall_perforation, target_depth_lost, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kWallPerforation);
}

TEST(ExpertRun, PullingTheGraspedDuctInjuresIt) {
  const SessionMetrics m = run_scripts(default_scene(), "clumsy_tear");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(kinds(m.task), "duct_injury, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kDuctInjury);
  const TaskEvent& e = m.task.events[0];
  EXPECT_FALSE(e.squeeze);  // by the pull, not the jaws' squeeze
  EXPECT_GT(e.value, default_scene().scenario.task->duct_injury_force_n);
  EXPECT_NEAR(e.duration_s, default_scene().scenario.task->duct_injury_time_s, 0.006);
}

TEST(ExpertRun, TheExpertsPaceRunsOutOfAShorterTimeLimit) {
  // The time limit's clumsy run: the expert's own, with 10 s to do what takes 15.8 s.
  Scene scene = default_scene();
  scene.scenario.task->time_limit_s = 10.0;
  const SessionMetrics m = run_scripts(scene, "expert");
  EXPECT_EQ(kinds(m.task), "catheter_grasped, tip_at_incision, time_limit, failure");
  EXPECT_EQ(m.task.reasons[0], TaskReason::kTimeLimit);
  EXPECT_DOUBLE_EQ(m.task.end_s, 10.0);
}

TEST(ExpertRun, TheTipInsideTheCommonBileDuctFails) {
  // The default scene has no common bile duct: the cystic duct's own closed mesh stands in for
  // one (as the scene holds it, not through the loader, which refuses the target): the tip that
  // enters the lumen is inside "it" too — the session's inside test on a real surface.
  Scene scene = default_scene();
  scene.scenario.task->common_bile_duct = "cystic_duct";
  const SessionMetrics m = run_scripts(scene, "expert");
  EXPECT_EQ(kinds(m.task),
            "catheter_grasped, tip_at_incision, tip_in_lumen, tip_in_common_bile_duct, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kCommonBileDuct);
  EXPECT_EQ(m.task.events[3].organ, 2);
}

}  // namespace
}  // namespace lap::sim
