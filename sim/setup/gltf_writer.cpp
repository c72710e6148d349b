#include "sim/setup/gltf_writer.h"

#include <array>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

namespace lap::sim {
namespace {

using json = nlohmann::ordered_json;

// glTF constants (glTF 2.0 specification, 5.1 accessors and 5.26 samplers).
constexpr int kFloat = 5126;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;
constexpr int kTriangles = 4;
constexpr int kLinear = 9729;
constexpr int kLinearMipmapLinear = 9987;
constexpr int kRepeat = 10497;
constexpr int kClampToEdge = 33071;

template <class T>
void put(std::vector<uint8_t>& buffer, T value) {
  uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  buffer.insert(buffer.end(), bytes, bytes + sizeof(T));
}

}  // namespace

Status save_gltf(const haptics::TriangleMesh& mesh, const std::filesystem::path& file,
                 const GltfMaterial& material) {
  const std::string where = file.string();
  const size_t n = mesh.positions.size();
  if (n == 0 || mesh.triangles.empty()) return file_diagnostic(where, 0, "", "the mesh is empty");
  if (mesh.normals.size() != n || mesh.uvs.size() != n) {
    return file_diagnostic(where, 0, "", "the mesh needs one normal and one uv per vertex");
  }
  std::vector<uint8_t> bin;
  std::array<float, 3> lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                          std::numeric_limits<float>::max()};
  std::array<float, 3> hi{-lo[0], -lo[1], -lo[2]};
  for (const Eigen::Vector3d& p : mesh.positions) {
    for (int k = 0; k < 3; ++k) {
      const auto f = static_cast<float>(p[k]);
      lo[k] = std::min(lo[k], f);
      hi[k] = std::max(hi[k], f);
      put(bin, f);
    }
  }
  const size_t normals_offset = bin.size();
  for (const Eigen::Vector3d& v : mesh.normals) {
    for (int k = 0; k < 3; ++k) put(bin, static_cast<float>(v[k]));
  }
  const size_t uvs_offset = bin.size();
  for (const Eigen::Vector2d& uv : mesh.uvs) {
    for (int k = 0; k < 2; ++k) put(bin, static_cast<float>(uv[k]));
  }
  const size_t indices_offset = bin.size();
  const bool short_indices = n <= 65535;
  for (const haptics::Triangle& t : mesh.triangles) {
    for (int32_t i : t) {
      if (i < 0 || static_cast<size_t>(i) >= n) {
        return file_diagnostic(where, 0, "", "a triangle indexes a vertex that does not exist");
      }
      if (short_indices) {
        put(bin, static_cast<uint16_t>(i));
      } else {
        put(bin, static_cast<uint32_t>(i));
      }
    }
  }
  const size_t indices_length = bin.size() - indices_offset;
  while (bin.size() % 4 != 0) bin.push_back(0);

  const std::filesystem::path bin_file = std::filesystem::path(file).replace_extension(".bin");
  const auto count = static_cast<int64_t>(n);
  auto view = [](size_t offset, size_t length, int target) {
    return json{{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}, {"target", target}};
  };
  json g;
  g["asset"] = {{"version", "2.0"}, {"generator", "laptrainer anatomy generator"}};
  g["scene"] = 0;
  g["scenes"] = json::array({{{"nodes", {0}}}});
  g["nodes"] = json::array({{{"name", material.name}, {"mesh", 0}}});
  g["meshes"] = json::array(
      {{{"name", material.name},
        {"primitives",
         json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                       {"indices", 3},
                       {"material", 0},
                       {"mode", kTriangles}}})}}});
  g["materials"] = json::array({{{"name", material.name},
                                 {"pbrMetallicRoughness",
                                  {{"baseColorTexture", {{"index", 0}}},
                                   {"metallicFactor", material.metallic},
                                   {"roughnessFactor", material.roughness}}}}});
  const int wrap = material.repeat ? kRepeat : kClampToEdge;
  g["samplers"] = json::array({{{"magFilter", kLinear},
                                {"minFilter", kLinearMipmapLinear},
                                {"wrapS", wrap},
                                {"wrapT", wrap}}});
  g["images"] = json::array({{{"uri", material.base_color_texture_uri}}});
  g["textures"] = json::array({{{"sampler", 0}, {"source", 0}}});
  g["buffers"] = json::array({{{"uri", bin_file.filename().string()}, {"byteLength", bin.size()}}});
  g["bufferViews"] = json::array({view(0, normals_offset, kArrayBuffer),
                                  view(normals_offset, uvs_offset - normals_offset, kArrayBuffer),
                                  view(uvs_offset, indices_offset - uvs_offset, kArrayBuffer),
                                  view(indices_offset, indices_length, kElementArrayBuffer)});
  g["accessors"] = json::array(
      {{{"bufferView", 0},
        {"componentType", kFloat},
        {"count", count},
        {"type", "VEC3"},
        {"min", {lo[0], lo[1], lo[2]}},
        {"max", {hi[0], hi[1], hi[2]}}},
       {{"bufferView", 1}, {"componentType", kFloat}, {"count", count}, {"type", "VEC3"}},
       {{"bufferView", 2}, {"componentType", kFloat}, {"count", count}, {"type", "VEC2"}},
       {{"bufferView", 3},
        {"componentType", short_indices ? kUnsignedShort : kUnsignedInt},
        {"count", 3 * mesh.triangle_count()},
        {"type", "SCALAR"}}});

  std::ofstream bin_out(bin_file, std::ios::binary);
  bin_out.write(reinterpret_cast<const char*>(bin.data()),
                static_cast<std::streamsize>(bin.size()));
  if (!bin_out) return file_diagnostic(bin_file.string(), 0, "", "cannot write the glTF buffer");
  std::ofstream out(file);
  out << g.dump(1) << "\n";
  if (!out) return file_diagnostic(where, 0, "", "cannot write the glTF file");
  return {};
}

}  // namespace lap::sim
