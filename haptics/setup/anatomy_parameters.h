#pragma once
/// \file
/// The numbers that make one generated patient (haptics/setup/anatomy_generator.h): sizes of the
/// liver, gallbladder and ducts, the cystic duct's course, the fat in the hilum. The named
/// presets are the project's graded patients: `default` (the textbook anatomy), `easy`,
/// `moderate` and `hard`.
///
/// Frame (as the stand-ins and scenarios/default.yaml): metres, y up (liver above the
/// gallbladder), +x medial (from the gallbladder towards the common bile duct), +z towards the
/// laparoscope at the umbilical port; the duct lies near the origin.

#include <string>
#include <string_view>
#include <vector>

namespace lap::haptics {

struct AnatomyParameters {
  std::string name = "default";

  /// Liver size relative to the textbook adult liver (about 18 x 9 x 14 cm at 1.0; Gray's
  /// Anatomy, 41st ed., ch. 70: transverse about 20 cm, antero-posterior 10-12.5 cm, vertical
  /// 15-17.5 cm at the right lobe). Scaled about the gallbladder fossa, so the gallbladder stays
  /// in its bed.
  double liver_scale = 1.0;

  /// Gallbladder length, neck tip to fundus tip, and body width [m]. 7-10 cm long and 3-4 cm
  /// wide (Gray's Anatomy, 41st ed., ch. 70; Sabiston Textbook of Surgery, 21st ed., ch. 54:
  /// "7 to 10 cm long", capacity 30-50 mL).
  double gallbladder_length_m = 0.085;
  double gallbladder_width_m = 0.032;
  /// Hartmann's pouch: how far the neck's bulge stands out beyond the neck [m] (estimate).
  double hartmann_pouch_m = 0.005;

  /// How far the gallbladder is retracted, turned about its neck so the fundus goes cephalad
  /// [deg]: 0 lies in its fossa under the liver. Before cholangiography the assistant holds the
  /// fundus up over the liver to open Calot's triangle (Sabiston Textbook of Surgery, 21st ed.,
  /// ch. 54, laparoscopic cholecystectomy: "the fundus of the gallbladder is grasped and
  /// retracted cephalad over the liver"); the liver's free edge is lifted with it. The duct
  /// keeps its course from the neck (the neck is the pivot).
  double gallbladder_retraction_deg = 0.0;

  /// Cystic duct: centre-line length from the gallbladder neck to the common bile duct's wall,
  /// inside diameter and wall [m]. 2-4 cm long, 2-3 mm inside (up to 4 mm; Gray's Anatomy,
  /// 41st ed., ch. 70; Sabiston ch. 54: "2 to 4 cm" long). Wall 1 mm: estimate, as the stand-in
  /// (docs/tissue-parameters.md).
  double cystic_duct_length_m = 0.032;
  double cystic_duct_inner_diameter_m = 0.003;
  double cystic_duct_wall_m = 0.001;
  /// Angle between the cystic duct and the common hepatic duct where they join [deg]: an
  /// acute angle of about 40 degrees is usual; a small angle is a parallel course (estimate).
  double cystic_duct_angle_deg = 40.0;
  /// Tortuosity: peak sideways excursion of the centre line from a smooth course [m] and the
  /// number of half waves (an S is 2). 0 is a smooth duct.
  double cystic_duct_tortuosity_m = 0.0;
  int cystic_duct_half_waves = 2;
  /// Common hepatic duct length from the hilum to the junction [m]: 3-4 cm usual (Gray's
  /// Anatomy, 41st ed., ch. 70: "about 3 cm"); longer is a low insertion of the cystic duct.
  double common_hepatic_duct_length_m = 0.03;
  /// Outer diameter of the common hepatic and common bile duct [m]: about 6-8 mm (Gray's
  /// Anatomy, 41st ed., ch. 70: common bile duct "about 6 mm" in diameter; up to 8 mm is taken
  /// as normal in adults on imaging, Sabiston ch. 54).
  double common_bile_duct_diameter_m = 0.007;
  /// Cystic artery outer diameter [m]: 1-2 mm (estimate, after standard surgical texts).
  double cystic_artery_diameter_m = 0.0018;

  /// Fat over the hepatoduodenal ligament and in Calot's triangle: 1 is a lean hilum, 2 a fatty
  /// one (the fat's size across, relative; estimate).
  double hilum_fat = 1.0;

  /// Where the two right-sided ports sit against their standard sites [m]: how much lower
  /// (caudal: -y, towards the pelvis) and, for the anterior axillary one, how much farther from
  /// the midline (lateral: -x). A surgeon places these ports where the instruments reach Calot's
  /// triangle past the liver and the gallbladder, so their sites move with the patient: over a
  /// bigger liver and gallbladder the standard sites' shafts meet the gallbladder. Estimates: how
  /// far is found with the expert's planner (each patient's scenario says how). The abdominal
  /// wall's patch widens to keep wall round a port moved near its rim.
  double midclavicular_port_caudal_m = 0.0;
  double anterior_axillary_port_caudal_m = 0.0;
  double anterior_axillary_port_lateral_m = 0.0;

  /// The laparoscope the incision faces (scenarios/default.yaml's camera) [m].
  double camera_x_m = 0.03;
  double camera_y_m = -0.02;
  double camera_z_m = 0.26;
};

/// The named presets: "default", "easy", "moderate", "hard" (see anatomy_parameters.cpp for
/// what each varies and why).
[[nodiscard]] std::vector<std::string> anatomy_preset_names();
/// A preset by name; false when there is no such preset.
[[nodiscard]] bool anatomy_preset(std::string_view name, AnatomyParameters* out);

}  // namespace lap::haptics
