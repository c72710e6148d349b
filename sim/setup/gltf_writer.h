#pragma once
/// \file
/// Writes a triangle mesh as glTF 2.0 (a `.gltf` JSON file beside its `.bin` buffer): positions
/// in metres, normals, texture coordinates and one material whose base colour is a PNG image
/// (written separately, sim/setup/png_writer.h). Single precision, as glTF stores vertices; the
/// same mesh gives the same bytes.

#include <filesystem>
#include <string>

#include "core/result.h"
#include "haptics/triangle_mesh.h"

namespace lap::sim {

/// The organ's look in glTF's metallic-roughness model.
struct GltfMaterial {
  std::string name;
  /// URI of the base colour image, relative to the .gltf file (e.g. "../textures/liver.png").
  std::string base_color_texture_uri;
  double metallic = 0.0;
  double roughness = 0.5;
  /// Repeat the image beyond [0, 1] texture coordinates (tileable albedo) rather than clamp.
  bool repeat = true;
};

/// Writes `file` (.gltf) and, beside it, the buffer with the same stem and `.bin`. The mesh
/// needs normals and texture coordinates, one per vertex.
[[nodiscard]] Status save_gltf(const haptics::TriangleMesh& mesh, const std::filesystem::path& file,
                               const GltfMaterial& material);

}  // namespace lap::sim
