// A stand-in for OpenHaptics' libHD.so, built as libHD.so for the tests: the HD API functions
// the PHANToM driver calls, a scheduler thread that runs the servo callbacks at about 1 kHz, and
// fake_hd_* controls with which a test moves the stylus, reads the force sent, breaks
// calibration, injects a servo error or unplugs a device. Written for laptrainer's tests from the
// HD API's published interface; it models nothing of the real device beyond that.

#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hardware/open_haptics_api.h"

namespace {

// The driver's own declarations of the HD API's types (hardware/open_haptics_api.h): the driver
// calls these functions through pointers of exactly these types, which clang's
// -fsanitize=function checks against the definitions here.
using lap::hardware::hd::HDCallbackCode;
using lap::hardware::hd::HDenum;
using lap::hardware::hd::HDErrorInfo;
using lap::hardware::hd::HHD;
using Callback = lap::hardware::hd::HDSchedulerCallback;

struct Device {
  std::string name;
  bool open = false;
  bool unplugged = false;
  double position_mm[3] = {0, 0, 0};
  double velocity_mm_s[3] = {0, 0, 0};
  double transform[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  int buttons = 0;
  double force[3] = {0, 0, 0};
  bool force_output = false;
  bool ramping = false;
};

struct Scheduled {
  Callback fn;
  void* data;
  HHD device;  // learnt from the first hdBeginFrame
  bool active;
};

// What a servo callback reads between hdBeginFrame and hdEndFrame: the device's state as the
// frame began, as the HD API gives it (one consistent state per frame), so that a test moving
// the stylus mid-frame never has a callback read the new buttons with the old position.
struct FrameState {
  double position_mm[3] = {0, 0, 0};
  double velocity_mm_s[3] = {0, 0, 0};
  int buttons = 0;
};

std::mutex g_mutex;
std::array<Device, 4> g_devices;
std::array<FrameState, 4> g_frames;
HHD g_current = 0xFFFFFFFFU;
// The pending error is the calling thread's own: the servo thread polls hdGetError every frame,
// and with one shared value it could take, and clear, an error that hdInitDevice had just set
// for the main thread (TSan's slow threads made that happen in CI: "HD error 0x0000").
thread_local unsigned int t_error = 0;
unsigned int g_servo_error = 0;  // reported by the next hdGetError in the servo thread
HDenum g_calibration = 0x5000;
std::vector<Scheduled> g_callbacks;
std::atomic<bool> g_running{false};
std::thread g_thread;
thread_local int t_in_callback = -1;

void scheduler_loop() {
  while (g_running.load()) {
    std::vector<Scheduled> now;
    {
      const std::lock_guard<std::mutex> lock(g_mutex);
      now = g_callbacks;
    }
    for (size_t i = 0; i < now.size(); ++i) {
      if (!now[i].active) continue;
      {
        const std::lock_guard<std::mutex> lock(g_mutex);
        const HHD d = g_callbacks[i].device;
        if (d < g_devices.size() && g_devices[d].unplugged) continue;
      }
      t_in_callback = static_cast<int>(i);
      now[i].fn(now[i].data);
      t_in_callback = -1;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(1000));
  }
}

}  // namespace

extern "C" {

HHD hdInitDevice(const char* name) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  const std::string n = name == nullptr ? "Default Device" : name;
  if (n == "Missing Device") {
    t_error = 0x0300;  // a device fault
    return 0xFFFFFFFFU;
  }
  for (HHD i = 0; i < g_devices.size(); ++i) {
    if (!g_devices[i].open) {
      g_devices[i] = Device{};
      g_devices[i].name = n;
      g_devices[i].open = true;
      g_current = i;
      return i;
    }
  }
  t_error = 0x0301;
  return 0xFFFFFFFFU;
}
void hdDisableDevice(HHD h) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (h < g_devices.size()) g_devices[h].open = false;
}
void hdMakeCurrentDevice(HHD h) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_current = h;
}
HDErrorInfo hdGetError() {
  const std::lock_guard<std::mutex> lock(g_mutex);
  HDErrorInfo e{t_error, 0, g_current};
  if (t_in_callback >= 0 && g_servo_error != 0) {
    e.errorCode = g_servo_error;
  }
  t_error = 0;
  return e;
}
void hdEnable(HDenum cap) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (g_current >= g_devices.size()) return;
  if (cap == 0x4000) g_devices[g_current].force_output = true;
  if (cap == 0x4002) g_devices[g_current].ramping = true;
}
HDenum hdCheckCalibration() {
  const std::lock_guard<std::mutex> lock(g_mutex);
  return g_calibration;
}
void hdUpdateCalibration(HDenum) {}
void hdGetDoublev(HDenum what, double* out) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (g_current >= g_devices.size()) return;
  const Device& d = g_devices[g_current];
  const bool framed = t_in_callback >= 0;  // in a servo callback's frame: the frame's state
  switch (what) {
    case 0x2050:
      std::memcpy(out, framed ? g_frames[g_current].position_mm : d.position_mm,
                  sizeof(d.position_mm));
      break;
    case 0x2051:
      std::memcpy(out, framed ? g_frames[g_current].velocity_mm_s : d.velocity_mm_s,
                  sizeof(d.velocity_mm_s));
      break;
    case 0x2052:
      std::memcpy(out, d.transform, sizeof(d.transform));
      break;
    case 0x2602:
      *out = 2.31;  // N/mm
      break;
    case 0x2603:
      *out = 3.3;  // N
      break;
    case 0x2604:    // HD_NOMINAL_MAX_CONTINUOUS_FORCE
      *out = 0.88;  // N, a PHANToM Omni's
      break;
    default:
      t_error = 0x0100;  // invalid enum
  }
}
void hdGetIntegerv(HDenum what, int* out) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (what == 0x2000 && g_current < g_devices.size()) {
    *out = t_in_callback >= 0 ? g_frames[g_current].buttons : g_devices[g_current].buttons;
  }
}
void hdSetDoublev(HDenum what, const double* in) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (what == 0x2700 && g_current < g_devices.size()) {
    std::memcpy(g_devices[g_current].force, in, 3 * sizeof(double));
  }
}
void hdBeginFrame(HHD h) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_current = h;
  if (t_in_callback >= 0) g_callbacks[static_cast<size_t>(t_in_callback)].device = h;
  if (h < g_devices.size()) {
    FrameState& f = g_frames[h];
    std::memcpy(f.position_mm, g_devices[h].position_mm, sizeof(f.position_mm));
    std::memcpy(f.velocity_mm_s, g_devices[h].velocity_mm_s, sizeof(f.velocity_mm_s));
    f.buttons = g_devices[h].buttons;
  }
}
void hdEndFrame(HHD) {}
unsigned long hdScheduleAsynchronous(Callback fn, void* data, unsigned short) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_callbacks.push_back({fn, data, 0xFFFFFFFFU, true});
  return g_callbacks.size();  // handle = index + 1
}
void hdUnschedule(unsigned long handle) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (handle >= 1 && handle <= g_callbacks.size()) g_callbacks[handle - 1].active = false;
}
void hdStartScheduler() {
  if (g_running.exchange(true)) return;
  g_thread = std::thread(scheduler_loop);
}
void hdStopScheduler() {
  if (!g_running.exchange(false)) return;
  g_thread.join();
}

// Test controls.
void fake_hd_set_state(HHD h, const double position_mm[3], const double velocity_mm_s[3],
                       int buttons) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  std::memcpy(g_devices[h].position_mm, position_mm, 3 * sizeof(double));
  std::memcpy(g_devices[h].velocity_mm_s, velocity_mm_s, 3 * sizeof(double));
  g_devices[h].buttons = buttons;
}
void fake_hd_force(HHD h, double out[3]) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  std::memcpy(out, g_devices[h].force, 3 * sizeof(double));
}
int fake_hd_force_output_enabled(HHD h) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  return g_devices[h].force_output && g_devices[h].ramping ? 1 : 0;
}
void fake_hd_set_calibration(HDenum c) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_calibration = c;
}
void fake_hd_set_servo_error(unsigned int code) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_servo_error = code;
}
void fake_hd_unplug(HHD h, int unplugged) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_devices[h].unplugged = unplugged != 0;
}
void fake_hd_reset() {
  hdStopScheduler();
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_devices = {};
  g_callbacks.clear();
  g_calibration = 0x5000;
  g_servo_error = 0;
  t_error = 0;
}

}  // extern "C"
