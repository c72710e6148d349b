#include "sim/setup/png_image_data.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <memory>

namespace lap::sim {
namespace {

uint32_t be32(std::span<const uint8_t> b, size_t at) {
  return (static_cast<uint32_t>(b[at]) << 24U) | (static_cast<uint32_t>(b[at + 1]) << 16U) |
         (static_cast<uint32_t>(b[at + 2]) << 8U) | static_cast<uint32_t>(b[at + 3]);
}

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

int64_t rows_bytes(int64_t width, int64_t height, int64_t bytes_per_pixel) {
  if (width <= 0 || height <= 0) return 0;  // an empty pass has no rows, not even filter bytes
  return height * (1 + width * bytes_per_pixel);
}

// Inflates the joined IDAT data without keeping it, counting what comes out.
class StreamCounter {
 public:
  StreamCounter() { ok_ = inflateInit(&z_) == Z_OK; }
  ~StreamCounter() {
    if (ok_) inflateEnd(&z_);
  }
  StreamCounter(const StreamCounter&) = delete;
  StreamCounter& operator=(const StreamCounter&) = delete;

  [[nodiscard]] bool ok() const { return ok_; }
  [[nodiscard]] bool ended() const { return status_ == Z_STREAM_END; }
  [[nodiscard]] uint64_t out_bytes() const { return out_; }
  [[nodiscard]] const char* message() const { return z_.msg != nullptr ? z_.msg : "invalid data"; }

  // Feeds one chunk's data; false once the stream is corrupt or has given more than `limit`.
  bool feed(std::span<const uint8_t> data, uint64_t limit) {
    z_.next_in = const_cast<Bytef*>(data.data());  // zlib's API is not const-correct
    z_.avail_in = static_cast<uInt>(data.size());
    while (status_ == Z_OK && (z_.avail_in > 0 || z_.avail_out == 0)) {
      z_.next_out = scratch_.data();
      z_.avail_out = static_cast<uInt>(scratch_.size());
      status_ = inflate(&z_, Z_NO_FLUSH);
      out_ += scratch_.size() - z_.avail_out;
      if (out_ > limit) return false;
      if (status_ == Z_BUF_ERROR) status_ = Z_OK;  // no progress possible: wants more input
      if (z_.avail_out != 0) break;                // all input taken for now
    }
    return status_ == Z_OK || status_ == Z_STREAM_END;
  }

 private:
  z_stream z_{};
  int status_ = Z_OK;
  bool ok_ = false;
  uint64_t out_ = 0;
  std::array<Bytef, 16384> scratch_{};
};

}  // namespace

int64_t png_filtered_bytes(const PngLayout& layout) {
  const int64_t bpp = layout.bit_depth == 16 ? 2 : 1;
  if (!layout.interlaced) return rows_bytes(layout.width, layout.height, bpp);
  int64_t total = 0;
  for (const Pass& p : kAdam7) {
    total += rows_bytes((layout.width - p.x0 + p.dx - 1) / p.dx,
                        (layout.height - p.y0 + p.dy - 1) / p.dy, bpp);
  }
  return total;
}

std::optional<std::string> png_image_data_problem(std::span<const uint8_t> png,
                                                  const PngLayout& layout) {
  const auto expected = static_cast<uint64_t>(png_filtered_bytes(layout));
  const std::string promised = std::to_string(expected) + " bytes of rows for " +
                               std::to_string(layout.width) + " x " +
                               std::to_string(layout.height) + " pixels";
  auto counter = std::make_unique<StreamCounter>();  // 16 KiB of scratch: not on the stack
  if (!counter->ok()) return "zlib could not start (out of memory)";
  bool any_idat = false;
  size_t at = 8;  // after the signature
  while (at + 8 <= png.size()) {
    const uint64_t length = be32(png, at);
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
    if (type == "IDAT" && !counter->ended()) {
      any_idat = true;
      if (!counter->feed(png.subspan(at + 8, length), expected)) {
        if (counter->out_bytes() > expected) {
          return "corrupt image data: it inflates to more than the header's " + promised;
        }
        return std::string("corrupt compressed image data (zlib: ") + counter->message() + ")";
      }
    }
    at += 12 + length;
  }
  if (!any_idat) return "no image data (no IDAT chunk; truncated or corrupt)";
  if (!counter->ended()) {
    return "image data ends early: the compressed stream stops after " +
           std::to_string(counter->out_bytes()) + " of the header's " + promised +
           " (truncated or corrupt)";
  }
  if (counter->out_bytes() != expected) {
    return "corrupt image data: it holds " + std::to_string(counter->out_bytes()) +
           " bytes where the header promises " + promised;
  }
  return std::nullopt;
}

}  // namespace lap::sim
