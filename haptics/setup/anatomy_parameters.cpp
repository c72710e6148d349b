#include "haptics/setup/anatomy_parameters.h"

namespace lap::haptics {

namespace {
// The patients are shown as for cholangiography, the gallbladder retracted (its fundus held up
// over the liver, anatomy_parameters.h): the default keeps the textbook position.
constexpr double kRetractionDeg = 30.0;
}  // namespace

std::vector<std::string> anatomy_preset_names() { return {"default", "easy", "moderate", "hard"}; }

bool anatomy_preset(std::string_view name, AnatomyParameters* out) {
  AnatomyParameters p;  // default: textbook anatomy, the defaults of the struct
  p.name = std::string(name);
  if (name == "default") {
    // nothing to change
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
    // A short, narrower duct at the usual angle (little room for the clip and the
    // ductotomy), a little more fat and a bigger liver over it.
    p.gallbladder_retraction_deg = kRetractionDeg;
    p.cystic_duct_length_m = 0.022;
    p.cystic_duct_inner_diameter_m = 0.0025;
    p.cystic_duct_angle_deg = 35.0;
    p.common_hepatic_duct_length_m = 0.025;
    p.hilum_fat = 1.4;
    p.liver_scale = 1.08;
    p.gallbladder_length_m = 0.09;
    p.gallbladder_width_m = 0.035;
    p.hartmann_pouch_m = 0.006;
  } else if (name == "hard") {
    // Narrow, tortuous duct running down nearly parallel to the common hepatic duct to join it
    // low (a low insertion: a long common hepatic duct), in a fatty hilum, under a big liver:
    // the duct and the common hepatic duct look alike side by side, where misidentification is
    // the classic bile duct injury. A low insertion needs a duct long enough to reach down to
    // it, so this duct is not short (the short duct is `moderate`'s).
    p.gallbladder_retraction_deg = kRetractionDeg;
    p.cystic_duct_length_m = 0.038;
    p.cystic_duct_inner_diameter_m = 0.0021;
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
