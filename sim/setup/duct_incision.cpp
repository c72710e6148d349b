#include "sim/setup/duct_incision.h"

#include <cmath>
#include <string>

namespace lap::sim {

namespace {

std::string mm(double m) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f mm", 1e3 * m);
  return buf;
}

}  // namespace

Result<std::vector<uint8_t>> incision_faces(const haptics::TriangleMesh& wall_W,
                                            const models::DuctSettings& duct,
                                            const Eigen::Isometry3d& pose_WD,
                                            const IncisionSpec& incision) {
  auto fail = [&](const std::string& what) {
    return Diagnostic{"", incision.line, "incision", what};
  };
  const Eigen::Isometry3d pose_DW = pose_WD.inverse();
  const double mid_radius = 0.5 * (duct.outer_diameter_m - duct.wall_thickness_m);
  const Eigen::Vector3d c = pose_DW * incision.center_m;
  const double off_wall = std::abs(c.head<2>().norm() - mid_radius);
  if (off_wall > 0.5 * duct.outer_diameter_m) {
    return fail("center_m is " + mm(off_wall) + " from the duct's wall (mid-surface radius " +
                mm(mid_radius) + " about its axis); expected a point on the wall");
  }
  if (c.z() < 0.0 || c.z() > duct.length_m) {
    return fail("center_m lies beyond the duct's ends (" + mm(c.z()) + " along its " +
                mm(duct.length_m) + "); expected a point on the wall");
  }
  const double angle = std::atan2(c.y(), c.x());
  std::vector<uint8_t> open(wall_W.triangles.size(), 0);
  int32_t count = 0;
  for (size_t f = 0; f < wall_W.triangles.size(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const int32_t v : wall_W.triangles[f])
      centroid += wall_W.positions[static_cast<size_t>(v)];
    const Eigen::Vector3d p = pose_DW * (centroid / 3.0);
    const double along = (p.z() - c.z()) / (0.5 * incision.length_m);
    const double around = mid_radius *
                          std::remainder(std::atan2(p.y(), p.x()) - angle, 2.0 * M_PI) /
                          (0.5 * incision.width_m);
    if (along * along + around * around <= 1.0) {
      open[f] = 1;
      ++count;
    }
  }
  if (count == 0) {
    return fail("opens none of the wall's faces (each about " + mm(duct.length_m / duct.along) +
                " along and " + mm(2.0 * M_PI * mid_radius / duct.around) +
                " around); expected length_m and width_m at least that");
  }
  return open;
}

}  // namespace lap::sim
