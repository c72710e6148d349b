#pragma once
/// \file
/// The project's one triangle-mesh representation: flat indexed arrays of vertices and triangles.
///
/// Why flat arrays and not an OpenMesh half-edge kernel as the primary store: the half-edge kernel
/// cannot hold the defects we must diagnose (it splits non-manifold vertices and refuses complex
/// edges on insertion), and the haptic step wants contiguous arrays indexed by integers
/// (hot data flat, docs/architecture.md). OpenMesh is used underneath for reading files and is
/// available as a view through to_openmesh() for algorithms that need a half-edge structure on a
/// clean mesh.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <array>
#include <cstdint>
#include <vector>

namespace lap::haptics {

/// Three vertex indices, counter-clockwise seen from outside.
using Triangle = std::array<int32_t, 3>;

/// OpenMesh mesh type with double precision points and normals.
struct OpenMeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::Status);
};
using OpenTriMesh = OpenMesh::TriMesh_ArrayKernelT<OpenMeshTraits>;

/// A triangle mesh in metres. Normals and texture coordinates are optional per-vertex arrays:
/// either empty or exactly one entry per vertex.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> positions;  ///< n_vertices [m]
  std::vector<Triangle> triangles;         ///< n_triangles, indices into positions
  std::vector<Eigen::Vector3d> normals;    ///< empty or n_vertices, unit
  std::vector<Eigen::Vector2d> uvs;        ///< empty or n_vertices

  [[nodiscard]] int32_t vertex_count() const { return static_cast<int32_t>(positions.size()); }
  [[nodiscard]] int32_t triangle_count() const { return static_cast<int32_t>(triangles.size()); }

  /// Axis-aligned bounds of the vertices that triangles use.
  [[nodiscard]] Eigen::AlignedBox3d bounds() const;
  /// Area-weighted normal of triangle t times 2 (cross product of two edges) [m^2].
  [[nodiscard]] Eigen::Vector3d triangle_cross(int32_t t) const;
  /// Sum of triangle areas [m^2].
  [[nodiscard]] double surface_area() const;
  /// Signed enclosed volume by the divergence theorem [m^3]; positive for a closed mesh whose
  /// triangles are counter-clockwise seen from outside.
  [[nodiscard]] double signed_volume() const;
  /// Area-weighted centroid of the surface [m].
  [[nodiscard]] Eigen::Vector3d surface_centroid() const;

  /// Scales positions about the origin (e.g. 0.001 for millimetres to metres).
  void scale(double factor);
  /// Applies a rigid or affine transform to positions (and rotates normals).
  void transform(const Eigen::Affine3d& T);
  /// Appends another mesh (indices shifted). Optional arrays are kept only if both have them.
  void append(const TriangleMesh& other);
  /// Recomputes per-vertex normals weighted by the angle each triangle subtends at the vertex
  /// (thesis §4.2).
  void compute_vertex_normals();

  /// Half-edge view for algorithms that need one. Triangles OpenMesh refuses (non-manifold) are
  /// skipped and counted in *skipped if given; validate first.
  [[nodiscard]] OpenTriMesh to_openmesh(int32_t* skipped = nullptr) const;
};

}  // namespace lap::haptics
