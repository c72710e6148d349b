#include "models/rigid_body.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace lap::models {
namespace {

constexpr int kMidpointIterations = 3;

Eigen::Matrix3d inverse_inertia_W(const RigidBodyModel& model, const Eigen::Matrix3d& r) {
  return r * model.inertia_B.inverse() * r.transpose();
}

}  // namespace

const char* RigidBodyModel::problem() const {
  if (!(mass_kg > 0.0) || !std::isfinite(mass_kg)) return "mass_kg must be positive and finite";
  if (!inertia_B.allFinite() || !inertia_B.isApprox(inertia_B.transpose(), 1e-12)) {
    return "inertia must be a finite symmetric matrix";
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia_B);
  const Eigen::Vector3d& m = eig.eigenvalues();
  if (!(m.minCoeff() > 0.0)) return "inertia must be positive definite";
  // Principal moments of a real body satisfy I1 + I2 >= I3 for every ordering.
  const double tol = 1e-9 * m.sum();
  if (m(0) + m(1) < m(2) - tol) return "principal moments violate I1 + I2 >= I3";
  if (!com_B.allFinite()) return "centre of mass must be finite";
  if (!(linear_damping_per_s >= 0.0) || !(angular_damping_per_s >= 0.0)) {
    return "damping must be non-negative";
  }
  return "";
}

RigidBodyModel RigidBodyModel::solid_box(double mass_kg, const Eigen::Vector3d& sides_m) {
  RigidBodyModel m;
  m.mass_kg = mass_kg;
  const Eigen::Vector3d s2 = sides_m.cwiseProduct(sides_m);
  m.inertia_B =
      (mass_kg / 12.0 * Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y()))
          .asDiagonal();
  return m;
}

Eigen::Vector3d com_W(const RigidBodyModel& model, const RigidBodyState& state) {
  return state.pose_WB * model.com_B;
}

Eigen::Vector3d linear_velocity_W(const RigidBodyModel& model, const RigidBodyState& state) {
  return state.linear_momentum_W / model.mass_kg;
}

Eigen::Vector3d angular_velocity_W(const RigidBodyModel& model, const RigidBodyState& state) {
  return inverse_inertia_W(model, state.pose_WB.linear()) * state.angular_momentum_W;
}

double kinetic_energy(const RigidBodyModel& model, const RigidBodyState& state) {
  return 0.5 * state.linear_momentum_W.squaredNorm() / model.mass_kg +
         0.5 * state.angular_momentum_W.dot(angular_velocity_W(model, state));
}

void apply_force_at(const RigidBodyModel& model, RigidBodyState* state,
                    const Eigen::Vector3d& force_W, const Eigen::Vector3d& p_W) {
  state->force_W += force_W;
  state->torque_W += (p_W - com_W(model, *state)).cross(force_W);
}

bool step_rigid_body(const RigidBodyModel& model, RigidBodyState* state, double dt) noexcept {
  if (!(dt > 0.0) || !std::isfinite(dt) || !state->force_W.allFinite() ||
      !state->torque_W.allFinite()) {
    state->linear_momentum_W.setZero();
    state->angular_momentum_W.setZero();
    state->force_W.setZero();
    state->torque_W.setZero();
    return false;
  }
  // Momenta first (exact impulse), damping as an exact exponential decay (unconditionally
  // stable, never reverses the motion).
  state->linear_momentum_W += dt * state->force_W;
  state->angular_momentum_W += dt * state->torque_W;
  state->linear_momentum_W *= std::exp(-model.linear_damping_per_s * dt);
  state->angular_momentum_W *= std::exp(-model.angular_damping_per_s * dt);
  state->force_W.setZero();
  state->torque_W.setZero();

  // Then the pose, about the centre of mass.
  const Eigen::Vector3d c0 = com_W(model, *state);
  const Eigen::Vector3d c1 = c0 + dt * linear_velocity_W(model, *state);
  // The rotation by the implicit midpoint rule: R1 = exp(dt ω(R½)) R0 with ω taken at the
  // half-step attitude R½ = exp(dt ω / 2) R0, by fixed-point iteration. Second order, and its
  // energy error stays bounded instead of drifting (with ω taken at R0 the symmetric top's energy
  // drifted 5.7e-4 in 2 s; see rigid_body_test).
  const Eigen::Matrix3d r0 = state->pose_WB.linear();
  const Eigen::Matrix3d inv_inertia_B = model.inertia_B.inverse();
  const Eigen::Vector3d& l = state->angular_momentum_W;
  Eigen::Vector3d omega = r0 * inv_inertia_B * r0.transpose() * l;
  for (int it = 0; it < kMidpointIterations; ++it) {
    const double half = 0.5 * omega.norm() * dt;
    const Eigen::Matrix3d r_half =
        half > 0.0 ? Eigen::Matrix3d(Eigen::AngleAxisd(half, omega.normalized()) * r0) : r0;
    omega = r_half * inv_inertia_B * r_half.transpose() * l;
  }
  const double angle = omega.norm() * dt;
  Eigen::Matrix3d r = r0;
  if (angle > 0.0) {
    r = Eigen::AngleAxisd(angle, omega.normalized()).toRotationMatrix() * r0;
    // Keep R orthonormal against drift over millions of steps.
    const Eigen::Quaterniond q(r);
    r = q.normalized().toRotationMatrix();
  }
  state->pose_WB.linear() = r;
  state->pose_WB.translation() = c1 - r * model.com_B;
  return true;
}

}  // namespace lap::models
