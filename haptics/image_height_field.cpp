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
  if (!std::isfinite(s) || !std::isfinite(t) || std::abs(s) > 1e15 || std::abs(t) > 1e15) {
    return 0.5;
  }
  const double fs = std::floor(s);
  const double ft = std::floor(t);
  const auto ws = catmull_rom(s - fs);
  const auto wt = catmull_rom(t - ft);
  // One modulo per axis; the other three taps step on with a compare (tiling).
  std::array<int32_t, 4> xs{};
  std::array<int32_t, 4> ys{};
  xs[0] = wrap(static_cast<int64_t>(fs) - 1, image_.width);
  ys[0] = wrap(static_cast<int64_t>(ft) - 1, image_.height);
  for (int k = 1; k < 4; ++k) {
    xs[k] = xs[k - 1] + 1 == image_.width ? 0 : xs[k - 1] + 1;
    ys[k] = ys[k - 1] + 1 == image_.height ? 0 : ys[k - 1] + 1;
  }
  double g = 0.0;
  for (int j = 0; j < 4; ++j) {
    const float* row = image_.values.data() + static_cast<size_t>(ys[j]) * image_.width;
    g +=
        wt[j] * (ws[0] * row[xs[0]] + ws[1] * row[xs[1]] + ws[2] * row[xs[2]] + ws[3] * row[xs[3]]);
  }
  return g;
}

double ImageHeightField::height(const Eigen::Vector3d& p) const noexcept {
  return amplitude_ * (2.0 * grey(map(p)) - 1.0);
}

HeightSample ImageHeightField::sample(const Eigen::Vector3d& p) const noexcept {
  // eq. 6-5 on the intermediate surface: central differences of the height along its two
  // parameters (step epsilon on the surface), carried to the object's axes by the chain rule
  // through the O-mapping's Jacobian. The same as differencing along x, y, z (eq. 6-6) for a
  // smooth mapping, with four texture look-ups instead of six mappings and look-ups.
  const Eigen::Vector3d q = frame_SO_ * p;
  const Eigen::Vector2d uv = map(p);
  Eigen::Matrix<double, 2, 3> jac = Eigen::Matrix<double, 2, 3>::Zero();  // d(u, v) / dq
  constexpr double kTwoPi = 2.0 * kPi;
  switch (surface_.kind) {
    case IntermediateSurface::Kind::kPlane:
      jac(0, 0) = 1.0 / surface_.tile_u_m;
      jac(1, 1) = 1.0 / surface_.tile_v_m;
      break;
    case IntermediateSurface::Kind::kCylinder:
    case IntermediateSurface::Kind::kSphere: {
      const double rho2 = std::max(q.x() * q.x() + q.y() * q.y(), 1e-18);
      jac(0, 0) = -q.y() / rho2 / kTwoPi * surface_.repeat_u;
      jac(0, 1) = q.x() / rho2 / kTwoPi * surface_.repeat_u;
      if (surface_.kind == IntermediateSurface::Kind::kCylinder) {
        jac(1, 2) = 1.0 / surface_.tile_v_m;
      } else {
        // v = acos(z / r) / pi: dv/dq = -(e_z r^2 - z q) / (r^3 sqrt(1 - z^2 / r^2)) / pi.
        const double r2 = std::max(q.squaredNorm(), 1e-18);
        const double r = std::sqrt(r2);
        const double sin_polar = std::max(std::sqrt(rho2) / r, 1e-9);
        const Eigen::Vector3d dcos = (Eigen::Vector3d::UnitZ() * r2 - q.z() * q) / (r2 * r);
        jac.row(1) = (-surface_.repeat_v / (kPi * sin_polar)) * dcos.transpose();
      }
      break;
    }
    case IntermediateSurface::Kind::kBox: {
      const Eigen::Vector3d a = q.cwiseAbs();
      const int axis = a.x() >= a.y() && a.x() >= a.z() ? 0 : (a.y() >= a.z() ? 1 : 2);
      const int iu = axis == 0 ? 1 : 0;
      const int iv = axis == 2 ? 1 : 2;
      jac(0, iu) = 1.0 / surface_.tile_u_m;
      jac(1, iv) = 1.0 / surface_.tile_v_m;
      break;
    }
  }
  // The parameter steps that move epsilon on the surface.
  const double du = epsilon_ * std::max(jac.row(0).norm(), 1e-12);
  const double dv = epsilon_ * std::max(jac.row(1).norm(), 1e-12);
  const double g = grey(uv);
  const double dg_du = (grey({uv.x() + du, uv.y()}) - grey({uv.x() - du, uv.y()})) / (2.0 * du);
  const double dg_dv = (grey({uv.x(), uv.y() + dv}) - grey({uv.x(), uv.y() - dv})) / (2.0 * dv);
  HeightSample out;
  out.height_m = amplitude_ * (2.0 * g - 1.0);
  const Eigen::Vector3d grad_S =
      (2.0 * amplitude_) * (dg_du * jac.row(0).transpose() + dg_dv * jac.row(1).transpose());
  out.gradient = surface_.frame_OS.linear() * grad_S;
  return out;
}

}  // namespace lap::haptics
