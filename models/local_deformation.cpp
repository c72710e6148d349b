#include "models/local_deformation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "haptics/closest_point.h"
#include "haptics/segment_segment.h"

namespace lap::models {

double LocalDeformationModel::weight(double distance_m) const {
  const double r = settings_.radius_m;
  if (!(distance_m < r)) return 0.0;
  const double x = distance_m / r;
  if (settings_.profile == DeformationProfile::kLinear) return 1.0 - x;
  const double s = 1.0 - x * x;
  return s * s;
}

LocalDeformationModel LocalDeformationModel::build(const haptics::MeshDatabase& rest,
                                                   const LocalDeformationSettings& settings) {
  if (!(settings.radius_m > 0.0) || !std::isfinite(settings.radius_m)) {
    throw std::invalid_argument("local deformation: radius_m must be positive, got " +
                                std::to_string(settings.radius_m));
  }
  if (!(settings.surface_share > 0.0 && settings.surface_share < 1.0)) {
    throw std::invalid_argument("local deformation: surface_share must be in (0, 1), got " +
                                std::to_string(settings.surface_share));
  }
  if (!(settings.max_displacement_m > 0.0)) {
    throw std::invalid_argument("local deformation: max_displacement_m must be positive");
  }
  if (!(settings.max_move_per_step_m >= 0.0) || !std::isfinite(settings.max_move_per_step_m)) {
    throw std::invalid_argument(
        "local deformation: max_move_per_step_m must be 0 (no limit) or positive, got " +
        std::to_string(settings.max_move_per_step_m));
  }
  LocalDeformationModel m;
  m.settings_ = settings;
  const int32_t n = rest.vertex_count();
  m.rest_.resize(n);
  for (int32_t v = 0; v < n; ++v) m.rest_[v] = rest.position(v);
  m.face_vertices_.resize(rest.face_count());
  for (int32_t f = 0; f < rest.face_count(); ++f) m.face_vertices_[f] = rest.face_vertices(f);
  // Area-weighted vertex normals of the rest shape (the cross product's length is twice the
  // face's area): which way is out of the organ at each vertex.
  m.rest_normal_.assign(n, Eigen::Vector3d::Zero());
  for (const std::array<int32_t, 3>& f : m.face_vertices_) {
    const Eigen::Vector3d area =
        (m.rest_[f[1]] - m.rest_[f[0]]).cross(m.rest_[f[2]] - m.rest_[f[0]]);
    for (const int32_t v : f) m.rest_normal_[v] += area;
  }
  for (Eigen::Vector3d& normal : m.rest_normal_) {
    const double length = normal.norm();
    normal = length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
  }
  for (int32_t e = 0; e < rest.edge_count(); ++e) {
    const auto& ev = rest.edge_vertices(e);
    m.longest_edge_ = std::max(m.longest_edge_, (m.rest_[ev[1]] - m.rest_[ev[0]]).norm());
  }
  // Neighbours within R + h through a uniform grid of that cell size (setup only).
  const double reach = settings.radius_m + m.longest_edge_;
  const double reach2 = reach * reach;
  auto cell_of = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / reach)),
                           static_cast<int>(std::floor(p.y() / reach)),
                           static_cast<int>(std::floor(p.z() / reach)));
  };
  auto key = [](const Eigen::Vector3i& c) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(c.x()) & 0x1FFFFFU) << 42U) |
           (static_cast<uint64_t>(static_cast<uint32_t>(c.y()) & 0x1FFFFFU) << 21U) |
           static_cast<uint64_t>(static_cast<uint32_t>(c.z()) & 0x1FFFFFU);
  };
  std::unordered_map<uint64_t, std::vector<int32_t>> grid;
  for (int32_t v = 0; v < n; ++v) grid[key(cell_of(m.rest_[v]))].push_back(v);
  m.neighbour_offset_.assign(n + 1, 0);
  for (int32_t v = 0; v < n; ++v) {
    const Eigen::Vector3i c = cell_of(m.rest_[v]);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == grid.end()) continue;
          for (int32_t w : it->second) {
            if ((m.rest_[w] - m.rest_[v]).squaredNorm() <= reach2) m.neighbour_index_.push_back(w);
          }
        }
      }
    }
    if (m.neighbour_index_.size() > static_cast<size_t>(INT32_MAX)) {
      throw std::invalid_argument(
          "local deformation: radius_m too large for this mesh (neighbour lists overflow)");
    }
    m.neighbour_offset_[v + 1] = static_cast<int32_t>(m.neighbour_index_.size());
  }
  return m;
}

namespace {

template <typename Position>
DeformationContact rest_contact_at(const LocalDeformationModel& model,
                                   const haptics::MeshDatabase& topology, Position position,
                                   haptics::PrimitiveRef primitive, const Eigen::Vector3d& point_O,
                                   const Eigen::Vector3d& force_O, double stiffness_n_per_m) {
  DeformationContact c;
  // Where the force law puts the tool: force / k beyond the point on the deformed surface.
  const Eigen::Vector3d tool_O = point_O + force_O / stiffness_n_per_m;
  switch (primitive.kind) {
    case haptics::PrimitiveKind::kFace: {
      const auto& fv = topology.face_vertices(primitive.index);
      const Eigen::Vector3d bary =
          haptics::barycentric(point_O, position(fv[0]), position(fv[1]), position(fv[2]));
      const double v = bary.y();
      const double w = bary.z();
      c.face = primitive.index;
      c.point_O = (1.0 - v - w) * model.rest_position(fv[0]) + v * model.rest_position(fv[1]) +
                  w * model.rest_position(fv[2]);
      break;
    }
    case haptics::PrimitiveKind::kEdge: {
      const auto& ev = topology.edge_vertices(primitive.index);
      const Eigen::Vector3d& a = position(ev[0]);
      const Eigen::Vector3d ab = position(ev[1]) - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((point_O - a).dot(ab) / len2, 0.0, 1.0) : 0.5;
      c.face = topology.edge_faces(primitive.index)[0];
      c.point_O = (1.0 - t) * model.rest_position(ev[0]) + t * model.rest_position(ev[1]);
      break;
    }
    case haptics::PrimitiveKind::kVertex: {
      int32_t face = -1;
      topology.for_each_vertex_face(primitive.index, [&](int32_t f) { face = f; });
      c.face = face;
      c.point_O = model.rest_position(primitive.index);
      break;
    }
    case haptics::PrimitiveKind::kNone:
      c.penetration_O = force_O / stiffness_n_per_m;
      return c;  // face stays -1: deform() refuses it
  }
  // The tool's displacement into the rest surface: its depth below the deformed surface plus
  // that surface's own displacement at the point.
  c.penetration_O = tool_O - c.point_O;
  return c;
}

}  // namespace

DeformationContact rest_contact(const LocalDeformationModel& model,
                                const haptics::MeshDatabase& deformed,
                                haptics::PrimitiveRef primitive, const Eigen::Vector3d& point_O,
                                const Eigen::Vector3d& force_O, double stiffness_n_per_m) noexcept {
  return rest_contact_at(
      model, deformed, [&](int32_t v) -> const Eigen::Vector3d& { return deformed.position(v); },
      primitive, point_O, force_O, stiffness_n_per_m);
}

DeformationContact rest_contact(const LocalDeformationModel& model,
                                const haptics::MeshDatabase& topology,
                                std::span<const Eigen::Vector3d> deformed_positions,
                                haptics::PrimitiveRef primitive, const Eigen::Vector3d& point_O,
                                const Eigen::Vector3d& force_O, double stiffness_n_per_m) noexcept {
  return rest_contact_at(
      model, topology,
      [&](int32_t v) -> const Eigen::Vector3d& {
        return deformed_positions[static_cast<size_t>(v)];
      },
      primitive, point_O, force_O, stiffness_n_per_m);
}

LocalDeformationState::LocalDeformationState(const LocalDeformationModel& model)
    : positions(static_cast<size_t>(model.vertex_count())),
      flags(static_cast<size_t>(model.vertex_count()), 0),
      conforming(static_cast<size_t>(model.vertex_count()), Eigen::Vector3d::Zero()),
      previous(static_cast<size_t>(model.vertex_count())) {
  for (int32_t v = 0; v < model.vertex_count(); ++v) positions[v] = model.rest_position(v);
  previous = positions;
  // Both lists hold at most every vertex once: reserved here, never reallocated by deform().
  displaced.reserve(static_cast<size_t>(model.vertex_count()));
  changed.reserve(static_cast<size_t>(model.vertex_count()));
}

namespace {
constexpr uint8_t kDisplaced = 1U;
constexpr uint8_t kChanged = 2U;
// How far short of the level of an obstacle a vertex moving onto it stops [m]: the 0.5 mm the
// soak allows a proxy inside an organ (estimate).
constexpr double kObstacleSkinM = 0.0005;

// The vertices this call moved out of the organ stopped where their move from the last call's
// positions comes level with an obstacle, within one edge of it; each one stopped off rest is
// listed as displaced. Returns how many stopped.
int32_t stop_at_obstacles(const LocalDeformationModel& model,
                          std::span<const DeformationObstacle> obstacles,
                          LocalDeformationState* state) {
  const double capture = model.longest_edge_m();
  int32_t stopped = 0;
  for (const int32_t v : state->changed) {
    const Eigen::Vector3d& from = state->previous[v];
    Eigen::Vector3d& to = state->positions[v];
    const Eigen::Vector3d move = to - from;
    const double length = move.norm();
    if (!(length > 0.0) || !(move.dot(model.rest_normal(v)) > 0.0)) continue;  // not going out
    const Eigen::Vector3d middle = from + 0.5 * move;
    double stop = 1.0;
    for (const DeformationObstacle& o : obstacles) {
      if (!o.a_O.allFinite() || !o.b_O.allFinite()) continue;  // ignored (the header)
      // Far apart (the bounding spheres of the move and the segment, and the capture): skip.
      const Eigen::Vector3d centre = 0.5 * (o.a_O + o.b_O);
      const double reach = 0.5 * (length + (o.b_O - o.a_O).norm()) + capture;
      if (!((centre - middle).squaredNorm() < reach * reach)) continue;
      const haptics::SegmentPair cp = haptics::closest_segment_segment(from, to, o.a_O, o.b_O);
      if ((cp.p - cp.q).squaredNorm() < capture * capture) stop = std::min(stop, cp.s);
    }
    if (stop >= 1.0) continue;
    to = from + std::max(0.0, stop - kObstacleSkinM / length) * move;
    ++stopped;
    if ((state->flags[v] & kDisplaced) == 0 && to != model.rest_position(v)) {
      state->flags[v] |= kDisplaced;
      state->displaced.push_back(v);
    }
  }
  return stopped;
}

// The vertices this call moved along their rest normal by more than max_move_per_step_m (from
// where the last call left them, in or out) held to that, their move across the normal kept but
// shortened where it would take them beyond max_displacement_m from rest (the bound holds: the
// part along the normal lies between the last call's and the formula's, both within it); each
// one held off rest is listed as displaced. Returns how many.
int32_t limit_speed(const LocalDeformationModel& model, LocalDeformationState* state) {
  const double max_move = model.settings().max_move_per_step_m;
  if (!(max_move > 0.0)) return 0;
  const double max_d = model.settings().max_displacement_m;
  int32_t slowed = 0;
  for (const int32_t v : state->changed) {
    const Eigen::Vector3d& n = model.rest_normal(v);
    Eigen::Vector3d& to = state->positions[v];
    const double move = (to - state->previous[v]).dot(n);
    if (!(std::abs(move) > max_move)) continue;
    to -= (move - std::copysign(max_move, move)) * n;
    const Eigen::Vector3d& rest = model.rest_position(v);
    const double along = (to - rest).dot(n);
    const Eigen::Vector3d across = (to - rest) - along * n;
    const double room2 = std::max(0.0, max_d * max_d - along * along);
    if (across.squaredNorm() > room2) {
      to = rest + along * n + across * (std::sqrt(room2) / across.norm());
    }
    ++slowed;
    if ((state->flags[v] & kDisplaced) == 0) {
      state->flags[v] |= kDisplaced;
      state->displaced.push_back(v);
    }
  }
  return slowed;
}
}  // namespace

bool deform(const LocalDeformationModel& model, std::span<const DeformationContact> contacts,
            LocalDeformationState* state, std::span<const DeformationObstacle> obstacles) noexcept {
  auto& flags = state->flags;
  auto& positions = state->positions;
  // Back to rest where the last call displaced.
  state->changed.clear();
  for (int32_t v : state->displaced) {
    positions[v] = model.rest_position(v);
    flags[v] = kChanged;
    state->changed.push_back(v);
  }
  state->displaced.clear();
  const double r = model.settings().radius_m;
  const double r2 = r * r;
  bool ok = true;
  for (const DeformationContact& c : contacts) {
    if (c.face < 0 || c.face >= model.face_count() || !c.point_O.allFinite() ||
        !c.penetration_O.allFinite()) {
      ok = false;
      continue;
    }
    const Eigen::Vector3d p =
        c.conform ? c.penetration_O
                  : Eigen::Vector3d(model.settings().surface_share * c.penetration_O);
    // Any vertex of the contact face is within h of Pt: its list covers the radius.
    const int32_t start = model.face_vertices(c.face)[0];
    for (int32_t v : model.neighbours(start)) {
      // D² ≥ R² exactly when D ≥ R (a correctly rounded root of R² is R): such a vertex
      // weighs nothing, and needs no root.
      const double d2 = (model.rest_position(v) - c.point_O).squaredNorm();
      if (!(d2 < r2)) continue;
      const double w = model.weight(std::sqrt(d2));
      if (w <= 0.0) continue;
      if (c.conform) {
        const Eigen::Vector3d d = w * p;
        if (d.squaredNorm() > state->conforming[v].squaredNorm()) state->conforming[v] = d;
      } else {
        positions[v] += w * p;
      }
      if ((flags[v] & kDisplaced) == 0) {
        flags[v] |= kDisplaced;
        state->displaced.push_back(v);
      }
      if ((flags[v] & kChanged) == 0) {
        flags[v] |= kChanged;
        state->changed.push_back(v);
      }
    }
  }
  // The conforming displacements, then the bound against a runaway contact (not physics), and
  // the deepest displacement, in one pass.
  state->clamped = 0;
  const double max_d = model.settings().max_displacement_m;
  const double max_d2 = max_d * max_d;
  double deepest2 = 0.0;
  for (int32_t v : state->displaced) {
    Eigen::Vector3d& position = positions[v];
    position += state->conforming[v];
    state->conforming[v].setZero();
    const Eigen::Vector3d d = position - model.rest_position(v);
    double len2 = d.squaredNorm();
    if (len2 > max_d2) {
      position = model.rest_position(v) + d * (max_d / std::sqrt(len2));
      ++state->clamped;
      len2 = max_d2;
    }
    deepest2 = std::max(deepest2, len2);
  }
  state->deepest_m = std::sqrt(deepest2);
  // The surface's speed, then the tools' segments it must not pass.
  state->slowed = ok ? limit_speed(model, state) : 0;
  state->stopped = 0;
  if (ok && !obstacles.empty()) state->stopped = stop_at_obstacles(model, obstacles, state);
  if (ok && state->slowed + state->stopped > 0) {
    deepest2 = 0.0;
    for (int32_t v : state->displaced) {
      deepest2 = std::max(deepest2, (positions[v] - model.rest_position(v)).squaredNorm());
    }
    state->deepest_m = std::sqrt(deepest2);
  }
  if (!ok) {
    for (int32_t v : state->displaced) {
      positions[v] = model.rest_position(v);
      flags[v] &= static_cast<uint8_t>(~kDisplaced);
    }
    state->displaced.clear();
    state->deepest_m = 0.0;
  }
  for (int32_t v : state->changed) {
    flags[v] &= static_cast<uint8_t>(~kChanged);
    state->previous[v] = positions[v];
  }
  return ok;
}

}  // namespace lap::models
