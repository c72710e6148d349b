#pragma once
/// \file
/// A scenario with its meshes loaded, checked (and repaired where asked) and placed in the world.

#include <memory>
#include <string>
#include <vector>

#include "haptics/image_height_field.h"
#include "haptics/triangle_mesh.h"
#include "sim/setup/scenario.h"
#include "sim/setup/scenario_loader.h"

namespace lap::haptics {
struct RgbImage;  // haptics/setup/albedo_texture.h: only set-up and the app look inside
}  // namespace lap::haptics

namespace lap::sim {

/// One organ ready for rendering and haptics.
struct Organ {
  std::string name;
  haptics::TriangleMesh mesh;  ///< world frame [m], closed and outward-oriented
  Eigen::Vector3d color;
  MaterialSpec material;
  models::ModelKind model = models::ModelKind::kRigid;
  IncisionSpec incision;       ///< the duct's ductotomy (world frame), if the scenario cuts one
  std::string repair_summary;  ///< what repair did, empty when not asked
  /// An image texture's height map, decoded and checked at load (material.texture.image).
  std::shared_ptr<const haptics::HeightImage> height_image;
  /// The texture mapping's frame (material.texture.mapping, given in the mesh's frame) in the
  /// world, where `mesh` now is.
  Eigen::Isometry3d texture_frame_W = Eigen::Isometry3d::Identity();
  /// Its colour texture for drawing (a glTF's base colour image, mapped by `mesh.uvs`:
  /// sim/setup/gltf_albedo.h); null when the mesh file has none (drawn in `color`).
  std::shared_ptr<const haptics::RgbImage> albedo;
};

/// The loaded scene.
struct Scene {
  Scenario scenario;
  std::vector<Organ> organs;
  /// Bounds of all organs in the world [m].
  [[nodiscard]] Eigen::AlignedBox3d bounds() const;
  [[nodiscard]] int64_t triangle_count() const;
  /// Where the task happens: the centroid of the task's target organ (the duct), else the
  /// centre of the bounds. The tools point there at rest; the catheter is laid towards it.
  [[nodiscard]] Eigen::Vector3d task_target_point() const;
};

/// The scene, or every problem met while loading it and its meshes.
using SceneLoadResult = Result<Scene>;

/// Loads every organ mesh of a checked scenario. A mesh that is not a closed, oriented,
/// outward-facing manifold is a problem unless the organ asks for repair and repair succeeds.
[[nodiscard]] SceneLoadResult load_scene(const Scenario& scenario);

/// Loads scenario then scene, all problems together.
[[nodiscard]] SceneLoadResult load_scene_file(const std::filesystem::path& file,
                                              const ScenarioLoadSettings& settings = {});

/// A few lines describing the scene, for headless runs and the status bar.
[[nodiscard]] std::string describe_scene(const Scene& scene);

}  // namespace lap::sim
