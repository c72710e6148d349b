#include "sim/runtime/laparoscope.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace lap::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

// `v` made perpendicular to unit `n` and normalised; `fallback` (also made perpendicular) when
// v is (nearly) parallel to n.
Eigen::Vector3d perpendicular(const Eigen::Vector3d& v, const Eigen::Vector3d& n,
                              const Eigen::Vector3d& fallback) {
  Eigen::Vector3d p = v - v.dot(n) * n;
  if (p.norm() > 1e-9) return p.normalized();
  p = fallback - fallback.dot(n) * n;
  if (p.norm() > 1e-9) return p.normalized();
  return n.unitOrthogonal();
}

// Keeps the axis within `max_rad` of `home_axis`: beyond it, on the cone's edge nearest to it.
Eigen::Vector3d within_cone(const Eigen::Vector3d& axis, const Eigen::Vector3d& home_axis,
                            double max_rad) {
  const double c = std::clamp(axis.dot(home_axis), -1.0, 1.0);
  if (std::acos(c) <= max_rad) return axis;
  const Eigen::Vector3d side = perpendicular(axis, home_axis, Eigen::Vector3d::UnitX());
  return (std::cos(max_rad) * home_axis + std::sin(max_rad) * side).normalized();
}

// One aiming step without the pivot limit (the model's build has no home yet).
double aim_step(const LaparoscopeModel& model, LaparoscopeState* state,
                const Eigen::Vector3d& target_W, double fraction) {
  const LaparoscopeView view = laparoscope_view(model, *state);
  const Eigen::Vector3d to = target_W - view.eye_W;
  if (!(to.norm() > 1e-9)) return 0.0;
  const Eigen::Vector3d w = to.normalized();
  const double angle = std::acos(std::clamp(view.view_dir_W.dot(w), -1.0, 1.0));
  if (angle < 1e-12) return 0.0;
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(view.view_dir_W, w);
  const Eigen::Quaterniond part =
      Eigen::Quaterniond::Identity().slerp(std::clamp(fraction, 0.0, 1.0), q);
  state->axis_W = (part * state->axis_W).normalized();
  return angle;
}

}  // namespace

Eigen::Vector3d laparoscope_reference_up(const LaparoscopeModel& model,
                                         const Eigen::Vector3d& axis_W) {
  return perpendicular(model.horizon_up_W, axis_W, Eigen::Vector3d::UnitZ());
}

LaparoscopeView laparoscope_view(const LaparoscopeModel& model, const LaparoscopeState& state) {
  const Eigen::Vector3d a = state.axis_W.normalized();
  const Eigen::Vector3d r0 = laparoscope_reference_up(model, a);
  const Eigen::Vector3d s0 = a.cross(r0);
  const Eigen::Vector3d optic = std::cos(state.roll_rad) * r0 + std::sin(state.roll_rad) * s0;
  const double theta = model.optic_angle_rad;
  LaparoscopeView v;
  v.eye_W = model.port_W + state.insertion_m * a;
  v.view_dir_W = (std::cos(theta) * a + std::sin(theta) * optic).normalized();
  // The camera head holds the horizon: the world's up seen along the line of sight (the
  // optic's own up when looking straight along it), then turned by the head.
  const Eigen::Vector3d level = perpendicular(model.horizon_up_W, v.view_dir_W, optic);
  v.up_W = Eigen::AngleAxisd(state.horizon_rad, v.view_dir_W) * level;
  v.focal_point_W = v.eye_W + model.focal_distance_m * v.view_dir_W;
  v.light_W = v.eye_W;
  v.view_angle_deg = state.view_angle_deg;
  return v;
}

Result<LaparoscopeModel> LaparoscopeModel::build(const CameraSpec& camera,
                                                 const std::string& file) {
  auto problem = [&](const std::string& field, const std::string& what) {
    return Diagnostic{file, camera.line, field, what};
  };
  LaparoscopeModel m;
  m.port_W = camera.port();
  m.optic_angle_rad = camera.optics_deg * kDegToRad;
  m.horizon_up_W =
      camera.view_up.norm() > 0.0 ? camera.view_up.normalized() : Eigen::Vector3d::UnitY();
  m.min_view_angle_deg = std::min(m.min_view_angle_deg, camera.view_angle_deg);
  m.max_view_angle_deg = std::max(m.max_view_angle_deg, camera.view_angle_deg);
  LaparoscopeState s;
  s.view_angle_deg = camera.view_angle_deg;
  const Eigen::Vector3d inside = camera.position_m - m.port_W;
  s.insertion_m = inside.norm();
  if (!(s.insertion_m > 0.0)) {
    return problem("camera.port_m", "expected the port apart from position_m");
  }
  const double reach = (camera.focal_point_m - m.port_W).norm();
  if (!(reach > s.insertion_m + 0.01)) {
    return problem("camera.focal_point_m",
                   "expected the focal point at least 1 cm beyond the scope's tip (position_m) "
                   "as seen from the port");
  }
  s.axis_W = inside.normalized();
  // The axis that puts the focal point on the line of sight, by fixed-point steps (the eye moves
  // with the axis about the port; with the port on the line of sight a 0° scope is there at once).
  double left = M_PI;
  for (int k = 0; k < 500 && left > 1e-10; ++k) left = aim_step(m, &s, camera.focal_point_m, 1.0);
  left = aim_step(m, &s, camera.focal_point_m, 0.0);
  if (!(left < 1e-6)) {
    char angle[32];
    std::snprintf(angle, sizeof(angle), "%g", camera.optics_deg);
    return problem("camera.optics_deg", std::string("a ") + angle +
                                            " degree optic through the port cannot be aimed at "
                                            "focal_point_m");
  }
  m.home = s;
  const LaparoscopeView home = laparoscope_view(m, s);
  m.focal_distance_m = (camera.focal_point_m - home.eye_W).norm();
  // In as far as three quarters of the way to the focal point (the scope's tip kept off the
  // organs it looks at), out to just past the port.
  m.min_insertion_m = std::min(m.min_insertion_m, s.insertion_m);
  m.max_insertion_m = s.insertion_m + 0.75 * m.focal_distance_m;
  return m;
}

void pivot_laparoscope(const LaparoscopeModel& model, LaparoscopeState* state, double right_rad,
                       double up_rad) {
  const LaparoscopeView v = laparoscope_view(model, *state);
  const Eigen::Vector3d right = v.view_dir_W.cross(v.up_W);
  // About the picture's up by −right (a positive turn about up swings the view to the left),
  // then about its right by +up.
  const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(up_rad, right)) *
                               Eigen::Quaterniond(Eigen::AngleAxisd(-right_rad, v.up_W));
  state->axis_W = within_cone((q * state->axis_W).normalized(), model.home.axis_W.normalized(),
                              model.max_pivot_rad);
}

void insert_laparoscope(const LaparoscopeModel& model, LaparoscopeState* state, double delta_m) {
  state->insertion_m =
      std::clamp(state->insertion_m + delta_m, model.min_insertion_m, model.max_insertion_m);
}

void roll_laparoscope(LaparoscopeState* state, double delta_rad) {
  state->roll_rad = std::remainder(state->roll_rad + delta_rad, 2.0 * M_PI);
}

void turn_laparoscope_horizon(LaparoscopeState* state, double delta_rad) {
  state->horizon_rad = std::remainder(state->horizon_rad + delta_rad, 2.0 * M_PI);
}

void zoom_laparoscope(const LaparoscopeModel& model, LaparoscopeState* state, double factor) {
  if (!(factor > 0.0)) return;
  const double t = std::tan(0.5 * state->view_angle_deg * kDegToRad) / factor;
  state->view_angle_deg = std::clamp(2.0 * std::atan(t) / kDegToRad, model.min_view_angle_deg,
                                     model.max_view_angle_deg);
}

double aim_laparoscope(const LaparoscopeModel& model, LaparoscopeState* state,
                       const Eigen::Vector3d& target_W, double fraction) {
  aim_step(model, state, target_W, fraction);
  state->axis_W = within_cone(state->axis_W, model.home.axis_W.normalized(), model.max_pivot_rad);
  return laparoscope_off_axis_rad(laparoscope_view(model, *state), target_W);
}

double laparoscope_off_axis_rad(const LaparoscopeView& view, const Eigen::Vector3d& point_W) {
  const Eigen::Vector3d to = point_W - view.eye_W;
  if (!(to.norm() > 1e-12)) return 0.0;
  return std::acos(std::clamp(view.view_dir_W.dot(to.normalized()), -1.0, 1.0));
}

}  // namespace lap::sim
