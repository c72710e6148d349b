#include "hardware/command_limiter.h"

#include <algorithm>
#include <cmath>

namespace lap::hardware {
namespace {

// Scales v so that |v| <= limit (limit <= 0: the device renders none of it).
bool clamp_norm(Eigen::Vector3d* v, double limit) {
  const double n = v->norm();
  if (!(limit > 0.0)) {
    const bool cut = n > 0.0;
    v->setZero();
    return cut;
  }
  if (n <= limit) return false;
  *v *= limit / n;
  return true;
}

}  // namespace

LimitedCommand CommandLimiter::apply(const DeviceCommand& wanted, double dt, double gain) noexcept {
  LimitedCommand out;
  if (!wanted.force_W.allFinite() || !wanted.torque_W.allFinite() ||
      !std::isfinite(wanted.squeeze_n) || !std::isfinite(dt) || !std::isfinite(gain)) {
    out.non_finite = true;
    out.command = zero();
    return out;
  }
  DeviceCommand c = wanted;
  out.clamped = clamp_norm(&c.force_W, limits_.max_force_n);
  out.clamped = clamp_norm(&c.torque_W, limits_.max_torque_nm) || out.clamped;
  const double sq = std::clamp(c.squeeze_n, 0.0, std::max(0.0, limits_.max_squeeze_n));
  out.clamped = out.clamped || sq != c.squeeze_n;
  // The gain scales what the device can render, so a resume ramps up from zero to the clamped
  // force over the whole ramp (scaling a deep push before clamping would jump at once).
  const double g = std::clamp(gain, 0.0, 1.0);
  c.force_W *= g;
  c.torque_W *= g;
  c.squeeze_n = g * sq;
  // Rate limit on the force change; the torque and squeeze follow the same fraction so that the
  // wrench keeps its direction while it ramps.
  const double max_step = limits_.max_force_rate_n_per_s * std::max(dt, 0.0);
  const Eigen::Vector3d step = c.force_W - last_.force_W;
  const double step_norm = step.norm();
  if (step_norm > max_step) {
    const double f = max_step / step_norm;
    c.force_W = last_.force_W + f * step;
    c.torque_W = last_.torque_W + f * (c.torque_W - last_.torque_W);
    c.squeeze_n = last_.squeeze_n + f * (c.squeeze_n - last_.squeeze_n);
    out.rate_limited = true;
  }
  last_ = c;
  out.command = c;
  return out;
}

DeviceCommand CommandLimiter::zero() noexcept {
  last_ = DeviceCommand{};
  return last_;
}

}  // namespace lap::hardware
