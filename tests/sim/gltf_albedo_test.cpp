// An organ's colour texture (sim/setup/gltf_albedo.h): the glTF's base colour image decoded to
// the pixels that were written; a glTF without one has none; a missing, broken or oversized
// image is refused naming the glTF and the field; the generated patients' organs carry their
// textures and texture coordinates through the scene, and the duct's shell gets its own.

#include "sim/setup/gltf_albedo.h"

#include <gtest/gtest.h>

#include <fstream>

#include "haptics/setup/mesh_generators.h"
#include "sim/setup/gltf_writer.h"
#include "sim/setup/png_writer.h"
#include "sim/setup/scene.h"
#include "sim/setup/session_model.h"
#include "tests/test_support.h"

namespace lap::sim {
namespace {

// A small box with texture coordinates, written as glTF with `image` as its base colour.
std::filesystem::path write_textured(const test::TempDir& dir, const std::string& image) {
  haptics::TriangleMesh m = haptics::make_box(Eigen::Vector3d(0.01, 0.01, 0.01));
  m.compute_vertex_normals();
  m.uvs.assign(m.positions.size(), Eigen::Vector2d(0.25, 0.75));
  GltfMaterial material;
  material.name = "box";
  material.base_color_texture_uri = image;
  const std::filesystem::path file = dir.path() / "box.gltf";
  EXPECT_TRUE(save_gltf(m, file, material).ok());
  return file;
}

// The 1-based line of `file` that holds `text` (0 when none does).
int line_holding(const std::filesystem::path& file, const std::string& text) {
  std::ifstream in(file);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find(text) != std::string::npos) return n;
  }
  return 0;
}

TEST(GltfAlbedo, TheBaseColourImageIsDecodedToThePixelsWritten) {
  test::TempDir dir;
  haptics::RgbImage written;
  written.width = 3;
  written.height = 2;
  // Row 0 (the top): red, green, blue; row 1: grey levels.
  written.rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 10, 10, 128, 128, 128, 250, 250, 250};
  ASSERT_TRUE(save_png(written, dir.path() / "box.png").ok());
  const Result<std::shared_ptr<const haptics::RgbImage>> read =
      load_gltf_albedo(write_textured(dir, "box.png"));
  ASSERT_TRUE(read.ok()) << read.message();
  ASSERT_NE(read.value(), nullptr);
  EXPECT_EQ(read.value()->width, 3);
  EXPECT_EQ(read.value()->height, 2);
  EXPECT_EQ(read.value()->rgb, written.rgb);
}

TEST(GltfAlbedo, NoTextureMeansNoneAndABadOneIsAClearError) {
  test::TempDir dir;
  // No material at all: an OBJ-like glTF.
  const std::filesystem::path plain =
      dir.write("plain.gltf", R"({"asset": {"version": "2.0"}, "meshes": [{"primitives": [{}]}]})");
  const auto none = load_gltf_albedo(plain);
  ASSERT_TRUE(none.ok()) << none.message();
  EXPECT_EQ(none.value(), nullptr);

  const std::filesystem::path missing = write_textured(dir, "gone.png");
  auto r = load_gltf_albedo(missing);
  ASSERT_FALSE(r.ok());
  // Named by the line of the image's uri in the file save_gltf wrote.
  ASSERT_GT(line_holding(missing, "\"gone.png\""), 0);
  EXPECT_EQ(r.message(), missing.string() + ":" +
                             std::to_string(line_holding(missing, "\"gone.png\"")) +
                             ": images[0].uri: gone.png: texture image not found "
                             "(expected a PNG or JPEG)");

  dir.write("box.png", "this is not an image");
  r = load_gltf_albedo(write_textured(dir, "box.png"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("images[0].uri: box.png: not a PNG or JPEG image"), std::string::npos)
      << r.message();

  // Images stb_image would decode but glTF does not allow (a 1 x 1 GIF, a 1 x 1 BMP): refused
  // by their signatures, not decoded.
  const std::string gif(
      "GIF89a\x01\x00\x01\x00\x80\x00\x00\xff\x00\x00\x00\x00\x00"
      ",\x00\x00\x00\x00\x01\x00\x01\x00\x00\x02\x02"
      "D\x01\x00;",  // "D" apart: "\x02D" would be the one byte 0x2D
      35);
  std::string bmp(
      "BM\x3a\x00\x00\x00\x00\x00\x00\x00\x36\x00\x00\x00\x28\x00\x00\x00"
      "\x01\x00\x00\x00\x01\x00\x00\x00\x01\x00\x18\x00\x00\x00\x00\x00"
      "\x04\x00\x00\x00\x13\x0b\x00\x00\x13\x0b\x00\x00\x00\x00\x00\x00"
      "\x00\x00\x00\x00\x00\x00\xff\x00",
      58);
  for (const std::string& other : {gif, bmp}) {
    {
      std::ofstream out(dir.path() / "box.png", std::ios::binary);
      out << other;
    }
    r = load_gltf_albedo(write_textured(dir, "box.png"));
    ASSERT_FALSE(r.ok()) << other.substr(0, 2);
    EXPECT_EQ(r.message(), (dir.path() / "box.gltf").string() + ":" +
                               std::to_string(line_holding(dir.path() / "box.gltf", "box.png")) +
                               ": images[0].uri: box.png: not a PNG or JPEG image (glTF allows "
                               "no other)");
  }

  // A PNG whose header asks for 9000 x 9000 pixels: refused before anything is decoded.
  std::string png = "\x89PNG\r\n\x1a\n";
  png += std::string("\x00\x00\x00\x0dIHDR", 8);
  png += std::string("\x00\x00\x23\x28\x00\x00\x23\x28\x08\x02\x00\x00\x00", 13);
  png += std::string(4, '\0');  // the CRC (not checked by the header's reader)
  {
    std::ofstream out(dir.path() / "box.png", std::ios::binary);
    out << png;
  }
  r = load_gltf_albedo(write_textured(dir, "box.png"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("9000 x 9000 pixels is beyond the limit of 8192 a side"),
            std::string::npos)
      << r.message();

  // A PNG whose compressed rows do not end where its header says (the height-map fuzzer's
  // out-of-memory in stb_image): refused by the same check before stb inflates it.
  std::filesystem::copy_file(
      test::source_dir() / "tests/fuzz/regressions/height_image/oom-endless-zlib-stream.png",
      dir.path() / "box.png", std::filesystem::copy_options::overwrite_existing);
  r = load_gltf_albedo(write_textured(dir, "box.png"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("images[0].uri: box.png: IDAT chunk at byte 86 runs past the end"),
            std::string::npos)
      << r.message();
}

// The patients' organs are glTF with textures: each loads with its image and one texture
// coordinate per vertex; the duct's shell (which the session draws instead of the file's mesh)
// gets coordinates of its own, u round the duct in [0, 1] without a seam, v along it.
TEST(GltfAlbedo, ThePatientsOrgansCarryTheirTexturesToTheSession) {
  const SceneLoadResult scene = load_scene_file(test::source_dir() / "scenarios/patient_easy.yaml");
  ASSERT_TRUE(scene.ok()) << scene.message();
  for (const Organ& o : scene.value().organs) {
    ASSERT_NE(o.albedo, nullptr) << o.name;
    EXPECT_GT(o.albedo->width, 16) << o.name;
    EXPECT_EQ(o.albedo->rgb.size(), static_cast<size_t>(o.albedo->width) * o.albedo->height * 3);
    EXPECT_EQ(o.mesh.uvs.size(), o.mesh.positions.size()) << o.name;
  }
  const auto model = SessionModel::build(scene.value(), RuntimeSettings{}, {});
  ASSERT_TRUE(model.ok()) << model.message();
  const TissueModel& tissue = model.value()->tissue();
  const int32_t duct = tissue.duct_organ();
  ASSERT_GE(duct, 0);
  const haptics::TriangleMesh& shell = tissue.surface(duct);
  ASSERT_EQ(shell.uvs.size(), shell.positions.size());
  double v_min = 1e9;
  double v_max = -1e9;
  for (const Eigen::Vector2d& uv : shell.uvs) {
    EXPECT_GE(uv.x(), 0.0);
    EXPECT_LE(uv.x(), 1.0);
    v_min = std::min(v_min, uv.y());
    v_max = std::max(v_max, uv.y());
  }
  // v runs the duct's length in half-circumferences (3.8 cm over pi x ~2 mm: about 6).
  EXPECT_GT(v_max - v_min, 3.0);
  // Neighbours round the duct differ by less than a face's share of u: no seam.
  for (const haptics::Triangle& t : shell.triangles) {
    for (int k = 0; k < 3; ++k) {
      const double du = std::abs(shell.uvs[static_cast<size_t>(t[k])].x() -
                                 shell.uvs[static_cast<size_t>(t[(k + 1) % 3])].x());
      EXPECT_LT(du, 0.25);
    }
  }
}

}  // namespace
}  // namespace lap::sim
