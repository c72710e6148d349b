#pragma once
/// \file
/// Segment–segment geometry for the ray-based probe (thesis Appendix A.4, A.6, A.8):
/// closest points between two segments, and the exact first time a moving segment crosses a
/// static one. Header-only and allocation-free: both run in the haptic step.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace lap::haptics {

/// Closest points between segments p(s) = p0 + s (p1 - p0) and q(t) = q0 + t (q1 - q0),
/// s, t in [0, 1] (A.6, computed directly rather than by the projection of the appendix).
struct SegmentPair {
  double s = 0.0;
  double t = 0.0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
};

inline SegmentPair closest_segment_segment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                           const Eigen::Vector3d& q0, const Eigen::Vector3d& q1) {
  const Eigen::Vector3d d1 = p1 - p0;
  const Eigen::Vector3d d2 = q1 - q0;
  const Eigen::Vector3d r = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  SegmentPair out;
  double s = 0.0;
  double t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
    s = t = 0.0;
  } else if (a <= 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;  // >= 0; zero when parallel
      s = denom > 1e-300 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  out.s = s;
  out.t = t;
  out.p = p0 + s * d1;
  out.q = q0 + t * d2;
  return out;
}

/// First crossing of a moving segment with a static segment (A.8). The moving segment's end
/// points travel linearly: a(τ) = a0 + τ (a1 - a0), b(τ) = b0 + τ (b1 - b0), τ in [0, 1]. The
/// lines of ab(τ) and cd are coplanar where the triple product
///   g(τ) = ((b(τ) - a(τ)) × (d - c)) · (a(τ) - c)
/// vanishes, a quadratic in τ; a crossing is a sign change of g at which the two segments
/// actually meet (both line parameters in [0, 1]). Unlike the appendix's approximation this is
/// exact for any motion of the end points, so no tolerance on the step size is needed.
/// Lines that stay coplanar for the whole tick (g identically zero: a probe moving within the
/// plane of the edge) are not a crossing.
///
/// With `outward` (the edge's outward normal, perpendicular to cd) only *entering* crossings
/// count: those after which the part of the probe line near the edge is on the inner side, i.e.
/// g'(τ) (b - a) × (d - c) · outward < 0. A probe that starts a hair inside the edge line (by
/// rounding) and moves out is then not stopped at τ = 0. Where the probe crosses nearly head-on
/// (its line in the plane of the edge and `outward`, so neither side is outside) every crossing
/// counts.
///
/// With `interior_only`, a meeting at an end of the moving segment does not count: for the
/// segment proxy that is an end point reaching an edge, which the end point's own face crossing
/// (A.7, watertight) already catches. Counted, a probe whose tip rests exactly on an edge
/// (pressed onto a convex crease) "met" the edge again at τ = 0 whenever it turned about its tip,
/// and the ideal probe stayed stuck there while the hand went on.
struct MovingSegmentHit {
  bool hit = false;
  double tau = 0.0;  ///< time of the crossing in [0, 1]
  double u = 0.0;    ///< where on the moving segment (0 at a, 1 at b)
  double v = 0.0;    ///< where on the static segment (0 at c, 1 at d)
};

inline MovingSegmentHit moving_segment_crosses_segment(
    const Eigen::Vector3d& a0, const Eigen::Vector3d& b0, const Eigen::Vector3d& a1,
    const Eigen::Vector3d& b1, const Eigen::Vector3d& c, const Eigen::Vector3d& d,
    const Eigen::Vector3d* outward = nullptr, bool interior_only = false) {
  MovingSegmentHit out;
  const Eigen::Vector3d e = d - c;
  const Eigen::Vector3d w0 = b0 - a0;
  const Eigen::Vector3d w1 = (b1 - a1) - w0;  // d/dτ of b - a
  const Eigen::Vector3d p0 = a0 - c;
  const Eigen::Vector3d p1 = a1 - a0;  // d/dτ of a - c
  const Eigen::Vector3d m0 = w0.cross(e);
  const Eigen::Vector3d m1 = w1.cross(e);
  const double k0 = m0.dot(p0);
  const double k1 = m1.dot(p0) + m0.dot(p1);
  const double k2 = m1.dot(p1);
  // Every root in [0, 1] where the segments actually meet is a contact, the earliest first. A
  // touch without a sign change (resting exactly on the edge) also counts: being conservative
  // there only stops the motion at a contact the proxy already has.
  // Roots of k2 τ² + k1 τ + k0 in (0, 1], smallest first (numerically stable form).
  double roots[2];
  int count = 0;
  const double scale = std::abs(k0) + std::abs(k1) + std::abs(k2);
  if (!(scale > 0.0)) return out;
  if (std::abs(k2) <= 1e-14 * scale) {
    if (k1 != 0.0) roots[count++] = -k0 / k1;
  } else {
    const double disc = k1 * k1 - 4.0 * k2 * k0;
    if (disc < 0.0) return out;
    const double sq = std::sqrt(disc);
    const double qq = -0.5 * (k1 + std::copysign(sq, k1));
    const double r1 = qq / k2;
    const double r2 = qq != 0.0 ? k0 / qq : r1;
    roots[count++] = std::min(r1, r2);
    roots[count++] = std::max(r1, r2);
  }
  for (int i = 0; i < count; ++i) {
    const double tau = roots[i];
    if (!(tau >= 0.0 && tau <= 1.0)) continue;
    const Eigen::Vector3d a = a0 + tau * (a1 - a0);
    const Eigen::Vector3d b = b0 + tau * (b1 - b0);
    {
      // Cheap rejection first: where the (coplanar) lines meet, from the 2x2 normal equations;
      // far outside either segment is no crossing. Near-parallel lines take the full test.
      const Eigen::Vector3d w = b - a;
      const Eigen::Vector3d r = a - c;
      const double ww = w.dot(w);
      const double we = w.dot(e);
      const double ee = e.dot(e);
      const double wr = w.dot(r);
      const double er = e.dot(r);
      const double denom = ww * ee - we * we;
      if (denom > 1e-12 * ww * ee) {
        const double s_line = (we * er - ee * wr) / denom;
        const double t_line = (ww * er - we * wr) / denom;
        constexpr double kSlack = 1e-6;
        if (s_line < -kSlack || s_line > 1.0 + kSlack || t_line < -kSlack ||
            t_line > 1.0 + kSlack) {
          continue;
        }
      }
    }
    const SegmentPair cp = closest_segment_segment(a, b, c, d);
    // At a true crossing the closest points coincide; allow rounding relative to the lengths.
    const double tol = 1e-9 * ((b - a).norm() + e.norm()) + 1e-15;
    if ((cp.p - cp.q).norm() > tol) continue;
    if (interior_only && (cp.s <= 0.0 || cp.s >= 1.0)) continue;
    if (outward != nullptr) {
      const Eigen::Vector3d m = (b - a).cross(e);
      const double side = m.dot(*outward);
      const double slope = 2.0 * k2 * tau + k1;
      if (std::abs(side) > 1e-9 * m.norm() && slope * side >= 0.0) continue;  // leaving
    }
    out.hit = true;
    out.tau = tau;
    out.u = cp.s;
    out.v = cp.t;
    return out;
  }
  return out;
}

/// A.8 against a mesh edge: every crossing of a boundary edge (outward == nullptr: an open
/// surface has no inside), only entering ones elsewhere. The orientation test runs only when
/// there is a crossing at all. Meetings at the probe's ends are left to the faces (interior_only).
inline MovingSegmentHit moving_segment_enters_edge(
    const Eigen::Vector3d& a0, const Eigen::Vector3d& b0, const Eigen::Vector3d& a1,
    const Eigen::Vector3d& b1, const Eigen::Vector3d& c, const Eigen::Vector3d& d,
    const Eigen::Vector3d* outward) {
  const MovingSegmentHit any = moving_segment_crosses_segment(a0, b0, a1, b1, c, d, nullptr, true);
  if (!any.hit || outward == nullptr) return any;
  return moving_segment_crosses_segment(a0, b0, a1, b1, c, d, outward, true);
}

}  // namespace lap::haptics
