// The haptic step allocates nothing after warm-up. Proven with a
// counting operator new over thousands of steps that make and lose contact, slide, touch two
// objects at once, and refit a deforming mesh.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "haptics/friction.h"
#include "haptics/image_height_field.h"
#include "haptics/laparoscopic_gripper.h"
#include "haptics/mesh_database.h"
#include "haptics/point_proxy.h"
#include "haptics/procedural_textures.h"
#include "haptics/segment_database.h"
#include "haptics/segment_proxy.h"
#include "haptics/setup/mesh_generators.h"
#include "haptics/shading_normals.h"
#include "tests/support/counting_allocator.h"

namespace lap::haptics {
namespace {

TEST(PointProxyAllocation, StepAndRefitAllocateNothing) {
  TriangleMesh sphere_mesh = make_uv_sphere(0.03, 40, 80);
  MeshDatabase sphere = MeshDatabase::build(sphere_mesh);
  TriangleMesh box_mesh = make_box(Eigen::Vector3d(0.04, 0.04, 0.04), 6);
  box_mesh.transform(Eigen::Affine3d(Eigen::Translation3d(0.05, 0.0, 0.0)));
  const MeshDatabase box = MeshDatabase::build(box_mesh);
  const ShadingNormals box_shading = ShadingNormals::build(box, 0.5);  // force shading (§6.1)
  const MeshDatabase plate = MeshDatabase::build(make_plate(0.2, 10));
  HapticObject objects[3];
  objects[0].mesh = &sphere;
  objects[1].mesh = &box;
  objects[1].shading = &box_shading;
  objects[2].mesh = &plate;
  objects[2].two_sided = true;
  objects[2].pose_WO = objects[2].prev_pose_WO =
      Eigen::Isometry3d(Eigen::Translation3d(0.0, -0.035, 0.0));
  // Surface properties (§6.2, §6.3): a procedural texture with friction on the sphere, an image
  // texture with a random friction map on the plate.
  const WorleyCells cells(0.0004, 0.004);
  FrictionModel friction;
  friction.mu_static = 0.4;
  friction.mu_dynamic = 0.25;
  friction.stick_stiffness_n_per_m = 800.0;
  friction.slide_stiffness_n_per_m = 500.0;
  FrictionModel sandpaper = friction;
  sandpaper.map.kind = FrictionCoefficientMap::Kind::kRandom;
  objects[0].texture = &cells;
  objects[0].friction = &friction;
  HeightImage image;
  image.width = 32;
  image.height = 32;
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 32; ++x)
      image.values.push_back(0.5F + 0.5F * std::sin(0.4F * x + 0.3F * y));
  }
  IntermediateSurface plane;
  plane.frame_OS = Eigen::AngleAxisd(-M_PI / 2.0, Eigen::Vector3d::UnitX());  // z = plate normal
  const ImageHeightField image_texture(image, plane, 0.0003, 0.0001);
  objects[2].texture = &image_texture;
  objects[2].friction = &sandpaper;
  std::vector<Eigen::Vector3d> deformed = sphere_mesh.positions;  // sized before measuring

  PointProxy proxy;
  auto run = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      const double t = i * 0.001;
      // A path that dives into the sphere, slides over it, crosses to the box, and down to the
      // plate: first contacts, releases, two objects at once.
      const Eigen::Vector3d hip(0.045 * std::sin(1.3 * t), 0.033 * std::cos(2.1 * t) - 0.004,
                                0.01 * std::sin(0.7 * t));
      objects[1].prev_pose_WO = objects[1].pose_WO;
      objects[1].pose_WO = Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.002 * std::sin(t), 0.0));
      const PointProxyOutput out = proxy.step(objects, hip, 0.001);
      ASSERT_TRUE(out.force_W.allFinite());
      if (i % 50 == 0) {
        const double s = 1.0 + 0.02 * std::sin(t);
        for (size_t v = 0; v < deformed.size(); ++v) deformed[v] = sphere_mesh.positions[v] * s;
        sphere.set_positions(deformed);
      }
    }
  };
  run(0, 1000);  // warm-up
  int64_t allocations = -1;
  {
    test::AllocationCounter counter;
    run(1000, 21000);
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
  // The path really exercised the proxy.
  EXPECT_GT(proxy.stats().first_contacts, 10);
  EXPECT_GT(proxy.stats().releases, 10);
  EXPECT_GT(proxy.stats().texture_only_ticks, 10);
  EXPECT_GT(proxy.friction_state().stick_to_slide, 10);
}

// The modelling loop's side of a deforming surface: a dent sliding over a sphere, now jumping,
// now released, taken up by the incremental update of the mesh and its edge tree (the region
// kept from step to step, a workspace that missed an update), allocates nothing either.
TEST(MeshUpdateAllocation, IncrementalSurfaceUpdatesAllocateNothing) {
  const TriangleMesh mesh = make_uv_sphere(0.03, 40, 80);
  MeshDatabase db = MeshDatabase::build(mesh);
  SegmentDatabase edges = SegmentDatabase::build(db);
  MeshUpdateScratch scratch(db);
  SegmentUpdateScratch edge_scratch(edges);
  const auto n = static_cast<size_t>(db.vertex_count());
  std::vector<Eigen::Vector3d> positions = mesh.positions;
  std::vector<int32_t> displaced;
  std::vector<int32_t> now;
  std::vector<int32_t> moved;
  std::vector<uint8_t> was(n, 0);
  for (auto* list : {&displaced, &now, &moved}) list->reserve(n);
  auto run = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      const double a = (i % 500 < 400 ? 0.004 * i : 1.7 * i);  // sliding, then jumping
      const Eigen::Vector3d centre = 0.03 * Eigen::Vector3d(std::cos(a), 0.3, std::sin(a));
      now.clear();
      for (size_t v = 0; v < n; ++v) {
        const double d = (mesh.positions[v] - centre).norm();
        const bool dented = d < 0.008 && i % 97 != 0;  // now and then released
        positions[v] = dented
                           ? Eigen::Vector3d(mesh.positions[v] * (1.0 - 0.1 * (0.008 - d) / 0.008))
                           : mesh.positions[v];
        if (dented) now.push_back(static_cast<int32_t>(v));
      }
      moved.assign(displaced.begin(), displaced.end());
      for (const int32_t v : displaced) was[static_cast<size_t>(v)] = 1;
      for (const int32_t v : now) {
        if (was[static_cast<size_t>(v)] == 0) moved.push_back(v);
      }
      for (const int32_t v : displaced) was[static_cast<size_t>(v)] = 0;
      displaced.assign(now.begin(), now.end());
      if (moved.empty()) continue;
      db.set_positions(positions, moved, &scratch);
      if (i % 41 != 0)
        edges.refit_moved_edges(scratch.moved, &edge_scratch);  // now and then missed
    }
  };
  run(0, 200);  // warm-up
  int64_t allocations = -1;
  {
    test::AllocationCounter counter;
    run(200, 2200);
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(scratch.regions_updated, 1000);
}

TEST(SegmentProxyAllocation, SegmentAndGripperStepsAllocateNothing) {
  const MeshDatabase sphere = MeshDatabase::build(make_uv_sphere(0.03, 40, 80));
  const SegmentDatabase sphere_segments = SegmentDatabase::build(sphere);
  TriangleMesh box_mesh = make_box(Eigen::Vector3d(0.04, 0.04, 0.04), 6);
  box_mesh.transform(Eigen::Affine3d(Eigen::Translation3d(0.05, 0.0, 0.0)));
  const MeshDatabase box = MeshDatabase::build(box_mesh);
  const SegmentDatabase box_segments = SegmentDatabase::build(box);
  HapticObject objects[2];
  objects[0].mesh = &sphere;
  objects[0].segments = &sphere_segments;
  objects[1].mesh = &box;
  objects[1].segments = &box_segments;
  SegmentProxy proxy;
  LaparoscopicGripper gripper;
  auto run = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      const double t = i * 0.001;
      // The tip dives into the sphere and sweeps across to the box; the shaft swings.
      const Eigen::Vector3d tip(0.045 * std::sin(1.3 * t), 0.033 * std::cos(2.1 * t) - 0.004,
                                0.01 * std::sin(0.7 * t));
      const Eigen::Vector3d dir =
          Eigen::Vector3d(0.6 * std::sin(0.9 * t), 1.0, 0.4 * std::cos(0.5 * t)).normalized();
      objects[1].prev_pose_WO = objects[1].pose_WO;
      objects[1].pose_WO = Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.002 * std::sin(t), 0.0));
      const SegmentProxyOutput out = proxy.step(objects, tip, tip + 0.1 * dir, 0.001);
      ASSERT_TRUE(out.force_W.allFinite());
      GripperPose pose;
      pose.hinge_W = tip;
      pose.shaft_dir_W = dir;
      pose.open_dir_W = dir.cross(Eigen::Vector3d::UnitZ()).normalized();
      pose.opening_rad = 0.5 + 0.4 * std::sin(3.0 * t);
      const GripperOutput g = gripper.step(objects, pose, 0.001);
      ASSERT_TRUE(g.force_W.allFinite());
    }
  };
  run(0, 1000);
  int64_t allocations = -1;
  {
    test::AllocationCounter counter;
    run(1000, 21000);
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(proxy.stats().first_contacts, 10);
  EXPECT_GT(proxy.stats().releases, 10);
  EXPECT_GT(gripper.proxy(1).stats().swept_hits, 10);
}

TEST(PointProxyAllocation, TheCounterCounts) {
  test::AllocationCounter counter;
  auto* p = new std::vector<int>(100);
  delete p;
  EXPECT_GE(counter.count(), 2);
}

}  // namespace
}  // namespace lap::haptics
