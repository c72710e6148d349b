#include "haptics/haptic_object.h"

#include "haptics/friction.h"
#include "haptics/segment_database.h"

namespace lap::haptics {

const char* surface_problem(const HapticObject& object) {
  if (object.shading != nullptr && object.texture != nullptr) {
    return "force shading and a texture on one object: both change its shape and are not "
           "combined (thesis 6.6)";
  }
  if (object.texture != nullptr && !(object.texture_k >= 0.0)) return "texture K must be >= 0";
  if (object.segments != nullptr && object.segments->two_sided() != object.two_sided) {
    return "the segment database and the object disagree on whether it is two-sided";
  }
  if (object.friction != nullptr && object.friction->problem()[0] != '\0') {
    return object.friction->problem();
  }
  return "";
}

}  // namespace lap::haptics
