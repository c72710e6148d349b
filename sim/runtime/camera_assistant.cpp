#include "sim/runtime/camera_assistant.h"

#include <algorithm>
#include <cmath>

namespace lap::sim {

bool CameraAssistant::step(const LaparoscopeModel& model, LaparoscopeState* state,
                           std::span<const Eigen::Vector3d> tips_W, double dt_s) {
  if (tips_W.empty() || !(dt_s > 0.0)) return false;
  Eigen::Vector3d work = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& t : tips_W) work += t;
  work /= static_cast<double>(tips_W.size());
  if (!work.allFinite()) return false;
  const double half_view_rad = 0.5 * state->view_angle_deg * M_PI / 180.0;
  const double share = 1.0 - std::exp(-dt_s / std::max(settings_.time_constant_s, 1e-6));
  bool moved = false;

  // Aim: start beyond the dead zone, stop well inside it (hysteresis, so it settles).
  const LaparoscopeView before = laparoscope_view(model, *state);
  const double off = laparoscope_off_axis_rad(before, work);
  if (off > settings_.dead_zone * half_view_rad) following_ = true;
  if (following_) {
    const double left = aim_laparoscope(model, state, work, share);
    moved = true;
    if (left < 0.25 * settings_.dead_zone * half_view_rad) following_ = false;
  }

  // Distance: the tips' spread about the working point, as seen from the eye.
  const LaparoscopeView view = laparoscope_view(model, *state);
  const Eigen::Vector3d to_work = work - view.eye_W;
  const double distance = to_work.norm();
  if (!(distance > 1e-6)) return moved;
  double spread = 0.0;
  for (const Eigen::Vector3d& t : tips_W) {
    const Eigen::Vector3d to_tip = t - view.eye_W;
    if (to_tip.norm() < 1e-9) continue;
    spread = std::max(
        spread, std::acos(std::clamp(to_work.normalized().dot(to_tip.normalized()), -1.0, 1.0)));
  }
  // The distance that would put the spread at the middle of the band (small angles: the spread
  // goes as 1 / distance), approached by the same share; only outside the band.
  const double widest = settings_.widest * half_view_rad;
  const double closest = settings_.closest * half_view_rad;
  double wanted = distance;
  if (spread > widest) {
    wanted = distance * std::tan(spread) / std::tan(0.5 * (widest + closest));
  } else if (spread < closest && distance > settings_.min_distance_m) {
    wanted = std::max(settings_.min_distance_m, distance * std::tan(std::max(spread, 1e-6)) /
                                                    std::tan(0.5 * (widest + closest)));
  }
  if (wanted != distance) {
    // Sliding in by d brings the eye d · cos(axis, line to the work) closer.
    const double along = std::max(0.2, state->axis_W.normalized().dot(to_work / distance));
    const double before_m = state->insertion_m;
    insert_laparoscope(model, state, share * (distance - wanted) / along);
    moved = moved || state->insertion_m != before_m;
  }
  return moved;
}

}  // namespace lap::sim
