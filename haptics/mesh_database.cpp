#include "haptics/mesh_database.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace lap::haptics {

const char* to_string(PrimitiveKind kind) {
  switch (kind) {
    case PrimitiveKind::kVertex: return "vertex";
    case PrimitiveKind::kEdge: return "edge";
    case PrimitiveKind::kFace: return "face";
    case PrimitiveKind::kNone: break;
  }
  return "none";
}

MeshDatabase MeshDatabase::build(const TriangleMesh& mesh, const MeshDatabaseSettings& settings) {
  MeshDatabase db;
  const int32_t nv = mesh.vertex_count();
  const int32_t nf = mesh.triangle_count();
  db.positions_ = mesh.positions;

  // Tree first, so that faces can be stored in tree order; its boxes come from the refit below.
  {
    std::vector<Eigen::Vector3d> centres(nf);
    for (int32_t f = 0; f < nf; ++f) {
      const Triangle& t = mesh.triangles[f];
      centres[f] = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
    }
    db.tree_.build(centres, settings.max_leaf_faces, &db.original_face_);
  }
  db.face_vertices_.resize(nf);
  for (int32_t f = 0; f < nf; ++f) db.face_vertices_[f] = mesh.triangles[db.original_face_[f]];
  db.refit_tree();

  // Vertex -> faces (CSR), needed only while building.
  std::vector<int32_t> start(nv + 1, 0);
  for (const auto& t : db.face_vertices_) {
    for (int32_t v : t) ++start[v + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int32_t> around(static_cast<size_t>(3) * nf);
  {
    std::vector<int32_t> fill(start.begin(), start.end() - 1);
    for (int32_t f = 0; f < nf; ++f) {
      for (int32_t v : db.face_vertices_[f]) around[fill[v]++] = f;
    }
  }
  auto faces_of = [&](int32_t v) {
    return std::span<const int32_t>(around.data() + start[v], static_cast<size_t>(start[v + 1] - start[v]));
  };

  // Edges: each undirected edge is created at its first half-edge and matched with the other
  // face through the faces of one of its vertices, in linear time.
  db.face_edges_.assign(nf, {-1, -1, -1});
  db.edge_vertices_.reserve(static_cast<size_t>(nf) * 3 / 2 + 16);
  db.edge_faces_.reserve(static_cast<size_t>(nf) * 3 / 2 + 16);
  for (int32_t f = 0; f < nf; ++f) {
    const auto& t = db.face_vertices_[f];
    for (int k = 0; k < 3; ++k) {
      if (db.face_edges_[f][k] >= 0) continue;
      const int32_t a = t[k];
      const int32_t b = t[(k + 1) % 3];
      const auto e = static_cast<int32_t>(db.edge_vertices_.size());
      db.edge_vertices_.push_back({std::min(a, b), std::max(a, b)});
      db.edge_faces_.push_back({f, -1});
      db.face_edges_[f][k] = e;
      // The twin half-edge b -> a leaves b's corner in the other face; a -> b there means the
      // two faces disagree in orientation.
      for (int32_t g : faces_of(b)) {
        if (g == f) continue;
        const auto& u = db.face_vertices_[g];
        const int jb = u[0] == b ? 0 : (u[1] == b ? 1 : 2);
        int j = -1;
        if (u[(jb + 1) % 3] == a) {
          j = jb;  // edge b -> a is edge jb of g
        } else if (u[(jb + 2) % 3] == a) {
          throw std::invalid_argument("mesh edge " + std::to_string(a) + "-" + std::to_string(b) +
                                      " joins faces of opposite orientation (validate and repair first)");
        } else {
          continue;
        }
        if (db.edge_faces_[e][1] >= 0 || db.face_edges_[g][j] >= 0) {
          throw std::invalid_argument("mesh edge " + std::to_string(a) + "-" + std::to_string(b) +
                                      " has more than two faces (validate and repair first)");
        }
        db.edge_faces_[e][1] = g;
        db.face_edges_[g][j] = e;
      }
      if (db.edge_faces_[e][1] < 0) ++db.boundary_edges_;
    }
  }
  // One face per vertex; every vertex must have a single fan that the walk covers.
  db.vertex_face_.assign(nv, -1);
  for (int32_t v = 0; v < nv; ++v) {
    if (start[v + 1] == start[v]) {
      throw std::invalid_argument("mesh vertex " + std::to_string(v) +
                                  " is used by no face (remove unreferenced vertices)");
    }
    db.vertex_face_[v] = around[start[v]];
  }
  for (int32_t v = 0; v < nv; ++v) {
    int32_t walked = 0;
    db.for_each_vertex_face(v, [&walked](int32_t) { ++walked; });
    if (walked != start[v + 1] - start[v]) {
      throw std::invalid_argument("mesh vertex " + std::to_string(v) +
                                  " is non-manifold (its faces form several fans; repair first)");
    }
  }
  db.edge_vertices_.shrink_to_fit();
  db.edge_faces_.shrink_to_fit();
  db.vertex_normals_.resize(nv);
  db.mark_.assign(nv, 0);
  db.update_vertex_normals();
  return db;
}

Eigen::Vector3d MeshDatabase::face_normal(int32_t f) const {
  const auto& t = face_vertices_[f];
  const Eigen::Vector3d n =
      (positions_[t[1]] - positions_[t[0]]).cross(positions_[t[2]] - positions_[t[0]]);
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitY();
}

Eigen::Vector3d MeshDatabase::edge_normal(int32_t e) const {
  const auto& f = edge_faces_[e];
  Eigen::Vector3d n = face_normal(f[0]);
  if (f[1] >= 0) n += face_normal(f[1]);
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : face_normal(f[0]);
}

Eigen::Vector3d MeshDatabase::normal(PrimitiveRef p) const {
  switch (p.kind) {
    case PrimitiveKind::kVertex: return vertex_normals_[p.index];
    case PrimitiveKind::kEdge: return edge_normal(p.index);
    case PrimitiveKind::kFace: return face_normal(p.index);
    case PrimitiveKind::kNone: break;
  }
  return Eigen::Vector3d::UnitY();
}

namespace {

// Adds face t's normal to its three vertices, weighted by the angle at each (§4.2). The three
// angles share |e1 x e2| (twice the area) and sum to pi, so two atan2 calls suffice.
inline void accumulate_face(const std::array<int32_t, 3>& t, const std::vector<Eigen::Vector3d>& p,
                            Eigen::Vector3d* out0, Eigen::Vector3d* out1, Eigen::Vector3d* out2) {
  const Eigen::Vector3d& a = p[t[0]];
  const Eigen::Vector3d& b = p[t[1]];
  const Eigen::Vector3d& c = p[t[2]];
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d bc = c - b;
  const Eigen::Vector3d n = ab.cross(ac);
  const double twice_area = n.norm();
  if (!(twice_area > 0.0)) return;
  const Eigen::Vector3d unit = n / twice_area;
  const double angle_a = std::atan2(twice_area, ab.dot(ac));
  const double angle_b = std::atan2(twice_area, -ab.dot(bc));
  const double angle_c = 3.14159265358979323846 - angle_a - angle_b;
  if (out0 != nullptr) *out0 += angle_a * unit;
  if (out1 != nullptr) *out1 += angle_b * unit;
  if (out2 != nullptr) *out2 += angle_c * unit;
}

inline Eigen::Vector3d unit_or_up(const Eigen::Vector3d& n) {
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitY();
}

}  // namespace

void MeshDatabase::update_vertex_normals() {
  for (Eigen::Vector3d& n : vertex_normals_) n.setZero();
  for (const auto& t : face_vertices_) {
    accumulate_face(t, positions_, &vertex_normals_[t[0]], &vertex_normals_[t[1]], &vertex_normals_[t[2]]);
  }
  for (Eigen::Vector3d& n : vertex_normals_) n = unit_or_up(n);
}

void MeshDatabase::update_vertex_normal(int32_t v) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for_each_vertex_face(v, [&](int32_t f) {
    const auto& t = face_vertices_[f];
    const int k = corner_of(f, v);
    accumulate_face(t, positions_, k == 0 ? &sum : nullptr, k == 1 ? &sum : nullptr,
                    k == 2 ? &sum : nullptr);
  });
  vertex_normals_[v] = unit_or_up(sum);
}

void MeshDatabase::refit_tree() {
  tree_.refit([this](int32_t f) {
    const auto& t = face_vertices_[f];
    Eigen::AlignedBox3d box(positions_[t[0]]);
    box.extend(positions_[t[1]]);
    box.extend(positions_[t[2]]);
    return box;
  });
}

void MeshDatabase::set_positions(std::span<const Eigen::Vector3d> positions) {
  std::copy(positions.begin(), positions.end(), positions_.begin());
  update_vertex_normals();
  refit_tree();
}

void MeshDatabase::set_positions(std::span<const Eigen::Vector3d> positions,
                                 std::span<const int32_t> moved) {
  for (int32_t v : moved) positions_[v] = positions[v];
  // The normals that change are those of the moved vertices and of their neighbours.
  if (++mark_generation_ == 0) {
    std::fill(mark_.begin(), mark_.end(), 0U);
    mark_generation_ = 1;
  }
  for (int32_t v : moved) {
    for_each_vertex_face(v, [&](int32_t f) {
      for (int32_t w : face_vertices_[f]) {
        if (mark_[w] == mark_generation_) continue;
        mark_[w] = mark_generation_;
        update_vertex_normal(w);
      }
    });
  }
  refit_tree();
}

size_t MeshDatabase::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(positions_) + bytes(vertex_normals_) + bytes(face_vertices_) + bytes(face_edges_) +
         bytes(edge_vertices_) + bytes(edge_faces_) + bytes(vertex_face_) + bytes(mark_) +
         bytes(original_face_) + tree_.memory_bytes();
}

}  // namespace lap::haptics
