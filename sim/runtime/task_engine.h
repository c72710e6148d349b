#pragma once
/// \file
/// The task engine (thesis §7.4): stepped in the modelling loop on what that loop already has,
/// it follows the catheter insertion through its phases and watches for errors, emitting
/// timestamped events and, at the end, a result with its reasons.
///
/// Phases (catheter-insertion), each an event when reached:
///   catheter_grasped → tip_at_incision → tip_in_lumen (entered through the incision) →
///   target_depth_reached (the catheter inside the lumen from its tip back to where it enters,
///   at least insertion_depth_m) → held there hold_s: `success`.
/// Going back is allowed and told (catheter_released, tip_left_lumen, target_depth_lost); the
/// hold starts again at the next target_depth_reached.
/// Errors, each ending the task as `failure` with its reason (reasons() vocabulary, to_string):
///   catheter_dropped  no tool holds the catheter, once grasped, its tip not in the lumen, for
///                     drop_grace_s;
///   duct_injury       a tool, its grasp or the catheter pushes the duct harder than
///                     duct_injury_force_n, or the jaws squeeze it harder than duct_squeeze_n,
///                     for longer than duct_injury_time_s;
///   organ_injury      the same on another organ (organ_injury_force_n, organ_injury_time_s);
///   wall_perforation  the tip enters the lumen through the wall outside the incision, or leaves
///                     it through the wall;
///   common_bile_duct  the tip inside the common bile duct (the scenario's organ named by
///                     task.common_bile_duct: the catheter is for the cystic duct alone);
///   time_limit        time_limit_s passed (catheter-insertion only);
///   out_of_view       an instrument's tip outside the laparoscope's view cone for longer than
///                     out_of_view_grace_s;
///   forbidden_contact a tool touches an organ in forbidden_organs.
/// Errors in the same step as the success win: the task fails.
///
/// The step allocates nothing (events go into space reserved by create(); more than that are
/// counted, not kept), never throws, and is a function of its inputs: equal inputs give equal
/// events, so a --fast run and its replay score the same.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "sim/setup/task_model.h"

namespace lap::sim {

enum class TaskResult : uint8_t { kIncomplete, kSuccess, kFailure };
/// "incomplete", "success", "failure".
[[nodiscard]] std::string_view to_string(TaskResult result);

/// Why a task failed (the JSON's "reasons").
enum class TaskReason : uint8_t {
  kCatheterDropped,
  kDuctInjury,
  kOrganInjury,
  kWallPerforation,
  kTimeLimit,
  kOutOfView,
  kForbiddenContact,
  kCommonBileDuct,
};
inline constexpr size_t kTaskReasons = 8;
/// "catheter_dropped", "duct_injury", "organ_injury", "wall_perforation", "time_limit",
/// "out_of_view", "forbidden_contact", "common_bile_duct".
[[nodiscard]] std::string_view to_string(TaskReason reason);

enum class TaskEventKind : uint8_t {
  kCatheterGrasped,     ///< a tool took hold of the catheter (tool)
  kCatheterReleased,    ///< no tool holds it any more
  kTipAtIncision,       ///< the tip came within at_incision_m of the incision (first time)
  kTipInLumen,          ///< the tip entered the lumen through the incision
  kTipEnteredOpenEnd,   ///< the tip entered the lumen by one of the duct's open ends (no phase)
  kTipLeftLumen,        ///< the tip came out, by the incision or an open end
  kTargetDepthReached,  ///< depth_m at least insertion_depth_m
  kTargetDepthLost,     ///< depth_m back below it (by more than kDepthHysteresisM)
  kSuccess,             ///< held at depth hold_s
  kCatheterDropped,
  kDuctInjury,  ///< value: peak force or squeeze [N]; duration_s: over the threshold; squeeze
  kOrganInjury,
  kWallPerforation,
  kTimeLimit,
  kOutOfView,  ///< tool; duration_s
  kForbiddenContact,
  kTipInCommonBileDuct,
  kFailure,  ///< the task ended in failure (its reasons are the error events before it)
};
/// snake_case names: "catheter_grasped", …, "failure".
[[nodiscard]] std::string_view to_string(TaskEventKind kind);

struct TaskEvent {
  double t_s = 0.0;
  TaskEventKind kind = TaskEventKind::kCatheterGrasped;
  int32_t tool = -1;        ///< 0 left, 1 right, -1 none
  int32_t organ = -1;       ///< -1 none
  double value = 0.0;       ///< depth [m] for the lumen's events, force [N] for injuries
  double duration_s = 0.0;  ///< for injuries and out_of_view: how long it lasted
  bool squeeze = false;     ///< duct_injury by the jaws' squeeze (value: the squeeze)
};

/// What the modelling loop hands the engine each step (spans into storage sized at set-up).
struct TaskInput {
  double t_s = 0.0;                           ///< session time at this step
  std::span<const Eigen::Vector3d> catheter;  ///< particle positions [m]; the last is the tip
  std::array<bool, 2> catheter_held{};        ///< per tool
  std::array<bool, 2> tool_valid{};           ///< its pose is known (after the first haptic tick)
  std::array<Eigen::Vector3d, 2> tool_tip_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  /// Per organ: the hardest push on it by one tool (its contacts' sum, its grasp's pull) or by
  /// the catheter (its contacts' sum) [N].
  std::span<const double> organ_force_n;
  std::span<const uint8_t> organ_touched;  ///< per organ: 1 where a tool touches it
  double duct_squeeze_n = 0.0;             ///< the harder of the two jaws' squeeze on the duct
  bool tip_in_common_bile_duct = false;    ///< the tip inside that organ (at rest)
};

/// The catheter's tip and depth as the engine measured them at the last step.
struct TipState {
  bool known = false;
  bool inside = false;        ///< in the lumen (rest geometry)
  bool via_incision = false;  ///< inside, having entered through the incision
  double depth_m = 0.0;       ///< catheter inside the lumen from the tip back [m]
  Eigen::Vector3d tip_D = Eigen::Vector3d::Zero();
};

/// A threshold watched over time: since when it has been exceeded, and how hard.
struct OverTimer {
  double since_s = -1.0;  ///< < 0: not exceeded now
  double peak = 0.0;
};

/// The engine's state for one session (the modelling thread's own).
struct TaskState {
  static constexpr size_t kDefaultEventCapacity = 1024;
  static constexpr double kDepthHysteresisM = 0.0005;  ///< depth lost only this far below

  TaskResult result = TaskResult::kIncomplete;
  double end_s = -1.0;            ///< when it ended (success or failure); < 0: not yet
  std::vector<TaskEvent> events;  ///< capacity reserved by create(); never grows in step
  int64_t events_dropped = 0;
  std::array<TaskReason, kTaskReasons> reasons{};  ///< in the order found
  size_t reason_count = 0;
  /// First time each phase was reached: grasped, at incision, in lumen, at depth, held; < 0 not.
  std::array<double, 5> phase_s{-1.0, -1.0, -1.0, -1.0, -1.0};

  // Running state.
  std::array<bool, 2> held_by{};  ///< each tool holds the catheter
  bool held = false;              ///< some tool holds it
  bool ever_grasped = false;
  double loose_since_s = -1.0;  ///< held by no tool, its tip out of the lumen, since; < 0 not
  bool at_depth = false;
  double at_depth_since_s = -1.0;
  TipState tip;
  OverTimer duct_force;
  OverTimer duct_squeeze;
  std::vector<OverTimer> organ_force;  ///< per organ
  std::array<OverTimer, 2> out_of_view{};
  bool failing = false;  ///< an error this step (the step ends the task)

  /// State for `model`, event space for `event_capacity` events.
  static TaskState create(const TaskModel& model, size_t event_capacity = kDefaultEventCapacity);
  [[nodiscard]] bool done() const { return result != TaskResult::kIncomplete; }
  [[nodiscard]] bool has_reason(TaskReason r) const;
};

/// One step of the engine at input.t_s. Does nothing once the task has ended, nor for a scenario
/// without a task.
void step_task(const TaskModel& model, const TaskInput& input, TaskState* state) noexcept;

/// The catheter inside the lumen, from its tip back to where it enters it [m]; 0 when the tip
/// is outside. Exposed for tests.
[[nodiscard]] double lumen_depth_m(const TaskModel& model,
                                   std::span<const Eigen::Vector3d> catheter) noexcept;

}  // namespace lap::sim
