#pragma once
/// \file
/// The scene of one trial of the §5.5 shape-perception experiment (sim/runtime/
/// perception_experiment.h): the trial's shape, `size_m` across, centred at the origin at the
/// trial's orientation, a fixed rigid obstacle; the right tool a probe of the trial's mode (`probe`
/// for point-based, `ray-probe` for ray-based rendering) through a port 15 cm above it, the left
/// one parked clear. §5.5 gives haptic cues only: whoever shows the session draws no picture of
/// the shape (`Scene::scenario.description` says so).

#include "sim/runtime/perception_experiment.h"
#include "sim/setup/scene.h"

namespace lap::sim {

/// The shape's mesh, `size_m` across (sphere's and cylinder's diameter, cone's base, cube's
/// side; the cone and cylinder as tall as wide), centred at the origin, unrotated.
[[nodiscard]] haptics::TriangleMesh perceived_shape_mesh(PerceivedShape shape, double size_m);

/// The trial's scene, ready for a session.
[[nodiscard]] Scene perception_scene(const PerceptionTrial& trial, double size_m = 0.04);

}  // namespace lap::sim
