#pragma once
/// \file
/// The scene's free rigid bodies (thesis §6.4): each `rigid` organ with `dynamics` becomes a body
/// of its mass, uniformly dense, its centre of mass and inertia taken from its closed mesh
/// (models/mass_properties.h). The body frame is the world frame the organ was placed in: at rest
/// the body's pose is the identity, and its pose is then exactly the transform the proxies apply
/// to the organ's surface (HapticObject::pose_WO), which never moves a vertex.
///
/// A `rigid` organ without `dynamics` is anchored: it is no body and never moves.

#include <cstdint>
#include <vector>

#include "core/result.h"
#include "models/rigid_body.h"
#include "sim/setup/scene.h"

namespace lap::sim {

/// The most free bodies a scene may have (the snapshots carry them in fixed arrays).
inline constexpr int32_t kMaxRigidBodies = 16;

/// One free body: which organ, and its mass properties in the body (rest world) frame.
struct RigidBodyOfOrgan {
  int32_t organ = -1;
  models::RigidBodyModel model;
};

/// Every free body of the scene; diagnostics name the scenario file and the dynamics' line.
[[nodiscard]] Result<std::vector<RigidBodyOfOrgan>> build_rigid_bodies(const Scene& scene);

}  // namespace lap::sim
