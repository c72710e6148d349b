#pragma once
/// \file
/// Training metrics (thesis §7.4: "the computer could record all of the activities during the
/// training process … record and measure the forces applied by surgeons"). Stepped in the
/// modelling loop right after the task engine, on the same input: each tool's tip, the forces on
/// every organ, the squeeze on the duct, the catheter's grasp, the task's phases; plus each
/// tool's jaw opening. Every figure, its unit and its source are defined in docs/metrics.md.
///
/// The step allocates nothing (the series' space is reserved by create(); samples past it are
/// counted, not kept), never throws, and is a function of its inputs, so a --fast session and
/// its replay give the same metrics to the last bit. It stops at the task's end (the step that
/// ends it included), or runs to the session's end for a scenario without a task.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sim/runtime/task_engine.h"
#include "sim/setup/metric_names.h"
#include "sim/setup/task_model.h"

namespace lap::sim {

/// What the metrics need from set-up: the thresholds (the task's), the jaws' grasp thresholds,
/// the modelling step, which hand is the trainee's dominant one.
struct MetricsModel {
  double dt_s = 0.005;  ///< the modelling step
  int32_t organ_count = 0;
  int32_t duct_organ = -1;
  double duct_injury_force_n = 0.0;
  double duct_squeeze_n = 0.0;
  double organ_injury_force_n = 0.0;
  /// A grasp attempt: the jaws closing past grasp_below_rad after being open past
  /// release_above_rad (models/catheter_grasp.h's thresholds: what can grasp, counted).
  double grasp_below_rad = 0.30;
  double release_above_rad = 0.45;
  int32_t dominant_tool = 1;  ///< 0 left, 1 right
  /// Series for plots (insertion depth, force on the duct, tool speeds), one sample per period.
  double series_period_s = 0.1;
  size_t series_capacity = 0;  ///< samples reserved

  // Motion analysis. The tip's speed is smoothed by a first-order filter (time constant
  // kSpeedFilterS); a movement starts when it rises past kMoveStartMPerS and ends when it falls
  // below kMoveStopMPerS, and the tip is idle below kMoveStopMPerS. Thresholds: estimates, of
  // the order the ICSAD motion tracker's movement count resolves (Datta et al., J Am Coll Surg
  // 2001;193:479-485, who define number of movements and path length for laparoscopy).
  static constexpr double kSpeedFilterS = 0.05;
  static constexpr double kMoveStartMPerS = 0.010;
  static constexpr double kMoveStopMPerS = 0.005;
  /// Jerk by the third difference of the tip's position sampled every kJerkStrideSteps modelling
  /// steps (20 ms at 200 Hz): a coarser stride than the step keeps a device's position noise
  /// (~0.03 mm) from swamping it, at a bias of (sin x / x)³ with x = ω·stride/2, 0.2 % at 1 Hz.
  static constexpr int32_t kJerkStrideSteps = 4;

  /// From the task's model, the catheter grasp's thresholds, the modelling step, the session's
  /// length (series space for it, at most an hour) and the dominant hand.
  static MetricsModel build(const TaskModel& task, double grasp_below_rad, double release_above_rad,
                            double dt_s, double duration_s, int32_t dominant_tool);
};

/// One tool's motion so far.
struct ToolMotion {
  bool seen = false;
  Eigen::Vector3d last_W = Eigen::Vector3d::Zero();  ///< the tip at the last step
  double path_m = 0.0;
  double speed_m_per_s = 0.0;  ///< smoothed
  bool moving = false;
  int64_t movements = 0;
  double idle_s = 0.0;
  int64_t steps = 0;                              ///< steps seen (for the jerk's stride)
  std::array<Eigen::Vector3d, 3> jerk_history{};  ///< the last three strided samples, newest first
  int32_t jerk_filled = 0;
  double jerk_sum = 0.0;  ///< of |jerk| [m/s³]
  int64_t jerk_samples = 0;
  /// Straight-line need: the tip's straight lines between its positions at the session's start,
  /// each phase the task reached, and the end.
  Eigen::Vector3d waypoint_W = Eigen::Vector3d::Zero();
  double need_m = 0.0;
  bool jaws_open = false;
  int64_t grasp_attempts = 0;
  double out_of_view_s = 0.0;
};

/// One organ's load: the hardest push on it (TaskInput::organ_force_n).
struct OrganLoad {
  double max_n = 0.0;
  double impulse_n_s = 0.0;  ///< force × time while touched
  double contact_s = 0.0;    ///< time with a push on it
  double over_s = 0.0;       ///< time above its injury threshold
};

/// Samples for plots, one per series_period_s.
struct MetricsSeries {
  std::vector<double> t_s;
  std::vector<double> depth_m;
  std::vector<double> duct_force_n;
  std::vector<double> squeeze_n;
  std::array<std::vector<double>, 2> speed_m_per_s;
  int64_t dropped = 0;  ///< samples past the reserved space
};

struct MetricsState {
  double t_s = 0.0;  ///< the last step's time
  double first_t_s = -1.0;
  bool done = false;
  std::array<ToolMotion, 2> tools{};
  std::vector<OrganLoad> organs;
  double max_squeeze_duct_n = 0.0;
  double over_threshold_s = 0.0;  ///< some organ above its threshold (or the duct's squeeze)
  int64_t catheter_drops = 0;
  bool loose = false;
  double max_depth_m = 0.0;
  double depth_m = 0.0;
  size_t phases_seen = 0;
  int64_t injury_events = 0;
  size_t events_seen = 0;
  double next_series_s = 0.0;
  MetricsSeries series;

  static MetricsState create(const MetricsModel& model);
};

/// One step at input.t_s, after the task engine's step on the same input (`task_model` for the
/// laparoscope's view cone).
void step_metrics(const MetricsModel& model, const TaskModel& task_model, const TaskInput& input,
                  const std::array<double, 2>& opening_rad, const TaskState& task,
                  MetricsState* state) noexcept;

/// One figure of the report: snake_case name with its unit as suffix; NaN where it is
/// undefined (a mean over nothing, an economy with no need: JSON null).
struct Metric {
  std::string name;
  double value = 0.0;
};

/// The figures in the contract's order (docs/metrics.md): completion and phase times, per tool
/// motion, handedness, forces on the duct and on each other organ (named by `organ_names`,
/// snake_case), squeeze, drops, grasp attempts, depth, time out of view.
[[nodiscard]] std::vector<Metric> training_metrics(const MetricsModel& model,
                                                   const MetricsState& state, const TaskState& task,
                                                   const std::vector<std::string>& organ_names);

}  // namespace lap::sim
