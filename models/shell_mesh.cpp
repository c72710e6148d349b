#include "models/shell_mesh.h"

#include <cmath>
#include <stdexcept>

namespace lap::models {

ShellMesh make_tube_shell(double radius_m, double length_m, int32_t around, int32_t along) {
  if (!(radius_m > 0.0) || !(length_m > 0.0) || around < 3 || along < 1) {
    throw std::invalid_argument("tube shell: radius, length > 0, around >= 3, along >= 1");
  }
  ShellMesh m;
  for (int32_t j = 0; j <= along; ++j) {
    for (int32_t i = 0; i < around; ++i) {
      const double a = 2.0 * M_PI * i / around;
      m.nodes.emplace_back(radius_m * std::cos(a), radius_m * std::sin(a), length_m * j / along);
    }
  }
  for (int32_t j = 0; j < along; ++j) {
    for (int32_t i = 0; i < around; ++i) {
      const int32_t i1 = (i + 1) % around;
      m.quads.push_back(
          {j * around + i, j * around + i1, (j + 1) * around + i1, (j + 1) * around + i});
    }
  }
  return m;
}

haptics::TriangleMesh triangulate(const ShellMesh& mesh) {
  haptics::TriangleMesh t;
  t.positions = mesh.nodes;
  for (const auto& q : mesh.quads) {
    t.triangles.push_back({q[0], q[1], q[2]});
    t.triangles.push_back({q[0], q[2], q[3]});
  }
  return t;
}

}  // namespace lap::models
