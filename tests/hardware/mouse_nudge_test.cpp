// The mouse's gestures on the operative field, as nudges of the active tool
// (hardware/mouse_nudge.h).

#include "hardware/mouse_nudge.h"

#include <gtest/gtest.h>

namespace lap::hardware {
namespace {

// The mouse's gestures with Ctrl (app/vtk_view.cpp), in a view looking down -z with +y up: a drag
// 10 pixels right and 5 down moves the handle 2 mm along +x and 1 mm along -y; a notch of the
// wheel 2 mm into the picture (0.5 mm with Shift, 0.25 mm for an eighth of a notch); a middle
// drag 40 pixels right turns it 0.2 rad; a right drag 40 pixels down closes the jaws 0.2 rad.
TEST(ToolNudge, TheMousesGesturesMoveOpenAndTurnByTheirScales) {
  const Eigen::Vector3d right(1, 0, 0);
  const Eigen::Vector3d up(0, 1, 0);
  const Eigen::Vector3d into(0, 0, -1);
  EXPECT_LT((mouse_drag_nudge(10, 5, right, up).delta_W - Eigen::Vector3d(0.002, -0.001, 0)).norm(),
            1e-15);
  EXPECT_LT((mouse_wheel_nudge(1.0, into, false).delta_W - Eigen::Vector3d(0, 0, -0.002)).norm(),
            1e-15);
  EXPECT_LT((mouse_wheel_nudge(1.0, into, true).delta_W - Eigen::Vector3d(0, 0, -0.0005)).norm(),
            1e-15);
  EXPECT_LT(
      (mouse_wheel_nudge(-0.125, into, false).delta_W - Eigen::Vector3d(0, 0, 0.00025)).norm(),
      1e-15);
  EXPECT_NEAR(mouse_roll_nudge(40).roll_rad, 0.2, 1e-15);
  EXPECT_NEAR(mouse_jaws_nudge(40).opening_rad, -0.2, 1e-15);
  EXPECT_NEAR(mouse_jaws_nudge(-10).opening_rad, 0.05, 1e-15);
  // Each gesture moves one thing only.
  EXPECT_EQ(mouse_drag_nudge(10, 5, right, up).opening_rad, 0.0);
  EXPECT_EQ(mouse_roll_nudge(40).delta_W, Eigen::Vector3d::Zero());
  EXPECT_EQ(mouse_jaws_nudge(40).roll_rad, 0.0);
}

}  // namespace
}  // namespace lap::hardware
