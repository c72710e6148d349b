#include "tests/support/brute_force_reference.h"

#include <algorithm>
#include <limits>
#include <vector>

#include "haptics/closest_point.h"
#include "haptics/segment_segment.h"
#include "haptics/segment_triangle.h"

namespace lap::haptics {

ReferenceClosest reference_closest_point(const MeshDatabase& m, const Eigen::Vector3d& p) {
  ReferenceClosest best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int32_t f = 0; f < m.face_count(); ++f) {
    const auto& v = m.face_vertices(f);
    TriangleFeature feature;
    const Eigen::Vector3d q =
        closest_on_triangle(p, m.position(v[0]), m.position(v[1]), m.position(v[2]), &feature);
    const double d2 = (q - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best.face = f;
      best.point = q;
    }
  }
  best.distance = std::sqrt(best_d2);
  return best;
}

ReferenceCrossing reference_first_crossing(const MeshDatabase& m, const Eigen::Vector3d& p0,
                                           const Eigen::Vector3d& p1, bool two_sided) {
  ReferenceCrossing best;
  best.t = std::numeric_limits<double>::infinity();
  for (int32_t f = 0; f < m.face_count(); ++f) {
    const auto& v = m.face_vertices(f);
    const SegmentCrossing s = segment_crosses_triangle(
        p0, p1, m.position(v[0]), v[0], m.position(v[1]), v[1], m.position(v[2]), v[2]);
    if (s.hit && (two_sided || s.from_front) && s.t < best.t) {
      best.face = f;
      best.t = s.t;
      best.from_front = s.from_front;
    }
  }
  if (best.face < 0) best.t = 0.0;
  return best;
}

bool reference_inside(const MeshDatabase& m, const Eigen::Vector3d& p) {
  // A ray far beyond the mesh in a direction unlikely to graze any edge or vertex exactly.
  const Eigen::Vector3d dir =
      Eigen::Vector3d(0.5773502691896258, 0.5773502691896257, 0.5773502691896259)
          .cross(Eigen::Vector3d(0.1234567, 0.7654321, 0.3141592))
          .normalized();
  double reach = 0.0;
  for (int32_t v = 0; v < m.vertex_count(); ++v)
    reach = std::max(reach, (m.position(v) - p).norm());
  const Eigen::Vector3d far = p + dir * (2.0 * reach + 1.0);
  int crossings = 0;
  for (int32_t f = 0; f < m.face_count(); ++f) {
    const auto& v = m.face_vertices(f);
    const SegmentCrossing s = segment_crosses_triangle(
        p, far, m.position(v[0]), v[0], m.position(v[1]), v[1], m.position(v[2]), v[2]);
    crossings += s.hit ? 1 : 0;
  }
  return (crossings % 2) == 1;
}

ReferenceSegmentDistance reference_segment_distance(const MeshDatabase& m, const Eigen::Vector3d& a,
                                                    const Eigen::Vector3d& b) {
  ReferenceSegmentDistance best;
  best.distance = std::numeric_limits<double>::infinity();
  auto consider = [&](int32_t f, const Eigen::Vector3d& on_segment,
                      const Eigen::Vector3d& on_surface) {
    const double d = (on_segment - on_surface).norm();
    if (d < best.distance) {
      best.distance = d;
      best.face = f;
      best.on_segment = on_segment;
      best.on_surface = on_surface;
    }
  };
  for (int32_t f = 0; f < m.face_count(); ++f) {
    const auto& v = m.face_vertices(f);
    const Eigen::Vector3d& p0 = m.position(v[0]);
    const Eigen::Vector3d& p1 = m.position(v[1]);
    const Eigen::Vector3d& p2 = m.position(v[2]);
    const SegmentCrossing s = segment_crosses_triangle(a, b, p0, v[0], p1, v[1], p2, v[2]);
    if (s.hit) {
      const Eigen::Vector3d x = a + s.t * (b - a);
      consider(f, x, x);
      continue;
    }
    TriangleFeature feature;
    consider(f, a, closest_on_triangle(a, p0, p1, p2, &feature));
    consider(f, b, closest_on_triangle(b, p0, p1, p2, &feature));
    for (int k = 0; k < 3; ++k) {
      const SegmentPair cp =
          closest_segment_segment(a, b, m.position(v[k]), m.position(v[(k + 1) % 3]));
      consider(f, cp.p, cp.q);
    }
  }
  return best;
}

bool reference_segment_penetrates(const MeshDatabase& m, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, double tolerance) {
  // The segment alternates between outside and inside at each crossing of the surface; every
  // inside stretch is measured by the depth of its midpoint (and the end points').
  std::vector<double> ts;
  for (int32_t f = 0; f < m.face_count(); ++f) {
    const auto& v = m.face_vertices(f);
    const SegmentCrossing s = segment_crosses_triangle(
        a, b, m.position(v[0]), v[0], m.position(v[1]), v[1], m.position(v[2]), v[2]);
    if (s.hit) ts.push_back(s.t);
  }
  std::sort(ts.begin(), ts.end());
  // A crossing through an edge or vertex is reported by each face there: count it once.
  ts.erase(std::unique(ts.begin(), ts.end(), [](double x, double y) { return y - x < 1e-12; }),
           ts.end());
  ts.insert(ts.begin(), 0.0);
  ts.push_back(1.0);
  bool inside = reference_inside(m, a);
  for (size_t i = 0; i + 1 < ts.size(); ++i) {
    if (inside) {
      for (double t : {ts[i], 0.5 * (ts[i] + ts[i + 1]), ts[i + 1]}) {
        if (reference_closest_point(m, a + t * (b - a)).distance > tolerance) return true;
      }
    }
    inside = !inside;
  }
  return false;
}

void BruteForcePointProxy::reset(const Eigen::Vector3d& hip) {
  in_contact_ = false;
  prev_hip_ = hip;
  ihip_ = hip;
}

Eigen::Vector3d BruteForcePointProxy::step(const MeshDatabase& m, const Eigen::Vector3d& hip) {
  if (!in_contact_) {
    const ReferenceCrossing c = reference_first_crossing(m, prev_hip_, hip, false);
    in_contact_ = c.face >= 0;
  }
  if (in_contact_) {
    const ReferenceClosest r = reference_closest_point(m, hip);
    ihip_ = r.point;
    if ((ihip_ - hip).dot(m.face_normal(r.face)) < 0.0) in_contact_ = false;
  }
  if (!in_contact_) ihip_ = hip;
  prev_hip_ = hip;
  return ihip_;
}

}  // namespace lap::haptics
