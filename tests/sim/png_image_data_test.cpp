// The PNG image-data check (sim/setup/png_image_data.h): the size it expects matches a brute-force
// count of Adam7's passes, real deflate streams split over chunks pass, and every way a stream can
// disagree with its header (too long, never ending, corrupt, past the file's end) is refused with
// a reason, before stb_image's decoder sees it.

#include "sim/setup/png_image_data.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <array>
#include <set>
#include <string>
#include <vector>

#include "sim/setup/height_image_loader.h"
#include "tests/test_support.h"

namespace lap::sim {
namespace {

using Bytes = std::vector<uint8_t>;

void put32(Bytes& b, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<uint8_t>(v >> s));
}

void chunk(Bytes& png, const std::string& type, const Bytes& data) {
  put32(png, static_cast<uint32_t>(data.size()));
  png.insert(png.end(), type.begin(), type.end());
  png.insert(png.end(), data.begin(), data.end());
  uLong crc = crc32(0, reinterpret_cast<const Bytef*>(type.data()), 4);
  crc = crc32(crc, data.data(), static_cast<uInt>(data.size()));
  put32(png, static_cast<uint32_t>(crc));
}

Bytes ihdr(uint32_t w, uint32_t h, int depth, bool interlaced) {
  Bytes d;
  put32(d, w);
  put32(d, h);
  d.insert(d.end(), {static_cast<uint8_t>(depth), 0, 0, 0, static_cast<uint8_t>(interlaced)});
  return d;
}

// zlib's own deflate (not stored blocks), finished or only flushed (a stream that does not end).
Bytes deflated(const Bytes& raw, bool finish = true) {
  z_stream z{};
  EXPECT_EQ(deflateInit(&z, 9), Z_OK);
  Bytes out(deflateBound(&z, raw.size()) + 64);
  z.next_in = const_cast<Bytef*>(raw.data());
  z.avail_in = static_cast<uInt>(raw.size());
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&z, finish ? Z_FINISH : Z_SYNC_FLUSH), finish ? Z_STREAM_END : Z_OK);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

// A greyscale PNG whose IDAT data are `stream`, cut into `pieces` chunks with a text chunk
// between the first two (a reader must join IDATs across other chunks).
Bytes png_with(const PngLayout& l, const Bytes& stream, int pieces = 1) {
  Bytes png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  chunk(png, "IHDR",
        ihdr(static_cast<uint32_t>(l.width), static_cast<uint32_t>(l.height), l.bit_depth,
             l.interlaced));
  const size_t step = (stream.size() + pieces - 1) / pieces;
  for (size_t at = 0; at < stream.size(); at += step) {
    const size_t end = std::min(stream.size(), at + step);
    chunk(png, "IDAT", Bytes(stream.begin() + at, stream.begin() + end));
    if (at == 0) chunk(png, "tEXt", Bytes{'C', 'o', 'm', 'm', 'e', 'n', 't', 0, 'h', 'i'});
  }
  chunk(png, "IEND", {});
  return png;
}

// Filtered rows of the layout's size: filter byte 0, then a ramp.
Bytes rows_of_size(int64_t n) {
  Bytes raw(static_cast<size_t>(n));
  for (size_t i = 0; i < raw.size(); ++i) raw[i] = static_cast<uint8_t>(i * 7);
  return raw;
}

TEST(PngImageData, FilteredSizeMatchesABruteForceCountOfTheScanlines) {
  // PNG spec §8.2: pass p holds the pixels with x = x0 + k dx, y = y0 + k dy; each of its rows
  // has one filter byte; an empty pass has no rows.
  const std::array<std::array<int, 4>, 7> adam7 = {{{0, 0, 8, 8},
                                                    {4, 0, 8, 8},
                                                    {0, 4, 4, 8},
                                                    {2, 0, 4, 4},
                                                    {0, 2, 2, 4},
                                                    {1, 0, 2, 2},
                                                    {0, 1, 1, 2}}};
  for (int depth : {8, 16}) {
    for (int w = 1; w <= 19; ++w) {
      for (int h = 1; h <= 19; ++h) {
        const int bpp = depth / 8;
        EXPECT_EQ(png_filtered_bytes({w, h, depth, false}), h * (1 + w * bpp));
        int64_t total = 0;
        for (const auto& p : adam7) {
          std::set<int> xs;
          std::set<int> ys;
          for (int x = 0; x < w; ++x) {
            if (x >= p[0] && (x - p[0]) % p[2] == 0) xs.insert(x);
          }
          for (int y = 0; y < h; ++y) {
            if (y >= p[1] && (y - p[1]) % p[3] == 0) ys.insert(y);
          }
          if (!xs.empty()) total += static_cast<int64_t>(ys.size()) * (1 + xs.size() * bpp);
        }
        EXPECT_EQ(png_filtered_bytes({w, h, depth, true}), total) << w << " x " << h;
      }
    }
  }
  EXPECT_EQ(png_filtered_bytes({8, 8, 8, true}), 2 + 2 + 3 + 6 + 10 + 20 + 36);  // by hand
}

TEST(PngImageData, AcceptsACompleteDeflateStreamSplitOverChunks) {
  for (const PngLayout l : {PngLayout{5, 3, 8, false}, PngLayout{9, 7, 16, true},
                            PngLayout{1, 1, 8, true}, PngLayout{300, 40, 16, false}}) {
    const Bytes stream = deflated(rows_of_size(png_filtered_bytes(l)));
    for (int pieces : {1, 3}) {
      EXPECT_EQ(png_image_data_problem(png_with(l, stream, pieces), l), std::nullopt)
          << l.width << " x " << l.height << " in " << pieces;
    }
  }
}

TEST(PngImageData, RefusesAStreamLongerThanTheHeader) {
  const PngLayout l{4, 4, 16, false};
  const auto problem =
      png_image_data_problem(png_with(l, deflated(rows_of_size(png_filtered_bytes(l) + 1))), l);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("more than the header's 36 bytes of rows for 4 x 4 pixels"),
            std::string::npos)
      << *problem;
  // A bomb: a megabyte of zeros deflates to about a kilobyte; refused after the expected size,
  // not after inflating it all.
  const auto bomb = png_image_data_problem(png_with(l, deflated(Bytes(1 << 20, 0))), l);
  ASSERT_TRUE(bomb.has_value());
  EXPECT_NE(bomb->find("more than"), std::string::npos) << *bomb;
}

TEST(PngImageData, RefusesAStreamShorterThanTheHeader) {
  const PngLayout l{6, 5, 8, false};
  const auto problem =
      png_image_data_problem(png_with(l, deflated(rows_of_size(png_filtered_bytes(l) - 1))), l);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("holds 34 bytes where the header promises 35"), std::string::npos)
      << *problem;
}

TEST(PngImageData, RefusesAStreamThatNeverEnds) {
  // Flushed, not finished: every block complete, none marked last. stb_image read zeros past
  // such a stream's end and grew its output without bound (a fuzzer's out-of-memory, CI stop 35).
  const PngLayout l{4, 4, 16, false};
  const auto flushed = png_image_data_problem(
      png_with(l, deflated(rows_of_size(png_filtered_bytes(l) / 2), false)), l);
  ASSERT_TRUE(flushed.has_value());
  EXPECT_NE(flushed->find("image data ends early: the compressed stream stops after 18 of"),
            std::string::npos)
      << *flushed;
  // Cut in the middle of the stream.
  Bytes cut = deflated(rows_of_size(png_filtered_bytes(l)));
  cut.resize(cut.size() / 2);
  const auto truncated = png_image_data_problem(png_with(l, cut), l);
  ASSERT_TRUE(truncated.has_value());
  EXPECT_NE(truncated->find("ends early"), std::string::npos) << *truncated;
}

TEST(PngImageData, RefusesCorruptDataAndChunksPastTheEnd) {
  const PngLayout l{4, 4, 8, false};
  const auto garbage = png_image_data_problem(png_with(l, Bytes{'h', 'e', 'l', 'l', 'o'}), l);
  ASSERT_TRUE(garbage.has_value());
  EXPECT_NE(garbage->find("corrupt compressed image data (zlib: "), std::string::npos) << *garbage;

  Bytes no_data = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  chunk(no_data, "IHDR", ihdr(4, 4, 8, false));
  chunk(no_data, "IEND", {});
  EXPECT_EQ(png_image_data_problem(no_data, l),
            std::optional<std::string>("no image data (no IDAT chunk; truncated or corrupt)"));

  Bytes past_end = png_with(l, deflated(rows_of_size(png_filtered_bytes(l))));
  past_end.resize(past_end.size() - 16);  // into the IDAT chunk: IEND (12) and its CRC (4) gone
  const auto past = png_image_data_problem(past_end, l);
  ASSERT_TRUE(past.has_value());
  EXPECT_NE(past->find("runs past the end of the file"), std::string::npos) << *past;
}

TEST(PngImageData, TheLoaderNamesTheFileOfAStreamThatNeverEnds) {
  const PngLayout l{4, 4, 16, false};
  test::TempDir dir;
  const Bytes png = png_with(l, deflated(rows_of_size(20), false));
  dir.write("endless.png", std::string(png.begin(), png.end()));
  const Result<haptics::HeightImage> r = load_height_image(dir.path() / "endless.png");
  ASSERT_FALSE(r.ok());
  const std::string e = r.message();
  EXPECT_NE(e.find("endless.png"), std::string::npos) << e;
  EXPECT_NE(e.find("image data ends early"), std::string::npos) << e;
  // And a good deflated 16-bit file decodes to its levels (row filter 0, big-endian samples).
  Bytes raw;
  for (int y = 0; y < 4; ++y) {
    raw.push_back(0);
    for (int x = 0; x < 4; ++x) {
      const auto v = static_cast<uint16_t>((y * 4 + x) * 4000);
      raw.push_back(static_cast<uint8_t>(v >> 8));
      raw.push_back(static_cast<uint8_t>(v & 0xFF));
    }
  }
  const Bytes good = png_with(l, deflated(raw), 2);
  dir.write("good.png", std::string(good.begin(), good.end()));
  const haptics::HeightImage image = load_height_image(dir.path() / "good.png").value();
  ASSERT_EQ(image.values.size(), 16U);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(image.values[i], i * 4000 / 65535.0, 1e-6) << i;
}

}  // namespace
}  // namespace lap::sim
