#pragma once
/// \file
/// The flat rectangular facet shell element of the duct model (thesis §7.7(2): the duct's wall as
/// an assemblage of shell elements). Chosen: a 4-node rectangle with 6 degrees of freedom per
/// node (u, v, w, θx, θy, θz), the sum of
///  - membrane: bilinear Q4 with Wilson's incompatible modes (1 − ξ², 1 − η²), condensed out,
///    so that in-plane bending, which carries a tube's beam bending, does not lock;
///  - bending: the Adini–Clough–Melosh Kirchhoff rectangle (12-term polynomial in w; non-
///    conforming but convergent on rectangles; no transverse shear, so no shear locking and no
///    spurious mechanisms at any thickness);
///  - a small drilling stiffness on θz (a flat facet has none; 1e-5 E t A) to keep K regular.
/// A straight tube meshed around and along is exactly such rectangles. Mass is lumped: a quarter
/// of the element's mass per node, with the rotary inertia of the wall, m t² / 12.
///
/// Setup code (may allocate); used to assemble the global matrices once.

#include <Eigen/Core>
#include <array>

namespace lap::models {

struct ShellMaterial {
  double young_pa = 1e6;
  double poisson = 0.45;
  double density_kg_per_m3 = 1060.0;
  double thickness_m = 0.001;
};

using ShellElementMatrix = Eigen::Matrix<double, 24, 24>;

/// Element stiffness and (diagonal) mass in global coordinates for the rectangle p0 p1 p2 p3
/// (counter-clockwise about its normal). Throws std::invalid_argument when the four points are
/// not a rectangle (to 1e-6 relative).
void shell_element_matrices(const std::array<Eigen::Vector3d, 4>& p, const ShellMaterial& material,
                            ShellElementMatrix* stiffness, Eigen::Matrix<double, 24, 1>* mass);

}  // namespace lap::models
