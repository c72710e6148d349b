#include "sim/scenario_loader.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <regex>
#include <set>
#include <sstream>
#include <utility>

namespace lap::sim {
namespace fs = std::filesystem;

std::string ScenarioProblem::to_string() const {
  std::ostringstream s;
  s << file;
  if (line > 0) s << ':' << line;
  s << ": " << field << ": " << message;
  return s.str();
}

namespace {

int line_of(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing";
    case YAML::NodeType::Scalar:
      return "'" + n.Scalar() + "'";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a mapping";
    default:
      return "an undefined value";
  }
}

// Walks the YAML tree with a field path, collecting problems instead of stopping at the first.
class Parser {
 public:
  Parser(const fs::path& file, const ScenarioLoadSettings& settings, ScenarioLoadResult& out)
      : file_(file), settings_(settings), out_(out), dir_(fs::absolute(file).parent_path()) {}

  void problem(int line, const std::string& field, const std::string& message) {
    out_.problems.push_back({file_.string(), line, field, message});
  }

  // Reports keys not in `allowed`; returns false if n is not a mapping.
  bool expect_map(const YAML::Node& n, const std::string& field,
                  const std::vector<std::string>& allowed) {
    if (!n.IsMap()) {
      problem(line_of(n), field, "expected a mapping, got " + describe(n));
      return false;
    }
    std::set<std::string> seen;
    for (const auto& kv : n) {
      const std::string key = kv.first.Scalar();
      if (!seen.insert(key).second) {
        problem(line_of(kv.first), join(field, key),
                "field given twice (expected each field once)");
      }
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        problem(line_of(kv.first), join(field, key),
                "unknown field (expected one of: " + list + ")");
      }
    }
    return true;
  }

  static std::string join(const std::string& a, const std::string& b) {
    return a.empty() ? b : a + "." + b;
  }

  bool require(const YAML::Node& parent, const std::string& key, const std::string& field) {
    if (!parent[key]) {
      problem(line_of(parent), join(field, key), "required field is missing");
      return false;
    }
    return true;
  }

  std::optional<std::string> string(const YAML::Node& n, const std::string& field) {
    if (!n.IsScalar() || n.Scalar().empty()) {
      problem(line_of(n), field, "expected a non-empty string, got " + describe(n));
      return std::nullopt;
    }
    return n.Scalar();
  }

  // One of an enumeration's spellings; otherwise the error lists them ("expected a, b or c").
  template <typename E>
  std::optional<E> one_of(const YAML::Node& n, const std::string& field,
                          std::initializer_list<std::pair<const char*, E>> choices) {
    const std::optional<std::string> v = string(n, field);
    if (!v) return std::nullopt;
    std::string names;
    size_t i = 0;
    for (const auto& [name, value] : choices) {
      if (*v == name) return value;
      if (i > 0) names += i + 1 == choices.size() ? " or " : ", ";
      names += name;
      ++i;
    }
    problem(line_of(n), field, "expected " + names + ", got '" + *v + "'");
    return std::nullopt;
  }

  std::optional<double> number(const YAML::Node& n, const std::string& field, double lo, double hi,
                               const std::string& range_text) {
    double v = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v)) {
      problem(line_of(n), field, "expected a number " + range_text + ", got " + describe(n));
      return std::nullopt;
    }
    if (v < lo || v > hi) {
      std::ostringstream s;
      s << "expected a number " << range_text << ", got " << n.Scalar();
      problem(line_of(n), field, s.str());
      return std::nullopt;
    }
    return v;
  }

  std::optional<double> positive(const YAML::Node& n, const std::string& field) {
    double v = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v) || !(v > 0.0)) {
      problem(line_of(n), field, "expected a positive number, got " + describe(n));
      return std::nullopt;
    }
    return v;
  }

  std::optional<int> integer(const YAML::Node& n, const std::string& field, int lo, int hi) {
    int v = 0;
    const std::string range = "from " + std::to_string(lo) + " to " + std::to_string(hi);
    if (!n.IsScalar() || !YAML::convert<int>::decode(n, v) || v < lo || v > hi) {
      problem(line_of(n), field, "expected a whole number " + range + ", got " + describe(n));
      return std::nullopt;
    }
    return v;
  }

  std::optional<bool> boolean(const YAML::Node& n, const std::string& field) {
    bool v = false;
    if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) {
      problem(line_of(n), field, "expected true or false, got " + describe(n));
      return std::nullopt;
    }
    return v;
  }

  std::optional<Eigen::Vector3d> vec3(const YAML::Node& n, const std::string& field) {
    if (!n.IsSequence() || n.size() != 3) {
      problem(line_of(n), field, "expected a list of 3 numbers [x, y, z], got " + describe(n));
      return std::nullopt;
    }
    Eigen::Vector3d v;
    for (size_t i = 0; i < 3; ++i) {
      if (!n[i].IsScalar() || !YAML::convert<double>::decode(n[i], v[static_cast<int>(i)]) ||
          !std::isfinite(v[static_cast<int>(i)])) {
        problem(line_of(n), field,
                "expected a list of 3 numbers [x, y, z], got " + describe(n[i]) + " at position " +
                    std::to_string(i + 1));
        return std::nullopt;
      }
    }
    return v;
  }

  template <typename T>
  void optional_number(const YAML::Node& parent, const std::string& key, const std::string& field,
                       T& target, double lo, double hi, const std::string& range_text) {
    if (parent[key]) {
      if (auto v = number(parent[key], join(field, key), lo, hi, range_text)) target = *v;
    }
  }

  // Resolves a file reference and checks it stays inside an allowed tree and exists.
  std::optional<fs::path> file_path(const YAML::Node& n, const std::string& field) {
    auto text = string(n, field);
    if (!text) return std::nullopt;
    fs::path p(*text);
    const fs::path resolved = fs::weakly_canonical(p.is_absolute() ? p : dir_ / p);
    if (!inside_allowed(resolved)) {
      problem(line_of(n), field,
              "path '" + *text + "' leaves the scenario's folder (expected a file under " +
                  dir_.string() + " or under a directory listed in allowed_paths)");
      return std::nullopt;
    }
    if (settings_.check_files) {
      std::error_code ec;
      if (!fs::is_regular_file(resolved, ec)) {
        problem(line_of(n), field,
                "file '" + *text + "' not found (looked for " + resolved.string() + ")");
        return std::nullopt;
      }
    }
    return resolved;
  }

  bool inside_allowed(const fs::path& resolved) const {
    auto under = [&resolved](const fs::path& root) {
      const fs::path r = fs::weakly_canonical(root);
      auto rit = r.begin();
      auto pit = resolved.begin();
      for (; rit != r.end(); ++rit, ++pit) {
        if (rit->empty()) continue;  // trailing separator
        if (pit == resolved.end() || *rit != *pit) return false;
      }
      return true;
    };
    if (under(dir_)) return true;
    for (const auto& a : out_.scenario.allowed_paths) {
      if (under(a)) return true;
    }
    for (const auto& a : settings_.allowed_paths) {
      if (under(a)) return true;
    }
    return false;
  }

  void parse(const YAML::Node& root) {
    Scenario& s = out_.scenario;
    if (!root.IsMap()) {
      problem(std::max(1, line_of(root)), "(document)",
              "expected a mapping with version, name and organs, got " + describe(root));
      return;
    }
    expect_map(root, "",
               {"version", "name", "description", "allowed_paths", "camera", "organs", "trocars",
                "tools", "catheter", "task"});
    if (require(root, "version", "")) {
      if (auto v = integer(root["version"], "version", 1, 1)) s.version = *v;
    }
    if (require(root, "name", "")) {
      if (auto v = string(root["name"], "name")) s.name = *v;
    }
    if (root["description"]) {
      if (auto v = string(root["description"], "description")) s.description = *v;
    }
    if (const YAML::Node ap = root["allowed_paths"]) {
      if (!ap.IsSequence()) {
        problem(line_of(ap), "allowed_paths",
                "expected a list of directories, got " + describe(ap));
      } else {
        for (size_t i = 0; i < ap.size(); ++i) {
          const std::string f = "allowed_paths[" + std::to_string(i) + "]";
          if (auto t = string(ap[i], f)) {
            const fs::path p(*t);
            const fs::path resolved = fs::weakly_canonical(p.is_absolute() ? p : dir_ / p);
            std::error_code ec;
            if (settings_.check_files && !fs::is_directory(resolved, ec)) {
              problem(line_of(ap[i]), f,
                      "directory '" + *t + "' not found (looked for " + resolved.string() + ")");
            } else {
              s.allowed_paths.push_back(resolved);
            }
          }
        }
      }
    }
    if (root["camera"]) parse_camera(root["camera"]);
    if (require(root, "organs", "")) parse_organs(root["organs"]);
    if (root["trocars"]) parse_trocars(root["trocars"]);
    if (root["tools"]) parse_tools(root["tools"]);
    if (root["catheter"]) parse_catheter(root["catheter"]);
    if (root["task"]) parse_task(root["task"]);
  }

  void parse_camera(const YAML::Node& n) {
    CameraSpec& c = out_.scenario.camera;
    if (!expect_map(n, "camera", {"position_m", "focal_point_m", "view_up", "view_angle_deg"}))
      return;
    if (n["position_m"]) {
      if (auto v = vec3(n["position_m"], "camera.position_m")) c.position_m = *v;
    }
    if (n["focal_point_m"]) {
      if (auto v = vec3(n["focal_point_m"], "camera.focal_point_m")) c.focal_point_m = *v;
    }
    if (n["view_up"]) {
      if (auto v = vec3(n["view_up"], "camera.view_up")) {
        if (v->norm() < 1e-9) {
          problem(line_of(n["view_up"]), "camera.view_up", "expected a non-zero direction");
        } else {
          c.view_up = v->normalized();
        }
      }
    }
    optional_number(n, "view_angle_deg", "camera", c.view_angle_deg, 1.0, 120.0,
                    "from 1 to 120 (degrees)");
    if ((c.position_m - c.focal_point_m).norm() < 1e-6) {
      problem(line_of(n), "camera", "position_m and focal_point_m must differ");
    }
  }

  void parse_material(const YAML::Node& n, const std::string& f, MaterialSpec& m) {
    if (!expect_map(n, f,
                    {"stiffness_n_per_m", "damping_n_s_per_m", "friction_static",
                     "friction_dynamic", "friction_stick_stiffness_n_per_m",
                     "friction_slide_stiffness_n_per_m", "friction_map", "shading", "texture"})) {
      return;
    }
    if (require(n, "stiffness_n_per_m", f)) {
      if (auto v = positive(n["stiffness_n_per_m"], f + ".stiffness_n_per_m"))
        m.stiffness_n_per_m = *v;
    }
    optional_number(n, "damping_n_s_per_m", f, m.damping_n_s_per_m, 0.0, 1e6,
                    "from 0 to 1e6 (N s/m)");
    optional_number(n, "friction_static", f, m.friction_static, 0.0, 10.0, "from 0 to 10");
    optional_number(n, "friction_dynamic", f, m.friction_dynamic, 0.0, 10.0, "from 0 to 10");
    if (n["friction_dynamic"] && m.friction_dynamic > m.friction_static) {
      problem(line_of(n["friction_dynamic"]), f + ".friction_dynamic",
              "expected at most friction_static (" + std::to_string(m.friction_static) + ")");
    }
    optional_number(n, "friction_stick_stiffness_n_per_m", f, m.friction_stick_stiffness_n_per_m,
                    1.0, 1e5, "from 1 to 1e5 (N/m)");
    optional_number(n, "friction_slide_stiffness_n_per_m", f, m.friction_slide_stiffness_n_per_m,
                    1.0, 1e5, "from 1 to 1e5 (N/m)");
    if (n["friction_slide_stiffness_n_per_m"]) {
      const double ks = m.friction_stick_stiffness_n_per_m > 0.0
                            ? m.friction_stick_stiffness_n_per_m
                            : m.stiffness_n_per_m;
      if (m.friction_slide_stiffness_n_per_m > ks) {
        problem(line_of(n["friction_slide_stiffness_n_per_m"]),
                f + ".friction_slide_stiffness_n_per_m",
                "expected at most the sticking stiffness k_s (" + std::to_string(ks) +
                    " N/m): sliding is softer than sticking (thesis 6.2)");
      }
    }
    if (n["friction_map"]) parse_friction_map(n["friction_map"], f + ".friction_map", m);
    if (n["shading"]) {
      const YAML::Node s = n["shading"];
      const std::string fs_ = f + ".shading";
      if (expect_map(s, fs_, {"enabled", "crease_angle_deg"})) {
        if (s["enabled"]) {
          if (auto v = boolean(s["enabled"], fs_ + ".enabled")) m.shading.enabled = *v;
        }
        optional_number(s, "crease_angle_deg", fs_, m.shading.crease_angle_deg, 0.0, 180.0,
                        "from 0 to 180 (degrees)");
      }
    }
    if (n["texture"]) parse_texture(n["texture"], f + ".texture", m.texture);
    if (m.shading.enabled && m.texture.kind != TextureSpec::Kind::kNone) {
      problem(line_of(n["shading"]), f + ".shading",
              "force shading and a texture on one material: both change the surface's shape and "
              "are not combined (thesis 6.6); switch one off");
    }
  }

  void parse_friction_map(const YAML::Node& n, const std::string& f, MaterialSpec& m) {
    if (!expect_map(n, f,
                    {"kind", "period_m", "amplitude", "grain_m", "relative_std_dev", "seed"})) {
      return;
    }
    FrictionMapSpec& fm = m.friction_map;
    if (require(n, "kind", f)) {
      using K = FrictionMapSpec::Kind;
      if (auto k = one_of<K>(
              n["kind"], f + ".kind",
              {{"uniform", K::kUniform}, {"periodic", K::kPeriodic}, {"random", K::kRandom}})) {
        fm.kind = *k;
      }
    }
    optional_number(n, "period_m", f, fm.period_m, 1e-5, 0.1, "from 1e-5 to 0.1 (m)");
    optional_number(n, "amplitude", f, fm.amplitude, 0.0, 0.99, "from 0 to 0.99 (relative)");
    optional_number(n, "grain_m", f, fm.grain_m, 1e-6, 0.01, "from 1e-6 to 0.01 (m)");
    optional_number(n, "relative_std_dev", f, fm.relative_std_dev, 0.0, 1.0,
                    "from 0 to 1 (standard deviation / mean)");
    if (n["seed"]) {
      if (auto v = integer(n["seed"], f + ".seed", 0, 1000000000)) fm.seed = *v;
    }
  }

  void parse_texture(const YAML::Node& n, const std::string& f, TextureSpec& t) {
    if (!expect_map(n, f,
                    {"kind", "image", "function", "amplitude_m", "wavelength_m", "k_mix", "octaves",
                     "seed", "direction", "mapping"})) {
      return;
    }
    t.line = line_of(n);
    std::string kind = "none";
    if (require(n, "kind", f)) {
      if (auto v = string(n["kind"], f + ".kind")) kind = *v;
    }
    if (kind == "none") {
      t.kind = TextureSpec::Kind::kNone;
      return;
    }
    if (kind == "image") {
      t.kind = TextureSpec::Kind::kImage;
      if (require(n, "image", f)) {
        if (auto p = file_path(n["image"], f + ".image")) t.image = *p;
      }
      if (n["mapping"]) parse_mapping(n["mapping"], f + ".mapping", t.mapping);
    } else if (kind == "procedural") {
      t.kind = TextureSpec::Kind::kProcedural;
      if (require(n, "function", f)) {
        if (auto v = string(n["function"], f + ".function")) {
          static const std::set<std::string> kFunctions = {"perlin", "fbm", "worley", "fourier"};
          if (kFunctions.count(*v) == 0) {
            problem(line_of(n["function"]), f + ".function",
                    "expected perlin, fbm, worley or fourier, got '" + *v + "'");
          } else {
            t.function = *v;
          }
        }
      }
    } else {
      problem(line_of(n["kind"]), f + ".kind",
              "expected none, image or procedural, got '" + kind + "'");
      return;
    }
    if (require(n, "amplitude_m", f)) {
      if (auto v = number(n["amplitude_m"], f + ".amplitude_m", 0.0, 0.01, "from 0 to 0.01 (m)"))
        t.amplitude_m = *v;
    }
    if (t.kind == TextureSpec::Kind::kProcedural && require(n, "wavelength_m", f)) {
      if (auto v =
              number(n["wavelength_m"], f + ".wavelength_m", 1e-5, 0.1, "from 1e-5 to 0.1 (m)"))
        t.wavelength_m = *v;
    }
    optional_number(n, "k_mix", f, t.k_mix, 0.0, 10.0, "from 0 to 10 (thesis: 1 to 2)");
    if (n["octaves"]) {
      if (auto v = integer(n["octaves"], f + ".octaves", 1, 8)) t.octaves = *v;
    }
    if (n["seed"]) {
      if (auto v = integer(n["seed"], f + ".seed", 0, 1000000000)) t.seed = *v;
    }
    if (n["direction"]) {
      if (auto v = vec3(n["direction"], f + ".direction")) {
        if (v->norm() < 1e-9) {
          problem(line_of(n["direction"]), f + ".direction", "expected a non-zero direction");
        } else {
          t.direction = v->normalized();
        }
      }
    }
  }

  void parse_mapping(const YAML::Node& n, const std::string& f, TextureMappingSpec& m) {
    if (!expect_map(n, f, {"kind", "origin_m", "axis", "tile_m", "repeat"})) return;
    if (require(n, "kind", f)) {
      using K = TextureMappingSpec::Kind;
      if (auto k = one_of<K>(n["kind"], f + ".kind",
                             {{"plane", K::kPlane},
                              {"cylinder", K::kCylinder},
                              {"sphere", K::kSphere},
                              {"box", K::kBox}})) {
        m.kind = *k;
      }
    }
    if (n["origin_m"]) {
      if (auto v = vec3(n["origin_m"], f + ".origin_m")) m.origin_m = *v;
    }
    if (n["axis"]) {
      if (auto v = vec3(n["axis"], f + ".axis")) {
        if (v->norm() < 1e-9) {
          problem(line_of(n["axis"]), f + ".axis", "expected a non-zero direction");
        } else {
          m.axis = v->normalized();
        }
      }
    }
    if (n["tile_m"]) {
      const YAML::Node t = n["tile_m"];
      if (!t.IsSequence() || t.size() != 2) {
        problem(line_of(t), f + ".tile_m", "expected [u, v] in metres, got " + describe(t));
      } else {
        for (size_t i = 0; i < 2; ++i) {
          if (auto v = number(t[i], f + ".tile_m[" + std::to_string(i) + "]", 1e-5, 1.0,
                              "from 1e-5 to 1 (m)"))
            m.tile_m[i] = *v;
        }
      }
    }
    if (n["repeat"]) {
      const YAML::Node r = n["repeat"];
      if (!r.IsSequence() || r.size() != 2) {
        problem(line_of(r), f + ".repeat", "expected [u, v] whole numbers, got " + describe(r));
      } else {
        for (size_t i = 0; i < 2; ++i) {
          if (auto v = integer(r[i], f + ".repeat[" + std::to_string(i) + "]", 1, 1000))
            m.repeat[i] = *v;
        }
      }
    }
  }

  void parse_organs(const YAML::Node& n) {
    if (!n.IsSequence() || n.size() == 0) {
      problem(line_of(n), "organs", "expected a non-empty list of organs, got " + describe(n));
      return;
    }
    std::set<std::string> names;
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string f = "organs[" + std::to_string(i) + "]";
      const YAML::Node o = n[i];
      if (!expect_map(
              o, f,
              {"name", "mesh", "scale", "repair", "transform", "color", "model", "material"})) {
        continue;
      }
      OrganSpec organ;
      organ.line = line_of(o);
      if (require(o, "name", f)) {
        if (auto v = string(o["name"], f + ".name")) {
          static const std::regex kName("[a-z][a-z0-9_]*");
          if (!std::regex_match(*v, kName)) {
            problem(line_of(o["name"]), f + ".name",
                    "expected lower-case letters, digits and underscores starting with a letter, "
                    "got '" +
                        *v + "'");
          } else if (!names.insert(*v).second) {
            problem(line_of(o["name"]), f + ".name",
                    "duplicate organ name '" + *v + "' (names must be unique)");
          }
          organ.name = *v;
        }
      }
      if (require(o, "mesh", f)) {
        if (auto p = file_path(o["mesh"], f + ".mesh")) organ.mesh = *p;
      }
      if (o["scale"]) {
        if (auto v = positive(o["scale"], f + ".scale")) organ.scale = *v;
      }
      if (o["repair"]) {
        if (auto v = boolean(o["repair"], f + ".repair")) organ.repair = *v;
      }
      if (const YAML::Node t = o["transform"]) {
        if (expect_map(t, f + ".transform", {"translation_m", "rotation_deg"})) {
          if (t["translation_m"]) {
            if (auto v = vec3(t["translation_m"], f + ".transform.translation_m"))
              organ.translation_m = *v;
          }
          if (t["rotation_deg"]) {
            if (auto v = vec3(t["rotation_deg"], f + ".transform.rotation_deg"))
              organ.rotation_deg = *v;
          }
        }
      }
      if (o["color"]) {
        if (auto v = vec3(o["color"], f + ".color")) {
          if (v->minCoeff() < 0.0 || v->maxCoeff() > 1.0) {
            problem(line_of(o["color"]), f + ".color", "expected RGB components from 0 to 1");
          } else {
            organ.color = *v;
          }
        }
      }
      if (o["model"]) {
        if (auto v = string(o["model"], f + ".model")) {
          if (auto k = models::parse_model_kind(*v)) {
            organ.model = *k;
          } else {
            problem(line_of(o["model"]), f + ".model",
                    "expected rigid, local, modal-shell or mass-spring, got '" + *v + "'");
          }
        }
      }
      if (require(o, "material", f)) parse_material(o["material"], f + ".material", organ.material);
      out_.scenario.organs.push_back(std::move(organ));
    }
  }

  void parse_trocars(const YAML::Node& n) {
    if (!n.IsSequence()) {
      problem(line_of(n), "trocars", "expected a list of trocar ports, got " + describe(n));
      return;
    }
    std::set<std::string> names;
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string f = "trocars[" + std::to_string(i) + "]";
      if (!expect_map(n[i], f, {"name", "position_m"})) continue;
      TrocarSpec t;
      if (require(n[i], "name", f)) {
        if (auto v = string(n[i]["name"], f + ".name")) {
          t.name = *v;
          if (!names.insert(*v).second) {
            problem(line_of(n[i]["name"]), f + ".name", "duplicate trocar name '" + *v + "'");
          }
        }
      }
      if (require(n[i], "position_m", f)) {
        if (auto v = vec3(n[i]["position_m"], f + ".position_m")) t.position_m = *v;
      }
      out_.scenario.trocars.push_back(t);
    }
  }

  void parse_tools(const YAML::Node& n) {
    if (!n.IsSequence()) {
      problem(line_of(n), "tools", "expected a list of tools, got " + describe(n));
      return;
    }
    std::set<std::string> sides;
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string f = "tools[" + std::to_string(i) + "]";
      const YAML::Node t = n[i];
      if (!expect_map(t, f,
                      {"name", "side", "trocar", "kind", "shaft_length_m", "shaft_radius_m",
                       "jaw_length_m"})) {
        continue;
      }
      ToolSpec tool;
      if (require(t, "name", f)) {
        if (auto v = string(t["name"], f + ".name")) tool.name = *v;
      }
      if (require(t, "side", f)) {
        if (auto v = string(t["side"], f + ".side")) {
          if (*v == "left" || *v == "right") {
            tool.side = *v == "left" ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight;
            if (!sides.insert(*v).second) {
              problem(line_of(t["side"]), f + ".side",
                      "a " + *v + " tool is already defined (one tool per hand)");
            }
          } else {
            problem(line_of(t["side"]), f + ".side", "expected left or right, got '" + *v + "'");
          }
        }
      }
      if (require(t, "trocar", f)) {
        if (auto v = string(t["trocar"], f + ".trocar")) {
          tool.trocar = *v;
          if (out_.scenario.trocar(*v) == nullptr) {
            problem(line_of(t["trocar"]), f + ".trocar",
                    "no trocar named '" + *v + "' (expected a name from trocars)");
          }
        }
      }
      if (t["kind"]) {
        if (auto v = string(t["kind"], f + ".kind")) {
          static const std::set<std::string> kKinds = {"grasper", "dissector", "clip-applier",
                                                       "scissors"};
          if (kKinds.count(*v) == 0) {
            problem(line_of(t["kind"]), f + ".kind",
                    "expected grasper, dissector, clip-applier or scissors, got '" + *v + "'");
          } else {
            tool.kind = *v;
          }
        }
      }
      optional_number(t, "shaft_length_m", f, tool.shaft_length_m, 0.05, 1.0, "from 0.05 to 1 (m)");
      optional_number(t, "shaft_radius_m", f, tool.shaft_radius_m, 0.0005, 0.01,
                      "from 0.0005 to 0.01 (m)");
      optional_number(t, "jaw_length_m", f, tool.jaw_length_m, 0.002, 0.05,
                      "from 0.002 to 0.05 (m)");
      out_.scenario.tools.push_back(tool);
    }
  }

  void parse_catheter(const YAML::Node& n) {
    CatheterSpec c;
    if (!expect_map(n, "catheter",
                    {"length_m", "diameter_m", "particles", "mass_kg", "bending_stiffness_n_m2"})) {
      return;
    }
    optional_number(n, "length_m", "catheter", c.length_m, 0.01, 2.0, "from 0.01 to 2 (m)");
    optional_number(n, "diameter_m", "catheter", c.diameter_m, 0.0005, 0.005,
                    "from 0.0005 to 0.005 (m)");
    if (n["particles"]) {
      if (auto v = integer(n["particles"], "catheter.particles", 2, 4096)) c.particles = *v;
    }
    optional_number(n, "mass_kg", "catheter", c.mass_kg, 1e-6, 1.0, "from 1e-6 to 1 (kg)");
    optional_number(n, "bending_stiffness_n_m2", "catheter", c.bending_stiffness_n_m2, 1e-9, 1.0,
                    "from 1e-9 to 1 (N m^2)");
    out_.scenario.catheter = c;
  }

  void parse_task(const YAML::Node& n) {
    TaskSpec t;
    if (!expect_map(n, "task", {"kind", "target", "insertion_depth_m", "time_limit_s"})) return;
    if (require(n, "kind", "task")) {
      if (auto v = string(n["kind"], "task.kind")) {
        if (*v != "catheter-insertion" && *v != "free-exploration") {
          problem(line_of(n["kind"]), "task.kind",
                  "expected catheter-insertion or free-exploration, got '" + *v + "'");
        }
        t.kind = *v;
      }
    }
    if (n["target"]) {
      if (auto v = string(n["target"], "task.target")) {
        t.target = *v;
        const auto& os = out_.scenario.organs;
        if (std::none_of(os.begin(), os.end(), [&](const OrganSpec& o) { return o.name == *v; })) {
          problem(line_of(n["target"]), "task.target",
                  "no organ named '" + *v + "' (expected a name from organs)");
        }
      }
    } else if (t.kind == "catheter-insertion") {
      problem(line_of(n), "task.target", "required field is missing (the organ to insert into)");
    }
    optional_number(n, "insertion_depth_m", "task", t.insertion_depth_m, 0.001, 0.2,
                    "from 0.001 to 0.2 (m)");
    optional_number(n, "time_limit_s", "task", t.time_limit_s, 1.0, 7200.0, "from 1 to 7200 (s)");
    if (t.kind == "catheter-insertion" && !out_.scenario.catheter) {
      problem(line_of(n), "task.kind", "catheter-insertion needs a catheter section");
    }
    out_.scenario.task = t;
  }

 private:
  fs::path file_;
  const ScenarioLoadSettings& settings_;
  ScenarioLoadResult& out_;
  fs::path dir_;
};

}  // namespace

ScenarioLoadResult parse_scenario(std::string_view text, const fs::path& file,
                                  const ScenarioLoadSettings& settings) {
  ScenarioLoadResult result;
  result.scenario.file = fs::absolute(file);
  Parser parser(file, settings, result);
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::ParserException& e) {
    parser.problem(e.mark.line >= 0 ? e.mark.line + 1 : 0, "(syntax)", "not valid YAML: " + e.msg);
    return result;
  }
  try {
    parser.parse(root);
  } catch (const YAML::Exception& e) {
    // yaml-cpp throws on some malformed trees (e.g. duplicate keys); report, never crash.
    parser.problem(e.mark.line >= 0 ? e.mark.line + 1 : 0, "(document)", e.msg);
  }
  return result;
}

ScenarioLoadResult load_scenario(const fs::path& file, const ScenarioLoadSettings& settings) {
  std::ifstream in(file, std::ios::binary);
  std::error_code ec;
  if (!in || fs::is_directory(file, ec)) {
    ScenarioLoadResult r;
    r.problems.push_back({file.string(), 0, "(file)",
                          "cannot read the scenario file (expected a readable YAML file)"});
    return r;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), file, settings);
}

fs::path default_scenario_path() {
  for (const fs::path& candidate :
       {fs::path(LAP_SOURCE_DIR) / "scenarios/default.yaml",
        fs::path("/usr/share/laptrainer/scenarios/default.yaml"),
        fs::path("/usr/local/share/laptrainer/scenarios/default.yaml")}) {
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) return candidate;
  }
  return fs::path(LAP_SOURCE_DIR) / "scenarios/default.yaml";
}

}  // namespace lap::sim
