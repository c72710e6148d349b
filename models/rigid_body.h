#pragma once
/// \file
/// Rigid-body dynamics of a moveable object (thesis §6.4): a transform per object, contact forces
/// at contact points giving force and torque, the equations of motion integrated every modelling
/// step. The haptic proxies work in the object's frame through HapticObject::pose_WO, so moving
/// the object never touches its vertices.
///
/// Integration (semi-implicit, not eq. 7-2's explicit Euler): the momenta are advanced first from
/// the applied wrench, p += F dt and L += τ dt (world frame, about the centre of mass); the
/// velocities follow from the new momenta, v = p / m and ω = R I⁻¹ Rᵀ L; the rotation is advanced
/// by the exact exponential of ω dt with ω taken at the half-step attitude (implicit midpoint,
/// second order). So an impulse changes the momenta by exactly F dt and r × F dt, a free body
/// keeps its angular momentum to rounding at any step, and its kinetic energy error stays small
/// and bounded (figures in the tests).
///
/// Model (immutable) apart from state (per instance), as in MuJoCo's mjModel and mjData. The step
/// allocates nothing and never throws.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lap::models {

struct RigidBodyModel {
  double mass_kg = 1.0;
  /// Inertia about the centre of mass, in the body frame [kg m²]; symmetric positive definite.
  Eigen::Matrix3d inertia_B = Eigen::Matrix3d::Identity();
  /// Centre of mass in the body (mesh) frame [m].
  Eigen::Vector3d com_B = Eigen::Vector3d::Zero();
  double linear_damping_per_s = 0.0;   ///< momentum decay rate (tissue and air drag) [1/s]
  double angular_damping_per_s = 0.0;  ///< angular momentum decay rate [1/s]

  /// Empty when usable, else what is wrong (mass, inertia not SPD or violating the triangle
  /// inequality of principal moments, negative damping).
  [[nodiscard]] const char* problem() const;
  /// A solid box of the given mass and full side lengths, centred at the body origin.
  [[nodiscard]] static RigidBodyModel solid_box(double mass_kg, const Eigen::Vector3d& sides_m);
};

struct RigidBodyState {
  /// Body (mesh) frame to world: what the haptic objects' pose_WO is set to.
  Eigen::Isometry3d pose_WB = Eigen::Isometry3d::Identity();
  Eigen::Vector3d linear_momentum_W = Eigen::Vector3d::Zero();   ///< [kg m/s]
  Eigen::Vector3d angular_momentum_W = Eigen::Vector3d::Zero();  ///< about the COM [kg m²/s]
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();   ///< accumulated for the next step [N]
  Eigen::Vector3d torque_W = Eigen::Vector3d::Zero();  ///< about the COM, accumulated [N m]
};

/// The centre of mass in the world frame.
[[nodiscard]] Eigen::Vector3d com_W(const RigidBodyModel& model, const RigidBodyState& state);
/// Velocity of the COM [m/s] and angular velocity [rad/s], world frame.
[[nodiscard]] Eigen::Vector3d linear_velocity_W(const RigidBodyModel& model,
                                                const RigidBodyState& state);
[[nodiscard]] Eigen::Vector3d angular_velocity_W(const RigidBodyModel& model,
                                                 const RigidBodyState& state);
/// Kinetic energy [J].
[[nodiscard]] double kinetic_energy(const RigidBodyModel& model, const RigidBodyState& state);

/// Adds a force applied at the world point p_W (a probe contact, §6.4) to the next step.
void apply_force_at(const RigidBodyModel& model, RigidBodyState* state,
                    const Eigen::Vector3d& force_W, const Eigen::Vector3d& p_W);

/// Advances by dt and clears the accumulated wrench. A non-finite wrench or dt > 0 not holding
/// leaves the body where it is, at rest, and returns false.
bool step_rigid_body(const RigidBodyModel& model, RigidBodyState* state, double dt) noexcept;

}  // namespace lap::models
