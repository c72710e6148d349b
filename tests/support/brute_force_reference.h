#pragma once
/// \file
/// Exhaustive reference implementations (no tree, no local search) that the tests and benchmarks
/// compare the proxies against: every face is examined every time.

#include <Eigen/Core>
#include <cstdint>

#include "haptics/mesh_database.h"

namespace lap::haptics {

/// Nearest point of the whole surface to p.
struct ReferenceClosest {
  int32_t face = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double distance = 0.0;
};
[[nodiscard]] ReferenceClosest reference_closest_point(const MeshDatabase& mesh,
                                                       const Eigen::Vector3d& p);

/// First face crossed by segment p0 -> p1 (from the front only, unless two_sided).
struct ReferenceCrossing {
  int32_t face = -1;
  double t = 0.0;
  bool from_front = true;
};
[[nodiscard]] ReferenceCrossing reference_first_crossing(const MeshDatabase& mesh,
                                                         const Eigen::Vector3d& p0,
                                                         const Eigen::Vector3d& p1, bool two_sided);

/// Is p inside the closed mesh? Parity of crossings along a ray in a fixed irrational direction.
[[nodiscard]] bool reference_inside(const MeshDatabase& mesh, const Eigen::Vector3d& p);

/// Distance from segment a-b to the whole surface (0 when they intersect), by testing every
/// face: segment–triangle distance from the triangle's three edges against the segment and the
/// segment's end points against the triangle, or zero when the segment crosses the triangle.
struct ReferenceSegmentDistance {
  int32_t face = -1;
  double distance = 0.0;
  Eigen::Vector3d on_segment = Eigen::Vector3d::Zero();
  Eigen::Vector3d on_surface = Eigen::Vector3d::Zero();
};
[[nodiscard]] ReferenceSegmentDistance reference_segment_distance(const MeshDatabase& mesh,
                                                                  const Eigen::Vector3d& a,
                                                                  const Eigen::Vector3d& b);

/// Does segment a-b reach into the interior of the closed mesh by more than `tolerance`? True
/// when it crosses a face with both sides of the crossing more than `tolerance` from that face's
/// plane, or when its end points or midpoint lie inside (parity) more than `tolerance` deep.
[[nodiscard]] bool reference_segment_penetrates(const MeshDatabase& mesh, const Eigen::Vector3d& a,
                                                const Eigen::Vector3d& b, double tolerance);

/// A point proxy built only from the exhaustive queries: first contact by testing the path
/// against every face, then the IHIP at the globally nearest surface point while inside.
class BruteForcePointProxy {
 public:
  void reset(const Eigen::Vector3d& hip);
  /// Returns the IHIP.
  Eigen::Vector3d step(const MeshDatabase& mesh, const Eigen::Vector3d& hip);
  [[nodiscard]] bool in_contact() const { return in_contact_; }

 private:
  bool in_contact_ = false;
  Eigen::Vector3d prev_hip_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d ihip_ = Eigen::Vector3d::Zero();
};

}  // namespace lap::haptics
