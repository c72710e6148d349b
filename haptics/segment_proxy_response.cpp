// The segment proxy's response (§5.4): the constraints grouped into the thesis' contacts, each
// contact's equilibrium point and spring force, and the forces distributed to the two ends.

#include <algorithm>
#include <array>
#include <cmath>

#include "haptics/force_law.h"
#include "haptics/segment_contact_geometry.h"
#include "haptics/segment_proxy.h"

namespace lap::haptics {
namespace {

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
      // Either side: a two-sided surface is touched from behind too.
      if (f >= 0 && std::abs(m.face_normal(f).dot(c.normal_O)) >= cos_eps) return f;
    }
  }
  return -1;
}

}  // namespace

// One thesis contact: the constraints of one object whose normals agree within θε (member[0,
// count)); ia and ib are those with the smallest and the largest u, the contour's ends.
struct SegmentProxy::ContactGroup {
  std::array<int, kMaxConstraints> member{};
  int count = 0;
  int ia = 0;
  int ib = 0;
};

// §5.4: group the constraints into the thesis' contacts, find each one's equilibrium point and
// spring force, and distribute the forces to the two ends.
void SegmentProxy::respond(std::span<const HapticObject> objects, double dt,
                           SegmentProxyOutput* out) noexcept {
  contact_count_ = 0;
  for (FrictionSlot& slot : friction_) slot.used = false;
  const double cos_eps = std::cos(settings_.theta_epsilon_rad);
  std::array<bool, kMaxConstraints> used{};
  for (int i = 0; i < constraint_count_; ++i) {
    if (used[i]) continue;
    const ContactGroup group = gather_contact(i, cos_eps, &used);
    const SegmentConstraint& ca = constraints_[group.ia];
    SegmentContact& contact = contacts_[contact_count_++];
    contact.object = ca.object;
    contact.primitive = ca.feature;
    contact.theta_rad = 0.0;
    contact.u_a = ca.u;
    contact.u_b = constraints_[group.ib].u;
    widen_over_face(objects, group, cos_eps, &contact.u_a, &contact.u_b);
    const Eigen::Vector3d plane_point = find_equilibrium(group, &contact);
    contact.stiffness_factor = 1.0;
    const bool ideal_spring = settings_.response == SegmentResponse::kIdealVirtualSpring;
    const Eigen::Vector3d stretch =
        ideal_spring ? spring_stretch(group, &contact) : Eigen::Vector3d::Zero();
    apply_contact_force(objects, dt, plane_point, stretch, ideal_spring, &contact, out);
    const bool hold = contact.kind == SegmentContactKind::kSegmentFace &&
                      std::abs(contact.theta_rad) < settings_.theta_epsilon_rad &&
                      contact.depth_m > 0.0;
    for (int k = 0; k < group.count; ++k) constraints_[group.member[k]].face_hold = hold;
  }
  release_unused_friction();
  out->ideal_a_W = ideal_a_;
  out->ideal_b_W = ideal_b_;
  out->contact_count = contact_count_;
}

SegmentProxy::ContactGroup SegmentProxy::gather_contact(
    int i, double cos_eps, std::array<bool, kMaxConstraints>* used) const noexcept {
  ContactGroup g;
  g.member[g.count++] = i;
  (*used)[i] = true;
  const SegmentConstraint& ci = constraints_[i];
  for (int j = i + 1; j < constraint_count_; ++j) {
    const SegmentConstraint& cj = constraints_[j];
    // One contact: normals within θε (a face), or one end point held by several planes of one
    // object (a tip on a convex crease: one penetration, not a spring per plane).
    const bool same_end = ci.at_end && cj.at_end && ci.u == cj.u;
    if (!(*used)[j] && cj.object == ci.object &&
        (same_end || cj.normal_W.dot(ci.normal_W) >= cos_eps)) {
      g.member[g.count++] = j;
      (*used)[j] = true;
    }
  }
  g.ia = g.member[0];
  g.ib = g.member[0];
  for (int k = 1; k < g.count; ++k) {
    if (constraints_[g.member[k]].u < constraints_[g.ia].u) g.ia = g.member[k];
    if (constraints_[g.member[k]].u > constraints_[g.ib].u) g.ib = g.member[k];
  }
  return g;
}

// A probe lying within θε of the contacted face touches the whole part of it over the face
// (Figure 5-3c), even where no constraint was needed to hold it there.
void SegmentProxy::widen_over_face(std::span<const HapticObject> objects, const ContactGroup& g,
                                   double cos_eps, double* u_a, double* u_b) const noexcept {
  const HapticObject& o = objects[constraints_[g.ia].object];
  const MeshDatabase& m = o.segments->mesh();
  const Eigen::Isometry3d inv = o.pose_WO.inverse();
  const Eigen::Vector3d ia_O = inv * ideal_a_;
  const Eigen::Vector3d ib_O = inv * ideal_b_;
  // θ is measured on the virtual probe (the ideal one is held on the face).
  const Eigen::Vector3d dir_O =
      o.pose_WO.linear().transpose() * (virtual_b_ - virtual_a_).normalized();
  const double sin_eps = std::sin(settings_.theta_epsilon_rad);
  for (int k = 0; k < g.count; ++k) {
    const int32_t f = face_of_contact(m, constraints_[g.member[k]], cos_eps);
    if (f < 0 || std::abs(m.face_normal(f).dot(dir_O)) > sin_eps) continue;
    double u0 = 0.0;
    double u1 = 0.0;
    if (portion_on_face(*o.segments, f, ia_O, ib_O, &u0, &u1)) {
      *u_a = std::min(*u_a, u0);
      *u_b = std::max(*u_b, u1);
    }
  }
}

// The contact's kind and equilibrium point: the contact point for point–polygon and
// segment–edge contacts; for a segment–face contact (a contour [u_a, u_b] of some length), eq.
// 5-2 from the probe's angle θ to the face.
Eigen::Vector3d SegmentProxy::find_equilibrium(const ContactGroup& g,
                                               SegmentContact* contact) const noexcept {
  const SegmentConstraint& ca = constraints_[g.ia];
  const SegmentConstraint& cb = constraints_[g.ib];
  const double u_a = contact->u_a;
  const double u_b = contact->u_b;
  double u_eq = ca.u;
  Eigen::Vector3d normal = ca.normal_W;
  Eigen::Vector3d plane_point = ca.point_W;
  if (u_b - u_a <= 1e-12) {
    contact->kind =
        ca.at_end ? SegmentContactKind::kPointPolygon : SegmentContactKind::kSegmentEdge;
    if (g.count > 1) {
      // An end point held by several planes (on a crease): as the point proxy has it (§4.4), the
      // penetration is from the ideal end point to the virtual one, whatever the planes.
      const Eigen::Vector3d x = lerp(ideal_a_, ideal_b_, u_eq) - lerp(virtual_a_, virtual_b_, u_eq);
      if (x.squaredNorm() > 0.0 && x.dot(normal) > 0.0) normal = x.normalized();
      plane_point = lerp(ideal_a_, ideal_b_, u_eq);
    }
  } else {
    contact->kind = SegmentContactKind::kSegmentFace;
    normal = (ca.normal_W + cb.normal_W).normalized();
    // θ: the virtual probe's angle to the face, positive when A is the deeper end (eq. 5-2).
    const Eigen::Vector3d span =
        lerp(virtual_a_, virtual_b_, u_b) - lerp(virtual_a_, virtual_b_, u_a);
    const double len = span.norm();
    const double sine = len > 0.0 ? std::clamp(normal.dot(span) / len, -1.0, 1.0) : 0.0;
    contact->theta_rad = std::asin(sine);
    const double r = std::clamp(contact->theta_rad / settings_.theta_epsilon_rad, -1.0, 1.0);
    u_eq = 0.5 * (u_a + u_b) + r * 0.5 * (u_a - u_b);  // eq. 5-2, as fractions of L
    // The face plane through the constraint points (all on it within the skin).
    plane_point = ca.point_W + normal.dot(cb.point_W - ca.point_W) * 0.5 * normal;
  }
  contact->u_equilibrium = u_eq;
  contact->normal_W = normal;
  return plane_point;
}

// The contact's part of the spring between the ideal and the virtual probe (Figure 5-4; see
// segment_proxy.h, "Response"): the placement left the ideal probe at x = x_virtual + Σ λ_i g_i,
// so the spring k (x − x_virtual) on the two ends is the sum over constraints of k λ_i n_i acting
// at u_i (less the skin). A contact's share is its constraints' Σ λ_i n_i (the returned stretch
// [m]), acting at their λ-weighted u (the exact lever for it), which becomes its equilibrium point.
// A contact none of whose constraints presses (all λ = 0: the ideal probe rests on it but the hand
// does not push) carries no force; its equilibrium point stays eq. 5-2's.
Eigen::Vector3d SegmentProxy::spring_stretch(const ContactGroup& g,
                                             SegmentContact* contact) const noexcept {
  Eigen::Vector3d stretch = Eigen::Vector3d::Zero();
  double lambda = 0.0;
  double lambda_u = 0.0;
  double factor = 0.0;
  for (int k = 0; k < g.count; ++k) {
    const SegmentConstraint& c = constraints_[g.member[k]];
    // Measured from the surface, not from the skin the ideal probe keeps above it.
    const double l = c.lambda_surface;
    if (!(c.lambda > 0.0) || !(l > 0.0)) continue;
    const double g2 = (1.0 - c.u) * (1.0 - c.u) + c.u * c.u;  // |g_i|² ≥ ½
    stretch += l * c.normal_W;
    lambda += l;
    lambda_u += l * c.u;
    factor += 1.0 / g2;
  }
  contact->stiffness_factor = std::clamp(factor, 1.0, 2.0);
  if (lambda > 0.0 && stretch.squaredNorm() > 0.0) {
    contact->u_equilibrium = std::clamp(lambda_u / lambda, 0.0, 1.0);
  }
  return stretch;
}

// The contact's spring with the object's surface properties (chapter 6), split to the two ends.
// Its depth is the virtual probe's penetration at the equilibrium point below the plane through
// plane_point. The thesis' spring (kContactSprings) stretches by that depth; the spring between
// the ideal and the virtual probe (kIdealVirtualSpring) by the contact's stretch from
// spring_stretch.
void SegmentProxy::apply_contact_force(std::span<const HapticObject> objects, double dt,
                                       const Eigen::Vector3d& plane_point,
                                       const Eigen::Vector3d& stretch, bool ideal_spring,
                                       SegmentContact* contact, SegmentProxyOutput* out) noexcept {
  const double u_eq = contact->u_equilibrium;
  double stretch_m = stretch.norm();
  // The spring's direction is the contact's normal while it presses (its constraints' normals
  // weighted by their multipliers: the contact plane's, for a single plane).
  if (ideal_spring && stretch_m > 0.0) contact->normal_W = stretch / stretch_m;
  const Eigen::Vector3d& normal = contact->normal_W;
  const Eigen::Vector3d x_virtual = lerp(virtual_a_, virtual_b_, u_eq);
  const double depth = normal.dot(plane_point - x_virtual);
  if (!ideal_spring) {
    stretch_m = depth;  // §5.4: the contact's own penetration
  } else if (stretch_m > 0.0 && depth > 1e-9) {
    // Its stiffness, as the stretch over the depth it answers: continuous as the probe tilts
    // and one end's constraint starts or stops pressing (the count of pressing ones jumps).
    contact->stiffness_factor = std::clamp(stretch_m / depth, 1.0, 2.0);
  }
  const HapticObject& o = objects[contact->object];
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d friction = Eigen::Vector3d::Zero();
  contact->friction_phase = FrictionState::Phase::kNone;
  if (stretch_m > 0.0) {
    // The surface point: the virtual probe's equilibrium point projected onto the plane.
    const Eigen::Vector3d surface_W = x_virtual + std::max(depth, 0.0) * normal;
    const SurfacePoint s = surface_point(o, *contact, surface_W);
    // Damped on the probe's own motion into the surface (the virtual probe's point at u_eq, the
    // hand's), relative to the object's point there (§6.4), as the point proxy is: never on the
    // change of the penetration, which jumps with the ideal probe and the equilibrium point.
    double approach = 0.0;
    if (dt > 0.0) {
      const Eigen::Vector3d probe_moved = x_virtual - lerp(prev_virtual_a_, prev_virtual_b_, u_eq);
      const Eigen::Vector3d surface_moved =
          surface_W - o.prev_pose_WO * (o.pose_WO.inverse() * surface_W);
      approach = -normal.dot(probe_moved - surface_moved) / dt;
    }
    // A texture raises the surface by h at the contact (§6.3): the spring of that contact,
    // stiffness_factor k, stretches by h more.
    const double factor = contact->stiffness_factor;
    const Eigen::Vector3d penetration =
        o.texture != nullptr ? factor * surface_penetration(o, s, stretch_m / factor, normal)
                             : surface_penetration(o, s, stretch_m, normal);
    force = contact_force(o.law, penetration, approach);
    if (o.friction != nullptr) {
      friction = contact_friction(o, contact_count_ - 1, s, std::max(0.0, force.dot(normal)));
      force += friction;
      const double magnitude = force.norm();
      if (magnitude > o.law.max_force_n) force *= o.law.max_force_n / magnitude;
    }
  }
  contact->depth_m = depth;
  contact->point_W = lerp(ideal_a_, ideal_b_, u_eq);
  contact->force_W = force;
  contact->friction_W = friction;
  out->friction_W += friction;
  out->force_W += force;
  out->force_a_W += (1.0 - u_eq) * force;  // eq. 5-1 / 5-4 / 5-5: the lever rule
  out->force_b_W += u_eq * force;
  out->torque_W += (x_virtual - virtual_b_).cross(force);  // eq. 5-3
}

}  // namespace lap::haptics
