#pragma once
/// \file
/// Writes PNG files of any header (including invalid ones) for loader tests: uncompressed
/// ("stored") deflate blocks, correct CRCs and Adler-32, so any bit depth and colour type can
/// be produced without an encoder library.

#include <cstdint>
#include <filesystem>
#include <vector>

namespace lap::test {

/// `rows`: the raw scanlines without filter bytes (each row's bytes as PNG packs them).
void write_png(const std::filesystem::path& file, uint32_t width, uint32_t height, int bit_depth,
               int colour_type, const std::vector<std::vector<uint8_t>>& rows);

/// A greyscale PNG from levels in [0, 1] at 8 or 16 bits.
void write_grey_png(const std::filesystem::path& file, int width, int height, int bit_depth,
                    const std::vector<double>& levels);

}  // namespace lap::test
