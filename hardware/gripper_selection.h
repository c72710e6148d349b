#pragma once
/// \file
/// Which actuated gripper a tool opens when several are plugged in (two tools, two grippers):
/// by its USB serial number (`+gripper:SERIAL`) or by where it is plugged (`+gripper@BUS-PORTS`,
/// e.g. `1-2.3`: bus 1, port 2 of the root hub, port 3 of the hub there — what `lsusb -t` and
/// the kernel's /sys/bus/usb/devices call it). Without either, the only gripper found; with
/// two or more found that is refused, naming them, since the first found is not always the
/// same one.

#include <string>
#include <vector>

#include "core/result.h"

namespace lap::hardware {

/// What a DEV argument asks for (both empty: whichever single gripper is there).
struct GripperSelector {
  std::string serial;
  std::string bus_path;
};

/// A gripper found on the bus.
struct FoundGripper {
  std::string serial;  ///< empty when it has none or it could not be read (permissions)
  std::string bus_path;
};

/// The index in `found` of the gripper `want` names; otherwise what was found and how to name
/// one.
[[nodiscard]] Result<size_t> select_gripper(const std::vector<FoundGripper>& found,
                                            const GripperSelector& want);

/// "serial A at 1-2, serial (unreadable) at 1-3".
[[nodiscard]] std::string describe(const std::vector<FoundGripper>& found);

}  // namespace lap::hardware
