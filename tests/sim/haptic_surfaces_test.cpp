// The proxies' three copies of the organ surfaces (haptic_surfaces.h): the modelling thread's
// side takes up every step into its copy (a dent now held, now moved on), the haptic side takes
// only some of them, and the copy it holds is still exactly the surface of the newest step —
// checked against databases built afresh over that surface (vertex normals, first contacts), its
// edge tree's boxes containing their edges, and its shading normals equal to a fresh build's.

#include "sim/runtime/haptic_surfaces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "haptics/setup/mesh_generators.h"
#include "hardware/triple_buffer.h"

namespace lap::sim {
namespace {

// Step s of a dent moving round the sphere's equator, 15 mm across: held in one place for
// four steps at a time while it deepens (2, 2.33, 2.67, 3 mm), then moved on.
SurfaceDeformation dent_at_step(const haptics::TriangleMesh& m, int s) {
  const double a = 0.3 * (s / 4);
  const double depth = 0.04 + 0.02 * (s % 4) / 3.0;
  const Eigen::Vector3d centre = 0.05 * Eigen::Vector3d(std::cos(a), 0.0, std::sin(a));
  SurfaceDeformation d(m.positions.size());
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const double dist = (m.positions[v] - centre).norm();
    if (dist >= 0.015) continue;
    d.vertex[static_cast<size_t>(d.count)] = static_cast<int32_t>(v);
    d.position[static_cast<size_t>(d.count++)] =
        m.positions[v] * (1.0 - depth * (0.015 - dist) / 0.015);
  }
  return d;
}

TEST(HapticSurfaces, TheCopyTheHapticSideHoldsIsTheNewestStepsSurfaceWhateverItSkipped) {
  const haptics::TriangleMesh sphere = haptics::make_uv_sphere(0.05, 40, 80);
  const haptics::MeshDatabase rest = haptics::MeshDatabase::build(sphere);
  const haptics::SegmentDatabase rest_edges = haptics::SegmentDatabase::build(rest);
  const double crease = 0.5;
  const haptics::ShadingNormals rest_shading = haptics::ShadingNormals::build(rest, crease);
  const std::vector<const haptics::MeshDatabase*> dbs = {&rest};
  const std::vector<const haptics::SegmentDatabase*> sds = {&rest_edges};
  const std::vector<const haptics::ShadingNormals*> shading = {&rest_shading};
  hardware::TripleBuffer<std::unique_ptr<HapticSurfaces>> buffer;
  std::array<std::unique_ptr<HapticSurfaces>, 3> copies;
  for (auto& c : copies) c = std::make_unique<HapticSurfaces>(dbs, sds, shading);
  buffer.reset(std::move(copies));

  std::vector<haptics::HapticObject> objects(1);
  buffer.read()->point(objects);
  ASSERT_EQ(objects[0].mesh, &buffer.read()->db(0));
  int taken = 0;
  for (int s = 1; s <= 40; ++s) {
    const std::vector<SurfaceDeformation> d = {dent_at_step(sphere, s)};
    ASSERT_GT(d[0].count, 10);
    buffer.write_slot()->take_up(d, s);
    buffer.publish();
    // The haptic side looks only now and then (and misses steps in between).
    if (s % 7 == 0 || s == 40) {
      ASSERT_TRUE(buffer.update());
      buffer.read()->point(objects);
      ++taken;
    }
  }
  const HapticSurfaces& held = *buffer.read();
  EXPECT_EQ(held.model_steps(), 40);
  EXPECT_EQ(objects[0].mesh, &held.db(0));
  ASSERT_NE(objects[0].segments, nullptr);
  ASSERT_NE(objects[0].shading, nullptr);
  EXPECT_EQ(&objects[0].segments->mesh(), &held.db(0));

  // The reference: the surface of step 40, built afresh.
  haptics::TriangleMesh last = sphere;
  const SurfaceDeformation d40 = dent_at_step(sphere, 40);
  for (int32_t k = 0; k < d40.count; ++k) {
    last.positions[static_cast<size_t>(d40.vertex[static_cast<size_t>(k)])] =
        d40.position[static_cast<size_t>(k)];
  }
  const haptics::MeshDatabase fresh = haptics::MeshDatabase::build(last);
  const haptics::MeshDatabase& db = held.db(0);
  double normal_error = 0.0;
  for (int32_t v = 0; v < db.vertex_count(); ++v) {
    ASSERT_EQ(db.position(v), last.positions[static_cast<size_t>(v)]) << "vertex " << v;
    normal_error = std::max(normal_error, (db.vertex_normal(v) - fresh.vertex_normal(v)).norm());
  }
  EXPECT_LT(normal_error, 1e-12);
  // First contacts through the refitted face tree agree with the fresh one's.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.07, 0.07);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p0(u(rng), u(rng), u(rng));
    const Eigen::Vector3d p1(u(rng), u(rng), u(rng));
    const auto a = db.first_crossing(p0, p1, false);
    const auto b = fresh.first_crossing(p0, p1, false);
    ASSERT_EQ(a.face >= 0, b.face >= 0) << i;
    if (a.face >= 0) {
      ++hits;
      EXPECT_DOUBLE_EQ(a.t, b.t) << i;
    }
  }
  EXPECT_GT(hits, 100);
  // The edge tree's boxes hold their edges as they now are.
  const haptics::SegmentDatabase& edges = *objects[0].segments;
  const auto tree_edges = edges.tree_edges();
  for (const haptics::BvhNode& n : edges.edge_tree().nodes()) {
    for (int32_t k = n.first; n.count > 0 && k < n.first + n.count; ++k) {
      for (const int32_t v : db.edge_vertices(tree_edges[static_cast<size_t>(k)])) {
        for (int a = 0; a < 3; ++a) {
          ASSERT_LE(n.lo[static_cast<size_t>(a)], db.position(v)[a]);
          ASSERT_GE(n.hi[static_cast<size_t>(a)], db.position(v)[a]);
        }
      }
    }
  }
  // And the shading normals are those of the dented surface.
  const haptics::ShadingNormals want = haptics::ShadingNormals::build(db, crease);
  double shading_error = 0.0;
  for (int32_t f = 0; f < db.face_count(); ++f) {
    for (size_t k = 0; k < 3; ++k) {
      shading_error =
          std::max(shading_error,
                   (objects[0].shading->corner_normals(f)[k] - want.corner_normals(f)[k]).norm());
    }
  }
  EXPECT_LT(shading_error, 1e-12);
  EXPECT_EQ(taken, 6);
  // While the dent was held, copies took it up again through the region found before.
  // The three copies: the one read, the one being written, and the one published before it.
  int64_t reused = buffer.read()->regions_reused();
  int64_t all = buffer.read()->regions_taken_up();
  for (int i = 0; i < 2; ++i) {
    reused += buffer.write_slot()->regions_reused();
    all += buffer.write_slot()->regions_taken_up();
    buffer.publish();
  }
  EXPECT_EQ(all, 40);  // each step taken up by one copy
  EXPECT_GT(reused, 0);
  EXPECT_LT(reused, all);
}

}  // namespace
}  // namespace lap::sim
