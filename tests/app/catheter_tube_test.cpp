// The catheter's tube (app/catheter_tube.h) along a bent centre line: every ring vertex at the
// catheter's radius from its particle and across the centre line there, the normals unit and
// pointing out, the triangles wound outwards, the rings untwisted by parallel transport, and the
// tip capped just beyond the last particle.

#include "app/catheter_tube.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace lap::app {
namespace {

TEST(CatheterTube, RingsAtTheRadiusAcrossTheCentreLine) {
  // A quarter circle of radius 5 cm in the x-y plane, 33 particles.
  const int32_t n = 33;
  std::vector<Eigen::Vector3d> centre;
  for (int32_t i = 0; i < n; ++i) {
    const double a = 0.5 * M_PI * i / (n - 1);
    centre.emplace_back(0.05 * std::cos(a), 0.05 * std::sin(a), 0.0);
  }
  const double radius = 0.000835;  // 5 Fr
  const CatheterTube tube(n, 10);
  std::vector<float> points(static_cast<size_t>(tube.vertex_count()) * 3);
  std::vector<float> normals(points.size());
  ASSERT_TRUE(tube.write(centre, radius, points, normals));
  auto at = [](const std::vector<float>& v, int32_t k) {
    return Eigen::Vector3d(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
  };
  for (int32_t i = 0; i < n; ++i) {
    // The centre line's direction there (the circle's tangent).
    const double a = 0.5 * M_PI * i / (n - 1);
    const Eigen::Vector3d t(-std::sin(a), std::cos(a), 0.0);
    for (int32_t k = 0; k < 10; ++k) {
      const Eigen::Vector3d p = at(points, i * 10 + k);
      const Eigen::Vector3d nrm = at(normals, i * 10 + k);
      // The tube is stored in floats: coordinates of 5 cm are kept to about 4 nm.
      EXPECT_NEAR((p - centre[static_cast<size_t>(i)]).norm(), radius, 1e-8);
      // Across the centre line: within the chord's turn (2.8° between particles).
      EXPECT_LT(std::abs((p - centre[static_cast<size_t>(i)]).normalized().dot(t)), 0.05);
      EXPECT_NEAR(nrm.norm(), 1.0, 1e-6);
      EXPECT_GT(nrm.dot(p - centre[static_cast<size_t>(i)]), 0.0);
    }
    // No twist: the bend is in one plane, so the ring's first vertex keeps its height (z).
    EXPECT_NEAR(at(points, i * 10).z(), at(points, 0).z(), 1e-7);
  }
  // Wound outwards: each triangle's normal points away from the nearest particle.
  const std::vector<int32_t>& tri = tube.triangles();
  for (size_t k = 0; k + 2 < tri.size(); k += 3) {
    const Eigen::Vector3d a = at(points, tri[k]);
    const Eigen::Vector3d b = at(points, tri[k + 1]);
    const Eigen::Vector3d c = at(points, tri[k + 2]);
    const Eigen::Vector3d mid = (a + b + c) / 3.0;
    double nearest = 1e9;
    Eigen::Vector3d from = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& q : centre) {
      if ((q - mid).norm() < nearest) {
        nearest = (q - mid).norm();
        from = q;
      }
    }
    EXPECT_GT((b - a).cross(c - a).dot(mid - from), 0.0) << "triangle " << k / 3;
  }
  // The cap's apex 0.6 radius beyond the tip, along the last direction (+x at the end... −x).
  const Eigen::Vector3d apex = at(points, tube.vertex_count() - 1);
  EXPECT_NEAR((apex - centre.back()).norm(), 0.6 * radius, 1e-8);
  EXPECT_GT((apex - centre.back()).dot(Eigen::Vector3d(-1.0, 0.0, 0.0)), 0.0);
  // A centre line of another length is refused.
  centre.pop_back();
  EXPECT_FALSE(tube.write(centre, radius, points, normals));
}

}  // namespace
}  // namespace lap::app
