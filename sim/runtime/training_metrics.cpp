#include "sim/runtime/training_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lap::sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Series space for at most an hour: longer sessions keep their first hour of plots (their
/// metrics are whole).
constexpr double kMaxSeriesS = 3600.0;

/// A tool's tip this step: path, smoothed speed and its movements, idle time, jerk.
void step_motion(const MetricsModel& model, const Eigen::Vector3d& tip_W, ToolMotion* t) {
  const double dt = model.dt_s;
  if (!t->seen) {
    t->seen = true;
    t->last_W = tip_W;
    t->waypoint_W = tip_W;
  }
  const double step_m = (tip_W - t->last_W).norm();
  t->path_m += step_m;
  t->last_W = tip_W;
  // First-order smoothing of the speed, exact for a constant input over the step.
  const double a = 1.0 - std::exp(-dt / MetricsModel::kSpeedFilterS);
  t->speed_m_per_s += a * (step_m / dt - t->speed_m_per_s);
  if (!t->moving && t->speed_m_per_s > MetricsModel::kMoveStartMPerS) {
    t->moving = true;
    ++t->movements;
  } else if (t->moving && t->speed_m_per_s < MetricsModel::kMoveStopMPerS) {
    t->moving = false;
  }
  if (t->speed_m_per_s < MetricsModel::kMoveStopMPerS) t->idle_s += dt;
  // Jerk: the third difference of the strided samples.
  if (t->steps++ % MetricsModel::kJerkStrideSteps != 0) return;
  auto& h = t->jerk_history;
  if (t->jerk_filled == 3) {
    const double stride = dt * MetricsModel::kJerkStrideSteps;
    const Eigen::Vector3d d3 = tip_W - 3.0 * h[0] + 3.0 * h[1] - h[2];
    t->jerk_sum += d3.norm() / (stride * stride * stride);
    ++t->jerk_samples;
  }
  h[2] = h[1];
  h[1] = h[0];
  h[0] = tip_W;
  t->jerk_filled = std::min(t->jerk_filled + 1, 3);
}

/// The jaws closing past the grasp threshold after opening past the release one.
void step_jaws(const MetricsModel& model, double opening_rad, ToolMotion* t) {
  if (!std::isfinite(opening_rad)) return;
  if (opening_rad > model.release_above_rad) {
    t->jaws_open = true;
  } else if (t->jaws_open && opening_rad < model.grasp_below_rad) {
    t->jaws_open = false;
    ++t->grasp_attempts;
  }
}

/// Each organ's push: its peak, its mean while touched, its time above the threshold.
void step_loads(const MetricsModel& model, const TaskInput& in, MetricsState* s) {
  const double dt = model.dt_s;
  bool over = false;
  const size_t n = std::min(in.organ_force_n.size(), s->organs.size());
  for (size_t o = 0; o < n; ++o) {
    const double f = in.organ_force_n[o];
    if (!std::isfinite(f)) continue;
    OrganLoad& load = s->organs[o];
    load.max_n = std::max(load.max_n, f);
    if (f > 0.0) {
      load.impulse_n_s += f * dt;
      load.contact_s += dt;
    }
    const bool duct = static_cast<int32_t>(o) == model.duct_organ;
    const double limit = duct ? model.duct_injury_force_n : model.organ_injury_force_n;
    const bool over_here = limit > 0.0 && f > limit;
    if (over_here) load.over_s += dt;
    over = over || over_here;
  }
  if (model.duct_organ >= 0 && std::isfinite(in.duct_squeeze_n)) {
    s->max_squeeze_duct_n = std::max(s->max_squeeze_duct_n, in.duct_squeeze_n);
    over = over || (model.duct_squeeze_n > 0.0 && in.duct_squeeze_n > model.duct_squeeze_n);
  }
  if (over) s->over_threshold_s += dt;
}

/// What the task engine found this step: drops, injuries, new phases (the tips' waypoints).
void step_task_figures(const TaskInput& in, const TaskState& task, MetricsState* s) {
  const bool loose = task.loose_since_s >= 0.0;
  if (loose && !s->loose) ++s->catheter_drops;
  s->loose = loose;
  s->depth_m = task.tip.known ? task.tip.depth_m : 0.0;
  s->max_depth_m = std::max(s->max_depth_m, s->depth_m);
  for (; s->events_seen < task.events.size(); ++s->events_seen) {
    const TaskEventKind k = task.events[s->events_seen].kind;
    if (k == TaskEventKind::kDuctInjury || k == TaskEventKind::kOrganInjury) ++s->injury_events;
  }
  size_t reached = 0;
  for (const double p : task.phase_s) reached += p >= 0.0 ? 1 : 0;
  if (reached == s->phases_seen && !task.done()) return;
  s->phases_seen = reached;
  for (size_t i = 0; i < 2; ++i) {
    ToolMotion& t = s->tools[i];
    if (!t.seen || !in.tool_valid[i]) continue;
    t.need_m += (t.last_W - t.waypoint_W).norm();
    t.waypoint_W = t.last_W;
  }
}

void step_series(const MetricsModel& model, const TaskInput& in, MetricsState* s) {
  if (in.t_s + 1e-9 < s->next_series_s) return;
  s->next_series_s += model.series_period_s;
  MetricsSeries& x = s->series;
  if (x.t_s.size() >= model.series_capacity) {
    ++x.dropped;
    return;
  }
  x.t_s.push_back(in.t_s);  // within the capacity reserved: no allocation
  x.depth_m.push_back(s->depth_m);
  const auto duct = static_cast<size_t>(model.duct_organ);
  x.duct_force_n.push_back(
      model.duct_organ >= 0 && duct < in.organ_force_n.size() ? in.organ_force_n[duct] : 0.0);
  x.squeeze_n.push_back(in.duct_squeeze_n);
  for (size_t i = 0; i < 2; ++i) x.speed_m_per_s[i].push_back(s->tools[i].speed_m_per_s);
}

double ratio(double num, double den) { return den > 1e-3 ? num / den : kNaN; }
double mean_or_nan(double sum, double count) { return count > 0.0 ? sum / count : kNaN; }

}  // namespace

MetricsModel MetricsModel::build(const TaskModel& task, double grasp_below_rad,
                                 double release_above_rad, double dt_s, double duration_s,
                                 int32_t dominant_tool) {
  MetricsModel m;
  m.dt_s = dt_s;
  m.organ_count = task.organ_count;
  m.duct_organ = task.duct_organ;
  m.duct_injury_force_n = task.spec.duct_injury_force_n;
  m.duct_squeeze_n = task.spec.duct_squeeze_n;
  m.organ_injury_force_n = task.spec.organ_injury_force_n;
  m.grasp_below_rad = grasp_below_rad;
  m.release_above_rad = release_above_rad;
  m.dominant_tool = dominant_tool == 0 ? 0 : 1;
  const double span_s = std::clamp(duration_s, 0.0, kMaxSeriesS);
  m.series_capacity = static_cast<size_t>(std::ceil(span_s / m.series_period_s)) + 2;
  return m;
}

MetricsState MetricsState::create(const MetricsModel& model) {
  MetricsState s;
  s.organs.assign(static_cast<size_t>(std::max(model.organ_count, 0)), OrganLoad{});
  MetricsSeries& x = s.series;
  for (std::vector<double>* v : {&x.t_s, &x.depth_m, &x.duct_force_n, &x.squeeze_n,
                                 &x.speed_m_per_s[0], &x.speed_m_per_s[1]}) {
    // Reserved and touched now: the modelling loop then neither allocates nor page-faults as
    // the series grow (an hour's are 1.7 MB).
    v->assign(model.series_capacity, 0.0);
    v->clear();
  }
  return s;
}

void step_metrics(const MetricsModel& model, const TaskModel& task_model, const TaskInput& in,
                  const std::array<double, 2>& opening_rad, const TaskState& task,
                  MetricsState* s) noexcept {
  if (s->done) return;
  if (s->first_t_s < 0.0) s->first_t_s = in.t_s;
  s->t_s = in.t_s;
  for (size_t i = 0; i < 2; ++i) {
    if (!in.tool_valid[i] || !in.tool_tip_W[i].allFinite()) continue;
    ToolMotion& t = s->tools[i];
    step_motion(model, in.tool_tip_W[i], &t);
    step_jaws(model, opening_rad[i], &t);
    if (!task_model.in_view(in.tool_tip_W[i])) t.out_of_view_s += model.dt_s;
  }
  step_loads(model, in, s);
  step_task_figures(in, task, s);
  step_series(model, in, s);
  s->done = task.done();
}

std::vector<Metric> training_metrics(const MetricsModel& model, const MetricsState& s,
                                     const TaskState& task,
                                     const std::vector<std::string>& organ_names) {
  std::vector<Metric> out;
  const auto put = [&](std::string name, double value) { out.push_back({std::move(name), value}); };
  // Completed: succeeded (a failure ends the task without completing it).
  put("completion_time_s", task.result == TaskResult::kSuccess ? task.end_s : kNaN);
  put("session_time_s", s.first_t_s >= 0.0 ? s.t_s - s.first_t_s + model.dt_s : 0.0);
  const char* const phases[] = {"catheter_grasped", "tip_at_incision", "tip_in_lumen",
                                "target_depth_reached", "held"};
  for (size_t p = 0; p < task.phase_s.size(); ++p) {
    put(std::string("phase_") + phases[p] + "_s", task.phase_s[p] >= 0.0 ? task.phase_s[p] : kNaN);
  }
  const char* const sides[] = {"left", "right"};
  for (size_t i = 0; i < 2; ++i) {
    const ToolMotion& t = s.tools[i];
    const std::string side = sides[i];
    // The need closes at the tip's last position (the end is the last waypoint).
    const double need = t.need_m + (t.last_W - t.waypoint_W).norm();
    put("path_length_" + side + "_m", t.path_m);
    put("movements_" + side, static_cast<double>(t.movements));
    put("economy_of_motion_" + side, ratio(t.path_m, need));
    put("mean_jerk_" + side + "_m_per_s3",
        mean_or_nan(t.jerk_sum, static_cast<double>(t.jerk_samples)));
    put("idle_time_" + side + "_s", t.idle_s);
    put("grasp_attempts_" + side, static_cast<double>(t.grasp_attempts));
    put("out_of_view_" + side + "_s", t.out_of_view_s);
  }
  const auto dominant = static_cast<size_t>(model.dominant_tool);
  put("path_length_dominant_m", s.tools[dominant].path_m);
  put("path_length_non_dominant_m", s.tools[1 - dominant].path_m);
  put("path_ratio_non_dominant", ratio(s.tools[1 - dominant].path_m, s.tools[dominant].path_m));
  for (size_t o = 0; o < s.organs.size(); ++o) {
    const OrganLoad& load = s.organs[o];
    const bool duct = static_cast<int32_t>(o) == model.duct_organ;
    std::string name = duct ? "duct" : snake_case(o < organ_names.size() ? organ_names[o] : "");
    if (!duct && (name.empty() || name == "duct")) name = "organ_" + std::to_string(o);
    const std::vector<std::string> names = organ_metric_names(name);
    put(names[0], load.max_n);
    put(names[1], mean_or_nan(load.impulse_n_s, load.contact_s));
    put(names[2], load.contact_s);
    put(names[3], load.over_s);
  }
  put("time_over_threshold_s", s.over_threshold_s);
  put("injury_events", static_cast<double>(s.injury_events));
  put("max_squeeze_duct_n", s.max_squeeze_duct_n);
  put("catheter_drops", static_cast<double>(s.catheter_drops));
  put("grasp_attempts", static_cast<double>(s.tools[0].grasp_attempts + s.tools[1].grasp_attempts));
  put("max_insertion_depth_m", s.max_depth_m);
  put("final_insertion_depth_m", s.depth_m);
  put("time_out_of_view_s", s.tools[0].out_of_view_s + s.tools[1].out_of_view_s);
  return out;
}

}  // namespace lap::sim
