#pragma once
/// \file
/// Point-based haptic rendering, "Neighborhood Watch" (thesis chapter 4): the haptic interface
/// point (HIP) follows the device; the ideal haptic interface point (IHIP) stays on the surface.
///
/// - First contact (§4.3): the IHIP's path since the last tick (in free space, the HIP's path)
///   crossing a face from outside, found with the bounding-box tree.
/// - In contact: local search from the contacted primitive over its neighbours (face: its
///   edges and vertices; edge: its vertices and faces; vertex: its faces and edges), repeated
///   until no neighbour is strictly closer to the HIP; IHIP = nearest point on the primitive.
///   Where a face's nearest point lies on one of its edges or vertices, the search steps down to
///   that edge or vertex first (same distance), so it can pass on to the next face.
/// - Release when (IHIP - HIP) . n < 0, n the normal of the contacted primitive.
/// - Thin (open) surfaces are two-sided: the side first touched is kept for the contact.
/// - Moving objects (§6.4): the HIP is taken into each object's frame.
/// - Several objects: each contact constrains the one IHIP (nearest point to the HIP that
///   satisfies every contact's plane), so sliding along one object never enters another.
///
/// The step allocates nothing, takes no lock, never throws; a non-finite input or result zeroes
/// the force, resets the proxy and is counted.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <span>

#include "haptics/force_law.h"
#include "haptics/friction.h"
#include "haptics/haptic_object.h"
#include "haptics/mesh_database.h"

namespace lap::haptics {

/// One contact of the proxy.
struct PointContact {
  int32_t object = -1;
  PrimitiveRef primitive;
  int8_t side = 1;                                      ///< +1 front (normal side), -1 back
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero();    ///< nearest point on the primitive
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitY();  ///< outward, towards the side touched
};

/// What one step produced.
struct PointProxyOutput {
  Eigen::Vector3d ihip_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();  ///< on the HIP (send to the device) [N]
  int32_t contact_count = 0;
  int32_t object = -1;     ///< first contact's object, -1 in free space
  PrimitiveRef primitive;  ///< first contact's primitive
  /// Touching a texture's bump above the original surface (Figure 6-5, HIP_1): a contact with
  /// force although contact_count is 0. Below the surface in a texture's trough (HIP_2),
  /// contact_count is 1 and the force may be zero.
  bool texture_contact = false;
  Eigen::Vector3d friction_W = Eigen::Vector3d::Zero();  ///< friction part of force_W [N]
  bool fault = false;  ///< non-finite input or result: force zeroed, proxy reset
};

/// Counters for tests and statistics.
struct PointProxyStats {
  int64_t steps = 0;
  int64_t first_contacts = 0;
  int64_t releases = 0;
  /// Releases undone because the IHIP's path entered the object again (PointProxy::reentered).
  int64_t reentries = 0;
  int64_t search_iterations = 0;  ///< local-search rounds over all steps
  int64_t search_limit_hits = 0;  ///< searches stopped by the iteration bound
  int64_t faults = 0;
  int64_t texture_only_ticks = 0;  ///< ticks touching a texture above the original surface
};

class PointProxy {
 public:
  static constexpr int kMaxContacts = 4;
  /// Bound on local-search rounds per contact per tick (each round strictly decreases the
  /// distance or steps down a dimension, so this is a guard, not a tuning knob).
  static constexpr int kMaxSearchRounds = 256;

  /// Places the proxy in free space at hip_W.
  void reset(const Eigen::Vector3d& hip_W);

  /// One haptic tick. dt [s] gives the HIP's velocity (from its last position) for the damping.
  PointProxyOutput step(std::span<const HapticObject> objects, const Eigen::Vector3d& hip_W,
                        double dt) noexcept;

  [[nodiscard]] std::span<const PointContact> contacts() const {
    return {contacts_.data(), static_cast<size_t>(count_)};
  }
  [[nodiscard]] const Eigen::Vector3d& ihip() const { return ihip_W_; }
  [[nodiscard]] const PointProxyStats& stats() const { return stats_; }
  [[nodiscard]] const FrictionState& friction_state() const { return friction_; }

  /// Local search on one mesh from `start` for point p (object frame); returns the nearest
  /// primitive found and its nearest point in *q. Exposed for tests and the segment proxy.
  static PrimitiveRef local_search(const MeshDatabase& mesh, PrimitiveRef start,
                                   const Eigen::Vector3d& p, Eigen::Vector3d* q, int32_t* rounds);

 private:
  struct Leaving;      // contacts whose HIP left their object this tick (point_proxy.cpp)
  struct ForceSource;  // what the force comes from (point_proxy.cpp)
  /// The first face one object's IHIP path crosses (stage 3 of step()).
  struct ObjectCrossing {
    int32_t object = -1;  ///< -1: no object is crossed
    MeshDatabase::Crossing crossing;
  };

  // The stages of step(), in order.
  /// Resets the proxy after a non-finite input or result and returns the zero-force output.
  PointProxyOutput fault(const Eigen::Vector3d& hip_W) noexcept;
  /// Stage 1: each contact follows the HIP by local search; those whose HIP left their object
  /// are removed and kept in *leaving.
  void follow_contacts(std::span<const HapticObject> objects, const Eigen::Vector3d& hip_W,
                       Leaving* leaving) noexcept;
  /// Stage 3: adds a contact for each object whose face the IHIP's path crosses from outside,
  /// nearest first, re-placing the IHIP *x after each.
  void add_first_contacts(std::span<const HapticObject> objects, const Eigen::Vector3d& hip_W,
                          const Leaving& leaving, Eigen::Vector3d* x) noexcept;
  /// The earliest crossing of the IHIP's path to x by an object not in contact or leaving.
  [[nodiscard]] ObjectCrossing first_crossing(std::span<const HapticObject> objects,
                                              const Eigen::Vector3d& x,
                                              const Leaving& leaving) const noexcept;
  [[nodiscard]] bool in_contact_or_leaving(int32_t object, const Leaving& leaving) const noexcept;
  /// A new contact on the crossed face, at its nearest point to the HIP (§4.3).
  void add_first_contact(const HapticObject& o, const ObjectCrossing& crossed,
                         const Eigen::Vector3d& hip_W) noexcept;
  /// Stage 4: holds each leaving contact that still constrains the IHIP *x, else releases it.
  /// (Unless the IHIP's path enters its object again: see reentered.)
  void hold_or_release(std::span<const HapticObject> objects, const Eigen::Vector3d& hip_W,
                       const Leaving& leaving, Eigen::Vector3d* x) noexcept;
  /// Whether the IHIP's path to *x enters `object` (one-sided, no other contact on it): then a
  /// contact on the face it enters, and *x re-placed.
  bool reentered(std::span<const HapticObject> objects, int32_t object,
                 const Eigen::Vector3d& hip_W, Eigen::Vector3d* x) noexcept;
  /// Stage 5, in contact: the penetration (shaded or textured where one object is touched).
  [[nodiscard]] ForceSource contact_force_source(std::span<const HapticObject> objects,
                                                 const Eigen::Vector3d& hip_W,
                                                 PointProxyOutput* out) const noexcept;
  /// Stage 5, free of contacts near a textured object: the penetration into its bumps.
  ForceSource hover_force_source(std::span<const HapticObject> objects,
                                 const Eigen::Vector3d& hip_W, PointProxyOutput* out) noexcept;
  /// Stage 5: the force law, damped on the HIP's approach to the touched surface, and friction
  /// (§6.2), clamped to the law's maximum.
  void apply_force(std::span<const HapticObject> objects, const Eigen::Vector3d& hip_W, double dt,
                   const ForceSource& source, PointProxyOutput* out) noexcept;
  /// The HIP's speed into the touched surface along its outward normal n_W [m/s]: its velocity
  /// from its last position, less that of the object's point at the contact (§6.4).
  [[nodiscard]] double approach_speed(const HapticObject& touched, const Eigen::Vector3d& hip_W,
                                      double dt, const ForceSource& source) const noexcept;

  /// The IHIP: the point nearest the HIP on or outside every contact's plane.
  Eigen::Vector3d combine(const Eigen::Vector3d& hip_W) const noexcept;
  /// The textured object near the HIP while not in contact (Figure 6-5): found by the tree
  /// within the texture's height band, then followed by local search.
  void find_hover(std::span<const HapticObject> objects, const Eigen::Vector3d& hip_W) noexcept;
  /// Penetration under the textured surface (eq. 6-4) at contact point q_O with unit outward
  /// normal n_O and nearest distance s of the HIP (negative below the surface); zero when the
  /// HIP is outside the textured surface.
  static Eigen::Vector3d texture_penetration(const HapticObject& o, const Eigen::Vector3d& q_O,
                                             const Eigen::Vector3d& n_O, double s) noexcept;

  std::array<PointContact, kMaxContacts> contacts_{};
  int32_t count_ = 0;
  Eigen::Vector3d ihip_W_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d prev_hip_W_ = Eigen::Vector3d::Zero();  // the HIP at the last tick [m]
  bool initialised_ = false;
  PointProxyStats stats_;
  FrictionState friction_;
  int32_t hover_object_ = -1;
  PrimitiveRef hover_primitive_;
  int8_t hover_side_ = 1;
};

}  // namespace lap::haptics
