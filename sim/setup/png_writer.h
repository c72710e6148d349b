#pragma once
/// \file
/// Writes an 8-bit RGB image as PNG (stb_image_write): the generated organs' albedo textures.

#include <filesystem>

#include "core/result.h"
#include "haptics/setup/albedo_texture.h"

namespace lap::sim {

[[nodiscard]] Status save_png(const haptics::RgbImage& image, const std::filesystem::path& file);

}  // namespace lap::sim
