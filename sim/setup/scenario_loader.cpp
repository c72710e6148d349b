#include "sim/setup/scenario_loader.h"

#include <algorithm>
#include <cstdio>
#include <set>
#include <utility>

#include "core/bounded_file.h"
#include "sim/setup/content_digest.h"
#include "sim/setup/metric_names.h"
#include "sim/setup/scenario_files.h"
#include "sim/setup/scenario_material.h"
#include "sim/setup/yaml_fields.h"

namespace lap::sim {
namespace fs = std::filesystem;

namespace {

// The scenario schema, one stage per section. Generic field reading and its messages live in
// YamlFields, file references in ScenarioFiles, materials in scenario_material.cpp.
class ScenarioParser {
 public:
  ScenarioParser(YamlFields& fields, const fs::path& file, const ScenarioLoadSettings& settings,
                 Scenario& scenario)
      : fields_(fields), files_(fields, file, settings, scenario.allowed_paths), s_(scenario) {}

  void parse(const YAML::Node& root) {
    if (!root.IsMap()) {
      fields_.problem(
          std::max(1, yaml_line(root)), "(document)",
          "expected a mapping with version, name and organs, got " + describe_yaml(root));
      return;
    }
    fields_.expect_map(root, "",
                       {"version", "name", "description", "difficulty", "allowed_paths", "camera",
                        "organs", "trocars", "tools", "catheter", "task", "proficiency"});
    parse_header(root);
    // allowed_paths first: the file references below are checked against it.
    if (root["allowed_paths"]) files_.read_allowed_paths(root["allowed_paths"]);
    if (root["camera"]) parse_camera(root["camera"]);
    if (fields_.require(root, "organs", "")) parse_organs(root["organs"]);
    // Tools name trocars, and the task names an organ and needs the catheter: read them after.
    if (root["trocars"]) parse_trocars(root["trocars"]);
    if (root["tools"]) parse_tools(root["tools"]);
    if (root["catheter"]) parse_catheter(root["catheter"]);
    if (root["task"]) parse_task(root["task"]);
    if (root["catheter"] && root["task"]) check_catheter_reach(root["catheter"]);
    if (root["proficiency"]) parse_proficiency(root["proficiency"]);
  }

 private:
  void parse_header(const YAML::Node& root) {
    if (fields_.require(root, "version", "")) {
      if (auto v = fields_.integer(root["version"], "version", 1, 1)) s_.version = *v;
    }
    if (fields_.require(root, "name", "")) {
      if (auto v = fields_.string(root["name"], "name")) s_.name = *v;
    }
    if (root["description"]) {
      if (auto v = fields_.string(root["description"], "description")) s_.description = *v;
    }
    if (root["difficulty"]) {
      if (auto v = fields_.word(root["difficulty"], "difficulty",
                                {"introductory", "easy", "moderate", "hard"})) {
        s_.difficulty = *v;
      }
    }
  }

  void parse_camera(const YAML::Node& n) {
    CameraSpec& c = s_.camera;
    if (!fields_.expect_map(
            n, "camera",
            {"position_m", "focal_point_m", "view_up", "view_angle_deg", "port_m", "optics_deg"})) {
      return;
    }
    c.line = yaml_line(n);
    if (n["position_m"]) {
      if (auto v = fields_.vec3(n["position_m"], "camera.position_m")) c.position_m = *v;
    }
    if (n["focal_point_m"]) {
      if (auto v = fields_.vec3(n["focal_point_m"], "camera.focal_point_m")) c.focal_point_m = *v;
    }
    if (n["view_up"]) {
      if (auto v = fields_.direction(n["view_up"], "camera.view_up")) c.view_up = *v;
    }
    fields_.optional_number(n, "view_angle_deg", "camera", c.view_angle_deg, 1.0, 120.0,
                            "from 1 to 120 (degrees)");
    if ((c.position_m - c.focal_point_m).norm() < 1e-6) {
      fields_.problem(n, "camera", "position_m and focal_point_m must differ");
    }
    if (n["port_m"]) {
      if (auto v = fields_.vec3(n["port_m"], "camera.port_m")) {
        c.port_m = *v;
        // The scope's tip is inside, past its port: a tip on the port leaves no shaft to pivot.
        if ((c.position_m - *v).norm() < 1e-3) {
          fields_.problem(n["port_m"], "camera.port_m",
                          "expected the port at least 1 mm from position_m (the scope's tip, "
                          "inside the abdomen)");
        }
      }
    }
    fields_.optional_number(n, "optics_deg", "camera", c.optics_deg, 0.0, 70.0,
                            "from 0 to 70 (degrees; laparoscopes are 0, 30, 45 or 70)");
    // The scope looks from its tip: what it looks at lies beyond it, not behind its port.
    const Eigen::Vector3d port = c.port();
    if ((c.position_m - port).norm() >= 1e-3 &&
        (c.focal_point_m - port).norm() <= (c.position_m - port).norm() + 0.01) {
      fields_.problem(n, "camera.focal_point_m",
                      "expected the focal point at least 1 cm beyond the scope's tip (position_m) "
                      "as seen from its port");
    }
  }

  void parse_organs(const YAML::Node& n) {
    if (!n.IsSequence() || n.size() == 0) {
      fields_.problem(n, "organs", "expected a non-empty list of organs, got " + describe_yaml(n));
      return;
    }
    std::set<std::string> names;
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string f = "organs[" + std::to_string(i) + "]";
      const YAML::Node o = n[i];
      if (!fields_.expect_map(o, f,
                              {"name", "mesh", "scale", "repair", "transform", "color", "model",
                               "material", "incision", "dynamics"})) {
        continue;
      }
      OrganSpec organ;
      organ.line = yaml_line(o);
      if (fields_.require(o, "name", f)) parse_organ_name(o["name"], f + ".name", names, organ);
      if (fields_.require(o, "mesh", f)) {
        if (auto p = files_.file(o["mesh"], f + ".mesh")) organ.mesh = *p;
      }
      if (o["scale"]) {
        if (auto v = fields_.positive(o["scale"], f + ".scale")) organ.scale = *v;
      }
      if (o["repair"]) {
        if (auto v = fields_.boolean(o["repair"], f + ".repair")) organ.repair = *v;
      }
      if (o["transform"]) parse_organ_transform(o["transform"], f + ".transform", organ);
      parse_organ_looks(o, f, organ);
      if (fields_.require(o, "material", f)) {
        parse_material(fields_, files_, o["material"], f + ".material", organ.material);
      }
      if (o["incision"]) parse_incision(o["incision"], f + ".incision", organ);
      if (o["dynamics"]) parse_dynamics(o["dynamics"], f + ".dynamics", organ);
      s_.organs.push_back(std::move(organ));
    }
  }

  // The ductotomy: where (on the wall: checked against the duct's shell when it is built) and
  // how large; only a modal-shell duct has a wall to cut.
  void parse_incision(const YAML::Node& n, const std::string& f, OrganSpec& organ) {
    if (!fields_.expect_map(n, f, {"center_m", "length_m", "width_m"})) return;
    IncisionSpec& c = organ.incision;
    c.present = true;
    c.line = yaml_line(n);
    if (organ.model != models::ModelKind::kModalShell) {
      fields_.problem(n, f, "an incision is cut in a duct's wall: expected model: modal-shell");
    }
    if (fields_.require(n, "center_m", f)) {
      if (auto v = fields_.vec3(n["center_m"], f + ".center_m")) c.center_m = *v;
    }
    fields_.optional_number(n, "length_m", f, c.length_m, 1e-4, 0.05, "from 1e-4 to 0.05 (m)");
    fields_.optional_number(n, "width_m", f, c.width_m, 1e-4, 0.05, "from 1e-4 to 0.05 (m)");
  }

  // A rigid organ's mass and drag make it a free body (§6.4); only a rigid organ moves whole.
  void parse_dynamics(const YAML::Node& n, const std::string& f, OrganSpec& organ) {
    if (!fields_.expect_map(n, f, {"mass_kg", "linear_damping_per_s", "angular_damping_per_s"})) {
      return;
    }
    DynamicsSpec& d = organ.dynamics;
    d.present = true;
    d.line = yaml_line(n);
    if (organ.model != models::ModelKind::kRigid) {
      fields_.problem(n, f, "only a rigid organ moves as a body: expected model: rigid");
    }
    if (fields_.require(n, "mass_kg", f)) {
      fields_.optional_number(n, "mass_kg", f, d.mass_kg, 1e-4, 100.0, "from 1e-4 to 100 (kg)");
    }
    fields_.optional_number(n, "linear_damping_per_s", f, d.linear_damping_per_s, 0.0, 1000.0,
                            "from 0 to 1000 (1/s)");
    fields_.optional_number(n, "angular_damping_per_s", f, d.angular_damping_per_s, 0.0, 1000.0,
                            "from 0 to 1000 (1/s)");
  }

  // The name is kept even when it breaks a rule, so a task naming it gets no second problem.
  void parse_organ_name(const YAML::Node& n, const std::string& f, std::set<std::string>& names,
                        OrganSpec& organ) {
    const std::optional<std::string> v = fields_.string(n, f);
    if (!v) return;
    // [a-z][a-z0-9_]*, by hand: std::regex_match recurses once per character, and a name of a
    // few hundred kilobytes overflowed the stack.
    const auto lower = [](char c) { return c >= 'a' && c <= 'z'; };
    const bool well_formed = lower(v->front()) && std::all_of(v->begin(), v->end(), [&](char c) {
                               return lower(c) || (c >= '0' && c <= '9') || c == '_';
                             });
    if (!well_formed) {
      fields_.problem(n, f,
                      "expected lower-case letters, digits and underscores starting with a "
                      "letter, got " +
                          quote_excerpt(*v));
    } else if (!names.insert(*v).second) {
      fields_.problem(n, f,
                      "duplicate organ name " + quote_excerpt(*v) + " (names must be unique)");
    }
    organ.name = *v;
  }

  void parse_organ_transform(const YAML::Node& n, const std::string& f, OrganSpec& organ) {
    if (!fields_.expect_map(n, f, {"translation_m", "rotation_deg"})) return;
    if (n["translation_m"]) {
      if (auto v = fields_.vec3(n["translation_m"], f + ".translation_m")) organ.translation_m = *v;
    }
    if (n["rotation_deg"]) {
      if (auto v = fields_.vec3(n["rotation_deg"], f + ".rotation_deg")) organ.rotation_deg = *v;
    }
  }

  // How the organ is drawn and simulated: its colour and its model kind.
  void parse_organ_looks(const YAML::Node& o, const std::string& f, OrganSpec& organ) {
    if (o["color"]) {
      if (auto v = fields_.vec3(o["color"], f + ".color")) {
        if (v->minCoeff() < 0.0 || v->maxCoeff() > 1.0) {
          fields_.problem(o["color"], f + ".color", "expected RGB components from 0 to 1");
        } else {
          organ.color = *v;
        }
      }
    }
    if (o["model"]) {
      if (auto v = fields_.string(o["model"], f + ".model")) {
        const std::optional<models::ModelKind> k = models::parse_model_kind(*v);
        if (k && *k != models::ModelKind::kMassSpring) {
          organ.model = *k;
        } else if (k) {
          // The mass-spring chain is the catheter's model (catheter:), not an organ's: an organ
          // given it would silently be rigid, so it is refused.
          fields_.problem(o["model"], f + ".model",
                          "mass-spring is the catheter's model (the catheter section), not an "
                          "organ's: expected rigid, local or modal-shell");
        } else {
          fields_.problem(o["model"], f + ".model",
                          "expected rigid, local or modal-shell, got " + quote_excerpt(*v));
        }
      }
    }
  }

  void parse_trocars(const YAML::Node& n) {
    if (!fields_.expect_list(n, "trocars", "a list of trocar ports")) return;
    std::set<std::string> names;
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string f = "trocars[" + std::to_string(i) + "]";
      if (!fields_.expect_map(n[i], f, {"name", "position_m"})) continue;
      TrocarSpec t;
      if (fields_.require(n[i], "name", f)) {
        if (auto v = fields_.string(n[i]["name"], f + ".name")) {
          t.name = *v;
          if (!names.insert(*v).second) {
            fields_.problem(n[i]["name"], f + ".name",
                            "duplicate trocar name " + quote_excerpt(*v));
          }
        }
      }
      if (fields_.require(n[i], "position_m", f)) {
        if (auto v = fields_.vec3(n[i]["position_m"], f + ".position_m")) t.position_m = *v;
      }
      s_.trocars.push_back(t);
    }
  }

  void parse_tools(const YAML::Node& n) {
    if (!fields_.expect_list(n, "tools", "a list of tools")) return;
    std::set<std::string> sides;
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string f = "tools[" + std::to_string(i) + "]";
      const YAML::Node t = n[i];
      if (!fields_.expect_map(t, f,
                              {"name", "side", "trocar", "kind", "shaft_length_m", "shaft_radius_m",
                               "jaw_length_m"})) {
        continue;
      }
      ToolSpec tool;
      if (fields_.require(t, "name", f)) {
        if (auto v = fields_.string(t["name"], f + ".name")) tool.name = *v;
      }
      if (fields_.require(t, "side", f)) parse_tool_side(t["side"], f + ".side", sides, tool);
      if (fields_.require(t, "trocar", f)) parse_tool_trocar(t["trocar"], f + ".trocar", tool);
      if (t["kind"]) {
        if (auto v = fields_.word(
                t["kind"], f + ".kind",
                {"grasper", "dissector", "clip-applier", "scissors", "probe", "ray-probe"})) {
          tool.kind = *v;
        }
      }
      fields_.optional_number(t, "shaft_length_m", f, tool.shaft_length_m, 0.05, 1.0,
                              "from 0.05 to 1 (m)");
      fields_.optional_number(t, "shaft_radius_m", f, tool.shaft_radius_m, 0.0005, 0.01,
                              "from 0.0005 to 0.01 (m)");
      fields_.optional_number(t, "jaw_length_m", f, tool.jaw_length_m, 0.002, 0.05,
                              "from 0.002 to 0.05 (m)");
      s_.tools.push_back(tool);
    }
  }

  void parse_tool_side(const YAML::Node& n, const std::string& f, std::set<std::string>& sides,
                       ToolSpec& tool) {
    const std::optional<std::string> v = fields_.word(n, f, {"left", "right"});
    if (!v) return;
    tool.side = *v == "left" ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight;
    if (!sides.insert(*v).second) {
      fields_.problem(n, f, "a " + *v + " tool is already defined (one tool per hand)");
    }
  }

  void parse_tool_trocar(const YAML::Node& n, const std::string& f, ToolSpec& tool) {
    const std::optional<std::string> v = fields_.string(n, f);
    if (!v) return;
    tool.trocar = *v;
    if (s_.trocar(*v) == nullptr) {
      fields_.problem(n, f,
                      "no trocar named " + quote_excerpt(*v) + " (expected a name from trocars)");
    }
  }

  void parse_catheter(const YAML::Node& n) {
    CatheterSpec c;
    if (!fields_.expect_map(n, "catheter",
                            {"port", "aim_m", "length_m", "diameter_m", "particles", "mass_kg",
                             "bending_stiffness_n_m2"})) {
      return;
    }
    c.line = yaml_line(n);
    c.length_line = n["length_m"] ? yaml_line(n["length_m"]) : c.line;
    c.aim_line = n["aim_m"] ? yaml_line(n["aim_m"]) : c.line;
    if (n["port"]) {
      if (auto v = fields_.string(n["port"], "catheter.port")) {
        c.port = *v;
        if (s_.trocar(*v) == nullptr) {
          fields_.problem(
              n["port"], "catheter.port",
              "no trocar named " + quote_excerpt(*v) + " (expected a name from trocars)");
        }
      }
    }
    if (n["aim_m"]) c.aim_m = fields_.vec3(n["aim_m"], "catheter.aim_m");
    fields_.optional_number(n, "length_m", "catheter", c.length_m, 0.01, 2.0, "from 0.01 to 2 (m)");
    fields_.optional_number(n, "diameter_m", "catheter", c.diameter_m, 0.0005, 0.005,
                            "from 0.0005 to 0.005 (m)");
    if (n["particles"]) {
      if (auto v = fields_.integer(n["particles"], "catheter.particles", 2, 4096)) c.particles = *v;
    }
    fields_.optional_number(n, "mass_kg", "catheter", c.mass_kg, 1e-6, 1.0, "from 1e-6 to 1 (kg)");
    fields_.optional_number(n, "bending_stiffness_n_m2", "catheter", c.bending_stiffness_n_m2, 1e-9,
                            1.0, "from 1e-9 to 1 (N m^2)");
    s_.catheter = c;
  }

  // A catheter-insertion task must be possible: the catheter, held at its port, reaches the
  // target depth past the incision with 5 mm to spare (its length is all there is: the chain is
  // nearly inextensible), and it starts outside the duct, at least 1 cm from the incision.
  void check_catheter_reach(const YAML::Node& n) {
    if (!s_.catheter || !s_.task || s_.task->kind != "catheter-insertion") return;
    const CatheterSpec& c = *s_.catheter;
    const TrocarSpec* port = c.port.empty() ? nullptr : s_.trocar(c.port);
    if (port == nullptr || !c.aim_m) return;  // the old lay, or a problem reported already
    const auto target = std::find_if(s_.organs.begin(), s_.organs.end(),
                                     [&](const OrganSpec& o) { return o.name == s_.task->target; });
    if (target == s_.organs.end() || !target->incision.present) return;
    const Eigen::Vector3d incision = target->incision.center_m;
    const double to_incision = (incision - port->position_m).norm();
    const double need = to_incision + s_.task->insertion_depth_m + 0.005;
    if (c.length_m < need) {
      fields_.problem(n["length_m"] ? n["length_m"] : n, "catheter.length_m",
                      fixed_mm(c.length_m) + " cannot reach " +
                          fixed_mm(s_.task->insertion_depth_m) + " into the incision " +
                          fixed_mm(to_incision) + " from the port '" + c.port + "': at least " +
                          fixed_mm(need) + " (with 5 mm to spare)");
      return;
    }
    const Eigen::Vector3d dir = *c.aim_m - port->position_m;
    if (dir.norm() < 1e-6) {
      fields_.problem(n["aim_m"], "catheter.aim_m", "must differ from the port's position");
      return;
    }
    const Eigen::Vector3d tip = port->position_m + c.length_m * dir.normalized();
    if ((tip - incision).norm() < 0.01) {
      fields_.problem(n["aim_m"], "catheter.aim_m",
                      "lays the catheter's tip " + fixed_mm((tip - incision).norm()) +
                          " from the incision: it must start outside the duct, at least 10 mm "
                          "away");
    }
  }

  static std::string fixed_mm(double m) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.0f mm", m * 1000.0);
    return buf;
  }

  void parse_task(const YAML::Node& n) {
    TaskSpec t;
    if (!fields_.expect_map(
            n, "task",
            {"kind", "target", "insertion_depth_m", "hold_s", "time_limit_s", "duct_injury_force_n",
             "duct_injury_time_s", "duct_squeeze_n", "organ_injury_force_n", "organ_injury_time_s",
             "drop_grace_s", "out_of_view_grace_s", "forbidden_organs", "common_bile_duct",
             "expert_entry_slant_deg"})) {
      return;
    }
    t.line = yaml_line(n);
    if (fields_.require(n, "kind", "task")) {
      if (auto v = fields_.string(n["kind"], "task.kind")) {
        if (*v != "catheter-insertion" && *v != "free-exploration") {
          fields_.problem(
              n["kind"], "task.kind",
              "expected catheter-insertion or free-exploration, got " + quote_excerpt(*v));
        }
        t.kind = *v;
      }
    }
    parse_task_target(n, t);
    parse_task_limits(n, t);
    if (n["forbidden_organs"]) parse_forbidden_organs(n["forbidden_organs"], t);
    if (n["common_bile_duct"]) parse_common_bile_duct(n["common_bile_duct"], t);
    if (t.kind == "catheter-insertion" && !s_.catheter) {
      fields_.problem(n, "task.kind", "catheter-insertion needs a catheter section");
    }
    s_.task = t;
  }

  // The goal's depth and hold, the time limit, and the thresholds of the errors.
  void parse_task_limits(const YAML::Node& n, TaskSpec& t) {
    fields_.optional_number(n, "insertion_depth_m", "task", t.insertion_depth_m, 0.001, 0.2,
                            "from 0.001 to 0.2 (m)");
    fields_.optional_number(n, "hold_s", "task", t.hold_s, 0.0, 600.0, "from 0 to 600 (s)");
    fields_.optional_number(n, "time_limit_s", "task", t.time_limit_s, 1.0, 7200.0,
                            "from 1 to 7200 (s)");
    fields_.optional_number(n, "duct_injury_force_n", "task", t.duct_injury_force_n, 0.01, 100.0,
                            "from 0.01 to 100 (N)");
    fields_.optional_number(n, "duct_injury_time_s", "task", t.duct_injury_time_s, 0.0, 60.0,
                            "from 0 to 60 (s)");
    fields_.optional_number(n, "duct_squeeze_n", "task", t.duct_squeeze_n, 0.01, 100.0,
                            "from 0.01 to 100 (N)");
    fields_.optional_number(n, "organ_injury_force_n", "task", t.organ_injury_force_n, 0.01, 100.0,
                            "from 0.01 to 100 (N)");
    fields_.optional_number(n, "organ_injury_time_s", "task", t.organ_injury_time_s, 0.0, 60.0,
                            "from 0 to 60 (s)");
    fields_.optional_number(n, "drop_grace_s", "task", t.drop_grace_s, 0.0, 60.0,
                            "from 0 to 60 (s)");
    fields_.optional_number(n, "out_of_view_grace_s", "task", t.out_of_view_grace_s, 0.0, 600.0,
                            "from 0 to 600 (s)");
    fields_.optional_number(n, "expert_entry_slant_deg", "task", t.expert_entry_slant_deg, 20.0,
                            70.0, "from 20 to 70 (degrees)");
  }

  // The experts' benchmarks: a source, and per training metric (named as the reports name them,
  // the scene's organs included) its mean, SD and which side is better.
  void parse_proficiency(const YAML::Node& n) {
    if (!fields_.expect_map(n, "proficiency", {"source", "metrics"})) return;
    ProficiencySpec p;
    p.line = yaml_line(n);
    if (fields_.require(n, "source", "proficiency")) {
      if (auto v = fields_.string(n["source"], "proficiency.source")) p.source = *v;
    }
    if (fields_.require(n, "metrics", "proficiency")) {
      const YAML::Node& ms = n["metrics"];
      if (!ms.IsMap() || ms.size() == 0) {
        fields_.problem(
            ms, "proficiency.metrics",
            "expected a mapping of metric names to {mean, sd}, got " + describe_yaml(ms));
      } else {
        for (const auto& kv : ms) parse_benchmark(kv.first, kv.second, p);
      }
    }
    s_.proficiency = p;
  }

  void parse_benchmark(const YAML::Node& key, const YAML::Node& n, ProficiencySpec& p) {
    const std::optional<std::string> name = fields_.string(key, "proficiency.metrics");
    if (!name) return;
    const std::string f = "proficiency.metrics." + *name;
    // The duct's per-organ metrics are named "duct" (the task's target, else the modal shell),
    // never by its organ name.
    std::vector<std::string> organs;
    for (const OrganSpec& o : s_.organs) {
      const bool duct =
          s_.task ? o.name == s_.task->target : o.model == models::ModelKind::kModalShell;
      if (!duct) organs.push_back(o.name);
    }
    if (!is_metric_name(*name, organs)) {
      fields_.problem(key, f,
                      "not a training metric of this scenario (docs/metrics.md lists them; "
                      "per-organ ones are named max_force_<organ>_n, with <organ> duct or an "
                      "organ's name in snake_case)");
      return;
    }
    if (std::any_of(p.metrics.begin(), p.metrics.end(),
                    [&](const MetricBenchmark& b) { return b.metric == *name; })) {
      fields_.problem(key, f, "is given twice");
      return;
    }
    if (!fields_.expect_map(n, f, {"mean", "sd", "better"})) return;
    MetricBenchmark b;
    b.metric = *name;
    b.line = yaml_line(key);
    bool ok = fields_.require(n, "mean", f) && fields_.require(n, "sd", f);
    if (ok) {
      const auto mean = fields_.number(n["mean"], f + ".mean", -1e12, 1e12, "in the metric's unit");
      const auto sd = fields_.number(n["sd"], f + ".sd", 0.0, 1e12, "of 0 or more");
      ok = mean && sd;
      if (ok) {
        b.mean = *mean;
        b.sd = *sd;
      }
    }
    if (n["better"]) {
      const auto better = fields_.word(n["better"], f + ".better", {"lower", "higher"});
      ok = ok && better;
      if (better) b.higher_is_better = *better == "higher";
    }
    if (ok) p.metrics.push_back(b);
  }

  void parse_forbidden_organs(const YAML::Node& n, TaskSpec& t) {
    if (!fields_.expect_list(n, "task.forbidden_organs", "a list of organ names")) return;
    const auto& os = s_.organs;
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string f = "task.forbidden_organs[" + std::to_string(i) + "]";
      const std::optional<std::string> v = fields_.string(n[i], f);
      if (!v) continue;
      if (std::none_of(os.begin(), os.end(), [&](const OrganSpec& o) { return o.name == *v; })) {
        fields_.problem(n[i], f,
                        "no organ named " + quote_excerpt(*v) + " (expected a name from organs)");
      } else if (*v == t.target) {
        fields_.problem(n[i], f,
                        quote_excerpt(*v) + " is the task's target (the instruments work on it)");
      } else if (std::find(t.forbidden_organs.begin(), t.forbidden_organs.end(), *v) !=
                 t.forbidden_organs.end()) {
        fields_.problem(n[i], f, quote_excerpt(*v) + " is listed twice");
      } else {
        t.forbidden_organs.push_back(*v);
      }
    }
  }

  void parse_common_bile_duct(const YAML::Node& n, TaskSpec& t) {
    const std::optional<std::string> v = fields_.string(n, "task.common_bile_duct");
    if (!v) return;
    const auto& os = s_.organs;
    if (std::none_of(os.begin(), os.end(), [&](const OrganSpec& o) { return o.name == *v; })) {
      fields_.problem(n, "task.common_bile_duct",
                      "no organ named " + quote_excerpt(*v) + " (expected a name from organs)");
    } else if (*v == t.target) {
      fields_.problem(n, "task.common_bile_duct",
                      quote_excerpt(*v) + " is the task's target (the catheter goes into it)");
    } else {
      t.common_bile_duct = *v;
    }
  }

  void parse_task_target(const YAML::Node& n, TaskSpec& t) {
    if (!n["target"]) {
      if (t.kind == "catheter-insertion") {
        fields_.problem(n, "task.target", "required field is missing (the organ to insert into)");
      }
      return;
    }
    const std::optional<std::string> v = fields_.string(n["target"], "task.target");
    if (!v) return;
    t.target = *v;
    const auto& os = s_.organs;
    if (std::none_of(os.begin(), os.end(), [&](const OrganSpec& o) { return o.name == *v; })) {
      fields_.problem(n["target"], "task.target",
                      "no organ named " + quote_excerpt(*v) + " (expected a name from organs)");
    }
  }

  YamlFields& fields_;
  ScenarioFiles files_;
  Scenario& s_;
};

}  // namespace

ScenarioLoadResult parse_scenario(std::string_view text, const fs::path& file,
                                  const ScenarioLoadSettings& settings) {
  Scenario scenario;
  scenario.file = fs::absolute(file);
  scenario.digest = content_digest(text);
  YamlFields fields(file.string());
  // A NUL byte is no YAML's (yaml-cpp's own words for it mislead: "unknown escape character"):
  // a binary file, or a text damaged, named at its line.
  if (const size_t nul = text.find('\0'); nul != std::string_view::npos) {
    const auto line =
        1 + std::count(text.begin(), text.begin() + static_cast<ptrdiff_t>(nul), '\n');
    fields.problem(static_cast<int>(line), "(file)",
                   "a NUL byte at byte " + std::to_string(nul) +
                       ": expected a YAML text file, not a binary one");
    return fields.take_problems();
  }
  if (const std::optional<YAML::Node> root = fields.load(text)) {
    try {
      ScenarioParser(fields, file, settings, scenario).parse(*root);
    } catch (const YAML::Exception& e) {
      // yaml-cpp throws on some malformed trees (e.g. duplicate keys); report, never crash.
      fields.problem(e.mark.line >= 0 ? e.mark.line + 1 : 0, "(document)", e.msg);
    }
  }
  std::vector<Diagnostic> problems = fields.take_problems();
  if (!problems.empty()) return problems;
  return scenario;
}

ScenarioLoadResult load_scenario(const fs::path& file, const ScenarioLoadSettings& settings) {
  const Result<std::string> text = read_bounded_file(
      file, kMaxScenarioFileBytes, "a YAML scenario file", "sim/setup/scenario_loader.h");
  if (!text.ok()) return text.diagnostics();
  return parse_scenario(text.value(), file, settings);
}

std::vector<fs::path> shipped_scenario_folders() {
  // Installed: beside the binary, PREFIX/bin/../share/laptrainer (the package's layout, wherever
  // it was unpacked); else the source tree the binary was built from; else the system's.
  std::vector<fs::path> folders;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) folders.push_back(exe.parent_path().parent_path() / "share/laptrainer/scenarios");
  folders.emplace_back(fs::path(LAP_SOURCE_DIR) / "scenarios");
  folders.emplace_back("/usr/share/laptrainer/scenarios");
  folders.emplace_back("/usr/local/share/laptrainer/scenarios");
  return folders;
}

fs::path default_scenario_path() {
  std::error_code ec;
  for (const fs::path& folder : shipped_scenario_folders()) {
    if (fs::is_regular_file(folder / "default.yaml", ec)) return folder / "default.yaml";
  }
  return fs::path(LAP_SOURCE_DIR) / "scenarios/default.yaml";
}

}  // namespace lap::sim
