#pragma once
/// \file
/// A hand holding a device's handle, for the passivity tests: a mass pulled towards where a
/// script wants the handle by a spring and a damper, pushed by the device's force. Estimates:
/// the hand and forearm moving the handle, 0.15 kg (the range 0.1–0.3 kg used for a hand holding
/// a stylus); a light grip, 200 N/m, of the order of finger-pad stiffnesses measured under small
/// forces (0.1–0.5 N/mm); 3 N s/m, a damping ratio of 0.27: an underdamped hand, the harder case
/// for stability.

#include <Eigen/Core>

namespace lap::test {

struct SimulatedHand {
  double mass_kg = 0.15;
  double stiffness_n_per_m = 200.0;
  double damping_n_s_per_m = 3.0;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  ///< the handle [m]
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  ///< [m/s]

  struct Step {
    Eigen::Vector3d dx = Eigen::Vector3d::Zero();          ///< the handle's displacement [m]
    Eigen::Vector3d hand_force = Eigen::Vector3d::Zero();  ///< the hand's own push [N]
  };
  /// One tick of dt with the device's force held over it (semi-implicit Euler).
  Step step(const Eigen::Vector3d& device_force, const Eigen::Vector3d& target, double dt) {
    Step s;
    s.hand_force = stiffness_n_per_m * (target - x) - damping_n_s_per_m * v;
    v += dt * (device_force + s.hand_force) / mass_kg;
    s.dx = dt * v;
    x += s.dx;
    return s;
  }
};

}  // namespace lap::test
