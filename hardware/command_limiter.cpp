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

double CommandLimiter::force_bound_n() const noexcept {
  const double peak = limits_.max_force_n;
  const double fc = limits_.max_continuous_force_n;
  if (!(fc > 0.0) || !(fc < peak) || !(limits_.thermal_time_constant_s > 0.0)) return peak;
  // Linear in θ from the peak at the knee to F_c at θ = F_c² (the header's item 3).
  const double r = thermal_n2_ / (fc * fc);
  const double w = std::clamp((1.0 - r) / (1.0 - kThermalKnee), 0.0, 1.0);
  return fc + (peak - fc) * w;
}

LimitedCommand CommandLimiter::apply(const DeviceCommand& wanted, double dt, double gain) noexcept {
  LimitedCommand out;
  if (!wanted.force_W.allFinite() || !wanted.torque_W.allFinite() ||
      !std::isfinite(wanted.squeeze_n) || !std::isfinite(wanted.stiffness_n_per_m) ||
      !std::isfinite(dt) || !std::isfinite(gain)) {
    out.non_finite = true;
    out.command = zero();
    return out;
  }
  const double step_s = std::max(dt, 0.0);
  DeviceCommand c = wanted;
  // 1. Stiffness: down at once, up at a bounded rate.
  const double k_max = limits_.max_stiffness_n_per_m;
  const double target =
      (k_max > 0.0 && c.stiffness_n_per_m > k_max) ? k_max / c.stiffness_n_per_m : 1.0;
  stiffness_scale_ = std::min(target, stiffness_scale_ + step_s / kStiffnessRecoveryS);
  if (stiffness_scale_ < 1.0) {
    c.force_W *= stiffness_scale_;
    c.torque_W *= stiffness_scale_;
    c.stiffness_n_per_m *= stiffness_scale_;
    out.stiffness_scaled = true;
  }
  // 2. Peak magnitudes; 3. the sustained force (the torque follows the force's fraction).
  out.clamped = clamp_norm(&c.force_W, limits_.max_force_n);
  out.clamped = clamp_norm(&c.torque_W, limits_.max_torque_nm) || out.clamped;
  const double sq = std::clamp(c.squeeze_n, 0.0, std::max(0.0, limits_.max_squeeze_n));
  out.clamped = out.clamped || sq != c.squeeze_n;
  const double bound = force_bound_n();
  const double f_norm = c.force_W.norm();
  if (f_norm > bound) {
    const double f = bound / f_norm;
    c.force_W *= f;
    c.torque_W *= f;
    out.sustained_limited = true;
  }
  // 4. The gain scales what the device can render, so a resume ramps up from zero to the clamped
  // force over the whole ramp (scaling a deep push before clamping would jump at once).
  const double g = std::clamp(gain, 0.0, 1.0);
  c.force_W *= g;
  c.torque_W *= g;
  c.squeeze_n = g * sq;
  // Rate limit on the force change; the torque and squeeze follow the same fraction so that the
  // wrench keeps its direction while it ramps.
  const double max_step = limits_.max_force_rate_n_per_s * step_s;
  const Eigen::Vector3d step = c.force_W - last_.force_W;
  const double step_norm = step.norm();
  if (step_norm > max_step) {
    const double f = max_step / step_norm;
    c.force_W = last_.force_W + f * step;
    c.torque_W = last_.torque_W + f * (c.torque_W - last_.torque_W);
    c.squeeze_n = last_.squeeze_n + f * (c.squeeze_n - last_.squeeze_n);
    out.rate_limited = true;
  }
  // The motors heat with what is sent: θ follows |F|² with time constant τ (exact for |F| held
  // over the tick).
  if (limits_.thermal_time_constant_s > 0.0) {
    const double a = -std::expm1(-step_s / limits_.thermal_time_constant_s);
    thermal_n2_ += a * (c.force_W.squaredNorm() - thermal_n2_);
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
