// The task engine inside a session: its model built from the introductory scene, its inputs handed
// over by the modelling loop (the tools' tips and contacts), and the session ending with the
// task (sim/runtime/session.h, sim/runtime/task_engine.h).

#include <gtest/gtest.h>

#include <cmath>

#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

TEST(SessionTask, TheDuctsLumenAndIncisionAreTheScenarios) {
  // The introductory scenario's duct: 5 mm across with a 1 mm wall (mid-surface radius 2 mm), 35 mm
  // long; its incision 3 mm x 2 mm on the anterior wall.
  auto s = scripted_session(fast(0.01));
  const TaskModel& m = s->model().task();
  EXPECT_EQ(m.kind, TaskKind::kCatheterInsertion);
  ASSERT_GE(m.duct_organ, 0);
  EXPECT_EQ(s->model().organ_names()[static_cast<size_t>(m.duct_organ)], "cystic_duct");
  EXPECT_NEAR(m.lumen_radius_m, 0.002, 0.0002);
  EXPECT_NEAR(m.duct_length_m, 0.035, 0.002);
  ASSERT_TRUE(m.has_incision);
  const Eigen::Vector3d c = m.pose_DW * m.incision_center_W;
  EXPECT_NEAR(c.head<2>().norm(), m.lumen_radius_m, 0.0006);  // on the wall
  EXPECT_GT(m.incision_half_length_m, 0.0015);                // the half length and a margin
  EXPECT_LT(m.incision_half_length_m, 0.0015 + 0.0025);
  EXPECT_DOUBLE_EQ(m.at_incision_m, 0.0035);
  EXPECT_EQ(m.forbidden, std::vector<uint8_t>(3, 0));
}

TEST(SessionTask, AnInsertionIntoWhatIsNoDuctWithAnIncisionIsAClearError) {
  auto expect_refused = [](const Scene& scene, const std::string& message) {
    const Result<std::shared_ptr<const SessionModel>> m =
        SessionModel::build(scene, fast(1.0), {DeviceDescription{}, DeviceDescription{}});
    ASSERT_FALSE(m.ok());
    ASSERT_EQ(m.diagnostics().size(), 1U) << m.message();
    EXPECT_EQ(m.diagnostics()[0].to_string(), scene.scenario.file.string() + ":" +
                                                  std::to_string(scene.scenario.task->line) +
                                                  ": task.target: " + message);
  };
  Scene liver = introductory_scene();
  liver.scenario.task->target = "liver";
  expect_refused(liver,
                 "'liver' is not a modal-shell duct (the catheter is inserted into its lumen): "
                 "expected the organ with model: modal-shell");
  Scene uncut = introductory_scene();
  for (OrganSpec& organ : uncut.scenario.organs) organ.incision.present = false;
  expect_refused(uncut,
                 "the duct 'cystic_duct' has no incision to insert the catheter by: expected an "
                 "incision on it (organs[].incision)");
  EXPECT_GT(introductory_scene().scenario.task->line, 0);
}

TEST(SessionTask, TheSessionEndsWithTheTaskUnlessAskedToGoOn) {
  Scene scene = introductory_scene();
  scene.scenario.task->time_limit_s = 1.0;
  const SessionMetrics ended = session_over(scene, fast(2.0))->run();
  EXPECT_EQ(ended.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(ended.task), "time_limit, failure");
  EXPECT_DOUBLE_EQ(ended.task.end_s, 1.0);
  EXPECT_EQ(ended.haptic.ticks(), 1001);  // the step at tick 1000 ended it
  RuntimeSettings on = fast(2.0);
  on.end_with_task = false;
  const SessionMetrics went_on = session_over(scene, on)->run();
  EXPECT_EQ(went_on.task.result, TaskResult::kFailure);
  EXPECT_EQ(went_on.haptic.ticks(), 2000);
}

TEST(SessionTask, ToolsOutOfTheCamerasViewFail) {
  // The laparoscope turned round to look away from the organs: both tips out of view from the
  // first step, for the 0.5 s grace.
  Scene scene = introductory_scene();
  CameraSpec& cam = scene.scenario.camera;
  cam.focal_point_m = cam.position_m + (cam.position_m - cam.focal_point_m);
  scene.scenario.task->out_of_view_grace_s = 0.5;
  const SessionMetrics m = session_over(scene, fast(2.0))->run();
  EXPECT_EQ(event_kinds(m.task), "out_of_view, out_of_view, failure");
  ASSERT_EQ(m.task.events.size(), 3U);
  EXPECT_EQ(m.task.events[0].tool, 0);
  EXPECT_EQ(m.task.events[1].tool, 1);
  EXPECT_DOUBLE_EQ(m.task.end_s, 0.5);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kOutOfView);
}

TEST(SessionTask, ATouchOnAForbiddenOrganIsSeen) {
  // Every organ but the duct forbidden: the pushed-in tools meet one of them (kPressingTick).
  Scene scene = introductory_scene();
  scene.scenario.task->forbidden_organs = {"liver", "gallbladder"};
  const SessionMetrics m = session_over(scene, fast(2.5))->run();
  ASSERT_EQ(m.task.result, TaskResult::kFailure) << event_kinds(m.task);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kForbiddenContact);
  ASSERT_GE(m.task.events.size(), 2U);
  const TaskEvent& e = m.task.events[m.task.events.size() - 2];
  EXPECT_EQ(e.kind, TaskEventKind::kForbiddenContact);
  EXPECT_NE(e.organ, 2);  // not the duct
  EXPECT_LE(m.task.end_s, static_cast<double>(kPressingTick) * 1e-3);
}

TEST(SessionTask, FastRunsScoreTheSameTwice) {
  // The forbidden touch of the test above, twice: the same events at the same times.
  Scene scene = introductory_scene();
  scene.scenario.task->forbidden_organs = {"liver", "gallbladder"};
  const SessionMetrics a = session_over(scene, fast(2.5))->run();
  const SessionMetrics b = session_over(scene, fast(2.5))->run();
  ASSERT_FALSE(a.task.events.empty());
  ASSERT_EQ(a.task.events.size(), b.task.events.size());
  for (size_t i = 0; i < a.task.events.size(); ++i) {
    const TaskEvent& x = a.task.events[i];
    const TaskEvent& y = b.task.events[i];
    EXPECT_EQ(x.t_s, y.t_s);
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.tool, y.tool);
    EXPECT_EQ(x.organ, y.organ);
    EXPECT_EQ(x.value, y.value);
  }
  EXPECT_EQ(a.task.end_s, b.task.end_s);
  EXPECT_EQ(a.state_hash, b.state_hash);
}

}  // namespace
}  // namespace lap::sim
