#include "hardware/space_mouse.h"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>

namespace lap::hardware {

Result<std::unique_ptr<SpaceMouse>> SpaceMouse::open(const std::string& library) {
  void* handle = dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    return diagnostic("no 3D mouse: " + library + " could not be loaded (" +
                      (why != nullptr ? why : "not found") +
                      "); install libspnav0 and spacenavd (apt-get install libspnav0 spacenavd)");
  }
  SpnavApi api;
  // NOLINTBEGIN(*-reinterpret-cast): dlsym returns untyped addresses
  api.open = reinterpret_cast<int (*)()>(dlsym(handle, "spnav_open"));
  api.close = reinterpret_cast<int (*)()>(dlsym(handle, "spnav_close"));
  api.poll_event = reinterpret_cast<int (*)(SpnavEvent*)>(dlsym(handle, "spnav_poll_event"));
  // NOLINTEND(*-reinterpret-cast)
  if (api.open == nullptr || api.close == nullptr || api.poll_event == nullptr) {
    dlclose(handle);
    return diagnostic("no 3D mouse: " + library +
                      " lacks spnav_open, spnav_close or spnav_poll_event (expected libspnav)");
  }
  return open_with(api, handle);
}

Result<std::unique_ptr<SpaceMouse>> SpaceMouse::open_with(const SpnavApi& api, void* handle) {
  if (api.open() == -1) {
    if (handle != nullptr) dlclose(handle);
    return diagnostic(
        "no 3D mouse: spacenavd is not running (start it: systemctl start spacenavd), or no "
        "3D mouse is plugged in");
  }
  return std::unique_ptr<SpaceMouse>(new SpaceMouse(api, handle));
}

SpaceMouse::~SpaceMouse() {
  api_.close();
  if (handle_ != nullptr) dlclose(handle_);
}

const SpaceMouseState& SpaceMouse::poll(double now_s) {
  SpnavEvent e{};
  for (int k = 0; k < kMaxEventsPerPoll && api_.poll_event(&e) > 0; ++k) {
    ++state_.events;
    if (e.type == kSpnavEventMotion) {
      state_.axes = {e.motion.x, e.motion.y, e.motion.z, e.motion.rx, e.motion.ry, e.motion.rz};
      last_motion_s_ = now_s;
    } else if (e.type == kSpnavEventButton && e.button.bnum >= 0 && e.button.bnum < 32) {
      const uint32_t bit = 1U << static_cast<unsigned>(e.button.bnum);
      state_.buttons = e.button.press != 0 ? (state_.buttons | bit) : (state_.buttons & ~bit);
    } else {
      ++state_.malformed;
    }
    e = SpnavEvent{};
  }
  if (now_s - last_motion_s_ > kStaleAfterS) state_.axes.fill(0);
  return state_;
}

ToolNudge space_mouse_nudge(const SpaceMouseState& s, const SpaceMouseMapping& m, double dt_s) {
  ToolNudge n;
  if (!(dt_s > 0.0) || !(m.full_scale > 0.0) || !(m.dead_zone >= 0.0 && m.dead_zone < 1.0)) {
    return n;
  }
  for (int a = 0; a < 3; ++a) {
    const double u =
        std::clamp(static_cast<double>(s.axes[static_cast<size_t>(a)]) / m.full_scale, -1.0, 1.0);
    const double beyond = std::max(0.0, std::abs(u) - m.dead_zone) / (1.0 - m.dead_zone);
    n.delta_W[a] = std::copysign(beyond, u) * m.axis_sign[a] * m.speed_m_per_s * dt_s;
  }
  const double twist = std::clamp(static_cast<double>(s.axes[5]) / m.full_scale, -1.0, 1.0);
  const double twist_beyond = std::max(0.0, std::abs(twist) - m.dead_zone) / (1.0 - m.dead_zone);
  n.roll_rad = std::copysign(twist_beyond, twist) * m.roll_sign * m.roll_rate_rad_per_s * dt_s;
  const bool close = (s.buttons & 1U) != 0;
  const bool open = (s.buttons & 2U) != 0;
  if (close != open) n.opening_rad = (open ? 1.0 : -1.0) * m.jaw_rate_rad_per_s * dt_s;
  return n;
}

}  // namespace lap::hardware
