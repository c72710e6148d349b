#include "hardware/open_haptics_library.h"

#include <dlfcn.h>

namespace lap::hardware {

bool open_haptics_available(std::string* error) {
  void* hd = dlopen("libHD.so", RTLD_NOW | RTLD_LOCAL);
  if (hd == nullptr) {
    const char* why = dlerror();
    if (error != nullptr) {
      *error = std::string("OpenHaptics' HD library (libHD.so) could not be loaded (") +
               (why != nullptr ? why : "not found") +
               "). Install OpenHaptics for Linux and the Touch/PHANToM device driver from "
               "3D Systems";
    }
    return false;
  }
  dlclose(hd);
  return true;
}

}  // namespace lap::hardware
