#pragma once
/// \file
/// The mass properties of a solid bounded by a closed, outward-oriented triangle mesh of uniform
/// density (thesis §6.4: "object properties such as the mass, inertia matrix and mass centre"):
/// its volume, centre of mass and inertia tensor, by the divergence theorem over the tetrahedra
/// each triangle spans with the origin (each tetrahedron's second moment ∫ x xᵀ dV in closed form,
/// signed by its orientation, so the origin may lie anywhere). Set-up only.

#include <Eigen/Core>

#include "haptics/triangle_mesh.h"
#include "models/rigid_body.h"

namespace lap::models {

struct MassProperties {
  double volume_m3 = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< in the mesh's frame [m]
  /// ∫ (|r|² 1 − r rᵀ) dV about the centroid, r = x − centroid [m⁵]: the inertia per unit
  /// density.
  Eigen::Matrix3d inertia_per_density = Eigen::Matrix3d::Zero();
};

/// The mesh's mass properties; volume <= 0 for an open or inward-facing mesh.
[[nodiscard]] MassProperties mass_properties(const haptics::TriangleMesh& mesh);

/// A rigid body of the mesh's shape and the given mass, uniformly dense: its centre of mass and
/// inertia in the mesh's frame (the body frame). Throws std::invalid_argument when the mesh
/// encloses no volume or the mass is not positive.
[[nodiscard]] RigidBodyModel rigid_body_of_mesh(const haptics::TriangleMesh& mesh, double mass_kg);

}  // namespace lap::models
