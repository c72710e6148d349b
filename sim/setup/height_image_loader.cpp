#include "sim/setup/height_image_loader.h"

#include <stb_image.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "core/bounded_file.h"
#include "sim/setup/load_error.h"
#include "sim/setup/png_image_data.h"

namespace lap::sim {
namespace {

struct Header {
  int64_t width = 0;
  int64_t height = 0;
  int bit_depth = 0;
  int channels = 0;
};

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
  throw LoadError(file, what);
}

// PNG: the IHDR chunk must come first (PNG spec §5.2, §11.2.2).
Header png_header(const std::filesystem::path& file, const std::vector<uint8_t>& b) {
  if (b.size() < 33 || std::string(b.begin() + 12, b.begin() + 16) != "IHDR") {
    fail(file, "PNG without an IHDR chunk (truncated or corrupt)");
  }
  Header h;
  h.width = png_u32(b, 16);
  h.height = png_u32(b, 20);
  h.bit_depth = b[24];
  const int colour = b[25];
  switch (colour) {
    case 0:
      h.channels = 1;
      break;
    case 2:
      fail(file, "expected a greyscale height map, got an RGB PNG (convert it to grey)");
    case 3:
      fail(file, "expected a greyscale height map, got a palette PNG (convert it to grey)");
    case 4:
      fail(file, "expected a greyscale height map without alpha, got grey + alpha");
    case 6:
      fail(file, "expected a greyscale height map, got an RGBA PNG (convert it to grey)");
    default:
      fail(file, "PNG colour type " + std::to_string(colour) + " is invalid");
  }
  if (h.bit_depth != 8 && h.bit_depth != 16) {
    fail(file, "expected an 8- or 16-bit greyscale PNG, got " + std::to_string(h.bit_depth) +
                   "-bit (too few height levels for a haptic texture)");
  }
  return h;
}

// JPEG: the first start-of-frame marker carries precision, size and components.
Header jpeg_header(const std::filesystem::path& file, const std::vector<uint8_t>& b) {
  size_t i = 2;
  while (i + 4 <= b.size()) {
    if (b[i] != 0xFF) fail(file, "corrupt JPEG: expected a marker at byte " + std::to_string(i));
    const uint8_t marker = b[i + 1];
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    const size_t length = (static_cast<size_t>(b[i + 2]) << 8U) | b[i + 3];
    const bool sof =
        marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      if (i + 10 > b.size()) break;
      Header h;
      h.bit_depth = b[i + 4];
      h.height = (static_cast<int64_t>(b[i + 5]) << 8) | b[i + 6];
      h.width = (static_cast<int64_t>(b[i + 7]) << 8) | b[i + 8];
      h.channels = b[i + 9];
      if (h.channels != 1) {
        fail(file, "expected a greyscale JPEG height map, got " + std::to_string(h.channels) +
                       " colour components (convert it to grey)");
      }
      if (h.bit_depth != 8) {
        fail(file, "expected an 8-bit JPEG, got " + std::to_string(h.bit_depth) +
                       "-bit (use a 16-bit PNG for more height levels)");
      }
      if (marker != 0xC0 && marker != 0xC1 && marker != 0xC2) {
        fail(file, "unsupported JPEG coding (lossless or arithmetic); use PNG");
      }
      return h;
    }
    i += 2 + length;
  }
  fail(file, "JPEG without a frame header (truncated or corrupt)");
}

haptics::HeightImage read_height_image(const std::filesystem::path& file) {
  // The largest PNG of the most pixels allowed, 16 bits each, barely compressed.
  const Result<std::string> read =
      read_bounded_file(file, static_cast<uintmax_t>(kMaxHeightMapPixels) * 4U,
                        "a PNG or JPEG height map", "sim/setup/height_image_loader.h");
  if (!read.ok()) throw LoadError(read.diagnostics().front());
  const std::vector<uint8_t> bytes(read.value().begin(), read.value().end());
  if (bytes.empty()) fail(file, "empty file; expected a PNG or JPEG height map");
  const bool png = is_png(bytes);
  Header h;
  if (png) {
    h = png_header(file, bytes);
  } else if (is_jpeg(bytes)) {
    h = jpeg_header(file, bytes);
  } else {
    fail(file, "not a PNG or JPEG file (expected a greyscale height map)");
  }
  if (h.width == 0 || h.height == 0) {
    fail(file, "zero size (" + std::to_string(h.width) + " x " + std::to_string(h.height) +
                   " pixels); expected at least 1 x 1");
  }
  if (h.width > kMaxHeightMapSide || h.height > kMaxHeightMapSide ||
      h.width * h.height > kMaxHeightMapPixels) {
    fail(file, "absurd dimensions " + std::to_string(h.width) + " x " + std::to_string(h.height) +
                   " pixels; expected at most " + std::to_string(kMaxHeightMapSide) +
                   " per side and " + std::to_string(kMaxHeightMapPixels) + " pixels");
  }
  if (png) {
    if (const auto problem = png_image_data_problem(bytes)) fail(file, *problem);
  }
  const int n = static_cast<int>(bytes.size());
  int w = 0;
  int ht = 0;
  int comp = 0;
  // The decoder's own reading of the header must agree with ours before it allocates by it (a
  // guard: both read the same IHDR or first frame header, so this should never refuse a file).
  if (stbi_info_from_memory(bytes.data(), n, &w, &ht, &comp) == 0) {
    fail(file, std::string("corrupt image header (") + stbi_failure_reason() + ")");
  }
  if (w != h.width || ht != h.height) {
    fail(file, "corrupt image header: two sizes, " + std::to_string(h.width) + " x " +
                   std::to_string(h.height) + " and " + std::to_string(w) + " x " +
                   std::to_string(ht) + " pixels");
  }
  haptics::HeightImage image;
  if (h.bit_depth == 16) {
    std::unique_ptr<stbi_us, decltype(&stbi_image_free)> data(
        stbi_load_16_from_memory(bytes.data(), n, &w, &ht, &comp, 1), &stbi_image_free);
    if (!data) fail(file, std::string("corrupt PNG data (") + stbi_failure_reason() + ")");
    image.values.resize(static_cast<size_t>(w) * static_cast<size_t>(ht));
    for (size_t i = 0; i < image.values.size(); ++i) image.values[i] = data.get()[i] / 65535.0F;
  } else {
    std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> data(
        stbi_load_from_memory(bytes.data(), n, &w, &ht, &comp, 1), &stbi_image_free);
    if (!data) fail(file, std::string("corrupt image data (") + stbi_failure_reason() + ")");
    image.values.resize(static_cast<size_t>(w) * static_cast<size_t>(ht));
    for (size_t i = 0; i < image.values.size(); ++i) image.values[i] = data.get()[i] / 255.0F;
  }
  if (w != h.width || ht != h.height) fail(file, "decoded size differs from the header");
  image.width = w;
  image.height = ht;
  return image;
}

}  // namespace

Result<haptics::HeightImage> load_height_image(const std::filesystem::path& file) {
  try {
    return read_height_image(file);
  } catch (const LoadError& e) {
    return e.diagnostic();
  }
}

}  // namespace lap::sim
