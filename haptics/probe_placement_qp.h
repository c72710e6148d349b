#pragma once
/// \file
/// The placement problem of the segment proxy (§5.3, our formulation; see segment_proxy.h): the
/// configuration x = (a, b) of a two-point probe nearest a goal x0 that keeps each constrained
/// point (1 − u_i) a + u_i b on the outside of its plane,
///
///     minimise ½ |x − x0|²  subject to  g_i · x ≥ h_i,  g_i = ((1 − u_i) n_i, u_i n_i) ∈ R⁶.
///
/// Solved exactly, in a finite number of steps, on its dual — non-negative least squares in the
/// multipliers λ (x = x0 + Σ λ_i g_i), by the active-set method of Lawson & Hanson (1974). An
/// iterative projection (Hildreth's) converges slowly when constraint planes are nearly parallel,
/// which is the common case of a probe lying on a gently curved organ. A tiny ridge keeps
/// linearly dependent constraints (more than six, or duplicates) well-posed; it moves x by at
/// most 1e-12 × |λ|.
///
/// Allocates nothing, never throws.

#include <Eigen/Core>
#include <array>
#include <cstdint>

namespace lap::haptics {

struct ProbePlacementQp {
  static constexpr int kMaxConstraints = 8;
  using Vector6 = Eigen::Matrix<double, 6, 1>;

  int32_t count = 0;
  std::array<Vector6, kMaxConstraints> g{};
  std::array<double, kMaxConstraints> h{};
  /// A clearance included in every offset h (the segment proxy's skin) [m]: the solution also
  /// gives the multipliers without it, for a spring measured from the planes themselves (0: they
  /// are the multipliers, and cost nothing).
  double skin_m = 0.0;

  /// Adds the constraint n · ((1 − u) a + u b) ≥ offset. Returns false when full.
  bool add(const Eigen::Vector3d& n, double u, double offset);
};

struct ProbePlacementSolution {
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  std::array<double, ProbePlacementQp::kMaxConstraints> lambda{};
  /// The multipliers of the same active set for the offsets less the skin (clamped at 0): where
  /// the goal is that far inside, x_surface = x0 + Σ lambda_surface_i g_i lies on the planes.
  std::array<double, ProbePlacementQp::kMaxConstraints> lambda_surface{};
  int32_t iterations = 0;
  bool converged = false;  ///< false only if the iteration guard was hit (then x is still finite)
};

/// Solves the problem for the goal (a0, b0). `warm_active` (bit i: constraint i) is a guess of
/// the active set, e.g. the last solution's: used when its own solution is a valid start, which
/// saves the one-by-one build-up of a cold start. The answer does not depend on it.
[[nodiscard]] ProbePlacementSolution solve_probe_placement(const ProbePlacementQp& qp,
                                                           const Eigen::Vector3d& a0,
                                                           const Eigen::Vector3d& b0,
                                                           uint32_t warm_active = 0) noexcept;

}  // namespace lap::haptics
