#include "haptics/shading_normals.h"

#include <algorithm>
#include <cmath>

#include "haptics/corner_angle.h"

namespace lap::haptics {
namespace {

// Angle of face f at its corner k (the weight of the face in its vertex's normal).
double angle_at(const MeshDatabase& m, int32_t f, int k) {
  const auto& v = m.face_vertices(f);
  const Eigen::Vector3d e1 = m.position(v[(k + 1) % 3]) - m.position(v[k]);
  const Eigen::Vector3d e2 = m.position(v[(k + 2) % 3]) - m.position(v[k]);
  return corner_angle(e1.cross(e2).norm(), e1.dot(e2));
}

int corner_of(const MeshDatabase& m, int32_t f, int32_t vertex) {
  const auto& v = m.face_vertices(f);
  return v[0] == vertex ? 0 : (v[1] == vertex ? 1 : 2);
}

}  // namespace

ShadingNormals ShadingNormals::build(const MeshDatabase& mesh, double crease_angle_rad,
                                     std::span<const uint8_t> face_shaded) {
  ShadingNormals s;
  const int32_t nf = mesh.face_count();
  s.shaded_.assign(nf, 1);
  if (!face_shaded.empty()) {
    for (int32_t f = 0; f < nf && f < static_cast<int32_t>(face_shaded.size()); ++f) {
      s.shaded_[f] = face_shaded[f] != 0 ? 1 : 0;
    }
  }
  s.cos_crease_ = std::cos(crease_angle_rad);
  s.corners_.resize(nf);
  for (int32_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d& nf_f = mesh.face_normal(f);
    for (int k = 0; k < 3; ++k) {
      if (s.shaded_[f] == 0) {
        s.corners_[f][k] = nf_f;
        continue;
      }
      s.corners_[f][k] = s.blended_corner(mesh, f, mesh.face_vertices(f)[k]);
    }
  }
  s.smooth_vertex_.assign(mesh.vertex_count(), 1);
  std::vector<Eigen::Vector3d> first(mesh.vertex_count(), Eigen::Vector3d::Zero());
  std::vector<uint8_t> seen(mesh.vertex_count(), 0);
  for (int32_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int32_t v = mesh.face_vertices(f)[k];
      if (s.shaded_[f] == 0) {
        s.smooth_vertex_[v] = 0;
        continue;
      }
      if (seen[v] == 0) {
        seen[v] = 1;
        first[v] = s.corners_[f][k];
      } else if ((first[v] - s.corners_[f][k]).norm() > 1e-12) {
        s.smooth_vertex_[v] = 0;
      }
    }
  }
  s.smooth_edge_.assign(mesh.edge_count(), 0);
  for (int32_t e = 0; e < mesh.edge_count(); ++e) {
    const auto& ef = mesh.edge_faces(e);
    if (ef[1] < 0 || s.shaded_[ef[0]] == 0 || s.shaded_[ef[1]] == 0) continue;
    bool same = true;
    for (int32_t v : mesh.edge_vertices(e)) {
      same = same && (s.corners_[ef[0]][corner_of(mesh, ef[0], v)] -
                      s.corners_[ef[1]][corner_of(mesh, ef[1], v)])
                             .norm() <= 1e-12;
    }
    s.smooth_edge_[e] = same ? 1 : 0;
  }
  return s;
}

Eigen::Vector3d ShadingNormals::blended_corner(const MeshDatabase& mesh, int32_t f,
                                               int32_t v) const {
  const Eigen::Vector3d& nf_f = mesh.face_normal(f);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  mesh.for_each_vertex_face(v, [&](int32_t g) {
    if (shaded_[g] == 0) return;
    const Eigen::Vector3d& ng = mesh.face_normal(g);
    if (ng.dot(nf_f) < cos_crease_) return;
    sum += angle_at(mesh, g, corner_of(mesh, g, v)) * ng;
  });
  const double len = sum.norm();
  return len > 0.0 ? Eigen::Vector3d(sum / len) : nf_f;
}

void ShadingNormals::update(const MeshDatabase& mesh, std::span<const int32_t> vertices) {
  for (const int32_t v : vertices) {
    if (smooth_vertex_[v] != 0) {
      const Eigen::Vector3d& n = mesh.vertex_normal(v);
      mesh.for_each_vertex_face(v, [&](int32_t f) { corners_[f][corner_of(mesh, f, v)] = n; });
      continue;
    }
    mesh.for_each_vertex_face(v, [&](int32_t f) {
      corners_[f][corner_of(mesh, f, v)] =
          shaded_[f] == 0 ? mesh.face_normal(f) : blended_corner(mesh, f, v);
    });
  }
}

void ShadingNormals::update(const MeshDatabase& mesh, const MeshUpdateScratch& scratch) {
  for (const int32_t v : scratch.dirty_vertices) {
    if (smooth_vertex_[v] != 0) {
      const Eigen::Vector3d& n = mesh.vertex_normal(v);
      for (const int32_t c : scratch.corners_of(v)) corners_[c >> 2][c & 3] = n;
      continue;
    }
    for (const int32_t c : scratch.corners_of(v)) {
      const int32_t f = c >> 2;
      corners_[f][c & 3] = shaded_[f] == 0 ? mesh.face_normal(f) : blended_corner(mesh, f, v);
    }
  }
}

Eigen::Vector3d ShadingNormals::normal(const MeshDatabase& mesh, PrimitiveRef on,
                                       const Eigen::Vector3d& p) const {
  switch (on.kind) {
    case PrimitiveKind::kFace: {
      const int32_t f = on.index;
      if (shaded_[f] == 0) return mesh.face_normal(f);
      // Eq. 6-1: each corner's normal weighted by the area of the sub-triangle opposite it.
      const auto& v = mesh.face_vertices(f);
      const Eigen::Vector3d& x0 = mesh.position(v[0]);
      const Eigen::Vector3d& x1 = mesh.position(v[1]);
      const Eigen::Vector3d& x2 = mesh.position(v[2]);
      const Eigen::Vector3d n = (x1 - x0).cross(x2 - x0);
      const double a0 = std::max(0.0, n.dot((x1 - p).cross(x2 - p)));
      const double a1 = std::max(0.0, n.dot((x2 - p).cross(x0 - p)));
      const double a2 = std::max(0.0, n.dot((x0 - p).cross(x1 - p)));
      const Eigen::Vector3d sum = a0 * corners_[f][0] + a1 * corners_[f][1] + a2 * corners_[f][2];
      const double len = sum.norm();
      return len > 0.0 ? Eigen::Vector3d(sum / len) : mesh.face_normal(f);
    }
    case PrimitiveKind::kEdge: {
      const int32_t e = on.index;
      if (smooth_edge_[e] == 0) return mesh.normal(on);
      // Inverse-distance weighting of the two vertex normals (§6.1).
      const int32_t f = mesh.edge_faces(e)[0];
      const auto& ev = mesh.edge_vertices(e);
      const double d0 = (p - mesh.position(ev[0])).norm();
      const double d1 = (p - mesh.position(ev[1])).norm();
      const Eigen::Vector3d& n0 = corners_[f][corner_of(mesh, f, ev[0])];
      const Eigen::Vector3d& n1 = corners_[f][corner_of(mesh, f, ev[1])];
      if (d0 == 0.0) return n0;
      if (d1 == 0.0) return n1;
      const Eigen::Vector3d sum = n0 / d0 + n1 / d1;
      const double len = sum.norm();
      return len > 0.0 ? Eigen::Vector3d(sum / len) : mesh.normal(on);
    }
    case PrimitiveKind::kVertex: {
      const int32_t v = on.index;
      if (smooth_vertex_[v] == 0) return mesh.normal(on);
      int32_t f = -1;
      mesh.for_each_vertex_face(v, [&](int32_t g) { f = f < 0 ? g : f; });
      return corners_[f][corner_of(mesh, f, v)];
    }
    case PrimitiveKind::kNone:
      break;
  }
  return Eigen::Vector3d::UnitY();
}

}  // namespace lap::haptics
