// glTF 2.0 input: all triangle primitives of all meshes reached from the scene's nodes, with the
// node transforms (matrix and TRS, nested) applied; positions, normals and texture coordinates.

#include <gtest/gtest.h>

#include <cstring>

#include "haptics/setup/mesh_validation.h"
#include "sim/setup/gltf_references.h"
#include "sim/setup/json_lines.h"
#include "sim/setup/mesh_limits.h"
#include "sim/setup/mesh_loader.h"
#include "tests/test_support.h"

namespace lap::sim {
namespace {

using haptics::TriangleMesh;

std::string base64(const std::string& in) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t n = (uint8_t(in[i]) << 16U) | (uint8_t(in[i + 1]) << 8U) | uint8_t(in[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(n >> s) & 63U];
  }
  if (i + 1 == in.size()) {
    const uint32_t n = uint8_t(in[i]) << 16U;
    out += kAlphabet[(n >> 18U) & 63U];
    out += kAlphabet[(n >> 12U) & 63U];
    out += "==";
  } else if (i + 2 == in.size()) {
    const uint32_t n = (uint8_t(in[i]) << 16U) | (uint8_t(in[i + 1]) << 8U);
    out += kAlphabet[(n >> 18U) & 63U];
    out += kAlphabet[(n >> 12U) & 63U];
    out += kAlphabet[(n >> 6U) & 63U];
    out += '=';
  }
  return out;
}

template <typename T>
void put(std::string& buf, T v) {
  buf.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// Tetrahedron vertices, its outward triangles, and a lone extra triangle.
const float kTetra[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const uint16_t kTetraIdx[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

// Binary buffer layout (offsets in bytes):
//   0   positions of mesh 0 primitive 0     4 x vec3 float   48 bytes
//   48  normals (all +z, to see rotation)   4 x vec3 float   48
//   96  texcoords                           4 x vec2 float   32
//   128 indices uint16                      12 x 2           24
//   152 positions of primitive 1 (no idx)   3 x vec3 float   36
//   188 interleaved pos+normal of mesh 1    4 x 24 bytes     96   (byteStride 24)
//   284 indices uint32                      12 x 4           48
//   332 end
std::string make_buffer() {
  std::string b;
  for (auto& p : kTetra)
    for (float c : p) put(b, c);
  for (int i = 0; i < 4; ++i) {
    put(b, 0.0f);
    put(b, 0.0f);
    put(b, 1.0f);
  }
  const float uv[4][2] = {{0, 0}, {1, 0}, {0, 1}, {0.25f, 0.75f}};
  for (auto& t : uv)
    for (float c : t) put(b, c);
  for (uint16_t i : kTetraIdx) put(b, i);
  const float lone[3][3] = {{5, 5, 5}, {6, 5, 5}, {5, 6, 5}};
  for (auto& p : lone)
    for (float c : p) put(b, c);
  for (auto& p : kTetra) {
    for (float c : p) put(b, c);
    put(b, 0.0f);
    put(b, 1.0f);
    put(b, 0.0f);
  }
  for (uint16_t i : kTetraIdx) put(b, static_cast<uint32_t>(i));
  return b;
}

std::string make_json(const std::string& buffer_entry) {
  return R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 2, 3]}],
  "nodes": [
    {"matrix": [2,0,0,0, 0,2,0,0, 0,0,2,0, 10,0,0,1], "children": [1]},
    {"translation": [0, 1, 0], "rotation": [0, 0, 0.7071067811865476, 0.7071067811865476], "mesh": 0},
    {"mesh": 1, "translation": [0, 0, -5]},
    {"mesh": 1, "scale": [-1, 1, 1], "translation": [-20, 0, 0]},
    {"mesh": 0, "translation": [100, 100, 100]}
  ],
  "meshes": [
    {"primitives": [
      {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "mode": 4},
      {"attributes": {"POSITION": 4}}
    ]},
    {"primitives": [{"attributes": {"POSITION": 5, "NORMAL": 6}, "indices": 7}]}
  ],
  "buffers": [)" +
         buffer_entry + R"(],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 48},
    {"buffer": 0, "byteOffset": 48, "byteLength": 48},
    {"buffer": 0, "byteOffset": 96, "byteLength": 32},
    {"buffer": 0, "byteOffset": 128, "byteLength": 24},
    {"buffer": 0, "byteOffset": 152, "byteLength": 36},
    {"buffer": 0, "byteOffset": 188, "byteLength": 96, "byteStride": 24},
    {"buffer": 0, "byteOffset": 284, "byteLength": 48}
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0,0,0], "max": [1,1,1]},
    {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
    {"bufferView": 3, "componentType": 5123, "count": 12, "type": "SCALAR"},
    {"bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC3", "min": [5,5,5], "max": [6,6,5]},
    {"bufferView": 5, "byteOffset": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0,0,0], "max": [1,1,1]},
    {"bufferView": 5, "byteOffset": 12, "componentType": 5126, "count": 4, "type": "VEC3"},
    {"bufferView": 6, "componentType": 5125, "count": 12, "type": "SCALAR"}
  ]
})";
}

// The buffer entry of a .gltf whose binary data is embedded as a base64 data URI.
std::string embedded_entry(const std::string& buffer) {
  return R"({"byteLength": )" + std::to_string(buffer.size()) +
         R"(, "uri": "data:application/octet-stream;base64,)" + base64(buffer) + "\"}";
}

// What the scene must contain, computed here with Eigen from the node definitions above.
std::vector<Eigen::Vector3d> expected_positions() {
  Eigen::Affine3d parent = Eigen::Affine3d::Identity();
  parent.translate(Eigen::Vector3d(10, 0, 0)).scale(2.0);
  Eigen::Affine3d child = Eigen::Affine3d::Identity();
  child.translate(Eigen::Vector3d(0, 1, 0))
      .rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const Eigen::Affine3d node1 = parent * child;
  Eigen::Affine3d node2 = Eigen::Affine3d::Identity();
  node2.translate(Eigen::Vector3d(0, 0, -5));
  Eigen::Affine3d node3 = Eigen::Affine3d::Identity();
  node3.translate(Eigen::Vector3d(-20, 0, 0)).scale(Eigen::Vector3d(-1, 1, 1));
  std::vector<Eigen::Vector3d> out;
  for (auto& p : kTetra) out.push_back(node1 * Eigen::Vector3d(p[0], p[1], p[2]));
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(6, 5, 5), Eigen::Vector3d(5, 6, 5)}) {
    out.push_back(node1 * p);
  }
  for (auto& p : kTetra) out.push_back(node2 * Eigen::Vector3d(p[0], p[1], p[2]));
  for (auto& p : kTetra) out.push_back(node3 * Eigen::Vector3d(p[0], p[1], p[2]));
  return out;
}

void check_scene(const TriangleMesh& m) {
  // 4 + 1 triangles from mesh 0 (node 1), 4 + 4 from mesh 1 (nodes 2 and 3); node 4 is not in
  // the scene and must not appear.
  EXPECT_EQ(m.triangle_count(), 13);
  const auto expected = expected_positions();
  ASSERT_EQ(m.vertex_count(), static_cast<int32_t>(expected.size()));
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_LT((m.positions[i] - expected[i]).norm(), 1e-6) << "vertex " << i;
  }
  // Volumes: the tetrahedron scaled by 2 (8/6), plus two unit ones; the mirrored node's winding
  // is flipped so it stays outward. The lone triangle adds an open part.
  TriangleMesh closed = m;
  closed.triangles.erase(closed.triangles.begin() + 4);
  EXPECT_NEAR(closed.signed_volume(), 8.0 / 6.0 + 2.0 / 6.0, 1e-9);
  // Normals: +z rotated 90 degrees about z stays +z for mesh 0; mesh 1 normals are +y.
  ASSERT_EQ(m.normals.size(), m.positions.size());
  EXPECT_TRUE(m.normals[0].isApprox(Eigen::Vector3d(0, 0, 1), 1e-6));
  EXPECT_TRUE(m.normals[7].isApprox(Eigen::Vector3d(0, 1, 0), 1e-6));
}

TEST(GltfLoader, EmbeddedBufferNestedTransformsAndSeveralPrimitives) {
  test::TempDir dir;
  const std::string buffer = make_buffer();
  const std::string entry = embedded_entry(buffer);
  check_scene(load_mesh(dir.write("scene.gltf", make_json(entry))).value());
}

TEST(GltfLoader, ExternalBinFile) {
  test::TempDir dir;
  const std::string buffer = make_buffer();
  dir.write("scene.bin", buffer);
  const std::string entry =
      R"({"byteLength": )" + std::to_string(buffer.size()) + R"(, "uri": "scene.bin"})";
  check_scene(load_mesh(dir.write("scene.gltf", make_json(entry))).value());
}

TEST(GltfLoader, BinaryGlb) {
  test::TempDir dir;
  std::string bin = make_buffer();
  while (bin.size() % 4 != 0) bin.push_back('\0');
  std::string json = make_json(R"({"byteLength": )" + std::to_string(bin.size()) + "}");
  while (json.size() % 4 != 0) json.push_back(' ');
  std::string glb;
  put(glb, uint32_t{0x46546C67});  // "glTF"
  put(glb, uint32_t{2});
  put(glb, static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  put(glb, static_cast<uint32_t>(json.size()));
  put(glb, uint32_t{0x4E4F534A});  // JSON
  glb += json;
  put(glb, static_cast<uint32_t>(bin.size()));
  put(glb, uint32_t{0x004E4942});  // BIN
  glb += bin;
  check_scene(load_mesh(dir.write("scene.glb", glb)).value());
}

TEST(GltfLoader, TextureCoordinatesSurvive) {
  test::TempDir dir;
  const std::string buffer = make_buffer();
  const std::string entry = embedded_entry(buffer);
  std::string json = make_json(entry);
  // Keep only node 1's mesh so every vertex has texture coordinates.
  json.replace(json.find(R"("nodes": [0, 2, 3])"), 18, R"("nodes": [0])");
  json.replace(json.find(R"({"attributes": {"POSITION": 4}})"), 31, "");
  json.replace(json.find(R"("mode": 4},)"), 11, R"("mode": 4})");
  const TriangleMesh m = load_mesh(dir.write("uv.gltf", json)).value();
  ASSERT_EQ(m.uvs.size(), 4U);
  EXPECT_TRUE(m.uvs[3].isApprox(Eigen::Vector2d(0.25, 0.75)));
  EXPECT_TRUE(haptics::validate_mesh(m).clean());
}

TEST(GltfLoaderErrors, InvalidJson) {
  test::TempDir dir;
  const auto f = dir.write("bad.gltf", "{ this is not json");
  const Result<TriangleMesh> r = load_mesh(f);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message().rfind(f.string() + ": not a valid glTF 2.0 file: ", 0), 0U) << r.message();
}

TEST(GltfLoaderErrors, IndexOutsideVertices) {
  test::TempDir dir;
  std::string buffer = make_buffer();
  const uint16_t bad = 9;
  std::memcpy(buffer.data() + 128, &bad, 2);
  const std::string entry = embedded_entry(buffer);
  const auto f = dir.write("bad.gltf", make_json(entry));
  const Result<TriangleMesh> r = load_mesh(f);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), f.string() + ": mesh 0 primitive 0: index 9 is outside the 4 vertices");
}

TEST(GltfLoaderErrors, NodeNamesMissingMesh) {
  test::TempDir dir;
  const std::string buffer = make_buffer();
  const std::string entry = embedded_entry(buffer);
  std::string json = make_json(entry);
  json.replace(json.find(R"("mesh": 1, "translation": [0, 0, -5])"), 9, R"("mesh": 7)");
  const auto f = dir.write("bad.gltf", json);
  EXPECT_FALSE(load_mesh(f).ok());
}

// Issue 25: files a glTF reaches stay in its folder. Each case below loaded (and read the file
// outside) before the check: the buffer is a valid one, so only confinement can refuse it.
TEST(GltfLoaderConfinement, BufferUriLeavingTheFolderIsRefusedWithoutReadingIt) {
  test::TempDir dir;
  const std::string buffer = make_buffer();
  dir.write("secret.bin", buffer);
  const std::string entry =
      R"({"byteLength": )" + std::to_string(buffer.size()) + R"(, "uri": "../secret.bin"})";
  const auto f = dir.write("scene/scene.gltf", make_json(entry));
  const Result<TriangleMesh> r = load_mesh(f);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(),
            f.string() + ":19: buffers[0].uri: '../secret.bin' leaves the scene's folder");
}

TEST(GltfLoaderConfinement, PercentEncodedDotsAndAbsolutePathsAreRefused) {
  test::TempDir dir;
  const std::string buffer = make_buffer();
  const auto secret = dir.write("secret.bin", buffer);
  for (const std::string& uri :
       {std::string("%2e%2e/secret.bin"), secret.string(), std::string("sub/../../secret.bin"),
        std::string("..\\\\secret.bin")}) {
    const std::string entry =
        R"({"byteLength": )" + std::to_string(buffer.size()) + R"(, "uri": ")" + uri + "\"}";
    const Result<TriangleMesh> r = load_mesh(dir.write("scene/scene.gltf", make_json(entry)));
    ASSERT_FALSE(r.ok()) << uri;
    EXPECT_NE(r.message().find("buffers[0].uri: '"), std::string::npos) << r.message();
  }
}

TEST(GltfLoaderConfinement, ASymbolicLinkOutOfTheFolderIsNotFollowed) {
  test::TempDir dir;
  const std::string buffer = make_buffer();
  const auto secret = dir.write("secret.bin", buffer);
  std::filesystem::create_directories(dir.path() / "scene");
  std::filesystem::create_symlink(secret, dir.path() / "scene" / "link.bin");
  const std::string entry =
      R"({"byteLength": )" + std::to_string(buffer.size()) + R"(, "uri": "link.bin"})";
  const Result<TriangleMesh> r = load_mesh(dir.write("scene/scene.gltf", make_json(entry)));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("outside the scene's folder"), std::string::npos) << r.message();
}

TEST(GltfLoaderConfinement, AFileInASubfolderIsFine) {
  test::TempDir dir;
  const std::string buffer = make_buffer();
  dir.write("scene/data/scene.bin", buffer);
  const std::string entry =
      R"({"byteLength": )" + std::to_string(buffer.size()) + R"(, "uri": "data/scene.bin"})";
  check_scene(load_mesh(dir.write("scene/scene.gltf", make_json(entry))).value());
}

TEST(GltfLoaderConfinement, ImageUriLeavingTheFolderIsRefused) {
  test::TempDir dir;
  std::string json = make_json(embedded_entry(make_buffer()));
  json.insert(json.rfind('}'), R"(, "images": [{"uri": "../../../../etc/passwd"}])");
  const auto f = dir.write("scene.gltf", json);
  const Result<TriangleMesh> r = load_mesh(f);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(),
            f.string() + ":39: images[0].uri: '../../../../etc/passwd' leaves the scene's folder");
}

TEST(GltfLoaderLimits, ADataUriLongerThanTheLimitIsRefused) {
  std::string uri = "data:application/octet-stream;base64,";
  uri.resize(kMaxGltfDataUriChars + 1, 'A');
  const std::string json = R"({"buffers": [{"byteLength": 4, "uri": ")" + uri + "\"}]}";
  const Status s = check_gltf_references("scene.gltf", json);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(
      s.message(),
      "scene.gltf:1: buffers[0].uri: data URI of 67108865 characters is longer than the limit "
      "of 67108864 (sim/setup/mesh_limits.h); put the data in a .bin file beside the glTF");
  uri.resize(kMaxGltfDataUriChars);
  EXPECT_TRUE(check_gltf_references("scene.gltf",
                                    R"({"buffers": [{"byteLength": 4, "uri": ")" + uri + "\"}]}")
                  .ok());
}

// A text .gltf's problems name the line of the field (sim/setup/json_lines.h): the key's line
// for a member, the element's first byte for an array's element, and where a text stops being
// JSON.
TEST(JsonLines, NameTheLineOfEachShallowFieldAndOfAParseError) {
  const std::string text =
      "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"buffers\": [\n    {\"byteLength\": 4,\n"
      "     \"uri\": \"a.bin\"},\n    {\"uri\":\n \"b.bin\"}\n  ],\n  \"scene\": 0\n}\n";
  const JsonLines lines = JsonLines::scan(text);
  EXPECT_TRUE(lines.parsed());
  EXPECT_EQ(lines.line("asset"), 2);
  EXPECT_EQ(lines.line("asset.version"), 2);
  EXPECT_EQ(lines.line("buffers"), 3);
  EXPECT_EQ(lines.line("buffers[0]"), 4);
  EXPECT_EQ(lines.line("buffers[0].byteLength"), 4);
  EXPECT_EQ(lines.line("buffers[0].uri"), 5);
  EXPECT_EQ(lines.line("buffers[1].uri"), 6);
  EXPECT_EQ(lines.line("scene"), 9);
  EXPECT_EQ(lines.line("nodes", -1), -1);
  // Deeper than the levels recorded: not kept.
  EXPECT_EQ(JsonLines::scan(text, 2).line("buffers[0].uri"), 0);
  const JsonLines broken = JsonLines::scan("{\n  \"a\": 1,\n  \"b\": tru\n}\n");
  EXPECT_FALSE(broken.parsed());
  EXPECT_EQ(broken.error_line(), 3);
  EXPECT_NE(broken.error().find("invalid literal"), std::string::npos) << broken.error();
  EXPECT_EQ(broken.line("a"), 2);
  // A document of a million entries keeps no more than it is asked to.
  std::string big = "{\"x\": [";
  for (int i = 0; i < 1000000; ++i) big += i == 0 ? "0" : ",0";
  big += "]}";
  const JsonLines many = JsonLines::scan(big, 3, 100);
  EXPECT_EQ(many.line("x[98]"), 1);
  EXPECT_EQ(many.line("x[99]"), 0);
}

TEST(GltfLoaderConfinement, InsideFolderResolvesDotsAndLinks) {
  test::TempDir dir;
  const auto inner = dir.write("scene/a.bin", "x");
  const auto outer = dir.write("b.bin", "x");
  const auto folder = dir.path() / "scene";
  EXPECT_TRUE(inside_folder(folder, inner));
  EXPECT_TRUE(inside_folder(folder, folder / "sub" / ".." / "a.bin"));
  EXPECT_FALSE(inside_folder(folder, outer));
  EXPECT_FALSE(inside_folder(folder, folder / ".." / "b.bin"));
  EXPECT_FALSE(inside_folder(folder, dir.path() / "scene-other" / "a.bin"));  // not a prefix
}

TEST(GltfLoaderLimits, AHugeBufferLengthIsRefusedBeforeReading) {
  test::TempDir dir;
  const auto f =
      dir.write("scene.gltf", make_json(R"({"byteLength": 1000000000000, "uri": "scene.bin"})"));
  const Result<TriangleMesh> r = load_mesh(f);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), f.string() +
                             ":19: buffers[0].byteLength: 1000000000000 bytes is more than the "
                             "limit of 536870912 (sim/setup/mesh_limits.h)");
}

TEST(GltfLoaderLimits, AnAccessorCountThatWouldWrapTheBoundsCheckIsRefused) {
  test::TempDir dir;
  std::string json = make_json(embedded_entry(make_buffer()));
  // 2^62 elements of 12 bytes: (count - 1) * stride wraps around in 64 bits.
  const std::string from = R"("count": 12, "type": "SCALAR"})";
  json.replace(json.find(from), from.size(), R"("count": 4611686018427387904, "type": "SCALAR"})");
  const Result<TriangleMesh> r = load_mesh(dir.write("scene.gltf", json));
  ASSERT_FALSE(r.ok());
}

}  // namespace
}  // namespace lap::sim
