#pragma once
/// \file
/// Loads a haptic texture's height map (thesis §6.3.3 a) from a PNG (8- or 16-bit greyscale) or
/// a baseline JPEG (8-bit greyscale). Setup only. Every refusal is a Diagnostic naming the file
/// and what was expected: missing or unreadable file, not a PNG/JPEG, colour or alpha, another
/// bit depth, zero size, dimensions beyond kMaxSide or kMaxPixels, corrupt data, a PNG whose
/// compressed rows do not end where its header says (checked with zlib before stb_image decodes:
/// png_image_data.h).

#include <cstdint>
#include <filesystem>

#include "core/result.h"
#include "haptics/image_height_field.h"

namespace lap::sim {

/// Largest accepted side [pixels] and pixel count: a 0.1 m organ at 10 um per texel needs
/// 10^4; anything beyond is a mistake (and would take gigabytes).
constexpr int32_t kMaxHeightMapSide = 16384;
constexpr int64_t kMaxHeightMapPixels = 64LL * 1024 * 1024;

/// Grey levels in [0, 1] (8-bit: v / 255, 16-bit: v / 65535), row 0 at the top of the image.
/// The diagnostic names the file and what was expected.
[[nodiscard]] Result<haptics::HeightImage> load_height_image(const std::filesystem::path& file);

}  // namespace lap::sim
