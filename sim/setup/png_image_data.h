#pragma once
/// \file
/// Checks a PNG's image data before a decoder sees it (setup only): the IDAT chunks, joined, must
/// be one zlib stream that inflates to at least the filtered rows the header promises and ends
/// within kPngSlackBytes of them (PNG spec §7.2 scanlines, §8.2 Adam7 passes, §10 compression).
/// stb_image's inflater reads zeros past the end of its input, so a stream that never ends made it
/// grow its output until memory ran out; zlib, stopped at the expected size, refuses such a file
/// here with a clear reason. Apple's CgBI variant (raw deflate, which stb then reads differently
/// from zlib) is refused by name.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace lap::sim {

/// What a PNG header promises: size, samples per pixel (by colour type), bits per sample, Adam7.
struct PngLayout {
  int64_t width = 0;
  int64_t height = 0;
  int channels = 1;  // grey 1, RGB 3, palette 1, grey + alpha 2, RGBA 4
  int bit_depth = 8;
  bool interlaced = false;
};

/// Image data beyond the header's rows that is tolerated (and ignored, as stb_image and libpng
/// do: some encoders pad the stream): enough for any padding, far from gigabytes.
constexpr uint64_t kPngSlackBytes = 1U << 20U;

/// Whether the bytes start with PNG's 8-byte signature (PNG spec §5.2).
[[nodiscard]] bool is_png(std::span<const uint8_t> bytes);

/// Whether the bytes start as a JPEG does: its SOI marker (FF D8) and the next marker's FF
/// (ITU T.81 §B.1.1.3). With is_png, what the image loaders let reach stb_image, which would also
/// decode GIF, BMP, PSD, TGA, HDR, PIC and PNM.
[[nodiscard]] bool is_jpeg(std::span<const uint8_t> bytes);

/// The big-endian 32-bit field at `at` (PNG's lengths, widths and heights); the caller checks
/// that 4 bytes are there.
[[nodiscard]] uint32_t png_u32(std::span<const uint8_t> bytes, size_t at);

/// Bytes of filtered scanlines (one filter byte per row of each pass) the layout holds.
[[nodiscard]] int64_t png_filtered_bytes(const PngLayout& layout);

/// The layout the file's IHDR chunk declares, or why it cannot be read (no IHDR first, an invalid
/// colour type or bit depth for it, a compression, filter or interlace method PNG does not
/// define). `png` is the whole file, signature included.
struct PngHeader {
  std::optional<PngLayout> layout;
  std::string problem;  // when there is no layout
};
[[nodiscard]] PngHeader read_png_header(std::span<const uint8_t> png);

/// Why the file's image data cannot be decoded, or nothing when its header reads and its IDAT
/// stream is complete and of the header's size (up to kPngSlackBytes more).
[[nodiscard]] std::optional<std::string> png_image_data_problem(std::span<const uint8_t> png);

}  // namespace lap::sim
