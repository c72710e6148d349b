#pragma once
/// \file
/// Does a short segment (the HIP's path over one tick) cross a triangle, and from which side?
/// Watertight: the side of the segment relative to each triangle edge is computed from the edge's
/// two vertices in a canonical order (by vertex index), so the two triangles sharing an edge get
/// exactly opposite values and a path through the edge cannot slip between them.
/// Header-only: used in the haptic step (first contact, §4.3).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace lap::haptics {

/// Result of a crossing test.
struct SegmentCrossing {
  bool hit = false;
  double t = 0.0;           ///< crossing at p0 + t (p1 - p0), t in [0, 1]
  bool from_front = false;  ///< p0 on the side the (counter-clockwise) normal points to
};

/// Signed volume of (a - p0, b - p0, d): which side of the edge a->b the line p0 + s d passes.
inline double edge_side(const Eigen::Vector3d& p0, const Eigen::Vector3d& d,
                        const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - p0).cross(b - p0).dot(d);
}

/// Canonical edge side: evaluated with the lower-indexed vertex first, negated if needed, so that
/// both triangles of a shared edge see bit-identical magnitudes.
inline double canonical_edge_side(const Eigen::Vector3d& p0, const Eigen::Vector3d& d,
                                  const Eigen::Vector3d& a, int32_t ia, const Eigen::Vector3d& b,
                                  int32_t ib) {
  return ia < ib ? edge_side(p0, d, a, b) : -edge_side(p0, d, b, a);
}

/// Where the line p0 + s d passes triangle (a, b, c): inside (or on its boundary) when the three
/// canonical edge sides agree in sign; kDegenerate when all three vanish (the line lies in the
/// triangle's plane).
enum class LinePass : uint8_t { kOutside, kInside, kDegenerate };
inline LinePass line_through_triangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& d,
                                      const Eigen::Vector3d& a, int32_t ia,
                                      const Eigen::Vector3d& b, int32_t ib,
                                      const Eigen::Vector3d& c, int32_t ic) {
  const double e0 = canonical_edge_side(p0, d, a, ia, b, ib);
  const double e1 = canonical_edge_side(p0, d, b, ib, c, ic);
  const double e2 = canonical_edge_side(p0, d, c, ic, a, ia);
  const bool inside =
      (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0);
  if (!inside) return LinePass::kOutside;
  return (e0 == 0.0 && e1 == 0.0 && e2 == 0.0) ? LinePass::kDegenerate : LinePass::kInside;
}

/// Tests segment p0 -> p1 against triangle (a, b, c) with vertex indices (ia, ib, ic).
/// A crossing needs p0 strictly on one side of the triangle's plane and p1 on the other side or
/// on the plane: a path that starts on the surface (a proxy leaving it) is not a new contact.
inline SegmentCrossing segment_crosses_triangle(const Eigen::Vector3d& p0,
                                                const Eigen::Vector3d& p1, const Eigen::Vector3d& a,
                                                int32_t ia, const Eigen::Vector3d& b, int32_t ib,
                                                const Eigen::Vector3d& c, int32_t ic) {
  SegmentCrossing r;
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double s0 = n.dot(p0 - a);
  const double s1 = n.dot(p1 - a);
  const bool front_to_back = s0 > 0.0 && s1 <= 0.0;
  const bool back_to_front = s0 < 0.0 && s1 >= 0.0;
  if (!front_to_back && !back_to_front) return r;
  if (line_through_triangle(p0, p1 - p0, a, ia, b, ib, c, ic) != LinePass::kInside) return r;
  r.hit = true;
  r.t = s0 / (s0 - s1);
  r.from_front = front_to_back;
  return r;
}

/// A.7 for the segment proxy's end points: the parameter at which p0 -> p1 crosses triangle
/// (a, b, c) from its front (-1: none). A start exactly on the plane counts, so an end point
/// resting on the surface cannot slip in; a path leaving through the back is not a contact.
/// `n` is the triangle's unnormalised normal (b - a) × (c - a), which a caller testing the same
/// triangle often may keep.
inline double front_crossing_time(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                  const Eigen::Vector3d& n, const Eigen::Vector3d& a, int32_t ia,
                                  const Eigen::Vector3d& b, int32_t ib, const Eigen::Vector3d& c,
                                  int32_t ic) {
  const double s0 = n.dot(p0 - a);
  const double s1 = n.dot(p1 - a);
  if (!(s0 >= 0.0 && s1 < 0.0)) return -1.0;
  if (line_through_triangle(p0, p1 - p0, a, ia, b, ib, c, ic) == LinePass::kOutside) return -1.0;
  return s0 / (s0 - s1);
}

inline double front_crossing_time(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                  const Eigen::Vector3d& a, int32_t ia, const Eigen::Vector3d& b,
                                  int32_t ib, const Eigen::Vector3d& c, int32_t ic) {
  return front_crossing_time(p0, p1, (b - a).cross(c - a), a, ia, b, ib, c, ic);
}

/// The same for a two-sided (open, thin) surface: a crossing from either side, *side = +1 when
/// from the front, -1 from the back. The line test does not depend on the triangle's winding.
inline double crossing_time(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& n, bool two_sided, const Eigen::Vector3d& a,
                            int32_t ia, const Eigen::Vector3d& b, int32_t ib,
                            const Eigen::Vector3d& c, int32_t ic, int8_t* side) {
  *side = 1;
  const double t = front_crossing_time(p0, p1, n, a, ia, b, ib, c, ic);
  if (t >= 0.0 || !two_sided) return t;
  *side = -1;
  return front_crossing_time(p0, p1, -n, a, ia, b, ib, c, ic);
}

}  // namespace lap::haptics
