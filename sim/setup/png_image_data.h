#pragma once
/// \file
/// Checks a greyscale PNG's image data before a decoder sees it (setup only): the IDAT chunks,
/// joined, must be one zlib stream that inflates to exactly the filtered rows the header promises
/// (PNG spec §7.2 scanlines, §8.2 Adam7 passes, §10 compression). stb_image's inflater reads zeros
/// past the end of its input, so a stream that never ends made it grow its output until memory ran
/// out; zlib, stopped at the expected size, refuses such a file here with a clear reason.

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace lap::sim {

/// What the PNG header promised: size, bits per grey sample (8 or 16), Adam7 or not.
struct PngLayout {
  int64_t width = 0;
  int64_t height = 0;
  int bit_depth = 8;
  bool interlaced = false;
};

/// Bytes of filtered scanlines (one filter byte per row of each pass) the layout holds.
[[nodiscard]] int64_t png_filtered_bytes(const PngLayout& layout);

/// Why the file's image data cannot be decoded, or nothing when the IDAT stream is complete and
/// exactly the layout's size. `png` is the whole file, signature included.
[[nodiscard]] std::optional<std::string> png_image_data_problem(std::span<const uint8_t> png,
                                                                const PngLayout& layout);

}  // namespace lap::sim
