#include "app/dynamic_resolution.h"

#include <algorithm>

namespace lap::app {

double next_scene_scale(double scale, double frames_per_s) {
  constexpr double kTarget = 30.0;  // frames/s: the application issue's target
  if (!(frames_per_s > 0.0)) return scale;
  if (frames_per_s < kTarget * 1.03) return std::max(kMinSceneScale, scale * 0.93);
  if (frames_per_s > kTarget * 1.35) return std::min(1.0, scale * 1.05);
  return scale;
}

}  // namespace lap::app
