#include "app/render_quality.h"

#include <algorithm>
#include <cctype>
#include <string>

namespace lap::app {

std::optional<RenderQualityChoice> parse_render_quality(const QString& text) {
  const QString t = text.trimmed().toLower();
  if (t == "auto") return RenderQualityChoice::kAuto;
  if (t == "full") return RenderQualityChoice::kFull;
  if (t == "fast") return RenderQualityChoice::kFast;
  return std::nullopt;
}

QString render_quality_name(RenderQualityChoice choice) {
  switch (choice) {
    case RenderQualityChoice::kFull:
      return "full";
    case RenderQualityChoice::kFast:
      return "fast";
    case RenderQualityChoice::kAuto:
      break;
  }
  return "auto";
}

bool is_software_renderer(std::string_view gl_renderer) {
  std::string lower(gl_renderer);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* name : {"llvmpipe", "softpipe", "swrast"}) {
    if (lower.find(name) != std::string::npos) return true;
  }
  return false;
}

RenderProfile render_profile(RenderQualityChoice choice, std::string_view gl_renderer) {
  const bool fast = choice == RenderQualityChoice::kFast ||
                    (choice == RenderQualityChoice::kAuto && is_software_renderer(gl_renderer));
  if (!fast) return {};
  // Started at 0.7 of each side, then adjusted (dynamic_resolution.h). With the other savings
  // on, the hardest patient measured 27.1 frames/s at 1280x720 and 34.6 at 1024x576 (0.8 of
  // each side; llvmpipe, the 2-core VM: docs/benchmarks.md); the default scenario settled at
  // 0.65.
  return {.fast = true, .mipmaps = false, .spot_light = false, .scene_scale = 0.7};
}

}  // namespace lap::app
