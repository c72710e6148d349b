// The segment proxy's step and its constraints: tracking them between ticks, placing the ideal
// probe under them and moving it towards the virtual probe. The swept check is in
// segment_proxy_sweep.cpp (its cache in segment_proxy_sweep_cache.cpp), the response (§5.4) in
// segment_proxy_response.cpp.

#include "haptics/segment_proxy.h"

#include <algorithm>
#include <cmath>

#include "haptics/point_proxy.h"
#include "haptics/probe_placement_qp.h"
#include "haptics/segment_contact_geometry.h"
#include "haptics/segment_segment.h"

namespace lap::haptics {
namespace {

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// Whether constraint k holds the same contact as c: one feature of one object (and, for an end
// point, the same end).
bool same_feature(const SegmentConstraint& k, const SegmentConstraint& c) {
  return k.object == c.object && k.feature == c.feature && k.at_end == c.at_end &&
         (!c.at_end || k.u == c.u);
}

// Segment–edge: the closest points of probe (a, b) and edge *e; past an end of the edge, move to
// the contactable edge at that vertex the probe now crosses most deeply (edge PCPs).
SegmentPair slide_along_edges(const SegmentDatabase& sd, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, int32_t* e) {
  const MeshDatabase& m = sd.mesh();
  auto pair_of = [&](int32_t g) {
    const auto& ev = m.edge_vertices(g);
    return closest_segment_segment(a, b, m.position(ev[0]), m.position(ev[1]));
  };
  SegmentPair cp = pair_of(*e);
  if (cp.t <= 0.0 || cp.t >= 1.0) {
    double best = (cp.q - cp.p).squaredNorm();
    for (const PrimitiveRef& p : sd.edge_pcps(*e)) {
      if (p.kind != PrimitiveKind::kEdge) continue;
      const SegmentPair cq = pair_of(p.index);
      if (cq.t <= 0.0 || cq.t >= 1.0) continue;
      const double d2 = (cq.q - cq.p).squaredNorm();
      if (d2 < best) {
        best = d2;
        *e = p.index;
        cp = cq;
      }
    }
  }
  return cp;
}

// Point–polygon: the end point's own Neighborhood Watch (chapter 4), for the probe (a, b).
void track_point_contact(const MeshDatabase& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         SegmentConstraint* c) {
  const Eigen::Vector3d p = c->u == 0.0 ? a : b;
  Eigen::Vector3d q;
  int32_t rounds = 0;
  c->feature = PointProxy::local_search(m, c->feature, p, &q, &rounds);
  c->point_O = q;
  c->normal_O = static_cast<double>(c->side) * m.normal(c->feature);
}

// A pass moves each end point at most kMaxPassMotion, so that the swept check stays local even
// when the virtual probe is far inside (the rest is done by the next passes). Shortens the
// motion (sa, sb) -> (*ca, *cb) to that; true when it did.
bool limit_pass_motion(const Eigen::Vector3d& sa, const Eigen::Vector3d& sb, Eigen::Vector3d* ca,
                       Eigen::Vector3d* cb) {
  const double motion = std::max((*ca - sa).norm(), (*cb - sb).norm());
  const bool partial = motion > SegmentProxy::kMaxPassMotion;
  if (partial) {
    const double f = SegmentProxy::kMaxPassMotion / motion;
    *ca = sa + f * (*ca - sa);
    *cb = sb + f * (*cb - sb);
  }
  return partial;
}

// Stop at time s of the pass (*sa, *sb) -> (ca, cb) that hit object o, interpolating in o's frame
// so a moving object is respected (in the first pass o moves from its previous pose).
void stop_at(const HapticObject& o, bool first_pass, double s, const Eigen::Vector3d& ca,
             const Eigen::Vector3d& cb, Eigen::Vector3d* sa, Eigen::Vector3d* sb) {
  const Eigen::Isometry3d inv0 = (first_pass ? o.prev_pose_WO : o.pose_WO).inverse();
  const Eigen::Isometry3d inv1 = o.pose_WO.inverse();
  *sa = o.pose_WO * lerp(inv0 * *sa, inv1 * ca, s);
  *sb = o.pose_WO * lerp(inv0 * *sb, inv1 * cb, s);
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
  for (FrictionSlot& f : friction_) f.object = -1;
  seen_ = {};
  initialised_ = true;
}

void SegmentProxy::remove_constraint(int i) noexcept {
  constraints_[i] = constraints_[constraint_count_ - 1];
  --constraint_count_;
}

bool SegmentProxy::add_constraint(const SegmentConstraint& c) noexcept {
  for (int i = 0; i < constraint_count_; ++i) {
    SegmentConstraint& k = constraints_[i];
    if (same_feature(k, c)) {
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
void SegmentProxy::track(std::span<const HapticObject> objects) noexcept {
  for (int i = constraint_count_ - 1; i >= 0; --i) {
    SegmentConstraint& c = constraints_[i];
    if (c.object < 0 || c.object >= static_cast<int32_t>(objects.size()) ||
        objects[c.object].segments == nullptr) {
      remove_constraint(i);
      continue;
    }
    const HapticObject& o = objects[c.object];
    const SegmentDatabase& sd = *o.segments;
    const Eigen::Isometry3d inv = o.pose_WO.inverse();
    const Eigen::Vector3d a = inv * virtual_a_;
    const Eigen::Vector3d b = inv * virtual_b_;
    if (!c.at_end) track_edge_contact(sd, inv, a, b, &c);
    if (c.at_end) track_point_contact(sd.mesh(), a, b, &c);
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
      if (same_feature(constraints_[j], c)) {
        remove_constraint(i);
        break;
      }
    }
  }
}

void SegmentProxy::track_edge_contact(const SegmentDatabase& sd, const Eigen::Isometry3d& inv,
                                      const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      SegmentConstraint* c) const noexcept {
  int32_t e = c->feature.index;
  const SegmentPair cp = slide_along_edges(sd, a, b, &e);
  if (cp.s <= 0.0 || cp.s >= 1.0) {
    // The probe's end has reached the edge (Figure 5-9c): a point contact from here on, on the
    // side the edge contact was on.
    c->at_end = true;
    c->u = cp.s <= 0.0 ? 0.0 : 1.0;
    c->feature = {PrimitiveKind::kEdge, e};
    c->side = c->normal_O.dot(sd.mesh().normal(c->feature)) >= 0.0 ? 1 : -1;
  } else {
    const Eigen::Vector3d side = inv * lerp(ideal_a_, ideal_b_, cp.s) - cp.q;
    c->feature = {PrimitiveKind::kEdge, e};
    c->u = cp.s;
    c->point_O = cp.q;
    c->normal_O = edge_contact_normal(sd.mesh(), e, sd.convex_side(e), b - a, side);
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
                         const Eigen::Vector3d& b_W, Eigen::Vector3d* a,
                         Eigen::Vector3d* b) noexcept {
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
      c.normal_O = edge_contact_normal(m, c.feature.index, o.segments->convex_side(c.feature.index),
                                       pb - pa, c.normal_O);
      c.point_W = o.pose_WO * c.point_O;
      c.normal_W = o.pose_WO.linear() * c.normal_O;
      moved = true;
    }
    if (!moved) break;
  }
}

void SegmentProxy::solve_placement(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W,
                                   Eigen::Vector3d* a, Eigen::Vector3d* b) noexcept {
  ProbePlacementQp qp;
  // Only the passive response reads the multipliers without the skin (one more small solve).
  if (settings_.response == SegmentResponse::kIdealVirtualSpring) qp.skin_m = settings_.skin_m;
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
  for (int i = 0; i < constraint_count_; ++i) {
    constraints_[i].lambda = sol.lambda[i];
    constraints_[i].lambda_surface = sol.lambda_surface[i];
  }
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
    for (FrictionSlot& f : friction_) f.object = -1;
    return out;
  }
  if (!initialised_) reset(a_W, b_W);
  prev_virtual_a_ = virtual_a_;
  prev_virtual_b_ = virtual_b_;
  virtual_a_ = a_W;
  virtual_b_ = b_W;

  push_out_of_moved_surfaces(objects);
  track(objects);
  move_ideal_probe(objects, a_W, b_W);
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

// Move the ideal probe towards the virtual one: place, sweep, stop at a new contact, add it,
// place again (§5.3 first contact and its continuation).
void SegmentProxy::move_ideal_probe(std::span<const HapticObject> objects,
                                    const Eigen::Vector3d& a_W,
                                    const Eigen::Vector3d& b_W) noexcept {
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
    const bool partial = limit_pass_motion(sa, sb, &ca, &cb);
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
    // constraint).
    const double s = std::max(0.0, tau - 1e-6);
    const HapticObject& o = objects[hit.object];
    stop_at(o, pass == 0, s, ca, cb, &sa, &sb);
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
