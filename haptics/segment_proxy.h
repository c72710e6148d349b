#pragma once
/// \file
/// Ray-based haptic rendering (thesis chapter 5): the probe is a line segment from its tip `a`
/// to its handle end `b`. The *virtual* probe follows the device; the *ideal* probe (the IHIP of
/// chapter 4, for a segment) never enters an object.
///
/// How the ideal probe moves (our extension of §5.3 to concave organs; see haptics/README.md):
/// each tick it moves from where it was towards the virtual probe, its two end points
/// travelling in straight lines, and that whole motion is checked exactly for first contacts
/// (an end point's path crossing a face, A.7; the moving segment crossing a convex edge, A.8)
/// through the two trees of §5.2. A contact stops the motion there and becomes a constraint
/// (a plane the contact point of the probe must stay on the outside of); the rest of the
/// motion is re-planned as the nearest configuration to the virtual probe that satisfies every
/// constraint (a least-squares problem over the two end points) and checked again. Because
/// every motion of the ideal probe is swept and checked, it cannot pass through any part of a
/// concave mesh, however far from the current contacts.
///
/// The constraints are the thesis' contacts and are tracked by local search between ticks
/// (only PCPs): an end point on a face follows the point proxy's Neighborhood Watch; a
/// segment–edge contact slides to the neighbouring convex edges; the α/β test of Figure 5-9
/// turns an edge contact whose plane would cut one of the edge's faces into contact with that
/// face. Contacts of one object whose normals agree within θε form one *segment–face* contact
/// with the contour points A and B of Figure 5-13c, held while |θ| < θε.
///
/// Response (§5.4), two rules (SegmentProxySettings::response). The thesis' (kept for comparison):
/// each contact has an equilibrium point on the probe — the contact point for point–polygon and
/// segment–edge, equation 5-2 for segment–face — and a spring along its normal from the
/// penetration of the virtual probe there (the object's ForceLaw). The passive one (Figure 5-4:
/// "a virtual spring between the ideal and virtual probes"; the default): the force on the two ends
/// is the object's spring k (ideal − virtual) at each end. The placement leaves the ideal probe at
/// x = x_virtual + Σ λ_i g_i (probe_placement_qp.h), so that spring is the sum over constraints of
/// k λ_i n_i acting at u_i: each contact takes its constraints' share, acting at their λ-weighted
/// point (its equilibrium point; eq. 5-2's for a segment–face contact that does not press). Forces
/// are split to the two ends by equations 5-1, 5-4 and 5-5 (the lever rule); the net torque is
/// equation 5-3. This departs from the thesis' spring of each contact from its own penetration
/// (which counts one spot twice when a contact splits in two, and so gives the hand energy back
/// over a loop: docs/anatomy.md, "Stop 61"): as a spring from a proxy that moves only towards the
/// device, it is passive. Its stiffness is k at an end point, and up to 2k at the probe's middle or
/// for a probe lying on a face (both ends held).
///
/// Surface properties (chapter 6; the thesis applies them to the ray-based probe too, at its
/// contact points; segment_proxy_surface.cpp): at each contact, the virtual probe's equilibrium
/// point projected onto the contact plane is the surface point, on the contact's feature. There
/// the object's force shading (§6.1) turns the spring along the shaded normal, its
/// texture (§6.3, eq. 6-2/6-4) perturbs it, and its stick-slip friction (§6.2) adds a tangential
/// force, with one friction state per contact kept from tick to tick (by object, and by order
/// among that object's contacts).
///
/// The step allocates nothing, takes no lock, never throws; a non-finite input or result zeroes
/// the force, resets the proxy and is counted.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <span>

#include "haptics/friction.h"
#include "haptics/haptic_object.h"
#include "haptics/probe_placement_qp.h"
#include "haptics/segment_database.h"

namespace lap::haptics {

/// The thesis' three contact types (Figure 5-3).
enum class SegmentContactKind : uint8_t { kPointPolygon, kSegmentEdge, kSegmentFace };
[[nodiscard]] const char* to_string(SegmentContactKind kind);

/// One constraint on the ideal probe: its point at parameter u (0 at a, 1 at b) stays on the
/// outside of the plane through `point` with normal `normal`.
struct SegmentConstraint {
  int32_t object = -1;
  PrimitiveRef feature;    ///< end point: the point proxy's primitive; interior: an edge
  bool at_end = false;     ///< u is 0 or 1 and the feature is tracked as a point contact
  bool face_hold = false;  ///< part of a segment–face contact with |θ| < θε (held)
  int8_t side = 1;  ///< at an end: +1 on its feature's front, -1 its back (two-sided surfaces)
  double u = 0.0;
  Eigen::Vector3d point_O = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_O = Eigen::Vector3d::UnitY();
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitY();
  double lambda = 0.0;          ///< multiplier of the last placement (0: not pressing)
  double lambda_surface = 0.0;  ///< the same without the skin (ProbePlacementSolution) [m]
};

/// One thesis contact (a group of constraints of one object).
struct SegmentContact {
  int32_t object = -1;
  SegmentContactKind kind = SegmentContactKind::kPointPolygon;
  PrimitiveRef primitive;      ///< the first constraint's feature
  double u_a = 0.0;            ///< contour point A (segment–face), else the contact point
  double u_b = 0.0;            ///< contour point B (segment–face), else the contact point
  double u_equilibrium = 0.0;  ///< where the force acts (eq. 5-2 for segment–face)
  double theta_rad = 0.0;      ///< probe angle to the face (segment–face)
  double depth_m = 0.0;        ///< penetration of the virtual probe at the equilibrium point
  /// Its spring's stiffness at the equilibrium point in units of the object's k, in [1, 2]: 1
  /// under the thesis' rule; under kIdealVirtualSpring (the default) its stretch over its depth
  /// (1 at an end point, 2 at the middle or for both ends held; where the depth is at most 1 nm,
  /// Σ over its pressing constraints of 1 / ((1 − u)² + u²); 1 when none presses). For the
  /// stiffness budget at the handle and the tissue model's reading of force as depth.
  double stiffness_factor = 1.0;
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero();  ///< equilibrium point, ideal probe
  Eigen::Vector3d normal_W = Eigen::Vector3d::UnitY();
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();     ///< on the probe, friction included [N]
  Eigen::Vector3d friction_W = Eigen::Vector3d::Zero();  ///< its friction part (§6.2) [N]
  FrictionState::Phase friction_phase = FrictionState::Phase::kNone;
};

/// How a contact's spring is measured (segment_proxy.h, "Response").
enum class SegmentResponse : uint8_t {
  /// The thesis' rule (§5.4): each contact a spring from the virtual probe's penetration at its
  /// equilibrium point (eq. 5-2). Not passive on curved surfaces (docs/anatomy.md, "Stop 61").
  kContactSprings,
  /// The spring between the ideal and the virtual probe (Figure 5-4), k at each end: passive.
  kIdealVirtualSpring,
};

struct SegmentProxySettings {
  double theta_epsilon_rad = 1.0 * M_PI / 180.0;  ///< θε of §5.3/eq. 5-2 (the thesis: 1°)
  double skin_m = 1e-6;  ///< clearance the ideal probe keeps from a constraint plane
  /// The passive spring is the default (docs/anatomy.md, "Stop 63"); the thesis' springs stay
  /// for comparison with §5.4 (not passive: haptics/README.md, "Response").
  SegmentResponse response = SegmentResponse::kIdealVirtualSpring;
  /// Answer swept checks of slow motions from the sweep cache (exact; off: always the trees).
  bool sweep_cache = true;
};

struct SegmentProxyOutput {
  Eigen::Vector3d ideal_a_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d ideal_b_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();     ///< net force on the probe [N]
  Eigen::Vector3d torque_W = Eigen::Vector3d::Zero();    ///< about the virtual end b [N m]
  Eigen::Vector3d force_a_W = Eigen::Vector3d::Zero();   ///< share at end a (eq. 5-1/5-4/5-5)
  Eigen::Vector3d force_b_W = Eigen::Vector3d::Zero();   ///< share at end b
  Eigen::Vector3d friction_W = Eigen::Vector3d::Zero();  ///< friction part of force_W [N]
  int32_t contact_count = 0;
  bool fault = false;
};

struct SegmentProxyStats {
  int64_t steps = 0;
  int64_t first_contacts = 0;  ///< contacts found by the swept check with none before
  int64_t swept_hits = 0;      ///< all contacts found by the swept check
  int64_t releases = 0;
  int64_t placements = 0;            ///< constrained placements + swept checks over all steps
  int64_t placement_limit_hits = 0;  ///< steps that ran out of placements (probe stopped safe)
  int64_t constraint_overflows = 0;  ///< contacts not added because the list was full
  int64_t cached_sweeps = 0;         ///< swept checks answered from the sweep cache
  /// Cached primitives tested exactly (those within reach of the motion: faces per end + edges),
  /// including the first 0.2 mm of long motions that then went on to the trees.
  int64_t cached_tests = 0;
  int64_t cache_rebuilds = 0;  ///< sweep cache refilled from the trees
  int64_t tree_sweeps = 0;     ///< swept checks that went through the trees
  /// Ticks that found the ideal probe partly inside a closed object whose surface had moved
  /// onto it since the last tick (a deforming organ, §6.5) and pushed it back out.
  int64_t surface_push_outs = 0;
  int64_t stick_to_slide = 0;  ///< friction (§6.2) transitions over all contacts
  int64_t slide_to_stick = 0;
  int64_t faults = 0;
};

class SegmentProxy {
 public:
  static constexpr int kMaxConstraints = ProbePlacementQp::kMaxConstraints;
  static constexpr int kMaxPlacements = 8;
  /// Largest end-point motion of one placement pass [m] (a tool moves about 1 mm per tick).
  static constexpr double kMaxPassMotion = 0.004;

  explicit SegmentProxy(const SegmentProxySettings& settings = {}) : settings_(settings) {}

  /// Places the probe in free space at a_W -> b_W.
  void reset(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W);

  /// One haptic tick. Every object must carry a SegmentDatabase (HapticObject::segments).
  SegmentProxyOutput step(std::span<const HapticObject> objects, const Eigen::Vector3d& a_W,
                          const Eigen::Vector3d& b_W, double dt) noexcept;

  [[nodiscard]] std::span<const SegmentContact> contacts() const {
    return {contacts_.data(), static_cast<size_t>(contact_count_)};
  }
  [[nodiscard]] std::span<const SegmentConstraint> constraints() const {
    return {constraints_.data(), static_cast<size_t>(constraint_count_)};
  }
  [[nodiscard]] const Eigen::Vector3d& ideal_a() const { return ideal_a_; }
  [[nodiscard]] const Eigen::Vector3d& ideal_b() const { return ideal_b_; }
  [[nodiscard]] const SegmentProxyStats& stats() const { return stats_; }
  [[nodiscard]] const SegmentProxySettings& settings() const { return settings_; }

  /// Net torque of the last step's contact forces about point p_W (eq. 5-3).
  [[nodiscard]] Eigen::Vector3d torque_about(const Eigen::Vector3d& p_W) const;

 private:
  struct SweptHit;      // the earliest hit of one swept check (segment_proxy_sweep.cpp)
  struct ContactGroup;  // the constraints of one thesis contact (segment_proxy_response.cpp)

  // The step's stages: the ideal probe pushed out of surfaces that moved onto it
  // (segment_proxy_surface_motion.cpp), then (segment_proxy.cpp) tracking the constraints and
  // moving the ideal probe by placements and swept checks.
  /// Pushes the ideal probe out of each closed object whose surface changed since the last tick
  /// and now holds part of it (§6.5: a dent springing back under a tool that does not touch it).
  void push_out_of_moved_surfaces(std::span<const HapticObject> objects) noexcept;
  /// True when part of the probe (a, b) (object frame) is inside closed mesh m and there is a
  /// way out: *push, along the outward normals where it crosses the surface (or of the face
  /// nearest it, when it lies wholly inside), as far as the deepest of its points inside needs.
  [[nodiscard]] static bool partly_inside(const MeshDatabase& m, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, Eigen::Vector3d* push) noexcept;
  /// Translates the ideal probe out of object o (up to a few rounds); true when it moved.
  bool push_out_of(const HapticObject& o) noexcept;
  /// Local search for every constraint against the new virtual probe (§5.3, PCPs only).
  void track(std::span<const HapticObject> objects) noexcept;
  /// Slides a segment–edge constraint along the contactable edges, or turns it into a point
  /// contact where an end of the probe has reached the edge.
  void track_edge_contact(const SegmentDatabase& sd, const Eigen::Isometry3d& inv,
                          const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          SegmentConstraint* c) const noexcept;
  /// Moves the ideal probe towards the virtual probe (a_W, b_W), adding the contacts it meets.
  void move_ideal_probe(std::span<const HapticObject> objects, const Eigen::Vector3d& a_W,
                        const Eigen::Vector3d& b_W) noexcept;
  /// The configuration nearest the virtual probe that keeps every constraint (see the .cpp).
  void place(std::span<const HapticObject> objects, const Eigen::Vector3d& a_W,
             const Eigen::Vector3d& b_W, Eigen::Vector3d* a, Eigen::Vector3d* b) noexcept;
  void solve_placement(const Eigen::Vector3d& a_W, const Eigen::Vector3d& b_W, Eigen::Vector3d* a,
                       Eigen::Vector3d* b) noexcept;
  /// Adds or updates a constraint; false when nothing changed (or the list is full).
  bool add_constraint(const SegmentConstraint& c) noexcept;
  void remove_constraint(int i) noexcept;

  // The swept check (segment_proxy_sweep.cpp) and its cache (segment_proxy_sweep_cache.cpp).
  /// The first contact of the motion (a0, b0) -> (a1, b1), at time *tau, as constraint *hit.
  bool sweep(std::span<const HapticObject> objects, bool first_pass, const Eigen::Vector3d& a0,
             const Eigen::Vector3d& b0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b1,
             double* tau, SegmentConstraint* hit) noexcept;
  /// The motion's first part (fraction *f) against the cache; false when it does not cover it.
  bool sweep_cached(std::span<const HapticObject> objects, const Eigen::Vector3d& a0,
                    const Eigen::Vector3d& b0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b1,
                    SweptHit* first, double* f) noexcept;
  /// The cached faces and edges within reach of the motion (a0, b0) -> (af, bf), exactly.
  void sweep_cached_primitives(std::span<const HapticObject> objects, const Eigen::Vector3d& a0,
                               const Eigen::Vector3d& b0, const Eigen::Vector3d& af,
                               const Eigen::Vector3d& bf, SweptHit* first) noexcept;
  /// The whole motion against every object through its two trees (§5.2).
  void sweep_trees(std::span<const HapticObject> objects, bool first_pass,
                   const Eigen::Vector3d& a0, const Eigen::Vector3d& b0, const Eigen::Vector3d& a1,
                   const Eigen::Vector3d& b1, SweptHit* first) const noexcept;
  bool cache_covers(std::span<const HapticObject> objects, const Eigen::Vector3d& a0,
                    const Eigen::Vector3d& b0, const Eigen::Vector3d& a1,
                    const Eigen::Vector3d& b1) const noexcept;
  bool fill_cache(std::span<const HapticObject> objects, const Eigen::Vector3d& a,
                  const Eigen::Vector3d& b, double ra, double rb) noexcept;
  /// Caches object k's faces within r of end point `end` at p (object frame).
  bool cache_faces(const SegmentDatabase& sd, int32_t k, int end, const Eigen::Vector3d& p,
                   double r, std::span<int32_t> scratch) noexcept;
  /// Caches object k's contactable edges within reach of the probe (A, B) (object frame).
  bool cache_edges(const SegmentDatabase& sd, int32_t k, const Eigen::Vector3d& A,
                   const Eigen::Vector3d& B, double ra, double rb,
                   std::span<int32_t> scratch) noexcept;

  // The response (§5.4, segment_proxy_response.cpp).
  void respond(std::span<const HapticObject> objects, double dt, SegmentProxyOutput* out) noexcept;
  /// The constraints grouped with constraint i (those not yet *used).
  ContactGroup gather_contact(int i, double cos_eps,
                              std::array<bool, kMaxConstraints>* used) const noexcept;
  /// Widens the contour [*u_a, *u_b] over the face the probe lies on within θε (Figure 5-3c).
  void widen_over_face(std::span<const HapticObject> objects, const ContactGroup& g, double cos_eps,
                       double* u_a, double* u_b) const noexcept;
  /// Sets the contact's kind, equilibrium point and normal; returns a point of its plane.
  Eigen::Vector3d find_equilibrium(const ContactGroup& g, SegmentContact* contact) const noexcept;
  /// The contact's share of the spring between the ideal and the virtual probe, Σ λ_i n_i over
  /// its constraints [m]; moves its equilibrium point to where that share acts.
  Eigen::Vector3d spring_stretch(const ContactGroup& g, SegmentContact* contact) const noexcept;
  /// The contact's spring force with the object's surface properties, added to *out with its
  /// shares at the ends and its torque.
  void apply_contact_force(std::span<const HapticObject> objects, double dt,
                           const Eigen::Vector3d& plane_point, const Eigen::Vector3d& stretch,
                           bool ideal_spring, SegmentContact* contact,
                           SegmentProxyOutput* out) noexcept;

  // Surface properties at a contact (chapter 6, segment_proxy_surface.cpp).
  /// Where a contact acts on its object's surface (object frame): the primitive under it, the
  /// point and the contact's normal.
  struct SurfacePoint {
    PrimitiveRef primitive;
    Eigen::Vector3d q_O = Eigen::Vector3d::Zero();
    Eigen::Vector3d n_O = Eigen::Vector3d::UnitY();
  };
  /// The surface point of a contact: on_plane_W on the contact plane, on the contact's feature.
  [[nodiscard]] SurfacePoint surface_point(const HapticObject& o, const SegmentContact& contact,
                                           const Eigen::Vector3d& on_plane_W) const noexcept;
  /// The penetration vector for the force law: -depth n (flat), along the shaded normal (§6.1,
  /// Figure 6-3) or under the textured surface (§6.3, eq. 6-4).
  [[nodiscard]] static Eigen::Vector3d surface_penetration(
      const HapticObject& o, const SurfacePoint& s, double depth,
      const Eigen::Vector3d& normal_W) noexcept;
  /// The friction force (§6.2, world frame) of the contact-th contact for normal force fn.
  Eigen::Vector3d contact_friction(const HapticObject& o, int contact, const SurfacePoint& s,
                                   double fn) noexcept;
  /// Friction states of contacts that ended this tick start afresh at their next contact.
  void release_unused_friction() noexcept;

  // The sweep cache (a clearance certificate): every face within radius_a of end point a (and
  // radius_b of b) and every contactable edge within r(u) = (1 - u) radius_a + u radius_b of the
  // probe's point u, at the cached position (a, b). While each end point of a swept motion
  // stays within its radius of its cached position, the probe's point u stays within r(u) of
  // its cached position, so any face or edge the motion crosses is in the cache: testing only
  // those is exact, and its cost does not depend on the mesh size. The trees refill it when the
  // probe leaves it, an object moves or deforms.
  static constexpr int kCacheObjects = 4;
  static constexpr int kCacheFaces = 32;  ///< per end point
  static constexpr int kCacheEdges = 64;
  static constexpr double kCacheGrowth = 4.0;  ///< radius / end-point motion of the refilling pass
  /// Largest growth for a cache that keeps coming up empty (a segment in free space: a bigger
  /// empty cache is free to test and is refilled less often).
  static constexpr double kCacheMaxGrowth = 64.0;
  static constexpr double kCacheMinRadius = 5e-5;  ///< [m]
  static constexpr double kCacheMaxMotion = 2e-4;  ///< [m] per pass; faster motions use the trees
  // Each cached primitive carries its own geometry (copied at refill, checked by the mesh
  // revision), so the cached sweep reads only this proxy's memory however big the mesh.
  //
  // Each also keeps its distance from the probe at the refill (`clearance`): a motion that keeps
  // every point of the probe within D of where it was then cannot reach a primitive farther than
  // D, so the sweep skips it with one comparison (most of the cache, most ticks).
  struct CachedFace {
    int32_t object = -1;
    int32_t index = -1;
    double clearance = 0.0;  ///< from the cached end point [m]
    bool two_sided = false;  ///< crossed from either side (SegmentDatabase::two_sided)
    std::array<int32_t, 3> vertex{};
    std::array<Eigen::Vector3d, 3> p{};
    Eigen::Vector3d n = Eigen::Vector3d::Zero();  ///< (p1 - p0) × (p2 - p0)
  };
  struct CachedEdge {
    int32_t object = -1;
    int32_t index = -1;
    bool closed = false;     ///< has an inside (two faces): only entering crossings count
    double clearance = 0.0;  ///< from the cached probe [m]
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    Eigen::Vector3d outward = Eigen::Vector3d::Zero();
  };
  struct SweepCache {
    bool valid = false;
    Eigen::Vector3d a = Eigen::Vector3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    double radius_a = 0.0;  ///< how far end point a may move from `a`
    double radius_b = 0.0;
    int32_t object_count = 0;
    std::array<Eigen::Matrix<double, 3, 4>, kCacheObjects> poses{};
    std::array<uint64_t, kCacheObjects> revisions{};
    // Which database each object's edges came from: with its revision, what identifies the
    // geometry (the session passes the proxies one of several copies of a deforming organ).
    std::array<const MeshDatabase*, kCacheObjects> meshes{};
    std::array<std::array<CachedFace, kCacheFaces>, 2> faces{};  // near a, near b
    std::array<int32_t, 2> face_count{};
    std::array<CachedEdge, kCacheEdges> edges{};
    int32_t edge_count = 0;
  };

  SegmentProxySettings settings_;
  SweepCache cache_;
  // The surface each object had when the ideal probe last checked it (by database and its
  // revision: the session passes one of several copies of a deforming organ).
  static constexpr int kSeenObjects = 16;  ///< objects past these are checked every tick
  struct SeenSurface {
    const MeshDatabase* mesh = nullptr;  ///< null: not seen since the last reset
    uint64_t revision = 0;
    bool started_inside = false;  ///< inside when first seen, and not yet found clear
  };
  std::array<SeenSurface, kSeenObjects> seen_{};
  // One friction state per contact, found again next tick by its object and its order among
  // that object's contacts.
  struct FrictionSlot {
    int32_t object = -1;  ///< -1: free
    int32_t ordinal = 0;
    bool used = false;  ///< by a contact this tick
    FrictionState state;
  };
  std::array<FrictionSlot, kMaxConstraints> friction_{};
  double cache_growth_ = kCacheGrowth;
  std::array<SegmentConstraint, kMaxConstraints> constraints_{};
  int32_t constraint_count_ = 0;
  std::array<SegmentContact, kMaxConstraints> contacts_{};
  int32_t contact_count_ = 0;
  Eigen::Vector3d ideal_a_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d ideal_b_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d virtual_a_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d virtual_b_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d prev_virtual_a_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d prev_virtual_b_ = Eigen::Vector3d::Zero();
  bool initialised_ = false;
  SegmentProxyStats stats_;
};

}  // namespace lap::haptics
