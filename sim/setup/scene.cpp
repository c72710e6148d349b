#include "sim/setup/scene.h"

#include <sstream>

#include "haptics/setup/mesh_repair.h"
#include "haptics/setup/mesh_validation.h"
#include "sim/setup/gltf_albedo.h"
#include "sim/setup/height_image_loader.h"
#include "sim/setup/mesh_loader.h"

namespace lap::sim {

Eigen::AlignedBox3d Scene::bounds() const {
  Eigen::AlignedBox3d box;
  for (const Organ& o : organs) box.extend(o.mesh.bounds());
  return box;
}

Eigen::Vector3d Scene::task_target_point() const {
  if (scenario.task) {
    for (const Organ& organ : organs) {
      if (organ.name != scenario.task->target || organ.mesh.positions.empty()) continue;
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& p : organ.mesh.positions) c += p;
      return c / static_cast<double>(organ.mesh.positions.size());
    }
  }
  return bounds().center();
}

int64_t Scene::triangle_count() const {
  int64_t n = 0;
  for (const Organ& o : organs) n += o.mesh.triangle_count();
  return n;
}

SceneLoadResult load_scene(const Scenario& scenario) {
  Scene scene;
  std::vector<Diagnostic> problems;
  scene.scenario = scenario;
  for (size_t i = 0; i < scenario.organs.size(); ++i) {
    const OrganSpec& spec = scenario.organs[i];
    const std::string field = "organs[" + std::to_string(i) + "].mesh";
    Organ organ;
    organ.name = spec.name;
    organ.color = spec.color;
    organ.material = spec.material;
    organ.model = spec.model;
    organ.incision = spec.incision;
    MeshLoadSettings load;
    load.scale = spec.scale;
    Result<haptics::TriangleMesh> mesh = load_mesh(spec.mesh, load);
    if (!mesh.ok()) {
      problems.push_back({scenario.file.string(), spec.line, field, mesh.message()});
      continue;
    }
    organ.mesh = std::move(mesh).value();
    if (spec.repair) {
      organ.repair_summary = haptics::repair_mesh(organ.mesh).summary();
    }
    const haptics::MeshDiagnostics d = haptics::validate_mesh(organ.mesh);
    if (!d.clean()) {
      std::string what;
      for (const std::string& line : d.describe()) what += (what.empty() ? "" : "; ") + line;
      problems.push_back(
          {scenario.file.string(), spec.line, field,
           spec.mesh.string() + " is not a closed, oriented, outward-facing manifold: " + what +
               (spec.repair ? " (left after repair)" : " (fix the mesh or set repair: true)")});
      continue;
    }
    std::string extension = spec.mesh.extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (extension == ".gltf" || extension == ".glb") {
      Result<std::shared_ptr<const haptics::RgbImage>> albedo = load_gltf_albedo(spec.mesh);
      if (!albedo.ok()) {
        problems.push_back({scenario.file.string(), spec.line, field, albedo.message()});
        continue;
      }
      // Drawn only where every vertex has its texture coordinate.
      if (organ.mesh.uvs.size() == organ.mesh.positions.size()) organ.albedo = albedo.value();
    }
    const TextureSpec& texture = spec.material.texture;
    if (texture.kind == TextureSpec::Kind::kImage) {
      Result<haptics::HeightImage> image = load_height_image(texture.image);
      if (!image.ok()) {
        problems.push_back({scenario.file.string(), texture.line,
                            "organs[" + std::to_string(i) + "].material.texture.image",
                            image.message()});
        continue;
      }
      organ.height_image = std::make_shared<const haptics::HeightImage>(std::move(image).value());
    }
    // The mapping's z axis along `axis`, its origin at `origin_m`, both in the mesh frame.
    Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
    frame.linear() =
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), texture.mapping.axis)
            .toRotationMatrix();
    frame.translation() = texture.mapping.origin_m;
    const Eigen::Affine3d placed = spec.transform();
    organ.texture_frame_W.linear() = placed.linear() * frame.linear();
    organ.texture_frame_W.translation() = placed * frame.translation();
    organ.mesh.transform(placed);
    if (organ.mesh.normals.size() != organ.mesh.positions.size())
      organ.mesh.compute_vertex_normals();
    scene.organs.push_back(std::move(organ));
  }
  if (!problems.empty()) return problems;
  return scene;
}

SceneLoadResult load_scene_file(const std::filesystem::path& file,
                                const ScenarioLoadSettings& settings) {
  ScenarioLoadResult scenario = load_scenario(file, settings);
  if (!scenario.ok()) {
    return scenario.diagnostics();
  }
  return load_scene(scenario.value());
}

std::string describe_scene(const Scene& scene) {
  std::ostringstream s;
  s << "scenario: " << scene.scenario.name << " (" << scene.scenario.file.string() << ")\n";
  s << "organs: " << scene.organs.size() << ", triangles: " << scene.triangle_count() << "\n";
  for (const Organ& o : scene.organs) {
    const Eigen::AlignedBox3d b = o.mesh.bounds();
    const Eigen::Vector3d size = b.sizes() * 1000.0;
    s.precision(1);
    s << std::fixed << "  " << o.name << ": " << o.mesh.triangle_count() << " triangles, "
      << size.x() << " x " << size.y() << " x " << size.z() << " mm, model "
      << models::to_string(o.model) << ", stiffness " << o.material.stiffness_n_per_m << " N/m";
    if (!o.repair_summary.empty()) s << ", repaired: " << o.repair_summary;
    s << "\n";
  }
  s << "tools: " << scene.scenario.tools.size() << ", trocars: " << scene.scenario.trocars.size();
  if (scene.scenario.task) s << ", task: " << scene.scenario.task->kind;
  s << "\n";
  return s.str();
}

}  // namespace lap::sim
