#include "sim/setup/scenario_loader.h"

#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "tests/test_support.h"

namespace lap::sim {
namespace {

// A valid scenario; each bad case replaces one line (numbers below are 1-based file lines).
const std::string kBase = R"(version: 1
name: test scene
organs:
  - name: liver
    mesh: meshes/tetra.obj
    scale: 0.001
    color: [0.5, 0.2, 0.1]
    model: local
    transform:
      translation_m: [0, 0.05, 0]
      rotation_deg: [0, 90, 0]
    material:
      stiffness_n_per_m: 300
      damping_n_s_per_m: 0.5
      friction_static: 0.2
      friction_dynamic: 0.1
  - name: duct
    mesh: meshes/tetra.obj
    model: modal-shell
    material:
      stiffness_n_per_m: 150
trocars:
  - name: left_port
    position_m: [-0.1, 0.2, 0.1]
tools:
  - name: left_grasper
    side: left
    trocar: left_port
catheter:
  particles: 32
task:
  kind: catheter-insertion
  target: duct
camera:
  view_angle_deg: 30
)";

const char* const kTetraObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

class ScenarioFixture : public ::testing::Test {
 protected:
  void SetUp() override { dir_.write("scene/meshes/tetra.obj", kTetraObj); }

  // Loads kBase with `line` (1-based) replaced by `replacement` (may hold several lines, or be
  // empty to delete the line).
  ScenarioLoadResult load_with(int line, const std::string& replacement) {
    return load_with(std::map<int, std::string>{{line, replacement}});
  }
  ScenarioLoadResult load_with(const std::map<int, std::string>& replacements) {
    std::string text;
    std::istringstream in(kBase);
    std::string l;
    for (int n = 1; std::getline(in, l); ++n) {
      const auto it = replacements.find(n);
      if (it == replacements.end()) {
        text += l + "\n";
      } else if (!it->second.empty()) {
        text += it->second + "\n";
      }
    }
    return load_scenario(dir_.write("scene/s.yaml", text));
  }

  std::string file() const { return (dir_.path() / "scene/s.yaml").string(); }

  // Exactly one problem, with exactly this text after the file name.
  void expect_one(const ScenarioLoadResult& r, const std::string& expected) {
    ASSERT_EQ(r.diagnostics().size(), 1U) << all(r);
    EXPECT_EQ(r.diagnostics()[0].to_string(), file() + ":" + expected);
  }

  static std::string all(const ScenarioLoadResult& r) {
    std::string s;
    for (const auto& p : r.diagnostics()) s += p.to_string() + "\n";
    return s;
  }

  test::TempDir dir_;
};

TEST_F(ScenarioFixture, BaseScenarioIsValid) {
  const ScenarioLoadResult r = load_with(0, "");
  ASSERT_TRUE(r.ok()) << all(r);
  const Scenario& s = r.value();
  ASSERT_EQ(s.organs.size(), 2U);
  EXPECT_EQ(s.organs[0].name, "liver");
  EXPECT_DOUBLE_EQ(s.organs[0].scale, 0.001);
  EXPECT_DOUBLE_EQ(s.organs[0].material.stiffness_n_per_m, 300.0);
  EXPECT_EQ(s.organs[1].model, models::ModelKind::kModalShell);
  EXPECT_TRUE(s.organs[0].translation_m.isApprox(Eigen::Vector3d(0, 0.05, 0)));
  // rotation_deg [0, 90, 0]: x maps to -z.
  EXPECT_TRUE((s.organs[0].transform().linear() * Eigen::Vector3d::UnitX())
                  .isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_EQ(s.tools.size(), 1U);
  EXPECT_EQ(s.catheter->particles, 32);
  EXPECT_EQ(s.task->target, "duct");
  EXPECT_TRUE(
      std::filesystem::equivalent(s.organs[0].mesh, dir_.path() / "scene/meshes/tetra.obj"));
}

// --- The bad scenarios: one defect each, one exact message each. ---

TEST_F(ScenarioFixture, Bad01_MissingVersion) {
  expect_one(load_with(1, ""), "1: version: required field is missing");
}

TEST_F(ScenarioFixture, Bad02_UnsupportedVersion) {
  expect_one(load_with(1, "version: 2"),
             "1: version: expected a whole number from 1 to 1, got '2'");
}

TEST_F(ScenarioFixture, Bad03_UnknownTopLevelField) {
  expect_one(load_with(2, "name: test scene\ncolour: red"),
             "3: colour: unknown field (expected one of: version, name, description, difficulty, "
             "allowed_paths, camera, organs, trocars, tools, catheter, task, proficiency)");
}

TEST_F(ScenarioFixture, Bad04_MissingMesh) {
  expect_one(load_with(18, ""), "17: organs[1].mesh: required field is missing");
}

TEST_F(ScenarioFixture, Bad05_MeshFileNotFound) {
  expect_one(load_with(18, "    mesh: meshes/nothing.obj"),
             "18: organs[1].mesh: file 'meshes/nothing.obj' not found (looked for " +
                 (dir_.path() / "scene/meshes/nothing.obj").string() + ")");
}

TEST_F(ScenarioFixture, Bad06_MeshPathLeavesTheScenarioFolder) {
  dir_.write("outside.obj", kTetraObj);
  expect_one(load_with(18, "    mesh: ../outside.obj"),
             "18: organs[1].mesh: path '../outside.obj' leaves the scenario's folder (expected a "
             "file under " +
                 (dir_.path() / "scene").string() +
                 " or under a directory listed in allowed_paths)");
}

TEST_F(ScenarioFixture, Bad07_NegativeStiffness) {
  expect_one(load_with(13, "      stiffness_n_per_m: -5"),
             "13: organs[0].material.stiffness_n_per_m: expected a positive number, got '-5'");
}

TEST_F(ScenarioFixture, Bad08_StiffnessNotANumber) {
  expect_one(load_with(13, "      stiffness_n_per_m: soft"),
             "13: organs[0].material.stiffness_n_per_m: expected a positive number, got 'soft'");
}

TEST_F(ScenarioFixture, Bad09_DynamicFrictionAboveStatic) {
  expect_one(
      load_with(16, "      friction_dynamic: 0.5"),
      "16: organs[0].material.friction_dynamic: expected at most friction_static (0.200000)");
}

TEST_F(ScenarioFixture, Bad10_UnknownModelKind) {
  expect_one(load_with(8, "    model: jelly"),
             "8: organs[0].model: expected rigid, local or modal-shell, got 'jelly'");
}

TEST_F(ScenarioFixture, Bad11_ColourOutOfRange) {
  expect_one(load_with(7, "    color: [1.5, 0.2, 0.1]"),
             "7: organs[0].color: expected RGB components from 0 to 1");
}

TEST_F(ScenarioFixture, Bad12_TranslationWithTwoNumbers) {
  expect_one(
      load_with(10, "      translation_m: [0, 0.05]"),
      "10: organs[0].transform.translation_m: expected a list of 3 numbers [x, y, z], got a list");
}

TEST_F(ScenarioFixture, Bad13_DuplicateOrganName) {
  expect_one(load_with(4, "  - name: duct"),
             "17: organs[1].name: duplicate organ name 'duct' (names must be unique)");
}

TEST_F(ScenarioFixture, Bad14_ToolThroughUnknownTrocar) {
  expect_one(load_with(28, "    trocar: umbilical"),
             "28: tools[0].trocar: no trocar named 'umbilical' (expected a name from trocars)");
}

TEST_F(ScenarioFixture, Bad15_ToolSideNotLeftOrRight) {
  expect_one(load_with(27, "    side: middle"),
             "27: tools[0].side: expected left or right, got 'middle'");
}

TEST_F(ScenarioFixture, Bad16_TwoLeftTools) {
  expect_one(
      load_with(28,
                "    trocar: left_port\n  - name: second\n    side: left\n    trocar: left_port"),
      "30: tools[1].side: a left tool is already defined (one tool per hand)");
}

TEST_F(ScenarioFixture, Bad17_TaskTargetsUnknownOrgan) {
  expect_one(load_with(33, "  target: bile_duct"),
             "33: task.target: no organ named 'bile_duct' (expected a name from organs)");
}

TEST_F(ScenarioFixture, Bad18_YamlSyntaxError) {
  expect_one(load_with(7, "    color: [0.5, 0.2, 0.1"),
             "8: (syntax): not valid YAML: end of sequence flow not found");
}

TEST_F(ScenarioFixture, Bad19_FieldGivenTwice) {
  expect_one(load_with(6, "    scale: 0.001\n    scale: 0.002"),
             "7: organs[0].scale: field given twice (expected each field once)");
}

TEST_F(ScenarioFixture, Bad20_ImageTextureFileMissing) {
  expect_one(
      load_with(16,
                "      friction_dynamic: 0.1\n      texture:\n        kind: image\n"
                "        image: textures/bumps.png\n        amplitude_m: 0.0002\n"
                "        wavelength_m: 0.002"),
      "19: organs[0].material.texture.image: file 'textures/bumps.png' not found (looked for " +
          (dir_.path() / "scene/textures/bumps.png").string() + ")");
}

TEST_F(ScenarioFixture, Bad21_UnknownProceduralFunction) {
  expect_one(load_with(16,
                       "      friction_dynamic: 0.1\n      texture:\n        kind: procedural\n"
                       "        function: plaid\n        amplitude_m: 0.0002\n"
                       "        wavelength_m: 0.002"),
             "19: organs[0].material.texture.function: expected perlin, fbm, worley or fourier, "
             "got 'plaid'");
}

TEST_F(ScenarioFixture, Bad22_CatheterWithOneParticle) {
  expect_one(load_with(30, "  particles: 1"),
             "30: catheter.particles: expected a whole number from 2 to 4096, got '1'");
}

TEST_F(ScenarioFixture, Bad23_CameraViewAngleTooWide) {
  expect_one(load_with(35, "  view_angle_deg: 170"),
             "35: camera.view_angle_deg: expected a number from 1 to 120 (degrees), got 170");
}

TEST_F(ScenarioFixture, Bad23b_LaparoscopeOpticsAndPort) {
  expect_one(load_with(35, "  view_angle_deg: 30\n  optics_deg: 90"),
             "36: camera.optics_deg: expected a number from 0 to 70 (degrees; laparoscopes are "
             "0, 30, 45 or 70), got 90");
  expect_one(load_with(35, "  view_angle_deg: 30\n  port_m: [0, 0.25, 0.35]"),
             "36: camera.port_m: expected the port at least 1 mm from position_m (the scope's "
             "tip, inside the abdomen)");
  // A port beyond what the scope looks at: the focal point would lie behind the tip.
  expect_one(load_with(35, "  view_angle_deg: 30\n  port_m: [0, -0.1, -0.1]"),
             "35: camera.focal_point_m: expected the focal point at least 1 cm beyond the "
             "scope's tip (position_m) as seen from its port");
}

// The laparoscope's port and optic (scenarios/README.md): absent, the port is 12 mm behind the
// camera's position on its line of sight and the optic looks straight ahead; given, as given.
TEST_F(ScenarioFixture, TheLaparoscopesPortAndOptic) {
  const ScenarioLoadResult plain = load_with(0, "");
  ASSERT_TRUE(plain.ok()) << all(plain);
  const CameraSpec& c = plain.value().camera;
  EXPECT_FALSE(c.port_m.has_value());
  EXPECT_EQ(c.optics_deg, 0.0);
  const Eigen::Vector3d sight = (c.focal_point_m - c.position_m).normalized();
  EXPECT_LT((c.port() - (c.position_m - 0.012 * sight)).norm(), 1e-15);
  const ScenarioLoadResult scope =
      load_with(35, "  view_angle_deg: 30\n  port_m: [0.01, 0.26, 0.37]\n  optics_deg: 30");
  ASSERT_TRUE(scope.ok()) << all(scope);
  EXPECT_EQ(scope.value().camera.port(), Eigen::Vector3d(0.01, 0.26, 0.37));
  EXPECT_EQ(scope.value().camera.optics_deg, 30.0);
}

TEST_F(ScenarioFixture, Bad24_OrganNameNotAnIdentifier) {
  expect_one(load_with(4, "  - name: Big Liver"),
             "4: organs[0].name: expected lower-case letters, digits and underscores starting "
             "with a letter, got 'Big Liver'");
}

TEST_F(ScenarioFixture, Bad25_TaskWithoutCatheter) {
  // Lines 29-30 hold the catheter section; without it the task that needs it is reported (at
  // the task mapping, whose first field is then on line 30).
  expect_one(load_with({{29, ""}, {30, ""}}),
             "30: task.kind: catheter-insertion needs a catheter section");
}

TEST_F(ScenarioFixture, Bad26_MisspelledMaterialField) {
  const ScenarioLoadResult r = load_with(21, "      stiffnes_n_per_m: 150");
  ASSERT_EQ(r.diagnostics().size(), 2U) << all(r);
  EXPECT_EQ(r.diagnostics()[0].to_string(),
            file() +
                ":21: organs[1].material.stiffnes_n_per_m: unknown field (expected one of: "
                "stiffness_n_per_m, damping_n_s_per_m, friction_static, friction_dynamic, "
                "friction_stick_stiffness_n_per_m, friction_slide_stiffness_n_per_m, friction_map, "
                "shading, texture, catheter_friction)");
  EXPECT_EQ(r.diagnostics()[1].to_string(),
            file() + ":21: organs[1].material.stiffness_n_per_m: required field is missing");
}

TEST_F(ScenarioFixture, Bad27_AllowedPathThatDoesNotExist) {
  expect_one(load_with(2, "name: test scene\nallowed_paths: [../assets]"),
             "3: allowed_paths[0]: directory '../assets' not found (looked for " +
                 (dir_.path() / "assets").string() + ")");
}

TEST_F(ScenarioFixture, Bad28_EmptyDocument) {
  const ScenarioLoadResult r = load_scenario(dir_.write("scene/s.yaml", "# nothing here\n"));
  ASSERT_EQ(r.diagnostics().size(), 1U);
  EXPECT_EQ(
      r.diagnostics()[0].to_string(),
      file() + ":1: (document): expected a mapping with version, name and organs, got nothing");
}

TEST_F(ScenarioFixture, Bad29_IncisionInAnOrganThatIsNotADuct) {
  expect_one(load_with(16, "      friction_dynamic: 0.1\n    incision:\n      center_m: [0, 0, 0]"),
             "18: organs[0].incision: an incision is cut in a duct's wall: expected model: "
             "modal-shell");
}

TEST_F(ScenarioFixture, Bad30_IncisionWithoutItsCentre) {
  expect_one(load_with(21, "      stiffness_n_per_m: 150\n    incision:\n      length_m: 0.003"),
             "23: organs[1].incision.center_m: required field is missing");
}

TEST_F(ScenarioFixture, Bad31_CatheterFrictionOutOfRange) {
  expect_one(load_with(16, "      friction_dynamic: 0.1\n      catheter_friction: 3"),
             "17: organs[0].material.catheter_friction: expected a number from 0 to 2, got 3");
}

TEST_F(ScenarioFixture, Bad32_TaskHoldTimeNegative) {
  expect_one(load_with(33, "  target: duct\n  hold_s: -1"),
             "34: task.hold_s: expected a number from 0 to 600 (s), got -1");
}

TEST_F(ScenarioFixture, Bad33_DuctInjuryForceZero) {
  expect_one(load_with(33, "  target: duct\n  duct_injury_force_n: 0"),
             "34: task.duct_injury_force_n: expected a number from 0.01 to 100 (N), got 0");
}

TEST_F(ScenarioFixture, Bad34_ForbiddenOrganUnknown) {
  expect_one(load_with(33, "  target: duct\n  forbidden_organs: [liver, stomach]"),
             "34: task.forbidden_organs[1]: no organ named 'stomach' (expected a name from "
             "organs)");
}

TEST_F(ScenarioFixture, Bad35_ForbiddenOrganIsTheTarget) {
  expect_one(load_with(33, "  target: duct\n  forbidden_organs: [duct]"),
             "34: task.forbidden_organs[0]: 'duct' is the task's target (the instruments work "
             "on it)");
}

TEST_F(ScenarioFixture, Bad36_ForbiddenOrgansNotAList) {
  expect_one(load_with(33, "  target: duct\n  forbidden_organs: liver"),
             "34: task.forbidden_organs: expected a list of organ names, got 'liver'");
}

TEST_F(ScenarioFixture, Bad37_MisspelledTaskField) {
  expect_one(load_with(33, "  target: duct\n  hold_time_s: 3"),
             "34: task.hold_time_s: unknown field (expected one of: kind, target, "
             "insertion_depth_m, hold_s, time_limit_s, duct_injury_force_n, duct_injury_time_s, "
             "duct_squeeze_n, organ_injury_force_n, organ_injury_time_s, drop_grace_s, "
             "out_of_view_grace_s, forbidden_organs, common_bile_duct, expert_entry_slant_deg)");
}

TEST_F(ScenarioFixture, Bad38_OutOfViewGraceTooLong) {
  expect_one(load_with(33, "  target: duct\n  out_of_view_grace_s: 601"),
             "34: task.out_of_view_grace_s: expected a number from 0 to 600 (s), got 601");
}

TEST_F(ScenarioFixture, Bad38b_ExpertSlantOutOfRange) {
  expect_one(load_with(33, "  target: duct\n  expert_entry_slant_deg: 90"),
             "34: task.expert_entry_slant_deg: expected a number from 20 to 70 (degrees), got 90");
}

TEST_F(ScenarioFixture, Bad39_CatheterPortIsNoTrocar) {
  expect_one(load_with(30, "  particles: 32\n  port: nowhere"),
             "31: catheter.port: no trocar named 'nowhere' (expected a name from trocars)");
}

// The duct with an incision at the origin (kBase's line 21 and after it), the catheter from
// left_port (0.245 m from it) towards `aim`, `length` long, and the task's depth.
std::map<int, std::string> catheter_towards_incision(const std::string& aim,
                                                     const std::string& length,
                                                     const std::string& depth = "0.01") {
  return {{21, "      stiffness_n_per_m: 150\n    incision:\n      center_m: [0, 0, 0]"},
          {30, "  particles: 32\n  port: left_port\n  aim_m: " + aim + "\n  length_m: " + length},
          {33, "  target: duct\n  insertion_depth_m: " + depth}};
}

TEST_F(ScenarioFixture, Bad40_CatheterTooShortToReachTheTargetDepth) {
  expect_one(load_with(catheter_towards_incision("[0, 0, -0.1]", "0.1")),
             "35: catheter.length_m: 100 mm cannot reach 10 mm into the incision 245 mm from the "
             "port 'left_port': at least 260 mm (with 5 mm to spare)");
  EXPECT_TRUE(load_with(catheter_towards_incision("[0, 0, -0.1]", "0.26")).ok());
}

TEST_F(ScenarioFixture, Bad41_CatheterLaidWithItsTipAtTheIncision) {
  // A 2 mm target depth lets a catheter 8 mm longer than the way to the incision through the
  // reach check; aimed straight at the incision it would start with its tip 8 mm past it.
  expect_one(load_with(catheter_towards_incision("[0, 0, 0]", "0.2529", "0.002")),
             "34: catheter.aim_m: lays the catheter's tip 8 mm from the incision: it must start "
             "outside the duct, at least 10 mm away");
}

TEST_F(ScenarioFixture, Bad42_CommonBileDuctIsNoOrgan) {
  expect_one(load_with(33, "  target: duct\n  common_bile_duct: cbd"),
             "34: task.common_bile_duct: no organ named 'cbd' (expected a name from organs)");
}

TEST_F(ScenarioFixture, Bad43_CommonBileDuctIsTheTarget) {
  expect_one(load_with(33, "  target: duct\n  common_bile_duct: duct"),
             "34: task.common_bile_duct: 'duct' is the task's target (the catheter goes into it)");
}

// kBase's camera (line 35), then a proficiency section from line 36: source on 37, the
// metrics' first on 39.
std::map<int, std::string> with_proficiency(const std::string& metrics) {
  return {{35, "  view_angle_deg: 30\nproficiency:\n  source: planned expert runs\n  metrics:\n" +
                   metrics}};
}

TEST_F(ScenarioFixture, TheProficiencyBenchmarksAreRead) {
  const ScenarioLoadResult r = load_with(
      with_proficiency("    completion_time_s: {mean: 16, sd: 1.5}\n"
                       "    max_force_liver_n: {mean: 0.3, sd: 0.1}\n"
                       "    mean_force_duct_n: {mean: 0.2, sd: 0.05, better: lower}\n"
                       "    max_insertion_depth_m: {mean: 0.013, sd: 0.001, better: higher}"));
  ASSERT_TRUE(r.ok()) << all(r);
  ASSERT_TRUE(r.value().proficiency.has_value());
  const ProficiencySpec& p = *r.value().proficiency;
  EXPECT_EQ(p.source, "planned expert runs");
  ASSERT_EQ(p.metrics.size(), 4U);
  EXPECT_EQ(p.metrics[0].metric, "completion_time_s");
  EXPECT_DOUBLE_EQ(p.metrics[0].mean, 16.0);
  EXPECT_DOUBLE_EQ(p.metrics[0].sd, 1.5);
  EXPECT_FALSE(p.metrics[0].higher_is_better);
  EXPECT_EQ(p.metrics[1].metric, "max_force_liver_n");  // an organ of the scene, by its name
  EXPECT_EQ(p.metrics[1].line, 40);
  EXPECT_TRUE(p.metrics[3].higher_is_better);
  EXPECT_FALSE(load_with(0, "").value().proficiency.has_value());
}

TEST_F(ScenarioFixture, Bad44_ProficiencyNamesNoMetricOfTheScene) {
  expect_one(load_with(with_proficiency("    max_force_spleen_n: {mean: 1, sd: 0.1}")),
             "39: proficiency.metrics.max_force_spleen_n: not a training metric of this scenario "
             "(docs/metrics.md lists them; per-organ ones are named max_force_<organ>_n, with "
             "<organ> duct or an organ's name in snake_case)");
}

TEST_F(ScenarioFixture, Bad45_ProficiencyBenchmarkOutOfRange) {
  expect_one(load_with(with_proficiency("    catheter_drops: {mean: 0, sd: -1}")),
             "39: proficiency.metrics.catheter_drops.sd: expected a number of 0 or more, got -1");
  expect_one(load_with(with_proficiency("    catheter_drops: {mean: .nan, sd: 1}")),
             "39: proficiency.metrics.catheter_drops.mean: expected a number in the metric's unit, "
             "got '.nan'");
  expect_one(load_with(with_proficiency("    catheter_drops: {mean: 0, sd: 1, better: more}")),
             "39: proficiency.metrics.catheter_drops.better: expected lower or higher, got 'more'");
  expect_one(load_with(with_proficiency("    catheter_drops: {mean: 0}")),
             "39: proficiency.metrics.catheter_drops.sd: required field is missing");
}

TEST_F(ScenarioFixture, Bad46_ProficiencyWithoutASourceOrTwice) {
  expect_one(load_with({{35,
                         "  view_angle_deg: 30\nproficiency:\n  metrics:\n"
                         "    catheter_drops: {mean: 0, sd: 1}"}}),
             "37: proficiency.source: required field is missing");
  expect_one(load_with(with_proficiency("    catheter_drops: {mean: 0, sd: 1}\n"
                                        "    catheter_drops: {mean: 1, sd: 1}")),
             "40: proficiency.metrics.catheter_drops: is given twice");
}

// The scenario chooser shows how hard each patient is: one of four words, or nothing said.
TEST_F(ScenarioFixture, DifficultyIsOneOfFourWordsOrUnsaid) {
  EXPECT_EQ(load_with(0, "").value().difficulty, "");
  for (const char* word : {"introductory", "easy", "moderate", "hard"}) {
    const ScenarioLoadResult r = load_with(2, std::string("name: test scene\ndifficulty: ") + word);
    ASSERT_TRUE(r.ok()) << all(r);
    EXPECT_EQ(r.value().difficulty, word);
  }
}

TEST_F(ScenarioFixture, Bad47_DifficultyNotOneOfTheFourWords) {
  expect_one(load_with(2, "name: test scene\ndifficulty: tricky"),
             "3: difficulty: expected introductory, easy, moderate or hard, got 'tricky'");
}

TEST_F(ScenarioFixture, TheTasksThresholdsAreReadWithTheirDefaults) {
  const ScenarioLoadResult defaults = load_with(0, "");
  ASSERT_TRUE(defaults.ok()) << all(defaults);
  const TaskSpec& d = *defaults.value().task;
  EXPECT_DOUBLE_EQ(d.hold_s, 3.0);
  EXPECT_DOUBLE_EQ(d.duct_injury_force_n, 2.0);
  EXPECT_DOUBLE_EQ(d.duct_injury_time_s, 1.0);
  EXPECT_DOUBLE_EQ(d.duct_squeeze_n, 5.0);
  EXPECT_DOUBLE_EQ(d.organ_injury_force_n, 5.0);
  EXPECT_DOUBLE_EQ(d.organ_injury_time_s, 2.0);
  EXPECT_DOUBLE_EQ(d.drop_grace_s, 1.0);
  EXPECT_DOUBLE_EQ(d.out_of_view_grace_s, 3.0);
  EXPECT_TRUE(d.forbidden_organs.empty());
  EXPECT_FALSE(d.expert_entry_slant_deg.has_value());
  EXPECT_EQ(d.line, 32);
  const ScenarioLoadResult r =
      load_with(33,
                "  target: duct\n  insertion_depth_m: 0.015\n  hold_s: 5\n  time_limit_s: 300\n"
                "  duct_injury_force_n: 1.5\n  duct_injury_time_s: 0.5\n  duct_squeeze_n: 4\n"
                "  organ_injury_force_n: 6\n  organ_injury_time_s: 3\n  drop_grace_s: 2\n"
                "  out_of_view_grace_s: 10\n  forbidden_organs: [liver]\n"
                "  expert_entry_slant_deg: 42.5");
  ASSERT_TRUE(r.ok()) << all(r);
  const TaskSpec& t = *r.value().task;
  EXPECT_DOUBLE_EQ(t.insertion_depth_m, 0.015);
  EXPECT_DOUBLE_EQ(t.hold_s, 5.0);
  EXPECT_DOUBLE_EQ(t.time_limit_s, 300.0);
  EXPECT_DOUBLE_EQ(t.duct_injury_force_n, 1.5);
  EXPECT_DOUBLE_EQ(t.duct_injury_time_s, 0.5);
  EXPECT_DOUBLE_EQ(t.duct_squeeze_n, 4.0);
  EXPECT_DOUBLE_EQ(t.organ_injury_force_n, 6.0);
  EXPECT_DOUBLE_EQ(t.organ_injury_time_s, 3.0);
  EXPECT_DOUBLE_EQ(t.drop_grace_s, 2.0);
  EXPECT_DOUBLE_EQ(t.out_of_view_grace_s, 10.0);
  EXPECT_EQ(t.forbidden_organs, std::vector<std::string>{"liver"});
  EXPECT_EQ(t.expert_entry_slant_deg, 42.5);
}

TEST_F(ScenarioFixture, AnIncisionInTheDuctIsRead) {
  const ScenarioLoadResult r =
      load_with(21,
                "      stiffness_n_per_m: 150\n      catheter_friction: 0.2\n    incision:\n"
                "      center_m: [0.01, 0.02, 0.03]\n      width_m: 0.0025");
  ASSERT_TRUE(r.ok()) << all(r);
  const OrganSpec& duct = r.value().organs[1];
  EXPECT_TRUE(duct.incision.present);
  EXPECT_TRUE(duct.incision.center_m.isApprox(Eigen::Vector3d(0.01, 0.02, 0.03)));
  EXPECT_DOUBLE_EQ(duct.incision.length_m, 0.003);  // the default
  EXPECT_DOUBLE_EQ(duct.incision.width_m, 0.0025);
  EXPECT_DOUBLE_EQ(duct.material.catheter_friction, 0.2);
  EXPECT_FALSE(r.value().organs[0].incision.present);
}

TEST_F(ScenarioFixture, ManyProblemsAreAllReported) {
  const ScenarioLoadResult r = load_with(13, "      stiffness_n_per_m: -1\n      color: red");
  EXPECT_EQ(r.diagnostics().size(), 2U) << all(r);
}

TEST_F(ScenarioFixture, AllowedPathsLetAFileOutsideTheFolderIn) {
  dir_.write("assets/outside.obj", kTetraObj);
  std::string text = kBase;
  text.replace(text.find("    mesh: meshes/tetra.obj\n    model"), 26,
               "    mesh: ../assets/outside.obj");
  const ScenarioLoadResult refused = load_scenario(dir_.write("scene/s.yaml", text));
  ASSERT_EQ(refused.diagnostics().size(), 1U) << all(refused);
  EXPECT_NE(refused.diagnostics()[0].message.find("leaves the scenario's folder"),
            std::string::npos);
  text.replace(text.find("name: test scene"), 16, "name: test scene\nallowed_paths: [../assets]");
  const ScenarioLoadResult allowed = load_scenario(dir_.write("scene/s.yaml", text));
  EXPECT_TRUE(allowed.ok()) << all(allowed);
  EXPECT_TRUE(std::filesystem::equivalent(allowed.value().organs[1].mesh,
                                          dir_.path() / "assets/outside.obj"));
}

TEST_F(ScenarioFixture, CallerAllowedPathsWorkToo) {
  dir_.write("assets/outside.obj", kTetraObj);
  std::string text = kBase;
  text.replace(text.find("    mesh: meshes/tetra.obj\n    model"), 26,
               "    mesh: ../assets/outside.obj");
  const auto f = dir_.write("scene/s.yaml", text);
  EXPECT_FALSE(load_scenario(f).ok());
  ScenarioLoadSettings settings;
  settings.allowed_paths.push_back(dir_.path() / "assets");
  EXPECT_TRUE(load_scenario(f, settings).ok());
}

TEST(ScenarioLoader, UnreadableFile) {
  const ScenarioLoadResult r = load_scenario("/nonexistent/dir/s.yaml");
  ASSERT_EQ(r.diagnostics().size(), 1U);
  EXPECT_EQ(r.diagnostics()[0].to_string(),
            "/nonexistent/dir/s.yaml: not found (expected a YAML scenario file)");
}

TEST(ScenarioLoader, IntroductoryScenarioIsValid) {
  const ScenarioLoadResult r = load_scenario(test::source_dir() / "scenarios/introductory.yaml");
  for (const auto& p : r.diagnostics()) ADD_FAILURE() << p.to_string();
  EXPECT_GE(r.value().organs.size(), 3U);
  EXPECT_EQ(r.value().tools.size(), 2U);
}

}  // namespace
}  // namespace lap::sim
