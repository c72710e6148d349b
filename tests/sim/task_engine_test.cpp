// The task engine (sim/runtime/task_engine.h) driven with constructed inputs: a straight duct
// along the world's z axis (its frame is the world's), 30 mm long, lumen radius 2 mm, an
// incision on its top (+y) at z = 10 mm; a straight or bent catheter placed by hand; forces,
// squeezes, touches and tool tips set step by step. Each test asserts the exact event sequence.

#include "sim/runtime/task_engine.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/counting_allocator.h"

namespace lap::sim {
namespace {

constexpr int32_t kLiver = 0;
constexpr int32_t kDuct = 1;
constexpr int32_t kGallbladder = 2;
constexpr double kRadius = 0.002;
constexpr double kIncisionZ = 0.010;

TaskModel duct_model() {
  TaskModel m;
  m.kind = TaskKind::kCatheterInsertion;
  m.spec.insertion_depth_m = 0.010;
  m.spec.hold_s = 3.0;
  m.spec.time_limit_s = 600.0;
  m.organ_count = 3;
  m.duct_organ = kDuct;
  m.pose_DW = Eigen::Isometry3d::Identity();
  m.duct_length_m = 0.030;
  m.lumen_radius_m = kRadius;
  m.has_incision = true;
  m.incision_center_W = Eigen::Vector3d(0.0, kRadius, kIncisionZ);
  m.incision_z_m = kIncisionZ;
  m.incision_angle_rad = M_PI / 2;
  m.incision_half_length_m = 0.002;
  m.incision_half_width_m = 0.0015;
  m.at_incision_m = 0.0035;
  m.forbidden = {0, 0, 1};
  m.picture.camera_W = Eigen::Vector3d(0.0, 0.0, 0.2);
  m.picture.view_dir_W = -Eigen::Vector3d::UnitZ();
  m.picture.cos_half_view = std::cos(17.5 * M_PI / 180.0);
  return m;
}

// Particles every 1 mm along a polyline, from its first point to its last (the tip).
std::vector<Eigen::Vector3d> along(const std::vector<Eigen::Vector3d>& corners) {
  std::vector<Eigen::Vector3d> p{corners.front()};
  for (size_t c = 1; c < corners.size(); ++c) {
    const Eigen::Vector3d d = corners[c] - corners[c - 1];
    const int n = static_cast<int>(std::lround(d.norm() / 0.001));
    for (int k = 1; k <= n; ++k) p.push_back(corners[c - 1] + d * (static_cast<double>(k) / n));
  }
  return p;
}

// The catheter coming straight down (−y) at z onto the duct, its tip at height y.
std::vector<Eigen::Vector3d> above(double y, double z = kIncisionZ, double x = 0.0) {
  return along({Eigen::Vector3d(x, 0.03, z), Eigen::Vector3d(x, y, z)});
}

// Down through the incision to the axis, then `d` along it (+z): inside the lumen d + 2 mm.
std::vector<Eigen::Vector3d> inserted(double d) {
  const Eigen::Vector3d corner(0.0, 0.0, kIncisionZ);
  if (d <= 0.0) return along({Eigen::Vector3d(0.0, 0.03, kIncisionZ), corner});
  return along(
      {Eigen::Vector3d(0.0, 0.03, kIncisionZ), corner, corner + d * Eigen::Vector3d::UnitZ()});
}

// One session's inputs as the modelling loop would hand them, step by step.
class Driver {
 public:
  explicit Driver(TaskModel m) : model(std::move(m)), state(TaskState::create(model)) {
    catheter = above(0.03 - 0.01);  // far from the duct
    input.tool_valid = {true, true};
    input.tool_tip_W = {Eigen::Vector3d(0.0, 0.0, 0.02), Eigen::Vector3d(0.001, 0.0, 0.02)};
  }
  void step(double t) {
    input.t_s = t;
    input.catheter = catheter;
    input.organ_force_n = force;
    input.organ_touched = touched;
    step_task(model, input, &state);
  }
  // Steps every 0.1 s from t0 to t1, both included.
  void hold(double t0, double t1) {
    for (int k = 0; t0 + 0.1 * k <= t1 + 1e-9; ++k) step(t0 + 0.1 * k);
  }
  [[nodiscard]] std::string kinds() const {
    std::string s;
    for (const TaskEvent& e : state.events) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s%.1f %s", s.empty() ? "" : ", ", e.t_s,
                    std::string(to_string(e.kind)).c_str());
      s += buf;
    }
    return s;
  }

  TaskModel model;
  TaskState state;
  TaskInput input;
  std::vector<Eigen::Vector3d> catheter;
  std::vector<double> force = std::vector<double>(3, 0.0);
  std::vector<uint8_t> touched = std::vector<uint8_t>(3, 0);
};

// The picture's frustum (task_model.h): a 35° vertical view angle at 16:9 reaches
// atan(16/9 tan 17.5°) = 29.27° to each side; the old cone of 17.5° called the sides out of view.
TEST(TaskView, ATipAnywhereInTheSixteenByNinePictureIsInView) {
  TaskModel m;
  m.picture.camera_W = Eigen::Vector3d::Zero();
  m.picture.view_dir_W = -Eigen::Vector3d::UnitZ();
  m.picture.view_up_W = Eigen::Vector3d::UnitY();
  m.picture.view_right_W = m.picture.view_dir_W.cross(m.picture.view_up_W);  // +x
  m.picture.cos_half_view = std::cos(17.5 * M_PI / 180.0);
  m.picture.tan_half_vertical = std::tan(17.5 * M_PI / 180.0);
  m.picture.tan_half_horizontal = CameraPicture::kAspect * m.picture.tan_half_vertical;
  const double half_h_deg = std::atan(m.picture.tan_half_horizontal) * 180.0 / M_PI;
  EXPECT_NEAR(half_h_deg, 29.27, 0.01);
  auto at = [](double right_deg, double up_deg) {  // 0.1 m deep, turned by those angles
    const double d = 0.1;
    return Eigen::Vector3d(d * std::tan(right_deg * M_PI / 180.0),
                           d * std::tan(up_deg * M_PI / 180.0), -d);
  };
  EXPECT_TRUE(m.in_view(at(0.0, 0.0)));
  EXPECT_TRUE(m.in_view(at(25.0, 0.0)));  // beyond the old cone, inside the picture
  EXPECT_TRUE(m.in_view(at(-29.0, 0.0)));
  EXPECT_FALSE(m.in_view(at(29.6, 0.0)));  // past the picture's side
  EXPECT_TRUE(m.in_view(at(0.0, 17.0)));
  EXPECT_FALSE(m.in_view(at(0.0, 18.0)));                   // past its top
  EXPECT_TRUE(m.in_view(at(28.0, -17.0)));                  // a corner
  EXPECT_FALSE(m.in_view(Eigen::Vector3d(0.0, 0.0, 0.1)));  // behind the scope
  // Without the frustum's fields (older models), the cone of half the vertical angle.
  m.picture.tan_half_vertical = 0.0;
  EXPECT_FALSE(m.in_view(at(25.0, 0.0)));
  EXPECT_TRUE(m.in_view(at(17.0, 0.0)));
}

TEST(TaskDepth, IsTheCatheterInsideTheLumenFromItsTipBackToWhereItEnters) {
  const TaskModel m = duct_model();
  EXPECT_EQ(lumen_depth_m(m, above(0.004)), 0.0);
  EXPECT_NEAR(lumen_depth_m(m, inserted(0.0)), kRadius, 1e-9);
  EXPECT_NEAR(lumen_depth_m(m, inserted(0.0065)), 0.0065 + kRadius, 1e-9);
  // Entering between two particles: the crossing is interpolated (particles at y = 2.5 and 1.5
  // mm on a 1 mm spacing straddle the wall at 2 mm).
  EXPECT_NEAR(lumen_depth_m(m, above(0.0005)), 0.0015, 1e-9);
  // A catheter lying wholly in the lumen along the axis: its whole length.
  EXPECT_NEAR(lumen_depth_m(m, along({Eigen::Vector3d(0, 0, 0.005), Eigen::Vector3d(0, 0, 0.02)})),
              0.015, 1e-9);
}

TEST(TaskEngine, EveryPhaseInTurnEndsInSuccess) {
  Driver d(duct_model());
  d.step(0.0);
  d.input.catheter_held = {true, false};
  d.step(0.1);
  d.catheter = above(0.004);  // 2 mm above the incision's centre
  d.step(0.2);
  d.catheter = inserted(0.0);
  d.step(0.3);
  d.catheter = inserted(0.004);  // 6 mm in
  d.step(0.4);
  d.catheter = inserted(0.009);  // 11 mm in
  d.hold(0.5, 3.4);
  EXPECT_EQ(d.state.result, TaskResult::kIncomplete);
  d.step(3.5);
  EXPECT_EQ(d.kinds(),
            "0.1 catheter_grasped, 0.2 tip_at_incision, 0.3 tip_in_lumen, "
            "0.5 target_depth_reached, 3.5 success");
  EXPECT_EQ(d.state.result, TaskResult::kSuccess);
  EXPECT_EQ(d.state.reason_count, 0U);
  EXPECT_DOUBLE_EQ(d.state.end_s, 3.5);
  EXPECT_EQ(d.state.events[0].tool, 0);
  EXPECT_NEAR(d.state.events[3].value, 0.011, 1e-9);  // the depth reached
  const std::array<double, 5> phases{0.1, 0.2, 0.3, 0.5, 3.5};
  for (size_t p = 0; p < phases.size(); ++p) EXPECT_DOUBLE_EQ(d.state.phase_s[p], phases[p]);
  // Once ended it stays ended.
  d.catheter = above(0.004);
  d.step(3.6);
  EXPECT_EQ(d.state.events.size(), 5U);
}

TEST(TaskEngine, GoingBackIsToldAndTheHoldStartsAgain) {
  Driver d(duct_model());
  d.input.catheter_held = {false, true};
  d.step(0.0);
  d.catheter = inserted(0.0);  // straight in through the incision (no step near it before)
  d.step(0.1);
  d.catheter = inserted(0.009);
  d.hold(0.2, 1.0);
  d.catheter = inserted(0.0076);  // 9.6 mm: within the hysteresis, still at depth
  d.step(1.1);
  d.catheter = inserted(0.007);  // 9 mm: lost
  d.step(1.2);
  d.catheter = inserted(0.0);
  d.step(1.3);
  d.catheter = above(0.004);  // out by the incision
  d.step(1.4);
  d.catheter = inserted(0.0);  // in again
  d.step(1.5);
  d.catheter = inserted(0.009);
  d.hold(1.6, 4.5);
  EXPECT_EQ(d.state.result, TaskResult::kIncomplete);
  d.step(4.6);
  EXPECT_EQ(d.kinds(),
            "0.0 catheter_grasped, 0.1 tip_at_incision, 0.1 tip_in_lumen, "
            "0.2 target_depth_reached, 1.2 target_depth_lost, 1.4 tip_left_lumen, "
            "1.5 tip_in_lumen, 1.6 target_depth_reached, 4.6 success");
  EXPECT_EQ(d.state.events[0].tool, 1);
  EXPECT_DOUBLE_EQ(d.state.phase_s[3], 0.2);  // the first time
}

TEST(TaskEngine, LeavingTheLumenAtDepthLosesTheDepthFirst) {
  TaskModel m = duct_model();
  m.spec.insertion_depth_m = 0.0019;  // the lumen's radius is at depth: in and out radially
  Driver d(m);
  d.input.catheter_held = {true, false};
  d.step(0.0);
  d.catheter = inserted(0.0);
  d.step(0.1);
  d.catheter = above(0.004);
  d.step(0.2);
  EXPECT_EQ(d.kinds(),
            "0.0 catheter_grasped, 0.1 tip_at_incision, 0.1 tip_in_lumen, "
            "0.1 target_depth_reached, 0.2 target_depth_lost, 0.2 tip_left_lumen");
}

TEST(TaskEngine, LettingGoBrieflyIsNoDrop) {
  Driver d(duct_model());
  d.input.catheter_held = {true, false};
  d.step(0.0);
  d.input.catheter_held = {false, false};
  d.hold(0.1, 1.0);  // 0.9 s loose, the grace is 1 s
  d.input.catheter_held = {false, true};
  d.step(1.1);
  EXPECT_EQ(d.kinds(), "0.0 catheter_grasped, 0.1 catheter_released, 1.1 catheter_grasped");
  EXPECT_EQ(d.state.result, TaskResult::kIncomplete);
  EXPECT_EQ(d.state.events[1].tool, 0);
  EXPECT_EQ(d.state.events[2].tool, 1);
}

TEST(TaskEngine, ACatheterLeftLooseOutsideTheLumenIsDropped) {
  Driver d(duct_model());
  d.input.catheter_held = {true, false};
  d.step(0.0);
  d.input.catheter_held = {false, false};
  d.hold(0.1, 1.1);
  EXPECT_EQ(d.kinds(),
            "0.0 catheter_grasped, 0.1 catheter_released, 1.1 catheter_dropped, 1.1 failure");
  EXPECT_EQ(d.state.result, TaskResult::kFailure);
  ASSERT_EQ(d.state.reason_count, 1U);
  EXPECT_EQ(d.state.reasons[0], TaskReason::kCatheterDropped);
  EXPECT_NEAR(d.state.events[2].duration_s, 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(d.state.end_s, 1.1);
}

TEST(TaskEngine, LettingGoWithTheTipInTheLumenIsNoDrop) {
  Driver d(duct_model());
  d.input.catheter_held = {true, false};
  d.step(0.0);
  d.catheter = inserted(0.0);
  d.step(0.1);
  d.catheter = inserted(0.004);
  d.step(0.2);
  d.input.catheter_held = {false, false};
  d.hold(0.3, 2.5);
  EXPECT_EQ(d.kinds(),
            "0.0 catheter_grasped, 0.1 tip_at_incision, 0.1 tip_in_lumen, 0.3 catheter_released");
  EXPECT_EQ(d.state.result, TaskResult::kIncomplete);
}

TEST(TaskEngine, EnteringThroughTheWallBesideTheIncisionPerforatesIt) {
  Driver d(duct_model());
  d.input.catheter_held = {true, false};
  d.step(0.0);
  d.catheter = above(0.004, 0.020);  // 10 mm along from the incision
  d.step(0.1);
  d.catheter = above(0.001, 0.020);
  d.step(0.2);
  EXPECT_EQ(d.kinds(), "0.0 catheter_grasped, 0.2 wall_perforation, 0.2 failure");
  ASSERT_EQ(d.state.reason_count, 1U);
  EXPECT_EQ(d.state.reasons[0], TaskReason::kWallPerforation);
}

TEST(TaskEngine, EnteringByAnOpenEndIsNoPhaseAndLeavingThroughTheWallPerforates) {
  Driver d(duct_model());
  d.input.catheter_held = {true, false};
  d.catheter = along({Eigen::Vector3d(0, 0, -0.02), Eigen::Vector3d(0, 0, -0.002)});
  d.step(0.0);
  d.catheter = along({Eigen::Vector3d(0, 0, -0.02), Eigen::Vector3d(0, 0, 0.004)});
  d.step(0.1);
  d.catheter = along({Eigen::Vector3d(0, 0, -0.02), Eigen::Vector3d(0, 0, 0.004),
                      Eigen::Vector3d(-0.003, 0, 0.004)});
  d.step(0.2);
  EXPECT_EQ(d.kinds(),
            "0.0 catheter_grasped, 0.1 tip_entered_open_end, 0.2 wall_perforation, 0.2 failure");
  EXPECT_LT(d.state.phase_s[2], 0.0);  // never in the lumen by the incision
}

TEST(TaskEngine, PushingTheDuctTooHardForTooLongInjuresIt) {
  Driver d(duct_model());
  d.force[kDuct] = 3.0;  // over the 2 N threshold, for 0.5 s: no injury
  d.hold(0.0, 0.5);
  d.force[kDuct] = 1.0;
  d.step(0.6);
  d.force[kDuct] = 2.5;
  d.hold(0.7, 1.6);
  d.force[kDuct] = 3.5;
  d.step(1.7);  // 1.0 s over at last
  EXPECT_EQ(d.kinds(), "1.7 duct_injury, 1.7 failure");
  const TaskEvent& e = d.state.events[0];
  EXPECT_EQ(e.organ, kDuct);
  EXPECT_DOUBLE_EQ(e.value, 3.5);
  EXPECT_NEAR(e.duration_s, 1.0, 1e-9);
  EXPECT_FALSE(e.squeeze);
  EXPECT_EQ(d.state.reasons[0], TaskReason::kDuctInjury);
}

TEST(TaskEngine, SqueezingTheDuctTooHardForTooLongInjuresIt) {
  Driver d(duct_model());
  d.input.duct_squeeze_n = 6.0;
  d.hold(0.0, 1.0);
  EXPECT_EQ(d.kinds(), "1.0 duct_injury, 1.0 failure");
  EXPECT_TRUE(d.state.events[0].squeeze);
  EXPECT_DOUBLE_EQ(d.state.events[0].value, 6.0);
}

TEST(TaskEngine, PushingAnotherOrganTooHardForTooLongInjuresIt) {
  Driver d(duct_model());
  d.force[kLiver] = 4.0;  // under its 5 N
  d.hold(0.0, 3.0);
  d.force[kLiver] = 6.0;
  d.hold(3.1, 5.1);
  EXPECT_EQ(d.kinds(), "5.1 organ_injury, 5.1 failure");
  EXPECT_EQ(d.state.events[0].organ, kLiver);
  EXPECT_EQ(d.state.reasons[0], TaskReason::kOrganInjury);
}

TEST(TaskEngine, TheTimeLimitEndsTheTask) {
  TaskModel m = duct_model();
  m.spec.time_limit_s = 2.0;
  Driver d(m);
  d.hold(0.0, 1.9);
  EXPECT_EQ(d.state.result, TaskResult::kIncomplete);
  d.step(2.0);
  EXPECT_EQ(d.kinds(), "2.0 time_limit, 2.0 failure");
  EXPECT_EQ(d.state.reasons[0], TaskReason::kTimeLimit);
}

TEST(TaskEngine, AToolOutOfViewForLongerThanTheGraceFails) {
  Driver d(duct_model());
  // 0.1 m off the line of sight 0.18 m from the camera: 29 degrees off, the cone is 17.5.
  d.input.tool_tip_W[1] = Eigen::Vector3d(0.1, 0.0, 0.02);
  d.hold(0.0, 2.0);
  d.input.tool_tip_W[1] = Eigen::Vector3d(0.04, 0.0, 0.02);  // 12.5 degrees: seen again
  d.step(2.1);
  d.input.tool_tip_W[1] = Eigen::Vector3d(0.1, 0.0, 0.02);
  d.hold(2.2, 5.2);
  EXPECT_EQ(d.kinds(), "5.2 out_of_view, 5.2 failure");
  EXPECT_EQ(d.state.events[0].tool, 1);
  EXPECT_NEAR(d.state.events[0].duration_s, 3.0, 1e-9);
  EXPECT_EQ(d.state.reasons[0], TaskReason::kOutOfView);
}

TEST(TaskEngine, TouchingAForbiddenOrganFailsAtOnce) {
  Driver d(duct_model());
  d.touched[kLiver] = 1;  // allowed
  d.step(0.0);
  d.touched[kGallbladder] = 1;
  d.step(0.1);
  EXPECT_EQ(d.kinds(), "0.1 forbidden_contact, 0.1 failure");
  EXPECT_EQ(d.state.events[0].organ, kGallbladder);
  EXPECT_EQ(d.state.reasons[0], TaskReason::kForbiddenContact);
}

TEST(TaskEngine, TheTipInTheCommonBileDuctFails) {
  TaskModel m = duct_model();
  m.cbd_organ = kLiver;  // stands for it here
  Driver d(m);
  d.step(0.0);
  d.input.tip_in_common_bile_duct = true;
  d.step(0.1);
  EXPECT_EQ(d.kinds(), "0.1 tip_in_common_bile_duct, 0.1 failure");
  EXPECT_EQ(d.state.events[0].organ, kLiver);
  ASSERT_EQ(d.state.reason_count, 1U);
  EXPECT_EQ(d.state.reasons[0], TaskReason::kCommonBileDuct);
  EXPECT_EQ(to_string(TaskReason::kCommonBileDuct), "common_bile_duct");
}

TEST(TaskEngine, AnErrorInTheStepOfTheSuccessWinsAndEveryReasonIsKept) {
  TaskModel m = duct_model();
  m.spec.hold_s = 0.0;
  m.spec.time_limit_s = 1.0;
  m.spec.insertion_depth_m = 0.0019;
  Driver d(m);
  d.input.catheter_held = {true, false};
  d.step(0.9);
  d.catheter = inserted(0.0);
  d.touched[kGallbladder] = 1;
  d.step(1.0);
  EXPECT_EQ(d.kinds(),
            "0.9 catheter_grasped, 1.0 tip_at_incision, 1.0 tip_in_lumen, "
            "1.0 target_depth_reached, 1.0 forbidden_contact, 1.0 time_limit, 1.0 failure");
  ASSERT_EQ(d.state.reason_count, 2U);
  EXPECT_EQ(d.state.reasons[0], TaskReason::kForbiddenContact);
  EXPECT_EQ(d.state.reasons[1], TaskReason::kTimeLimit);
  EXPECT_EQ(d.state.result, TaskResult::kFailure);
}

TEST(TaskEngine, FreeExplorationHasNoGoalNorTimeLimitButItsErrorsCount) {
  TaskModel m = duct_model();
  m.kind = TaskKind::kFreeExploration;
  m.spec.time_limit_s = 1.0;
  Driver d(m);
  d.input.catheter_held = {true, false};
  d.catheter = inserted(0.009);
  d.hold(0.0, 4.0);
  EXPECT_EQ(d.kinds(), "");
  d.force[kDuct] = 3.0;
  d.hold(4.1, 5.1);
  EXPECT_EQ(d.kinds(), "5.1 duct_injury, 5.1 failure");
}

TEST(TaskEngine, WithoutATaskNothingIsWatched) {
  TaskModel m = duct_model();
  m.kind = TaskKind::kNone;
  Driver d(m);
  d.touched[kGallbladder] = 1;
  d.force[kDuct] = 50.0;
  d.hold(0.0, 10.0);
  EXPECT_TRUE(d.state.events.empty());
  EXPECT_EQ(d.state.result, TaskResult::kIncomplete);
}

TEST(TaskEngine, EventsBeyondTheReservedSpaceAreCountedNotKept) {
  TaskModel m = duct_model();
  Driver d(m);
  d.state = TaskState::create(m, 4);
  for (int k = 0; k < 10; ++k) {
    d.input.catheter_held = {k % 2 == 0, false};
    d.step(0.1 * k);
  }
  EXPECT_EQ(d.state.events.size(), 4U);
  EXPECT_EQ(d.state.events.capacity(), 4U);
  EXPECT_EQ(d.state.events_dropped, 6);
}

TEST(TaskEngine, TheStepAllocatesNothing) {
  Driver d(duct_model());
  d.model.spec.time_limit_s = 1e9;
  d.model.spec.drop_grace_s = 1e9;
  // In and out through the incision, radially, never through the wall.
  const std::vector<std::vector<Eigen::Vector3d>> paths = {above(0.004), inserted(0.0),
                                                           inserted(0.009), inserted(0.0)};
  int64_t allocations = 0;
  {
    const test::AllocationCounter counter;
    for (int k = 0; k < 1000; ++k) {
      // Grasps, the tip in and out through the incision, forces coming and going.
      d.input.catheter_held = {k % 7 < 4, k % 11 < 3};
      d.input.catheter = paths[static_cast<size_t>(k / 3) % paths.size()];
      d.input.t_s = 0.005 * k;
      d.force[kLiver] = (k % 50) * 0.1;
      d.input.organ_force_n = d.force;
      d.input.organ_touched = d.touched;
      step_task(d.model, d.input, &d.state);
    }
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(d.state.result, TaskResult::kIncomplete);
  EXPECT_GT(d.state.events.size(), 100U);  // it did emit
}

}  // namespace
}  // namespace lap::sim
