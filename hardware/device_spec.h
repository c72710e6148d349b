#pragma once
/// \file
/// The device specifications accepted on the command line (docs/architecture.md `run --left DEV`):
/// `simulated`, `scripted:FILE`, `replay:FILE`, `phantom` or `phantom:NAME`, each optionally
/// followed by `+gripper`: the actuated USB gripper on the arm's end gives the jaw opening and
/// renders the squeeze (thesis Figure 7-9); `+gripper:SERIAL` or `+gripper@BUS-PORTS` names
/// which one when two are plugged in (gripper_selection.h).

#include <string>
#include <string_view>

#include "core/result.h"
#include "hardware/gripper_selection.h"

namespace lap::hardware {

/// Which driver serves a tool.
enum class DeviceKind { kSimulated, kScripted, kReplay, kPhantom };

/// A parsed DEV argument.
struct DeviceSpec {
  DeviceKind kind = DeviceKind::kSimulated;
  std::string argument;      ///< file for scripted/replay, device name for phantom (may be empty)
  bool usb_gripper = false;  ///< `+gripper`: the actuated gripper over USB
  GripperSelector gripper;   ///< which one (`+gripper:SERIAL`, `+gripper@BUS-PORTS`)
};

/// Parses DEV; on failure a diagnostic saying what was expected.
[[nodiscard]] Result<DeviceSpec> parse_device_spec(std::string_view text);

}  // namespace lap::hardware
