// The introductory scenario's expert run (sim/authoring/expert_run.h) against what the scenario
// may change: a shorter time limit, a common bile duct the tip enters. The runs themselves, for
// the introductory scene, the default and the patients, are tests/sim/patient_runs_test.cpp's.
// --fast: inputs only.

#include "sim/authoring/expert_run.h"

#include <gtest/gtest.h>

#include "hardware/scripted_device.h"
#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

const fs::path kScripts = test::source_dir() / "scenarios/scripts/introductory";

// The shipped scripts, the expert's success and each clumsy run's exact events: the
// parameterised suite of tests/sim/patient_runs_test.cpp, for the introductory scene as for the
// default and the patients.
// Here, what only the introductory's expert shows.

TEST(ExpertRun, TheExpertsPaceRunsOutOfAShorterTimeLimit) {
  // The time limit's clumsy run: the expert's own, with 10 s to do what takes 15.8 s.
  Scene scene = introductory_scene();
  scene.scenario.task->time_limit_s = 10.0;
  const SessionMetrics m = run_scripts(scene, kScripts, "expert");
  EXPECT_EQ(event_kinds(m.task), "catheter_grasped, tip_at_incision, time_limit, failure");
  EXPECT_EQ(m.task.reasons[0], TaskReason::kTimeLimit);
  EXPECT_DOUBLE_EQ(m.task.end_s, 10.0);
}

TEST(ExpertRun, TheTipInsideTheCommonBileDuctFails) {
  // The introductory scene has no common bile duct: the cystic duct's own closed mesh stands in for
  // one (as the scene holds it, not through the loader, which refuses the target): the tip that
  // enters the lumen is inside "it" too — the session's inside test on a real surface.
  Scene scene = introductory_scene();
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
