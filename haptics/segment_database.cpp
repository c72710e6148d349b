#include "haptics/segment_database.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "haptics/closest_point.h"
#include "haptics/segment_segment.h"
#include "haptics/segment_triangle.h"

namespace lap::haptics {
namespace {

// Flat groups larger than this list only their edge neighbours as PCPs (a finely tessellated
// plane would otherwise give every triangle a list as long as the plane).
constexpr int32_t kMaxGroupPcps = 16;

int32_t find_root(std::vector<int32_t>& parent, int32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

// Height of the far vertex of edge e's second face over its first face's plane, relative to its
// distance from the edge line: the sine of the dihedral's deviation from flat (negative:
// convex). e has two faces.
double dihedral_sine(const MeshDatabase& mesh, int32_t e) {
  const auto& ef = mesh.edge_faces(e);
  const Eigen::Vector3d& n0 = mesh.face_normal(ef[0]);
  const auto& ev = mesh.edge_vertices(e);
  const auto& t1 = mesh.face_vertices(ef[1]);
  int32_t far = t1[0];
  for (int32_t v : t1) {
    if (v != ev[0] && v != ev[1]) far = v;
  }
  const Eigen::Vector3d edge = mesh.position(ev[1]) - mesh.position(ev[0]);
  const Eigen::Vector3d w = mesh.position(far) - mesh.position(ev[0]);
  const double dist_from_line = edge.cross(w).norm() / std::max(edge.norm(), 1e-300);
  const double height = n0.dot(w);
  return dist_from_line > 0.0 ? height / dist_from_line : 0.0;
}

// The faces of each flat group (CSR), for the face PCPs.
struct FlatGroupMembers {
  std::vector<int32_t> start;  // per group, + 1
  std::vector<int32_t> faces;  // grouped, ascending within each group
  [[nodiscard]] std::span<const int32_t> of(int32_t g) const {
    return {faces.data() + start[g], static_cast<size_t>(start[g + 1] - start[g])};
  }
};

FlatGroupMembers flat_group_members(const std::vector<int32_t>& flat_group, int32_t groups) {
  FlatGroupMembers m;
  const auto nf = static_cast<int32_t>(flat_group.size());
  m.start.assign(static_cast<size_t>(groups) + 1, 0);
  for (int32_t f = 0; f < nf; ++f) ++m.start[flat_group[f] + 1];
  std::partial_sum(m.start.begin(), m.start.end(), m.start.begin());
  m.faces.resize(nf);
  std::vector<int32_t> fill(m.start.begin(), m.start.end() - 1);
  for (int32_t f = 0; f < nf; ++f) m.faces[fill[flat_group[f]]++] = f;
  return m;
}

}  // namespace

SegmentDatabase SegmentDatabase::build(const MeshDatabase& mesh,
                                       const SegmentDatabaseSettings& settings) {
  SegmentDatabase db;
  db.mesh_ = &mesh;
  db.two_sided_ = settings.two_sided;
  std::vector<int32_t> flat_forest = db.classify_edges(settings.flat_angle_rad, settings.two_sided);
  db.number_flat_groups(&flat_forest);
  db.link_neighbours();
  db.list_face_pcps();
  db.list_edge_pcps();
  db.build_edge_tree(settings.max_leaf_edges);
  return db;
}

// Convexity of each edge from the far vertex of its second face against the first face's
// plane; flat edges join faces into the thesis' "faces" (the returned union-find forest).
std::vector<int32_t> SegmentDatabase::classify_edges(double flat_angle_rad, bool two_sided) {
  const MeshDatabase& mesh = *mesh_;
  const int32_t nf = mesh.face_count();
  const int32_t ne = mesh.edge_count();
  contactable_.assign(ne, 0);
  convex_side_.assign(ne, 0);
  std::vector<int32_t> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  const double sin_flat = std::sin(flat_angle_rad);
  for (int32_t e = 0; e < ne; ++e) {
    const auto& ef = mesh.edge_faces(e);
    if (ef[1] < 0) {
      contactable_[e] = 1;  // boundary: the probe can rest on it from either side
      continue;
    }
    const double sine = dihedral_sine(mesh, e);
    if (sine < -sin_flat) {
      contactable_[e] = 1;  // convex
      convex_side_[e] = 1;
    } else if (sine > sin_flat && two_sided) {
      contactable_[e] = 1;  // concave from the front: convex from the back
      convex_side_[e] = -1;
    } else if (std::abs(sine) <= sin_flat &&
               mesh.face_normal(ef[0]).dot(mesh.face_normal(ef[1])) > 0.0) {
      const int32_t a = find_root(parent, ef[0]);
      const int32_t b = find_root(parent, ef[1]);
      if (a != b) parent[a] = b;
    }
  }
  return parent;
}

void SegmentDatabase::number_flat_groups(std::vector<int32_t>* forest) {
  const int32_t nf = mesh_->face_count();
  flat_group_.resize(nf);
  std::vector<int32_t> group_id(nf, -1);
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t r = find_root(*forest, f);
    if (group_id[r] < 0) group_id[r] = flat_groups_++;
    flat_group_[f] = group_id[r];
  }
}

// Figure 5-5 neighbours.
void SegmentDatabase::link_neighbours() {
  const MeshDatabase& mesh = *mesh_;
  const int32_t nf = mesh.face_count();
  const int32_t ne = mesh.edge_count();
  face_neighbours_.resize(nf);
  for (int32_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) face_neighbours_[f][k] = mesh.other_face(mesh.face_edges(f)[k], f);
  }
  edge_neighbours_.assign(ne, {-1, -1, -1, -1});
  for (int32_t e = 0; e < ne; ++e) {
    int n = 0;
    for (int32_t f : mesh.edge_faces(e)) {
      if (f < 0) continue;
      for (int32_t g : mesh.face_edges(f)) {
        if (g != e && n < 4) edge_neighbours_[e][n++] = g;
      }
    }
  }
}

// Face PCPs: its edges; the faces (and their edges) of its flat group, or only the flat
// neighbours across its edges when the group is large.
void SegmentDatabase::list_face_pcps() {
  const MeshDatabase& mesh = *mesh_;
  const int32_t nf = mesh.face_count();
  const FlatGroupMembers members = flat_group_members(flat_group_, flat_groups_);
  face_pcp_start_.assign(nf + 1, 0);
  std::vector<PrimitiveRef> list;
  for (int32_t f = 0; f < nf; ++f) {
    list.clear();
    auto add = [&list](PrimitiveRef p) {
      if (std::find(list.begin(), list.end(), p) == list.end()) list.push_back(p);
    };
    for (int32_t e : mesh.face_edges(f)) add({PrimitiveKind::kEdge, e});
    const int32_t g = flat_group_[f];
    if (members.of(g).size() <= static_cast<size_t>(kMaxGroupPcps)) {
      for (const int32_t h : members.of(g)) {
        if (h == f) continue;
        add({PrimitiveKind::kFace, h});
        for (int32_t e : mesh.face_edges(h)) add({PrimitiveKind::kEdge, e});
      }
    } else {
      for (int32_t h : face_neighbours_[f]) {
        if (h >= 0 && flat_group_[h] == g) add({PrimitiveKind::kFace, h});
      }
    }
    face_pcp_.insert(face_pcp_.end(), list.begin(), list.end());
    face_pcp_start_[f + 1] = static_cast<int32_t>(face_pcp_.size());
  }
}

// Edge PCPs: its faces, and the contactable edges at its two vertices (where a probe resting
// on the edge slides next).
void SegmentDatabase::list_edge_pcps() {
  const MeshDatabase& mesh = *mesh_;
  const int32_t ne = mesh.edge_count();
  edge_pcp_start_.assign(ne + 1, 0);
  std::vector<PrimitiveRef> list;
  for (int32_t e = 0; e < ne; ++e) {
    list.clear();
    for (int32_t f : mesh.edge_faces(e)) {
      if (f >= 0) list.push_back({PrimitiveKind::kFace, f});
    }
    for (int32_t v : mesh.edge_vertices(e)) {
      mesh.for_each_vertex_face(v, [&](int32_t f) {
        const int c = mesh.corner_of(f, v);
        for (int32_t g : {mesh.face_edges(f)[c], mesh.face_edges(f)[(c + 2) % 3]}) {
          const PrimitiveRef p{PrimitiveKind::kEdge, g};
          if (g != e && contactable_[g] != 0 &&
              std::find(list.begin(), list.end(), p) == list.end()) {
            list.push_back(p);
          }
        }
      });
    }
    edge_pcp_.insert(edge_pcp_.end(), list.begin(), list.end());
    edge_pcp_start_[e + 1] = static_cast<int32_t>(edge_pcp_.size());
  }
}

// Second tree, over the contactable edges (§5.2), split by the edges' centres.
void SegmentDatabase::build_edge_tree(int32_t max_leaf_edges) {
  const MeshDatabase& mesh = *mesh_;
  std::vector<int32_t> edges;
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    if (contactable_[e] != 0) edges.push_back(e);
  }
  std::vector<int32_t> order;
  edge_tree_.build(
      static_cast<int32_t>(edges.size()),
      [&](int32_t i) {
        const auto& ev = mesh.edge_vertices(edges[i]);
        return Eigen::Vector3d(0.5 * (mesh.position(ev[0]) + mesh.position(ev[1])));
      },
      max_leaf_edges, &order);
  tree_edges_.resize(edges.size());
  for (size_t k = 0; k < edges.size(); ++k) tree_edges_[k] = edges[order[k]];
  refit_edge_tree();
}

void SegmentDatabase::refit_edge_tree() {
  const MeshDatabase& mesh = *mesh_;
  edge_tree_.refit([&](int32_t k, RefitBounds* b) {
    for (const int32_t v : mesh.edge_vertices(tree_edges_[k])) b->add(mesh.position(v));
  });
}

void SegmentDatabase::refit_moved_edges(const VertexSetDelta& moved, SegmentUpdateScratch* s) {
  const bool same_set = s->follows == &moved && s->region_of == this;
  if (same_set && moved.version() == s->version + 1) {
    // One change: a vertex that starts moving marks the leaves of its edges, one that stops
    // unmarks them (a leaf stays marked while another moved vertex holds it).
    for (const int32_t v : moved.entered) {
      for (const int32_t leaf : s->leaves_of(v)) s->tree.add_to_leaf(leaf);
    }
    for (const int32_t v : moved.left) {
      for (const int32_t leaf : s->leaves_of(v)) s->tree.remove_from_leaf(leaf);
    }
  } else if (!same_set || moved.version() != s->version) {
    // Another set, or a change missed (what moved then is not known): mark afresh, and refit
    // everything this once.
    s->tree.clear();
    for (const int32_t v : moved.current) {
      for (const int32_t leaf : s->leaves_of(v)) s->tree.add_to_leaf(leaf);
    }
    s->follows = &moved;
    s->version = moved.version();
    s->region_of = this;
    refit_edge_tree();
    return;
  }
  s->version = moved.version();
  const MeshDatabase& mesh = *mesh_;
  edge_tree_.refit_marked(s->tree, [&](int32_t k, RefitBounds* b) {
    for (const int32_t v : s->slot_vertices[static_cast<size_t>(k)]) b->add(mesh.position(v));
  });
}

SegmentUpdateScratch::SegmentUpdateScratch(const SegmentDatabase& db)
    : leaf_start(static_cast<size_t>(db.mesh().vertex_count()) + 1, 0),
      slot_vertices(db.tree_edges().size()),
      tree(db.edge_tree()) {
  const MeshDatabase& mesh = db.mesh();
  const std::span<const int32_t> edges = db.tree_edges();
  // Each vertex's (leaf) pairs, then sorted and made distinct per vertex (CSR).
  std::vector<std::array<int32_t, 2>> pairs;
  pairs.reserve(2 * edges.size());
  for (size_t k = 0; k < edges.size(); ++k) {
    slot_vertices[k] = mesh.edge_vertices(edges[k]);
    for (const int32_t v : slot_vertices[k]) pairs.push_back({v, tree.leaf_of[k]});
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  leaves.reserve(pairs.size());
  for (const auto& [v, leaf] : pairs) {
    ++leaf_start[static_cast<size_t>(v) + 1];
    leaves.push_back(leaf);
  }
  std::partial_sum(leaf_start.begin(), leaf_start.end(), leaf_start.begin());
}

double SegmentDatabase::face_crossing(int32_t f, const Eigen::Vector3d& p0,
                                      const Eigen::Vector3d& p1, int8_t* side) const {
  const MeshDatabase& mesh = *mesh_;
  const auto& v = mesh.face_vertices(f);
  const Eigen::Vector3d& a = mesh.position(v[0]);
  const Eigen::Vector3d& b = mesh.position(v[1]);
  const Eigen::Vector3d& c = mesh.position(v[2]);
  return crossing_time(p0, p1, (b - a).cross(c - a), two_sided_, a, v[0], b, v[1], c, v[2], side);
}

int32_t SegmentDatabase::first_face_crossing(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                             double* t, int8_t* side) const {
  return mesh_->tree().first_hit(
      p0, p1,
      [&](int32_t f, double t_max) {
        int8_t s = 1;
        const double tt = face_crossing(f, p0, p1, &s);
        if (tt < 0.0 || tt > t_max) return -1.0;
        *side = s;
        return tt;
      },
      t);
}

MovingSegmentHit SegmentDatabase::edge_crossing(int32_t e, const Eigen::Vector3d& a0,
                                                const Eigen::Vector3d& b0,
                                                const Eigen::Vector3d& a1,
                                                const Eigen::Vector3d& b1) const {
  const MeshDatabase& mesh = *mesh_;
  const auto& ev = mesh.edge_vertices(e);
  // Boundary edges of open surfaces have no inside: every crossing counts there. Others are
  // entered from their convex side.
  const bool closed = mesh.edge_faces(e)[1] >= 0;
  const Eigen::Vector3d outward =
      closed ? Eigen::Vector3d(convex_side_[e] * mesh.edge_normal(e)) : Eigen::Vector3d::Zero();
  return moving_segment_enters_edge(a0, b0, a1, b1, mesh.position(ev[0]), mesh.position(ev[1]),
                                    closed ? &outward : nullptr);
}

int32_t SegmentDatabase::first_edge_crossing(const Eigen::Vector3d& a0, const Eigen::Vector3d& b0,
                                             const Eigen::Vector3d& a1, const Eigen::Vector3d& b1,
                                             double* tau, double* u, double* v) const {
  const MeshDatabase& mesh = *mesh_;
  // The swept segment lies within max(|a1 - a0|, |b1 - b0|) of the final one.
  const double r = std::max((a1 - a0).norm(), (b1 - b0).norm());
  int32_t best = -1;
  double best_tau = 2.0;
  // And within the box of the four end point positions (the swept patch is in their hull).
  const Eigen::Vector3d lo = a0.cwiseMin(b0).cwiseMin(a1).cwiseMin(b1);
  const Eigen::Vector3d hi = a0.cwiseMax(b0).cwiseMax(a1).cwiseMax(b1);
  edge_tree_.for_each_near_segment(a1, b1, r, [&](int32_t k) {
    const int32_t e = tree_edges_[k];
    const auto& ev = mesh.edge_vertices(e);
    const Eigen::Vector3d& c = mesh.position(ev[0]);
    const Eigen::Vector3d& d = mesh.position(ev[1]);
    if ((c.cwiseMax(d).array() < lo.array()).any() || (c.cwiseMin(d).array() > hi.array()).any()) {
      return;
    }
    const MovingSegmentHit h = edge_crossing(e, a0, b0, a1, b1);
    if (h.hit && h.tau < best_tau) {
      best_tau = h.tau;
      best = e;
      *u = h.u;
      *v = h.v;
    }
  });
  *tau = best_tau;
  return best;
}

int32_t SegmentDatabase::faces_near_point(const Eigen::Vector3d& p, double r,
                                          std::span<int32_t> out) const {
  const MeshDatabase& mesh = *mesh_;
  int32_t n = 0;
  const double r2 = r * r;
  mesh.tree().for_each_near_segment(p, p, r, [&](int32_t f) {
    if (n < 0) return;
    const auto& v = mesh.face_vertices(f);
    TriangleFeature feature{};
    const Eigen::Vector3d q = closest_on_triangle(p, mesh.position(v[0]), mesh.position(v[1]),
                                                  mesh.position(v[2]), &feature);
    if ((q - p).squaredNorm() > r2) return;
    if (n == static_cast<int32_t>(out.size())) {
      n = -1;
      return;
    }
    out[n++] = f;
  });
  return n;
}

int32_t SegmentDatabase::edges_near_capsules(const Capsule& hull, std::span<const Capsule> capsules,
                                             std::span<int32_t> out) const {
  const MeshDatabase& mesh = *mesh_;
  // No pieces: the hull itself is the query.
  const std::span<const Capsule> pieces =
      capsules.empty()
          ? std::span<const Capsule>(&hull, 1)
          : capsules.first(
                std::min(capsules.size(), static_cast<size_t>(BoundingVolumeTree::kMaxCapsules)));
  int32_t n = 0;
  edge_tree_.for_each_near_capsules(hull, capsules, [&](int32_t k) {
    if (n < 0) return;
    const int32_t e = tree_edges_[k];
    const auto& ev = mesh.edge_vertices(e);
    const Eigen::Vector3d& c = mesh.position(ev[0]);
    const Eigen::Vector3d& d = mesh.position(ev[1]);
    bool near = false;
    for (const Capsule& piece : pieces) {
      const SegmentPair cp = closest_segment_segment(piece.p0, piece.p1, c, d);
      near = (cp.p - cp.q).squaredNorm() <= piece.r * piece.r;
      if (near) break;
    }
    if (!near) return;
    if (n == static_cast<int32_t>(out.size())) {
      n = -1;
      return;
    }
    out[n++] = e;
  });
  return n;
}

size_t SegmentDatabase::memory_bytes() const {
  return face_neighbours_.capacity() * sizeof(face_neighbours_[0]) +
         edge_neighbours_.capacity() * sizeof(edge_neighbours_[0]) +
         (face_pcp_start_.capacity() + edge_pcp_start_.capacity() + flat_group_.capacity() +
          tree_edges_.capacity()) *
             sizeof(int32_t) +
         (face_pcp_.capacity() + edge_pcp_.capacity()) * sizeof(PrimitiveRef) +
         contactable_.capacity() + convex_side_.capacity() + edge_tree_.memory_bytes();
}

}  // namespace lap::haptics
