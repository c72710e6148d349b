#pragma once
/// \file
/// The thesis' demonstrations as scenarios (scenarios/demos/): their meshes and height map,
/// generated here and committed in assets/demos/ (as assets/anatomy/ is), and their scripted
/// runs, the tools' tips led along paths through their trocars and written as keyframe CSV
/// (hardware/README.md) in scenarios/scripts/<demo>/demo_left.csv and demo_right.csv.
///
/// - floating_dumbbells (Figure 5-15): two free dumbbells touched at once by a ray probe.
/// - concave_rocket (Figure 5-17): a free rocket whose nozzle and waist are concave, touched
///   by a ray probe.
/// - pushed_object (Figure 6-8): a free block pushed by a point probe.
/// - deformable_ball (Figure 6-10): a ball dented locally under a point probe.
/// - textured_surfaces (Figures 6-6, 6-7): an image-textured and a procedurally textured slab
///   stroked by point probes.
/// - frictional_surface (§6.2): a slab with stick-slip friction stroked by a point probe.
///
/// Offline (set-up and tests): allocates and may be slow.

#include <Eigen/Core>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "haptics/triangle_mesh.h"
#include "hardware/scripted_trajectory.h"
#include "sim/setup/scene.h"

namespace lap::sim {

/// A closed surface of revolution about +y: `profile` holds (y, radius) from the bottom pole
/// (radius 0) to the top pole (radius 0), radii positive between; `slices` around the axis.
/// Outward-oriented.
[[nodiscard]] haptics::TriangleMesh make_revolution(std::span<const Eigen::Vector2d> profile,
                                                    int slices);

/// A dumbbell along y, centred at the origin: two balls of `ball_radius_m` whose centres are
/// ±`half_span_m` apart along the axis, joined by a bar of `bar_radius_m` (Figure 5-15).
[[nodiscard]] haptics::TriangleMesh make_dumbbell(double ball_radius_m, double half_span_m,
                                                  double bar_radius_m);
/// A rocket along +y from its nozzle (y = 0) to its nose: a flared nozzle bell and a waist
/// before the body, both concave (Figure 5-17).
[[nodiscard]] haptics::TriangleMesh make_rocket();

/// The demonstrations' file stems, in order.
[[nodiscard]] std::vector<std::string> demo_names();

/// Writes the meshes (OBJ) and the height map (8-bit grey PNG) into `dir` (assets/demos).
[[nodiscard]] Status write_demo_assets(const std::filesystem::path& dir);

/// A tool tip's waypoint: where the tip should be at time t (the handle follows through the
/// trocar).
struct TipWaypoint {
  double time_s = 0.0;
  Eigen::Vector3d tip_W = Eigen::Vector3d::Zero();
};

/// The keyframes that lead `side`'s tool tip (0 left, 1 right) of the scene along the
/// waypoints, in straight lines between them (a keyframe every millimetre of the tip's travel):
/// each handle on the line from the tip through the port, a shaft's length from the tip,
/// gripper open.
[[nodiscard]] hardware::ScriptedTrajectory tip_path_script(const Scene& scene, int side,
                                                           std::span<const TipWaypoint> path);

/// The demonstration's scripted run: per hand, its tip's waypoints (empty name: none).
[[nodiscard]] std::array<std::vector<TipWaypoint>, 2> demo_tip_paths(const std::string& demo);

/// Writes each demonstration's scripts from its scenario in `scenarios_dir`/demos into
/// `scripts_dir`/<demo>/demo_left.csv and demo_right.csv (scripts_dir: scenarios/scripts).
[[nodiscard]] Status write_demo_scripts(const std::filesystem::path& scenarios_dir,
                                        const std::filesystem::path& scripts_dir);

}  // namespace lap::sim
