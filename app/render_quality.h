#pragma once
/// \file
/// How much the operative field's picture costs to draw. A GPU draws the full picture (textures
/// filtered with mipmaps, the scope's tip light a spot whose brightness falls with distance, the
/// scene at the window's resolution) in a few milliseconds; Mesa's software renderer (llvmpipe,
/// on a station without a GPU) needs several times the 33 ms a 30 frames/s picture allows. The
/// fast profile gives up, in order of what they cost there (docs/benchmarks.md): trilinear
/// mipmap filtering (textures filtered bilinearly), the second light and the tip light's spot
/// and fall-off with distance (one light at the camera, where the scope's fibres nearly are:
/// what the tip nears no longer glares), and part of the 3D picture's resolution
/// (ScaledScenePass: 0.7 of each side to start with, then adjusted once a second towards 30
/// frames/s within 0.5 to 1 of each side, dynamic_resolution.h; the heads-up display stays
/// sharp). On the 2-core machine measured, the hardest patient needs the floor and is drawn at
/// 23-31 frames/s there (docs/benchmarks.md). `auto` picks fast on a software renderer and full
/// otherwise.

#include <QString>
#include <optional>
#include <string_view>

namespace lap::app {

enum class RenderQualityChoice { kAuto, kFull, kFast };

struct RenderProfile {
  bool fast = false;    ///< which of the two profiles this is
  bool mipmaps = true;  ///< organ textures filtered with mipmaps (trilinear)
  /// The scope's tip light a spot that falls off with distance, and a fill for the abdomen's
  /// scattered light; else one light at the camera (LaparoscopeCamera::set_spot_light).
  bool spot_light = true;
  double scene_scale = 1.0;  ///< the 3D picture's side as a fraction of the window's
  friend bool operator==(const RenderProfile&, const RenderProfile&) = default;
};

/// "auto", "full" or "fast" (as typed: --render-quality, the settings); nothing otherwise.
[[nodiscard]] std::optional<RenderQualityChoice> parse_render_quality(const QString& text);
[[nodiscard]] QString render_quality_name(RenderQualityChoice choice);

/// Whether an OpenGL renderer string (GL_RENDERER) names a software rasterizer: Mesa's
/// llvmpipe, softpipe or swrast.
[[nodiscard]] bool is_software_renderer(std::string_view gl_renderer);

/// The profile for `choice` on the renderer named `gl_renderer` ("" before it is known: auto
/// then means full until the first frame tells).
[[nodiscard]] RenderProfile render_profile(RenderQualityChoice choice,
                                           std::string_view gl_renderer);

}  // namespace lap::app
