// The ideal probe pushed out of a surface that moved onto it.
//
// The swept checks (segment_proxy_sweep.cpp) keep the ideal probe out of every object while the
// probe moves, and a rigid object's motion is swept too (its previous pose, §6.4). A deforming
// organ's new shape (§6.5) arrives as a whole, once per modelling step: where it rises onto a
// part of the probe that has no contact there — a dent springing back under a shaft that lay
// above it, one jaw's dent filling under the other jaw — that part is inside at once and no
// sweep ever crosses the surface again. The probe would then rest inside, the tool feel nothing
// there, and the tissue be drawn through it. (For a locally deformed organ and a gripper's
// segment the model now stops the surface short of it: models/local_deformation.h,
// DeformationObstacle. Not for a probe, the duct, or the surface between vertices.) So on each
// tick whose surface differs from the one the probe last saw, a closed object is tested for the
// probe crossing its surface, and the probe is translated out of it, the way it went in (along the
// outward normals where it crosses the surface) and as far as its deepest part inside needs: the
// organ pushed it. The rest of the tick then meets the surface from outside, as a contact that
// pushes the tool back. (Pushing the deepest point to its nearest surface point instead sent shafts
// out of the gallbladder through its side against the liver bed, into the liver.)
//
// A probe that starts inside an object (set there by a reset) is not in contact with it, as in
// the thesis: it is left inside until a check finds it clear. A push is not swept: it may end
// inside a neighbouring organ (a crease), so after a push every closed object is checked once
// more that tick.

#include <algorithm>
#include <cmath>

#include "haptics/mesh_database.h"
#include "haptics/segment_proxy.h"

namespace lap::haptics {
namespace {

// Rounds of push-out per object and tick: each clears the part inside it measured; a probe
// lying across two bumps needs two.
constexpr int kPushOutRounds = 4;
// Points of the probe's part inside (its ends included) whose depth along the way out is
// measured.
constexpr int kInsideSamples = 6;
// Length of the rays that tell inside from outside and measure depths [m]: beyond any organ.
constexpr double kReach = 0.1;
// The deepest a surface's motion over one modelling step can put a probe [m]: a dent springing
// back by its depth at most (estimate: the soaks' probes were found up to 3.7 mm inside, and up
// to 7.3 mm with the push capped at 5 mm). A probe found deeper inside got there some other way
// and is left as it was: in the easy patient's expert run a jaw was found 2 cm inside an organ
// at 1.3 s, and pushing it out threw the tool onto the liver (1.13 N sent, against 0.54 N
// without the push).
constexpr double kMaxPushM = 0.01;

// A closed, one-sided surface: only such an object has an inside to push a probe out of.
bool has_inside(const HapticObject& o) {
  return o.segments != nullptr && !o.two_sided && !o.segments->mesh().has_boundary();
}

}  // namespace

bool SegmentProxy::partly_inside(const MeshDatabase& m, const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b, Eigen::Vector3d* push) noexcept {
  const Eigen::Vector3d axis = b - a;
  const double length = axis.norm();
  if (!(length > 0.0)) return false;
  const Eigen::Vector3d d = axis / length;
  // Nowhere near the organ (on most ticks most organs): outside, without casting a ray. The
  // tree's root box bounds every face (rounded outward, refitted with every change), so a probe
  // missing it is wholly outside a closed surface that does not cross itself, and no ray along
  // it meets a face. (Where a dent has folded the surface through itself, the ray behind the
  // probe below could meet a face from behind and say inside where this says outside, the better
  // answer for a point outside the organ's box.) The first test the push-out stage makes of
  // every closed organ whose surface moved, for each proxy: 42 times a modelling step in the
  // hardest patient's expert run, where it doubled the haptic tick that follows a step
  // (docs/benchmarks.md).
  if (!m.tree().segment_touches_bounds(a, b)) return false;
  // The first crossings of the surface along the probe, from either end (either side). An end
  // is inside when the first crossing from it leaves the surface (the mesh is closed and
  // outward-facing), or when the first crossing from the other end enters it and nothing
  // crossed from this one (that crossing lies on this end's face plane). With no crossing at
  // all, both ends are on the side a ray from a away from b first leaves (none: outside).
  const MeshDatabase::Crossing from_a = m.first_crossing(a, b, true);
  const MeshDatabase::Crossing from_b = m.first_crossing(b, a, true);
  bool a_inside = false;
  bool b_inside = false;
  if (from_a.face < 0 && from_b.face < 0) {
    // Crossing nothing, the probe is on one side; outside if an end lies outside the bounds.
    if (!m.tree().segment_touches_bounds(a, a)) return false;
    const MeshDatabase::Crossing behind = m.first_crossing(a, a - kReach * d, true);
    a_inside = b_inside = behind.face >= 0 && !behind.from_front;
  } else {
    a_inside = from_a.face >= 0 ? !from_a.from_front : from_b.from_front;
    b_inside = from_b.face >= 0 ? !from_b.from_front : from_a.from_front;
  }
  // The part inside, [u0, u1] along a -> b: from a to where it leaves, from where it enters to
  // b, or, with both ends out, a bump through its middle. (Both ends inside with the probe out
  // between them: a's end goes first.)
  double u0 = 0.0;
  double u1 = 1.0;
  if (a_inside) {
    u1 = from_a.face >= 0 ? from_a.t : 1.0;
  } else if (b_inside) {
    u0 = from_b.face >= 0 ? 1.0 - from_b.t : 0.0;
  } else if (from_a.face >= 0 && from_b.face >= 0 && from_a.t < 1.0 - from_b.t) {
    u0 = from_a.t;
    u1 = 1.0 - from_b.t;
  } else {
    return false;
  }
  // Out the way it went in: along the outward normals of the faces it crosses, without their
  // part along the probe (which would slide it, not lift it out). Where they cancel (a thin
  // fold) or the probe crosses nothing (wholly inside), along the normal of the face nearest
  // the middle of its part inside.
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  if (from_a.face >= 0) n += m.face_normal(from_a.face);
  if (from_b.face >= 0) n += m.face_normal(from_b.face);
  n -= n.dot(d) * d;
  if (!(n.norm() > 0.5)) {
    Eigen::Vector3d q;
    const int32_t f = m.nearest_face(a + 0.5 * (u0 + u1) * axis, &q, nullptr);
    if (f < 0) return false;
    n = m.face_normal(f);
  }
  n.normalize();
  // As far along n as the deepest of its sampled points inside is from leaving that way.
  double out = 0.0;
  for (int i = 0; i < kInsideSamples; ++i) {
    const double u = u0 + (u1 - u0) * i / (kInsideSamples - 1.0);
    const Eigen::Vector3d p = a + u * axis;
    const MeshDatabase::Crossing exit = m.first_crossing(p, p + kReach * n, true);
    if (exit.face >= 0 && !exit.from_front) out = std::max(out, exit.t * kReach);
  }
  // No way out that way, or one deeper than a surface moves in a modelling step: nothing done
  // (a probe that deep did not get there by the surface's motion; see the file's head).
  if (!(out > 0.0) || out > kMaxPushM) return false;
  *push = out * n;
  return true;
}

bool SegmentProxy::push_out_of(const HapticObject& o) noexcept {
  const MeshDatabase& m = o.segments->mesh();
  const Eigen::Isometry3d inv = o.pose_WO.inverse();
  Eigen::Vector3d a = inv * ideal_a_;
  Eigen::Vector3d b = inv * ideal_b_;
  Eigen::Vector3d to_surface;
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int round = 0; round < kPushOutRounds && partly_inside(m, a, b, &to_surface); ++round) {
    // Out to the surface, and the proxies' clearance beyond it.
    const Eigen::Vector3d push = to_surface * (1.0 + settings_.skin_m / to_surface.norm());
    a += push;
    b += push;
    total += push;
  }
  // Nothing to do, or deeper than a surface's motion: left as it was. (Each round moves it.)
  const double moved = total.norm();
  if (moved == 0.0 || moved > kMaxPushM) return false;
  ideal_a_ = o.pose_WO * a;
  ideal_b_ = o.pose_WO * b;
  return true;
}

void SegmentProxy::push_out_of_moved_surfaces(std::span<const HapticObject> objects) noexcept {
  bool pushed = false;
  for (size_t k = 0; k < objects.size(); ++k) {
    const HapticObject& o = objects[k];
    if (!has_inside(o)) continue;
    const MeshDatabase& m = o.segments->mesh();
    if (k < seen_.size()) {
      SeenSurface& seen = seen_[k];
      const bool first = seen.mesh == nullptr;
      const bool same = seen.mesh == &m && seen.revision == m.revision();
      seen.mesh = &m;
      seen.revision = m.revision();
      if (same) continue;
      // Set here by a reset (first sight), or still inside since: not a contact while it stays.
      if (first || seen.started_inside) {
        const Eigen::Isometry3d inv = o.pose_WO.inverse();
        Eigen::Vector3d unused;
        seen.started_inside = partly_inside(m, inv * ideal_a_, inv * ideal_b_, &unused);
        continue;
      }
    }
    pushed = push_out_of(o) || pushed;
  }
  if (!pushed) return;
  ++stats_.surface_push_outs;
  // Once more, every closed object as it is (the pushes were not swept), but one the probe
  // started inside.
  for (size_t k = 0; k < objects.size(); ++k) {
    if (!has_inside(objects[k]) || (k < seen_.size() && seen_[k].started_inside)) continue;
    push_out_of(objects[k]);
  }
}

}  // namespace lap::haptics
