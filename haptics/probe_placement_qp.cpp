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

// The dual's state for a primal active-set method (Goldfarb–Idnani style): multipliers λ ≥ 0,
// the free set P of positive ones, and Q, c of the dual objective ½ λᵀ Q λ − cᵀ λ.
struct DualActiveSet {
  int n = 0;
  std::array<std::array<double, kN>, kN> q{};
  std::array<double, kN> c{};
  std::array<double, kN> lambda{};
  std::array<bool, kN> is_free{};
  std::array<int, kN> free{};
  int nf = 0;

  DualActiveSet(const ProbePlacementQp& qp, const ProbePlacementQp::Vector6& x0) : n(qp.count) {
    for (int i = 0; i < n; ++i) {
      c[i] = qp.h[i] - qp.g[i].dot(x0);
      for (int j = 0; j <= i; ++j) q[i][j] = q[j][i] = qp.g[i].dot(qp.g[j]);
      q[i][i] *= 1.0 + kRidge;
    }
  }

  // Warm start: if the guessed active set's own solution has every multiplier positive, it is a
  // valid starting point of the method (a feasible λ solving its free subproblem).
  bool warm_start(uint32_t warm_active) noexcept {
    for (int i = 0; i < n; ++i) {
      if (((warm_active >> i) & 1U) != 0U) free[nf++] = i;
    }
    std::array<double, kN> z{};
    solve_free(q, c, free, nf, &z);
    bool positive = true;
    for (int k = 0; k < nf; ++k) positive = positive && z[free[k]] > 0.0;
    if (!positive) {
      nf = 0;
      return false;
    }
    for (int k = 0; k < nf; ++k) {
      lambda[free[k]] = z[free[k]];
      is_free[free[k]] = true;
    }
    return true;
  }

  // The bound constraint most violated at the current λ (w, the negative gradient, above the
  // optimality tolerance), or -1 at the optimum.
  [[nodiscard]] int most_violated() const noexcept {
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
    return best;
  }

  // One inner step: towards the free subproblem's solution z until the first multiplier reaches
  // zero, binding it (and any other that got there too). True when z was reached (or nothing is
  // left free): the inner loop is done.
  bool step_towards_free_solution() noexcept {
    std::array<double, kN> z{};
    solve_free(q, c, free, nf, &z);
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
      return true;
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
    return nf == 0;
  }
};

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
    if (lambda > 0.0) out.lambda_surface[0] = std::max(0.0, c0 - qp.skin_m) / qp.g[0].squaredNorm();
    return out;
  }
  DualActiveSet dual(qp, x0);
  if (warm_active != 0 && dual.warm_start(warm_active)) ++out.iterations;
  // Each outer step frees one constraint; each inner step binds at least one: the guard is
  // far above what a problem of kN constraints can need.
  int guard = 4 * kN * kN;
  for (int best = dual.most_violated(); best >= 0 && out.converged; best = dual.most_violated()) {
    dual.is_free[best] = true;
    dual.free[dual.nf++] = best;
    for (;;) {
      if (--guard < 0) {
        out.converged = false;
        break;
      }
      ++out.iterations;
      if (dual.step_towards_free_solution()) break;
    }
  }
  const std::array<double, kN>& lambda = dual.lambda;
  ProbePlacementQp::Vector6 x = x0;
  for (int i = 0; i < n; ++i) {
    x += lambda[i] * qp.g[i];
    out.lambda[i] = lambda[i];
  }
  out.a = x.head<3>();
  out.b = x.tail<3>();
  // The same free set's multipliers without the skin (λ is linear in the offsets on it).
  if (!(qp.skin_m > 0.0)) {
    out.lambda_surface = out.lambda;
    return out;
  }
  std::array<double, kN> c_surface = dual.c;
  for (int i = 0; i < n; ++i) c_surface[i] -= qp.skin_m;
  std::array<double, kN> z{};
  solve_free(dual.q, c_surface, dual.free, dual.nf, &z);
  for (int k = 0; k < dual.nf; ++k) {
    out.lambda_surface[dual.free[k]] = std::max(0.0, z[dual.free[k]]);
  }
  return out;
}

}  // namespace lap::haptics
