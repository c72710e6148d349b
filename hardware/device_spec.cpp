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

/// "1-2.3": a bus number, '-', then port numbers separated by '.'.
bool is_bus_path(std::string_view p) {
  const size_t dash = p.find('-');
  if (dash == 0 || dash == std::string_view::npos || dash + 1 >= p.size()) return false;
  if (p.substr(0, dash).find_first_not_of("0123456789") != std::string_view::npos) return false;
  const std::string_view ports = p.substr(dash + 1);
  if (ports.front() == '.' || ports.back() == '.' || ports.find("..") != std::string_view::npos) {
    return false;
  }
  return ports.find_first_not_of("0123456789.") == std::string_view::npos;
}

}  // namespace

Result<DeviceSpec> parse_device_spec(std::string_view full) {
  // The gripper is the text's last part: +gripper, +gripper:SERIAL or +gripper@BUS-PORTS. A
  // file name that merely holds "+gripper" (scripted:a+gripper.csv) is a file name.
  constexpr std::string_view kGripper = "+gripper";
  const size_t at = full.rfind(kGripper);
  const std::string_view rest =
      at == std::string_view::npos ? std::string_view() : full.substr(at + kGripper.size());
  const bool serial = rest.size() > 1 && rest[0] == ':' &&
                      rest.substr(1).find_first_of("+:/") == std::string_view::npos;
  const bool path = rest.size() > 1 && rest[0] == '@';
  if (at == std::string_view::npos || at == 0 || (!rest.empty() && !serial && !path)) {
    return parse_arm_spec(full, full);
  }
  GripperSelector selector;
  if (serial) selector.serial = std::string(rest.substr(1));
  if (path) {
    if (!is_bus_path(rest.substr(1))) {
      return diagnostic("device '" + std::string(full) +
                        "': expected +gripper@BUS-PORTS as the kernel names a USB device's place "
                        "(e.g. +gripper@1-2.3), got '" +
                        std::string(rest.substr(1)) + "'");
    }
    selector.bus_path = std::string(rest.substr(1));
  }
  Result<DeviceSpec> spec = parse_arm_spec(full.substr(0, at), full);
  if (spec.ok()) {
    spec->usb_gripper = true;
    spec->gripper = selector;
  }
  return spec;
}

}  // namespace lap::hardware
