#include "haptics/setup/mesh_generators.h"

#include <gtest/gtest.h>

#include <cmath>

#include "haptics/setup/mesh_validation.h"

namespace lap::haptics {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(MeshGenerators, BoxIsCleanWithExactVolumeAndArea) {
  for (int n : {1, 3, 8}) {
    const TriangleMesh b = make_box(Eigen::Vector3d(0.1, 0.2, 0.3), n);
    EXPECT_TRUE(validate_mesh(b).clean()) << "n = " << n;
    EXPECT_EQ(b.triangle_count(), 12 * n * n);
    EXPECT_EQ(b.vertex_count(), 6 * n * n + 2);  // Euler: V = E - F + 2 with E = 3F/2
    EXPECT_NEAR(b.signed_volume(), 0.1 * 0.2 * 0.3, 1e-15);
    EXPECT_NEAR(b.surface_area(), 2 * (0.02 + 0.03 + 0.06), 1e-14);
  }
}

TEST(MeshGenerators, SphereConvergesToAnalyticVolumeFromBelow) {
  const double r = 0.03;
  const double exact = 4.0 / 3.0 * kPi * r * r * r;
  double previous_error = 1.0;
  for (int stacks : {8, 16, 32, 64}) {
    const TriangleMesh s = make_uv_sphere(r, stacks, 2 * stacks);
    ASSERT_TRUE(validate_mesh(s).clean());
    const double error = (exact - s.signed_volume()) / exact;
    EXPECT_GT(error, 0.0);  // an inscribed polyhedron is smaller
    // Second-order convergence: doubling the resolution divides the error by about 4.
    EXPECT_LT(error, previous_error / 3.5);
    previous_error = error;
  }
}

TEST(MeshGenerators, CylinderIsCleanAndHasPolygonPrismVolume) {
  const int slices = 32;
  const TriangleMesh c = make_cylinder(0.0045, 0.03, slices, 5);
  EXPECT_TRUE(validate_mesh(c).clean());
  // Regular n-gon area: n/2 r^2 sin(2 pi / n).
  const double area = 0.5 * slices * 0.0045 * 0.0045 * std::sin(2 * kPi / slices);
  EXPECT_NEAR(c.signed_volume(), area * 0.03, 1e-15);
}

TEST(MeshGenerators, StandInOrgansAreClosedOutwardManifolds) {
  for (const TriangleMesh& m :
       {make_stand_in_liver(), make_stand_in_gallbladder(), make_stand_in_cystic_duct()}) {
    const MeshDiagnostics d = validate_mesh(m);
    EXPECT_TRUE(d.clean());
    EXPECT_GT(m.signed_volume(), 0.0);
  }
}

}  // namespace
}  // namespace lap::haptics
