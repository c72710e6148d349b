#include "hardware/haptic_device.h"

namespace lap::hardware {

std::string_view to_string(DeviceStatus status) {
  switch (status) {
    case DeviceStatus::kOk:
      return "ok";
    case DeviceStatus::kFinished:
      return "finished";
    case DeviceStatus::kDisconnected:
      return "disconnected";
    case DeviceStatus::kError:
      return "error";
  }
  return "unknown";
}

}  // namespace lap::hardware
