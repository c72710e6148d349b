// The PNG image-data check (sim/setup/png_image_data.h): the size it expects matches a count of
// every pixel's Adam7 pass from the spec's figure, real deflate streams split over chunks pass
// (padding too), and every way a stream can disagree with its header (far too long, never ending,
// without its checksum, corrupt, past the file's end, Apple's CgBI) is refused with a reason,
// before stb_image's decoder sees it; what passes, stb decodes to the levels written.

#include "sim/setup/png_image_data.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <array>
#include <set>
#include <string>
#include <utility>
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

Bytes ihdr(const PngLayout& l, int colour_type, int compression = 0) {
  Bytes d;
  put32(d, static_cast<uint32_t>(l.width));
  put32(d, static_cast<uint32_t>(l.height));
  d.insert(d.end(), {static_cast<uint8_t>(l.bit_depth), static_cast<uint8_t>(colour_type),
                     static_cast<uint8_t>(compression), 0, static_cast<uint8_t>(l.interlaced)});
  return d;
}

// zlib's own deflate (not stored blocks), finished or only flushed (a stream that does not end),
// optionally with a preset dictionary (which PNG forbids).
Bytes deflated(const Bytes& raw, bool finish = true, bool dictionary = false) {
  z_stream z{};
  EXPECT_EQ(deflateInit(&z, 9), Z_OK);
  if (dictionary) {
    const Bytes dict(64, 7);
    EXPECT_EQ(deflateSetDictionary(&z, dict.data(), static_cast<uInt>(dict.size())), Z_OK);
  }
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

// A PNG whose IDAT data are `stream`, cut into `pieces` chunks with a text chunk and an empty
// IDAT between the first two (a reader must join IDATs across other chunks), and `extra` chunks
// after the header.
Bytes png_with(const PngLayout& l, const Bytes& stream, int pieces = 1, int colour_type = 0,
               const std::string& extra = "") {
  Bytes png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  chunk(png, "IHDR", ihdr(l, colour_type));
  if (!extra.empty()) chunk(png, extra, Bytes(4, 0));
  const size_t step = (stream.size() + pieces - 1) / pieces;
  for (size_t at = 0; at < stream.size(); at += step) {
    const size_t end = std::min(stream.size(), at + step);
    chunk(png, "IDAT", Bytes(stream.begin() + at, stream.begin() + end));
    if (at == 0) {
      chunk(png, "tEXt", Bytes{'C', 'o', 'm', 'm', 'e', 'n', 't', 0, 'h', 'i'});
      chunk(png, "IDAT", {});
    }
  }
  chunk(png, "IEND", {});
  return png;
}

// Filtered rows of the layout's size: a ramp of bytes (every fifth a valid filter type would not
// matter here: only the sizes are checked).
Bytes rows_of_size(int64_t n) {
  Bytes raw(static_cast<size_t>(n));
  for (size_t i = 0; i < raw.size(); ++i) raw[i] = static_cast<uint8_t>(i * 7);
  return raw;
}

// PNG spec §8.2's figure: the pass of each pixel of an 8 x 8 tile.
constexpr std::array<std::array<int, 8>, 8> kPassOfPixel = {{{1, 6, 4, 6, 2, 6, 4, 6},
                                                             {7, 7, 7, 7, 7, 7, 7, 7},
                                                             {5, 6, 5, 6, 5, 6, 5, 6},
                                                             {7, 7, 7, 7, 7, 7, 7, 7},
                                                             {3, 6, 4, 6, 3, 6, 4, 6},
                                                             {7, 7, 7, 7, 7, 7, 7, 7},
                                                             {5, 6, 5, 6, 5, 6, 5, 6},
                                                             {7, 7, 7, 7, 7, 7, 7, 7}}};

TEST(PngImageData, FilteredSizeMatchesACountOfEveryPixelsPass) {
  // Each pass is a sub-image of the columns and rows its pixels occupy; each of its rows has one
  // filter byte and ceil(columns * bits / 8) bytes; an empty pass has no rows.
  for (const auto& [channels, depth] : std::vector<std::pair<int, int>>{
           {1, 1}, {1, 2}, {1, 4}, {1, 8}, {1, 16}, {3, 8}, {2, 16}, {4, 16}}) {
    const int bits = channels * depth;
    for (int w = 1; w <= 19; ++w) {
      for (int h = 1; h <= 19; ++h) {
        EXPECT_EQ(png_filtered_bytes({w, h, channels, depth, false}), h * (1 + (w * bits + 7) / 8));
        int64_t total = 0;
        for (int pass = 1; pass <= 7; ++pass) {
          std::set<int> xs;
          std::set<int> ys;
          for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
              if (kPassOfPixel[y % 8][x % 8] == pass) {
                xs.insert(x);
                ys.insert(y);
              }
            }
          }
          if (!xs.empty()) {
            total += static_cast<int64_t>(ys.size()) *
                     (1 + (static_cast<int64_t>(xs.size()) * bits + 7) / 8);
          }
        }
        EXPECT_EQ(png_filtered_bytes({w, h, channels, depth, true}), total)
            << w << " x " << h << ", " << bits << " bits";
      }
    }
  }
  // By hand, pass by pass (8-bit grey): 8 x 8: 2 + 2 + 3 + 6 + 10 + 20 + 36; 5 x 3: 2 + 2 + 0 +
  // 2 + 4 + 6 + 6; 3 x 5: 2 + 0 + 2 + 4 + 3 + 6 + 8.
  EXPECT_EQ(png_filtered_bytes({8, 8, 1, 8, true}), 79);
  EXPECT_EQ(png_filtered_bytes({5, 3, 1, 8, true}), 22);
  EXPECT_EQ(png_filtered_bytes({3, 5, 1, 8, true}), 25);
  EXPECT_EQ(png_filtered_bytes({10, 3, 1, 1, false}), 9);  // 10 one-bit pixels: 2 bytes a row
}

TEST(PngImageData, ReadsTheHeaderAndRefusesWhatPngDoesNotDefine) {
  const PngLayout l{7, 5, 3, 16, true};
  Bytes png = png_with(l, deflated(rows_of_size(png_filtered_bytes(l))), 1, 2);
  const PngHeader h = read_png_header(png);
  ASSERT_TRUE(h.layout.has_value()) << h.problem;
  EXPECT_EQ(h.layout->width, 7);
  EXPECT_EQ(h.layout->height, 5);
  EXPECT_EQ(h.layout->channels, 3);
  EXPECT_EQ(h.layout->bit_depth, 16);
  EXPECT_TRUE(h.layout->interlaced);
  EXPECT_EQ(png_image_data_problem(png), std::nullopt);

  Bytes rgb4 = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  chunk(rgb4, "IHDR", ihdr({4, 4, 3, 4, false}, 2));
  EXPECT_EQ(png_image_data_problem(rgb4),
            "corrupt PNG header: colour type 2 with bit depth 4 is not a combination PNG defines");
  Bytes method = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  chunk(method, "IHDR", ihdr({4, 4, 1, 8, false}, 0, 1));
  EXPECT_EQ(png_image_data_problem(method),
            "corrupt PNG header: compression 1, filter 0, interlace 0 (expected 0, 0 and 0 or 1)");
  EXPECT_EQ(png_image_data_problem(Bytes(png.begin(), png.begin() + 20)),
            "PNG without an IHDR chunk (truncated or corrupt)");
}

TEST(PngImageData, AcceptsACompleteDeflateStreamSplitOverChunks) {
  for (const PngLayout l : {PngLayout{5, 3, 1, 8, false}, PngLayout{9, 7, 1, 16, true},
                            PngLayout{1, 1, 1, 8, true}, PngLayout{300, 40, 1, 16, false}}) {
    const Bytes stream = deflated(rows_of_size(png_filtered_bytes(l)));
    for (int pieces : {1, 3}) {
      EXPECT_EQ(png_image_data_problem(png_with(l, stream, pieces)), std::nullopt)
          << l.width << " x " << l.height << " in " << pieces;
    }
  }
}

TEST(PngImageData, ToleratesPaddingButRefusesAStreamFarLongerThanTheHeader) {
  const PngLayout l{4, 4, 1, 16, false};
  const int64_t rows = png_filtered_bytes(l);
  EXPECT_EQ(png_image_data_problem(png_with(l, deflated(rows_of_size(rows + 10)))), std::nullopt);
  const auto problem = png_image_data_problem(
      png_with(l, deflated(rows_of_size(rows + static_cast<int64_t>(kPngSlackBytes) + 1))));
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("more than the header's 36 bytes of rows for 4 x 4 pixels"),
            std::string::npos)
      << *problem;
  // A bomb: 16 MiB of zeros deflate to about 16 KiB; refused after the allowance, not after
  // inflating it all.
  const auto bomb = png_image_data_problem(png_with(l, deflated(Bytes(16U << 20U, 0))));
  ASSERT_TRUE(bomb.has_value());
  EXPECT_NE(bomb->find("more than"), std::string::npos) << *bomb;
}

TEST(PngImageData, RefusesAStreamShorterThanTheHeader) {
  const PngLayout l{6, 5, 1, 8, false};
  const auto problem =
      png_image_data_problem(png_with(l, deflated(rows_of_size(png_filtered_bytes(l) - 1))));
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("stops after 34 of the header's 35 bytes of rows for 6 x 5 pixels"),
            std::string::npos)
      << *problem;
}

TEST(PngImageData, RefusesAStreamThatNeverEnds) {
  // Flushed, not finished: every block complete, none marked last. stb_image read zeros past
  // such a stream's end and grew its output without bound (the CI's out-of-memory, stop 34).
  const PngLayout l{4, 4, 1, 16, false};
  const auto half =
      png_image_data_problem(png_with(l, deflated(rows_of_size(18), /*finish=*/false)));
  ASSERT_TRUE(half.has_value());
  EXPECT_NE(half->find("image data ends early: the compressed stream stops after 18 of"),
            std::string::npos)
      << *half;
  const auto whole =
      png_image_data_problem(png_with(l, deflated(rows_of_size(36), /*finish=*/false)));
  EXPECT_EQ(whole,
            "the compressed image data has all the header's 36 bytes of rows for 4 x 4 "
            "pixels but no end (its last block or its checksum is missing; truncated or "
            "corrupt)");
  // Finished, but without its Adler-32 checksum.
  Bytes no_checksum = deflated(rows_of_size(36));
  no_checksum.resize(no_checksum.size() - 4);
  EXPECT_EQ(png_image_data_problem(png_with(l, no_checksum)), whole);
  // Cut in the middle of the stream.
  Bytes cut = deflated(rows_of_size(png_filtered_bytes(l)));
  cut.resize(cut.size() / 2);
  const auto truncated = png_image_data_problem(png_with(l, cut));
  ASSERT_TRUE(truncated.has_value());
  EXPECT_NE(truncated->find("ends early"), std::string::npos) << *truncated;
  // The CI's own input, as the fuzzer wrote it: its first IDAT's stream does not end within the
  // allowance, and the chunk typed IDAT at byte 86 claims 1,375,731,753 bytes of a 104-byte file.
  const std::string ci = test::read_file(
      test::source_dir() / "tests/fuzz/regressions/height_image/oom-endless-zlib-stream.png");
  ASSERT_FALSE(ci.empty());
  EXPECT_EQ(png_image_data_problem(Bytes(ci.begin(), ci.end())),
            "IDAT chunk at byte 86 runs past the end of the file (truncated or corrupt)");
}

TEST(PngImageData, RefusesCorruptDataAndChunksPastTheEnd) {
  const PngLayout l{4, 4, 1, 8, false};
  const auto garbage = png_image_data_problem(png_with(l, Bytes{'h', 'e', 'l', 'l', 'o'}));
  ASSERT_TRUE(garbage.has_value());
  EXPECT_NE(garbage->find("corrupt compressed image data (zlib: "), std::string::npos) << *garbage;
  Bytes bad_checksum = deflated(rows_of_size(png_filtered_bytes(l)));
  bad_checksum.back() ^= 0x55U;
  EXPECT_EQ(png_image_data_problem(png_with(l, bad_checksum)),
            "corrupt compressed image data (zlib: incorrect data check)");
  EXPECT_EQ(
      png_image_data_problem(png_with(l, deflated(rows_of_size(20), true, /*dictionary=*/true))),
      "corrupt compressed image data (zlib: a preset dictionary, which PNG does not allow)");

  Bytes no_data = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  chunk(no_data, "IHDR", ihdr(l, 0));
  chunk(no_data, "IEND", {});
  EXPECT_EQ(png_image_data_problem(no_data),
            std::optional<std::string>("no image data (no IDAT chunk; truncated or corrupt)"));

  Bytes past_end = png_with(l, deflated(rows_of_size(png_filtered_bytes(l))));
  past_end.resize(33 + 8 + 3);  // the signature and IHDR (33 bytes), then 3 of IDAT's data
  EXPECT_EQ(png_image_data_problem(past_end),
            "IDAT chunk at byte 33 runs past the end of the file (truncated or corrupt)");
}

TEST(PngImageData, RefusesApplesCgBIVariantByName) {
  // stb_image reads a CgBI file's IDAT data as raw deflate, zlib as a zlib stream: the same bytes
  // can be two streams, one of which never ends (the reviewer's bypass of the first check).
  const PngLayout l{4, 4, 1, 8, false};
  const Bytes stream = deflated(rows_of_size(png_filtered_bytes(l)));
  EXPECT_EQ(png_image_data_problem(png_with(l, stream, 1, 0, "CgBI")),
            "an Apple CgBI chunk: this is Apple's iOS-optimised variant, not a standard PNG "
            "(re-save it as a standard PNG)");
}

// Adam7 rows of a 16-bit grey image (filter type 0), built from the spec's figure.
Bytes adam7_rows(int w, int h, const std::vector<uint16_t>& v) {
  Bytes raw;
  for (int pass = 1; pass <= 7; ++pass) {
    for (int y = 0; y < h; ++y) {
      Bytes row;
      for (int x = 0; x < w; ++x) {
        if (kPassOfPixel[y % 8][x % 8] != pass) continue;
        const uint16_t s = v[static_cast<size_t>(y * w + x)];
        row.push_back(static_cast<uint8_t>(s >> 8U));
        row.push_back(static_cast<uint8_t>(s & 0xFFU));
      }
      if (row.empty()) continue;
      raw.push_back(0);
      raw.insert(raw.end(), row.begin(), row.end());
    }
  }
  return raw;
}

TEST(PngImageData, TheLoaderDecodesWhatPassesAndNamesTheFileOfWhatDoesNot) {
  test::TempDir dir;
  const PngLayout l{4, 4, 1, 16, false};
  const Bytes endless = png_with(l, deflated(rows_of_size(20), false));
  dir.write("endless.png", std::string(endless.begin(), endless.end()));
  Result<haptics::HeightImage> r = load_height_image(dir.path() / "endless.png");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("endless.png: image data ends early"), std::string::npos)
      << r.message();
  // Interlaced, 16-bit, with padding after the rows: decoded by stb_image to its levels, which
  // also shows that stb agrees with the size counted here.
  const int w = 11;
  const int h = 9;
  std::vector<uint16_t> v(static_cast<size_t>(w * h));
  for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<uint16_t>(i * 601);
  Bytes raw = adam7_rows(w, h, v);
  ASSERT_EQ(static_cast<int64_t>(raw.size()), png_filtered_bytes({w, h, 1, 16, true}));
  raw.insert(raw.end(), 5, 0);
  const Bytes good = png_with({w, h, 1, 16, true}, deflated(raw), 2);
  dir.write("good.png", std::string(good.begin(), good.end()));
  r = load_height_image(dir.path() / "good.png");
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r.value().values.size(), v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    EXPECT_NEAR(r.value().values[i], v[i] / 65535.0, 1e-6) << i;
  }
  // The header's methods are checked before any data.
  Bytes method = good;
  method[8 + 8 + 10] = 1;  // IHDR's compression byte
  dir.write("method.png", std::string(method.begin(), method.end()));
  r = load_height_image(dir.path() / "method.png");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("method.png: corrupt PNG header: compression 1"), std::string::npos)
      << r.message();
}

}  // namespace
}  // namespace lap::sim
