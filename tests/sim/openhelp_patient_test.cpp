// The OpenHELP patient (tests/data/openhelp_patient.yaml): the real liver, stomach and duodenum
// scans in ../shared/meshes (read from there, never copied into the project) around the
// generated biliary tree. The expert's scripts beside it are what the planner writes from it,
// and they insert the catheter, with the exact sequence of events (sim/runtime/task_engine.h).
// All in --fast mode: a function of the inputs only. Without the real meshes, both skip.

#include <gtest/gtest.h>

#include "hardware/scripted_device.h"
#include "sim/authoring/expert_run.h"
#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

const fs::path kScenario = test::source_dir() / "tests/data/openhelp_patient.yaml";
const fs::path kScripts = test::source_dir() / "tests/data/scripts/openhelp_patient";

// The scenario reaches the scans as ../../../shared/meshes from tests/data: ../shared/meshes
// beside the source tree, whatever LAP_SHARED_DIR says.
bool scans_beside_the_source_tree() {
  std::error_code ec;
  return fs::is_directory(test::source_dir() / "../shared/meshes", ec);
}

// Skips the test (a macro: GTEST_SKIP returns from it) without the scans.
#define REQUIRE_SCANS_BESIDE_THE_SOURCE_TREE()                                                   \
  LAP_REQUIRE_SHARED_MESHES();                                                                   \
  if (!scans_beside_the_source_tree()) {                                                         \
    GTEST_SKIP() << "tests/data/openhelp_patient.yaml reads ../shared/meshes beside the source " \
                    "tree, which is absent";                                                     \
  }

TEST(RealMeshes, TheOpenHelpPatientsScriptsAreWhatThePlannerWritesFromTheScenario) {
  REQUIRE_SCANS_BESIDE_THE_SOURCE_TREE();
  const SceneLoadResult scene = load_scene_file(kScenario);
  ASSERT_TRUE(scene.ok()) << scene.message();
  expect_planned_scripts(scene.value(), ExpertMistake::kNone, kScripts, "expert");
}

TEST(RealMeshes, TheExpertInsertsTheCatheterInTheOpenHelpPatient) {
  REQUIRE_SCANS_BESIDE_THE_SOURCE_TREE();
  // The narrowest of the scenes (the scenario's catheter note): the right port and the
  // catheter's port were moved so that the planner's carry keeps the liver under organ_injury's
  // 5 N (1.64 N) and the catheter reaches the depth; the planner measures the right hand's and
  // the held catheter's clearances (ExpertRun::right_shaft, held_catheter) but does not steer
  // round the organs.
  const SceneLoadResult scene = load_scene_file(kScenario);
  ASSERT_TRUE(scene.ok()) << scene.message();
  const TaskSpec& task = *scene.value().scenario.task;
  const SessionMetrics m = run_scripts(scene.value(), kScripts, "expert");
  expect_expert_success(m, task);
}

}  // namespace
}  // namespace lap::sim
