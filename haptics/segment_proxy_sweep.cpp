// The segment proxy's exact swept check (§5.3): the ideal probe's motion in one placement pass
// against every object, end point paths against faces (A.7) and the moving segment against
// convex edges (A.8), from the sweep cache when it covers the motion, else through the trees.

#include <algorithm>
#include <array>
#include <cmath>

#include "haptics/segment_contact_geometry.h"
#include "haptics/segment_proxy.h"
#include "haptics/segment_segment.h"
#include "haptics/segment_triangle.h"

namespace lap::haptics {

// The earliest hit of one swept check so far (`best`, the time of the motion in [0, 1]; 2:
// none) and the constraint it becomes (*hit).
struct SegmentProxy::SweptHit {
  std::span<const HapticObject> objects;
  SegmentConstraint* hit = nullptr;
  double best = 2.0;

  // End point `end` (0: a, 1: b) of the probe, moving p0 -> p1 in object k's frame, crosses face
  // f at time t from its front (side +1) or its back (-1, two-sided surfaces).
  void face(int32_t k, int32_t f, int end, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
            double t, int8_t side) {
    best = t;
    hit->object = k;
    hit->feature = {PrimitiveKind::kFace, f};
    hit->at_end = true;
    hit->side = side;
    hit->u = end;
    hit->point_O = lerp(p0, p1, t);
    hit->normal_O = static_cast<double>(side) * objects[k].segments->mesh().face_normal(f);
  }

  // The probe, moving (A0, B0) -> (A1, B1) in object k's frame, crosses edge e as h says.
  void edge(int32_t k, int32_t e, const MovingSegmentHit& h, const Eigen::Vector3d& A0,
            const Eigen::Vector3d& B0, const Eigen::Vector3d& A1, const Eigen::Vector3d& B1) {
    best = h.tau;
    const SegmentDatabase& sd = *objects[k].segments;
    const MeshDatabase& m = sd.mesh();
    const Eigen::Vector3d at = lerp(A0, A1, h.tau);
    const Eigen::Vector3d bt = lerp(B0, B1, h.tau);
    const auto& ev = m.edge_vertices(e);
    const Eigen::Vector3d q = lerp(m.position(ev[0]), m.position(ev[1]), h.v);
    hit->object = k;
    hit->feature = {PrimitiveKind::kEdge, e};
    hit->at_end = false;
    hit->u = h.u;
    hit->point_O = q;
    // The side the probe came from orients boundary edges.
    hit->normal_O = edge_contact_normal(m, e, sd.convex_side(e), bt - at, lerp(A0, B0, h.u) - q);
    if (h.u <= 0.0 || h.u >= 1.0) {
      // An end point met the edge: track it as a point contact, on the side it came from.
      hit->at_end = true;
      hit->u = h.u <= 0.0 ? 0.0 : 1.0;
      hit->side = hit->normal_O.dot(m.normal(hit->feature)) >= 0.0 ? 1 : -1;
    }
  }
};

// Exact swept check of the ideal probe's motion (a0, b0) -> (a1, b1) against every object: end
// point paths against faces (A.7), the moving segment against convex edges (A.8). In the first
// pass objects move from their previous pose, so a moving organ cannot sweep through the probe.
// The candidates come from the sweep cache when it covers the motion, else from the trees.
bool SegmentProxy::sweep(std::span<const HapticObject> objects, bool first_pass,
                         const Eigen::Vector3d& a0, const Eigen::Vector3d& b0,
                         const Eigen::Vector3d& a1, const Eigen::Vector3d& b1, double* tau,
                         SegmentConstraint* hit) noexcept {
  SweptHit first{objects, hit};
  bool moving = false;
  if (first_pass) {
    for (const HapticObject& o : objects) {
      moving = moving || o.pose_WO.matrix() != o.prev_pose_WO.matrix();
    }
  }
  if (!moving && settings_.sweep_cache) {
    double f = 1.0;
    if (sweep_cached(objects, a0, b0, a1, b1, &first, &f) && (first.best <= 1.0 || f == 1.0)) {
      ++stats_.cached_sweeps;
      *tau = first.best <= 1.0 ? f * first.best : first.best;
      return first.best <= 1.0;
    }
  }
  ++stats_.tree_sweeps;
  sweep_trees(objects, first_pass, a0, b0, a1, b1, &first);
  *tau = first.best;
  return first.best <= 1.0;
}

// A long motion (a jerk of the tool, the first passes of a deep push, a probe held against a fold
// it cannot pass) would outgrow any cache: the cache checks its first kCacheMaxMotion, the
// fraction *f of the motion. The end points move linearly in time, so a hit there is the first
// hit of the whole motion; only a clear start sends the whole motion to the trees.
bool SegmentProxy::sweep_cached(std::span<const HapticObject> objects, const Eigen::Vector3d& a0,
                                const Eigen::Vector3d& b0, const Eigen::Vector3d& a1,
                                const Eigen::Vector3d& b1, SweptHit* first, double* f) noexcept {
  const double motion = std::max((a1 - a0).norm(), (b1 - b0).norm());
  *f = motion > kCacheMaxMotion ? kCacheMaxMotion / motion : 1.0;
  const Eigen::Vector3d af = lerp(a0, a1, *f);
  const Eigen::Vector3d bf = lerp(b0, b1, *f);
  bool covered = cache_covers(objects, a0, b0, af, bf);
  if (!covered) {
    covered =
        fill_cache(objects, a0, b0, std::max(cache_growth_ * (af - a0).norm(), kCacheMinRadius),
                   std::max(cache_growth_ * (bf - b0).norm(), kCacheMinRadius)) &&
        cache_covers(objects, a0, b0, af, bf);
  }
  if (covered) sweep_cached_primitives(objects, a0, b0, af, bf, first);
  return covered;
}

void SegmentProxy::sweep_cached_primitives(std::span<const HapticObject> objects,
                                           const Eigen::Vector3d& a0, const Eigen::Vector3d& b0,
                                           const Eigen::Vector3d& af, const Eigen::Vector3d& bf,
                                           SweptHit* first) noexcept {
  // How far any point of the probe gets from its cached position during the motion (the end
  // points move linearly, so the farthest is at a start or an end, and every point of the probe
  // is a convex combination of the end points); a small slack keeps the skip clear of the
  // crossing tests' own rounding.
  constexpr double kSlack = 1e-8;
  const double reach_a =
      std::sqrt(std::max((a0 - cache_.a).squaredNorm(), (af - cache_.a).squaredNorm())) + kSlack;
  const double reach_b =
      std::sqrt(std::max((b0 - cache_.b).squaredNorm(), (bf - cache_.b).squaredNorm())) + kSlack;
  const double reach = std::max(reach_a, reach_b);
  std::array<Eigen::Vector3d, kCacheObjects> A0;
  std::array<Eigen::Vector3d, kCacheObjects> B0;
  std::array<Eigen::Vector3d, kCacheObjects> A1;
  std::array<Eigen::Vector3d, kCacheObjects> B1;
  for (int32_t k = 0; k < cache_.object_count; ++k) {
    const Eigen::Isometry3d inv = objects[k].pose_WO.inverse();
    A0[k] = inv * a0;
    B0[k] = inv * b0;
    A1[k] = inv * af;
    B1[k] = inv * bf;
  }
  for (int end = 0; end < 2; ++end) {
    for (int32_t i = 0; i < cache_.face_count[end]; ++i) {
      const CachedFace& c = cache_.faces[end][i];
      if (c.clearance > (end == 0 ? reach_a : reach_b)) continue;
      ++stats_.cached_tests;
      const Eigen::Vector3d& p0 = end == 0 ? A0[c.object] : B0[c.object];
      const Eigen::Vector3d& p1 = end == 0 ? A1[c.object] : B1[c.object];
      int8_t side = 1;
      const double t = crossing_time(p0, p1, c.n, c.two_sided, c.p[0], c.vertex[0], c.p[1],
                                     c.vertex[1], c.p[2], c.vertex[2], &side);
      if (t >= 0.0 && t < first->best) first->face(c.object, c.index, end, p0, p1, t, side);
    }
  }
  for (int32_t i = 0; i < cache_.edge_count; ++i) {
    const CachedEdge& c = cache_.edges[i];
    if (c.clearance > reach) continue;
    ++stats_.cached_tests;
    const int32_t k = c.object;
    const MovingSegmentHit h = moving_segment_enters_edge(A0[k], B0[k], A1[k], B1[k], c.c, c.d,
                                                          c.closed ? &c.outward : nullptr);
    if (h.hit && h.tau < first->best) first->edge(k, c.index, h, A0[k], B0[k], A1[k], B1[k]);
  }
}

void SegmentProxy::sweep_trees(std::span<const HapticObject> objects, bool first_pass,
                               const Eigen::Vector3d& a0, const Eigen::Vector3d& b0,
                               const Eigen::Vector3d& a1, const Eigen::Vector3d& b1,
                               SweptHit* first) const noexcept {
  for (int32_t k = 0; k < static_cast<int32_t>(objects.size()); ++k) {
    const HapticObject& o = objects[k];
    if (o.segments == nullptr) continue;
    const SegmentDatabase& sd = *o.segments;
    const Eigen::Isometry3d inv1 = o.pose_WO.inverse();
    const Eigen::Isometry3d inv0 = first_pass ? o.prev_pose_WO.inverse() : inv1;
    const Eigen::Vector3d A0 = inv0 * a0;
    const Eigen::Vector3d B0 = inv0 * b0;
    const Eigen::Vector3d A1 = inv1 * a1;
    const Eigen::Vector3d B1 = inv1 * b1;
    for (int end = 0; end < 2; ++end) {
      const Eigen::Vector3d& p0 = end == 0 ? A0 : B0;
      const Eigen::Vector3d& p1 = end == 0 ? A1 : B1;
      double t = 1.0;
      int8_t side = 1;
      const int32_t f = sd.first_face_crossing(p0, p1, &t, &side);
      if (f >= 0 && t < first->best) first->face(k, f, end, p0, p1, t, side);
    }
    MovingSegmentHit h;
    const int32_t e = sd.first_edge_crossing(A0, B0, A1, B1, &h.tau, &h.u, &h.v);
    if (e >= 0 && h.tau < first->best) first->edge(k, e, h, A0, B0, A1, B1);
  }
}

}  // namespace lap::haptics
