#pragma once
/// \file
/// The scene's free rigid bodies as the haptic loop moves them (thesis §6.4, §3.2): each body's
/// state, stepped every haptic tick by the contact forces the tools' proxies put on it that tick
/// (and the catheter's push from the last modelling step), and the pose the proxies render it
/// at (HapticObject::pose_WO, the probe taken into the body's frame: no vertex ever moves).
///
/// Why the haptic loop and not the modelling loop: a body and the tool's contact spring form an
/// oscillator, and a spring whose force reaches the body up to a modelling period (5 ms) late
/// feeds it energy every bounce (a delay τ acts as a negative damping k τ). Stepped at the
/// haptic rate, right after the proxies, the coupling is a symplectic Euler step of the body and
/// the spring: an undamped bounce off a probe held still gives back its energy to 0.04 % (the
/// contact starting and ending inside a tick), against a 1.6 % gain stepped at 200 Hz, and with
/// the material's damping it loses energy; the impulse the tool gives is exactly the body's
/// change of momentum (tests/sim/moving_body_test.cpp).
/// The thesis' own structure for rigid objects (§3.2, §6.5) runs their dynamics with the
/// haptic rendering; the modelling loop reads the poses from the haptic snapshot.
///
/// The step allocates nothing and never throws.

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "haptics/haptic_object.h"
#include "models/rigid_body.h"
#include "sim/setup/rigid_body_models.h"

namespace lap::sim {

/// One free body as the snapshots carry it.
struct BodySnapshot {
  int32_t organ = -1;
  /// Body (the organ's rest world frame) to world: the organ's surface now is pose_W applied to
  /// its rest surface.
  Eigen::Isometry3d pose_W = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_W = Eigen::Vector3d::Zero();          ///< of its centre of mass [m/s]
  Eigen::Vector3d angular_velocity_W = Eigen::Vector3d::Zero();  ///< [rad/s]
};

/// Every free body, in fixed storage (no allocation in a snapshot's copy).
struct BodySnapshots {
  int32_t count = 0;
  std::array<BodySnapshot, kMaxRigidBodies> bodies{};
};

/// A push held on each body between modelling steps (the catheter's reactions), per body in the
/// order of BodySnapshots.
struct BodyPushes {
  std::array<Eigen::Vector3d, kMaxRigidBodies> force_W;   ///< [N]
  std::array<Eigen::Vector3d, kMaxRigidBodies> torque_W;  ///< about its centre of mass [N m]
  BodyPushes() { clear(); }
  void clear() noexcept {
    for (Eigen::Vector3d& f : force_W) f.setZero();
    for (Eigen::Vector3d& t : torque_W) t.setZero();
  }
};

class MovingBodies {
 public:
  /// The bodies at rest (pose identity) for a scene of `organ_count` organs. Setup: allocates.
  void init(std::span<const RigidBodyOfOrgan> bodies, int32_t organ_count);

  [[nodiscard]] int32_t count() const { return static_cast<int32_t>(models_.size()); }
  /// Which body organ o is, or -1 when it is fixed or deforms.
  [[nodiscard]] int32_t body_of(int32_t organ) const noexcept {
    return organ >= 0 && static_cast<size_t>(organ) < body_of_organ_.size()
               ? body_of_organ_[static_cast<size_t>(organ)]
               : -1;
  }

  /// Puts each body's object where the body is now, its previous pose where it was at the last
  /// call (the proxies take the object's motion from the two, §6.4).
  void pose_objects(std::span<haptics::HapticObject> objects) const noexcept;
  /// A contact force on organ `organ` at world point p_W, for this tick's step; ignored when the
  /// organ is no body.
  void push(int32_t organ, const Eigen::Vector3d& force_on_organ_W,
            const Eigen::Vector3d& p_W) noexcept;
  /// One tick of every body under this tick's pushes and the held pushes; false (the body left
  /// at rest where it is) when a wrench was not finite.
  bool step(const BodyPushes& held, double dt) noexcept;
  /// The bodies as they are now.
  void write(BodySnapshots* out) const noexcept;

  /// Puts a body in a given state (set-up and tests: a body launched at a speed).
  void set_state(int32_t body, const models::RigidBodyState& state) {
    states_[static_cast<size_t>(body)] = state;
  }
  [[nodiscard]] const models::RigidBodyModel& model(int32_t body) const {
    return models_[static_cast<size_t>(body)].model;
  }
  [[nodiscard]] const models::RigidBodyState& state(int32_t body) const {
    return states_[static_cast<size_t>(body)];
  }

 private:
  std::vector<RigidBodyOfOrgan> models_;
  std::vector<models::RigidBodyState> states_;
  std::vector<int32_t> body_of_organ_;
};

}  // namespace lap::sim
