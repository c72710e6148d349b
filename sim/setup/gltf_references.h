#pragma once
/// \file
/// What a glTF file may reach: its buffers and images are files in the glTF's own folder (or
/// below it), or `data:` URIs up to kMaxGltfDataUriChars (sim/setup/mesh_limits.h). A scene is
/// untrusted input: a buffer URI of `../../etc/passwd` or `/home/x/.ssh/id_rsa` must not make the
/// loader read that file. Checked twice: on the JSON before tinygltf runs (to name the field),
/// and by the file callbacks tinygltf reads through (symbolic links, and anything the first
/// check missed).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"

namespace lap::sim {

/// The JSON text of a .gltf file or of a .glb's JSON chunk ("" when the .glb's layout is broken:
/// tinygltf then says why).
[[nodiscard]] std::string gltf_json_text(const std::vector<unsigned char>& bytes, bool binary);

/// The references and counts of a glTF document (its JSON text) against the limits, each problem
/// as `file:line: buffers[0].uri: '../../etc/passwd' leaves the scene's folder` (the line of the
/// field in a text .gltf; a .glb's JSON chunk, `binary`, has no lines of the file's). Text that is
/// not JSON passes (tinygltf reports it).
[[nodiscard]] Status check_gltf_references(const std::filesystem::path& file,
                                           const std::string& json_text, bool binary = false);

/// A URI's %XX escapes decoded, as tinygltf decodes one before opening the file it names.
[[nodiscard]] std::string percent_decoded(const std::string& uri);

/// Whether `path` lies in `folder` or below it once symbolic links and `..` are resolved.
[[nodiscard]] bool inside_folder(const std::filesystem::path& folder,
                                 const std::filesystem::path& path);

}  // namespace lap::sim
