#pragma once
/// \file
/// Moving a simulated tool without a haptic device: what one key press does (the operative
/// field's and the set-up page's keys), and how any nudge (a key press, a mouse gesture:
/// mouse_nudge.h, the 3D mouse's motion over a frame: space_mouse.h) moves the device's input. The
/// UI thread nudges; the device publishes the result to the haptic thread
/// (hardware/simulated_device.h).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <numbers>
#include <optional>

#include "hardware/simulated_device.h"

namespace lap::hardware {

/// What to add to a simulated tool.
struct ToolNudge {
  Eigen::Vector3d delta_W = Eigen::Vector3d::Zero();  ///< handle motion [m]
  double opening_rad = 0.0;                           ///< jaws' opening [rad]
  double roll_rad = 0.0;  ///< turn about the shaft [rad], right-handed about handle → port
};

/// The keyboard's tool keys, one motion each (the application maps them to J L U O I K, [ ],
/// and , . : app/tool_keys.h).
enum class ToolKey : uint8_t {
  kXMinus,
  kXPlus,
  kYPlus,
  kYMinus,
  kZMinus,
  kZPlus,
  kClose,
  kOpen,
  kRollMinus,
  kRollPlus,
};

// One press. 2 mm: a tenth of the jaws' length (scenarios: 20 mm), coarse enough to cross the
// 15 cm from a port to the duct in a few seconds of a held key (the desktop's autorepeat, about
// 25 presses a second). The jaws: 20 presses from closed to fully open. The roll: 5 degrees,
// 72 presses a turn. With Shift held, a quarter of each (0.5 mm, 1.25 degrees, 0.0125 rad): the
// catheter's tip, 0.4 of the handle's motion away on the other side of the port, was not put
// into the ductotomy on the 2 mm steps alone (docs/benchmarks.md, "The keyboard's hand").
inline constexpr double kKeyStepM = 0.002;
inline constexpr double kKeyOpeningRad = 0.05;
inline constexpr double kKeyRollRad = std::numbers::pi / 36.0;  // 5 degrees
inline constexpr double kKeyFineFraction = 0.25;

/// One press of `key`; `fine` (Shift held) a quarter of it.
[[nodiscard]] ToolNudge key_nudge(ToolKey key, bool fine = false);

/// `in` moved by `n`: the handle kept inside `workspace_W` (as the device keeps its sample: a key
/// held against the edge must not wind up), the jaws' opening within [0, 1] rad, and the roll
/// turning the handle's orientation about the line from the handle through `port_W`, which
/// turns the device's x axis, and with it the jaws' opening direction (sim::tool_kinematics),
/// by roll_rad about the shaft. Without a port (the set-up page's test screen) there is no
/// shaft, and the roll turns the handle about its own z axis.
[[nodiscard]] SimulatedInput nudged(const SimulatedInput& in, const ToolNudge& n,
                                    const Eigen::AlignedBox3d& workspace_W,
                                    const std::optional<Eigen::Vector3d>& port_W);

}  // namespace lap::hardware
