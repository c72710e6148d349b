#include "haptics/triangle_mesh.h"

#include <cmath>

namespace lap::haptics {

Eigen::AlignedBox3d TriangleMesh::bounds() const {
  Eigen::AlignedBox3d box;
  for (const Triangle& t : triangles) {
    for (int32_t v : t) box.extend(positions[v]);
  }
  return box;
}

Eigen::Vector3d TriangleMesh::triangle_cross(int32_t t) const {
  const Triangle& tri = triangles[t];
  const Eigen::Vector3d& a = positions[tri[0]];
  return (positions[tri[1]] - a).cross(positions[tri[2]] - a);
}

double TriangleMesh::surface_area() const {
  double area = 0.0;
  for (int32_t t = 0; t < triangle_count(); ++t) area += 0.5 * triangle_cross(t).norm();
  return area;
}

double TriangleMesh::signed_volume() const {
  // Sum of signed tetrahedra against the bounds' centre: exact for closed meshes, and the
  // reference point keeps the terms small for meshes far from the origin.
  const Eigen::Vector3d o = bounds().center();
  double six_v = 0.0;
  for (const Triangle& t : triangles) {
    six_v += (positions[t[0]] - o).dot((positions[t[1]] - o).cross(positions[t[2]] - o));
  }
  return six_v / 6.0;
}

Eigen::Vector3d TriangleMesh::surface_centroid() const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double area = 0.0;
  for (int32_t t = 0; t < triangle_count(); ++t) {
    const double a = 0.5 * triangle_cross(t).norm();
    const Triangle& tri = triangles[t];
    sum += a * (positions[tri[0]] + positions[tri[1]] + positions[tri[2]]) / 3.0;
    area += a;
  }
  return area > 0.0 ? Eigen::Vector3d(sum / area) : Eigen::Vector3d::Zero();
}

void TriangleMesh::scale(double factor) {
  for (Eigen::Vector3d& p : positions) p *= factor;
  if (factor < 0.0) {
    for (Eigen::Vector3d& n : normals) n = -n;
  }
}

void TriangleMesh::transform(const Eigen::Affine3d& T) {
  for (Eigen::Vector3d& p : positions) p = T * p;
  // Normals transform with the inverse transpose of the linear part.
  const Eigen::Matrix3d N = T.linear().inverse().transpose();
  for (Eigen::Vector3d& n : normals) n = (N * n).normalized();
  if (T.linear().determinant() < 0.0) {
    for (Triangle& t : triangles) std::swap(t[1], t[2]);
  }
}

void TriangleMesh::append(const TriangleMesh& other) {
  const auto offset = static_cast<int32_t>(positions.size());
  const bool keep_normals =
      normals.size() == positions.size() && other.normals.size() == other.positions.size();
  const bool keep_uvs =
      uvs.size() == positions.size() && other.uvs.size() == other.positions.size();
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  for (Triangle t : other.triangles) {
    for (int32_t& v : t) v += offset;
    triangles.push_back(t);
  }
  if (keep_normals) {
    normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  } else {
    normals.clear();
  }
  if (keep_uvs) {
    uvs.insert(uvs.end(), other.uvs.begin(), other.uvs.end());
  } else {
    uvs.clear();
  }
}

void TriangleMesh::compute_vertex_normals() {
  normals.assign(positions.size(), Eigen::Vector3d::Zero());
  for (const Triangle& t : triangles) {
    const Eigen::Vector3d& a = positions[t[0]];
    const Eigen::Vector3d& b = positions[t[1]];
    const Eigen::Vector3d& c = positions[t[2]];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0.0)) continue;
    const Eigen::Vector3d unit = n / len;
    const std::array<Eigen::Vector3d, 3> p = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = p[(k + 1) % 3] - p[k];
      const Eigen::Vector3d e2 = p[(k + 2) % 3] - p[k];
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      normals[t[k]] += angle * unit;
    }
  }
  for (Eigen::Vector3d& n : normals) {
    const double len = n.norm();
    n = len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitY();
  }
}

OpenTriMesh TriangleMesh::to_openmesh(int32_t* skipped) const {
  OpenTriMesh mesh;
  std::vector<OpenTriMesh::VertexHandle> handles;
  handles.reserve(positions.size());
  for (const Eigen::Vector3d& p : positions) {
    handles.push_back(mesh.add_vertex(OpenMesh::Vec3d(p.x(), p.y(), p.z())));
  }
  int32_t refused = 0;
  for (const Triangle& t : triangles) {
    const auto fh = mesh.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
    if (!fh.is_valid()) ++refused;
  }
  if (skipped != nullptr) *skipped = refused;
  mesh.update_normals();
  return mesh;
}

}  // namespace lap::haptics
