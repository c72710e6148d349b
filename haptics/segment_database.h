#pragma once
/// \file
/// The extended database of ray-based rendering (thesis §5.2) over one MeshDatabase:
/// - neighbours as in Figure 5-5: each face's three faces across its edges; each edge's four
///   edges that share a face with it (its faces and vertices are in the MeshDatabase);
/// - the possible contacted primitives (PCPs, Figure 5-6): for a face, its edges and the faces
///   and edges of the same flat "face" (coplanar triangles joined across flat edges); for an
///   edge, its faces and the other contactable edges at its two vertices;
/// - which edges a segment's interior can touch first (convex and boundary edges: a straight
///   probe cannot first meet a closed surface at a concave or flat edge; on a two-sided surface
///   also the edges concave from the front, which are convex from the back), and a second
///   bounding-box tree over those edges (§5.2).
/// And the two first-contact queries of §5.3: an end point's path crossing a face (A.5, A.7)
/// and the moving segment crossing an edge (A.8), both exact.
///
/// Built once after the MeshDatabase (setup, may allocate); refit_edge_tree() and
/// refit_moved_edges() follow a deformation without allocating. The queries allocate nothing and
/// never throw.

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "haptics/bounding_volume_tree.h"
#include "haptics/mesh_database.h"
#include "haptics/segment_segment.h"

namespace lap::haptics {

struct SegmentDatabaseSettings {
  int32_t max_leaf_edges = 4;
  /// Dihedral angle below which an edge counts as flat (joins a "face" and is never a
  /// first contact of the probe's interior) [rad].
  double flat_angle_rad = 1e-6;
  /// A thin, open surface touched from either side (the duct's shell): end points cross faces
  /// from the back too, and an edge concave from the front is convex from the back, so it is
  /// contactable there. Must match the HapticObject's two_sided (surface_problem() checks).
  bool two_sided = false;
};

class SegmentDatabase {
 public:
  /// `mesh` must outlive the database and keep its topology.
  static SegmentDatabase build(const MeshDatabase& mesh, const SegmentDatabaseSettings& s = {});

  [[nodiscard]] const MeshDatabase& mesh() const { return *mesh_; }
  /// A copy of this database for a copy of its mesh: `mesh` must have the same topology and
  /// positions as the one this was built on (a copy of it). Setup (allocates).
  [[nodiscard]] SegmentDatabase copy_for(const MeshDatabase& mesh) const {
    SegmentDatabase c = *this;
    c.mesh_ = &mesh;
    return c;
  }

  // --- neighbours (Figure 5-5) ---
  /// The faces across face f's three edges (-1 across a boundary edge).
  [[nodiscard]] const std::array<int32_t, 3>& face_neighbours(int32_t f) const {
    return face_neighbours_[f];
  }
  /// The other edges of edge e's faces (up to four; -1 where absent).
  [[nodiscard]] const std::array<int32_t, 4>& edge_neighbours(int32_t e) const {
    return edge_neighbours_[e];
  }
  // --- possible contacted primitives (Figure 5-6) ---
  [[nodiscard]] std::span<const PrimitiveRef> face_pcps(int32_t f) const {
    return {face_pcp_.data() + face_pcp_start_[f],
            static_cast<size_t>(face_pcp_start_[f + 1] - face_pcp_start_[f])};
  }
  [[nodiscard]] std::span<const PrimitiveRef> edge_pcps(int32_t e) const {
    return {edge_pcp_.data() + edge_pcp_start_[e],
            static_cast<size_t>(edge_pcp_start_[e + 1] - edge_pcp_start_[e])};
  }
  /// The flat "face" (coplanar, edge-connected triangles) face f belongs to.
  [[nodiscard]] int32_t flat_group(int32_t f) const { return flat_group_[f]; }
  [[nodiscard]] int32_t flat_group_count() const { return flat_groups_; }
  /// True when the probe's interior can first touch edge e (convex or boundary).
  [[nodiscard]] bool contactable(int32_t e) const { return contactable_[e] != 0; }
  /// The side a contactable edge is convex from: +1 its normal's (front), -1 the back (concave
  /// edges of a two-sided surface), 0 either (a boundary edge).
  [[nodiscard]] int8_t convex_side(int32_t e) const { return convex_side_[e]; }
  [[nodiscard]] bool two_sided() const { return two_sided_; }
  [[nodiscard]] int32_t contactable_edge_count() const {
    return static_cast<int32_t>(tree_edges_.size());
  }

  /// Earliest crossing of an end point's path p0 -> p1 into a face from its front (A.7; either
  /// side when two-sided, *side = +1 front, -1 back). A start exactly on the face plane counts,
  /// so an end point resting on the surface cannot slip in. Returns the face (-1: none) and the
  /// parameter in *t.
  [[nodiscard]] int32_t first_face_crossing(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                            double* t, int8_t* side) const;
  /// Earliest crossing of the moving segment (a0, b0) -> (a1, b1) with a contactable edge (A.8,
  /// exact), found through the edge tree. Returns the edge (-1: none); *tau the time, *u and *v
  /// the parameters on the probe (0 at a) and on the edge (0 at its first vertex).
  [[nodiscard]] int32_t first_edge_crossing(const Eigen::Vector3d& a0, const Eigen::Vector3d& b0,
                                            const Eigen::Vector3d& a1, const Eigen::Vector3d& b1,
                                            double* tau, double* u, double* v) const;

  /// The two crossing tests for one primitive: A.7 for face f (the parameter, -1: none; *side as
  /// above) and A.8 for contactable edge e (entering crossings only, from its convex side, where
  /// the edge has an inside).
  [[nodiscard]] double face_crossing(int32_t f, const Eigen::Vector3d& p0,
                                     const Eigen::Vector3d& p1, int8_t* side) const;
  [[nodiscard]] MovingSegmentHit edge_crossing(int32_t e, const Eigen::Vector3d& a0,
                                               const Eigen::Vector3d& b0, const Eigen::Vector3d& a1,
                                               const Eigen::Vector3d& b1) const;

  /// The faces within distance r of p (exact), written to `out`: the count, or -1 when more
  /// than out.size() qualify. For the segment proxy's sweep cache; no allocation.
  int32_t faces_near_point(const Eigen::Vector3d& p, double r, std::span<int32_t> out) const;
  /// The contactable edges within reach of any of the capsules (at most
  /// BoundingVolumeTree::kMaxCapsules, all inside `hull`; none: the hull itself; exact), each
  /// once, by one traversal of the edge tree; the count, or -1 when more than out.size() qualify.
  int32_t edges_near_capsules(const Capsule& hull, std::span<const Capsule> capsules,
                              std::span<int32_t> out) const;

  /// Recomputes the edge tree's boxes after the mesh moved (topology and convexity kept).
  void refit_edge_tree();
  /// The same after the mesh's set_positions(positions, moved, mesh_scratch), given
  /// mesh_scratch.moved: the leaves holding an edge with a moved vertex and their ancestors. The
  /// marks are kept in the workspace from call to call and follow the moved set's changes (a
  /// vertex that starts or stops moving); a workspace that missed one (or meets another set)
  /// marks afresh and refits the whole tree once. Equal to refit_edge_tree(). No allocation.
  void refit_moved_edges(const VertexSetDelta& moved, struct SegmentUpdateScratch* s);

  [[nodiscard]] const BoundingVolumeTree& edge_tree() const { return edge_tree_; }
  /// The mesh edge in each slot of the edge tree (tree order).
  [[nodiscard]] std::span<const int32_t> tree_edges() const { return tree_edges_; }
  [[nodiscard]] size_t memory_bytes() const;

 private:
  // The stages of build(), in order.
  /// Marks the contactable edges; returns the faces joined across flat edges (union-find).
  std::vector<int32_t> classify_edges(double flat_angle_rad, bool two_sided);
  /// Numbers the flat "faces" (the trees of the forest).
  void number_flat_groups(std::vector<int32_t>* forest);
  void link_neighbours();
  void list_face_pcps();
  void list_edge_pcps();
  void build_edge_tree(int32_t max_leaf_edges);

  const MeshDatabase* mesh_ = nullptr;
  std::vector<std::array<int32_t, 3>> face_neighbours_;
  std::vector<std::array<int32_t, 4>> edge_neighbours_;
  std::vector<int32_t> face_pcp_start_;
  std::vector<PrimitiveRef> face_pcp_;
  std::vector<int32_t> edge_pcp_start_;
  std::vector<PrimitiveRef> edge_pcp_;
  std::vector<int32_t> flat_group_;
  int32_t flat_groups_ = 0;
  std::vector<uint8_t> contactable_;
  std::vector<int8_t> convex_side_;
  bool two_sided_ = false;
  std::vector<int32_t> tree_edges_;  // edge index of each edge-tree slot
  BoundingVolumeTree edge_tree_;
};

/// Workspace of SegmentDatabase::refit_moved_edges(moved, scratch), sized and filled at setup:
/// the edge-tree leaves each vertex's contactable edges lie in, the vertices of each tree slot,
/// and the marks of the moved set it last followed.
struct SegmentUpdateScratch {
  explicit SegmentUpdateScratch(const SegmentDatabase& db);
  /// The distinct edge-tree leaves holding vertex v's contactable edges.
  [[nodiscard]] std::span<const int32_t> leaves_of(int32_t v) const {
    const auto b = static_cast<size_t>(leaf_start[static_cast<size_t>(v)]);
    const auto e = static_cast<size_t>(leaf_start[static_cast<size_t>(v) + 1]);
    return {leaves.data() + b, e - b};
  }
  std::vector<int32_t> leaf_start;                    // n_v + 1
  std::vector<int32_t> leaves;                        // CSR, per vertex ascending
  std::vector<std::array<int32_t, 2>> slot_vertices;  // per edge-tree slot: the edge's vertices
  BoundingVolumeTree::PartialRefit tree;
  // What the marks follow: the set, at which version, for which database.
  const VertexSetDelta* follows = nullptr;
  uint64_t version = 0;
  const SegmentDatabase* region_of = nullptr;
};

}  // namespace lap::haptics
