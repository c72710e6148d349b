// The session the trainee window runs with keyboard-driven tools (app/live_session.h): what a
// key's nudge does to the instrument, read back from the running loops' snapshots.

#include "app/live_session.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "sim/setup/scene.h"
#include "tests/test_support.h"

namespace lap::app {
namespace {

// The right tool as the haptic loop last saw its device, once the loop has passed `tick` (the
// snapshot's tick through *seen); false after 5 s without.
bool right_tool_after(LiveSession& live, int64_t tick, haptics::GripperPose* pose, int64_t* seen) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (std::chrono::steady_clock::now() < give_up) {
    const sim::HapticSnapshot& h = live.haptic();
    if (h.tick > tick) {
      *pose = h.tools[1].pose;
      *seen = h.tick;
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return false;
}

// A nudge that moves the handle only.
hardware::ToolNudge handle_move(const Eigen::Vector3d& delta_W) {
  hardware::ToolNudge n;
  n.delta_W = delta_W;
  return n;
}

// The roll keys (, and .): the jaws' opening direction turns about the shaft by the angle asked,
// right-handed about the shaft from the handle to the tip, and nothing else about the tool moves.
// The second and third turns come after the handle has moved (the shaft pivoted in its port):
// each turn is about the shaft where it is then, in the world (a turn about the handle's own
// axes, or about the shaft's first direction, would fail them).
TEST(LiveSession, TheRollTurnsTheJawsAboutTheShaftByTheAngleAsked) {
  const sim::SceneLoadResult scene =
      sim::load_scene_file(test::source_dir() / "scenarios/introductory.yaml");
  ASSERT_TRUE(scene.ok()) << scene.message();
  LiveSession live;
  ASSERT_TRUE(live.start(scene.value(), {}).ok());  // both tools simulated (keyboard-driven)
  ASSERT_TRUE(live.keyboard_driven(1));
  haptics::GripperPose before;
  int64_t seen = 0;
  ASSERT_TRUE(right_tool_after(live, 20, &before, &seen));
  for (const double roll : {0.5, -0.2, 0.3}) {
    if (roll != 0.5) {  // the handle moved 3-4 cm first: the shaft pivots
      live.nudge(1, handle_move(Eigen::Vector3d(0.03, 0.0, 0.02)));
      haptics::GripperPose moved;
      // At the hand's 50 mm/s (hardware::SimulatedHandSpeeds), the 3.6 cm take 0.72 s.
      ASSERT_TRUE(right_tool_after(live, seen + 1500, &moved, &seen));
      ASSERT_GT(std::acos(std::clamp(moved.shaft_dir_W.dot(before.shaft_dir_W), -1.0, 1.0)), 0.05)
          << "the shaft did not pivot";
      before = moved;
    }
    hardware::ToolNudge turn;
    turn.roll_rad = roll;
    live.nudge(1, turn);
    haptics::GripperPose after;
    // The device turns the handle at the hand's 2.5 rad/s: half a radian in 0.2 s.
    ASSERT_TRUE(right_tool_after(live, seen + 600, &after, &seen));
    const Eigen::Vector3d to_tip = -before.shaft_dir_W;
    const double turned = std::atan2(before.open_dir_W.cross(after.open_dir_W).dot(to_tip),
                                     before.open_dir_W.dot(after.open_dir_W));
    EXPECT_NEAR(turned, roll, 1e-9);
    EXPECT_NEAR(after.open_dir_W.dot(to_tip), 0.0, 1e-12);
    EXPECT_LT((after.hinge_W - before.hinge_W).norm(), 1e-12);
    EXPECT_LT((after.shaft_dir_W - before.shaft_dir_W).norm(), 1e-12);
    EXPECT_EQ(after.opening_rad, before.opening_rad);
    before = after;
  }
  live.stop();
}

// A key held against the edge of the device's workspace does not wind up: the handle's input
// stops at the edge, so the first press back moves it (hardware::nudged with the device's own
// workspace).
TEST(LiveSession, AHandlePushedPastTheWorkspaceComesBackWithTheFirstPressBack) {
  const sim::SceneLoadResult scene =
      sim::load_scene_file(test::source_dir() / "scenarios/introductory.yaml");
  ASSERT_TRUE(scene.ok()) << scene.message();
  LiveSession live;
  ASSERT_TRUE(live.start(scene.value(), {}).ok());
  const double edge_x = hardware::DeviceLimits{}.workspace_W.max().x();  // the device's own
  live.nudge(1, handle_move(Eigen::Vector3d(5.0, 0.0, 0.0)));  // far past the workspace's +x face
  EXPECT_EQ(live.input(1).position_W.x(), edge_x);
  live.nudge(1, handle_move(Eigen::Vector3d(-0.02, 0.0, 0.0)));
  EXPECT_NEAR(live.input(1).position_W.x(), edge_x - 0.02, 1e-12);
  live.stop();
}

}  // namespace
}  // namespace lap::app
