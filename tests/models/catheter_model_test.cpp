// The mass-spring-damper catheter (§7.7(3)) against Euler–Bernoulli beam theory, energy and
// stretch.

#include "models/catheter_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "tests/test_support.h"

namespace lap::models {
namespace {

// A cantilever clamped at particles 0 and 1 (the clamp fixes the tangent) with a small tip load
// across it: the tip deflection against δ = F L³ / 3EI, EI = k_b l0, L from the clamp.
TEST(Catheter, CantileverTipDeflectionMatchesEulerBernoulli) {
  const CatheterModel model = CatheterModel::build({});
  CatheterState s(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  s.fixed[0] = s.fixed[1] = 1;
  const int n = model.particle_count();
  const double length = (n - 2) * model.rest_length_m();
  const double ei = model.bending_stiffness() * model.rest_length_m();
  const double delta_eb_target = 0.005 * length;  // small deflection: 0.5 % of the length
  const double f = 3.0 * ei * delta_eb_target / std::pow(length, 3);
  double speed = 0.0;
  for (int step = 0; step < 4000; ++step) {
    s.external_force[n - 1] = Eigen::Vector3d(0.0, -f, 0.0);
    ASSERT_TRUE(step_catheter(model, &s, 0.005));
    speed = 0.0;
    for (const auto& v : s.velocities) speed = std::max(speed, v.norm());
  }
  ASSERT_LT(speed, 1e-9);  // settled
  const double delta = -s.positions[n - 1].y();
  const double delta_eb = f * std::pow(length, 3) / (3.0 * ei);
  // The chain of n - 2 hinges is stiffer than the continuum by (N+1)(2N+1)/2N² (2.4 % here).
  const double error = std::abs(delta - delta_eb) / delta_eb;
  EXPECT_LT(error, 0.05);
  const double big_n = n - 2;
  const double discrete = delta_eb * (big_n + 1) * (2 * big_n + 1) / (2 * big_n * big_n);
  EXPECT_NEAR(delta, discrete, 0.002 * discrete);
  std::printf(
      "[ catheter ] cantilever L = %.4f m, EI = %.3g N m^2, F = %.3g N: tip %.4g mm, "
      "Euler-Bernoulli %.4g mm (%.2f %%)\n",
      length, ei, f, 1e3 * delta, 1e3 * delta_eb, 100.0 * error);
}

TEST(Catheter, PulledWithOneNewtonStretchesLessThanOnePercent) {
  const CatheterModel model = CatheterModel::build({});
  CatheterState s(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
  s.fixed[0] = 1;
  const int n = model.particle_count();
  for (int step = 0; step < 2000; ++step) {
    s.external_force[n - 1] = Eigen::Vector3d(0.0, 0.0, 1.0);
    ASSERT_TRUE(step_catheter(model, &s, 0.005));
  }
  const double length = (s.positions[n - 1] - s.positions[0]).norm();
  const double strain = length / model.settings().length_m - 1.0;
  EXPECT_LT(strain, 0.01);
  // Every segment carries the 1 N: strain = F / (k_l l0) exactly at equilibrium.
  EXPECT_NEAR(strain, 1.0 / (model.stretch_stiffness() * model.rest_length_m()), 1e-9);
  std::printf("[ catheter ] pulled with 1 N: strain %.4f %%\n", 100.0 * strain);
}

// No input: the energy (kinetic + stretch + bending) never grows, over 10^6 steps, from a bent
// and moving start, at the haptic and at the modelling rate (sanitizer builds: a twentieth).
TEST(Catheter, EnergyNeverGrowsWithoutInput) {
  CatheterSettings settings;
  settings.particles = 16;
  settings.length_m = 0.075;
  const CatheterModel model = CatheterModel::build(settings);
  for (const double dt : {0.001, 0.005}) {
    CatheterState s(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
    std::mt19937 rng(9);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int i = 0; i < model.particle_count(); ++i) {
      s.positions[i] += 0.002 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      s.velocities[i] = 0.05 * Eigen::Vector3d(g(rng), g(rng), g(rng));
    }
    const double e0 = catheter_energy(model, s);
    double last = e0;
    int64_t rises = 0;
    double worst_rise = 0.0;
    const int64_t steps = (dt < 0.002 ? 1000000 : 200000) / test::kSanitizerDivisor;
    for (int64_t k = 0; k < steps; ++k) {
      ASSERT_TRUE(step_catheter(model, &s, dt));
      const double e = catheter_energy(model, s);
      if (e > last + 1e-15 * e0) {
        ++rises;
        worst_rise = std::max(worst_rise, (e - last) / e0);
      }
      last = e;
    }
    EXPECT_EQ(rises, 0) << "dt " << dt << ": worst rise " << worst_rise << " of E0";
    if (test::kSanitizerDivisor == 1) {
      EXPECT_LT(last, 1e-6 * e0);  // and it has come to rest (a shortened run has not yet)
    }
    std::printf(
        "[ catheter ] %lld steps at dt = %g: energy %.3g J -> %.3g J, %lld rises, %lld steps "
        "split by the energy guard\n",
        static_cast<long long>(steps), dt, e0, last, static_cast<long long>(rises),
        static_cast<long long>(s.guard_refinements));
  }
}

TEST(Catheter, BadSettingsAndInputsAreRefused) {
  CatheterSettings bad;
  bad.particles = 2;
  try {
    (void)CatheterModel::build(bad);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("particles"), std::string::npos);
  }
  bad = {};
  bad.bending_stiffness_n_m2 = 0.0;
  EXPECT_THROW((void)CatheterModel::build(bad), std::invalid_argument);
  const CatheterModel model = CatheterModel::build({});
  CatheterState s(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  const auto before = s.positions;
  s.external_force[3].x() = std::nan("");
  EXPECT_FALSE(step_catheter(model, &s, 0.005));
  EXPECT_EQ(s.positions, before);
}

TEST(Catheter, FreeFallUnderGravityKeepsItsShape) {
  CatheterSettings settings;
  settings.gravity_m_per_s2 = Eigen::Vector3d(0.0, -9.81, 0.0);
  settings.drag_n_s_per_m = 0.0;
  const CatheterModel model = CatheterModel::build(settings);
  CatheterState s(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  const double dt = 0.001;
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(step_catheter(model, &s, dt));
  // Uniform gravity does not bend or stretch a free chain: every particle falls alike, as the
  // semi-implicit update gives, g dt² n (n + 1) / 2.
  const double expected = -9.81 * dt * dt * 100 * 101 / 2.0;
  for (const auto& p : s.positions) EXPECT_NEAR(p.y(), expected, 1e-12);
}

}  // namespace
}  // namespace lap::models
