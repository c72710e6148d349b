#pragma once
/// \file
/// The generated patients on disk (haptics/setup/anatomy_generator.h): per preset, one glTF 2.0
/// file per organ (`<organ>.gltf` + `<organ>.bin`) and `anatomy.json`, which says where the
/// scenario should put the ductotomy, the catheter and the trocars; and the albedo images,
/// `<tissue>.png`, beside them (a glTF may refer only to files in its own folder:
/// sim/setup/gltf_references.h, so each preset carries its copy of the same images).
/// `laptrainer-cli generate-assets --anatomy` writes them; assets/anatomy/ holds the committed
/// copy.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"
#include "haptics/setup/anatomy_generator.h"

namespace lap::sim {

/// The albedo images' size: square, this many pixels a side.
inline constexpr int32_t kAlbedoSizePx = 256;

/// Writes one patient's organs and anatomy.json into `dir` (created if missing).
[[nodiscard]] Status save_anatomy(const haptics::GeneratedAnatomy& anatomy,
                                  const std::filesystem::path& dir);

/// Writes every tissue's albedo image (`<tissue>.png`, kAlbedoSizePx square) into `dir`.
[[nodiscard]] Status save_albedo_textures(const std::filesystem::path& dir);

/// Writes the named presets, each with its textures, under root/<preset>/; an unknown preset
/// name is a diagnostic.
[[nodiscard]] Status save_anatomy_presets(const std::filesystem::path& root,
                                          const std::vector<std::string>& presets);

}  // namespace lap::sim
