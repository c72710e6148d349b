#pragma once
/// \file
/// A 3D mouse (3Dconnexion's SpaceNavigator, SpaceMouse and the like) through the spacenavd
/// daemon, so residents without a haptic device can steer a tool in three dimensions at once:
/// libspnav is loaded at run time (dlopen of libspnav.so.0, Debian's libspnav0), so it is
/// optional, and nothing changes when it or the daemon is absent. The UI thread polls the puck
/// (never the haptic thread) and space_mouse_nudge() turns its deflection into a motion of the
/// simulated device's tool tip.
///
/// Not yet tried with a real puck: which way each axis points is a guess to check with one;
/// SpaceMouseMapping::axis_sign flips them.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "core/result.h"
#include "hardware/tool_nudge.h"

namespace lap::hardware {

/// spnav_event as libspnav lays it out (spnav.h): a motion or a button record.
union SpnavEvent {
  int type;
  struct {
    int type;
    int x, y, z;
    int rx, ry, rz;
    unsigned int period;  // ms since the last motion event
    int* data;
  } motion;
  struct {
    int type;
    int press;
    int bnum;
  } button;
};
inline constexpr int kSpnavEventMotion = 1;
inline constexpr int kSpnavEventButton = 2;

/// The libspnav functions used: as loaded, or as a test supplies them.
struct SpnavApi {
  int (*open)() = nullptr;                   ///< spnav_open: -1 when the daemon is not there
  int (*close)() = nullptr;                  ///< spnav_close
  int (*poll_event)(SpnavEvent*) = nullptr;  ///< spnav_poll_event: 0 when none is pending
};

/// The puck after the events so far.
struct SpaceMouseState {
  std::array<int, 6> axes{};  ///< tx ty tz rx ry rz, raw (about ±350 at full deflection)
  uint32_t buttons = 0;       ///< bit b: button b held
  int64_t events = 0;         ///< events taken
  int64_t malformed = 0;      ///< events ignored: unknown type, button number out of range
};

class SpaceMouse {
 public:
  /// Connects to spacenavd through `library`; a diagnostic naming what to install or start
  /// when the library or the daemon is missing.
  static Result<std::unique_ptr<SpaceMouse>> open(const std::string& library = "libspnav.so.0");
  /// The same with given functions (tests; the handle, if any, is closed with the mouse).
  static Result<std::unique_ptr<SpaceMouse>> open_with(const SpnavApi& api, void* handle = nullptr);
  ~SpaceMouse();
  SpaceMouse(const SpaceMouse&) = delete;
  SpaceMouse& operator=(const SpaceMouse&) = delete;
  SpaceMouse(SpaceMouse&&) = delete;
  SpaceMouse& operator=(SpaceMouse&&) = delete;

  /// Takes the pending events (at most kMaxEventsPerPoll: a flood cannot stall the UI) at time
  /// now_s [s, any steady clock]. The axes fall back to zero when no motion event came for
  /// kStaleAfterS: a puck let go, or a daemon gone quiet, must not leave the tool drifting.
  const SpaceMouseState& poll(double now_s);
  [[nodiscard]] const SpaceMouseState& state() const { return state_; }

  static constexpr int kMaxEventsPerPoll = 256;
  static constexpr double kStaleAfterS = 0.25;

 private:
  SpaceMouse(const SpnavApi& api, void* handle) : api_(api), handle_(handle) {}
  SpnavApi api_;
  void* handle_ = nullptr;
  SpaceMouseState state_;
  double last_motion_s_ = -1e300;
};

/// How the puck steers a tool tip: velocity proportional to the deflection beyond a dead zone,
/// buttons 0 and 1 closing and opening the jaws.
struct SpaceMouseMapping {
  double full_scale = 350.0;        ///< raw deflection taken as full speed
  double dead_zone = 0.08;          ///< fraction of full scale ignored (the puck's rest noise)
  double speed_m_per_s = 0.05;      ///< tip speed at full deflection
  double jaw_rate_rad_per_s = 1.0;  ///< jaw opening rate while a button is held
  /// Roll rate at full twist: about a quarter turn in a second, a little under a held roll
  /// key's 2.2 rad/s (hardware/tool_nudge.h: 5 degrees a press, about 25 presses a second), for
  /// a puck's finer control. An estimate.
  double roll_rate_rad_per_s = 1.5;
  double roll_sign = 1.0;                    ///< the twist's direction to the roll's
  Eigen::Vector3d axis_sign{1.0, 1.0, 1.0};  ///< puck x, y, z to world x, y, z
};

/// The tool motion over dt_s from the puck's state. Each axis: zero within the dead zone, then
/// rising linearly to full speed at full scale (and no further); the twist about the puck's
/// vertical axis (rz) rolls the tool about its shaft the same way.
[[nodiscard]] ToolNudge space_mouse_nudge(const SpaceMouseState& s, const SpaceMouseMapping& m,
                                          double dt_s);

}  // namespace lap::hardware
