#pragma once
/// \file
/// An organ's colour texture for drawing (thesis §7.6: "texture maps were used to make those
/// geometrical models appear more realistic"): the base colour image of a glTF mesh's material
/// (pbrMetallicRoughness.baseColorTexture), decoded to 8-bit RGB at set-up so that the app only
/// uploads it (row 0 the image's top, glTF's texture coordinate v = 0). The haptic loop never
/// reads it; the texture coordinates travel with the mesh (haptics::TriangleMesh::uvs).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/result.h"
#include "haptics/setup/albedo_texture.h"

namespace lap::sim {

/// Largest accepted side [pixels] and pixel count of a colour texture (an 8k texture is more
/// than any organ on a 1080p monitor needs; beyond is a mistake and would take gigabytes).
constexpr int32_t kMaxAlbedoSide = 8192;
constexpr int64_t kMaxAlbedoPixels = 16LL * 1024 * 1024;

/// The base colour texture of the first material of `gltf` (a .gltf or .glb already loaded by
/// load_mesh, so its references are checked) that has one: the image file beside it, decoded.
/// Null when the file names none, or keeps its image inside a buffer or a data: URI (not
/// drawn). A named image that is missing, not PNG or JPEG, or too large is refused with the
/// glTF and the field (`images[0].uri`) named.
[[nodiscard]] Result<std::shared_ptr<const haptics::RgbImage>> load_gltf_albedo(
    const std::filesystem::path& gltf);

}  // namespace lap::sim
