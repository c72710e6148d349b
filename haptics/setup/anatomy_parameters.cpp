#include "haptics/setup/anatomy_parameters.h"

namespace lap::haptics {

namespace {
// Every patient is shown as for cholangiography, the gallbladder retracted (its fundus held up
// over the liver, anatomy_parameters.h); the struct's default of 0 is the textbook position.
constexpr double kRetractionDeg = 30.0;
}  // namespace

std::vector<std::string> anatomy_preset_names() { return {"default", "easy", "moderate", "hard"}; }

bool anatomy_preset(std::string_view name, AnatomyParameters* out) {
  AnatomyParameters p;  // default: textbook anatomy, the defaults of the struct
  p.name = std::string(name);
  if (name == "default") {
    // The textbook sizes (the struct's defaults), retracted as the others.
    p.gallbladder_retraction_deg = kRetractionDeg;
  } else if (name == "easy") {
    // A long, wide, straight duct leaving at an open angle, a lean hilum: the duct is easy to
    // see, to hold and to cannulate.
    p.gallbladder_retraction_deg = kRetractionDeg;
    p.cystic_duct_length_m = 0.038;
    p.cystic_duct_inner_diameter_m = 0.0038;
    p.cystic_duct_angle_deg = 55.0;
    p.hilum_fat = 0.8;
    p.gallbladder_length_m = 0.08;
    p.gallbladder_width_m = 0.031;
    p.liver_scale = 0.95;
  } else if (name == "moderate") {
    // A short duct (2.6 cm against the textbook 3.2) at a narrower angle than easy's, a high
    // junction (a short common hepatic duct), more fat and a bigger liver and gallbladder over
    // it: little room for the clip and the ductotomy, a more crowded view. The lumen is the
    // textbook 3 mm (2-4 mm, Gray's Anatomy, 41st ed., ch. 70): the expert's planned catheter
    // (sim/authoring/expert_run.h) does not stay in a lumen under 3 mm (an open defect,
    // docs/anatomy.md), so difficulty is graded by the duct's course, the fat and the liver.
    // Not shorter: at 2.2 cm the expert's run failed from every ductotomy site tried (25, 4-8 mm
    // from the neck), 7 of them through the wall just after reaching the 10 mm target depth
    // (scenarios/patient_moderate.yaml).
    p.gallbladder_retraction_deg = kRetractionDeg;
    p.cystic_duct_length_m = 0.026;
    p.cystic_duct_inner_diameter_m = 0.003;
    p.cystic_duct_angle_deg = 35.0;
    p.common_hepatic_duct_length_m = 0.025;
    p.hilum_fat = 1.4;
    p.liver_scale = 1.08;
    p.gallbladder_length_m = 0.09;
    p.gallbladder_width_m = 0.035;
    p.hartmann_pouch_m = 0.006;
    // Over this liver and gallbladder every line from the standard midclavicular site to the
    // duct beside the ductotomy passes through the gallbladder, so the left hand could not steady
    // the duct; 2 cm lower it reaches it (the planner's sweep of sites: 2, 3 and 4 cm lower did,
    // 1 cm lower did not; scenarios/patient_moderate.yaml).
    p.midclavicular_port_caudal_m = 0.02;
    // From the standard anterior axillary site the expert's shaft pressed 1.78 mm into the
    // gallbladder; 3 cm lower and 2 cm farther out it keeps 0.7 mm clear, the catheter it holds
    // 0.6 mm (plan-expert; scenarios/patient_moderate.yaml has the sweep).
    p.anterior_axillary_port_caudal_m = 0.03;
    p.anterior_axillary_port_lateral_m = 0.02;
  } else if (name == "hard") {
    // Narrow, tortuous duct running down nearly parallel to the common hepatic duct to join it
    // low (a low insertion: a long common hepatic duct), in a fatty hilum, under a big liver:
    // the duct and the common hepatic duct look alike side by side, where misidentification is
    // the classic bile duct injury. A low insertion needs a duct long enough to reach down to
    // it, so this duct is not short (the short duct is `moderate`'s). The lumen is the textbook
    // 3 mm, as moderate's (why: there); the duct's course, the fat and the liver make it hard.
    p.gallbladder_retraction_deg = kRetractionDeg;
    p.cystic_duct_length_m = 0.038;
    p.cystic_duct_inner_diameter_m = 0.003;
    p.cystic_duct_tortuosity_m = 0.0015;
    p.cystic_duct_half_waves = 2;
    p.cystic_duct_angle_deg = 18.0;
    p.common_hepatic_duct_length_m = 0.04;
    p.hilum_fat = 2.0;
    p.liver_scale = 1.15;
    p.gallbladder_length_m = 0.095;
    p.gallbladder_width_m = 0.038;
    p.hartmann_pouch_m = 0.007;
  } else {
    return false;
  }
  *out = p;
  return true;
}

}  // namespace lap::haptics
