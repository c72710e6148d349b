#include "hardware/device_spec.h"

namespace lap::hardware {
namespace {

Result<DeviceSpec> parse_arm_spec(std::string_view text, std::string_view full) {
  const size_t colon = text.find(':');
  const std::string_view head = text.substr(0, colon);
  const std::string_view tail = colon == std::string_view::npos ? "" : text.substr(colon + 1);
  auto fail = [&](const std::string& why) -> Result<DeviceSpec> {
    return diagnostic("device '" + std::string(full) + "': " + why);
  };
  if (head == "simulated") {
    if (colon != std::string_view::npos) return fail("'simulated' takes no argument");
    return DeviceSpec{DeviceKind::kSimulated, "", false, {}};
  }
  if (head == "scripted" || head == "replay") {
    if (tail.empty()) return fail("expected " + std::string(head) + ":FILE");
    return DeviceSpec{head == "scripted" ? DeviceKind::kScripted : DeviceKind::kReplay,
                      std::string(tail),
                      false,
                      {}};
  }
  if (head == "phantom") return DeviceSpec{DeviceKind::kPhantom, std::string(tail), false, {}};
  return fail(
      "expected simulated, scripted:FILE, replay:FILE, phantom or phantom:NAME (each optionally "
      "+gripper)");
}

}  // namespace

Result<DeviceSpec> parse_device_spec(std::string_view full) {
  constexpr std::string_view kGripper = "+gripper";
  const size_t at = full.rfind(kGripper);
  if (at == std::string_view::npos || at == 0) return parse_arm_spec(full, full);
  // After +gripper: nothing, :SERIAL or @BUS-PORTS.
  const std::string_view rest = full.substr(at + kGripper.size());
  GripperSelector selector;
  if (!rest.empty()) {
    const std::string_view value = rest.substr(1);
    const bool path_chars = value.find_first_not_of("0123456789.-") == std::string_view::npos;
    if (rest[0] == ':' && !value.empty()) {
      selector.serial = std::string(value);
    } else if (rest[0] == '@' && !value.empty() && path_chars && value.find('-') != 0 &&
               value.find('-') != std::string_view::npos) {
      selector.bus_path = std::string(value);
    } else {
      return diagnostic("device '" + std::string(full) +
                        "': expected +gripper, +gripper:SERIAL or +gripper@BUS-PORTS (e.g. "
                        "+gripper@1-2.3) at its end");
    }
  }
  Result<DeviceSpec> spec = parse_arm_spec(full.substr(0, at), full);
  if (spec.ok()) {
    spec->usb_gripper = true;
    spec->gripper = selector;
  }
  return spec;
}

}  // namespace lap::hardware
