// The expert's and the clumsy runs of the default scenario (sim/authoring/expert_run.h): the
// shipped scripts are what the planner writes from the scenario, the expert's run ends in
// success, and each clumsy run fails for its own reason, with the exact sequence of events
// (sim/runtime/task_engine.h). All in --fast mode: a function of the inputs only.

#include "sim/authoring/expert_run.h"

#include <gtest/gtest.h>

#include "hardware/scripted_device.h"
#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

const fs::path kScripts = test::source_dir() / "scenarios/scripts/default";

TEST(ExpertRun, TheShippedScriptsAreWhatThePlannerWritesFromTheScenario) {
  for (const auto& [mistake, stem] : {std::pair{ExpertMistake::kNone, "expert"},
                                      std::pair{ExpertMistake::kDropsCatheter, "clumsy_drop"},
                                      std::pair{ExpertMistake::kOvershoots, "clumsy_overshoot"},
                                      std::pair{ExpertMistake::kTearsDuct, "clumsy_tear"}}) {
    ExpertRunSettings settings;
    settings.mistake = mistake;
    expect_planned_scripts(default_scene(), settings, kScripts, stem);
  }
}

TEST(ExpertRun, TheExpertInsertsTheCatheterAndHoldsIt) {
  const SessionMetrics m = run_scripts(default_scene(), kScripts, "expert");
  EXPECT_EQ(m.task.result, TaskResult::kSuccess);
  EXPECT_EQ(event_kinds(m.task),
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
  const SessionMetrics m = run_scripts(default_scene(), kScripts, "clumsy_drop");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task), "catheter_grasped, catheter_released, catheter_dropped, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kCatheterDropped);
  // The drop is called the scenario's grace after the release.
  EXPECT_NEAR(m.task.events[2].t_s - m.task.events[1].t_s,
              default_scene().scenario.task->drop_grace_s, 0.006);
}

TEST(ExpertRun, PushingOnPastTheTargetPerforatesTheWall) {
  const SessionMetrics m = run_scripts(default_scene(), kScripts, "clumsy_overshoot");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task),
            "catheter_grasped, tip_at_incision, tip_in_lumen, target_depth_reached, "
            "wall_perforation, target_depth_lost, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kWallPerforation);
}

TEST(ExpertRun, PullingTheGraspedDuctInjuresIt) {
  const SessionMetrics m = run_scripts(default_scene(), kScripts, "clumsy_tear");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task), "duct_injury, failure");
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
  const SessionMetrics m = run_scripts(scene, kScripts, "expert");
  EXPECT_EQ(event_kinds(m.task), "catheter_grasped, tip_at_incision, time_limit, failure");
  EXPECT_EQ(m.task.reasons[0], TaskReason::kTimeLimit);
  EXPECT_DOUBLE_EQ(m.task.end_s, 10.0);
}

TEST(ExpertRun, TheTipInsideTheCommonBileDuctFails) {
  // The default scene has no common bile duct: the cystic duct's own closed mesh stands in for
  // one (as the scene holds it, not through the loader, which refuses the target): the tip that
  // enters the lumen is inside "it" too — the session's inside test on a real surface.
  Scene scene = default_scene();
  scene.scenario.task->common_bile_duct = "cystic_duct";
  const SessionMetrics m = run_scripts(scene, kScripts, "expert");
  EXPECT_EQ(event_kinds(m.task),
            "catheter_grasped, tip_at_incision, tip_in_lumen, tip_in_common_bile_duct, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kCommonBileDuct);
  EXPECT_EQ(m.task.events[3].organ, 2);
}

}  // namespace
}  // namespace lap::sim
