#include "haptics/setup/mesh_repair.h"

#include <gtest/gtest.h>

#include "haptics/setup/mesh_generators.h"
#include "tests/test_support.h"

namespace lap::haptics {
namespace {

TEST(WeldVertices, ExactDuplicatesOfATriangleSoup) {
  // A tetrahedron as a soup: 12 vertices, one copy per triangle corner (as STL stores it).
  const TriangleMesh t = test::tetrahedron();
  TriangleMesh soup;
  for (const Triangle& tri : t.triangles) {
    const int32_t b = soup.vertex_count();
    for (int32_t v : tri) soup.positions.push_back(t.positions[v]);
    soup.triangles.push_back({b, b + 1, b + 2});
  }
  EXPECT_EQ(weld_vertices(soup, 0.0), 8);
  EXPECT_EQ(soup.vertex_count(), 4);
  EXPECT_TRUE(validate_mesh(soup).clean());
}

TEST(WeldVertices, ToleranceMergesNearbyButNotDistantVertices) {
  TriangleMesh m = test::tetrahedron();
  m.positions.push_back(m.positions[1] + Eigen::Vector3d(4e-7, 0, 0));
  m.triangles[1][1] = 4;  // one triangle uses the near-copy of vertex 1
  TriangleMesh loose = m;
  EXPECT_EQ(weld_vertices(loose, 1e-7), 0);  // 4e-7 apart: kept apart at 1e-7
  EXPECT_FALSE(validate_mesh(loose).clean());
  EXPECT_EQ(weld_vertices(m, 1e-6), 1);
  EXPECT_TRUE(validate_mesh(m).clean());
}

TEST(RemoveUnreferenced, CompactsAndRemaps) {
  TriangleMesh m = test::tetrahedron();
  m.positions.insert(m.positions.begin(), Eigen::Vector3d(9, 9, 9));
  for (Triangle& t : m.triangles) {
    for (int32_t& v : t) ++v;
  }
  EXPECT_EQ(remove_unreferenced_vertices(m), 1);
  EXPECT_EQ(m.vertex_count(), 4);
  EXPECT_NEAR(m.signed_volume(), 1.0 / 6.0, 1e-12);
}

TEST(RepairMesh, ClosesAHoleAndKeepsTheShape) {
  TriangleMesh s = make_uv_sphere(0.05, 16, 32);
  const double volume = s.signed_volume();
  // Open a hole: remove the north pole fan (32 triangles).
  s.triangles.erase(s.triangles.begin(), s.triangles.begin() + 32);
  ASSERT_EQ(validate_mesh(s).boundary_edges.size(), 32U);
  const MeshRepairReport r = repair_mesh(s);
  EXPECT_EQ(r.closed_holes, 1);
  EXPECT_EQ(r.added_triangles, 32);
  EXPECT_TRUE(validate_mesh(s).clean());
  EXPECT_NEAR(s.signed_volume(), volume, 1e-3 * volume);  // the cap is flat: tiny loss
}

TEST(RepairMesh, LeavesLargeHolesOpenAndSaysSo) {
  TriangleMesh s = make_uv_sphere(0.05, 16, 32);
  s.triangles.erase(s.triangles.begin(), s.triangles.begin() + 32);
  MeshRepairSettings settings;
  settings.max_hole_edges = 16;
  const MeshRepairReport r = repair_mesh(s, settings);
  EXPECT_EQ(r.holes_left_open, 1);
  EXPECT_FALSE(validate_mesh(s).closed());
  EXPECT_NE(r.summary().find("1 holes too large to close"), std::string::npos);
}

TEST(RepairMesh, FixesFlippedTrianglesAndInwardNormals) {
  TriangleMesh box = make_box(Eigen::Vector3d(1, 2, 3), 3);
  std::swap(box.triangles[7][1], box.triangles[7][2]);
  std::swap(box.triangles[40][1], box.triangles[40][2]);
  MeshRepairReport r = repair_mesh(box);
  EXPECT_EQ(r.flipped_triangles, 2);
  EXPECT_TRUE(validate_mesh(box).clean());
  EXPECT_NEAR(box.signed_volume(), 6.0, 1e-12);

  for (Triangle& t : box.triangles) std::swap(t[1], t[2]);  // all inward
  r = repair_mesh(box);
  EXPECT_EQ(r.flipped_components, 1);
  EXPECT_NEAR(box.signed_volume(), 6.0, 1e-12);
}

TEST(RepairMesh, SplitsAPinchedVertexIntoTwoClosedBodies) {
  TriangleMesh m = test::tetrahedron();
  m.append(test::tetrahedron(Eigen::Vector3d(0, 0, 1)));
  for (Triangle& t : m.triangles) {
    for (int32_t& v : t) {
      if (v == 4) v = 3;
    }
  }
  ASSERT_EQ(validate_mesh(m).non_manifold_vertices.size(), 1U);
  const MeshRepairReport r = repair_mesh(m);
  EXPECT_EQ(r.split_vertices, 1);
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_TRUE(d.clean());
  EXPECT_EQ(d.component_count, 2);
  EXPECT_NEAR(m.signed_volume(), 2.0 / 6.0, 1e-12);
}

TEST(RepairMesh, RemovesDebrisDegenerateAndDuplicateTriangles) {
  TriangleMesh m = make_uv_sphere(0.05, 8, 16);
  const int32_t n = m.triangle_count();
  m.triangles.push_back(m.triangles[0]);  // duplicate
  m.triangles.push_back({0, 0, 1});       // degenerate
  const int32_t b = m.vertex_count();
  m.positions.insert(m.positions.end(), {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1 + 1e-8, 0, 0),
                                         Eigen::Vector3d(1, 1e-8, 0)});
  m.triangles.push_back({b, b + 1, b + 2});  // debris
  const MeshRepairReport r = repair_mesh(m);
  EXPECT_EQ(r.removed_duplicates, 1);
  EXPECT_EQ(r.removed_degenerate, 1);
  EXPECT_EQ(r.removed_fragments, 1);
  EXPECT_EQ(m.triangle_count(), n);
  EXPECT_TRUE(validate_mesh(m).clean());
}

TEST(RepairMesh, DropsTrianglesWithNonFiniteCornersOrBadIndices) {
  TriangleMesh m = test::tetrahedron();
  m.positions.push_back(Eigen::Vector3d(std::nan(""), 0, 0));
  m.triangles.push_back({0, 1, 4});
  m.triangles.push_back({0, 1, 99});
  const MeshRepairReport r = repair_mesh(m);
  EXPECT_EQ(r.removed_invalid, 2);
  EXPECT_TRUE(validate_mesh(m).clean());
  EXPECT_EQ(m.vertex_count(), 4);
}

TEST(RepairMesh, CleanMeshIsUnchanged) {
  TriangleMesh s = make_uv_sphere(0.05, 10, 20);
  const TriangleMesh before = s;
  const MeshRepairReport r = repair_mesh(s);
  EXPECT_EQ(r.summary(), MeshRepairReport{}.summary());
  EXPECT_EQ(s.triangles, before.triangles);
  EXPECT_EQ(s.positions, before.positions);
}

}  // namespace
}  // namespace lap::haptics
