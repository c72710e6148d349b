// How the operative field is drawn (app/render_quality.h): the choice as typed, software
// renderers recognised by their GL_RENDERER names, and the two profiles.

#include "app/render_quality.h"

#include <gtest/gtest.h>

#include "app/dynamic_resolution.h"

namespace lap::app {
namespace {

TEST(RenderQuality, TheChoiceIsReadAsTypedAndNamedBack) {
  EXPECT_EQ(parse_render_quality("auto"), RenderQualityChoice::kAuto);
  EXPECT_EQ(parse_render_quality(" Full "), RenderQualityChoice::kFull);
  EXPECT_EQ(parse_render_quality("FAST"), RenderQualityChoice::kFast);
  EXPECT_FALSE(parse_render_quality("ultra").has_value());
  EXPECT_FALSE(parse_render_quality("").has_value());
  for (const auto c :
       {RenderQualityChoice::kAuto, RenderQualityChoice::kFull, RenderQualityChoice::kFast}) {
    EXPECT_EQ(parse_render_quality(render_quality_name(c)), c);
  }
}

TEST(RenderQuality, SoftwareRenderersAreKnownByName) {
  EXPECT_TRUE(is_software_renderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
  EXPECT_TRUE(is_software_renderer("Gallium 0.4 on softpipe"));
  EXPECT_TRUE(is_software_renderer("Software Rasterizer (swrast)"));
  EXPECT_FALSE(is_software_renderer("Mesa Intel(R) UHD Graphics 620 (KBL GT2)"));
  EXPECT_FALSE(is_software_renderer("NVIDIA GeForce RTX 3060/PCIe/SSE2"));
  EXPECT_FALSE(is_software_renderer(""));
}

TEST(RenderQuality, AutoIsFastOnASoftwareRendererAndFullOtherwise) {
  const RenderProfile full = render_profile(RenderQualityChoice::kFull, "llvmpipe");
  EXPECT_FALSE(full.fast);
  EXPECT_TRUE(full.mipmaps);
  EXPECT_TRUE(full.spot_light);
  EXPECT_EQ(full.scene_scale, 1.0);
  const RenderProfile fast = render_profile(RenderQualityChoice::kFast, "NVIDIA GeForce");
  EXPECT_TRUE(fast.fast);
  EXPECT_FALSE(fast.mipmaps);
  EXPECT_FALSE(fast.spot_light);
  EXPECT_LT(fast.scene_scale, 1.0);
  EXPECT_GE(fast.scene_scale, kMinSceneScale);
  EXPECT_EQ(render_profile(RenderQualityChoice::kAuto, "llvmpipe (LLVM 15)"), fast);
  EXPECT_EQ(render_profile(RenderQualityChoice::kAuto, "NVIDIA GeForce"), full);
  // Before the first frame names the renderer, auto draws the full picture.
  EXPECT_EQ(render_profile(RenderQualityChoice::kAuto, ""), full);
}

}  // namespace
}  // namespace lap::app
