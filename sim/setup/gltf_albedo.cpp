#include "sim/setup/gltf_albedo.h"

#include <stb_image.h>

#include <cctype>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "sim/setup/gltf_references.h"
#include "sim/setup/json_lines.h"
#include "sim/setup/load_error.h"
#include "sim/setup/mesh_limits.h"
#include "sim/setup/png_image_data.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::vector<unsigned char> read_bytes(const fs::path& file, uint64_t limit) {
  std::error_code ec;
  const uintmax_t size = fs::file_size(file, ec);
  if (ec || !fs::is_regular_file(file, ec)) throw LoadError(file, "not a readable file");
  if (size > limit) {
    throw LoadError(file, "file of " + std::to_string(size) +
                              " bytes is larger than the limit of " + std::to_string(limit));
  }
  std::ifstream in(file, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw LoadError(file, "could not be read");
  return bytes;
}

// An index held at `j[key]` that lies within `of` entries, else none.
std::optional<size_t> index_at(const json& j, const char* key, const json& of) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number_integer() || !of.is_array()) {
    return std::nullopt;
  }
  const auto i = j[key].get<int64_t>();
  if (i < 0 || static_cast<uint64_t>(i) >= of.size()) return std::nullopt;
  return static_cast<size_t>(i);
}

// The first primitive's material with a base colour texture: the image's index.
std::optional<size_t> base_colour_image(const json& doc) {
  const json& meshes = doc.value("meshes", json::array());
  const json& materials = doc.value("materials", json::array());
  const json& textures = doc.value("textures", json::array());
  const json& images = doc.value("images", json::array());
  if (!meshes.is_array()) return std::nullopt;
  for (const json& mesh : meshes) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) {
      continue;
    }
    for (const json& prim : mesh["primitives"]) {
      const auto material = index_at(prim, "material", materials);
      if (!material) continue;
      const json& m = materials[*material];
      if (!m.is_object() || !m.contains("pbrMetallicRoughness")) continue;
      const json& pbr = m["pbrMetallicRoughness"];
      if (!pbr.is_object() || !pbr.contains("baseColorTexture")) continue;
      const auto texture = index_at(pbr["baseColorTexture"], "index", textures);
      if (!texture) continue;
      if (const auto image = index_at(textures[*texture], "source", images)) return image;
    }
  }
  return std::nullopt;
}

std::shared_ptr<const haptics::RgbImage> decode(const fs::path& gltf, const std::string& field,
                                                const fs::path& file) {
  auto fail = [&](const std::string& what) {
    throw LoadError(Diagnostic{gltf.string(), 0, field, file.filename().string() + ": " + what});
  };
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) fail("texture image not found (expected a PNG or JPEG)");
  std::vector<unsigned char> bytes;
  try {
    bytes = read_bytes(file, kMaxGltfBufferBytes);
  } catch (const LoadError& e) {
    fail(e.diagnostic().message);
  }
  if (bytes.size() > static_cast<size_t>(INT32_MAX)) fail("too large");
  const auto length = static_cast<int>(bytes.size());
  // PNG or JPEG by their signatures: glTF allows no other texture (glTF 2.0 §5.18: image/png or
  // image/jpeg), and stb_image's other decoders would widen what an untrusted file reaches.
  if (!is_png(bytes) && !is_jpeg(bytes)) fail("not a PNG or JPEG image (glTF allows no other)");
  int w = 0;
  int h = 0;
  int channels = 0;
  // The header first: an untrusted image's header alone can ask for gigabytes.
  if (stbi_info_from_memory(bytes.data(), length, &w, &h, &channels) == 0) {
    fail("not a PNG or JPEG image (" + std::string(stbi_failure_reason()) + ")");
  }
  if (w <= 0 || h <= 0 || w > kMaxAlbedoSide || h > kMaxAlbedoSide ||
      static_cast<int64_t>(w) * h > kMaxAlbedoPixels) {
    fail(std::to_string(w) + " x " + std::to_string(h) + " pixels is beyond the limit of " +
         std::to_string(kMaxAlbedoSide) + " a side and " + std::to_string(kMaxAlbedoPixels) +
         " pixels (sim/setup/gltf_albedo.h)");
  }
  // A PNG's compressed rows must end where its header says before stb_image inflates them.
  if (is_png(bytes)) {
    if (const auto problem = png_image_data_problem(bytes)) fail(*problem);
  }
  int got = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(bytes.data(), length, &w, &h, &got, 3), &stbi_image_free);
  if (pixels == nullptr) fail("corrupt image (" + std::string(stbi_failure_reason()) + ")");
  auto image = std::make_shared<haptics::RgbImage>();
  image->width = w;
  image->height = h;
  image->rgb.assign(pixels.get(), pixels.get() + static_cast<size_t>(w) * h * 3);
  return image;
}

}  // namespace

Result<std::shared_ptr<const haptics::RgbImage>> load_gltf_albedo(const fs::path& gltf) {
  try {
    std::string ext = gltf.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const bool binary = ext == ".glb";
    // The JSON text only, kept for the lines of a problem (not the file's bytes as well: a .gltf
    // may be hundreds of megabytes, and the texture is decoded while this is held).
    const std::string text = gltf_json_text(read_bytes(gltf, kMaxMeshFileBytes), binary);
    const json doc = json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return std::shared_ptr<const haptics::RgbImage>();
    const auto image = base_colour_image(doc);
    if (!image) return std::shared_ptr<const haptics::RgbImage>();
    const json& entry = doc["images"][*image];
    const std::string field = "images[" + std::to_string(*image) + "].uri";
    if (!entry.is_object() || !entry.contains("uri") || !entry["uri"].is_string()) {
      return std::shared_ptr<const haptics::RgbImage>();  // in a buffer view: not drawn
    }
    const std::string uri = entry["uri"].get<std::string>();
    if (uri.rfind("data:", 0) == 0) return std::shared_ptr<const haptics::RgbImage>();
    const fs::path folder = fs::absolute(gltf).parent_path();
    const fs::path file = folder / percent_decoded(uri);
    // load_mesh checked the reference; checked again here, as the file may have changed since.
    // A problem names the field's line in a text .gltf (a .glb's JSON has no lines of the
    // file's), found only when there is one.
    auto line = [&] { return binary ? 0 : JsonLines::scan(text).line(field); };
    if (!inside_folder(folder, file)) {
      return Diagnostic{gltf.string(), line(), field, "'" + uri + "' leaves the scene's folder"};
    }
    try {
      return decode(gltf, field, file);
    } catch (const LoadError& e) {
      Diagnostic d = e.diagnostic();
      d.line = line();
      return d;
    }
  } catch (const LoadError& e) {
    return e.diagnostic();
  }
}

}  // namespace lap::sim
