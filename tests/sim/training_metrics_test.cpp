// The training metrics (sim/runtime/training_metrics.h) on designed trajectories and force
// profiles, each figure against its hand-computed value: a straight stroke (path, one movement,
// economy 1, idle time from the speed filter's decay), a circle at constant speed (jerk R·ω³),
// out-and-back strokes (movements, economy), a stepped force on the duct (peak, mean while
// touched, time over the threshold), the jaws' closures, drops, the view cone.

#include "sim/runtime/training_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/support/counting_allocator.h"

namespace lap::sim {
namespace {

constexpr double kDt = 0.005;
constexpr int32_t kDuct = 1;

TaskModel view_model() {
  TaskModel m;
  m.kind = TaskKind::kFreeExploration;
  m.organ_count = 3;
  m.duct_organ = kDuct;
  m.spec.duct_injury_force_n = 1.5;
  m.spec.duct_squeeze_n = 4.0;
  m.spec.organ_injury_force_n = 2.5;
  m.picture.camera_W = Eigen::Vector3d(0.0, 0.0, 0.2);
  m.picture.view_dir_W = -Eigen::Vector3d::UnitZ();
  m.picture.cos_half_view = std::cos(17.5 * M_PI / 180.0);
  return m;
}

/// Steps the metrics with one tool (or both) following given positions.
struct Drive {
  TaskModel task = view_model();
  MetricsModel model = MetricsModel::build(task, 0.30, 0.45, kDt, 60.0, 1);
  MetricsState state = MetricsState::create(model);
  TaskState task_state = TaskState::create(task);
  TaskInput input;
  std::vector<double> force = std::vector<double>(3, 0.0);
  std::vector<uint8_t> touched = std::vector<uint8_t>(3, 0);
  std::array<double, 2> opening{0.8, 0.8};
  int64_t step = 0;

  void tick(const Eigen::Vector3d& left, const Eigen::Vector3d& right) {
    input.t_s = kDt * static_cast<double>(step++);
    input.tool_valid = {true, true};
    input.tool_tip_W = {left, right};
    input.organ_force_n = force;
    input.organ_touched = touched;
    step_metrics(model, task, input, opening, task_state, &state);
  }
  double metric(const std::string& name) const {
    for (const Metric& m :
         training_metrics(model, state, task_state, {"liver", "duct", "Gall Bladder"})) {
      if (m.name == name) return m.value;
    }
    ADD_FAILURE() << "no metric " << name;
    return NAN;
  }
};

const Eigen::Vector3d kStill(0.0, 0.0, 0.1);

// 2 s at 50 mm/s along x, then 1 s still: 0.1 m of path in one movement, straight (economy 1).
// Idle: the first step (the smoothed speed rises from 0: 0.05·(1 − e^(−dt/τ)) < 5 mm/s), and
// after the stop, once the speed has decayed from 50 to below 5 mm/s: τ·ln 10 = 115 ms.
TEST(TrainingMetrics, AStraightStrokeHasItsLengthOneMovementAndEconomyOne) {
  Drive d;
  const double v = 0.05;
  const int moving = 400, still = 200;
  for (int k = 0; k <= moving; ++k) d.tick(kStill, Eigen::Vector3d(v * kDt * k, 0.0, 0.1));
  for (int k = 0; k < still; ++k) d.tick(kStill, Eigen::Vector3d(v * kDt * moving, 0.0, 0.1));
  EXPECT_NEAR(d.metric("path_length_right_m"), 0.1, 1e-12);
  EXPECT_EQ(d.metric("movements_right"), 1.0);
  EXPECT_NEAR(d.metric("economy_of_motion_right"), 1.0, 1e-12);
  const double decay_s = MetricsModel::kSpeedFilterS * std::log(v / MetricsModel::kMoveStopMPerS);
  // The first two samples (at rest, rising), and the still samples n = 1 … still from the first
  // with v·e^(−n·dt/τ) below the threshold, n = ⌈decay / dt⌉.
  const double idle = (2 + still - std::ceil(decay_s / kDt) + 1) * kDt;
  EXPECT_NEAR(d.metric("idle_time_right_s"), idle, 1e-9);
  EXPECT_EQ(d.metric("path_length_left_m"), 0.0);
  EXPECT_EQ(d.metric("movements_left"), 0.0);
  EXPECT_TRUE(std::isnan(d.metric("economy_of_motion_left")));  // no need: undefined
  EXPECT_NEAR(d.metric("path_length_dominant_m"), 0.1, 1e-12);  // right is dominant
  EXPECT_EQ(d.metric("path_ratio_non_dominant"), 0.0);
  EXPECT_NEAR(d.metric("session_time_s"), (moving + still + 1) * kDt, 1e-12);
}

// A circle of radius R at f = 1 Hz: |jerk| = R·ω³ everywhere; the third difference over the
// 20 ms stride reads it times (sin x / x)³, x = ω·stride/2. Path: 3 turns of 2πR (the chords of
// 200 steps a turn fall short by (π/200)²/6 = 4e-5).
TEST(TrainingMetrics, AConstantSpeedCircleHasTheJerkRomegaCubed) {
  Drive d;
  const double r = 0.02, w = 2.0 * M_PI;
  for (int k = 0; k <= 600; ++k) {
    const double t = kDt * k;
    d.tick(kStill, Eigen::Vector3d(r * std::cos(w * t), r * std::sin(w * t), 0.1));
  }
  const double x = w * kDt * MetricsModel::kJerkStrideSteps / 2.0;
  const double expected = r * w * w * w * std::pow(std::sin(x) / x, 3);
  EXPECT_NEAR(d.metric("mean_jerk_right_m_per_s3"), expected, 1e-6 * expected);
  EXPECT_NEAR(d.metric("path_length_right_m"), 3 * 2 * M_PI * r, 5e-5 * 3 * 2 * M_PI * r);
  EXPECT_EQ(d.metric("movements_right"), 1.0);
  EXPECT_EQ(d.metric("mean_jerk_left_m_per_s3"), 0.0);  // still: no jerk
}

// Out 20 mm, back, out again, with 0.5 s still between: three movements; the need is the one
// straight line from start to end (no phase reached): economy 60 / 20 = 3.
TEST(TrainingMetrics, OutAndBackStrokesCountAsMovementsAndCostEconomy) {
  Drive d;
  Eigen::Vector3d p(0.0, 0.0, 0.1);
  const auto stroke = [&](double dx) {
    for (int k = 0; k < 100; ++k) {
      p.x() += dx / 100.0;
      d.tick(kStill, p);
    }
    for (int k = 0; k < 100; ++k) d.tick(kStill, p);
  };
  d.tick(kStill, p);
  stroke(0.02);
  stroke(-0.02);
  stroke(0.02);
  EXPECT_EQ(d.metric("movements_right"), 3.0);
  EXPECT_NEAR(d.metric("path_length_right_m"), 0.06, 1e-12);
  EXPECT_NEAR(d.metric("economy_of_motion_right"), 3.0, 1e-9);
}

// The need runs through the tip's positions where the task reached a phase: a stroke out and
// back with the phase "catheter grasped" reached at its far end needs both legs (economy 1).
TEST(TrainingMetrics, ThePhasesAreWaypointsOfTheNeed) {
  Drive d;
  Eigen::Vector3d p(0.0, 0.0, 0.1);
  d.tick(kStill, p);
  for (int k = 0; k < 100; ++k) {
    p.x() += 0.0002;
    d.tick(kStill, p);
  }
  d.task_state.phase_s[0] = d.input.t_s;  // grasped here
  d.tick(kStill, p);
  for (int k = 0; k < 100; ++k) {
    p.x() -= 0.0002;
    d.tick(kStill, p);
  }
  EXPECT_NEAR(d.metric("path_length_right_m"), 0.04, 1e-12);
  EXPECT_NEAR(d.metric("economy_of_motion_right"), 1.0, 1e-9);
  EXPECT_NEAR(d.metric("phase_catheter_grasped_s"), 100 * kDt, 1e-12);
  EXPECT_TRUE(std::isnan(d.metric("phase_held_s")));
  EXPECT_TRUE(std::isnan(d.metric("completion_time_s")));
}

// The duct pushed at 0.5 N for 1 s, then 2 N for 0.5 s (over its 1.5 N threshold), then left
// alone 1 s; the gallbladder at 3 N for 0.2 s (over its 2.5 N); the squeeze up to 5 N for
// 0.1 s (over its 4 N). Peak 2 N; mean while touched (0.5·1 + 2·0.5) / 1.5 = 1 N; over the
// threshold: duct 0.5 s, gallbladder 0.2 s (during the duct's), squeeze 0.1 s (alone): 0.6 s.
TEST(TrainingMetrics, AStepProfileOfForceGivesItsPeakMeanAndTimeOverThreshold) {
  Drive d;
  const auto hold = [&](double duct, double gallbladder, double squeeze, int steps) {
    for (int k = 0; k < steps; ++k) {
      d.force[kDuct] = duct;
      d.force[2] = gallbladder;
      d.input.duct_squeeze_n = squeeze;
      d.tick(kStill, kStill);
    }
  };
  hold(0.5, 0.0, 0.0, 200);
  hold(2.0, 0.0, 0.0, 60);
  hold(2.0, 3.0, 0.0, 40);
  hold(0.0, 0.0, 5.0, 20);
  hold(0.0, 0.0, 1.0, 180);
  EXPECT_DOUBLE_EQ(d.metric("max_force_duct_n"), 2.0);
  EXPECT_NEAR(d.metric("mean_force_duct_n"), 1.0, 1e-12);
  EXPECT_NEAR(d.metric("contact_time_duct_s"), 1.5, 1e-9);
  EXPECT_NEAR(d.metric("time_over_threshold_duct_s"), 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(d.metric("max_force_gall_bladder_n"), 3.0);
  EXPECT_NEAR(d.metric("time_over_threshold_gall_bladder_s"), 0.2, 1e-9);
  EXPECT_NEAR(d.metric("time_over_threshold_s"), 0.6, 1e-9);
  EXPECT_DOUBLE_EQ(d.metric("max_squeeze_duct_n"), 5.0);
  EXPECT_EQ(d.metric("max_force_liver_n"), 0.0);
  EXPECT_TRUE(std::isnan(d.metric("mean_force_liver_n")));  // never touched
}

// A grasp attempt: the jaws closing past 0.30 rad after opening past 0.45 rad. 0.8 → 0.2 (one),
// 0.4 → 0.2 (not re-opened: none), 0.6 → 0.1 (two).
TEST(TrainingMetrics, GraspAttemptsAreClosuresAfterAnOpening) {
  Drive d;
  for (const double a : {0.8, 0.2, 0.4, 0.2, 0.6, 0.1, 0.1}) {
    d.opening = {a, 0.8};
    d.tick(kStill, kStill);
  }
  EXPECT_EQ(d.metric("grasp_attempts_left"), 2.0);
  EXPECT_EQ(d.metric("grasp_attempts_right"), 0.0);
  EXPECT_EQ(d.metric("grasp_attempts"), 2.0);
}

// A drop: the catheter let go of by every tool, its tip out of the lumen (the task engine's
// loose_since_s), counted once per episode.
TEST(TrainingMetrics, EachLooseEpisodeOfTheCatheterIsOneDrop) {
  Drive d;
  for (const double since : {-1.0, 1.0, 1.0, -1.0, -1.0, 2.0, 2.0}) {
    d.task_state.loose_since_s = since;
    d.tick(kStill, kStill);
  }
  EXPECT_EQ(d.metric("catheter_drops"), 2.0);
}

// The left tip 0.3 s outside the 17.5° cone, the right always in it.
TEST(TrainingMetrics, TimeOutOfViewIsTheTimeOutsideTheLaparoscopesCone) {
  Drive d;
  const Eigen::Vector3d outside(0.2, 0.0, 0.1);  // 63° off the line of sight
  for (int k = 0; k < 60; ++k) d.tick(k < 20 ? kStill : outside, kStill);
  for (int k = 0; k < 40; ++k) d.tick(kStill, kStill);
  EXPECT_NEAR(d.metric("out_of_view_left_s"), 40 * kDt, 1e-9);
  EXPECT_EQ(d.metric("out_of_view_right_s"), 0.0);
  EXPECT_NEAR(d.metric("time_out_of_view_s"), 40 * kDt, 1e-9);
}

// The metrics stop with the task (its last step counted), and the step allocates nothing: the
// series fill their reserved space and count what does not fit.
TEST(TrainingMetrics, StopAtTheTasksEndAndAllocateNothing) {
  Drive d;
  d.model.series_capacity = 50;
  d.state = MetricsState::create(d.model);
  int64_t allocations = 0;
  {
    const test::AllocationCounter counter;
    for (int k = 0; k < 2000; ++k) {
      d.force[kDuct] = (k % 40) * 0.1;
      d.opening = {k % 30 < 15 ? 0.8 : 0.1, 0.8};
      d.tick(kStill, Eigen::Vector3d(0.001 * (k % 17), 0.0, 0.1));
    }
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(d.state.series.t_s.size(), 50u);
  EXPECT_EQ(d.state.series.dropped, 2000 / 20 - 50);  // one sample per 0.1 s
  d.task_state.result = TaskResult::kSuccess;
  d.task_state.end_s = d.input.t_s;
  const double path = d.metric("path_length_right_m");
  d.tick(kStill, kStill);  // the step that sees the end
  const double last = d.metric("path_length_right_m");
  EXPECT_GT(last, path);
  d.tick(kStill, Eigen::Vector3d(0.05, 0.0, 0.1));
  EXPECT_EQ(d.metric("path_length_right_m"), last);
}

// Every name the metrics write is one a scenario's proficiency benchmarks may name
// (sim/setup/metric_names.h checks them at load), in the same order for the fixed ones.
TEST(TrainingMetrics, TheirNamesAreTheOnesTheScenarioLoaderKnows) {
  Drive d;
  d.tick(kStill, kStill);
  const std::vector<std::string> organs = {"liver", "duct", "Gall Bladder"};
  std::vector<std::string> fixed;
  for (const Metric& m : training_metrics(d.model, d.state, d.task_state, organs)) {
    EXPECT_TRUE(is_metric_name(m.name, organs)) << m.name;
    if (m.name.find("force_") == std::string::npos && m.name.find("contact_time_") != 0 &&
        (m.name.find("time_over_threshold_") != 0 || m.name == "time_over_threshold_s")) {
      fixed.push_back(m.name);
    }
  }
  EXPECT_EQ(fixed, fixed_metric_names());
  EXPECT_FALSE(is_metric_name("max_force_spleen_n", organs));
  EXPECT_TRUE(is_metric_name("max_force_gall_bladder_n", organs));
}

TEST(TrainingMetrics, OrganNamesAreSnakeCase) {
  EXPECT_EQ(snake_case("Common Bile-Duct"), "common_bile_duct");
  EXPECT_EQ(snake_case("  liver  "), "liver");
  EXPECT_EQ(snake_case("Leber (Lappen) 2"), "leber_lappen_2");
  EXPECT_EQ(snake_case("\xc3\xa9t\xc3\xa9"), "t");
}

}  // namespace
}  // namespace lap::sim
