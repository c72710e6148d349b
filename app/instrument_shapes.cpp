#include "app/instrument_shapes.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "sim/setup/tool_model.h"

namespace lap::app {
namespace {

constexpr int kSides = 20;     // round sections
constexpr int kStations = 24;  // along a jaw
constexpr int kArc = 10;       // segments over a jaw's rounded back

// An open cylinder about the y axis from y0 to y1, outward normals.
void add_cylinder(haptics::TriangleMesh* m, double radius, double y0, double y1) {
  const auto base = static_cast<int32_t>(m->positions.size());
  for (int k = 0; k < kSides; ++k) {
    const double a = 2.0 * M_PI * k / kSides;
    const Eigen::Vector3d n(std::cos(a), 0.0, std::sin(a));
    for (const double y : {y0, y1}) {
      m->positions.emplace_back(radius * n.x(), y, radius * n.z());
      m->normals.push_back(n);
    }
  }
  for (int k = 0; k < kSides; ++k) {
    const int32_t a0 = base + 2 * k;
    const int32_t a1 = base + 2 * ((k + 1) % kSides);
    // Counter-clockwise from outside: around +y the angle runs from x towards z, so seen from
    // outside (+r) the next angle is to the left of the current one going up.
    m->triangles.push_back({a0, a0 + 1, a1});
    m->triangles.push_back({a1, a0 + 1, a1 + 1});
  }
}

// A flat disc at height y facing `facing` (+1: +y, −1: −y).
void add_disc(haptics::TriangleMesh* m, double radius, double y, int facing) {
  const auto centre = static_cast<int32_t>(m->positions.size());
  const Eigen::Vector3d n(0.0, facing, 0.0);
  m->positions.emplace_back(0.0, y, 0.0);
  m->normals.push_back(n);
  for (int k = 0; k < kSides; ++k) {
    const double a = 2.0 * M_PI * k / kSides;
    m->positions.emplace_back(radius * std::cos(a), y, radius * std::sin(a));
    m->normals.push_back(n);
  }
  for (int k = 0; k < kSides; ++k) {
    const int32_t a = centre + 1 + k;
    const int32_t b = centre + 1 + (k + 1) % kSides;
    if (facing > 0) {
      m->triangles.push_back({centre, b, a});
    } else {
      m->triangles.push_back({centre, a, b});
    }
  }
}

// A jaw's shape along it, s from 0 (hinge) to 1 (tip): half its width across (z), the depth of
// its back (x), and where its middle lies across (z) [m].
struct JawProfile {
  std::function<double(double)> half_width;
  std::function<double(double)> depth;
  std::function<double(double)> middle;
};

// 1 up to `from`, then a quarter ellipse down to 0 at the tip: a rounded end.
double rounded_end(double s, double from) {
  if (s <= from) return 1.0;
  const double t = (s - from) / (1.0 - from);
  return std::sqrt(std::max(0.0, 1.0 - t * t));
}

JawProfile profile(InstrumentKind kind, double length, double r, int side) {
  switch (kind) {
    case InstrumentKind::kDissector:  // Maryland: tapering, curved sideways
      return {[r](double s) { return r * (0.85 - 0.45 * s) * rounded_end(s, 0.9); },
              [r](double s) { return r * (0.75 - 0.35 * s) * rounded_end(s, 0.9); },
              [length, side](double s) { return side * 0.25 * length * s * s; }};
    case InstrumentKind::kClipApplier:  // wide, blunt, square-ended channel
      return {[r](double s) { return r * 0.95 * rounded_end(s, 0.96); },
              [r](double s) { return r * 0.8 * rounded_end(s, 0.96); }, [](double) { return 0.0; }};
    case InstrumentKind::kScissors:  // thin curved blades to a point
      return {[r](double s) { return r * 0.8 * (1.0 - 0.85 * s); },
              [r](double s) { return r * 0.45 * (1.0 - 0.6 * s); },
              [length, side](double s) { return side * 0.18 * length * s * s; }};
    case InstrumentKind::kGrasper:  // atraumatic: straight, flat, rounded tip
    default:
      return {[r](double s) { return r * 0.92 * (1.0 - 0.1 * s) * rounded_end(s, 0.8); },
              [r](double s) { return r * 0.7 * rounded_end(s, 0.8); }, [](double) { return 0.0; }};
  }
}

// A thin box (a loaded clip, between the clip applier's jaws).
void add_box(haptics::TriangleMesh* m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  for (int axis = 0; axis < 3; ++axis) {
    for (const int sign : {-1, 1}) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[axis] = sign;
      const int u = (axis + 1) % 3;
      const int v = (axis + 2) % 3;
      const auto base = static_cast<int32_t>(m->positions.size());
      for (int k = 0; k < 4; ++k) {
        Eigen::Vector3d p;
        p[axis] = sign > 0 ? hi[axis] : lo[axis];
        p[u] = (k == 1 || k == 2) ? hi[u] : lo[u];
        p[v] = (k >= 2) ? hi[v] : lo[v];
        m->positions.push_back(p);
        m->normals.push_back(n);
      }
      // u × v = +axis: (0,1,2) is counter-clockwise seen from +axis.
      if (sign > 0) {
        m->triangles.push_back({base, base + 1, base + 2});
        m->triangles.push_back({base, base + 2, base + 3});
      } else {
        m->triangles.push_back({base, base + 2, base + 1});
        m->triangles.push_back({base, base + 3, base + 2});
      }
    }
  }
}

}  // namespace

InstrumentKind instrument_kind(const std::string& name) {
  if (name == "dissector") return InstrumentKind::kDissector;
  if (name == "clip-applier") return InstrumentKind::kClipApplier;
  if (name == "scissors") return InstrumentKind::kScissors;
  if (sim::tool_kind(name) != sim::ToolKind::kGripper) return InstrumentKind::kProbe;
  return InstrumentKind::kGrasper;
}

haptics::TriangleMesh make_shaft(double radius_m, double length_m, double from_m) {
  haptics::TriangleMesh m;
  add_cylinder(&m, radius_m, from_m, std::max(length_m, from_m + 1e-3));
  return m;
}

haptics::TriangleMesh make_probe_tip(double radius_m) {
  haptics::TriangleMesh m;
  // Latitude rings from the south pole (−y) to the north pole (+y), kSides round each.
  constexpr int kRings = kSides / 2;
  for (int i = 0; i <= kRings; ++i) {
    const double theta = M_PI * i / kRings;  // from −y
    for (int k = 0; k < kSides; ++k) {
      const double a = 2.0 * M_PI * k / kSides;
      const Eigen::Vector3d n(std::sin(theta) * std::cos(a), -std::cos(theta),
                              std::sin(theta) * std::sin(a));
      m.positions.push_back(radius_m * n);
      m.normals.push_back(n);
    }
  }
  for (int i = 0; i < kRings; ++i) {
    for (int k = 0; k < kSides; ++k) {
      const int32_t a0 = i * kSides + k;
      const int32_t a1 = i * kSides + (k + 1) % kSides;
      // Going up (+y) as add_cylinder does: counter-clockwise from outside.
      if (i > 0) m.triangles.push_back({a0, a0 + kSides, a1});
      if (i + 1 < kRings) m.triangles.push_back({a1, a0 + kSides, a1 + kSides});
    }
  }
  return m;
}

haptics::TriangleMesh make_clevis(double radius_m) {
  haptics::TriangleMesh m;
  const double front = -0.0015;  // just past the hinge: the jaws' roots stay inside
  add_cylinder(&m, radius_m, front, kClevisLengthM);
  add_disc(&m, radius_m, front, -1);
  return m;
}

haptics::TriangleMesh make_jaw(InstrumentKind kind, double length_m, double radius_m, int side) {
  const JawProfile p = profile(kind, length_m, radius_m, side >= 0 ? 1 : -1);
  haptics::TriangleMesh m;
  // The rounded back: kArc + 1 points per station, angle a from −π/2 (z−) to π/2 (z+) through
  // the back (x+); an ellipse of half axes depth (x) and half width (z).
  const int ring = kArc + 1;
  for (int i = 0; i <= kStations; ++i) {
    const double s = static_cast<double>(i) / kStations;
    const double w = p.half_width(s);
    const double h = p.depth(s);
    const double c = p.middle(s);
    for (int k = 0; k < ring; ++k) {
      const double a = -0.5 * M_PI + M_PI * k / kArc;
      m.positions.emplace_back(h * std::cos(a), -s * length_m, c + w * std::sin(a));
      Eigen::Vector3d n(std::cos(a) / std::max(h, 1e-6), 0.0, std::sin(a) / std::max(w, 1e-6));
      m.normals.push_back(n.normalized());
    }
  }
  for (int i = 0; i < kStations; ++i) {
    for (int k = 0; k < kArc; ++k) {
      const int32_t a = i * ring + k;
      const int32_t b = a + ring;  // next station, towards the tip (−y)
      // Seen from outside (+x at the back), z runs left to right and the tip is down.
      m.triangles.push_back({a, a + 1, b});
      m.triangles.push_back({b, a + 1, b + 1});
    }
  }
  // The flat gripping face at x = 0, facing −x (towards the other jaw).
  const auto face = static_cast<int32_t>(m.positions.size());
  for (int i = 0; i <= kStations; ++i) {
    const double s = static_cast<double>(i) / kStations;
    const double w = p.half_width(s);
    const double c = p.middle(s);
    for (const double z : {c - w, c + w}) {
      m.positions.emplace_back(0.0, -s * length_m, z);
      m.normals.emplace_back(-1.0, 0.0, 0.0);
    }
  }
  for (int i = 0; i < kStations; ++i) {
    const int32_t a = face + 2 * i;
    const int32_t b = a + 2;
    m.triangles.push_back({a, b, a + 1});
    m.triangles.push_back({a + 1, b, b + 1});
  }
  if (kind == InstrumentKind::kClipApplier && side >= 0) {
    // A loaded titanium clip in jaw 0's channel: 0.8 mm wide, proud of the face by 0.3 mm.
    add_box(&m, Eigen::Vector3d(-0.0003, -0.85 * length_m, -0.0004),
            Eigen::Vector3d(0.0, -0.3 * length_m, 0.0004));
  }
  return m;
}

}  // namespace lap::app
