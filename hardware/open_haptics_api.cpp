#include "hardware/open_haptics_api.h"

#include <dlfcn.h>

#include <map>
#include <mutex>

namespace lap::hardware::hd {

Api::~Api() {
  if (handle != nullptr) dlclose(handle);
}

Result<std::shared_ptr<Api>> load_api(const std::string& library) {
  static std::mutex mutex;
  static std::map<std::string, std::weak_ptr<Api>> loaded;
  const std::lock_guard<std::mutex> lock(mutex);
  if (auto existing = loaded[library].lock()) return existing;
  auto api = std::make_shared<Api>();
  api->handle = dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (api->handle == nullptr) {
    const char* why = dlerror();
    return diagnostic("OpenHaptics' HD library (" + library + ") could not be loaded (" +
                      (why != nullptr ? why : "not found") +
                      "). Install OpenHaptics for Linux and the Touch/PHANToM device driver "
                      "from 3D Systems");
  }
  bool ok = true;
  std::string missing;
  auto bind = [&]<typename F>(F** fn, const char* name) {
    *fn = reinterpret_cast<F*>(dlsym(api->handle, name));  // NOLINT(*-reinterpret-cast)
    if (*fn == nullptr) {
      ok = false;
      missing += (missing.empty() ? "" : ", ") + std::string(name);
    }
  };
  bind(&api->hdInitDevice, "hdInitDevice");
  bind(&api->hdDisableDevice, "hdDisableDevice");
  bind(&api->hdMakeCurrentDevice, "hdMakeCurrentDevice");
  bind(&api->hdGetError, "hdGetError");
  bind(&api->hdEnable, "hdEnable");
  bind(&api->hdCheckCalibration, "hdCheckCalibration");
  bind(&api->hdUpdateCalibration, "hdUpdateCalibration");
  bind(&api->hdGetDoublev, "hdGetDoublev");
  bind(&api->hdGetIntegerv, "hdGetIntegerv");
  bind(&api->hdSetDoublev, "hdSetDoublev");
  bind(&api->hdBeginFrame, "hdBeginFrame");
  bind(&api->hdEndFrame, "hdEndFrame");
  bind(&api->hdScheduleAsynchronous, "hdScheduleAsynchronous");
  bind(&api->hdUnschedule, "hdUnschedule");
  bind(&api->hdStartScheduler, "hdStartScheduler");
  bind(&api->hdStopScheduler, "hdStopScheduler");
  if (!ok) {
    return diagnostic(library + " lacks HD API functions (" + missing +
                      "): expected OpenHaptics 3.x's libHD.so");
  }
  loaded[library] = api;
  return api;
}

}  // namespace lap::hardware::hd
