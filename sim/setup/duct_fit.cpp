#include "sim/setup/duct_fit.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace lap::sim {

Result<DuctFit> fit_duct(const haptics::TriangleMesh& tube, double wall_thickness_m) {
  const auto n = tube.positions.size();
  if (n < 8) return diagnostic("duct: the mesh has too few vertices to fit a tube");
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : tube.positions) c += p;
  c /= static_cast<double>(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : tube.positions) cov += (p - c) * (p - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d axis = eig.eigenvectors().col(2).normalized();  // largest spread
  double t_min = 0.0;
  double t_max = 0.0;
  for (const Eigen::Vector3d& p : tube.positions) {
    t_min = std::min(t_min, axis.dot(p - c));
    t_max = std::max(t_max, axis.dot(p - c));
  }
  const double length = t_max - t_min;
  // The radius from the side wall only: vertices within 10 % of the length from an end may be
  // on the caps.
  double sum = 0.0;
  int count = 0;
  for (const Eigen::Vector3d& p : tube.positions) {
    const double t = axis.dot(p - c);
    if (t - t_min < 0.1 * length || t_max - t < 0.1 * length) continue;
    sum += (p - c - t * axis).norm();
    ++count;
  }
  if (!(length > 0.0) || count == 0) {
    return diagnostic("duct: the mesh has no side wall to fit a tube to");
  }
  const double radius = sum / count;
  DuctFit f;
  f.duct.outer_diameter_m = 2.0 * radius;
  f.duct.wall_thickness_m = wall_thickness_m;
  f.duct.length_m = length;
  f.duct.along = std::max(4, static_cast<int>(std::lround(length / 0.001)));  // ~1 mm elements
  if (!(f.duct.outer_diameter_m > 2.0 * wall_thickness_m)) {
    return diagnostic("duct: the fitted radius is below the wall thickness");
  }
  // D: z along the axis, y the world's up as seen across the axis (membrane at local −y).
  Eigen::Vector3d up = Eigen::Vector3d::UnitY() - axis.dot(Eigen::Vector3d::UnitY()) * axis;
  if (up.norm() < 1e-6) up = Eigen::Vector3d::UnitX() - axis.dot(Eigen::Vector3d::UnitX()) * axis;
  up.normalize();
  Eigen::Matrix3d r;
  r.col(2) = axis;
  r.col(1) = up;
  r.col(0) = up.cross(axis);
  f.pose_WD.linear() = r;
  f.pose_WD.translation() = c + t_min * axis;
  return f;
}

}  // namespace lap::sim
