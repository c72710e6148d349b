#include "sim/setup/png_image_data.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <memory>

namespace lap::sim {
namespace {

// One Adam7 pass: its first pixel and its step in x and y (PNG spec §8.2).
struct Pass {
  int64_t x0, y0, dx, dy;
};
constexpr std::array<Pass, 7> kAdam7 = {{{0, 0, 8, 8},
                                         {4, 0, 8, 8},
                                         {0, 4, 4, 8},
                                         {2, 0, 4, 4},
                                         {0, 2, 2, 4},
                                         {1, 0, 2, 2},
                                         {0, 1, 1, 2}}};

int64_t rows_bytes(int64_t width, int64_t height, int64_t bits_per_pixel) {
  if (width <= 0 || height <= 0) return 0;  // an empty pass has no rows, not even filter bytes
  return height * (1 + (width * bits_per_pixel + 7) / 8);
}

// Inflates the joined IDAT data without keeping it, counting what comes out.
class StreamCounter {
 public:
  StreamCounter() { status_ = inflateInit(&z_); }
  ~StreamCounter() { inflateEnd(&z_); }
  StreamCounter(const StreamCounter&) = delete;
  StreamCounter& operator=(const StreamCounter&) = delete;

  [[nodiscard]] bool failed() const { return status_ != Z_OK && status_ != Z_STREAM_END; }
  [[nodiscard]] bool ended() const { return status_ == Z_STREAM_END; }
  [[nodiscard]] uint64_t out_bytes() const { return out_; }

  // zlib's reason, or one for the statuses it leaves without a message.
  [[nodiscard]] std::string reason() const {
    if (status_ == Z_NEED_DICT) return "a preset dictionary, which PNG does not allow";
    if (status_ == Z_MEM_ERROR) return "out of memory";
    return z_.msg != nullptr ? z_.msg : "invalid data";
  }

  // Feeds one chunk's data; stops once the stream is corrupt or has given more than `limit`.
  void feed(std::span<const uint8_t> data, uint64_t limit) {
    z_.next_in = const_cast<Bytef*>(data.data());  // zlib's API is not const-correct
    z_.avail_in = static_cast<uInt>(data.size());
    while (status_ == Z_OK && out_ <= limit) {
      z_.next_out = scratch_.data();
      z_.avail_out = static_cast<uInt>(scratch_.size());
      status_ = inflate(&z_, Z_NO_FLUSH);
      out_ += scratch_.size() - z_.avail_out;
      if (status_ == Z_BUF_ERROR) status_ = Z_OK;  // no progress possible: wants more input
      if (z_.avail_out != 0) break;                // all input taken for now
    }
  }

 private:
  z_stream z_{};
  int status_ = Z_OK;
  uint64_t out_ = 0;
  std::array<Bytef, 16384> scratch_{};
};

}  // namespace

bool is_png(std::span<const uint8_t> bytes) {
  static constexpr std::array<uint8_t, 8> kSignature = {0x89, 'P',  'N',  'G',
                                                        0x0D, 0x0A, 0x1A, 0x0A};
  return bytes.size() >= kSignature.size() &&
         std::equal(kSignature.begin(), kSignature.end(), bytes.begin());
}

bool is_jpeg(std::span<const uint8_t> bytes) {
  return bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
}

uint32_t png_u32(std::span<const uint8_t> bytes, size_t at) {
  return (static_cast<uint32_t>(bytes[at]) << 24U) | (static_cast<uint32_t>(bytes[at + 1]) << 16U) |
         (static_cast<uint32_t>(bytes[at + 2]) << 8U) | static_cast<uint32_t>(bytes[at + 3]);
}

int64_t png_filtered_bytes(const PngLayout& layout) {
  const int64_t bits = static_cast<int64_t>(layout.channels) * layout.bit_depth;
  if (!layout.interlaced) return rows_bytes(layout.width, layout.height, bits);
  int64_t total = 0;
  for (const Pass& p : kAdam7) {
    total += rows_bytes((layout.width - p.x0 + p.dx - 1) / p.dx,
                        (layout.height - p.y0 + p.dy - 1) / p.dy, bits);
  }
  return total;
}

PngHeader read_png_header(std::span<const uint8_t> png) {
  if (png.size() < 33 || std::string(png.begin() + 12, png.begin() + 16) != "IHDR") {
    return {std::nullopt, "PNG without an IHDR chunk (truncated or corrupt)"};
  }
  PngLayout l;
  l.width = png_u32(png, 16);
  l.height = png_u32(png, 20);
  l.bit_depth = png[24];
  const int colour = png[25];
  // The colour types and the bit depths each allows (PNG spec §11.2.2, table 11.1).
  const bool depth_1_to_16 = l.bit_depth == 1 || l.bit_depth == 2 || l.bit_depth == 4 ||
                             l.bit_depth == 8 || l.bit_depth == 16;
  bool valid = false;
  switch (colour) {
    case 0:
      l.channels = 1;
      valid = depth_1_to_16;
      break;
    case 3:
      l.channels = 1;
      valid = depth_1_to_16 && l.bit_depth <= 8;
      break;
    case 2:
    case 4:
    case 6:
      l.channels = colour == 2 ? 3 : (colour == 4 ? 2 : 4);
      valid = l.bit_depth == 8 || l.bit_depth == 16;
      break;
    default:
      break;
  }
  if (!valid) {
    return {std::nullopt, "corrupt PNG header: colour type " + std::to_string(colour) +
                              " with bit depth " + std::to_string(l.bit_depth) +
                              " is not a combination PNG defines"};
  }
  if (png[26] != 0 || png[27] != 0 || png[28] > 1) {
    return {std::nullopt, "corrupt PNG header: compression " + std::to_string(png[26]) +
                              ", filter " + std::to_string(png[27]) + ", interlace " +
                              std::to_string(png[28]) + " (expected 0, 0 and 0 or 1)"};
  }
  l.interlaced = png[28] == 1;
  return {l, ""};
}

std::optional<std::string> png_image_data_problem(std::span<const uint8_t> png) {
  const PngHeader header = read_png_header(png);
  if (!header.layout) return header.problem;
  const PngLayout& layout = *header.layout;
  const auto expected = static_cast<uint64_t>(png_filtered_bytes(layout));
  const std::string promised = std::to_string(expected) + " bytes of rows for " +
                               std::to_string(layout.width) + " x " +
                               std::to_string(layout.height) + " pixels";
  auto counter = std::make_unique<StreamCounter>();  // 16 KiB of scratch: not on the stack
  bool any_idat = false;
  size_t at = 8;  // after the signature
  while (at + 8 <= png.size() && !counter->failed()) {
    const uint64_t length = png_u32(png, at);
    const std::string type(png.begin() + static_cast<std::ptrdiff_t>(at + 4),
                           png.begin() + static_cast<std::ptrdiff_t>(at + 8));
    if (length > 0x7FFFFFFFU || at + 12 + length > png.size()) {
      const bool named = std::all_of(type.begin(), type.end(), [](char c) {
        return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
      });
      return (named ? type + " chunk" : std::string("chunk")) + " at byte " + std::to_string(at) +
             " runs past the end of the file (truncated or corrupt)";
    }
    if (type == "IEND") break;
    if (type == "CgBI") {
      return "an Apple CgBI chunk: this is Apple's iOS-optimised variant, not a standard PNG "
             "(re-save it as a standard PNG)";
    }
    if (type == "IDAT" && !counter->ended()) {
      any_idat = true;
      counter->feed(png.subspan(at + 8, length), expected + kPngSlackBytes);
      if (counter->out_bytes() > expected + kPngSlackBytes) {
        return "corrupt image data: it inflates to more than the header's " + promised;
      }
    }
    at += 12 + length;
  }
  if (counter->failed()) return "corrupt compressed image data (zlib: " + counter->reason() + ")";
  if (!any_idat) return "no image data (no IDAT chunk; truncated or corrupt)";
  if (counter->out_bytes() < expected) {
    return "image data ends early: the compressed stream stops after " +
           std::to_string(counter->out_bytes()) + " of the header's " + promised +
           " (truncated or corrupt)";
  }
  if (!counter->ended()) {
    return "the compressed image data has all the header's " + promised +
           " but no end (its last block or its checksum is missing; truncated or corrupt)";
  }
  return std::nullopt;
}

}  // namespace lap::sim
