#pragma once
/// \file
/// What the task has come to at the last modelling step, for whoever shows it while the session
/// runs (the app's heads-up display): the stage the trainee is at, the session's time, the
/// result and its reasons, the newest events, and the forces the injury thresholds watch — each
/// tool's push on the duct and on the other organs, the jaws' squeeze on the duct. The modelling
/// loop fills it after each task step and publishes it in its snapshot (session.h): fixed size,
/// so publishing copies and never allocates.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>

#include "sim/runtime/task_engine.h"
#include "sim/setup/task_model.h"

namespace lap::sim {

/// Where the trainee is in a catheter insertion now (unlike TaskState::phase_s, which records
/// the first time each phase was reached, this goes back when the trainee does).
enum class TaskStage : uint8_t {
  kNone,             ///< no task, or free exploration (no goal)
  kGraspCatheter,    ///< no tool holds the catheter
  kBringToIncision,  ///< held, its tip not at the ductotomy yet
  kEnterIncision,    ///< held, its tip at the ductotomy
  kAdvance,          ///< the tip in the lumen (through the incision), short of the target depth
  kHold,             ///< at the target depth: hold it there
  kDone,             ///< the task ended (TaskProgress::result says how)
};

/// The forces of one tool that the injury thresholds watch, at the last step [N].
struct ToolForces {
  double on_duct_n = 0.0;       ///< its contacts' push on the duct, plus its grasp's pull
  double on_organ_n = 0.0;      ///< its hardest push on any other organ
  int32_t organ = -1;           ///< which organ that is (-1: none)
  double duct_squeeze_n = 0.0;  ///< its jaws' squeeze on the duct they hold
};

struct TaskProgress {
  static constexpr size_t kRecentEvents = 8;

  TaskKind kind = TaskKind::kNone;
  TaskStage stage = TaskStage::kNone;
  double t_s = 0.0;  ///< session time of the step (stops when the task ends)
  TaskResult result = TaskResult::kIncomplete;
  std::array<TaskReason, kTaskReasons> reasons{};
  int32_t reason_count = 0;
  double depth_m = 0.0;     ///< the catheter inside the lumen from its tip back [m]
  double held_for_s = 0.0;  ///< at the target depth since this long [s]
  int64_t event_count = 0;  ///< every event so far (those dropped for lack of room too)
  /// The newest events, oldest first (the last recent_count of them).
  std::array<TaskEvent, kRecentEvents> recent{};
  int32_t recent_count = 0;
  std::array<ToolForces, 2> tools{};
  double catheter_on_duct_n = 0.0;  ///< the catheter's push on the duct
};

/// Fills `out` from the engine's state after a step at `t_s`, with each tool's forces and the
/// catheter's push as the step measured them. Real time: no allocation.
void write_task_progress(const TaskModel& model, const TaskState& state, double t_s,
                         const std::array<ToolForces, 2>& tools, double catheter_on_duct_n,
                         TaskProgress* out) noexcept;

}  // namespace lap::sim
