// The fast picture's resolution held to 30 frames/s (app/dynamic_resolution.h): smaller below,
// larger well above, unchanged between, never past its bounds.

#include "app/dynamic_resolution.h"

#include <gtest/gtest.h>

#include <limits>

namespace lap::app {
namespace {

TEST(DynamicResolution, TheFastPictureShrinksBelowThirtyFramesAndGrowsWellAbove) {
  // Below 30.9 frames/s: 7 % smaller; above 40.5: 5 % larger; between: unchanged.
  EXPECT_NEAR(next_scene_scale(0.7, 20.0), 0.7 * 0.93, 1e-12);
  EXPECT_NEAR(next_scene_scale(0.7, 30.5), 0.7 * 0.93, 1e-12);
  EXPECT_EQ(next_scene_scale(0.7, 31.0), 0.7);
  EXPECT_EQ(next_scene_scale(0.7, 40.0), 0.7);
  EXPECT_NEAR(next_scene_scale(0.7, 41.0), 0.7 * 1.05, 1e-12);
  // Never past its bounds, however slow or fast.
  EXPECT_EQ(next_scene_scale(kMinSceneScale, 5.0), kMinSceneScale);
  EXPECT_EQ(next_scene_scale(0.99, 200.0), 1.0);
  // A second without frames (a hidden window) or a rate that is not a number changes nothing.
  EXPECT_EQ(next_scene_scale(0.7, 0.0), 0.7);
  EXPECT_EQ(next_scene_scale(0.7, std::numeric_limits<double>::quiet_NaN()), 0.7);
  // Held at 20 frames/s it reaches the floor and stays; at 60 it reaches 1.
  double s = 0.7;
  for (int k = 0; k < 30; ++k) s = next_scene_scale(s, 20.0);
  EXPECT_EQ(s, kMinSceneScale);
  for (int k = 0; k < 30; ++k) s = next_scene_scale(s, 60.0);
  EXPECT_EQ(s, 1.0);
}

}  // namespace
}  // namespace lap::app
