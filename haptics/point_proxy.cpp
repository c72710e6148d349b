#include "haptics/point_proxy.h"

#include <limits>

#include "haptics/closest_point.h"
#include "haptics/height_field.h"
#include "haptics/shading_normals.h"
#include "haptics/texture_force.h"

namespace lap::haptics {
namespace {

// Where the IHIP's path from ihip_W (last tick's) to x_W first crosses o's surface, from outside
// (either side if two-sided), in o's frame at its previous and current pose (§6.4: an object
// moving onto the IHIP is crossed too).
MeshDatabase::Crossing path_crossing(const HapticObject& o, const Eigen::Vector3d& ihip_W,
                                     const Eigen::Vector3d& x_W) {
  return o.mesh->first_crossing(o.prev_pose_WO.inverse() * ihip_W, o.pose_WO.inverse() * x_W,
                                o.two_sided);
}

// Nearest point of one primitive, and the lower-dimensional feature it lies on (if any).
struct Candidate {
  PrimitiveRef prim;
  Eigen::Vector3d q;
  double d2 = 0.0;
  PrimitiveRef sub;  // kNone when the nearest point is inside the primitive
};

inline Candidate evaluate(const MeshDatabase& m, PrimitiveRef p, const Eigen::Vector3d& x) {
  Candidate c;
  c.prim = p;
  switch (p.kind) {
    case PrimitiveKind::kVertex:
      c.q = m.position(p.index);
      break;
    case PrimitiveKind::kEdge: {
      const auto& ev = m.edge_vertices(p.index);
      SegmentFeature f;
      c.q = closest_on_segment(x, m.position(ev[0]), m.position(ev[1]), &f);
      if (f == SegmentFeature::kEndA) c.sub = {PrimitiveKind::kVertex, ev[0]};
      if (f == SegmentFeature::kEndB) c.sub = {PrimitiveKind::kVertex, ev[1]};
      break;
    }
    case PrimitiveKind::kFace: {
      const auto& fv = m.face_vertices(p.index);
      const auto& fe = m.face_edges(p.index);
      TriangleFeature f;
      c.q = closest_on_triangle(x, m.position(fv[0]), m.position(fv[1]), m.position(fv[2]), &f);
      switch (f) {
        case TriangleFeature::kInterior:
          break;
        case TriangleFeature::kVertexA:
          c.sub = {PrimitiveKind::kVertex, fv[0]};
          break;
        case TriangleFeature::kVertexB:
          c.sub = {PrimitiveKind::kVertex, fv[1]};
          break;
        case TriangleFeature::kVertexC:
          c.sub = {PrimitiveKind::kVertex, fv[2]};
          break;
        case TriangleFeature::kEdgeAB:
          c.sub = {PrimitiveKind::kEdge, fe[0]};
          break;
        case TriangleFeature::kEdgeBC:
          c.sub = {PrimitiveKind::kEdge, fe[1]};
          break;
        case TriangleFeature::kEdgeCA:
          c.sub = {PrimitiveKind::kEdge, fe[2]};
          break;
      }
      break;
    }
    case PrimitiveKind::kNone:
      c.q = x;
      break;
  }
  c.d2 = (c.q - x).squaredNorm();
  return c;
}

// A primitive stands for the lowest-dimensional feature holding its nearest point (a face
// whose nearest point is on an edge stands for that edge, and so on down to a vertex), with that
// feature's own distance. Comparing canonical candidates only, every accepted move strictly
// lowers one consistently computed distance: no two routines' roundings can make the search
// ping-pong between a face and its edge.
inline Candidate canonical(const MeshDatabase& m, PrimitiveRef p, const Eigen::Vector3d& x) {
  Candidate c = evaluate(m, p, x);
  for (int k = 0; k < 2 && c.sub.kind != PrimitiveKind::kNone; ++k) c = evaluate(m, c.sub, x);
  return c;
}

inline void consider(const MeshDatabase& m, PrimitiveRef p, const Eigen::Vector3d& x,
                     Candidate& best) {
  const Candidate c = canonical(m, p, x);
  if (c.d2 < best.d2) best = c;
}

}  // namespace

PrimitiveRef PointProxy::local_search(const MeshDatabase& m, PrimitiveRef start,
                                      const Eigen::Vector3d& p, Eigen::Vector3d* q,
                                      int32_t* rounds) {
  // Start from the feature holding the nearest point of the contacted primitive (§4.3 plus the
  // step down that breaks a face/edge tie, see canonical()).
  Candidate cur = canonical(m, start, p);
  int32_t r = 0;
  for (; r < kMaxSearchRounds; ++r) {
    Candidate best = cur;
    switch (cur.prim.kind) {
      case PrimitiveKind::kFace:
        // A canonical face holds its nearest point in its interior (§4.3: the HIP projects into
        // the polygon), and its edges and vertices are parts of it, so none is nearer: the
        // search ends here without evaluating them.
        break;
      case PrimitiveKind::kEdge: {
        const auto& ev = m.edge_vertices(cur.prim.index);
        const auto& ef = m.edge_faces(cur.prim.index);
        consider(m, {PrimitiveKind::kVertex, ev[0]}, p, best);
        consider(m, {PrimitiveKind::kVertex, ev[1]}, p, best);
        consider(m, {PrimitiveKind::kFace, ef[0]}, p, best);
        if (ef[1] >= 0) consider(m, {PrimitiveKind::kFace, ef[1]}, p, best);
        break;
      }
      case PrimitiveKind::kVertex: {
        const int32_t v = cur.prim.index;
        m.for_each_vertex_face(v, [&](int32_t f) {
          consider(m, {PrimitiveKind::kFace, f}, p, best);
          // Each edge around v leaves v in exactly one face of a consistently oriented surface;
          // a boundary edge entering v has no such face, so take it from its only face.
          const auto& fe = m.face_edges(f);
          const int j = m.corner_of(f, v);
          consider(m, {PrimitiveKind::kEdge, fe[j]}, p, best);
          const int32_t incoming = fe[(j + 2) % 3];
          if (m.edge_faces(incoming)[1] < 0) consider(m, {PrimitiveKind::kEdge, incoming}, p, best);
        });
        break;
      }
      case PrimitiveKind::kNone:
        break;
    }
    if (best.prim == cur.prim) break;
    cur = best;
  }
  if (rounds != nullptr) *rounds = r;
  *q = cur.q;
  return cur.prim;
}

void PointProxy::reset(const Eigen::Vector3d& hip_W) {
  count_ = 0;
  ihip_W_ = hip_W.allFinite() ? hip_W : Eigen::Vector3d::Zero();
  prev_hip_W_ = ihip_W_;
  initialised_ = true;
  friction_.phase = FrictionState::Phase::kNone;
  hover_object_ = -1;
}

Eigen::Vector3d PointProxy::texture_penetration(const HapticObject& o, const Eigen::Vector3d& q_O,
                                                const Eigen::Vector3d& n_O, double s) noexcept {
  return o.pose_WO.linear() * haptics::texture_penetration(*o.texture, o.texture_k, q_O, n_O, s);
}

void PointProxy::find_hover(std::span<const HapticObject> objects,
                            const Eigen::Vector3d& hip) noexcept {
  double best = std::numeric_limits<double>::infinity();
  for (int32_t oi = 0; oi < static_cast<int32_t>(objects.size()); ++oi) {
    const HapticObject& o = objects[oi];
    if (o.mesh == nullptr || o.texture == nullptr) continue;
    const double band = o.texture->max_height_m();
    if (!(band > 0.0)) continue;
    const Eigen::Vector3d hip_O = o.pose_WO.inverse() * hip;
    const MeshDatabase& m = *o.mesh;
    m.tree().for_each_near_segment(hip_O, hip_O, band, [&](int32_t f) {
      const auto& v = m.face_vertices(f);
      TriangleFeature feature;
      const Eigen::Vector3d q = closest_on_triangle(hip_O, m.position(v[0]), m.position(v[1]),
                                                    m.position(v[2]), &feature);
      const double dist = (hip_O - q).norm();
      const double side = (hip_O - q).dot(m.face_normal(f));
      if (dist <= band && dist < best && (side > 0.0 || o.two_sided)) {
        best = dist;
        hover_object_ = oi;
        hover_primitive_ = {PrimitiveKind::kFace, f};
        hover_side_ = side >= 0.0 ? 1 : -1;
      }
    });
  }
}

Eigen::Vector3d PointProxy::combine(const Eigen::Vector3d& hip) const noexcept {
  if (count_ == 0) return hip;
  if (count_ == 1) return contacts_[0].point_W;
  // Nearest point to the HIP that is on or outside every contact's plane: try each active set
  // (one contact: its nearest point; two: the line where both planes meet; three: the point).
  auto feasible = [this](const Eigen::Vector3d& x) {
    for (int32_t c = 0; c < count_; ++c) {
      if (contacts_[c].normal_W.dot(x - contacts_[c].point_W) < -1e-12) return false;
    }
    return true;
  };
  Eigen::Vector3d best = contacts_[0].point_W;
  double best_d2 = std::numeric_limits<double>::infinity();
  auto offer = [&](const Eigen::Vector3d& x) {
    const double d2 = (x - hip).squaredNorm();
    if (d2 < best_d2 && x.allFinite() && feasible(x)) {
      best = x;
      best_d2 = d2;
    }
  };
  for (int32_t a = 0; a < count_; ++a) offer(contacts_[a].point_W);
  for (int32_t a = 0; a < count_; ++a) {
    for (int32_t b = a + 1; b < count_; ++b) {
      const Eigen::Vector3d& na = contacts_[a].normal_W;
      const Eigen::Vector3d& nb = contacts_[b].normal_W;
      const Eigen::Vector3d dir = na.cross(nb);
      const double s = dir.squaredNorm();
      if (s < 1e-18) continue;  // parallel planes
      // A point on both planes, then the HIP projected onto that line.
      const double ca = na.dot(contacts_[a].point_W);
      const double cb = nb.dot(contacts_[b].point_W);
      const Eigen::Vector3d on_line = (ca * nb.cross(dir) + cb * dir.cross(na)) / s;
      offer(on_line + dir * (dir.dot(hip - on_line) / s));
      for (int32_t c = b + 1; c < count_; ++c) {
        const Eigen::Vector3d& nc = contacts_[c].normal_W;
        const double det = na.dot(nb.cross(nc));
        if (std::abs(det) < 1e-12) continue;
        const double cc = nc.dot(contacts_[c].point_W);
        offer((ca * nb.cross(nc) + cb * nc.cross(na) + cc * na.cross(nb)) / det);
      }
    }
  }
  return best;
}

// The contacts whose HIP left their object this tick (stage 1), with last tick's contact
// (primitive and plane): each is held again or released in stage 4.
struct PointProxy::Leaving {
  std::array<PointContact, kMaxContacts> contacts{};
  int32_t count = 0;
};

// What the force of stage 5 comes from: the penetration vector, the law that turns it into a
// force, the touched object with its contact point and normal (object frame) for friction, and
// the outward normal the damper measures the HIP's approach along. No law: no force.
struct PointProxy::ForceSource {
  Eigen::Vector3d penetration = Eigen::Vector3d::Zero();
  const ForceLaw* law = nullptr;
  int32_t touched = -1;
  Eigen::Vector3d contact_O = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_O = Eigen::Vector3d::UnitY();
  Eigen::Vector3d approach_normal_W = Eigen::Vector3d::UnitY();
};

PointProxyOutput PointProxy::fault(const Eigen::Vector3d& hip) noexcept {
  ++stats_.faults;
  reset(hip.allFinite() ? hip : ihip_W_);
  PointProxyOutput out;
  out.ihip_W = ihip_W_;
  out.fault = true;
  return out;
}

void PointProxy::follow_contacts(std::span<const HapticObject> objects, const Eigen::Vector3d& hip,
                                 Leaving* leaving) noexcept {
  int32_t kept = 0;
  for (int32_t i = 0; i < count_; ++i) {
    PointContact c = contacts_[i];
    if (c.object < 0 || c.object >= static_cast<int32_t>(objects.size()) ||
        objects[c.object].mesh == nullptr) {
      continue;  // the object went away
    }
    const HapticObject& o = objects[c.object];
    const Eigen::Vector3d hip_O = o.pose_WO.inverse() * hip;
    Eigen::Vector3d q_O;
    int32_t rounds = 0;
    const PrimitiveRef found = local_search(*o.mesh, c.primitive, hip_O, &q_O, &rounds);
    stats_.search_iterations += rounds;
    if (rounds >= kMaxSearchRounds) ++stats_.search_limit_hits;
    const Eigen::Vector3d n_O = static_cast<double>(c.side) * o.mesh->normal(found);
    if ((q_O - hip_O).dot(n_O) < 0.0) {
      leaving->contacts[leaving->count++] = c;
      continue;
    }
    c.primitive = found;
    c.point_W = o.pose_WO * q_O;
    c.normal_W = o.pose_WO.linear() * n_O;
    contacts_[kept++] = c;
  }
  count_ = kept;
}

bool PointProxy::in_contact_or_leaving(int32_t object, const Leaving& leaving) const noexcept {
  bool found = false;
  for (int32_t c = 0; c < count_; ++c) found = found || contacts_[c].object == object;
  for (int32_t r = 0; r < leaving.count; ++r) found = found || leaving.contacts[r].object == object;
  return found;
}

PointProxy::ObjectCrossing PointProxy::first_crossing(std::span<const HapticObject> objects,
                                                      const Eigen::Vector3d& x,
                                                      const Leaving& leaving) const noexcept {
  ObjectCrossing best;
  best.crossing.t = std::numeric_limits<double>::infinity();
  for (int32_t oi = 0; oi < static_cast<int32_t>(objects.size()); ++oi) {
    const HapticObject& o = objects[oi];
    if (o.mesh == nullptr || in_contact_or_leaving(oi, leaving)) continue;
    const MeshDatabase::Crossing c = path_crossing(o, ihip_W_, x);
    if (c.face >= 0 && c.t < best.crossing.t) {
      best.object = oi;
      best.crossing = c;
    }
  }
  return best;
}

void PointProxy::add_first_contact(const HapticObject& o, const ObjectCrossing& crossed,
                                   const Eigen::Vector3d& hip) noexcept {
  const MeshDatabase& m = *o.mesh;
  const int32_t face = crossed.crossing.face;
  const Eigen::Vector3d hip_O = o.pose_WO.inverse() * hip;
  const auto& v = m.face_vertices(face);
  TriangleFeature feature;
  const Eigen::Vector3d q_O =
      closest_on_triangle(hip_O, m.position(v[0]), m.position(v[1]), m.position(v[2]), &feature);
  PointContact c;
  c.object = crossed.object;
  c.primitive = {PrimitiveKind::kFace, face};
  c.side = crossed.crossing.from_front ? 1 : -1;
  c.point_W = o.pose_WO * q_O;
  c.normal_W = o.pose_WO.linear() * (static_cast<double>(c.side) * m.face_normal(face));
  contacts_[count_++] = c;
  ++stats_.first_contacts;
}

void PointProxy::add_first_contacts(std::span<const HapticObject> objects,
                                    const Eigen::Vector3d& hip, const Leaving& leaving,
                                    Eigen::Vector3d* x) noexcept {
  for (int pass = 0; pass < kMaxContacts && count_ < kMaxContacts; ++pass) {
    const ObjectCrossing crossed = first_crossing(objects, *x, leaving);
    if (crossed.object < 0) break;
    // First contact: the crossed face; the IHIP goes to its nearest point to the HIP (§4.3).
    add_first_contact(objects[crossed.object], crossed, hip);
    *x = combine(hip);
  }
}

void PointProxy::hold_or_release(std::span<const HapticObject> objects, const Eigen::Vector3d& hip,
                                 const Leaving& leaving, Eigen::Vector3d* x) noexcept {
  for (int32_t r = 0; r < leaving.count; ++r) {
    const PointContact& c = leaving.contacts[r];
    if (count_ > 0 && count_ < kMaxContacts && c.normal_W.dot(*x - c.point_W) < -1e-12) {
      contacts_[count_++] = c;
      *x = combine(hip);
    } else if (!reentered(objects, c.object, hip, x)) {
      ++stats_.releases;
      if (objects[c.object].texture != nullptr) {
        hover_object_ = c.object;
        hover_primitive_ = c.primitive;
        hover_side_ = c.side;
      }
    }
  }
}

// A HIP deep in a thin part of a closed object can have as its nearest surface the far side of
// a fold, above which it is while inside the object (it went out through the part and back in
// through the fold): the local search then says it has left. The IHIP's path to it says whether
// it is inside: a face crossed on the way (a one-sided object's faces are crossed only from
// outside) holds it, as a first contact would. Seen in PointProxyRandom.RealOrganMeshes on a
// liver mesh, 22 mm deep, where the proxy let go and the HIP stayed inside with no force.
bool PointProxy::reentered(std::span<const HapticObject> objects, int32_t object,
                           const Eigen::Vector3d& hip, Eigen::Vector3d* x) noexcept {
  const HapticObject& o = objects[object];
  if (o.two_sided || count_ >= kMaxContacts) return false;
  for (int32_t i = 0; i < count_; ++i) {
    if (contacts_[i].object == object) return false;
  }
  ObjectCrossing crossed;
  crossed.object = object;
  crossed.crossing = path_crossing(o, ihip_W_, *x);  // one-sided: entered from outside only
  if (crossed.crossing.face < 0) return false;
  add_first_contact(o, crossed, hip);
  ++stats_.reentries;
  *x = combine(hip);
  return true;
}

PointProxy::ForceSource PointProxy::contact_force_source(std::span<const HapticObject> objects,
                                                         const Eigen::Vector3d& hip,
                                                         PointProxyOutput* out) const noexcept {
  ForceSource f;
  f.law = &objects[contacts_[0].object].law;
  for (int32_t c = 1; c < count_; ++c) {
    const ForceLaw& l = objects[contacts_[c].object].law;
    if (l.stiffness_n_per_m > f.law->stiffness_n_per_m) f.law = &l;
  }
  f.penetration = hip - ihip_W_;
  const PointContact& first = contacts_[0];
  const HapticObject& touched = objects[first.object];
  f.touched = first.object;
  const Eigen::Isometry3d pose_OW = touched.pose_WO.inverse();
  f.contact_O = pose_OW * first.point_W;
  f.normal_O = touched.pose_WO.linear().transpose() * first.normal_W;
  // The damper: along the contact's normal, whatever shading or a texture make of the force's
  // direction (sliding along the surface is not an approach); in a crease (several contacts)
  // along the force, from the HIP to the IHIP.
  f.approach_normal_W = first.normal_W;
  if (count_ > 1 && (ihip_W_ - hip).squaredNorm() > 0.0) {
    f.approach_normal_W = (ihip_W_ - hip).normalized();
  }
  if (count_ == 1 && touched.texture != nullptr) {
    const double depth = std::max(0.0, first.normal_W.dot(ihip_W_ - hip));
    f.penetration = texture_penetration(touched, f.contact_O, f.normal_O, -depth);
  } else if (count_ == 1 && touched.shading != nullptr) {
    // §6.1 / Figure 6-3: direction from the shaded normal, magnitude from the HIP projected
    // along it onto the contacted plane. Creases between objects (two or more contacts) are
    // real edges and stay sharp.
    const Eigen::Vector3d shaded =
        touched.pose_WO.linear() *
        (static_cast<double>(first.side) *
         touched.shading->normal(*touched.mesh, first.primitive, f.contact_O));
    const double depth = std::max(0.0, first.normal_W.dot(ihip_W_ - hip));
    f.penetration = shaded_penetration(depth, first.normal_W, shaded);
  }
  out->object = first.object;
  out->primitive = first.primitive;
  return f;
}

PointProxy::ForceSource PointProxy::hover_force_source(std::span<const HapticObject> objects,
                                                       const Eigen::Vector3d& hip,
                                                       PointProxyOutput* out) noexcept {
  ForceSource f;
  if (hover_object_ >= static_cast<int32_t>(objects.size()) ||
      objects[hover_object_].mesh == nullptr || objects[hover_object_].texture == nullptr) {
    hover_object_ = -1;
    return f;
  }
  const HapticObject& o = objects[hover_object_];
  const Eigen::Vector3d hip_O = o.pose_WO.inverse() * hip;
  Eigen::Vector3d q_O;
  int32_t rounds = 0;
  hover_primitive_ = local_search(*o.mesh, hover_primitive_, hip_O, &q_O, &rounds);
  stats_.search_iterations += rounds;
  const Eigen::Vector3d n_O = static_cast<double>(hover_side_) * o.mesh->normal(hover_primitive_);
  const double s = (hip_O - q_O).norm();  // above the surface: no crossing was found
  if (s > o.texture->max_height_m()) {
    hover_object_ = -1;
    return f;
  }
  f.penetration = texture_penetration(o, q_O, n_O, s);
  if (f.penetration.squaredNorm() > 0.0) {
    f.law = &o.law;
    f.touched = hover_object_;
    f.contact_O = q_O;
    f.normal_O = n_O;
    f.approach_normal_W = o.pose_WO.linear() * n_O;
    out->texture_contact = true;
    out->object = hover_object_;
    out->primitive = hover_primitive_;
    ++stats_.texture_only_ticks;
  }
  return f;
}

double PointProxy::approach_speed(const HapticObject& touched, const Eigen::Vector3d& hip,
                                  double dt, const ForceSource& f) const noexcept {
  if (!(dt > 0.0)) return 0.0;
  const Eigen::Vector3d surface_now = touched.pose_WO * f.contact_O;
  const Eigen::Vector3d surface_before = touched.prev_pose_WO * f.contact_O;
  const Eigen::Vector3d relative = ((hip - prev_hip_W_) - (surface_now - surface_before)) / dt;
  return -relative.dot(f.approach_normal_W);
}

void PointProxy::apply_force(std::span<const HapticObject> objects, const Eigen::Vector3d& hip,
                             double dt, const ForceSource& f, PointProxyOutput* out) noexcept {
  if (f.law == nullptr) {
    friction_.phase = FrictionState::Phase::kNone;
    return;
  }
  const HapticObject& touched = objects[f.touched];
  // Damped on the HIP's own velocity, not on the rate of the penetration vector: that jumps with
  // the IHIP (an edge passed, a contact added or released) while the hand moves smoothly.
  out->force_W = contact_force(*f.law, f.penetration, approach_speed(touched, hip, dt, f));
  if (touched.friction == nullptr) {
    friction_.phase = FrictionState::Phase::kNone;
    return;
  }
  const Eigen::Vector3d normal_W = touched.pose_WO.linear() * f.normal_O;
  const double fn = std::max(0.0, out->force_W.dot(normal_W));
  out->friction_W =
      touched.pose_WO.linear() *
      friction_step(*touched.friction, &friction_, f.touched, f.contact_O, f.normal_O, fn);
  out->force_W += out->friction_W;
  const double magnitude = out->force_W.norm();
  if (magnitude > f.law->max_force_n) out->force_W *= f.law->max_force_n / magnitude;
}

PointProxyOutput PointProxy::step(std::span<const HapticObject> objects, const Eigen::Vector3d& hip,
                                  double dt) noexcept {
  ++stats_.steps;
  if (!hip.allFinite()) return fault(hip);
  if (!initialised_) reset(hip);

  // 1. Contacts follow the HIP by local search. One whose HIP has left its object wants
  //    release; it is kept aside with last tick's contact (primitive and plane).
  Leaving leaving;
  follow_contacts(objects, hip, &leaving);
  // 2. The IHIP, then 3. new contacts where the IHIP's path crosses a face from outside.
  Eigen::Vector3d x = combine(hip);
  add_first_contacts(objects, hip, leaving, &x);
  // 4. A contact whose HIP left its object through a face shared with another object still
  //    holds the IHIP while the others would put it below last tick's plane (the crease between
  //    two touching organs); otherwise it is released. A textured object stays watched after
  //    release: its bumps stand above the surface (Figure 6-5).
  hold_or_release(objects, hip, leaving, &x);
  ihip_W_ = x;
  if (count_ > 0) hover_object_ = -1;
  if (count_ == 0 && hover_object_ < 0) find_hover(objects, hip);

  // 5. Force (§4.4) from the penetration vector, with the stiffest law among the contacts;
  //    shading (§6.1) or texture (§6.3) where one object is touched; then friction (§6.2).
  PointProxyOutput out;
  ForceSource source;
  if (count_ > 0) {
    source = contact_force_source(objects, hip, &out);
  } else if (hover_object_ >= 0) {
    source = hover_force_source(objects, hip, &out);
  }
  apply_force(objects, hip, dt, source, &out);
  prev_hip_W_ = hip;
  out.ihip_W = ihip_W_;
  out.contact_count = count_;
  if (!out.force_W.allFinite() || !out.ihip_W.allFinite()) return fault(hip);
  return out;
}

}  // namespace lap::haptics
