#include "sim/setup/mesh_text_check.h"

#include <locale.h>
#include <stdlib.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

#include "core/bounded_file.h"
#include "sim/setup/gltf_references.h"
#include "sim/setup/mesh_limits.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;
using Problem = std::optional<std::string>;

// A token as it may be shown in a message: printable, and short (a mutated file may put a
// megabyte of binary on one line).
std::string shown(std::string_view token) {
  std::string s;
  for (char c : token.substr(0, 32)) {
    const auto u = static_cast<unsigned char>(c);
    s += (u >= 0x20 && u < 0x7F) ? c : '?';
  }
  if (token.size() > 32) s += "...";
  return s;
}

// A byte as two hex digits.
std::string hex_byte(char c) {
  char buf[3];
  std::snprintf(buf, sizeof(buf), "%02x", static_cast<unsigned>(static_cast<unsigned char>(c)));
  return buf;
}

// `what 'token' is not a finite number` or `... is not a number`, or nothing when the token
// is a finite number. strtod reads what OpenMesh's stream extraction would (and more: nan, inf),
// in the C locale whatever the process's: the window's Qt sets the user's, where the decimal
// separator may be a comma.
Problem number_problem(std::string_view token, const std::string& what) {
  static const locale_t c_locale = newlocale(LC_ALL_MASK, "C", nullptr);
  const std::string s(token);
  char* end = nullptr;
  const double v = strtod_l(s.c_str(), &end, c_locale);
  if (end == s.c_str() || end != s.c_str() + s.size()) {
    return what + " '" + shown(token) + "' is not a number";
  }
  if (!std::isfinite(v)) return what + " '" + shown(token) + "' is not a finite number";
  return std::nullopt;
}

std::optional<int64_t> whole_number(std::string_view token) {
  int64_t v = 0;
  const char* end = token.data() + token.size();
  const auto r = std::from_chars(token.data(), end, v);
  if (r.ec != std::errc() || r.ptr != end) return std::nullopt;
  return v;
}

// The file's lines, split into whitespace-separated tokens, with comments removed; blank lines
// are skipped. Tokens view `text`, valid until the next call.
class LineReader {
 public:
  LineReader(const fs::path& file, char comment)
      : in_(file, std::ios::binary), file_(file.string()), comment_(comment) {}

  bool next() {
    while (std::getline(in_, text_)) {
      ++number_;
      std::string_view v(text_);
      if (comment_ != '\0') v = v.substr(0, v.find(comment_));
      tokens_.clear();
      size_t i = 0;
      while (i < v.size()) {
        while (i < v.size() && is_space(v[i])) ++i;
        const size_t start = i;
        while (i < v.size() && !is_space(v[i])) ++i;
        if (i > start) tokens_.push_back(v.substr(start, i - start));
      }
      if (!tokens_.empty()) return true;
    }
    return false;
  }
  [[nodiscard]] const std::vector<std::string_view>& tokens() const { return tokens_; }
  [[nodiscard]] std::string_view operator[](size_t i) const { return tokens_[i]; }
  [[nodiscard]] size_t size() const { return tokens_.size(); }
  /// The line after its first token, comments and all, without the spaces around it.
  [[nodiscard]] std::string_view rest() const {
    std::string_view v(text_);
    v.remove_prefix(static_cast<size_t>(tokens_[0].data() + tokens_[0].size() - text_.data()));
    while (!v.empty() && is_space(v.front())) v.remove_prefix(1);
    while (!v.empty() && (is_space(v.back()) || v.back() == '\n')) v.remove_suffix(1);
    return v;
  }
  /// The line right after its first token, as it is (spaces and all).
  [[nodiscard]] std::string_view after_first() const {
    std::string_view v(text_);
    v.remove_prefix(static_cast<size_t>(tokens_[0].data() + tokens_[0].size() - text_.data()));
    return v;
  }
  /// The problem at the current line.
  [[nodiscard]] Status fail(const std::string& field, const std::string& what) const {
    return file_diagnostic(file_, number_, field, what);
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v'; }
  std::ifstream in_;
  std::string file_;
  char comment_;
  std::string text_;
  int number_ = 0;
  std::vector<std::string_view> tokens_;
};

std::string over_limit(int64_t count, const char* what, int64_t limit) {
  return std::to_string(count) + " " + what + " is more than the limit of " +
         std::to_string(limit) + " (sim/setup/mesh_limits.h)";
}

// An OBJ index (1-based; negative counts back from the last one defined above) against the
// `defined` items read so far.
Problem obj_index_problem(std::string_view token, int64_t defined, const std::string& what,
                          const char* plural) {
  const std::optional<int64_t> i = whole_number(token);
  if (!i) return what + " '" + shown(token) + "' is not a whole number";
  const int64_t resolved = *i < 0 ? defined + *i + 1 : *i;
  if (*i == 0 || resolved < 1 || resolved > defined) {
    return what + " " + std::to_string(*i) + " is outside the " + std::to_string(defined) + " " +
           plural + " defined above";
  }
  return std::nullopt;
}

// A material library (`mtllib NAME`) is opened by OpenMesh's reader as the OBJ's folder followed
// by the rest of the line: it must lie in that folder, and be a regular file if it is there at
// all (a FIFO would block the reader; a missing one OpenMesh only warns about).
Problem material_library_problem(const fs::path& obj, std::string_view name) {
  const std::string folder = obj.parent_path().empty() ? "./" : obj.parent_path().string() + "/";
  const fs::path library = folder + std::string(name);
  if (name.empty()) return std::nullopt;  // OpenMesh opens the folder itself, and reads nothing
  if (!inside_folder(folder, library)) {
    return quote_excerpt(name) + " leaves the mesh's folder (expected a file beside the OBJ)";
  }
  std::error_code ec;
  const fs::file_status status = fs::status(library, ec);
  if (status.type() == fs::file_type::not_found) return std::nullopt;
  if (Status ok = check_regular_file(library, kMaxMeshFileBytes, "a material library"); !ok.ok()) {
    return quote_excerpt(name) + ": " + ok.diagnostics().front().to_string();
  }
  return std::nullopt;
}

Status check_obj(const fs::path& file) {
  LineReader r(file, '#');
  int64_t vertices = 0;
  int64_t uvs = 0;
  int64_t normals = 0;
  int64_t triangles = 0;
  while (r.next()) {
    const std::string_view key = r[0];
    if (key == "v" || key == "vn" || key == "vt") {
      const std::string field = key == "v"    ? "vertex"
                                : key == "vn" ? "normal"
                                              : "texture coordinate";
      const size_t needed = key == "vt" ? 1 : 3;
      if (r.size() < needed + 1) {
        return r.fail(field, "expected " + std::to_string(needed) + " numbers, got " +
                                 std::to_string(r.size() - 1));
      }
      for (size_t k = 1; k < r.size(); ++k) {
        if (Problem p = number_problem(r[k], key == "v" ? "coordinate" : "component")) {
          return r.fail(field, *p);
        }
      }
      int64_t& count = key == "v" ? vertices : key == "vn" ? normals : uvs;
      if (++count > kMaxMeshVertices) {
        return r.fail(field, over_limit(count, "entries", kMaxMeshVertices));
      }
    } else if (key == "mtllib") {
      if (Problem p = material_library_problem(file, r.rest())) return r.fail("mtllib", *p);
    } else if (key == "f") {
      if (r.size() < 4) {
        return r.fail("face", "expected at least 3 vertices, got " + std::to_string(r.size() - 1));
      }
      for (size_t k = 1; k < r.size(); ++k) {
        // v, v/vt, v//vn or v/vt/vn
        const std::string_view corner = r[k];
        const size_t s1 = corner.find('/');
        const size_t s2 = s1 == std::string_view::npos ? s1 : corner.find('/', s1 + 1);
        const std::string_view v = corner.substr(0, s1);
        if (Problem p = obj_index_problem(v, vertices, "vertex index", "vertices")) {
          return r.fail("face", *p);
        }
        if (s1 != std::string_view::npos) {
          const std::string_view t = corner.substr(
              s1 + 1, s2 == std::string_view::npos ? std::string_view::npos : s2 - s1 - 1);
          if (!t.empty()) {
            if (Problem p =
                    obj_index_problem(t, uvs, "texture coordinate index", "texture coordinates")) {
              return r.fail("face", *p);
            }
          }
        }
        if (s2 != std::string_view::npos) {
          const std::string_view n = corner.substr(s2 + 1);
          if (!n.empty()) {
            if (Problem p = obj_index_problem(n, normals, "normal index", "normals")) {
              return r.fail("face", *p);
            }
          }
        }
      }
      triangles += static_cast<int64_t>(r.size()) - 3;
      if (triangles > kMaxMeshTriangles) {
        return r.fail("face", over_limit(triangles, "triangles", kMaxMeshTriangles));
      }
    }
  }
  return {};
}

// OpenMesh's OFF reader takes a line that is only a comment for data (a comment between the
// header and the counts gave "no triangles", one among the vertices garbage indices: found by
// the fuzz targets' seeds), while a comment after the numbers on a line is read correctly. So a
// whole-line comment is refused, at its line, rather than misread.
Status no_comment_lines(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const size_t first = line.find_first_not_of(" \t\r\v");
    if (first == std::string::npos) continue;
    if (line.find("BINARY") != std::string::npos) return {};  // binary data follows the header
    if (line[first] == '#') {
      return file_diagnostic(file.string(), number, "comment",
                             "a line holding only a comment is not read correctly in an OFF file "
                             "(OpenMesh's reader); remove it or move it after the numbers of a "
                             "line");
    }
  }
  return {};
}

// OFF: [C|N|ST...]OFF header, `nv nf ne`, nv vertex lines, nf faces `n i0 .. in-1 [colour]`.
Status check_off(const fs::path& file) {
  if (Status s = no_comment_lines(file); !s.ok()) return s;
  LineReader r(file, '#');
  if (!r.next()) return {};
  const std::string_view head = r[0];
  bool other_dimension = false;
  if (head.find("OFF") != std::string_view::npos) {
    // [ST][C][N][4][n]OFF [BINARY], as OpenMesh reads it; anything else it half-reads.
    std::string_view rest = head;
    for (std::string_view prefix : {"ST", "C", "N", "4", "n"}) {
      if (rest.substr(0, prefix.size()) == prefix) rest.remove_prefix(prefix.size());
    }
    if (rest != "OFF") {
      return r.fail("header",
                    "expected OFF (or COFF, NOFF, STOFF, 4OFF, nOFF), got '" + shown(head) + "'");
    }
    // 4D and n-dimensional variants: their counts are checked, their vertices left to OpenMesh.
    other_dimension =
        head.find('4') != std::string_view::npos || head.find('n') != std::string_view::npos;
    // OpenMesh takes the data for binary only when " BINARY" follows the header's first word at
    // once, one space between; any other BINARY it skips, and reads the text after the line as
    // counts (the fuzzer's "OFF    BINARY" then asked for gigabytes).
    if (std::find(r.tokens().begin(), r.tokens().end(), "BINARY") != r.tokens().end()) {
      if (r.after_first().substr(0, 7) == " BINARY") {
        // OpenMesh trusts binary OFF's counts and face sizes as it reads them: a 178-byte file
        // kept it adding faces for over 10 s (found by the fuzzer). Its data cannot be checked
        // here without reading it as OpenMesh would, so binary OFF is refused, with what to do.
        return r.fail("header",
                      "binary OFF is not read (its counts cannot be checked before the reader "
                      "trusts them); save the mesh as text OFF, PLY, STL, OBJ or glTF");
      }
      std::string line = std::string(head) + std::string(r.after_first());
      line.erase(line.find_last_not_of(" \t\r\v") + 1);
      return r.fail("header", "expected '" + shown(head) +
                                  " BINARY' with one space between (any other header with BINARY "
                                  "is read as text), got '" +
                                  shown(line) + "'");
    }
    // OpenMesh skips the rest of the header line and reads the counts from the next: counts
    // beside OFF would be misread (the fuzzer's "OFF 0 0" then asked for gigabytes).
    if (r.size() > 1) {
      return r.fail("header",
                    "expected the counts on the line after '" + shown(head) + "', not on its line");
    }
    // Counts that are not there OpenMesh reads as whatever its variables held ("OFF\n").
    if (!r.next()) return r.fail("counts", "the file ends before the vertex and face counts");
  } else if (!whole_number(head)) {
    return {};  // not OFF at all: OpenMesh refuses it
  }
  // Three counts, the edges' ignored: OpenMesh reads three numbers, taking the first vertex's x
  // for the third where a line has only two.
  std::array<int64_t, 3> counts = {-1, -1, -1};
  for (size_t k = 0; k < counts.size() && k < r.size(); ++k) {
    counts[k] = whole_number(r[k]).value_or(-1);
  }
  if (counts[0] < 0 || counts[1] < 0 || counts[2] < 0) {
    return r.fail("counts", "expected the vertex, face and edge counts as whole numbers >= 0");
  }
  const int64_t nv = counts[0];
  const int64_t nf = counts[1];
  if (nv > kMaxMeshVertices) return r.fail("counts", over_limit(nv, "vertices", kMaxMeshVertices));
  if (nf > kMaxMeshTriangles) return r.fail("counts", over_limit(nf, "faces", kMaxMeshTriangles));
  if (other_dimension) return {};
  for (int64_t i = 0; i < nv; ++i) {
    if (!r.next()) {
      return r.fail("vertex", "the file ends after " + std::to_string(i) + " of the " +
                                  std::to_string(nv) + " vertices");
    }
    if (r.size() < 3) {
      return r.fail("vertex", "expected 3 coordinates, got " + std::to_string(r.size()));
    }
    for (size_t k = 0; k < r.size(); ++k) {
      if (Problem p = number_problem(r[k], k < 3 ? "coordinate" : "value")) {
        return r.fail("vertex", *p);
      }
    }
  }
  int64_t triangles = 0;
  for (int64_t j = 0; j < nf; ++j) {
    if (!r.next()) {
      return r.fail("face", "the file ends after " + std::to_string(j) + " of the " +
                                std::to_string(nf) + " faces");
    }
    const std::optional<int64_t> n = whole_number(r[0]);
    if (!n) return r.fail("face", "corner count '" + shown(r[0]) + "' is not a whole number");
    if (*n < 3) return r.fail("face", "expected at least 3 vertices, got " + std::to_string(*n));
    if (static_cast<int64_t>(r.size()) - 1 < *n) {
      return r.fail("face", "expected " + std::to_string(*n) + " vertex indices, got " +
                                std::to_string(r.size() - 1));
    }
    for (int64_t k = 1; k <= *n; ++k) {
      const std::optional<int64_t> v = whole_number(r[static_cast<size_t>(k)]);
      if (!v) {
        return r.fail("face", "vertex index '" + shown(r[static_cast<size_t>(k)]) +
                                  "' is not a whole number");
      }
      if (*v < 0 || *v >= nv) {
        return r.fail("face", "vertex index " + std::to_string(*v) + " is outside the " +
                                  std::to_string(nv) + " vertices");
      }
    }
    triangles += *n - 2;
    if (triangles > kMaxMeshTriangles) {
      return r.fail("face", over_limit(triangles, "triangles", kMaxMeshTriangles));
    }
  }
  return {};
}

// PLY: the header's element counts against the limits (any format); the values of an ascii body
// line by line (one element per line, as every writer does).
Status check_ply(const fs::path& file) {
  struct Property {
    std::string name;
    bool list = false;
  };
  struct Element {
    std::string name;
    int64_t count = 0;
    std::vector<Property> properties;
  };
  LineReader r(file, '\0');
  if (!r.next() || r[0] != "ply") return {};
  // The header is held to the PLY grammar: OpenMesh's reader crashes on some headers it does not
  // understand (a property before any element).
  static const std::vector<std::string_view> kTypes = {
      "char", "uchar", "short", "ushort", "int",   "uint",   "float",   "double",
      "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  static const std::vector<std::string_view> kIntegerTypes = {"char",  "uchar",  "short", "ushort",
                                                              "int",   "uint",   "int8",  "uint8",
                                                              "int16", "uint16", "int32", "uint32"};
  const auto is_one_of = [](std::string_view t, const std::vector<std::string_view>& set) {
    return std::find(set.begin(), set.end(), t) != set.end();
  };
  std::vector<Element> elements;
  bool ascii = false;
  bool ended = false;
  while (!ended && r.next()) {
    // OpenMesh's header parser loops forever on some bytes that are not text (found by fuzzing).
    for (std::string_view t : r.tokens()) {
      for (const char c : t) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7E) {
          return r.fail("header", "a byte that is not text (0x" + hex_byte(c) + ") in the header");
        }
      }
    }
    const std::string_view key = r[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (r.size() != 3 ||
          (r[1] != "ascii" && r[1] != "binary_little_endian" && r[1] != "binary_big_endian") ||
          r[2] != "1.0") {  // OpenMesh's reader loops forever on another version
        return r.fail("header",
                      "expected 'format ascii|binary_little_endian|binary_big_endian "
                      "1.0'");
      }
      ascii = r[1] == "ascii";
    } else if (key == "element") {
      const std::optional<int64_t> n = r.size() == 3 ? whole_number(r[2]) : std::nullopt;
      if (!n || *n < 0) return r.fail("header", "expected 'element NAME COUNT'");
      const std::string name(r[1]);
      if (name == "vertex" && *n > kMaxMeshVertices) {
        return r.fail("element vertex", over_limit(*n, "vertices", kMaxMeshVertices));
      }
      if (name == "face" && *n > kMaxMeshTriangles) {
        return r.fail("element face", over_limit(*n, "faces", kMaxMeshTriangles));
      }
      elements.push_back({name, *n, {}});
    } else if (key == "property") {
      if (elements.empty()) return r.fail("header", "a property before any element");
      const bool list = r.size() >= 2 && r[1] == "list";
      const bool ok =
          list ? r.size() == 5 && is_one_of(r[2], kIntegerTypes) && is_one_of(r[3], kTypes)
               : r.size() == 3 && is_one_of(r[1], kTypes);
      if (!ok) {
        return r.fail("header",
                      "expected 'property TYPE NAME' or 'property list COUNT_TYPE "
                      "TYPE NAME' (with PLY's types)");
      }
      elements.back().properties.push_back({std::string(r[r.size() - 1]), list});
    } else if (key == "end_header") {
      ended = true;
    } else {
      return r.fail("header", "unknown keyword '" + shown(key) + "'");
    }
  }
  // A header without its end: OpenMesh's reader loops forever at the end of the file (fuzzing).
  if (!ended) return r.fail("header", "the file ends before 'end_header'");
  if (!ascii) return {};
  int64_t vertex_count = -1;
  for (const Element& e : elements) {
    const bool face = e.name == "face";
    for (int64_t i = 0; i < e.count; ++i) {
      if (!r.next()) {
        return r.fail(e.name, "the file ends after " + std::to_string(i) + " of the " +
                                  std::to_string(e.count) + " " + e.name + " lines");
      }
      size_t at = 0;
      for (const Property& p : e.properties) {
        if (at >= r.size()) {
          return r.fail(e.name, "expected a value for property '" + p.name + "', the line ends");
        }
        if (!p.list) {
          const bool xyz = e.name == "vertex" && (p.name == "x" || p.name == "y" || p.name == "z");
          if (Problem pr = number_problem(r[at], xyz ? "coordinate" : p.name + " value")) {
            return r.fail(e.name, *pr);
          }
          ++at;
          continue;
        }
        const std::optional<int64_t> n = whole_number(r[at]);
        if (!n || *n < 0) {
          return r.fail(e.name, p.name + " length '" + shown(r[at]) + "' is not a whole number");
        }
        ++at;
        if (static_cast<int64_t>(r.size() - at) < *n) {
          return r.fail(e.name, "expected " + std::to_string(*n) + " entries in " + p.name +
                                    ", got " + std::to_string(r.size() - at));
        }
        const bool indices = face && (p.name == "vertex_indices" || p.name == "vertex_index");
        for (int64_t k = 0; k < *n; ++k, ++at) {
          if (!indices) {
            if (Problem pr = number_problem(r[at], p.name + " value")) return r.fail(e.name, *pr);
            continue;
          }
          const std::optional<int64_t> v = whole_number(r[at]);
          if (!v) {
            return r.fail(e.name, "vertex index '" + shown(r[at]) + "' is not a whole number");
          }
          if (vertex_count >= 0 && (*v < 0 || *v >= vertex_count)) {
            return r.fail(e.name, "vertex index " + std::to_string(*v) + " is outside the " +
                                      std::to_string(vertex_count) + " vertices");
          }
        }
      }
    }
    if (e.name == "vertex") vertex_count = e.count;
  }
  return {};
}

// Binary STL: 50 bytes per triangle, a normal and three corners as little-endian floats (and
// OpenMesh drops a triangle with a NaN corner without a word).
Status check_binary_stl_values(const fs::path& file, uint64_t triangles) {
  std::ifstream in(file, std::ios::binary);
  in.seekg(84);
  char record[50];
  for (uint64_t t = 0; t < triangles && in.read(record, 50); ++t) {
    for (int k = 0; k < 12; ++k) {
      float v = 0.0F;
      std::memcpy(&v, record + static_cast<ptrdiff_t>(4) * k,
                  4);  // x86 and ARM Linux are little-endian, as STL
      if (!std::isfinite(v)) {
        std::ostringstream text;
        text << v;
        return file_diagnostic(file.string(), 0, "triangles[" + std::to_string(t) + "]",
                               std::string(k < 3 ? "normal component" : "coordinate") + " '" +
                                   text.str() + "' is not a finite number");
      }
    }
  }
  return {};
}

// STL: binary when its size is what its triangle count says (as OpenMesh decides); then only
// the count is checked here. Text: each `vertex` and `facet normal` line.
Status check_stl(const fs::path& file) {
  std::error_code ec;
  const uintmax_t size = fs::file_size(file, ec);
  if (ec) return {};
  std::string head(84, '\0');
  {
    std::ifstream in(file, std::ios::binary);
    in.read(head.data(), 84);
    head.resize(static_cast<size_t>(in.gcount()));
  }
  if (head.size() == 84) {
    const auto b = [&](size_t i) { return static_cast<uint64_t>(static_cast<uint8_t>(head[i])); };
    const uint64_t n = b(80) | (b(81) << 8U) | (b(82) << 16U) | (b(83) << 24U);
    const bool binary = 84 + 50 * n == size || head.rfind("solid", 0) != 0;
    if (binary) {
      if (n > static_cast<uint64_t>(kMaxMeshTriangles)) {
        return file_diagnostic(file.string(), 0, "triangle count",
                               over_limit(static_cast<int64_t>(n), "triangles", kMaxMeshTriangles));
      }
      return check_binary_stl_values(file, n);
    }
  } else if (head.rfind("solid", 0) != 0) {
    return {};  // too short for binary, not text: OpenMesh refuses it
  }
  LineReader r(file, '\0');
  int64_t triangles = 0;
  while (r.next()) {
    const bool vertex = r[0] == "vertex";
    const bool normal = r[0] == "facet" && r.size() >= 2 && r[1] == "normal";
    if (!vertex && !normal) continue;
    const size_t first = vertex ? 1 : 2;
    const std::string field = vertex ? "vertex" : "facet normal";
    if (r.size() != first + 3) {
      return r.fail(field, "expected 3 numbers, got " + std::to_string(r.size() - first));
    }
    for (size_t k = first; k < r.size(); ++k) {
      if (Problem p = number_problem(r[k], vertex ? "coordinate" : "component")) {
        return r.fail(field, *p);
      }
    }
    if (normal && ++triangles > kMaxMeshTriangles) {
      return r.fail(field, over_limit(triangles, "triangles", kMaxMeshTriangles));
    }
  }
  return {};
}

}  // namespace

Status check_mesh_text(const fs::path& file, const std::string& ext) {
  if (ext == ".obj") return check_obj(file);
  if (ext == ".off") return check_off(file);
  if (ext == ".ply") return check_ply(file);
  if (ext == ".stl") return check_stl(file);
  return {};
}

}  // namespace lap::sim
