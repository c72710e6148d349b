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

  // Tree first, so that faces can be stored in tree order.
  std::vector<Eigen::AlignedBox3d> boxes(nf);
  for (int32_t f = 0; f < nf; ++f) {
    for (int32_t v : mesh.triangles[f]) boxes[f].extend(mesh.positions[v]);
  }
  db.tree_.build(boxes, settings.max_leaf_faces, &db.original_face_);
  boxes = {};
  db.face_vertices_.resize(nf);
  for (int32_t f = 0; f < nf; ++f) db.face_vertices_[f] = mesh.triangles[db.original_face_[f]];

  // Vertex -> faces (CSR).
  db.vertex_face_start_.assign(nv + 1, 0);
  for (const auto& t : db.face_vertices_) {
    for (int32_t v : t) ++db.vertex_face_start_[v + 1];
  }
  std::partial_sum(db.vertex_face_start_.begin(), db.vertex_face_start_.end(),
                   db.vertex_face_start_.begin());
  db.vertex_faces_.resize(static_cast<size_t>(3) * nf);
  {
    std::vector<int32_t> fill(db.vertex_face_start_.begin(), db.vertex_face_start_.end() - 1);
    for (int32_t f = 0; f < nf; ++f) {
      for (int32_t v : db.face_vertices_[f]) db.vertex_faces_[fill[v]++] = f;
    }
  }

  // Edges: each undirected edge found once through its lower vertex's faces, in linear time
  // (no global hash of 3 n_f half-edges).
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
      // The other face of this edge is among a's faces.
      for (int32_t g : db.vertex_faces(a)) {
        if (g == f) continue;
        const auto& u = db.face_vertices_[g];
        for (int j = 0; j < 3; ++j) {
          const int32_t c = u[j];
          const int32_t d = u[(j + 1) % 3];
          if ((c == a && d == b) || (c == b && d == a)) {
            if (db.face_edges_[g][j] >= 0) continue;
            if (db.edge_faces_[e][1] >= 0) {
              throw std::invalid_argument("mesh edge " + std::to_string(a) + "-" +
                                          std::to_string(b) +
                                          " has more than two faces (validate and repair first)");
            }
            db.edge_faces_[e][1] = g;
            db.face_edges_[g][j] = e;
          }
        }
      }
      if (db.edge_faces_[e][1] < 0) ++db.boundary_edges_;
    }
  }
  db.edge_vertices_.shrink_to_fit();
  db.edge_faces_.shrink_to_fit();
  db.vertex_normals_.resize(nv);
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

void MeshDatabase::update_vertex_normals() {
  for (Eigen::Vector3d& n : vertex_normals_) n.setZero();
  for (const auto& t : face_vertices_) {
    const Eigen::Vector3d& a = positions_[t[0]];
    const Eigen::Vector3d& b = positions_[t[1]];
    const Eigen::Vector3d& c = positions_[t[2]];
    Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0.0)) continue;
    n /= len;
    const Eigen::Vector3d* p[3] = {&a, &b, &c};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = *p[(k + 1) % 3] - *p[k];
      const Eigen::Vector3d e2 = *p[(k + 2) % 3] - *p[k];
      vertex_normals_[t[k]] += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * n;
    }
  }
  for (Eigen::Vector3d& n : vertex_normals_) {
    const double len = n.norm();
    n = len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitY();
  }
}

void MeshDatabase::set_positions(std::span<const Eigen::Vector3d> positions) {
  std::copy(positions.begin(), positions.end(), positions_.begin());
  update_vertex_normals();
  tree_.refit([this](int32_t f) {
    const auto& t = face_vertices_[f];
    Eigen::AlignedBox3d box(positions_[t[0]]);
    box.extend(positions_[t[1]]);
    box.extend(positions_[t[2]]);
    return box;
  });
}

size_t MeshDatabase::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(positions_) + bytes(vertex_normals_) + bytes(face_vertices_) + bytes(face_edges_) +
         bytes(edge_vertices_) + bytes(edge_faces_) + bytes(vertex_face_start_) +
         bytes(vertex_faces_) + bytes(original_face_) + tree_.memory_bytes();
}

}  // namespace lap::haptics
