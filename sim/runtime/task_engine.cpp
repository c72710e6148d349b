#include "sim/runtime/task_engine.h"

#include <algorithm>
#include <cmath>

namespace lap::sim {
namespace {

// Session times are tick counts times the period, so a span meant to be exactly a limit can
// come out a rounding short of it: a nanosecond, far below a tick, absorbs that.
constexpr double kTimeEpsilonS = 1e-9;

// How far inside the lumen (rest geometry, duct frame) a point is: positive inside, the nearest
// of the wall's mid-surface and the two open ends.
double inside_margin(const TaskModel& m, const Eigen::Vector3d& p_D) {
  return std::min({m.lumen_radius_m - p_D.head<2>().norm(), p_D.z(), m.duct_length_m - p_D.z()});
}

// Where the segment a → b (one inside, one outside) crosses the lumen's boundary: bisection on
// inside_margin, which is continuous (30 halvings: below a nanometre on a millimetre step).
// Returns the fraction from a.
double crossing_fraction(const TaskModel& m, const Eigen::Vector3d& a_D,
                         const Eigen::Vector3d& b_D) {
  const bool a_inside = inside_margin(m, a_D) > 0.0;
  double lo = 0.0;
  double hi = 1.0;
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (lo + hi);
    const bool mid_inside = inside_margin(m, a_D + mid * (b_D - a_D)) > 0.0;
    (mid_inside == a_inside ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// At a point on the lumen's boundary: whether it is on the wall (not an open end).
bool on_wall(const TaskModel& m, const Eigen::Vector3d& q_D) {
  const double wall = std::abs(m.lumen_radius_m - q_D.head<2>().norm());
  return wall <= std::min(std::abs(q_D.z()), std::abs(m.duct_length_m - q_D.z()));
}

// Whether a point on the wall lies in the incision (its ellipse with the margin).
bool in_incision(const TaskModel& m, const Eigen::Vector3d& q_D) {
  if (!m.has_incision) return false;
  const double along = (q_D.z() - m.incision_z_m) / m.incision_half_length_m;
  const double turn = std::remainder(std::atan2(q_D.y(), q_D.x()) - m.incision_angle_rad, 2 * M_PI);
  const double around = m.lumen_radius_m * turn / m.incision_half_width_m;
  return along * along + around * around <= 1.0;
}

// The engine's step in its parts, each emitting into the state.
class Stepper {
 public:
  Stepper(const TaskModel& m, const TaskInput& in, TaskState* s) : m_(m), in_(in), s_(*s) {}

  void emit(TaskEventKind kind, int32_t tool = -1, int32_t organ = -1, double value = 0.0,
            double duration_s = 0.0, bool squeeze = false) {
    if (s_.events.size() < s_.events.capacity()) {
      s_.events.push_back({in_.t_s, kind, tool, organ, value, duration_s, squeeze});
    } else {
      ++s_.events_dropped;
    }
  }

  void fail(TaskReason reason, TaskEventKind kind, int32_t tool = -1, int32_t organ = -1,
            double value = 0.0, double duration_s = 0.0, bool squeeze = false) {
    emit(kind, tool, organ, value, duration_s, squeeze);
    if (!s_.has_reason(reason) && s_.reason_count < s_.reasons.size()) {
      s_.reasons[s_.reason_count++] = reason;
    }
    s_.failing = true;
  }

  void first(size_t phase) {
    if (s_.phase_s[phase] < 0.0) s_.phase_s[phase] = in_.t_s;
  }

  // Each tool taking hold of the catheter or letting go; dropped when nobody has held it, its
  // tip out of the lumen, for drop_grace_s.
  void grasps(const std::array<bool, 2>& before) {
    for (int32_t i = 0; i < 2; ++i) {
      const bool now = in_.catheter_held[static_cast<size_t>(i)];
      if (now && !before[static_cast<size_t>(i)]) {
        emit(TaskEventKind::kCatheterGrasped, i);
        first(0);
        s_.ever_grasped = true;
      } else if (!now && before[static_cast<size_t>(i)]) {
        emit(TaskEventKind::kCatheterReleased, i);
      }
    }
    s_.held = in_.catheter_held[0] || in_.catheter_held[1];
  }

  void dropped() {
    const bool loose = s_.ever_grasped && !s_.held && !s_.tip.inside;
    if (!loose) {
      s_.loose_since_s = -1.0;
      return;
    }
    if (s_.loose_since_s < 0.0) s_.loose_since_s = in_.t_s;
    const double loose_s = in_.t_s - s_.loose_since_s;
    if (loose_s >= m_.spec.drop_grace_s - kTimeEpsilonS) {
      fail(TaskReason::kCatheterDropped, TaskEventKind::kCatheterDropped, -1, -1, 0.0, loose_s);
    }
  }

  // The tip: crossing the lumen's boundary (through the incision, an open end or the wall),
  // near the incision, and the depth it has reached.
  void tip() {
    if (in_.catheter.empty() || m_.duct_organ < 0) return;
    const Eigen::Vector3d& tip_W = in_.catheter.back();
    const Eigen::Vector3d p = m_.pose_DW * tip_W;
    const bool inside = inside_margin(m_, p) > 0.0;
    TipState& tip = s_.tip;
    if (!tip.known) {
      tip.known = true;  // a tip that starts inside did not come in by the incision
    } else if (inside != tip.inside) {
      cross(tip.tip_D, p, inside);
    }
    tip.inside = inside;
    tip.tip_D = p;
    if (!inside) tip.via_incision = false;
    tip.depth_m = inside ? lumen_depth_m(m_, in_.catheter) : 0.0;
    if (s_.phase_s[1] < 0.0 && s_.ever_grasped &&
        (tip_W - m_.incision_center_W).norm() <= m_.at_incision_m) {
      at_incision();
    }
    depth();
  }

  void cross(const Eigen::Vector3d& before_D, const Eigen::Vector3d& now_D, bool inside) {
    const Eigen::Vector3d q =
        before_D + crossing_fraction(m_, before_D, now_D) * (now_D - before_D);
    const bool wall = on_wall(m_, q);
    const bool incision = wall && in_incision(m_, q);
    if (wall && !incision) {
      fail(TaskReason::kWallPerforation, TaskEventKind::kWallPerforation);
      return;
    }
    if (inside) {
      if (incision) {
        if (s_.phase_s[1] < 0.0) at_incision();
        emit(TaskEventKind::kTipInLumen);
        first(2);
        s_.tip.via_incision = true;
      } else {
        emit(TaskEventKind::kTipEnteredOpenEnd);
      }
    } else {
      if (s_.at_depth) lose_depth();
      emit(TaskEventKind::kTipLeftLumen);
    }
  }

  void at_incision() {
    emit(TaskEventKind::kTipAtIncision);
    first(1);
  }

  void lose_depth() {
    s_.at_depth = false;
    s_.at_depth_since_s = -1.0;
    emit(TaskEventKind::kTargetDepthLost, -1, -1, s_.tip.depth_m);
  }

  void depth() {
    const TipState& tip = s_.tip;
    const double target = m_.spec.insertion_depth_m;
    if (!s_.at_depth && tip.via_incision && tip.depth_m >= target) {
      s_.at_depth = true;
      s_.at_depth_since_s = in_.t_s;
      emit(TaskEventKind::kTargetDepthReached, -1, -1, tip.depth_m);
      first(3);
    } else if (s_.at_depth &&
               (!tip.via_incision || tip.depth_m < target - TaskState::kDepthHysteresisM)) {
      lose_depth();
    }
  }

  // A threshold exceeded for `limit_s` or longer: true (with the timer's start and peak).
  bool over(OverTimer& timer, double value, double threshold, double limit_s) const {
    if (!(value > threshold)) {
      timer = OverTimer{};
      return false;
    }
    if (timer.since_s < 0.0) timer.since_s = in_.t_s;
    timer.peak = std::max(timer.peak, value);
    return in_.t_s - timer.since_s >= limit_s - kTimeEpsilonS;
  }

  void injuries() {
    const TaskSpec& spec = m_.spec;
    const size_t n = std::min(in_.organ_force_n.size(), s_.organ_force.size());
    for (size_t i = 0; i < n; ++i) {
      const auto organ = static_cast<int32_t>(i);
      OverTimer& timer = s_.organ_force[i];
      const double f = in_.organ_force_n[i];
      if (organ == m_.duct_organ) {
        if (over(timer, f, spec.duct_injury_force_n, spec.duct_injury_time_s)) {
          fail(TaskReason::kDuctInjury, TaskEventKind::kDuctInjury, -1, organ, timer.peak,
               in_.t_s - timer.since_s);
        }
      } else if (over(timer, f, spec.organ_injury_force_n, spec.organ_injury_time_s)) {
        fail(TaskReason::kOrganInjury, TaskEventKind::kOrganInjury, -1, organ, timer.peak,
             in_.t_s - timer.since_s);
      }
    }
    OverTimer& sq = s_.duct_squeeze;
    if (m_.duct_organ >= 0 &&
        over(sq, in_.duct_squeeze_n, spec.duct_squeeze_n, spec.duct_injury_time_s)) {
      fail(TaskReason::kDuctInjury, TaskEventKind::kDuctInjury, -1, m_.duct_organ, sq.peak,
           in_.t_s - sq.since_s, true);
    }
  }

  void view() {
    for (int32_t i = 0; i < 2; ++i) {
      const auto k = static_cast<size_t>(i);
      OverTimer& timer = s_.out_of_view[k];
      if (!in_.tool_valid[k]) continue;
      const Eigen::Vector3d v = in_.tool_tip_W[k] - m_.camera_W;
      const bool seen = v.dot(m_.view_dir_W) >= m_.cos_half_view * v.norm();
      if (over(timer, seen ? 0.0 : 1.0, 0.5, m_.spec.out_of_view_grace_s)) {
        fail(TaskReason::kOutOfView, TaskEventKind::kOutOfView, i, -1, 0.0,
             in_.t_s - timer.since_s);
      }
    }
  }

  void forbidden() {
    const size_t n = std::min(in_.organ_touched.size(), m_.forbidden.size());
    for (size_t i = 0; i < n; ++i) {
      if (m_.forbidden[i] != 0 && in_.organ_touched[i] != 0) {
        fail(TaskReason::kForbiddenContact, TaskEventKind::kForbiddenContact, -1,
             static_cast<int32_t>(i));
      }
    }
  }

  void common_bile_duct() {
    if (in_.tip_in_common_bile_duct) {
      fail(TaskReason::kCommonBileDuct, TaskEventKind::kTipInCommonBileDuct, -1, m_.cbd_organ);
    }
  }

  void end(TaskResult result, TaskEventKind kind) {
    emit(kind);
    s_.result = result;
    s_.end_s = in_.t_s;
  }

 private:
  const TaskModel& m_;
  const TaskInput& in_;
  TaskState& s_;
};

}  // namespace

std::string_view to_string(TaskResult result) {
  switch (result) {
    case TaskResult::kIncomplete:
      return "incomplete";
    case TaskResult::kSuccess:
      return "success";
    case TaskResult::kFailure:
      return "failure";
  }
  return "unknown";
}

std::string_view to_string(TaskReason reason) {
  switch (reason) {
    case TaskReason::kCatheterDropped:
      return "catheter_dropped";
    case TaskReason::kDuctInjury:
      return "duct_injury";
    case TaskReason::kOrganInjury:
      return "organ_injury";
    case TaskReason::kWallPerforation:
      return "wall_perforation";
    case TaskReason::kTimeLimit:
      return "time_limit";
    case TaskReason::kOutOfView:
      return "out_of_view";
    case TaskReason::kForbiddenContact:
      return "forbidden_contact";
    case TaskReason::kCommonBileDuct:
      return "common_bile_duct";
  }
  return "unknown";
}

std::string_view to_string(TaskEventKind kind) {
  switch (kind) {
    case TaskEventKind::kCatheterGrasped:
      return "catheter_grasped";
    case TaskEventKind::kCatheterReleased:
      return "catheter_released";
    case TaskEventKind::kTipAtIncision:
      return "tip_at_incision";
    case TaskEventKind::kTipInLumen:
      return "tip_in_lumen";
    case TaskEventKind::kTipEnteredOpenEnd:
      return "tip_entered_open_end";
    case TaskEventKind::kTipLeftLumen:
      return "tip_left_lumen";
    case TaskEventKind::kTargetDepthReached:
      return "target_depth_reached";
    case TaskEventKind::kTargetDepthLost:
      return "target_depth_lost";
    case TaskEventKind::kSuccess:
      return "success";
    case TaskEventKind::kCatheterDropped:
      return "catheter_dropped";
    case TaskEventKind::kDuctInjury:
      return "duct_injury";
    case TaskEventKind::kOrganInjury:
      return "organ_injury";
    case TaskEventKind::kWallPerforation:
      return "wall_perforation";
    case TaskEventKind::kTimeLimit:
      return "time_limit";
    case TaskEventKind::kOutOfView:
      return "out_of_view";
    case TaskEventKind::kForbiddenContact:
      return "forbidden_contact";
    case TaskEventKind::kTipInCommonBileDuct:
      return "tip_in_common_bile_duct";
    case TaskEventKind::kFailure:
      return "failure";
  }
  return "unknown";
}

TaskState TaskState::create(const TaskModel& model, size_t event_capacity) {
  TaskState s;
  s.events.reserve(event_capacity);
  s.organ_force.assign(static_cast<size_t>(std::max<int32_t>(model.organ_count, 0)), OverTimer{});
  return s;
}

bool TaskState::has_reason(TaskReason r) const {
  return std::find(reasons.begin(), reasons.begin() + static_cast<std::ptrdiff_t>(reason_count),
                   r) != reasons.begin() + static_cast<std::ptrdiff_t>(reason_count);
}

double lumen_depth_m(const TaskModel& model, std::span<const Eigen::Vector3d> catheter) noexcept {
  if (catheter.empty() || model.duct_organ < 0) return 0.0;
  Eigen::Vector3d inner = model.pose_DW * catheter.back();
  if (inside_margin(model, inner) <= 0.0) return 0.0;
  double depth = 0.0;
  for (size_t i = catheter.size() - 1; i > 0; --i) {
    const Eigen::Vector3d outer = model.pose_DW * catheter[i - 1];
    const double segment = (outer - inner).norm();
    if (inside_margin(model, outer) <= 0.0) {
      return depth + crossing_fraction(model, inner, outer) * segment;
    }
    depth += segment;
    inner = outer;
  }
  return depth;
}

void step_task(const TaskModel& model, const TaskInput& input, TaskState* state) noexcept {
  if (model.kind == TaskKind::kNone || state->done()) return;
  TaskState& s = *state;
  s.failing = false;
  Stepper step(model, input, state);
  const std::array<bool, 2> held_before = s.held_by;
  s.held_by = input.catheter_held;
  if (model.kind == TaskKind::kCatheterInsertion) {
    step.grasps(held_before);
    step.tip();
    step.dropped();
    step.common_bile_duct();
  }
  step.injuries();
  step.view();
  step.forbidden();
  if (model.kind == TaskKind::kCatheterInsertion &&
      input.t_s >= model.spec.time_limit_s - kTimeEpsilonS) {
    step.fail(TaskReason::kTimeLimit, TaskEventKind::kTimeLimit);
  }
  if (s.failing) {
    step.end(TaskResult::kFailure, TaskEventKind::kFailure);
  } else if (s.at_depth && input.t_s - s.at_depth_since_s >= model.spec.hold_s - kTimeEpsilonS) {
    s.phase_s[4] = input.t_s;
    step.end(TaskResult::kSuccess, TaskEventKind::kSuccess);
  }
}

}  // namespace lap::sim
