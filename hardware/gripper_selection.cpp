#include "hardware/gripper_selection.h"

namespace lap::hardware {

std::string describe(const std::vector<FoundGripper>& found) {
  std::string out;
  for (const FoundGripper& g : found) {
    if (!out.empty()) out += ", ";
    out += "serial " + (g.serial.empty() ? std::string("(unreadable)") : g.serial) + " at " +
           g.bus_path;
  }
  return out;
}

Result<size_t> select_gripper(const std::vector<FoundGripper>& found, const GripperSelector& want) {
  if (found.empty()) {
    return diagnostic(
        "no actuated gripper found (USB 1209:4c54); is it plugged in, and may this user open it "
        "(udev rule in hardware/README.md)?");
  }
  const bool by_serial = !want.serial.empty();
  const bool by_path = !want.bus_path.empty();
  if (!by_serial && !by_path) {
    if (found.size() == 1) return size_t{0};
    return diagnostic(std::to_string(found.size()) + " actuated grippers found (" +
                      describe(found) +
                      "): name the tool's with +gripper:SERIAL or +gripper@BUS-PORTS");
  }
  for (size_t i = 0; i < found.size(); ++i) {
    if ((by_serial && found[i].serial == want.serial) ||
        (by_path && found[i].bus_path == want.bus_path)) {
      return i;
    }
  }
  return diagnostic(
      std::string("no actuated gripper ") +
      (by_serial ? "with serial '" + want.serial + "'" : "plugged in at " + want.bus_path) +
      " (found: " + describe(found) + ")");
}

}  // namespace lap::hardware
