#include "sim/setup/ply_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/setup/mesh_limits.h"
#include "sim/setup/mesh_text_lines.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;
using haptics::TriangleMesh;
using namespace mesh_text;  // NOLINT(google-build-using-namespace): the text readers' helpers

enum class Type : uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::optional<Type> type_named(std::string_view n) {
  if (n == "char" || n == "int8") return Type::kInt8;
  if (n == "uchar" || n == "uint8") return Type::kUint8;
  if (n == "short" || n == "int16") return Type::kInt16;
  if (n == "ushort" || n == "uint16") return Type::kUint16;
  if (n == "int" || n == "int32") return Type::kInt32;
  if (n == "uint" || n == "uint32") return Type::kUint32;
  if (n == "float" || n == "float32") return Type::kFloat32;
  if (n == "double" || n == "float64") return Type::kFloat64;
  return std::nullopt;
}
size_t size_of(Type t) {
  constexpr std::array<size_t, 8> kSizes = {1, 1, 2, 2, 4, 4, 4, 8};
  return kSizes[static_cast<size_t>(t)];
}
bool is_integer(Type t) { return t != Type::kFloat32 && t != Type::kFloat64; }

// At most this many elements in a header, and properties in an element (real files have two
// or three, and a dozen properties).
constexpr size_t kMaxElements = 1024;

// Where a vertex property's value goes.
enum Slot : uint8_t { kX, kY, kZ, kNx, kNy, kNz, kU, kV, kOther };
Slot slot_named(std::string_view n) {
  if (n == "x") return kX;
  if (n == "y") return kY;
  if (n == "z") return kZ;
  if (n == "nx") return kNx;
  if (n == "ny") return kNy;
  if (n == "nz") return kNz;
  if (n == "u" || n == "s" || n == "texture_u") return kU;
  if (n == "v" || n == "t" || n == "texture_v") return kV;
  return kOther;
}

struct Property {
  std::string name;
  Type type = Type::kFloat32;  // a list's items
  bool list = false;
  Type count_type = Type::kUint8;
  Slot slot = kOther;    // in the vertex element
  bool indices = false;  // the face element's vertex_indices
};
struct Element {
  std::string name;
  int64_t count = 0;
  std::vector<Property> properties;
  int line = 0;
};
struct Header {
  std::vector<Element> elements;
  bool ascii = false;
  bool big_endian = false;
};

// The header, held to PLY's grammar, its counts to the limits.
Result<Header> read_header(LineReader& r) {
  if (!r.next() || r.size() != 1 || r[0] != "ply") {
    return r.problem("header", "expected 'ply' alone on the first line");
  }
  Header h;
  bool format = false;
  while (r.next()) {
    for (std::string_view t : r.tokens()) {
      for (const char c : t) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7E) {
          return r.problem("header",
                           "a byte that is not text (0x" + hex_byte(c) + ") in the header");
        }
      }
    }
    const std::string_view key = r[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (r.size() != 3 ||
          (r[1] != "ascii" && r[1] != "binary_little_endian" && r[1] != "binary_big_endian") ||
          r[2] != "1.0") {
        return r.problem("header",
                         "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      }
      format = true;
      h.ascii = r[1] == "ascii";
      h.big_endian = r[1] == "binary_big_endian";
    } else if (key == "element") {
      const std::optional<int64_t> n = r.size() == 3 ? whole_number(r[2]) : std::nullopt;
      if (!n || *n < 0) return r.problem("header", "expected 'element NAME COUNT'");
      const std::string name(r[1]);
      // Each element named once (a second `vertex` would add to the first past the limit), and
      // a header of a bounded size (each element and property is kept while the body is read).
      if (std::any_of(h.elements.begin(), h.elements.end(),
                      [&](const Element& e) { return e.name == name; })) {
        return r.problem("element " + shown(name), "given twice (expected each element once)");
      }
      if (h.elements.size() >= kMaxElements) {
        return r.problem("header", "more than " + std::to_string(kMaxElements) + " elements");
      }
      if (name == "vertex" && *n > kMaxMeshVertices) {
        return r.problem("element vertex", over_limit(*n, "vertices", kMaxMeshVertices));
      }
      if (name == "face" && *n > kMaxMeshTriangles) {
        return r.problem("element face", over_limit(*n, "faces", kMaxMeshTriangles));
      }
      h.elements.push_back({name, *n, {}, r.line()});
    } else if (key == "property") {
      if (h.elements.empty()) return r.problem("header", "a property before any element");
      const bool list = r.size() >= 2 && r[1] == "list";
      Property p;
      p.list = list;
      // `property list COUNT_TYPE TYPE NAME` or `property TYPE NAME`
      const bool shaped = list ? r.size() == 5 : r.size() == 3;
      const std::optional<Type> type = shaped ? type_named(r[list ? 3 : 1]) : std::nullopt;
      const Type count_type =
          list && shaped ? type_named(r[2]).value_or(Type::kFloat32) : Type::kUint8;
      if (!type || !is_integer(count_type)) {
        return r.problem("header",
                         "expected 'property TYPE NAME' or 'property list COUNT_TYPE "
                         "TYPE NAME' (with PLY's types)");
      }
      Element& e = h.elements.back();
      if (e.properties.size() >= kMaxElements) {
        return r.problem("element " + shown(e.name),
                         "more than " + std::to_string(kMaxElements) + " properties");
      }
      p.name = std::string(r[r.size() - 1]);
      p.type = *type;
      p.count_type = count_type;
      if (e.name == "vertex" && !list) p.slot = slot_named(p.name);
      p.indices =
          e.name == "face" && list && (p.name == "vertex_indices" || p.name == "vertex_index");
      if (p.indices && !is_integer(p.type)) {
        return r.problem("header", "the face's " + p.name + " must be a list of an integer type");
      }
      e.properties.push_back(std::move(p));
    } else if (key == "end_header") {
      if (!format) return r.problem("header", "'end_header' before the 'format' line");
      return h;
    } else {
      return r.problem("header", "unknown keyword '" + shown(key) + "'");
    }
  }
  return r.problem("header", "the file ends before 'end_header'");
}

// What the header says the mesh has, checked against what this reader needs.
Status check_layout(const fs::path& file, const Header& h) {
  bool vertices = false;
  for (const Element& e : h.elements) {
    if (e.name == "vertex") vertices = true;
    if (e.name == "face" && !vertices) {
      return file_diagnostic(file.string(), e.line, "element face",
                             "expected after the 'vertex' element (its indices refer to it)");
    }
    const auto has = [&](Slot s) {
      return std::any_of(e.properties.begin(), e.properties.end(),
                         [&](const Property& p) { return p.slot == s; });
    };
    if (e.name == "vertex" && !(has(kX) && has(kY) && has(kZ))) {
      return file_diagnostic(file.string(), e.line, "element vertex",
                             "expected the properties x, y and z");
    }
    if (e.name == "face" && std::none_of(e.properties.begin(), e.properties.end(),
                                         [](const Property& p) { return p.indices; })) {
      return file_diagnostic(file.string(), e.line, "element face",
                             "expected 'property list COUNT_TYPE INDEX_TYPE vertex_indices'");
    }
  }
  return {};
}

// The mesh being read: a vertex's values as they come, a face's indices.
struct Builder {
  TriangleMesh mesh;
  bool normals = false;
  bool uvs = false;
  int64_t vertex_count = -1;  // once the vertex element is read
  std::array<double, 8> slots{};
  std::vector<int64_t> polygon;

  void begin_element(const Element& e) {
    if (e.name != "vertex") return;
    const auto has = [&](Slot s) {
      return std::any_of(e.properties.begin(), e.properties.end(),
                         [&](const Property& p) { return p.slot == s; });
    };
    normals = has(kNx) && has(kNy) && has(kNz);
    uvs = has(kU) && has(kV);
  }
  void end_vertex() {
    mesh.positions.emplace_back(slots[kX], slots[kY], slots[kZ]);
    if (normals) mesh.normals.emplace_back(slots[kNx], slots[kNy], slots[kNz]);
    if (uvs) mesh.uvs.emplace_back(slots[kU], slots[kV]);
  }
  // The polygon fanned into triangles; a problem when it has fewer than 3 corners or the mesh
  // would pass the limit.
  Problem end_face() {
    if (polygon.size() < 3) {
      return "a face with " + std::to_string(polygon.size()) + " vertices (expected 3 or more)";
    }
    if (static_cast<int64_t>(mesh.triangles.size() + polygon.size() - 2) > kMaxMeshTriangles) {
      return over_limit(static_cast<int64_t>(mesh.triangles.size() + polygon.size() - 2),
                        "triangles", kMaxMeshTriangles);
    }
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
      mesh.triangles.push_back({static_cast<int32_t>(polygon[0]), static_cast<int32_t>(polygon[k]),
                                static_cast<int32_t>(polygon[k + 1])});
    }
    return std::nullopt;
  }
  // A face's vertex index, against the vertices read so far (when they come first).
  Problem index(int64_t v) {
    if (vertex_count >= 0 && (v < 0 || v >= vertex_count)) {
      return "vertex index " + std::to_string(v) + " is outside the " +
             std::to_string(vertex_count) + " vertices";
    }
    if (v < 0 || v > INT32_MAX) return "vertex index " + std::to_string(v) + " is out of range";
    polygon.push_back(v);
    return std::nullopt;
  }
};

// --- ascii: one element per line, as every writer does ---

Status read_ascii_element(LineReader& r, const Element& e, Builder* b) {
  const bool vertex = e.name == "vertex";
  const bool face = e.name == "face";
  for (int64_t i = 0; i < e.count; ++i) {
    if (e.properties.empty()) break;  // nothing to read: no line either
    if (!r.next()) {
      return r.fail(shown(e.name), "the file ends after " + std::to_string(i) + " of the " +
                                       std::to_string(e.count) + " " + shown(e.name) + " lines");
    }
    b->polygon.clear();
    size_t at = 0;
    for (const Property& p : e.properties) {
      if (at >= r.size()) {
        return r.fail(shown(e.name),
                      "expected a value for property '" + shown(p.name) + "', the line ends");
      }
      if (!p.list) {
        const bool xyz = vertex && p.slot <= kZ;
        if (Problem pr = number_problem(r[at], xyz ? "coordinate" : shown(p.name) + " value")) {
          return r.fail(shown(e.name), *pr);
        }
        if (vertex && p.slot != kOther) b->slots[p.slot] = *number_value(r[at]);
        ++at;
        continue;
      }
      const std::optional<int64_t> n = whole_number(r[at]);
      if (!n || *n < 0) {
        return r.fail(shown(e.name),
                      shown(p.name) + " length '" + shown(r[at]) + "' is not a whole number");
      }
      ++at;
      if (p.indices && *n > kMaxMeshTriangles + 2) {
        return r.fail(shown(e.name), "a face with " + std::to_string(*n) +
                                         " vertices is more than the limit of triangles allows");
      }
      if (static_cast<int64_t>(r.size() - at) < *n) {
        return r.fail(shown(e.name), "expected " + std::to_string(*n) + " entries in " +
                                         shown(p.name) + ", got " + std::to_string(r.size() - at));
      }
      for (int64_t k = 0; k < *n; ++k, ++at) {
        if (!p.indices) {
          if (Problem pr = number_problem(r[at], shown(p.name) + " value"))
            return r.fail(shown(e.name), *pr);
          continue;
        }
        const std::optional<int64_t> v = whole_number(r[at]);
        if (!v)
          return r.fail(shown(e.name), "vertex index '" + shown(r[at]) + "' is not a whole number");
        if (Problem pr = b->index(*v)) return r.fail(shown(e.name), *pr);
      }
    }
    if (vertex) b->end_vertex();
    if (face) {
      if (Problem pr = b->end_face()) return r.fail(shown(e.name), *pr);
    }
  }
  return {};
}

// --- binary: exactly the bytes the header announces ---

// One value at `p`, of type `t`, from a file of the given byte order (the host is
// little-endian: x86 and ARM Linux).
double decode(const unsigned char* p, Type t, bool big_endian) {
  std::array<unsigned char, 8> b{};
  const size_t n = size_of(t);
  for (size_t i = 0; i < n; ++i) b[i] = big_endian ? p[n - 1 - i] : p[i];
  switch (t) {
    case Type::kInt8:
      return static_cast<int8_t>(b[0]);
    case Type::kUint8:
      return b[0];
    case Type::kInt16: {
      int16_t v = 0;
      std::memcpy(&v, b.data(), 2);
      return v;
    }
    case Type::kUint16: {
      uint16_t v = 0;
      std::memcpy(&v, b.data(), 2);
      return v;
    }
    case Type::kInt32: {
      int32_t v = 0;
      std::memcpy(&v, b.data(), 4);
      return v;
    }
    case Type::kUint32: {
      uint32_t v = 0;
      std::memcpy(&v, b.data(), 4);
      return v;
    }
    case Type::kFloat32: {
      float v = 0;
      std::memcpy(&v, b.data(), 4);
      return v;
    }
    case Type::kFloat64: {
      double v = 0;
      std::memcpy(&v, b.data(), 8);
      return v;
    }
  }
  return 0.0;
}

struct ByteCursor {
  const std::string& bytes;
  size_t at = 0;
  int64_t body_start = 0;  // the file's byte where `bytes` begins
  [[nodiscard]] size_t left() const { return bytes.size() - at; }
  const unsigned char* take(size_t n) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data()) + at;
    at += n;
    return p;
  }
};

Status read_binary_element(const fs::path& file, const Header& h, const Element& e, ByteCursor* c,
                           Builder* b) {
  if (e.properties.empty()) return {};  // nothing to read, whatever its count
  // Each instance takes at least one byte: a count the rest of the file cannot hold is refused
  // before it is looped over.
  if (static_cast<uint64_t>(e.count) > c->left()) {
    return file_diagnostic(file.string(), e.line, "element " + shown(e.name),
                           std::to_string(e.count) + " elements cannot fit in the " +
                               std::to_string(c->left()) + " bytes after the header");
  }
  const bool vertex = e.name == "vertex";
  if (vertex) b->mesh.positions.reserve(static_cast<size_t>(e.count));  // fits: checked above
  const auto fail = [&](int64_t i, const std::string& what) {
    return file_diagnostic(
        file.string(), 0, shown(e.name) + "[" + std::to_string(i) + "]",
        what + " (byte " + std::to_string(c->body_start + static_cast<int64_t>(c->at)) + ")");
  };
  for (int64_t i = 0; i < e.count; ++i) {
    b->polygon.clear();
    for (const Property& p : e.properties) {
      if (!p.list) {
        if (c->left() < size_of(p.type))
          return fail(i, "the file ends in property " + shown(p.name));
        const double v = decode(c->take(size_of(p.type)), p.type, h.big_endian);
        if (vertex && p.slot != kOther) {
          if (!std::isfinite(v)) {
            return fail(i, std::string(p.slot <= kZ ? "coordinate" : shown(p.name) + " value") +
                               " is not a finite number");
          }
          b->slots[p.slot] = v;
        }
        continue;
      }
      if (c->left() < size_of(p.count_type))
        return fail(i, "the file ends in list " + shown(p.name));
      const double n = decode(c->take(size_of(p.count_type)), p.count_type, h.big_endian);
      if (n < 0 || n * static_cast<double>(size_of(p.type)) > static_cast<double>(c->left())) {
        return fail(i, shown(p.name) + " length " + std::to_string(static_cast<int64_t>(n)) +
                           " does not fit in the rest of the file");
      }
      if (p.indices && n > static_cast<double>(kMaxMeshTriangles + 2)) {
        return fail(i, "a face with " + std::to_string(static_cast<int64_t>(n)) +
                           " vertices is more than the limit of triangles allows");
      }
      for (int64_t k = 0; k < static_cast<int64_t>(n); ++k) {
        const double v = decode(c->take(size_of(p.type)), p.type, h.big_endian);
        if (!p.indices) continue;
        if (Problem pr = b->index(static_cast<int64_t>(v))) return fail(i, *pr);
      }
    }
    if (vertex) b->end_vertex();
    if (e.name == "face") {
      if (Problem pr = b->end_face()) return fail(i, *pr);
    }
  }
  return {};
}

}  // namespace

Result<TriangleMesh> read_ply(const fs::path& file) {
  LineReader r(file, '\0');
  Result<Header> header = read_header(r);
  if (!header.ok()) return header.diagnostics().front();
  const Header& h = header.value();
  if (Status layout = check_layout(file, h); !layout.ok()) return layout.diagnostics().front();
  Builder b;
  if (h.ascii) {
    for (const Element& e : h.elements) {
      b.begin_element(e);
      if (Status s = read_ascii_element(r, e, &b); !s.ok()) return s.diagnostics().front();
      if (e.name == "vertex") b.vertex_count = e.count;
    }
    return std::move(b.mesh);
  }
  std::string bytes;
  // -1 when 'end_header' ended the file without a newline: no body then.
  const std::streamoff body = r.offset_after_line();
  if (body >= 0) {
    std::ifstream in(file, std::ios::binary);
    in.seekg(body);
    if (in) bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ByteCursor c{bytes, 0, std::max<int64_t>(static_cast<int64_t>(body), 0)};
  for (const Element& e : h.elements) {
    b.begin_element(e);
    if (Status s = read_binary_element(file, h, e, &c, &b); !s.ok()) {
      return s.diagnostics().front();
    }
    if (e.name == "vertex") b.vertex_count = e.count;
  }
  return std::move(b.mesh);
}

}  // namespace lap::sim
