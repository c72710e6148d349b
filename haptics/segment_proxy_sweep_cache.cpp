// The segment proxy's sweep cache: the faces and contactable edges within reach of the probe,
// copied from the trees so that the swept check of a slow motion reads only the proxy's own
// memory (see SegmentProxy::SweepCache).

#include <algorithm>
#include <array>
#include <cmath>

#include "haptics/closest_point.h"
#include "haptics/segment_contact_geometry.h"
#include "haptics/segment_proxy.h"
#include "haptics/segment_segment.h"

namespace lap::haptics {
namespace {

// The tapered capsule around the probe (a, b) whose point u moves less than
// r(u) = (1 - u) ra + u rb, covered by four capsules that are finer towards the slower end (a
// tool's tip moves slowly while its handle end swings).
std::array<Capsule, 4> tapered_capsule_pieces(const Eigen::Vector3d& A, const Eigen::Vector3d& B,
                                              double ra, double rb) {
  constexpr std::array<double, 5> kBreaks = {0.0, 1.0 / 64.0, 1.0 / 16.0, 1.0 / 4.0, 1.0};
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
  return pieces;
}

}  // namespace

bool SegmentProxy::cache_covers(std::span<const HapticObject> objects, const Eigen::Vector3d& a0,
                                const Eigen::Vector3d& b0, const Eigen::Vector3d& a1,
                                const Eigen::Vector3d& b1) const noexcept {
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
// within that tapered capsule.
bool SegmentProxy::fill_cache(std::span<const HapticObject> objects, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, double ra, double rb) noexcept {
  SweepCache& c = cache_;
  c.valid = false;
  if (objects.size() > static_cast<size_t>(kCacheObjects)) return false;
  ++stats_.cache_rebuilds;
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
    if (!cache_faces(sd, k, 0, A, ra, scratch) || !cache_faces(sd, k, 1, B, rb, scratch) ||
        !cache_edges(sd, k, A, B, ra, rb, scratch)) {
      return false;
    }
    const MeshDatabase& m = sd.mesh();
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

bool SegmentProxy::cache_faces(const SegmentDatabase& sd, int32_t k, int end,
                               const Eigen::Vector3d& p, double r,
                               std::span<int32_t> scratch) noexcept {
  SweepCache& c = cache_;
  const MeshDatabase& m = sd.mesh();
  const int32_t room = kCacheFaces - c.face_count[end];
  const int32_t n = sd.faces_near_point(p, r, {scratch.data(), static_cast<size_t>(room)});
  if (n < 0) return false;
  for (int32_t i = 0; i < n; ++i) {
    CachedFace& cf = c.faces[end][c.face_count[end]++];
    cf.object = k;
    cf.index = scratch[i];
    cf.vertex = m.face_vertices(scratch[i]);
    for (int j = 0; j < 3; ++j) cf.p[j] = m.position(cf.vertex[j]);
    cf.n = (cf.p[1] - cf.p[0]).cross(cf.p[2] - cf.p[0]);
    cf.two_sided = sd.two_sided();
    TriangleFeature feature{};
    cf.clearance = (closest_on_triangle(p, cf.p[0], cf.p[1], cf.p[2], &feature) - p).norm();
  }
  return true;
}

bool SegmentProxy::cache_edges(const SegmentDatabase& sd, int32_t k, const Eigen::Vector3d& A,
                               const Eigen::Vector3d& B, double ra, double rb,
                               std::span<int32_t> scratch) noexcept {
  SweepCache& c = cache_;
  const MeshDatabase& m = sd.mesh();
  const std::array<Capsule, 4> pieces = tapered_capsule_pieces(A, B, ra, rb);
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
    ce.outward = static_cast<double>(sd.convex_side(scratch[i])) * m.edge_normal(scratch[i]);
    const SegmentPair cp = closest_segment_segment(A, B, ce.c, ce.d);
    ce.clearance = (cp.p - cp.q).norm();
  }
  return true;
}

}  // namespace lap::haptics
