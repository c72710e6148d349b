#include "sim/setup/anatomy_assets.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "sim/setup/gltf_writer.h"
#include "sim/setup/png_writer.h"

namespace lap::sim {
namespace {

using json = nlohmann::ordered_json;

// Millimetre-rounded numbers would lose the centre line's shape; micrometres keep the file
// short and exact enough.
double um(double metres) { return std::round(metres * 1e6) / 1e6; }
json vec_um(const Eigen::Vector3d& v) { return json::array({um(v.x()), um(v.y()), um(v.z())}); }

constexpr haptics::Tissue kTissues[] = {
    haptics::Tissue::liver,  haptics::Tissue::gallbladder,   haptics::Tissue::bile_duct,
    haptics::Tissue::artery, haptics::Tissue::clip,          haptics::Tissue::duodenum,
    haptics::Tissue::fat,    haptics::Tissue::abdominal_wall};

json parameters_json(const haptics::AnatomyParameters& p) {
  return {{"liver_scale", p.liver_scale},
          {"gallbladder_length_m", p.gallbladder_length_m},
          {"gallbladder_width_m", p.gallbladder_width_m},
          {"hartmann_pouch_m", p.hartmann_pouch_m},
          {"cystic_duct_length_m", p.cystic_duct_length_m},
          {"cystic_duct_inner_diameter_m", p.cystic_duct_inner_diameter_m},
          {"cystic_duct_wall_m", p.cystic_duct_wall_m},
          {"cystic_duct_angle_deg", p.cystic_duct_angle_deg},
          {"cystic_duct_tortuosity_m", p.cystic_duct_tortuosity_m},
          {"cystic_duct_half_waves", p.cystic_duct_half_waves},
          {"common_hepatic_duct_length_m", p.common_hepatic_duct_length_m},
          {"common_bile_duct_diameter_m", p.common_bile_duct_diameter_m},
          {"cystic_artery_diameter_m", p.cystic_artery_diameter_m},
          {"hilum_fat", p.hilum_fat},
          {"midclavicular_port_caudal_m", p.midclavicular_port_caudal_m},
          {"anterior_axillary_port_caudal_m", p.anterior_axillary_port_caudal_m},
          {"anterior_axillary_port_lateral_m", p.anterior_axillary_port_lateral_m},
          {"camera_m", json::array({p.camera_x_m, p.camera_y_m, p.camera_z_m})}};
}

}  // namespace

Status save_anatomy(const haptics::GeneratedAnatomy& anatomy, const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return file_diagnostic(dir.string(), 0, "", "cannot create the folder: " + ec.message());
  json organs = json::array();
  for (const haptics::GeneratedOrgan& o : anatomy.organs) {
    GltfMaterial material;
    material.name = o.name;
    material.base_color_texture_uri = std::string(haptics::tissue_name(o.tissue)) + ".png";
    if (o.tissue == haptics::Tissue::clip) {
      material.metallic = 1.0;
      material.roughness = 0.3;
    } else {
      material.roughness = 0.35;  // wet serosa: glossy (estimate)
    }
    if (Status s = save_gltf(o.mesh, dir / (o.name + ".gltf"), material); !s.ok()) return s;
    const Eigen::AlignedBox3d box = o.mesh.bounds();
    organs.push_back({{"name", o.name},
                      {"file", o.name + ".gltf"},
                      {"texture", material.base_color_texture_uri},
                      {"vertices", o.mesh.vertex_count()},
                      {"triangles", o.mesh.triangle_count()},
                      {"bounds_min_m", vec_um(box.min())},
                      {"bounds_max_m", vec_um(box.max())}});
  }
  const haptics::CysticDuctReport& d = anatomy.cystic_duct;
  json centre = json::array();
  for (const Eigen::Vector3d& c : d.centre_line_m) centre.push_back(vec_um(c));
  json ports = json::array();
  for (const haptics::PortSite& p : anatomy.ports) {
    ports.push_back({{"name", p.name},
                     {"position_m", vec_um(p.position_m)},
                     {"inward", vec_um(p.inward)},
                     {"diameter_m", p.diameter_m}});
  }
  json j;
  j["preset"] = anatomy.parameters.name;
  j["units"] = "metres; y up, +x medial, +z towards the laparoscope";
  j["parameters"] = parameters_json(anatomy.parameters);
  j["cystic_duct"] = {{"length_m", um(d.length_m)},
                      {"inner_diameter_m", d.inner_diameter_m},
                      {"outer_diameter_m", um(d.outer_diameter_m)},
                      {"wall_m", d.wall_m},
                      {"axis", vec_um(d.axis)},
                      {"angle_to_common_hepatic_duct_deg",
                       std::round(d.angle_to_common_hepatic_duct_deg * 10) / 10},
                      {"junction_m", vec_um(d.junction_m)},
                      {"incision",
                       {{"center_m", vec_um(d.incision_center_m)},
                        {"normal", vec_um(d.incision_normal)},
                        {"along", vec_um(d.incision_along)},
                        {"arc_from_neck_m", um(d.incision_arc_m)}}},
                      {"centre_line_m", centre}};
  j["common_bile_duct"] = {
      {"axis_point_m", vec_um(anatomy.common_bile_duct_point_m)},
      {"up", vec_um(anatomy.common_bile_duct_up)},
      {"common_hepatic_duct_length_m", um(anatomy.common_hepatic_duct_length_m)}};
  j["ports"] = ports;
  j["organs"] = organs;
  std::ofstream out(dir / "anatomy.json");
  out << j.dump(1) << "\n";
  if (!out) return file_diagnostic((dir / "anatomy.json").string(), 0, "", "cannot write");
  return {};
}

Status save_albedo_textures(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return file_diagnostic(dir.string(), 0, "", "cannot create the folder: " + ec.message());
  for (haptics::Tissue t : kTissues) {
    const std::filesystem::path file = dir / (std::string(haptics::tissue_name(t)) + ".png");
    if (Status s = save_png(haptics::make_albedo(t, kAlbedoSizePx), file); !s.ok()) return s;
  }
  return {};
}

Status save_anatomy_presets(const std::filesystem::path& root,
                            const std::vector<std::string>& presets) {
  for (const std::string& name : presets) {
    haptics::AnatomyParameters p;
    if (!haptics::anatomy_preset(name, &p)) {
      return diagnostic("unknown anatomy preset '" + name +
                        "' (expected default, easy, moderate, " + "hard or all)");
    }
    if (Status s = save_anatomy(haptics::generate_anatomy(p), root / name); !s.ok()) return s;
    if (Status s = save_albedo_textures(root / name); !s.ok()) return s;
  }
  return {};
}

}  // namespace lap::sim
