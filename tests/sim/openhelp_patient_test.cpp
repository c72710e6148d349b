// The OpenHELP patient (tests/data/openhelp_patient.yaml): the real liver, stomach and duodenum
// scans in ../shared/meshes (read from there, never copied into the project) around the
// generated biliary tree. The expert's scripts beside it are what the planner writes from it,
// and they insert the catheter, with the exact sequence of events (sim/runtime/task_engine.h).
// All in --fast mode: a function of the inputs only. Without the real meshes, both skip.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

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

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string kinds(const TaskState& t) {
  std::string s;
  for (const TaskEvent& e : t.events) {
    if (!s.empty()) s += ", ";
    s += std::string(to_string(e.kind));
  }
  return s;
}

// The scripts expert_left.csv and _right.csv run on the scene until the task ends (60 s at most).
SessionMetrics run_expert(const Scene& scene) {
  Devices d;
  for (int side = 0; side < 2; ++side) {
    const fs::path file = kScripts / (side == 0 ? "expert_left.csv" : "expert_right.csv");
    auto t = hardware::load_scripted_trajectory(file);
    EXPECT_TRUE(t.ok()) << t.message();
    d[static_cast<size_t>(side)] = std::make_unique<hardware::ScriptedDevice>(
        std::move(t).value(), side == 0 ? "left" : "right");
  }
  auto created = Session::create(scene, std::move(d), fast(60.0));
  EXPECT_TRUE(created.ok()) << created.message();
  return created.value()->run();
}

TEST(RealMeshes, TheOpenHelpPatientsScriptsAreWhatThePlannerWritesFromTheScenario) {
  LAP_REQUIRE_SHARED_MESHES();
  if (!scans_beside_the_source_tree()) {
    GTEST_SKIP() << "tests/data/openhelp_patient.yaml reads ../shared/meshes beside the source "
                    "tree, which is absent";
  }
  const SceneLoadResult scene = load_scene_file(kScenario);
  ASSERT_TRUE(scene.ok()) << scene.message();
  // The session's model for the planner, as `laptrainer-cli plan-expert` builds it.
  RuntimeSettings rs;
  rs.fast = true;
  auto model =
      SessionModel::build(scene.value(), rs, {DeviceDescription{"left", {}}, {"right", {}}});
  ASSERT_TRUE(model.ok()) << model.message();
  const Result<ExpertRun> plan = plan_expert_run(scene.value(), *model.value());
  ASSERT_TRUE(plan.ok()) << plan.message();
  const test::TempDir dir;
  for (const auto& [trajectory, file] : {std::pair{&plan.value().left, "expert_left.csv"},
                                         std::pair{&plan.value().right, "expert_right.csv"}}) {
    const fs::path written = dir.path() / file;
    ASSERT_TRUE(save_trajectory_csv(*trajectory, written).ok());
    EXPECT_EQ(read(written), read(kScripts / file))
        << file << " is stale: laptrainer-cli plan-expert --scenario "
        << "tests/data/openhelp_patient.yaml --out tests/data/scripts/openhelp_patient";
  }
}

TEST(RealMeshes, TheExpertInsertsTheCatheterInTheOpenHelpPatient) {
  LAP_REQUIRE_SHARED_MESHES();
  if (!scans_beside_the_source_tree()) {
    GTEST_SKIP() << "tests/data/openhelp_patient.yaml reads ../shared/meshes beside the source "
                    "tree, which is absent";
  }
  const SceneLoadResult scene = load_scene_file(kScenario);
  ASSERT_TRUE(scene.ok()) << scene.message();
  const TaskSpec& task = *scene.value().scenario.task;
  const SessionMetrics m = run_expert(scene.value());
  EXPECT_EQ(m.task.result, TaskResult::kSuccess);
  EXPECT_EQ(kinds(m.task),
            "catheter_grasped, tip_at_incision, tip_in_lumen, target_depth_reached, success");
  ASSERT_EQ(m.task.events.size(), 5U);
  EXPECT_EQ(m.task.events[0].tool, 1);  // the right hand holds the catheter
  const TaskEvent& depth = m.task.events[3];
  EXPECT_GE(depth.value, task.insertion_depth_m);
  // Held at depth for the scenario's 3 s, and done well within the time limit.
  EXPECT_NEAR(m.task.end_s - depth.t_s, task.hold_s, 0.006);
  EXPECT_LT(m.task.end_s, 20.0);
  EXPECT_FALSE(m.paused);
}

}  // namespace
}  // namespace lap::sim
