// What the modelling loop publishes of the task for the heads-up display
// (sim/runtime/task_progress.h): the stage the trainee is at, the newest events and their count,
// the result; and, in a session, the same as the task engine's own state at the end, and each
// tool's push on the organs while it presses them.

#include "sim/runtime/task_progress.h"

#include <gtest/gtest.h>

#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

TaskModel insertion() {
  TaskModel m;
  m.kind = TaskKind::kCatheterInsertion;
  m.has_incision = true;
  m.incision_center_W = Eigen::Vector3d(0.01, 0.0, 0.0);
  m.at_incision_m = 0.003;
  return m;
}

// The stage follows the state: nobody holding the catheter, held far from the incision, held
// at it, in the lumen through it, at depth, ended.
TEST(TaskProgress, TheStageIsWhereTheTraineeIsNow) {
  const TaskModel m = insertion();
  TaskState s = TaskState::create(m);
  TaskProgress p;
  auto stage = [&] {
    write_task_progress(m, s, 1.0, {}, 0.0, &p);
    return p.stage;
  };
  EXPECT_EQ(stage(), TaskStage::kGraspCatheter);
  s.held = true;
  s.tip.known = true;
  s.tip.tip_D = Eigen::Vector3d(0.05, 0.0, 0.0);  // pose_DW is the identity here
  EXPECT_EQ(stage(), TaskStage::kBringToIncision);
  s.tip.tip_D = Eigen::Vector3d(0.012, 0.0, 0.0);  // 2 mm from the incision's centre
  EXPECT_EQ(stage(), TaskStage::kEnterIncision);
  s.tip.inside = true;
  s.tip.via_incision = true;
  s.tip.depth_m = 0.004;
  EXPECT_EQ(stage(), TaskStage::kAdvance);
  EXPECT_EQ(p.depth_m, 0.004);
  s.at_depth = true;
  s.at_depth_since_s = 0.25;
  EXPECT_EQ(stage(), TaskStage::kHold);
  EXPECT_DOUBLE_EQ(p.held_for_s, 0.75);
  s.result = TaskResult::kSuccess;
  s.end_s = 1.5;
  EXPECT_EQ(stage(), TaskStage::kDone);
  EXPECT_EQ(p.t_s, 1.5);  // the clock stops with the task
  TaskModel none;
  EXPECT_EQ((write_task_progress(none, TaskState::create(none), 2.0, {}, 0.0, &p), p.stage),
            TaskStage::kNone);
}

// Twelve events: the count says twelve, the display gets the newest eight in order.
TEST(TaskProgress, TheNewestEventsAreKeptInOrder) {
  const TaskModel m = insertion();
  TaskState s = TaskState::create(m, 10);
  for (int k = 0; k < 12; ++k) {
    if (s.events.size() < s.events.capacity()) {
      s.events.push_back({0.1 * k, TaskEventKind::kCatheterGrasped, k % 2});
    } else {
      ++s.events_dropped;
    }
  }
  TaskProgress p;
  write_task_progress(m, s, 2.0, {}, 0.0, &p);
  EXPECT_EQ(p.event_count, 12);
  ASSERT_EQ(p.recent_count, 8);
  for (int k = 0; k < 8; ++k) EXPECT_DOUBLE_EQ(p.recent[static_cast<size_t>(k)].t_s, 0.1 * (k + 2));
}

// A session that runs out of time: its last model snapshot says so, as its metrics do.
TEST(TaskProgress, ASessionPublishesItsTaskAsTheEngineHasIt) {
  Scene scene = introductory_scene();
  scene.scenario.task->time_limit_s = 1.0;
  auto session = session_over(scene, fast(2.0));
  const SessionMetrics metrics = session->run();
  const TaskProgress& p = session->graphics_model().task;
  EXPECT_EQ(p.kind, TaskKind::kCatheterInsertion);
  EXPECT_EQ(p.stage, TaskStage::kDone);
  EXPECT_EQ(p.result, TaskResult::kFailure);
  ASSERT_EQ(p.reason_count, 1);
  EXPECT_EQ(p.reasons[0], TaskReason::kTimeLimit);
  EXPECT_DOUBLE_EQ(p.t_s, metrics.task.end_s);
  ASSERT_EQ(p.event_count, static_cast<int64_t>(metrics.task.events.size()));
  ASSERT_EQ(p.recent_count, static_cast<int32_t>(metrics.task.events.size()));
  for (size_t k = 0; k < metrics.task.events.size(); ++k) {
    EXPECT_EQ(p.recent[k].kind, metrics.task.events[k].kind);
  }
}

// The pushed-in tools of session_test_support press the organs at kPressingTick: the snapshot
// then names what the left tool pushes, with a force, and the task's clock is the session's.
TEST(TaskProgress, ToolsPushingOrgansAreMeasured) {
  auto session = scripted_session(fast(static_cast<double>(kPressingTick) * 1e-3));
  session->run();
  const TaskProgress& p = session->graphics_model().task;
  EXPECT_NEAR(p.t_s, static_cast<double>(kPressingTick) * 1e-3, 0.006);
  const ToolForces& left = p.tools[0];
  EXPECT_GT(left.on_duct_n + left.on_organ_n, 0.0);
  if (left.on_organ_n > 0.0) {
    EXPECT_GE(left.organ, 0);
    EXPECT_NE(left.organ, session->model().task().duct_organ);
  }
}

}  // namespace
}  // namespace lap::sim
