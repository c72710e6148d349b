#include "sim/setup/scenario.h"

#include <algorithm>

namespace lap::sim {

Eigen::Affine3d OrganSpec::transform() const {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  T.translate(translation_m);
  // Fixed-axis x, then y, then z: R = Rz * Ry * Rx.
  T.rotate(Eigen::AngleAxisd(rotation_deg.z() * kDeg, Eigen::Vector3d::UnitZ()) *
           Eigen::AngleAxisd(rotation_deg.y() * kDeg, Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(rotation_deg.x() * kDeg, Eigen::Vector3d::UnitX()));
  return T;
}

Eigen::Vector3d CameraSpec::port() const {
  if (port_m) return *port_m;
  const Eigen::Vector3d sight = focal_point_m - position_m;
  const double n = sight.norm();
  if (!(n > 0.0)) return position_m;
  return position_m - kDefaultPortDepthM / n * sight;
}

const ToolSpec* Scenario::tool(ToolSpec::Side side) const {
  const auto it =
      std::find_if(tools.begin(), tools.end(), [&](const ToolSpec& t) { return t.side == side; });
  return it == tools.end() ? nullptr : &*it;
}

const TrocarSpec* Scenario::trocar(const std::string& trocar_name) const {
  const auto it = std::find_if(trocars.begin(), trocars.end(),
                               [&](const TrocarSpec& t) { return t.name == trocar_name; });
  return it == trocars.end() ? nullptr : &*it;
}

}  // namespace lap::sim
