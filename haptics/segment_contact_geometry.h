#pragma once
/// \file
/// Geometry the segment proxy's stages share (segment_proxy*.cpp): the probe's point at a
/// parameter, and the outward normal of a segment–edge contact with the α/β test of Figure 5-9.
/// Inline, allocation-free and non-throwing: the haptic step calls them.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "haptics/mesh_database.h"

namespace lap::haptics {

/// The point at parameter u of the segment a -> b (0 at a, 1 at b).
inline Eigen::Vector3d lerp(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double u) {
  return a + u * (b - a);
}

/// The α/β test of Figure 5-9, as a normal cone: the plane of a segment–edge contact (normal m,
/// perpendicular to the edge) is a supporting plane only while m lies between the normals n1, n2
/// of the edge's two faces. Past one of them the probe would cut that face: the contact becomes
/// segment–face and takes the face's normal. Returns true when m was clamped.
inline bool clamp_to_normal_cone(const Eigen::Vector3d& axis, const Eigen::Vector3d& n1,
                                 const Eigen::Vector3d& n2, Eigen::Vector3d* m) {
  const double s12 = n1.cross(n2).dot(axis);
  const double s1 = n1.cross(*m).dot(axis);  // α side
  const double s2 = m->cross(n2).dot(axis);  // β - α side
  const bool inside = (s12 >= 0.0) ? (s1 >= 0.0 && s2 >= 0.0) : (s1 <= 0.0 && s2 <= 0.0);
  if (inside) return false;
  *m = m->dot(n1) >= m->dot(n2) ? n1 : n2;
  return true;
}

/// Outward normal of a segment–edge contact for a probe along w touching edge e (Figure 5-13b):
/// perpendicular to both, on the side the edge is convex from (convex_side: +1 its own normal's,
/// -1 the back of a two-sided surface; SegmentDatabase::convex_side); the edge normal itself when
/// the probe is parallel to the edge. `side` orients boundary edges (convex_side 0: either side).
inline Eigen::Vector3d edge_contact_normal(const MeshDatabase& mesh, int32_t e, int8_t convex_side,
                                           const Eigen::Vector3d& w, const Eigen::Vector3d& side) {
  const auto& ev = mesh.edge_vertices(e);
  const auto& ef = mesh.edge_faces(e);
  const Eigen::Vector3d axis = mesh.position(ev[1]) - mesh.position(ev[0]);
  // The edge normal is the normalised sum of its faces' normals (MeshDatabase::edge_normal),
  // computed here from the two normals the cone test needs anyway; orienting m needs only the
  // sum's direction, so it is normalised only when it is the answer.
  const bool boundary = ef[1] < 0;
  // Seen from the back, the faces' normals are reversed.
  const double s = convex_side < 0 ? -1.0 : 1.0;
  const Eigen::Vector3d n1 = s * mesh.face_normal(ef[0]);
  const Eigen::Vector3d n2 = boundary ? n1 : Eigen::Vector3d(s * mesh.face_normal(ef[1]));
  const Eigen::Vector3d sum = n1 + n2;
  Eigen::Vector3d m = w.cross(axis);
  const double norm2 = m.squaredNorm();
  if (!(norm2 > 1e-18 * w.squaredNorm() * axis.squaredNorm())) {
    const double sum_norm = sum.norm();
    const Eigen::Vector3d n = sum_norm > 0.0 ? Eigen::Vector3d(sum / sum_norm) : n1;
    return boundary && n.dot(side) < 0.0 ? Eigen::Vector3d(-n) : n;
  }
  m /= std::sqrt(norm2);
  const double orient = boundary ? m.dot(side) : m.dot(sum);
  if (orient < 0.0) m = -m;
  if (!boundary) clamp_to_normal_cone(axis, n1, n2, &m);
  return m;
}

}  // namespace lap::haptics
