// The 3D mouse through libspnav, loaded at run time: here a stand-in library (tests/support/
// fake_spnav.cpp) with the same entry points, fed events by the test.

#include "hardware/space_mouse.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <utility>

namespace lap::hardware {
namespace {

// The stand-in's controls, from the same loaded library the mouse uses.
struct Fake {
  Fake() : handle(dlopen(LAP_FAKE_SPNAV, RTLD_NOW | RTLD_LOCAL)) {
    // NOLINTBEGIN(*-reinterpret-cast)
    set_daemon = reinterpret_cast<void (*)(int)>(dlsym(handle, "fake_spnav_set_daemon"));
    open_count = reinterpret_cast<int (*)()>(dlsym(handle, "fake_spnav_open_count"));
    motion = reinterpret_cast<void (*)(int, int, int, int, int, int)>(
        dlsym(handle, "fake_spnav_push_motion"));
    button = reinterpret_cast<void (*)(int, int)>(dlsym(handle, "fake_spnav_push_button"));
    raw = reinterpret_cast<void (*)(int)>(dlsym(handle, "fake_spnav_push_raw"));
    // NOLINTEND(*-reinterpret-cast)
  }
  ~Fake() { dlclose(handle); }
  Fake(const Fake&) = delete;
  Fake& operator=(const Fake&) = delete;
  Fake(Fake&&) = delete;
  Fake& operator=(Fake&&) = delete;
  void* handle;
  void (*set_daemon)(int) = nullptr;
  int (*open_count)() = nullptr;
  void (*motion)(int, int, int, int, int, int) = nullptr;
  void (*button)(int, int) = nullptr;
  void (*raw)(int) = nullptr;
};

TEST(SpaceMouse, WithoutTheLibraryItSaysWhatToInstall) {
  const Result<std::unique_ptr<SpaceMouse>> mouse = SpaceMouse::open("/nonexistent/libspnav.so.0");
  EXPECT_FALSE(mouse.ok());
  const std::string error = mouse.message();
  EXPECT_NE(error.find("libspnav0"), std::string::npos) << error;
  EXPECT_NE(error.find("spacenavd"), std::string::npos) << error;
}

TEST(SpaceMouse, WithoutTheDaemonItSaysToStartIt) {
  const Fake fake;
  ASSERT_NE(fake.set_daemon, nullptr);
  fake.set_daemon(0);
  const Result<std::unique_ptr<SpaceMouse>> mouse = SpaceMouse::open(LAP_FAKE_SPNAV);
  EXPECT_FALSE(mouse.ok());
  EXPECT_NE(mouse.message().find("spacenavd is not running"), std::string::npos) << mouse.message();
  fake.set_daemon(1);
}

// Each axis: nothing within the dead zone, then linear up to full speed at full scale, and no
// further; the mapping's signs applied. The twist about the vertical rolls the tool about its
// shaft, the same way. Buttons 0 and 1 close and open the jaws.
TEST(SpaceMouse, ThePuckSteersTheToolTip) {
  const Fake fake;
  Result<std::unique_ptr<SpaceMouse>> opened = SpaceMouse::open(LAP_FAKE_SPNAV);
  ASSERT_TRUE(opened.ok()) << opened.message();
  std::unique_ptr<SpaceMouse> mouse = std::move(opened).value();
  ASSERT_NE(mouse, nullptr);
  EXPECT_EQ(fake.open_count(), 1);
  SpaceMouseMapping m;
  m.axis_sign = Eigen::Vector3d(1.0, 1.0, -1.0);
  const double dt = 1.0 / 60.0;
  fake.motion(20, -175, 700, 5, 6, 7);  // x within the dead zone (20/350 < 0.08), y half, z over
  const SpaceMouseState& s = mouse->poll(0.0);
  EXPECT_EQ(s.axes, (std::array<int, 6>{20, -175, 700, 5, 6, 7}));
  ToolNudge n = space_mouse_nudge(s, m, dt);
  EXPECT_EQ(n.delta_W.x(), 0.0);
  EXPECT_NEAR(n.delta_W.y(), -(0.5 - 0.08) / 0.92 * m.speed_m_per_s * dt, 1e-15);
  EXPECT_NEAR(n.delta_W.z(), -m.speed_m_per_s * dt, 1e-15);
  EXPECT_EQ(n.opening_rad, 0.0);
  EXPECT_EQ(n.roll_rad, 0.0);        // the twist (rz 7) within the dead zone
  fake.motion(0, 0, 0, 0, 0, -175);  // half a twist, clockwise seen from above: a roll
  n = space_mouse_nudge(mouse->poll(0.005), m, dt);
  EXPECT_TRUE(n.delta_W.isZero());
  EXPECT_NEAR(n.roll_rad, -(0.5 - 0.08) / 0.92 * m.roll_rate_rad_per_s * dt, 1e-15);
  m.roll_sign = -1.0;
  EXPECT_NEAR(space_mouse_nudge(mouse->state(), m, dt).roll_rad,
              (0.5 - 0.08) / 0.92 * m.roll_rate_rad_per_s * dt, 1e-15);
  fake.button(1, 0);  // close
  n = space_mouse_nudge(mouse->poll(0.01), m, dt);
  EXPECT_NEAR(n.opening_rad, -m.jaw_rate_rad_per_s * dt, 1e-15);
  fake.button(1, 1);  // both: nothing
  EXPECT_EQ(space_mouse_nudge(mouse->poll(0.02), m, dt).opening_rad, 0.0);
  fake.button(0, 0);  // open only
  EXPECT_NEAR(space_mouse_nudge(mouse->poll(0.03), m, dt).opening_rad, m.jaw_rate_rad_per_s * dt,
              1e-15);
  EXPECT_EQ(mouse->state().buttons, 2U);
  mouse.reset();
  EXPECT_EQ(fake.open_count(), 0);  // closed with the mouse
}

// Unknown events and button numbers are counted and ignored; a flood is taken a bounded number
// at a time; a puck that goes quiet stops the tool.
TEST(SpaceMouse, BadEventsFloodsAndSilenceAreHandled) {
  const Fake fake;
  Result<std::unique_ptr<SpaceMouse>> opened = SpaceMouse::open(LAP_FAKE_SPNAV);
  ASSERT_TRUE(opened.ok()) << opened.message();
  std::unique_ptr<SpaceMouse> mouse = std::move(opened).value();
  ASSERT_NE(mouse, nullptr);
  fake.motion(100, 0, 0, 0, 0, 0);
  fake.raw(7);
  fake.button(1, 40);
  const SpaceMouseState& s = mouse->poll(1.0);
  EXPECT_EQ(s.malformed, 2);
  EXPECT_EQ(s.buttons, 0U);
  EXPECT_EQ(s.axes[0], 100);
  // Quiet for less than kStaleAfterS: still deflected; longer: at rest.
  EXPECT_EQ(mouse->poll(1.0 + 0.5 * SpaceMouse::kStaleAfterS).axes[0], 100);
  EXPECT_EQ(mouse->poll(1.0 + 2.0 * SpaceMouse::kStaleAfterS).axes[0], 0);
  for (int i = 0; i < 1000; ++i) fake.motion(i, 0, 0, 0, 0, 0);
  const int64_t before = mouse->state().events;
  EXPECT_EQ(mouse->poll(2.0).events - before, SpaceMouse::kMaxEventsPerPoll);
  for (int k = 0; k < 10 && mouse->poll(2.0).events - before < 1000; ++k) {
  }
  EXPECT_EQ(mouse->state().axes[0], 999);
}

}  // namespace
}  // namespace lap::hardware
