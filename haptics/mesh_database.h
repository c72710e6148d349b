#pragma once
/// \file
/// The hierarchical database of one mesh (thesis §4.2): vertex, edge and face primitives in flat
/// arrays with their neighbour lists and normals, and a bounding-box tree over the faces.
/// Faces are stored in tree order (leaves hold contiguous face ranges), which also keeps
/// neighbouring faces close in memory for the local search.
///
/// Built once (setup, may allocate); when the mesh deforms with its topology fixed,
/// set_positions() updates normals and refits the tree in O(n) without allocating, and the
/// variant taking the moved vertices updates only the normals around them.
///
/// Memory: the faces around a vertex are not stored as a list; they are found by walking the
/// vertex's fan across its edges (a manifold vertex has exactly one fan), which keeps a
/// 10^6-triangle database under 100 MB.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "haptics/bounding_volume_tree.h"
#include "haptics/triangle_mesh.h"

namespace lap::haptics {

/// Kinds of primitive a proxy can be in contact with.
enum class PrimitiveKind : uint8_t { kNone = 0, kVertex = 1, kEdge = 2, kFace = 3 };

/// A primitive of one mesh: kind and index into that kind's arrays.
struct PrimitiveRef {
  PrimitiveKind kind = PrimitiveKind::kNone;
  int32_t index = -1;
  bool operator==(const PrimitiveRef&) const = default;
};

/// Printable name of a kind: none, vertex, edge, face.
[[nodiscard]] const char* to_string(PrimitiveKind kind);

/// Settings of the database build.
struct MeshDatabaseSettings {
  int32_t max_leaf_faces = 4;  ///< faces per tree leaf
};

class MeshDatabase;

/// A set of vertices followed from one call to the next (the vertices a deformation moved):
/// update() replaces it by a new list and says which vertices entered and which left, so what
/// is derived from the set (a region of faces, marks in a tree) changes by the difference only.
/// version() counts the changes, so that something derived elsewhere can tell whether it missed
/// one (the segment database's edge tree follows the mesh's moved set this way). Sized for a
/// vertex count at setup; update() allocates nothing.
struct VertexSetDelta {
  explicit VertexSetDelta(int32_t vertex_count);
  /// Makes `list` (vertices in range; one listed twice counts once) the set. Returns whether the
  /// set changed: if so the version moves on by one, if not (the same vertices, as when a dent
  /// is held still) entered and left are empty. The same list as the last, entry for entry, is
  /// recognised at once.
  bool update(std::span<const int32_t> list);
  /// Empties the set (O(vertex count)). The version moves on by two: entered and left do not say
  /// what changed, so a follower must start afresh from `current`.
  void clear();
  [[nodiscard]] uint64_t version() const { return version_; }
  std::vector<int32_t> current;  // reserved n_v: the set, as listed, without repeats
  std::vector<int32_t> entered;  // reserved n_v: after update(): in the set, not in the last one
  std::vector<int32_t> left;     // reserved n_v: after update(): in the last set, not in this one

 private:
  std::vector<int32_t> previous;  // reserved n_v: the last set during update()
  std::vector<uint8_t> state;     // n_v: bit 0 in `current`, bit 1 listed in this update()
  uint64_t version_ = 0;
};

/// Workspace of MeshDatabase::set_positions(positions, moved, scratch) for one database: the faces
/// around each vertex as a flat list (CSR: no fan walks in the update), each face's corner angles
/// as last computed (so a vertex at the rim of a dent sums its unmoved faces' shares without
/// trigonometry), and the region of the last call kept from call to call — the faces with a
/// moved vertex (they changed shape), those faces' vertices (their normals changed) and the tree
/// nodes above those faces — each with a count of what holds it there, so a dent that slides or
/// changes shape adds and drops only the difference. Sized and filled at setup; kept by whoever
/// deforms the database (not in the database, which the haptic loop reads). Memory: about 41
/// bytes per face and 27 per vertex, and the tree's refit workspace.
struct MeshUpdateScratch {
  explicit MeshUpdateScratch(const MeshDatabase& db);
  /// The (face, corner) pairs around vertex v, each packed as 4 face + corner, faces ascending.
  [[nodiscard]] std::span<const int32_t> corners_of(int32_t v) const {
    const auto b = static_cast<size_t>(corner_start[static_cast<size_t>(v)]);
    const auto e = static_cast<size_t>(corner_start[static_cast<size_t>(v) + 1]);
    return {corners.data() + b, e - b};
  }
  /// Empties the region (O(n)): done when the workspace meets another database.
  void clear_region();
  std::vector<int32_t> dirty_faces;     // reserved n_f; after set_positions(): the faces it
                                        // reshaped, ascending
  std::vector<int32_t> dirty_vertices;  // reserved n_v; after set_positions(): the vertices
                                        // whose normals it recomputed, ascending
  std::vector<int32_t> corner_start;    // n_v + 1
  std::vector<int32_t> corners;         // 3 n_f
  std::vector<std::array<double, 3>> face_angles;  // n_f [rad]: valid for angles_of at
                                                   // angles_revision (else recomputed)
  const MeshDatabase* angles_of = nullptr;
  uint64_t angles_revision = 0;
  // The region, for region_of: the moved vertices; per face, its corners among them (in the
  // region when > 0); per vertex, its faces in the region (dirty when > 0); the same as bits,
  // which the update walks in memory order; the face tree's marks.
  const MeshDatabase* region_of = nullptr;
  VertexSetDelta moved;
  std::vector<uint8_t> face_moved_corners;    // n_f, 0..3
  std::vector<uint16_t> vertex_region_faces;  // n_v, up to MeshDatabase::kMaxFan
  std::vector<uint64_t> face_bits;            // n_f bits
  std::vector<uint64_t> vertex_bits;          // n_v bits
  BoundingVolumeTree::PartialRefit tree;      // the face tree's local refit
  int64_t regions_updated = 0;  // calls whose moved vertices differed from the last call's
  int64_t regions_reused = 0;   // calls with the same moved list as the last (a dent held still)
};

class MeshDatabase {
 public:
  /// Builds from a consistently oriented mesh whose edges each have one or two faces and whose
  /// vertices each have one fan (validate and repair first). Throws std::invalid_argument naming
  /// the first offending edge or vertex otherwise.
  static MeshDatabase build(const TriangleMesh& mesh, const MeshDatabaseSettings& settings = {});

  /// Moves the vertices (same count, original vertex order) and updates what depends on them:
  /// vertex normals and the tree boxes. No allocation.
  void set_positions(std::span<const Eigen::Vector3d> positions);
  /// The same when only `moved` vertices changed (local deformation, §6.5): normals are
  /// recomputed only around them; the tree is refitted. No allocation.
  void set_positions(std::span<const Eigen::Vector3d> positions, std::span<const int32_t> moved);
  /// The same, with a workspace that keeps the region the moved vertices touch from call to
  /// call: only the vertices that started or stopped moving since the last call change it (a
  /// dent held still changes nothing, one sliding along the surface a rim's width). Each face of
  /// the region gets its normal and corner angles once, each vertex of those faces sums its
  /// faces' angle-weighted normals from those (the faces that did not move from the angles
  /// cached in the workspace), and only the tree nodes above the region are refitted, each once.
  /// Cost proportional to the deformed region and its change, not to the mesh. The normals equal
  /// the full update's bit for bit (same terms, same order), the boxes the full refit's. A
  /// workspace used with another database (a copy with the same topology), or after this one
  /// moved by another route, first recomputes its cached angles (O(n), once), and after another
  /// database its region. No allocation.
  void set_positions(std::span<const Eigen::Vector3d> positions, std::span<const int32_t> moved,
                     MeshUpdateScratch* scratch);
  /// The three parts of set_positions, for callers that schedule them apart: copy the
  /// positions, refit the tree (O(n)), recompute all face and vertex normals (O(n)).
  void move_vertices(std::span<const Eigen::Vector3d> positions);
  void refit_tree();
  void update_normals();

  /// Incremented whenever vertices move: caches of geometry (the segment proxy's) compare it.
  [[nodiscard]] uint64_t revision() const { return revision_; }

  // --- sizes ---
  [[nodiscard]] int32_t vertex_count() const { return static_cast<int32_t>(positions_.size()); }
  [[nodiscard]] int32_t edge_count() const { return static_cast<int32_t>(edge_vertices_.size()); }
  [[nodiscard]] int32_t face_count() const { return static_cast<int32_t>(face_vertices_.size()); }
  /// True when some edge has a single face (an open, thin surface: rendered two-sided).
  [[nodiscard]] bool has_boundary() const { return boundary_edges_ > 0; }

  // --- geometry (hot) ---
  [[nodiscard]] const Eigen::Vector3d& position(int32_t v) const { return positions_[v]; }
  [[nodiscard]] const std::array<int32_t, 3>& face_vertices(int32_t f) const {
    return face_vertices_[f];
  }
  [[nodiscard]] const std::array<int32_t, 3>& face_edges(int32_t f) const { return face_edges_[f]; }
  [[nodiscard]] const std::array<int32_t, 2>& edge_vertices(int32_t e) const {
    return edge_vertices_[e];
  }
  /// The one or two faces of an edge; the second is -1 on a boundary edge.
  [[nodiscard]] const std::array<int32_t, 2>& edge_faces(int32_t e) const { return edge_faces_[e]; }
  /// Calls visit(face) for each face around vertex v, walking its fan across its edges.
  template <typename Visit>
  void for_each_vertex_face(int32_t v, const Visit& visit) const {
    const int32_t f0 = vertex_face_[v];
    int32_t f = f0;
    for (int32_t guard = 0; guard < kMaxFan; ++guard) {  // forward, across the edge leaving v
      visit(f);
      const int32_t g = other_face(face_edges_[f][corner_of(f, v)], f);
      if (g == f0) return;
      if (g < 0) break;  // a boundary: the rest of the fan lies the other way
      f = g;
    }
    f = f0;
    for (int32_t guard = 0; guard < kMaxFan; ++guard) {  // backward, across the edge entering v
      const int32_t g = other_face(face_edges_[f][(corner_of(f, v) + 2) % 3], f);
      if (g < 0 || g == f0) return;
      visit(g);
      f = g;
    }
  }
  /// Which corner (0, 1, 2) of face f is vertex v.
  [[nodiscard]] int corner_of(int32_t f, int32_t v) const {
    const auto& t = face_vertices_[f];
    return t[0] == v ? 0 : (t[1] == v ? 1 : 2);
  }
  /// The face across edge e from face f, or -1 on a boundary.
  [[nodiscard]] int32_t other_face(int32_t e, int32_t f) const {
    const auto& ef = edge_faces_[e];
    return ef[0] == f ? ef[1] : ef[0];
  }
  /// Fans larger than this are refused at build (no real vertex has that many faces).
  static constexpr int32_t kMaxFan = 1024;
  /// Unit face normal (counter-clockwise winding), computed from the positions.
  [[nodiscard]] const Eigen::Vector3d& face_normal(int32_t f) const { return face_normals_[f]; }
  /// Unit edge normal: the normalised sum of its faces' normals (§4.2).
  [[nodiscard]] Eigen::Vector3d edge_normal(int32_t e) const;
  /// Unit vertex normal, weighted by the angles its faces subtend at it (§4.2).
  [[nodiscard]] const Eigen::Vector3d& vertex_normal(int32_t v) const { return vertex_normals_[v]; }
  /// Normal of any primitive.
  [[nodiscard]] Eigen::Vector3d normal(PrimitiveRef p) const;

  /// The first face the segment p0 -> p1 crosses (§4.3 first contact): by the tree, with the
  /// watertight crossing test; from the front only unless two_sided. No allocation.
  struct Crossing {
    int32_t face = -1;       ///< -1: none
    double t = 0.0;          ///< at p0 + t (p1 - p0)
    bool from_front = true;  ///< p0 was on the side the face normal points to
  };
  [[nodiscard]] Crossing first_crossing(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                        bool two_sided) const;

  /// The face nearest p — the closest point of the surface lies on it — found exactly by the
  /// tree (branch and bound), with that point in *q and its squared distance in *d2 (either may
  /// be null). No allocation.
  [[nodiscard]] int32_t nearest_face(const Eigen::Vector3d& p, Eigen::Vector3d* q,
                                     double* d2) const;

  [[nodiscard]] const BoundingVolumeTree& tree() const { return tree_; }
  /// Index of face f in the mesh the database was built from (faces are stored in tree order).
  [[nodiscard]] int32_t original_face(int32_t f) const { return original_face_[f]; }
  /// Bytes held by the database and its tree.
  [[nodiscard]] size_t memory_bytes() const;

 private:
  struct Fan;  // the faces around one vertex while building (mesh_database.cpp)
  // The stages of build(), in order: faces in tree order with the tree, then edges and fans
  // vertex by vertex (each vertex's faces gathered, paired across its edges, its own edges
  // added, its single fan checked).
  void build_tree(const TriangleMesh& mesh, int32_t max_leaf_faces);
  void build_edges_and_fans();
  void gather_fan(int32_t v, std::span<const int32_t> faces, Fan* fan) const;
  static void pair_fan(int32_t v, Fan* fan);
  void add_edges_owned_by(int32_t v, const Fan& fan);
  static int32_t first_corner_of_single_fan(int32_t v, const Fan& fan);

  void update_vertex_normal(int32_t v);
  // The stages of set_positions(positions, moved, scratch), in order.
  void update_region(std::span<const int32_t> moved, MeshUpdateScratch* s) const;
  void add_region_face(int32_t f, MeshUpdateScratch* s) const;
  void drop_region_face(int32_t f, MeshUpdateScratch* s) const;
  void update_region_normals(MeshUpdateScratch* s);
  void refit_region(const MeshUpdateScratch& s);
  friend struct MeshUpdateScratch;
  [[nodiscard]] Eigen::Vector3d compute_face_normal(int32_t f) const;

  std::vector<Eigen::Vector3d> positions_;       // n_v x 3 [m]
  std::vector<Eigen::Vector3d> face_normals_;    // n_f x 3, unit (stored: the segment proxy reads
                                                 // them many times per tick)
  std::vector<Eigen::Vector3d> vertex_normals_;  // n_v x 3, unit
  std::vector<std::array<int32_t, 3>> face_vertices_;  // n_f x 3, tree order
  std::vector<std::array<int32_t, 3>> face_edges_;     // n_f x 3: edge k joins corners k, k+1
  std::vector<std::array<int32_t, 2>> edge_vertices_;  // n_e x 2, smaller index first
  std::vector<std::array<int32_t, 2>> edge_faces_;     // n_e x 2, -1 when absent
  std::vector<int32_t> vertex_face_;                   // n_v: one face of each vertex's fan
  std::vector<int32_t> original_face_;                 // n_f
  int32_t boundary_edges_ = 0;
  BoundingVolumeTree tree_;
  uint64_t revision_ = 0;
};

}  // namespace lap::haptics
