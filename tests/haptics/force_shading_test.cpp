// Force shading (§6.1): stroking a tessellated cylinder feels smooth, its flat ends stay sharp.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/point_proxy.h"
#include "haptics/setup/mesh_generators.h"
#include "haptics/shading_normals.h"
#include "tests/test_support.h"

namespace lap::haptics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kR = 0.02;
constexpr double kLength = 0.06;
constexpr int kSlices = 24;
constexpr double kDt = 0.001;

using test::angle_between;

struct Cylinder {
  MeshDatabase mesh = MeshDatabase::build(make_cylinder(kR, kLength, kSlices, 4));
  ShadingNormals shading = ShadingNormals::build(mesh, 30.0 * kPi / 180.0);
  HapticObject object(bool shaded) const {
    HapticObject o;
    o.mesh = &mesh;
    o.shading = shaded ? &shading : nullptr;
    o.law.stiffness_n_per_m = 1000.0;
    o.law.max_force_n = 1e9;
    return o;
  }
};

// The HIP enters radially at height y and angle 0, then circles the axis at radius r.
// Returns the largest angle between consecutive force directions over one turn.
double stroke(const HapticObject& o, double r, double y, double dphi,
              std::vector<Eigen::Vector3d>* forces = nullptr) {
  PointProxy proxy;
  auto at = [&](double radius, double phi) {
    return Eigen::Vector3d(radius * std::cos(phi), y, -radius * std::sin(phi));
  };
  proxy.reset(at(kR + 0.005, 0.0));
  for (int i = 1; i <= 60; ++i)
    proxy.step({&o, 1}, at(kR + 0.005 - i * (kR + 0.005 - r) / 60, 0.0), kDt);
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  double worst = 0.0;
  const int ticks = static_cast<int>(std::lround(2.0 * kPi / dphi));
  for (int i = 1; i <= ticks; ++i) {
    const PointProxyOutput out = proxy.step({&o, 1}, at(r, i * dphi), kDt);
    EXPECT_EQ(out.contact_count, 1) << "tick " << i;
    const Eigen::Vector3d f = out.force_W;
    if (forces != nullptr) forces->push_back(f);
    if (i > 1) worst = std::max(worst, angle_between(previous, f));
    previous = f;
  }
  return worst;
}

TEST(ForceShading, StrokingACylinderTurnsTheForceSmoothlyWithinTheTessellationBound) {
  const Cylinder c;
  const double facet = 2.0 * kPi / kSlices;  // Δφ between neighbouring facets
  const double dphi = facet / 20.0;          // the HIP's turn per tick
  const double r = kR - 0.001;               // 1 mm under the vertices
  // On a facet the shaded normal is normalize((1 - x) n_j + x n_j+1) with x the IHIP's
  // fraction across it (the two triangles of a facet interpolate alike), so its turn rate is
  // |n_j x n_j+1| / |v|^2 <= 2 tan(Δφ/2) per unit x; x moves r cos(.)/(2 R sin(Δφ/2)) per
  // radian of the HIP. Together: at most dphi * r / (R cos(Δφ/2)) per tick.
  // Plus one jump per facet: the IHIP keeps to the facet it entered until the HIP leaves the
  // region under it (Figure 2-11), where it sits on the edge (x = 1); on the next facet it
  // starts at the HIP's projection, at most depth * sin Δφ from the edge (depth <= R - r),
  // i.e. x' <= depth sin Δφ / (2 R sin(Δφ/2)), turning the normal by at most
  // x' sin Δφ / cos²(Δφ/2). (The thesis: shading works while the penetration is small
  // compared with the polygon.)
  const double half = facet / 2.0;
  const double per_tick = dphi * r / (kR * std::cos(half));
  const double jump = (kR - r) * std::sin(facet) / (2.0 * kR * std::sin(half)) * std::sin(facet) /
                      (std::cos(half) * std::cos(half));
  const double bound = per_tick + jump;
  std::vector<Eigen::Vector3d> forces;
  const double shaded = stroke(c.object(true), r, 0.0225, dphi, &forces);
  const double flat = stroke(c.object(false), r, 0.0225, dphi);
  std::printf("stroke: shaded max turn %.5f rad (bound %.5f), flat max turn %.5f rad, ratio %.1f\n",
              shaded, bound, flat, flat / shaded);
  EXPECT_LE(shaded, bound + 1e-9);
  EXPECT_GE(flat, 0.9 * facet);  // without shading the force jumps by a facet at each edge
  EXPECT_LE(5.0 * shaded, flat);
  // The shaded force is horizontal, points outward, and its magnitude is k times the HIP's
  // distance to the facet plane along the shaded normal (Figure 6-3).
  for (const Eigen::Vector3d& f : forces) {
    EXPECT_NEAR(f.y(), 0.0, 1e-9);
    EXPECT_GT(f.norm(), 1000.0 * (kR * std::cos(facet / 2.0) - r) * 0.999);
    EXPECT_LT(f.norm(), 1000.0 * (kR - r) / std::cos(facet / 2.0) * 1.001);
  }
}

TEST(ForceShading, AtAFacetEdgeTheShadedNormalIsTheVertexNormal) {
  const Cylinder c;
  // Vertex column j = 0 lies at angle 0: its shaded normal is radial, +x.
  const MeshDatabase& m = c.mesh;
  for (int32_t f = 0; f < m.face_count(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& p = m.position(m.face_vertices(f)[k]);
      const Eigen::Vector3d n = c.shading.corner_normals(f)[k];
      const bool cap = std::abs(m.face_normal(f).y()) > 0.5;
      if (cap) {
        EXPECT_NEAR(std::abs(n.y()), 1.0, 1e-12);  // ends do not blend with the side
      } else {
        const Eigen::Vector3d radial = Eigen::Vector3d(p.x(), 0.0, p.z()).normalized();
        EXPECT_NEAR((n - radial).norm(), 0.0, 1e-12);
      }
    }
  }
}

TEST(ForceShading, FlatEndsKeepTheirEdge) {
  const Cylinder c;
  const HapticObject o = c.object(true);
  // Pressing the top end near the rim: the force is along the axis, exactly.
  PointProxy top;
  const Eigen::Vector3d above(0.018, kLength + 0.003, 0.0);
  top.reset(above);
  PointProxyOutput out;
  for (int i = 1; i <= 40; ++i) {
    out = top.step({&o, 1}, above - Eigen::Vector3d(0, 0.004 * i / 40.0, 0), kDt);
  }
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_NEAR(angle_between(out.force_W, Eigen::Vector3d::UnitY()), 0.0, 1e-9);
  EXPECT_NEAR(out.force_W.norm(), 1000.0 * 0.001, 1e-9);
  // Pressing the side 1 mm below the rim: the force is horizontal — 90° from the end's.
  PointProxy side;
  const Eigen::Vector3d outside(kR + 0.003, kLength - 0.001, 0.0);
  side.reset(outside);
  for (int i = 1; i <= 40; ++i) {
    out = side.step({&o, 1}, outside - Eigen::Vector3d(0.004 * i / 40.0, 0, 0), kDt);
  }
  ASSERT_EQ(out.contact_count, 1);
  EXPECT_NEAR(out.force_W.normalized().y(), 0.0, 1e-9);
  EXPECT_GT(out.force_W.x(), 0.0);
}

// A dent (§6.5) changes the normals the shading blends: after the update the corner normals are
// those a build over the dented surface gives (the brute-force reference), across the rim's
// crease and the edge of a region with shading switched off.
TEST(ForceShading, ADentedSurfaceIsShadedLikeItsDeformedShape) {
  MeshDatabase mesh = MeshDatabase::build(make_cylinder(kR, kLength, 2 * kSlices, 12));
  std::vector<uint8_t> shaded(static_cast<size_t>(mesh.face_count()), 1);
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    const auto& v = mesh.face_vertices(f);
    const double z = (mesh.position(v[0]) + mesh.position(v[1]) + mesh.position(v[2])).z();
    if (z < -1e-9) shaded[static_cast<size_t>(f)] = 0;  // the back half: flat polygons
  }
  const double crease = 30.0 * kPi / 180.0;
  ShadingNormals shading = ShadingNormals::build(mesh, crease, shaded);
  const ShadingNormals at_rest = shading;
  MeshUpdateScratch scratch(mesh);
  // Pressed in 1.5 mm at the rim, where the side meets the flat top and the shaded half meets
  // the flat one; linear profile over 12 mm.
  const Eigen::Vector3d centre(kR, kLength, 0.0);
  std::vector<Eigen::Vector3d> positions(static_cast<size_t>(mesh.vertex_count()));
  std::vector<int32_t> moved;
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Vector3d& p = mesh.position(v);
    const double d = (p - centre).norm();
    positions[static_cast<size_t>(v)] = p;
    if (d >= 0.012) continue;
    positions[static_cast<size_t>(v)] += (0.012 - d) / 0.012 * Eigen::Vector3d(-0.0015, -0.0005, 0);
    moved.push_back(v);
  }
  ASSERT_GT(moved.size(), 20U);
  mesh.set_positions(positions, moved, &scratch);
  shading.update(mesh, scratch.dirty_vertices);
  ShadingNormals by_lists = at_rest;  // the same through the workspace's face lists
  by_lists.update(mesh, scratch);
  const ShadingNormals reference = ShadingNormals::build(mesh, crease, shaded);
  double worst = 0.0;
  double worst_by_lists = 0.0;
  double stale = 0.0;
  for (int32_t f = 0; f < mesh.face_count(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& want = reference.corner_normals(f)[static_cast<size_t>(k)];
      worst = std::max(worst, (shading.corner_normals(f)[static_cast<size_t>(k)] - want).norm());
      worst_by_lists = std::max(worst_by_lists,
                                (by_lists.corner_normals(f)[static_cast<size_t>(k)] - want).norm());
      stale = std::max(stale, (at_rest.corner_normals(f)[static_cast<size_t>(k)] - want).norm());
    }
  }
  std::printf(
      "dented shading: worst corner error %.2e (by face lists %.2e), the rest shape's %.3f\n",
      worst, worst_by_lists, stale);
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worst_by_lists, 1e-12);
  EXPECT_GT(stale, 0.05);  // the dent did change them: the test can tell
}

// Figure 6-3's penetration vector as the shaded normal turns from the contacted plane's (θ = 0)
// to its reverse (θ = 180°), with the segment proxy's two-sided flip (the shaded normal is turned
// to the contact's side when it points away). The spring's normal part is always the depth; the
// shaded push is Figure 6-3's own up to 60°, none from 75°; and nothing jumps. Without the flip
// (the point proxy turns the shaded normal by the contact's side only) a shaded normal pointing
// away gives the plane's push, never a pull. The old form (divide by max(cos, 0.1)) passes only
// the finiteness and the up-to-60° checks: the normal part off by the whole depth, no plain push
// past 75°, 10 depths sideways, a jump of 20 depths at 90° (the default patient's flipping
// press, docs/anatomy.md), a pull past 90° unflipped.
TEST(ForceShading, TheShadedPushFadesToThePlanesNormalBeforeItCouldFlip) {
  const double depth = 0.004;
  const Eigen::Vector3d n(0.0, 0.0, 1.0);
  const int steps = 1800;  // 0.1°
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  double worst_jump = 0.0;
  double worst_lateral = 0.0;
  for (int i = 0; i <= steps; ++i) {
    const double theta = kPi * i / steps;
    Eigen::Vector3d shaded(std::sin(theta), 0.0, std::cos(theta));
    if (shaded.dot(n) < 0.0) shaded = -shaded;
    const Eigen::Vector3d p = shaded_penetration(depth, n, shaded);
    ASSERT_TRUE(p.allFinite()) << theta;
    EXPECT_NEAR(p.dot(n), -depth, 1e-15) << "the normal part at " << theta * 180.0 / kPi << "°";
    const double c = shaded.dot(n);
    if (c >= std::cos(60.0 * kPi / 180.0)) {
      EXPECT_LT((p + (depth / c) * shaded).norm(), 1e-15) << theta * 180.0 / kPi << "°";
    }
    if (c <= std::cos(75.0 * kPi / 180.0)) {
      EXPECT_LT((p + depth * n).norm(), 1e-15) << theta * 180.0 / kPi << "°";
    }
    worst_lateral = std::max(worst_lateral, (p - p.dot(n) * n).norm());
    if (i > 0) worst_jump = std::max(worst_jump, (p - previous).norm());
    previous = p;
  }
  // Lateral push at most tan 60° times the depth; over 0.1° the steepest change is Figure 6-3's
  // own at 60°, depth / cos² 60° per radian (0.007 depth), and the fade's, a few times that.
  EXPECT_LE(worst_lateral, std::tan(60.0 * kPi / 180.0) * depth * (1.0 + 1e-12));
  EXPECT_LT(worst_jump, 0.05 * depth);
  for (int i = steps / 2 + 1; i <= steps; ++i) {
    const double theta = kPi * i / steps;
    const Eigen::Vector3d away(std::sin(theta), 0.0, std::cos(theta));
    EXPECT_LT((shaded_penetration(depth, n, away) + depth * n).norm(), 1e-15)
        << "unflipped at " << theta * 180.0 / kPi << "°";
  }
  std::printf(
      "shaded penetration: lateral at most %.3f depth, largest change per 0.1° %.4f depth\n",
      worst_lateral / depth, worst_jump / depth);
}

TEST(ForceShading, RegionSwitchedOffFeelsLikeFlatPolygons) {
  const Cylinder c;
  const std::vector<uint8_t> off(c.mesh.face_count(), 0);
  const ShadingNormals none = ShadingNormals::build(c.mesh, 30.0 * kPi / 180.0, off);
  HapticObject with_none = c.object(false);
  with_none.shading = &none;
  const HapticObject flat = c.object(false);
  std::vector<Eigen::Vector3d> a;
  std::vector<Eigen::Vector3d> b;
  const double dphi = 2.0 * kPi / kSlices / 7.0;
  stroke(with_none, kR - 0.001, 0.0225, dphi, &a);
  stroke(flat, kR - 0.001, 0.0225, dphi, &b);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_LT((a[i] - b[i]).norm(), 1e-12) << i;
}

}  // namespace
}  // namespace lap::haptics
