// The segment proxy's placement QP against a brute-force reference: every subset of constraints
// taken as active, the KKT conditions checked, the feasible one with the least distance kept.

#include "haptics/probe_placement_qp.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <random>

namespace lap::haptics {
namespace {

using Vector6 = ProbePlacementQp::Vector6;

// The nearest feasible point by enumeration: for each subset S, x = x0 + G_Sᵀ λ_S with
// G_S x = h_S; kept if λ_S ≥ 0 and every constraint holds. The QP is strictly convex, so the
// feasible KKT point is its unique minimiser.
Vector6 brute_force(const ProbePlacementQp& qp, const Vector6& x0) {
  const int n = qp.count;
  double best = std::numeric_limits<double>::infinity();
  Vector6 best_x = Vector6::Constant(std::nan(""));
  for (uint32_t mask = 0; mask < (1U << n); ++mask) {
    std::vector<int> s;
    for (int i = 0; i < n; ++i) {
      if (((mask >> i) & 1U) != 0U) s.push_back(i);
    }
    const int k = static_cast<int>(s.size());
    Eigen::MatrixXd g(k, 6);
    Eigen::VectorXd r(k);
    for (int i = 0; i < k; ++i) {
      g.row(i) = qp.g[s[i]].transpose();
      r(i) = qp.h[s[i]] - qp.g[s[i]].dot(x0);
    }
    Vector6 x = x0;
    if (k > 0) {
      const Eigen::MatrixXd q = g * g.transpose();
      Eigen::FullPivLU<Eigen::MatrixXd> lu(q);
      if (lu.rank() < k) continue;  // dependent rows: another subset gives the same point
      const Eigen::VectorXd lambda = lu.solve(r);
      if ((lambda.array() < -1e-12).any()) continue;
      x += g.transpose() * lambda;
    }
    bool feasible = true;
    for (int i = 0; i < n; ++i) feasible = feasible && qp.g[i].dot(x) >= qp.h[i] - 1e-12;
    if (feasible && (x - x0).norm() < best) {
      best = (x - x0).norm();
      best_x = x;
    }
  }
  return best_x;
}

// Random constraints like a probe's: unit normals, points along the probe, planes through points
// near the goal so that some are violated and some are not.
ProbePlacementQp random_problem(std::mt19937& rng, int n, const Vector6& x0) {
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  ProbePlacementQp qp;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d normal(uni(rng), uni(rng), 1.0 + 0.5 * uni(rng));  // mostly facing one way
    normal.normalize();
    const double u = u01(rng) < 0.3 ? std::round(u01(rng)) : u01(rng);
    const Eigen::Vector3d x = (1.0 - u) * x0.head<3>() + u * x0.tail<3>();
    EXPECT_TRUE(qp.add(normal, u, normal.dot(x) + 0.002 * uni(rng)));
  }
  return qp;
}

TEST(ProbePlacementQp, MatchesBruteForceOnRandomProblems) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  double worst = 0.0;
  int checked = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int n = 1 + trial % ProbePlacementQp::kMaxConstraints;
    Vector6 x0;
    x0 << 0.01 * uni(rng), 0.01 * uni(rng), 0.0, 0.01 * uni(rng), 0.01 * uni(rng), 0.02;
    const ProbePlacementQp qp = random_problem(rng, n, x0);
    const Vector6 reference = brute_force(qp, x0);
    if (!reference.allFinite()) continue;
    const ProbePlacementSolution sol = solve_probe_placement(qp, x0.head<3>(), x0.tail<3>());
    ASSERT_TRUE(sol.converged);
    Vector6 x;
    x << sol.a, sol.b;
    worst = std::max(worst, (x - reference).norm());
    for (int i = 0; i < n; ++i) {
      EXPECT_GE(qp.g[i].dot(x), qp.h[i] - 1e-11) << "trial " << trial << " constraint " << i;
      EXPECT_GE(sol.lambda[i], 0.0);
    }
    ++checked;
  }
  EXPECT_GT(checked, 2500);
  EXPECT_LT(worst, 1e-10);  // metres, on problems of millimetres
  std::printf("[ placement QP ] %d random problems, worst distance to brute force %.3g m\n",
              checked, worst);
}

TEST(ProbePlacementQp, WarmStartGivesTheSameAnswer) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 2 + trial % (ProbePlacementQp::kMaxConstraints - 1);
    Vector6 x0;
    x0 << 0.01 * uni(rng), 0.01 * uni(rng), 0.0, 0.01 * uni(rng), 0.01 * uni(rng), 0.02;
    const ProbePlacementQp qp = random_problem(rng, n, x0);
    const ProbePlacementSolution cold = solve_probe_placement(qp, x0.head<3>(), x0.tail<3>());
    // Any guess, right or wrong, gives the same point.
    const auto guess = static_cast<uint32_t>(rng()) & ((1U << n) - 1U);
    const ProbePlacementSolution warm =
        solve_probe_placement(qp, x0.head<3>(), x0.tail<3>(), guess);
    EXPECT_LT((warm.a - cold.a).norm() + (warm.b - cold.b).norm(), 1e-12) << "trial " << trial;
  }
}

TEST(ProbePlacementQp, DuplicateAndParallelConstraintsAreWellPosed) {
  // Eight copies of one plane under the whole probe, which the goal lies 1 mm below: the probe
  // is lifted onto the plane exactly, whatever the redundancy.
  ProbePlacementQp qp;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  for (int i = 0; i < ProbePlacementQp::kMaxConstraints; ++i) {
    EXPECT_TRUE(qp.add(up, (i % 3) / 2.0, 0.0));
  }
  EXPECT_FALSE(qp.add(up, 0.5, 0.0));
  const ProbePlacementSolution sol = solve_probe_placement(qp, Eigen::Vector3d(0.0, 0.0, -0.001),
                                                           Eigen::Vector3d(0.02, 0.0, -0.001));
  ASSERT_TRUE(sol.converged);
  EXPECT_NEAR(sol.a.z(), 0.0, 1e-12);
  EXPECT_NEAR(sol.b.z(), 0.0, 1e-12);
  EXPECT_NEAR(sol.a.x(), 0.0, 1e-15);
  EXPECT_NEAR(sol.b.x(), 0.02, 1e-15);
}

// lambda_surface: the same active set's multipliers for the offsets less the skin. Where the
// problem without the skin has the same active set, they are its multipliers, and the
// configuration they give lies on the planes themselves.
TEST(ProbePlacementQp, TheMultipliersWithoutTheSkinAreThoseOfTheProblemWithoutIt) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  constexpr double kSkin = 1e-4;
  int compared = 0;
  double worst = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 1 + trial % ProbePlacementQp::kMaxConstraints;
    Vector6 x0;
    x0 << 0.01 * uni(rng), 0.01 * uni(rng), 0.0, 0.01 * uni(rng), 0.01 * uni(rng), 0.02;
    ProbePlacementQp bare = random_problem(rng, n, x0);
    ProbePlacementQp skinned = bare;
    skinned.skin_m = kSkin;
    for (int i = 0; i < n; ++i) skinned.h[i] += kSkin;
    const ProbePlacementSolution with = solve_probe_placement(skinned, x0.head<3>(), x0.tail<3>());
    const ProbePlacementSolution without = solve_probe_placement(bare, x0.head<3>(), x0.tail<3>());
    bool same_set = true;
    for (int i = 0; i < n; ++i)
      same_set = same_set && (with.lambda[i] > 0.0) == (without.lambda[i] > 0.0);
    if (!same_set) continue;
    ++compared;
    Vector6 x = x0;
    for (int i = 0; i < n; ++i) {
      worst = std::max(worst, std::abs(with.lambda_surface[i] - without.lambda[i]));
      EXPECT_EQ(with.lambda_surface[i] > 0.0, without.lambda[i] > 0.0) << trial << " " << i;
      x += with.lambda_surface[i] * bare.g[i];
    }
    Vector6 reference;
    reference << without.a, without.b;
    EXPECT_LT((x - reference).norm(), 1e-10) << "trial " << trial;
  }
  EXPECT_GT(compared, 1000);
  EXPECT_LT(worst, 1e-10);
  // And with no skin they are the multipliers themselves.
  ProbePlacementQp one;
  EXPECT_TRUE(one.add(Eigen::Vector3d::UnitZ(), 0.5, 0.001));
  const ProbePlacementSolution s =
      solve_probe_placement(one, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  EXPECT_EQ(s.lambda_surface[0], s.lambda[0]);
  EXPECT_GT(s.lambda[0], 0.0);
}

TEST(ProbePlacementQp, OneConstraintIsTheProjectionOnItsHalfSpace) {
  // A point at u = 1/4 held 1 mm above where the goal puts it: the least-squares split moves a
  // by (1 - u) / ((1 - u)^2 + u^2) mm and b by u / (...) mm.
  ProbePlacementQp qp;
  const double u = 0.25;
  EXPECT_TRUE(qp.add(Eigen::Vector3d::UnitZ(), u, 0.001));
  const ProbePlacementSolution sol =
      solve_probe_placement(qp, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 0.0, 0.0));
  const double w = (1.0 - u) * (1.0 - u) + u * u;
  EXPECT_NEAR(sol.a.z(), 0.001 * (1.0 - u) / w, 1e-15);
  EXPECT_NEAR(sol.b.z(), 0.001 * u / w, 1e-15);
  EXPECT_NEAR((1.0 - u) * sol.a.z() + u * sol.b.z(), 0.001, 1e-15);
}

}  // namespace
}  // namespace lap::haptics
