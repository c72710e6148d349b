#include "haptics/probe_placement_qp.h"

#include <algorithm>
#include <cmath>

namespace lap::haptics {
namespace {

constexpr int kN = ProbePlacementQp::kMaxConstraints;
constexpr double kRidge = 1e-12;       // relative to the Gram diagonal (≥ 1/2)
constexpr double kOptimality = 1e-15;  // [m]: a constraint violated by less is satisfied

// Solves Q_PP z_P = c_P for the free set P (Cholesky; Q + ridge is positive definite).
void solve_free(const std::array<std::array<double, kN>, kN>& q, const std::array<double, kN>& c,
                const std::array<int, kN>& free, int nf, std::array<double, kN>* z) {
  std::array<std::array<double, kN>, kN> l{};
  for (int i = 0; i < nf; ++i) {
    for (int j = 0; j <= i; ++j) {
      double s = q[free[i]][free[j]];
      for (int k = 0; k < j; ++k) s -= l[i][k] * l[j][k];
      l[i][j] = i == j ? std::sqrt(std::max(s, 1e-300)) : s / l[j][j];
    }
  }
  std::array<double, kN> y{};
  for (int i = 0; i < nf; ++i) {
    double s = c[free[i]];
    for (int k = 0; k < i; ++k) s -= l[i][k] * y[k];
    y[i] = s / l[i][i];
  }
  for (int i = nf - 1; i >= 0; --i) {
    double s = y[i];
    for (int k = i + 1; k < nf; ++k) s -= l[k][i] * (*z)[free[k]];
    (*z)[free[i]] = s / l[i][i];
  }
}

}  // namespace

bool ProbePlacementQp::add(const Eigen::Vector3d& n, double u, double offset) {
  if (count == kMaxConstraints) return false;
  g[count] << (1.0 - u) * n, u * n;
  h[count] = offset;
  ++count;
  return true;
}

ProbePlacementSolution solve_probe_placement(const ProbePlacementQp& qp, const Eigen::Vector3d& a0,
                                             const Eigen::Vector3d& b0,
                                             uint32_t warm_active) noexcept {
  ProbePlacementSolution out;
  const int n = qp.count;
  ProbePlacementQp::Vector6 x0;
  x0 << a0, b0;
  // Dual: minimise ½ λᵀ Q λ − cᵀ λ over λ ≥ 0, Q = G Gᵀ (+ ridge), c = h − G x0.
  out.converged = true;
  if (n == 1) {
    // One constraint: the projection onto its half-space, in closed form.
    const double c0 = qp.h[0] - qp.g[0].dot(x0);
    const double lambda = c0 > kOptimality ? c0 / qp.g[0].squaredNorm() : 0.0;
    const ProbePlacementQp::Vector6 x = x0 + lambda * qp.g[0];
    out.a = x.head<3>();
    out.b = x.tail<3>();
    out.lambda[0] = lambda;
    return out;
  }
  std::array<std::array<double, kN>, kN> q{};
  std::array<double, kN> c{};
  for (int i = 0; i < n; ++i) {
    c[i] = qp.h[i] - qp.g[i].dot(x0);
    for (int j = 0; j <= i; ++j) q[i][j] = q[j][i] = qp.g[i].dot(qp.g[j]);
    q[i][i] *= 1.0 + kRidge;
  }
  std::array<double, kN> lambda{};
  std::array<bool, kN> is_free{};
  std::array<int, kN> free{};
  int nf = 0;
  if (warm_active != 0) {
    // Warm start: if the guessed active set's own solution has every multiplier positive, it
    // is a valid starting point of the method (a feasible λ solving its free subproblem).
    for (int i = 0; i < n; ++i) {
      if (((warm_active >> i) & 1U) != 0U) free[nf++] = i;
    }
    std::array<double, kN> z{};
    solve_free(q, c, free, nf, &z);
    bool positive = true;
    for (int k = 0; k < nf; ++k) positive = positive && z[free[k]] > 0.0;
    if (positive) {
      for (int k = 0; k < nf; ++k) {
        lambda[free[k]] = z[free[k]];
        is_free[free[k]] = true;
      }
      ++out.iterations;
    } else {
      nf = 0;
    }
  }
  // Each outer step frees one constraint; each inner step binds at least one: the guard is
  // far above what a problem of kN constraints can need.
  int guard = 4 * kN * kN;
  for (;;) {
    // w: the negative gradient, how violated each constraint is at the current λ.
    int best = -1;
    double best_w = kOptimality;
    for (int i = 0; i < n; ++i) {
      if (is_free[i]) continue;
      double w = c[i];
      for (int j = 0; j < nf; ++j) w -= q[i][free[j]] * lambda[free[j]];
      if (w > best_w) {
        best_w = w;
        best = i;
      }
    }
    if (best < 0) break;
    is_free[best] = true;
    free[nf++] = best;
    for (;;) {
      if (--guard < 0) {
        out.converged = false;
        break;
      }
      ++out.iterations;
      std::array<double, kN> z{};
      solve_free(q, c, free, nf, &z);
      // Step towards z until the first multiplier reaches zero, and bind it (and any other
      // that got there too).
      int first = -1;
      double alpha = 1.0;
      for (int k = 0; k < nf; ++k) {
        const int i = free[k];
        if (z[i] <= 0.0) {
          const double den = lambda[i] - z[i];
          const double t = den > 0.0 ? lambda[i] / den : 0.0;
          if (first < 0 || t < alpha) {
            alpha = t;
            first = i;
          }
        }
      }
      if (first < 0) {
        for (int k = 0; k < nf; ++k) lambda[free[k]] = z[free[k]];
        break;
      }
      int kept = 0;
      for (int k = 0; k < nf; ++k) {
        const int i = free[k];
        lambda[i] += alpha * (z[i] - lambda[i]);
        if (i == first || lambda[i] <= 0.0) {
          lambda[i] = 0.0;
          is_free[i] = false;
        } else {
          free[kept++] = i;
        }
      }
      nf = kept;
      if (nf == 0) break;
    }
    if (!out.converged) break;
  }
  ProbePlacementQp::Vector6 x = x0;
  for (int i = 0; i < n; ++i) {
    x += lambda[i] * qp.g[i];
    out.lambda[i] = lambda[i];
  }
  out.a = x.head<3>();
  out.b = x.tail<3>();
  return out;
}

}  // namespace lap::haptics
