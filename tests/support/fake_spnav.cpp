// A stand-in for libspnav (the spacenavd client library) for the 3D mouse tests: the same three
// entry points, fed from a queue the test fills through fake_spnav_push() and told whether the
// daemon "runs" by fake_spnav_set_daemon(). Written here from libspnav's published interface.

#include <deque>

#include "hardware/space_mouse.h"

namespace {

// libspnav's event record, as the driver declares it.
using Event = lap::hardware::SpnavEvent;

std::deque<Event>& queue() {
  static std::deque<Event> q;
  return q;
}
bool g_daemon = true;
int g_open = 0;

}  // namespace

extern "C" {

// NOLINTBEGIN(readability-identifier-naming): libspnav's names
int spnav_open() {
  if (!g_daemon) return -1;
  ++g_open;
  return 0;
}

int spnav_close() {
  --g_open;
  return 0;
}

int spnav_poll_event(Event* e) {
  if (queue().empty()) return 0;
  *e = queue().front();
  queue().pop_front();
  return e->type;
}
// NOLINTEND(readability-identifier-naming)

// Test controls.
void fake_spnav_set_daemon(int running) { g_daemon = running != 0; }
int fake_spnav_open_count() { return g_open; }
void fake_spnav_push_motion(int x, int y, int z, int rx, int ry, int rz) {
  Event e{};
  e.motion = {lap::hardware::kSpnavEventMotion, x, y, z, rx, ry, rz, 8U, nullptr};
  queue().push_back(e);
}
void fake_spnav_push_button(int press, int bnum) {
  Event e{};
  e.button = {lap::hardware::kSpnavEventButton, press, bnum};
  queue().push_back(e);
}
void fake_spnav_push_raw(int type) {
  Event e{};
  e.type = type;
  queue().push_back(e);
}
}
