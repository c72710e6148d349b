// Surface properties at the segment proxy's contacts (thesis chapter 6, which applies them to the
// ray-based probe too, at its contact points): where on the surface a contact acts, the
// penetration vector with force shading (§6.1) or a texture (§6.3), and stick-slip friction
// (§6.2) with a state per contact.

#include <algorithm>
#include <cmath>

#include "haptics/segment_proxy.h"
#include "haptics/shading_normals.h"
#include "haptics/texture_force.h"

namespace lap::haptics {

SegmentProxy::SurfacePoint SegmentProxy::surface_point(
    const HapticObject& o, const SegmentContact& contact,
    const Eigen::Vector3d& on_plane_W) const noexcept {
  // The contact's feature is the primitive under the point: for an end point, what this tick's
  // local search found nearest to it (chapter 4); for a segment–edge contact, the edge; for a
  // probe lying on a face, a face of that flat (whose triangles' corner normals differ by less
  // than θε, so which one interpolates hardly matters).
  return {contact.primitive, o.pose_WO.inverse() * on_plane_W,
          o.pose_WO.linear().transpose() * contact.normal_W};
}

Eigen::Vector3d SegmentProxy::surface_penetration(const HapticObject& o, const SurfacePoint& s,
                                                  double depth,
                                                  const Eigen::Vector3d& normal_W) noexcept {
  if (o.texture != nullptr) {
    // §6.3.1 with the nearest distance -depth below the contact plane (§6.6: a texture wins
    // over shading).
    return o.pose_WO.linear() * texture_penetration(*o.texture, o.texture_k, s.q_O, s.n_O, -depth);
  }
  if (o.shading == nullptr || s.primitive.kind == PrimitiveKind::kNone) return -depth * normal_W;
  // §6.1, Figure 6-3: along the shaded normal, on the side the contact is on (two-sided walls
  // are touched from behind too).
  Eigen::Vector3d shaded = o.shading->normal(o.segments->mesh(), s.primitive, s.q_O);
  if (shaded.dot(s.n_O) < 0.0) shaded = -shaded;
  return shaded_penetration(depth, normal_W, o.pose_WO.linear() * shaded);
}

Eigen::Vector3d SegmentProxy::contact_friction(const HapticObject& o, int contact,
                                               const SurfacePoint& s, double fn) noexcept {
  const int32_t object = contacts_[contact].object;
  int32_t ordinal = 0;
  for (int i = 0; i < contact; ++i) ordinal += contacts_[i].object == object ? 1 : 0;
  FrictionSlot* slot = nullptr;
  FrictionSlot* free_slot = nullptr;
  for (FrictionSlot& f : friction_) {
    if (f.object == object && f.ordinal == ordinal && !f.used) slot = &f;
    if (f.object < 0 && free_slot == nullptr) free_slot = &f;
  }
  if (slot == nullptr) {
    if (free_slot == nullptr) return Eigen::Vector3d::Zero();  // never: a slot per constraint
    slot = free_slot;
    slot->object = object;
    slot->ordinal = ordinal;
    slot->state = FrictionState{};
  }
  slot->used = true;
  const int64_t slips = slot->state.stick_to_slide;
  const int64_t sticks = slot->state.slide_to_stick;
  const Eigen::Vector3d f_O = friction_step(*o.friction, &slot->state, object, s.q_O, s.n_O, fn);
  stats_.stick_to_slide += slot->state.stick_to_slide - slips;
  stats_.slide_to_stick += slot->state.slide_to_stick - sticks;
  contacts_[contact].friction_phase = slot->state.phase;
  return o.pose_WO.linear() * f_O;
}

void SegmentProxy::release_unused_friction() noexcept {
  for (FrictionSlot& f : friction_) {
    if (!f.used) f.object = -1;
  }
}

}  // namespace lap::haptics
