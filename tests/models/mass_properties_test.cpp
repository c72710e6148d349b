// Mass properties of closed meshes (§6.4) against the solids' closed forms: a box's inertia
// m (b² + c²) / 12 exactly (it is polyhedral), a sphere's 2/5 m r² to the tessellation's error,
// the centroid of a shifted, rotated body, and an open mesh refused.

#include "models/mass_properties.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "haptics/setup/mesh_generators.h"

namespace lap::models {
namespace {

TEST(MassProperties, ABoxHasItsClosedFormVolumeCentroidAndInertia) {
  const Eigen::Vector3d sides(0.04, 0.02, 0.06);
  haptics::TriangleMesh box = haptics::make_box(sides, 3);
  const Eigen::Vector3d shift(0.1, -0.2, 0.05);
  for (Eigen::Vector3d& p : box.positions) p += shift;  // the origin outside the solid
  const MassProperties p = mass_properties(box);
  EXPECT_NEAR(p.volume_m3, sides.prod(), 1e-15);
  EXPECT_LT((p.centroid - shift).norm(), 1e-12);
  const RigidBodyModel body = rigid_body_of_mesh(box, 0.5);
  const RigidBodyModel expected = RigidBodyModel::solid_box(0.5, sides);
  EXPECT_LT((body.inertia_B - expected.inertia_B).norm(), 1e-12 * expected.inertia_B.norm());
  EXPECT_STREQ(body.problem(), "");
}

TEST(MassProperties, ARotatedBoxsInertiaIsRotated) {
  const Eigen::Vector3d sides(0.05, 0.01, 0.03);
  haptics::TriangleMesh box = haptics::make_box(sides, 1);
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  for (Eigen::Vector3d& p : box.positions) p = r * p;
  const RigidBodyModel body = rigid_body_of_mesh(box, 2.0);
  const Eigen::Matrix3d expected =
      r * RigidBodyModel::solid_box(2.0, sides).inertia_B * r.transpose();
  EXPECT_LT((body.inertia_B - expected).norm(), 1e-12 * expected.norm());
}

TEST(MassProperties, ASphereHasTwoFifthsMrSquaredToItsTessellation) {
  const double r = 0.03;
  const haptics::TriangleMesh sphere = haptics::make_uv_sphere(r, 64, 128);
  const MassProperties p = mass_properties(sphere);
  // The inscribed polyhedron's volume falls short of 4/3 π r³ by O(h²): 0.1 % at this size.
  EXPECT_NEAR(p.volume_m3, 4.0 / 3.0 * M_PI * r * r * r, 2e-3 * p.volume_m3);
  const RigidBodyModel body = rigid_body_of_mesh(sphere, 0.1);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(body.inertia_B(i, i), 0.4 * 0.1 * r * r, 3e-3 * 0.4 * 0.1 * r * r);
  EXPECT_NEAR(body.inertia_B(0, 1), 0.0, 1e-12);
}

TEST(MassProperties, AnOpenMeshHasNoMassProperties) {
  EXPECT_THROW((void)rigid_body_of_mesh(haptics::make_plate(0.1, 4), 1.0), std::invalid_argument);
  EXPECT_THROW((void)rigid_body_of_mesh(haptics::make_box({0.1, 0.1, 0.1}), 0.0),
               std::invalid_argument);
}

}  // namespace
}  // namespace lap::models
