#include "haptics/setup/anatomy_generator.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "haptics/setup/mesh_generators.h"

namespace lap::haptics {
namespace {

constexpr double kPi = std::numbers::pi;
using V3 = Eigen::Vector3d;

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Smooth maximum: at least max(a, b), rounded over a width w where the two meet.
double smooth_max(double a, double b, double w) {
  return 0.5 * (a + b + std::sqrt((a - b) * (a - b) + w * w));
}

V3 hermite(const V3& p0, const V3& p1, const V3& t0, const V3& t1, double s) {
  const double s2 = s * s;
  const double s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * t0 + (-2 * s3 + 3 * s2) * p1 +
         (s3 - s2) * t1;
}

double arc_length(const std::vector<V3>& c) {
  double len = 0.0;
  for (size_t i = 1; i < c.size(); ++i) len += (c[i] - c[i - 1]).norm();
  return len;
}

// Point at arc length s along a polyline and its unit tangent.
V3 point_at_arc(const std::vector<V3>& c, double s, V3* tangent) {
  double acc = 0.0;
  for (size_t i = 1; i < c.size(); ++i) {
    const double seg = (c[i] - c[i - 1]).norm();
    if (acc + seg >= s || i + 1 == c.size()) {
      const double f = seg > 0.0 ? std::clamp((s - acc) / seg, 0.0, 1.0) : 0.0;
      if (tangent != nullptr) *tangent = (c[i] - c[i - 1]).normalized();
      return c[i - 1] + f * (c[i] - c[i - 1]);
    }
    acc += seg;
  }
  if (tangent != nullptr) *tangent = V3::UnitX();
  return c.front();
}

// Unit vector perpendicular to t, as close to `hint` as possible.
V3 perpendicular(const V3& t, const V3& hint) {
  V3 n = hint - hint.dot(t) * t;
  if (n.norm() < 1e-9) n = t.unitOrthogonal();
  return n.normalized();
}

// Closed meshes here are built with a rule that makes them outward; this turns one that came
// out inward (a mirroring map) rather than trusting the rule alone. Then normals and the
// seamless planar texture coordinates.
void finish(TriangleMesh& m, double tile_m) {
  if (m.signed_volume() < 0.0) {
    for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
  }
  m.compute_vertex_normals();
  m.uvs.resize(m.positions.size());
  for (size_t v = 0; v < m.positions.size(); ++v) {
    m.uvs[v] = Eigen::Vector2d(m.positions[v].x() / tile_m, m.positions[v].y() / tile_m);
  }
}

// --- Liver ---------------------------------------------------------------------------------

// The liver's shape at scale 1 before the fossa: the stand-in's flattened ellipsoid (about
// 18 x 9 x 14 cm, make_stand_in_liver) with a right-lobe dome, a tapering left lobe and a
// thinner anterior part ending in a rounded free edge (the inferior border faces the camera).
struct LiverShape {
  V3 centre{0.0, 0.040, 0.0};
  static double dome(double ux) { return 0.012 * std::exp(-std::pow((ux + 0.4) / 0.45, 2)); }
  // The anterior third thins towards the free edge (estimate: a wedge-shaped inferior border).
  static double thin(double uz) { return 1.0 - 0.45 * smoothstep(0.1, 1.0, uz); }
  [[nodiscard]] V3 at(const V3& u) const {
    const double half = u.y() >= 0.0 ? 0.045 : 0.045 * 0.55;  // flatter visceral face
    return centre + V3(0.09 * u.x(), half * u.y() * thin(u.z()) + dome(u.x()),
                       0.07 * u.z() * (1.0 - 0.25 * std::max(0.0, u.x())));
  }
  // Underside height and thickness at horizontal (x, z); false outside the outline.
  bool underside(double x, double z, double* y, double* thickness) const {
    const double ux = (x - centre.x()) / 0.09;
    const double uz = (z - centre.z()) / (0.07 * (1.0 - 0.25 * std::max(0.0, ux)));
    const double r2 = ux * ux + uz * uz;
    if (r2 >= 1.0) return false;
    const double uy = std::sqrt(1.0 - r2);
    *y = centre.y() - 0.045 * 0.55 * uy * thin(uz) + dome(ux);
    *thickness = 0.045 * 1.55 * uy * thin(uz);
    return true;
  }
};

// --- Gallbladder ---------------------------------------------------------------------------

// The gallbladder as a bent sac around a centre line from the neck tip (s = 0) to the fundus tip
// (s = 1); cross sections are circles of radius radius(s) except for Hartmann's pouch.
struct GallbladderShape {
  V3 neck;  // C(0)
  V3 g;     // unit, neck to fundus
  V3 up;    // unit, perpendicular to g, towards the liver
  V3 side;  // g x up
  double length = 0.085;
  double radius = 0.016;
  double pouch = 0.005;
  double pouch_angle = 0.0;              // in the (up, side) plane
  static constexpr double kSag = 0.003;  // the fundus hangs a little away from the liver

  [[nodiscard]] V3 centre(double s) const {
    return neck + s * length * g - kSag * 4.0 * s * (1.0 - s) * up;
  }
  // Neck narrower than body and fundus: about half the body's width (estimate from the
  // textbook outline; Gray's Anatomy ch. 70 figure of the gallbladder's parts).
  static double profile(double s) { return 0.55 + 0.45 * smoothstep(0.05, 0.55, s); }
  // The ring factor at s: sin(theta)^0.6 with s = (1 - cos theta) / 2 (make_gallbladder).
  static double ring_factor(double s) { return std::pow(std::max(0.0, 4.0 * s * (1.0 - s)), 0.3); }
  [[nodiscard]] double ring_radius(double s) const { return radius * profile(s) * ring_factor(s); }
  [[nodiscard]] V3 at(double s, double ring, double angle) const {
    // Hartmann's pouch: a bulge of the neck-body junction towards the common bile duct.
    const double pouch_here = pouch * std::exp(-std::pow((s - 0.22) / 0.08, 2)) *
                              std::pow(std::max(0.0, std::cos(angle - pouch_angle)), 2) *
                              std::min(1.0, ring / 0.4);
    const double r = radius * profile(s) * ring + pouch_here;
    return centre(s) + r * (std::cos(angle) * up + std::sin(angle) * side);
  }
};

// The gallbladder turned by `deg` about its neck tip, the fundus towards +y (cephalad): about
// the axis across its long axis and the vertical. 0 leaves it as it is.
GallbladderShape retracted(const GallbladderShape& gb, double deg) {
  if (deg == 0.0) return gb;
  const Eigen::AngleAxisd turn(deg * kPi / 180.0, gb.g.cross(V3::UnitY()).normalized());
  GallbladderShape r = gb;
  r.g = turn * gb.g;
  r.up = turn * gb.up;
  r.side = turn * gb.side;
  return r;
}

// The height of the gallbladder fossa's floor over the underside point q: the gallbladder's top
// with a 1 mm gap, wider than the gallbladder; false away from it. Over the ring nearest q
// across (the fossa of a gallbladder lying in it).
bool fossa_floor(const GallbladderShape& gb, const V3& q, double* floor_y) {
  double best_d = 1e9;
  double best_s = 0.0;
  for (int i = 0; i <= 128; ++i) {
    const double s = i / 128.0;
    const V3 c = gb.centre(s);
    const double d = std::hypot(q.x() - c.x(), q.z() - c.z());
    if (d < best_d) {
      best_d = d;
      best_s = s;
    }
  }
  const double r = gb.ring_radius(best_s) + 0.002;
  const double width = 1.5 * r;
  if (best_d >= width) return false;
  *floor_y = gb.centre(best_s).y() + r * std::sqrt(1.0 - std::pow(best_d / width, 2)) + 0.001;
  return true;
}

// The height of the liver's edge draped over a retracted gallbladder at the underside point q:
// the highest over all rings (a gallbladder tilted out of the horizontal stacks its rings) of
// a drape that clears each ring's top by 1 mm and falls away from it at a slope of kDrape. A
// circular floor cut off at a width (fossa_floor) leaves a wall as high as the fundus stands
// over the liver (about 4 cm at 30 degrees), which the surface drew as pleated curtains; the
// drape falls smoothly until it passes under the liver, where the lift fades out (make_liver).
double draped_floor(const GallbladderShape& gb, const V3& q) {
  // Rise over run of the drape's sides, about 35 degrees: a look, not a measurement. At 1.2 the
  // rings' drapes met in a crease that a tool's shaft could lie along (docs/anatomy.md).
  constexpr double kDrape = 0.7;
  double highest = -1e9;
  for (int i = 0; i <= 128; ++i) {
    const double s = i / 128.0;
    const V3 c = gb.centre(s);
    const double d = std::hypot(q.x() - c.x(), q.z() - c.z());
    // Over the ring: the parabola osculating its top (radius r, 1 mm clear), which lies over
    // the circle everywhere; from where its slope reaches kDrape, a straight fall at kDrape.
    // Hartmann's pouch is not in r: it bulges away from the liver, towards the common bile duct
    // (AnatomyGenerator.OrgansThatMustNotOverlapDoNot checks no gallbladder vertex is inside).
    const double r = gb.ring_radius(s) + 0.001;
    const double d0 = kDrape * r;
    const double top = c.y() + r;
    const double y =
        d <= d0 ? top - d * d / (2.0 * r) : top - d0 * d0 / (2.0 * r) - kDrape * (d - d0);
    highest = std::max(highest, y);
  }
  return highest;
}

// The liver over the gallbladder. In its fossa (lift_edge false) the visceral face is lifted
// over the gallbladder's top, at most half the liver's thickness there. Over a retracted
// gallbladder (lift_edge true) the free edge is lifted whole: the visceral face to the
// gallbladder's top and the diaphragmatic face with it, keeping half the thickness.
TriangleMesh make_liver(const LiverShape& shape, double scale, const V3& anchor,
                        const GallbladderShape& gb, bool lift_edge) {
  TriangleMesh m = make_mapped_sphere(40, 80, [&](const V3& u) {
    V3 p = anchor + scale * (shape.at(u) - anchor);
    if (u.y() < 0.0 || lift_edge) {
      const V3 under = anchor + scale * (shape.at(V3(u.x(), -std::abs(u.y()), u.z())) - anchor);
      const V3 top = anchor + scale * (shape.at(V3(u.x(), std::abs(u.y()), u.z())) - anchor);
      if (!lift_edge) {
        double floor_y = 0.0;
        if (!fossa_floor(gb, under, &floor_y)) return p;
        const double limit = p.y() + 0.5 * (top.y() - p.y());
        p.y() = smooth_max(p.y(), std::min(floor_y, limit), 0.001);
        return p;
      }
      const double floor_y = draped_floor(gb, under);
      // Well under the liver the drape lifts nothing (smooth_max would add 0.025 mm at 1 cm).
      if (floor_y < under.y() - 0.01) return p;
      const double lift = smooth_max(under.y(), floor_y, 0.001) - under.y();
      p.y() += u.y() < 0.0 ? lift : std::max(0.0, lift - 0.5 * (top.y() - under.y()));
    }
    return p;
  });
  return m;
}

TriangleMesh make_gallbladder(const GallbladderShape& gb) {
  return make_mapped_sphere(40, 48, [&](const V3& u) {
    // Along the axis as an ellipsoid's (s = (1 - cos theta) / 2 from the +y pole, the neck), the
    // ring radius as sin(theta)^0.6: blunter than an ellipsoid's tip, a rounded fundus.
    const double s = 0.5 * (1.0 - std::clamp(u.y(), -1.0, 1.0));
    const double ring = std::pow(std::hypot(u.x(), u.z()), 0.6);
    return gb.at(s, ring, std::atan2(u.z(), u.x()));
  });
}

// --- Abdominal wall --------------------------------------------------------------------------

struct Dome {
  V3 centre;
  double radius = 0.22;
  double thickness = 0.025;
  [[nodiscard]] double inner_z(double x, double y) const {
    const double dx = x - centre.x();
    const double dy = y - centre.y();
    return centre.z() + std::sqrt(radius * radius - dx * dx - dy * dy);
  }
};

TriangleMesh make_abdominal_wall(const Dome& dome, const V3& apex, double extent_m,
                                 const std::vector<PortSite>& ports) {
  const double cell = 0.0075;
  const int n = static_cast<int>(std::ceil(2.0 * extent_m / cell));
  const double x0 = apex.x() - 0.5 * n * cell;
  const double y0 = apex.y() - 0.5 * n * cell;
  auto cx = [&](int i) { return x0 + (i + 0.5) * cell; };
  auto cy = [&](int j) { return y0 + (j + 0.5) * cell; };
  std::vector<char> keep(static_cast<size_t>(n) * n, 0);
  std::vector<int> hole_of(static_cast<size_t>(n) * n, -1);
  auto at = [&](int i, int j) -> char {
    return (i < 0 || j < 0 || i >= n || j >= n) ? 0 : keep[static_cast<size_t>(j) * n + i];
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      bool k = std::hypot(cx(i) - apex.x(), cy(j) - apex.y()) < extent_m;
      for (size_t p = 0; p < ports.size(); ++p) {
        // The cells near the port, and always every cell it touches (a 5 mm port is smaller
        // than a cell; on a grid point all four go, so no hole vertex sits on the port).
        const double r = 0.5 * ports[p].diameter_m + 0.35 * cell;
        const double touch = 0.5 * cell + 1e-7;
        const bool own = std::abs(cx(i) - ports[p].position_m.x()) <= touch &&
                         std::abs(cy(j) - ports[p].position_m.y()) <= touch;
        if (own ||
            std::hypot(cx(i) - ports[p].position_m.x(), cy(j) - ports[p].position_m.y()) < r) {
          k = false;
          hole_of[static_cast<size_t>(j) * n + i] = static_cast<int>(p);
        }
      }
      keep[static_cast<size_t>(j) * n + i] = k ? 1 : 0;
    }
  }
  // Cells meeting only at a corner would make a non-manifold vertex: fill one of the two gaps.
  for (bool changed = true; changed;) {
    changed = false;
    for (int j = 1; j < n; ++j) {
      for (int i = 1; i < n; ++i) {
        const bool a = at(i - 1, j - 1) != 0, b = at(i, j - 1) != 0, c = at(i - 1, j) != 0,
                   d = at(i, j) != 0;
        if ((a && d && !b && !c) || (b && c && !a && !d)) {
          keep[static_cast<size_t>(j - 1) * n + i] = 1;
          hole_of[static_cast<size_t>(j - 1) * n + i] = -1;
          changed = true;
        }
      }
    }
  }
  // Vertices: (n + 1)^2 grid points on each sheet, used ones only.
  const int nv = n + 1;
  std::vector<int32_t> inner(static_cast<size_t>(nv) * nv, -1);
  std::vector<int32_t> outer(static_cast<size_t>(nv) * nv, -1);
  TriangleMesh m;
  auto vertex = [&](int i, int j, bool out) {
    std::vector<int32_t>& ids = out ? outer : inner;
    int32_t& id = ids[static_cast<size_t>(j) * nv + i];
    if (id < 0) {
      double x = x0 + i * cell;
      double y = y0 + j * cell;
      // A vertex on a port's hole is moved onto the hole's circle, so the holes are round.
      for (size_t p = 0; p < ports.size(); ++p) {
        bool on_hole = false;
        for (int dj = -1; dj <= 0; ++dj) {
          for (int di = -1; di <= 0; ++di) {
            const int ci = i + di, cj = j + dj;
            if (ci >= 0 && cj >= 0 && ci < n && cj < n &&
                hole_of[static_cast<size_t>(cj) * n + ci] == static_cast<int>(p) &&
                keep[static_cast<size_t>(cj) * n + ci] == 0) {
              on_hole = true;
            }
          }
        }
        if (on_hole) {
          const Eigen::Vector2d c(ports[p].position_m.x(), ports[p].position_m.y());
          const Eigen::Vector2d d = Eigen::Vector2d(x, y) - c;
          if (d.norm() < 1e-9) continue;
          const Eigen::Vector2d q = c + 0.5 * ports[p].diameter_m * d.normalized();
          x = q.x();
          y = q.y();
        }
      }
      // The outer sheet is the inner one pushed out along the dome's radius: the wall's
      // thickness and the ports' holes run along its normal.
      const V3 in(x, y, dome.inner_z(x, y));
      id = m.vertex_count();
      m.positions.push_back(
          out ? V3(dome.centre + (dome.radius + dome.thickness) / dome.radius * (in - dome.centre))
              : in);
    }
    return id;
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (at(i, j) == 0) continue;
      // Outer face (+z outward) counter-clockwise seen from +z; inner face the reverse.
      const int32_t o00 = vertex(i, j, true), o10 = vertex(i + 1, j, true),
                    o11 = vertex(i + 1, j + 1, true), o01 = vertex(i, j + 1, true);
      const int32_t n00 = vertex(i, j, false), n10 = vertex(i + 1, j, false),
                    n11 = vertex(i + 1, j + 1, false), n01 = vertex(i, j + 1, false);
      m.triangles.push_back({o00, o10, o11});
      m.triangles.push_back({o00, o11, o01});
      m.triangles.push_back({n00, n11, n10});
      m.triangles.push_back({n00, n01, n11});
      // Side faces towards empty neighbours, between grid points p -> q with (q - p) x z
      // pointing out of the cell.
      auto side = [&](int pi, int pj, int qi, int qj) {
        const int32_t np = vertex(pi, pj, false), nq = vertex(qi, qj, false);
        const int32_t op = vertex(pi, pj, true), oq = vertex(qi, qj, true);
        m.triangles.push_back({np, oq, op});
        m.triangles.push_back({np, nq, oq});
      };
      if (at(i - 1, j) == 0) side(i, j + 1, i, j);
      if (at(i + 1, j) == 0) side(i + 1, j, i + 1, j + 1);
      if (at(i, j - 1) == 0) side(i, j, i + 1, j);
      if (at(i, j + 1) == 0) side(i + 1, j + 1, i, j + 1);
    }
  }
  return m;
}

// A clip (closed titanium ligating clip, about 9 x 1.5 x 1 mm closed: estimate after the
// medium-large clips used on the cystic duct and artery) across a vessel at `centre` with
// tangent t, its long side across the vessel as the camera sees it.
TriangleMesh make_clip(const V3& centre, const V3& t, const V3& camera) {
  const V3 view = (camera - centre).normalized();
  V3 across = t.cross(view);
  if (across.norm() < 1e-9) across = t.unitOrthogonal();
  across.normalize();
  const V3 third = across.cross(t);
  TriangleMesh box = make_box(V3(0.009, 0.0015, 0.0012), 1);
  Eigen::Matrix3d R;
  R.col(0) = across;
  R.col(1) = t;
  R.col(2) = third;
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  T.translate(centre);
  T.linear() = R;
  box.transform(T);
  return box;
}

std::vector<V3> sample_curve(int n, const std::function<V3(double)>& f) {
  std::vector<V3> c;
  c.reserve(static_cast<size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) c.push_back(f(static_cast<double>(i) / n));
  return c;
}

// Resamples a polyline to about `spacing` between points (keeps both ends).
std::vector<V3> resample(const std::vector<V3>& c, double spacing) {
  const double len = arc_length(c);
  const int n = std::max(2, static_cast<int>(std::ceil(len / spacing)));
  std::vector<V3> out;
  for (int i = 0; i <= n; ++i) out.push_back(point_at_arc(c, len * i / n, nullptr));
  return out;
}

// Does the segment from a to b cross a triangle of m (Moller-Trumbore)?
bool segment_crosses(const TriangleMesh& m, const V3& a, const V3& b) {
  const V3 d = b - a;
  for (const Triangle& t : m.triangles) {
    const V3& p0 = m.positions[t[0]];
    const V3 e1 = m.positions[t[1]] - p0;
    const V3 e2 = m.positions[t[2]] - p0;
    const V3 q = d.cross(e2);
    const double det = e1.dot(q);
    if (std::abs(det) < 1e-18) continue;
    const V3 r = a - p0;
    const double u = r.dot(q) / det;
    if (u < 0.0 || u > 1.0) continue;
    const V3 w = r.cross(e1);
    const double v = d.dot(w) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    const double s = e2.dot(w) / det;
    if (s > 0.0 && s < 1.0) return true;
  }
  return false;
}

}  // namespace

const GeneratedOrgan* GeneratedAnatomy::organ(const std::string& name) const {
  for (const GeneratedOrgan& o : organs) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

TriangleMesh make_tube(const std::vector<V3>& centre, const std::vector<double>& radius,
                       int32_t slices) {
  TriangleMesh m;
  const auto n = static_cast<int32_t>(centre.size());
  std::vector<V3> tangent(centre.size());
  for (int32_t i = 0; i < n; ++i) {
    const V3& a = centre[std::max(0, i - 1)];
    const V3& b = centre[std::min(n - 1, i + 1)];
    tangent[i] = (b - a).normalized();
  }
  V3 normal = perpendicular(tangent[0], V3::UnitZ());
  for (int32_t i = 0; i < n; ++i) {
    normal = perpendicular(tangent[i], normal);  // parallel transport
    const V3 binormal = tangent[i].cross(normal);
    for (int32_t k = 0; k < slices; ++k) {
      const double a = 2.0 * kPi * k / slices;
      m.positions.push_back(centre[i] +
                            radius[i] * (std::cos(a) * normal + std::sin(a) * binormal));
    }
  }
  auto ring = [slices](int32_t i, int32_t k) { return i * slices + (k % slices); };
  for (int32_t i = 0; i + 1 < n; ++i) {
    for (int32_t k = 0; k < slices; ++k) {
      m.triangles.push_back({ring(i, k), ring(i, k + 1), ring(i + 1, k + 1)});
      m.triangles.push_back({ring(i, k), ring(i + 1, k + 1), ring(i + 1, k)});
    }
  }
  const int32_t first = m.vertex_count();
  m.positions.push_back(centre.front());
  const int32_t last = m.vertex_count();
  m.positions.push_back(centre.back());
  for (int32_t k = 0; k < slices; ++k) {
    m.triangles.push_back({first, ring(0, k + 1), ring(0, k)});
    m.triangles.push_back({last, ring(n - 1, k), ring(n - 1, k + 1)});
  }
  if (m.signed_volume() < 0.0) {
    for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
  }
  m.compute_vertex_normals();
  return m;
}

GeneratedAnatomy generate_anatomy(const AnatomyParameters& p) {
  GeneratedAnatomy out;
  out.parameters = p;
  const V3 camera(p.camera_x_m, p.camera_y_m, p.camera_z_m);

  // Gallbladder: its middle under the liver where the stand-in's is, lying with 40 % of its
  // radius in the fossa, neck up, back and medial, fundus forward and down (as the stand-in).
  const LiverShape liver;
  GallbladderShape gb;
  gb.length = p.gallbladder_length_m;
  gb.radius = 0.5 * p.gallbladder_width_m;
  gb.pouch = p.hartmann_pouch_m;
  gb.g = V3(-0.15, -0.12, 1.0).normalized();
  gb.up = perpendicular(gb.g, V3::UnitY());
  gb.side = gb.g.cross(gb.up);
  const double mid_x = -0.022;
  const double mid_z = 0.030;
  double under_y = 0.0;
  double thickness = 0.0;
  (void)liver.underside(mid_x, mid_z, &under_y, &thickness);
  const V3 anchor(mid_x, under_y, mid_z);
  const V3 mid(mid_x, under_y - 0.6 * gb.radius, mid_z);
  gb.neck = mid - 0.5 * gb.length * gb.g;
  const V3 medial = perpendicular(gb.g, V3::UnitX());
  {
    const V3 towards = (-gb.up + 0.6 * medial).normalized();
    gb.pouch_angle = std::atan2(towards.dot(gb.side), towards.dot(gb.up));
  }
  // The gallbladder as shown: retracted about its neck (the duct leaves the neck as it lay).
  const GallbladderShape shown = retracted(gb, p.gallbladder_retraction_deg);
  auto liver_under = [&](double x, double z) {
    double y = 0.0;
    double t = 0.0;
    const double s = p.liver_scale;
    if (!liver.underside(anchor.x() + (x - anchor.x()) / s, anchor.z() + (z - anchor.z()) / s, &y,
                         &t)) {
      return anchor.y();
    }
    return anchor.y() + s * (y - anchor.y());
  };

  // Cystic duct: from the neck tip, continuing the gallbladder's axis, to the wall of the common
  // hepatic duct, arriving at the set angle to it; the junction lies the common hepatic duct's
  // length below the hilum, so a longer common hepatic duct is a lower insertion.
  const double r_duct = 0.5 * p.cystic_duct_inner_diameter_m + p.cystic_duct_wall_m;
  const double r_cbd = 0.5 * p.common_bile_duct_diameter_m;
  const V3 up_cbd = V3(0.05, 1.0, 0.15).normalized();
  const V3 lateral = perpendicular(up_cbd, -V3::UnitX());  // from the duct towards the gallbladder
  const double alpha = p.cystic_duct_angle_deg * kPi / 180.0;
  const V3 t_end = -(std::cos(alpha) * up_cbd + std::sin(alpha) * lateral);
  // Leaving the neck along the gallbladder's axis, turned down clear of the liver.
  const V3 t_start = (-gb.g - 0.9 * V3::UnitY()).normalized();
  const V3& n0 = gb.neck;
  // The porta hepatis, where the common hepatic duct leaves the liver: about 1 cm above the
  // gallbladder's neck (estimate); the duct itself runs on into the liver from there.
  const double hilum_y = n0.y() + 0.01;
  V3 junction = n0;
  std::vector<V3> duct;
  double chord = 0.85 * p.cystic_duct_length_m;
  for (int iter = 0; iter < 30; ++iter) {
    junction.z() = n0.z() - 0.006;
    junction.y() = hilum_y - p.common_hepatic_duct_length_m * up_cbd.y();
    double dy = junction.y() - n0.y();
    const double dz = junction.z() - n0.z();
    double dx2 = chord * chord - dy * dy - dz * dz;
    if (dx2 < std::pow(0.3 * chord, 2)) {
      // Too short a duct for so low a junction: the junction rises to what the duct reaches.
      dx2 = std::pow(0.3 * chord, 2);
      dy = -std::sqrt(std::max(0.0, chord * chord - dx2 - dz * dz));
      junction.y() = n0.y() + dy;
    }
    junction.x() = n0.x() + std::sqrt(dx2);
    const V3 along = junction - n0;
    const V3 wiggle = perpendicular(along.normalized(), along.cross(V3::UnitZ()));
    const double k = along.norm();
    const int waves = std::max(1, p.cystic_duct_half_waves);
    duct = sample_curve(200, [&](double s) {
      // sin(n pi s) sin(pi s) keeps the ends' position and direction; 1.3 scales its peak
      // (about 0.77 for n = 2) back to about the set excursion.
      const double w =
          1.3 * p.cystic_duct_tortuosity_m * std::sin(waves * kPi * s) * std::sin(kPi * s);
      return V3(hermite(n0, junction, k * t_start, k * t_end, s) + w * wiggle);
    });
    const double len = arc_length(duct);
    if (std::abs(len - p.cystic_duct_length_m) < 1e-7) break;
    chord *= p.cystic_duct_length_m / len;
  }
  const V3 arrive = (duct.back() - duct[duct.size() - 2]).normalized();
  duct = resample(duct, 0.001);
  CysticDuctReport& rep = out.cystic_duct;
  rep.centre_line_m = duct;
  rep.length_m = arc_length(duct);
  rep.axis = (duct.back() - duct.front()).normalized();
  rep.inner_diameter_m = p.cystic_duct_inner_diameter_m;
  rep.wall_m = p.cystic_duct_wall_m;
  rep.outer_diameter_m = 2.0 * r_duct;
  rep.junction_m = duct.back();
  rep.angle_to_common_hepatic_duct_deg =
      std::acos(std::clamp((-arrive).dot(up_cbd), -1.0, 1.0)) * 180.0 / kPi;
  // The duct's mesh runs 3 mm into the neck and on into the common bile duct's lumen.
  std::vector<V3> duct_mesh_line;
  duct_mesh_line.push_back(n0 + 0.003 * gb.g);
  duct_mesh_line.insert(duct_mesh_line.end(), duct.begin(), duct.end());
  const double into_cbd = std::min(0.008, 0.9 * r_cbd / std::max(std::sin(alpha), 0.2));
  duct_mesh_line.push_back(duct.back() + 0.5 * into_cbd * t_end);
  duct_mesh_line.push_back(duct.back() + into_cbd * t_end);

  // Common hepatic + common bile duct: straight, through the junction's wall point, from inside
  // the duodenum to a centimetre inside the liver's hilum.
  const V3 axis_point = junction - r_cbd * lateral;
  out.common_bile_duct_point_m = axis_point;
  out.common_bile_duct_up = up_cbd;
  out.common_hepatic_duct_length_m = (hilum_y - junction.y()) / up_cbd.y();
  const double to_liver =
      (liver_under(axis_point.x(), axis_point.z()) - axis_point.y()) / up_cbd.y();
  const double above = std::max(out.common_hepatic_duct_length_m, to_liver) + 0.012;
  const double duodenum_radius = 0.014;  // about 3 cm across (estimate; Gray's ch. 66)
  const V3 duodenum_entry = axis_point - 0.035 * up_cbd;
  const std::vector<V3> cbd_line = resample({duodenum_entry, axis_point + above * up_cbd}, 0.002);

  // Cystic artery: from behind the common hepatic duct (the right hepatic artery's side, not
  // modelled) across Calot's triangle above the duct to the gallbladder's neck-body junction.
  const V3 artery_start = axis_point + 0.016 * up_cbd - 0.006 * V3::UnitZ();
  const double s_gb = 0.3;
  const V3 shown_medial = perpendicular(shown.g, V3::UnitX());
  const V3 artery_end = shown.centre(s_gb) + 0.85 * shown.ring_radius(s_gb) *
                                                 (0.7 * shown.up + 0.7 * shown_medial).normalized();
  const double a_len = (artery_end - artery_start).norm();
  const std::vector<V3> artery =
      resample(sample_curve(60,
                            [&](double s) {
                              return hermite(artery_start, artery_end,
                                             a_len * V3(-1.0, 0.3, 0.3).normalized(),
                                             a_len * (-shown.up - 0.5 * shown.g).normalized(), s);
                            }),
               0.0015);
  const double r_artery = 0.5 * p.cystic_artery_diameter_m;

  // Clips before cholangiography (Sabiston ch. 54): two on the artery's patient side and one at
  // its gallbladder side; one on the cystic duct next to the neck, so no bile or stones come
  // down past the catheter.
  TriangleMesh clips;
  const double artery_len = arc_length(artery);
  for (double f : {0.3, 0.42, 0.78}) {
    V3 t;
    const V3 c = point_at_arc(artery, f * artery_len, &t);
    clips.append(make_clip(c, t, camera));
  }
  {
    V3 t;
    const V3 c = point_at_arc(duct, 0.12 * rep.length_m, &t);
    clips.append(make_clip(c, t, camera));
  }

  // Duodenum: the first part from the pylorus (medial) to the right, then bending down into the
  // second part, behind and below the gallbladder; the common bile duct ends in it.
  const V3 d0 = duodenum_entry;
  const std::vector<V3> duodenum_line = resample(
      sample_curve(80,
                   [&](double s) {
                     const V3 a = d0 + V3(0.055, 0.004, 0.012);
                     const V3 c = d0 + V3(-0.035, -0.05, -0.012);
                     if (s < 0.5) {
                       return V3(hermite(a, d0, V3(-0.06, 0, -0.01), V3(-0.06, 0, -0.01), 2 * s));
                     }
                     return V3(hermite(d0, c, V3(-0.06, 0, -0.01), V3(0, -0.06, 0), 2 * s - 1));
                   }),
      0.004);

  // The ductotomy: on the anterior wall facing the laparoscope, at the first site from 35 % of
  // the duct's length (past the clip at the neck) whose line of sight is clear of the
  // gallbladder, the liver, the artery, the clips and the duodenum (a short duct under a big
  // gallbladder is partly hidden behind it, as through the real laparoscope).
  TriangleMesh liver_mesh =
      make_liver(liver, p.liver_scale, anchor, shown, p.gallbladder_retraction_deg != 0.0);
  TriangleMesh gb_mesh = make_gallbladder(shown);
  TriangleMesh artery_mesh = make_tube(artery, std::vector<double>(artery.size(), r_artery), 12);
  TriangleMesh duodenum_mesh =
      make_tube(duodenum_line, std::vector<double>(duodenum_line.size(), duodenum_radius), 32);
  auto site = [&](double arc, V3* centre, V3* normal, V3* along) {
    const V3 c = point_at_arc(duct, arc, along);
    *normal = perpendicular(*along, camera - c);
    *centre = c + r_duct * *normal;
  };
  auto in_view = [&](const V3& point, const V3& normal) {
    const V3 from = point + 0.0005 * normal;
    for (const TriangleMesh* m : {&gb_mesh, &liver_mesh, &artery_mesh, &clips, &duodenum_mesh}) {
      if (segment_crosses(*m, from, camera)) return false;
    }
    return true;
  };
  rep.incision_arc_m = 0.35 * rep.length_m;
  for (double f = 0.35; f <= 0.8; f += 0.01) {
    V3 c, n, t;
    site(f * rep.length_m, &c, &n, &t);
    if (in_view(c, n)) {
      rep.incision_arc_m = f * rep.length_m;
      break;
    }
  }
  site(rep.incision_arc_m, &rep.incision_center_m, &rep.incision_normal, &rep.incision_along);

  // Fat over the hepatoduodenal ligament: a lobulated body around the common bile duct below
  // the junction, bigger and reaching up round the junction in a fatty hilum; it never covers
  // the incision site.
  const V3 fat_centre =
      axis_point - 0.02 * up_cbd + V3(0.004, 0.0, -0.003) + (p.hilum_fat - 1.0) * 0.006 * up_cbd;
  V3 fat_radii = V3(0.011, 0.02, 0.009) * std::sqrt(p.hilum_fat);
  fat_radii.y() = 0.02 + 0.008 * (p.hilum_fat - 1.0);
  const V3 fat_x = perpendicular(up_cbd, V3::UnitX());
  const V3 fat_z = fat_x.cross(up_cbd);
  auto fat_inside = [&](const V3& q) {
    const V3 d = q - fat_centre;
    return std::pow(d.dot(fat_x) / fat_radii.x(), 2) + std::pow(d.dot(up_cbd) / fat_radii.y(), 2) +
           std::pow(d.dot(fat_z) / fat_radii.z(), 2);
  };
  const double clearance = fat_inside(rep.incision_center_m + 0.004 * rep.incision_normal);
  if (clearance < 1.69) fat_radii *= std::sqrt(clearance / 1.69);

  // --- meshes
  auto add = [&](std::string name, TriangleMesh mesh, Tissue tissue, double tile) {
    finish(mesh, tile);
    out.organs.push_back({std::move(name), std::move(mesh), tissue, tile});
  };
  add("liver", std::move(liver_mesh), Tissue::liver, 0.06);
  add("gallbladder", std::move(gb_mesh), Tissue::gallbladder, 0.05);
  add("cystic_duct",
      make_tube(duct_mesh_line, std::vector<double>(duct_mesh_line.size(), r_duct), 24),
      Tissue::bile_duct, 0.02);
  add("common_bile_duct", make_tube(cbd_line, std::vector<double>(cbd_line.size(), r_cbd), 24),
      Tissue::bile_duct, 0.02);
  add("cystic_artery", std::move(artery_mesh), Tissue::artery, 0.02);
  add("clips", clips, Tissue::clip, 0.01);
  add("duodenum", std::move(duodenum_mesh), Tissue::duodenum, 0.06);
  auto make_fat = [&]() {
    return make_mapped_sphere(20, 40, [&](const V3& u) {
      // Lobulated: the radius varies by up to 8 % with smooth bumps (star-shaped, so embedded).
      const double bump = 1.0 + 0.08 * std::sin(7.0 * u.x() + 2.0) * std::sin(5.0 * u.y() + 1.0) *
                                    std::cos(6.0 * u.z());
      return V3(fat_centre +
                bump * (fat_radii.x() * u.x() * fat_x + fat_radii.y() * u.y() * up_cbd +
                        fat_radii.z() * u.z() * fat_z));
    });
  };
  TriangleMesh fat = make_fat();
  for (int i = 0;
       i < 20 && segment_crosses(fat, rep.incision_center_m + 0.0005 * rep.incision_normal, camera);
       ++i) {
    fat_radii *= 0.95;  // the fat must not hide the incision either
    fat = make_fat();
  }
  add("hepatoduodenal_fat", std::move(fat), Tissue::fat, 0.04);

  // Abdominal wall: an insufflated dome (radius 22 cm, 2.5 cm thick: estimates) whose inner
  // surface passes 1.2 cm beyond the laparoscope, with the four ports of the standard
  // (American) technique (Sabiston ch. 54): 12 mm umbilical for the laparoscope, 10 mm
  // epigastric, and two 5 mm right subcostal (midclavicular and anterior axillary lines).
  Dome dome;
  const V3 apex = camera + V3(0.0, 0.0, 0.012);
  dome.centre = apex - dome.radius * V3::UnitZ();
  const double midline_x = camera.x();
  struct Site {
    const char* name;
    double x, y, d;
  };
  for (const Site& s :
       {Site{"umbilical", camera.x(), camera.y(), 0.012},
        Site{"epigastric", midline_x, camera.y() + 0.115, 0.010},
        Site{"right_midclavicular", midline_x - 0.085,
             camera.y() + 0.085 - p.midclavicular_port_caudal_m, 0.005},
        Site{"right_anterior_axillary", midline_x - 0.12 - p.anterior_axillary_port_lateral_m,
             camera.y() + 0.03 - p.anterior_axillary_port_caudal_m, 0.005}}) {
    PortSite port;
    port.name = s.name;
    port.position_m = V3(s.x, s.y, dome.inner_z(s.x, s.y));
    port.inward = (dome.centre - port.position_m).normalized();
    port.diameter_m = s.d;
    out.ports.push_back(port);
  }
  // The wall's patch: 15 cm round the umbilicus, wider where a port placed for the patient lies
  // nearer its rim than 2.5 cm (estimate: enough wall round the hole to hold the trocar).
  double extent_m = 0.15;
  for (const PortSite& port : out.ports) {
    extent_m = std::max(
        extent_m,
        std::hypot(port.position_m.x() - apex.x(), port.position_m.y() - apex.y()) + 0.025);
  }
  add("abdominal_wall", make_abdominal_wall(dome, apex, extent_m, out.ports),
      Tissue::abdominal_wall, 0.08);
  return out;
}

}  // namespace lap::haptics
