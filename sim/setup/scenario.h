#pragma once
/// \file
/// A scenario v1 as loaded from YAML: plain data in SI units, paths already resolved. The schema
/// is documented in scenarios/README.md.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "models/model_kind.h"

namespace lap::sim {

/// How an image texture is wrapped onto the organ (thesis §6.3.3, two-stage mapping): the
/// intermediate surface, placed in the organ's mesh frame.
struct TextureMappingSpec {
  enum class Kind { kPlane, kCylinder, kSphere, kBox };
  Kind kind = Kind::kPlane;
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();  ///< centre, mesh frame [m]
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();     ///< plane normal / cylinder or pole axis
  std::array<double, 2> tile_m = {0.01, 0.01};         ///< plane, box: one image [m]; cylinder: v
  std::array<int, 2> repeat = {1, 1};                  ///< cylinder, sphere: image repeats
};

/// Surface texture of a material (thesis §6.3).
struct TextureSpec {
  enum class Kind { kNone, kImage, kProcedural };
  Kind kind = Kind::kNone;
  std::filesystem::path image;  ///< kImage: PNG/JPEG height map
  std::string function;         ///< kProcedural: perlin, fbm, worley, fourier
  double amplitude_m = 0.0;     ///< peak height of the texture [m]
  double wavelength_m = 0.0;    ///< spatial period or feature size [m]
  double k_mix = 1.5;           ///< K of eq. 6-4
  int octaves = 4;              ///< fbm
  uint32_t seed = 1;            ///< perlin, fbm, worley
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  ///< fourier: the wave's direction
  TextureMappingSpec mapping;                            ///< image
  int line = 0;                                          ///< where it starts, for messages
};

/// Force shading of a material (thesis §6.1).
struct ShadingSpec {
  bool enabled = false;
  double crease_angle_deg = 30.0;  ///< faces meeting at more stay a sharp edge
};

/// Where the friction coefficients vary over the surface (thesis §6.2).
struct FrictionMapSpec {
  enum class Kind { kUniform, kPeriodic, kRandom };
  Kind kind = Kind::kUniform;
  double period_m = 0.005;        ///< periodic
  double amplitude = 0.5;         ///< periodic, relative, [0, 1)
  double grain_m = 0.0005;        ///< random: grain size [m]
  double relative_std_dev = 0.3;  ///< random: standard deviation / mean
  uint32_t seed = 1;              ///< random
};

/// Haptic and mechanical material of an organ.
struct MaterialSpec {
  double stiffness_n_per_m = 0.0;  ///< contact spring [N/m]
  double damping_n_s_per_m = 0.0;  ///< contact damper [N s/m]
  double friction_static = 0.0;    ///< coefficient, dimensionless
  double friction_dynamic = 0.0;   ///< coefficient, dimensionless, <= static
  /// k_s [N/m]; 0 = the contact stiffness.
  double friction_stick_stiffness_n_per_m = 0.0;
  /// k_d [N/m]; 0 = k_s * friction_dynamic / friction_static (proportional, §6.2).
  double friction_slide_stiffness_n_per_m = 0.0;
  /// Coulomb coefficient between the catheter and this organ (its lumen, for the duct), as the
  /// catheter's model applies it (models/catheter_contacts.h); 0: frictionless.
  double catheter_friction = 0.0;
  FrictionMapSpec friction_map;
  ShadingSpec shading;
  TextureSpec texture;
};

/// The ductotomy the catheter enters by (thesis §7.4, Figure 7-18): an opening in the wall of a
/// modal-shell duct, an ellipse on the wall around `center_m`, `length_m` along the duct and
/// `width_m` around it (arc length). The catheter's contacts treat the wall's faces inside it
/// as open (sim/setup/tissue_model.h).
struct IncisionSpec {
  bool present = false;
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();  ///< world frame, on the duct's wall
  double length_m = 0.003;
  double width_m = 0.002;
  int line = 0;  ///< where it is in the file, for later messages
};

/// A `rigid` organ's dynamics (thesis §6.4): given, the organ is a free rigid body of this mass,
/// uniformly dense (its centre of mass and inertia from its closed mesh, models/mass_properties.h),
/// pushed by the tools; absent, it is fixed where it is placed (an anchored obstacle).
struct DynamicsSpec {
  bool present = false;
  double mass_kg = 0.0;
  double linear_damping_per_s = 0.0;   ///< momentum decay rate (drag) [1/s]
  double angular_damping_per_s = 0.0;  ///< angular momentum decay rate [1/s]
  int line = 0;                        ///< where it is in the file, for later messages
};

/// One organ: a mesh placed in the world with a material and a model kind.
struct OrganSpec {
  std::string name;
  std::filesystem::path mesh;  ///< resolved, absolute
  double scale = 1.0;          ///< file units to metres
  bool repair = false;         ///< opt-in mesh repair at load
  Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_deg = Eigen::Vector3d::Zero();   ///< about fixed x, then y, then z
  Eigen::Vector3d color = Eigen::Vector3d(0.8, 0.5, 0.45);  ///< RGB in [0, 1]
  models::ModelKind model = models::ModelKind::kRigid;
  MaterialSpec material;
  IncisionSpec incision;  ///< modal-shell organs only
  DynamicsSpec dynamics;  ///< rigid organs only: a free body when present
  int line = 0;           ///< where the organ starts in the file, for later messages

  /// Mesh frame to world frame.
  [[nodiscard]] Eigen::Affine3d transform() const;
};

/// A trocar port on the abdominal wall through which one tool pivots (thesis §7.6.2).
struct TrocarSpec {
  std::string name;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
};

/// A laparoscopic tool: a shaft and two jaws, entering through a trocar.
struct ToolSpec {
  enum class Side { kLeft, kRight };
  std::string name;
  Side side = Side::kLeft;
  std::string trocar;
  /// grasper, dissector, clip-applier, scissors (the gripper's three segments), or a probe:
  /// `probe` (its tip rendered by the point proxy, chapter 4) or `ray-probe` (its shaft rendered
  /// as one line segment by the ray-based proxy, chapter 5).
  std::string kind = "grasper";
  double shaft_length_m = 0.36;
  double shaft_radius_m = 0.0025;
  double jaw_length_m = 0.02;
};

/// The virtual laparoscope (thesis §7.8): a scope through its own port, its objective and light
/// at its tip. `position_m` and `focal_point_m` give the view at the start (and the task
/// engine's fixed view cone, task_model.h); the scope pivots about `port_m`
/// (sim/runtime/laparoscope.h).
struct CameraSpec {
  Eigen::Vector3d position_m = Eigen::Vector3d(0.0, 0.25, 0.35);  ///< the scope's tip at start
  Eigen::Vector3d focal_point_m = Eigen::Vector3d(0.0, 0.03, 0.0);
  Eigen::Vector3d view_up = Eigen::Vector3d::UnitY();
  double view_angle_deg = 30.0;
  /// The scope's port on the abdominal wall, the pivot its shaft passes through [m]. Absent:
  /// kDefaultPortDepthM behind position_m on the line of sight.
  std::optional<Eigen::Vector3d> port_m;
  /// The optic's angle between the scope's axis and its line of sight [deg]: 0 (forward
  /// viewing) or 30 (the usual laparoscope for a cholecystectomy); up to 70.
  double optics_deg = 0.0;
  int line = 0;  ///< where the section starts, for later messages

  /// The generated anatomy's camera sits 12 mm inside its port (assets/anatomy/*/anatomy.json:
  /// parameters.camera_m against the umbilical port).
  static constexpr double kDefaultPortDepthM = 0.012;
  /// The port: port_m, or the default above.
  [[nodiscard]] Eigen::Vector3d port() const;
};

/// The catheter inserted into the cystic duct (thesis §7.7(3)).
struct CatheterSpec {
  /// The port it enters by (a trocar's name; its own, or an instrument's for a cholangiography
  /// clamp): its proximal end is held there. Empty: between the two tools' ports.
  std::string port;
  /// Where it lies at the start: straight from the port towards this point, for its length.
  /// Absent: towards the task's target, ending 2 cm short of it.
  std::optional<Eigen::Vector3d> aim_m;
  double length_m = 0.3;
  double diameter_m = 0.0025;
  int particles = 64;
  double mass_kg = 0.01;
  double bending_stiffness_n_m2 = 1.0e-4;  ///< EI [N m^2]
  int line = 0;                            ///< where the section starts, for later messages
  int length_line = 0;                     ///< where length_m is (its own line when given)
  int aim_line = 0;                        ///< where aim_m is (its own line when given)
};

/// What the resident must do (thesis §7.4), and what counts as an error; the task engine
/// (sim/setup/task_model.h, sim/runtime/task_engine.h) watches it. Defaults and their sources:
/// scenarios/README.md.
struct TaskSpec {
  std::string kind = "catheter-insertion";
  std::string target;               ///< organ name (the duct)
  double insertion_depth_m = 0.01;  ///< catheter inside the lumen that counts as the goal [m]
  double hold_s = 3.0;              ///< kept at that depth this long: success [s] (estimate)
  double time_limit_s = 600.0;
  /// A tool or the catheter pushing (or a grasp pulling) the duct harder than this for longer
  /// than duct_injury_time_s injures it [N] (estimate).
  double duct_injury_force_n = 2.0;
  double duct_injury_time_s = 1.0;
  /// The jaws squeezing the duct harder than this for longer than duct_injury_time_s crush it
  /// [N] (estimate, below the 15 N pinch that damaged pig cecum in Heijnsdijk et al., Surg
  /// Endosc 2004;18:974).
  double duct_squeeze_n = 5.0;
  /// The same for every other organ [N], [s] (estimates).
  double organ_injury_force_n = 5.0;
  double organ_injury_time_s = 2.0;
  /// A catheter held by no tool, its tip not in the lumen, this long: dropped [s] (estimate;
  /// shorter lets go and grasps again, hand over hand).
  double drop_grace_s = 1.0;
  /// An instrument's tip outside the laparoscope's view this long: out of view [s] (estimate).
  double out_of_view_grace_s = 3.0;
  /// Organs the instruments must not touch (names from organs).
  std::vector<std::string> forbidden_organs;
  /// The organ that is the common bile duct (closed, its lumen inside), or empty: the catheter's
  /// tip inside it is the error `common_bile_duct`.
  std::string common_bile_duct;
  /// The slant at which the expert's run (`laptrainer-cli plan-expert`,
  /// sim/authoring/expert_run.h) brings the catheter into the duct's wall, to its axis [deg];
  /// absent, the planner's 39. Not read by the task engine: an approach, not a rule.
  std::optional<double> expert_entry_slant_deg;
  int line = 0;  ///< where it is in the file, for later messages
};

/// An expert benchmark for one training metric (docs/metrics.md): the experts' mean and standard
/// deviation; a trainee meets it within two SDs of the mean on the side that counts (at most
/// mean + 2 SD where lower is better, at least mean − 2 SD where higher is).
struct MetricBenchmark {
  std::string metric;  ///< a training metric's name
  double mean = 0.0;
  double sd = 0.0;
  bool higher_is_better = false;
  int line = 0;
};

/// The scenario's proficiency benchmarks (`proficiency:`).
struct ProficiencySpec {
  std::string source;  ///< where the experts' figures come from
  std::vector<MetricBenchmark> metrics;
  int line = 0;
};

/// A whole scenario file.
struct Scenario {
  std::filesystem::path file;  ///< the scenario file itself
  /// FNV-1a 64 of the bytes parsed (sim/setup/content_digest.h): what a recorded session keeps,
  /// and what the file's digest at the session's end is compared with.
  uint64_t digest = 0;
  int version = 1;
  std::string name;
  std::string description;
  /// How hard the patient is for a trainee (`difficulty`): `introductory`, `easy`, `moderate`
  /// or `hard`; empty when the file does not say (the scenario chooser shows "not graded").
  std::string difficulty;
  std::vector<std::filesystem::path> allowed_paths;  ///< resolved
  CameraSpec camera;
  std::vector<OrganSpec> organs;
  std::vector<TrocarSpec> trocars;
  std::vector<ToolSpec> tools;
  std::optional<CatheterSpec> catheter;
  std::optional<TaskSpec> task;
  std::optional<ProficiencySpec> proficiency;

  /// The tool held in that hand, or nullptr.
  [[nodiscard]] const ToolSpec* tool(ToolSpec::Side side) const;
  /// The trocar of that name, or nullptr.
  [[nodiscard]] const TrocarSpec* trocar(const std::string& trocar_name) const;
};

}  // namespace lap::sim
