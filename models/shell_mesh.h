#pragma once
/// \file
/// A quadrilateral shell mesh (the duct's wall, §7.7(2), Figure 7-20) and the straight tube
/// generator.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "haptics/triangle_mesh.h"

namespace lap::models {

struct ShellMesh {
  std::vector<Eigen::Vector3d> nodes;         ///< mid-surface points [m]
  std::vector<std::array<int32_t, 4>> quads;  ///< counter-clockwise about the outward normal
};

/// A straight tube along +z from z = 0 to `length_m`, mid-surface radius `radius_m`, `around`
/// nodes per ring and `along` elements along: node (i, j) is j * around + i, at angle 2π i /
/// around. Every quad is a planar rectangle.
[[nodiscard]] ShellMesh make_tube_shell(double radius_m, double length_m, int32_t around,
                                        int32_t along);

/// The surface the proxies and the catheter touch: each quad as two triangles (0 1 2, 0 2 3),
/// the shell's nodes as its vertices in the same order (so a displacement per node moves it).
[[nodiscard]] haptics::TriangleMesh triangulate(const ShellMesh& mesh);

}  // namespace lap::models
