#include "hardware/passivity_controller.h"

#include <algorithm>
#include <cmath>

namespace lap::hardware {

Eigen::Vector3d PassivityController::apply(const Eigen::Vector3d& handle_W,
                                           const Eigen::Vector3d& wanted_W, double dt,
                                           double max_force_n) noexcept {
  if (!handle_W.allFinite() || !wanted_W.allFinite() || !(dt > 0.0)) {
    has_handle_ = false;
    return wanted_W;
  }
  if (!has_handle_) {  // nothing to observe yet: the first tick, or after a gap
    handle_W_ = handle_W;
    has_handle_ = true;
    return wanted_W;
  }
  // Observer: the work the force held over the last tick did on the handle.
  const Eigen::Vector3d step_W = handle_W - handle_W_;
  handle_W_ = handle_W;
  if (leak_s_ > 0.0 && figures_.observed_j > 0.0) figures_.observed_j *= std::exp(-dt / leak_s_);
  figures_.observed_j -= sent_W_.dot(step_W);
  figures_.lowest_j = std::min(figures_.lowest_j, figures_.observed_j);
  // Controller: the deficit predicted after the coming tick at the handle's last velocity.
  const Eigen::Vector3d v = step_W / dt;
  const double v2 = v.squaredNorm();
  const double predicted_j = figures_.observed_j - wanted_W.dot(v) * dt;
  if (!control_ || !(predicted_j < 0.0) || !(v2 > 0.0)) return wanted_W;
  const double alpha = std::min(-predicted_j / (v2 * dt), max_damping_);
  Eigen::Vector3d out = wanted_W - alpha * v;
  const double norm = out.norm();
  if (norm > max_force_n) out *= max_force_n / norm;
  if (!out.allFinite()) return wanted_W;
  ++figures_.active_ticks;
  figures_.dissipated_j += (wanted_W - out).dot(v) * dt;
  figures_.max_damping_n_s_per_m = std::max(figures_.max_damping_n_s_per_m, alpha);
  return out;
}

void PassivityController::sent(const Eigen::Vector3d& force_W) noexcept {
  sent_W_ = force_W.allFinite() ? force_W : Eigen::Vector3d::Zero();
}

}  // namespace lap::hardware
