#include "tests/support/png_writer.h"

#include <array>
#include <cmath>
#include <fstream>
#include <string>

namespace lap::test {
namespace {

uint32_t crc32(const uint8_t* data, size_t n, uint32_t crc = 0xFFFFFFFFU) {
  for (size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1U) ^ (0xEDB88320U & (0U - (crc & 1U)));
  }
  return crc;
}

void put32(std::vector<uint8_t>& out, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8)
    out.push_back(static_cast<uint8_t>(v >> static_cast<unsigned>(s)));
}

void chunk(std::vector<uint8_t>& out, const char* type, const std::vector<uint8_t>& data) {
  put32(out, static_cast<uint32_t>(data.size()));
  std::vector<uint8_t> body(type, type + 4);
  body.insert(body.end(), data.begin(), data.end());
  out.insert(out.end(), body.begin(), body.end());
  put32(out, crc32(body.data(), body.size()) ^ 0xFFFFFFFFU);
}

}  // namespace

void write_png(const std::filesystem::path& file, uint32_t width, uint32_t height, int bit_depth,
               int colour_type, const std::vector<std::vector<uint8_t>>& rows) {
  std::vector<uint8_t> out = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  std::vector<uint8_t> ihdr;
  put32(ihdr, width);
  put32(ihdr, height);
  ihdr.push_back(static_cast<uint8_t>(bit_depth));
  ihdr.push_back(static_cast<uint8_t>(colour_type));
  ihdr.push_back(0);
  ihdr.push_back(0);
  ihdr.push_back(0);
  chunk(out, "IHDR", ihdr);
  std::vector<uint8_t> raw;
  for (const auto& row : rows) {
    raw.push_back(0);  // filter: none
    raw.insert(raw.end(), row.begin(), row.end());
  }
  std::vector<uint8_t> z = {0x78, 0x01};
  size_t at = 0;
  do {
    const size_t n = std::min<size_t>(65535, raw.size() - at);
    const bool last = at + n == raw.size();
    z.push_back(last ? 1 : 0);
    z.push_back(static_cast<uint8_t>(n & 0xFFU));
    z.push_back(static_cast<uint8_t>(n >> 8U));
    z.push_back(static_cast<uint8_t>(~n & 0xFFU));
    z.push_back(static_cast<uint8_t>((~n >> 8U) & 0xFFU));
    z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(at),
             raw.begin() + static_cast<std::ptrdiff_t>(at + n));
    at += n;
  } while (at < raw.size());
  uint32_t a = 1;
  uint32_t b = 0;
  for (uint8_t c : raw) {
    a = (a + c) % 65521U;
    b = (b + a) % 65521U;
  }
  put32(z, (b << 16U) | a);
  chunk(out, "IDAT", z);
  chunk(out, "IEND", {});
  std::ofstream f(file, std::ios::binary);
  f.write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
}

void write_grey_png(const std::filesystem::path& file, int width, int height, int bit_depth,
                    const std::vector<double>& levels) {
  std::vector<std::vector<uint8_t>> rows(static_cast<size_t>(height));
  const double top = bit_depth == 16 ? 65535.0 : 255.0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const auto v =
          static_cast<uint32_t>(std::lround(levels[static_cast<size_t>(y * width + x)] * top));
      if (bit_depth == 16) rows[y].push_back(static_cast<uint8_t>(v >> 8U));
      rows[y].push_back(static_cast<uint8_t>(v & 0xFFU));
    }
  }
  write_png(file, static_cast<uint32_t>(width), static_cast<uint32_t>(height), bit_depth, 0, rows);
}

}  // namespace lap::test
