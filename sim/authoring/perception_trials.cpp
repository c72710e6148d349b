#include "sim/authoring/perception_trials.h"

#include <cmath>

#include "haptics/setup/mesh_generators.h"
#include "sim/authoring/demo_assets.h"

namespace lap::sim {

haptics::TriangleMesh perceived_shape_mesh(PerceivedShape shape, double size_m) {
  const double r = 0.5 * size_m;
  switch (shape) {
    case PerceivedShape::kSphere:
      return haptics::make_uv_sphere(r, 24, 48);
    case PerceivedShape::kCube:
      return haptics::make_box(Eigen::Vector3d::Constant(size_m), 4);
    case PerceivedShape::kCylinder: {
      haptics::TriangleMesh m = haptics::make_cylinder(r, size_m, 48, 8);
      for (Eigen::Vector3d& p : m.positions) p.y() -= r;
      return m;
    }
    case PerceivedShape::kCone: {
      // The base disc from the axis out, then the slant to the apex: (y, radius).
      std::vector<Eigen::Vector2d> profile;
      for (int i = 0; i <= 8; ++i) profile.emplace_back(-r, r * i / 8.0);
      for (int i = 1; i <= 24; ++i)
        profile.emplace_back(-r + size_m * i / 24.0, r * (1.0 - i / 24.0));
      return make_revolution(profile, 48);
    }
  }
  return haptics::make_uv_sphere(r, 24, 48);
}

Scene perception_scene(const PerceptionTrial& trial, double size_m) {
  Scene scene;
  Scenario& sc = scene.scenario;
  sc.name = "Shape perception, trial " + std::to_string(trial.index + 1) + " (" +
            std::string(to_string(trial.mode)) + " probe)";
  sc.description = "Thesis 5.5: name the shape by touch alone; the shape is not drawn.";
  OrganSpec spec;
  spec.name = "shape";
  spec.model = models::ModelKind::kRigid;
  spec.material.stiffness_n_per_m = 400.0;  // estimate: firm, within a desktop arm's range
  sc.organs.push_back(spec);
  sc.trocars.push_back({"port_left", Eigen::Vector3d(-0.15, 0.12, 0.0)});
  sc.trocars.push_back({"port_right", Eigen::Vector3d(0.0, 0.15, 0.0)});
  ToolSpec left;
  left.name = "idle";
  left.side = ToolSpec::Side::kLeft;
  left.trocar = "port_left";
  left.kind = "probe";
  ToolSpec right;
  right.name = "probe";
  right.side = ToolSpec::Side::kRight;
  right.trocar = "port_right";
  right.kind = trial.mode == ProbeMode::kPoint ? "probe" : "ray-probe";
  sc.tools = {left, right};
  Organ organ;
  organ.name = spec.name;
  organ.mesh = perceived_shape_mesh(trial.shape, size_m);
  const Eigen::Matrix3d rot = trial.orientation.toRotationMatrix();
  for (Eigen::Vector3d& p : organ.mesh.positions) p = rot * p;
  organ.mesh.normals.clear();
  organ.color = Eigen::Vector3d(0.5, 0.5, 0.5);
  organ.material = spec.material;
  organ.model = spec.model;
  scene.organs.push_back(std::move(organ));
  return scene;
}

}  // namespace lap::sim
