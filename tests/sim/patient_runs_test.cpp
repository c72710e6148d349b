// The default scenario and the patients of graded difficulty (scenarios/patient_*.yaml on the
// generated anatomy, docs/anatomy.md; issue 22): for each, the shipped scripts are what the
// planner (sim/authoring/expert_run.h) writes from the scenario, the expert's run ends in success
// and each clumsy run fails for its own reason, with the exact sequence of events
// (sim/runtime/task_engine.h). All in --fast mode: a function of the inputs only.

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "sim/authoring/expert_run.h"
#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

struct Patient {
  std::string stem;  ///< scenarios/<stem>.yaml, scripts in scenarios/scripts/<stem>/
};

const Scene& scene_of(const Patient& p) {
  static std::map<std::string, SceneLoadResult> loaded;
  auto it = loaded.find(p.stem);
  if (it == loaded.end()) {
    it =
        loaded
            .emplace(p.stem, load_scene_file(test::source_dir() / "scenarios" / (p.stem + ".yaml")))
            .first;
  }
  EXPECT_TRUE(it->second.ok()) << it->second.message();
  return it->second.value();
}

fs::path scripts_of(const Patient& p) { return test::source_dir() / "scenarios/scripts" / p.stem; }

class PatientRun : public ::testing::TestWithParam<Patient> {};

TEST_P(PatientRun, TheShippedScriptsAreWhatThePlannerWritesFromTheScenario) {
  for (const auto& [mistake, stem] : {std::pair{ExpertMistake::kNone, "expert"},
                                      std::pair{ExpertMistake::kDropsCatheter, "clumsy_drop"},
                                      std::pair{ExpertMistake::kOvershoots, "clumsy_overshoot"},
                                      std::pair{ExpertMistake::kTearsDuct, "clumsy_tear"}}) {
    ExpertRunSettings settings;
    settings.mistake = mistake;
    expect_planned_scripts(scene_of(GetParam()), settings, scripts_of(GetParam()), stem);
  }
}

TEST_P(PatientRun, TheExpertInsertsTheCatheterAndHoldsIt) {
  const Scene& scene = scene_of(GetParam());
  const SessionMetrics m = run_scripts(scene, scripts_of(GetParam()), "expert");
  EXPECT_EQ(m.task.result, TaskResult::kSuccess);
  EXPECT_EQ(event_kinds(m.task),
            "catheter_grasped, tip_at_incision, tip_in_lumen, target_depth_reached, success");
  ASSERT_EQ(m.task.events.size(), 5U);
  EXPECT_EQ(m.task.events[0].tool, 1);  // the right hand holds the catheter
  const TaskEvent& depth = m.task.events[3];
  EXPECT_GE(depth.value, scene.scenario.task->insertion_depth_m);
  // Held at depth for the scenario's 3 s, and done well within the time limit.
  EXPECT_NEAR(m.task.end_s - depth.t_s, scene.scenario.task->hold_s, 0.006);
  EXPECT_LT(m.task.end_s, 20.0);
  // Gently: a fraction of a newton at the hands (nothing pressed on the way).
  EXPECT_LT(m.max_force_sent_n, 1.0);
  EXPECT_FALSE(m.paused);
}

TEST_P(PatientRun, ACatheterLetGoOnTheWayIsDropped) {
  const Scene& scene = scene_of(GetParam());
  const SessionMetrics m = run_scripts(scene, scripts_of(GetParam()), "clumsy_drop");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task), "catheter_grasped, catheter_released, catheter_dropped, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kCatheterDropped);
  ASSERT_EQ(m.task.events.size(), 4U);
  EXPECT_NEAR(m.task.events[2].t_s - m.task.events[1].t_s, scene.scenario.task->drop_grace_s,
              0.006);
}

TEST_P(PatientRun, PushingOnPastTheTargetPerforatesTheWall) {
  const SessionMetrics m =
      run_scripts(scene_of(GetParam()), scripts_of(GetParam()), "clumsy_overshoot");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task),
            "catheter_grasped, tip_at_incision, tip_in_lumen, target_depth_reached, "
            "wall_perforation, target_depth_lost, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kWallPerforation);
}

TEST_P(PatientRun, PullingTheGraspedDuctInjuresIt) {
  const Scene& scene = scene_of(GetParam());
  const SessionMetrics m = run_scripts(scene, scripts_of(GetParam()), "clumsy_tear");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task), "duct_injury, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kDuctInjury);
  const TaskEvent& e = m.task.events[0];
  EXPECT_FALSE(e.squeeze);  // by the pull, not the jaws' squeeze
  EXPECT_GT(e.value, scene.scenario.task->duct_injury_force_n);
  EXPECT_NEAR(e.duration_s, scene.scenario.task->duct_injury_time_s, 0.006);
}

INSTANTIATE_TEST_SUITE_P(Patients, PatientRun,
                         ::testing::Values(Patient{"default"}, Patient{"patient_easy"},
                                           Patient{"patient_moderate"}, Patient{"patient_hard"}),
                         [](const ::testing::TestParamInfo<Patient>& info) {
                           return info.param.stem;
                         });

}  // namespace
}  // namespace lap::sim
