#include "sim/setup/scenario_material.h"

namespace lap::sim {

namespace {

// One material section; each stage reads one part and reports against the path `f` it is given.
class MaterialParser {
 public:
  MaterialParser(YamlFields& fields, ScenarioFiles& files) : fields_(fields), files_(files) {}

  void parse(const YAML::Node& n, const std::string& f, MaterialSpec& m) {
    if (!fields_.expect_map(
            n, f,
            {"stiffness_n_per_m", "damping_n_s_per_m", "friction_static", "friction_dynamic",
             "friction_stick_stiffness_n_per_m", "friction_slide_stiffness_n_per_m", "friction_map",
             "shading", "texture", "catheter_friction"})) {
      return;
    }
    parse_contact(n, f, m);
    parse_friction(n, f, m);
    if (n["friction_map"]) parse_friction_map(n["friction_map"], f + ".friction_map", m);
    if (n["shading"]) parse_shading(n["shading"], f + ".shading", m.shading);
    if (n["texture"]) parse_texture(n["texture"], f + ".texture", m.texture);
    if (m.shading.enabled && m.texture.kind != TextureSpec::Kind::kNone) {
      fields_.problem(n["shading"], f + ".shading",
                      "force shading and a texture on one material: both change the surface's "
                      "shape and are not combined (thesis 6.6); switch one off");
    }
  }

 private:
  void parse_contact(const YAML::Node& n, const std::string& f, MaterialSpec& m) {
    if (fields_.require(n, "stiffness_n_per_m", f)) {
      if (auto v = fields_.positive(n["stiffness_n_per_m"], f + ".stiffness_n_per_m"))
        m.stiffness_n_per_m = *v;
    }
    fields_.optional_number(n, "damping_n_s_per_m", f, m.damping_n_s_per_m, 0.0, 1e6,
                            "from 0 to 1e6 (N s/m)");
  }

  // The coefficients and the stick and slide springs of the friction model (thesis 6.2).
  void parse_friction(const YAML::Node& n, const std::string& f, MaterialSpec& m) {
    fields_.optional_number(n, "friction_static", f, m.friction_static, 0.0, 10.0, "from 0 to 10");
    fields_.optional_number(n, "friction_dynamic", f, m.friction_dynamic, 0.0, 10.0,
                            "from 0 to 10");
    if (n["friction_dynamic"] && m.friction_dynamic > m.friction_static) {
      fields_.problem(
          n["friction_dynamic"], f + ".friction_dynamic",
          "expected at most friction_static (" + std::to_string(m.friction_static) + ")");
    }
    fields_.optional_number(n, "catheter_friction", f, m.catheter_friction, 0.0, 2.0,
                            "from 0 to 2");
    fields_.optional_number(n, "friction_stick_stiffness_n_per_m", f,
                            m.friction_stick_stiffness_n_per_m, 1.0, 1e5, "from 1 to 1e5 (N/m)");
    fields_.optional_number(n, "friction_slide_stiffness_n_per_m", f,
                            m.friction_slide_stiffness_n_per_m, 1.0, 1e5, "from 1 to 1e5 (N/m)");
    if (n["friction_slide_stiffness_n_per_m"]) {
      const double ks = m.friction_stick_stiffness_n_per_m > 0.0
                            ? m.friction_stick_stiffness_n_per_m
                            : m.stiffness_n_per_m;
      if (m.friction_slide_stiffness_n_per_m > ks) {
        fields_.problem(n["friction_slide_stiffness_n_per_m"],
                        f + ".friction_slide_stiffness_n_per_m",
                        "expected at most the sticking stiffness k_s (" + std::to_string(ks) +
                            " N/m): sliding is softer than sticking (thesis 6.2)");
      }
    }
  }

  void parse_friction_map(const YAML::Node& n, const std::string& f, MaterialSpec& m) {
    if (!fields_.expect_map(
            n, f, {"kind", "period_m", "amplitude", "grain_m", "relative_std_dev", "seed"})) {
      return;
    }
    FrictionMapSpec& fm = m.friction_map;
    if (fields_.require(n, "kind", f)) {
      using K = FrictionMapSpec::Kind;
      if (auto k = fields_.one_of<K>(
              n["kind"], f + ".kind",
              {{"uniform", K::kUniform}, {"periodic", K::kPeriodic}, {"random", K::kRandom}})) {
        fm.kind = *k;
      }
    }
    fields_.optional_number(n, "period_m", f, fm.period_m, 1e-5, 0.1, "from 1e-5 to 0.1 (m)");
    fields_.optional_number(n, "amplitude", f, fm.amplitude, 0.0, 0.99,
                            "from 0 to 0.99 (relative)");
    fields_.optional_number(n, "grain_m", f, fm.grain_m, 1e-6, 0.01, "from 1e-6 to 0.01 (m)");
    fields_.optional_number(n, "relative_std_dev", f, fm.relative_std_dev, 0.0, 1.0,
                            "from 0 to 1 (standard deviation / mean)");
    if (n["seed"]) {
      if (auto v = fields_.integer(n["seed"], f + ".seed", 0, 1000000000)) fm.seed = *v;
    }
  }

  void parse_shading(const YAML::Node& n, const std::string& f, ShadingSpec& s) {
    if (!fields_.expect_map(n, f, {"enabled", "crease_angle_deg"})) return;
    if (n["enabled"]) {
      if (auto v = fields_.boolean(n["enabled"], f + ".enabled")) s.enabled = *v;
    }
    fields_.optional_number(n, "crease_angle_deg", f, s.crease_angle_deg, 0.0, 180.0,
                            "from 0 to 180 (degrees)");
  }

  void parse_texture(const YAML::Node& n, const std::string& f, TextureSpec& t) {
    if (!fields_.expect_map(n, f,
                            {"kind", "image", "function", "amplitude_m", "wavelength_m", "k_mix",
                             "octaves", "seed", "direction", "mapping"})) {
      return;
    }
    t.line = yaml_line(n);
    using K = TextureSpec::Kind;
    // A missing or unreadable kind leaves the texture off; its problem is already reported.
    if (!fields_.require(n, "kind", f)) return;
    const std::optional<K> kind = fields_.one_of<K>(
        n["kind"], f + ".kind",
        {{"none", K::kNone}, {"image", K::kImage}, {"procedural", K::kProcedural}});
    if (!kind) return;
    t.kind = *kind;
    if (t.kind == K::kNone) return;
    if (t.kind == K::kImage) {
      if (fields_.require(n, "image", f)) {
        if (auto p = files_.file(n["image"], f + ".image")) t.image = *p;
      }
      if (n["mapping"]) parse_mapping(n["mapping"], f + ".mapping", t.mapping);
    } else if (fields_.require(n, "function", f)) {
      if (auto v = fields_.word(n["function"], f + ".function",
                                {"perlin", "fbm", "worley", "fourier"})) {
        t.function = *v;
      }
    }
    parse_texture_shape(n, f, t);
  }

  // The height field's size and pattern, shared by image and procedural textures.
  void parse_texture_shape(const YAML::Node& n, const std::string& f, TextureSpec& t) {
    if (fields_.require(n, "amplitude_m", f)) {
      if (auto v =
              fields_.number(n["amplitude_m"], f + ".amplitude_m", 0.0, 0.01, "from 0 to 0.01 (m)"))
        t.amplitude_m = *v;
    }
    if (t.kind == TextureSpec::Kind::kProcedural && fields_.require(n, "wavelength_m", f)) {
      if (auto v = fields_.number(n["wavelength_m"], f + ".wavelength_m", 1e-5, 0.1,
                                  "from 1e-5 to 0.1 (m)"))
        t.wavelength_m = *v;
    }
    fields_.optional_number(n, "k_mix", f, t.k_mix, 0.0, 10.0, "from 0 to 10 (thesis: 1 to 2)");
    if (n["octaves"]) {
      if (auto v = fields_.integer(n["octaves"], f + ".octaves", 1, 8)) t.octaves = *v;
    }
    if (n["seed"]) {
      if (auto v = fields_.integer(n["seed"], f + ".seed", 0, 1000000000)) t.seed = *v;
    }
    if (n["direction"]) {
      if (auto v = fields_.direction(n["direction"], f + ".direction")) t.direction = *v;
    }
  }

  void parse_mapping(const YAML::Node& n, const std::string& f, TextureMappingSpec& m) {
    if (!fields_.expect_map(n, f, {"kind", "origin_m", "axis", "tile_m", "repeat"})) return;
    if (fields_.require(n, "kind", f)) {
      using K = TextureMappingSpec::Kind;
      if (auto k = fields_.one_of<K>(n["kind"], f + ".kind",
                                     {{"plane", K::kPlane},
                                      {"cylinder", K::kCylinder},
                                      {"sphere", K::kSphere},
                                      {"box", K::kBox}})) {
        m.kind = *k;
      }
    }
    if (n["origin_m"]) {
      if (auto v = fields_.vec3(n["origin_m"], f + ".origin_m")) m.origin_m = *v;
    }
    if (n["axis"]) {
      if (auto v = fields_.direction(n["axis"], f + ".axis")) m.axis = *v;
    }
    if (n["tile_m"]) parse_mapping_tile(n["tile_m"], f + ".tile_m", m);
    if (n["repeat"]) parse_mapping_repeat(n["repeat"], f + ".repeat", m);
  }

  void parse_mapping_tile(const YAML::Node& n, const std::string& f, TextureMappingSpec& m) {
    if (!fields_.expect_list(n, f, "[u, v] in metres", 2)) return;
    for (size_t i = 0; i < 2; ++i) {
      if (auto v = fields_.number(n[i], f + "[" + std::to_string(i) + "]", 1e-5, 1.0,
                                  "from 1e-5 to 1 (m)"))
        m.tile_m[i] = *v;
    }
  }

  void parse_mapping_repeat(const YAML::Node& n, const std::string& f, TextureMappingSpec& m) {
    if (!fields_.expect_list(n, f, "[u, v] whole numbers", 2)) return;
    for (size_t i = 0; i < 2; ++i) {
      if (auto v = fields_.integer(n[i], f + "[" + std::to_string(i) + "]", 1, 1000))
        m.repeat[i] = *v;
    }
  }

  YamlFields& fields_;
  ScenarioFiles& files_;
};

}  // namespace

void parse_material(YamlFields& fields, ScenarioFiles& files, const YAML::Node& n,
                    const std::string& field, MaterialSpec& material) {
  MaterialParser(fields, files).parse(n, field, material);
}

}  // namespace lap::sim
