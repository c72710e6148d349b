#pragma once
/// \file
/// The project's procedural hepatobiliary anatomy (issue 22): liver with the gallbladder fossa,
/// gallbladder (fundus, body, neck, Hartmann's pouch), cystic duct, common hepatic and common
/// bile duct, cystic artery with its clips, duodenum, the fat over the hepatoduodenal ligament
/// and the abdominal wall with the ports, from AnatomyParameters (anatomy_parameters.h).
///
/// Every organ is a closed, outward-oriented triangle mesh in metres with per-vertex normals and
/// texture coordinates. The ducts follow the stand-in cystic duct's convention
/// (make_stand_in_cystic_duct): a closed tube whose surface is the duct's outer wall (inside
/// diameter + 2 walls across), capped at both ends, which sim/setup/duct_fit.h turns into the
/// two-sided modal shell. Texture coordinates are a planar projection along z (the laparoscope's
/// axis) divided by the organ's texture tile: no seams, so the closed meshes stay closed when
/// the loader welds coincident vertices; the albedo images tile (albedo_texture.h).

#include <string>
#include <vector>

#include "haptics/setup/albedo_texture.h"
#include "haptics/setup/anatomy_parameters.h"
#include "haptics/triangle_mesh.h"

namespace lap::haptics {

/// One generated organ: its mesh and how it is coloured.
struct GeneratedOrgan {
  std::string name;   ///< file stem: "liver", "cystic_duct", ...
  TriangleMesh mesh;  ///< closed, outward, normals and uvs set [m]
  Tissue tissue = Tissue::liver;
  double texture_tile_m = 0.05;  ///< the albedo image repeats every this many metres
};

/// What a scenario needs to place the ductotomy and the catheter on the generated cystic duct.
struct CysticDuctReport {
  /// Centre line from the gallbladder neck (first) to the common bile duct's wall (last) [m].
  std::vector<Eigen::Vector3d> centre_line_m;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  ///< unit, first to last centre-line point
  double length_m = 0.0;                            ///< arc length of the centre line
  double inner_diameter_m = 0.0;
  double outer_diameter_m = 0.0;
  double wall_m = 0.0;
  /// The ductotomy site: on the outer wall facing the laparoscope, 35 % of the way from the
  /// neck (between the clip at the gallbladder side and the common bile duct) [m].
  Eigen::Vector3d incision_center_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d incision_normal = Eigen::Vector3d::UnitZ();  ///< unit, outward
  Eigen::Vector3d incision_along = Eigen::Vector3d::UnitX();   ///< unit, the duct's tangent
  double incision_arc_m = 0.0;  ///< distance from the neck along the centre line
  /// Where the centre line meets the common bile duct's wall [m].
  Eigen::Vector3d junction_m = Eigen::Vector3d::Zero();
  /// The angle actually made with the common hepatic duct [deg].
  double angle_to_common_hepatic_duct_deg = 0.0;
};

/// A trocar site in the abdominal wall.
struct PortSite {
  std::string name;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  ///< on the wall's inner surface
  Eigen::Vector3d inward = -Eigen::Vector3d::UnitZ();    ///< unit, into the abdomen
  double diameter_m = 0.0;
};

/// A whole generated patient.
struct GeneratedAnatomy {
  AnatomyParameters parameters;
  std::vector<GeneratedOrgan> organs;  ///< liver, gallbladder, cystic_duct, ...
  CysticDuctReport cystic_duct;
  std::vector<PortSite> ports;
  /// The common hepatic + common bile duct's axis: a point at the junction and the unit
  /// direction up towards the hilum; its length above the junction (the common hepatic duct).
  Eigen::Vector3d common_bile_duct_point_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d common_bile_duct_up = Eigen::Vector3d::UnitY();
  double common_hepatic_duct_length_m = 0.0;

  /// The organ with this name, or nullptr.
  [[nodiscard]] const GeneratedOrgan* organ(const std::string& name) const;
};

/// Generates every organ of the patient; deterministic (same parameters, same numbers).
[[nodiscard]] GeneratedAnatomy generate_anatomy(const AnatomyParameters& p);

/// Closed tube around a centre line: rings of `slices` vertices of the given radius (one radius
/// per centre-line point), frames by parallel transport, capped with fans at both ends.
[[nodiscard]] TriangleMesh make_tube(const std::vector<Eigen::Vector3d>& centre,
                                     const std::vector<double>& radius, int32_t slices);

}  // namespace lap::haptics
