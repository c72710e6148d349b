#include "sim/setup/rigid_body_models.h"

#include <stdexcept>
#include <string>

#include "models/mass_properties.h"

namespace lap::sim {

Result<std::vector<RigidBodyOfOrgan>> build_rigid_bodies(const Scene& scene) {
  std::vector<RigidBodyOfOrgan> bodies;
  std::vector<Diagnostic> problems;
  const std::string file = scene.scenario.file.string();
  for (size_t i = 0; i < scene.organs.size(); ++i) {
    const OrganSpec& spec = scene.scenario.organs[i];
    if (!spec.dynamics.present || spec.model != models::ModelKind::kRigid) continue;
    const std::string field = "organs[" + std::to_string(i) + "].dynamics";
    if (static_cast<int32_t>(bodies.size()) >= kMaxRigidBodies) {
      problems.push_back({file, spec.dynamics.line, field,
                          "at most " + std::to_string(kMaxRigidBodies) + " free bodies a scene"});
      continue;
    }
    RigidBodyOfOrgan b;
    b.organ = static_cast<int32_t>(i);
    try {
      b.model = models::rigid_body_of_mesh(scene.organs[i].mesh, spec.dynamics.mass_kg);
    } catch (const std::invalid_argument& e) {
      problems.push_back({file, spec.dynamics.line, field, e.what()});
      continue;
    }
    b.model.linear_damping_per_s = spec.dynamics.linear_damping_per_s;
    b.model.angular_damping_per_s = spec.dynamics.angular_damping_per_s;
    if (const char* p = b.model.problem(); p[0] != '\0') {
      problems.push_back({file, spec.dynamics.line, field, p});
      continue;
    }
    bodies.push_back(b);
  }
  if (!problems.empty()) return problems;
  return bodies;
}

}  // namespace lap::sim
