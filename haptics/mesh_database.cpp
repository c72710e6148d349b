#include "haptics/mesh_database.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <numeric>
#include <span>
#include <stdexcept>

#include "haptics/closest_point.h"
#include "haptics/corner_angle.h"
#include "haptics/segment_triangle.h"

namespace lap::haptics {

const char* to_string(PrimitiveKind kind) {
  switch (kind) {
    case PrimitiveKind::kVertex:
      return "vertex";
    case PrimitiveKind::kEdge:
      return "edge";
    case PrimitiveKind::kFace:
      return "face";
    case PrimitiveKind::kNone:
      break;
  }
  return "none";
}

namespace {

// Vertex -> faces (CSR), needed only while building.
struct FacesAroundVertices {
  std::vector<int32_t> start;   // n_v + 1
  std::vector<int32_t> around;  // 3 n_f
  [[nodiscard]] std::span<const int32_t> of(int32_t v) const {
    return std::span<const int32_t>(around.data() + start[v],
                                    static_cast<size_t>(start[v + 1] - start[v]));
  }
};

FacesAroundVertices faces_around_vertices(const std::vector<std::array<int32_t, 3>>& faces,
                                          int32_t nv) {
  FacesAroundVertices r;
  r.start.assign(static_cast<size_t>(nv) + 1, 0);
  for (const auto& t : faces) {
    for (int32_t v : t) ++r.start[v + 1];
  }
  std::partial_sum(r.start.begin(), r.start.end(), r.start.begin());
  r.around.resize(static_cast<size_t>(3) * faces.size());
  std::vector<int32_t> fill(r.start.begin(), r.start.end() - 1);
  for (int32_t f = 0; f < static_cast<int32_t>(faces.size()); ++f) {
    for (int32_t v : faces[f]) r.around[fill[v]++] = f;
  }
  return r;
}

[[noreturn]] void fail_edge(int32_t a, int32_t b, const char* what) {
  throw std::invalid_argument("mesh edge " + std::to_string(a) + "-" + std::to_string(b) + " " +
                              what + " (validate and repair first)");
}

}  // namespace

// The faces around one vertex v while building, as corners, and how they pair across v's edges;
// sized once for the largest fan.
struct MeshDatabase::Fan {
  struct Corner {
    int32_t face;
    int32_t next;  // vertex after v in the face
    int32_t prev;  // vertex before v in the face
    int32_t j;     // v's corner index
  };
  int32_t size = 0;
  std::vector<Corner> corner = std::vector<Corner>(kMaxFan);
  // successor[i]: the corner whose face enters v from corner i's next vertex (-1 on a boundary);
  // predecessors[i]: how many corners have i as their successor.
  std::vector<int32_t> successor = std::vector<int32_t>(kMaxFan);
  std::vector<int32_t> predecessors = std::vector<int32_t>(kMaxFan);
};

MeshDatabase MeshDatabase::build(const TriangleMesh& mesh, const MeshDatabaseSettings& settings) {
  MeshDatabase db;
  db.positions_ = mesh.positions;
  db.build_tree(mesh, settings.max_leaf_faces);
  db.build_edges_and_fans();
  db.vertex_normals_.resize(mesh.vertex_count());
  db.face_normals_.resize(db.face_vertices_.size());
  db.update_normals();
  return db;
}

// Tree first, so that faces can be stored in tree order; its boxes come from the refit.
void MeshDatabase::build_tree(const TriangleMesh& mesh, int32_t max_leaf_faces) {
  const int32_t nf = mesh.triangle_count();
  {
    std::vector<Eigen::Vector3d> centres(nf);
    for (int32_t f = 0; f < nf; ++f) {
      const Triangle& t = mesh.triangles[f];
      centres[f] = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
    }
    tree_.build(centres, max_leaf_faces, &original_face_);
  }
  face_vertices_.resize(nf);
  for (int32_t f = 0; f < nf; ++f) face_vertices_[f] = mesh.triangles[original_face_[f]];
  refit_tree();
}

// Edges and fans, one vertex at a time over its own faces only. In face g, v's corner has an
// outgoing half-edge v -> next and an incoming one prev -> v. The undirected edge {v, w} with
// v < w pairs the face leaving v towards w with the face entering v from w; a face with no
// partner lies on a boundary. The same pairing (g -> the face entering v from g's next) must
// chain all of v's faces into one fan.
void MeshDatabase::build_edges_and_fans() {
  const int32_t nv = vertex_count();
  const int32_t nf = face_count();
  const FacesAroundVertices around = faces_around_vertices(face_vertices_, nv);
  face_edges_.assign(nf, {-1, -1, -1});
  edge_vertices_.reserve(static_cast<size_t>(nf) * 3 / 2 + 16);
  edge_faces_.reserve(static_cast<size_t>(nf) * 3 / 2 + 16);
  vertex_face_.assign(nv, -1);
  Fan fan;
  for (int32_t v = 0; v < nv; ++v) {
    gather_fan(v, around.of(v), &fan);
    pair_fan(v, &fan);
    add_edges_owned_by(v, fan);
    vertex_face_[v] = fan.corner[first_corner_of_single_fan(v, fan)].face;
  }
  // A closed mesh has exactly 3F/2 edges, the capacity reserved: shrink only open meshes with
  // real slack (shrinking copies the arrays).
  if (edge_vertices_.capacity() > edge_vertices_.size() + edge_vertices_.size() / 8) {
    edge_vertices_.shrink_to_fit();
    edge_faces_.shrink_to_fit();
  }
}

void MeshDatabase::gather_fan(int32_t v, std::span<const int32_t> faces, Fan* fan) const {
  const auto d = static_cast<int32_t>(faces.size());
  if (d == 0) {
    throw std::invalid_argument("mesh vertex " + std::to_string(v) +
                                " is used by no face (remove unreferenced vertices)");
  }
  if (d > kMaxFan) {
    throw std::invalid_argument("mesh vertex " + std::to_string(v) + " has more than " +
                                std::to_string(kMaxFan) + " faces");
  }
  fan->size = d;
  for (int32_t i = 0; i < d; ++i) {
    const auto& t = face_vertices_[faces[i]];
    const int j = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
    fan->corner[i] = {faces[i], t[(j + 1) % 3], t[(j + 2) % 3], j};
    fan->successor[i] = -1;
    fan->predecessors[i] = 0;
  }
}

void MeshDatabase::pair_fan(int32_t v, Fan* fan) {
  const int32_t d = fan->size;
  const std::vector<Fan::Corner>& corner = fan->corner;
  std::vector<int32_t>& successor = fan->successor;
  std::vector<int32_t>& predecessors = fan->predecessors;
  // successor[i]: the face entering v from corner i's next vertex (-1 on a boundary).
  for (int32_t i = 0; i < d; ++i) {
    for (int32_t k = 0; k < d; ++k) {
      if (k == i) continue;
      if (corner[k].next == corner[i].next) {
        fail_edge(v, corner[i].next, "joins faces of opposite orientation");
      }
      if (corner[k].prev != corner[i].next) continue;
      if (successor[i] >= 0) fail_edge(v, corner[i].next, "has more than two faces");
      successor[i] = k;
    }
    if (successor[i] >= 0) ++predecessors[successor[i]];
  }
  for (int32_t i = 0; i < d; ++i) {
    if (predecessors[i] > 1) fail_edge(corner[i].prev, v, "has more than two faces");
  }
}

// Edges owned by v (v < w): outgoing v -> w paired with its successor, and incoming w -> v that
// no face leaves v towards (a boundary).
void MeshDatabase::add_edges_owned_by(int32_t v, const Fan& fan) {
  for (int32_t i = 0; i < fan.size; ++i) {
    const Fan::Corner& c = fan.corner[i];
    if (v < c.next) {
      const auto e = static_cast<int32_t>(edge_vertices_.size());
      edge_vertices_.push_back({v, c.next});
      face_edges_[c.face][c.j] = e;
      if (fan.successor[i] >= 0) {
        const Fan::Corner& h = fan.corner[fan.successor[i]];
        edge_faces_.push_back({c.face, h.face});
        face_edges_[h.face][(h.j + 2) % 3] = e;
      } else {
        edge_faces_.push_back({c.face, -1});
        ++boundary_edges_;
      }
    }
    if (v < c.prev && fan.predecessors[i] == 0) {
      const auto e = static_cast<int32_t>(edge_vertices_.size());
      edge_vertices_.push_back({v, c.prev});
      edge_faces_.push_back({c.face, -1});
      face_edges_[c.face][(c.j + 2) % 3] = e;
      ++boundary_edges_;
    }
  }
}

// One fan: following successors from a face with no predecessor (any face, if the fan is
// closed) reaches every face. Returns that first corner.
int32_t MeshDatabase::first_corner_of_single_fan(int32_t v, const Fan& fan) {
  const int32_t d = fan.size;
  int32_t first = 0;
  for (int32_t i = 0; i < d; ++i) {
    if (fan.predecessors[i] == 0) {
      first = i;
      break;
    }
  }
  int32_t walked = 0;
  for (int32_t i = first; i >= 0 && walked <= d; i = fan.successor[i]) {
    ++walked;
    if (fan.successor[i] == first) break;
  }
  if (walked != d) {
    throw std::invalid_argument("mesh vertex " + std::to_string(v) +
                                " is non-manifold (its faces form several fans; repair first)");
  }
  return first;
}

Eigen::Vector3d MeshDatabase::compute_face_normal(int32_t f) const {
  const auto& t = face_vertices_[f];
  const Eigen::Vector3d n =
      (positions_[t[1]] - positions_[t[0]]).cross(positions_[t[2]] - positions_[t[0]]);
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitY();
}

Eigen::Vector3d MeshDatabase::edge_normal(int32_t e) const {
  const auto& f = edge_faces_[e];
  Eigen::Vector3d n = face_normal(f[0]);
  if (f[1] >= 0) n += face_normal(f[1]);
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : face_normal(f[0]);
}

Eigen::Vector3d MeshDatabase::normal(PrimitiveRef p) const {
  switch (p.kind) {
    case PrimitiveKind::kVertex:
      return vertex_normals_[p.index];
    case PrimitiveKind::kEdge:
      return edge_normal(p.index);
    case PrimitiveKind::kFace:
      return face_normal(p.index);
    case PrimitiveKind::kNone:
      break;
  }
  return Eigen::Vector3d::UnitY();
}

namespace {

// A face's unit normal and the angles at its corners (§4.2: the vertex normals weight each face
// by the angle it subtends at the vertex). A degenerate face gets +y (as compute_face_normal())
// and zero angles, so it adds nothing. The three angles share |e1 x e2| (twice the area) and sum
// to pi, so two arctangents suffice.
struct FaceShape {
  Eigen::Vector3d unit;
  std::array<double, 3> angle;
};

// The parts of face_shape() before the arctangents.
struct FaceParts {
  Eigen::Vector3d unit;
  double twice_area;  // 0 for a degenerate face
  double dot_a;       // (b - a).(c - a)
  double dot_b;       // (a - b).(c - b)
};

// u / len, the first two components as one packed division: the same quotients bit for bit
// (IEEE division is correctly rounded either way), for one pass through the divider instead of
// two. The normal updates are bound by the divider's throughput (seven divisions and a square
// root per face).
inline Eigen::Vector3d divided(const Eigen::Vector3d& u, double len) {
  const Eigen::Array2d xy = Eigen::Array2d(u.x(), u.y()) / len;
  return {xy[0], xy[1], u.z() / len};
}

inline FaceParts face_parts(const std::array<int32_t, 3>& t,
                            const std::vector<Eigen::Vector3d>& p) {
  const Eigen::Vector3d& a = p[t[0]];
  const Eigen::Vector3d& b = p[t[1]];
  const Eigen::Vector3d& c = p[t[2]];
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d bc = c - b;
  const Eigen::Vector3d n = ab.cross(ac);
  const double twice_area = n.norm();
  if (!(twice_area > 0.0)) return {Eigen::Vector3d::UnitY(), 0.0, 0.0, 0.0};
  return {divided(n, twice_area), twice_area, ab.dot(ac), -ab.dot(bc)};
}

// The corner angles from {twice_area, dot_a, dot_b} (zero for a degenerate face): corner_angle()
// (corner_angle.h) at the first two corners, both at once in the lanes of one vector, the same
// operations in the same order per lane, so the same bits (the incremental-region test of
// tests/haptics/mesh_database_test.cpp checks the vertex normals against corner_angle() bit for
// bit): four divisions in two passes through the divider instead of four. y > 0, so the ratio
// min(y, |x|) / max(y, |x|) is corner_angle()'s y / |x| or |x| / y, in [0, 1]. Always inlined:
// out of line (GCC's choice, with several callers) each call in the loop of arctangents waited
// for the last one's result, about 5 µs of the sliding dent's modelling step.
[[gnu::always_inline]] inline std::array<double, 3> corner_angles(
    const std::array<double, 3>& y_dots) {
  constexpr double kPi = 3.14159265358979323846;
  const double y = y_dots[0];
  if (!(y > 0.0)) return {0.0, 0.0, 0.0};
  const Eigen::Array2d x(y_dots[1], y_dots[2]);
  const Eigen::Array2d ax = x.abs();
  const Eigen::Array2d ys = Eigen::Array2d::Constant(y);
  const Eigen::Array2d t = ys.min(ax) / ys.max(ax);
  // detail::atan_unit(t) per lane.
  const Eigen::Array2d nearest = t * detail::kAtanSteps + 0.5;
  const std::array<int, 2> k = {static_cast<int>(nearest[0]), static_cast<int>(nearest[1])};
  const Eigen::Array2d c = Eigen::Array2d(k[0], k[1]) / detail::kAtanSteps;
  const Eigen::Array2d d = (t - c) / (1.0 + t * c);
  const Eigen::Array2d d2 = d * d;
  const Eigen::Array2d series = d * (1.0 + d2 * (-1.0 / 3 + d2 * (1.0 / 5 + d2 * (-1.0 / 7))));
  const auto& table = detail::atan_table();
  const Eigen::Array2d atan_t = Eigen::Array2d(table[k[0]], table[k[1]]) + series;
  std::array<double, 2> angle{};
  for (int i = 0; i < 2; ++i) {
    const double a = y <= ax[i] ? atan_t[i] : 0.5 * kPi - atan_t[i];
    angle[i] = x[i] < 0.0 ? kPi - a : a;
  }
  return {angle[0], angle[1], kPi - angle[0] - angle[1]};
}

inline FaceShape face_shape(const std::array<int32_t, 3>& t,
                            const std::vector<Eigen::Vector3d>& p) {
  const FaceParts parts = face_parts(t, p);
  return {parts.unit, corner_angles({parts.twice_area, parts.dot_a, parts.dot_b})};
}

inline Eigen::Vector3d unit_or_up(const Eigen::Vector3d& n) {
  const double len = n.norm();
  return len > 0.0 ? divided(n, len) : Eigen::Vector3d::UnitY();
}

}  // namespace

void MeshDatabase::update_normals() {
  // Each vertex sums its faces' shares in ascending face order, as the scratch update does.
  for (Eigen::Vector3d& n : vertex_normals_) n.setZero();
  for (int32_t f = 0; f < face_count(); ++f) {
    const auto& t = face_vertices_[f];
    const FaceShape shape = face_shape(t, positions_);
    face_normals_[f] = shape.unit;
    for (int k = 0; k < 3; ++k) vertex_normals_[t[k]] += shape.angle[k] * shape.unit;
  }
  for (Eigen::Vector3d& n : vertex_normals_) n = unit_or_up(n);
}

void MeshDatabase::update_vertex_normal(int32_t v) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for_each_vertex_face(v, [&](int32_t f) {
    const FaceShape shape = face_shape(face_vertices_[f], positions_);
    sum += shape.angle[corner_of(f, v)] * shape.unit;
  });
  vertex_normals_[v] = unit_or_up(sum);
}

void MeshDatabase::refit_tree() {
  tree_.refit([this](int32_t f, RefitBounds* b) {
    for (const int32_t v : face_vertices_[f]) b->add(positions_[v]);
  });
}

MeshDatabase::Crossing MeshDatabase::first_crossing(const Eigen::Vector3d& p0,
                                                    const Eigen::Vector3d& p1,
                                                    bool two_sided) const {
  Crossing c;
  c.face = tree_.first_hit(
      p0, p1,
      [&](int32_t f, double t_max) {
        const auto& v = face_vertices_[f];
        const SegmentCrossing s = segment_crosses_triangle(
            p0, p1, positions_[v[0]], v[0], positions_[v[1]], v[1], positions_[v[2]], v[2]);
        if (!s.hit || !(two_sided || s.from_front) || s.t > t_max) return -1.0;
        c.from_front = s.from_front;  // first_hit keeps exactly the hits with t <= t_max
        return s.t;
      },
      &c.t);
  return c;
}

int32_t MeshDatabase::nearest_face(const Eigen::Vector3d& p, Eigen::Vector3d* q, double* d2) const {
  Eigen::Vector3d best_q = p;
  const int32_t f = tree_.nearest(
      p,
      [&](int32_t k, double best_d2) {
        const auto& v = face_vertices_[k];
        TriangleFeature feature;
        const Eigen::Vector3d c =
            closest_on_triangle(p, positions_[v[0]], positions_[v[1]], positions_[v[2]], &feature);
        const double d = (c - p).squaredNorm();
        if (d < best_d2) best_q = c;
        return d;
      },
      d2);
  if (q != nullptr) *q = best_q;
  return f;
}

void MeshDatabase::move_vertices(std::span<const Eigen::Vector3d> positions) {
  ++revision_;
  std::copy(positions.begin(), positions.end(), positions_.begin());
}

void MeshDatabase::set_positions(std::span<const Eigen::Vector3d> positions) {
  move_vertices(positions);
  update_normals();
  refit_tree();
}

void MeshDatabase::set_positions(std::span<const Eigen::Vector3d> positions,
                                 std::span<const int32_t> moved) {
  for (int32_t v : moved) positions_[v] = positions[v];
  ++revision_;
  // The normals that change are those of the moved vertices and of their neighbours. A vertex
  // next to several moved ones is simply recomputed several times: cheaper, for the few
  // hundred vertices a local deformation moves, than a mark per vertex of the mesh.
  for (int32_t v : moved) {
    for_each_vertex_face(v, [&](int32_t f) {
      face_normals_[f] = compute_face_normal(f);
      for (int32_t w : face_vertices_[f]) update_vertex_normal(w);
    });
  }
  refit_tree();
}

VertexSetDelta::VertexSetDelta(int32_t vertex_count)
    : state(static_cast<size_t>(std::max(vertex_count, 0)), 0) {
  for (auto* list : {&current, &entered, &left, &previous}) list->reserve(state.size());
}

bool VertexSetDelta::update(std::span<const int32_t> list) {
  entered.clear();
  left.clear();
  if (list.size() == current.size() && std::equal(list.begin(), list.end(), current.begin())) {
    return false;
  }
  previous.swap(current);  // no allocation: both keep their reserved capacity
  current.clear();
  for (const int32_t v : list) {
    uint8_t& st = state[static_cast<size_t>(v)];
    if ((st & 2U) != 0) continue;  // listed twice
    st |= 2U;
    current.push_back(v);
    if ((st & 1U) == 0) entered.push_back(v);
  }
  for (const int32_t v : previous) {
    uint8_t& st = state[static_cast<size_t>(v)];
    if ((st & 2U) == 0) left.push_back(v);
    st = 0;
  }
  for (const int32_t v : current) state[static_cast<size_t>(v)] = 1;
  const bool changed = !entered.empty() || !left.empty();
  if (changed) ++version_;
  return changed;
}

void VertexSetDelta::clear() {
  current.clear();
  entered.clear();
  left.clear();
  std::fill(state.begin(), state.end(), uint8_t{0});
  version_ += 2;
}

MeshUpdateScratch::MeshUpdateScratch(const MeshDatabase& db)
    : corner_start(static_cast<size_t>(db.vertex_count()) + 1, 0),
      corners(static_cast<size_t>(db.face_count()) * 3),
      face_angles(static_cast<size_t>(db.face_count())),
      angles_of(&db),
      angles_revision(db.revision()),
      region_of(&db),
      moved(db.vertex_count()),
      face_moved_corners(static_cast<size_t>(db.face_count()), 0),
      vertex_region_faces(static_cast<size_t>(db.vertex_count()), 0),
      face_bits((static_cast<size_t>(db.face_count()) + 63) / 64, 0),
      vertex_bits((static_cast<size_t>(db.vertex_count()) + 63) / 64, 0),
      tree(db.tree()) {
  dirty_faces.reserve(static_cast<size_t>(db.face_count()));
  dirty_vertices.reserve(static_cast<size_t>(db.vertex_count()));
  for (int32_t f = 0; f < db.face_count(); ++f) {
    for (const int32_t v : db.face_vertices(f)) ++corner_start[static_cast<size_t>(v) + 1];
  }
  std::partial_sum(corner_start.begin(), corner_start.end(), corner_start.begin());
  std::vector<int32_t> fill(corner_start.begin(), corner_start.end() - 1);
  for (int32_t f = 0; f < db.face_count(); ++f) {  // ascending faces, so each list is sorted
    const auto& t = db.face_vertices(f);
    for (int k = 0; k < 3; ++k) corners[static_cast<size_t>(fill[t[k]]++)] = 4 * f + k;
  }
  for (int32_t f = 0; f < db.face_count(); ++f) {
    face_angles[static_cast<size_t>(f)] = face_shape(db.face_vertices(f), db.positions_).angle;
  }
}

void MeshUpdateScratch::clear_region() {
  moved.clear();
  std::fill(face_moved_corners.begin(), face_moved_corners.end(), uint8_t{0});
  std::fill(vertex_region_faces.begin(), vertex_region_faces.end(), uint16_t{0});
  std::fill(face_bits.begin(), face_bits.end(), uint64_t{0});
  std::fill(vertex_bits.begin(), vertex_bits.end(), uint64_t{0});
  tree.clear();
  dirty_faces.clear();
  dirty_vertices.clear();
}

namespace {

inline void flip_bit(std::vector<uint64_t>& bits, int32_t i) {
  bits[static_cast<size_t>(i) >> 6U] ^= uint64_t{1} << (static_cast<unsigned>(i) & 63U);
}

// The set bits' indices, ascending, into *list (within its reserved capacity).
inline void list_bits(const std::vector<uint64_t>& bits, std::vector<int32_t>* list) {
  list->clear();
  for (size_t w = 0; w < bits.size(); ++w) {
    for (uint64_t b = bits[w]; b != 0; b &= b - 1) {
      list->push_back(static_cast<int32_t>(w * 64 + static_cast<size_t>(std::countr_zero(b))));
    }
  }
}

}  // namespace

// Face f joins the region: its vertices' normals and its leaf's box now depend on the update.
void MeshDatabase::add_region_face(int32_t f, MeshUpdateScratch* s) const {
  flip_bit(s->face_bits, f);
  s->tree.add(f);
  for (const int32_t w : face_vertices_[f]) {
    if (s->vertex_region_faces[static_cast<size_t>(w)]++ == 0) flip_bit(s->vertex_bits, w);
  }
}

void MeshDatabase::drop_region_face(int32_t f, MeshUpdateScratch* s) const {
  flip_bit(s->face_bits, f);
  s->tree.remove(f);
  for (const int32_t w : face_vertices_[f]) {
    if (--s->vertex_region_faces[static_cast<size_t>(w)] == 0) flip_bit(s->vertex_bits, w);
  }
}

// The region follows the moved vertices: a vertex that starts moving adds the faces around it
// that had no moved corner, one that stops drops those left with none. A vertex moving in both
// calls changes nothing, so a dent sliding by a face costs its rim, not its area.
void MeshDatabase::update_region(std::span<const int32_t> moved, MeshUpdateScratch* s) const {
  if (s->region_of != this) {
    s->clear_region();
    s->region_of = this;
  }
  if (!s->moved.update(moved)) {
    ++s->regions_reused;
    return;
  }
  ++s->regions_updated;
  // Entered first: a face that keeps a moved corner never leaves and comes back.
  for (const int32_t v : s->moved.entered) {
    for (const int32_t c : s->corners_of(v)) {
      if (s->face_moved_corners[static_cast<size_t>(c >> 2)]++ == 0) add_region_face(c >> 2, s);
    }
  }
  for (const int32_t v : s->moved.left) {
    for (const int32_t c : s->corners_of(v)) {
      if (--s->face_moved_corners[static_cast<size_t>(c >> 2)] == 0) drop_region_face(c >> 2, s);
    }
  }
}

// The normals of the region, in memory order (faces and vertices ascending): each face once, its
// normal and corner angles, then each vertex of those faces sums its faces' shares (§4.2),
// reshaped or not, as update_normals() does. Lists the faces and vertices it recomputed.
void MeshDatabase::update_region_normals(MeshUpdateScratch* s) {
  // The lists first, so that the loops below carry nothing from one iteration to the next
  // through memory: each is a chain of a square root and divisions, and the processor overlaps
  // consecutive chains only as far as nothing else holds them up.
  list_bits(s->face_bits, &s->dirty_faces);
  list_bits(s->vertex_bits, &s->dirty_vertices);
  // The faces in two passes, the second only the arctangents (from y = |e1 x e2| and the
  // corners' dot products, parked in face_angles): a short loop of independent iterations, which
  // the processor overlaps far better than the whole shape's long chain.
  for (const int32_t f : s->dirty_faces) {
    const FaceParts parts = face_parts(face_vertices_[f], positions_);
    face_normals_[f] = parts.unit;
    s->face_angles[f] = {parts.twice_area, parts.dot_a, parts.dot_b};
  }
  for (const int32_t f : s->dirty_faces) s->face_angles[f] = corner_angles(s->face_angles[f]);
  for (const int32_t w : s->dirty_vertices) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const int32_t c : s->corners_of(w)) {
      sum += s->face_angles[c >> 2][c & 3] * face_normals_[c >> 2];
    }
    vertex_normals_[w] = unit_or_up(sum);
  }
  s->angles_of = this;
  s->angles_revision = revision_;
}

// The tree: the leaves holding the region's faces and their ancestors, each once.
void MeshDatabase::refit_region(const MeshUpdateScratch& s) {
  tree_.refit_marked(s.tree, [this](int32_t f, RefitBounds* b) {
    for (const int32_t v : face_vertices_[f]) b->add(positions_[v]);
  });
}

void MeshDatabase::set_positions(std::span<const Eigen::Vector3d> positions,
                                 std::span<const int32_t> moved, MeshUpdateScratch* s) {
  if (moved.empty()) return;
  for (int32_t v : moved) positions_[v] = positions[v];
  if (s->angles_of != this || s->angles_revision != revision_) {
    // The cached angles are another database's, or this one moved by another route.
    for (int32_t f = 0; f < face_count(); ++f) {
      s->face_angles[f] = face_shape(face_vertices_[f], positions_).angle;
    }
  }
  ++revision_;
  update_region(moved, s);
  update_region_normals(s);
  refit_region(*s);
}

size_t MeshDatabase::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(positions_) + bytes(vertex_normals_) + bytes(face_vertices_) + bytes(face_edges_) +
         bytes(edge_vertices_) + bytes(edge_faces_) + bytes(vertex_face_) + bytes(original_face_) +
         tree_.memory_bytes();
}

}  // namespace lap::haptics
