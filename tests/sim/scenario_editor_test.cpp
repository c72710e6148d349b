// The scenario editor (sim/authoring/scenario_editor.h): tuned material values written back into
// a commented scenario change only their own lines, load back with the scenario loader as the
// new values, and what cannot be edited safely is refused with its file and line.

#include "sim/authoring/scenario_editor.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "sim/setup/scenario_loader.h"
#include "tests/test_support.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;

using test::lines_of;
using test::read_file;

// The 1-based number of the first line containing `needle` after the line containing `after`.
int line_of(const std::string& text, const std::string& after, const std::string& needle) {
  const std::vector<std::string> lines = lines_of(text);
  bool seen = after.empty();
  for (size_t i = 0; i < lines.size(); ++i) {
    if (!seen && lines[i].find(after) != std::string::npos) seen = true;
    if (seen && lines[i].find(needle) != std::string::npos) return static_cast<int>(i) + 1;
  }
  return -1;
}

const OrganSpec& organ(const Scenario& s, const std::string& name) {
  for (const OrganSpec& o : s.organs) {
    if (o.name == name) return o;
  }
  throw std::runtime_error("no organ " + name);
}

fs::path introductory_scenario() { return test::source_dir() / "scenarios/introductory.yaml"; }

TEST(ScenarioEditor, ChangesOnlyTheEditedLinesOfACommentedScenario) {
  const std::string before = read_file(introductory_scenario());
  const std::vector<MaterialEdit> edits = {
      {"liver", "stiffness_n_per_m", 144.0},
      {"gallbladder", "texture.amplitude_m", 0.00025},
      {"cystic_duct", "friction_dynamic", 0.05},
  };
  const Result<std::string> after = edit_scenario_materials(before, introductory_scenario(), edits);
  ASSERT_TRUE(after.ok()) << after.message();

  const std::vector<std::string> a = lines_of(before);
  const std::vector<std::string> b = lines_of(after.value());
  ASSERT_EQ(a.size(), b.size());
  std::vector<int> changed;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i] != b[i]) changed.push_back(static_cast<int>(i) + 1);
  }
  const std::vector<int> expected = {
      line_of(before, "name: liver", "stiffness_n_per_m:"),
      line_of(before, "name: gallbladder", "amplitude_m:"),
      line_of(before, "name: cystic_duct", "friction_dynamic:"),
  };
  EXPECT_EQ(changed, expected);
  // The key, its indentation and its comment (in the same column) stay.
  const auto at = [](const std::vector<std::string>& l, int n) {
    return l[static_cast<size_t>(n - 1)];
  };
  EXPECT_EQ(at(b, expected[0]), "      stiffness_n_per_m: 144");
  EXPECT_EQ(at(a, expected[2]), "      friction_dynamic: 0.08        # estimate");
  EXPECT_EQ(at(b, expected[2]), "      friction_dynamic: 0.05        # estimate");
  EXPECT_EQ(at(b, expected[1]), "        amplitude_m: 0.00025");
  // A longer value pushes a comment only as far as it must.
  const std::vector<MaterialEdit> longer = {{"cystic_duct", "friction_dynamic", 0.0512345678}};
  const Result<std::string> pushed =
      edit_scenario_materials(before, introductory_scenario(), longer);
  ASSERT_TRUE(pushed.ok()) << pushed.message();
  EXPECT_EQ(at(lines_of(pushed.value()), expected[2]),
            "      friction_dynamic: 0.0512345678 # estimate");

  // It loads, with the new values and every other one as before.
  const ScenarioLoadResult old_s = parse_scenario(before, introductory_scenario());
  const ScenarioLoadResult new_s = parse_scenario(after.value(), introductory_scenario());
  ASSERT_TRUE(old_s.ok()) << old_s.message();
  ASSERT_TRUE(new_s.ok()) << new_s.message();
  EXPECT_EQ(organ(new_s.value(), "liver").material.stiffness_n_per_m, 144.0);
  EXPECT_EQ(organ(new_s.value(), "gallbladder").material.texture.amplitude_m, 0.00025);
  EXPECT_EQ(organ(new_s.value(), "cystic_duct").material.friction_dynamic, 0.05);
  EXPECT_EQ(organ(new_s.value(), "liver").material.damping_n_s_per_m,
            organ(old_s.value(), "liver").material.damping_n_s_per_m);
  EXPECT_EQ(organ(new_s.value(), "gallbladder").material.stiffness_n_per_m,
            organ(old_s.value(), "gallbladder").material.stiffness_n_per_m);
  EXPECT_TRUE(organ(new_s.value(), "liver").material.shading.enabled);
}

TEST(ScenarioEditor, NumbersReadBackAsTheSameDouble) {
  for (const double x : {72.0, 0.1, 1.0 / 3.0, 1e-4, 2.5e-7, 123456.789}) {
    EXPECT_EQ(std::stod(yaml_value_text(x)), x) << yaml_value_text(x);
  }
  EXPECT_EQ(yaml_value_text(true), "true");
  EXPECT_EQ(yaml_value_text(false), "false");
}

TEST(ScenarioEditor, AddsAMissingFieldAtTheEndOfTheOrgansMaterial) {
  const std::string before = read_file(introductory_scenario());
  const std::vector<MaterialEdit> edits = {{"cystic_duct", "shading.enabled", true}};
  const Result<std::string> after = edit_scenario_materials(before, introductory_scenario(), edits);
  ASSERT_TRUE(after.ok()) << after.message();
  const std::vector<std::string> a = lines_of(before);
  const std::vector<std::string> b = lines_of(after.value());
  ASSERT_EQ(b.size(), a.size() + 2);
  // Inserted right after the duct's last material line, at the material's indentation.
  const int last = line_of(before, "name: cystic_duct", "catheter_friction:");
  for (int i = 0; i < last; ++i) EXPECT_EQ(a[static_cast<size_t>(i)], b[static_cast<size_t>(i)]);
  EXPECT_EQ(b[static_cast<size_t>(last)], "      shading:");
  EXPECT_EQ(b[static_cast<size_t>(last + 1)], "        enabled: true");
  for (size_t i = static_cast<size_t>(last); i < a.size(); ++i) EXPECT_EQ(a[i], b[i + 2]);

  const ScenarioLoadResult s = parse_scenario(after.value(), introductory_scenario());
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_TRUE(organ(s.value(), "cystic_duct").material.shading.enabled);
}

// An inline scenario's organs with the given text in place of the material block.
std::string scenario_with(const std::string& organs) {
  return "version: 1\nname: t\norgans:\n" + organs +
         "tools:\n  - name: left\n    side: left\n    kind: probe\n";
}

TEST(ScenarioEditor, AddsAMaterialAndAnItemsKeysOnTheirOwnLine) {
  const std::string text = scenario_with(
      "  -\n    name: a   # dash alone on its line\n    mesh: a.obj\n"
      "  - name: 'b'\n    mesh: b.obj\n    material:\n      stiffness_n_per_m: 1\n");
  const std::vector<MaterialEdit> edits = {{"a", "damping_n_s_per_m", 0.5},
                                           {"b", "stiffness_n_per_m", 2.0}};
  const Result<std::string> after = edit_scenario_materials(text, "t.yaml", edits);
  ASSERT_TRUE(after.ok()) << after.message();
  EXPECT_EQ(after.value(),
            scenario_with("  -\n    name: a   # dash alone on its line\n    mesh: a.obj\n"
                          "    material:\n      damping_n_s_per_m: 0.5\n"
                          "  - name: 'b'\n    mesh: b.obj\n    material:\n"
                          "      stiffness_n_per_m: 2\n"));
}

TEST(ScenarioEditor, KeepsWindowsLineEndingsAndAMissingFinalNewline) {
  const std::string text =
      "organs:\r\n  - name: a\r\n    material:\r\n      stiffness_n_per_m: 1 # k\r\n"
      "      damping_n_s_per_m: 0";
  const std::vector<MaterialEdit> edits = {{"a", "stiffness_n_per_m", 30.0},
                                           {"a", "damping_n_s_per_m", 0.25}};
  const Result<std::string> after = edit_scenario_materials(text, "t.yaml", edits);
  ASSERT_TRUE(after.ok()) << after.message();
  EXPECT_EQ(after.value(),
            "organs:\r\n  - name: a\r\n    material:\r\n      stiffness_n_per_m: 30 # k\r\n"
            "      damping_n_s_per_m: 0.25");
}

// The shipped scenarios write the liver's shading as a one-line flow map: an entry is set in
// place and a missing one added before the brace, the comment kept in its column.
TEST(ScenarioEditor, EditsAOneLineFlowMapInPlace) {
  const std::string before = read_file(introductory_scenario());
  const std::vector<MaterialEdit> edits = {{"liver", "shading.enabled", false},
                                           {"liver", "shading.crease_angle_deg", 30.0}};
  const Result<std::string> r = edit_scenario_materials(before, introductory_scenario(), edits);
  ASSERT_TRUE(r.ok()) << r.message();
  const std::string old_line = "      shading: {enabled: true, crease_angle_deg: 40}   # smooth";
  const std::string new_line = "      shading: {enabled: false, crease_angle_deg: 30}  # smooth";
  ASSERT_NE(before.find(old_line), std::string::npos);
  std::string expected = before;
  expected.replace(expected.find(old_line), old_line.size(), new_line);
  EXPECT_EQ(r.value(), expected);

  const std::string flow = scenario_with(
      "  - name: a\n    mesh: a.obj\n    material: {stiffness_n_per_m: 1}\n"
      "  - name: b\n    mesh: b.obj\n    material:\n      shading: {}\n");
  const std::vector<MaterialEdit> k = {{"a", "stiffness_n_per_m", 2.0},
                                       {"a", "damping_n_s_per_m", 0.5},
                                       {"b", "shading.enabled", true}};
  const Result<std::string> r2 = edit_scenario_materials(flow, "t.yaml", k);
  ASSERT_TRUE(r2.ok()) << r2.message();
  EXPECT_EQ(r2.value(),
            scenario_with("  - name: a\n    mesh: a.obj\n"
                          "    material: {stiffness_n_per_m: 2, damping_n_s_per_m: 0.5}\n"
                          "  - name: b\n    mesh: b.obj\n    material:\n"
                          "      shading: {enabled: true}\n"));
}

// What a text edit cannot do safely in a flow map is refused with its line: nested maps, quotes,
// a map over several lines.
TEST(ScenarioEditor, RefusesAFlowMapItCannotEditWithItsLine) {
  const std::string nested =
      scenario_with("  - name: a\n    mesh: a.obj\n    material: {shading: {enabled: true}}\n");
  const std::vector<MaterialEdit> k = {{"a", "shading.enabled", false}};
  const Result<std::string> r = edit_scenario_materials(nested, "t.yaml", k);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.diagnostics()[0].to_string().substr(0, 35), "t.yaml:6: organs[0].material: writt");

  const std::string quoted = scenario_with(
      "  - name: a\n    mesh: a.obj\n    material:\n      shading: {'enabled': true}\n");
  const Result<std::string> r2 = edit_scenario_materials(quoted, "t.yaml", k);
  ASSERT_FALSE(r2.ok());
  EXPECT_EQ(r2.diagnostics()[0].line, 7);
  EXPECT_EQ(r2.diagnostics()[0].field, "organs[0].material.shading.enabled");
  EXPECT_NE(r2.message().find("a nested, quoted or tagged flow map"), std::string::npos);

  const std::string multi = scenario_with(
      "  - name: a\n    mesh: a.obj\n    material:\n      shading: {enabled: true,\n"
      "        crease_angle_deg: 40}\n");
  const Result<std::string> r3 = edit_scenario_materials(multi, "t.yaml", k);
  ASSERT_FALSE(r3.ok());
  EXPECT_NE(r3.message().find("over several lines"), std::string::npos) << r3.message();

  // `a:1` is one plain key in YAML, `a` a key without a value: not edited by guesswork.
  for (const char* map : {"{enabled:true}", "{enabled}", "{crease_angle_deg: 40, enabled}"}) {
    const std::string odd = scenario_with(
        "  - name: a\n    mesh: a.obj\n    material:\n      shading: " + std::string(map) + "\n");
    const Result<std::string> r4 = edit_scenario_materials(odd, "t.yaml", k);
    ASSERT_FALSE(r4.ok()) << map;
    EXPECT_NE(r4.message().find("an entry that is not `key: value`"), std::string::npos)
        << r4.message();
  }
  // A trailing comma is YAML's too: the added entry follows it once.
  const std::string trailing = scenario_with(
      "  - name: a\n    mesh: a.obj\n    material:\n      shading: {crease_angle_deg: 40, }\n");
  const Result<std::string> r5 = edit_scenario_materials(trailing, "t.yaml", k);
  ASSERT_TRUE(r5.ok()) << r5.message();
  EXPECT_NE(r5.value().find("shading: {crease_angle_deg: 40, enabled: false }\n"),
            std::string::npos)
      << r5.value();
}

TEST(ScenarioEditor, RefusesAnchorsAliasesAndMergeKeys) {
  const std::string anchored = scenario_with(
      "  - name: a\n    mesh: a.obj\n    material: &soft\n      stiffness_n_per_m: 1\n"
      "  - name: b\n    mesh: b.obj\n    material: *soft\n");
  for (const char* name : {"a", "b"}) {
    const std::vector<MaterialEdit> edits = {{name, "stiffness_n_per_m", 2.0}};
    const Result<std::string> r = edit_scenario_materials(anchored, "t.yaml", edits);
    ASSERT_FALSE(r.ok()) << name;
    EXPECT_EQ(r.diagnostics()[0].line, std::string(name) == "a" ? 6 : 10);
    EXPECT_NE(r.message().find("anchor"), std::string::npos) << r.message();
  }
  const std::string merged = scenario_with(
      "  - name: a\n    mesh: a.obj\n    material:\n      <<: {damping_n_s_per_m: 1}\n"
      "      stiffness_n_per_m: 1\n");
  const std::vector<MaterialEdit> edits = {{"a", "stiffness_n_per_m", 2.0}};
  const Result<std::string> r = edit_scenario_materials(merged, "t.yaml", edits);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.diagnostics()[0].line, 7);
}

TEST(ScenarioEditor, RefusesAnUnknownOrganAndABlockScalar) {
  const std::string text =
      scenario_with("  - name: a\n    material:\n      stiffness_n_per_m: >\n        1\n");
  const std::vector<MaterialEdit> unknown = {{"nope", "stiffness_n_per_m", 2.0}};
  const Result<std::string> r = edit_scenario_materials(text, "t.yaml", unknown);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("no organ named 'nope'"), std::string::npos) << r.message();
  const std::vector<MaterialEdit> block = {{"a", "stiffness_n_per_m", 2.0}};
  const Result<std::string> r2 = edit_scenario_materials(text, "t.yaml", block);
  ASSERT_FALSE(r2.ok());
  EXPECT_EQ(r2.diagnostics()[0].line, 6);
}

// A copy of the introductory scenario in a folder of its own whose assets/ is the project's.
struct ScenarioCopy {
  test::TempDir dir;
  fs::path file;
  ScenarioCopy() {
    fs::create_directories(dir.path() / "scenarios");
    fs::create_directory_symlink(test::source_dir() / "assets", dir.path() / "assets");
    file = dir.path() / "scenarios/introductory.yaml";
    fs::copy_file(introductory_scenario(), file);
  }
};

TEST(ScenarioEditor, SavesTheFileAndRefusesValuesThatWouldNotLoad) {
  const ScenarioCopy copy;
  const std::string before = read_file(copy.file);
  ASSERT_TRUE(load_scenario(copy.file).ok()) << load_scenario(copy.file).message();
  const std::vector<MaterialEdit> edits = {{"gallbladder", "stiffness_n_per_m", 400.0}};
  const Status saved = save_scenario_materials(copy.file, edits);
  ASSERT_TRUE(saved.ok()) << saved.message();
  const ScenarioLoadResult s = load_scenario(copy.file);
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(organ(s.value(), "gallbladder").material.stiffness_n_per_m, 400.0);
  EXPECT_FALSE(fs::exists(copy.file.string() + ".saving"));

  // Shading on the textured gallbladder breaks §6.6: refused, the file left as it was.
  const std::string good = read_file(copy.file);
  EXPECT_NE(good, before);
  const std::vector<MaterialEdit> bad = {{"gallbladder", "shading.enabled", true}};
  const Status refused = save_scenario_materials(copy.file, bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("not saved"), std::string::npos) << refused.message();
  EXPECT_EQ(read_file(copy.file), good);
}

}  // namespace
}  // namespace lap::sim
