#include "hardware/device_spec.h"

namespace lap::hardware {

std::optional<DeviceSpec> parse_device_spec(std::string_view text, std::string* error) {
  const size_t colon = text.find(':');
  const std::string_view head = text.substr(0, colon);
  const std::string_view tail = colon == std::string_view::npos ? "" : text.substr(colon + 1);
  auto fail = [&](const std::string& why) -> std::optional<DeviceSpec> {
    if (error != nullptr) *error = "device '" + std::string(text) + "': " + why;
    return std::nullopt;
  };
  if (head == "simulated") {
    if (colon != std::string_view::npos) return fail("'simulated' takes no argument");
    return DeviceSpec{DeviceKind::kSimulated, ""};
  }
  if (head == "scripted" || head == "replay") {
    if (tail.empty()) return fail("expected " + std::string(head) + ":FILE");
    return DeviceSpec{head == "scripted" ? DeviceKind::kScripted : DeviceKind::kReplay,
                      std::string(tail)};
  }
  if (head == "phantom") return DeviceSpec{DeviceKind::kPhantom, std::string(tail)};
  return fail("expected simulated, scripted:FILE, replay:FILE, phantom or phantom:NAME");
}

}  // namespace lap::hardware
