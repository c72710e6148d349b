#include "app/catheter_tube.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace lap::app {

CatheterTube::CatheterTube(int32_t particles, int32_t sides)
    : particles_(std::max<int32_t>(particles, 2)),
      sides_(std::max<int32_t>(sides, 3)),
      vertex_count_(particles_ * sides_ + 1) {
  for (int32_t i = 0; i + 1 < particles_; ++i) {
    for (int32_t k = 0; k < sides_; ++k) {
      const int32_t a = i * sides_ + k;
      const int32_t a1 = i * sides_ + (k + 1) % sides_;
      const int32_t b = a + sides_;
      const int32_t b1 = a1 + sides_;
      // Round the ring k → k+1, along the tube i → i+1: outward (catheter_tube.h's frames).
      triangles_.insert(triangles_.end(), {a, a1, b, b, a1, b1});
    }
  }
  // The tip's cap: a fan from the last ring to the apex.
  const int32_t apex = vertex_count_ - 1;
  const int32_t last = (particles_ - 1) * sides_;
  for (int32_t k = 0; k < sides_; ++k) {
    triangles_.insert(triangles_.end(), {last + k, last + (k + 1) % sides_, apex});
  }
}

bool CatheterTube::write(std::span<const Eigen::Vector3d> centre_W, double radius_m,
                         std::span<float> points, std::span<float> normals) const {
  const auto n = static_cast<size_t>(particles_);
  const auto need = static_cast<size_t>(vertex_count_) * 3;
  if (centre_W.size() != n || points.size() < need || normals.size() < need) return false;
  auto tangent = [&](size_t i) -> Eigen::Vector3d {
    const Eigen::Vector3d d = centre_W[std::min(i + 1, n - 1)] - centre_W[i == 0 ? 0 : i - 1];
    return d.norm() > 1e-12 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::Zero();
  };
  Eigen::Vector3d t = tangent(0);
  if (t.isZero()) t = Eigen::Vector3d::UnitX();
  Eigen::Vector3d normal = t.unitOrthogonal();
  auto put = [](std::span<float> out, size_t v, const Eigen::Vector3d& x) {
    out[3 * v] = static_cast<float>(x.x());
    out[3 * v + 1] = static_cast<float>(x.y());
    out[3 * v + 2] = static_cast<float>(x.z());
  };
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d next = tangent(i);
    if (!next.isZero()) {
      // Parallel transport: the smallest rotation taking the last tangent to this one.
      normal = Eigen::Quaterniond::FromTwoVectors(t, next) * normal;
      t = next;
    }
    normal = (normal - normal.dot(t) * t).normalized();
    const Eigen::Vector3d binormal = t.cross(normal);
    for (int32_t k = 0; k < sides_; ++k) {
      const double a = 2.0 * M_PI * k / sides_;
      const Eigen::Vector3d radial = std::cos(a) * normal + std::sin(a) * binormal;
      const auto v = static_cast<size_t>(static_cast<int32_t>(i) * sides_ + k);
      put(points, v, centre_W[i] + radius_m * radial);
      put(normals, v, radial);
    }
  }
  const auto apex = static_cast<size_t>(vertex_count_ - 1);
  put(points, apex, centre_W[n - 1] + 0.6 * radius_m * t);
  put(normals, apex, t);
  return true;
}

}  // namespace lap::app
