#include "sim/setup/anatomy_assets.h"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "haptics/mesh_database.h"
#include "haptics/setup/mesh_validation.h"
#include "models/shell_mesh.h"
#include "sim/setup/duct_fit.h"
#include "sim/setup/duct_incision.h"
#include "sim/setup/mesh_loader.h"
#include "sim/setup/scenario_loader.h"
#include "tests/test_support.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Every file below root, as paths relative to it.
std::set<fs::path> files_below(const fs::path& root) {
  std::set<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (e.is_regular_file()) out.insert(fs::relative(e.path(), root));
  }
  return out;
}

haptics::GeneratedAnatomy generated(const std::string& preset) {
  haptics::AnatomyParameters p;
  EXPECT_TRUE(haptics::anatomy_preset(preset, &p));
  return haptics::generate_anatomy(p);
}

TEST(AnatomyAssets, GltfLoadsBackWithTheSameMeshInMetresAndItsTexture) {
  test::TempDir dir;
  ASSERT_TRUE(save_anatomy_presets(dir.path(), {"default"}).ok());
  const haptics::GeneratedAnatomy a = generated("default");
  for (const haptics::GeneratedOrgan& o : a.organs) {
    const fs::path file = dir.path() / "default" / (o.name + ".gltf");
    const Result<haptics::TriangleMesh> loaded = load_mesh(file);
    ASSERT_TRUE(loaded.ok()) << loaded.message();
    const haptics::TriangleMesh& m = loaded.value();
    ASSERT_EQ(m.vertex_count(), o.mesh.vertex_count()) << o.name;
    ASSERT_EQ(m.triangle_count(), o.mesh.triangle_count()) << o.name;
    EXPECT_EQ(m.triangles, o.mesh.triangles) << o.name;
    ASSERT_EQ(m.uvs.size(), m.positions.size()) << o.name;
    ASSERT_EQ(m.normals.size(), m.positions.size()) << o.name;
    double worst = 0.0;
    for (int32_t v = 0; v < m.vertex_count(); ++v) {
      worst = std::max(worst, (m.positions[v] - o.mesh.positions[v]).norm());
      EXPECT_NEAR((m.uvs[v] - o.mesh.uvs[v]).norm(), 0.0, 1e-5) << o.name;
      EXPECT_GT(m.normals[v].dot(o.mesh.normals[v]), 0.999) << o.name;
    }
    EXPECT_LT(worst, 1e-7) << o.name;  // single precision in the file
    EXPECT_TRUE(haptics::validate_mesh(m).clean()) << o.name;
    // The material's base colour image exists and is the stated size, 3 channels.
    const nlohmann::json g = nlohmann::json::parse(read_bytes(file));
    ASSERT_EQ(g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
    const fs::path image = file.parent_path() / g["images"][0]["uri"].get<std::string>();
    int w = 0, h = 0, comp = 0;
    ASSERT_EQ(stbi_info(image.string().c_str(), &w, &h, &comp), 1) << image;
    EXPECT_EQ(w, kAlbedoSizePx);
    EXPECT_EQ(h, kAlbedoSizePx);
    EXPECT_EQ(comp, 3);
  }
  // Metres: the liver spans organ size, 15-25 cm, not millimetres or centimetres.
  const haptics::TriangleMesh liver = load_mesh(dir.path() / "default/liver.gltf").value();
  const double span = liver.bounds().sizes().maxCoeff();
  EXPECT_GT(span, 0.15);
  EXPECT_LT(span, 0.25);
  // anatomy.json carries the incision site for the scenario.
  const nlohmann::json j = nlohmann::json::parse(read_bytes(dir.path() / "default/anatomy.json"));
  const auto c = j["cystic_duct"]["incision"]["center_m"];
  EXPECT_NEAR(c[0].get<double>(), a.cystic_duct.incision_center_m.x(), 1e-6);
  EXPECT_NEAR(c[2].get<double>(), a.cystic_duct.incision_center_m.z(), 1e-6);
}

TEST(AnatomyAssets, SameBytesTwice) {
  test::TempDir one;
  test::TempDir two;
  const std::vector<std::string> all = haptics::anatomy_preset_names();
  ASSERT_TRUE(save_anatomy_presets(one.path(), all).ok());
  ASSERT_TRUE(save_anatomy_presets(two.path(), all).ok());
  const std::set<fs::path> files = files_below(one.path());
  EXPECT_EQ(files, files_below(two.path()));
  EXPECT_EQ(files.size(), 4U * (9U * 2U + 1U + 8U));  // 9 organs (.gltf, .bin), json, textures
  for (const fs::path& f : files) {
    EXPECT_TRUE(read_bytes(one.path() / f) == read_bytes(two.path() / f)) << f;
  }
}

TEST(AnatomyAssets, TheSessionFitsItsDuctToTheGeneratedCysticDuct) {
  // The generated duct follows the stand-in's convention (a closed tube, outer wall), so the
  // session's modal-shell duct (a straight tube, sim/setup/duct_fit.h) can be placed on it. The
  // straight fit measures a curved duct's bend as extra radius: how much is printed, and it
  // must stay within 1 mm of the true outer diameter.
  for (const std::string& name : haptics::anatomy_preset_names()) {
    const haptics::GeneratedAnatomy a = generated(name);
    const Result<DuctFit> fit = fit_duct(a.organ("cystic_duct")->mesh, a.cystic_duct.wall_m);
    ASSERT_TRUE(fit.ok()) << name << ": " << fit.message();
    EXPECT_NEAR(fit->duct.outer_diameter_m, a.cystic_duct.outer_diameter_m, 0.001) << name;
    EXPECT_GT(
        fit->duct.length_m,
        0.8 * (a.cystic_duct.centre_line_m.back() - a.cystic_duct.centre_line_m.front()).norm())
        << name;
    // The reported incision site opens the fitted shell's wall where the session puts it
    // (sim/setup/tissue_model.cpp): a default-sized ductotomy (3 x 2 mm) on it is accepted.
    haptics::TriangleMesh wall = models::triangulate(models::make_duct_shell(fit->duct).mesh);
    wall.transform(Eigen::Affine3d(fit->pose_WD.matrix()));
    IncisionSpec incision;
    incision.present = true;
    incision.center_m = a.cystic_duct.incision_center_m;
    const Result<std::vector<uint8_t>> open =
        incision_faces(wall, fit->duct, fit->pose_WD, incision);
    ASSERT_TRUE(open.ok()) << name << ": " << open.message();
    EXPECT_GT(std::count(open->begin(), open->end(), 1), 0) << name;
    std::printf("%-9s duct fit: %.2f mm across (generated %.2f), %.1f mm long (centre line %.1f)\n",
                name.c_str(), 1e3 * fit->duct.outer_diameter_m,
                1e3 * a.cystic_duct.outer_diameter_m, 1e3 * fit->duct.length_m,
                1e3 * a.cystic_duct.length_m);
  }
}

// The scenarios on the generated anatomy (the default patient and the graded ones) copy their
// trocars and camera from their anatomy's anatomy.json by hand (the generator places the ports,
// docs/anatomy.md): a port moved in the preset and not in the scenario, or the other way round,
// fails here. A trocar of the scenario's own (the hard patient's catheter puncture) must lie on
// the abdominal wall's inner surface, where there is no hole for it.
TEST(AnatomyAssets, EachPatientsTrocarsAndCameraAreWhereItsAnatomyPutsThem) {
  int patients = 0;
  for (const auto& e : fs::directory_iterator(test::source_dir() / "scenarios")) {
    const std::string stem = e.path().stem().string();
    if (e.path().extension() != ".yaml" || (stem != "default" && !stem.starts_with("patient_"))) {
      continue;
    }
    ++patients;
    const ScenarioLoadResult s = load_scenario(e.path());
    ASSERT_TRUE(s.ok()) << s.message();
    ASSERT_FALSE(s->organs.empty()) << stem;
    // The anatomy is the folder of the scenario's meshes, one for all of them.
    const fs::path anatomy = s->organs.front().mesh.parent_path();
    for (const OrganSpec& o : s->organs) EXPECT_EQ(o.mesh.parent_path(), anatomy) << stem;
    const nlohmann::json a = nlohmann::json::parse(read_bytes(anatomy / "anatomy.json"));
    std::map<std::string, Eigen::Vector3d> ports;
    for (const nlohmann::json& p : a.at("ports")) {
      const auto xyz = p.at("position_m").get<std::array<double, 3>>();
      ports[p.at("name").get<std::string>()] = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
    }
    const haptics::MeshDatabase wall =
        haptics::MeshDatabase::build(load_mesh(anatomy / "abdominal_wall.gltf").value());
    int named = 0;
    for (const TrocarSpec& t : s->trocars) {
      const auto port = ports.find(t.name);
      if (port != ports.end()) {
        ++named;
        // The scenarios write the ports to 0.1 mm.
        EXPECT_LT((t.position_m - port->second).norm(), 1e-4)
            << stem << ": trocar " << t.name << " at " << t.position_m.transpose()
            << ", anatomy.json's port at " << port->second.transpose();
        continue;
      }
      double d2 = std::numeric_limits<double>::infinity();
      ASSERT_GE(wall.nearest_face(t.position_m, nullptr, &d2), 0) << stem;
      const double nearest = std::sqrt(d2);
      EXPECT_LT(nearest, 1e-3) << stem << ": trocar " << t.name << " is " << 1e3 * nearest
                               << " mm from the abdominal wall";
    }
    EXPECT_GE(named, 2) << stem << ": the instruments' trocars are anatomy.json's ports";
    const auto cam = a.at("parameters").at("camera_m").get<std::array<double, 3>>();
    EXPECT_LT((s->camera.position_m - Eigen::Vector3d(cam[0], cam[1], cam[2])).norm(), 1e-4)
        << stem << ": the laparoscope is anatomy.json's camera_m";
    // It pivots in the umbilical port.
    ASSERT_TRUE(s->camera.port_m.has_value()) << stem;
    ASSERT_EQ(ports.count("umbilical"), 1U) << stem;
    EXPECT_LT((*s->camera.port_m - ports.at("umbilical")).norm(), 1e-4) << stem;
  }
  EXPECT_EQ(patients, 4);  // the default patient and the three graded ones
}

TEST(AnatomyAssets, UnknownPresetIsADiagnostic) {
  test::TempDir dir;
  const Status s = save_anatomy_presets(dir.path(), {"obese"});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("unknown anatomy preset 'obese'"), std::string::npos);
}

TEST(AnatomyAssets, CommittedAssetsAreWhatTheGeneratorWrites) {
  // assets/anatomy is written by `laptrainer-cli generate-assets --out assets/anatomy --anatomy
  // all`; a stale or missing file fails here. Meshes are compared as loaded (single precision),
  // images as pixels, anatomy.json as numbers, so another libm's last bit does not fail it.
  const fs::path committed = test::source_dir() / "assets/anatomy";
  test::TempDir dir;
  ASSERT_TRUE(save_anatomy_presets(dir.path(), haptics::anatomy_preset_names()).ok());
  const std::set<fs::path> files = files_below(dir.path());
  ASSERT_EQ(files_below(committed), files);
  for (const fs::path& f : files) {
    const std::string ext = f.extension().string();
    if (ext == ".gltf") {
      const haptics::TriangleMesh fresh = load_mesh(dir.path() / f).value();
      const haptics::TriangleMesh old = load_mesh(committed / f).value();
      ASSERT_EQ(old.vertex_count(), fresh.vertex_count()) << f;
      EXPECT_EQ(old.triangles, fresh.triangles) << f;
      double worst = 0.0;
      for (int32_t v = 0; v < old.vertex_count(); ++v) {
        worst = std::max(worst, (old.positions[v] - fresh.positions[v]).norm());
      }
      EXPECT_LT(worst, 1e-7) << f;
    } else if (ext == ".png") {
      int w1 = 0, h1 = 0, c1 = 0, w2 = 0, h2 = 0, c2 = 0;
      stbi_uc* a = stbi_load((dir.path() / f).string().c_str(), &w1, &h1, &c1, 3);
      stbi_uc* b = stbi_load((committed / f).string().c_str(), &w2, &h2, &c2, 3);
      ASSERT_TRUE(a != nullptr && b != nullptr) << f;
      ASSERT_EQ(w1, w2) << f;
      ASSERT_EQ(h1, h2) << f;
      int worst = 0;
      for (int i = 0; i < w1 * h1 * 3; ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
      stbi_image_free(a);
      stbi_image_free(b);
      EXPECT_LE(worst, 1) << f;
    } else if (ext == ".json") {
      const nlohmann::json a = nlohmann::json::parse(read_bytes(dir.path() / f));
      const nlohmann::json b = nlohmann::json::parse(read_bytes(committed / f));
      const nlohmann::json diff = nlohmann::json::diff(a, b);
      for (const auto& op : diff) {
        const std::string path = op["path"];
        const nlohmann::json x = a.at(nlohmann::json::json_pointer(path));
        ASSERT_TRUE(x.is_number() && op.contains("value") && op["value"].is_number())
            << f << " " << path;
        EXPECT_NEAR(x.get<double>(), op["value"].get<double>(), 2e-6) << f << " " << path;
      }
    }
  }
}

}  // namespace
}  // namespace lap::sim
