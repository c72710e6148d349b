#pragma once
/// \file
/// The camera assistant (§7.8's camera, driven as a human assistant drives it): keeps the
/// instruments' working point — the middle of their tips — in the middle of the picture, and
/// both tips in view, by pivoting the scope about its port and sliding it in or out.
///
/// Like an assistant it does not chase every tremor: it starts to follow only when the working
/// point has drifted more than `dead_zone` off the line of sight and follows until it is back
/// within a quarter of that; it closes a fraction 1 − exp(−dt / τ) of the remaining angle per
/// step, so the view glides (a first-order lag) instead of jumping. Distance: when the tips
/// spread beyond `widest` of the half view angle it withdraws the scope, and when they gather
/// within `closest` of it it goes in, at the same rate, within the scope's insertion limits.
///
/// Deterministic and pure (Eigen only): the graphics loop steps it with its frame time.

#include <Eigen/Core>
#include <span>

#include "sim/runtime/laparoscope.h"

namespace lap::sim {

struct CameraAssistantSettings {
  /// Time constant of the follow [s] (estimate: an assistant re-centres in about a second).
  double time_constant_s = 0.4;
  /// Off-centre angle of the working point that starts a follow, as a fraction of the half view
  /// angle (estimate: a tenth of the picture's height).
  double dead_zone = 0.2;
  /// The tips' spread (the larger angle from the working point to a tip, seen from the eye) the
  /// assistant keeps between these fractions of the half view angle.
  double closest = 0.25;
  double widest = 0.7;
  /// The scope's tip kept at least this far from the working point [m] (estimate: a hand's
  /// width of working room under a 5-10 cm working distance).
  double min_distance_m = 0.04;
};

class CameraAssistant {
 public:
  explicit CameraAssistant(const CameraAssistantSettings& settings = {}) : settings_(settings) {}

  /// One step of `dt_s` towards keeping `tips_W` (one or two instrument tips) in view. Returns
  /// whether the scope moved.
  bool step(const LaparoscopeModel& model, LaparoscopeState* state,
            std::span<const Eigen::Vector3d> tips_W, double dt_s);

  /// Forgets a follow under way (when switched on again).
  void reset() { following_ = false; }
  [[nodiscard]] bool following() const { return following_; }
  [[nodiscard]] const CameraAssistantSettings& settings() const { return settings_; }

 private:
  CameraAssistantSettings settings_;
  bool following_ = false;
};

}  // namespace lap::sim
