#include "sim/setup/mesh_loader.h"

#include <tiny_gltf.h>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/bounded_file.h"
#include "haptics/setup/mesh_repair.h"
#include "sim/setup/gltf_references.h"
#include "sim/setup/json_lines.h"
#include "sim/setup/load_error.h"
#include "sim/setup/mesh_limits.h"
#include "sim/setup/mesh_text_check.h"
#include "sim/setup/ply_reader.h"

namespace lap::sim {
namespace {

using haptics::TriangleMesh;

// Records what OpenMesh's readers parse, as it is: the half-edge ImporterT would drop degenerate
// faces and split non-manifold ones, hiding exactly the defects validation must report.
class CapturingImporter final : public OpenMesh::IO::BaseImporter {
 public:
  using VH = OpenMesh::VertexHandle;
  using FH = OpenMesh::FaceHandle;
  using HH = OpenMesh::HalfedgeHandle;
  using EH = OpenMesh::EdgeHandle;

  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;
  std::vector<bool> has_normal;
  std::vector<Eigen::Vector2d> uvs;
  std::vector<bool> has_uv;
  std::vector<std::vector<int32_t>> faces;

  VH add_vertex(const OpenMesh::Vec3f& p) override { return add_vertex(OpenMesh::Vec3d(p)); }
  VH add_vertex(const OpenMesh::Vec3d& p) override {
    points.emplace_back(p[0], p[1], p[2]);
    normals.emplace_back(Eigen::Vector3d::Zero());
    has_normal.push_back(false);
    uvs.emplace_back(Eigen::Vector2d::Zero());
    has_uv.push_back(false);
    return VH(static_cast<int>(points.size()) - 1);
  }
  VH add_vertex() override { return add_vertex(OpenMesh::Vec3d(0, 0, 0)); }
  HH add_edge(VH, VH) override { return HH(); }
  FH add_face(const VHandles& idx) override {
    std::vector<int32_t> f;
    f.reserve(idx.size());
    for (const VH& v : idx) f.push_back(v.idx());
    faces.push_back(std::move(f));
    return FH(static_cast<int>(faces.size()) - 1);
  }
  FH add_face(HH) override { return FH(); }
  void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(FH, int) override {}
  void set_point(VH v, const OpenMesh::Vec3f& p) override {
    if (valid(v)) points[v.idx()] = Eigen::Vector3d(p[0], p[1], p[2]);
  }
  void set_halfedge(VH, HH) override {}
  void set_normal(VH v, const OpenMesh::Vec3f& n) override { set_normal(v, OpenMesh::Vec3d(n)); }
  void set_normal(VH v, const OpenMesh::Vec3d& n) override {
    if (!valid(v)) return;
    normals[v.idx()] = Eigen::Vector3d(n[0], n[1], n[2]);
    has_normal[v.idx()] = true;
  }
  void set_color(VH, const OpenMesh::Vec3uc&) override {}
  void set_color(VH, const OpenMesh::Vec4uc&) override {}
  void set_color(VH, const OpenMesh::Vec3f&) override {}
  void set_color(VH, const OpenMesh::Vec4f&) override {}
  void set_texcoord(VH v, const OpenMesh::Vec2f& uv) override {
    if (!valid(v)) return;
    uvs[v.idx()] = Eigen::Vector2d(uv[0], uv[1]);
    has_uv[v.idx()] = true;
  }
  void set_status(VH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HH, HH) override {}
  void set_face(HH, FH) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HH, const OpenMesh::Vec2f&) override {}
  void set_texcoord(VH v, const OpenMesh::Vec3f& uv) override {
    set_texcoord(v, OpenMesh::Vec2f(uv[0], uv[1]));
  }
  void set_texcoord(HH, const OpenMesh::Vec3f&) override {}
  void set_status(HH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(EH, const OpenMesh::Vec3uc&) override {}
  void set_color(EH, const OpenMesh::Vec4uc&) override {}
  void set_color(EH, const OpenMesh::Vec3f&) override {}
  void set_color(EH, const OpenMesh::Vec4f&) override {}
  void set_status(EH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FH, const OpenMesh::Vec3f&) override {}
  void set_normal(FH, const OpenMesh::Vec3d&) override {}
  void set_color(FH, const OpenMesh::Vec3uc&) override {}
  void set_color(FH, const OpenMesh::Vec4uc&) override {}
  void set_color(FH, const OpenMesh::Vec3f&) override {}
  void set_color(FH, const OpenMesh::Vec4f&) override {}
  void set_status(FH, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  bool is_triangle_mesh() const override { return false; }
  size_t n_vertices() const override { return points.size(); }
  size_t n_faces() const override { return faces.size(); }
  size_t n_edges() const override { return 0; }

 private:
  bool valid(VH v) const { return v.idx() >= 0 && static_cast<size_t>(v.idx()) < points.size(); }
};

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

TriangleMesh load_with_openmesh(const std::filesystem::path& file) {
  CapturingImporter importer;
  OpenMesh::IO::Options options;
  options += OpenMesh::IO::Options::VertexNormal;
  options += OpenMesh::IO::Options::VertexTexCoord;
  // OpenMesh reports its own parse errors on stderr; we turn failure into one clear message.
  if (!OpenMesh::IO::IOManager().read(file.string(), importer, options)) {
    throw LoadError(file,
                    "the mesh reader could not parse this file (expected a "
                    "valid " +
                        lower_extension(file).substr(1) + " mesh)");
  }
  TriangleMesh mesh;
  mesh.positions = std::move(importer.points);
  for (const auto& face : importer.faces) {
    // Fan polygons into triangles; n-gons from OBJ/OFF/PLY are planar in practice.
    for (size_t k = 1; k + 1 < face.size(); ++k)
      mesh.triangles.push_back({face[0], face[k], face[k + 1]});
  }
  const bool all_normals =
      !importer.has_normal.empty() &&
      std::all_of(importer.has_normal.begin(), importer.has_normal.end(), [](bool b) { return b; });
  if (all_normals && options.vertex_has_normal()) mesh.normals = std::move(importer.normals);
  const bool all_uvs =
      !importer.has_uv.empty() &&
      std::all_of(importer.has_uv.begin(), importer.has_uv.end(), [](bool b) { return b; });
  if (all_uvs) mesh.uvs = std::move(importer.uvs);
  return mesh;
}

// --- glTF 2.0 ---

Eigen::Affine3d node_local_transform(const tinygltf::Node& node) {
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  if (node.matrix.size() == 16) {
    Eigen::Matrix4d m;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) m(r, c) = node.matrix[c * 4 + r];  // column-major
    }
    T.matrix() = m;
    return T;
  }
  if (node.translation.size() == 3) {
    T.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  }
  if (node.rotation.size() == 4) {  // glTF quaternions are (x, y, z, w)
    T.rotate(
        Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2])
            .normalized());
  }
  if (node.scale.size() == 3) {
    T.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  }
  return T;
}

class GltfReader {
 public:
  GltfReader(const tinygltf::Model& model, std::string file)
      : model_(model), file_(std::move(file)) {}

  // Reads accessor element i as up to 4 doubles, honouring byteStride and normalisation.
  std::vector<std::array<double, 4>> read(int accessor_index, const std::string& what) const {
    if (accessor_index < 0 || accessor_index >= static_cast<int>(model_.accessors.size())) {
      fail(what + ": accessor index " + std::to_string(accessor_index) + " does not exist");
    }
    const tinygltf::Accessor& acc = model_.accessors[accessor_index];
    if (acc.sparse.isSparse) fail(what + ": sparse accessors are not supported");
    const int ncomp = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type));
    const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType));
    if (ncomp < 1 || ncomp > 4 || csize < 1) fail(what + ": unsupported accessor type");
    // Three indices per triangle is the most any accessor of a mesh within the limits needs.
    if (acc.count > static_cast<size_t>(3 * kMaxMeshTriangles)) {
      fail(what + ": " + std::to_string(acc.count) + " elements is more than the limit of " +
           std::to_string(3 * kMaxMeshTriangles) + " (sim/setup/mesh_limits.h)");
    }
    if (acc.bufferView < 0) {  // all zeros per the specification
      return std::vector<std::array<double, 4>>(acc.count, std::array<double, 4>{0, 0, 0, 0});
    }
    if (acc.bufferView >= static_cast<int>(model_.bufferViews.size())) {
      fail(what + ": buffer view " + std::to_string(acc.bufferView) + " does not exist");
    }
    const tinygltf::BufferView& view = model_.bufferViews[acc.bufferView];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size())) {
      fail(what + ": buffer " + std::to_string(view.buffer) + " does not exist");
    }
    const tinygltf::Buffer& buffer = model_.buffers[view.buffer];
    const size_t element = static_cast<size_t>(ncomp) * static_cast<size_t>(csize);
    const size_t stride = view.byteStride > 0 ? view.byteStride : element;
    const size_t size = buffer.data.size();
    // In this order so that no sum or product can wrap around (count and offsets are the
    // file's).
    const bool fits =
        view.byteOffset <= size && acc.byteOffset <= size - view.byteOffset &&
        element <= size - view.byteOffset - acc.byteOffset &&
        (acc.count == 0 ||
         acc.count - 1 <= (size - view.byteOffset - acc.byteOffset - element) / stride);
    if (acc.count > 0 && !fits) fail(what + ": accessor reads past the end of its buffer");
    const size_t begin = view.byteOffset + acc.byteOffset;
    std::vector<std::array<double, 4>> out(acc.count, std::array<double, 4>{0, 0, 0, 0});
    for (size_t i = 0; i < acc.count; ++i) {
      const unsigned char* p = buffer.data.data() + begin + i * stride;
      for (int c = 0; c < ncomp; ++c)
        out[i][c] =
            component(p + static_cast<ptrdiff_t>(c) * csize, acc.componentType, acc.normalized);
    }
    return out;
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw LoadError(std::filesystem::path(file_), message);
  }

 private:
  static double component(const unsigned char* p, int type, bool normalized) {
    auto get = [p](auto tag) {
      decltype(tag) v;
      std::memcpy(&v, p, sizeof(v));
      return v;
    };
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return get(float{});
      case TINYGLTF_COMPONENT_TYPE_DOUBLE:
        return get(double{});
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        const double v = get(uint8_t{});
        return normalized ? v / 255.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const double v = get(int8_t{});
        return normalized ? std::max(v / 127.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        const double v = get(uint16_t{});
        return normalized ? v / 65535.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        const double v = get(int16_t{});
        return normalized ? std::max(v / 32767.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return get(uint32_t{});
      case TINYGLTF_COMPONENT_TYPE_INT:
        return get(int32_t{});
      default:
        return 0.0;
    }
  }

  const tinygltf::Model& model_;
  std::string file_;
};

void append_primitive(const GltfReader& reader, const tinygltf::Primitive& prim,
                      const Eigen::Affine3d& T, const std::string& where, TriangleMesh& out) {
  const auto pos_it = prim.attributes.find("POSITION");
  if (pos_it == prim.attributes.end()) reader.fail(where + ": primitive has no POSITION attribute");
  const auto positions = reader.read(pos_it->second, where + ".POSITION");
  TriangleMesh part;
  part.positions.reserve(positions.size());
  for (const auto& p : positions)
    part.positions.emplace_back(T * Eigen::Vector3d(p[0], p[1], p[2]));
  if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
    const Eigen::Matrix3d N = T.linear().inverse().transpose();
    for (const auto& n : reader.read(it->second, where + ".NORMAL")) {
      part.normals.emplace_back((N * Eigen::Vector3d(n[0], n[1], n[2])).normalized());
    }
  }
  if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
    for (const auto& uv : reader.read(it->second, where + ".TEXCOORD_0"))
      part.uvs.emplace_back(uv[0], uv[1]);
  }
  std::vector<int64_t> idx;
  if (prim.indices >= 0) {
    for (const auto& i : reader.read(prim.indices, where + ".indices")) {
      // glTF's indices are unsigned integers; an accessor of floats could hold anything (a
      // cast of 1e30 is undefined: found by fuzzing).
      if (!(i[0] >= 0.0 && i[0] <= static_cast<double>(INT32_MAX) && i[0] == std::floor(i[0]))) {
        reader.fail(where + ".indices: " + std::to_string(i[0]) +
                    " is not a vertex index (expected whole numbers from 0)");
      }
      idx.push_back(static_cast<int64_t>(i[0]));
    }
  } else {
    for (size_t i = 0; i < positions.size(); ++i) idx.push_back(static_cast<int64_t>(i));
  }
  for (int64_t i : idx) {
    if (i < 0 || i >= static_cast<int64_t>(positions.size())) {
      reader.fail(where + ": index " + std::to_string(i) + " is outside the " +
                  std::to_string(positions.size()) + " vertices");
    }
  }
  auto tri = [&](int64_t a, int64_t b, int64_t c) {
    part.triangles.push_back(
        {static_cast<int32_t>(a), static_cast<int32_t>(b), static_cast<int32_t>(c)});
  };
  switch (prim.mode) {
    case -1:
    case TINYGLTF_MODE_TRIANGLES:
      if (idx.size() % 3 != 0) reader.fail(where + ": triangle index count is not a multiple of 3");
      for (size_t i = 0; i + 2 < idx.size(); i += 3) tri(idx[i], idx[i + 1], idx[i + 2]);
      break;
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      for (size_t i = 0; i + 2 < idx.size(); ++i) {
        if (i % 2 == 0)
          tri(idx[i], idx[i + 1], idx[i + 2]);
        else
          tri(idx[i + 1], idx[i], idx[i + 2]);
      }
      break;
    case TINYGLTF_MODE_TRIANGLE_FAN:
      for (size_t i = 1; i + 1 < idx.size(); ++i) tri(idx[0], idx[i], idx[i + 1]);
      break;
    default:
      return;  // points and lines carry no surface
  }
  if (T.linear().determinant() < 0.0) {
    for (auto& t : part.triangles) std::swap(t[1], t[2]);
  }
  // A primitive without normals gets angle-weighted ones, so that a file mixing primitives with
  // and without normals keeps the ones it has (append() keeps an array only if all parts have it).
  if (part.normals.size() != part.positions.size()) part.compute_vertex_normals();
  if (part.uvs.size() != part.positions.size()) part.uvs.clear();
  if (out.positions.empty()) {
    out = std::move(part);
  } else {
    out.append(part);
  }
}

void visit_node(const tinygltf::Model& model, const GltfReader& reader, int node_index,
                const Eigen::Affine3d& parent, int depth, TriangleMesh& out) {
  if (node_index < 0 || node_index >= static_cast<int>(model.nodes.size())) {
    reader.fail("node " + std::to_string(node_index) + " does not exist");
  }
  if (depth > 256) reader.fail("node hierarchy deeper than 256 levels (a cycle?)");
  const tinygltf::Node& node = model.nodes[node_index];
  const Eigen::Affine3d T = parent * node_local_transform(node);
  if (node.mesh >= 0) {
    if (node.mesh >= static_cast<int>(model.meshes.size())) {
      reader.fail("node " + std::to_string(node_index) + ": mesh " + std::to_string(node.mesh) +
                  " does not exist");
    }
    const tinygltf::Mesh& mesh = model.meshes[node.mesh];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      append_primitive(reader, mesh.primitives[p], T,
                       "mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(p),
                       out);
    }
  }
  for (int child : node.children) visit_node(model, reader, child, T, depth + 1, out);
}

// tinygltf's file access, its reading confined to the glTF's folder (user_data: the folder).
// The checks on the JSON name the field first; these catch what they cannot see (symbolic
// links; tinygltf also looks in the working folder).
std::string unexpanded(const std::string& path, void*) { return path; }  // no ~ or $VAR
bool confined_read(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void* folder) {
  if (!inside_folder(*static_cast<const std::filesystem::path*>(folder), path)) {
    *err = "'" + path + "' is outside the scene's folder";
    return false;
  }
  // A regular file within the limit only: a FIFO or /dev/zero linked into the folder would
  // block or never end.
  const Result<std::string> bytes =
      read_bounded_file(path, kMaxGltfBufferBytes, "a glTF buffer", "sim/setup/mesh_limits.h");
  if (!bytes.ok()) {
    *err = bytes.message();
    return false;
  }
  out->assign(bytes.value().begin(), bytes.value().end());
  return true;
}
// Whether a referenced file is there, by its status: tinygltf's own opens it to see, and opening
// a FIFO blocks until someone writes to it. What is there is then read through confined_read,
// which names what is wrong with it (outside the folder, not a regular file, too large).
bool confined_exists(const std::string& path, void* /*folder*/) {
  std::error_code ec;
  return std::filesystem::exists(std::filesystem::status(path, ec));
}
bool no_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  *err = "writing is not allowed";
  return false;
}
// Textures are not used: images are not decoded (an untrusted image's header alone can ask for
// gigabytes).
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;
}

TriangleMesh load_gltf(const std::filesystem::path& file) {
  const bool binary = lower_extension(file) == ".glb";
  std::vector<unsigned char> bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  if (Status refs = check_gltf_references(file, gltf_json_text(bytes, binary), binary);
      !refs.ok()) {
    throw LoadError(refs.diagnostics().front());
  }
  std::filesystem::path folder = std::filesystem::absolute(file).parent_path();
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&confined_exists, &unexpanded, &confined_read, &no_write, &folder});
  loader.SetImageLoader(&skip_image, nullptr);
  tinygltf::Model model;
  std::string err;
  std::string warn;
  // The bytes checked above are the ones parsed (the file may change in between).
  const auto length = static_cast<unsigned int>(bytes.size());  // within kMaxMeshFileBytes
  bool ok = false;
  // tinygltf may throw on inputs its checks miss (a std::vector::at on an empty buffer was one,
  // found by fuzzing): whatever it throws is this file's problem, not a crash.
  try {
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), length,
                                              folder.string())
                : loader.LoadASCIIFromString(&model, &err, &warn,
                                             reinterpret_cast<const char*>(bytes.data()), length,
                                             folder.string());
  } catch (const std::exception& e) {
    throw LoadError(
        file, std::string("not a valid glTF 2.0 file: the reader stopped (") + e.what() + ")");
  }
  if (!ok) {
    throw LoadError(file, "not a valid glTF 2.0 file: " + (err.empty() ? warn : err));
  }
  GltfReader reader(model, file.string());
  TriangleMesh out;
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int s = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (s >= static_cast<int>(model.scenes.size())) {  // found by fuzzing: an uncaught throw
      const int line = binary ? 0 : JsonLines::scan(gltf_json_text(bytes, binary)).line("scene");
      throw LoadError(Diagnostic{file.string(), line, "scene",
                                 "scene " + std::to_string(s) + " does not exist (the file has " +
                                     std::to_string(model.scenes.size()) + ")"});
    }
    roots = model.scenes[static_cast<size_t>(s)].nodes;
  } else {
    // No scene: every node that is nobody's child is a root.
    std::vector<bool> is_child(model.nodes.size(), false);
    for (const auto& n : model.nodes) {
      for (int c : n.children) {
        if (c >= 0 && c < static_cast<int>(is_child.size())) is_child[c] = true;
      }
    }
    for (size_t i = 0; i < model.nodes.size(); ++i) {
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
    }
  }
  for (int r : roots) visit_node(model, reader, r, Eigen::Affine3d::Identity(), 0, out);
  if (model.nodes.empty()) {
    // A file with meshes but no nodes: take every mesh untransformed.
    for (size_t m = 0; m < model.meshes.size(); ++m) {
      for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
        append_primitive(reader, model.meshes[m].primitives[p], Eigen::Affine3d::Identity(),
                         "mesh " + std::to_string(m) + " primitive " + std::to_string(p), out);
      }
    }
  }
  return out;
}

}  // namespace

namespace {

// What every reader's result must be, whatever the format: within the limits, finite, every
// index in range (binary files, and anything the line checks could not see).
void check_loaded(const std::filesystem::path& file, const TriangleMesh& mesh) {
  const auto fail = [&](const std::string& field, const std::string& what) {
    throw LoadError(Diagnostic{file.string(), 0, field, what});
  };
  if (mesh.positions.size() > static_cast<size_t>(kMaxMeshVertices)) {
    fail("vertices", std::to_string(mesh.positions.size()) + " is more than the limit of " +
                         std::to_string(kMaxMeshVertices) + " (sim/setup/mesh_limits.h)");
  }
  if (mesh.triangles.size() > static_cast<size_t>(kMaxMeshTriangles)) {
    fail("triangles", std::to_string(mesh.triangles.size()) + " is more than the limit of " +
                          std::to_string(kMaxMeshTriangles) + " (sim/setup/mesh_limits.h)");
  }
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    for (int k = 0; k < 3; ++k) {
      const double x = mesh.positions[v][k];
      if (!std::isfinite(x)) {
        std::ostringstream text;
        text << x;
        fail("vertices[" + std::to_string(v) + "]",
             "coordinate '" + text.str() + "' is not a finite number");
      }
    }
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int32_t v : mesh.triangles[t]) {
      if (v < 0 || v >= mesh.vertex_count()) {
        fail("triangles[" + std::to_string(t) + "]",
             "vertex index " + std::to_string(v) + " is outside the " +
                 std::to_string(mesh.vertex_count()) + " vertices");
      }
    }
  }
}

TriangleMesh read_mesh(const std::filesystem::path& file, const MeshLoadSettings& settings) {
  // A regular file within the limit (a FIFO or /dev/zero would block or never end).
  if (Status ok =
          check_regular_file(file, kMaxMeshFileBytes, "a mesh file", "sim/setup/mesh_limits.h");
      !ok.ok()) {
    throw LoadError(ok.diagnostics().front());
  }
  if (!(settings.scale > 0.0) || !std::isfinite(settings.scale)) {
    throw LoadError(file, "scale must be a positive finite number");
  }
  const std::string ext = lower_extension(file);
  TriangleMesh mesh;
  if (ext == ".ply") {
    Result<TriangleMesh> ply = read_ply(file);
    if (!ply.ok()) throw LoadError(ply.diagnostics().front());
    mesh = std::move(ply).value();
  } else if (ext == ".obj" || ext == ".stl" || ext == ".off") {
    if (Status text = check_mesh_text(file, ext); !text.ok()) {
      throw LoadError(text.diagnostics().front());
    }
    mesh = load_with_openmesh(file);
  } else if (ext == ".gltf" || ext == ".glb") {
    mesh = load_gltf(file);
  } else {
    throw LoadError(file, "unsupported mesh format '" + ext +
                              "' (expected .obj, .stl, .ply, .off, .gltf or .glb)");
  }
  check_loaded(file, mesh);
  if (mesh.triangles.empty()) throw LoadError(file, "the file contains no triangles");
  mesh.scale(settings.scale);
  haptics::weld_vertices(mesh, settings.weld_tolerance);
  return mesh;
}

}  // namespace

Result<TriangleMesh> load_mesh(const std::filesystem::path& file,
                               const MeshLoadSettings& settings) {
  try {
    return read_mesh(file, settings);
  } catch (const LoadError& e) {
    return e.diagnostic();
  }
}

Status save_obj(const haptics::TriangleMesh& mesh, const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) return Diagnostic{file.string(), 0, "", "cannot open for writing"};
  out.precision(9);
  out << "# written by laptrainer\n";
  for (const auto& p : mesh.positions) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  const bool n = mesh.normals.size() == mesh.positions.size();
  const bool t = mesh.uvs.size() == mesh.positions.size();
  if (n) {
    for (const auto& v : mesh.normals)
      out << "vn " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  }
  if (t) {
    for (const auto& v : mesh.uvs) out << "vt " << v.x() << ' ' << v.y() << '\n';
  }
  for (const auto& tri : mesh.triangles) {
    out << 'f';
    for (int32_t v : tri) {
      out << ' ' << v + 1;
      if (t || n)
        out << '/' << (t ? std::to_string(v + 1) : "") << (n ? "/" + std::to_string(v + 1) : "");
    }
    out << '\n';
  }
  if (!out) return Diagnostic{file.string(), 0, "", "write failed"};
  return {};
}

}  // namespace lap::sim
