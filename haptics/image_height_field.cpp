#include "haptics/image_height_field.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace lap::haptics {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Catmull-Rom weights of the four texels around fraction t in [0, 1).
std::array<double, 4> catmull_rom(double t) {
  const double t2 = t * t;
  const double t3 = t2 * t;
  return {0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
          0.5 * (-3.0 * t3 + 4.0 * t2 + t), 0.5 * (t3 - t2)};
}

int32_t wrap(int64_t i, int32_t n) {
  const int64_t m = i % n;
  return static_cast<int32_t>(m < 0 ? m + n : m);
}

}  // namespace

ImageHeightField::ImageHeightField(HeightImage image, const IntermediateSurface& surface,
                                   double amplitude_m, double epsilon_m)
    : image_(std::move(image)),
      surface_(surface),
      frame_SO_(surface.frame_OS.inverse()),
      amplitude_(amplitude_m),
      epsilon_(epsilon_m) {}

Eigen::Vector2d ImageHeightField::map(const Eigen::Vector3d& p) const noexcept {
  const Eigen::Vector3d q = frame_SO_ * p;
  switch (surface_.kind) {
    case IntermediateSurface::Kind::kPlane:
      return {q.x() / surface_.tile_u_m, q.y() / surface_.tile_v_m};
    case IntermediateSurface::Kind::kCylinder: {
      const double around = std::atan2(q.y(), q.x()) / (2.0 * kPi) + 0.5;
      return {around * surface_.repeat_u, q.z() / surface_.tile_v_m};
    }
    case IntermediateSurface::Kind::kSphere: {
      const double around = std::atan2(q.y(), q.x()) / (2.0 * kPi) + 0.5;
      const double r = q.norm();
      const double polar = r > 0.0 ? std::acos(std::clamp(q.z() / r, -1.0, 1.0)) / kPi : 0.0;
      return {around * surface_.repeat_u, polar * surface_.repeat_v};
    }
    case IntermediateSurface::Kind::kBox: {
      const Eigen::Vector3d a = q.cwiseAbs();
      if (a.x() >= a.y() && a.x() >= a.z()) {
        return {q.y() / surface_.tile_u_m, q.z() / surface_.tile_v_m};
      }
      if (a.y() >= a.z()) return {q.x() / surface_.tile_u_m, q.z() / surface_.tile_v_m};
      return {q.x() / surface_.tile_u_m, q.y() / surface_.tile_v_m};
    }
  }
  return {0.0, 0.0};
}

double ImageHeightField::grey(const Eigen::Vector2d& uv) const noexcept {
  // Texel centres at (i + 0.5) / width.
  const double s = uv.x() * image_.width - 0.5;
  const double t = uv.y() * image_.height - 0.5;
  if (!std::isfinite(s) || !std::isfinite(t)) return 0.5;
  const double fs = std::floor(s);
  const double ft = std::floor(t);
  const auto ws = catmull_rom(s - fs);
  const auto wt = catmull_rom(t - ft);
  const auto is = static_cast<int64_t>(fs);
  const auto it = static_cast<int64_t>(ft);
  double g = 0.0;
  for (int j = 0; j < 4; ++j) {
    const int32_t y = wrap(it - 1 + j, image_.height);
    double row = 0.0;
    for (int i = 0; i < 4; ++i) row += ws[i] * image_.at(wrap(is - 1 + i, image_.width), y);
    g += wt[j] * row;
  }
  return g;
}

double ImageHeightField::height(const Eigen::Vector3d& p) const noexcept {
  return amplitude_ * (2.0 * grey(map(p)) - 1.0);
}

HeightSample ImageHeightField::sample(const Eigen::Vector3d& p) const noexcept {
  HeightSample s;
  s.height_m = height(p);
  const double inv = 1.0 / (2.0 * epsilon_);
  for (int a = 0; a < 3; ++a) {  // eq. 6-5
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[a] = epsilon_;
    s.gradient[a] = (height(p + d) - height(p - d)) * inv;
  }
  return s;
}

}  // namespace lap::haptics
