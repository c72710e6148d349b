#pragma once
/// \file
/// Stick-slip friction (thesis §6.2, Figure 6-4): a sticking point on the surface pulls the
/// IHIP back with a spring, k_s while sticking and k_d (< k_s) while sliding.
///
/// - First contact: the contact point becomes the sticking point; state = sticking.
/// - Sticking: F = k_s x, x = sticking point - IHIP. When |F| > mu_s Fn the state becomes
///   sliding and the sticking point moves onto the line towards the IHIP, at mu_d Fn / k_d
///   from it (so |F| = mu_d Fn).
/// - Sliding: F = k_d x. While |F| > mu_d Fn the user keeps moving the same way: the state
///   stays sliding and the sticking point follows as above (the thesis' change to Salisbury
///   et al. 1995, which keeps the feel of dynamic friction). Otherwise the user has stopped:
///   the state becomes sticking, and the sticking point moves in to k_d/k_s of its distance so
///   that the sticking spring starts at the sliding spring's force: the force is continuous
///   when sliding stops and no energy appears (left in place, the force would step up by
///   k_s/k_d and ½(k_s − k_d)x² would appear each time).
///
/// The coefficients may vary over the surface (FrictionCoefficientMap): uniform, periodic, or
/// random per grain with a mean and a standard deviation (sandpaper grades, Green & Salisbury
/// 1997). k_s and k_d scale with the local coefficients, as the thesis has them proportional.
///
/// Everything here is allocation-free and runs in the haptic step.

#include <Eigen/Core>
#include <cstdint>

namespace lap::haptics {

/// Where the coefficients come from at a surface point (object frame).
struct FrictionCoefficientMap {
  enum class Kind : uint8_t { kUniform, kPeriodic, kRandom };
  Kind kind = Kind::kUniform;
  /// kPeriodic: coefficients multiplied by 1 + amplitude * (sin(2 pi x / L) + sin(2 pi y / L)
  /// + sin(2 pi z / L)) / 3, L = period_m. amplitude in [0, 1).
  double period_m = 0.005;
  double amplitude = 0.5;
  /// kRandom: each cubic grain of side grain_m gets a factor with mean 1 and standard
  /// deviation relative_std_dev (clamped to [0, 3]), fixed by `seed` (reproducible).
  double grain_m = 0.0005;
  double relative_std_dev = 0.3;
  uint32_t seed = 1;

  /// The factor (>= 0) applied to both coefficients at p (object frame).
  [[nodiscard]] double factor(const Eigen::Vector3d& p) const noexcept;
};

/// A material's friction.
struct FrictionModel {
  double mu_static = 0.0;                ///< mean static coefficient
  double mu_dynamic = 0.0;               ///< mean dynamic coefficient, <= mu_static
  double stick_stiffness_n_per_m = 0.0;  ///< k_s at the mean coefficient [N/m]
  double slide_stiffness_n_per_m = 0.0;  ///< k_d at the mean coefficient, <= k_s [N/m]
  FrictionCoefficientMap map;

  [[nodiscard]] bool enabled() const {
    return mu_static > 0.0 && stick_stiffness_n_per_m > 0.0 && slide_stiffness_n_per_m > 0.0;
  }
  /// Empty when usable, else what is wrong (for setup-time validation).
  [[nodiscard]] const char* problem() const;
};

/// Per-proxy friction state. The sticking point is kept in the object's frame so that it moves
/// with a moving object (§6.4 + §6.2 together).
struct FrictionState {
  enum class Phase : uint8_t { kNone, kSticking, kSliding };
  Phase phase = Phase::kNone;
  int32_t object = -1;
  Eigen::Vector3d stick_O = Eigen::Vector3d::Zero();
  int64_t stick_to_slide = 0;  ///< transitions, for tests and statistics
  int64_t slide_to_stick = 0;
};

/// One tick of the state machine. ihip_O: the IHIP (object frame); n_O: unit surface normal
/// there; normal_force_n: magnitude of the normal force this tick. Returns the friction force
/// on the HIP (object frame, tangent to the surface). Starts sticking at ihip_O when the state
/// is not yet in contact with `object`.
[[nodiscard]] Eigen::Vector3d friction_step(const FrictionModel& model, FrictionState* state,
                                            int32_t object, const Eigen::Vector3d& ihip_O,
                                            const Eigen::Vector3d& n_O,
                                            double normal_force_n) noexcept;

}  // namespace lap::haptics
