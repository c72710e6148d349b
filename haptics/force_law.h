#pragma once
/// \file
/// Contact force from penetration (thesis §4.4): Hooke, Hooke with damping on the probe's speed
/// into the surface, and the nonlinear law F = -(k1 sqrt|x| + k2 |x| + k3 |x|^2) x/|x|, always
/// clamped to a maximum magnitude.
/// Header-only and allocation-free: it runs in the haptic step.

#include <Eigen/Core>
#include <cmath>

namespace lap::haptics {

/// A material's force law. x is the penetration vector from the IHIP to the HIP [m].
struct ForceLaw {
  enum class Kind { kHooke, kHookeDamped, kNonlinear };
  Kind kind = Kind::kHooke;
  double stiffness_n_per_m = 500.0;  ///< k (Hooke) [N/m]
  double damping_n_s_per_m = 0.0;    ///< b (Hooke + damping), on the approach speed [N s/m]
  double k1_n_per_sqrt_m = 0.0;      ///< nonlinear: coefficient of sqrt|x| [N/m^0.5]
  double k2_n_per_m = 0.0;           ///< nonlinear: coefficient of |x| [N/m]
  double k3_n_per_m2 = 0.0;          ///< nonlinear: coefficient of |x|^2 [N/m^2]
  double max_force_n = 10.0;         ///< magnitude clamp [N]
};

/// Force on the HIP for penetration x (IHIP -> HIP) [m] while the probe approaches the surface
/// at approach_speed [m/s]: the probe's velocity relative to the surface along the contact's
/// inward normal (negative while it withdraws).
inline Eigen::Vector3d contact_force(const ForceLaw& law, const Eigen::Vector3d& x,
                                     double approach_speed_m_per_s) {
  const double depth = x.norm();
  if (!(depth > 0.0)) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d dir = x / depth;
  double magnitude = 0.0;  // along -dir (pushing the HIP out)
  switch (law.kind) {
    case ForceLaw::Kind::kHooke:
      magnitude = law.stiffness_n_per_m * depth;
      break;
    case ForceLaw::Kind::kHookeDamped:
      // The damper acts on the probe's own motion into the surface, not on the rate of change
      // of x: x also changes when the IHIP jumps (the proxy passing over an edge onto the next
      // face, a contact added or released), and its rate then spikes with no motion of the hand.
      // So |magnitude| <= k |x| + b |v|. A surface pushes, it never pulls the HIP in.
      magnitude = law.stiffness_n_per_m * depth + law.damping_n_s_per_m * approach_speed_m_per_s;
      magnitude = magnitude > 0.0 ? magnitude : 0.0;
      break;
    case ForceLaw::Kind::kNonlinear:
      magnitude = law.k1_n_per_sqrt_m * std::sqrt(depth) + law.k2_n_per_m * depth +
                  law.k3_n_per_m2 * depth * depth;
      break;
  }
  if (!std::isfinite(magnitude)) return Eigen::Vector3d::Zero();  // bad parameters: no force
  if (magnitude > law.max_force_n) magnitude = law.max_force_n;
  return -magnitude * dir;
}

}  // namespace lap::haptics
