#pragma once
/// \file
/// Writes an 8-bit RGB image as PNG (stb_image_write): the generated organs' albedo textures.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/result.h"
#include "haptics/setup/albedo_texture.h"

namespace lap::sim {

[[nodiscard]] Status save_png(const haptics::RgbImage& image, const std::filesystem::path& file);
/// Writes an 8-bit grey image (row-major, width × height bytes) as PNG: a haptic height map.
[[nodiscard]] Status save_grey_png(int width, int height, const std::vector<uint8_t>& grey,
                                   const std::filesystem::path& file);

}  // namespace lap::sim
