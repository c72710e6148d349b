// scenarios/README.md's walk-through "Adding a new organ from a mesh file, end to end", followed
// step by step on a mesh this test generates: the mesh written as binary STL in millimetres,
// checked with mesh-info, the scenario taken word for word from the README's example, validated,
// and run with a scripted probe pressing the new organ (its force in the metrics).

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>

#include "haptics/setup/mesh_generators.h"
#include "tests/sim/demo_test_support.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;

// Binary STL: an 80-byte header, the triangle count, then per triangle its normal, three
// vertices (float32) and a 2-byte attribute.
void write_binary_stl(const haptics::TriangleMesh& m, const fs::path& file) {
  std::ofstream out(file, std::ios::binary);
  const std::string header(80, ' ');
  out.write(header.data(), 80);
  const auto n = static_cast<uint32_t>(m.triangles.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (int32_t t = 0; t < m.triangle_count(); ++t) {
    const Eigen::Vector3f normal = m.triangle_cross(t).normalized().cast<float>();
    out.write(reinterpret_cast<const char*>(normal.data()), 12);
    for (const int32_t v : m.triangles[static_cast<size_t>(t)]) {
      const Eigen::Vector3f p = m.positions[static_cast<size_t>(v)].cast<float>();
      out.write(reinterpret_cast<const char*>(p.data()), 12);
    }
    const uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
}

// The README's example scenario: the first ```yaml block after the walk-through's heading.
std::string readme_example() {
  const std::string text = test::read_file(test::source_dir() / "scenarios/README.md");
  const size_t section = text.find("## Adding a new organ from a mesh file");
  EXPECT_NE(section, std::string::npos);
  const size_t start = text.find("```yaml\n", section);
  const size_t end = text.find("```", start + 8);
  EXPECT_NE(start, std::string::npos);
  // The block is indented as part of a list item: take the indentation off.
  std::string block = text.substr(start + 8, end - start - 8);
  return std::regex_replace(block, std::regex("(^|\n)   "), "$1");
}

TEST(OrganWalkthrough, TheReadmesStepsAddAnOrganFromAnStlFile) {
  const test::TempDir dir;
  fs::create_directories(dir.path() / "my");
  // Step 1: a kidney-like ellipsoid, 100 x 60 x 50 mm, in millimetres, as binary STL.
  const haptics::TriangleMesh kidney =
      haptics::make_mapped_sphere(24, 48, [](const Eigen::Vector3d& u) {
        return Eigen::Vector3d(50.0 * u.x(), 30.0 * u.y(), 25.0 * u.z());
      });
  write_binary_stl(kidney, dir.path() / "my/kidney.stl");
  const fs::path cli = test::bin_dir() / "laptrainer-cli";
  const bool have_cli = fs::exists(cli);
  if (have_cli) {
    const test::CommandResult info =
        test::run_command(cli.string() + " mesh-info --mesh " +
                          (dir.path() / "my/kidney.stl").string() + " --scale 0.001");
    EXPECT_EQ(info.exit_code, 0) << info.out << info.err;
  }
  // Step 2: the scenario, as the README writes it.
  const fs::path scenario = dir.write("my/kidney.yaml", readme_example());
  // Step 3: validate.
  const SceneLoadResult scene = load_scene_file(scenario);
  ASSERT_TRUE(scene.ok()) << scene.message();
  ASSERT_EQ(scene.value().organs.size(), 1U);
  // Placed as the README says: 100 mm along x turned 90° about y, centred 2 cm up.
  const Eigen::AlignedBox3d box = scene.value().organs[0].mesh.bounds();
  EXPECT_NEAR(box.sizes().z(), 0.100, 1e-4);
  EXPECT_NEAR(box.center().y(), 0.02, 1e-4);
  if (have_cli) {
    const test::CommandResult v =
        test::run_command(cli.string() + " validate --scenario " + scenario.string());
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  }
  // Step 4: run, the right probe pressing 5 mm into the kidney's top (y = 0.05).
  auto run = demo_test::observed_session(
      scene.value(),
      {{{{0.0, Eigen::Vector3d(-0.08, 0.1, 0.05)}, {1.5, Eigen::Vector3d(-0.08, 0.1, 0.05)}},
        {{0.0, Eigen::Vector3d(0.0, 0.08, 0.0)},
         {1.0, Eigen::Vector3d(0.0, 0.045, 0.0)},
         {1.5, Eigen::Vector3d(0.0, 0.045, 0.0)}}}},
      1.5, nullptr);
  ASSERT_NE(run.session, nullptr);
  const SessionMetrics m = run.session->run();
  double force = -1.0;
  for (const Metric& metric : m.training) {
    if (metric.name == "max_force_kidney_n") force = metric.value;
  }
  // A local organ: the surface takes half the 5 mm, the probe feels (1 − 0.5) × 150 N/m of it.
  EXPECT_NEAR(force, 0.5 * 150.0 * 0.005, 0.1);
}

}  // namespace
}  // namespace lap::sim
