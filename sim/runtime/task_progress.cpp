#include "sim/runtime/task_progress.h"

#include <algorithm>

namespace lap::sim {
namespace {

TaskStage stage_of(const TaskModel& model, const TaskState& s) {
  if (model.kind != TaskKind::kCatheterInsertion) {
    return s.done() ? TaskStage::kDone : TaskStage::kNone;
  }
  if (s.done()) return TaskStage::kDone;
  if (s.at_depth) return TaskStage::kHold;
  if (s.tip.inside && s.tip.via_incision) return TaskStage::kAdvance;
  if (!s.held) return TaskStage::kGraspCatheter;
  // The tip as the engine last placed it (duct frame) against the incision's "at" distance.
  if (s.tip.known && model.has_incision &&
      (model.pose_DW.inverse() * s.tip.tip_D - model.incision_center_W).norm() <=
          model.at_incision_m) {
    return TaskStage::kEnterIncision;
  }
  return TaskStage::kBringToIncision;
}

}  // namespace

void write_task_progress(const TaskModel& model, const TaskState& state, double t_s,
                         const std::array<ToolForces, 2>& tools, double catheter_on_duct_n,
                         TaskProgress* out) noexcept {
  TaskProgress& p = *out;
  p.kind = model.kind;
  p.stage = stage_of(model, state);
  p.t_s = state.done() ? state.end_s : t_s;
  p.result = state.result;
  p.reasons = state.reasons;
  p.reason_count = static_cast<int32_t>(state.reason_count);
  p.depth_m = state.tip.inside ? state.tip.depth_m : 0.0;
  p.held_for_s = state.at_depth && state.at_depth_since_s >= 0.0
                     ? std::max(0.0, p.t_s - state.at_depth_since_s)
                     : 0.0;
  p.event_count = static_cast<int64_t>(state.events.size()) + state.events_dropped;
  const size_t n = std::min(state.events.size(), TaskProgress::kRecentEvents);
  const size_t first = state.events.size() - n;
  for (size_t k = 0; k < n; ++k) p.recent[k] = state.events[first + k];
  p.recent_count = static_cast<int32_t>(n);
  p.tools = tools;
  p.catheter_on_duct_n = catheter_on_duct_n;
}

}  // namespace lap::sim
