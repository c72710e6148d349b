#pragma once
/// \file
/// Reads triangle meshes from OBJ, STL (ascii and binary), PLY and OFF through OpenMesh's readers,
/// and glTF 2.0 (.gltf/.glb) through tinygltf, into haptics::TriangleMesh.

#include <filesystem>
#include <string>

#include "core/result.h"
#include "haptics/triangle_mesh.h"

namespace lap::sim {

/// How a mesh file becomes a mesh in metres.
struct MeshLoadSettings {
  /// File units to metres (0.001 for millimetres). Applied before any transform.
  double scale = 1.0;
  /// Vertices closer than this after scaling are merged [m]; 0 merges exact duplicates only,
  /// which STL (one vertex copy per triangle) always needs.
  double weld_tolerance = 0.0;
};

/// Loads a mesh file; the diagnostic names the file and the problem. Polygons with more than
/// three corners are fanned into triangles; glTF node transforms are applied, glTF primitives
/// without normals get computed ones, and texture coordinates are kept only when every part has
/// them. OpenMesh's text readers parse coordinates in single precision (about 6 nm at 0.1 m).
[[nodiscard]] Result<haptics::TriangleMesh> load_mesh(const std::filesystem::path& file,
                                                      const MeshLoadSettings& settings = {});

/// Writes a mesh as Wavefront OBJ (positions, normals and uvs when present).
[[nodiscard]] Status save_obj(const haptics::TriangleMesh& mesh, const std::filesystem::path& file);

}  // namespace lap::sim
