#include "haptics/triangle_mesh.h"

#include <gtest/gtest.h>

#include "haptics/setup/mesh_generators.h"
#include "tests/test_support.h"

namespace lap::haptics {
namespace {

TEST(TriangleMesh, TetrahedronAreaVolumeAndBounds) {
  const TriangleMesh t = test::tetrahedron(Eigen::Vector3d(1, 2, 3), 2.0);
  // Unit right tetrahedron scaled by 2: volume 8/6, area 3 * (2*2/2) + sqrt(3)/4 * (2*sqrt2)^2.
  EXPECT_NEAR(t.signed_volume(), 8.0 / 6.0, 1e-12);
  EXPECT_NEAR(t.surface_area(), 6.0 + std::sqrt(3.0) / 4.0 * 8.0, 1e-12);
  EXPECT_TRUE(t.bounds().min().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE(t.bounds().max().isApprox(Eigen::Vector3d(3, 4, 5)));
}

TEST(TriangleMesh, MirrorTransformKeepsOutwardOrientation) {
  TriangleMesh t = test::tetrahedron();
  Eigen::Affine3d mirror = Eigen::Affine3d::Identity();
  mirror.linear()(0, 0) = -1.0;
  t.transform(mirror);
  EXPECT_NEAR(t.signed_volume(), 1.0 / 6.0, 1e-12);
}

TEST(TriangleMesh, RigidTransformMovesNormalsWithTheSurface) {
  TriangleMesh s = make_uv_sphere(1.0, 8, 16);
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  T.translate(Eigen::Vector3d(5, 0, 0));
  T.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()));
  s.transform(T);
  for (int32_t v = 0; v < s.vertex_count(); ++v) {
    // On a sphere the vertex normal is the radial direction (to within tessellation error).
    const Eigen::Vector3d radial = (s.positions[v] - Eigen::Vector3d(5, 0, 0)).normalized();
    EXPECT_GT(s.normals[v].dot(radial), 0.99);
  }
}

TEST(TriangleMesh, AngleWeightedNormalsOfACubeCornerPointDiagonally) {
  TriangleMesh box = make_box(Eigen::Vector3d(1, 1, 1), 1);
  box.compute_vertex_normals();
  for (int32_t v = 0; v < box.vertex_count(); ++v) {
    // Angle weighting (§4.2) makes a cube corner's normal the diagonal, whatever the
    // triangulation; plain averaging would not.
    const Eigen::Vector3d diag = box.positions[v].cwiseSign().normalized();
    EXPECT_NEAR(box.normals[v].dot(diag), 1.0, 1e-12) << "vertex " << v;
  }
}

TEST(TriangleMesh, AppendShiftsIndices) {
  TriangleMesh a = test::tetrahedron();
  a.append(test::tetrahedron(Eigen::Vector3d(5, 0, 0)));
  EXPECT_EQ(a.vertex_count(), 8);
  EXPECT_EQ(a.triangle_count(), 8);
  EXPECT_EQ(a.triangles[4][0], 4);
  EXPECT_NEAR(a.signed_volume(), 2.0 / 6.0, 1e-12);
}

TEST(TriangleMesh, OpenMeshViewOfACleanMeshHasAllFaces) {
  const TriangleMesh s = make_uv_sphere(0.05, 12, 24);
  int32_t skipped = -1;
  const OpenTriMesh om = s.to_openmesh(&skipped);
  EXPECT_EQ(skipped, 0);
  EXPECT_EQ(static_cast<int32_t>(om.n_faces()), s.triangle_count());
  EXPECT_EQ(static_cast<int32_t>(om.n_vertices()), s.vertex_count());
  // Euler characteristic of a sphere.
  EXPECT_EQ(static_cast<int64_t>(om.n_vertices()) - static_cast<int64_t>(om.n_edges()) +
                static_cast<int64_t>(om.n_faces()),
            2);
}

}  // namespace
}  // namespace lap::haptics
