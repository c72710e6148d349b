#pragma once
/// \file
/// A passivity observer and controller at one device port (Hannaford & Ryu 2002, "Time-domain
/// passivity control of haptic interfaces", IEEE T-RO 18(1)): whatever renders the force — the
/// proxies, the couplings to models that step at 200 Hz, the limiter's scaling — the energy the
/// simulation has given the hand over the whole session never exceeds what it took from the hand
/// by more than one tick's prediction error.
///
/// Observer. The force sent at tick n is held by the device until tick n + 1, so the work it does
/// on the handle over that tick is exactly F(n)·(x(n+1) − x(n)). The observer sums what the
/// simulation absorbed: E(n) = E(n − 1) − F(n − 1)·(x(n) − x(n − 1)), with x the handle as read
/// (E ≥ 0: passive so far; E < 0: the simulation gave the hand more than it took).
///
/// Controller. Before a force is sent, the energy after the coming tick is predicted with the
/// handle's last velocity v = (x(n) − x(n − 1)) / dt: E(n) − F·v dt. Where that would go below
/// zero, a damper −α v is added in series with the rendering (impedance causality: velocity in,
/// force out), α = −(E(n) − F·v dt) / (|v|² dt), which dissipates exactly the deficit on that
/// tick; α is clamped to max_damping and the force to the bound given (the peak and sustained
/// limits of command_limiter.h). What the prediction misses (the handle's change of velocity over
/// the tick) is observed on the next tick and dissipated then. The damper acts only while the
/// simulation is active, not on the rest of the rendering, and bypasses the rate limit, as the
/// watchdog's zero does.
///
/// Covers the handle's translation (the force); the roll torque and the gripper's squeeze are
/// not observed (the default arms render no torque; the squeeze is a spring of the jaws' own
/// closure, passive in itself).
///
/// Real time: no allocation, no lock, no exception.

#include <Eigen/Core>
#include <cstdint>

namespace lap::hardware {

struct PassivityFigures {
  double observed_j = 0.0;    ///< E: energy the simulation absorbed from the hand so far [J]
  double lowest_j = 0.0;      ///< the lowest E so far (≤ 0) [J]
  double dissipated_j = 0.0;  ///< by the controller's damper, as predicted [J]
  int64_t active_ticks = 0;   ///< ticks on which the damper acted
  double max_damping_n_s_per_m = 0.0;  ///< the largest α used
};

class PassivityController {
 public:
  /// Default: the bound on α (estimate). A damper acting on a velocity one tick old stays stable
  /// on a handle of mass m while α dt / m < 1: 50 N s/m for 50 g of hand and arm at 1 kHz; a
  /// fifth of that.
  static constexpr double kMaxDampingNsPerM = 10.0;

  PassivityController() = default;
  /// `control` false: observe only (apply() returns the force unchanged), to show what the
  /// controller guards against. `leak_s` > 0: the energy absorbed (E > 0) leaks away with this
  /// time constant, so that what the rendering dissipated long ago cannot pay for its activity
  /// now (a sustained oscillation that feeds the hand a little energy every cycle); a deficit
  /// (E < 0) never leaks. 0: the plain observer.
  explicit PassivityController(double max_damping_n_s_per_m, bool control = true,
                               double leak_s = 0.0)
      : max_damping_(max_damping_n_s_per_m), control_(control), leak_s_(leak_s) {}

  /// Real time, once a tick: observes the last tick's exchange with the handle now at
  /// `handle_W`, and returns `wanted_W` with the damper added where the simulation would give
  /// more than it took, its norm at most `max_force_n` (beyond which the damper is cut: the
  /// deficit carries to the next tick). Non-finite inputs return `wanted_W` unchanged.
  [[nodiscard]] Eigen::Vector3d apply(const Eigen::Vector3d& handle_W,
                                      const Eigen::Vector3d& wanted_W, double dt,
                                      double max_force_n) noexcept;
  /// Real time: the force actually sent this tick (after apply(); the watchdog may have zeroed
  /// it), held until the next tick's observation.
  void sent(const Eigen::Vector3d& force_W) noexcept;
  /// Real time: the handle was not read this tick (a non-finite sample): the next tick observes
  /// nothing across the gap.
  void skip() noexcept { has_handle_ = false; }

  [[nodiscard]] const PassivityFigures& figures() const { return figures_; }

 private:
  double max_damping_ = kMaxDampingNsPerM;
  bool control_ = true;
  double leak_s_ = 0.0;
  Eigen::Vector3d handle_W_ = Eigen::Vector3d::Zero();  ///< at the last tick
  Eigen::Vector3d sent_W_ = Eigen::Vector3d::Zero();    ///< held since the last tick
  bool has_handle_ = false;
  PassivityFigures figures_;
};

}  // namespace lap::hardware
