#include "haptics/friction.h"

#include <algorithm>
#include <cmath>

#include "haptics/spatial_hash.h"

namespace lap::haptics {
namespace {

constexpr double kTwoPi = 6.283185307179586;

}  // namespace

double FrictionCoefficientMap::factor(const Eigen::Vector3d& p) const noexcept {
  switch (kind) {
    case Kind::kUniform:
      return 1.0;
    case Kind::kPeriodic: {
      const double w = kTwoPi / period_m;
      const double s = (std::sin(w * p.x()) + std::sin(w * p.y()) + std::sin(w * p.z())) / 3.0;
      return std::max(0.0, 1.0 + amplitude * s);
    }
    case Kind::kRandom: {
      // Sum of four uniforms (Irwin-Hall): mean 2, variance 1/3; standardised, it is close to a
      // normal deviate, bounded, and costs four hashes.
      const auto cell = [&](double c) {
        return static_cast<uint32_t>(static_cast<int32_t>(std::floor(c / grain_m)));
      };
      uint32_t h = hash32(seed ^ 0x9e3779b9U);
      h = hash32(h ^ cell(p.x()));
      h = hash32(h ^ (cell(p.y()) * 0x85ebca6bU));
      h = hash32(h ^ (cell(p.z()) * 0xc2b2ae35U));
      double sum = 0.0;
      for (uint32_t k = 0; k < 4; ++k) {
        h = hash32(h + k);
        sum += static_cast<double>(h) / 4294967296.0;
      }
      const double z = (sum - 2.0) / std::sqrt(1.0 / 3.0);
      return std::clamp(1.0 + relative_std_dev * z, 0.0, 3.0);
    }
  }
  return 1.0;
}

const char* FrictionModel::problem() const {
  if (!(mu_static >= 0.0) || !(mu_dynamic >= 0.0)) return "coefficients must be >= 0";
  if (mu_dynamic > mu_static) return "the dynamic coefficient must not exceed the static one";
  if (!(stick_stiffness_n_per_m >= 0.0) || !(slide_stiffness_n_per_m >= 0.0)) {
    return "stiffnesses must be >= 0";
  }
  if (slide_stiffness_n_per_m > stick_stiffness_n_per_m) {
    return "k_d (sliding) must not exceed k_s (sticking)";
  }
  if (map.kind == FrictionCoefficientMap::Kind::kPeriodic &&
      (!(map.period_m > 0.0) || !(map.amplitude >= 0.0 && map.amplitude < 1.0))) {
    return "periodic map needs period_m > 0 and amplitude in [0, 1)";
  }
  if (map.kind == FrictionCoefficientMap::Kind::kRandom &&
      (!(map.grain_m > 0.0) || !(map.relative_std_dev >= 0.0))) {
    return "random map needs grain_m > 0 and relative_std_dev >= 0";
  }
  return "";
}

Eigen::Vector3d friction_step(const FrictionModel& model, FrictionState* state, int32_t object,
                              const Eigen::Vector3d& ihip_O, const Eigen::Vector3d& n_O,
                              double normal_force_n) noexcept {
  using Phase = FrictionState::Phase;
  const double f = model.map.factor(ihip_O);
  const double mu_s = model.mu_static * f;
  const double mu_d = model.mu_dynamic * f;
  const double k_s = model.stick_stiffness_n_per_m * f;
  const double k_d = model.slide_stiffness_n_per_m * f;
  if (!model.enabled() || !(normal_force_n > 0.0) || !(k_d > 1e-9) || !(mu_s > 0.0)) {
    // No friction here (or no normal force): the next contact starts sticking afresh.
    state->phase = Phase::kNone;
    return Eigen::Vector3d::Zero();
  }
  if (state->phase == Phase::kNone || state->object != object) {
    state->phase = Phase::kSticking;  // first contact: the contact point sticks (§6.2)
    state->object = object;
    state->stick_O = ihip_O;
  }
  // The sticking point lies on the surface; on a curved one keep only the tangential part.
  Eigen::Vector3d x = state->stick_O - ihip_O;
  x -= x.dot(n_O) * n_O;
  const double len = x.norm();
  const double slide_force = mu_d * normal_force_n;
  auto slide = [&]() -> Eigen::Vector3d {
    // The sticking point moves onto the line towards the IHIP, at mu_d Fn / k_d from it.
    const Eigen::Vector3d dir = x / len;
    state->stick_O = ihip_O + (slide_force / k_d) * dir;
    return slide_force * dir;
  };
  if (state->phase == Phase::kSticking) {
    if (k_s * len > mu_s * normal_force_n && len > 0.0) {
      state->phase = Phase::kSliding;
      ++state->stick_to_slide;
      return slide();
    }
    return k_s * x;
  }
  if (k_d * len > slide_force && len > 0.0) return slide();  // still moving: keep sliding
  // The user stopped: sticking again. The sticking spring takes over at the sliding spring's
  // force, so the sticking point moves in to k_d / k_s of the stretch. Left where it was, the
  // force would step up by k_s / k_d under the user's hand, and ½(k_s − k_d)x² of energy would
  // appear from nothing each time sliding stops (not passive).
  state->phase = Phase::kSticking;
  ++state->slide_to_stick;
  state->stick_O = ihip_O + (k_d / k_s) * x;
  return k_d * x;
}

}  // namespace lap::haptics
