#include "models/mass_properties.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace lap::models {

MassProperties mass_properties(const haptics::TriangleMesh& mesh) {
  // Per triangle (a, b, c) the tetrahedron (0, a, b, c): signed volume det[a b c] / 6, first
  // moment V (a + b + c) / 4, second moment ∫ x xᵀ dV = det / 120 (a aᵀ + b bᵀ + c cᵀ + s sᵀ),
  // s = a + b + c (the canonical tetrahedron's covariance mapped by [a b c]).
  double volume = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const haptics::Triangle& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.positions[static_cast<size_t>(t[0])];
    const Eigen::Vector3d& b = mesh.positions[static_cast<size_t>(t[1])];
    const Eigen::Vector3d& c = mesh.positions[static_cast<size_t>(t[2])];
    const double det = a.dot(b.cross(c));
    const Eigen::Vector3d s = a + b + c;
    volume += det / 6.0;
    first += det / 24.0 * s;
    second += det / 120.0 *
              (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  MassProperties p;
  p.volume_m3 = volume;
  if (!(volume > 0.0)) return p;
  p.centroid = first / volume;
  // Parallel axis: the second moment about the centroid, then the inertia from it.
  const Eigen::Matrix3d about_centroid = second - volume * p.centroid * p.centroid.transpose();
  p.inertia_per_density = about_centroid.trace() * Eigen::Matrix3d::Identity() - about_centroid;
  return p;
}

RigidBodyModel rigid_body_of_mesh(const haptics::TriangleMesh& mesh, double mass_kg) {
  if (!(mass_kg > 0.0) || !std::isfinite(mass_kg)) {
    throw std::invalid_argument("mass_kg must be positive and finite");
  }
  const MassProperties p = mass_properties(mesh);
  if (!(p.volume_m3 > 0.0)) {
    throw std::invalid_argument(
        "the mesh encloses no volume (open or inward-facing): no mass properties");
  }
  RigidBodyModel m;
  m.mass_kg = mass_kg;
  m.com_B = p.centroid;
  m.inertia_B = mass_kg / p.volume_m3 * p.inertia_per_density;
  m.inertia_B = 0.5 * (m.inertia_B + m.inertia_B.transpose()).eval();
  return m;
}

}  // namespace lap::models
