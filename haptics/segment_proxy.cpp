#include "haptics/segment_proxy.h"

#include <algorithm>
#include <cmath>

#include "haptics/closest_point.h"
#include "haptics/probe_placement_qp.h"
#include "haptics/segment_segment.h"
#include "haptics/segment_triangle.h"

namespace lap::haptics {
namespace {

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

Eigen::Vector3d lerp(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double u) {
  return a + u * (b - a);
}

// The α/β test of Figure 5-9, as a normal cone: the plane of a segment–edge contact (normal m,
// perpendicular to the edge) is a supporting plane only while m lies between the normals n1, n2
// of the edge's two faces. Past one of them the probe would cut that face: the contact becomes
// segment–face and takes the face's normal. Returns true when m was clamped.
bool clamp_to_normal_cone(const Eigen::Vector3d& axis, const Eigen::Vector3d& n1,
                          const Eigen::Vector3d& n2, Eigen::Vector3d* m) {
  const double s12 = n1.cross(n2).dot(axis);
  const double s1 = n1.cross(*m).dot(axis);  // α side
  const double s2 = m->cross(n2).dot(axis);  // β - α side
  const bool inside = (s12 >= 0.0) ? (s1 >= 0.0 && s2 >= 0.0) : (s1 <= 0.0 && s2 <= 0.0);
  if (inside) return false;
  *m = m->dot(n1) >= m->dot(n2) ? n1 : n2;
  return true;
}

// Outward normal of a segment–edge contact for a probe along w touching edge e (Figure 5-13b):
// perpendicular to both, on the side of the edge's own normal; the edge normal itself when the
// probe is parallel to the edge. `side` orients boundary edges (open surfaces: either side).
Eigen::Vector3d edge_contact_normal(const MeshDatabase& mesh, int32_t e, const Eigen::Vector3d& w,
                                    const Eigen::Vector3d& side) {
  const auto& ev = mesh.edge_vertices(e);
  const auto& ef = mesh.edge_faces(e);
  const Eigen::Vector3d axis = mesh.position(ev[1]) - mesh.position(ev[0]);
  // The edge normal is the normalised sum of its faces' normals (MeshDatabase::edge_normal),
  // computed here from the two normals the cone test needs anyway; orienting m needs only the
  // sum's direction, so it is normalised only when it is the answer.
  const Eigen::Vector3d& n1 = mesh.face_normal(ef[0]);
  const bool boundary = ef[1] < 0;
  const Eigen::Vector3d& n2 = boundary ? n1 : mesh.face_normal(ef[1]);
  const Eigen::Vector3d sum = n1 + n2;
  Eigen::Vector3d m = w.cross(axis);
  const double norm2 = m.squaredNorm();
  if (!(norm2 > 1e-18 * w.squaredNorm() * axis.squaredNorm())) {
    const double sum_norm = sum.norm();
    return sum_norm > 0.0 ? Eigen::Vector3d(sum / sum_norm) : n1;
  }
  m /= std::sqrt(norm2);
  const double orient = boundary ? m.dot(side) : m.dot(sum);
  if (orient < 0.0) m = -m;
  if (!boundary) clamp_to_normal_cone(axis, n1, n2, &m);
  return m;
}

// The part [u0, u1] of the probe (a, b, object frame) whose projection on face f's plane lies on
// f's flat "face" (f and the faces among its PCPs): the contour points A and B of Figure 5-13c.
// Returns false when no part does.
bool portion_on_face(const SegmentDatabase& sd, int32_t f, const Eigen::Vector3d& a,
                     const Eigen::Vector3d& b, double* u0, double* u1) {
  const MeshDatabase& m = sd.mesh();
  const Eigen::Vector3d& n = m.face_normal(f);
  double lo = 2.0;
  double hi = -1.0;
  auto clip = [&](int32_t g) {
    const auto& v = m.face_vertices(g);
    double t0 = 0.0;
    double t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& p = m.position(v[k]);
      const Eigen::Vector3d inward = n.cross(m.position(v[(k + 1) % 3]) - p);  // in-plane
      const double g0 = inward.dot(a - p);
      const double g1 = inward.dot(b - a);
      if (g1 == 0.0) {
        if (g0 < 0.0) return;
      } else {
        const double t = -g0 / g1;
        if (g1 > 0.0) {
          t0 = std::max(t0, t);
        } else {
          t1 = std::min(t1, t);
        }
      }
    }
    if (t0 > t1) return;
    lo = std::min(lo, t0);
    hi = std::max(hi, t1);
  };
  clip(f);
  for (const PrimitiveRef& p : sd.face_pcps(f)) {
    if (p.kind == PrimitiveKind::kFace) clip(p.index);
  }
  if (lo > hi) return false;
  *u0 = lo;
  *u1 = hi;
  return true;
}

// The face a contact lies on when the probe is within θε of its plane: the end point's face,
// or the edge face whose normal the contact normal has taken (the α/β clamp). -1: none.
int32_t face_of_contact(const MeshDatabase& m, const SegmentConstraint& c, double cos_eps) {
  if (c.feature.kind == PrimitiveKind::kFace) return c.feature.index;
  if (c.feature.kind == PrimitiveKind::kEdge) {
    for (int32_t f : m.edge_faces(c.feature.index)) {
      if (f >= 0 && m.face_normal(f).dot(c.normal_O) >= cos_eps) return f;
    }
  }
  return -1;
}

}  // namespace

const char* to_string(SegmentContactKind kind) {
  switch (kind) {
    case SegmentContactKind::kPointPolygon:
      return "point-polygon";
    case SegmentContactKind::kSegmentEdge:
      return "segment-edge";
    case SegmentContactKind::kSegmentFace:
      return "segment-face";
  }
  return "?";
}

void SegmentProxy::reset(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W) {
  ideal_a_ = virtual_a_ = prev_virtual_a_ = a_W;
  ideal_b_ = virtual_b_ = prev_virtual_b_ = b_W;
  constraint_count_ = 0;
  contact_count_ = 0;
  initialised_ = true;
}

void SegmentProxy::remove_constraint(int i) {
  constraints_[i] = constraints_[constraint_count_ - 1];
  --constraint_count_;
}

bool SegmentProxy::add_constraint(const SegmentConstraint& c) {
  for (int i = 0; i < constraint_count_; ++i) {
    SegmentConstraint& k = constraints_[i];
    if (k.object == c.object && k.feature == c.feature && k.at_end == c.at_end &&
        (!c.at_end || k.u == c.u)) {
      const bool same = std::abs(k.u - c.u) < 1e-9 && (k.point_W - c.point_W).norm() < 1e-12 &&
                        k.normal_W.dot(c.normal_W) > 1.0 - 1e-12;
      const bool hold = k.face_hold;
      k = c;
      k.face_hold = hold;
      return !same;
    }
  }
  if (constraint_count_ == kMaxConstraints) {
    ++stats_.constraint_overflows;
    return false;
  }
  constraints_[constraint_count_++] = c;
  return true;
}

// Local search for every constraint (§5.3, PCPs only), against the new virtual probe.
void SegmentProxy::track(std::span<const HapticObject> objects) {
  for (int i = constraint_count_ - 1; i >= 0; --i) {
    SegmentConstraint& c = constraints_[i];
    if (c.object < 0 || c.object >= static_cast<int32_t>(objects.size()) ||
        objects[c.object].segments == nullptr) {
      remove_constraint(i);
      continue;
    }
    const HapticObject& o = objects[c.object];
    const SegmentDatabase& sd = *o.segments;
    const MeshDatabase& m = sd.mesh();
    const Eigen::Isometry3d inv = o.pose_WO.inverse();
    const Eigen::Vector3d a = inv * virtual_a_;
    const Eigen::Vector3d b = inv * virtual_b_;
    if (!c.at_end) {
      // Segment–edge: the closest points of probe and edge; past an end of the edge, move to
      // the contactable edge at that vertex the probe now crosses most deeply (edge PCPs).
      int32_t e = c.feature.index;
      auto pair_of = [&](int32_t g) {
        const auto& ev = m.edge_vertices(g);
        return closest_segment_segment(a, b, m.position(ev[0]), m.position(ev[1]));
      };
      SegmentPair cp = pair_of(e);
      if (cp.t <= 0.0 || cp.t >= 1.0) {
        double best = (cp.q - cp.p).squaredNorm();
        for (const PrimitiveRef& p : sd.edge_pcps(e)) {
          if (p.kind != PrimitiveKind::kEdge) continue;
          const SegmentPair cq = pair_of(p.index);
          if (cq.t <= 0.0 || cq.t >= 1.0) continue;
          const double d2 = (cq.q - cq.p).squaredNorm();
          if (d2 < best) {
            best = d2;
            e = p.index;
            cp = cq;
          }
        }
      }
      if (cp.s <= 0.0 || cp.s >= 1.0) {
        // The probe's end has reached the edge (Figure 5-9c): a point contact from here on.
        c.at_end = true;
        c.u = cp.s <= 0.0 ? 0.0 : 1.0;
        c.feature = {PrimitiveKind::kEdge, e};
      } else {
        const Eigen::Vector3d side = inv * lerp(ideal_a_, ideal_b_, cp.s) - cp.q;
        c.feature = {PrimitiveKind::kEdge, e};
        c.u = cp.s;
        c.point_O = cp.q;
        c.normal_O = edge_contact_normal(m, e, b - a, side);
      }
    }
    if (c.at_end) {
      // Point–polygon: the end point's own Neighborhood Watch (chapter 4).
      const Eigen::Vector3d p = c.u == 0.0 ? a : b;
      Eigen::Vector3d q;
      int32_t rounds = 0;
      c.feature = PointProxy::local_search(m, c.feature, p, &q, &rounds);
      c.point_O = q;
      c.normal_O = m.normal(c.feature);
    }
    const Eigen::Vector3d x = lerp(a, b, c.u);
    if (c.normal_O.dot(x - c.point_O) > 0.0 && !c.face_hold) {
      remove_constraint(i);
      ++stats_.releases;
      continue;
    }
    c.point_W = o.pose_WO * c.point_O;
    c.normal_W = o.pose_WO.linear() * c.normal_O;
    // Two contacts that slid onto the same feature are one.
    for (int j = i + 1; j < constraint_count_; ++j) {
      const SegmentConstraint& k = constraints_[j];
      if (k.object == c.object && k.feature == c.feature && k.at_end == c.at_end &&
          (!c.at_end || k.u == c.u)) {
        remove_constraint(i);
        break;
      }
    }
  }
}

// The configuration nearest the virtual probe (least squares over the two end points) that
// keeps every constraint point outside its plane by the skin: a small convex QP, solved exactly
// (probe_placement_qp.h).
//
// A segment–edge constraint is really "the probe's line stays outside the edge's line", which
// the plane at a fixed u only linearises: once the probe turns, another point of it is nearest
// the edge. So the QP is solved once more with each edge constraint moved to the new nearest
// point (and its normal to the new probe direction); without this the swept check finds the same
// edge crossed at once and the placement makes no progress. Only once: on a nearly flat edge the
// nearest point does not settle but runs to an end of the probe, and a jaw re-linearised up to
// four times could stay caught on such an edge, pushing, after the tool had left the organ
// (ToolOnOrgans.NoForceOnceTheToolIsClearOfEveryOrgan). The constraints are still moved after
// the last solve, so the next pass starts from the new nearest points.
void SegmentProxy::place(std::span<const HapticObject> objects, const Eigen::Vector3d& a_W,
                         const Eigen::Vector3d& b_W, Eigen::Vector3d* a, Eigen::Vector3d* b) {
  constexpr int kSolves = 2;  // the first and the re-linearised one
  for (int outer = 0; outer < kSolves; ++outer) {
    solve_placement(a_W, b_W, a, b);
    bool moved = false;
    for (int i = 0; i < constraint_count_; ++i) {
      SegmentConstraint& c = constraints_[i];
      if (c.at_end || c.feature.kind != PrimitiveKind::kEdge) continue;
      const HapticObject& o = objects[c.object];
      const MeshDatabase& m = o.segments->mesh();
      const Eigen::Isometry3d inv = o.pose_WO.inverse();
      const Eigen::Vector3d pa = inv * *a;
      const Eigen::Vector3d pb = inv * *b;
      const auto& ev = m.edge_vertices(c.feature.index);
      const SegmentPair cp = closest_segment_segment(pa, pb, m.position(ev[0]), m.position(ev[1]));
      if (cp.s <= 0.0 || cp.s >= 1.0 || std::abs(cp.s - c.u) < 1e-9) continue;
      c.u = cp.s;
      c.point_O = cp.q;
      c.normal_O = edge_contact_normal(m, c.feature.index, pb - pa, c.normal_O);
      c.point_W = o.pose_WO * c.point_O;
      c.normal_W = o.pose_WO.linear() * c.normal_O;
      moved = true;
    }
    if (!moved) break;
  }
}

void SegmentProxy::solve_placement(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W,
                                   Eigen::Vector3d* a, Eigen::Vector3d* b) {
  ProbePlacementQp qp;
  for (int i = 0; i < constraint_count_; ++i) {
    const SegmentConstraint& c = constraints_[i];
    qp.add(c.normal_W, c.u, c.normal_W.dot(c.point_W) + settings_.skin_m);
  }
  uint32_t warm = 0;
  for (int i = 0; i < constraint_count_; ++i) {
    if (constraints_[i].lambda > 0.0) warm |= 1U << i;
  }
  const ProbePlacementSolution sol = solve_probe_placement(qp, a_W, b_W, warm);
  *a = sol.a;
  *b = sol.b;
  for (int i = 0; i < constraint_count_; ++i) constraints_[i].lambda = sol.lambda[i];
}

bool SegmentProxy::cache_covers(std::span<const HapticObject> objects, const Eigen::Vector3d& a0,
                                const Eigen::Vector3d& b0, const Eigen::Vector3d& a1,
                                const Eigen::Vector3d& b1) const {
  const SweepCache& c = cache_;
  if (!c.valid || c.object_count != static_cast<int32_t>(objects.size())) return false;
  const double ra2 = c.radius_a * c.radius_a;
  const double rb2 = c.radius_b * c.radius_b;
  if ((a0 - c.a).squaredNorm() >= ra2 || (a1 - c.a).squaredNorm() >= ra2 ||
      (b0 - c.b).squaredNorm() >= rb2 || (b1 - c.b).squaredNorm() >= rb2) {
    return false;
  }
  for (int32_t k = 0; k < c.object_count; ++k) {
    const HapticObject& o = objects[k];
    if (o.segments == nullptr) continue;
    if (&o.segments->mesh() != c.meshes[k] || o.segments->mesh().revision() != c.revisions[k] ||
        o.pose_WO.matrix().topRows<3>() != c.poses[k]) {
      return false;
    }
  }
  return true;
}

// Refills the sweep cache around the probe (a, b) for end-point motions up to ra and rb. A point
// of the probe at u then moves less than r(u) = (1 - u) ra + u rb, so the edges are gathered
// within that tapered capsule, covered by four capsules that are finer towards the slower end
// (a tool's tip moves slowly while its handle end swings).
bool SegmentProxy::fill_cache(std::span<const HapticObject> objects, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, double ra, double rb) {
  SweepCache& c = cache_;
  c.valid = false;
  if (objects.size() > static_cast<size_t>(kCacheObjects)) return false;
  ++stats_.cache_rebuilds;
  constexpr std::array<double, 5> kBreaks = {0.0, 1.0 / 64.0, 1.0 / 16.0, 1.0 / 4.0, 1.0};
  std::array<int32_t, kCacheEdges> scratch{};
  c.face_count = {0, 0};
  c.edge_count = 0;
  for (int32_t k = 0; k < static_cast<int32_t>(objects.size()); ++k) {
    const HapticObject& o = objects[k];
    if (o.segments == nullptr) continue;
    const SegmentDatabase& sd = *o.segments;
    const Eigen::Isometry3d inv = o.pose_WO.inverse();
    const Eigen::Vector3d A = inv * a;
    const Eigen::Vector3d B = inv * b;
    const MeshDatabase& m = sd.mesh();
    for (int end = 0; end < 2; ++end) {
      const Eigen::Vector3d& p = end == 0 ? A : B;
      const int32_t room = kCacheFaces - c.face_count[end];
      const int32_t n =
          sd.faces_near_point(p, end == 0 ? ra : rb, {scratch.data(), static_cast<size_t>(room)});
      if (n < 0) return false;
      for (int32_t i = 0; i < n; ++i) {
        CachedFace& cf = c.faces[end][c.face_count[end]++];
        cf.object = k;
        cf.index = scratch[i];
        cf.vertex = m.face_vertices(scratch[i]);
        for (int j = 0; j < 3; ++j) cf.p[j] = m.position(cf.vertex[j]);
        cf.n = (cf.p[1] - cf.p[0]).cross(cf.p[2] - cf.p[0]);
        TriangleFeature feature{};
        cf.clearance = (closest_on_triangle(p, cf.p[0], cf.p[1], cf.p[2], &feature) - p).norm();
      }
    }
    std::array<Capsule, kBreaks.size() - 1> pieces;
    for (size_t piece = 0; piece + 1 < kBreaks.size(); ++piece) {
      // Pieces measured from the slower end.
      double u0 = kBreaks[piece];
      double u1 = kBreaks[piece + 1];
      if (rb < ra) {
        u0 = 1.0 - kBreaks[piece + 1];
        u1 = 1.0 - kBreaks[piece];
      }
      pieces[piece] = {lerp(A, B, u0), lerp(A, B, u1),
                       std::max((1.0 - u0) * ra + u0 * rb, (1.0 - u1) * ra + u1 * rb)};
    }
    const int32_t room = kCacheEdges - c.edge_count;
    const int32_t n = sd.edges_near_capsules({A, B, std::max(ra, rb)}, pieces,
                                             {scratch.data(), static_cast<size_t>(room)});
    if (n < 0) return false;
    for (int32_t i = 0; i < n; ++i) {
      CachedEdge& ce = c.edges[c.edge_count++];
      ce.object = k;
      ce.index = scratch[i];
      const auto& ev = m.edge_vertices(scratch[i]);
      ce.c = m.position(ev[0]);
      ce.d = m.position(ev[1]);
      ce.closed = m.edge_faces(scratch[i])[1] >= 0;
      ce.outward = m.edge_normal(scratch[i]);
      const SegmentPair cp = closest_segment_segment(A, B, ce.c, ce.d);
      ce.clearance = (cp.p - cp.q).norm();
    }
    c.poses[k] = o.pose_WO.matrix().topRows<3>();
    c.revisions[k] = m.revision();
    c.meshes[k] = &m;
  }
  c.a = a;
  c.b = b;
  c.radius_a = ra;
  c.radius_b = rb;
  c.object_count = static_cast<int32_t>(objects.size());
  c.valid = true;
  const bool empty = c.face_count[0] + c.face_count[1] + c.edge_count == 0;
  cache_growth_ = empty ? std::min(2.0 * cache_growth_, kCacheMaxGrowth) : kCacheGrowth;
  return true;
}

// Exact swept check of the ideal probe's motion (a0, b0) -> (a1, b1) against every object: end
// point paths against faces (A.7), the moving segment against convex edges (A.8). In the first
// pass objects move from their previous pose, so a moving organ cannot sweep through the probe.
// The candidates come from the sweep cache when it covers the motion, else from the trees.
bool SegmentProxy::sweep(std::span<const HapticObject> objects, bool first_pass,
                         const Eigen::Vector3d& a0, const Eigen::Vector3d& b0,
                         const Eigen::Vector3d& a1, const Eigen::Vector3d& b1, double* tau,
                         SegmentConstraint* hit) {
  double best = 2.0;
  bool moving = false;
  if (first_pass) {
    for (const HapticObject& o : objects) {
      moving = moving || o.pose_WO.matrix() != o.prev_pose_WO.matrix();
    }
  }
  auto face_hit = [&](int32_t k, int32_t f, int end, const Eigen::Vector3d& p0,
                      const Eigen::Vector3d& p1, double t) {
    best = t;
    hit->object = k;
    hit->feature = {PrimitiveKind::kFace, f};
    hit->at_end = true;
    hit->u = end;
    hit->point_O = lerp(p0, p1, t);
    hit->normal_O = objects[k].segments->mesh().face_normal(f);
  };
  auto edge_hit = [&](int32_t k, int32_t e, const MovingSegmentHit& h, const Eigen::Vector3d& A0,
                      const Eigen::Vector3d& B0, const Eigen::Vector3d& A1,
                      const Eigen::Vector3d& B1) {
    best = h.tau;
    const MeshDatabase& m = objects[k].segments->mesh();
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
    hit->normal_O = edge_contact_normal(m, e, bt - at, lerp(A0, B0, h.u) - q);
    if (h.u <= 0.0 || h.u >= 1.0) {
      // An end point met the edge: track it as a point contact.
      hit->at_end = true;
      hit->u = h.u <= 0.0 ? 0.0 : 1.0;
    }
  };

  if (!moving && settings_.sweep_cache) {
    // A long motion (a jerk of the tool, the first passes of a deep push, a probe held against
    // a fold it cannot pass) would outgrow any cache: the cache checks its first
    // kCacheMaxMotion. The end points move linearly in time, so a hit there is the first hit of
    // the whole motion; only a clear start sends the whole motion to the trees.
    const double motion = std::max((a1 - a0).norm(), (b1 - b0).norm());
    const double f = motion > kCacheMaxMotion ? kCacheMaxMotion / motion : 1.0;
    const Eigen::Vector3d af = lerp(a0, a1, f);
    const Eigen::Vector3d bf = lerp(b0, b1, f);
    bool covered = cache_covers(objects, a0, b0, af, bf);
    if (!covered) {
      covered =
          fill_cache(objects, a0, b0, std::max(cache_growth_ * (af - a0).norm(), kCacheMinRadius),
                     std::max(cache_growth_ * (bf - b0).norm(), kCacheMinRadius)) &&
          cache_covers(objects, a0, b0, af, bf);
    }
    if (covered) {
      // How far any point of the probe gets from its cached position during the motion (the
      // end points move linearly, so the farthest is at a start or an end, and every point of
      // the probe is a convex combination of the end points); a small slack keeps the skip
      // clear of the crossing tests' own rounding.
      constexpr double kSlack = 1e-8;
      const double reach_a =
          std::sqrt(std::max((a0 - cache_.a).squaredNorm(), (af - cache_.a).squaredNorm())) +
          kSlack;
      const double reach_b =
          std::sqrt(std::max((b0 - cache_.b).squaredNorm(), (bf - cache_.b).squaredNorm())) +
          kSlack;
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
          const double t = front_crossing_time(p0, p1, c.n, c.p[0], c.vertex[0], c.p[1],
                                               c.vertex[1], c.p[2], c.vertex[2]);
          if (t >= 0.0 && t < best) face_hit(c.object, c.index, end, p0, p1, t);
        }
      }
      for (int32_t i = 0; i < cache_.edge_count; ++i) {
        const CachedEdge& c = cache_.edges[i];
        if (c.clearance > reach) continue;
        ++stats_.cached_tests;
        const int32_t k = c.object;
        const MovingSegmentHit h = moving_segment_enters_edge(A0[k], B0[k], A1[k], B1[k], c.c, c.d,
                                                              c.closed ? &c.outward : nullptr);
        if (h.hit && h.tau < best) edge_hit(k, c.index, h, A0[k], B0[k], A1[k], B1[k]);
      }
      if (best <= 1.0 || f == 1.0) {
        ++stats_.cached_sweeps;
        *tau = best <= 1.0 ? f * best : best;
        return best <= 1.0;
      }
    }
  }

  ++stats_.tree_sweeps;
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
      const int32_t f = sd.first_face_crossing(p0, p1, &t);
      if (f >= 0 && t < best) face_hit(k, f, end, p0, p1, t);
    }
    MovingSegmentHit h;
    const int32_t e = sd.first_edge_crossing(A0, B0, A1, B1, &h.tau, &h.u, &h.v);
    if (e >= 0 && h.tau < best) edge_hit(k, e, h, A0, B0, A1, B1);
  }
  *tau = best;
  return best <= 1.0;
}

SegmentProxyOutput SegmentProxy::step(std::span<const HapticObject> objects,
                                      const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W,
                                      double dt) noexcept {
  ++stats_.steps;
  SegmentProxyOutput out;
  if (!finite(a_W) || !finite(b_W) || !(dt > 0.0) || !std::isfinite(dt)) {
    ++stats_.faults;
    out.fault = true;
    initialised_ = false;
    constraint_count_ = contact_count_ = 0;
    return out;
  }
  if (!initialised_) reset(a_W, b_W);
  prev_virtual_a_ = virtual_a_;
  prev_virtual_b_ = virtual_b_;
  virtual_a_ = a_W;
  virtual_b_ = b_W;

  track(objects);

  // Move the ideal probe towards the virtual one: place, sweep, stop at a new contact, add it,
  // place again (§5.3 first contact and its continuation).
  Eigen::Vector3d sa = ideal_a_;
  Eigen::Vector3d sb = ideal_b_;
  bool clean = false;
  int32_t stalled_object = -1;
  PrimitiveRef stalled_feature;
  for (int pass = 0; pass < kMaxPlacements; ++pass) {
    Eigen::Vector3d ca;
    Eigen::Vector3d cb;
    place(objects, a_W, b_W, &ca, &cb);
    ++stats_.placements;
    // A pass moves each end point at most kMaxPassMotion, so that the swept check stays local
    // even when the virtual probe is far inside (the rest is done by the next passes).
    const double motion = std::max((ca - sa).norm(), (cb - sb).norm());
    const bool partial = motion > kMaxPassMotion;
    if (partial) {
      const double f = kMaxPassMotion / motion;
      ca = sa + f * (ca - sa);
      cb = sb + f * (cb - sb);
    }
    double tau = 2.0;
    SegmentConstraint hit;
    if (!sweep(objects, pass == 0, sa, sb, ca, cb, &tau, &hit)) {
      sa = ca;
      sb = cb;
      if (partial) continue;
      clean = true;
      break;
    }
    ++stats_.swept_hits;
    if (constraint_count_ == 0) ++stats_.first_contacts;
    // Stop just short of the contact (the rest of the way is re-planned with it as a
    // constraint), interpolating in the hit object's frame so a moving object is respected.
    const double s = std::max(0.0, tau - 1e-6);
    const HapticObject& o = objects[hit.object];
    const Eigen::Isometry3d inv0 = (pass == 0 ? o.prev_pose_WO : o.pose_WO).inverse();
    const Eigen::Isometry3d inv1 = o.pose_WO.inverse();
    sa = o.pose_WO * lerp(inv0 * sa, inv1 * ca, s);
    sb = o.pose_WO * lerp(inv0 * sb, inv1 * cb, s);
    hit.point_W = o.pose_WO * hit.point_O;
    hit.normal_W = o.pose_WO.linear() * hit.normal_O;
    // Two passes in a row stopped at once by the same feature make no progress: the probe stays
    // where it safely is for this tick (further passes would repeat the same placement).
    const bool changed = add_constraint(hit);
    if (s == 0.0 &&
        (!changed || (stalled_object == hit.object && stalled_feature == hit.feature))) {
      break;
    }
    stalled_object = s == 0.0 ? hit.object : -1;
    stalled_feature = hit.feature;
  }
  if (!clean) ++stats_.placement_limit_hits;
  ideal_a_ = sa;
  ideal_b_ = sb;

  respond(objects, dt, &out);
  if (!finite(out.force_W) || !finite(out.torque_W) || !finite(ideal_a_) || !finite(ideal_b_)) {
    ++stats_.faults;
    SegmentProxyOutput bad;
    bad.fault = true;
    reset(a_W, b_W);
    return bad;
  }
  return out;
}

// §5.4: group the constraints into the thesis' contacts, find each one's equilibrium point and
// spring force, and distribute the forces to the two ends.
void SegmentProxy::respond(std::span<const HapticObject> objects, double dt,
                           SegmentProxyOutput* out) {
  contact_count_ = 0;
  const double cos_eps = std::cos(settings_.theta_epsilon_rad);
  std::array<bool, kMaxConstraints> used{};
  for (int i = 0; i < constraint_count_; ++i) {
    if (used[i]) continue;
    std::array<int, kMaxConstraints> group{};
    int n = 0;
    group[n++] = i;
    used[i] = true;
    for (int j = i + 1; j < constraint_count_; ++j) {
      if (!used[j] && constraints_[j].object == constraints_[i].object &&
          constraints_[j].normal_W.dot(constraints_[i].normal_W) >= cos_eps) {
        group[n++] = j;
        used[j] = true;
      }
    }
    int ia = group[0];
    int ib = group[0];
    for (int k = 1; k < n; ++k) {
      if (constraints_[group[k]].u < constraints_[ia].u) ia = group[k];
      if (constraints_[group[k]].u > constraints_[ib].u) ib = group[k];
    }
    const SegmentConstraint& ca = constraints_[ia];
    const SegmentConstraint& cb = constraints_[ib];
    SegmentContact& contact = contacts_[contact_count_++];
    contact.object = ca.object;
    contact.primitive = ca.feature;
    contact.theta_rad = 0.0;
    double u_a = ca.u;
    double u_b = cb.u;
    // A probe lying within θε of the contacted face touches the whole part of it over the
    // face (Figure 5-3c), even where no constraint was needed to hold it there.
    const HapticObject& o = objects[ca.object];
    const MeshDatabase& m = o.segments->mesh();
    const Eigen::Isometry3d inv = o.pose_WO.inverse();
    const Eigen::Vector3d ia_O = inv * ideal_a_;
    const Eigen::Vector3d ib_O = inv * ideal_b_;
    // θ is measured on the virtual probe (the ideal one is held on the face).
    const Eigen::Vector3d dir_O =
        o.pose_WO.linear().transpose() * (virtual_b_ - virtual_a_).normalized();
    const double sin_eps = std::sin(settings_.theta_epsilon_rad);
    for (int k = 0; k < n; ++k) {
      const int32_t f = face_of_contact(m, constraints_[group[k]], cos_eps);
      if (f < 0 || std::abs(m.face_normal(f).dot(dir_O)) > sin_eps) continue;
      double u0 = 0.0;
      double u1 = 0.0;
      if (portion_on_face(*o.segments, f, ia_O, ib_O, &u0, &u1)) {
        u_a = std::min(u_a, u0);
        u_b = std::max(u_b, u1);
      }
    }
    contact.u_a = u_a;
    contact.u_b = u_b;
    double u_eq = ca.u;
    Eigen::Vector3d normal = ca.normal_W;
    Eigen::Vector3d plane_point = ca.point_W;
    if (u_b - u_a <= 1e-12) {
      contact.kind =
          ca.at_end ? SegmentContactKind::kPointPolygon : SegmentContactKind::kSegmentEdge;
    } else {
      contact.kind = SegmentContactKind::kSegmentFace;
      normal = (ca.normal_W + cb.normal_W).normalized();
      // θ: the virtual probe's angle to the face, positive when A is the deeper end (eq. 5-2).
      const Eigen::Vector3d span =
          lerp(virtual_a_, virtual_b_, u_b) - lerp(virtual_a_, virtual_b_, u_a);
      const double len = span.norm();
      const double sine = len > 0.0 ? std::clamp(normal.dot(span) / len, -1.0, 1.0) : 0.0;
      contact.theta_rad = std::asin(sine);
      const double r = std::clamp(contact.theta_rad / settings_.theta_epsilon_rad, -1.0, 1.0);
      u_eq = 0.5 * (u_a + u_b) + r * 0.5 * (u_a - u_b);  // eq. 5-2, as fractions of L
      // The face plane through the constraint points (all on it within the skin).
      plane_point = ca.point_W + normal.dot(cb.point_W - ca.point_W) * 0.5 * normal;
    }
    const Eigen::Vector3d x_virtual = lerp(virtual_a_, virtual_b_, u_eq);
    const double depth = normal.dot(plane_point - x_virtual);
    const Eigen::Vector3d velocity =
        (lerp(virtual_a_, virtual_b_, u_eq) - lerp(prev_virtual_a_, prev_virtual_b_, u_eq)) / dt;
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    if (depth > 0.0) {
      force = contact_force(objects[ca.object].law, -depth * normal, normal.dot(velocity) * normal);
    }
    contact.u_equilibrium = u_eq;
    contact.depth_m = depth;
    contact.normal_W = normal;
    contact.point_W = lerp(ideal_a_, ideal_b_, u_eq);
    contact.force_W = force;
    out->force_W += force;
    out->force_a_W += (1.0 - u_eq) * force;  // eq. 5-1 / 5-4 / 5-5: the lever rule
    out->force_b_W += u_eq * force;
    out->torque_W += (x_virtual - virtual_b_).cross(force);  // eq. 5-3
    const bool hold = contact.kind == SegmentContactKind::kSegmentFace &&
                      std::abs(contact.theta_rad) < settings_.theta_epsilon_rad && depth > 0.0;
    for (int k = 0; k < n; ++k) constraints_[group[k]].face_hold = hold;
  }
  out->ideal_a_W = ideal_a_;
  out->ideal_b_W = ideal_b_;
  out->contact_count = contact_count_;
}

Eigen::Vector3d SegmentProxy::torque_about(const Eigen::Vector3d& p_W) const {
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  for (int i = 0; i < contact_count_; ++i) {
    const SegmentContact& c = contacts_[i];
    torque += (lerp(virtual_a_, virtual_b_, c.u_equilibrium) - p_W).cross(c.force_W);
  }
  return torque;
}

}  // namespace lap::haptics
