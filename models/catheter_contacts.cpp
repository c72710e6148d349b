#include "models/catheter_contacts.h"

#include <algorithm>

#include "haptics/point_proxy.h"

namespace lap::models {

namespace {

// Where a primitive lies with respect to the openings: the wall, an opening's rim (an open
// surface's boundary — the duct's ends — or the edge between an open face and a closed one),
// or inside an opening (only open faces about it).
enum class Opening { kWall, kRim, kHole };

// Face f of the database (tree order); open_faces is in the order of the mesh it was built from.
bool is_open(const haptics::MeshDatabase& m, std::span<const uint8_t> open_faces, int32_t f) {
  return f < 0 || (!open_faces.empty() && open_faces[static_cast<size_t>(m.original_face(f))] != 0);
}

Opening opening(const haptics::MeshDatabase& m, haptics::PrimitiveRef p,
                std::span<const uint8_t> open_faces) {
  if (!m.has_boundary() && open_faces.empty()) return Opening::kWall;
  int32_t open = 0;
  int32_t closed = 0;
  auto count = [&](int32_t f) { is_open(m, open_faces, f) ? ++open : ++closed; };
  if (p.kind == haptics::PrimitiveKind::kFace) {
    count(p.index);
  } else if (p.kind == haptics::PrimitiveKind::kEdge) {
    for (const int32_t f : m.edge_faces(p.index)) count(f);
  } else {
    // A vertex: its faces, and past a boundary edge of them, the missing face beyond.
    m.for_each_vertex_face(p.index, [&](int32_t f) {
      count(f);
      for (const int32_t e : m.face_edges(f)) {
        if (m.edge_faces(e)[1] < 0) ++open;
      }
    });
  }
  if (closed == 0) return Opening::kHole;
  return open > 0 ? Opening::kRim : Opening::kWall;
}

// Beside an opening: a rim, or a wall face with a corner on an open face (or on the surface's
// boundary).
bool beside_opening(const haptics::MeshDatabase& m, haptics::PrimitiveRef p, Opening where,
                    std::span<const uint8_t> open_faces) {
  if (where != Opening::kWall) return true;
  if (p.kind != haptics::PrimitiveKind::kFace) return false;
  bool beside = false;
  for (const int32_t v : m.face_vertices(p.index)) {
    m.for_each_vertex_face(v, [&](int32_t f) {
      if (is_open(m, open_faces, f)) beside = true;
      for (const int32_t e : m.face_edges(f)) {
        if (m.edge_faces(e)[1] < 0) beside = true;
      }
    });
  }
  return beside;
}

// The nearest face of p by the tree, and the side of it p is on.
void find_nearest(const haptics::MeshDatabase& surface, const Eigen::Vector3d& p,
                  haptics::PrimitiveRef* nearest, int8_t* side) noexcept {
  Eigen::Vector3d q;
  const int32_t f = surface.nearest_face(p, &q, nullptr);
  if (f < 0) return;
  *nearest = {haptics::PrimitiveKind::kFace, f};
  *side = surface.face_normal(f).dot(p - q) >= 0.0 ? 1 : -1;
}

}  // namespace

SurfaceTracking::SurfaceTracking(const haptics::MeshDatabase& surface,
                                 const Eigen::Isometry3d& pose_WO, const CatheterState& catheter) {
  const Eigen::Isometry3d inv = pose_WO.inverse();
  nearest.resize(catheter.positions.size());
  side.assign(catheter.positions.size(), 1);
  away.assign(catheter.positions.size(), 0);
  for (size_t i = 0; i < catheter.positions.size(); ++i) {
    find_nearest(surface, inv * catheter.positions[i], &nearest[i], &side[i]);
  }
}

void settle_reactions(const CatheterState& c, std::span<SurfaceReaction> reactions) noexcept {
  for (SurfaceReaction& r : reactions) {
    const auto i = static_cast<size_t>(r.particle);
    const Eigen::Vector3d& n = c.contact_normal[i];
    const double push = c.contact_stiffness[i] * (c.contact_offset[i] - n.dot(c.positions[i])) -
                        c.contact_damping[i] * n.dot(c.velocities[i]);
    // With the friction the step applied along the plane, returned to the surface.
    r.force_on_surface_W = -std::max(0.0, push) * n - contact_friction_force(c, r.particle);
  }
}

int32_t catheter_dents(const LocalDeformationModel& model, const haptics::MeshDatabase& rest,
                       const Eigen::Isometry3d& pose_WO, double stiffness_n_per_m,
                       std::span<const SurfaceReaction> reactions,
                       std::span<DeformationContact> out) noexcept {
  if (!(stiffness_n_per_m > 0.0)) return 0;
  int32_t n = 0;
  for (const SurfaceReaction& r : reactions) {
    if (n >= static_cast<int32_t>(out.size())) break;
    // The reaction is on the rest surface already: rest_contact's mapping is the identity here.
    DeformationContact c =
        rest_contact(model, rest, r.primitive, r.point_O,
                     pose_WO.linear().transpose() * r.force_on_surface_W, stiffness_n_per_m);
    if (c.face < 0) continue;
    c.conform = true;
    out[n++] = c;
  }
  return n;
}

void clear_contacts(CatheterState* catheter) noexcept {
  for (double& k : catheter->contact_stiffness) k = 0.0;
  for (double& c : catheter->contact_damping) c = 0.0;
  for (double& mu : catheter->contact_friction) mu = 0.0;
}

int32_t update_surface_contacts(const haptics::MeshDatabase& surface,
                                const Eigen::Isometry3d& pose_WO, const SurfaceContactSettings& s,
                                SurfaceTracking* tracking, CatheterState* cath,
                                std::span<SurfaceReaction> out,
                                std::span<const uint8_t> open_faces) noexcept {
  const Eigen::Isometry3d inv = pose_WO.inverse();
  const std::vector<haptics::BvhNode>& nodes = surface.tree().nodes();
  const haptics::BvhNode* root = nodes.empty() ? nullptr : nodes.data();
  int32_t count = 0;
  for (size_t i = 0; i < cath->positions.size(); ++i) {
    const Eigen::Vector3d p = inv * cath->positions[i];
    if (!p.allFinite()) continue;
    // Beyond the box grown by the clearance no point of the surface is near enough to touch.
    if (root == nullptr ||
        haptics::BoundingVolumeTree::box_distance2(*root, p) > s.clearance_m * s.clearance_m) {
      tracking->away[i] = 1;
      continue;
    }
    if (tracking->away[i] != 0) {  // back: found afresh, as at setup
      find_nearest(surface, p, &tracking->nearest[i], &tracking->side[i]);
      tracking->away[i] = 0;
    }
    Eigen::Vector3d q;
    int32_t rounds = 0;
    haptics::PrimitiveRef prim =
        haptics::PointProxy::local_search(surface, tracking->nearest[i], p, &q, &rounds);
    if (s.keep_side && (p - q).squaredNorm() >= s.clearance_m * s.clearance_m) {
      // Inside a tube the far wall's foot is a local minimum of the distance too: a particle
      // crossing the lumen's axis would keep the far wall and pass the near one unseen. Out of
      // reach of what the local search found, the tree says whether a nearer wall is in reach;
      // it is taken only when clearly nearer (by a quarter of the clearance), not for a tie
      // between the two facets of a valley of the wall, where changing faces back and forth
      // would push the particle along the wall each way in turn.
      Eigen::Vector3d q_tree;
      const int32_t f = surface.nearest_face(p, &q_tree, nullptr);
      if (f >= 0 && (p - q_tree).norm() + 0.25 * s.clearance_m < (p - q).norm()) {
        prim = haptics::PointProxy::local_search(surface, {haptics::PrimitiveKind::kFace, f}, p, &q,
                                                 &rounds);
      }
    }
    tracking->nearest[i] = prim;
    // Past the rim of an open surface (the duct's ends, an incision) there is no wall: a
    // particle whose nearest point is on a rim and which lies off to the side of it rather than
    // in front, or whose nearest point is inside an opening, is free. Passing a rim or an
    // opening is the one way from one side to the other.
    const Opening where = opening(surface, prim, open_faces);
    // Threading an opening: a neighbour along the catheter has passed to the other side, so the
    // catheter's line already goes through the opening; at its edge the particle follows it
    // through (the soft rim gives way to the catheter's body) instead of being held back by the
    // wall beside the opening, which on a chain of particles a few millimetres apart would stop
    // the catheter after its first particle or two.
    const size_t count_n = cath->positions.size();
    const auto other_side = [&](size_t j) {
      return tracking->away[j] == 0 && tracking->side[j] != tracking->side[i];
    };
    const bool threading = (i + 1 < count_n && other_side(i + 1)) || (i > 0 && other_side(i - 1));
    if (threading && (open_faces.size() > 0 || surface.has_boundary()) &&
        beside_opening(surface, prim, where, open_faces)) {
      const double along_normal = surface.normal(prim).dot(p - q);
      if (along_normal != 0.0) tracking->side[i] = along_normal > 0.0 ? 1 : -1;
      continue;
    }
    if (where != Opening::kWall) {
      const Eigen::Vector3d d = p - q;
      const double len = d.norm();
      const double along_normal = surface.normal(prim).dot(d);
      if (where == Opening::kHole || (len > 0.0 && std::abs(along_normal) < 0.7 * len)) {
        if (len > 0.0) tracking->side[i] = along_normal >= 0.0 ? 1 : -1;
        continue;
      }
    }
    Eigen::Vector3d n = surface.normal(prim);
    if (s.from_inside) n = -n;
    if (s.keep_side && tracking->side[i] < 0) n = -n;
    const double distance = n.dot(p - q);  // signed, along the side the particle may be on
    if (distance >= s.clearance_m) continue;
    // The plane the particle must stay beyond: through q + clearance n, in the world frame.
    const Eigen::Vector3d n_W = pose_WO.linear() * n;
    const Eigen::Vector3d q_W = pose_WO * q;
    cath->contact_normal[i] = n_W;
    cath->contact_offset[i] = n_W.dot(q_W) + s.clearance_m;
    cath->contact_stiffness[i] = s.stiffness_n_per_m;
    cath->contact_damping[i] = s.damping_n_s_per_m;
    cath->contact_friction[i] = s.friction_coefficient;
    cath->contact_surface_velocity[i].setZero();
    if (count < static_cast<int32_t>(out.size())) {
      SurfaceReaction& r = out[count++];
      r.particle = static_cast<int32_t>(i);
      r.primitive = prim;
      r.point_O = q;
      r.force_on_surface_W = -s.stiffness_n_per_m * (s.clearance_m - distance) * n_W;
    }
  }
  return count;
}

}  // namespace lap::models
