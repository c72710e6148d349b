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
    return DeviceSpec{DeviceKind::kSimulated, "", false};
  }
  if (head == "scripted" || head == "replay") {
    if (tail.empty()) return fail("expected " + std::string(head) + ":FILE");
    return DeviceSpec{head == "scripted" ? DeviceKind::kScripted : DeviceKind::kReplay,
                      std::string(tail), false};
  }
  if (head == "phantom") return DeviceSpec{DeviceKind::kPhantom, std::string(tail), false};
  return fail(
      "expected simulated, scripted:FILE, replay:FILE, phantom or phantom:NAME (each optionally "
      "+gripper)");
}

}  // namespace

Result<DeviceSpec> parse_device_spec(std::string_view full) {
  constexpr std::string_view kGripper = "+gripper";
  const bool gripper =
      full.size() > kGripper.size() && full.substr(full.size() - kGripper.size()) == kGripper;
  const std::string_view text = gripper ? full.substr(0, full.size() - kGripper.size()) : full;
  Result<DeviceSpec> spec = parse_arm_spec(text, full);
  if (spec.ok()) spec->usb_gripper = gripper;
  return spec;
}

}  // namespace lap::hardware
