#include "models/incision_rim.h"

#include <cmath>
#include <numbers>

namespace lap::models {
namespace {

// How far inside the incision's ellipse a crossing is: below 1 inside.
double ellipse_measure(const IncisionRim& rim, const Eigen::Vector3d& p_D) {
  double dphi = std::atan2(p_D.y(), p_D.x()) - rim.angle_rad;
  dphi = std::remainder(dphi, 2.0 * std::numbers::pi);
  const double along = (p_D.z() - rim.z_m) / rim.half_length_m;
  const double around = rim.mid_radius_m * dphi / rim.half_width_m;
  return along * along + around * around;
}

}  // namespace

RimCrossing find_rim_crossing(const IncisionRim& rim,
                              std::span<const Eigen::Vector3d> positions) noexcept {
  RimCrossing best;
  if (!(rim.half_length_m > 0.0) || !(rim.half_width_m > 0.0) || !(rim.mid_radius_m > 0.0)) {
    return best;
  }
  double best_measure = 1.0;
  const double r2 = rim.mid_radius_m * rim.mid_radius_m;
  for (size_t i = 0; i + 1 < positions.size(); ++i) {
    const Eigen::Vector3d a = rim.pose_DW * positions[i];
    const Eigen::Vector3d b = rim.pose_DW * positions[i + 1];
    const double fa = a.head<2>().squaredNorm() - r2;
    const double fb = b.head<2>().squaredNorm() - r2;
    if (!((fa < 0.0) != (fb < 0.0))) continue;  // both inside the mid-surface or both outside
    // |a + t (b - a)|² = R² across the axis: the root in [0, 1] (one, as the signs differ).
    const Eigen::Vector2d d = (b - a).head<2>();
    const double qa = d.squaredNorm();
    const double qb = 2.0 * a.head<2>().dot(d);
    const double disc = qb * qb - 4.0 * qa * fa;
    if (!(qa > 0.0) || !(disc >= 0.0)) continue;
    const double sq = std::sqrt(disc);
    double t = (-qb + sq) / (2.0 * qa);
    if (t < 0.0 || t > 1.0) t = (-qb - sq) / (2.0 * qa);
    if (!(t >= 0.0 && t <= 1.0)) continue;
    const Eigen::Vector3d p = a + t * (b - a);
    if (p.z() < 0.0 || p.z() > rim.length_m) continue;
    const double m = ellipse_measure(rim, p);
    if (m < best_measure) {
      best_measure = m;
      best = {static_cast<int32_t>(i), t, p};
    }
  }
  return best;
}

bool hold_at_incision(const IncisionRim& rim, const CatheterModel& model,
                      CatheterState* state) noexcept {
  const RimCrossing c = find_rim_crossing(rim, state->positions);
  if (c.segment < 0) return false;
  const auto i = static_cast<size_t>(c.segment);
  const Eigen::Vector3d axis = state->positions[i + 1] - state->positions[i];
  if (!(axis.norm() > 0.0)) return false;
  const Eigen::Vector3d centre_D(rim.mid_radius_m * std::cos(rim.angle_rad),
                                 rim.mid_radius_m * std::sin(rim.angle_rad), rim.z_m);
  CenterlineAnchor anchor;
  anchor.segment = c.segment;
  anchor.t = c.t;
  anchor.target_W = rim.pose_DW.inverse() * centre_D;
  anchor.stiffness_n_per_m = rim.stiffness_n_per_m;
  anchor.damping_n_s_per_m = rim.damping_n_s_per_m;
  const int32_t first = state->anchor_count;
  if (!add_anchor(model, anchor, state)) return false;
  // No limit along the catheter: it slides through the rim; held across it only.
  if (add_anchor_friction(axis.normalized(), 0.0, first, state) < 0) {
    state->anchor_count = first;
    return false;
  }
  return true;
}

}  // namespace lap::models
