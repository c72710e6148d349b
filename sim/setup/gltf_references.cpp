#include "sim/setup/gltf_references.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <optional>

#include "sim/setup/json_lines.h"
#include "sim/setup/mesh_limits.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;

uint32_t le32(const std::vector<unsigned char>& b, size_t at) {
  return static_cast<uint32_t>(b[at]) | (static_cast<uint32_t>(b[at + 1]) << 8U) |
         (static_cast<uint32_t>(b[at + 2]) << 16U) | (static_cast<uint32_t>(b[at + 3]) << 24U);
}

// A URI shown in a message: printable and not too long (a data: URI can be megabytes).
std::string shown(const std::string& uri) {
  std::string s;
  for (char c : uri.substr(0, 80)) {
    const auto u = static_cast<unsigned char>(c);
    s += (u >= 0x20 && u < 0x7F) ? c : '?';
  }
  if (uri.size() > 80) s += "...";
  return "'" + s + "'";
}

// Why a URI may not be followed, or nothing.
std::optional<std::string> uri_problem(const std::string& uri) {
  if (uri.rfind("data:", 0) == 0) {
    if (uri.size() > kMaxGltfDataUriChars) {
      return "data URI of " + std::to_string(uri.size()) +
             " characters is longer than the limit of " + std::to_string(kMaxGltfDataUriChars) +
             " (sim/setup/mesh_limits.h); put the data in a .bin file beside the glTF";
    }
    return std::nullopt;
  }
  const std::string path = percent_decoded(uri);
  if (path.find("://") != std::string::npos || path.rfind("file:", 0) == 0) {
    return shown(uri) + " is a URL; expected a file in the scene's folder";
  }
  if (!path.empty() && path[0] == '~') {
    return shown(uri) + " starts in the home folder; expected a file in the scene's folder";
  }
  if (!path.empty() &&
      (path[0] == '/' || path[0] == '\\' || (path.size() >= 2 && path[1] == ':'))) {
    return shown(uri) + " is an absolute path; expected a file in the scene's folder";
  }
  size_t start = 0;
  while (start <= path.size()) {
    size_t end = path.find_first_of("/\\", start);
    if (end == std::string::npos) end = path.size();
    if (path.compare(start, end - start, "..") == 0 && end - start == 2) {
      return shown(uri) + " leaves the scene's folder";
    }
    start = end + 1;
  }
  return std::nullopt;
}

}  // namespace

std::string percent_decoded(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

std::string gltf_json_text(const std::vector<unsigned char>& bytes, bool binary) {
  if (!binary) return std::string(bytes.begin(), bytes.end());
  // GLB: 12-byte header, then the JSON chunk (length, type "JSON", data).
  if (bytes.size() < 20 || le32(bytes, 16) != 0x4E4F534AU) return {};
  const uint64_t length = le32(bytes, 12);
  if (20 + length > bytes.size()) return {};
  return std::string(bytes.begin() + 20, bytes.begin() + 20 + static_cast<ptrdiff_t>(length));
}

Status check_gltf_references(const fs::path& file, const std::string& json_text, bool binary) {
  const nlohmann::json doc = nlohmann::json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded() || !doc.is_object()) return {};
  std::vector<Diagnostic> problems;
  std::optional<JsonLines> lines;  // read again for the lines only when there is a problem
  auto problem = [&](const std::string& field, const std::string& what) {
    if (!binary && !lines) lines = JsonLines::scan(json_text);
    problems.push_back(
        file_diagnostic(file.string(), binary ? 0 : lines->line(field), field, what));
  };
  for (const auto& [key, limit] :
       {std::pair<const char*, int64_t>{"buffers", kMaxGltfBuffers}, {"images", kMaxGltfImages}}) {
    const auto it = doc.find(key);
    if (it == doc.end() || !it->is_array()) continue;
    if (static_cast<int64_t>(it->size()) > limit) {
      problem(key, std::to_string(it->size()) + " entries is more than the limit of " +
                       std::to_string(limit) + " (sim/setup/mesh_limits.h)");
      continue;
    }
    for (size_t i = 0; i < it->size(); ++i) {
      const nlohmann::json& entry = (*it)[i];
      if (!entry.is_object()) continue;
      const std::string where = std::string(key) + "[" + std::to_string(i) + "]";
      if (const auto uri = entry.find("uri"); uri != entry.end() && uri->is_string()) {
        if (auto p = uri_problem(uri->get<std::string>())) problem(where + ".uri", *p);
      }
      if (const auto n = entry.find("byteLength"); n != entry.end() && n->is_number()) {
        const double bytes = n->get<double>();
        // glTF 2.0 sets byteLength's minimum at 1 (tinygltf's reader throws on an embedded
        // buffer of 0 bytes: found by fuzzing).
        if (std::string(key) == "buffers" && !(bytes >= 1.0)) {
          problem(where + ".byteLength", n->dump() + " is not a length of 1 byte or more");
        } else if (bytes > static_cast<double>(kMaxGltfBufferBytes)) {
          problem(where + ".byteLength", n->dump() + " bytes is more than the limit of " +
                                             std::to_string(kMaxGltfBufferBytes) +
                                             " (sim/setup/mesh_limits.h)");
        }
      }
    }
  }
  return problems;
}

bool inside_folder(const fs::path& folder, const fs::path& path) {
  std::error_code ec;
  const fs::path f = fs::weakly_canonical(folder, ec);
  if (ec) return false;
  const fs::path p = fs::weakly_canonical(path, ec);
  if (ec) return false;
  const auto [fi, pi] = std::mismatch(f.begin(), f.end(), p.begin(), p.end());
  // An empty last component (a trailing separator) of the folder still matches.
  return fi == f.end() || (std::next(fi) == f.end() && fi->empty());
}

}  // namespace lap::sim
