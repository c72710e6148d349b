#pragma once
/// \file
/// Closest points on the mesh primitives (thesis §4.3), reporting which feature of the primitive
/// the closest point lies on. The local search uses the feature to step down from a face to the
/// edge or vertex where its closest point sits: otherwise a face whose closest point is on its
/// boundary ties with that boundary and the search cannot pass to the next face.
/// Header-only: these run in the haptic step.

#include <Eigen/Core>

namespace lap::haptics {

/// Where on a triangle (a, b, c) the closest point lies. Edges are numbered by their first
/// corner: edge 0 = ab, 1 = bc, 2 = ca.
enum class TriangleFeature : uint8_t {
  kInterior,
  kVertexA,
  kVertexB,
  kVertexC,
  kEdgeAB,
  kEdgeBC,
  kEdgeCA
};

/// Where on a segment the closest point lies.
enum class SegmentFeature : uint8_t { kInterior, kEndA, kEndB };

/// Closest point on segment [a, b] to p.
inline Eigen::Vector3d closest_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, SegmentFeature* feature) {
  const Eigen::Vector3d ab = b - a;
  const double t = (p - a).dot(ab);
  if (t <= 0.0) {
    *feature = SegmentFeature::kEndA;
    return a;
  }
  const double len2 = ab.squaredNorm();
  if (t >= len2) {
    *feature = SegmentFeature::kEndB;
    return b;
  }
  *feature = SegmentFeature::kInterior;
  return a + (t / len2) * ab;
}

/// Closest point on triangle (a, b, c) to p, by Voronoi regions (Ericson, Real-Time Collision
/// Detection, §5.1.5). Exact for sub-micrometre triangles: no tolerance depends on size.
inline Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                           const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                           TriangleFeature* feature) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    *feature = TriangleFeature::kVertexA;
    return a;
  }
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    *feature = TriangleFeature::kVertexB;
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    *feature = TriangleFeature::kEdgeAB;
    return a + (d1 / (d1 - d3)) * ab;
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    *feature = TriangleFeature::kVertexC;
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    *feature = TriangleFeature::kEdgeCA;
    return a + (d2 / (d2 - d6)) * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    *feature = TriangleFeature::kEdgeBC;
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = va + vb + vc;
  if (!(denom > 0.0)) {
    // Collapsed triangle: fall back to its longest edge.
    SegmentFeature f;
    *feature = TriangleFeature::kEdgeAB;
    return closest_on_segment(p, a, b, &f);
  }
  *feature = TriangleFeature::kInterior;
  const double v = vb / denom;
  const double w = vc / denom;
  return a + v * ab + w * ac;
}

/// Barycentric coordinates (weights of a, b, c) of p's projection on the plane of triangle
/// (a, b, c); the centroid's for a degenerate triangle. Not clamped to the triangle.
inline Eigen::Vector3d barycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a;
  const Eigen::Vector3d e2 = c - a;
  const Eigen::Vector3d d = p - a;
  const double d11 = e1.dot(e1);
  const double d12 = e1.dot(e2);
  const double d22 = e2.dot(e2);
  const double det = d11 * d22 - d12 * d12;
  if (!(det > 0.0)) return Eigen::Vector3d::Constant(1.0 / 3.0);
  const double v = (d22 * d.dot(e1) - d12 * d.dot(e2)) / det;
  const double w = (d11 * d.dot(e2) - d12 * d.dot(e1)) / det;
  return {1.0 - v - w, v, w};
}

}  // namespace lap::haptics
